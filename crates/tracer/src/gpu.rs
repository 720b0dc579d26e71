//! Driver of the WGSL photon-tracing kernel (`shaders/tracer.wgsl`): uploads
//! the prepared scene, dispatches batches, reads back the counts.

use bytemuck::{Pod, Zeroable};
use lucerna_gpu::{GpuContext, GpuError};
use lucerna_scene::EmitterShape;
use wgpu::util::DeviceExt;

use crate::cpu::{Tally, TraceSettings};
use crate::prepared::{EmitterDirections, PreparedScene};

/// Kernel parameters (48 bytes), WGSL twin `Params`.
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
struct Params {
    photon_offset: u32,
    photon_count: u32,
    seed: u32,
    iteration: u32,
    max_bounces: u32,
    resolution: u32,
    emitter_count: u32,
    threads_per_row: u32,
    epsilon: f32,
    bvh_scale: f32,
    pad0: u32,
    pad1: u32,
}
const _: () = assert!(std::mem::size_of::<Params>() == 48);

/// An emitter for the kernel (160 bytes), WGSL twin `Emitter`.
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
struct GpuEmitter {
    x_axis: [f32; 4],
    y_axis: [f32; 4],
    z_axis: [f32; 4],
    translation: [f32; 4],
    normal_x: [f32; 4],
    normal_y: [f32; 4],
    normal_z: [f32; 4],
    params: [f32; 4],
    shape: u32,
    cdf: f32,
    profile_offset: u32,
    profile_planes: u32,
    profile_gammas: u32,
    pad: [u32; 3],
}
const _: () = assert!(std::mem::size_of::<GpuEmitter>() == 160);

const WORKGROUP: u32 = 64;
const MAX_GROUPS_PER_ROW: u32 = 65_535;

/// The kernel, its scene buffers and its counters on one device.
#[derive(Debug)]
pub struct GpuTracer {
    ctx: GpuContext,
    pipeline: wgpu::ComputePipeline,
    bind_group: wgpu::BindGroup,
    params: wgpu::Buffer,
    counts: wgpu::Buffer,
    tallies: wgpu::Buffer,
    counts_readback: wgpu::Buffer,
    tallies_readback: wgpu::Buffer,
    settings: TraceSettings,
    emitter_count: u32,
    epsilon: f32,
    bvh_scale: f32,
}

fn column(v: glam::Vec3A) -> [f32; 4] {
    [v.x, v.y, v.z, 0.0]
}

fn gpu_emitters(scene: &PreparedScene) -> (Vec<GpuEmitter>, Vec<f32>) {
    let mut profiles = Vec::new();
    let emitters = scene
        .emitters
        .iter()
        .zip(&scene.emitter_cdf)
        .map(|(e, &cdf)| {
            let m = e.luminaire_from_emitter.matrix3;
            let (shape, params) = match e.shape {
                EmitterShape::Disk { radius } => (0, [radius as f32, 0.0, 0.0, 0.0]),
                EmitterShape::Rectangle { width, depth } => {
                    (1, [width as f32, depth as f32, 0.0, 0.0])
                }
                EmitterShape::Sphere { radius } => (2, [radius as f32, 0.0, 0.0, 0.0]),
                EmitterShape::Cylinder { radius, height } => {
                    (3, [radius as f32, height as f32, 0.0, 0.0])
                }
                // The interpolation kernel's width (rad) in w; 0: the
                // file's rays as they are.
                EmitterShape::RayFile { .. } => (
                    4,
                    [0.0, 0.0, 0.0, e.ray_kernel.map_or(0.0, |k| k.direction_rad)],
                ),
            };
            let (profile_offset, profile_planes, profile_gammas) = match &e.directions {
                EmitterDirections::Lambertian => (u32::MAX, 0, 0),
                EmitterDirections::Profile(sampler) => {
                    let (nc, ng, data) = sampler.packed();
                    let offset = profiles.len() as u32;
                    profiles.extend(data);
                    (offset, nc, ng)
                }
                // The rays at `profile_offset`, 8 values each; their count
                // in `profile_planes`.
                EmitterDirections::RayFile(sampler) => {
                    let offset = profiles.len() as u32;
                    profiles.extend(sampler.packed());
                    (offset, sampler.rays.len() as u32, 0)
                }
            };
            GpuEmitter {
                x_axis: column(m.x_axis),
                y_axis: column(m.y_axis),
                z_axis: column(m.z_axis),
                translation: column(e.luminaire_from_emitter.translation),
                normal_x: column(e.normal_matrix.x_axis),
                normal_y: column(e.normal_matrix.y_axis),
                normal_z: column(e.normal_matrix.z_axis),
                params,
                shape,
                cdf,
                profile_offset,
                profile_planes,
                profile_gammas,
                pad: [0; 3],
            }
        })
        .collect();
    if profiles.is_empty() {
        profiles.push(0.0); // storage bindings cannot be empty
    }
    (emitters, profiles)
}

