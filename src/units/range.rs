//! Admissible ranges of physical inputs: what a drillstring model can mean, wide enough for any
//! real string, narrow enough that a typo (a missing unit, an exponent too many) is refused with
//! the key named instead of running for hours or failing deep in the numerics.

use super::Dimension;

/// An admissible range [lo, hi] (or (lo, hi] when `open_below`), in SI units, and why.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Range {
    pub lo: f64,
    pub hi: f64,
    pub open_below: bool,
    pub why: &'static str,
}

impl Range {
    /// [lo, hi].
    pub const fn closed(lo: f64, hi: f64, why: &'static str) -> Range {
        Range {
            lo,
            hi,
            open_below: false,
            why,
        }
    }

    /// (lo, hi].
    pub const fn open(lo: f64, hi: f64, why: &'static str) -> Range {
        Range {
            lo,
            hi,
            open_below: true,
            why,
        }
    }

    /// Whether `x` is finite and inside the range.
    pub fn contains(&self, x: f64) -> bool {
        x.is_finite()
            && (if self.open_below {
                x > self.lo
            } else {
                x >= self.lo
            })
            && x <= self.hi
    }

    /// "in [0, 1000] m/h (why)": the range in a unit of the dimension, `unit` being worth
    /// `factor` SI units (as in [`Dimension::units`]), for messages in the unit a user typed.
    pub fn describe_in(&self, unit: &str, factor: f64) -> String {
        let show = |x: f64| {
            let t = format!("{:.9}", x / factor);
            t.trim_end_matches('0').trim_end_matches('.').to_string()
        };
        format!(
            "in {}{}, {}] {unit} ({})",
            if self.open_below { "(" } else { "[" },
            show(self.lo),
            show(self.hi),
            self.why
        )
    }

    /// "in (0, 15000] m (why)".
    pub fn describe(&self, dim: Dimension) -> String {
        format!(
            "in {}{}, {}] {} ({})",
            if self.open_below { "(" } else { "[" },
            self.lo,
            self.hi,
            dim.si_unit(),
            self.why
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn open_and_closed_ends_and_non_finite_values() {
        let o = Range::open(0.0, 1.0, "");
        let c = Range::closed(0.0, 1.0, "");
        assert!(!o.contains(0.0) && c.contains(0.0));
        assert!(o.contains(1.0) && !o.contains(1.0 + 1e-12));
        assert!(!c.contains(f64::NAN) && !c.contains(f64::INFINITY));
        assert_eq!(o.describe(Dimension::Length), "in (0, 1] m ()");
        let v0 = Range::closed(0.0, 1000.0 / 3600.0, "at most 1000 m/h");
        assert_eq!(
            v0.describe_in("m/h", 1.0 / 3600.0),
            "in [0, 1000] m/h (at most 1000 m/h)"
        );
    }
}
