//! Lucerna's preview room: photometric polygonal lights shaded with the
//! cubature of Luksch, Prost and Wimmer 2020 (diffuse) and Linearly
//! Transformed Cosines (specular, eq. 12–16), work-plane illuminance
//! figures, Monte Carlo and far-field references, a CPU renderer and its
//! WGSL twin (`gpu`, `shaders/room.wgsl`), and the pipeline `lucerna
//! render` and the editor's preview share (`setup`, `lighting`, `task`).

pub mod cubature;
pub mod evaluation;
pub mod gpu;
pub mod light;
pub mod lighting;
pub mod ltc;
pub mod model;
pub mod polar;
pub mod profile;
pub mod radial;
pub mod reference;
pub mod render;
pub mod scene;
pub mod setup;
pub mod shading;
pub mod task;
pub mod work_plane;

pub use light::{Opening, PlacedLight};
pub use lighting::{LitRoom, RoomRenderer};
pub use model::{RoomFile, RoomFileError, load_room, parse_room};
pub use profile::ProfileGrid;
pub use render::{Frame, Shading, render_cpu, tone_map};
pub use scene::RoomScene;
pub use setup::{RoomSetup, room_files};
pub use task::{TASK_TARGETS, TaskTarget};
pub use work_plane::{IlluminanceFigures, WorkPlaneGrid, WriteGridCsvError, work_plane_cpu};
