//! Physical dimensions, the units a value may be written in, and admissible ranges.
//!
//! Low in the house: the model's parameter tables ([`crate::model::parameters`], the bit–rock laws)
//! declare each input's [`Dimension`] and [`Range`] here, and [`crate::problem`] reads and checks
//! problem files against them.

mod dimension;
mod fraction;
mod range;
mod system;

pub use dimension::{Dimension, UnitError};
pub use range::Range;
pub use system::{Shown, UnitSystem};

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

/// rad/s per rpm (2π/60): the factor of `rpm` in [`Dimension::units`], so that [`from_rpm`] and
/// the parse of `"60rpm"` give the same bits.
pub const RAD_S_PER_RPM: f64 = 2.0 * std::f64::consts::PI / 60.0;
/// m/s per m/h (1/3600): the factor of `m/h` in [`Dimension::units`].
pub const M_S_PER_M_PER_H: f64 = 1.0 / 3600.0;

/// Ω in rpm → rad/s: the one conversion, the same arithmetic as the parse of `"<rpm> rpm"`.
pub const fn from_rpm(rpm: f64) -> f64 {
    rpm * RAD_S_PER_RPM
}

/// V in m/s → m/h.
pub fn to_m_per_h(v_m_s: f64) -> f64 {
    v_m_s * M_PER_H_PER_M_PER_S
}

/// V in m/h → m/s: the one conversion, the same arithmetic as the parse of `"<v> m/h"`.
pub const fn from_m_per_h(v_m_h: f64) -> f64 {
    v_m_h * M_S_PER_M_PER_H
}

/// Significant digits of the driller's units an operating point is snapped to by
/// [`canonical_point`]: far below any physical meaning (1e-12 relative), far above round-off.
pub const POINT_DIGITS: usize = 12;

/// The canonical bits of an operating point (Ω rad/s, V0 m/s): Ω in rpm and V0 in m/h rounded to
/// [`POINT_DIGITS`] significant digits, converted back with [`from_rpm`] and [`from_m_per_h`].
/// Every point a study evaluates goes through it, so that the same point reached by different
/// arithmetic (the parse of `--point 60rpm,5m/h`, the optimizer's unit-box scaling, a grid node)
/// has the same bits and the same evaluation-cache key. Idempotent; a point parsed from a
/// decimal of at most 12 significant digits is unchanged.
pub fn canonical_point(omega_rad_s: f64, v0_m_s: f64) -> (f64, f64) {
    (
        from_rpm(round_point(to_rpm(omega_rad_s))),
        from_m_per_h(round_point(to_m_per_h(v0_m_s))),
    )
}

/// `x` rounded to [`POINT_DIGITS`] significant digits (0 and non-finite values as they are): the
/// rounding of [`canonical_point`], for a set-point in the unit it is shown in (a WOB in kN).
pub fn round_point(x: f64) -> f64 {
    if x == 0.0 || !x.is_finite() {
        return x;
    }
    format!("{x:.prec$e}", prec = POINT_DIGITS - 1)
        .parse()
        .unwrap_or(x)
}

/// Whether a value is exactly 0: `serde(skip_serializing_if = "crate::units::is_zero")` for a
/// quantity that only some problems have (a hook load's WOB set-point).
pub fn is_zero(x: &f64) -> bool {
    *x == 0.0
}

