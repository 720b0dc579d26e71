//! `lucerna-editor --benchmark-drag SECONDS SCENE`: the core gesture,
//! measured in the real window. After the first preview and 1.5 s of
//! settling, a scripted drag changes one generator parameter of the
//! luminaire's main part every frame for SECONDS (a ramp to 92 % of its
//! value, as a hand drags a focal length down; a finished part's dimple
//! depth, wave amplitude or slope spread; a trough 5 mm deeper; a
//! mesh part 5 mm lower), exactly as a held
//! DragValue does (the editor sees a pointer gesture: coarse preview, one
//! undo step); then it is released and the benchmark waits for the first
//! preview at the chosen resolution. Printed at the end:
//! - drag start to the first frame showing a preview of the drag;
//! - preview age: for every frame of the drag from then on, the time since
//!   the edit whose snapshot the frame shows was made (median, p95);
//! - preview lag: for every frame of the drag, the time since the shown
//!   snapshot went out of date (the first edit it does not show; zero
//!   while it shows the newest);
//! - distinct previews shown per second during the drag;
//! - release to the first full-resolution preview;
//! - the frame interval during the drag (median, p95) and the longest.

use std::time::{Duration, Instant};

use lucerna_scene::{Scene, Shape};

use super::Quantiles;
use crate::state::EditorState;

/// Settling time between the first preview and the drag.
const SETTLE: Duration = Duration::from_millis(1500);
/// How long to wait after the release for the full-resolution preview.
const RELEASE_TIMEOUT: Duration = Duration::from_secs(5);
/// The dragged parameter ends at this fraction of its start.
const RAMP_TO: f64 = 0.92;

/// What the drag changes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum DragTarget {
    /// A scalar shape parameter of part `part`, named as the panel names
    /// it, from `start` to `end`.
    Parameter {
        part: usize,
        name: &'static str,
        start: f64,
        end: f64,
    },
    /// The part's height (a mesh has no generator parameter).
    Height { part: usize, start: f64 },
    /// The main number of the part's finish (dimple depth, first wave's
    /// amplitude, slope σ along, a height map's height per level).
    Finish { part: usize, start: f64, end: f64 },
}

impl DragTarget {
    /// The luminaire's main generated part (a reflector if there is one)
    /// and its main parameter; a mesh part's height otherwise.
    pub fn choose(scene: &Scene) -> Option<DragTarget> {
        let rank = |shape: &Shape| match shape {
            Shape::Paraboloid(_) | Shape::Ellipsoid(_) | Shape::Revolved(_) => 0,
            Shape::Extruded(_) | Shape::Dome(_) => 1,
            Shape::Louvre(_) | Shape::Cylinder(_) => 2,
            Shape::Plate(_) | Shape::Disk(_) | Shape::Box(_) => 3,
            Shape::Mesh(_) => 4,
        };
        let (part, p) = scene
            .parts
            .iter()
            .enumerate()
            .min_by_key(|(_, p)| rank(&p.shape))?;
        if let Some(f) = &p.finish {
            use lucerna_scene::finish::Finish;
            let start = match f {
                Finish::Dimples { depth, .. } => *depth,
                Finish::Ripples { waves } => waves.first()?.amplitude,
                Finish::Slopes { sigma_u, .. } => *sigma_u,
                Finish::HeightMap { height_step, .. } => *height_step,
                Finish::Facets { size_along, .. } => *size_along,
            };
            return Some(DragTarget::Finish {
                part,
                start,
                end: start * RAMP_TO,
            });
        }
        let parameter = |name, start: f64| DragTarget::Parameter {
            part,
            name,
            start,
            end: start * RAMP_TO,
        };
        Some(match &p.shape {
            Shape::Paraboloid(s) => parameter("focal length", s.focal_length),
            Shape::Ellipsoid(s) => parameter("focal distance", s.focal_distance),
            Shape::Revolved(s) => parameter("profile point radius", middle_point(&s.profile)?[0]),
            // A trough's middle point sits on its axis (x = 0): deepen it
            // by 5 mm instead.
            Shape::Extruded(s) => {
                let z = middle_point(&s.profile)?[1];
                DragTarget::Parameter {
                    part,
                    name: "profile point z",
                    start: z,
                    end: z - 0.005,
                }
            }
            Shape::Dome(s) => parameter("height", s.height),
            Shape::Louvre(s) => parameter("spacing", s.spacing),
            Shape::Cylinder(s) => parameter("radius", s.radius),
            Shape::Plate(s) => parameter("width", s.width),
            Shape::Disk(s) => parameter("radius", s.radius),
            Shape::Box(_) | Shape::Mesh(_) => DragTarget::Height {
                part,
                start: p.transform.translate[2],
            },
        })
    }

