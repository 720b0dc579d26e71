//! A CI-sized fuzzing campaign (a few thousand inputs) and the regression
//! corpus: zero findings.

use lucerna_fuzz::{Target, campaign};

fn no_findings(target: Target, inputs: usize) {
    std::panic::set_hook(Box::new(|_| {}));
    let findings = campaign(target, inputs, 20_261_201);
    let _ = std::panic::take_hook();
    let report: Vec<String> = findings
        .iter()
        .take(5)
        .map(|f| format!("{}: {}", f.target.name(), f.what))
        .collect();
    assert!(
        findings.is_empty(),
        "{} findings, e.g.\n{}",
        findings.len(),
        report.join("\n")
    );
}

#[test]
fn photometric_files() {
    no_findings(Target::Photometry, 3000);
}

#[test]
fn scene_files() {
    no_findings(Target::Scene, 600);
}

#[test]
fn room_files() {
    no_findings(Target::Room, 600);
}

#[test]
fn ray_files() {
    no_findings(Target::RayFile, 600);
}
