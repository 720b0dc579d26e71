// Cube-map layout, the WGSL twin of crates/photometry/src/cubemap.rs.
// Faces +X, -X, +Y, -Y, +Z, -Z with the WebGPU face (u, v); texel order in
// cube_texel_index. The major axis is the largest |component|, ties going
// to x, then y (as in Rust).

// Texels of a cube map of `resolution` texels per edge.
fn cube_texel_count(resolution: u32) -> u32 {
    return 6u * resolution * resolution;
}

// Texel index of (face, column, row), the twin of CubeMapLayout::texel_index
// and the only place the WGSL spells out the texel order.
fn cube_texel_index(face: u32, column: u32, row: u32, resolution: u32) -> u32 {
    return face * resolution * resolution + row * resolution + column;
}

// (face, column, row) of a texel index: the inverse of cube_texel_index,
// twin of CubeMapLayout::texel_coordinates.
fn cube_texel_coordinates(texel: u32, resolution: u32) -> vec3<u32> {
    let per_face = resolution * resolution;
    let rest = texel % per_face;
    return vec3<u32>(texel / per_face, rest % resolution, rest / resolution);
}

// Face and face coordinates (a, b) in [-1, 1] of a non-zero direction.
fn cube_face_coordinates(d: vec3<f32>) -> vec3<f32> {
    let ad = abs(d);
    if ad.x >= ad.y && ad.x >= ad.z {
        if d.x >= 0.0 {
            return vec3<f32>(0.0, -d.z / ad.x, -d.y / ad.x);
        }
        return vec3<f32>(1.0, d.z / ad.x, -d.y / ad.x);
    }
    if ad.y >= ad.z {
        if d.y >= 0.0 {
            return vec3<f32>(2.0, d.x / ad.y, d.z / ad.y);
        }
        return vec3<f32>(3.0, d.x / ad.y, -d.z / ad.y);
    }
    if d.z >= 0.0 {
        return vec3<f32>(4.0, d.x / ad.z, -d.y / ad.z);
    }
    return vec3<f32>(5.0, -d.x / ad.z, -d.y / ad.z);
}

// Texel index of direction d on a cube map of `resolution` texels per edge.
fn cube_texel_of_direction(d: vec3<f32>, resolution: u32) -> u32 {
    let fab = cube_face_coordinates(d);
    let n = f32(resolution);
    let column = u32(clamp(floor((fab.y + 1.0) * 0.5 * n), 0.0, n - 1.0));
    let row = u32(clamp(floor((fab.z + 1.0) * 0.5 * n), 0.0, n - 1.0));
    return cube_texel_index(u32(fab.x), column, row, resolution);
}

// Direction (not normalised) through face coordinates (a, b) of `face`:
// the inverse of cube_face_coordinates.
fn cube_face_direction(face: u32, a: f32, b: f32) -> vec3<f32> {
    switch face {
        case 0u: { return vec3<f32>(1.0, -b, -a); }
        case 1u: { return vec3<f32>(-1.0, -b, a); }
        case 2u: { return vec3<f32>(a, 1.0, b); }
        case 3u: { return vec3<f32>(a, -1.0, -b); }
        case 4u: { return vec3<f32>(a, -b, 1.0); }
        default: { return vec3<f32>(-a, -b, -1.0); }
    }
}
