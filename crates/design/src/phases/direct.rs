//! What the geometry can reach, and the point-source direct design.
//!
//! Before anything is searched: the LED's direct light through the
//! aperture is traced with the mirror black, and with what the mirror can
//! catch it gives the bound of [`crate::model::reach`]. The light the
//! mirror should make (the target less the direct light, the bound's best
//! split) is mapped onto a profile between the fixed ends by energy
//! balance, for both sweeps ([`crate::model::mapping`]); the profile gets
//! as many control points as the model says its detail needs.

use lucerna_scene::{Material, Scene};

use crate::history::Phase;
use crate::model::direct::mapped_profiles;
use crate::model::mapping::{Closure, MappedProfile, Sweep, control_points};
use crate::model::reach::{self, AxialLight, Reachability};
use crate::search::polish::{Measure, polish};
use crate::variables;

use super::{Context, Judged, PHASE_PHOTONS, ProfilePlan};

/// The fewest and most control points a designed profile gets, the
/// counts tried between, and the reference count the fits are compared
/// with.
pub const MIN_POINTS: usize = 3;
pub const MAX_POINTS: usize = 33;
const DEFAULT_LEAST_POINTS: usize = 5;
/// The most control points a profile is polished on in the model (the
/// mapping's family is many starts), how many of the polished the tracer
/// judges, and how far apart (the largest distance between their
/// control points) two must be to count as two.
const POLISH_POINTS: usize = 9;
const TRACED_STARTS: usize = 3;
const DISTINCT_M: f64 = 0.5e-3;
/// The polish's share of the time left, and the most it takes.
const POLISH_TIME_SHARE: f64 = 0.2;
const POLISH_TIME_MAX: std::time::Duration = std::time::Duration::from_secs(30);
const POLISH_MEASURES: [Measure; 2] = [Measure::Wasserstein, Measure::L2];
/// Depths (factors of the start's) for which the bound is stated again.
const DEEPER: [f64; 3] = [1.25, 1.5, 2.0];

/// What the direct design prepared before anything is traced as a
/// candidate.
#[derive(Debug, Clone)]
pub struct Prepared {
    pub reach: Reachability,
    /// The direct light (lamp candela on the target's nodes).
    pub direct: Vec<f64>,
    /// The light the mirror should make (target units on its nodes).
    pub wanted: Vec<f64>,
    pub mapped: Vec<MappedProfile>,
    /// The mapped profiles polished in the model, best first: (mapping,
    /// control points, model L2); without a model, as mapped.
    pub polished: Vec<(MappedProfile, Vec<[f64; 2]>, f64)>,
    pub points: usize,
}

/// A direct design traced.
#[derive(Debug, Clone)]
pub struct DirectDesign {
    pub sweep: Sweep,
    pub crossing_share: f64,
    pub closure: Closure,
    pub values: Vec<f64>,
    pub judged: Judged,
}

/// The bound, the mapped profiles and the point count (`requested`, or
/// what the model says the target's detail needs); None where the direct
/// light cannot be traced.
pub fn prepare(
    ctx: &mut Context,
    plan: &ProfilePlan,
    requested: Option<usize>,
) -> Option<Prepared> {
    let (direct, lamp_flux, escaped) = direct_light(ctx, plan)?;
    let axial = &plan.axial;
    let target = AxialLight {
        intensity: &axial.intensity,
        solid_angle_sr: &axial.solid_angle_sr,
    };
    let direct_light = AxialLight {
        intensity: &direct,
        solid_angle_sr: &axial.solid_angle_sr,
    };
    let reflected_max = plan.geometry.reflectance * (lamp_flux - escaped).max(0.0);
    let bound = reach::bound(&target, &direct_light, reflected_max, axial.absolute);
    let scale = if axial.absolute {
        1.0
    } else {
        axial.flux(&axial.intensity) / (direct_light.flux() + bound.reflected_flux).max(1e-300)
    };
    let scaled: Vec<f64> = direct.iter().map(|d| scale * d).collect();
    let wanted = reach::reflected_wanted(&target, &scaled, &bound);
    let reach = reachability(
        plan,
        &direct,
        lamp_flux,
        reflected_max,
        bound.relative_l2,
        ctx.request.free_ends,
    );
    let mapped = mapped_profiles(&plan.geometry, &axial.gammas_deg, &wanted);
    let start_profile = plan.profile(ctx, &ctx.start_values()).unwrap_or_default();
    let (polished, points) = match &plan.model {
        Some(model) => {
            let points = requested.unwrap_or_else(|| default_points(plan));
            let polished = polished(ctx, plan, model, &mapped, &start_profile, points);
            (polished, points)
        }
        None => {
            let points = requested.unwrap_or_else(|| default_points(plan));
            let as_mapped = mapped
                .iter()
                .map(|m| (m.clone(), control_points(&m.points, points), f64::NAN))
                .collect();
            (as_mapped, points)
        }
    };
    Some(Prepared {
        reach,
        direct,
        wanted,
        mapped,
        polished,
        points,
    })
}

