//! Admissible ranges of the physical inputs: what a drillstring model can mean, wide enough for any
//! real string, narrow enough that a typo (a missing unit, an exponent too many) is refused with
//! the key named instead of running for hours or failing deep in the numerics.

pub use crate::units::Range;

const fn closed(lo: f64, hi: f64, why: &'static str) -> Range {
    Range::closed(lo, hi, why)
}

const fn open(lo: f64, hi: f64, why: &'static str) -> Range {
    Range::open(lo, hi, why)
}

/// The admissible range of a problem-file key, if it has one: the model's parameter table
/// ([`crate::model::parameters`]) for the parameters a study may vary, else the table below. The
/// parameters of the wall contact and bit–rock laws are checked against the law's own table.
pub fn range_of(key: &str) -> Option<Range> {
    use crate::model::parameters::STRING_PARAMETERS;
    if let Some(row) = STRING_PARAMETERS.iter().find(|r| r.spec.key == key) {
        return Some(row.spec.range);
    }
    Some(match key {
        // Lower ends: a string of a few nanometres (or a pipe 2 nm across) is a typo, and the
        // element shape functions and the mass matrix lose their meaning long before 0 (a
        // 1e-300 m string panicked in the shape functions; a 1e-300 m radius made the mass
        // matrix singular, reported under `mesh.basis`).
        "model.length" => closed(
            1.0,
            15e3,
            "from a 1 m laboratory string to the longest wells, about 15 km",
        ),
        "model.gravity" => closed(0.0, 30.0, "0 to a few g"),
        "model.pipe.inner_radius" => closed(0.0, 1.0, "a pipe bore of at most 2 m"),
        "model.pipe.outer_radius" => closed(1e-3, 1.0, "a pipe 2 mm to 2 m across"),
        "model.pipe.yield_strength" => open(0.0, 3e9, "at most the strongest steels, 3 GPa"),
        "model.bit.inertia" => closed(
            0.0,
            1e3,
            "at most 1000 kg·m² (a 12¼ in bit is about 1 kg·m², a whole BHA tens to hundreds)",
        ),
        "operating_point.omega" => closed(
            crate::units::from_rpm(1.0),
            crate::units::from_rpm(1000.0),
            "1 to 1000 rpm: the stick-slip statistics are relative to Ω",
        ),
        "operating_point.v0" => closed(
            0.0,
            crate::units::from_m_per_h(1000.0),
            "at most 1000 m/h; 0 is off-bottom rotation",
        ),
        "campbell.excitation_multiple" => closed(
            1.0,
            50.0,
            "1× to 50× the rotation frequency: 3 for a tri-cone bit, the blade count of a PDC bit",
        ),
        "simulation.duration" => open(0.0, 86_400.0, "at most a day of simulated time"),
        "simulation.time_step" => closed(1e-6, 1.0, "a nominal step between 1 µs and 1 s"),
        "simulation.sample_interval" => closed(
            1e-6,
            1.0,
            "an output interval between 1 µs and 1 s (or \"step\": every accepted step)",
        ),
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
        assert!(!range_of("model.length").unwrap().contains(1e-300));
        assert!(
            !range_of("model.pipe.outer_radius")
                .unwrap()
                .contains(1e-300)
        );
        // Off-bottom rotation (issue 13 item 13); a negative feed is refused.
        assert!(range_of("operating_point.v0").unwrap().contains(0.0));
        assert!(!range_of("operating_point.v0").unwrap().contains(-1e-9));
        assert_eq!(range_of("mesh.elements"), None);
    }
}
