#![allow(clippy::unwrap_used, clippy::expect_used)]
//! The cubature against exact and reference solutions.

use std::sync::Arc;

use glam::{DMat3, DVec3};
use lucerna_room::cubature::{
    CubatureRule, illuminance, illuminance_with, point_illuminance, triangle_solid_angle,
};
use lucerna_room::reference::{SplitMix, monte_carlo_illuminance, uniform_polygon_illuminance};
use lucerna_room::{Opening, PlacedLight, ProfileGrid};

fn lambertian(i0: f64) -> Arc<ProfileGrid> {
    Arc::new(ProfileGrid::from_fn(true, |_, g| {
        if g <= 90.0 {
            i0 * g.to_radians().cos()
        } else {
            0.0
        }
    }))
}

fn light(
    profile: Arc<ProfileGrid>,
    opening: Opening,
    position: DVec3,
    rotation: DMat3,
) -> PlacedLight {
    PlacedLight {
        profile,
        opening,
        position,
        rotation,
    }
}

#[test]
fn solid_angle_of_a_cube_face_is_four_pi_over_six() {
    // Two triangles of one face of the cube [-1, 1]³ seen from its centre.
    let v = |x: f64, y: f64| DVec3::new(x, y, 1.0).normalize();
    let omega = triangle_solid_angle(v(-1.0, -1.0), v(1.0, -1.0), v(1.0, 1.0))
        + triangle_solid_angle(v(-1.0, -1.0), v(1.0, 1.0), v(-1.0, 1.0));
    assert!(
        (omega - 4.0 * std::f64::consts::PI / 6.0).abs() < 1e-12,
        "{omega}"
    );
    // Degenerate triangles give 0, not NaN.
    assert_eq!(
        triangle_solid_angle(v(0.0, 0.0), v(0.0, 0.0), v(1.0, 0.0)),
        0.0
    );
}

/// Uniform (Lambertian) 1 m × 0.6 m opening: the cubature against the
/// exact polygon-to-point form factor at receivers of every orientation
/// in front of the light.
#[test]
fn lambertian_rectangle_matches_the_exact_form_factor_within_two_percent() {
    let i0 = 1000.0;
    let opening = Opening::Rectangle {
        length_m: 1.0,
        width_m: 0.6,
    };
    let tilt = DMat3::from_rotation_x(0.3) * DMat3::from_rotation_z(0.4);
    let l = light(lambertian(i0), opening, DVec3::new(0.2, -0.1, 3.0), tilt);
    let radiance = i0 / opening.area_m2();
    let polygon = l.world_polygon();
    let mut rng = SplitMix::new(7);
    let mut worst = 0.0f64;
    let mut worst_paper = 0.0f64;
    let mut tested = 0;
    for _ in 0..4000 {
        // Receivers within 4 m of the light, in front of its plane.
        let x = l.position + rng.unit_vector() * (0.02 + 4.0 * rng.next_f64());
        if (x - l.position).dot(l.normal()) <= 1e-3 {
            continue;
        }
        let n = rng.unit_vector();
        let exact = uniform_polygon_illuminance(&polygon, radiance, x, n);
        let got = illuminance(&l, x, n).lux;
        assert!(got.is_finite() && got >= 0.0);
        // Relative to the receiver's own illuminance, with a floor of 0.1 %
        // of what a receiver facing the light at that distance gets.
        let facing =
            uniform_polygon_illuminance(&polygon, radiance, x, (l.position - x).normalize());
        let floor = exact.max(1e-3 * facing);
        worst = worst.max((got - exact).abs() / floor);
        let paper = illuminance_with(&l, x, n, CubatureRule::Paper).lux;
        worst_paper = worst_paper.max((paper - exact).abs() / floor);
        tested += 1;
    }
    eprintln!(
        "Lambertian rectangle: {tested} receivers, worst relative error {:.4} % (the paper's eq. 10: {:.2} %)",
        worst * 100.0,
        worst_paper * 100.0
    );
    assert!(tested > 1500);
    assert!(worst <= 0.02, "worst relative error {worst}");
}

