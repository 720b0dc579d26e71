//! Serde defaults of the file format, shared by the shapes and the model
//! (segment counts, flags written only when they differ from the default).

/// Default steps around the axis of a surface of revolution (and disks).
pub(crate) fn default_around() -> u32 {
    64
}
/// Default steps along a generated curve (meridian of a reflector or dome).
pub(crate) fn default_along() -> u32 {
    32
}
/// Default steps per span between two control points of a profile.
pub(crate) fn default_per_span() -> u32 {
    8
}
pub(crate) fn yes() -> bool {
    true
}
pub(crate) fn is_false(b: &bool) -> bool {
    !*b
}
pub(crate) fn is_true(b: &bool) -> bool {
    *b
}
pub(crate) fn is_zero(x: &f64) -> bool {
    *x == 0.0
}
pub(crate) fn is_zero_u32(x: &u32) -> bool {
    *x == 0
}
