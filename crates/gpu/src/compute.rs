//! What every compute kernel of the workspace sets up the same way: its
//! shader module, one explicit bind-group layout of buffers shared by its
//! entry points (derived layouts of different pipelines are not
//! interchangeable), their pipelines, and read-back buffers.

use crate::{GpuError, create_compute_pipeline, create_shader_module};

/// A buffer binding of group 0: `binding` is its index in the list.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Binding {
    Uniform,
    Storage { read_only: bool },
}

impl Binding {
    pub const READ: Binding = Binding::Storage { read_only: true };
    pub const READ_WRITE: Binding = Binding::Storage { read_only: false };
}

/// A WGSL compute shader with its one bind-group layout, ready to make
/// the pipelines of its entry points.
#[derive(Debug)]
pub struct ComputeProgram {
    pub module: wgpu::ShaderModule,
    pub bind_layout: wgpu::BindGroupLayout,
    pipeline_layout: wgpu::PipelineLayout,
    label: &'static str,
}

impl ComputeProgram {
    /// Compiles `source` (named `label` in errors) with group 0 holding
    /// `bindings` at 0, 1, 2, …, each seen by the compute stage.
    pub fn new(
        device: &wgpu::Device,
        label: &'static str,
        source: String,
        bindings: &[Binding],
    ) -> Result<ComputeProgram, GpuError> {
        let module = create_shader_module(
            device,
            wgpu::ShaderModuleDescriptor {
                label: Some(label),
                source: wgpu::ShaderSource::Wgsl(source.into()),
            },
        )?;
        let entries: Vec<wgpu::BindGroupLayoutEntry> = bindings
            .iter()
            .zip(0u32..)
            .map(|(b, binding)| wgpu::BindGroupLayoutEntry {
                binding,
                visibility: wgpu::ShaderStages::COMPUTE,
                ty: wgpu::BindingType::Buffer {
                    ty: match *b {
                        Binding::Uniform => wgpu::BufferBindingType::Uniform,
                        Binding::Storage { read_only } => {
                            wgpu::BufferBindingType::Storage { read_only }
                        }
                    },
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            })
            .collect();
        let bind_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some(label),
            entries: &entries,
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some(label),
            bind_group_layouts: &[Some(&bind_layout)],
            immediate_size: 0,
        });
        Ok(ComputeProgram {
            module,
            bind_layout,
            pipeline_layout,
            label,
        })
    }

    /// The pipeline of entry point `entry`, on the shared layout.
    pub fn pipeline(
        &self,
        device: &wgpu::Device,
        entry: &str,
    ) -> Result<wgpu::ComputePipeline, GpuError> {
        let label = format!("{} {entry}", self.label);
        Ok(create_compute_pipeline(
            device,
            &wgpu::ComputePipelineDescriptor {
                label: Some(&label),
                layout: Some(&self.pipeline_layout),
                module: &self.module,
                entry_point: Some(entry),
                compilation_options: Default::default(),
                cache: None,
            },
        )?)
    }
}

/// A buffer of `size` bytes the GPU copies results into and the CPU maps
/// to read them ([`crate::read_buffer`]).
pub fn readback_buffer(device: &wgpu::Device, label: &str, size: u64) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}