/// Beyond five times the opening's size the cubature agrees with the
/// inverse-square law within 1 % for a Lambertian opening (the five-times
/// rule is a statement about near-diffuse emitters), at receivers that see
/// the light at cos θ ≥ 0.2. For a C-dependent profile the point law itself
/// is off by about as much (its curvature across the opening's angular
/// size), so there the cubature is held to the Monte Carlo truth (1 %).
#[test]
fn far_field_matches_the_inverse_square_law_within_one_percent() {
    let smooth = Arc::new(ProfileGrid::from_fn(false, |c, g| {
        let cg = g.to_radians().cos().max(0.0);
        // C-dependence fading at the pole, so the function is smooth on the sphere.
        let sg = g.to_radians().sin();
        1000.0 * cg * (1.0 + 0.3 * sg * sg * (2.0 * c.to_radians()).cos()) + 20.0
    }));
    let opening = Opening::Rectangle {
        length_m: 0.6,
        width_m: 0.3,
    };
    for (name, profile, against_mc) in [
        ("Lambertian", lambertian(1000.0), false),
        ("C-dependent", smooth, true),
    ] {
        let l = light(
            profile,
            opening,
            DVec3::new(0.0, 0.0, 0.0),
            DMat3::from_rotation_x(0.2),
        );
        let size = l.size_m();
        let mut rng = SplitMix::new(11);
        let (mut worst_point, mut worst_mc, mut tested) = (0.0f64, 0.0f64, 0);
        for _ in 0..600 {
            let d = rng.unit_vector();
            let x = d * size * (5.0 + 20.0 * rng.next_f64());
            let n = (-d + rng.unit_vector() * 0.8).normalize();
            if n.dot(-d) < 0.2 || l.candela_towards(d) < 0.05 * 1000.0 {
                continue;
            }
            let point = point_illuminance(&l, x, n).lux;
            let got = illuminance(&l, x, n).lux;
            worst_point = worst_point.max((got - point).abs() / point);
            if against_mc {
                let mc = monte_carlo_illuminance(&l, x, n, 4096, 5);
                worst_mc = worst_mc.max((got - mc).abs() / mc);
            }
            tested += 1;
        }
        eprintln!(
            "far field, {name}: {tested} receivers, worst vs I cos/d² {:.3} %, vs Monte Carlo {:.3} %",
            worst_point * 100.0,
            worst_mc * 100.0
        );
        assert!(tested > 100);
        if against_mc {
            assert!(worst_mc <= 0.01, "{name}: {worst_mc}");
        } else {
            assert!(worst_point <= 0.01, "{name}: {worst_point}");
        }
    }
}

/// Points in the light's plane, on the opening itself, behind it and
/// grazing: never NaN, never negative.
#[test]
fn no_nan_or_negative_anywhere() {
    let profile = Arc::new(ProfileGrid::from_fn(false, |c, g| {
        500.0 + 400.0 * (c.to_radians() + g.to_radians()).sin()
    }));
    for opening in [
        Opening::Rectangle {
            length_m: 1.0,
            width_m: 1.0,
        },
        Opening::Disk { diameter_m: 0.4 },
        Opening::Point,
    ] {
        let l = light(
            profile.clone(),
            opening,
            DVec3::new(0.0, 0.0, 2.0),
            DMat3::IDENTITY,
        );
        let mut rng = SplitMix::new(3);
        let probe = |x: DVec3, n: DVec3| {
            let r = illuminance(&l, x, n);
            assert!(
                r.lux.is_finite() && r.lux >= 0.0,
                "{opening:?} at {x} normal {n}: {r:?}"
            );
            assert!(r.cosine_solid_angle.is_finite() && r.cosine_solid_angle >= 0.0);
            assert!(r.equivalent_radiance().is_finite());
        };
        for _ in 0..3000 {
            let n = rng.unit_vector();
            let u = 4.0 * rng.next_f64() - 2.0;
            let v = 4.0 * rng.next_f64() - 2.0;
            probe(DVec3::new(u, v, 2.0), n); // in the plane
            probe(DVec3::new(u * 0.25, v * 0.25, 2.0), n); // on the opening
            probe(DVec3::new(u, v, 2.0 + 1e-9), n);
            probe(DVec3::new(u, v, 2.0 + 3.0 * rng.next_f64()), n); // behind
            probe(DVec3::new(u, v, 2.0 - 3.0 * rng.next_f64()), n);
        }
        probe(l.position, DVec3::Z);
        probe(l.position, DVec3::NEG_Z);
    }
}

