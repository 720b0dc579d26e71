//! CPU reference tracer: the same physics as the WGSL kernel, in Rust, run
//! in parallel with rayon. Tests compare the kernel against it, and on a
//! machine without a GPU it is the fast path.

use glam::Vec3A;
use lucerna_photometry::CubeMapLayout;
use rayon::prelude::*;

use crate::prepared::{
    EmitterDirections, FLAT_TAG, PreparedScene, TriangleShading, kind, sample_emitter_surface,
};
use crate::rng::PhotonRng;
use crate::sampling::{
    basis, cosine_hemisphere, fresnel_dielectric, ggx_lambda, reflect, sample_ggx_vndf,
};

/// What became of one photon.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Fate {
    /// Left the luminaire in this direction (luminaire coordinates).
    Escaped(Vec3A),
    Absorbed,
    /// Still bouncing at the bounce limit.
    CutOff,
}

/// Photon bookkeeping for a batch; counts add exactly across batches.
#[derive(Debug, Clone, PartialEq)]
pub struct Tally {
    /// Escaped photons per cube-map texel.
    pub counts: Vec<u32>,
    pub emitted: u64,
    pub absorbed: u64,
    pub cut_off: u64,
    /// Surface interactions survived (for mean bounces per photon).
    pub bounces: u64,
    /// Rays cast (segments traced).
    pub rays: u64,
}

impl Tally {
    pub fn new(texels: usize) -> Tally {
        Tally {
            counts: vec![0; texels],
            emitted: 0,
            absorbed: 0,
            cut_off: 0,
            bounces: 0,
            rays: 0,
        }
    }

    pub fn escaped(&self) -> u64 {
        self.counts.iter().map(|&c| u64::from(c)).sum()
    }
}

/// Tracing settings shared by every backend.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TraceSettings {
    pub seed: u32,
    /// Surface interactions after which a photon is cut off.
    pub max_bounces: u32,
    pub layout: CubeMapLayout,
}

impl Default for TraceSettings {
    fn default() -> Self {
        TraceSettings {
            seed: 1,
            max_bounces: 64,
            layout: CubeMapLayout::new(256),
        }
    }
}

/// Orients `n` to the side a photon travelling along `d` comes from.
#[inline]
fn facing(n: Vec3A, d: Vec3A) -> Vec3A {
    if n.dot(d) > 0.0 { -n } else { n }
}

/// Traces one photon; returns its fate, the bounces it survived and the
/// rays it cast. Inlined into the batch loop so that loop's AVX2 build
/// ([`crate::cpu_features::with_best_features`]) covers it.
#[inline(always)]
pub fn trace_photon(
    scene: &PreparedScene,
    max_bounces: u32,
    rng: &mut PhotonRng,
) -> (Fate, u32, u32) {
    trace_photon_recorded(scene, max_bounces, rng, |_| {})
}

/// [`trace_photon`], telling `record` where the photon starts and every
/// point where it meets a surface (absorbed there or not): the same code
/// path, so a drawn path is exactly a traced photon.
#[inline(always)]
pub fn trace_photon_recorded(
    scene: &PreparedScene,
    max_bounces: u32,
    rng: &mut PhotonRng,
    mut record: impl FnMut(Vec3A),
) -> (Fate, u32, u32) {
    let mut photon = Photon::emit(scene, rng.clone(), &mut record);
    let fate = loop {
        let (origin, dir) = photon.ray();
        let hit = scene.bvh.intersect(origin, dir, f32::INFINITY);
        if let Some(fate) = photon.advance(scene, max_bounces, hit, &mut record) {
            break fate;
        }
    };
    *rng = photon.rng.clone();
    (fate, photon.bounces, photon.rays)
}

/// A photon between two rays: the ray it casts next, the medium it is in,
/// and its random stream. [`trace_photon`] advances one photon ray by ray;
/// the batch loop two at once, so that their traversals overlap
/// ([`crate::bvh::Bvh::intersect_pair`]); both run this code.
#[derive(Debug, Clone)]
pub struct Photon {
    rng: PhotonRng,
    origin: Vec3A,
    dir: Vec3A,
    /// Absorption coefficient of the medium the photon travels in (1/m).
    medium_absorption: f32,
    /// Surface interactions survived.
    bounces: u32,
    /// Rays cast.
    rays: u32,
}

