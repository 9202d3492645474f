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
    }
}
