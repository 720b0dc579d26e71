//! The viewport's orbit camera about the luminaire, in luminaire
//! coordinates (m, z up, nadir −z, C0 along +x).

use glam::{Mat4, Vec2, Vec3};

/// Vertical field of view: a moderate telephoto, so reflectors keep their
/// proportions.
pub const FIELD_OF_VIEW_Y_RAD: f32 = 0.6;

/// Pitch stops short of the poles, where "up" would be undefined.
const MAX_PITCH_RAD: f32 = 1.5620;

/// A sphere that holds what is drawn.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bounds {
    pub centre: Vec3,
    pub radius: f32,
}

impl Bounds {
    /// The sphere about the box of `points`; a unit-ish default for none.
    pub fn of_points(points: &[Vec3]) -> Bounds {
        let (lo, hi) = points.iter().filter(|p| p.is_finite()).fold(
            (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
            |(lo, hi), p| (lo.min(*p), hi.max(*p)),
        );
        if lo.x > hi.x {
            return Bounds {
                centre: Vec3::ZERO,
                radius: 0.1,
            };
        }
        Bounds {
            centre: 0.5 * (lo + hi),
            radius: (0.5 * (hi - lo).length()).max(1e-3),
        }
    }
}

/// The views a datasheet shows a luminaire in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StandardView {
    /// From −y: C0 (+x) to the right, up is up.
    Front,
    /// From +x: C90 (+y) to the right.
    Side,
    /// From below, into the opening.
    Below,
    /// From above and aside: the outline, and the light on the cube's
    /// floor behind it.
    Perspective,
}

impl StandardView {
    pub const ALL: [StandardView; 4] = [
        StandardView::Perspective,
        StandardView::Front,
        StandardView::Side,
        StandardView::Below,
    ];

    pub fn label(self) -> &'static str {
        match self {
            StandardView::Front => "Front",
            StandardView::Side => "Side",
            StandardView::Below => "Below",
            StandardView::Perspective => "Perspective",
        }
    }

    /// (yaw, pitch) of the direction from the target to the eye.
    fn angles(self) -> (f32, f32) {
        use std::f32::consts::FRAC_PI_2;
        match self {
            StandardView::Front => (-FRAC_PI_2, 0.0),
            StandardView::Side => (0.0, 0.0),
            StandardView::Below => (-FRAC_PI_2, -MAX_PITCH_RAD),
            StandardView::Perspective => (-1.0, 0.4),
        }
    }
}

/// Orbits a target point: yaw about +z, pitch above the horizon.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OrbitCamera {
    pub target: Vec3,
    pub distance: f32,
    pub yaw_rad: f32,
    pub pitch_rad: f32,
}

impl Default for OrbitCamera {
    fn default() -> Self {
        let mut camera = OrbitCamera {
            target: Vec3::ZERO,
            distance: 0.5,
            yaw_rad: 0.0,
            pitch_rad: 0.0,
        };
        camera.look_from(StandardView::Perspective);
        camera
    }
}

impl OrbitCamera {
    /// Unit vector from the target to the eye.
    fn backward(&self) -> Vec3 {
        let (sy, cy) = self.yaw_rad.sin_cos();
        let (sp, cp) = self.pitch_rad.sin_cos();
        Vec3::new(cp * cy, cp * sy, sp)
    }

    pub fn eye(&self) -> Vec3 {
        self.target + self.distance * self.backward()
    }

    pub fn view(&self) -> Mat4 {
        glam::camera::rh::view::look_at_mat4(self.eye(), self.target, Vec3::Z)
    }

    /// Perspective for `aspect` (width / height) with depth planes around
    /// `bounds` (wgpu's 0..1 depth).
    pub fn view_projection(&self, aspect: f32, bounds: Bounds) -> Mat4 {
        let reach = (self.eye() - bounds.centre).length();
        let far = reach + 2.0 * bounds.radius;
        let near = (reach - 2.0 * bounds.radius).max(far * 1e-4);
        // wgpu's clip space: depth 0..1, y up (Direct3D's convention).
        glam::camera::rh::proj::directx::perspective(
            FIELD_OF_VIEW_Y_RAD,
            aspect.max(1e-3),
            near,
            far,
        ) * self.view()
    }

    pub fn look_from(&mut self, view: StandardView) {
        (self.yaw_rad, self.pitch_rad) = view.angles();
    }

    /// Centres `bounds` and backs off until its sphere fits a view of
    /// `aspect` (width / height) both ways.
    pub fn frame(&mut self, bounds: Bounds, aspect: f32) {
        let half_y = 0.5 * FIELD_OF_VIEW_Y_RAD;
        let half_x = (half_y.tan() * aspect.clamp(0.05, 20.0)).atan();
        self.target = bounds.centre;
        self.distance = 1.1 * bounds.radius / half_y.min(half_x).sin();
    }

    /// Turns by a pointer drag of `delta` points.
    pub fn orbit(&mut self, delta: Vec2) {
        self.yaw_rad -= delta.x * 0.008;
        self.pitch_rad = (self.pitch_rad + delta.y * 0.008).clamp(-MAX_PITCH_RAD, MAX_PITCH_RAD);
    }