impl Photon {
    /// A new photon from the scene's emitters, its start recorded.
    #[inline(always)]
    pub fn emit(
        scene: &PreparedScene,
        mut rng: PhotonRng,
        record: &mut impl FnMut(Vec3A),
    ) -> Photon {
        let (origin, dir) = emit(scene, &mut rng);
        record(origin);
        Photon {
            rng,
            origin,
            dir,
            medium_absorption: 0.0,
            bounces: 0,
            rays: 0,
        }
    }

    /// The ray it casts next: origin and unit direction (m, luminaire
    /// coordinates).
    #[inline(always)]
    pub fn ray(&self) -> (Vec3A, Vec3A) {
        (self.origin, self.dir)
    }

    /// Surface interactions survived so far, and rays cast.
    pub fn counts(&self) -> (u32, u32) {
        (self.bounces, self.rays)
    }

    /// Goes on from `hit`, the closest hit of its ray: `Some(fate)` once
    /// the photon is done, else it has a new ray. Every surface point it
    /// reaches is recorded.
    #[inline(always)]
    pub fn advance(
        &mut self,
        scene: &PreparedScene,
        max_bounces: u32,
        hit: Option<crate::bvh::Hit>,
        record: &mut impl FnMut(Vec3A),
    ) -> Option<Fate> {
        let (origin, dir) = (self.origin, self.dir);
        let rng = &mut self.rng;
        self.rays += 1;
        let Some(hit) = hit else {
            return Some(Fate::Escaped(dir));
        };
        let position = origin + dir * hit.t;
        if self.medium_absorption > 0.0 && rng.next_f32() >= (-self.medium_absorption * hit.t).exp()
        {
            // Absorbed inside the medium: somewhere along this segment;
            // the path is drawn to the surface ahead.
            record(position);
            return Some(Fate::Absorbed);
        }
        record(position);
        if self.bounces >= max_bounces {
            return Some(Fate::CutOff);
        }
        // The material and geometric normal come with the hit; a smooth
        // triangle's vertex normals from its shading record.
        let material = TriangleShading::material_of_tag(hit.tag) as usize;
        let m = &scene.materials[material];
        let geometric = hit.normal;
        let mut shading_normal = shading_normal(scene, &hit);
        // A finish: its normals band tilts the shading normal where the
        // photon lands; its BRDF band draws a visible facet about which
        // the material then scatters. What leaves into the surface is
        // lost (shadowed).
        let finish = scene.material_finish.get(material).and_then(Option::as_ref);
        if let Some(f) = finish
            && f.surface.normals.is_some()
        {
            let t = crate::finish_trace::tangents(f, position, shading_normal);
            shading_normal = crate::finish_trace::normals_band(scene, f, &hit, shading_normal, t);
        }
        let (ng, mut ns) = facing_normals(geometric, shading_normal, dir);
        if let Some(f) = finish
            && let Some(brdf) = &f.brdf
        {
            match crate::finish_trace::facet(f, brdf, position, shading_normal, ns, dir, rng) {
                Some(facet) => ns = facet,
                None => return Some(Fate::Absorbed),
            }
        }
        let next = match m.kind {
            kind::LAMBERTIAN => (rng.next_f32() < m.reflectance)
                .then(|| cosine_hemisphere(ns, rng.next_f32(), rng.next_f32())),
            kind::MIRROR if finish.is_some() => {
                (rng.next_f32() < m.reflectance).then(|| reflect(dir, ns))
            }
            kind::MIRROR => (rng.next_f32() < m.reflectance).then(|| specular(dir, ns, ng)),
            kind::ROUGH_CONDUCTOR => rough_conductor(m, dir, ns, rng),
            kind::DIFFUSER => {
                let u = rng.next_f32();
                if u < m.reflectance {
                    Some(cosine_hemisphere(ns, rng.next_f32(), rng.next_f32()))
                } else if u < m.reflectance + m.transmittance {
                    Some(cosine_hemisphere(-ns, rng.next_f32(), rng.next_f32()))
                } else {
                    None
                }
            }
            kind::DIELECTRIC => {
                let (d, inside_after) = dielectric(m, dir, geometric, shading_normal, rng);
                self.medium_absorption = if inside_after {
                    m.absorption_per_m
                } else {
                    0.0
                };
                Some(d)
            }
            _ => None,
        };
        let Some(next) = next else {
            return Some(Fate::Absorbed);
        };
        if finish.is_some() && next.dot(ng) <= 0.0 {
            return Some(Fate::Absorbed);
        }
        // Leave the surface on the side the new direction goes.
        let side = if next.dot(geometric) > 0.0 {
            geometric
        } else {
            -geometric
        };
        self.origin = position + side * scene.epsilon;
        self.dir = next;
        self.bounces += 1;
        None
    }
}

