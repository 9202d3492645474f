//! The physical model of the drillstring: validated parameters (MODEL.md §1, §5, §6) and the
//! section constants derived from them. All values are SI.

mod basis;
mod params;
mod section;

pub use basis::{BasisSpec, FamilySize};
pub use params::{
    BitRock, Drillstring, Mesh, OperatingPoint, Pipe, Simulation, Start, WallContact,
};
pub use section::{Section, cowper_shear_factor};
