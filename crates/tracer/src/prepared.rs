//! The luminaire prepared for tracing: BVH, per-triangle shading data and
//! materials, emitter samplers. Shared by the CPU tracer and the GPU upload.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::{Duration, Instant};

use bytemuck::{Pod, Zeroable};
use glam::{Affine3A, Mat3A, Vec3, Vec3A};
use lucerna_scene::file::{MAX_PROFILE_FILE_BYTES, read_limited};
use lucerna_scene::{Emission, EmitterShape, Material, Scene, TessellatedScene};

use crate::bvh::{Bvh, BvhQuality};
use crate::sampling::{ProfileSampler, RaySampler};

/// Material kinds as the kernels switch on them.
pub mod kind {
    pub const ABSORBER: u32 = 0;
    pub const LAMBERTIAN: u32 = 1;
    pub const MIRROR: u32 = 2;
    pub const ROUGH_CONDUCTOR: u32 = 3;
    pub const DIELECTRIC: u32 = 4;
    pub const DIFFUSER: u32 = 5;
}

/// A material flattened for the kernels (32 bytes, WGSL twin `Material`).
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable, PartialEq)]
pub struct TraceMaterial {
    pub kind: u32,
    /// Albedo or reflectance (0–1).
    pub reflectance: f32,
    /// Diffuse transmittance (0–1).
    pub transmittance: f32,
    pub ior: f32,
    /// GGX α along the tangent and bitangent.
    pub alpha_u: f32,
    pub alpha_v: f32,
    /// Anisotropy orientation about the normal (rad).
    pub orientation_rad: f32,
    /// Internal absorption coefficient (1/m).
    pub absorption_per_m: f32,
}
const _: () = assert!(std::mem::size_of::<TraceMaterial>() == 32);

impl TraceMaterial {
    /// A dielectric of index 1 that absorbs nothing: photons cross it as
    /// if it were not there (no Fresnel reflection, no bending).
    pub fn is_index_matched(&self) -> bool {
        self.kind == kind::DIELECTRIC && self.ior == 1.0 && self.absorption_per_m == 0.0
    }

    pub fn from_material(m: &Material) -> TraceMaterial {
        let mut t = TraceMaterial::zeroed();
        match *m {
            Material::Absorber => t.kind = kind::ABSORBER,
            Material::Lambertian { albedo } => {
                t.kind = kind::LAMBERTIAN;
                t.reflectance = albedo as f32;
            }
            Material::Mirror { reflectance } => {
                t.kind = kind::MIRROR;
                t.reflectance = reflectance as f32;
            }
            Material::RoughConductor {
                reflectance,
                roughness_u,
                roughness_v,
                orientation_deg,
            } => {
                t.kind = kind::ROUGH_CONDUCTOR;
                t.reflectance = reflectance as f32;
                t.alpha_u = roughness_u as f32;
                t.alpha_v = roughness_v as f32;
                t.orientation_rad = orientation_deg.to_radians() as f32;
            }
            Material::Dielectric {
                ior,
                absorption_per_m,
            } => {
                t.kind = kind::DIELECTRIC;
                t.ior = ior as f32;
                t.absorption_per_m = absorption_per_m as f32;
            }
            Material::Diffuser {
                reflectance,
                transmittance,
            } => {
                t.kind = kind::DIFFUSER;
                t.reflectance = reflectance as f32;
                t.transmittance = transmittance as f32;
            }
        }
        t
    }
}

/// Per-triangle data the kernels need after a hit (64 bytes): geometric
/// normal and the three vertex shading normals, material in `n0.w`.
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable, PartialEq)]
pub struct TriangleShading {
    pub geometric_normal: [f32; 3],
    pub material: u32,
    pub n0: [f32; 4],
    pub n1: [f32; 4],
    pub n2: [f32; 4],
}
const _: () = assert!(std::mem::size_of::<TriangleShading>() == 64);

/// Tag bit of a flat triangle: its three vertex normals are one normal
/// along its geometric one, so the tracer shades it with the geometric
/// normal the hit carries and never reads its shading record.
pub const FLAT_TAG: u32 = 1 << 31;

