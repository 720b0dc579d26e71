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

/// The first wavelength of the V(λ) table and its step (nm).
const V_FIRST_NM: f64 = 360.0;
const V_STEP_NM: f64 = 1.0;

/// CIE V(λ) at 1 nm from 360 nm to 830 nm (`data/cie_photopic_v_1nm.csv`:
/// the CIE's table, its source and licence in the file's head).
fn v_table() -> &'static [f64] {
    static TABLE: OnceLock<Vec<f64>> = OnceLock::new();
    TABLE.get_or_init(|| {
        include_str!("../../data/cie_photopic_v_1nm.csv")
            .lines()
            .filter(|l| !l.starts_with('#') && !l.starts_with("wavelength"))
            .filter_map(|l| l.split_once(',').and_then(|(_, v)| v.trim().parse().ok()))
            .collect()
    })
}

/// The photopic luminous efficiency V(λ): the CIE's 1 nm values, linear
/// between them, 0 outside 360-830 nm.
pub fn photopic_v(wavelength_nm: f64) -> f64 {
    let table = v_table();
    let x = (wavelength_nm - V_FIRST_NM) / V_STEP_NM;
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

/// Sub-steps of the integration within a nanometre: V(λ) is linear
/// between its 1 nm values and a table's spectrum between its own
/// wavelengths, so their product is a quadratic on each piece, which
/// Simpson's rule integrates exactly on pieces this fine.
const STEPS_PER_NM: f64 = 4.0;

/// The efficacy of a spectral table's radiation (lm/W): 683 lm/W ×
/// ∫ S(λ) V(λ) dλ / ∫ S(λ) dλ, the spectrum S linear between the table's
/// wavelengths (its weights as relative spectral power), integrated as
/// the functions are, not as a sum of samples (a 5 nm table summed reads
/// a white LED's lumens 0.46 % high).
pub fn table_efficacy(table: &SpectralTable) -> f64 {
    let points: Vec<(f64, f64)> = table
        .wavelengths_nm
        .iter()
        .zip(&table.weights)
        .map(|(&l, &w)| (f64::from(l), f64::from(w)))
        .filter(|(l, w)| l.is_finite() && w.is_finite())
        .collect();
    if let [(l, w)] = points.as_slice() {
        return if *w > 0.0 {
            luminous_efficacy_lm_per_w(*l)
        } else {
            0.0
        };
    }
    let (mut power, mut luminous) = (0.0, 0.0);
    for pair in points.windows(2) {
        let ((l0, w0), (l1, w1)) = (pair[0], pair[1]);
        let span = l1 - l0;
        if !(span > 0.0) {
            continue;
        }
        // Simpson on pieces no wider than 1/STEPS_PER_NM nm, aligned so
        // that V's own kinks (its integer wavelengths) fall on piece ends.
        let mut cuts = vec![l0];
        let mut nm = l0.floor() + 1.0;
        while nm < l1 {
            cuts.push(nm);
            nm += 1.0;
        }
        cuts.push(l1);
        let s = |l: f64| w0 + (w1 - w0) * (l - l0) / span;
        for c in cuts.windows(2) {
            let pieces = ((c[1] - c[0]) * STEPS_PER_NM).ceil().max(1.0) as usize;
            let h = (c[1] - c[0]) / pieces as f64;
            for k in 0..pieces {
                let (a, b) = (c[0] + k as f64 * h, c[0] + (k + 1) as f64 * h);
                let m = 0.5 * (a + b);
                let f = |l: f64| s(l) * photopic_v(l);
                luminous += h / 6.0 * (f(a) + 4.0 * f(m) + f(b));
                power += h / 6.0 * (s(a) + 4.0 * s(m) + s(b));
            }
        }
    }
    if power > 0.0 {
        KM_LM_PER_W * luminous / power
    } else {
        0.0
    }
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
        assert_eq!(photopic_v(300.0), 0.0);
        assert_eq!(photopic_v(900.0), 0.0);
        // The CIE's 1 nm values, and linear between them.
        assert_eq!(photopic_v(360.0), 0.000003917);
        assert_eq!(photopic_v(650.0), 0.107);
        assert!((photopic_v(554.5) - 0.5 * (0.9997482 + 1.0)).abs() < 1e-9);
        assert!((luminous_efficacy_lm_per_w(555.0) - 683.0).abs() < 1e-9);
        // 471 values; their sum × 1 nm is the known 106.857 nm.
        assert_eq!(v_table().len(), 471);
        let integral: f64 = v_table().iter().sum::<f64>();
        assert!((integral - 106.857).abs() < 0.001, "{integral}");
    }

    #[test]
    fn a_tables_efficacy_is_the_integral_not_the_sum_of_its_samples() {
        // A flat spectrum over 400-700 nm on unequal steps: its efficacy
        // is 683 × ∫V / 300 nm whatever the steps; a sum of weights at the
        // wavelengths would weigh the finely stepped part more.
        let wavelengths: Vec<f32> = [400.0, 401.0, 402.0, 403.0, 450.0, 550.0, 700.0].to_vec();
        let table = SpectralTable {
            weights: vec![1.0; wavelengths.len()],
            wavelengths_nm: wavelengths,
        };
        let exact: f64 = {
            // ∫ V over 400-700 nm of the piecewise-linear V: trapezoid
            // on its own 1 nm values is exact.
            let t = v_table();
            (40..340).map(|i| 0.5 * (t[i] + t[i + 1])).sum::<f64>() / 300.0 * 683.0
        };
        let got = table_efficacy(&table);
        assert!((got - exact).abs() < 1e-9 * exact, "{got} against {exact}");
        // One wavelength: that wavelength's efficacy.
        let single = SpectralTable {
            wavelengths_nm: vec![555.0],
            weights: vec![2.0],
        };
        assert!((table_efficacy(&single) - 683.0).abs() < 1e-9);
    }
}