    /// Moves the target with the pointer: a drag of `delta` points in a
    /// view `height` points tall moves the scene under the pointer.
    pub fn pan(&mut self, delta: Vec2, height: f32) {
        let per_point = 2.0 * self.distance * (0.5 * FIELD_OF_VIEW_Y_RAD).tan() / height.max(1.0);
        let forward = -self.backward();
        let right = forward.cross(Vec3::Z).normalize_or(Vec3::X);
        let up = right.cross(forward);
        self.target += (-delta.x * right + delta.y * up) * per_point;
    }

    /// Dollies in (positive `scroll`) or out, never through the target.
    pub fn zoom(&mut self, scroll: f32, bounds: Bounds) {
        let factor = (-scroll * 0.003).exp().clamp(0.5, 2.0);
        self.distance = (self.distance * factor).clamp(0.02 * bounds.radius, 200.0 * bounds.radius);
    }

    /// The ray through a point of the view, `ndc` in [−1, 1]² (y up):
    /// origin and unit direction.
    pub fn ray(&self, ndc: Vec2, aspect: f32, bounds: Bounds) -> (Vec3, Vec3) {
        let inverse = self.view_projection(aspect, bounds).inverse();
        let near = inverse.project_point3(ndc.extend(0.0));
        let far = inverse.project_point3(ndc.extend(1.0));
        (near, (far - near).normalize_or(-self.backward()))
    }

    /// Where a point lands in the view, `ndc` in [−1, 1]² (y up), if in
    /// front of the camera.
    pub fn project(&self, point: Vec3, aspect: f32, bounds: Bounds) -> Option<Vec2> {
        let clip = self.view_projection(aspect, bounds) * point.extend(1.0);
        (clip.w > 0.0).then(|| Vec2::new(clip.x / clip.w, clip.y / clip.w))
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    const BOUNDS: Bounds = Bounds {
        centre: Vec3::new(0.0, 0.0, 0.05),
        radius: 0.1,
    };

    fn framed(view: StandardView) -> OrbitCamera {
        let mut c = OrbitCamera::default();
        c.look_from(view);
        c.frame(BOUNDS, 1.0);
        c
    }

    #[test]
    fn standard_views_put_the_axes_where_datasheets_do() {
        // Front: +x to the right, +z up.
        let c = framed(StandardView::Front);
        let right = c
            .project(BOUNDS.centre + Vec3::X * 0.05, 1.0, BOUNDS)
            .unwrap();
        let up = c
            .project(BOUNDS.centre + Vec3::Z * 0.05, 1.0, BOUNDS)
            .unwrap();
        assert!(right.x > 0.1 && right.y.abs() < 1e-4, "{right}");
        assert!(up.y > 0.1 && up.x.abs() < 1e-4, "{up}");
        // Side: +y to the right.
        let c = framed(StandardView::Side);
        let right = c
            .project(BOUNDS.centre + Vec3::Y * 0.05, 1.0, BOUNDS)
            .unwrap();
        assert!(right.x > 0.1 && right.y.abs() < 1e-4, "{right}");
        // Below: the eye is under the luminaire, looking up.
        let c = framed(StandardView::Below);
        assert!(c.eye().z < BOUNDS.centre.z - 0.9 * c.distance);
    }

    #[test]
    fn a_framed_sphere_fits_the_view_and_rays_invert_projection() {
        for view in StandardView::ALL {
            let c = framed(view);
            let (origin, dir) = c.ray(Vec2::ZERO, 1.5, BOUNDS);
            // The centre ray passes through the target.
            let to_target = c.target - origin;
            assert!(to_target.cross(dir).length() < 1e-4 * to_target.length());
            // Points on the sphere's rim project inside the view.
            let forward = (c.target - c.eye()).normalize();
            let side = forward.cross(Vec3::Z).normalize_or(Vec3::X);
            let up = side.cross(forward);
            for rim in [side, -side, up, -up] {
                let p = c.project(BOUNDS.centre + rim * BOUNDS.radius, 1.0, BOUNDS);
                let p = p.unwrap();
                assert!(p.x.abs() < 1.0 && p.y.abs() < 1.0, "{view:?} {p}");
            }
            // A ray through a projected point comes back through it.
            let point = BOUNDS.centre + Vec3::new(0.03, -0.02, 0.01);
            let ndc = c.project(point, 1.5, BOUNDS).unwrap();
            let (o, d) = c.ray(ndc, 1.5, BOUNDS);
            let miss = (point - o).cross(d).length();
            assert!(miss < 1e-5, "{view:?}: {miss}");
        }
    }

    #[test]
    fn zoom_never_passes_the_target_and_pan_follows_the_pointer() {
        let mut c = framed(StandardView::Front);
        for _ in 0..100 {
            c.zoom(1000.0, BOUNDS);
        }
        assert!(c.distance >= 0.02 * BOUNDS.radius * 0.999);
        let mut c = framed(StandardView::Front);
        let before = c.target;
        // Dragging right moves the scene right: the target moves left (−x).
        c.pan(Vec2::new(50.0, 0.0), 500.0);
        assert!(c.target.x < before.x);
        assert!((c.target.z - before.z).abs() < 1e-6);
    }
}
