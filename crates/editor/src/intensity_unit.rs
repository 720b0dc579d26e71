//! The unit intensities are drawn in, shared by the views and the
//! reference they draw beside the result.

/// How intensities are drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum IntensityUnit {
    /// Absolute candela, as the simulation gives them.
    #[default]
    Candela,
    /// Candela per 1000 lm of lamp (emitter) flux, as datasheets draw them.
    CandelaPerKilolumen,
}

impl IntensityUnit {
    pub fn label(self) -> &'static str {
        match self {
            IntensityUnit::Candela => "cd",
            IntensityUnit::CandelaPerKilolumen => "cd/klm",
        }
    }

    /// The factor from candela for a lamp flux of `lamp_flux_lm`.
    pub fn factor(self, lamp_flux_lm: f64) -> f64 {
        match self {
            IntensityUnit::Candela => 1.0,
            IntensityUnit::CandelaPerKilolumen if lamp_flux_lm > 0.0 => 1000.0 / lamp_flux_lm,
            IntensityUnit::CandelaPerKilolumen => 1.0,
        }
    }
}
