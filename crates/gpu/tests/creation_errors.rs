#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)] // reason: tests may panic
//! An invalid shader or pipeline is an `Err` from the checked creation
//! helpers, not a panic in wgpu's uncaptured-error handler.

use lucerna_gpu::{
    CreatePipelineError, CreateShaderModuleError, create_compute_pipeline, create_shader_module,
};

const VALID: &str = "@compute @workgroup_size(1) fn main() {}";

fn module(
    device: &wgpu::Device,
    source: &str,
) -> Result<wgpu::ShaderModule, CreateShaderModuleError> {
    create_shader_module(
        device,
        wgpu::ShaderModuleDescriptor {
            label: Some("test.wgsl"),
            source: wgpu::ShaderSource::Wgsl(source.into()),
        },
    )
}

fn pipeline(
    device: &wgpu::Device,
    module: &wgpu::ShaderModule,
    entry_point: &str,
) -> Result<wgpu::ComputePipeline, CreatePipelineError> {
    create_compute_pipeline(
        device,
        &wgpu::ComputePipelineDescriptor {
            label: Some("test pipeline"),
            layout: None,
            module,
            entry_point: Some(entry_point),
            compilation_options: Default::default(),
            cache: None,
        },
    )
}

#[test]
fn a_valid_shader_and_pipeline_are_created() {
    let Some(ctx) = lucerna_gpu::open_for_tests() else {
        return;
    };
    let m = module(&ctx.device, VALID).unwrap();
    pipeline(&ctx.device, &m, "main").unwrap();
}

#[test]
fn invalid_wgsl_is_an_error_naming_the_module() {
    let Some(ctx) = lucerna_gpu::open_for_tests() else {
        return;
    };
    // A type error: a float returned where the function promises u32.
    let err = module(&ctx.device, "fn f() -> u32 { return 1.5; }").unwrap_err();
    let CreateShaderModuleError::Rejected { label, source } = &err else {
        panic!("unexpected error {err:?}");
    };
    assert_eq!(label, "test.wgsl");
    assert!(
        matches!(source, wgpu::Error::Validation { .. }),
        "{source:?}"
    );
    // The device is still usable afterwards.
    module(&ctx.device, VALID).unwrap();
}

#[test]
fn a_wrong_entry_point_is_an_error_naming_it() {
    let Some(ctx) = lucerna_gpu::open_for_tests() else {
        return;
    };
    let m = module(&ctx.device, VALID).unwrap();
    let err = pipeline(&ctx.device, &m, "no_such_entry").unwrap_err();
    let CreatePipelineError::Compute {
        label, entry_point, ..
    } = &err
    else {
        panic!("unexpected error {err:?}");
    };
    assert_eq!(
        (label.as_str(), entry_point.as_str()),
        ("test pipeline", "no_such_entry")
    );
    // Through `GpuError`, the chain still names the operation and the cause.
    let gpu_error = lucerna_gpu::GpuError::from(err);
    assert!(
        gpu_error
            .to_string()
            .contains("compute pipeline 'test pipeline'")
    );
    pipeline(&ctx.device, &m, "main").unwrap();
}
