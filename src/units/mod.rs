//! Physical dimensions, the units a value may be written in, and admissible ranges.
//!
//! Low in the house: the model's parameter tables ([`crate::model::parameters`], the bit–rock laws)
//! declare each input's [`Dimension`] and [`Range`] here, and [`crate::problem`] reads and checks
//! problem files against them.

mod dimension;
mod range;

pub use dimension::{Dimension, UnitError};
pub use range::Range;

/// "1 thread", "2 threads": a count with its noun in the right number (regular English plurals:
/// the noun plus "s").
pub fn count(n: usize, noun: &str) -> String {
    if n == 1 {
        format!("1 {noun}")
    } else {
        format!("{n} {noun}s")
    }
}

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

/// `x` with at most 4 decimals and no trailing zeros (`30`, `111.1111`, `0.25`), for messages.
pub fn short(x: f64) -> String {
    let s = format!("{x:.4}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// `x` as Rust prints it when that is short (`0.005`, `250000`), in exponent form when it is
/// not (`1e308`, `1e-300`), for echoing a value in a message.
pub fn show(x: f64) -> String {
    let a = x.abs();
    if a == 0.0 || !a.is_finite() || (1e-4..1e9).contains(&a) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn short_numbers_for_messages() {
        assert_eq!(super::short(30.000000000000004), "30");
        assert_eq!(super::short(111.11111), "111.1111");
        assert_eq!(super::short(0.25), "0.25");
        assert_eq!(super::short(-3.0), "-3");
        assert_eq!(super::show(1e308), "1e308");
        assert_eq!(super::show(-2.5e-300), "-2.5e-300");
        assert_eq!(super::show(0.005), "0.005");
        assert_eq!(super::show(f64::NAN), "NaN");
    }
}

#[cfg(test)]
mod count_tests {
    #[test]
    fn counts_say_one_thread_and_two_threads() {
        assert_eq!(super::count(1, "thread"), "1 thread");
        assert_eq!(super::count(2, "thread"), "2 threads");
        assert_eq!(super::count(0, "sample"), "0 samples");
    }
}
