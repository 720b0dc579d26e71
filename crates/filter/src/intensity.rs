//! A texel's intensity from its photons, shared by the pull-push pass and
//! the cross-validation that judges it.

/// Photons per steradian of a texel; 0 for a texel of no solid angle.
pub(crate) fn safe_intensity(count: f64, omega: f64) -> f64 {
    if omega > 0.0 { count / omega } else { 0.0 }
}