impl TriangleShading {
    /// The BVH tag of this triangle: its material, [`FLAT_TAG`], and
    /// [`crate::bvh::PASS_THROUGH_TAG`] for a material photons cross
    /// unchanged.
    pub fn tag(&self, materials: &[TraceMaterial]) -> u32 {
        let g = Vec3A::from_array(self.geometric_normal);
        let n0 = Vec3A::from_slice(&self.n0[..3]);
        let flat = self.n0 == self.n1 && self.n0 == self.n2 && (n0 - g).length() < 1e-5;
        let pass_through = materials
            .get(self.material as usize)
            .is_some_and(TraceMaterial::is_index_matched);
        self.material
            | if flat { FLAT_TAG } else { 0 }
            | if pass_through {
                crate::bvh::PASS_THROUGH_TAG
            } else {
                0
            }
    }

    /// The material index without the tag bits.
    pub fn material_of_tag(tag: u32) -> u32 {
        tag & !(FLAT_TAG | crate::bvh::PASS_THROUGH_TAG)
    }
}

/// How an emitter chooses directions.
#[derive(Debug, Clone)]
pub enum EmitterDirections {
    Lambertian,
    /// Shared by the emitters that name the same file.
    Profile(Arc<ProfileSampler>),
    /// Starts and directions both from a TM-25 ray file (the shape is
    /// [`EmitterShape::RayFile`]); shared like profiles, and kept between
    /// preparations while any scene holds it.
    RayFile(Arc<RaySampler>),
}

/// One emitter ready to sample.
#[derive(Debug, Clone)]
pub struct TraceEmitter {
    pub shape: EmitterShape,
    pub luminaire_from_emitter: Affine3A,
    pub normal_matrix: Mat3A,
    pub directions: EmitterDirections,
    pub flux_lm: f64,
    /// For a ray-file emitter whose rays are interpolated: the kernel
    /// each photon's ray is moved by ([`crate::ray_kernel`]); None:
    /// the file's rays as they are.
    pub ray_kernel: Option<crate::ray_kernel::RayKernel>,
}

/// A finished surface ready to trace: its BRDF band's sampler and its
/// layout for the normals band and the frame.
#[derive(Debug, Clone)]
pub struct TraceFinish {
    pub surface: Arc<lucerna_scene::finish_layout::SurfaceFinish>,
    pub brdf: Option<Arc<crate::finish_brdf::FinishBrdf>>,
    /// The surface's tangent rule in single precision: v around `axis`
    /// through `origin` (or along `axis`), u = handedness · v × n.
    pub around: bool,
    pub axis: Vec3A,
    pub origin: Vec3A,
    pub handedness: f32,
}

#[derive(Debug, Clone)]
pub struct PreparedScene {
    pub bvh: Bvh,
    /// One per triangle, in the scene's order (like `bvh.triangles`).
    pub shading: Vec<TriangleShading>,
    pub materials: Vec<TraceMaterial>,
    /// Per material: the finish its triangles are traced with.
    pub material_finish: Vec<Option<TraceFinish>>,
    /// Per triangle, its corners' finish coordinates where a finish is
    /// traced as normals (see [`TessellatedScene::finish_corners`]).
    pub finish_corners: Vec<[[f32; 3]; 3]>,
    pub emitters: Vec<TraceEmitter>,
    /// Cumulative flux fraction per emitter.
    pub emitter_cdf: Vec<f32>,
    pub total_flux_lm: f64,
    /// Offset (m) that moves a new ray off the surface it leaves.
    pub epsilon: f32,
    pub bvh_build_time: Duration,
}

#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum PrepareError {
    #[error("the luminaire has no enabled emitter with flux")]
    NoEmitter,
    #[error("emitter '{emitter}': cannot read emission profile {path}")]
    ProfileRead {
        emitter: String,
        path: std::path::PathBuf,
        #[source]
        source: lucerna_scene::file::ReadFileError,
    },
    #[error("emitter '{emitter}': emission profile {path}")]
    ProfileParse {
        emitter: String,
        path: std::path::PathBuf,
        #[source]
        source: lucerna_photometry::ParsePhotometryError,
    },
    #[error("emitter '{emitter}': the emission profile carries no flux")]
    EmptyProfile { emitter: String },
    #[error("emitter '{emitter}': ray file")]
    RayFile {
        emitter: String,
        #[source]
        source: lucerna_photometry::tm25::ReadRayFileError,
    },
}

