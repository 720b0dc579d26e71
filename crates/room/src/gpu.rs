//! Driver of `shaders/room.wgsl`: uploads the room (lights, prefiltered
//! profiles, the LTC table) and runs the per-pixel renderer or the
//! per-point illuminance kernel.

use std::sync::Arc;
use std::time::{Duration, Instant};

use bytemuck::{Pod, Zeroable};
use glam::DVec3;
use lucerna_gpu::{Binding, ComputeProgram, GpuContext, GpuError, readback_buffer};
use wgpu::util::DeviceExt;

use crate::light::PlacedLight;
use crate::ltc::ggx_table;
use crate::profile::ProfileGrid;
use crate::render::{Frame, Shading, ViewRays};
use crate::scene::RoomScene;
use crate::work_plane::{WorkPlaneGrid, grid_points};

/// WGSL twin `Params` (128 bytes).
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
struct Params {
    origin: [f32; 4],
    forward: [f32; 4],
    right: [f32; 4],
    up: [f32; 4],
    room: [f32; 4],
    width: u32,
    height: u32,
    light_count: u32,
    mode: u32,
    tan_half_fov: f32,
    aspect: f32,
    point_count: u32,
    triangle_count: u32,
    indirect_lux: f32,
    pad: [u32; 3],
}
const _: () = assert!(std::mem::size_of::<Params>() == 128);

/// WGSL twin `Light` (288 bytes).
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
struct GpuLight {
    col0: [f32; 4],
    col1: [f32; 4],
    col2: [f32; 4],
    position: [f32; 4],
    info: [u32; 4],
    steps: [f32; 4],
    vertices: [[f32; 4]; 12],
}
const _: () = assert!(std::mem::size_of::<GpuLight>() == 288);

fn v4(v: DVec3, w: f32) -> [f32; 4] {
    [v.x as f32, v.y as f32, v.z as f32, w]
}

/// The room's lights and profiles on the device.
#[derive(Debug)]
pub struct UploadedRoom {
    lights: wgpu::Buffer,
    profiles: wgpu::Buffer,
    surfaces: wgpu::Buffer,
    triangles: wgpu::Buffer,
    scene_params: Params,
}

/// The compiled kernels and the LTC table.
#[derive(Debug)]
pub struct GpuRoomRenderer {
    ctx: GpuContext,
    layout: wgpu::BindGroupLayout,
    render: wgpu::ComputePipeline,
    points: wgpu::ComputePipeline,
    ltc: wgpu::Buffer,
}

