//! The CPU renderer: one view ray per pixel into the box room, diffuse
//! cubature plus LTC specular from every light (no visibility, as in the
//! paper), the openings drawn with their own luminance.

use glam::DVec3;
use rayon::prelude::*;

use crate::cubature::{self, CubatureResult, CubatureRule};
use crate::light::{PlacedLight, Polygon};
use crate::ltc;
use crate::scene::RoomScene;

/// How lights are shaded.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Shading {
    /// Photometric polygonal lights (eq. 1–3 of Luksch et al. 2020) by
    /// the default `CubatureRule` (the polar rule), with LTC specular.
    Cubature,
    /// One intensity lookup and inverse-square law from the opening's
    /// centre, no specular: the point-light baseline.
    PointLight,
    /// The polar rule with fewer nodes (`polar::RuleNodes::draft`), LTC
    /// specular: the editor's room while a drag runs.
    Draft,
}

impl Shading {
    /// Whether surfaces get their LTC specular term.
    pub fn has_specular(self) -> bool {
        self != Shading::PointLight
    }
}

/// A rendered view: luminance for the picture, surface illuminance for the
/// false-colour view. Pixels showing a luminaire's opening have
/// illuminance −1.
#[derive(Debug, Clone, PartialEq)]
pub struct Frame {
    pub width: u32,
    pub height: u32,
    /// cd/m².
    pub luminance: Vec<f32>,
    /// lx on the surface seen in the pixel.
    pub illuminance: Vec<f32>,
}

/// The pinhole camera's frame: origin, and per pixel a direction.
#[derive(Debug, Clone, Copy)]
pub struct ViewRays {
    pub origin: DVec3,
    pub forward: DVec3,
    pub right: DVec3,
    pub up: DVec3,
    pub tan_half_fov: f64,
    pub aspect: f64,
}

impl ViewRays {
    pub fn new(scene: &RoomScene, width: u32, height: u32) -> ViewRays {
        let c = scene.camera;
        let origin = DVec3::from_array(c.position);
        let forward = (DVec3::from_array(c.look_at) - origin).normalize();
        let mut right = forward.cross(DVec3::Z);
        if right.length_squared() < 1e-12 {
            right = DVec3::X;
        }
        let right = right.normalize();
        let up = right.cross(forward);
        ViewRays {
            origin,
            forward,
            right,
            up,
            tan_half_fov: (c.fov_deg.to_radians() / 2.0).tan(),
            aspect: width as f64 / height as f64,
        }
    }

    /// Direction through the centre of pixel (i, j), j from the top.
    pub fn direction(&self, i: u32, j: u32, width: u32, height: u32) -> DVec3 {
        let sx = (2.0 * (i as f64 + 0.5) / width as f64 - 1.0) * self.tan_half_fov * self.aspect;
        let sy = (1.0 - 2.0 * (j as f64 + 0.5) / height as f64) * self.tan_half_fov;
        (self.forward + self.right * sx + self.up * sy).normalize()
    }
}

/// Illuminance from one light at a point, by the chosen shading.
pub fn light_illuminance(
    light: &PlacedLight,
    x: DVec3,
    n: DVec3,
    shading: Shading,
) -> CubatureResult {
    light_illuminance_of(light, &light.world_polygon(), x, n, shading)
}

/// As [`light_illuminance`] with the opening's room-space polygon given.
fn light_illuminance_of(
    light: &PlacedLight,
    polygon: &[DVec3],
    x: DVec3,
    n: DVec3,
    shading: Shading,
) -> CubatureResult {
    match shading {
        Shading::Cubature => {
            cubature::illuminance_of(light, polygon, x, n, CubatureRule::default())
        }
        Shading::PointLight => cubature::point_illuminance(light, x, n),
        Shading::Draft => {
            crate::polar::illuminance_with_nodes(
                light,
                x,
                n,
                crate::polar::RuleNodes::draft(&light.profile),
            )
            .0
        }
    }
}

/// Distance along a ray to a light's opening (`polygon`, its
/// `world_polygon()`) and the opening's luminance seen from there, if the
/// ray meets it.
pub fn opening_hit(
    light: &PlacedLight,
    polygon: &[DVec3],
    origin: DVec3,
    dir: DVec3,
) -> Option<(f64, f64)> {
    if polygon.len() < 3 {
        return None;
    }
    let normal = light.normal();
    let denom = dir.dot(normal);
    if denom.abs() < 1e-12 {
        return None;
    }
    let t = (light.position - origin).dot(normal) / denom;
    if t <= 0.0 {
        return None;
    }
    let p = origin + dir * t;
    let q = cubature::closest_point_on_polygon(polygon, normal, p);
    if (q - p).length_squared() > 1e-18 {
        return None;
    }
    let luminance = light.candela_towards(-dir) / (light.opening.area_m2() * denom.abs());
    Some((t, luminance))
}

