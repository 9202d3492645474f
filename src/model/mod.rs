//! The physical model of the drillstring: validated parameters (MODEL.md §1, §5, §6) and the
//! section constants derived from them. All values are SI.

mod basis;
pub mod bit;
pub mod parameters;
mod params;
mod section;

pub use basis::{BasisSpec, FamilySize};
pub use bit::{BitLoad, BitRock, BitRockLaw};
pub use parameters::{Enters, ParameterKey, ParameterSpec};
pub use params::{
    API_GRADES, CampbellSettings, Drillstring, Mesh, OperatingPoint, Pipe, Simulation, Start,
    WallContact,
};
pub use section::{Section, cowper_shear_factor};
