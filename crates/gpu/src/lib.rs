//! GPU access for Lucerna's kernels: adapter and device selection, the
//! WGSL shaders composed from `shaders/`, shader-module and pipeline
//! creation that returns the device's errors instead of panicking, and the
//! set-up every compute kernel shares (`ComputeProgram`, read-back
//! buffers).

mod checked;
mod compute;
pub mod shaders;

pub use checked::{
    CreatePipelineError, CreateShaderModuleError, create_compute_pipeline, create_shader_module,
};
pub use compute::{Binding, ComputeProgram, readback_buffer};

/// Which processor a job asks for: the one backend request of the
/// workspace, for the photon tracer, the filter and the room renderer.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum BackendRequest {
    /// The native CPU implementation.
    Cpu,
    /// The WGSL implementation on a GPU adapter (a software one included).
    Gpu,
    /// A hardware GPU if there is one; otherwise the CPU for the tracer
    /// (a software adapter runs on the same cores, 5x less efficiently),
    /// and whichever a renderer finds faster.
    #[default]
    Auto,
}

impl std::str::FromStr for BackendRequest {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.to_ascii_lowercase().as_str() {
            "cpu" => Ok(BackendRequest::Cpu),
            "gpu" => Ok(BackendRequest::Gpu),
            "auto" => Ok(BackendRequest::Auto),
            _ => Err(format!("'{s}' is not cpu, gpu or auto")),
        }
    }
}

impl std::fmt::Display for BackendRequest {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            BackendRequest::Cpu => "cpu",
            BackendRequest::Gpu => "gpu",
            BackendRequest::Auto => "auto",
        })
    }
}

/// A device ready for compute, with what it is.
#[derive(Debug, Clone)]
pub struct GpuContext {
    pub device: wgpu::Device,
    pub queue: wgpu::Queue,
    pub info: wgpu::AdapterInfo,
    pub limits: wgpu::Limits,
}

#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum GpuError {
    #[error("no GPU adapter is available ({0})")]
    NoAdapter(String),
    #[error("the adapter '{adapter}' refused a device")]
    Device {
        adapter: String,
        #[source]
        source: wgpu::RequestDeviceError,
    },
    #[error(
        "the adapter '{adapter}' has {got} storage buffers per shader stage; the {kernel} needs {needed}"
    )]
    Limits {
        adapter: String,
        kernel: &'static str,
        got: u32,
        needed: u32,
    },
    #[error(transparent)]
    CreateShaderModule(#[from] CreateShaderModuleError),
    #[error(transparent)]
    CreatePipeline(#[from] CreatePipelineError),
    #[error("GPU work failed: {0}")]
    Failed(String),
}

impl GpuContext {
    /// Whether the adapter runs on the CPU (llvmpipe, lavapipe, WARP).
    pub fn is_software(&self) -> bool {
        self.info.device_type == wgpu::DeviceType::Cpu
    }

    /// Fails unless a kernel's `needed` storage buffers per shader stage
    /// fit the adapter (each driver knows its own kernel's count).
    pub fn require_storage_buffers(
        &self,
        needed: u32,
        kernel: &'static str,
    ) -> Result<(), GpuError> {
        let got = self.limits.max_storage_buffers_per_shader_stage;
        if got < needed {
            return Err(GpuError::Limits {
                adapter: self.info.name.clone(),
                kernel,
                got,
                needed,
            });
        }
        Ok(())
    }

    /// One line naming the adapter and backend.
    pub fn describe(&self) -> String {
        format!(
            "{} ({:?}, {:?})",
            self.info.name, self.info.backend, self.info.device_type
        )
    }
}

/// Opens the preferred adapter (`WGPU_BACKEND=vulkan|gl|...` honoured) and
/// requests a device with the adapter's own limits: the defaults give a GL
/// adapter no storage buffers at all.
pub fn open() -> Result<GpuContext, GpuError> {
    let instance =
        wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
    let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
        power_preference: wgpu::PowerPreference::HighPerformance,
        ..Default::default()
    }))
    .map_err(|e| GpuError::NoAdapter(e.to_string()))?;
    let info = adapter.get_info();
    let limits = adapter.limits();
    let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
        label: Some("lucerna compute"),
        required_features: wgpu::Features::empty(),
        required_limits: limits.clone(),
        ..Default::default()
    }))
    .map_err(|source| GpuError::Device {
        adapter: info.name.clone(),
        source,
    })?;
    Ok(GpuContext {
        device,
        queue,
        info,
        limits,
    })
}

/// For tests of GPU code: the adapter, or `None` (with a message) when
/// there is none and `LUCERNA_SKIP_GPU_TESTS` is set. Without that
/// variable a missing adapter is a failure, so CI's software adapter is
/// really exercised.
///
/// # Panics
/// When no adapter opens and `LUCERNA_SKIP_GPU_TESTS` is not set.
#[cfg(feature = "test-support")]
#[allow(clippy::panic)] // reason: a test-support helper whose failure is the point
pub fn open_for_tests() -> Option<GpuContext> {
    match open() {
        Ok(ctx) => {
            eprintln!("adapter: {}", ctx.describe());
            Some(ctx)
        }
        Err(e) if std::env::var_os("LUCERNA_SKIP_GPU_TESTS").is_some() => {
            eprintln!("skipping GPU test: {e}");
            None
        }
        Err(e) => panic!(
            "no GPU adapter ({e}); install Mesa (llvmpipe/lavapipe) or set LUCERNA_SKIP_GPU_TESTS=1"
        ),
    }
}

/// Reads a buffer back to the CPU (blocking).
pub fn read_buffer(ctx: &GpuContext, buffer: &wgpu::Buffer) -> Result<Vec<u8>, GpuError> {
    let slice = buffer.slice(..);
    let (sender, receiver) = std::sync::mpsc::channel();
    slice.map_async(wgpu::MapMode::Read, move |r| {
        let _ = sender.send(r);
    });
    ctx.device
        .poll(wgpu::PollType::wait_indefinitely())
        .map_err(|e| GpuError::Failed(e.to_string()))?;
    receiver
        .recv()
        .map_err(|e| GpuError::Failed(e.to_string()))?
        .map_err(|e| GpuError::Failed(e.to_string()))?;
    let bytes = slice
        .get_mapped_range()
        .map_err(|e| GpuError::Failed(e.to_string()))?
        .to_vec();
    buffer.unmap();
    Ok(bytes)
}
