//! The automatic filter at the pace of a live preview.

use lucerna_filter::{AutomaticReport, FilterSettings, Filtered, Threshold, filter_map};
use lucerna_photometry::{IntensityMap, TexelSymmetry};

/// Cross-validating the automatic rule costs about 13 candidates × 5
/// folds of filter passes; its choice changes slowly with the photon
/// count. So the rule is chosen again only once the photons have grown by
/// [`LiveFilter::RECHOOSE_GROWTH`] since the last choice, and reused (one
/// pass) in between. Fixed thresholds pass straight through.
#[derive(Debug, Clone, Default)]
pub struct LiveFilter {
    /// The rule last chosen and the photons it was chosen at.
    chosen: Option<(FilterSettings, u64, Option<AutomaticReport>)>,
}

impl LiveFilter {
    pub const RECHOOSE_GROWTH: u64 = 2;

    pub fn new() -> Self {
        Self::default()
    }

    /// Forgets the choice (a new scene or layout).
    pub fn reset(&mut self) {
        self.chosen = None;
    }

    /// Candela per texel of `map` filtered by `threshold`, and the report;
    /// `reuse` lets an automatic rule be reused while the photons have not
    /// doubled (a final export passes `false` and chooses afresh).
    pub fn filter(
        &mut self,
        map: &IntensityMap,
        threshold: Threshold,
        symmetry: &TexelSymmetry,
        reuse: bool,
    ) -> (Vec<f64>, Filtered) {
        let photons = map.photons_emitted;
        if threshold != Threshold::Automatic {
            let settings = FilterSettings {
                threshold,
                ..Default::default()
            };
            return filter_map(map, &settings, symmetry);
        }
        if reuse
            && let Some((settings, at, estimate)) = &self.chosen
            && photons < at.saturating_mul(Self::RECHOOSE_GROWTH)
            && photons >= *at
        {
            // The cross-validated error estimate is that of the choice.
            let (candela, mut report) = filter_map(map, settings, symmetry);
            report.automatic = *estimate;
            return (candela, report);
        }
        let settings = FilterSettings {
            threshold: Threshold::Automatic,
            ..Default::default()
        };
        let (candela, report) = filter_map(map, &settings, symmetry);
        self.chosen = Some((report.settings, photons, report.automatic));
        (candela, report)
    }
}
