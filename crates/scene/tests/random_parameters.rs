#![allow(clippy::unwrap_used, clippy::expect_used)] // reason: test helpers may panic
//! Property test: generators never panic or produce NaN for any parameters
//! that pass validation.

use lucerna_scene::shapes::generate;
use lucerna_scene::shapes::{Cylinder, Dome, Ellipsoid, Extruded, Louvre, Paraboloid, Revolved};
use lucerna_scene::{Interpolation, Shape};
use proptest::prelude::*;

fn len() -> impl Strategy<Value = f64> {
    1e-3f64..2.0
}

fn shape() -> impl Strategy<Value = Shape> {
    let seg = 3u32..64;
    prop_oneof![
        (
            len(),
            len(),
            0.0f64..0.99,
            seg.clone(),
            1u32..40,
            any::<bool>()
        )
            .prop_map(|(f, a, neck, around, along, faceted)| Shape::Paraboloid(
                Paraboloid {
                    focal_length: f,
                    aperture_diameter: a,
                    neck_diameter: a * neck,
                    segments_around: around,
                    segments_along: along,
                    faceted
                }
            )),
        (
            len(),
            len(),
            0.0f64..1.0,
            seg.clone(),
            1u32..40,
            any::<bool>()
        )
            .prop_map(|(fd, vd, cut, around, along, faceted)| Shape::Ellipsoid(
                Ellipsoid {
                    focal_distance: fd,
                    vertex_distance: vd,
                    cut_below_focus: -vd + cut * (fd + 2.0 * vd) * 0.999 + 1e-6,
                    neck_diameter: 0.0,
                    segments_around: around,
                    segments_along: along,
                    faceted
                }
            )),
        (
            prop::collection::vec((0.0f64..0.5, -0.5f64..0.5), 2..8),
            seg.clone(),
            1u32..10,
            any::<bool>(),
            any::<bool>()
        )
            .prop_map(
                |(pts, around, per, faceted, linear)| Shape::Revolved(Revolved {
                    profile: pts.into_iter().map(|(r, z)| [r, z]).collect(),
                    interpolation: if linear {
                        Interpolation::Linear
                    } else {
                        Interpolation::CatmullRom
                    },
                    segments_around: around,
                    segments_per_span: per,
                    faceted
                })
            ),
        (
            prop::collection::vec((-0.5f64..0.5, -0.5f64..0.5), 2..8),
            len(),
            1u32..10,
            any::<bool>(),
            any::<bool>()
        )
            .prop_map(
                |(pts, length, per, caps, linear)| Shape::Extruded(Extruded {
                    profile: pts.into_iter().map(|(x, z)| [x, z]).collect(),
                    length,
                    interpolation: if linear {
                        Interpolation::Linear
                    } else {
                        Interpolation::CatmullRom
                    },
                    segments_per_span: per,
                    end_caps: caps
                })
            ),
        (
            1u32..20,
            len(),
            len(),
            len(),
            -80.0f64..80.0,
            0u32..10,
            len()
        )
            .prop_map(|(n, s, h, l, tilt, cn, cs)| Shape::Louvre(Louvre {
                blade_count: n.max(2),
                spacing: s,
                blade_height: h,
                blade_length: l,
                tilt_deg: tilt,
                cross_blade_count: cn,
                cross_spacing: cs
            })),
        (len(), 0.01f64..2.0, seg.clone(), 1u32..40).prop_map(|(r, hf, around, along)| {
            Shape::Dome(Dome {
                radius: r,
                height: r * hf,
                segments_around: around,
                segments_along: along,
            })
        }),
        (len(), len(), any::<bool>(), any::<bool>(), seg).prop_map(|(r, h, t, b, around)| {
            Shape::Cylinder(Cylinder {
                radius: r,
                height: h,
                cap_top: t,
                cap_bottom: b,
                segments_around: around,
            })
        }),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 400, ..ProptestConfig::default() })]
    #[test]
    fn tessellation_never_panics_or_makes_nan(shape in shape()) {
        let scene_like = lucerna_scene::Scene {
            format_version: 1, name: "p".into(), description: String::new(), manufacturer: String::new(),
            materials: [("m".to_owned(), lucerna_scene::Material::Absorber)].into(),
            emitters: vec![lucerna_scene::Emitter { name: "e".into(), shape: lucerna_scene::EmitterShape::Disk { radius: 0.001 }, flux_lm: 1.0, emission: lucerna_scene::Emission::Lambertian, material: None, enabled: true, transform: Default::default() }],
            parts: vec![lucerna_scene::Part { name: "p".into(), shape: shape.clone(), material: "m".into(), enabled: true, transform: Default::default(), finish: None }],
            opening: None,
            export: Default::default(),
        };
        // Only parameters that pass validation are promised a mesh.
        prop_assume!(lucerna_scene::validate(&scene_like).is_empty());
        let mesh = generate(&shape).expect("generated");
        prop_assert!(mesh.positions.iter().all(|p| p.is_finite()));
        prop_assert!(mesh.normals.iter().all(|n| n.is_finite()));
        prop_assert_eq!(mesh.normals.len(), mesh.positions.len());
        prop_assert!(mesh.triangles.iter().flatten().all(|&i| (i as usize) < mesh.positions.len()));
    }
}
