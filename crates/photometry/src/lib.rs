//! Lucerna's photometry core: cube-map intensity maps, candela tables on
//! C-γ grids, IES LM-63 and EULUMDAT read/write, derived figures. No GPU.
//!
//! Conventions (ARCHITECTURE.md): candela, lumens, metres; degrees at file
//! boundaries; type C photometry with γ = 0 at nadir (−z), C0 along +x,
//! C90 along +y.

pub mod cubemap;
pub mod fidelity;
pub mod figures;
pub mod gamma_grid;
pub mod ies;
pub mod intensity_map;
pub mod ldt;
pub mod limits;
pub mod noise;
pub mod photometry;
pub mod read;
pub mod resample;
pub mod symmetry;
pub mod table;
pub mod tabulate;
pub mod text;
pub mod tm25;

pub use cubemap::{CubeFace, CubeMapLayout};
pub use figures::{Figures, figures};
pub use ies::{IesVersion, parse_ies, write_ies, write_ies_with};
pub use intensity_map::IntensityMap;
pub use ldt::{parse_ldt, to_latin1, write_ldt, write_ldt_with};
pub use limits::WritePhotometryError;
pub use photometry::{
    Dimensions, Format, LampSet, LampVariant, Metadata, ParsePhotometryError, Photometry,
    WriteOptions,
};
pub use read::{read_photometry, sniff};
pub use resample::{CellBinning, table_from_cube_map};
pub use symmetry::{AxialIsometry, AxialSymmetry, TexelSymmetry};
pub use table::{CPlaneSymmetry, CandelaTable};
pub use text::format_number;
