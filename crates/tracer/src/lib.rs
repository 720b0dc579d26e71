//! Lucerna's photon tracer: photons from the emitters bounce through the
//! luminaire and are counted by escape direction on a cube-map intensity
//! map (Litemaker 2017, sections 3.2 and 4). This crate holds the BVH, the
//! CPU reference tracer and the progressive session.

pub mod bvh;
pub mod cpu;
// reason: `#[target_feature]` functions and a prefetch intrinsic, called
// only after run-time feature detection.
#[allow(unsafe_code)]
pub mod cpu_features;
pub mod finish_brdf;
pub mod finish_trace;
pub mod gpu;
pub mod paths;
pub mod prepared;
pub mod ray_kernel;
pub mod rng;
pub mod sampling;
pub mod session;
pub mod symmetry;
pub mod triangle;
pub mod wide_bvh;
// reason: SIMD intrinsics and `#[target_feature]` functions, called only
// after run-time feature detection.
#[allow(unsafe_code)]
pub mod wide_traversal;

pub use cpu::{
    BatchTotals, CountBuffers, Fate, Tally, TraceSettings, trace_batch, trace_batch_into,
    trace_batch_into_unless,
};
pub use paths::{
    EscapingRay, PhotonPath, SectionPlane, escaping_rays, sample_photon_paths, section_fan,
    trace_principal_ray,
};
pub use prepared::{PrepareError, PreparedScene};
pub use ray_kernel::{RayKernel, RayReuse};
pub use session::{Backend, BackendRequest, IterationReport, Session, choose_backend};
pub use symmetry::{LuminaireSymmetry, luminaire_symmetry, prepared_luminaire_symmetry};
