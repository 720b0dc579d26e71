// Pull-push bilateral upsampling filter (Litemaker 2017, section 5), the
// WGSL twin of crates/filter/src/pyramid.rs. The pyramid lives in flat
// buffers with one offset per level; each dispatch works on one level.
// Composed after cubemap.wgsl, whose texel order every level follows.

struct LevelParams {
    // Offsets (in texels) and resolutions of this level and the coarser one.
    offset: u32,
    resolution: u32,
    coarse_offset: u32,
    coarse_resolution: u32,
    // Counts below this may be replaced; the border test's threshold.
    threshold: f32,
    border_threshold: f32,
    // 1 where the rule is the Poisson test.
    poisson_test: u32,
    // 1 where Algorithm 2's shadow-border test applies.
    border_test: u32,
    sigma_closeness: f32,
    sigma_range: f32,
    // The Poisson test's z, and the fewest photons it keeps as structure.
    poisson_z: f32,
    poisson_min_keep: f32,
}

@group(0) @binding(0) var<uniform> level: LevelParams;
@group(0) @binding(1) var<storage, read_write> counts: array<f32>;
@group(0) @binding(2) var<storage, read> omega: array<f32>;
@group(0) @binding(3) var<storage, read_write> intensity: array<f32>;
@group(0) @binding(4) var<storage, read_write> replaced: array<u32>;

// Flat invocation index of a 2D dispatch (rows of at most 65535 groups).
fn flat_index(gid: vec3<u32>, groups: vec3<u32>) -> u32 {
    return gid.x + gid.y * groups.x * 64u;
}

// Pull: each coarse texel sums its (up to) 2x2 children.
@compute @workgroup_size(64)
fn pull(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let t = flat_index(gid, groups);
    let n = level.coarse_resolution;
    if t >= cube_texel_count(n) {
        return;
    }
    let coarse = cube_texel_coordinates(t, n);
    let fine = level.resolution;
    var sum = 0.0;
    for (var dj = 0u; dj < 2u; dj++) {
        for (var di = 0u; di < 2u; di++) {
            let i = 2u * coarse.y + di;
            let j = 2u * coarse.z + dj;
            if i < fine && j < fine {
                sum += counts[level.offset + cube_texel_index(coarse.x, i, j, fine)];
            }
        }
    }
    counts[level.coarse_offset + t] = sum;
}

fn safe_intensity(c: f32, w: f32) -> f32 {
    if w > 0.0 {
        return c / w;
    }
    return 0.0;
}

// The coarsest level keeps its own intensities.
@compute @workgroup_size(64)
fn top(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let t = flat_index(gid, groups);
    if t >= cube_texel_count(level.resolution) {
        return;
    }
    let k = level.offset + t;
    intensity[k] = safe_intensity(counts[k], omega[k]);
}

// Texel (cx, cy) of `face` at a level, across an edge when needed; an
// index within the level.
fn texel_at(resolution: u32, face: u32, cx: i32, cy: i32) -> u32 {
    let n = i32(resolution);
    if cx >= 0 && cx < n && cy >= 0 && cy < n {
        return cube_texel_index(face, u32(cx), u32(cy), resolution);
    }
    // Past a cube corner: the face's own corner texel (as in Rust).
    if (cx < 0 || cx >= n) && (cy < 0 || cy >= n) {
        return cube_texel_index(face, u32(clamp(cx, 0, n - 1)), u32(clamp(cy, 0, n - 1)), resolution);
    }
    let step = 2.0 / f32(n);
    let a = -1.0 + (f32(cx) + 0.5) * step;
    let b = -1.0 + (f32(cy) + 0.5) * step;
    return cube_texel_of_direction(cube_face_direction(face, a, b), resolution);
}

fn upsample(face: u32, i: u32, j: u32) -> f32 {
    let ratio = f32(level.coarse_resolution) / f32(level.resolution);
    let x = (f32(i) + 0.5) * ratio - 0.5;
    let y = (f32(j) + 0.5) * ratio - 0.5;
    let x0 = floor(x);
    let y0 = floor(y);
    let fx = x - x0;
    let fy = y - y0;
    var values: array<f32, 4>;
    var bilinear: array<f32, 4>;
    var closeness: array<f32, 4>;
    for (var k = 0u; k < 4u; k++) {
        let dx = f32(k & 1u);
        let dy = f32(k >> 1u);
        let cx = x0 + dx;
        let cy = y0 + dy;
        values[k] = intensity[level.coarse_offset + texel_at(level.coarse_resolution, face, i32(cx), i32(cy))];
        bilinear[k] = select(1.0 - fx, fx, dx > 0.0) * select(1.0 - fy, fy, dy > 0.0);
        let d2 = (x - cx) * (x - cx) + (y - cy) * (y - cy);
        closeness[k] = exp(-0.5 * d2 / (level.sigma_closeness * level.sigma_closeness));
    }
    var estimate = 0.0;
    for (var k = 0u; k < 4u; k++) {
        estimate += values[k] * bilinear[k];
    }
    var num = 0.0;
    var den = 0.0;
    for (var k = 0u; k < 4u; k++) {
        let larger = max(estimate, values[k]);
        var delta = 0.0;
        if larger > 0.0 {
            delta = abs(estimate - values[k]) / larger;
        }
        let similarity = exp(-0.5 * (delta / level.sigma_range) * (delta / level.sigma_range));
        let w = closeness[k] * similarity;
        num += values[k] * w;
        den += w;
    }
    if den > 0.0 {
        return num / den;
    }
    return estimate;
}

// Algorithm 2: true when the unstable texel sits on a shadow border.
fn on_shadow_border(face: u32, i: u32, j: u32, own: f32) -> bool {
    var stable = 0u;
    for (var dy = -1; dy <= 1; dy++) {
        for (var dx = -1; dx <= 1; dx++) {
            if dx == 0 && dy == 0 {
                continue;
            }
            let t = texel_at(level.resolution, face, i32(i) + dx, i32(j) + dy);
            if counts[level.offset + t] + own >= 2.0 * level.border_threshold {
                stable += 1u;
            }
        }
    }
    return !(stable == 0u || stable > 6u);
}

// Push: one level from the filtered coarser one.
@compute @workgroup_size(64)
fn push(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let t = flat_index(gid, groups);
    let n = level.resolution;
    if t >= cube_texel_count(n) {
        return;
    }
    let k = level.offset + t;
    let c = counts[k];
    let own = safe_intensity(c, omega[k]);
    var value = own;
    var was_replaced = 0u;
    if c < level.threshold {
        let texel = cube_texel_coordinates(t, n);
        let face = texel.x;
        let i = texel.y;
        let j = texel.z;
        if level.border_test == 0u || !on_shadow_border(face, i, j, c) {
            let estimate = upsample(face, i, j);
            var keep = false;
            if level.poisson_test == 1u {
                let expected = estimate * omega[k];
                let darker = c < expected && expected - c > level.poisson_z * sqrt(expected);
                let brighter = c >= level.poisson_min_keep && c - expected > level.poisson_z * sqrt(expected + 1.0);
                keep = darker || brighter;
            }
            if !keep {
                value = estimate;
                was_replaced = 1u;
            }
        }
    }
    intensity[k] = value;
    if level.offset == 0u {
        replaced[t] = was_replaced;
    }
}
