//! The viewport's wgpu side: an `egui_wgpu` paint callback that draws the
//! luminaire, cube and lines offscreen (MSAA, depth) in `prepare`, only
//! when something changed, and blits the picture into egui's pass in
//! `paint`. Pipelines and buffers live in egui's callback resources.

use std::sync::Arc;

use bytemuck::{Pod, Zeroable};
use eframe::egui_wgpu::{self, CallbackResources, CallbackTrait, ScreenDescriptor};
use eframe::wgpu;
use wgpu::util::DeviceExt;

use super::geometry::{
    ATLAS_COLUMNS, ATLAS_ROWS, CubeVertex, LineVertex, MeshVertex, cube_vertices,
};

/// The format and sample count of egui's pass, which the blit must match,
/// and the multisampling the adapter allows the view's own picture.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct GpuTarget {
    pub format: wgpu::TextureFormat,
    pub samples: u32,
    /// 4 where the adapter multisamples the picture and depth formats
    /// (paths are thin lines), else 1.
    pub picture_samples: u32,
}

impl GpuTarget {
    /// The target of egui's pass in `format` (not multisampled, as
    /// eframe and kittest draw it) on `adapter`.
    pub fn new(adapter: &wgpu::Adapter, format: wgpu::TextureFormat) -> GpuTarget {
        // WebGPU guarantees 4x for both; a GL driver's downlevel limits
        // need not, and a refused sample count would be a panic at draw.
        let four = [PICTURE_FORMAT, DEPTH_FORMAT].iter().all(|&f| {
            adapter
                .get_texture_format_features(f)
                .flags
                .sample_count_supported(4)
        }) && adapter
            .get_texture_format_features(PICTURE_FORMAT)
            .flags
            .contains(wgpu::TextureFormatFeatureFlags::MULTISAMPLE_RESOLVE);
        GpuTarget {
            format,
            samples: 1,
            picture_samples: if four { 4 } else { 1 },
        }
    }
}

const PICTURE_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;
const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// The shader's `Uniforms`.
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable, PartialEq)]
pub struct Uniforms {
    pub view_projection: [[f32; 4]; 4],
    pub eye: [f32; 4],
    /// Centre and half edge of the intensity cube (m).
    pub cube: [f32; 4],
    pub selected_surface: u32,
    pub _pad: [u32; 3],
}

/// The cube's false-colour texels (RGBA8 sRGB, the 3n × 2n atlas).
#[derive(Debug, Clone)]
pub struct CubeTexels {
    pub resolution: u32,
    pub texels: Arc<Vec<u8>>,
}

/// One frame of the viewport, as the UI hands it to the renderer. The
/// `Arc`s say by identity whether their buffers must be uploaded again.
#[derive(Debug, Clone)]
pub struct ViewportFrame {
    pub target: GpuTarget,
    pub size_px: [u32; 2],
    pub uniforms: Uniforms,
    /// Linear clear colour.
    pub background: [f32; 3],
    pub mesh: Arc<Vec<MeshVertex>>,
    /// The photometric solid, drawn like the luminaire's surfaces.
    pub solid: Option<Arc<Vec<MeshVertex>>>,
    pub cube: Option<CubeTexels>,
    pub lines: Arc<Vec<LineVertex>>,
}

/// The paint callback of one viewport frame.
#[derive(Debug)]
pub struct ViewportCallback(pub ViewportFrame);

/// What a rendered picture showed; equal keys need no new render.
#[derive(Debug, Clone, PartialEq)]
struct RenderKey {
    size_px: [u32; 2],
    uniforms: Uniforms,
    background: [f32; 3],
    mesh: usize,
    solid: Option<usize>,
    cube: Option<usize>,
    lines: usize,
}

impl RenderKey {
    fn of(frame: &ViewportFrame) -> RenderKey {
        RenderKey {
            size_px: frame.size_px,
            uniforms: frame.uniforms,
            background: frame.background,
            mesh: Arc::as_ptr(&frame.mesh) as usize,
            solid: frame.solid.as_ref().map(|s| Arc::as_ptr(s) as usize),
            cube: frame.cube.as_ref().map(|c| Arc::as_ptr(&c.texels) as usize),
            lines: Arc::as_ptr(&frame.lines) as usize,
        }
    }
}

struct Targets {
    size: [u32; 2],
    /// Drawn into and resolved to `picture`; none without multisampling,
    /// when the pass draws into `picture` itself.
    multisampled: Option<wgpu::TextureView>,
    depth: wgpu::TextureView,
    picture: wgpu::TextureView,
    blit_group: wgpu::BindGroup,
}

