// Maps directions to texel indices with cubemap.wgsl, so a test can compare
// the WGSL mapping with the Rust one.

struct TestParams {
    count: u32,
    resolution: u32,
    pad0: u32,
    pad1: u32,
}

@group(0) @binding(0) var<uniform> test_params: TestParams;
@group(0) @binding(1) var<storage, read> directions: array<vec4<f32>>;
@group(0) @binding(2) var<storage, read_write> texels: array<u32>;

@compute @workgroup_size(64)
fn map_directions(@builtin(global_invocation_id) gid: vec3<u32>) {
    if gid.x >= test_params.count {
        return;
    }
    texels[gid.x] = cube_texel_of_direction(directions[gid.x].xyz, test_params.resolution);
}
