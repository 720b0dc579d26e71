// Progressive photon tracing kernel (Litemaker 2017, sections 3.2 and 4):
// one invocation traces one photon from an emitter through the luminaire
// and counts it by escape direction on the cube map, or as absorbed or cut
// off. The CPU reference is crates/tracer/src/cpu.rs; every step here has
// its twin there. Composed after cubemap.wgsl and rng.wgsl.

struct Params {
    photon_offset: u32,
    photon_count: u32,
    seed: u32,
    iteration: u32,
    max_bounces: u32,
    resolution: u32,
    emitter_count: u32,
    // Invocations per row of the 2D dispatch.
    threads_per_row: u32,
    // Offset (m) that moves a new ray off the surface it leaves.
    epsilon: f32,
    // BVH units per metre.
    bvh_scale: f32,
    pad0: u32,
    pad1: u32,
}

// BVH2 node: inner when count == 0 (children first, first + 1); leaf slots
// first .. first + count index leaf_triangles.
struct BvhNode {
    min: vec3<f32>,
    first: u32,
    max: vec3<f32>,
    count: u32,
}

struct Triangle {
    v0: vec3<f32>,
    pad0: u32,
    e1: vec3<f32>,
    pad1: u32,
    e2: vec3<f32>,
    pad2: u32,
}

struct Shading {
    geometric_normal: vec3<f32>,
    material: u32,
    n0: vec4<f32>,
    n1: vec4<f32>,
    n2: vec4<f32>,
}

struct Material {
    kind: u32,
    reflectance: f32,
    transmittance: f32,
    ior: f32,
    alpha_u: f32,
    alpha_v: f32,
    orientation_rad: f32,
    absorption_per_m: f32,
}

struct Emitter {
    x_axis: vec4<f32>,
    y_axis: vec4<f32>,
    z_axis: vec4<f32>,
    translation: vec4<f32>,
    normal_x: vec4<f32>,
    normal_y: vec4<f32>,
    normal_z: vec4<f32>,
    // disk: radius; rectangle: width, depth; sphere: radius; cylinder: radius, height
    params: vec4<f32>,
    // 0 disk, 1 rectangle, 2 sphere, 3 cylinder, 4 ray file
    shape: u32,
    // cumulative flux fraction
    cdf: f32,
    // offset in `profiles`, or 0xffffffff for Lambertian emission; a ray
    // file's rays (start, unit direction, keep probability, alias bits)
    profile_offset: u32,
    // a profile's C-planes, or a ray file's ray count
    profile_planes: u32,
    profile_gammas: u32,
    pad0: u32,
    pad1: u32,
    pad2: u32,
}

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read> nodes: array<BvhNode>;
@group(0) @binding(2) var<storage, read> leaf_triangles: array<u32>;
@group(0) @binding(3) var<storage, read> triangles: array<Triangle>;
@group(0) @binding(4) var<storage, read> shading: array<Shading>;
@group(0) @binding(5) var<storage, read> materials: array<Material>;
@group(0) @binding(6) var<storage, read> emitters: array<Emitter>;
@group(0) @binding(7) var<storage, read> profiles: array<f32>;
@group(0) @binding(8) var<storage, read_write> counts: array<atomic<u32>>;
// absorbed, cut off, bounces, rays
@group(0) @binding(9) var<storage, read_write> tallies: array<atomic<u32>, 4>;

const PI: f32 = 3.14159265358979;
const TAU: f32 = 6.28318530717959;
const FAR: f32 = 3.0e38;

const ABSORBER: u32 = 0u;
const LAMBERTIAN: u32 = 1u;
const MIRROR: u32 = 2u;
const ROUGH_CONDUCTOR: u32 = 3u;
const DIELECTRIC: u32 = 4u;
const DIFFUSER: u32 = 5u;

struct Hit {
    t: f32,
    triangle: u32,
    u: f32,
    v: f32,
}

