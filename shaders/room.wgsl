// Preview room: photometric polygonal lights shaded by polar integration
// of the polygonal-light integral of Luksch et al. 2020 (CPU twin:
// crates/room/src/polar.rs) and LTC specular (crates/room/src/ltc.rs).
// One invocation per pixel (`render`) or per shading point (`shade_points`).

const PI: f32 = 3.14159265358979;
const MAX_VERTICES: u32 = 12u;
const MAX_CLIPPED: u32 = 16u;
// Largest angle one group of 4 Gauss–Legendre nodes spans (π/4); pieces
// up to π/8 take 3 nodes, up to π/32 2 (polar::MAX_ARC_RAD and friends);
// pieces are joined across vertices turning the boundary by under 35°.
const MAX_ARC: f32 = 0.785398163397448;
const MEDIUM_ARC: f32 = 0.392699081698724;
const SMALL_ARC: f32 = 0.0981747704246810;
const SOFT_VERTEX_COS: f32 = 0.819152044288992;
// The draft rule's (mode 2) 2-node pieces up to π/8, 3-node up to π/4,
// 4 nodes per π/2 (polar::RuleNodes::draft).
const DRAFT_SMALL_ARC: f32 = 0.392699081698724;
const DRAFT_MAX_ARC: f32 = 1.57079632679490;
// Grids of a profile: candela, then the radial tables (polar::RadialTables).
const RADIAL_SEC: u32 = 1u;
const RADIAL_SIN: u32 = 2u;
// Closer to an opening's plane than this × its size: the front-side limit.
const IN_PLANE: f32 = 1e-4;
const LTC_SIZE: u32 = 64u;

struct Params {
    origin: vec4<f32>,
    forward: vec4<f32>,
    right: vec4<f32>,
    up: vec4<f32>,
    // width, depth, height (m)
    room: vec4<f32>,
    width: u32,
    height: u32,
    light_count: u32,
    // 0: cubature + LTC, 1: point-light baseline, 2: the draft rule + LTC
    mode: u32,
    tan_half_fov: f32,
    aspect: f32,
    point_count: u32,
    // 0: the box room; else the OBJ room's triangles
    triangle_count: u32,
    // uniform inter-reflected illuminance added to every surface (lx)
    indirect_lux: f32,
    pad0: u32,
    pad1: u32,
    pad2: u32,
}

struct Light {
    // Columns of the luminaire → room rotation.
    col0: vec4<f32>,
    col1: vec4<f32>,
    col2: vec4<f32>,
    // xyz: centre of the opening; w: its area (m², 0 for a point).
    position: vec4<f32>,
    // vertex count, profile offset (floats), C columns, γ rows
    info: vec4<u32>,
    // C step (deg), γ step (deg), size (m), the sweep's cut step at kinked
    // C-planes (rad, 0: none)
    steps: vec4<f32>,
    vertices: array<vec4<f32>, 12>,
}

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read> lights: array<Light>;
@group(0) @binding(2) var<storage, read> profiles: array<f32>;
@group(0) @binding(3) var<storage, read> ltc: array<vec4<f32>>;
@group(0) @binding(4) var<storage, read_write> output: array<vec4<f32>>;
@group(0) @binding(5) var<storage, read> points: array<vec4<f32>>;
// per surface: diffuse reflectance, F0, roughness (floor, ceiling, walls
// x = 0, x = width, y = 0, y = depth, then the OBJ's materials)
@group(0) @binding(6) var<storage, read> surfaces: array<vec4<f32>>;
// OBJ room: three vertices per triangle, the first's w = surface index
@group(0) @binding(7) var<storage, read> triangles: array<vec4<f32>>;

fn to_luminaire(l: Light, d: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(dot(l.col0.xyz, d), dot(l.col1.xyz, d), dot(l.col2.xyz, d));
}

// A direction's cell in a profile's C-γ grid: lower indices (x = C,
// y = γ) and fractions within the cell (z = C, w = γ).
struct Cell {
    c0: u32,
    g0: u32,
    tc: f32,
    tg: f32,
}

