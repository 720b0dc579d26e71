//! Design from the light you want: a luminaire's shape parameters or a
//! reflector's profile shaped toward a target distribution (an IES or
//! EULUMDAT file) or a spec of figures (beam, field, cut-off, LOR, UGR).
//!
//! Where a revolved profile is varied toward a rotationally symmetric
//! target, a direct design for a point source at the emitter gives the
//! start in milliseconds ([`direct`]); then the photon tracer in the loop
//! corrects it for the real extended source and package ([`optimise`]:
//! Nelder–Mead on common random numbers, in stages of growing photon
//! counts, pooled over the luminaire's symmetry). [`output`] writes the
//! designed scene (the start scene's file with the values replaced), its
//! bake, the design's history and its picture, all or none.

pub mod direct;
pub mod evaluate;
pub mod least_squares;
pub mod merit;
pub mod optimise;
pub mod outcome;
pub mod output;
pub mod picture;
pub mod target;
pub mod variables;

use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;

use lucerna_photometry::AxialSymmetry;
use lucerna_scene::{Scene, Shape, parse_scene};
use lucerna_simulation::Luminaire;

pub use optimise::{Budget, Found, Progress, Record, Stopped};
pub use target::{Maximise, Spec, Target};
pub use variables::Variable;

use crate::evaluate::Evaluator;
use crate::merit::Aim;

/// Why a design could not start or could not be written.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum DesignError {
    #[error("cannot load the scene {path}")]
    Scene {
        path: String,
        #[source]
        source: lucerna_scene::LoadSceneError,
    },
    #[error("the scene {path} cannot be traced")]
    Prepare {
        path: String,
        #[source]
        source: Box<lucerna_simulation::SimulationError>,
    },
    #[error("target {path}: {why}")]
    Target { path: String, why: String },
    #[error("--vary {what}: {why}")]
    Vary { what: String, why: String },
    #[error("the time for a design must be positive")]
    Time,
    #[error("the start scene itself cannot be traced: {0}")]
    Start(String),
    #[error("the design's files cannot be made: {0}")]
    Output(String),
    #[error("cannot write {path}")]
    Write {
        path: String,
        #[source]
        source: std::io::Error,
    },
}

/// Everything a design needs.
#[derive(Debug, Clone)]
pub struct DesignRequest {
    pub scene_path: PathBuf,
    pub target: Target,
    /// `PART.FIELD` or `PART.profile`.
    pub vary: Vec<String>,
    /// Frees a profile's end points.
    pub free_ends: bool,
    pub budget: Budget,
    pub seed: u32,
    /// Texels per cube-face edge of the candidates' maps.
    pub resolution: u32,
    /// Start a varied revolved profile from the point-source direct design.
    pub direct: bool,
    /// Fit a distribution by damped least squares instead of Nelder–Mead.
    pub least_squares: bool,
}

/// A finished design.
#[derive(Debug, Clone)]
pub struct Design {
    /// The start scene, its file's text and folder.
    pub start: Scene,
    pub start_text: String,
    pub scene_dir: PathBuf,
    pub variables: Vec<Variable>,
    /// The start's merit at the first stage's photons.
    pub start_merit: f64,
    /// The direct design's values and merit, where one was made.
    pub direct: Option<(Vec<f64>, f64)>,
    pub found: Found,
    /// The designed scene.
    pub scene: Scene,
    pub aim: Aim,
    pub symmetry: AxialSymmetry,
    pub seed: u32,
    pub resolution: u32,
    pub lamp_flux_lm: f64,
}