// Möller–Trumbore; t <= 0 means no hit.
fn intersect_triangle(tri: Triangle, origin: vec3<f32>, dir: vec3<f32>) -> vec3<f32> {
    let p = cross(dir, tri.e2);
    let det = dot(tri.e1, p);
    if abs(det) < 1e-20 {
        return vec3<f32>(-1.0, 0.0, 0.0);
    }
    let inv_det = 1.0 / det;
    let s = origin - tri.v0;
    let u = dot(s, p) * inv_det;
    if u < 0.0 || u > 1.0 {
        return vec3<f32>(-1.0, 0.0, 0.0);
    }
    let q = cross(s, tri.e1);
    let v = dot(dir, q) * inv_det;
    if v < 0.0 || u + v > 1.0 {
        return vec3<f32>(-1.0, 0.0, 0.0);
    }
    return vec3<f32>(dot(tri.e2, q) * inv_det, u, v);
}

// Entry distance into a node's box, or -1 when it is missed before t_max.
fn slab(n: BvhNode, origin: vec3<f32>, inv: vec3<f32>, t_max: f32) -> f32 {
    let t0 = (n.min - origin) * inv;
    let t1 = (n.max - origin) * inv;
    let lo = min(t0, t1);
    let hi = max(t0, t1);
    let near = max(max(max(lo.x, lo.y), lo.z), 0.0);
    let far = min(min(min(hi.x, hi.y), hi.z), t_max);
    if near <= far {
        return near;
    }
    return -1.0;
}

// Closest hit (origin in metres, unit dir); t = FAR when nothing is hit.
fn intersect(origin_m: vec3<f32>, dir: vec3<f32>) -> Hit {
    let origin = origin_m * params.bvh_scale;
    let inv = 1.0 / dir;
    var best = Hit(FAR, 0xffffffffu, 0.0, 0.0);
    var stack: array<u32, 64>;
    var top = 0u;
    var node = 0u;
    if arrayLength(&nodes) == 0u || slab(nodes[0], origin, inv, best.t) < 0.0 {
        return best;
    }
    loop {
        let n = nodes[node];
        var descended = false;
        if n.count > 0u {
            for (var slot = n.first; slot < n.first + n.count; slot++) {
                let i = leaf_triangles[slot];
                let h = intersect_triangle(triangles[i], origin, dir);
                if h.x > 0.0 && h.x < best.t {
                    best = Hit(h.x, i, h.y, h.z);
                }
            }
        } else {
            let a = n.first;
            let b = n.first + 1u;
            let ta = slab(nodes[a], origin, inv, best.t);
            let tb = slab(nodes[b], origin, inv, best.t);
            if ta >= 0.0 && tb >= 0.0 {
                var near = a;
                var far = b;
                if tb < ta {
                    near = b;
                    far = a;
                }
                if top < 64u {
                    stack[top] = far;
                    top += 1u;
                }
                node = near;
                descended = true;
            } else if ta >= 0.0 {
                node = a;
                descended = true;
            } else if tb >= 0.0 {
                node = b;
                descended = true;
            }
        }
        if !descended {
            if top == 0u {
                break;
            }
            top -= 1u;
            node = stack[top];
        }
    }
    if best.triangle != 0xffffffffu {
        best.t = best.t / params.bvh_scale;
    }
    return best;
}

// Orthonormal tangent and bitangent around unit n (Duff et al. 2017).
fn basis_t(n: vec3<f32>) -> vec3<f32> {
    let s = select(-1.0, 1.0, n.z >= 0.0);
    let a = -1.0 / (s + n.z);
    let b = n.x * n.y * a;
    return vec3<f32>(1.0 + s * n.x * n.x * a, s * b, -s * n.x);
}

fn basis_b(n: vec3<f32>) -> vec3<f32> {
    let s = select(-1.0, 1.0, n.z >= 0.0);
    let a = -1.0 / (s + n.z);
    let b = n.x * n.y * a;
    return vec3<f32>(b, s + n.y * n.y * a, -n.y);
}

