//! Pictures of photometry: false-colour cube maps and polar diagrams as
//! PNG, the raw intensity map as EXR. No GPU.

pub mod canvas;
pub mod chart;
pub mod cube;
pub mod exr_map;
pub mod isocandela;
pub mod polar;
pub mod room;
pub mod scale;

pub use cube::cube_map_png;
pub use exr_map::{ExrError, intensity_map_exr};
pub use polar::polar_png;
pub use room::{illuminance_png, image_rows_png, room_view_png, work_plane_png};
