//! Admissible ranges of the physical inputs: what a drillstring model can mean, wide enough for any
//! real string, narrow enough that a typo (a missing unit, an exponent too many) is refused with
//! the key named instead of running for hours or failing deep in the numerics.
//!
//! Every range is closed and its lower end excludes the values that make the model meaningless
//! (issue 34): each row says why its ends are where they are. The operating point's ranges are
//! also those of the bounds of `[constraints]`, of `optimizer.start` and of the command line's
//! `--omega`, `--v0`, `--point` and `--duration` ([`range_of`] is the one table).

pub use crate::units::Range;

const fn closed(lo: f64, hi: f64, why: &'static str) -> Range {
    Range::closed(lo, hi, why)
}

const fn zero_or(lo: f64, hi: f64, why: &'static str) -> Range {
    Range::zero_or(lo, hi, why)
}

/// The lowest feed that is drilling, m/h: the axial statistics are relative to V0 (a V0 of
/// 1e-300 m/h gave an axial velocity fluctuation of 1.7e288), and 0.1 m/h is slower than any
/// rock is drilled. 0 is off-bottom rotation, a state of its own.
pub const MIN_FEED_M_PER_H: f64 = 0.1;

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
        // A gravity of 1e-300 printed a 150-digit buckling figure (the figures scale as a power
        // of 1/g): 0 is a weightless test of the bare dynamics, else at least 0.1 m/s², below
        // the gravity of any body a string is drilled on (the Moon's is 1.6 m/s²).
        "model.gravity" => zero_or(
            0.1,
            30.0,
            "0 (weightless) or 0.1 m/s² to a few g; a tiny gravity inflates the buckling figures",
        ),
        // 0 is a solid bar; a bore below it is a solid bar too (continuous in the radius).
        "model.pipe.inner_radius" => closed(0.0, 1.0, "a pipe bore of at most 2 m"),
        "model.pipe.outer_radius" => closed(1e-3, 1.0, "a pipe 2 mm to 2 m across"),
        // The stresses are reported relative to it (1e-300 printed a 300-digit utilisation):
        // from a polymer pipe's 10 MPa to the strongest steels.
        "model.pipe.yield_strength" => closed(
            10e6,
            3e9,
            "from a polymer pipe's 10 MPa to the strongest steels, 3 GPa",
        ),
        // ν = −1 makes the shear modulus E/(2(1 + ν)) infinite and ν = 0.5 is incompressible:
        // from auxetic foams (about −0.8) to rubber-like 0.499.
        "model.pipe.poisson_ratio" => closed(
            -0.9,
            0.499,
            "from auxetic foams to nearly incompressible solids; −1 makes the shear modulus infinite",
        ),
        // A factor of 1e-300 removed the shear (torsional) stiffness and failed in the
        // eigen-solve naming other keys. Cowper's factor of a thin-walled tube is about 0.5
        // (0.15 at ν = −0.9), of a solid bar about 0.9.
        "model.pipe.shear_factor" => closed(
            0.1,
            1.0,
            "a shear correction factor; Cowper's is 0.5 for a thin tube, 0.9 for a solid bar",
        ),
        "model.pipe.torsion_factor" => closed(
            0.1,
            1.0,
            "a torsional stiffness factor κ_t; the paper takes it equal to the shear factor",
        ),
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
        "operating_point.v0" => zero_or(
            crate::units::from_m_per_h(MIN_FEED_M_PER_H),
            crate::units::from_m_per_h(1000.0),
            "0 is off-bottom rotation; else from 0.1 m/h, slower than any rock is drilled, to at most 1000 m/h",
        ),
        // The hook load's WOB set-point (top = "hook_load"): the one range of the file key, its
        // bounds and `--point`.
        "operating_point.wob" => crate::model::WOB_RANGE,
        // Depth of cut per revolution 2π V0/Ω: a limit below 1 µm is finer than any cutter's
        // edge, above 10 cm taller than any cutter (PDC cutters are 8-19 mm).
        "constraints.max_depth_of_cut" => closed(
            1e-6,
            0.1,
            "a depth of cut per revolution from 1 µm to 10 cm",
        ),
        "campbell.excitation_multiple" => closed(
            1.0,
            50.0,
            "1× to 50× the rotation frequency: 3 for a tri-cone bit, the blade count of a PDC bit",
        ),
        // At least the shortest time step: `--duration 1e-300` took no step and failed naming
        // no key; a run of one step ends with its metrics refused, said so.
        "simulation.duration" => closed(
            1e-6,
            86_400.0,
            "at least the shortest time step, 1 µs, at most a day of simulated time",
        ),
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
