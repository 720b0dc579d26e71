//! The PDF writer against a reader: poppler (pdftotext, pdftoppm) finds
//! the text where the elements put it, anchored as asked, reads it back
//! as the same characters, and paints shapes where and in the colour
//! they were drawn. Without poppler the tests say so and pass, except
//! under CI, which installs it.

use std::path::Path;
use std::process::Command;

use lucerna_datasheet::pdf::pdf_of_pages;
use lucerna_datasheet::svg::{Anchor, Rgb, Svg, text_width_pt};

/// Runs a poppler tool; `None` when it is not installed outside CI.
fn poppler(tool: &str, args: &[&str]) -> Option<Vec<u8>> {
    match Command::new(tool).args(args).output() {
        Ok(out) => {
            assert!(
                out.status.success(),
                "{tool} failed: {}",
                String::from_utf8_lossy(&out.stderr)
            );
            Some(out.stdout)
        }
        Err(e) if std::env::var_os("CI").is_none() => {
            eprintln!("{tool} not found ({e}): PDF not read back");
            None
        }
        Err(e) => panic!("{tool} is needed under CI: {e}"),
    }
}

fn write_pdf(dir: &Path, pages: &[Svg]) -> String {
    let pdf = pdf_of_pages(pages, "Test – sheet").expect("pdf");
    let path = dir.join("sheet.pdf");
    std::fs::write(&path, pdf).expect("write");
    path.to_str().expect("utf-8").to_owned()
}

/// pdftotext -bbox's words: (text, xMin, yMin, xMax, yMax) in points
/// from the page's top-left corner.
fn words(bbox_html: &str) -> Vec<(String, [f64; 4])> {
    let attr = |w: &str, name: &str| -> f64 {
        let start = w.find(&format!("{name}=\"")).expect("attribute") + name.len() + 2;
        let end = start + w[start..].find('"').expect("quote");
        w[start..end].parse().expect("number")
    };
    bbox_html
        .split("<word ")
        .skip(1)
        .map(|w| {
            let start = w.find('>').expect(">") + 1;
            let end = w.find("</word>").expect("</word>");
            let text = w[start..end]
                .replace("&amp;", "&")
                .replace("&lt;", "<")
                .replace("&gt;", ">");
            (
                text,
                [
                    attr(w, "xMin"),
                    attr(w, "yMin"),
                    attr(w, "xMax"),
                    attr(w, "yMax"),
                ],
            )
        })
        .collect()
}

#[test]
fn text_is_where_its_anchor_puts_it_and_reads_back_as_written() {
    let dir = tempfile::tempdir().expect("dir");
    let mut svg = Svg::new();
    let size = 20.0;
    // Kerned pairs (AV, Te) and characters beyond ASCII.
    svg.text(100.0, 200.0, size, Anchor::Start, Rgb(0x1a1a1a), "AVATe");
    svg.text(500.0, 300.0, size, Anchor::End, Rgb(0x1a1a1a), "γ=12.5°");
    svg.text(300.0, 400.0, size, Anchor::Middle, Rgb(0x1a1a1a), "cd/m²");
    let path = write_pdf(dir.path(), &[svg]);
    let Some(html) = poppler("pdftotext", &["-bbox", &path, "-"]) else {
        return;
    };
    let words = words(&String::from_utf8(html).expect("utf-8"));
    let expect = [
        ("AVATe", 100.0, 200.0, 0.0),
        ("γ=12.5°", 500.0, 300.0, 1.0),
        ("cd/m²", 300.0, 400.0, 0.5),
    ];
    assert_eq!(words.len(), expect.len(), "{words:?}");
    for ((text, [x_min, y_min, x_max, y_max]), (want, x, y, before)) in words.iter().zip(expect) {
        assert_eq!(text, want);
        let width = text_width_pt(want, size);
        let left = x - before * width;
        // Poppler's box spans the glyphs' advances, kerning included.
        assert!(
            (x_min - left).abs() < 0.3,
            "{want}: xMin {x_min}, expected {left}"
        );
        assert!(
            (x_max - (left + width)).abs() < 0.3,
            "{want}: xMax {x_max}, expected {}",
            left + width
        );
        assert!(
            *y_min < y && y < *y_max,
            "{want}: baseline {y} outside {y_min}..{y_max}"
        );
        assert!(
            y - y_min > 0.6 * size,
            "{want}: the text hangs below its baseline"
        );
    }
}