/// Flag in a material's kind for the kernel: a finish's record follows
/// at the offset in the bits of `ior` (WGSL `FINISHED`).
const FINISHED: u32 = 0x100;

/// The materials as the kernel reads them: a finished one flagged, its
/// finish's record appended to `profiles` (see `shaders/tracer.wgsl`).
/// A finish traced as shading normals needs the CPU tracer.
fn gpu_materials(
    scene: &PreparedScene,
    profiles: &mut Vec<f32>,
) -> Result<Vec<crate::prepared::TraceMaterial>, GpuError> {
    use lucerna_scene::finish_layout::TangentRule;
    let mut out = scene.materials.clone();
    for (m, f) in out.iter_mut().zip(&scene.material_finish) {
        let Some(f) = f else { continue };
        if f.surface.normals.is_some() {
            return Err(GpuError::Failed(format!(
                "part '{}': a finish traced as shading normals runs on the CPU tracer only",
                f.surface.part
            )));
        }
        let Some(brdf) = &f.brdf else { continue };
        let offset = profiles.len() as u32;
        let (rule, axis, origin) = match f.surface.tangents {
            TangentRule::Around { axis, origin } => (0.0, axis, origin),
            TangentRule::Along { direction } => (1.0, direction, glam::DVec3::ZERO),
        };
        profiles.extend([
            brdf.flat_share() as f32,
            brdf.range() as f32,
            brdf.bins() as f32,
            rule,
            axis.x as f32,
            axis.y as f32,
            axis.z as f32,
            origin.x as f32,
            origin.y as f32,
            origin.z as f32,
            f.surface.handedness as f32,
            0.0,
        ]);
        profiles.extend(brdf.normalised_cumulative().map(|c| c as f32));
        m.kind |= FINISHED;
        m.ior = f32::from_bits(offset);
    }
    Ok(out)
}