fn grid_cell(l: Light, d: vec3<f32>) -> Cell {
    let c_count = l.info.z;
    let g_count = l.info.w;
    let horizontal = sqrt(d.x * d.x + d.y * d.y);
    let gamma = degrees(atan2(horizontal, -d.z));
    let gf = clamp(gamma / l.steps.y, 0.0, f32(g_count - 1u));
    let g0 = min(u32(floor(gf)), g_count - 2u);
    if c_count == 1u {
        return Cell(0u, g0, 0.0, gf - f32(g0));
    }
    var c = 0.0;
    if horizontal > 0.0 {
        c = degrees(atan2(d.y, d.x));
        if c < 0.0 {
            c += 360.0;
        }
    }
    let cf = clamp(c / l.steps.x, 0.0, f32(c_count - 1u));
    let c0 = min(u32(floor(cf)), c_count - 2u);
    return Cell(c0, g0, cf - f32(c0), gf - f32(g0));
}

// Bilinear lookup in one grid of a profile stack (`grid` counts grids).
fn sample_cell(l: Light, grid: u32, cell: Cell) -> f32 {
    let g_count = l.info.w;
    let base = l.info.y + grid * l.info.z * g_count;
    let i00 = profiles[base + cell.c0 * g_count + cell.g0];
    let i01 = profiles[base + cell.c0 * g_count + cell.g0 + 1u];
    let low = i00 + (i01 - i00) * cell.tg;
    if l.info.z == 1u {
        return low;
    }
    let i10 = profiles[base + (cell.c0 + 1u) * g_count + cell.g0];
    let i11 = profiles[base + (cell.c0 + 1u) * g_count + cell.g0 + 1u];
    let high = i10 + (i11 - i10) * cell.tg;
    return low + (high - low) * cell.tc;
}

fn sample_grid(l: Light, grid: u32, d: vec3<f32>) -> f32 {
    return sample_cell(l, grid, grid_cell(l, d));
}

fn candela(l: Light, lum_dir: vec3<f32>) -> f32 {
    return sample_grid(l, 0u, lum_dir);
}

fn edge_integral(p: vec3<f32>, q: vec3<f32>, n: vec3<f32>) -> f32 {
    let c = cross(p, q);
    let s = length(c);
    if s < 1e-30 {
        return 0.0;
    }
    return atan2(s, dot(p, q)) * dot(c, n) / s;
}

fn safe_normalize(v: vec3<f32>) -> vec3<f32> {
    let len = length(v);
    if len > 0.0 {
        return v / len;
    }
    return vec3<f32>(0.0);
}

struct Cubature {
    lux: f32,
    cosine_solid_angle: f32,
}

fn point_illuminance(l: Light, x: vec3<f32>, n: vec3<f32>) -> f32 {
    let to_x = x - l.position.xyz;
    let d2 = dot(to_x, to_x);
    if d2 <= 0.0 {
        return 0.0;
    }
    let omega = to_x / sqrt(d2);
    let cos_x = max(dot(-omega, n), 0.0);
    return candela(l, to_luminaire(l, omega)) * cos_x / d2;
}

// Ti₂(y) = ∫₀^y atan(t)/t dt for small y (polar::inverse_tangent_integral).
fn inverse_tangent_integral(y: f32) -> f32 {
    let y2 = y * y;
    return y * (1.0 - y2 * (1.0 / 9.0 - y2 * (1.0 / 25.0 - y2 * (1.0 / 49.0 - y2 / 81.0))));
}

// The radial integrals (x: the sec − cos kernel, y: the sin kernel) from
// the opening's axis to angle atan(t) along C-plane `c_deg`, on the side
// `front` (CPU twin: polar::radial).
fn radial_column(l: Light, c: u32, i_lo: u32, i_hi: u32, theta0: f32, theta: f32, u0: f32, u: f32) -> vec2<f32> {
    let g_count = l.info.w;
    let level = l.info.z * g_count;
    let base = l.info.y + c * g_count;
    let step = radians(l.steps.y);
    let i0 = profiles[base + i_lo];
    let slope = (profiles[base + i_hi] - i0) / step;
    let s0 = sin(theta0);
    let c0 = cos(theta0);
    let s1 = sin(theta);
    let c1 = cos(theta);
    let dt = theta - theta0;
    let sin_kernel = i0 * (c0 - c1) + slope * (s1 - s0 - dt * c1);
    let cos_kernel = i0 * (s1 - s0) + slope * (dt * s1 + c1 - c0);
    // About the piece's value at 90°: π/2 − θ = 2 atan(e^−u).
    let at_axis = i0 + slope * (0.5 * PI - theta0);
    var moment = atan(exp(-0.5 * (u0 + u))) * (u - u0);
    if u0 >= 2.0 {
        moment = inverse_tangent_integral(exp(-u0)) - inverse_tangent_integral(exp(-u));
    }
    let sec_kernel = at_axis * (u - u0) - 2.0 * slope * moment - cos_kernel;
    return vec2<f32>(
        profiles[base + RADIAL_SEC * level + i_lo] + sec_kernel,
        profiles[base + RADIAL_SIN * level + i_lo] + sin_kernel,
    );
}