/// The ray file at `path`, read once while any prepared scene holds it:
/// an editor prepares the scene again at every edit, and a maker's file
/// is half a gigabyte.
fn ray_sampler(path: &Path) -> Result<Arc<RaySampler>, lucerna_photometry::tm25::ReadRayFileError> {
    use std::sync::{Mutex, Weak};
    type Key = (PathBuf, u64, Option<std::time::SystemTime>);
    static CACHE: Mutex<Vec<(Key, Weak<RaySampler>)>> = Mutex::new(Vec::new());
    let meta = std::fs::metadata(path).ok();
    let key: Key = (
        path.to_path_buf(),
        meta.as_ref().map_or(0, |m| m.len()),
        meta.and_then(|m| m.modified().ok()),
    );
    let mut cache = CACHE
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner);
    cache.retain(|(_, w)| w.strong_count() > 0);
    if let Some(sampler) = cache
        .iter()
        .find(|(k, _)| *k == key)
        .and_then(|(_, w)| w.upgrade())
    {
        return Ok(sampler);
    }
    let rays = lucerna_photometry::tm25::read_ray_file(path)?;
    // The reader refuses a file whose rays carry no flux.
    let sampler = Arc::new(RaySampler::new(rays).ok_or_else(|| {
        lucerna_photometry::tm25::ReadRayFileError::Format {
            file: path.display().to_string(),
            field: "ray data (4.7.7)",
            message: "the rays carry no flux".to_owned(),
        }
    })?);
    cache.push((key, Arc::downgrade(&sampler)));
    Ok(sampler)
}

impl PreparedScene {
    /// How ray-file emitters reuse their rays (interpolated unless set).
    pub fn set_ray_reuse(&mut self, reuse: crate::ray_kernel::RayReuse) {
        for e in &mut self.emitters {
            if let EmitterDirections::RayFile(rays) = &e.directions {
                e.ray_kernel = match reuse {
                    crate::ray_kernel::RayReuse::Interpolate => rays.kernel(),
                    crate::ray_kernel::RayReuse::Loop => None,
                };
            }
        }
    }

    /// The ray-file emitters' rays (distinct rays in all) and whether
    /// any is interpolated; None without a ray-file emitter.
    pub fn ray_file_rays(&self) -> Option<(u64, bool)> {
        let mut found = None;
        for e in &self.emitters {
            if let EmitterDirections::RayFile(rays) = &e.directions {
                let (n, moved) = found.unwrap_or((0, false));
                found = Some((n + rays.rays.len() as u64, moved || e.ray_kernel.is_some()));
            }
        }
        found
    }

    pub fn triangle_count(&self) -> usize {
        self.bvh.triangles.len()
    }

    /// Prepares a validated, tessellated scene; `scene_dir` resolves
    /// emission-profile paths.
    pub fn new(
        scene: &Scene,
        tessellated: &TessellatedScene,
        scene_dir: &Path,
    ) -> Result<PreparedScene, PrepareError> {
        PreparedScene::with_quality(scene, tessellated, scene_dir, BvhQuality::Final)
    }

    /// [`PreparedScene::new`] with its BVH built at `quality`.
    pub fn with_quality(
        scene: &Scene,
        tessellated: &TessellatedScene,
        scene_dir: &Path,
        quality: BvhQuality,
    ) -> Result<PreparedScene, PrepareError> {
        let built = PreparedScene::with_bvh(scene, tessellated, scene_dir, |corners, tags| {
            Some(Bvh::build_with(corners, tags, quality))
        })?;
        let Some(prepared) = built else {
            unreachable!("a build always makes a BVH");
        };
        Ok(prepared)
    }

