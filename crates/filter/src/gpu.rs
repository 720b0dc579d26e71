//! Driver of the filter's WGSL kernels (`shaders/filter.wgsl`): the pull
//! and push passes run on the GPU, level by level in one submission; the
//! flux renormalisation (a sum over the replaced texels) runs on the CPU
//! after read-back, exactly as in the CPU reference.

use bytemuck::{Pod, Zeroable};
use lucerna_gpu::{Binding, ComputeProgram, GpuContext, GpuError, readback_buffer};
use lucerna_photometry::{AxialSymmetry, CubeMapLayout, TexelSymmetry};
use wgpu::util::DeviceExt;

use crate::driver::filter_pooled;
use crate::filtered::Filtered;
use crate::pyramid::{pyramid_resolutions, pyramid_solid_angles, renormalise};
use crate::settings::{FilterSettings, POISSON_MIN_KEEP_PHOTONS, Threshold};

/// Per-level parameters (48 bytes), WGSL twin `LevelParams`.
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
struct LevelParams {
    /// Offsets (in texels) and resolutions of this level and the coarser one.
    offset: u32,
    resolution: u32,
    coarse_offset: u32,
    coarse_resolution: u32,
    /// Counts below this may be replaced; the border test's threshold.
    threshold: f32,
    border_threshold: f32,
    /// 1 where the rule is the Poisson test.
    poisson_test: u32,
    /// 1 where Algorithm 2's shadow-border test applies.
    border_test: u32,
    sigma_closeness: f32,
    sigma_range: f32,
    /// The Poisson test's z, and the fewest photons it keeps as structure.
    poisson_z: f32,
    poisson_min_keep: f32,
}
const _: () = assert!(std::mem::size_of::<LevelParams>() == 48);

/// The filter's pipelines and pyramid buffers for one map resolution.
#[derive(Debug)]
pub struct GpuFilter {
    ctx: GpuContext,
    layout: CubeMapLayout,
    resolutions: Vec<u32>,
    offsets: Vec<u32>,
    omega_level0: Vec<f64>,
    pull: wgpu::ComputePipeline,
    top: wgpu::ComputePipeline,
    push: wgpu::ComputePipeline,
    params: Vec<wgpu::Buffer>,
    bind_groups: Vec<wgpu::BindGroup>,
    counts: wgpu::Buffer,
    intensity: wgpu::Buffer,
    replaced: wgpu::Buffer,
    intensity_readback: wgpu::Buffer,
    replaced_readback: wgpu::Buffer,
}