fn radial(l: Light, c_deg: f32, t: f32, front: bool) -> vec2<f32> {
    let g_count = l.info.w;
    let half = (g_count - 1u) / 2u;
    let step = radians(l.steps.y);
    let theta = atan(t);
    let j0 = min(u32(theta / step), half - 1u);
    let theta0 = f32(j0) * step;
    let u = asinh(t);
    let u0 = asinh(tan(theta0));
    var i_lo = j0;
    var i_hi = j0 + 1u;
    if !front {
        i_lo = g_count - 1u - j0;
        i_hi = g_count - 2u - j0;
    }
    if l.info.z == 1u {
        return radial_column(l, 0u, i_lo, i_hi, theta0, theta, u0, u);
    }
    var c = c_deg % 360.0;
    if c < 0.0 {
        c += 360.0;
    }
    let cf = clamp(c / l.steps.x, 0.0, f32(l.info.z - 1u));
    let c0 = min(u32(floor(cf)), l.info.z - 2u);
    let tc = cf - f32(c0);
    let low = radial_column(l, c0, i_lo, i_hi, theta0, theta, u0, u);
    let high = radial_column(l, c0 + 1u, i_lo, i_hi, theta0, theta, u0, u);
    return low + (high - low) * tc;
}

// J(φ): the radial integral over the part of the ray along φ inside the
// clipped opening (`m` vertices relative to the foot point), both ends
// read in the same C column (polar::PolarSetup::ray_integral).
fn ray_integral(l: Light, phi: f32, poly: ptr<function, array<vec3<f32>, 16>>, m: u32, inside: bool, height: f32, front: bool, nl: vec3<f32>) -> f32 {
    let dir = vec2<f32>(cos(phi), sin(phi));
    var lo = 1e30;
    var hi = -1e30;
    for (var i = 0u; i < m; i++) {
        let a = (*poly)[i].xy;
        let edge = (*poly)[(i + 1u) % m].xy - a;
        let denominator = dir.x * edge.y - dir.y * edge.x;
        if denominator == 0.0 {
            continue;
        }
        // ρ dir = a + s (b − a).
        let along = (a.x * dir.y - a.y * dir.x) / denominator;
        if along < -1e-5 || along > 1.0 + 1e-5 {
            continue;
        }
        let rho = max((a.x * edge.y - a.y * edge.x) / denominator, 0.0);
        lo = min(lo, rho);
        hi = max(hi, rho);
    }
    if hi < lo {
        return 0.0;
    }
    let c_deg = degrees(phi) + 180.0;
    var r = radial(l, c_deg, hi / height, front);
    if !inside && lo > 0.0 {
        r -= radial(l, c_deg, lo / height, front);
    }
    let side = select(-1.0, 1.0, front);
    return (dir.x * nl.x + dir.y * nl.y) * r.x + side * nl.z * r.y;
}

