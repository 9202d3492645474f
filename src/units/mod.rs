//! Physical dimensions, the units a value may be written in, and admissible ranges.
//!
//! Low in the house: the model's parameter tables ([`crate::model::parameters`], the bit–rock laws)
//! declare each input's [`Dimension`] and [`Range`] here, and [`crate::problem`] reads and checks
//! problem files against them.

mod dimension;
mod range;

pub use dimension::{Dimension, UnitError};
pub use range::Range;

/// rpm per rad/s (60/2π): the one place the conversion is written.
pub const RPM_PER_RAD_S: f64 = 30.0 / std::f64::consts::PI;
/// m/h per m/s.
pub const M_PER_H_PER_M_PER_S: f64 = 3600.0;

/// Ω in rad/s → rpm.
pub fn to_rpm(omega_rad_s: f64) -> f64 {
    omega_rad_s * 30.0 / std::f64::consts::PI
}

/// Ω in rpm → rad/s.
pub fn from_rpm(rpm: f64) -> f64 {
    rpm * std::f64::consts::PI / 30.0
}

/// V in m/s → m/h.
pub fn to_m_per_h(v_m_s: f64) -> f64 {
    v_m_s * M_PER_H_PER_M_PER_S
}

/// V in m/h → m/s.
pub fn from_m_per_h(v_m_h: f64) -> f64 {
    v_m_h / M_PER_H_PER_M_PER_S
}