#[test]
fn shapes_are_painted_where_and_as_drawn() {
    let dir = tempfile::tempdir().expect("dir");
    let mut svg = Svg::new();
    svg.rect(50.0, 100.0, 100.0, 50.0, Rgb(0x0000ff), Rgb(0x0000ff));
    svg.polygon(
        &[
            [300.0, 100.0],
            [400.0, 100.0],
            [400.0, 200.0],
            [300.0, 200.0],
        ],
        Rgb(0xff0000),
        0.5,
    );
    svg.line(50.0, 400.0, 550.0, 400.0, Rgb(0x00a000), 4.0);
    svg.circle(300.0, 600.0, 80.0, Rgb(0x000000), 3.0);
    let path = write_pdf(dir.path(), &[svg]);
    let prefix = dir.path().join("page");
    // 72 dpi: one pixel a point.
    if poppler(
        "pdftoppm",
        &["-r", "72", "-png", &path, prefix.to_str().expect("utf-8")],
    )
    .is_none()
    {
        return;
    }
    let image = image::open(dir.path().join("page-1.png"))
        .expect("png")
        .to_rgb8();
    let at = |x: u32, y: u32| image.get_pixel(x, y).0;
    let near = |got: [u8; 3], want: [u8; 3]| got.iter().zip(want).all(|(g, w)| g.abs_diff(w) <= 3);
    assert!(near(at(100, 125), [0, 0, 255]), "rect {:?}", at(100, 125));
    assert!(
        near(at(30, 125), [255, 255, 255]),
        "left of the rect {:?}",
        at(30, 125)
    );
    // Half-transparent red over white.
    let half = at(350, 150);
    assert!(
        half[0] == 255 && (125..=130).contains(&half[1]) && half[1] == half[2],
        "polygon {half:?}"
    );
    assert!(near(at(300, 400), [0, 160, 0]), "line {:?}", at(300, 400));
    assert!(
        near(at(300, 408), [255, 255, 255]),
        "below the line {:?}",
        at(300, 408)
    );
    // The circle's outline at four points of its radius, empty inside.
    for (x, y) in [(380, 600), (220, 600), (300, 520), (300, 680)] {
        assert!(at(x, y)[0] < 80, "circle at ({x}, {y}) {:?}", at(x, y));
    }
    assert!(near(at(300, 600), [255, 255, 255]), "inside the circle");
}

#[test]
fn a_sheet_reads_back_as_its_text() {
    let dir = tempfile::tempdir().expect("dir");
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../assets/profiles/examples/parabolic_spot.ies");
    let p = lucerna_photometry::read_photometry(&std::fs::read(path).expect("file"))
        .expect("photometry");
    let sheet =
        lucerna_datasheet::Datasheet::new(&p, &lucerna_datasheet::DatasheetOptions::default())
            .expect("sheet");
    let rendered = sheet.render().expect("renders");
    let file = dir.path().join("spot.pdf");
    std::fs::write(&file, &rendered.pdf).expect("write");
    let Some(text) = poppler("pdftotext", &[file.to_str().expect("utf-8"), "-"]) else {
        return;
    };
    let text = String::from_utf8(text).expect("utf-8");
    for phrase in [
        "Photometric datasheet",
        "page 3 of 3",
        "Cartesian diagram",
        "Luminance (cd/m²)",
        "UGR",
    ] {
        assert!(text.contains(phrase), "{phrase:?} not in the PDF's text");
    }
    assert!(
        text.contains('γ') && text.contains('°'),
        "Greek and degree signs lost"
    );
}