    /// Sets the dragged value to `fraction` of the way from its start to
    /// its end.
    pub fn set(&self, scene: &mut Scene, fraction: f64) {
        let fraction = fraction.clamp(0.0, 1.0);
        match *self {
            DragTarget::Parameter {
                part, start, end, ..
            } => {
                let Some(p) = scene.parts.get_mut(part) else {
                    return;
                };
                let value = start + (end - start) * fraction;
                match &mut p.shape {
                    Shape::Paraboloid(s) => s.focal_length = value,
                    Shape::Ellipsoid(s) => s.focal_distance = value,
                    Shape::Revolved(s) => set_middle_point(&mut s.profile, 0, value),
                    Shape::Extruded(s) => set_middle_point(&mut s.profile, 1, value),
                    Shape::Dome(s) => s.height = value,
                    Shape::Louvre(s) => s.spacing = value,
                    Shape::Cylinder(s) => s.radius = value,
                    Shape::Plate(s) => s.width = value,
                    Shape::Disk(s) => s.radius = value,
                    Shape::Box(_) | Shape::Mesh(_) => {}
                }
            }
            DragTarget::Height { part, start } => {
                if let Some(p) = scene.parts.get_mut(part) {
                    // 5 mm down over the drag.
                    p.transform.translate[2] = start - 0.005 * fraction;
                }
            }
            DragTarget::Finish { part, start, end } => {
                use lucerna_scene::finish::Finish;
                let value = start + (end - start) * fraction;
                match scene.parts.get_mut(part).and_then(|p| p.finish.as_mut()) {
                    Some(Finish::Dimples { depth, .. }) => *depth = value,
                    Some(Finish::Ripples { waves }) => {
                        if let Some(w) = waves.first_mut() {
                            w.amplitude = value;
                        }
                    }
                    Some(Finish::Slopes { sigma_u, .. }) => *sigma_u = value,
                    Some(Finish::HeightMap { height_step, .. }) => *height_step = value,
                    Some(Finish::Facets { size_along, .. }) => *size_along = value,
                    None => {}
                }
            }
        }
    }

    pub fn describe(&self, scene: &Scene) -> String {
        let (part, name) = match *self {
            DragTarget::Parameter { part, name, .. } => (part, name),
            DragTarget::Height { part, .. } => (part, "height (translate z)"),
            DragTarget::Finish { part, .. } => (part, "finish (dimple depth, wave amplitude, σ)"),
        };
        let part = scene.parts.get(part).map_or("?", |p| p.name.as_str());
        format!("{part}: {name}")
    }
}

fn middle_point(profile: &[[f64; 2]]) -> Option<[f64; 2]> {
    profile.get(profile.len() / 2).copied()
}

