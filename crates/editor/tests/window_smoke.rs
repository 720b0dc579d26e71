#![allow(clippy::unwrap_used, clippy::expect_used)] // reason: tests may panic
//! The real `lucerna-editor` binary in a real X server (Xvfb): it opens its
//! window on an example, traces for a few seconds, shows something (a
//! screenshot that is not one flat colour) and quits cleanly on Ctrl+Q.
//! The kittest tests never create a window or a wgpu surface; this one
//! does, so a broken window path fails CI. `.ci/run` installs Xvfb,
//! xdotool and ImageMagick; without them the test is skipped locally and
//! fails under CI.

use std::io::BufRead;
use std::path::Path;
use std::process::{Child, Command, ExitStatus, Stdio};
use std::time::{Duration, Instant};

fn on_path(program: &str) -> bool {
    std::env::var_os("PATH")
        .is_some_and(|path| std::env::split_paths(&path).any(|dir| dir.join(program).is_file()))
}

/// Kills the child when dropped, so a failing assertion leaves no Xvfb or
/// editor behind.
struct Reaped(Child);

impl Drop for Reaped {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

fn wait_timeout(child: &mut Child, timeout: Duration) -> Option<ExitStatus> {
    let deadline = Instant::now() + timeout;
    while Instant::now() < deadline {
        if let Some(status) = child.try_wait().unwrap() {
            return Some(status);
        }
        std::thread::sleep(Duration::from_millis(50));
    }
    None
}

fn xdotool(display: &str, args: &[&str]) -> std::process::Output {
    Command::new("xdotool")
        .args(args)
        .env("DISPLAY", display)
        .output()
        .unwrap()
}

fn log_of(dir: &Path) -> String {
    let read = |name| std::fs::read_to_string(dir.join(name)).unwrap_or_default();
    format!(
        "editor stdout:\n{}\neditor stderr:\n{}",
        read("stdout"),
        read("stderr")
    )
}

#[test]
fn the_editor_opens_traces_shows_the_scene_and_quits_on_ctrl_q() {
    let missing: Vec<&str> = ["Xvfb", "xdotool", "import", "identify"]
        .into_iter()
        .filter(|p| !on_path(p))
        .collect();
    if !missing.is_empty() {
        assert!(
            std::env::var_os("CI").is_none(),
            "CI must run the editor under Xvfb, but {missing:?} are not installed \
             (.ci/run installs xvfb x11-apps imagemagick xdotool)"
        );
        println!("skipped: Xvfb not installed ({missing:?} missing)");
        return;
    }
    let work = tempfile::tempdir().unwrap();
    // Xvfb picks a free display itself and writes its number once it
    // accepts clients: no race with other X servers starting meanwhile.
    let mut xvfb = Reaped(
        Command::new("Xvfb")
            .args([
                "-displayfd",
                "1",
                "-screen",
                "0",
                "1366x768x24",
                "-nolisten",
                "tcp",
            ])
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .unwrap(),
    );
    let mut number = String::new();
    std::io::BufReader::new(xvfb.0.stdout.take().unwrap())
        .read_line(&mut number)
        .unwrap();
    let number: u32 = number
        .trim()
        .parse()
        .unwrap_or_else(|_| panic!("Xvfb did not report a display: {number:?}"));
    let display = format!(":{number}");

    let example =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/luminaires/parabolic_spot.toml");
    let config = work.path().join("config");
    let mut editor = Reaped(
        Command::new(env!("CARGO_BIN_EXE_lucerna-editor"))
            .arg(&example)
            .env("DISPLAY", &display)
            .env_remove("WAYLAND_DISPLAY")
            .env("NODEVICE_SELECT", "1")
            // Its recent files and recovery file stay out of the real home.
            .env("XDG_CONFIG_HOME", &config)
            .stdin(Stdio::null())
            .stdout(std::fs::File::create(work.path().join("stdout")).unwrap())
            .stderr(std::fs::File::create(work.path().join("stderr")).unwrap())
            .spawn()
            .unwrap(),
    );

    // The window appears (a debug build on a software adapter takes a while)…
    let deadline = Instant::now() + Duration::from_secs(90);
    loop {
        if let Some(status) = editor.0.try_wait().unwrap() {
            panic!("the editor exited early: {status}\n{}", log_of(work.path()));
        }
        let found = xdotool(&display, &["search", "--name", "Lucerna editor"]);
        if found.status.success() && !found.stdout.is_empty() {
            break;
        }
        assert!(
            Instant::now() < deadline,
            "no editor window after 90 s\n{}",
            log_of(work.path())
        );
        std::thread::sleep(Duration::from_millis(200));
    }
    // …and the editor traces for a few seconds without dying.
    std::thread::sleep(Duration::from_secs(5));
    if let Some(status) = editor.0.try_wait().unwrap() {
        panic!(
            "the editor died while tracing: {status}\n{}",
            log_of(work.path())
        );
    }

    let shot = work.path().join("editor.png");
    let import = Command::new("import")
        .args(["-window", "root"])
        .arg(&shot)
        .env("DISPLAY", &display)
        .output()
        .unwrap();
    assert!(import.status.success(), "import failed: {import:?}");
    // Kept for a look by hand.
    let kept = Path::new(env!("CARGO_TARGET_TMPDIR")).join("window_smoke.png");
    let _ = std::fs::copy(&shot, &kept);
    let bytes = std::fs::read(&shot).unwrap();
    assert!(bytes.starts_with(b"\x89PNG\r\n\x1a\n"), "not a PNG");
    let colours = Command::new("identify")
        .args(["-format", "%k"])
        .arg(&shot)
        .output()
        .unwrap();
    let colours: u64 = String::from_utf8_lossy(&colours.stdout)
        .trim()
        .parse()
        .unwrap();
    // A black screen has one colour; panels, text and the false-colour
    // views have hundreds.
    assert!(
        colours > 50,
        "the screenshot ({}) has only {colours} colours",
        kept.display()
    );

    // Ctrl+Q quits cleanly (no window manager: focus the window by hand).
    xdotool(&display, &["mousemove", "683", "384"]);
    xdotool(
        &display,
        &["search", "--name", "Lucerna editor", "windowfocus"],
    );
    xdotool(&display, &["key", "ctrl+q"]);
    let status = match wait_timeout(&mut editor.0, Duration::from_secs(20)) {
        Some(status) => status,
        None => panic!(
            "the editor did not quit within 20 s of Ctrl+Q\n{}",
            log_of(work.path())
        ),
    };
    assert!(
        status.success(),
        "the editor exited with {status}\n{}",
        log_of(work.path())
    );
    // A clean exit leaves nothing to recover.
    assert!(!config.join("lucerna/recovery.toml").exists());
}