impl GpuRoomRenderer {
    pub fn new(ctx: GpuContext) -> Result<GpuRoomRenderer, GpuError> {
        // shaders/room.wgsl binds seven storage buffers.
        ctx.require_storage_buffers(7, "room renderer")?;
        let device = &ctx.device;
        // One explicit layout for both entry points.
        let program = ComputeProgram::new(
            device,
            "room.wgsl",
            lucerna_gpu::shaders::room(),
            &[
                Binding::Uniform,
                Binding::READ,
                Binding::READ,
                Binding::READ,
                Binding::READ_WRITE,
                Binding::READ,
                Binding::READ,
                Binding::READ,
            ],
        )?;
        let pipeline = |name: &str| program.pipeline(device, name);
        let render = pipeline("render")?;
        let points = pipeline("shade_points")?;
        let table: Vec<f32> = ggx_table().entries.iter().flatten().copied().collect();
        let ltc = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("ltc"),
            contents: bytemuck::cast_slice(&table),
            usage: wgpu::BufferUsages::STORAGE,
        });
        Ok(GpuRoomRenderer {
            ctx,
            layout: program.bind_layout,
            render,
            points,
            ltc,
        })
    }

    pub fn context(&self) -> &GpuContext {
        &self.ctx
    }

    /// Fails unless a buffer of `bytes` fits the adapter's limits.
    fn check_size(&self, what: &str, bytes: u64) -> Result<(), GpuError> {
        let limits = &self.ctx.limits;
        let max = limits
            .max_storage_buffer_binding_size
            .min(limits.max_buffer_size);
        if bytes > max {
            return Err(GpuError::Failed(format!(
                "{what}: {:.1} MB of GPU storage needed, this adapter allows {:.1} MB per buffer (render on the CPU instead)",
                bytes as f64 / 1e6,
                max as f64 / 1e6
            )));
        }
        Ok(())
    }

    /// Uploads lights and their profiles (each distinct profile once).
    pub fn upload(&self, scene: &RoomScene) -> Result<UploadedRoom, GpuError> {
        let mut data: Vec<f32> = Vec::new();
        let mut seen: Vec<(*const ProfileGrid, u32)> = Vec::new();
        let mut lights = Vec::with_capacity(scene.lights.len());
        for light in &scene.lights {
            let key = Arc::as_ptr(&light.profile);
            let offset = match seen.iter().find(|(k, _)| *k == key) {
                Some(&(_, o)) => o,
                None => {
                    let o = data.len() as u32;
                    // The shader's grids: candela, then the radial
                    // tables of the polar rule.
                    let profile = &light.profile;
                    data.extend_from_slice(&profile.candela);
                    data.extend(profile.radial.sec.iter().map(|&v| v as f32));
                    data.extend(profile.radial.sin.iter().map(|&v| v as f32));
                    seen.push((key, o));
                    o
                }
            };
            lights.push(gpu_light(light, offset));
        }
        if lights.is_empty() {
            lights.push(GpuLight::zeroed());
        }
        if data.is_empty() {
            data.push(0.0);
        }
        self.check_size("the room's profiles", 4 * data.len() as u64)?;
        self.check_size(
            "the room's lights",
            std::mem::size_of_val(lights.as_slice()) as u64,
        )?;
        let device = &self.ctx.device;
        let lights_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("room lights"),
            contents: bytemuck::cast_slice(&lights),
            usage: wgpu::BufferUsages::STORAGE,
        });
        let profiles = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("room profiles"),
            contents: bytemuck::cast_slice(&data),
            usage: wgpu::BufferUsages::STORAGE,
        });
        let surface_data: Vec<[f32; 4]> = scene
            .surfaces
            .iter()
            .map(|s| {
                [
                    s.reflectance as f32,
                    s.specular as f32,
                    s.roughness as f32,
                    0.0,
                ]
            })
            .collect();
        let surfaces = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("room surfaces"),
            contents: bytemuck::cast_slice(&surface_data),
            usage: wgpu::BufferUsages::STORAGE,
        });
        let mut triangle_data: Vec<[f32; 4]> = Vec::new();
        if let Some(mesh) = &scene.mesh {
            for (t, &surface) in mesh.triangles.iter().zip(&mesh.surface) {
                triangle_data.push(v4(t[0], surface as f32));
                triangle_data.push(v4(t[1], 0.0));
                triangle_data.push(v4(t[2], 0.0));
            }
        }
        self.check_size("the room's triangles", 16 * triangle_data.len() as u64)?;
        let triangle_count = (triangle_data.len() / 3) as u32;
        if triangle_data.is_empty() {
            triangle_data.push([0.0; 4]);
        }
        let triangles = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("room triangles"),
            contents: bytemuck::cast_slice(&triangle_data),
            usage: wgpu::BufferUsages::STORAGE,
        });
        let scene_params = Params {
            origin: [0.0; 4],
            forward: [0.0; 4],
            right: [0.0; 4],
            up: [0.0; 4],
            room: v4(scene.size, 0.0),
            width: 0,
            height: 0,
            light_count: scene.lights.len() as u32,
            mode: 0,
            tan_half_fov: 0.0,
            aspect: 1.0,
            point_count: 0,
            triangle_count,
            indirect_lux: scene.indirect_lux() as f32,
            pad: [0; 3],
        };
        Ok(UploadedRoom {
            lights: lights_buffer,
            profiles,
            surfaces,
            triangles,
            scene_params,
        })
    }

    fn run(
        &self,
        room: &UploadedRoom,
        params: Params,
        points: &[[f32; 4]],
        outputs: u32,
        render: bool,
    ) -> Result<(Vec<[f32; 4]>, Duration), GpuError> {
        let device = &self.ctx.device;
        let uniform = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("room params"),
            contents: bytemuck::bytes_of(&params),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let dummy = [[0.0f32; 4]; 2];
        let points_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("room points"),
            contents: bytemuck::cast_slice(if points.is_empty() { &dummy } else { points }),
            usage: wgpu::BufferUsages::STORAGE,
        });
        let size = 16 * outputs.max(1) as u64;
        self.check_size("the image", size)?;
        self.check_size("the points", 16 * points.len() as u64)?;
        let output = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("room output"),
            size,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let readback = readback_buffer(device, "room readback", size);
        let bind = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("room"),
            layout: &self.layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: uniform.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: room.lights.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: room.profiles.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 3,
                    resource: self.ltc.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 4,
                    resource: output.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 5,
                    resource: points_buffer.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 6,
                    resource: room.surfaces.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 7,
                    resource: room.triangles.as_entire_binding(),
                },
            ],
        });
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("room"),
        });
        {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: None,
                timestamp_writes: None,
            });
            pass.set_bind_group(0, &bind, &[]);
            if render {
                pass.set_pipeline(&self.render);
                pass.dispatch_workgroups(params.width.div_ceil(8), params.height.div_ceil(8), 1);
            } else {
                pass.set_pipeline(&self.points);
                let groups = outputs.div_ceil(64).max(1);
                let x = groups.min(65_535);
                pass.dispatch_workgroups(x, groups.div_ceil(x), 1);
            }
        }
        let start = Instant::now();
        self.ctx.queue.submit([encoder.finish()]);
        self.ctx
            .device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| GpuError::Failed(e.to_string()))?;
        let elapsed = start.elapsed();
        let mut copy = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("room readback"),
        });
        copy.copy_buffer_to_buffer(&output, 0, &readback, 0, Some(size));
        self.ctx.queue.submit([copy.finish()]);
        let bytes = lucerna_gpu::read_buffer(&self.ctx, &readback)?;
        Ok((bytemuck::cast_slice(&bytes).to_vec(), elapsed))
    }

    /// Renders the camera's view; also returns the kernel's time (submit
    /// to completion, without the read-back).
    pub fn render(
        &self,
        scene: &RoomScene,
        room: &UploadedRoom,
        width: u32,
        height: u32,
        shading: Shading,
    ) -> Result<(Frame, Duration), GpuError> {
        let rays = ViewRays::new(scene, width, height);
        let mut params = room.scene_params;
        params.origin = v4(rays.origin, 0.0);
        params.forward = v4(rays.forward, 0.0);
        params.right = v4(rays.right, 0.0);
        params.up = v4(rays.up, 0.0);
        params.width = width;
        params.height = height;
        params.mode = mode(shading);
        params.tan_half_fov = rays.tan_half_fov as f32;
        params.aspect = rays.aspect as f32;
        let (out, elapsed) = self.run(room, params, &[], width * height, true)?;
        Ok((
            Frame {
                width,
                height,
                luminance: out.iter().map(|p| p[0]).collect(),
                illuminance: out.iter().map(|p| p[1]).collect(),
            },
            elapsed,
        ))
    }

    /// Illuminance (lx) and cosine-weighted solid angle at points with
    /// normals, summed over the room's lights.
    pub fn shade_points(
        &self,
        room: &UploadedRoom,
        points: &[(DVec3, DVec3)],
        shading: Shading,
    ) -> Result<Vec<(f64, f64)>, GpuError> {
        let mut packed = Vec::with_capacity(points.len() * 2);
        for (x, n) in points {
            packed.push(v4(*x, 1.0));
            packed.push(v4(*n, 0.0));
        }
        let mut params = room.scene_params;
        params.mode = mode(shading);
        params.point_count = points.len() as u32;
        let (out, _) = self.run(room, params, &packed, points.len() as u32, false)?;
        Ok(out
            .iter()
            .take(points.len())
            .map(|p| (p[0] as f64, p[1] as f64))
            .collect())
    }
}

