//! The room lit, start to end, for `lucerna render` and the editor's
//! preview alike: the renderer chosen (a hardware GPU, else the CPU,
//! which outruns a software adapter), the view and the work-plane grid
//! from the same renderer, the uniform indirect estimate added, and the
//! EN 12464-1 figures.

use lucerna_gpu::{BackendRequest, GpuError};

use crate::gpu::GpuRoomRenderer;
use crate::render::{Frame, Shading, render_cpu_rows};
use crate::scene::RoomScene;
use crate::work_plane::{IlluminanceFigures, WorkPlaneGrid, work_plane_cpu};

/// The room as a renderer saw it.
#[derive(Debug, Clone)]
pub struct LitRoom {
    pub frame: Frame,
    /// The work plane, the uniform indirect estimate included.
    pub grid: WorkPlaneGrid,
    pub figures: IlluminanceFigures,
    /// The uniform indirect illuminance added (lx; 0 for direct only).
    pub indirect_lux: f64,
    /// The renderer that made it, in words.
    pub backend: String,
}

/// The renderer a request opened, and why that one.
pub struct RoomRenderer {
    gpu: Option<GpuRoomRenderer>,
    description: String,
}

impl std::fmt::Debug for RoomRenderer {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.description)
    }
}

impl RoomRenderer {
    /// The GPU renderer where `request` asks for one and it opens (for
    /// `Auto`, only a hardware adapter); otherwise the CPU, saying why.
    pub fn open(request: BackendRequest) -> RoomRenderer {
        let cpu = |why: String| RoomRenderer {
            gpu: None,
            description: why,
        };
        if request == BackendRequest::Cpu {
            return cpu("CPU".to_owned());
        }
        let ctx = match lucerna_gpu::open() {
            Ok(ctx) => ctx,
            Err(e) => return cpu(format!("CPU (no GPU: {e})")),
        };
        if request == BackendRequest::Auto && ctx.is_software() {
            return cpu(format!(
                "CPU (the adapter {} is software, slower than the CPU renderer)",
                ctx.describe()
            ));
        }
        let name = ctx.describe();
        match GpuRoomRenderer::new(ctx) {
            Ok(gpu) => RoomRenderer {
                gpu: Some(gpu),
                description: format!("GPU: {name}"),
            },
            Err(e) => cpu(format!("CPU (the GPU renderer failed on {name}: {e})")),
        }
    }

    pub fn description(&self) -> &str {
        &self.description
    }

    /// Whether it renders on a GPU.
    pub fn is_gpu(&self) -> bool {
        self.gpu.is_some()
    }

    /// The view (`size` pixels) and the work plane of `scene`, by the same
    /// renderer, with the indirect estimate and the figures. A GPU failure
    /// falls back to the CPU for good, and the result says so. On the CPU
    /// the view is rendered in bands of rows and given up (`None`) between
    /// two when `give_up` says so.
    pub fn light(
        &mut self,
        scene: &RoomScene,
        size: [u32; 2],
        shading: Shading,
        give_up: &dyn Fn() -> bool,
    ) -> Option<LitRoom> {
        let [w, h] = size;
        let gpu_result = self.gpu.as_ref().map(|gpu| {
            let uploaded = gpu.upload(scene)?;
            let (frame, _) = gpu.render(scene, &uploaded, w, h, shading)?;
            let grid = gpu.work_plane(scene, &uploaded, shading)?;
            Ok::<_, GpuError>((frame, grid))
        });
        let (frame, mut grid) = match gpu_result {
            Some(Ok(done)) => done,
            other => {
                if let Some(Err(e)) = other {
                    self.gpu = None;
                    self.description = format!("CPU (the GPU render failed: {e})");
                }
                let band = (h / 10).max(1);
                let mut frame = Frame {
                    width: w,
                    height: h,
                    luminance: Vec::with_capacity((w * h) as usize),
                    illuminance: Vec::with_capacity((w * h) as usize),
                };
                for top in (0..h).step_by(band as usize) {
                    if give_up() {
                        return None;
                    }
                    let rows = render_cpu_rows(scene, w, h, top..top + band, shading);
                    frame.luminance.extend(rows.luminance);
                    frame.illuminance.extend(rows.illuminance);
                }
                (frame, work_plane_cpu(scene, shading))
            }
        };
        let indirect_lux = scene.indirect_lux();
        for e in &mut grid.lux {
            *e += indirect_lux;
        }
        let figures = grid.figures();
        Some(LitRoom {
            frame,
            grid,
            figures,
            indirect_lux,
            backend: self.description.clone(),
        })
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)] // reason: tests may panic
    use std::sync::Arc;

    use super::*;
    use crate::light::Opening;
    use crate::profile::ProfileGrid;
    use crate::render::render_cpu;
    use crate::setup::RoomSetup;

    #[test]
    fn banded_lighting_is_the_whole_frame_and_adds_the_indirect_light_to_the_grid() {
        let path =
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/rooms/office.toml");
        let office = RoomSetup::load(&path).unwrap();
        // 100 cd in every lower direction: a flux of 200π lm per luminaire.
        let grid = Arc::new(ProfileGrid::from_fn(true, |_, g| {
            if g < 90.0 { 100.0 } else { 0.0 }
        }));
        let scene = office.scene_lit_by(|_| grid.clone(), Opening::Point);
        let mut renderer = RoomRenderer::open(BackendRequest::Cpu);
        assert!(!renderer.is_gpu());
        let lit = renderer
            .light(&scene, [40, 25], Shading::Cubature, &|| false)
            .unwrap();
        let whole = render_cpu(&scene, 40, 25, Shading::Cubature);
        assert_eq!(lit.frame.illuminance, whole.illuminance);
        assert_eq!(lit.frame.luminance, whole.luminance);
        let direct = work_plane_cpu(&scene, Shading::Cubature);
        assert!(lit.indirect_lux > 0.0);
        for (with, without) in lit.grid.lux.iter().zip(&direct.lux) {
            assert_eq!(*with, without + lit.indirect_lux);
        }
        assert_eq!(lit.figures, lit.grid.figures());
        // Given up before the first band: nothing.
        assert!(
            renderer
                .light(&scene, [40, 25], Shading::Cubature, &|| true)
                .is_none()
        );
    }
}
