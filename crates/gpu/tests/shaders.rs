#![allow(clippy::unwrap_used, clippy::expect_used)] // reason: test helpers may panic
//! Every composed WGSL shader parses and validates with naga.

#[test]
fn every_shader_validates() {
    for (name, source) in lucerna_gpu::shaders::all() {
        let module = naga::front::wgsl::parse_str(&source)
            .unwrap_or_else(|e| panic!("{name}: {}", e.emit_to_string(&source)));
        naga::valid::Validator::new(
            naga::valid::ValidationFlags::all(),
            naga::valid::Capabilities::empty(),
        )
        .validate(&module)
        .unwrap_or_else(|e| panic!("{name}: {}", e.emit_to_string(&source)));
    }
}