// One piece of the sweep: 2 Gauss–Legendre nodes up to SMALL_ARC, 3 up
// to MEDIUM_ARC, else 4 per MAX_ARC (polar::illuminance_with_nodes).
fn piece_integral(l: Light, lo: f32, span: f32, clipped: ptr<function, array<vec3<f32>, 16>>, m: u32, inside: bool, height: f32, front: bool, nl: vec3<f32>) -> f32 {
    var sum = 0.0;
    if span <= 1e-7 {
        return sum;
    }
    var small_arc = SMALL_ARC;
    var medium_arc = MEDIUM_ARC;
    var max_arc = MAX_ARC;
    if params.mode == 2u {
        small_arc = DRAFT_SMALL_ARC;
        medium_arc = 2.0 * DRAFT_SMALL_ARC;
        max_arc = DRAFT_MAX_ARC;
    }
    if span <= small_arc {
        sum += 0.5 * span * ray_integral(l, lo + 0.2113248654051871 * span, clipped, m, inside, height, front, nl);
        sum += 0.5 * span * ray_integral(l, lo + 0.7886751345948129 * span, clipped, m, inside, height, front, nl);
        return sum;
    }
    if span <= medium_arc {
        sum += (5.0 / 18.0) * span * ray_integral(l, lo + 0.1127016653792583 * span, clipped, m, inside, height, front, nl);
        sum += (8.0 / 18.0) * span * ray_integral(l, lo + 0.5 * span, clipped, m, inside, height, front, nl);
        sum += (5.0 / 18.0) * span * ray_integral(l, lo + 0.8872983346207417 * span, clipped, m, inside, height, front, nl);
        return sum;
    }
    let arcs = max(ceil(span / max_arc), 1.0);
    let width = span / arcs;
    let w_outer = 0.1739274225687269 * width;
    let w_inner = 0.3260725774312731 * width;
    for (var a = 0u; a < u32(arcs); a++) {
        let start = lo + f32(a) * width;
        sum += w_outer * ray_integral(l, start + 0.0694318442029737 * width, clipped, m, inside, height, front, nl);
        sum += w_inner * ray_integral(l, start + 0.3300094782075719 * width, clipped, m, inside, height, front, nl);
        sum += w_inner * ray_integral(l, start + 0.6699905217924281 * width, clipped, m, inside, height, front, nl);
        sum += w_outer * ray_integral(l, start + 0.9305681557970263 * width, clipped, m, inside, height, front, nl);
    }
    return sum;
}

