//! Fatigue of the rotating pipe (issue 14, item 2): rainflow cycle counting of a stress history
//! ([`Rainflow`], ASTM E1049-85) and Miner damage against an S-N curve with an endurance limit
//! ([`SnCurve`], DNV-RP-C203 (2016) Table 2-1). The simulator feeds the axial stress of material
//! fibres of every section to the counters at each accepted step ([`crate::sim::StressEnvelope`]).

mod rainflow;
mod sn_curve;

pub use rainflow::{
    Cycle, RAINFLOW_CAPACITY, Rainflow, astm_cycles, streaming_cycles, turning_points,
};
pub use sn_curve::{DEFAULT_SN_CURVE, DNV_AIR, DNV_M2, SnCurve};