impl GpuTracer {
    pub fn new(
        ctx: GpuContext,
        scene: &PreparedScene,
        settings: TraceSettings,
    ) -> Result<GpuTracer, GpuError> {
        // The kernel binds nine storage buffers (shaders/tracer.wgsl).
        ctx.require_storage_buffers(9, "photon tracer")?;
        let device = &ctx.device;
        let source = lucerna_gpu::shaders::tracer();
        let module = lucerna_gpu::create_shader_module(
            device,
            wgpu::ShaderModuleDescriptor {
                label: Some("tracer.wgsl"),
                source: wgpu::ShaderSource::Wgsl(source.into()),
            },
        )?;
        let pipeline = lucerna_gpu::create_compute_pipeline(
            device,
            &wgpu::ComputePipelineDescriptor {
                label: Some("photon tracing"),
                layout: None,
                module: &module,
                entry_point: Some("trace"),
                compilation_options: Default::default(),
                cache: None,
            },
        )?;
        let storage = |label: &str, bytes: &[u8]| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents: bytes,
                usage: wgpu::BufferUsages::STORAGE,
            })
        };
        let bvh = &scene.bvh;
        let bvh2 = bvh.bvh2();
        let nodes = storage("bvh nodes", bytemuck::cast_slice(&bvh2.nodes));
        let leaves = storage(
            "bvh leaf triangles",
            bytemuck::cast_slice(&bvh2.leaf_triangles),
        );
        let triangles = storage("triangles", bytemuck::cast_slice(&bvh.triangles));
        let shading = storage("shading", bytemuck::cast_slice(&scene.shading));
        let (emitters, mut profiles) = gpu_emitters(scene);
        let materials = gpu_materials(scene, &mut profiles)?;
        let materials = storage("materials", bytemuck::cast_slice(&materials));
        let emitters_buffer = storage("emitters", bytemuck::cast_slice(&emitters));
        let profiles = storage("profiles", bytemuck::cast_slice(&profiles));
        let texels = settings.layout.texel_count() as u64;
        let params = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("params"),
            size: std::mem::size_of::<Params>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let counter = |label: &str, size: u64| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage: wgpu::BufferUsages::STORAGE
                    | wgpu::BufferUsages::COPY_SRC
                    | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        };
        let readback = |label: &str, size: u64| lucerna_gpu::readback_buffer(device, label, size);
        let counts = counter("counts", 4 * texels);
        let tallies = counter("tallies", 16);
        let counts_readback = readback("counts readback", 4 * texels);
        let tallies_readback = readback("tallies readback", 16);
        let entries: Vec<wgpu::BindGroupEntry> = [
            &params,
            &nodes,
            &leaves,
            &triangles,
            &shading,
            &materials,
            &emitters_buffer,
            &profiles,
            &counts,
            &tallies,
        ]
        .iter()
        .enumerate()
        .map(|(i, b)| wgpu::BindGroupEntry {
            binding: i as u32,
            resource: b.as_entire_binding(),
        })
        .collect();
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("tracer bindings"),
            layout: &pipeline.get_bind_group_layout(0),
            entries: &entries,
        });
        Ok(GpuTracer {
            emitter_count: emitters.len() as u32,
            epsilon: scene.epsilon,
            bvh_scale: scene.bvh.scale,
            ctx,
            pipeline,
            bind_group,
            params,
            counts,
            tallies,
            counts_readback,
            tallies_readback,
            settings,
        })
    }

    pub fn context(&self) -> &GpuContext {
        &self.ctx
    }

    /// Traces photons `first .. first + count` of `iteration`; the same
    /// photon indices as [`crate::cpu::trace_batch`].
    pub fn trace_batch(&self, iteration: u32, first: u32, count: u32) -> Result<Tally, GpuError> {
        let groups = count.div_ceil(WORKGROUP).max(1);
        let groups_x = groups.min(MAX_GROUPS_PER_ROW);
        let groups_y = groups.div_ceil(groups_x);
        let params = Params {
            photon_offset: first,
            photon_count: count,
            seed: self.settings.seed,
            iteration,
            max_bounces: self.settings.max_bounces,
            resolution: self.settings.layout.resolution,
            emitter_count: self.emitter_count,
            threads_per_row: groups_x * WORKGROUP,
            epsilon: self.epsilon,
            bvh_scale: self.bvh_scale,
            pad0: 0,
            pad1: 0,
        };
        let queue = &self.ctx.queue;
        queue.write_buffer(&self.params, 0, bytemuck::bytes_of(&params));
        let mut encoder = self
            .ctx
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("trace"),
            });
        encoder.clear_buffer(&self.counts, 0, None);
        encoder.clear_buffer(&self.tallies, 0, None);
        {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("trace"),
                timestamp_writes: None,
            });
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(0, &self.bind_group, &[]);
            pass.dispatch_workgroups(groups_x, groups_y, 1);
        }
        encoder.copy_buffer_to_buffer(&self.counts, 0, &self.counts_readback, 0, None);
        encoder.copy_buffer_to_buffer(&self.tallies, 0, &self.tallies_readback, 0, None);
        queue.submit([encoder.finish()]);
        let counts: Vec<u32> =
            bytemuck::cast_slice(&lucerna_gpu::read_buffer(&self.ctx, &self.counts_readback)?)
                .to_vec();
        let tallies: Vec<u32> = bytemuck::cast_slice(&lucerna_gpu::read_buffer(
            &self.ctx,
            &self.tallies_readback,
        )?)
        .to_vec();
        Ok(Tally {
            counts,
            emitted: u64::from(count),
            absorbed: u64::from(tallies[0]),
            cut_off: u64::from(tallies[1]),
            bounces: u64::from(tallies[2]),
            rays: u64::from(tallies[3]),
        })
    }
}