// Illuminance at x (normal n) by the polar rule (CPU twin:
// crates/room/src/polar.rs): the opening clipped by x's horizon in the
// luminaire's frame, relative to x's foot point on the opening's plane;
// between consecutive vertex directions seen from the foot point, 4
// Gauss–Legendre nodes in angle per MAX_ARC, each an exact radial integral
// of the profile from the radial tables (a midpoint in u below 74.6°).
// `clipped` is scratch space.
fn illuminance(l: Light, x_in: vec3<f32>, n_in: vec3<f32>, clipped: ptr<function, array<vec3<f32>, 16>>) -> Cubature {
    var result = Cubature(0.0, 0.0);
    let count = l.info.x;
    let area = l.position.w;
    if count < 3u || area <= 0.0 {
        result.lux = point_illuminance(l, x_in, n_in);
        return result;
    }
    let xl = to_luminaire(l, x_in - l.position.xyz);
    let nl = to_luminaire(l, n_in);
    let epsilon = IN_PLANE * l.steps.z;
    // The emitting normal is −z; in the plane, the front-side limit.
    var height = abs(xl.z);
    var front = xl.z < 0.0;
    if height < epsilon {
        height = epsilon;
        front = true;
    }
    let side = select(-1.0, 1.0, front);
    let foot = xl.xy;
    // Horizon clip: (p − x)·n ≥ 0 for p on the opening's plane.
    let axial = side * height * nl.z;
    var m = 0u;
    for (var i = 0u; i < count; i++) {
        let a = to_luminaire(l, l.vertices[i].xyz - l.position.xyz).xy - foot;
        let b = to_luminaire(l, l.vertices[(i + 1u) % count].xyz - l.position.xyz).xy - foot;
        let da = dot(a, nl.xy) + axial;
        let db = dot(b, nl.xy) + axial;
        if da >= 0.0 {
            (*clipped)[m] = vec3<f32>(a, 0.0);
            m++;
        }
        if (da >= 0.0) != (db >= 0.0) {
            (*clipped)[m] = vec3<f32>(a + (b - a) * (da / (da - db)), 0.0);
            m++;
        }
    }
    if m < 3u {
        return result;
    }
    // ∫ cos dω (Lambert's edge formula, for the specular term) and the
    // winding of the edges around the foot point.
    let z = select(height, -height, front);
    var cosine = 0.0;
    var winding = 0.0;
    var centre = vec2<f32>(0.0);
    for (var i = 0u; i < m; i++) {
        let a = (*clipped)[i].xy;
        let b = (*clipped)[(i + 1u) % m].xy;
        cosine += edge_integral(safe_normalize(vec3<f32>(a, -z)), safe_normalize(vec3<f32>(b, -z)), nl);
        winding += atan2(a.x * b.y - a.y * b.x, dot(a, b));
        centre += a;
    }
    result.cosine_solid_angle = 0.5 * abs(cosine);
    let inside = abs(winding) > PI;
    // The vertex directions, increasing, each with whether its vertex is
    // soft (turns the boundary by under 35°): the whole circle from inside,
    // else the span between the tangent vertices.
    var angles: array<f32, 16>;
    var soft: array<bool, 16>;
    var k = 0u;
    let reference = atan2(centre.y, centre.x);
    for (var i = 0u; i < m; i++) {
        let v = (*clipped)[i].xy;
        let e0 = v - (*clipped)[(i + m - 1u) % m].xy;
        let e1 = (*clipped)[(i + 1u) % m].xy - v;
        let is_soft = dot(e0, e1) >= SOFT_VERTEX_COS * length(e0) * length(e1);
        if inside {
            if dot(v, v) > 0.0 {
                angles[k] = atan2(v.y, v.x);
                soft[k] = is_soft;
                k++;
            }
        } else {
            var d = atan2(v.y, v.x) - reference;
            d -= 2.0 * PI * floor((d + PI) / (2.0 * PI));
            angles[k] = reference + d;
            soft[k] = is_soft;
            k++;
        }
    }
    for (var i = 1u; i < k; i++) {
        let key = angles[i];
        let key_soft = soft[i];
        var j = i;
        while j > 0u && angles[j - 1u] > key {
            angles[j] = angles[j - 1u];
            soft[j] = soft[j - 1u];
            j--;
        }
        angles[j] = key;
        soft[j] = key_soft;
    }
    if inside && k > 0u {
        angles[k] = angles[0] + 2.0 * PI;
        soft[k] = soft[0];
        k++;
    }
    // Pieces between vertex directions, joined across soft vertices while
    // they span under MEDIUM_ARC, and cut at kinked C-planes
    // (polar::illuminance_with_nodes).
    var sum = 0.0;
    var w = 0u;
    let join_arc = select(MEDIUM_ARC, 2.0 * DRAFT_SMALL_ARC, params.mode == 2u);
    while w + 1u < k {
        let lo = angles[w];
        var end = w + 1u;
        while end + 1u < k && soft[end] && angles[end + 1u] - lo <= join_arc {
            end++;
        }
        let span = angles[end] - lo;
        w = end;
        if span <= 1e-7 {
            continue;
        }
        if l.steps.w > 0.0 {
            // Cut where the ray's C-plane (φ + π) crosses a kinked C-plane,
            // a multiple of steps.w (polar::RuleNodes::kink_step_rad).
            let step = l.steps.w;
            let hi = lo + span;
            var start = lo;
            var cut = (floor((lo + PI) / step) + 1.0) * step - PI;
            while cut < hi {
                sum += piece_integral(l, start, cut - start, clipped, m, inside, height, front, nl);
                start = cut;
                cut += step;
            }
            sum += piece_integral(l, start, hi - start, clipped, m, inside, height, front, nl);
        } else {
            sum += piece_integral(l, lo, span, clipped, m, inside, height, front, nl);
        }
    }
    result.lux = max(sum / area, 0.0);
    return result;
}

// Cosine form factor of a polygon of directions, clipped to z ≥ 0.
fn polygon_form_factor(poly: ptr<function, array<vec3<f32>, 16>>, count: u32) -> f32 {
    var clipped: array<vec3<f32>, 16>;
    var m = 0u;
    for (var i = 0u; i < count; i++) {
        let a = (*poly)[i];
        let b = (*poly)[(i + 1u) % count];
        if a.z >= 0.0 {
            clipped[m] = a;
            m++;
        }
        if (a.z >= 0.0) != (b.z >= 0.0) && m < MAX_CLIPPED {
            clipped[m] = a + (b - a) * (a.z / (a.z - b.z));
            m++;
        }
    }
    if m < 3u {
        return 0.0;
    }
    var sum = 0.0;
    for (var i = 0u; i < m; i++) {
        sum += edge_integral(safe_normalize(clipped[i]), safe_normalize(clipped[(i + 1u) % m]), vec3<f32>(0.0, 0.0, 1.0));
    }
    return abs(sum / (2.0 * PI));
}

fn ltc_entry(a: u32, t: u32, k: u32) -> vec4<f32> {
    return ltc[(a + LTC_SIZE * t) * 2u + k];
}