fn set_middle_point(profile: &mut [[f64; 2]], coordinate: usize, value: f64) {
    let middle = profile.len() / 2;
    if let Some(p) = profile.get_mut(middle) {
        p[coordinate] = value;
    }
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Phase {
    /// Until the first snapshot.
    Loading,
    Settling {
        since: Instant,
    },
    Dragging {
        since: Instant,
    },
    /// Released at `at`; waiting for generation `generation` at full
    /// resolution.
    Released {
        at: Instant,
        generation: u64,
    },
    Done,
}

/// A running drag benchmark.
#[derive(Debug)]
pub struct DragBenchmark {
    drag: Duration,
    phase: Phase,
    target: Option<DragTarget>,
    described: String,
    last_frame: Option<Instant>,
    /// The frame whose edit made each generation (the newest last).
    sent: Vec<(u64, Instant)>,
    last_generation: u64,
    /// When this frame's edit was made, until the next frame sees its
    /// generation.
    edited_at: Option<Instant>,
    last_shown: Option<(u64, u32)>,
    /// The newest generation before the drag.
    before_drag: u64,
    first_drag_preview: Option<Duration>,
    ages: Vec<Duration>,
    lags: Vec<Duration>,
    distinct: u32,
    drag_intervals: Vec<Duration>,
    longest_frame: Duration,
    release_to_full: Option<Duration>,
    /// Whether the drag's last edit is what the final preview shows.
    released_value_shown: bool,
}

impl DragBenchmark {
    pub fn new(drag: Duration) -> Self {
        DragBenchmark {
            drag,
            phase: Phase::Loading,
            target: None,
            described: String::new(),
            last_frame: None,
            sent: Vec::new(),
            last_generation: 0,
            edited_at: None,
            last_shown: None,
            before_drag: 0,
            first_drag_preview: None,
            ages: Vec::new(),
            lags: Vec::new(),
            distinct: 0,
            drag_intervals: Vec::new(),
            longest_frame: Duration::ZERO,
            release_to_full: None,
            released_value_shown: false,
        }
    }

    pub fn is_finished(&self) -> bool {
        self.phase == Phase::Done
    }

    /// Whether a scripted pointer is held (the editor previews coarsely).
    pub fn holds_pointer(&self) -> bool {
        matches!(self.phase, Phase::Dragging { .. })
    }

    /// The time of the edit that made `generation` (the newest one at or
    /// before it: a settings change and an edit in one frame make two).
    fn sent_at(&self, generation: u64) -> Option<Instant> {
        self.sent
            .iter()
            .rev()
            .find(|(g, _)| *g <= generation)
            .map(|&(_, at)| at)
    }

    /// Called at the start of a frame, after the state took the newest
    /// snapshot: measures, and edits the scene as a held DragValue would.
    pub fn begin_frame(&mut self, state: &mut EditorState, now: Instant) {
        let generation = state.simulation().map_or(0, |s| s.generation());
        if generation > self.last_generation {
            self.sent.push((generation, self.edited_at.unwrap_or(now)));
            self.last_generation = generation;
        }
        self.edited_at = None;
        let interval = self.last_frame.map(|last| now - last);
        self.last_frame = Some(now);
        let shown = state
            .snapshot()
            .map(|s| (s.generation, s.iteration, s.map.layout.resolution));
        match self.phase {
            Phase::Loading => {
                if shown.is_some() {
                    self.phase = Phase::Settling { since: now };
                    // The opening of the file: generation 0.
                    self.sent.insert(0, (0, now));
                }
            }
            Phase::Settling { since } => {
                if now - since >= SETTLE {
                    if let Some(scene) = state.doc.scene.as_ref() {
                        self.target = DragTarget::choose(scene);
                        self.described = self
                            .target
                            .map_or("nothing to drag".to_owned(), |t| t.describe(scene));
                    }
                    self.before_drag = self.last_generation;
                    self.phase = Phase::Dragging { since: now };
                }
            }
            Phase::Dragging { since } => {
                if let Some(interval) = interval {
                    self.drag_intervals.push(interval);
                    self.longest_frame = self.longest_frame.max(interval);
                }
                if let Some((g, iteration, _)) = shown {
                    if g > self.before_drag && self.first_drag_preview.is_none() {
                        self.first_drag_preview = Some(now - since);
                    }
                    if self.first_drag_preview.is_some()
                        && let Some(at) = self.sent_at(g)
                    {
                        self.ages.push(now.saturating_duration_since(at));
                    }
                    // Out of date since the first edit after its own.
                    let outdated = self
                        .sent
                        .iter()
                        .find(|(sent, _)| *sent > g)
                        .map(|&(_, at)| at);
                    self.lags.push(
                        outdated.map_or(Duration::ZERO, |at| now.saturating_duration_since(at)),
                    );
                    if self.last_shown != Some((g, iteration)) {
                        self.distinct += 1;
                        self.last_shown = Some((g, iteration));
                    }
                }
                let fraction = (now - since).as_secs_f64() / self.drag.as_secs_f64();
                if let (Some(target), Some(scene)) = (self.target, state.doc.scene.as_mut()) {
                    target.set(scene, fraction.min(1.0));
                    self.edited_at = Some(now);
                }
                if fraction >= 1.0 {
                    // Released this frame: its end goes back to the chosen
                    // resolution, a generation the next frame sees.
                    self.phase = Phase::Released {
                        at: now,
                        generation: u64::MAX,
                    };
                }
            }
            Phase::Released { at, generation } => {
                let generation = if generation == u64::MAX {
                    self.last_generation
                } else {
                    generation
                };
                self.phase = Phase::Released { at, generation };
                let chosen = state.settings().resolution;
                if let Some((g, _, resolution)) = shown
                    && g >= generation
                    && resolution == chosen
                {
                    self.release_to_full = Some(now - at);
                    self.released_value_shown = self.shows_released_value(state);
                    self.phase = Phase::Done;
                } else if now - at >= RELEASE_TIMEOUT {
                    self.phase = Phase::Done;
                }
            }
            Phase::Done => {}
        }
    }

    /// Whether the shown snapshot's luminaire is the edited scene.
    fn shows_released_value(&self, state: &EditorState) -> bool {
        match (state.snapshot(), state.doc.scene.as_ref()) {
            (Some(s), Some(scene)) => s.luminaire.scene == *scene,
            _ => false,
        }
    }

    /// The figures, as the benchmark prints them.
    pub fn report(&self) -> String {
        let ms = |d: Duration| d.as_secs_f64() * 1e3;
        let quantiles = |v: &[Duration]| {
            let q = Quantiles::of(v);
            (q.median_ms, q.p95_ms, q.count)
        };
        let (age_median, age_p95, frames) = quantiles(&self.ages);
        let (lag_median, lag_p95, lag_frames) = quantiles(&self.lags);
        let (interval_median, interval_p95, _) = quantiles(&self.drag_intervals);
        let first = self
            .first_drag_preview
            .map_or("none".to_owned(), |d| format!("{:.0} ms", ms(d)));
        let release = self
            .release_to_full
            .map_or("not within 5 s".to_owned(), |d| format!("{:.0} ms", ms(d)));
        format!(
            "dragged: {}
drag start to its first preview: {first}
preview age during the drag: median {age_median:.0} ms, p95 {age_p95:.0} ms over {frames} frames
preview lag during the drag: median {lag_median:.0} ms, p95 {lag_p95:.0} ms over {lag_frames} frames
distinct previews shown: {:.1} per second
release to full-resolution preview: {release}{}
frame interval during the drag: median {interval_median:.0} ms, p95 {interval_p95:.0} ms, longest {:.0} ms",
            self.described,
            f64::from(self.distinct) / self.drag.as_secs_f64(),
            if self.released_value_shown {
                " (of the released value)"
            } else {
                ""
            },
            ms(self.longest_frame),
        )
    }
}