/// The normal a hit shades with: the geometric one of a flat triangle,
/// else its vertex normals interpolated.
#[inline(always)]
pub(crate) fn shading_normal(scene: &PreparedScene, hit: &crate::bvh::Hit) -> Vec3A {
    let geometric = hit.normal;
    if hit.tag & FLAT_TAG != 0 {
        geometric
    } else {
        let s = &scene.shading[hit.triangle as usize];
        let w = 1.0 - hit.u - hit.v;
        (Vec3A::from_slice(&s.n0[..3]) * w
            + Vec3A::from_slice(&s.n1[..3]) * hit.u
            + Vec3A::from_slice(&s.n2[..3]) * hit.v)
            .normalize_or(geometric)
    }
}

/// Two-sided sheets: the geometric and shading normals, both facing the
/// incoming direction `dir`.
#[inline(always)]
pub(crate) fn facing_normals(geometric: Vec3A, shading: Vec3A, dir: Vec3A) -> (Vec3A, Vec3A) {
    let ng = facing(geometric, dir);
    let ns = if shading.dot(ng) < 0.0 {
        -shading
    } else {
        shading
    };
    (ng, facing_consistent(ns, ng))
}

/// The shading normal, kept in the geometric normal's hemisphere.
#[inline]
fn facing_consistent(ns: Vec3A, ng: Vec3A) -> Vec3A {
    if ns.dot(ng) > 1e-4 { ns } else { ng }
}

/// A new photon: emitter chosen by flux, point uniform on its surface,
/// direction Lambertian or from its measured profile.
#[inline(always)]
fn emit(scene: &PreparedScene, rng: &mut PhotonRng) -> (Vec3A, Vec3A) {
    let u = rng.next_f32();
    let index = scene
        .emitter_cdf
        .partition_point(|&c| c <= u)
        .min(scene.emitters.len() - 1);
    let e = &scene.emitters[index];
    if let EmitterDirections::RayFile(rays) = &e.directions {
        // The file's start and direction, placed by the emitter's
        // transform; no surface to step off.
        // The surface's two numbers are drawn and unused, as the kernel
        // draws them before it knows the shape.
        let _surface = (rng.next_f32(), rng.next_f32());
        let (column, u) = (rng.next_u32(), rng.next_f32());
        let (p_local, d_local) = match &e.ray_kernel {
            Some(k) => {
                let more = [rng.next_f32(), rng.next_f32()];
                rays.sample_turned(column, u, k, more)
            }
            None => rays.sample(column, u),
        };
        let p = e.luminaire_from_emitter.transform_point3a(p_local);
        let d = e
            .luminaire_from_emitter
            .matrix3
            .mul_vec3a(d_local)
            .normalize();
        return (p + d * scene.epsilon, d);
    }
    let (p_local, n_local) = sample_emitter_surface(&e.shape, rng.next_f32(), rng.next_f32());
    let p = e.luminaire_from_emitter.transform_point3a(p_local);
    let n = (e.normal_matrix * n_local).normalize();
    let d = match &e.directions {
        EmitterDirections::Lambertian => cosine_hemisphere(n, rng.next_f32(), rng.next_f32()),
        EmitterDirections::Profile(sampler) => {
            let local = sampler.sample(rng.next_f32(), rng.next_f32(), rng.next_f32());
            e.luminaire_from_emitter
                .matrix3
                .mul_vec3a(local)
                .normalize()
        }
        EmitterDirections::RayFile(_) => unreachable!("ray files return above"),
    };
    let off = if d.dot(n) >= 0.0 { n } else { -n };
    (p + (off + d) * scene.epsilon, d)
}