fn ltc_lookup(roughness: f32, cos_theta: f32, k: u32) -> vec4<f32> {
    let size = f32(LTC_SIZE - 1u);
    let u = clamp(roughness, 0.0, 1.0) * size;
    let v = sqrt(1.0 - clamp(cos_theta, 0.0, 1.0)) * size;
    let u0 = min(u32(floor(u)), LTC_SIZE - 2u);
    let v0 = min(u32(floor(v)), LTC_SIZE - 2u);
    let tu = u - f32(u0);
    let tv = v - f32(v0);
    let low = mix(ltc_entry(u0, v0, k), ltc_entry(u0 + 1u, v0, k), tu);
    let high = mix(ltc_entry(u0, v0 + 1u, k), ltc_entry(u0 + 1u, v0 + 1u, k), tu);
    return mix(low, high, tv);
}

// Specular radiance from a polygon (relative to x) of uniform radiance.
fn specular_radiance(l: Light, x: vec3<f32>, n: vec3<f32>, to_viewer: vec3<f32>, roughness: f32, f0: f32, radiance: f32) -> f32 {
    let cos_v = dot(to_viewer, n);
    if radiance <= 0.0 || f0 <= 0.0 || cos_v <= 0.0 {
        return 0.0;
    }
    let t1v = ltc_lookup(roughness, cos_v, 0u);
    let t2v = ltc_lookup(roughness, cos_v, 1u);
    var t1 = to_viewer - n * cos_v;
    if dot(t1, t1) < 1e-12 {
        if abs(n.x) < 0.9 {
            t1 = cross(n, vec3<f32>(1.0, 0.0, 0.0));
        } else {
            t1 = cross(n, vec3<f32>(0.0, 1.0, 0.0));
        }
    }
    t1 = normalize(t1);
    let t2 = cross(n, t1);
    var local: array<vec3<f32>, 16>;
    let count = l.info.x;
    for (var i = 0u; i < count; i++) {
        let d = l.vertices[i].xyz - x;
        let p = vec3<f32>(dot(d, t1), dot(d, t2), dot(d, n));
        // Inverse LTC matrix rows: (m00, 0, m02), (0, 1, 0), (m20, 0, m22).
        local[i] = vec3<f32>(t1v.x * p.x + t1v.z * p.z, p.y, t1v.y * p.x + t1v.w * p.z);
    }
    let albedo = f0 * t2v.x + (1.0 - f0) * t2v.y;
    return radiance * polygon_form_factor(&local, count) * albedo;
}

// Distance to a light's opening along a ray and its luminance, or -1.
fn opening_hit(l: Light, origin: vec3<f32>, dir: vec3<f32>) -> vec2<f32> {
    let count = l.info.x;
    if count < 3u || l.position.w <= 0.0 {
        return vec2<f32>(-1.0, 0.0);
    }
    let normal = -l.col2.xyz;
    let denom = dot(dir, normal);
    if abs(denom) < 1e-12 {
        return vec2<f32>(-1.0, 0.0);
    }
    let t = dot(l.position.xyz - origin, normal) / denom;
    if t <= 0.0 {
        return vec2<f32>(-1.0, 0.0);
    }
    let p = origin + dir * t;
    var orientation = 0.0;
    for (var i = 0u; i < count; i++) {
        let a = l.vertices[i].xyz;
        let b = l.vertices[(i + 1u) % count].xyz;
        let s = dot(cross(b - a, p - a), normal);
        if s != 0.0 {
            if orientation == 0.0 {
                orientation = sign(s);
            } else if sign(s) != orientation {
                return vec2<f32>(-1.0, 0.0);
            }
        }
    }
    let luminance = candela(l, to_luminaire(l, -dir)) / (l.position.w * abs(denom));
    return vec2<f32>(t, luminance);
}

