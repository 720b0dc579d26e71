//! A mutation fuzzer for every file Lucerna reads, in the tree and on
//! stable Rust: seeds from `assets/` and the regression corpus, mutated
//! the way hostile files differ from good ones (extreme numbers in place
//! of numbers, lines lost, repeated or swapped, truncation, stray bytes,
//! other line ends), each fed to a target that checks the invariants:
//! no panic; a file that reads gives finite figures; what Lucerna writes,
//! Lucerna reads back with the same flux and peak.
//!
//! `cargo test -p lucerna-fuzz` runs a CI-sized campaign; the
//! `lucerna-fuzz` binary runs long ones (README, "Fuzzing").

use std::panic::AssertUnwindSafe;
use std::path::{Path, PathBuf};

pub mod mutate;
pub mod rays;
pub mod targets;

pub use mutate::{Rng, mutate};

/// A file kind the fuzzer feeds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Target {
    /// IES and EULUMDAT files through `read_photometry`, then written and
    /// read back.
    Photometry,
    /// A luminaire scene (TOML) with an OBJ mesh and its MTL, loaded,
    /// validated and tessellated.
    Scene,
    /// A room file, loaded and validated.
    Room,
    /// A TM-25 ray file, read, its far field tabulated, written and read
    /// back with the same rays.
    RayFile,
}

impl Target {
    pub const ALL: [Target; 4] = [
        Target::Photometry,
        Target::Scene,
        Target::Room,
        Target::RayFile,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Target::Photometry => "photometry",
            Target::Scene => "scene",
            Target::Room => "room",
            Target::RayFile => "rayfile",
        }
    }
}

/// An input that broke an invariant.
#[derive(Debug, Clone)]
pub struct Finding {
    pub target: Target,
    /// What went wrong: the panic message or the broken invariant.
    pub what: String,
    /// The files of the input (name, bytes).
    pub files: Vec<(String, Vec<u8>)>,
}

/// The workspace's `assets/` folder.
pub fn assets() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets")
}

/// The committed regression inputs of a target (`corpus/TARGET/`).
pub fn corpus_dir(target: Target) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("corpus")
        .join(target.name())
}

/// Runs `check` on `files`, turning a panic into a finding.
pub fn run_case(
    target: Target,
    files: Vec<(String, Vec<u8>)>,
    check: impl FnOnce(&[(String, Vec<u8>)]) -> Result<(), String>,
) -> Option<Finding> {
    // reason: the harness reports panics as findings; product code never
    // relies on catching them.
    let result = std::panic::catch_unwind(AssertUnwindSafe(|| check(&files)));
    let what = match result {
        Ok(Ok(())) => return None,
        Ok(Err(broken)) => broken,
        Err(payload) => format!(
            "panic: {}",
            payload
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| payload.downcast_ref::<&str>().map(|s| (*s).to_owned()))
                .unwrap_or_default()
        ),
    };
    Some(Finding {
        target,
        what,
        files,
    })
}

/// A campaign: `inputs` mutated cases of `target` from `seed`, plus every
/// seed and regression input as it is.
pub fn campaign(target: Target, inputs: usize, seed: u64) -> Vec<Finding> {
    let seeds = targets::seeds(target);
    let mut rng = Rng::new(seed);
    let mut findings = Vec::new();
    for case in &seeds {
        findings.extend(targets::run(target, case.clone()));
    }
    if seeds.is_empty() {
        return findings;
    }
    for k in 0..inputs {
        // Every fourth ray file built field by field rather than mutated.
        if target == Target::RayFile && k % 4 == 3 {
            let (bytes, promise) = rays::structured_ray_file(&mut rng);
            findings.extend(run_case(
                target,
                vec![("rays.tm25ray".to_owned(), bytes)],
                |files| targets::ray_file_promised(&files[0].1, &promise),
            ));
            continue;
        }
        let mut case = seeds[rng.below(seeds.len())].clone();
        // Mutate one file of the case, now and then twice.
        for _ in 0..1 + usize::from(rng.below(4) == 0) {
            let k = rng.below(case.len());
            case[k].1 = mutate(&case[k].1, &mut rng);
        }
        findings.extend(targets::run(target, case));
    }
    findings
}
