//! Admissible ranges of physical inputs: what a drillstring model can mean, wide enough for any
//! real string, narrow enough that a typo (a missing unit, an exponent too many) is refused with
//! the key named instead of running for hours or failing deep in the numerics.
//!
//! Every range is closed, [lo, hi], with a lower end chosen so that the model keeps its meaning
//! (issue 34): an open end (0, hi] admitted 5e-324, and a V0 of 1e-300 m/h, a yield strength of
//! 1e-300 Pa or a bit rate of 1e-300 s/m ran to absurd numbers with exit status 0. A value that
//! is meaningful at exactly 0 but not just above it (V0 = 0 is off-bottom rotation, a gravity of
//! 0 a weightless test) is admitted as an isolated 0 beside [lo, hi]: [`Range::zero_or`].

use super::Dimension;

/// An admissible range [lo, hi] in SI units (and the isolated value 0 when `zero`), and why.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Range {
    pub lo: f64,
    pub hi: f64,
    /// 0 is admitted too (an "off" state such as off-bottom rotation); `lo` > 0.
    pub zero: bool,
    /// Only whole numbers (a count, such as a bit's blades).
    pub integer: bool,
    pub why: &'static str,
}

impl Range {
    /// [lo, hi].
    pub const fn closed(lo: f64, hi: f64, why: &'static str) -> Range {
        Range {
            lo,
            hi,
            zero: false,
            integer: false,
            why,
        }
    }

    /// The whole numbers in [lo, hi] (a count).
    pub const fn integer(lo: f64, hi: f64, why: &'static str) -> Range {
        Range {
            lo,
            hi,
            zero: false,
            integer: true,
            why,
        }
    }

    /// {0} ∪ [lo, hi], lo > 0: 0 is a state of its own (V0 = 0, off bottom), values between 0
    /// and `lo` are not.
    pub const fn zero_or(lo: f64, hi: f64, why: &'static str) -> Range {
        assert!(lo > 0.0, "zero_or: the range above 0 must start above 0");
        Range {
            lo,
            hi,
            zero: true,
            integer: false,
            why,
        }
    }

    /// Whether `x` is finite and inside the range.
    pub fn contains(&self, x: f64) -> bool {
        x.is_finite()
            && ((x >= self.lo && x <= self.hi) || (self.zero && x == 0.0))
            && (!self.integer || x.fract() == 0.0)
    }

    /// "in [0, 1000] m/h (why)" (or "0 or in [0.1, 1000] m/h (why)"): the range in a unit of the
    /// dimension, `unit` being worth `factor` SI units (as in [`Dimension::units`]), for messages
    /// in the unit a user typed.
    pub fn describe_in(&self, unit: &str, factor: f64) -> String {
        let show = |x: f64| {
            let v = x / factor;
            // 1e22 was written with 23 digits: large and tiny ends in exponent form.
            if v != 0.0 && !(EXPONENT_BELOW..EXPONENT_FROM).contains(&v.abs()) {
                return format!("{v:e}");
            }
            let t = format!("{v:.9}");
            t.trim_end_matches('0').trim_end_matches('.').to_string()
        };
        // No unit (a bare factor): no space before the reason.
        let unit = if unit.is_empty() {
            String::new()
        } else {
            format!(" {unit}")
        };
        format!(
            "{}in [{}, {}]{unit} ({})",
            self.prefix(),
            show(self.lo),
            show(self.hi),
            self.why
        )
    }

    fn prefix(&self) -> &'static str {
        match (self.zero, self.integer) {
            (true, _) => "0 or ",
            (false, true) => "a whole number ",
            (false, false) => "",
        }
    }

    /// "in [1, 15000] m (why)", in the dimension's SI unit, the ends as Rust prints them.
    pub fn describe(&self, dim: Dimension) -> String {
        format!(
            "{}in [{}, {}] {} ({})",
            self.prefix(),
            wide(self.lo),
            wide(self.hi),
            dim.si_unit(),
            self.why
        )
    }
}

/// An end of a range as Rust prints it, in exponent form beyond 1e15 or below 1e-9 (1e22 was
/// written with 23 digits).
/// Range ends below this magnitude are written in exponent form (`1e-6`, not `0.000001`).
const EXPONENT_BELOW: f64 = 1e-3;
/// Range ends from this magnitude on are written in exponent form (`1e12`, not
/// `1000000000000`).
const EXPONENT_FROM: f64 = 1e6;

fn wide(x: f64) -> String {
    if x != 0.0 && !(EXPONENT_BELOW..EXPONENT_FROM).contains(&x.abs()) {
        format!("{x:e}")
    } else {
        format!("{x}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn closed_ends_an_isolated_zero_and_non_finite_values() {
        let c = Range::closed(0.0, 1.0, "");
        assert!(c.contains(0.0) && c.contains(1.0) && !c.contains(1.0 + 1e-12));
        assert!(!c.contains(f64::NAN) && !c.contains(f64::INFINITY));
        assert_eq!(c.describe(Dimension::Length), "in [0, 1] m ()");
        // 0 as a state of its own: nothing between it and the lower end (issue 34: a V0 of
        // 1e-300 m/h made a fluctuation of 1.7e288).
        let z = Range::zero_or(0.5, 1.0, "why");
        assert!(z.contains(0.0) && z.contains(0.5) && z.contains(1.0));
        assert!(
            !z.contains(1e-300)
                && !z.contains(5e-324)
                && !z.contains(0.4)
                && !z.contains(-0.0 - 1e-9)
        );
        assert_eq!(z.describe(Dimension::Length), "0 or in [0.5, 1] m (why)");
        // A count: whole numbers only.
        let n = Range::integer(1.0, 16.0, "blades");
        assert!(n.contains(1.0) && n.contains(6.0) && n.contains(16.0));
        assert!(!n.contains(5.5) && !n.contains(0.0) && !n.contains(17.0));
        assert_eq!(
            n.describe(Dimension::Dimensionless),
            format!(
                "a whole number in [1, 16] {} (blades)",
                Dimension::Dimensionless.si_unit()
            )
        );
        let v0 = Range::closed(0.0, 1000.0 / 3600.0, "at most 1000 m/h");
        assert_eq!(
            v0.describe_in("m/h", 1.0 / 3600.0),
            "in [0, 1000] m/h (at most 1000 m/h)"
        );
        // Ends of many digits in exponent form, in every unit (was [0, 100000000000000] N/m
        // beside [0, 1e15] N/m).
        let k = Range::closed(1e9, 1e12, "");
        assert_eq!(k.describe(Dimension::Pressure), "in [1e9, 1e12] Pa ()");
        assert_eq!(k.describe_in("Pa", 1.0), "in [1e9, 1e12] Pa ()");
        let dt = Range::closed(1e-6, 86_400.0, "");
        assert_eq!(dt.describe(Dimension::Time), "in [1e-6, 86400] s ()");
        assert_eq!(dt.describe_in("s", 1.0), "in [1e-6, 86400] s ()");
        assert_eq!(
            Range::closed(0.001, 999_999.0, "").describe(Dimension::Time),
            "in [0.001, 999999] s ()"
        );
    }
}