/// The Monte Carlo reference itself converges to the exact form factor
/// (so it can serve as ground truth for measured profiles).
#[test]
fn monte_carlo_reference_converges_to_the_exact_solution() {
    let i0 = 800.0;
    let opening = Opening::Rectangle {
        length_m: 1.0,
        width_m: 1.0,
    };
    let l = light(
        lambertian(i0),
        opening,
        DVec3::new(0.0, 0.0, 1.0),
        DMat3::IDENTITY,
    );
    let polygon = l.world_polygon();
    for (x, n) in [
        (DVec3::new(0.0, 0.0, 0.9), DVec3::Z),
        (
            DVec3::new(0.3, 0.1, 0.5),
            DVec3::new(0.3, 0.0, 1.0).normalize(),
        ),
        (DVec3::new(1.5, 0.0, 0.0), DVec3::Z),
    ] {
        let exact = uniform_polygon_illuminance(&polygon, i0, x, n);
        let mc = monte_carlo_illuminance(&l, x, n, 16384, 1);
        assert!(
            (mc - exact).abs() / exact < 2e-3,
            "{x}: MC {mc} exact {exact}"
        );
    }
}

/// The MIS reference agrees with the exact form factor for a uniform
/// opening, and with brute-force area sampling (10⁶ points) for a narrow
/// 3° beam close to the opening, where 1024 area samples alone miss most
/// of the light.
#[test]
fn mis_reference_is_right_for_wide_and_narrow_profiles() {
    use lucerna_room::reference::{ProfileDirectionSampler, mis_illuminance};
    let i0 = 800.0;
    let opening = Opening::Rectangle {
        length_m: 1.0,
        width_m: 1.0,
    };
    let wide = light(
        lambertian(i0),
        opening,
        DVec3::new(0.0, 0.0, 1.0),
        DMat3::from_rotation_x(0.4),
    );
    let sampler = ProfileDirectionSampler::new(&wide.profile).unwrap();
    let polygon = wide.world_polygon();
    for x in [
        DVec3::new(0.0, 0.0, 0.9),
        DVec3::new(0.3, -0.4, 0.2),
        DVec3::new(1.5, 0.0, 0.0),
    ] {
        let exact = uniform_polygon_illuminance(&polygon, i0, x, DVec3::Z);
        let mis = mis_illuminance(&wide, &sampler, x, DVec3::Z, 4096, 3);
        // Converges: 0.86 % off at 4096 samples per technique, 0.09 % at 2²⁰.
        assert!(
            (mis - exact).abs() / exact < 0.015,
            "{x}: MIS {mis} exact {exact}"
        );
    }
    // A 3° (half-angle) cosine-power spot, 0.1 m above the ground.
    let spot = Arc::new(ProfileGrid::from_fn(true, |_, g| {
        if g <= 90.0 {
            1e5 * g.to_radians().cos().powi(1000)
        } else {
            0.0
        }
    }));
    let l = light(spot, opening, DVec3::new(0.0, 0.0, 0.1), DMat3::IDENTITY);
    let sampler = ProfileDirectionSampler::new(&l.profile).unwrap();
    for x in [DVec3::new(0.1, 0.2, 0.0), DVec3::new(0.49, 0.0, 0.0)] {
        let truth = monte_carlo_illuminance(&l, x, DVec3::Z, 1_000_000, 11);
        let mis = mis_illuminance(&l, &sampler, x, DVec3::Z, 1024, 5);
        let area_only = monte_carlo_illuminance(&l, x, DVec3::Z, 1024, 5);
        eprintln!(
            "narrow spot at {x}: brute force {truth:.1}, MIS {mis:.1}, area sampling {area_only:.1}"
        );
        assert!((mis - truth).abs() / truth < 0.03, "MIS {mis} vs {truth}");
    }
}
