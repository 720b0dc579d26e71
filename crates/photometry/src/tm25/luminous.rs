//! Each ray's luminous flux, the weight photons are sampled by:
//! - a luminous-flux column is taken as it is (lm);
//! - otherwise the radiant flux (W) × 683 lm/W × V(λ), with λ the header's
//!   single wavelength, the ray's wavelength column, or averaged over the
//!   ray's spectral table (its weights as the spectrum's shares);
//! - a file with radiant flux and no spectrum at all gives no λ: its
//!   radiant flux stands in for the luminous flux (only the rays' shares
//!   matter once the scene sets the emitter's flux).

use std::sync::OnceLock;

use super::{Columns, RayFileHeader, SpectralTable, SpectrumType};

/// Maximum luminous efficacy of photopic vision (lm/W at 555 nm).
const KM_LM_PER_W: f64 = 683.0;

/// CIE V(λ) at 5 nm from 380 nm (`data/cie_photopic_v_5nm.csv`).
fn v_table() -> &'static [f64] {
    static TABLE: OnceLock<Vec<f64>> = OnceLock::new();
    TABLE.get_or_init(|| {
        include_str!("../../data/cie_photopic_v_5nm.csv")
            .lines()
            .filter(|l| !l.starts_with('#') && !l.starts_with("wavelength"))
            .filter_map(|l| l.split_once(',').and_then(|(_, v)| v.trim().parse().ok()))
            .collect()
    })
}

/// The photopic luminous efficiency V(λ), linear between the 5 nm
/// values, 0 outside 380-780 nm.
pub fn photopic_v(wavelength_nm: f64) -> f64 {
    let table = v_table();
    let x = (wavelength_nm - 380.0) / 5.0;
    if !(x >= 0.0 && x <= (table.len() - 1) as f64) {
        return 0.0;
    }
    let i = (x.floor() as usize).min(table.len() - 2);
    let t = x - i as f64;
    table[i] * (1.0 - t) + table[i + 1] * t
}

/// Luminous efficacy of monochromatic radiation (lm/W).
pub fn luminous_efficacy_lm_per_w(wavelength_nm: f64) -> f64 {
    KM_LM_PER_W * photopic_v(wavelength_nm)
}

/// The efficacy of a spectral table's radiation: its weights as the
/// shares of radiant flux at its wavelengths.
fn table_efficacy(table: &SpectralTable) -> f64 {
    let total: f64 = table.weights.iter().map(|&w| f64::from(w)).sum();
    if !(total > 0.0) {
        return 0.0;
    }
    table
        .wavelengths_nm
        .iter()
        .zip(&table.weights)
        .map(|(&l, &w)| f64::from(w) * luminous_efficacy_lm_per_w(f64::from(l)))
        .sum::<f64>()
        / total
}

/// How a ray's record gives its luminous flux.
#[derive(Debug, Clone)]
pub(super) enum LuminousRule {
    Column(usize),
    /// Radiant flux × a fixed efficacy (lm/W; 1 where no λ is known).
    Radiant {
        column: usize,
        efficacy: f64,
    },
    /// Radiant flux × the efficacy at the ray's wavelength.
    RadiantAtWavelength {
        column: usize,
        wavelength: usize,
    },
    /// Radiant flux × its spectral table's efficacy (index base 1).
    RadiantByTable {
        column: usize,
        index: usize,
        efficacies: Vec<f64>,
    },
}

impl LuminousRule {
    /// The rule for `header`'s columns; `None` where the columns its
    /// spectrum type needs are missing.
    pub(super) fn of(header: &RayFileHeader, columns: &Columns) -> Option<Self> {
        if let Some(c) = columns.luminous_flux {
            return Some(LuminousRule::Column(c));
        }
        let column = columns.radiant_flux?;
        Some(match header.spectrum {
            SpectrumType::None => LuminousRule::Radiant {
                column,
                efficacy: 1.0,
            },
            SpectrumType::SingleWavelength => LuminousRule::Radiant {
                column,
                efficacy: luminous_efficacy_lm_per_w(f64::from(header.wavelength_nm?)),
            },
            SpectrumType::PerRayWavelength => LuminousRule::RadiantAtWavelength {
                column,
                wavelength: columns.wavelength?,
            },
            SpectrumType::Table => LuminousRule::Radiant {
                column,
                efficacy: table_efficacy(header.spectral_tables.first()?),
            },
            SpectrumType::PerRayTable => LuminousRule::RadiantByTable {
                column,
                index: columns.spectrum_index?,
                efficacies: header.spectral_tables.iter().map(table_efficacy).collect(),
            },
        })
    }

    /// The luminous flux of one record; `None` for a spectrum index
    /// that names no table.
    pub(super) fn flux(&self, record: &[f32]) -> Option<f64> {
        Some(match self {
            LuminousRule::Column(c) => f64::from(record[*c]),
            LuminousRule::Radiant { column, efficacy } => f64::from(record[*column]) * efficacy,
            LuminousRule::RadiantAtWavelength { column, wavelength } => {
                f64::from(record[*column])
                    * luminous_efficacy_lm_per_w(f64::from(record[*wavelength]))
            }
            LuminousRule::RadiantByTable {
                column,
                index,
                efficacies,
            } => {
                let i = record[*index];
                if !(i >= 1.0 && i.fract() == 0.0 && (i as usize) <= efficacies.len()) {
                    return None;
                }
                f64::from(record[*column]) * efficacies[i as usize - 1]
            }
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn v_lambda_peaks_at_555_nm_and_vanishes_outside_the_visible() {
        assert_eq!(photopic_v(555.0), 1.0);
        assert_eq!(photopic_v(380.0), 0.0);
        assert_eq!(photopic_v(300.0), 0.0);
        assert_eq!(photopic_v(900.0), 0.0);
        assert!((photopic_v(507.5) - 0.5 * (0.4073 + 0.503)).abs() < 1e-12);
        assert!((luminous_efficacy_lm_per_w(555.0) - 683.0).abs() < 1e-9);
        // The table integrates to the known 106.86 nm (5 nm steps).
        let integral: f64 = v_table().iter().sum::<f64>() * 5.0;
        assert!((integral - 106.86).abs() < 0.05, "{integral}");
    }
}
