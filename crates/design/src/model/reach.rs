//! What a geometry cannot do: a lower bound on the remaining difference
//! from what its fixed parts make impossible.
//!
//! The LED's direct light through the aperture is there whatever the
//! mirror's shape (as long as the mirror stays outside the cone from the
//! LED to the aperture's rim), and the mirror reflects at most its
//! reflectance times the flux it catches. The reflected light, on the
//! other hand, may go anywhere. So every design's light is the direct
//! light plus some non-negative distribution of at most that flux, and
//! the least relative L2 difference over all such sums is a bound no
//! mirror beats. For a shape match (both scaled to the target's flux),
//! the best non-negative addition of a given flux is the target's
//! deficit water-filled: g = max(0, T − a − μ), μ set by the flux; the
//! bound is the least over the reflected flux.
//!
//! Angles are the target's γ nodes (its table's, averaged over C), each
//! weighted by the solid angle of its cell.

use serde::Serialize;

/// What the fixed parts make impossible, for the CLI, the JSON and the
/// Design pane.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Reachability {
    /// The aperture rim's angle from the LED's axis (degrees): the cone
    /// the LED's direct light leaves through.
    pub direct_cone_deg: f64,
    /// The LED's direct light through the aperture, and the most the
    /// mirror can send out (its reflectance times what it catches), as
    /// shares of the lamp flux.
    pub direct_share: f64,
    pub mirror_share_max: f64,
    /// Shares of the light inside the direct cone: at least this much of
    /// any design's (its direct light, the mirror's all outside), and the
    /// target's.
    pub design_cone_share_min: f64,
    pub target_cone_share: f64,
    /// The least relative L2 difference any mirror between these ends
    /// can reach while it stays out of the direct cone.
    pub bound: f64,
    /// The same with the direct light shielded: a cap over the LED, or a
    /// mirror that reaches into the direct cone and shades it (so this is
    /// the bound of every mirror between these ends).
    pub with_cap: f64,
    /// The same with the aperture deeper by each factor: (factor, the
    /// direct cone's angle in degrees, bound).
    pub deeper: Vec<(f64, f64, f64)>,
    /// Whether the design already moves the ends (`--free-ends`): a
    /// deeper aperture is then the design's to find, not a switch to set.
    pub ends_free: bool,
}

impl Reachability {
    /// What would help, in words, for a design that wants `aim` or less.
    pub fn advice(&self, aim: f64) -> Vec<String> {
        let mut out = Vec::new();
        if self.bound <= aim {
            return out;
        }
        let deeper = if self.ends_free {
            "a deeper aperture (the ends are free: the design may move them there)"
        } else {
            "free the ends (--free-ends)"
        };
        if let Some((k, cone, b)) = self.deeper.iter().find(|d| d.2 <= aim) {
            out.push(format!(
                "{deeper}: an aperture {k}× as deep (a {cone:.1}° direct cone) would allow {b:.3}"
            ));
        } else if let Some((k, cone, b)) = self.deeper.last() {
            out.push(format!(
                "{deeper}: even an aperture {k}× as deep (a {cone:.1}° direct cone) allows only {b:.3}"
            ));
        }
        out.push(format!(
            "a cap or shield over the LED (its direct light sent to the mirror) would allow {:.3}",
            self.with_cap
        ));
        out
    }
}

/// Reflected fluxes the bound tries between none and the most.
const FLUX_STEPS: usize = 64;
const BISECTIONS: usize = 100;

/// Light against γ on the target's nodes: intensity (cd, or the target's
/// units) and each node's solid angle (sr).
#[derive(Debug, Clone, PartialEq)]
pub struct AxialLight<'a> {
    pub intensity: &'a [f64],
    pub solid_angle_sr: &'a [f64],
}

impl AxialLight<'_> {
    pub fn flux(&self) -> f64 {
        self.intensity
            .iter()
            .zip(self.solid_angle_sr)
            .map(|(i, w)| i * w)
            .sum()
    }
}

/// The solid angle each γ node stands for (its cell: halfway to its
/// neighbours, the whole circle of C).
pub fn node_solid_angles(gammas_deg: &[f64]) -> Vec<f64> {
    let n = gammas_deg.len();
    (0..n)
        .map(|j| {
            let lo = if j == 0 {
                gammas_deg[0]
            } else {
                0.5 * (gammas_deg[j - 1] + gammas_deg[j])
            };
            let hi = if j + 1 == n {
                gammas_deg[n - 1]
            } else {
                0.5 * (gammas_deg[j] + gammas_deg[j + 1])
            };
            2.0 * std::f64::consts::PI * (lo.to_radians().cos() - hi.to_radians().cos()).max(0.0)
        })
        .collect()
}

