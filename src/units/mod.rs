//! Physical dimensions, the units a value may be written in, and admissible ranges.
//!
//! Low in the house: the model's parameter tables ([`crate::model::parameters`], the bit–rock laws)
//! declare each input's [`Dimension`] and [`Range`] here, and [`crate::problem`] reads and checks
//! problem files against them.

mod dimension;
mod range;

pub use dimension::{Dimension, UnitError};
pub use range::Range;

/// rad/s per rpm (2π/60): the one place the conversion is written.
pub const RAD_S_PER_RPM: f64 = std::f64::consts::PI / 30.0;
/// m/s per m/h (1/3600).
pub const M_S_PER_M_H: f64 = 1.0 / 3600.0;

/// Ω in rad/s → rpm.
pub fn to_rpm(omega_rad_s: f64) -> f64 {
    omega_rad_s / RAD_S_PER_RPM
}

/// Ω in rpm → rad/s.
pub fn from_rpm(rpm: f64) -> f64 {
    rpm * RAD_S_PER_RPM
}

/// V in m/s → m/h.
pub fn to_m_per_h(v_m_s: f64) -> f64 {
    v_m_s * 3600.0
}

/// V in m/h → m/s.
pub fn from_m_per_h(v_m_h: f64) -> f64 {
    v_m_h * M_S_PER_M_H
}