/// The direct light on the target's nodes (lamp candela), the lamp flux
/// and the flux escaping with the mirror black.
fn direct_light(ctx: &mut Context, plan: &ProfilePlan) -> Option<(Vec<f64>, f64, f64)> {
    let black = blackened(&ctx.start, plan.geometry.part);
    let traced = ctx.evaluator.trace(&black, PHASE_PHOTONS).ok()?;
    let direct = crate::target::axial_nodes(&traced.table);
    Some((
        direct,
        traced.map.emitter_flux_lm,
        traced.map.escaped_flux_lm(),
    ))
}

/// `scene` with `part` an absorber.
fn blackened(scene: &Scene, part: usize) -> Scene {
    let mut black = scene.clone();
    let mut name = "black".to_owned();
    while black.materials.contains_key(&name) {
        name.push('_');
    }
    black.materials.insert(name.clone(), Material::Absorber);
    black.parts[part].material = name;
    black
}

/// The statement of what the geometry allows.
fn reachability(
    plan: &ProfilePlan,
    direct: &[f64],
    lamp_flux: f64,
    reflected_max: f64,
    bound: f64,
    ends_free: bool,
) -> Reachability {
    let axial = &plan.axial;
    let w = &axial.solid_angle_sr;
    let cone = plan.geometry.rim_theta().to_degrees();
    let direct_flux = axial.flux(direct);
    let inside = |light: &[f64], cone: f64| -> f64 {
        light
            .iter()
            .zip(w)
            .zip(&axial.gammas_deg)
            .filter(|(_, g)| **g <= cone)
            .map(|((l, w), _)| l * w)
            .sum()
    };
    let target_flux = axial.flux(&axial.intensity).max(1e-300);
    let bound_with = |direct: &[f64], reflected: f64| {
        reach::bound(
            &AxialLight {
                intensity: &axial.intensity,
                solid_angle_sr: w,
            },
            &AxialLight {
                intensity: direct,
                solid_angle_sr: w,
            },
            reflected,
            axial.absolute,
        )
        .relative_l2
    };
    let dark = vec![0.0; direct.len()];
    let with_cap = bound_with(&dark, plan.geometry.reflectance * lamp_flux);
    let [a, b] = plan.geometry.ends();
    let rim = if plan.geometry.source.polar(a).0 < plan.geometry.source.polar(b).0 {
        a
    } else {
        b
    };
    let (theta, rho) = plan.geometry.source.polar(rim);
    let (radius, depth) = (rho * theta.sin(), rho * theta.cos());
    let deeper = DEEPER
        .iter()
        .map(|&k| {
            let cone_k = radius.atan2(depth * k).to_degrees();
            let cut: Vec<f64> = direct
                .iter()
                .zip(&axial.gammas_deg)
                .map(|(d, g)| if *g <= cone_k { *d } else { 0.0 })
                .collect();
            let more = plan.geometry.reflectance * (direct_flux - axial.flux(&cut)).max(0.0);
            (k, cone_k, bound_with(&cut, reflected_max + more))
        })
        .collect();
    Reachability {
        direct_cone_deg: cone,
        direct_share: direct_flux / lamp_flux.max(1e-300),
        mirror_share_max: reflected_max / lamp_flux.max(1e-300),
        design_cone_share_min: inside(direct, cone) / (direct_flux + reflected_max).max(1e-300),
        target_cone_share: inside(&axial.intensity, cone) / target_flux,
        bound,
        with_cap,
        deeper,
        ends_free,
    }
}

/// The point count a design keeps unless asked for another: the start's
/// (at least [`DEFAULT_LEAST_POINTS`]). More points give the profile more
/// freedom, but each is two more coordinates for the refinement, whose
/// tracer-measured steps make the last factor of a needle's difference
/// (BENCHMARKS.md, "Design": the development set's profiles on 5, 9 and
/// 17 points); the report says when more points might help.
fn default_points(plan: &ProfilePlan) -> usize {
    plan.geometry
        .profile
        .len()
        .clamp(DEFAULT_LEAST_POINTS, MAX_POINTS)
}