    /// The scene prepared with `previous`'s BVH refitted to its moved
    /// triangles ([`Bvh::refit`]), where the tessellation has the same
    /// triangles as `previous`'s; `Ok(None)` where it cannot be refitted.
    pub fn refitted(
        previous: &PreparedScene,
        scene: &Scene,
        tessellated: &TessellatedScene,
        scene_dir: &Path,
    ) -> Result<Option<PreparedScene>, PrepareError> {
        PreparedScene::with_bvh(scene, tessellated, scene_dir, |corners, tags| {
            previous.bvh.refit(corners, tags)
        })
    }

    /// Prepares the scene with the BVH `make_bvh` makes of its corners and
    /// tags (`Ok(None)` if it makes none).
    fn with_bvh(
        scene: &Scene,
        tessellated: &TessellatedScene,
        scene_dir: &Path,
        make_bvh: impl FnOnce(&[[Vec3; 3]], &[u32]) -> Option<Bvh>,
    ) -> Result<Option<PreparedScene>, PrepareError> {
        let mesh = &tessellated.mesh;
        let corners: Vec<[Vec3; 3]> = mesh
            .triangles
            .iter()
            .map(|t| t.map(|i| mesh.positions[i as usize]))
            .collect();
        let shading: Vec<TriangleShading> = (0..mesh.triangles.len())
            .map(|i| {
                let t = mesh.triangles[i];
                let [a, b, c] = corners[i];
                let g = (b - a).cross(c - a).normalize_or_zero();
                let n = |k: usize| {
                    let v = mesh.normals[t[k] as usize];
                    [v.x, v.y, v.z, 0.0]
                };
                TriangleShading {
                    geometric_normal: g.to_array(),
                    material: tessellated.triangle_material[i],
                    n0: n(0),
                    n1: n(1),
                    n2: n(2),
                }
            })
            .collect();
        let materials: Vec<TraceMaterial> = tessellated
            .materials
            .iter()
            .map(|(_, m)| TraceMaterial::from_material(m))
            .collect();
        let material_finish: Vec<Option<TraceFinish>> = tessellated
            .material_finish
            .iter()
            .map(|f| {
                f.as_ref().map(|surface| {
                    use lucerna_scene::finish_layout::TangentRule;
                    let v = |d: glam::DVec3| Vec3A::new(d.x as f32, d.y as f32, d.z as f32);
                    let (around, axis, origin) = match surface.tangents {
                        TangentRule::Around { axis, origin } => (true, v(axis), v(origin)),
                        TangentRule::Along { direction } => (false, v(direction), Vec3A::ZERO),
                    };
                    TraceFinish {
                        brdf: surface
                            .brdf_statistics
                            .as_ref()
                            .map(|s| Arc::new(crate::finish_brdf::FinishBrdf::new(s))),
                        surface: surface.clone(),
                        around,
                        axis,
                        origin,
                        handedness: surface.handedness as f32,
                    }
                })
            })
            .chain(std::iter::repeat(None))
            .take(materials.len())
            .collect();
        let tags: Vec<u32> = shading.iter().map(|s| s.tag(&materials)).collect();
        let start = Instant::now();
        let Some(bvh) = make_bvh(&corners, &tags) else {
            return Ok(None);
        };
        let bvh_build_time = start.elapsed();
        let mut emitters = Vec::new();
        // Each file is read once however many emitters name it (an LED
        // array of hundreds shares one profile).
        let mut samplers: HashMap<PathBuf, Arc<ProfileSampler>> = HashMap::new();
        for e in scene
            .emitters
            .iter()
            .filter(|e| e.enabled && e.flux_lm > 0.0)
        {
            let directions = match (&e.shape, &e.emission) {
                (EmitterShape::RayFile { path }, _) => EmitterDirections::RayFile(
                    ray_sampler(&scene_dir.join(path)).map_err(|source| PrepareError::RayFile {
                        emitter: e.name.clone(),
                        source,
                    })?,
                ),
                (_, Emission::Lambertian) => EmitterDirections::Lambertian,
                (_, Emission::Profile(file)) => {
                    let path = scene_dir.join(file);
                    if let Some(sampler) = samplers.get(&path) {
                        EmitterDirections::Profile(sampler.clone())
                    } else {
                        let bytes =
                            read_limited(&path, MAX_PROFILE_FILE_BYTES).map_err(|source| {
                                PrepareError::ProfileRead {
                                    emitter: e.name.clone(),
                                    path: path.clone(),
                                    source,
                                }
                            })?;
                        let p = lucerna_photometry::read_photometry(&bytes).map_err(|source| {
                            PrepareError::ProfileParse {
                                emitter: e.name.clone(),
                                path: path.clone(),
                                source,
                            }
                        })?;
                        let sampler = ProfileSampler::new(&p.table).ok_or_else(|| {
                            PrepareError::EmptyProfile {
                                emitter: e.name.clone(),
                            }
                        })?;
                        let sampler = Arc::new(sampler);
                        samplers.insert(path, sampler.clone());
                        EmitterDirections::Profile(sampler)
                    }
                }
            };
            let m = e.transform.matrix();
            let luminaire_from_emitter = Affine3A::from_mat3_translation(
                glam::Mat3::from_cols(
                    m.matrix3.x_axis.as_vec3(),
                    m.matrix3.y_axis.as_vec3(),
                    m.matrix3.z_axis.as_vec3(),
                ),
                m.translation.as_vec3(),
            );
            let ray_kernel = match &directions {
                EmitterDirections::RayFile(rays) => rays.kernel(),
                _ => None,
            };
            emitters.push(TraceEmitter {
                shape: e.shape.clone(),
                normal_matrix: luminaire_from_emitter.matrix3.inverse().transpose(),
                luminaire_from_emitter,
                directions,
                flux_lm: e.flux_lm,
                ray_kernel,
            });
        }
        if emitters.is_empty() {
            return Err(PrepareError::NoEmitter);
        }
        let total_flux_lm: f64 = emitters.iter().map(|e| e.flux_lm).sum();
        let mut acc = 0.0;
        let emitter_cdf = emitters
            .iter()
            .map(|e| {
                acc += e.flux_lm;
                (acc / total_flux_lm) as f32
            })
            .collect();
        let extent = mesh
            .bounds()
            .map_or(0.1, |(lo, hi)| (hi - lo).max_element());
        Ok(Some(PreparedScene {
            bvh,
            shading,
            materials,
            material_finish,
            finish_corners: tessellated.finish_corners.clone(),
            emitters,
            emitter_cdf,
            total_flux_lm,
            epsilon: (2e-6 * extent).max(1e-7),
            bvh_build_time,
        }))
    }
}