/// A vertex buffer and what it was uploaded from (kept, so its address
/// identifies it).
struct Uploaded<T> {
    source: Arc<Vec<T>>,
    buffer: Option<wgpu::Buffer>,
    count: u32,
}

struct Resources {
    target: GpuTarget,
    mesh_pipeline: wgpu::RenderPipeline,
    /// The selected surface again over everything, faint: a reflector
    /// inside a housing stays visible when selected.
    xray_pipeline: wgpu::RenderPipeline,
    cube_pipeline: wgpu::RenderPipeline,
    line_pipeline: wgpu::RenderPipeline,
    blit_pipeline: wgpu::RenderPipeline,
    uniform_buffer: wgpu::Buffer,
    uniform_group: wgpu::BindGroup,
    cube_layout: wgpu::BindGroupLayout,
    blit_layout: wgpu::BindGroupLayout,
    nearest: wgpu::Sampler,
    linear: wgpu::Sampler,
    cube_vertices: wgpu::Buffer,
    cube: Option<(Arc<Vec<u8>>, wgpu::BindGroup)>,
    mesh: Option<Uploaded<MeshVertex>>,
    solid: Option<Uploaded<MeshVertex>>,
    lines: Option<Uploaded<LineVertex>>,
    targets: Option<Targets>,
    rendered: Option<RenderKey>,
}

impl CallbackTrait for ViewportCallback {
    fn prepare(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        _screen: &ScreenDescriptor,
        encoder: &mut wgpu::CommandEncoder,
        resources: &mut CallbackResources,
    ) -> Vec<wgpu::CommandBuffer> {
        let frame = &self.0;
        if resources
            .get::<Resources>()
            .is_none_or(|r| r.target != frame.target)
        {
            resources.insert(Resources::new(device, frame.target));
        }
        if let Some(r) = resources.get_mut::<Resources>() {
            r.render(device, queue, encoder, frame);
        }
        Vec::new()
    }

    fn paint(
        &self,
        _info: egui::PaintCallbackInfo,
        pass: &mut wgpu::RenderPass<'static>,
        resources: &CallbackResources,
    ) {
        let Some(r) = resources.get::<Resources>() else {
            return;
        };
        let Some(targets) = &r.targets else { return };
        pass.set_pipeline(&r.blit_pipeline);
        pass.set_bind_group(0, &targets.blit_group, &[]);
        pass.draw(0..3, 0..1);
    }
}

/// The callback as egui's paint primitive for `rect`.
pub fn paint_callback(rect: egui::Rect, frame: ViewportFrame) -> egui::PaintCallback {
    egui_wgpu::Callback::new_paint_callback(rect, ViewportCallback(frame))
}

fn upload<T: Pod>(
    device: &wgpu::Device,
    slot: &mut Option<Uploaded<T>>,
    source: &Arc<Vec<T>>,
    label: &str,
) {
    if slot
        .as_ref()
        .is_some_and(|u| Arc::ptr_eq(&u.source, source))
    {
        return;
    }
    let buffer = (!source.is_empty()).then(|| {
        device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(label),
            contents: bytemuck::cast_slice(source),
            usage: wgpu::BufferUsages::VERTEX,
        })
    });
    *slot = Some(Uploaded {
        source: source.clone(),
        buffer,
        count: source.len() as u32,
    });
}

fn draw<T>(pass: &mut wgpu::RenderPass<'_>, uploaded: Option<&Uploaded<T>>) {
    if let Some(Uploaded {
        buffer: Some(buffer),
        count,
        ..
    }) = uploaded
    {
        pass.set_vertex_buffer(0, buffer.slice(..));
        pass.draw(0..*count, 0..1);
    }
}

