//! Admissible ranges of the physical inputs: what a drillstring model can mean, wide enough for any
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

const fn closed(lo: f64, hi: f64, why: &'static str) -> Range {
    Range {
        lo,
        hi,
        open_below: false,
        why,
    }
}

const fn open(lo: f64, hi: f64, why: &'static str) -> Range {
    Range {
        lo,
        hi,
        open_below: true,
        why,
    }
}

/// The admissible range of a problem-file key, if it has one.
pub fn range_of(key: &str) -> Option<Range> {
    Some(match key {
        "model.length" => open(0.0, 15e3, "the longest wells are about 15 km"),
        "model.gravity" => closed(0.0, 30.0, "0 to a few g"),
        "model.pipe.density" => closed(1e3, 25e3, "from light alloys to tungsten"),
        "model.pipe.youngs_modulus" => closed(1e9, 1e12, "from polymers to tungsten carbide"),
        "model.pipe.inner_radius" => closed(0.0, 1.0, "a pipe bore of at most 2 m"),
        "model.pipe.outer_radius" => open(0.0, 1.0, "a pipe of at most 2 m across"),
        "model.pipe.damping" => closed(0.0, 1e3, "mass-proportional damping c"),
        "model.fluid.density" => closed(0.0, 3e3, "from air to the heaviest muds"),
        "model.borehole.radius" => open(0.0, 2.0, "a hole of at most 4 m across"),
        "model.wall.stiffness" => closed(0.0, 1e14, "contact stiffness of rock"),
        "model.wall.cubic_stiffness" => closed(0.0, 1e22, "cubic contact stiffness"),
        "model.wall.damping" => closed(0.0, 1e15, "Hunt-Crossley damping c_FS"),
        "model.wall.friction" => closed(0.0, 2.0, "a Coulomb friction coefficient"),
        "model.wall.sign_smoothing" => open(0.0, 10.0, "small against the rotation speed"),
        "model.bit.limit_force" => closed(0.0, 5e6, "at most 5 MN on the bit"),
        "model.bit.rate" => open(0.0, 1e5, "the bit law's α_BR"),
        "model.bit.friction" => closed(0.0, 1.0, "μ_BR, a length of the order of the bit radius"),
        "operating_point.omega" => closed(
            std::f64::consts::PI / 30.0,
            1000.0 * std::f64::consts::PI / 30.0,
            "1 to 1000 rpm: the stick-slip statistics are relative to Ω",
        ),
        "operating_point.v0" => open(0.0, 1000.0 / 3600.0, "at most 1000 m/h"),
        "simulation.duration" => open(0.0, 86_400.0, "at most a day of simulated time"),
        "simulation.time_step" => closed(1e-6, 1.0, "a nominal step between 1 µs and 1 s"),
        _ => return None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_hold_the_seed_and_refuse_typos() {
        for (key, seed) in [
            ("model.length", 35.0),
            ("model.pipe.density", 7900.0),
            ("model.pipe.youngs_modulus", 203e9),
            ("model.wall.stiffness", 1e10),
            ("model.wall.cubic_stiffness", 1e16),
            ("model.wall.friction", 1e-5),
            ("model.bit.limit_force", 250e3),
            ("model.bit.rate", 180.0),
            ("operating_point.omega", 2.0 * std::f64::consts::PI),
            ("operating_point.v0", 1.0 / 720.0),
            ("simulation.duration", 90.0),
            ("simulation.time_step", 0.069),
        ] {
            let r = range_of(key).unwrap();
            assert!(r.contains(seed), "{key} = {seed}");
            assert!(!r.contains(seed * 1e7), "{key} × 1e7");
            assert!(!r.contains(f64::INFINITY) && !r.contains(f64::NAN));
        }
        assert!(!range_of("model.length").unwrap().contains(0.0));
        assert!(range_of("model.wall.friction").unwrap().contains(0.0));
        assert_eq!(range_of("mesh.elements"), None);
    }
}