// Cosine-weighted direction about n (pdf cos θ / π).
fn cosine_hemisphere(n: vec3<f32>, u1: f32, u2: f32) -> vec3<f32> {
    let r = sqrt(u1);
    let phi = TAU * u2;
    let z = sqrt(max(1.0 - u1, 0.0));
    return normalize(basis_t(n) * (r * cos(phi)) + basis_b(n) * (r * sin(phi)) + n * z);
}

fn mirror(d: vec3<f32>, n: vec3<f32>) -> vec3<f32> {
    return d - n * (2.0 * dot(d, n));
}

// Unpolarised Fresnel reflectance and cos θt; reflectance 1 under TIR.
fn fresnel_dielectric(cos_i: f32, eta: f32) -> vec2<f32> {
    let sin2_t = eta * eta * max(1.0 - cos_i * cos_i, 0.0);
    if sin2_t >= 1.0 {
        return vec2<f32>(1.0, 0.0);
    }
    let cos_t = sqrt(1.0 - sin2_t);
    let rs = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    let rp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    return vec2<f32>(0.5 * (rs * rs + rp * rp), cos_t);
}

// GGX Smith Λ, local frame.
fn ggx_lambda(w: vec3<f32>, ax: f32, ay: f32) -> f32 {
    let z2 = w.z * w.z;
    if z2 <= 0.0 {
        return FAR;
    }
    let a2 = (ax * ax * w.x * w.x + ay * ay * w.y * w.y) / z2;
    return 0.5 * (-1.0 + sqrt(1.0 + a2));
}

// Visible-normal sampling of GGX (Heitz 2018), local frame.
fn sample_ggx_vndf(wo: vec3<f32>, ax: f32, ay: f32, u1: f32, u2: f32) -> vec3<f32> {
    let vh = normalize(vec3<f32>(ax * wo.x, ay * wo.y, wo.z));
    let len2 = vh.x * vh.x + vh.y * vh.y;
    var t1 = vec3<f32>(1.0, 0.0, 0.0);
    if len2 > 0.0 {
        t1 = vec3<f32>(-vh.y, vh.x, 0.0) / sqrt(len2);
    }
    let t2 = cross(vh, t1);
    let r = sqrt(u1);
    let phi = TAU * u2;
    let p1 = r * cos(phi);
    let s = 0.5 * (1.0 + vh.z);
    let p2 = (1.0 - s) * sqrt(max(1.0 - p1 * p1, 0.0)) + s * r * sin(phi);
    let nh = t1 * p1 + t2 * p2 + vh * sqrt(max(1.0 - p1 * p1 - p2 * p2, 0.0));
    return normalize(vec3<f32>(ax * nh.x, ay * nh.y, max(nh.z, 1e-7)));
}

fn facing(n: vec3<f32>, d: vec3<f32>) -> vec3<f32> {
    return select(n, -n, dot(n, d) > 0.0);
}

fn facing_consistent(ns: vec3<f32>, ng: vec3<f32>) -> vec3<f32> {
    return select(ng, ns, dot(ns, ng) > 1e-4);
}

// A direction from an emitter's measured profile (local frame, nadir -z):
// a cell chosen by the CDF, uniform in solid angle within it.
fn sample_profile(e: Emitter, u_cell: f32, u1: f32, u2: f32) -> vec3<f32> {
    let nc = e.profile_planes;
    let ng = e.profile_gammas;
    let cells = nc * ng;
    let c_base = e.profile_offset;
    let g_base = c_base + 2u * nc;
    let cdf_base = g_base + 2u * ng;
    // partition point: first cell whose CDF exceeds u_cell
    var lo = 0u;
    var hi = cells;
    while lo < hi {
        let mid = (lo + hi) / 2u;
        if profiles[cdf_base + mid] <= u_cell {
            lo = mid + 1u;
        } else {
            hi = mid;
        }
    }
    let k = min(lo, cells - 1u);
    let i = k / ng;
    let j = k % ng;
    let c0 = profiles[c_base + 2u * i];
    let c1 = profiles[c_base + 2u * i + 1u];
    let z0 = profiles[g_base + 2u * j];
    let z1 = profiles[g_base + 2u * j + 1u];
    let c = c0 + (c1 - c0) * u1;
    let cos_g = z0 + (z1 - z0) * u2;
    let sin_g = sqrt(max(1.0 - cos_g * cos_g, 0.0));
    return vec3<f32>(sin_g * cos(c), sin_g * sin(c), -cos_g);
}