impl Resources {
    fn new(device: &wgpu::Device, target: GpuTarget) -> Resources {
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("viewport"),
            source: wgpu::ShaderSource::Wgsl(include_str!("viewport.wgsl").into()),
        });
        let blit_module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("viewport blit"),
            source: wgpu::ShaderSource::Wgsl(include_str!("blit.wgsl").into()),
        });
        let uniform_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("viewport uniforms"),
            entries: &[wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::VERTEX | wgpu::ShaderStages::FRAGMENT,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            }],
        });
        let texture_layout = |label: &str, dimension: wgpu::TextureViewDimension| {
            device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some(label),
                entries: &[
                    wgpu::BindGroupLayoutEntry {
                        binding: 0,
                        visibility: wgpu::ShaderStages::FRAGMENT,
                        ty: wgpu::BindingType::Texture {
                            multisampled: false,
                            sample_type: wgpu::TextureSampleType::Float { filterable: true },
                            view_dimension: dimension,
                        },
                        count: None,
                    },
                    wgpu::BindGroupLayoutEntry {
                        binding: 1,
                        visibility: wgpu::ShaderStages::FRAGMENT,
                        ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
                        count: None,
                    },
                ],
            })
        };
        let cube_layout = texture_layout("viewport cube", wgpu::TextureViewDimension::D2);
        let blit_layout = texture_layout("viewport picture", wgpu::TextureViewDimension::D2);
        let layout = |label: &str, groups: &[Option<&wgpu::BindGroupLayout>]| {
            device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some(label),
                bind_group_layouts: groups,
                immediate_size: 0,
            })
        };
        let scene_layout = layout("viewport scene", &[Some(&uniform_layout)]);
        let cube_pipeline_layout = layout(
            "viewport cube",
            &[Some(&uniform_layout), Some(&cube_layout)],
        );
        let blit_pipeline_layout = layout("viewport blit", &[Some(&blit_layout)]);
        // An overlay is drawn over everything, blended, writing no depth
        // (the selection seen through the parts in front of it).
        let depth = |write: bool, overlay: bool| {
            Some(wgpu::DepthStencilState {
                format: DEPTH_FORMAT,
                depth_write_enabled: Some(write && !overlay),
                depth_compare: Some(if overlay {
                    wgpu::CompareFunction::Always
                } else {
                    wgpu::CompareFunction::LessEqual
                }),
                stencil: wgpu::StencilState::default(),
                bias: wgpu::DepthBiasState::default(),
            })
        };
        let scene_pipeline_with = |label: &str,
                                   pipeline_layout: &wgpu::PipelineLayout,
                                   vs: &str,
                                   fs: &str,
                                   buffer: wgpu::VertexBufferLayout<'_>,
                                   topology: wgpu::PrimitiveTopology,
                                   overlay: bool| {
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(label),
                layout: Some(pipeline_layout),
                vertex: wgpu::VertexState {
                    module: &module,
                    entry_point: Some(vs),
                    compilation_options: wgpu::PipelineCompilationOptions::default(),
                    buffers: &[Some(buffer)],
                },
                primitive: wgpu::PrimitiveState {
                    topology,
                    cull_mode: None,
                    ..wgpu::PrimitiveState::default()
                },
                depth_stencil: depth(true, overlay),
                multisample: wgpu::MultisampleState {
                    count: target.picture_samples,
                    mask: !0,
                    alpha_to_coverage_enabled: false,
                },
                fragment: Some(wgpu::FragmentState {
                    module: &module,
                    entry_point: Some(fs),
                    compilation_options: wgpu::PipelineCompilationOptions::default(),
                    targets: &[Some(wgpu::ColorTargetState {
                        format: PICTURE_FORMAT,
                        blend: overlay.then_some(wgpu::BlendState::ALPHA_BLENDING),
                        write_mask: wgpu::ColorWrites::ALL,
                    })],
                }),
                multiview_mask: None,
                cache: None,
            })
        };
        let scene_pipeline = |label: &str,
                              pipeline_layout: &wgpu::PipelineLayout,
                              vs: &str,
                              fs: &str,
                              buffer: wgpu::VertexBufferLayout<'_>,
                              topology: wgpu::PrimitiveTopology| {
            scene_pipeline_with(label, pipeline_layout, vs, fs, buffer, topology, false)
        };
        let mesh_attributes = wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Float32x4, 3 => Uint32, 4 => Uint32];
        let cube_attributes =
            wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Float32x2, 3 => Uint32];
        let line_attributes = wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x4];
        let buffer_layout = |stride: usize, attributes| wgpu::VertexBufferLayout {
            array_stride: stride as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes,
        };
        let mesh_pipeline = scene_pipeline(
            "viewport mesh",
            &scene_layout,
            "vs_mesh",
            "fs_mesh",
            buffer_layout(size_of::<MeshVertex>(), &mesh_attributes),
            wgpu::PrimitiveTopology::TriangleList,
        );
        let xray_pipeline = scene_pipeline_with(
            "viewport x-ray",
            &scene_layout,
            "vs_mesh",
            "fs_xray",
            buffer_layout(size_of::<MeshVertex>(), &mesh_attributes),
            wgpu::PrimitiveTopology::TriangleList,
            true,
        );
        let cube_pipeline = scene_pipeline(
            "viewport cube",
            &cube_pipeline_layout,
            "vs_cube",
            "fs_cube",
            buffer_layout(size_of::<CubeVertex>(), &cube_attributes),
            wgpu::PrimitiveTopology::TriangleList,
        );
        let line_pipeline = scene_pipeline(
            "viewport lines",
            &scene_layout,
            "vs_line",
            "fs_line",
            buffer_layout(size_of::<LineVertex>(), &line_attributes),
            wgpu::PrimitiveTopology::LineList,
        );
        let blit_pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("viewport blit"),
            layout: Some(&blit_pipeline_layout),
            vertex: wgpu::VertexState {
                module: &blit_module,
                entry_point: Some("vs_blit"),
                compilation_options: wgpu::PipelineCompilationOptions::default(),
                buffers: &[],
            },
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: None,
            multisample: wgpu::MultisampleState {
                count: target.samples.max(1),
                mask: !0,
                alpha_to_coverage_enabled: false,
            },
            fragment: Some(wgpu::FragmentState {
                module: &blit_module,
                entry_point: Some(if target.format.is_srgb() {
                    "fs_blit_linear"
                } else {
                    "fs_blit_gamma"
                }),
                compilation_options: wgpu::PipelineCompilationOptions::default(),
                targets: &[Some(wgpu::ColorTargetState {
                    format: target.format,
                    blend: None,
                    write_mask: wgpu::ColorWrites::ALL,
                })],
            }),
            multiview_mask: None,
            cache: None,
        });
        let uniform_buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("viewport uniforms"),
            size: size_of::<Uniforms>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let uniform_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("viewport uniforms"),
            layout: &uniform_layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: uniform_buffer.as_entire_binding(),
            }],
        });
        let sampler = |label: &str, filter: wgpu::FilterMode| {
            device.create_sampler(&wgpu::SamplerDescriptor {
                label: Some(label),
                mag_filter: filter,
                min_filter: filter,
                ..wgpu::SamplerDescriptor::default()
            })
        };
        let cube_vertices = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("viewport cube"),
            contents: bytemuck::cast_slice(&cube_vertices()),
            usage: wgpu::BufferUsages::VERTEX,
        });
        Resources {
            target,
            mesh_pipeline,
            xray_pipeline,
            cube_pipeline,
            line_pipeline,
            blit_pipeline,
            uniform_buffer,
            uniform_group,
            cube_layout,
            blit_layout,
            // Texels stay visible on the cube, as in the cube-map view.
            nearest: sampler("viewport nearest", wgpu::FilterMode::Nearest),
            linear: sampler("viewport linear", wgpu::FilterMode::Linear),
            cube_vertices,
            cube: None,
            mesh: None,
            solid: None,
            lines: None,
            targets: None,
            rendered: None,
        }
    }

    /// Offscreen targets of `size` (clamped to what the device allows; the
    /// blit scales a clamped picture up).
    fn ensure_targets(&mut self, device: &wgpu::Device, size: [u32; 2]) {
        let max = device.limits().max_texture_dimension_2d;
        let size = size.map(|s| s.clamp(1, max));
        if self.targets.as_ref().is_some_and(|t| t.size == size) {
            return;
        }
        let texture = |label: &str, format, samples, usage| {
            device
                .create_texture(&wgpu::TextureDescriptor {
                    label: Some(label),
                    size: wgpu::Extent3d {
                        width: size[0],
                        height: size[1],
                        depth_or_array_layers: 1,
                    },
                    mip_level_count: 1,
                    sample_count: samples,
                    dimension: wgpu::TextureDimension::D2,
                    format,
                    usage,
                    view_formats: &[],
                })
                .create_view(&wgpu::TextureViewDescriptor::default())
        };
        let multisampled = (self.target.picture_samples > 1).then(|| {
            texture(
                "viewport msaa",
                PICTURE_FORMAT,
                self.target.picture_samples,
                wgpu::TextureUsages::RENDER_ATTACHMENT,
            )
        });
        let depth = texture(
            "viewport depth",
            DEPTH_FORMAT,
            self.target.picture_samples,
            wgpu::TextureUsages::RENDER_ATTACHMENT,
        );
        let picture = texture(
            "viewport picture",
            PICTURE_FORMAT,
            1,
            wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
        );
        let blit_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("viewport picture"),
            layout: &self.blit_layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: wgpu::BindingResource::TextureView(&picture),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: wgpu::BindingResource::Sampler(&self.linear),
                },
            ],
        });
        self.targets = Some(Targets {
            size,
            multisampled,
            depth,
            picture,
            blit_group,
        });
        self.rendered = None;
    }

    fn upload_cube(&mut self, device: &wgpu::Device, queue: &wgpu::Queue, cube: &CubeTexels) {
        if self
            .cube
            .as_ref()
            .is_some_and(|(source, _)| Arc::ptr_eq(source, &cube.texels))
        {
            return;
        }
        let n = cube.resolution.max(1);
        let (width, height) = (ATLAS_COLUMNS as u32 * n, ATLAS_ROWS as u32 * n);
        if cube.texels.len() != 4 * (width * height) as usize
            || width.max(height) > device.limits().max_texture_dimension_2d
        {
            self.cube = None;
            return;
        }
        let size = wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        };
        let texture = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("viewport cube"),
            size,
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: PICTURE_FORMAT,
            usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
            view_formats: &[],
        });
        queue.write_texture(
            wgpu::TexelCopyTextureInfo {
                texture: &texture,
                mip_level: 0,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            },
            &cube.texels,
            wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(4 * width),
                rows_per_image: Some(height),
            },
            size,
        );
        let view = texture.create_view(&wgpu::TextureViewDescriptor::default());
        let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("viewport cube"),
            layout: &self.cube_layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: wgpu::BindingResource::TextureView(&view),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: wgpu::BindingResource::Sampler(&self.nearest),
                },
            ],
        });
        self.cube = Some((cube.texels.clone(), group));
    }

    fn render(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        frame: &ViewportFrame,
    ) {
        self.ensure_targets(device, frame.size_px);
        let key = RenderKey::of(frame);
        if self.rendered.as_ref() == Some(&key) {
            return;
        }
        upload(device, &mut self.mesh, &frame.mesh, "viewport mesh");
        upload(device, &mut self.lines, &frame.lines, "viewport lines");
        match &frame.solid {
            Some(solid) => upload(device, &mut self.solid, solid, "photometric solid"),
            None => self.solid = None,
        }
        match &frame.cube {
            Some(cube) => self.upload_cube(device, queue, cube),
            None => self.cube = None,
        }
        queue.write_buffer(&self.uniform_buffer, 0, bytemuck::bytes_of(&frame.uniforms));
        let Some(targets) = &self.targets else { return };
        let [r, g, b] = frame.background.map(f64::from);
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("viewport"),
            color_attachments: &[Some(match &targets.multisampled {
                Some(multisampled) => wgpu::RenderPassColorAttachment {
                    view: multisampled,
                    depth_slice: None,
                    resolve_target: Some(&targets.picture),
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color { r, g, b, a: 1.0 }),
                        store: wgpu::StoreOp::Discard,
                    },
                },
                None => wgpu::RenderPassColorAttachment {
                    view: &targets.picture,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color { r, g, b, a: 1.0 }),
                        store: wgpu::StoreOp::Store,
                    },
                },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &targets.depth,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(1.0),
                    store: wgpu::StoreOp::Discard,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_bind_group(0, &self.uniform_group, &[]);
        pass.set_pipeline(&self.mesh_pipeline);
        draw(&mut pass, self.mesh.as_ref());
        draw(&mut pass, self.solid.as_ref());
        pass.set_pipeline(&self.line_pipeline);
        draw(&mut pass, self.lines.as_ref());
        if let Some((_, group)) = &self.cube {
            pass.set_pipeline(&self.cube_pipeline);
            pass.set_bind_group(1, group, &[]);
            pass.set_vertex_buffer(0, self.cube_vertices.slice(..));
            pass.draw(0..36, 0..1);
        }
        if frame.uniforms.selected_surface != u32::MAX {
            pass.set_pipeline(&self.xray_pipeline);
            draw(&mut pass, self.mesh.as_ref());
        }
        drop(pass);
        self.rendered = Some(key);
    }
}

#[cfg(test)]
mod tests {
    /// The shaders parse and validate (naga, as wgpu does at run time) and
    /// declare the entry points the pipelines name.
    #[test]
    fn the_viewport_shaders_validate() {
        for (name, source, entries) in [
            (
                "viewport.wgsl",
                include_str!("viewport.wgsl"),
                &[
                    "vs_mesh", "fs_mesh", "vs_cube", "fs_cube", "vs_line", "fs_line",
                ][..],
            ),
            (
                "blit.wgsl",
                include_str!("blit.wgsl"),
                &["vs_blit", "fs_blit_gamma", "fs_blit_linear"][..],
            ),
        ] {
            let module = naga::front::wgsl::parse_str(source)
                .unwrap_or_else(|e| panic!("{name}: {}", e.emit_to_string(source)));
            naga::valid::Validator::new(
                naga::valid::ValidationFlags::all(),
                naga::valid::Capabilities::empty(),
            )
            .validate(&module)
            .unwrap_or_else(|e| panic!("{name}: {e:?}"));
            for entry in entries {
                assert!(
                    module.entry_points.iter().any(|e| e.name == *entry),
                    "{name} lacks {entry}"
                );
            }
        }
    }
}
