//! What the user chooses: the rule that tells unstable texels from stable
//! ones ([`Threshold`]), the two σ of the bilateral interpolation, and the
//! constants of the Poisson rule.

/// How unstable texels are told from stable ones.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Threshold {
    /// Photons a texel needs to be stable (the paper's user threshold).
    Fixed(f64),
    /// Per texel, from the photon statistics: a texel is replaced when its
    /// count is what Poisson noise around the upsampled estimate would
    /// give (|c − E| ≤ z·√(E + 1), E = estimate × texel solid angle),
    /// and kept when it deviates significantly (real structure: a caustic,
    /// a cut-off) or holds at least `cap` photons. Smooth regions get
    /// smoothed as much as a high threshold would, structured ones as
    /// little as a low one.
    Poisson { cap: f64, z: f64 },
    /// No user threshold: the rule is chosen per map among
    /// [`automatic_candidates`](crate::automatic_candidates) by K-fold
    /// cross-validation on the photon counts themselves
    /// ([`choose_automatic`](crate::choose_automatic)).
    Automatic,
}

impl std::fmt::Display for Threshold {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Threshold::Fixed(t) if *t <= 0.0 => write!(f, "no filtering (raw)"),
            Threshold::Fixed(t) => write!(f, "fixed threshold {t:.0}"),
            Threshold::Poisson { cap, z } if *cap >= UNCAPPED => {
                write!(f, "Poisson test (no cap, z {z})")
            }
            Threshold::Poisson { cap, z } => write!(f, "Poisson test (cap {cap:.0}, z {z})"),
            Threshold::Automatic => write!(f, "automatic"),
        }
    }
}

/// z-score of the Poisson consistency test when no other is given (the
/// fallback rule's, and half of the automatic mode's candidates').
pub const POISSON_Z: f64 = 4.0;
/// Fewest photons a texel needs before the Poisson test believes its
/// excess over the estimate is structure rather than Poisson's long tail.
pub const POISSON_MIN_KEEP_PHOTONS: f64 = 32.0;
/// A cap no texel reaches: the Poisson test alone decides which texels
/// are kept (finite, so it survives the f32 of the WGSL twin).
pub const UNCAPPED: f64 = 1e15;
/// The fallback rule's cap (relative noise ≤ 1/√256 ≈ 6 % above it).
pub const POISSON_FALLBACK_CAP_PHOTONS: f64 = 256.0;
/// Threshold the Poisson rule uses for Algorithm 2's border test.
pub const POISSON_BORDER_THRESHOLD_PHOTONS: f64 = 64.0;

/// The rule `Automatic` stands for when no choice is made.
pub const AUTOMATIC_FALLBACK: Threshold = Threshold::Poisson {
    cap: POISSON_FALLBACK_CAP_PHOTONS,
    z: POISSON_Z,
};

/// The two photon counts a rule filters by.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct PhotonThresholds {
    /// A texel with at least this many photons is stable and never
    /// replaced (the Poisson rule's cap).
    pub(crate) stable: f64,
    /// Algorithm 2's border test: a neighbour is stable with a texel when
    /// their counts sum to at least twice this.
    pub(crate) border: f64,
}

impl Threshold {
    /// The photon counts this rule filters by. `Automatic` reads as its
    /// fallback rule (it is resolved by cross-validation before filtering).
    pub(crate) fn photon_thresholds(self) -> PhotonThresholds {
        match self {
            Threshold::Fixed(t) => PhotonThresholds {
                stable: t,
                border: t,
            },
            Threshold::Poisson { cap, .. } => PhotonThresholds {
                stable: cap,
                border: POISSON_BORDER_THRESHOLD_PHOTONS,
            },
            Threshold::Automatic => AUTOMATIC_FALLBACK.photon_thresholds(),
        }
    }

    /// The Poisson test's z, if the rule has one.
    pub(crate) fn poisson_z(self) -> Option<f64> {
        match self {
            Threshold::Poisson { z, .. } => Some(z),
            _ => None,
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FilterSettings {
    pub threshold: Threshold,
    /// σ of the closeness Gaussian, in texels of the coarser level.
    pub sigma_closeness: f64,
    /// σ of the similarity Gaussian on the relative intensity difference
    /// |f̃ − f| / max(f̃, f).
    pub sigma_range: f64,
    /// Levels on which Algorithm 2's shadow-border test applies (the paper:
    /// all but 0 and 1).
    pub first_border_level: usize,
}

impl Default for FilterSettings {
    fn default() -> Self {
        FilterSettings {
            threshold: Threshold::Automatic,
            sigma_closeness: 0.75,
            sigma_range: 0.3,
            first_border_level: 2,
        }
    }
}

/// What a user reads about the settings: the rule and the two σ.
impl std::fmt::Display for FilterSettings {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{}, σ closeness {}, σ range {}",
            self.threshold, self.sigma_closeness, self.sigma_range
        )
    }
}
