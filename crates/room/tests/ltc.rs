#![allow(clippy::unwrap_used, clippy::expect_used)]
//! The LTC specular term against brute-force integration of the GGX BRDF
//! (height-correlated Smith masking-shadowing, Schlick Fresnel: the model
//! the table was fitted to) over a uniform polygonal light.

use glam::DVec3;
use lucerna_room::ltc::specular_radiance;
use lucerna_room::reference::SplitMix;

fn lambda(alpha: f64, cos: f64) -> f64 {
    if cos >= 1.0 {
        return 0.0;
    }
    let tan2 = (1.0 - cos * cos) / (cos * cos);
    0.5 * (-1.0 + (1.0 + alpha * alpha * tan2).sqrt())
}

/// f_r(l, v) cos θ_l for GGX with normal +z.
fn ggx_cos(l: DVec3, v: DVec3, roughness: f64, f0: f64) -> f64 {
    if l.z <= 0.0 || v.z <= 0.0 {
        return 0.0;
    }
    let alpha = (roughness * roughness).max(1e-4);
    let h = (l + v).normalize();
    let a2 = alpha * alpha;
    let d = a2 / (std::f64::consts::PI * (h.z * h.z * (a2 - 1.0) + 1.0).powi(2));
    let g2 = 1.0 / (1.0 + lambda(alpha, v.z) + lambda(alpha, l.z));
    let f = f0 + (1.0 - f0) * (1.0 - v.dot(h).max(0.0)).powi(5);
    d * g2 * f / (4.0 * v.z)
}

/// Brute force: ∫ L f cos dω over a planar polygon (uniform area samples,
/// dω = |cos θ_A| dA / r²).
fn brute_force(polygon: &[DVec3], v: DVec3, roughness: f64, f0: f64, radiance: f64) -> f64 {
    let mut rng = SplitMix::new(9);
    let normal = (polygon[1] - polygon[0])
        .cross(polygon[2] - polygon[0])
        .normalize();
    let mut sum = 0.0;
    let mut area_total = 0.0;
    let n = 200_000;
    for i in 1..polygon.len() - 1 {
        let (a, b, c) = (polygon[0], polygon[i], polygon[i + 1]);
        let area = 0.5 * (b - a).cross(c - a).length();
        area_total += area;
        let k = n * polygon.len();
        let mut s = 0.0;
        for _ in 0..k {
            let (u, w) = (rng.next_f64(), rng.next_f64());
            let su = u.sqrt();
            let p = a * (1.0 - su) + b * (su * (1.0 - w)) + c * (su * w);
            let r2 = p.length_squared();
            let l = p / r2.sqrt();
            s += ggx_cos(l, v, roughness, f0) * l.dot(normal).abs() / r2;
        }
        sum += area * s / k as f64;
    }
    assert!(area_total > 0.0);
    radiance * sum
}

fn view(theta_deg: f64) -> DVec3 {
    let t = theta_deg.to_radians();
    DVec3::new(t.sin(), 0.0, t.cos())
}

/// A light filling the whole upper hemisphere: the LTC integral is 1 and
/// the result is the BRDF's directional albedo, which the table's
/// magnitude and Fresnel terms hold (a swapped roughness/angle index
/// fails this).
#[test]
fn hemisphere_light_gives_the_directional_albedo() {
    let big = 1e4;
    let polygon = [
        DVec3::new(-big, -big, 1.0),
        DVec3::new(big, -big, 1.0),
        DVec3::new(big, big, 1.0),
        DVec3::new(-big, big, 1.0),
    ];
    // At 75° the fit gives 9.6 % less than the albedo (0.0981 vs 0.1086
    // measured): part of the fitted lobe falls below the horizon at
    // grazing views, a property of the published table.
    for (roughness, theta) in [(0.3, 10.0), (0.5, 45.0), (0.7, 60.0), (0.9, 30.0)] {
        let v = view(theta);
        let ltc = specular_radiance(&polygon, DVec3::ZERO, DVec3::Z, v, roughness, 0.04, 1.0);
        // Analytic-free reference: integrate over the hemisphere.
        let mut rng = SplitMix::new(3);
        let n = 400_000;
        let mut s = 0.0;
        for _ in 0..n {
            // Cosine-weighted hemisphere sample.
            let (u, w) = (rng.next_f64(), rng.next_f64());
            let r = u.sqrt();
            let phi = std::f64::consts::TAU * w;
            let l = DVec3::new(r * phi.cos(), r * phi.sin(), (1.0 - u).sqrt());
            s += ggx_cos(l, v, roughness, 0.04) / l.z * std::f64::consts::PI;
        }
        let albedo = s / n as f64;
        eprintln!("roughness {roughness}, θv {theta}°: LTC {ltc:.5}, albedo {albedo:.5}");
        // The table's magnitude was integrated with 32² samples per entry.
        assert!((ltc - albedo).abs() / albedo < 0.05, "{ltc} vs {albedo}");
    }
}

/// A 1 m × 0.5 m light 1.5 m away in several positions: the LTC value is
/// within the fit's accuracy of the brute-force integral. LTC is an
/// approximation: measured 0.5–9 % here, and 21 % for a rough-ish
/// (0.5) surface seen at 60° with the light near the mirror direction
/// (too bright), the known weak spot of the fit at grazing views.
#[test]
fn rectangle_light_matches_brute_force_ggx() {
    let rect = |cx: f64, cy: f64, z: f64| {
        [
            DVec3::new(cx - 0.5, cy - 0.25, z),
            DVec3::new(cx + 0.5, cy - 0.25, z),
            DVec3::new(cx + 0.5, cy + 0.25, z),
            DVec3::new(cx - 0.5, cy + 0.25, z),
        ]
    };
    let mut worst = 0.0f64;
    let mut sum = 0.0;
    for (roughness, theta, cx) in [
        (0.4, 30.0, -0.9),
        (0.6, 45.0, -1.5),
        (0.8, 20.0, 0.0),
        (0.5, 60.0, -2.0),
        (0.7, 0.0, 0.3),
    ] {
        let v = view(theta);
        let polygon = rect(cx, 0.1, 1.5);
        let ltc = specular_radiance(&polygon, DVec3::ZERO, DVec3::Z, v, roughness, 0.04, 100.0);
        let bf = brute_force(&polygon, v, roughness, 0.04, 100.0);
        let err = (ltc - bf).abs() / bf;
        eprintln!(
            "roughness {roughness}, θv {theta}°, light at x = {cx}: LTC {ltc:.4}, brute force {bf:.4} ({:.1} %)",
            100.0 * err
        );
        worst = worst.max(err);
        sum += err;
    }
    assert!(
        worst < 0.25 && sum / 5.0 < 0.1,
        "worst {worst}, mean {}",
        sum / 5.0
    );
}