/// What the fixed parts allow: the bound and the best split of the light.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Bound {
    /// The least relative L2 difference any mirror can reach.
    pub relative_l2: f64,
    /// The reflected flux (lamp lumens) at which it is reached.
    pub reflected_flux: f64,
    /// The reflected light that reaches it, in the target's units on its
    /// nodes (what the mirror should make).
    #[serde(skip)]
    pub reflected: Vec<f64>,
}

/// The bound for a target `target` (its units), the direct light
/// `direct` (lamp candela) and at most `reflected_max` lumens the mirror
/// can send out; `absolute` compares candela as they are, else both
/// scaled to the target's flux.
pub fn bound(
    target: &AxialLight,
    direct: &AxialLight,
    reflected_max: f64,
    absolute: bool,
) -> Bound {
    let w = target.solid_angle_sr;
    let t = target.intensity;
    let norm: f64 = t.iter().zip(w).map(|(t, w)| w * t * t).sum();
    let target_flux = target.flux();
    let direct_flux = direct.flux();
    let reflected_max = reflected_max.max(0.0);
    let none = Bound {
        relative_l2: f64::INFINITY,
        reflected_flux: 0.0,
        reflected: vec![0.0; t.len()],
    };
    if !(norm > 0.0) {
        return none;
    }
    // The difference of (scale × direct + the best addition of `added`
    // target-unit lumens).
    let at = |scale: f64, added: f64| -> (f64, Vec<f64>) {
        let a: Vec<f64> = direct.intensity.iter().map(|d| scale * d).collect();
        let g = water_fill(t, &a, w, added);
        let cost: f64 = (0..t.len())
            .map(|k| w[k] * (a[k] + g[k] - t[k]).powi(2))
            .sum();
        ((cost / norm).sqrt(), g)
    };
    let mut best = none;
    for k in 0..=FLUX_STEPS {
        let reflected = reflected_max * k as f64 / FLUX_STEPS as f64;
        let (scale, added) = if absolute {
            (1.0, reflected)
        } else {
            let total = direct_flux + reflected;
            if !(total > 0.0) {
                continue;
            }
            let s = target_flux / total;
            (s, s * reflected)
        };
        let (l2, g) = at(scale, added);
        if l2 < best.relative_l2 {
            best = Bound {
                relative_l2: l2,
                reflected_flux: reflected,
                reflected: g,
            };
        }
    }
    best
}

