//! Cylinder (housings, tubes, cans).

use glam::{DVec2, DVec3};
use serde::{Deserialize, Serialize};

use super::ShapeGenerator;
use crate::check::{Checker, FieldPath};
use crate::exact::{ExactSurface, ProfileCurve};
use crate::generators::{disk, revolve};
use crate::mesh::TriangleMesh;
use crate::profile::sample_curve;

/// Cylinder about z, centred at the origin, outward normals.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Cylinder {
    /// Radius (m).
    pub radius: f64,
    /// Extent along z (m).
    pub height: f64,
    /// Close the top (z = height / 2) with a disk.
    #[serde(
        default = "crate::shapes::defaults::yes",
        skip_serializing_if = "crate::shapes::defaults::is_true"
    )]
    pub cap_top: bool,
    /// Close the bottom (z = −height / 2) with a disk.
    #[serde(
        default = "crate::shapes::defaults::yes",
        skip_serializing_if = "crate::shapes::defaults::is_true"
    )]
    pub cap_bottom: bool,
    #[serde(default = "crate::shapes::defaults::default_around")]
    pub segments_around: u32,
}

impl ShapeGenerator for Cylinder {
    fn kind(&self) -> &'static str {
        "cylinder"
    }

    fn segments_around(&self) -> Option<u32> {
        Some(self.segments_around)
    }

    fn validate(&self, at: &FieldPath, check: &mut Checker<'_>) {
        check.length(at, "radius", self.radius);
        check.length(at, "height", self.height);
        check.segments(at, "segments_around", self.segments_around, 3);
    }

    /// Two per step around on the side, one per step on each cap.
    fn triangle_count(&self) -> Option<u64> {
        let caps = u64::from(self.cap_top) + u64::from(self.cap_bottom);
        Some((2 + caps) * u64::from(self.segments_around))
    }

    fn generate(&self) -> Option<TriangleMesh> {
        let (radius, segments_around) = (self.radius, self.segments_around);
        let h = 0.5 * self.height;
        // Bottom to top: the right-hand normal of the profile points out.
        let side = sample_curve(
            -h,
            h,
            1,
            |z| DVec2::new(radius, z),
            |_| DVec2::new(0.0, 1.0),
        );
        let mut mesh = revolve(&[side], segments_around, false);
        if self.cap_top {
            mesh.append(&disk(radius, h, segments_around, DVec3::Z));
        }
        if self.cap_bottom {
            mesh.append(&disk(radius, -h, segments_around, DVec3::NEG_Z));
        }
        Some(mesh)
    }

    fn exact(&self) -> Option<Vec<ExactSurface>> {
        let (radius, h) = (self.radius, 0.5 * self.height);
        let mut surfaces = vec![ExactSurface::Revolution(vec![ProfileCurve::Line {
            from: DVec2::new(radius, -h),
            to: DVec2::new(radius, h),
        }])];
        if self.cap_top {
            surfaces.push(ExactSurface::Disk { radius, z: h });
        }
        if self.cap_bottom {
            surfaces.push(ExactSurface::Disk { radius, z: -h });
        }
        Some(surfaces)
    }
}
