//! WGSL sources: one file per kernel plus shared modules, composed by
//! concatenation (the cube-map mapping lives only in `cubemap.wgsl`).

/// Cube-map layout, twin of `lucerna_photometry::cubemap`.
pub const CUBEMAP: &str = include_str!("../../../shaders/cubemap.wgsl");
/// Counter-based RNG, twin of `lucerna_tracer::rng`.
pub const RNG: &str = include_str!("../../../shaders/rng.wgsl");
/// The photon-tracing kernel.
pub const TRACER: &str = include_str!("../../../shaders/tracer.wgsl");
/// The pull-push filter's kernels.
pub const FILTER: &str = include_str!("../../../shaders/filter.wgsl");
/// The preview room's renderer (cubature + LTC).
pub const ROOM: &str = include_str!("../../../shaders/room.wgsl");
/// Test kernel mapping directions to texels.
pub const CUBEMAP_TEST: &str = include_str!("../../../shaders/cubemap_test.wgsl");

/// The tracer kernel with its modules.
pub fn tracer() -> String {
    [CUBEMAP, RNG, TRACER].join("\n")
}

/// The filter kernels with their module.
pub fn filter() -> String {
    [CUBEMAP, FILTER].join("\n")
}

/// The preview room's kernels (self-contained).
pub fn room() -> String {
    ROOM.to_owned()
}

/// The cube-map test kernel with its module.
pub fn cubemap_test() -> String {
    [CUBEMAP, CUBEMAP_TEST].join("\n")
}

/// Every composed shader, by name, for validation.
pub fn all() -> Vec<(&'static str, String)> {
    vec![
        ("tracer", tracer()),
        ("filter", filter()),
        ("cubemap_test", cubemap_test()),
        ("room", room()),
    ]
}