/// Anisotropic GGX conductor: a microfacet normal from the visible-normal
/// distribution, mirror reflection about it; the photon goes on with
/// probability R · G2/G1 (the single-scattering albedo for this direction),
/// so photons keep equal flux.
fn rough_conductor(
    m: &crate::prepared::TraceMaterial,
    dir: Vec3A,
    n: Vec3A,
    rng: &mut PhotonRng,
) -> Option<Vec3A> {
    // Anisotropy axes: circumferential about the luminaire's z axis (the
    // brushing direction of spun reflectors), turned by the orientation.
    let around_z = Vec3A::Z.cross(n);
    let t0 = if around_z.length_squared() > 1e-8 {
        around_z.normalize()
    } else {
        basis(n).0
    };
    let b0 = n.cross(t0);
    let (so, co) = m.orientation_rad.sin_cos();
    let t = t0 * co + b0 * so;
    let b = n.cross(t);
    let wo_world = -dir;
    let wo = Vec3A::new(wo_world.dot(t), wo_world.dot(b), wo_world.dot(n));
    if wo.z <= 0.0 {
        return None;
    }
    let mn = sample_ggx_vndf(wo, m.alpha_u, m.alpha_v, rng.next_f32(), rng.next_f32());
    let wi = mn * (2.0 * wo.dot(mn)) - wo;
    if wi.z <= 0.0 {
        return None;
    }
    let lo = ggx_lambda(wo, m.alpha_u, m.alpha_v);
    let li = ggx_lambda(wi, m.alpha_u, m.alpha_v);
    let survive = m.reflectance * (1.0 + lo) / (1.0 + lo + li);
    (rng.next_f32() < survive).then(|| (t * wi.x + b * wi.y + n * wi.z).normalize())
}

/// Smooth dielectric: Fresnel reflection or refraction, total internal
/// reflection. Closed solids have outward geometric normals, so the sign of
/// d·n tells entering from leaving. Returns the new direction and whether
/// the photon is inside the solid afterwards.
fn dielectric(
    m: &crate::prepared::TraceMaterial,
    dir: Vec3A,
    geometric: Vec3A,
    shading: Vec3A,
    rng: &mut PhotonRng,
) -> (Vec3A, bool) {
    let d = dielectric_directions(m, dir, geometric, shading);
    if rng.next_f32() < d.fresnel {
        (d.reflected, !d.entering)
    } else {
        (d.transmitted, d.entering)
    }
}

/// The two ways a ray may leave a dielectric's surface, and the share
/// reflected (1 where it is totally reflected).
pub(crate) struct DielectricDirections {
    pub fresnel: f32,
    pub reflected: Vec3A,
    pub transmitted: Vec3A,
    /// Whether the ray came from outside.
    pub entering: bool,
}

#[inline(always)]
pub(crate) fn dielectric_directions(
    m: &crate::prepared::TraceMaterial,
    dir: Vec3A,
    geometric: Vec3A,
    shading: Vec3A,
) -> DielectricDirections {
    let entering = dir.dot(geometric) < 0.0;
    let ng = if entering { geometric } else { -geometric };
    let ns = facing_consistent(
        if shading.dot(ng) < 0.0 {
            -shading
        } else {
            shading
        },
        ng,
    );
    let eta = if entering { 1.0 / m.ior } else { m.ior };
    let cos_i = (-dir.dot(ns)).clamp(0.0, 1.0);
    let (fresnel, cos_t) = fresnel_dielectric(cos_i, eta);
    let t = (dir * eta + ns * (eta * cos_i - cos_t)).normalize();
    DielectricDirections {
        fresnel,
        reflected: specular(dir, ns, ng),
        transmitted: if t.dot(ng) < 0.0 { t } else { dir },
        entering,
    }
}

/// The mirror reflection of `dir` about the shading normal `ns`, about
/// the geometric `ng` where that would go through the surface.
#[inline(always)]
pub(crate) fn specular(dir: Vec3A, ns: Vec3A, ng: Vec3A) -> Vec3A {
    let r = reflect(dir, ns);
    if r.dot(ng) > 0.0 { r } else { reflect(dir, ng) }
}

/// Photon bookkeeping of a batch apart from its counts; adds exactly.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct BatchTotals {
    pub emitted: u64,
    pub absorbed: u64,
    pub cut_off: u64,
    /// Surface interactions survived.
    pub bounces: u64,
    /// Rays cast.
    pub rays: u64,
}

