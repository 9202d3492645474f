//! The physical model of the drillstring: validated parameters (MODEL.md §1, §5, §6), the laws of
//! wall contact and bit–rock interaction, and the
//! section constants derived from them. All values are SI.

mod basis;
pub mod bit;
mod buckling;
pub mod law;
pub mod parameters;
mod params;
mod section;
mod top;
mod torque_drag;
pub mod wall;

pub use basis::{BasisSpec, FamilySize};
pub use bit::{BitLoad, BitRock, BitRockLaw, bit_damping_ratio, torsional_impedance};
pub use buckling::BucklingLoads;
pub use law::{Chosen, Law, LawEntry};
pub use parameters::{Enters, ParameterKey, ParameterSpec};
pub use params::{
    API_GRADES, CampbellSettings, Drillstring, Mesh, MultipleSource, OperatingPoint, Pipe,
    SampleInterval, SetPoint, SetPointValue, Simulation, Start, StringSection,
};
pub use section::{Section, cowper_shear_factor};
pub use top::{
    AUTODRILLER_TIME_CONSTANT, Autodriller, DEFAULT_TIME_CONSTANT, POWER_LIMIT, POWER_RANGE,
    TIME_CONSTANT_RANGE, TOP_DRIVES, TORQUE_LIMIT, TORQUE_RANGE, TopDrive, WOB_LIMIT, WOB_RANGE,
    WOB_SET_POINT, autodriller_acceleration,
};
pub use torque_drag::SoftString;
pub use wall::{NormalForce, WallContact, WallContactLaw, WallFriction, WallStiffnessPer};