/// `x` with at most 4 decimals and no trailing zeros (`30`, `111.1111`, `0.25`), for messages;
/// in exponent form beyond 1e9 or below 1e-4 (`1e300` was printed with 301 digits), never a
/// negative zero.
pub fn short(x: f64) -> String {
    let a = x.abs();
    if a != 0.0 && a.is_finite() && !(1e-4..1e9).contains(&a) {
        return show(x);
    }
    let s = format!("{:.4}", x + 0.0);
    let s = if s
        .trim_start_matches('-')
        .trim_matches(['0', '.'])
        .is_empty()
    {
        s.trim_start_matches('-').to_string()
    } else {
        s
    };
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// `x` with `decimals` decimals, never a negative zero (`-0.0001` to 3 decimals is `0.000`, not
/// `-0.000`), for figures on the terminal.
pub fn fixed(x: f64, decimals: usize) -> String {
    let s = format!("{x:.decimals$}");
    match s.strip_prefix('-') {
        Some(rest) if rest.chars().all(|c| c == '0' || c == '.') => rest.to_string(),
        _ => s,
    }
}

/// `x` rounded to `digits` significant digits and printed as [`show`] prints it
/// (`0.5423145542816914` to 4 digits is `0.5423`, 2π is `6.283`).
pub fn sig(x: f64, digits: usize) -> String {
    if x == 0.0 || !x.is_finite() {
        return show(x + 0.0);
    }
    let rounded: f64 = format!("{x:.prec$e}", prec = digits.max(1) - 1)
        .parse()
        .unwrap_or(x);
    show(rounded)
}

/// Six significant digits, in exponent form outside [1e-3, 1e6) (`verify`'s and the numerical
/// check's tables).
pub fn significant(x: f64) -> String {
    if x != 0.0 && !(1e-3..1e6).contains(&x.abs()) {
        format!("{x:.5e}")
    } else {
        let decimals = (5 - x.abs().log10().floor().max(0.0) as i32).max(0) as usize;
        format!("{x:.decimals$}")
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
        // No 301-digit numbers and no negative zero (issue 34).
        assert_eq!(super::short(1e300), "1e300");
        assert_eq!(super::short(-0.0), "0");
        assert_eq!(super::short(-0.00001), "-1e-5");
        assert_eq!(super::short(-0.00004), "-4e-5");
        assert_eq!(super::short(-4e-305), "-4e-305");
        assert_eq!(super::short(-3.0), "-3");
        assert_eq!(super::show(1e308), "1e308");
        assert_eq!(super::show(-2.5e-300), "-2.5e-300");
        assert_eq!(super::show(0.005), "0.005");
        assert_eq!(super::show(f64::NAN), "NaN");
        assert_eq!(super::fixed(-0.0001, 3), "0.000");
        assert_eq!(super::fixed(-0.0, 1), "0.0");
        assert_eq!(super::fixed(-0.02, 1), "0.0");
        assert_eq!(super::fixed(-0.06, 1), "-0.1");
        assert_eq!(super::fixed(4.9454, 3), "4.945");
        assert_eq!(super::sig(0.5423145542816914, 4), "0.5423");
        assert_eq!(super::sig(std::f64::consts::TAU, 4), "6.283");
        assert_eq!(super::sig(2.03e11, 4), "2.03e11");
        assert_eq!(super::sig(1e16, 4), "1e16");
        assert_eq!(super::sig(-0.0, 4), "0");
    }
}

#[cfg(test)]
mod point_tests {
    use super::*;

    #[test]
    fn the_conversion_functions_and_the_parse_give_the_same_bits() {
        for rpm in [1.0, 12.5, 40.0, 60.0, 77.7, 120.0, 1000.0] {
            let parsed = Dimension::AngularVelocity
                .parse(&format!("{rpm}rpm"))
                .unwrap();
            assert_eq!(from_rpm(rpm).to_bits(), parsed.to_bits(), "{rpm} rpm");
        }
        for v in [0.0, 2.0, 5.0, 11.0, 12.0, 20.0, 1000.0] {
            let parsed = Dimension::Velocity.parse(&format!("{v}m/h")).unwrap();
            assert_eq!(from_m_per_h(v).to_bits(), parsed.to_bits(), "{v} m/h");
        }
    }

    #[test]
    fn points_reached_by_other_arithmetic_snap_to_the_parsed_bits() {
        // The unit-box scaling of the optimizer: lo + x (hi − lo). At 80 rpm, the middle of 40
        // and 120 rpm (x = 1/2), it is one ulp away from the parse of "80rpm" (the cache missed).
        let (lo, hi) = (from_rpm(40.0), from_rpm(120.0));
        let scaled = lo + 0.5 * (hi - lo);
        let parsed = Dimension::AngularVelocity.parse("80rpm").unwrap();
        assert_ne!(
            scaled.to_bits(),
            parsed.to_bits(),
            "the trap this guards against"
        );
        let (vlo, vhi) = (from_m_per_h(2.0), from_m_per_h(20.0));
        let v_scaled = vlo + (1.0 / 6.0) * (vhi - vlo);
        assert_ne!(v_scaled.to_bits(), from_m_per_h(5.0).to_bits());
        let (w, v) = canonical_point(scaled, v_scaled);
        assert_eq!(w.to_bits(), parsed.to_bits());
        assert_eq!(
            v.to_bits(),
            Dimension::Velocity.parse("5m/h").unwrap().to_bits()
        );
        // Idempotent, and a parsed point is its own canonical point.
        assert_eq!(canonical_point(w, v), (w, v));
        let odd = (1.234_567_890_123_4, 3.3e-4);
        let c = canonical_point(odd.0, odd.1);
        assert_eq!(canonical_point(c.0, c.1), c);
        assert!((c.0 - odd.0).abs() <= 1e-11 * odd.0 && (c.1 - odd.1).abs() <= 1e-11 * odd.1);
        assert_eq!(canonical_point(1.0, 0.0).1, 0.0);
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