/// A point and its outward (emitting) normal on an emitter, local frame.
pub fn sample_emitter_surface(shape: &EmitterShape, u1: f32, u2: f32) -> (Vec3A, Vec3A) {
    use std::f32::consts::TAU;
    match *shape {
        EmitterShape::Disk { radius } => {
            let r = radius as f32 * u1.sqrt();
            let phi = TAU * u2;
            (Vec3A::new(r * phi.cos(), r * phi.sin(), 0.0), Vec3A::NEG_Z)
        }
        EmitterShape::Rectangle { width, depth } => (
            Vec3A::new((u1 - 0.5) * width as f32, (u2 - 0.5) * depth as f32, 0.0),
            Vec3A::NEG_Z,
        ),
        EmitterShape::Sphere { radius } => {
            let z = 1.0 - 2.0 * u1;
            let r = (1.0 - z * z).max(0.0).sqrt();
            let phi = TAU * u2;
            let n = Vec3A::new(r * phi.cos(), r * phi.sin(), z);
            (n * radius as f32, n)
        }
        EmitterShape::Cylinder { radius, height } => {
            let phi = TAU * u1;
            let n = Vec3A::new(phi.cos(), phi.sin(), 0.0);
            (
                n * radius as f32 + Vec3A::new(0.0, 0.0, (u2 - 0.5) * height as f32),
                n,
            )
        }
        // Its rays are sampled from the file (`EmitterDirections::RayFile`).
        EmitterShape::RayFile { .. } => (Vec3A::ZERO, Vec3A::NEG_Z),
    }
}