// (luminance, illuminance) along one view ray.
fn shade_ray(origin: vec3<f32>, dir: vec3<f32>) -> vec2<f32> {
    var distance = 1e30;
    var surface = 0u;
    var normal = vec3<f32>(0.0, 0.0, 1.0);
    for (var k = 0u; k < params.triangle_count; k++) {
        let a = triangles[3u * k];
        let e1 = triangles[3u * k + 1u].xyz - a.xyz;
        let e2 = triangles[3u * k + 2u].xyz - a.xyz;
        let p = cross(dir, e2);
        let det = dot(e1, p);
        if abs(det) < 1e-14 {
            continue;
        }
        let inv = 1.0 / det;
        let sv = origin - a.xyz;
        let u = dot(sv, p) * inv;
        if u < 0.0 || u > 1.0 {
            continue;
        }
        let q = cross(sv, e1);
        let v = dot(dir, q) * inv;
        if v < 0.0 || u + v > 1.0 {
            continue;
        }
        let d = dot(e2, q) * inv;
        if d > 1e-6 && d < distance {
            distance = d;
            surface = u32(a.w);
            let n = normalize(cross(e1, e2));
            normal = select(n, -n, dot(n, dir) > 0.0);
        }
    }
    for (var axis = 0u; axis < 3u && params.triangle_count == 0u; axis++) {
        let d = dir[axis];
        if d == 0.0 {
            continue;
        }
        var plane = 0.0;
        var s = 0u;
        var nrm = vec3<f32>(0.0);
        if d > 0.0 {
            plane = params.room[axis];
            s = select(select(1u, 5u, axis == 1u), 3u, axis == 0u);
            nrm[axis] = -1.0;
        } else {
            s = select(select(0u, 4u, axis == 1u), 2u, axis == 0u);
            nrm[axis] = 1.0;
        }
        let t = (plane - origin[axis]) / d;
        if t < distance {
            distance = max(t, 0.0);
            surface = s;
            normal = nrm;
        }
    }
    var nearest = 1e30;
    var light_luminance = -1.0;
    for (var i = 0u; i < params.light_count; i++) {
        let h = opening_hit(lights[i], origin, dir);
        if h.x > 0.0 && h.x < distance && h.x < nearest {
            nearest = h.x;
            light_luminance = h.y;
        }
    }
    if light_luminance >= 0.0 {
        return vec2<f32>(light_luminance, -1.0);
    }
    if distance >= 1e29 {
        return vec2<f32>(0.0, 0.0);
    }
    let x = origin + dir * distance;
    let material = surfaces[surface];
    var lux = params.indirect_lux;
    var luminance = material.x / PI * params.indirect_lux;
    var clipped: array<vec3<f32>, 16>;
    for (var i = 0u; i < params.light_count; i++) {
        let l = lights[i];
        var r = Cubature(0.0, 0.0);
        if params.mode == 1u {
            r.lux = point_illuminance(l, x, normal);
        } else {
            r = illuminance(l, x, normal, &clipped);
        }
        lux += r.lux;
        luminance += material.x / PI * r.lux;
        if params.mode != 1u && material.y > 0.0 && r.lux > 0.0 && r.cosine_solid_angle > 1e-12 {
            luminance += specular_radiance(l, x, normal, -dir, material.z, material.y, r.lux / r.cosine_solid_angle);
        }
    }
    return vec2<f32>(luminance, lux);
}

@compute @workgroup_size(8, 8)
fn render(@builtin(global_invocation_id) gid: vec3<u32>) {
    if gid.x >= params.width || gid.y >= params.height {
        return;
    }
    let sx = (2.0 * (f32(gid.x) + 0.5) / f32(params.width) - 1.0) * params.tan_half_fov * params.aspect;
    let sy = (1.0 - 2.0 * (f32(gid.y) + 0.5) / f32(params.height)) * params.tan_half_fov;
    let dir = normalize(params.forward.xyz + params.right.xyz * sx + params.up.xyz * sy);
    let shaded = shade_ray(params.origin.xyz, dir);
    output[gid.y * params.width + gid.x] = vec4<f32>(shaded.x, shaded.y, 0.0, 0.0);
}

// points[2i] = position, points[2i + 1] = unit normal; output[i].x = lux,
// .y = cosine-weighted solid angle (summed over the lights).
@compute @workgroup_size(64)
fn shade_points(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if i >= params.point_count {
        return;
    }
    let x = points[2u * i].xyz;
    let n = points[2u * i + 1u].xyz;
    var clipped: array<vec3<f32>, 16>;
    var lux = 0.0;
    var g = 0.0;
    for (var k = 0u; k < params.light_count; k++) {
        var r = Cubature(0.0, 0.0);
        if params.mode == 1u {
            r.lux = point_illuminance(lights[k], x, n);
        } else {
            r = illuminance(lights[k], x, n, &clipped);
        }
        lux += r.lux;
        g += r.cosine_solid_angle;
    }
    output[i] = vec4<f32>(lux, g, 0.0, 0.0);
}