// The high 32 bits of a × b (WGSL has no 64-bit integers): a column of
// an alias table from all 32 random bits.
// Two standard normal deviates from two uniforms in [0, 1) (Box-Muller,
// as ray_kernel.rs's normal_pair).
fn normal_pair(u1: f32, u2: f32) -> vec2<f32> {
    let r = sqrt(-2.0 * log(1.0 - u1));
    let a = TAU * u2;
    return vec2<f32>(r * cos(a), r * sin(a));
}

fn mul_hi(a: u32, b: u32) -> u32 {
    let a_lo = a & 0xffffu;
    let a_hi = a >> 16u;
    let b_lo = b & 0xffffu;
    let b_hi = b >> 16u;
    let lo_lo = a_lo * b_lo;
    let hi_lo = a_hi * b_lo;
    let lo_hi = a_lo * b_hi;
    let cross = (lo_lo >> 16u) + (hi_lo & 0xffffu) + (lo_hi & 0xffffu);
    return a_hi * b_hi + (hi_lo >> 16u) + (lo_hi >> 16u) + (cross >> 16u);
}

struct Ray {
    origin: vec3<f32>,
    dir: vec3<f32>,
}

fn emit() -> Ray {
    let u = rng_next_f32();
    var index = 0u;
    for (var k = 0u; k < params.emitter_count; k++) {
        if emitters[k].cdf <= u {
            index = k + 1u;
        }
    }
    let e = emitters[min(index, params.emitter_count - 1u)];
    let u1 = rng_next_f32();
    let u2 = rng_next_f32();
    if e.shape == 4u {
        // A ray from the file by the alias method, placed by the
        // emitter's transform; no surface to step off.
        let n_rays = e.profile_planes;
        let i = mul_hi(rng_next_u32(), n_rays);
        let base = e.profile_offset + 8u * i;
        var k = i;
        if rng_next_f32() >= profiles[base + 6u] {
            k = bitcast<u32>(profiles[base + 7u]);
        }
        let r = e.profile_offset + 8u * k;
        let lp = vec3<f32>(profiles[r], profiles[r + 1u], profiles[r + 2u]);
        var ld = vec3<f32>(profiles[r + 3u], profiles[r + 4u], profiles[r + 5u]);
        if e.params.w > 0.0 {
            // The direction turned by the file's interpolation kernel
            // (ray_kernel.rs): one Box-Muller pair, the CPU's draws.
            let m = normal_pair(rng_next_f32(), rng_next_f32()) * e.params.w;
            let sgn = select(-1.0, 1.0, ld.z >= 0.0);
            let a = -1.0 / (sgn + ld.z);
            let b = ld.x * ld.y * a;
            let t1 = vec3<f32>(1.0 + sgn * ld.x * ld.x * a, sgn * b, -sgn * ld.x);
            let t2 = vec3<f32>(b, sgn + ld.y * ld.y * a, -ld.y);
            ld = normalize(ld + t1 * m.x + t2 * m.y);
        }
        let wp = e.x_axis.xyz * lp.x + e.y_axis.xyz * lp.y + e.z_axis.xyz * lp.z + e.translation.xyz;
        let wd = normalize(e.x_axis.xyz * ld.x + e.y_axis.xyz * ld.y + e.z_axis.xyz * ld.z);
        return Ray(wp + wd * params.epsilon, wd);
    }
    var p = vec3<f32>(0.0);
    var n = vec3<f32>(0.0, 0.0, -1.0);
    switch e.shape {
        case 0u: {
            let r = e.params.x * sqrt(u1);
            let phi = TAU * u2;
            p = vec3<f32>(r * cos(phi), r * sin(phi), 0.0);
        }
        case 1u: {
            p = vec3<f32>((u1 - 0.5) * e.params.x, (u2 - 0.5) * e.params.y, 0.0);
        }
        case 2u: {
            let z = 1.0 - 2.0 * u1;
            let r = sqrt(max(1.0 - z * z, 0.0));
            let phi = TAU * u2;
            n = vec3<f32>(r * cos(phi), r * sin(phi), z);
            p = n * e.params.x;
        }
        default: {
            let phi = TAU * u1;
            n = vec3<f32>(cos(phi), sin(phi), 0.0);
            p = n * e.params.x + vec3<f32>(0.0, 0.0, (u2 - 0.5) * e.params.y);
        }
    }
    let world_p = e.x_axis.xyz * p.x + e.y_axis.xyz * p.y + e.z_axis.xyz * p.z + e.translation.xyz;
    let world_n = normalize(e.normal_x.xyz * n.x + e.normal_y.xyz * n.y + e.normal_z.xyz * n.z);
    var d: vec3<f32>;
    if e.profile_offset == 0xffffffffu {
        let a = rng_next_f32();
        let b = rng_next_f32();
        d = cosine_hemisphere(world_n, a, b);
    } else {
        let uc = rng_next_f32();
        let a = rng_next_f32();
        let b = rng_next_f32();
        let local = sample_profile(e, uc, a, b);
        d = normalize(e.x_axis.xyz * local.x + e.y_axis.xyz * local.y + e.z_axis.xyz * local.z);
    }
    let off = select(-world_n, world_n, dot(d, world_n) >= 0.0);
    return Ray(world_p + (off + d) * params.epsilon, d);
}