/// Luminance and illuminance seen along one view ray; `polygons` are the
/// lights' openings in room coordinates (computed once per frame),
/// `indirect_lux` is added to every surface (see
/// `RoomScene::indirect_lux`).
pub fn shade_ray(
    scene: &RoomScene,
    polygons: &[Polygon],
    origin: DVec3,
    dir: DVec3,
    shading: Shading,
    indirect_lux: f64,
) -> (f64, f64) {
    let hit = scene.cast(origin, dir);
    let mut nearest_light: Option<(f64, f64)> = None;
    for (light, polygon) in scene.lights.iter().zip(polygons) {
        if let Some((t, l)) = opening_hit(light, polygon, origin, dir)
            && t < hit.distance
            && nearest_light.is_none_or(|(bt, _)| t < bt)
        {
            nearest_light = Some((t, l));
        }
    }
    if let Some((_, l)) = nearest_light {
        return (l, -1.0);
    }
    if !hit.distance.is_finite() {
        return (0.0, 0.0); // out through a gap in an OBJ room
    }
    let x = origin + dir * hit.distance;
    let n = hit.normal;
    let surface = scene.surfaces[hit.surface];
    let to_viewer = -dir;
    let mut lux = indirect_lux;
    let mut luminance = surface.reflectance / std::f64::consts::PI * indirect_lux;
    for (light, polygon) in scene.lights.iter().zip(polygons) {
        let r = light_illuminance_of(light, polygon, x, n, shading);
        lux += r.lux;
        luminance += surface.reflectance / std::f64::consts::PI * r.lux;
        if shading.has_specular() && surface.specular > 0.0 && r.lux > 0.0 {
            luminance += ltc::specular_radiance(
                polygon,
                x,
                n,
                to_viewer,
                surface.roughness,
                surface.specular,
                r.equivalent_radiance(),
            );
        }
    }
    (luminance, lux)
}

/// Renders the camera's view on the CPU (rayon over rows).
pub fn render_cpu(scene: &RoomScene, width: u32, height: u32, shading: Shading) -> Frame {
    render_cpu_rows(scene, width, height, 0..height, shading)
}

/// Rows `rows` (from the top) of the camera's `width × height` view, as a
/// frame `rows.len()` pixels high: a caller can render a frame in bands and
/// give up between them (the editor's preview, when a newer request comes).
pub fn render_cpu_rows(
    scene: &RoomScene,
    width: u32,
    height: u32,
    rows: std::ops::Range<u32>,
    shading: Shading,
) -> Frame {
    let rays = ViewRays::new(scene, width, height);
    let indirect = scene.indirect_lux();
    let polygons: Vec<Polygon> = scene.lights.iter().map(|l| l.world_polygon()).collect();
    let polygons = &polygons;
    let rows = rows.start.min(height)..rows.end.min(height);
    let band_height = rows.len() as u32;
    let pixels: Vec<(f32, f32)> = rows
        .into_par_iter()
        .flat_map_iter(|j| {
            (0..width).map(move |i| {
                let dir = rays.direction(i, j, width, height);
                let (l, e) = shade_ray(scene, polygons, rays.origin, dir, shading, indirect);
                (l as f32, e as f32)
            })
        })
        .collect();
    Frame {
        width,
        height: band_height,
        luminance: pixels.iter().map(|p| p.0).collect(),
        illuminance: pixels.iter().map(|p| p.1).collect(),
    }
}

/// Reinhard's global operator with key 0.18 over the log-average luminance
/// of the lit surfaces, then sRGB: 8-bit RGB, row-major.
pub fn tone_map(frame: &Frame) -> Vec<u8> {
    let surfaces: Vec<f64> = frame
        .luminance
        .iter()
        .zip(&frame.illuminance)
        .filter(|(_, e)| **e >= 0.0)
        .map(|(l, _)| *l as f64)
        .collect();
    let log_average = if surfaces.is_empty() {
        1.0
    } else {
        (surfaces.iter().map(|l| (l + 1e-4).ln()).sum::<f64>() / surfaces.len() as f64).exp()
    };
    let scale = 0.18 / log_average.max(1e-9);
    let mut out = Vec::with_capacity(frame.luminance.len() * 3);
    for &l in &frame.luminance {
        let v = l as f64 * scale;
        let mapped = v / (1.0 + v);
        let s = srgb(mapped);
        // A faintly warm white, as most interior renderings are.
        out.extend_from_slice(&[s, srgb(mapped * 0.97), srgb(mapped * 0.92)]);
    }
    out
}

fn srgb(linear: f64) -> u8 {
    let c = linear.clamp(0.0, 1.0);
    let e = if c <= 0.003_130_8 {
        12.92 * c
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    };
    (e * 255.0).round() as u8
}