impl GpuRoomRenderer {
    /// The work-plane grid shaded on the device.
    pub fn work_plane(
        &self,
        scene: &RoomScene,
        room: &UploadedRoom,
        shading: Shading,
    ) -> Result<WorkPlaneGrid, GpuError> {
        let (xs, ys) = grid_points(scene);
        let h = scene.work_plane.height_m;
        let points: Vec<(DVec3, DVec3)> = ys
            .iter()
            .flat_map(|&y| xs.iter().map(move |&x| (DVec3::new(x, y, h), DVec3::Z)))
            .collect();
        let lux = self
            .shade_points(room, &points, shading)?
            .into_iter()
            .map(|(e, _)| e)
            .collect();
        Ok(WorkPlaneGrid {
            xs,
            ys,
            height_m: h,
            lux,
        })
    }
}

fn mode(shading: Shading) -> u32 {
    match shading {
        Shading::Cubature => 0,
        Shading::PointLight => 1,
        Shading::Draft => 2,
    }
}

fn gpu_light(light: &PlacedLight, profile_offset: u32) -> GpuLight {
    let polygon = light.world_polygon();
    let mut vertices = [[0.0f32; 4]; 12];
    for (slot, v) in vertices.iter_mut().zip(&polygon) {
        *slot = v4(*v, 1.0);
    }
    let r = light.rotation;
    GpuLight {
        col0: v4(r.x_axis, 0.0),
        col1: v4(r.y_axis, 0.0),
        col2: v4(r.z_axis, 0.0),
        position: v4(light.position, light.opening.area_m2() as f32),
        info: [
            polygon.len().min(12) as u32,
            profile_offset,
            light.profile.c_count as u32,
            light.profile.gamma_count as u32,
        ],
        steps: [
            light.profile.c_step_deg as f32,
            light.profile.gamma_step_deg as f32,
            light.size_m() as f32,
            crate::polar::RuleNodes::for_profile(&light.profile).kink_step_rad as f32,
        ],
        vertices,
    }
}
