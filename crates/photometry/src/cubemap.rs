//! Cube-map layout: faces, direction ↔ texel mapping and exact texel solid
//! angles. The WGSL twin lives in `shaders/cubemap.wgsl`; a test proves the
//! two agree.
//!
//! Faces are ordered +X, −X, +Y, −Y, +Z, −Z with the face-local (u, v) of the
//! Vulkan/WebGPU cube-map convention (v grows downwards in the face image),
//! so a map uploads as a cube texture and samples by direction unchanged.

use std::sync::{Arc, Mutex, PoisonError};

use serde::{Deserialize, Serialize};

/// Unit-free 3-vector (a direction in luminaire coordinates).
pub type Dir = [f64; 3];

/// The six faces in storage order.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[repr(u8)]
pub enum CubeFace {
    PosX = 0,
    NegX = 1,
    PosY = 2,
    NegY = 3,
    PosZ = 4,
    NegZ = 5,
}

impl CubeFace {
    pub const ALL: [CubeFace; 6] = [
        CubeFace::PosX,
        CubeFace::NegX,
        CubeFace::PosY,
        CubeFace::NegY,
        CubeFace::PosZ,
        CubeFace::NegZ,
    ];

    pub fn from_index(i: usize) -> CubeFace {
        CubeFace::ALL[i % 6]
    }

    /// Direction (not normalised) through face coordinates
    /// `a = 2u − 1`, `b = 2v − 1` in [−1, 1]: the inverse of
    /// [`face_coordinates`].
    pub fn direction(self, a: f64, b: f64) -> Dir {
        match self {
            CubeFace::PosX => [1.0, -b, -a],
            CubeFace::NegX => [-1.0, -b, a],
            CubeFace::PosY => [a, 1.0, b],
            CubeFace::NegY => [a, -1.0, -b],
            CubeFace::PosZ => [a, -b, 1.0],
            CubeFace::NegZ => [-a, -b, -1.0],
        }
    }
}

/// Face and face coordinates `(a, b) ∈ [−1, 1]²` of a direction. The major
/// axis is the largest |component|; ties go to x, then y.
#[inline]
pub fn face_coordinates(d: Dir) -> (CubeFace, f64, f64) {
    let [x, y, z] = d;
    let (ax, ay, az) = (x.abs(), y.abs(), z.abs());
    if ax >= ay && ax >= az {
        if x >= 0.0 {
            (CubeFace::PosX, -z / ax, -y / ax)
        } else {
            (CubeFace::NegX, z / ax, -y / ax)
        }
    } else if ay >= az {
        if y >= 0.0 {
            (CubeFace::PosY, x / ay, z / ay)
        } else {
            (CubeFace::NegY, x / ay, -z / ay)
        }
    } else if z >= 0.0 {
        (CubeFace::PosZ, x / az, -y / az)
    } else {
        (CubeFace::NegZ, -x / az, -y / az)
    }
}

/// `F(x, y) = atan2(x·y, √(x² + y² + 1))`: the solid angle of the face-plane
/// rectangle from (0, 0) to (x, y) at distance 1.
fn area_element(x: f64, y: f64) -> f64 {
    (x * y).atan2((x * x + y * y + 1.0).sqrt())
}

/// Exact solid angle (sr) of the face-plane rectangle [a0, a1] × [b0, b1].
pub fn rectangle_solid_angle(a0: f64, b0: f64, a1: f64, b1: f64) -> f64 {
    area_element(a1, b1) - area_element(a0, b1) - area_element(a1, b0) + area_element(a0, b0)
}

fn normalise(d: Dir) -> Dir {
    let l = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
    [d[0] / l, d[1] / l, d[2] / l]
}

/// Square cube map of `resolution` × `resolution` texels per face. Texel
/// index = face · N² + row · N + column, row counted along v.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct CubeMapLayout {
    pub resolution: u32,
}

impl CubeMapLayout {
    pub fn new(resolution: u32) -> Self {
        CubeMapLayout { resolution }
    }

    pub fn texel_count(&self) -> usize {
        6 * (self.resolution as usize).pow(2)
    }

    /// Face, column, row of a texel index.
    pub fn texel_coordinates(&self, texel: usize) -> (CubeFace, u32, u32) {
        let n = self.resolution as usize;
        let face = texel / (n * n);
        let rest = texel % (n * n);
        (
            CubeFace::from_index(face),
            (rest % n) as u32,
            (rest / n) as u32,
        )
    }

    /// Texel index of (face, column, row): the one Rust home of the texel
    /// order, twin of `cube_texel_index` in `shaders/cubemap.wgsl`.
    #[inline]
    pub fn texel_index(&self, face: CubeFace, column: u32, row: u32) -> usize {
        let n = self.resolution as usize;
        face as usize * n * n + row as usize * n + column as usize
    }

    /// Texel containing direction `d` (need not be normalised, must be
    /// non-zero and finite). Inline: the tracer calls it once per photon.
    #[inline]
    pub fn texel_of_direction(&self, d: Dir) -> usize {
        let (face, a, b) = face_coordinates(d);
        let n = self.resolution;
        let to_cell = |t: f64| {
            (((t + 1.0) * 0.5 * f64::from(n)).floor() as i64).clamp(0, i64::from(n) - 1) as u32
        };
        self.texel_index(face, to_cell(a), to_cell(b))
    }

    /// Face-coordinate bounds `(a0, b0, a1, b1)` of a texel.
    pub fn texel_bounds(&self, texel: usize) -> (CubeFace, f64, f64, f64, f64) {
        let (face, i, j) = self.texel_coordinates(texel);
        let step = 2.0 / f64::from(self.resolution);
        let a0 = -1.0 + f64::from(i) * step;
        let b0 = -1.0 + f64::from(j) * step;
        (face, a0, b0, a0 + step, b0 + step)
    }

    /// Unit direction through the texel's centre.
    pub fn texel_centre_direction(&self, texel: usize) -> Dir {
        let (face, a0, b0, a1, b1) = self.texel_bounds(texel);
        normalise(face.direction(0.5 * (a0 + a1), 0.5 * (b0 + b1)))
    }

    /// Exact solid angle of a texel (sr): `F(u1,v1) − F(u0,v1) − F(u1,v0) + F(u0,v0)`.
    pub fn texel_solid_angle(&self, texel: usize) -> f64 {
        let (_, a0, b0, a1, b1) = self.texel_bounds(texel);
        rectangle_solid_angle(a0, b0, a1, b1)
    }

    /// All texel solid angles, in texel order.
    pub fn solid_angles(&self) -> Vec<f64> {
        (0..self.texel_count())
            .map(|t| self.texel_solid_angle(t))
            .collect()
    }

    /// All texel solid angles, computed once per resolution and process
    /// and shared: four `atan2` per texel cost ~20 ms at 6 × 256², which a
    /// live preview would otherwise pay on every snapshot (candela, filter).
    pub fn shared_solid_angles(&self) -> Arc<Vec<f64>> {
        static CACHE: Mutex<Vec<(u32, Arc<Vec<f64>>)>> = Mutex::new(Vec::new());
        let mut cache = CACHE.lock().unwrap_or_else(PoisonError::into_inner);
        if let Some((_, omega)) = cache.iter().find(|(n, _)| *n == self.resolution) {
            return omega.clone();
        }
        let omega = Arc::new(self.solid_angles());
        // A few layouts at most (a bake's, the editor's coarse preview).
        if cache.len() >= 4 {
            cache.remove(0);
        }
        cache.push((self.resolution, omega.clone()));
        omega
    }
}