// Returns the new direction, or zero when the photon is absorbed.
fn rough_conductor(m: Material, dir: vec3<f32>, n: vec3<f32>) -> vec3<f32> {
    let around_z = cross(vec3<f32>(0.0, 0.0, 1.0), n);
    var t0 = basis_t(n);
    if dot(around_z, around_z) > 1e-8 {
        t0 = normalize(around_z);
    }
    let b0 = cross(n, t0);
    let t = t0 * cos(m.orientation_rad) + b0 * sin(m.orientation_rad);
    let b = cross(n, t);
    let wo_world = -dir;
    let wo = vec3<f32>(dot(wo_world, t), dot(wo_world, b), dot(wo_world, n));
    if wo.z <= 0.0 {
        return vec3<f32>(0.0);
    }
    let u1 = rng_next_f32();
    let u2 = rng_next_f32();
    let mn = sample_ggx_vndf(wo, m.alpha_u, m.alpha_v, u1, u2);
    let wi = mn * (2.0 * dot(wo, mn)) - wo;
    if wi.z <= 0.0 {
        return vec3<f32>(0.0);
    }
    let lo = ggx_lambda(wo, m.alpha_u, m.alpha_v);
    let li = ggx_lambda(wi, m.alpha_u, m.alpha_v);
    let survive = m.reflectance * (1.0 + lo) / (1.0 + lo + li);
    if rng_next_f32() < survive {
        return normalize(t * wi.x + b * wi.y + n * wi.z);
    }
    return vec3<f32>(0.0);
}

var<private> inside_after: bool;