impl GpuFilter {
    pub fn new(ctx: GpuContext, layout: CubeMapLayout) -> Result<GpuFilter, GpuError> {
        // shaders/filter.wgsl binds four storage buffers.
        ctx.require_storage_buffers(4, "filter")?;
        let device = &ctx.device;
        // One explicit layout shared by the three entry points.
        let program = ComputeProgram::new(
            device,
            "filter.wgsl",
            lucerna_gpu::shaders::filter(),
            &[
                Binding::Uniform,
                Binding::READ_WRITE,
                Binding::READ,
                Binding::READ_WRITE,
                Binding::READ_WRITE,
            ],
        )?;
        let pipeline = |entry: &str| program.pipeline(device, entry);
        let resolutions = pyramid_resolutions(layout.resolution);
        let mut offsets = Vec::with_capacity(resolutions.len());
        let mut total = 0u32;
        for &n in &resolutions {
            offsets.push(total);
            total += CubeMapLayout::new(n).texel_count() as u32;
        }
        let omega_levels = pyramid_solid_angles(layout);
        let omega: Vec<f32> = omega_levels.iter().flatten().map(|&w| w as f32).collect();
        let texels0 = layout.texel_count() as u64;
        let storage = |label: &str, size: u64, extra: wgpu::BufferUsages| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage: wgpu::BufferUsages::STORAGE | extra,
                mapped_at_creation: false,
            })
        };
        let counts = storage(
            "pyramid counts",
            4 * u64::from(total),
            wgpu::BufferUsages::COPY_DST,
        );
        let intensity = storage(
            "pyramid intensity",
            4 * u64::from(total),
            wgpu::BufferUsages::COPY_SRC,
        );
        let replaced = storage("replaced", 4 * texels0, wgpu::BufferUsages::COPY_SRC);
        let omega_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("pyramid solid angles"),
            contents: bytemuck::cast_slice(&omega),
            usage: wgpu::BufferUsages::STORAGE,
        });
        let readback = |label: &str, size: u64| readback_buffer(device, label, size);
        let pull = pipeline("pull")?;
        let top = pipeline("top")?;
        let push = pipeline("push")?;
        let params: Vec<wgpu::Buffer> = resolutions
            .iter()
            .map(|_| {
                device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("level params"),
                    size: std::mem::size_of::<LevelParams>() as u64,
                    usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                    mapped_at_creation: false,
                })
            })
            .collect();
        let bind_groups = params
            .iter()
            .map(|p| {
                device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some("filter level"),
                    layout: &program.bind_layout,
                    entries: &[
                        wgpu::BindGroupEntry {
                            binding: 0,
                            resource: p.as_entire_binding(),
                        },
                        wgpu::BindGroupEntry {
                            binding: 1,
                            resource: counts.as_entire_binding(),
                        },
                        wgpu::BindGroupEntry {
                            binding: 2,
                            resource: omega_buffer.as_entire_binding(),
                        },
                        wgpu::BindGroupEntry {
                            binding: 3,
                            resource: intensity.as_entire_binding(),
                        },
                        wgpu::BindGroupEntry {
                            binding: 4,
                            resource: replaced.as_entire_binding(),
                        },
                    ],
                })
            })
            .collect();
        Ok(GpuFilter {
            intensity_readback: readback("intensity readback", 4 * texels0),
            replaced_readback: readback("replaced readback", 4 * texels0),
            omega_level0: omega_levels.into_iter().next().unwrap_or_default(),
            ctx,
            layout,
            resolutions,
            offsets,
            pull,
            top,
            push,
            params,
            bind_groups,
            counts,
            intensity,
            replaced,
        })
    }

    pub fn context(&self) -> &GpuContext {
        &self.ctx
    }

    /// Filters counts (texel order of the layout given to `new`). The
    /// automatic rule is chosen as on the CPU ([`crate::choose_automatic`]), with
    /// its candidates run on the GPU.
    pub fn filter(&self, counts: &[u64], settings: &FilterSettings) -> Result<Filtered, GpuError> {
        self.filter_symmetric(counts, settings, &TexelSymmetry::none(self.layout))
    }

    /// [`crate::filter_symmetric`] on the GPU: the images are pooled on the
    /// CPU (the counts live there), the pyramid is built on the GPU.
    pub fn filter_symmetric(
        &self,
        counts: &[u64],
        settings: &FilterSettings,
        symmetry: &TexelSymmetry,
    ) -> Result<Filtered, GpuError> {
        debug_assert_eq!(symmetry.layout, self.layout);
        filter_pooled(
            &self.omega_level0,
            counts,
            settings,
            symmetry,
            |c, concrete| self.filter_with(c, concrete),
        )
    }

    /// Filters with concrete settings (not `Automatic`).
    fn filter_with(&self, counts: &[u64], settings: &FilterSettings) -> Result<Filtered, GpuError> {
        // `filter` resolves `Automatic` first (`choose_automatic`).
        debug_assert!(settings.threshold != Threshold::Automatic);
        let thresholds = settings.threshold.photon_thresholds();
        let poisson_z = settings.threshold.poisson_z();
        let levels = self.resolutions.len();
        let level0: Vec<f32> = counts.iter().map(|&c| c as f32).collect();
        let queue = &self.ctx.queue;
        queue.write_buffer(&self.counts, 0, bytemuck::cast_slice(&level0));
        for k in 0..levels {
            let coarse = (k + 1).min(levels - 1);
            let p = LevelParams {
                offset: self.offsets[k],
                resolution: self.resolutions[k],
                coarse_offset: self.offsets[coarse],
                coarse_resolution: self.resolutions[coarse],
                threshold: thresholds.stable as f32,
                border_threshold: thresholds.border as f32,
                poisson_test: u32::from(poisson_z.is_some()),
                border_test: u32::from(k >= settings.first_border_level),
                sigma_closeness: settings.sigma_closeness as f32,
                sigma_range: settings.sigma_range as f32,
                poisson_z: poisson_z.unwrap_or(0.0) as f32,
                poisson_min_keep: POISSON_MIN_KEEP_PHOTONS as f32,
            };
            queue.write_buffer(&self.params[k], 0, bytemuck::bytes_of(&p));
        }
        let groups = |n: u32| (CubeMapLayout::new(n).texel_count() as u32).div_ceil(64);
        let mut encoder = self
            .ctx
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("filter"),
            });
        let mut pass_for = |pipeline: &wgpu::ComputePipeline, k: usize, texels_of: u32| {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: None,
                timestamp_writes: None,
            });
            pass.set_pipeline(pipeline);
            pass.set_bind_group(0, &self.bind_groups[k], &[]);
            // At most 65535 groups per dimension: wrap into rows.
            let g = groups(texels_of);
            let x = g.min(65_535);
            pass.dispatch_workgroups(x, g.div_ceil(x), 1);
        };
        for k in 0..levels - 1 {
            pass_for(&self.pull, k, self.resolutions[k + 1]);
        }
        pass_for(&self.top, levels - 1, self.resolutions[levels - 1]);
        for k in (0..levels - 1).rev() {
            pass_for(&self.push, k, self.resolutions[k]);
        }
        let texels0 = 4 * self.layout.texel_count() as u64;
        encoder.copy_buffer_to_buffer(
            &self.intensity,
            0,
            &self.intensity_readback,
            0,
            Some(texels0),
        );
        encoder.copy_buffer_to_buffer(&self.replaced, 0, &self.replaced_readback, 0, Some(texels0));
        queue.submit([encoder.finish()]);
        let intensity: Vec<f32> = bytemuck::cast_slice(&lucerna_gpu::read_buffer(
            &self.ctx,
            &self.intensity_readback,
        )?)
        .to_vec();
        let replaced: Vec<u32> = bytemuck::cast_slice(&lucerna_gpu::read_buffer(
            &self.ctx,
            &self.replaced_readback,
        )?)
        .to_vec();
        let mut intensity: Vec<f64> = intensity.iter().map(|&v| f64::from(v)).collect();
        let mut replaced: Vec<bool> = replaced.iter().map(|&r| r != 0).collect();
        if levels == 1 {
            // A 1×1 map is its own top level: nothing is replaced.
            replaced.iter_mut().for_each(|r| *r = false);
        }
        let counts_f64: Vec<f64> = counts.iter().map(|&c| c as f64).collect();
        let renormalisation =
            renormalise(&counts_f64, &self.omega_level0, &mut intensity, &replaced);
        Ok(Filtered {
            photons_per_sr: intensity,
            replaced,
            threshold: thresholds.stable,
            settings: *settings,
            automatic: None,
            renormalisation,
            symmetry: AxialSymmetry::None,
        })
    }
}
