// Preview room: photometric polygonal lights shaded with the cubature of
// Luksch et al. 2020 (prefiltered, exact cosine weights; CPU twin:
// crates/room/src/cubature.rs) and LTC specular (crates/room/src/ltc.rs).
// One invocation per pixel (`render`) or per shading point (`shade_points`).

const PI: f32 = 3.14159265358979;
const MAX_VERTICES: u32 = 12u;
const MAX_CLIPPED: u32 = 16u;
const BLUR_LEVELS: u32 = 7u;
const BLUR_BASE_DEG: f32 = 1.0;
const PLANE_EPSILON: f32 = 1e-3;
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
    // 0: cubature + LTC, 1: point-light baseline
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
    // C step (deg), γ step (deg), size (m), pieces
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

fn filter_level(radius_rad: f32) -> f32 {
    let r = degrees(radius_rad) / BLUR_BASE_DEG;
    if r <= 0.5 {
        return 0.0;
    }
    return clamp(log2(r) + 1.0, 0.0, f32(BLUR_LEVELS));
}

// I / |cos γ| over a cap of `radius` around a luminaire direction.
fn projected_filtered(l: Light, d: vec3<f32>, radius: f32) -> f32 {
    let level = filter_level(radius);
    let l0 = min(u32(floor(level)), BLUR_LEVELS);
    let t = level - f32(l0);
    let cosine = BLUR_LEVELS + 1u;
    let cell = grid_cell(l, d);
    var i = sample_cell(l, l0, cell);
    var c = sample_cell(l, cosine + l0, cell);
    if t > 0.0 && l0 < BLUR_LEVELS {
        i = i * (1.0 - t) + sample_cell(l, l0 + 1u, cell) * t;
        c = c * (1.0 - t) + sample_cell(l, cosine + l0 + 1u, cell) * t;
    }
    if c > 1e-9 {
        return i / c;
    }
    return 0.0;
}

fn triangle_solid_angle(a: vec3<f32>, b: vec3<f32>, c: vec3<f32>) -> f32 {
    let numerator = abs(dot(a, cross(b, c)));
    let denominator = 1.0 + dot(a, b) + dot(a, c) + dot(b, c);
    return 2.0 * atan2(numerator, denominator);
}

fn edge_integral(p: vec3<f32>, q: vec3<f32>, n: vec3<f32>) -> f32 {
    let c = cross(p, q);
    let s = length(c);
    if s < 1e-30 {
        return 0.0;
    }
    return atan2(s, dot(p, q)) * dot(c, n) / s;
}

fn triangle_cosine_solid_angle(a: vec3<f32>, b: vec3<f32>, c: vec3<f32>, n: vec3<f32>) -> f32 {
    return 0.5 * abs(edge_integral(a, b, n) + edge_integral(b, c, n) + edge_integral(c, a, n));
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

// Vertex i of piece j of k of the opening: elongated rectangles are cut
// into strips across their longer sides (twin of `light::split_quad`).
fn piece_vertex(l: Light, j: u32, k: u32, i: u32) -> vec3<f32> {
    if k <= 1u || l.info.x != 4u {
        return l.vertices[i].xyz;
    }
    let v0 = l.vertices[0].xyz;
    let v1 = l.vertices[1].xyz;
    let v3 = l.vertices[3].xyz;
    let e01 = v1 - v0;
    let e03 = v3 - v0;
    let t0 = f32(j) / f32(k);
    let t1 = f32(j + 1u) / f32(k);
    if dot(e01, e01) > dot(e03, e03) {
        switch i {
            case 0u: { return v0 + e01 * t0; }
            case 1u: { return v0 + e01 * t1; }
            case 2u: { return v3 + e01 * t1; }
            default: { return v3 + e01 * t0; }
        }
    }
    switch i {
        case 0u: { return v0 + e03 * t0; }
        case 1u: { return v1 + e03 * t0; }
        case 2u: { return v1 + e03 * t1; }
        default: { return v0 + e03 * t1; }
    }
}

// Illuminance at x (normal n); `clipped` is scratch space.
fn illuminance(l: Light, x_in: vec3<f32>, n: vec3<f32>, clipped: ptr<function, array<vec3<f32>, 16>>) -> Cubature {
    var result = Cubature(0.0, 0.0);
    let count = l.info.x;
    let area = l.position.w;
    if count < 3u || area <= 0.0 {
        result.lux = point_illuminance(l, x_in, n);
        return result;
    }
    let normal_a = -l.col2.xyz;
    let epsilon = PLANE_EPSILON * l.steps.z;
    let height = dot(x_in - l.position.xyz, normal_a);
    var x = x_in;
    if abs(height) < epsilon {
        x = x_in + normal_a * (epsilon - height);
    }
    let pieces = max(u32(l.steps.w), 1u);
    for (var piece = 0u; piece < pieces; piece++) {
        // Clip the opening (relative to x) by x's horizon.
        var m = 0u;
        for (var i = 0u; i < count; i++) {
            let a = piece_vertex(l, piece, pieces, i) - x;
            let b = piece_vertex(l, piece, pieces, (i + 1u) % count) - x;
            let da = dot(a, n);
            let db = dot(b, n);
            if da >= 0.0 {
                (*clipped)[m] = a;
                m++;
            }
            if (da >= 0.0) != (db >= 0.0) {
                (*clipped)[m] = a + (b - a) * (da / (da - db));
                m++;
            }
        }
        if m < 3u {
            continue;
        }
        // Closest point of the visible polygon to x's projection on the plane.
        let q = -normal_a * dot(x - l.position.xyz, normal_a);
        var inside = true;
        var orientation = 0.0;
        for (var i = 0u; i < m; i++) {
            let a = (*clipped)[i];
            let b = (*clipped)[(i + 1u) % m];
            let s = dot(cross(b - a, q - a), normal_a);
            if s != 0.0 {
                if orientation == 0.0 {
                    orientation = sign(s);
                } else if sign(s) != orientation {
                    inside = false;
                }
            }
        }
        var closest = q;
        if !inside {
            var best = 1e30;
            for (var i = 0u; i < m; i++) {
                let a = (*clipped)[i];
                let ab = (*clipped)[(i + 1u) % m] - a;
                let len2 = dot(ab, ab);
                var t = 0.0;
                if len2 > 0.0 {
                    t = clamp(dot(q - a, ab) / len2, 0.0, 1.0);
                }
                let p = a + ab * t;
                let d = dot(p - q, p - q);
                if d < best {
                    best = d;
                    closest = p;
                }
            }
        }
        let dc = safe_normalize(closest);
        var prev = safe_normalize((*clipped)[m - 1u]);
        for (var i = 0u; i < m; i++) {
            let cur = safe_normalize((*clipped)[i]);
            let weight = triangle_cosine_solid_angle(dc, prev, cur, n);
            if weight > 0.0 {
                let omega = triangle_solid_angle(dc, prev, cur);
                let radius = sqrt(omega / PI);
                let centre = to_luminaire(l, -safe_normalize(dc + prev + cur));
                result.lux += projected_filtered(l, centre, radius) / area * weight;
            }
            result.cosine_solid_angle += weight;
            prev = cur;
        }
    }
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
        if params.mode == 0u && material.y > 0.0 && r.lux > 0.0 && r.cosine_solid_angle > 1e-12 {
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