impl BatchTotals {
    fn add(&mut self, other: BatchTotals) {
        self.emitted += other.emitted;
        self.absorbed += other.absorbed;
        self.cut_off += other.cut_off;
        self.bounces += other.bounces;
        self.rays += other.rays;
    }
}

/// Per-thread count buffers kept between batches: a fresh 6 × n² buffer
/// per batch and thread costs page faults and zeroing (1.5 MB at 256²,
/// several % of a 50 ms iteration); a reused one is zeroed while it is
/// merged.
#[derive(Debug, Default)]
pub struct CountBuffers {
    free: std::sync::Mutex<Vec<Vec<u32>>>,
}

impl CountBuffers {
    fn take(&self, texels: usize) -> Vec<u32> {
        let reused = self
            .free
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
            .pop();
        match reused {
            Some(b) if b.len() == texels => b,
            _ => vec![0; texels],
        }
    }

    fn give_back(&self, buffer: Vec<u32>) {
        self.free
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
            .push(buffer);
    }
}

/// Photons per work item: small enough that two threads finish a 50 ms
/// batch within a few percent of each other.
const CHUNK_PHOTONS: u32 = 4096;

/// Traces photons `first .. first + count` of `iteration` in parallel and
/// adds their escape counts to `counts` (one per texel of the layout).
/// Each thread claims chunks of photons from a shared counter into its own
/// buffer; which thread traced a photon never changes its fate (its random
/// stream is a hash of its index), so the counts are the same however the
/// work was shared.
pub fn trace_batch_into(
    scene: &PreparedScene,
    settings: &TraceSettings,
    iteration: u32,
    first: u32,
    count: u32,
    buffers: &CountBuffers,
    counts: &mut [u64],
) -> BatchTotals {
    let totals = trace_batch_into_unless(
        scene,
        settings,
        iteration,
        first,
        count,
        buffers,
        counts,
        &|| false,
    );
    totals.unwrap_or_default()
}

/// [`trace_batch_into`], given up when `stop` says so (asked between
/// chunks of 4096 photons): then nothing is added to `counts` and `None`
/// is returned. An editor stops an iteration that an edit has made stale.
pub fn trace_batch_into_unless(
    scene: &PreparedScene,
    settings: &TraceSettings,
    iteration: u32,
    first: u32,
    count: u32,
    buffers: &CountBuffers,
    counts: &mut [u64],
    stop: &(dyn Fn() -> bool + Sync),
) -> Option<BatchTotals> {
    use std::sync::atomic::{AtomicBool, AtomicU32, Ordering};
    let texels = settings.layout.texel_count();
    assert_eq!(counts.len(), texels, "counts must match the layout");
    let chunks = count.div_ceil(CHUNK_PHOTONS);
    let next = AtomicU32::new(0);
    let stopped = AtomicBool::new(false);
    let workers = rayon::current_num_threads().clamp(1, chunks.max(1) as usize);
    let traced: Vec<(Vec<u32>, BatchTotals)> = (0..workers)
        .into_par_iter()
        .map(|_| {
            let mut buffer = buffers.take(texels);
            let mut totals = BatchTotals::default();
            let mut work = || {
                loop {
                    if stop() {
                        stopped.store(true, Ordering::Relaxed);
                        break;
                    }
                    let c = next.fetch_add(1, Ordering::Relaxed);
                    if c >= chunks {
                        break;
                    }
                    let start = first + c * CHUNK_PHOTONS;
                    let end = start + CHUNK_PHOTONS.min(first + count - start);
                    trace_range(
                        scene,
                        settings,
                        iteration,
                        start..end,
                        &mut buffer,
                        &mut totals,
                    );
                }
            };
            if scene.bvh.traversal == crate::bvh::CpuTraversal::Avx2 {
                crate::cpu_features::with_best_features(work);
            } else {
                work();
            }
            (buffer, totals)
        })
        .collect();
    if stopped.load(Ordering::Relaxed) {
        for (mut buffer, _) in traced {
            buffer.fill(0);
            buffers.give_back(buffer);
        }
        return None;
    }
    let mut totals = BatchTotals::default();
    for (mut buffer, t) in traced {
        for (total, c) in counts.iter_mut().zip(buffer.iter_mut()) {
            *total += u64::from(*c);
            *c = 0;
        }
        totals.add(t);
        buffers.give_back(buffer);
    }
    Some(totals)
}