/// Each mapped profile polished in the meridian model (on at most
/// [`POLISH_POINTS`] control points, the most promising first, on two
/// threads, until the phase's share of the time), the best few distinct
/// ones resampled to the context's point count and traced; the designs
/// traced, best first. Without a model, the mapped profiles as they are.
pub fn direct(ctx: &mut Context, plan: &ProfilePlan, prepared: &Prepared) -> Vec<DirectDesign> {
    let others = ctx.start_values();
    for (_, p, d) in &prepared.polished {
        if d.is_finite() {
            let values = plan.values(ctx, &resampled(p, plan, prepared.points), &others);
            ctx.history.record(
                Phase::Direct,
                0,
                Some(*d),
                "meridian model",
                values,
                ctx.progress,
            );
        }
    }
    let polished = prepared.polished.clone();
    let mut kept: Vec<(MappedProfile, Vec<[f64; 2]>, f64)> = Vec::new();
    for p in polished {
        if kept.len() < TRACED_STARTS
            && kept
                .iter()
                .all(|k| crate::search::global::farthest_apart_m(&k.1, &p.1) > DISTINCT_M)
        {
            kept.push(p);
        }
    }
    let mut out = Vec::new();
    for (m, profile, _) in kept {
        if ctx.spent().is_some() {
            break;
        }
        let values = plan.values(ctx, &resampled(&profile, plan, prepared.points), &others);
        if let Some(judged) = ctx.judge(Phase::Direct, &values, PHASE_PHOTONS) {
            out.push(DirectDesign {
                sweep: m.sweep,
                crossing_share: m.crossing_share,
                closure: m.closure,
                values,
                judged,
            });
        }
    }
    out.sort_by(|a, b| a.judged.merit.total_cmp(&b.judged.merit));
    out
}

/// Control points polished in the model, the start traced as well as
/// each mapping, best first: (mapping, profile, model L2).
fn polished(
    ctx: &Context,
    plan: &ProfilePlan,
    model: &crate::model::meridian::MeridianModel,
    mapped: &[MappedProfile],
    start: &[[f64; 2]],
    points: usize,
) -> Vec<(MappedProfile, Vec<[f64; 2]>, f64)> {
    let points = points.min(POLISH_POINTS);
    let l2 = |p: &[[f64; 2]]| {
        model.at_nodes(p).map_or(f64::INFINITY, |l| {
            plan.axial.relative_l2_between(&l, &plan.axial.intensity)
        })
    };
    let mut starts: Vec<(MappedProfile, Vec<[f64; 2]>, f64)> = mapped
        .iter()
        .map(|m| {
            let p = control_points(&m.points, points);
            let d = l2(&p);
            (m.clone(), p, d)
        })
        .collect();
    if let Some(first) = mapped.first() {
        let p = resampled(start, plan, points);
        let d = l2(&p);
        starts.push((
            MappedProfile {
                points: Vec::new(),
                ..first.clone()
            },
            p,
            d,
        ));
    }
    starts.sort_by(|a, b| a.2.total_cmp(&b.2));
    let now = std::time::Instant::now();
    let left = ctx.deadline().saturating_duration_since(now);
    // With an evaluation budget (a design that must not depend on the
    // machine's speed) every start is polished to its end.
    let deadline = if ctx.budget().evaluations.is_some() {
        ctx.deadline()
    } else {
        now + left.mul_f64(POLISH_TIME_SHARE).min(POLISH_TIME_MAX)
    };
    let next = std::sync::atomic::AtomicUsize::new(0);
    let done = std::sync::Mutex::new(Vec::new());
    let interrupt = ctx.interrupt;
    std::thread::scope(|scope| {
        for _ in 0..2 {
            scope.spawn(|| {
                loop {
                    let k = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                    if k >= starts.len() || std::time::Instant::now() >= deadline {
                        break;
                    }
                    let (m, p, _) = &starts[k];
                    let polished = polish(
                        model,
                        &plan.axial,
                        p.clone(),
                        &POLISH_MEASURES,
                        deadline,
                        interrupt,
                    );
                    if let (Some((q, d)), Ok(mut done)) = (polished, done.lock()) {
                        done.push((m.clone(), q, d));
                    }
                }
            });
        }
    });
    let mut out = done.into_inner().unwrap_or_default();
    out.sort_by(|a, b| a.2.total_cmp(&b.2));
    out
}

/// `profile` resampled to `points` control points on its own curve.
pub fn resampled(profile: &[[f64; 2]], plan: &ProfilePlan, points: usize) -> Vec<[f64; 2]> {
    if profile.len() == points {
        return profile.to_vec();
    }
    let curve: Vec<[f64; 2]> =
        lucerna_scene::profile::sample_profile(profile, plan.geometry.interpolation, 64)
            .iter()
            .flatten()
            .map(|s| s.point.to_array())
            .collect();
    control_points(&curve, points)
}

/// `ctx.start` with the varied profile resampled to `points` control
/// points on its own curve (the same light, within the fit), and the
/// variables parsed again on it.
pub fn resample(
    ctx: &mut Context,
    plan: &ProfilePlan,
    points: usize,
) -> Result<(), crate::DesignError> {
    let part = plan.geometry.part;
    let Some(profile) = variables::profile(&ctx.start.parts[part].shape) else {
        return Ok(());
    };
    if profile.len() == points {
        return Ok(());
    }
    let resampled = resampled(profile, plan, points);
    if let Some(p) = variables::profile_mut(&mut ctx.start.parts[part].shape) {
        *p = resampled;
    }
    ctx.variables = variables::parse(&ctx.start, &ctx.request.vary, ctx.request.free_ends)?;
    ctx.history.set_frame(crate::history::Frame {
        start: ctx.start.clone(),
        variables: ctx.variables.clone(),
    });
    Ok(())
}
