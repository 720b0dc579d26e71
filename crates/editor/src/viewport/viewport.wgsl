// The 3D viewport: the luminaire's surfaces, the intensity cube around it
// and traced photon paths, drawn offscreen with depth (blit.wgsl copies
// the picture into egui's pass). Colours are linear; the target is sRGB.

struct Uniforms {
    view_projection: mat4x4<f32>,
    // xyz: camera position (m, luminaire coordinates).
    eye: vec4<f32>,
    // xyz: cube centre, w: half its edge (m).
    cube: vec4<f32>,
    // Index into the tessellated surfaces of the selected one, or none.
    selected_surface: u32,
    _pad0: u32,
    _pad1: u32,
    _pad2: u32,
};

@group(0) @binding(0) var<uniform> u: Uniforms;

// ---- luminaire surfaces ------------------------------------------------

// How a surface is shaded: diffuse paint, polished or brushed metal,
// clear or diffusing plastic, an emitter's glowing surface.
const LOOK_DIFFUSE: u32 = 0u;
const LOOK_METAL: u32 = 1u;
const LOOK_GLASS: u32 = 2u;
const LOOK_EMITTER: u32 = 3u;

struct MeshIn {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) colour: vec4<f32>,
    @location(3) look: u32,
    @location(4) surface: u32,
};

struct MeshOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) colour: vec4<f32>,
    @location(3) @interpolate(flat) look: u32,
    @location(4) @interpolate(flat) surface: u32,
};

@vertex
fn vs_mesh(v: MeshIn) -> MeshOut {
    var out: MeshOut;
    out.clip = u.view_projection * vec4<f32>(v.position, 1.0);
    out.world = v.position;
    out.normal = v.normal;
    out.colour = v.colour;
    out.look = v.look;
    out.surface = v.surface;
    return out;
}

@fragment
fn fs_mesh(v: MeshOut) -> @location(0) vec4<f32> {
    let to_eye = normalize(u.eye.xyz - v.world);
    var n = normalize(v.normal);
    // Sheets are two-sided: light the side the camera sees.
    if dot(n, to_eye) < 0.0 {
        n = -n;
    }
    let base = v.colour.rgb;
    // A headlight and a key light from above, so shapes read at any angle.
    let key = normalize(vec3<f32>(0.4, -0.3, 1.0));
    let diffuse = 0.18 + 0.55 * max(dot(n, to_eye), 0.0) + 0.35 * max(dot(n, key), 0.0);
    var colour = base * diffuse;
    if v.look == LOOK_METAL {
        // A mirror shows its surroundings: a sky-to-floor gradient by the
        // reflected direction, plus a sharp highlight.
        let r = reflect(-to_eye, n);
        let sky = mix(vec3<f32>(0.08, 0.08, 0.09), vec3<f32>(0.85, 0.88, 0.95), 0.5 + 0.5 * r.z);
        let h = normalize(to_eye + key);
        let highlight = pow(max(dot(n, h), 0.0), 80.0);
        colour = base * (0.25 * diffuse + 0.75 * sky) + vec3<f32>(highlight);
    } else if v.look == LOOK_GLASS {
        let fresnel = pow(1.0 - max(dot(n, to_eye), 0.0), 3.0);
        colour = base * (0.6 + 0.4 * diffuse) + vec3<f32>(0.5 * fresnel);
    } else if v.look == LOOK_EMITTER {
        colour = base;
    }
    if v.surface == u.selected_surface {
        // Selected: an orange tint that leaves the shading readable.
        colour = mix(colour, vec3<f32>(1.0, 0.45, 0.05), 0.55);
    }
    return vec4<f32>(colour, 1.0);
}

// The selected surface drawn again over everything in front of it (depth
// test off, blended): a reflector inside its housing stays visible.
@fragment
fn fs_xray(v: MeshOut) -> @location(0) vec4<f32> {
    if v.surface != u.selected_surface {
        discard;
    }
    let to_eye = normalize(u.eye.xyz - v.world);
    let facing = abs(dot(normalize(v.normal), to_eye));
    // Brighter at grazing angles, so the outline reads.
    return vec4<f32>(1.0, 0.55, 0.1, 0.18 + 0.3 * (1.0 - facing));
}

// ---- intensity cube -----------------------------------------------------

// The six faces in a 3 × 2 atlas (face k at column k mod 3, row k / 3).
@group(1) @binding(0) var cube_faces: texture_2d<f32>;
@group(1) @binding(1) var cube_sampler: sampler;

struct CubeIn {
    // Corner on the unit cube (±1), the face's outward normal, face
    // coordinates in [0, 1] and the face's layer.
    @location(0) corner: vec3<f32>,
    @location(1) outward: vec3<f32>,
    @location(2) uv: vec2<f32>,
    @location(3) layer: u32,
};

struct CubeOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) outward: vec3<f32>,
    @location(2) uv: vec2<f32>,
    @location(3) @interpolate(flat) layer: u32,
};

@vertex
fn vs_cube(v: CubeIn) -> CubeOut {
    var out: CubeOut;
    let world = u.cube.xyz + v.corner * u.cube.w;
    out.clip = u.view_projection * vec4<f32>(world, 1.0);
    out.world = world;
    out.outward = v.outward;
    out.uv = v.uv;
    out.layer = v.layer;
    return out;
}

@fragment
fn fs_cube(v: CubeOut) -> @location(0) vec4<f32> {
    // Only the faces behind the luminaire: a face whose plane the camera
    // is outside of would hide it.
    if dot(v.outward, u.eye.xyz - v.world) > 0.0 {
        discard;
    }
    let cell = vec2<f32>(f32(v.layer % 3u), f32(v.layer / 3u));
    // Kept inside the face's cell so nearest sampling never takes a
    // neighbour face's texel at an edge.
    let dims = vec2<f32>(textureDimensions(cube_faces));
    let inset = clamp(v.uv, vec2<f32>(0.0), vec2<f32>(1.0) - 0.5 / (dims / vec2<f32>(3.0, 2.0)));
    let atlas = (cell + inset) / vec2<f32>(3.0, 2.0);
    return vec4<f32>(textureSample(cube_faces, cube_sampler, atlas).rgb, 1.0);
}

// ---- photon paths and axes ---------------------------------------------

struct LineIn {
    @location(0) position: vec3<f32>,
    @location(1) colour: vec4<f32>,
};

struct LineOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) colour: vec4<f32>,
};

@vertex
fn vs_line(v: LineIn) -> LineOut {
    var out: LineOut;
    out.clip = u.view_projection * vec4<f32>(v.position, 1.0);
    out.colour = v.colour;
    return out;
}

@fragment
fn fs_line(v: LineOut) -> @location(0) vec4<f32> {
    return v.colour;
}