/// The non-negative g of flux `added` (Σ w g) that brings `a + g` nearest
/// `t` in the w-weighted L2: max(0, t − a − μ), μ by bisection.
fn water_fill(t: &[f64], a: &[f64], w: &[f64], added: f64) -> Vec<f64> {
    let total_w: f64 = w.iter().sum();
    if !(added > 0.0) || !(total_w > 0.0) {
        return vec![0.0; t.len()];
    }
    let deficit_max = t
        .iter()
        .zip(a)
        .map(|(t, a)| t - a)
        .fold(f64::NEG_INFINITY, f64::max);
    let flux_at = |mu: f64| -> f64 {
        (0..t.len())
            .map(|k| w[k] * (t[k] - a[k] - mu).max(0.0))
            .sum()
    };
    // μ from where nothing is added down to where even the least
    // deficit gets enough.
    let (mut hi, mut lo) = (deficit_max, deficit_max - 1.0);
    let mut guard = 0;
    while flux_at(lo) < added && guard < 200 {
        let span = hi - lo;
        lo -= 2.0 * span.max(added / total_w);
        guard += 1;
    }
    for _ in 0..BISECTIONS {
        let mid = 0.5 * (lo + hi);
        if flux_at(mid) > added {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let mu = 0.5 * (lo + hi);
    (0..t.len()).map(|k| (t[k] - a[k] - mu).max(0.0)).collect()
}

/// The light the mirror should make for a direct design: the bound's
/// reflected light where the target lacks light, but where the mirror
/// has more light than the target lacks (the bound would spread the rest
/// evenly, even upwards), the deficit max(0, t − a) scaled up instead.
pub fn reflected_wanted(target: &AxialLight, direct_scaled: &[f64], bound: &Bound) -> Vec<f64> {
    let w = target.solid_angle_sr;
    let deficit: Vec<f64> = target
        .intensity
        .iter()
        .zip(direct_scaled)
        .map(|(t, a)| (t - a).max(0.0))
        .collect();
    let deficit_flux: f64 = deficit.iter().zip(w).map(|(d, w)| d * w).sum();
    let bound_flux: f64 = bound.reflected.iter().zip(w).map(|(g, w)| g * w).sum();
    if bound_flux > deficit_flux && deficit_flux > 0.0 {
        let k = bound_flux / deficit_flux;
        deficit.iter().map(|d| d * k).collect()
    } else {
        bound.reflected.clone()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid() -> Vec<f64> {
        (0..=180).map(f64::from).collect()
    }

    #[test]
    fn water_filling_adds_its_flux_where_the_deficit_is_deepest() {
        let g = grid();
        let w = node_solid_angles(&g);
        let t: Vec<f64> = g
            .iter()
            .map(|&x| if x < 20.0 { 10.0 } else { 0.0 })
            .collect();
        let a: Vec<f64> = g
            .iter()
            .map(|&x| if x < 10.0 { 6.0 } else { 0.0 })
            .collect();
        let added = 5.0 * w[..20].iter().sum::<f64>() * 0.5;
        let fill = water_fill(&t, &a, &w, added);
        let got: f64 = fill.iter().zip(&w).map(|(g, w)| g * w).sum();
        assert!((got - added).abs() < 1e-9 * added.max(1.0));
        // Nothing where the target is dark, more where the direct light
        // leaves more of it.
        assert!(fill[30..].iter().all(|&x| x == 0.0));
        assert!(fill[15] >= fill[5]);
    }

    #[test]
    fn a_target_the_direct_light_already_is_has_no_bound() {
        let g = grid();
        let w = node_solid_angles(&g);
        let d: Vec<f64> = g.iter().map(|&x| x.to_radians().cos().max(0.0)).collect();
        let b = bound(
            &AxialLight {
                intensity: &d,
                solid_angle_sr: &w,
            },
            &AxialLight {
                intensity: &d,
                solid_angle_sr: &w,
            },
            1.0,
            false,
        );
        assert!(b.relative_l2 < 1e-9, "{}", b.relative_l2);
    }

    #[test]
    fn a_narrow_target_beside_strong_direct_light_is_bounded_away_from_zero() {
        // A 5° beam against a bare Lambertian cone of 30°: whatever the
        // reflected half of the light does, the cone's own light outside
        // 5° stays. The bound is the cone's share of the difference,
        // computed here by hand for the best split: the cone scaled to
        // s, the beam's deficit filled.
        let g: Vec<f64> = (0..=1800).map(|k| f64::from(k) * 0.1).collect();
        let w = node_solid_angles(&g);
        let t: Vec<f64> = g
            .iter()
            .map(|&x| if x <= 5.0 { 100.0 } else { 0.0 })
            .collect();
        let d: Vec<f64> = g
            .iter()
            .map(|&x| if x <= 30.0 { x.to_radians().cos() } else { 0.0 })
            .collect();
        let target = AxialLight {
            intensity: &t,
            solid_angle_sr: &w,
        };
        let direct = AxialLight {
            intensity: &d,
            solid_angle_sr: &w,
        };
        let b = bound(&target, &direct, 3.0 * direct.flux(), false);
        assert!(
            b.relative_l2 > 0.05 && b.relative_l2 < 1.0,
            "{}",
            b.relative_l2
        );
        // No split of the flux does better: a brute force over the
        // reflected flux, each filled by water-filling's brute
        // equivalent (the deficit inside 5° evenly, which is what the
        // optimum is for a flat target over a cone flat inside 5°).
        for k in 0..=300 {
            let reflected = 3.0 * direct.flux() * f64::from(k) / 300.0;
            let s = target.flux() / (direct.flux() + reflected);
            let inside: f64 = w
                .iter()
                .zip(&g)
                .filter(|(_, x)| **x <= 5.0)
                .map(|(w, _)| w)
                .sum();
            let fill = s * reflected / inside;
            let cost: f64 = (0..g.len())
                .map(|j| {
                    let add = if g[j] <= 5.0 { fill } else { 0.0 };
                    w[j] * (s * d[j] + add - t[j]).powi(2)
                })
                .sum::<f64>();
            let norm: f64 = (0..g.len()).map(|j| w[j] * t[j] * t[j]).sum();
            assert!((cost / norm).sqrt() >= b.relative_l2 - 1e-3);
        }
    }
}