fn dielectric(m: Material, dir: vec3<f32>, geometric: vec3<f32>, shading_n: vec3<f32>) -> vec3<f32> {
    let entering = dot(dir, geometric) < 0.0;
    let ng = select(-geometric, geometric, entering);
    let ns = facing_consistent(select(shading_n, -shading_n, dot(shading_n, ng) < 0.0), ng);
    let eta = select(m.ior, 1.0 / m.ior, entering);
    let cos_i = clamp(-dot(dir, ns), 0.0, 1.0);
    let f = fresnel_dielectric(cos_i, eta);
    if rng_next_f32() < f.x {
        var r = mirror(dir, ns);
        if dot(r, ng) <= 0.0 {
            r = mirror(dir, ng);
        }
        inside_after = !entering;
        return r;
    }
    var t = normalize(dir * eta + ns * (eta * cos_i - f.y));
    if dot(t, ng) >= 0.0 {
        t = dir;
    }
    inside_after = entering;
    return t;
}

// A finished surface (finish_brdf.rs, finish_trace.rs): a material whose
// kind carries FINISHED keeps its record's offset in `profiles` in the
// bits of `ior` (unused by the kinds that take a finish). The record:
// flat share, slope range, bins, tangent rule (0 around the axis, 1
// along the direction), axis xyz, origin xyz, handedness, then bins²
// cumulative cell probabilities (u fastest) ending at 1.
const FINISHED: u32 = 0x100u;

fn finish_v(o: u32, p: vec3<f32>, n: vec3<f32>) -> vec3<f32> {
    let axis = vec3<f32>(profiles[o + 4u], profiles[o + 5u], profiles[o + 6u]);
    var v = axis;
    if profiles[o + 3u] == 0.0 {
        let origin = vec3<f32>(profiles[o + 7u], profiles[o + 8u], profiles[o + 9u]);
        v = cross(axis, p - origin);
    }
    v = v - n * dot(v, n);
    if dot(v, v) > 1e-20 {
        return normalize(v);
    }
    return basis_b(n);
}

// The normal of a facet visible from the photon (zero where none was
// accepted): a slope from the table (or the flat land), kept in
// proportion to its projected area toward the photon.
fn finish_facet(o: u32, dir: vec3<f32>, ns: vec3<f32>, n_own: vec3<f32>, p: vec3<f32>) -> vec3<f32> {
    let flat = profiles[o];
    let range = profiles[o + 1u];
    let bins = u32(profiles[o + 2u]);
    let handedness = profiles[o + 10u];
    let tv = finish_v(o, p, n_own);
    let tu = normalize(cross(tv, n_own)) * handedness;
    var v = tv - ns * dot(tv, ns);
    if dot(v, v) > 1e-20 {
        v = normalize(v);
    } else {
        v = basis_b(ns);
    }
    var u = cross(v, ns);
    if dot(u, tu) < 0.0 {
        u = -u;
    }
    let wo_w = -dir;
    let wo = vec3<f32>(dot(wo_w, u), dot(wo_w, v), dot(wo_w, ns));
    if wo.z <= 0.0 {
        return vec3<f32>(0.0);
    }
    let bound = wo.z + range * (abs(wo.x) + abs(wo.y));
    let width = 2.0 * range / f32(bins);
    let cells = bins * bins;
    let table = o + 12u;
    for (var tries = 0u; tries < 256u; tries++) {
        var s = vec2<f32>(0.0);
        if rng_next_f32() >= flat {
            let pick = rng_next_f32();
            var lo = 0u;
            var hi = cells - 1u;
            while lo < hi {
                let mid = (lo + hi) / 2u;
                if profiles[table + mid] < pick {
                    lo = mid + 1u;
                } else {
                    hi = mid;
                }
            }
            let i = lo % bins;
            let j = lo / bins;
            let a = rng_next_f32();
            let b = rng_next_f32();
            s = vec2<f32>(-range + (f32(i) + a) * width, -range + (f32(j) + b) * width);
        }
        let visible = wo.z - wo.x * s.x - wo.y * s.y;
        if visible > 0.0 && rng_next_f32() * bound < visible {
            let m = normalize(vec3<f32>(-s.x, -s.y, 1.0));
            return normalize(u * m.x + v * m.y + ns * m.z);
        }
    }
    return vec3<f32>(0.0);
}

