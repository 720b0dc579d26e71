//! The automatic filter at the pace of a live preview.

use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::mpsc::{Receiver, TryRecvError, channel};
use std::time::{Duration, Instant};

use lucerna_filter::{AutomaticReport, FilterSettings, Filtered, Threshold, filter_map};
use lucerna_photometry::{IntensityMap, TexelSymmetry};

/// A rule chosen by cross-validation, and the photons it was chosen at.
#[derive(Debug, Clone, Copy)]
struct Choice {
    settings: FilterSettings,
    photons: u64,
    estimate: Option<AutomaticReport>,
}

/// Cross-validating the automatic rule costs 13 candidates × 5 folds of
/// filter passes (about a second at 6 × 256² on two cores), and its
/// choice changes slowly with the photon count. On the live path the rule
/// is therefore chosen again only once the photons have grown by
/// [`LiveFilter::RECHOOSE_GROWTH`], on a thread of its own from a copy of
/// the counts, once the run is half a second old, one at a time in the
/// process; until its answer arrives each snapshot is one filter pass
/// with the last rule (before the first answer, the paper's fixed
/// threshold of 100 photons). A final export chooses afresh, in line.
/// Fixed thresholds pass straight through.
#[derive(Debug)]
pub struct LiveFilter {
    chosen: Option<Choice>,
    pending: Option<Receiver<Choice>>,
    created: Instant,
}

impl Default for LiveFilter {
    fn default() -> Self {
        LiveFilter {
            chosen: None,
            pending: None,
            created: Instant::now(),
        }
    }
}

/// Until cross-validation has answered: the paper's threshold.
const FIRST_RULE: Threshold = Threshold::Fixed(100.0);

/// A run this young gets no background choice: while a slider is dragged
/// each edit restarts the run, and a second of cross-validation for a
/// scene already replaced would only slow the next one down.
const SETTLE_BEFORE_CHOOSING: Duration = Duration::from_millis(500);

/// Background choices running in this process (at most one: a choice for
/// a run that an edit has since replaced finishes alone, and no second
/// starts beside it).
static CHOICES_IN_FLIGHT: AtomicUsize = AtomicUsize::new(0);

/// Frees the one background slot when its thread ends, however it ends.
struct InFlight;

impl Drop for InFlight {
    fn drop(&mut self) {
        CHOICES_IN_FLIGHT.store(0, Ordering::Release);
    }
}

impl LiveFilter {
    pub const RECHOOSE_GROWTH: u64 = 2;

    pub fn new() -> Self {
        Self::default()
    }

    /// Whether a cross-validation is running in the background.
    pub fn is_choosing(&self) -> bool {
        self.pending.is_some()
    }

    /// Candela per texel of `map` filtered by `threshold`, and the report.
    /// With `live`, an automatic rule comes from the background choice
    /// (see the type's doc); without, it is chosen now.
    pub fn filter(
        &mut self,
        map: &IntensityMap,
        threshold: Threshold,
        symmetry: &TexelSymmetry,
        live: bool,
    ) -> (Vec<f64>, Filtered) {
        let with = |threshold| FilterSettings {
            threshold,
            ..Default::default()
        };
        if threshold != Threshold::Automatic {
            return filter_map(map, &with(threshold), symmetry);
        }
        if !live {
            let (candela, report) = filter_map(map, &with(Threshold::Automatic), symmetry);
            self.chosen = Some(Choice {
                settings: report.settings,
                photons: map.photons_emitted,
                estimate: report.automatic,
            });
            return (candela, report);
        }
        self.collect();
        let photons = map.photons_emitted;
        let stale = self.chosen.is_none_or(|c| {
            photons >= c.photons.saturating_mul(Self::RECHOOSE_GROWTH) || photons < c.photons
        });
        if stale
            && self.pending.is_none()
            && photons > 0
            && self.created.elapsed() >= SETTLE_BEFORE_CHOOSING
        {
            self.choose_in_background(map.clone(), symmetry.clone());
        }
        match self.chosen {
            Some(c) => {
                let (candela, mut report) = filter_map(map, &c.settings, symmetry);
                // The cross-validated error estimate is that of the choice.
                report.automatic = c.estimate;
                (candela, report)
            }
            None => filter_map(map, &with(FIRST_RULE), symmetry),
        }
    }

    /// Blocks until a background choice (if any) has answered: tests and
    /// benches that want the rule settled.
    pub fn wait_for_choice(&mut self) {
        if let Some(rx) = self.pending.take()
            && let Ok(choice) = rx.recv()
        {
            self.chosen = Some(choice);
        }
    }

    /// Takes a finished background choice.
    fn collect(&mut self) {
        let Some(rx) = &self.pending else { return };
        match rx.try_recv() {
            Ok(choice) => {
                self.chosen = Some(choice);
                self.pending = None;
            }
            Err(TryRecvError::Empty) => {}
            Err(TryRecvError::Disconnected) => self.pending = None,
        }
    }

    fn choose_in_background(&mut self, map: IntensityMap, symmetry: TexelSymmetry) {
        if CHOICES_IN_FLIGHT
            .compare_exchange(0, 1, Ordering::AcqRel, Ordering::Acquire)
            .is_err()
        {
            return;
        }
        let (tx, rx) = channel();
        let spawned = std::thread::Builder::new()
            .name("lucerna-filter-choice".to_owned())
            .spawn(move || {
                let _slot = InFlight;
                let settings = FilterSettings {
                    threshold: Threshold::Automatic,
                    ..Default::default()
                };
                // On a one-thread pool of its own: the tracer and the
                // snapshots keep the shared pool's threads, and the choice
                // takes what is left of the machine.
                let choose = || filter_map(&map, &settings, &symmetry).1;
                let report = match rayon::ThreadPoolBuilder::new().num_threads(1).build() {
                    Ok(pool) => pool.install(choose),
                    Err(_) => choose(),
                };
                let _ = tx.send(Choice {
                    settings: report.settings,
                    photons: map.photons_emitted,
                    estimate: report.automatic,
                });
            });
        // Without a thread the last rule simply stays.
        match spawned {
            Ok(_) => self.pending = Some(rx),
            Err(_) => CHOICES_IN_FLIGHT.store(0, Ordering::Release),
        }
    }
}
