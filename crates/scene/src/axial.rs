//! Whether a luminaire's light is the same in every C-plane, read from its
//! parameters: known at once, also during a drag, where the tracer's
//! geometric symmetry search (150 ms on the parabolic spot) waits for the
//! edits to settle.

use glam::{DQuat, DVec3, EulerRot};

use crate::exact::ExactSurface;
use crate::model::{Emission, EmitterShape, Material, Scene, Shape, Transform};

/// The fewest segments around a smooth surface of revolution for its light
/// to count as round: the tessellation is exactly N-fold symmetric, and
/// with smooth normals its ripple between segments 360°/N apart is finer
/// than a table's 5° C-planes from N = 24 on (15°, three planes).
pub const MIN_SEGMENTS_AROUND: u32 = 24;

/// Within this (m, or of a unit vector) a transform keeps the z axis.
const ON_AXIS: f64 = 1e-9;

impl Scene {
    /// Whether the light is the same in every C-plane: every enabled part
    /// a smooth surface of revolution (paraboloid, ellipsoid, revolved
    /// profile, dome, cylinder, disk; not faceted, at least
    /// [`MIN_SEGMENTS_AROUND`] segments around) of an isotropic material,
    /// and every enabled emitter a Lambertian disk, sphere or cylinder,
    /// all about the luminaire's z axis. Tables of such a luminaire may be
    /// pooled over C: every plane then carries all the photons of its γ.
    pub fn rotationally_symmetric(&self) -> bool {
        let isotropic = |name: &str| match self.materials.get(name) {
            Some(Material::RoughConductor {
                roughness_u,
                roughness_v,
                ..
            }) => roughness_u == roughness_v,
            Some(_) => true,
            // An unknown name is the validator's to report.
            None => false,
        };
        let parts =
            self.parts.iter().filter(|p| p.enabled).all(|p| {
                round_part(&p.shape) && keeps_axis(&p.transform) && isotropic(&p.material)
            });
        let emitters = self.emitters.iter().filter(|e| e.enabled).all(|e| {
            matches!(
                e.shape,
                EmitterShape::Disk { .. }
                    | EmitterShape::Sphere { .. }
                    | EmitterShape::Cylinder { .. }
            ) && e.emission == Emission::Lambertian
                && keeps_axis(&e.transform)
                && e.material.as_deref().is_none_or(isotropic)
        });
        parts && emitters && self.emitters.iter().any(|e| e.enabled)
    }
}

/// A smooth surface of revolution (or disk) about its local z axis.
fn round_part(shape: &Shape) -> bool {
    let generator = shape.generator();
    // Faceted shapes have no exact surface: their facets are the light's.
    generator
        .segments_around()
        .is_some_and(|n| n >= MIN_SEGMENTS_AROUND)
        && generator.exact().is_some_and(|surfaces| {
            surfaces
                .iter()
                .all(|s| matches!(s, ExactSurface::Revolution(_) | ExactSurface::Disk { .. }))
        })
}

/// Whether `t` maps the z axis onto itself (either way up) and scales x
/// and y alike, so a shape round about its local z stays round about the
/// luminaire's.
fn keeps_axis(t: &Transform) -> bool {
    let [rx, ry, rz] = t.rotate_deg.map(f64::to_radians);
    let axis = DQuat::from_euler(EulerRot::ZYX, rz, ry, rx) * DVec3::Z;
    t.translate[0].abs() <= ON_AXIS
        && t.translate[1].abs() <= ON_AXIS
        && axis.x.abs() <= ON_AXIS
        && axis.y.abs() <= ON_AXIS
        && t.scale[0].abs() == t.scale[1].abs()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_support::SMALL_SCENE;

    fn scene(text: &str) -> Scene {
        crate::parse_scene(text, std::path::Path::new("spot.toml")).expect("scene")
    }

    /// `SMALL_SCENE` with `from` replaced by `to` (which must occur).
    fn with(from: &str, to: &str) -> String {
        assert!(SMALL_SCENE.contains(from), "{from:?} not in the scene");
        SMALL_SCENE.replace(from, to)
    }

    const LED: &str = r#"shape = { type = "disk", radius = 0.002 }"#;
    const REFLECTOR: &str = "aperture_diameter = 0.08 }";

    #[test]
    fn a_paraboloid_around_an_led_on_its_axis_is_round() {
        assert!(scene(SMALL_SCENE).rotationally_symmetric());
        // Turned about z, or upside down: still round.
        for turn in ["[0.0, 0.0, 33.0]", "[180.0, 0.0, 0.0]"] {
            let turned = with(
                LED,
                &format!("{LED}\ntransform = {{ rotate_deg = {turn} }}"),
            );
            assert!(scene(&turned).rotationally_symmetric(), "{turn}");
        }
    }

    #[test]
    fn anything_that_breaks_the_round_is_seen() {
        let broken = [
            // The LED 1 mm off the axis.
            with(
                LED,
                &format!("{LED}\ntransform = {{ translate = [0.001, 0.0, 0.0] }}"),
            ),
            // Tilted 5°.
            with(
                LED,
                &format!("{LED}\ntransform = {{ rotate_deg = [5.0, 0.0, 0.0] }}"),
            ),
            // A square LED.
            with(
                LED,
                r#"shape = { type = "rectangle", width = 0.003, depth = 0.003 }"#,
            ),
            // Facets, or too few segments.
            with(REFLECTOR, "aperture_diameter = 0.08, faceted = true }"),
            with(
                REFLECTOR,
                "aperture_diameter = 0.08, segments_around = 12 }",
            ),
            // Brushed aluminium.
            with(
                "type = \"mirror\"\nreflectance = 0.9",
                "type = \"rough_conductor\"\nreflectance = 0.9\nroughness_u = 0.05\nroughness_v = 0.2",
            ),
            // Squashed into an ellipse.
            with(
                REFLECTOR,
                &format!("{REFLECTOR}\ntransform = {{ scale = [1.0, 0.8, 1.0] }}"),
            ),
        ];
        for (i, text) in broken.iter().enumerate() {
            assert!(
                !scene(text).rotationally_symmetric(),
                "case {i} counted as round"
            );
        }
        // Isotropic roughness keeps it round.
        let rough = with(
            "type = \"mirror\"\nreflectance = 0.9",
            "type = \"rough_conductor\"\nreflectance = 0.9\nroughness_u = 0.1\nroughness_v = 0.1",
        );
        assert!(scene(&rough).rotationally_symmetric());
    }
}