@compute @workgroup_size(64)
fn trace(@builtin(global_invocation_id) gid: vec3<u32>) {
    let local = gid.x + gid.y * params.threads_per_row;
    if local >= params.photon_count {
        return;
    }
    rng_init(params.seed, params.iteration, params.photon_offset + local);
    var ray = emit();
    var medium_absorption = 0.0;
    var rays = 0u;
    var bounces = 0u;
    // 0 escaped, 1 absorbed, 2 cut off
    var fate = 2u;
    for (var bounce = 0u; bounce <= params.max_bounces; bounce++) {
        rays += 1u;
        bounces = bounce;
        let hit = intersect(ray.origin, ray.dir);
        if hit.triangle == 0xffffffffu {
            fate = 0u;
            break;
        }
        if medium_absorption > 0.0 && rng_next_f32() >= exp(-medium_absorption * hit.t) {
            fate = 1u;
            break;
        }
        if bounce == params.max_bounces {
            fate = 2u;
            break;
        }
        let s = shading[hit.triangle];
        let m = materials[s.material];
        let position = ray.origin + ray.dir * hit.t;
        let geometric = s.geometric_normal;
        let w = 1.0 - hit.u - hit.v;
        var shading_n = s.n0.xyz * w + s.n1.xyz * hit.u + s.n2.xyz * hit.v;
        let len2 = dot(shading_n, shading_n);
        if len2 > 0.0 {
            shading_n = shading_n / sqrt(len2);
        } else {
            shading_n = geometric;
        }
        let ng = facing(geometric, ray.dir);
        var ns = facing_consistent(select(shading_n, -shading_n, dot(shading_n, ng) < 0.0), ng);
        let finished = (m.kind & FINISHED) != 0u;
        if finished {
            let facet = finish_facet(bitcast<u32>(m.ior), ray.dir, ns, shading_n, position);
            if dot(facet, facet) == 0.0 {
                fate = 1u;
                break;
            }
            ns = facet;
        }
        var next = vec3<f32>(0.0);
        switch m.kind & 0xffu {
            case 1u: {
                if rng_next_f32() < m.reflectance {
                    let a = rng_next_f32();
                    let b = rng_next_f32();
                    next = cosine_hemisphere(ns, a, b);
                }
            }
            case 2u: {
                if rng_next_f32() < m.reflectance {
                    next = mirror(ray.dir, ns);
                    if dot(next, ng) <= 0.0 && !finished {
                        next = mirror(ray.dir, ng);
                    }
                }
            }
            case 3u: {
                next = rough_conductor(m, ray.dir, ns);
            }
            case 5u: {
                let u = rng_next_f32();
                if u < m.reflectance {
                    let a = rng_next_f32();
                    let b = rng_next_f32();
                    next = cosine_hemisphere(ns, a, b);
                } else if u < m.reflectance + m.transmittance {
                    let a = rng_next_f32();
                    let b = rng_next_f32();
                    next = cosine_hemisphere(-ns, a, b);
                }
            }
            case 4u: {
                next = dielectric(m, ray.dir, geometric, shading_n);
                medium_absorption = select(0.0, m.absorption_per_m, inside_after);
            }
            default: {}
        }
        // A finished surface loses what its facets send into it.
        if dot(next, next) == 0.0 || (finished && dot(next, ng) <= 0.0) {
            fate = 1u;
            break;
        }
        let side = select(-geometric, geometric, dot(next, geometric) > 0.0);
        ray = Ray(position + side * params.epsilon, next);
    }
    atomicAdd(&tallies[2], bounces);
    atomicAdd(&tallies[3], rays);
    switch fate {
        case 0u: {
            atomicAdd(&counts[cube_texel_of_direction(ray.dir, params.resolution)], 1u);
        }
        case 1u: {
            atomicAdd(&tallies[0], 1u);
        }
        default: {
            atomicAdd(&tallies[1], 1u);
        }
    }
}