/// Traces photons `first .. first + count` of `iteration` in parallel.
pub fn trace_batch(
    scene: &PreparedScene,
    settings: &TraceSettings,
    iteration: u32,
    first: u32,
    count: u32,
) -> Tally {
    let mut counts = vec![0u64; settings.layout.texel_count()];
    let totals = trace_batch_into(
        scene,
        settings,
        iteration,
        first,
        count,
        &CountBuffers::default(),
        &mut counts,
    );
    Tally {
        // A batch has at most 2³² photons, so no texel count overflows.
        counts: counts.into_iter().map(|c| c as u32).collect(),
        emitted: totals.emitted,
        absorbed: totals.absorbed,
        cut_off: totals.cut_off,
        bounces: totals.bounces,
        rays: totals.rays,
    }
}

/// Escapes held back before they are counted: a 256² map's counts (1.5 MB
/// per thread) do not stay in cache, and an increment that waits for its
/// line stalls the photon loop; counted together, with the lines asked for
/// ahead, the waits overlap.
const PENDING_ESCAPES: usize = 256;

/// Traces photons `photons` of `iteration` into `counts` and `totals`, two
/// at a time: both photons' rays are traced together, and a finished
/// photon's place goes to the next one. Which photon finishes first never
/// changes a count (each has its own random stream).
#[inline(always)]
fn trace_range(
    scene: &PreparedScene,
    settings: &TraceSettings,
    iteration: u32,
    photons: std::ops::Range<u32>,
    counts: &mut [u32],
    totals: &mut BatchTotals,
) {
    let mut pending = [0u32; PENDING_ESCAPES];
    let mut held = 0usize;
    let mut next = photons.start;
    let start = |next: &mut u32| {
        (*next < photons.end).then(|| {
            let rng = PhotonRng::new(settings.seed, iteration, *next);
            *next += 1;
            Photon::emit(scene, rng, &mut |_| {})
        })
    };
    let mut lanes = [start(&mut next), start(&mut next)];
    loop {
        let hits = match &lanes {
            [Some(a), Some(b)] => scene.bvh.intersect_pair([a.ray(), b.ray()], f32::INFINITY),
            [Some(a), None] => {
                let (o, d) = a.ray();
                [scene.bvh.intersect(o, d, f32::INFINITY), None]
            }
            [None, Some(b)] => {
                let (o, d) = b.ray();
                [None, scene.bvh.intersect(o, d, f32::INFINITY)]
            }
            [None, None] => break,
        };
        for (lane, hit) in lanes.iter_mut().zip(hits) {
            let Some(photon) = lane.as_mut() else {
                continue;
            };
            let Some(fate) = photon.advance(scene, settings.max_bounces, hit, &mut |_| {}) else {
                continue;
            };
            let (bounces, rays) = photon.counts();
            totals.emitted += 1;
            totals.bounces += u64::from(bounces);
            totals.rays += u64::from(rays);
            match fate {
                Fate::Escaped(d) => {
                    let texel = settings.layout.texel_of_direction([
                        f64::from(d.x),
                        f64::from(d.y),
                        f64::from(d.z),
                    ]);
                    pending[held] = texel as u32;
                    held += 1;
                    if held == PENDING_ESCAPES {
                        count_escapes(counts, &pending);
                        held = 0;
                    }
                }
                Fate::Absorbed => totals.absorbed += 1,
                Fate::CutOff => totals.cut_off += 1,
            }
            *lane = start(&mut next);
        }
    }
    count_escapes(counts, &pending[..held]);
}

/// Adds one to each texel's count, the cache lines of the next few asked
/// for while one is counted.
#[inline(always)]
fn count_escapes(counts: &mut [u32], texels: &[u32]) {
    const AHEAD: usize = 16;
    for &t in texels.iter().take(AHEAD) {
        if let Some(c) = counts.get(t as usize) {
            crate::cpu_features::prefetch(c);
        }
    }
    for (i, &t) in texels.iter().enumerate() {
        if let Some(&ahead) = texels.get(i + AHEAD)
            && let Some(c) = counts.get(ahead as usize)
        {
            crate::cpu_features::prefetch(c);
        }
        counts[t as usize] += 1;
    }
}
