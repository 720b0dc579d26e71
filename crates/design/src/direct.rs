//! The direct design of a revolved reflector for a point source.

use lucerna_scene::Scene;

use crate::target::Target;
use crate::variables::Variable;

/// Values of `variables` from a direct design, where one applies.
pub fn design(_start: &Scene, _variables: &[Variable], _target: &Target) -> Option<Vec<f64>> {
    None
}
