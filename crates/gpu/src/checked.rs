//! Shader-module and pipeline creation that returns the device's errors.
//!
//! wgpu reports an invalid shader or pipeline to the device's uncaptured-
//! error handler, which panics by default; inside error scopes the same
//! error comes back as a value, so a bad kernel is an `Err` its caller can
//! report rather than a crash.

/// A shader module the device rejected.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum CreateShaderModuleError {
    /// The source failed to parse or validate, or the backend could not
    /// translate it (the source error says which and where).
    #[error("the device rejected shader module '{label}'")]
    Rejected {
        label: String,
        #[source]
        source: wgpu::Error,
    },
}

/// A pipeline the device rejected.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum CreatePipelineError {
    /// A compute pipeline: a missing or mistyped entry point, a layout
    /// that does not match the shader's bindings, an invalid module.
    #[error("the device rejected compute pipeline '{label}' (entry point '{entry_point}')")]
    Compute {
        label: String,
        entry_point: String,
        #[source]
        source: wgpu::Error,
    },
}

/// Runs `create` inside validation, internal and out-of-memory error
/// scopes; the first error any of them caught, if one did.
fn captured<T>(device: &wgpu::Device, create: impl FnOnce() -> T) -> Result<T, wgpu::Error> {
    let out_of_memory = device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
    let internal = device.push_error_scope(wgpu::ErrorFilter::Internal);
    let validation = device.push_error_scope(wgpu::ErrorFilter::Validation);
    let created = create();
    // Innermost first, as wgpu requires. On native backends creation
    // reports synchronously, so the futures are ready at once.
    let validation = pollster::block_on(validation.pop());
    let internal = pollster::block_on(internal.pop());
    let out_of_memory = pollster::block_on(out_of_memory.pop());
    match validation.or(internal).or(out_of_memory) {
        Some(error) => Err(error),
        None => Ok(created),
    }
}

fn label_of(label: wgpu::Label<'_>) -> String {
    label.unwrap_or("unlabelled").to_owned()
}

/// [`wgpu::Device::create_shader_module`], with the device's error as an
/// `Err` instead of a panic.
pub fn create_shader_module(
    device: &wgpu::Device,
    descriptor: wgpu::ShaderModuleDescriptor<'_>,
) -> Result<wgpu::ShaderModule, CreateShaderModuleError> {
    let label = label_of(descriptor.label);
    captured(device, || device.create_shader_module(descriptor))
        .map_err(|source| CreateShaderModuleError::Rejected { label, source })
}

/// [`wgpu::Device::create_compute_pipeline`], with the device's error as
/// an `Err` instead of a panic.
pub fn create_compute_pipeline(
    device: &wgpu::Device,
    descriptor: &wgpu::ComputePipelineDescriptor<'_>,
) -> Result<wgpu::ComputePipeline, CreatePipelineError> {
    captured(device, || device.create_compute_pipeline(descriptor)).map_err(|source| {
        CreatePipelineError::Compute {
            label: label_of(descriptor.label),
            entry_point: descriptor.entry_point.unwrap_or("(default)").to_owned(),
            source,
        }
    })
}