/// Loads, checks and runs a design; `progress` hears of every traced
/// candidate, `interrupt` stops it with the best so far.
pub fn design(
    request: &DesignRequest,
    interrupt: &AtomicBool,
    progress: &mut dyn FnMut(&Progress),
) -> Result<Design, DesignError> {
    if request.budget.time.is_zero() {
        return Err(DesignError::Time);
    }
    let path = &request.scene_path;
    let scene_err = |source| DesignError::Scene {
        path: path.display().to_string(),
        source,
    };
    let start_text =
        lucerna_scene::read_limited_text(path, lucerna_scene::file::MAX_SCENE_FILE_BYTES)
            .map_err(|e| scene_err(lucerna_scene::LoadSceneError::from(e)))?;
    let start = parse_scene(&start_text, path).map_err(scene_err)?;
    let scene_dir = path.parent().unwrap_or(Path::new(".")).to_path_buf();
    let variables = variables::parse(&start, &request.vary, request.free_ends)?;
    let luminaire =
        Luminaire::new(start.clone(), &scene_dir).map_err(|source| DesignError::Prepare {
            path: path.display().to_string(),
            source: Box::new(source),
        })?;
    // Pooled over the start's symmetry where every varied part is a
    // surface of revolution about the axis (which varying keeps);
    // otherwise not at all.
    let keeps_symmetry = variables.iter().all(|v| {
        let part = match &v.place {
            variables::Place::Field { part, .. } | variables::Place::ProfilePoint { part, .. } => {
                &start.parts[*part]
            }
        };
        let about_axis = part.transform.translate[0] == 0.0
            && part.transform.translate[1] == 0.0
            && part.transform.rotate_deg[0] == 0.0
            && part.transform.rotate_deg[1] == 0.0;
        about_axis
            && matches!(
                part.shape,
                Shape::Paraboloid(_)
                    | Shape::Ellipsoid(_)
                    | Shape::Revolved(_)
                    | Shape::Dome(_)
                    | Shape::Cylinder(_)
                    | Shape::Disk(_)
            )
    });
    let symmetry = if keeps_symmetry {
        luminaire.find_symmetry().symmetry
    } else {
        AxialSymmetry::None
    };
    let lamp_flux_lm = luminaire.prepared.total_flux_lm;
    let aim = Aim::new(request.target.clone());
    let mut evaluator = Evaluator::new(
        &scene_dir,
        request.seed,
        request.resolution,
        symmetry,
        &variables,
        aim.grid(),
    );
    let start_values: Vec<f64> = variables.iter().map(|v| v.start).collect();
    let trace = |e: &mut Evaluator, values: &[f64]| -> Option<f64> {
        let scene = variables::apply(&start, &variables, values)?;
        let t = e.trace(&scene, optimise::FIRST_STAGE_PHOTONS).ok()?;
        Some(optimise::merit_of(&aim, &t, lamp_flux_lm, &t.opening))
    };
    let start_merit = trace(&mut evaluator, &start_values).ok_or_else(|| {
        DesignError::Start(
            evaluator
                .check(&start)
                .err()
                .map_or("it is refused".to_owned(), |r| r.to_string()),
        )
    })?;
    // The direct design, where it applies, replaces the start if it is
    // better.
    let direct = if request.direct {
        direct::designs(&start, &variables, &request.target)
            .into_iter()
            .filter(|values| {
                values
                    .iter()
                    .zip(&variables)
                    .all(|(&x, v)| (v.lower..=v.upper).contains(&x))
            })
            .filter_map(|values| Some((values.clone(), trace(&mut evaluator, &values)?)))
            .min_by(|a, b| a.1.total_cmp(&b.1))
    } else {
        None
    };
    let x0: Vec<f64> = match &direct {
        Some((values, m)) if *m < start_merit => values,
        _ => &start_values,
    }
    .iter()
    .zip(&variables)
    .map(|(&x, v)| v.fraction(x))
    .collect();
    // A distribution is a sum of squares: damped least squares on its
    // residuals; a spec's terms are not, Nelder–Mead on its merit.
    let found = match &request.target {
        Target::Distribution { .. } if request.least_squares => least_squares::fit(
            &start,
            &variables,
            x0,
            &aim,
            &mut evaluator,
            request.budget,
            interrupt,
            progress,
        ),
        _ => optimise::optimise(
            &start,
            &variables,
            x0,
            &aim,
            &mut evaluator,
            lamp_flux_lm,
            request.budget,
            interrupt,
            progress,
        ),
    };
    let values = output::rounded(&variables, &found.values);
    let scene = variables::apply(&start, &variables, &values)
        .ok_or_else(|| DesignError::Output("the designed values do not apply".to_owned()))?;
    Ok(Design {
        start,
        start_text,
        scene_dir,
        variables,
        start_merit,
        direct,
        found: Found { values, ..found },
        scene,
        aim,
        symmetry,
        seed: request.seed,
        resolution: request.resolution,
        lamp_flux_lm,
    })
}
