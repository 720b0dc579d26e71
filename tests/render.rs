#![allow(clippy::unwrap_used, clippy::expect_used)] // reason: test helpers may panic
//! End-to-end: `lucerna render` and `lucerna render-bench` on the example
//! rooms, and on broken room files.

mod common;
use common::{assets, lucerna, text};

/// Width and height from a PNG's IHDR chunk.
fn png_size(bytes: &[u8]) -> (u32, u32) {
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n", "not a PNG");
    let w = u32::from_be_bytes(bytes[16..20].try_into().unwrap());
    let h = u32::from_be_bytes(bytes[20..24].try_into().unwrap());
    (w, h)
}

/// The number after `key` in the figures line.
fn figure(stdout: &str, key: &str) -> f64 {
    let rest = stdout
        .split(key)
        .nth(1)
        .unwrap_or_else(|| panic!("no {key} in {stdout}"));
    rest.split_whitespace()
        .next()
        .unwrap()
        .trim_end_matches(',')
        .parse()
        .unwrap()
}

#[test]
fn render_writes_views_and_a_lux_grid_that_agree_with_the_figures() {
    let dir = tempfile::tempdir().unwrap();
    let room = assets().join("rooms/office.toml");
    let png = dir.path().join("office.png");
    let csv = dir.path().join("grid.csv");
    let out = lucerna(&[
        "render",
        room.to_str().unwrap(),
        "--out",
        png.to_str().unwrap(),
        "--lux-grid",
        csv.to_str().unwrap(),
        "--size",
        "160x90",
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let stdout = text(&out.stdout);
    let (w, h) = png_size(&std::fs::read(&png).unwrap());
    assert_eq!((w, h), (160, 90 + 22), "view plus caption strip");
    // The grid's mean, min and max are the printed figures.
    let grid = std::fs::read_to_string(&csv).unwrap();
    let lux: Vec<f64> = grid
        .lines()
        .skip(1)
        .map(|l| l.rsplit(',').next().unwrap().parse().unwrap())
        .collect();
    assert_eq!(
        lux.len(),
        20 * 15,
        "5 m × 3.8 m inside the border at 0.25 m"
    );
    let mean = lux.iter().sum::<f64>() / lux.len() as f64;
    let min = lux.iter().copied().fold(f64::INFINITY, f64::min);
    assert!((mean - figure(&stdout, "Eavg")).abs() < 0.1, "{stdout}");
    assert!((min - figure(&stdout, "Emin")).abs() < 0.1, "{stdout}");
    let u0 = figure(&stdout, "Emin/Eavg");
    assert!((u0 - min / mean).abs() < 0.01);

    let fc = dir.path().join("office_lux.png");
    let out = lucerna(&[
        "render",
        room.to_str().unwrap(),
        "--out",
        fc.to_str().unwrap(),
        "--false-colour",
        "--size",
        "160x90",
        "--backend",
        "cpu",
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert_eq!(
        png_size(&std::fs::read(&fc).unwrap()),
        (160 + 110, 90 + 22),
        "legend beside"
    );
}

#[test]
fn render_bakes_a_luminaire_scene_given_as_profile() {
    let dir = tempfile::tempdir().unwrap();
    let room = std::fs::read_to_string(assets().join("rooms/office.toml"))
        .unwrap()
        .replace(
            "profile = \"../profiles/examples/faceted_downlight.ies\"",
            &format!(
                "luminaire = \"{}\"",
                assets().join("luminaires/faceted_downlight.toml").display()
            ),
        );
    let path = dir.path().join("baked.toml");
    std::fs::write(&path, room).unwrap();
    let png = dir.path().join("baked.png");
    let out = lucerna(&[
        "render",
        path.to_str().unwrap(),
        "--out",
        png.to_str().unwrap(),
        "--size",
        "64x36",
        "--photons",
        "300000",
        "--backend",
        "cpu",
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    // The baked profile lights the office like the committed bake of the
    // same luminaire (2·10⁷ photons) within the noise of 3·10⁵ photons.
    let eavg = figure(&text(&out.stdout), "Eavg");
    let reference = lucerna(&[
        "render",
        assets().join("rooms/office.toml").to_str().unwrap(),
        "--out",
        dir.path().join("ref.png").to_str().unwrap(),
        "--size",
        "64x36",
        "--backend",
        "cpu",
    ]);
    let eavg_ref = figure(&text(&reference.stdout), "Eavg");
    assert!(
        (eavg - eavg_ref).abs() / eavg_ref < 0.03,
        "{eavg} vs {eavg_ref}"
    );
}

#[test]
fn broken_rooms_fail_clearly_and_write_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let good = std::fs::read_to_string(assets().join("rooms/office.toml")).unwrap();
    let base = assets().join("rooms");
    let zoomed = good.replace("fov_deg = 70", "fov_deg = 70\nzoom = 2");
    let zoom_line = format!(
        "line {}",
        zoomed.lines().position(|l| l.starts_with("zoom")).unwrap() + 1
    );
    let cases = [
        (zoomed.clone(), zoom_line.as_str()),
        (
            good.replace("reflectance = 0.5", "reflectance = 1.5"),
            "room.walls.reflectance",
        ),
        (
            good.replace("width_m = 6.0", "width_m = nan"),
            "room.width_m",
        ),
        (
            good.replace("position = [0.4, 0.4, 1.6]", "position = [9.0, 0.4, 1.6]"),
            "camera.position[0]",
        ),
        (
            good.replace("faceted_downlight.ies", "missing.ies"),
            "missing.ies",
        ),
        (
            good.replace("count = [3, 2]", "count = [300, 2]"),
            "array.count[0]",
        ),
        (
            good.replace(
                "[[luminaire]]\nprofile",
                "[[luminaire]]\nluminaire = \"x.toml\"\nprofile",
            ),
            "exactly one",
        ),
        ("version = 1\n[room\n".to_owned(), "line 2"),
    ];
    for (i, (room, expected)) in cases.iter().enumerate() {
        // Inside the assets' rooms directory so the relative profile paths
        // resolve; removed again below.
        let path = base.join(format!("_broken_{i}_{}.toml", std::process::id()));
        std::fs::write(&path, room).unwrap();
        let png = dir.path().join(format!("{i}.png"));
        let out = lucerna(&[
            "render",
            path.to_str().unwrap(),
            "--out",
            png.to_str().unwrap(),
            "--size",
            "32x18",
        ]);
        std::fs::remove_file(&path).unwrap();
        assert!(!out.status.success(), "case {i} rendered");
        let err = text(&out.stderr);
        assert!(
            err.contains(expected),
            "case {i}: expected {expected:?} in {err}"
        );
        assert!(!png.exists(), "case {i} wrote an image");
    }
    let out = lucerna(&["render", "nope.toml", "--out", "x.png", "--size", "10by10"]);
    assert!(!out.status.success());
    assert!(text(&out.stderr).contains("WIDTHxHEIGHT"));
}

#[test]
fn render_bench_reports_every_light_count_and_backend() {
    let out = lucerna(&[
        "render-bench",
        assets().join("rooms/office.toml").to_str().unwrap(),
        "--size",
        "64x36",
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let stdout = text(&out.stdout);
    for backend in ["CPU", "llvmpipe"] {
        let rows: Vec<&str> = stdout.lines().filter(|l| l.contains(backend)).collect();
        if backend == "llvmpipe"
            && rows.is_empty()
            && std::env::var_os("LUCERNA_SKIP_GPU_TESTS").is_some()
        {
            continue;
        }
        assert_eq!(rows.len(), 3, "{backend}: {stdout}");
        for (row, lights) in rows.iter().zip([1, 4, 16]) {
            let cols: Vec<f64> = row
                .split_whitespace()
                .rev()
                .take(6)
                .map(|c| c.parse().unwrap())
                .collect();
            // draft ratio, ratio, point, draft, cubature, lights (read
            // from the right)
            assert_eq!(cols[5] as usize, lights, "{row}");
            // The ratios are cubature / point and draft / point, within
            // the printed rounding.
            let (draft_ratio, ratio, point, draft, cubature) =
                (cols[0], cols[1], cols[2], cols[3], cols[4]);
            assert!(point > 0.0 && cubature > 0.0 && draft > 0.0, "{row}");
            let slack = ratio * (0.005 / cubature + 0.005 / point) + 0.01;
            assert!((ratio - cubature / point).abs() <= slack, "{row}");
            let slack = draft_ratio * (0.005 / draft + 0.005 / point) + 0.01;
            assert!((draft_ratio - draft / point).abs() <= slack, "{row}");
        }
    }
}

#[test]
fn render_writes_a_work_plane_plan() {
    let dir = tempfile::tempdir().unwrap();
    let plan = dir.path().join("plan.png");
    let out = lucerna(&[
        "render",
        assets().join("rooms/corridor.toml").to_str().unwrap(),
        "--out",
        dir.path().join("view.png").to_str().unwrap(),
        "--size",
        "32x18",
        "--backend",
        "cpu",
        "--work-plane-png",
        plan.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let (w, h) = png_size(&std::fs::read(&plan).unwrap());
    // 12 m deep at 60 px/m plus margins and caption; wide enough for the caption.
    assert_eq!(h, 720 + 32 + 22);
    assert!(w > 400, "{w}");
}

/// `lucerna near-field-eval PROFILE --pixels P --out DIR` (the exact
/// reference).
fn near_field_eval(
    profile: &std::path::Path,
    pixels: u32,
    out: &std::path::Path,
) -> std::process::Output {
    lucerna(&[
        "near-field-eval",
        profile.to_str().unwrap(),
        "--pixels",
        &pixels.to_string(),
        "--out",
        out.to_str().unwrap(),
    ])
}

#[test]
fn near_field_eval_writes_its_table_and_pictures() {
    let dir = tempfile::tempdir().unwrap();
    let profile = assets().join("profiles/samples/rab_indoor3_2002_full360.ies");
    let out = near_field_eval(&profile, 8, dir.path());
    assert!(out.status.success(), "{}", text(&out.stderr));
    let csv = std::fs::read_to_string(dir.path().join("near_field_nrms.csv")).unwrap();
    let rows: Vec<&str> = csv.lines().skip(1).collect();
    assert_eq!(rows.len(), 3, "{csv}");
    for (row, h) in rows.iter().zip(["0.1", "1", "2.5"]) {
        let cols: Vec<&str> = row.split(',').collect();
        assert_eq!(cols[1], h);
        let values: Vec<f64> = cols[2..].iter().map(|c| c.parse().unwrap()).collect();
        assert!(values.iter().all(|v| v.is_finite() && *v >= 0.0), "{row}");
    }
    for h in ["0.1", "1", "2.5"] {
        for suffix in ["", "_error"] {
            let file = format!("rab_indoor3_2002_full360_h{h}{suffix}.png");
            let png = std::fs::read(dir.path().join(&file)).unwrap();
            assert_eq!(&png[..4], b"\x89PNG", "{file}");
        }
        // Every point of the 8 × 8 grid and 5 tilts, with its error.
        let points = std::fs::read(
            dir.path()
                .join(format!("rab_indoor3_2002_full360_h{h}_points.csv")),
        )
        .unwrap();
        let mut reader = csv::Reader::from_reader(points.as_slice());
        assert_eq!(reader.headers().unwrap().len(), 9);
        let rows: Vec<csv::StringRecord> = reader.records().map(|r| r.unwrap()).collect();
        assert_eq!(rows.len(), 8 * 8 * 5);
        // The corners of the protocol's region are sampled.
        assert_eq!(&rows[0][1], "-2.5000");
        assert_eq!(&rows[7][1], "2.5000");
    }
}

#[test]
fn near_field_csv_quotes_a_profile_name_with_a_comma() {
    let dir = tempfile::tempdir().unwrap();
    let profile = dir.path().join("rab, \"indoor\".ies");
    std::fs::copy(
        assets().join("profiles/samples/rab_indoor3_2002_full360.ies"),
        &profile,
    )
    .unwrap();
    let out = near_field_eval(&profile, 4, dir.path());
    assert!(out.status.success(), "{}", text(&out.stderr));
    let csv = std::fs::read(dir.path().join("near_field_nrms.csv")).unwrap();
    let mut reader = csv::Reader::from_reader(csv.as_slice());
    assert_eq!(reader.headers().unwrap().len(), 9);
    let rows: Vec<csv::StringRecord> = reader.records().map(|r| r.unwrap()).collect();
    assert_eq!(rows.len(), 3);
    for row in &rows {
        assert_eq!(row.len(), 9, "{row:?}");
        assert_eq!(&row[0], "rab, \"indoor\"");
    }
}

#[test]
fn an_image_too_large_for_the_adapter_is_refused_clearly() {
    // The image's buffer holds 16 bytes a pixel. The size asked for is
    // the smallest square beyond the adapter's own limit per buffer, read
    // from the adapter `lucerna render --backend gpu` opens too, so the
    // refusal applies on any adapter (8192² fits llvmpipe's GL limit: it
    // was rendered there, for 16 minutes). The GPU renderer refuses it
    // before any work, saying how much it needed and allows; the room is
    // then rendered on the CPU, as the line says (point lights keep that
    // short).
    let Ok(ctx) = lucerna_gpu::open() else {
        eprintln!("no GPU adapter: nothing to refuse");
        return;
    };
    let max = ctx
        .limits
        .max_storage_buffer_binding_size
        .min(ctx.limits.max_buffer_size);
    let side = ((max as f64 / 16.0).sqrt().floor() as u64 + 8) / 8 * 8;
    assert!(16 * side * side > max);
    if side > 8192 {
        eprintln!(
            "{}: an image the CLI accepts (at most 8192²) fits its {max} bytes per buffer",
            ctx.describe()
        );
        return;
    }
    drop(ctx);
    let size = format!("{side}x{side}");
    let dir = tempfile::tempdir().unwrap();
    let png = dir.path().join("huge.png");
    let out = lucerna(&[
        "render",
        assets().join("rooms/office.toml").to_str().unwrap(),
        "--out",
        png.to_str().unwrap(),
        "--size",
        &size,
        "--backend",
        "gpu",
        "--point-lights",
    ]);
    let err = text(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(
        err.contains("on CPU (the GPU render failed")
            && err.contains("MB of GPU storage needed, this adapter allows"),
        "{err}"
    );
    assert!(png.exists());
}

/// `lucerna render` and the editor's live room preview share one
/// pipeline (`lucerna_room::RoomSetup`, `RoomRenderer`): for the same room
/// and table, the editor's figures are the CLI's to the printed digit and
/// its work-plane grid is the CLI's CSV byte for byte.
#[test]
fn the_editor_preview_gives_lucerna_renders_figures_for_the_same_room_and_table() {
    use std::sync::Arc;

    use lucerna_editor::{PictureQuality, RenderRequest, Renderer, RoomLight};
    use lucerna_room::RoomSetup;
    use lucerna_room::scene::opening_from_dimensions;
    use lucerna_simulation::BackendRequest;

    let dir = tempfile::tempdir().unwrap();
    let room = assets().join("rooms/office.toml");
    let csv = dir.path().join("grid.csv");
    let out = lucerna(&[
        "render",
        room.to_str().unwrap(),
        "--out",
        dir.path().join("office.png").to_str().unwrap(),
        "--lux-grid",
        csv.to_str().unwrap(),
        "--size",
        "64x40",
        "--backend",
        "cpu",
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let stdout = text(&out.stdout);

    // The editor lit by the table of the office's own profile file, from
    // that file's luminous opening, as the room file gives it.
    let bytes = std::fs::read(assets().join("profiles/examples/faceted_downlight.ies")).unwrap();
    let photometry = lucerna_photometry::read_photometry(&bytes).unwrap();
    let light = RoomLight {
        table: Arc::new(photometry.table.clone()),
        opening: opening_from_dimensions(photometry.meta.luminous_area),
        generation: 0,
        photons: 0,
    };
    let request = RenderRequest {
        light,
        room: Arc::new(RoomSetup::load(&room).unwrap()),
        room_revision: 0,
        // The full rule, as `lucerna render` shades (the work plane does
        // not depend on the picture's size).
        quality: PictureQuality::Draft,
    };
    let picture = Renderer::open(BackendRequest::Cpu)
        .render(&request, 1, &|| false)
        .unwrap();
    let f = picture.figures;
    let editor = format!(
        "{} points (0.50 m border): Emin {:.1} lx, Eavg {:.1} lx, Emax {:.1} lx, U0 = Emin/Eavg {:.2}",
        f.points, f.e_min_lx, f.e_avg_lx, f.e_max_lx, f.u0
    );
    assert!(stdout.contains(&editor), "CLI: {stdout}\neditor: {editor}");
    assert_eq!(
        std::fs::read(&csv).unwrap(),
        picture.grid.csv().unwrap(),
        "the work-plane grids differ"
    );
}

#[test]
fn render_judges_the_work_plane_against_the_task_area_asked_or_suggested() {
    let dir = tempfile::tempdir().unwrap();
    let room = assets().join("rooms/office.toml");
    let png = dir.path().join("office.png");
    let run = |task: Option<&str>| {
        let mut args = vec![
            "render",
            room.to_str().unwrap(),
            "--out",
            png.to_str().unwrap(),
            "--size",
            "32x20",
            "--backend",
            "cpu",
        ];
        if let Some(t) = task {
            args.extend(["--task", t]);
        }
        lucerna(&args)
    };
    // The office's name suggests writing and reading: 500 lx, U0 0.60.
    let out = run(None);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let stdout = text(&out.stdout);
    let verdict = stdout
        .lines()
        .find(|l| l.starts_with("EN 12464-1 "))
        .unwrap_or_else(|| panic!("no verdict in {stdout}"));
    assert!(
        verdict.contains("writing, reading") && verdict.contains("Em 500 lx, U0 0.60"),
        "{verdict}"
    );
    let (e_avg, u0) = (figure(&stdout, "Eavg"), figure(&stdout, "Emin/Eavg"));
    let meets = e_avg >= 500.0 && u0 >= 0.60;
    assert!(
        verdict.ends_with(if meets { "meets" } else { "fails" }),
        "{verdict}"
    );
    // Corridors ask 100 lx and U0 0.40.
    let out = run(Some("corridors"));
    let stdout = text(&out.stdout);
    assert!(
        stdout.contains("Corridors, circulation areas (Em 100 lx, U0 0.40)"),
        "{stdout}"
    );
    // An unknown task is refused before anything is rendered, naming the
    // task areas there are.
    let _ = std::fs::remove_file(&png);
    let out = run(Some("spaceship bridge"));
    assert!(!out.status.success());
    let stderr = text(&out.stderr);
    assert!(
        stderr.contains("spaceship bridge") && stderr.contains("Classrooms"),
        "{stderr}"
    );
    assert!(!png.exists());
}
