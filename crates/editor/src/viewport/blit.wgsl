// Copies the viewport's offscreen picture into egui's pass (egui sets the
// viewport to our rectangle). The picture is sRGB: sampling decodes it.

@group(0) @binding(0) var picture: texture_2d<f32>;
@group(0) @binding(1) var picture_sampler: sampler;

struct BlitOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) uv: vec2<f32>,
};

// One triangle that covers the viewport.
@vertex
fn vs_blit(@builtin(vertex_index) i: u32) -> BlitOut {
    let x = f32((i << 1u) & 2u);
    let y = f32(i & 2u);
    var out: BlitOut;
    out.clip = vec4<f32>(2.0 * x - 1.0, 1.0 - 2.0 * y, 0.0, 1.0);
    out.uv = vec2<f32>(x, y);
    return out;
}

fn srgb_from_linear(c: vec3<f32>) -> vec3<f32> {
    let low = c * 12.92;
    let high = 1.055 * pow(c, vec3<f32>(1.0 / 2.4)) - 0.055;
    return select(high, low, c <= vec3<f32>(0.0031308));
}

// egui's preferred target is not sRGB-aware: write encoded values.
@fragment
fn fs_blit_gamma(v: BlitOut) -> @location(0) vec4<f32> {
    let c = textureSample(picture, picture_sampler, v.uv);
    return vec4<f32>(srgb_from_linear(c.rgb), 1.0);
}

@fragment
fn fs_blit_linear(v: BlitOut) -> @location(0) vec4<f32> {
    let c = textureSample(picture, picture_sampler, v.uv);
    return vec4<f32>(c.rgb, 1.0);
}
