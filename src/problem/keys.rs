//! Which problem keys enter each numerical stage of a run, with their values in a problem: what a
//! numerical failure names (the eigen-solve's mass or stiffness matrix, the resting shape, the
//! start, the time march), read from this one table rather than from lists written at each error.
//!
//! The rows are the string's keys (one section; a string of sections points at its
//! `[[model.section]]` tables), the operating point and the step; the wall contact and bit–rock
//! laws add their own parameter tables ([`crate::model::Law::parameters`]) to the stages they
//! enter.

use super::Problem;
use crate::model::Law;
use crate::units::Dimension::{self, *};

/// A numerical stage of building a model or running it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stage {
    /// The mass matrix of the eigen-solve (not positive definite).
    MassMatrix,
    /// The stiffness matrix of the eigen-solve (not positive), with the mass.
    StiffnessMatrix,
    /// The resting shape: the string's static deflection on the wall under its weight.
    RestingShape,
    /// The starting state (static, or the steady drilling state of the operating point).
    Start,
    /// The time march (Newton on each step, the adaptive step).
    Step,
}

impl Stage {
    /// What the stage is, for a message.
    pub fn describe(self) -> &'static str {
        match self {
            Stage::MassMatrix => "the mass matrix of the eigen-solve",
            Stage::StiffnessMatrix => "the stiffness and mass matrices of the eigen-solve",
            Stage::RestingShape => "the resting shape (the string's weight on the wall)",
            Stage::Start => "the starting state",
            Stage::Step => "the time march",
        }
    }
}

use Stage::*;

const ALL: &[Stage] = &[MassMatrix, StiffnessMatrix, RestingShape, Start, Step];
/// The mass (weight, inertia) enters every stage.
const MASS: &[Stage] = ALL;
/// A rotary inertia: in the mass matrix and the motion, not in a static shape.
const INERTIA: &[Stage] = &[MassMatrix, StiffnessMatrix, Start, Step];
const STIFFNESS: &[Stage] = &[StiffnessMatrix, RestingShape, Start, Step];
const STATIC: &[Stage] = &[RestingShape, Start, Step];
const DYNAMIC: &[Stage] = &[Start, Step];

/// A key of the problem file, the stages it enters and its value (SI) in a problem.
struct Row {
    key: &'static str,
    dimension: Dimension,
    stages: &'static [Stage],
    /// Whether the key is a size or material of the pipe, given per section in a string of
    /// sections.
    per_section: bool,
    value: fn(&Problem) -> f64,
}

const fn row(
    key: &'static str,
    dimension: Dimension,
    stages: &'static [Stage],
    value: fn(&Problem) -> f64,
) -> Row {
    Row {
        key,
        dimension,
        stages,
        per_section: false,
        value,
    }
}

/// A [`row`] of the pipe's sizes and materials (given per section in a string of sections).
const fn pipe(
    key: &'static str,
    dimension: Dimension,
    stages: &'static [Stage],
    value: fn(&Problem) -> f64,
) -> Row {
    Row {
        per_section: true,
        ..row(key, dimension, stages, value)
    }
}

static ROWS: [Row; 20] = [
    row("model.length", Length, ALL, |p| p.model.length),
    row("mesh.elements", Dimensionless, ALL, |p| {
        p.mesh.elements as f64
    }),
    pipe("model.pipe.outer_radius", Length, ALL, |p| {
        p.model.pipe.outer_radius
    }),
    pipe("model.pipe.inner_radius", Length, ALL, |p| {
        p.model.pipe.inner_radius
    }),
    pipe("model.pipe.density", Density, MASS, |p| {
        p.model.pipe.density
    }),
    row("model.fluid.density", Density, MASS, |p| {
        p.model.fluid_density
    }),
    row("model.fluid.annulus_density", Density, MASS, |p| {
        p.model.annulus_density
    }),
    row("model.bit.inertia", MomentOfInertia, INERTIA, |p| {
        p.model.bit_inertia
    }),
    pipe("model.pipe.youngs_modulus", Pressure, STIFFNESS, |p| {
        p.model.pipe.youngs_modulus
    }),
    pipe("model.pipe.poisson_ratio", Dimensionless, STIFFNESS, |p| {
        p.model.pipe.poisson_ratio
    }),
    pipe("model.pipe.shear_factor", Dimensionless, STIFFNESS, |p| {
        p.model.pipe.shear_factor
    }),
    pipe("model.pipe.torsion_factor", Dimensionless, STIFFNESS, |p| {
        p.model.pipe.torsion_factor
    }),
    row("model.gravity", Acceleration, STATIC, |p| p.model.gravity),
    row("model.borehole.radius", Length, STATIC, |p| {
        p.model.borehole_radius
    }),
    row("model.pipe.damping", Rate, DYNAMIC, |p| p.model.damping),
    row("model.pipe.stiffness_damping", Time, DYNAMIC, |p| {
        p.model.stiffness_damping
    }),
    row("operating_point.omega", AngularVelocity, DYNAMIC, |p| {
        p.operating_point.omega
    }),
    row("operating_point.v0", Velocity, DYNAMIC, |p| {
        p.operating_point.v0
    }),
    row("simulation.time_step", Time, &[Step], |p| {
        p.simulation.time_step
    }),
    row("simulation.duration", Time, &[Step], |p| {
        p.simulation.duration
    }),
];

/// The dimension of a problem-file key of the model's parameter table or of this one (for the
/// range a message gives); `None` for other keys.
pub fn dimension_of(key: &str) -> Option<Dimension> {
    crate::model::parameters::STRING_PARAMETERS
        .iter()
        .find(|r| r.spec.key == key)
        .map(|r| r.spec.dimension)
        .or_else(|| ROWS.iter().find(|r| r.key == key).map(|r| r.dimension))
}

/// Whether the laws' parameters enter `stage`: the wall's from the resting shape on, the bit's
/// in the start and the march.
fn laws_enter(stage: Stage) -> (bool, bool) {
    (STATIC.contains(&stage), DYNAMIC.contains(&stage))
}

/// `value` to 4 significant digits, in exponent form from a million on (`1.5e8`, not
/// `150000000`).
fn digits(value: f64) -> String {
    let text = crate::units::sig(value, 4);
    match text.parse::<f64>() {
        Ok(v) if v.abs() >= 1e6 && v.is_finite() => format!("{v:e}"),
        _ => text,
    }
}

/// The value of `key` with its unit, as a message shows it: rotation speeds in rpm, the feed and
/// the bit's velocities in m/h (as a driller types them), the wall's impact speed and every other
/// quantity in SI.
fn shown(key: &str, value: f64, dimension: Dimension) -> String {
    match dimension {
        AngularVelocity => {
            return format!("{} rpm", digits(crate::units::to_rpm(value)));
        }
        Velocity if !key.starts_with("model.wall.") => {
            return format!("{} m/h", digits(crate::units::to_m_per_h(value)));
        }
        _ => {}
    }
    let unit = dimension.si_unit();
    if matches!(dimension, Dimensionless) || unit.is_empty() {
        digits(value)
    } else {
        format!("{} {unit}", digits(value))
    }
}

/// The keys that enter `stage`, in table order: (key, value with its unit). The pipe's keys of a
/// string of sections are named once, as its sections' (`model.section[*]`).
pub fn entering(problem: &Problem, stage: Stage) -> Vec<(String, String)> {
    let sections = !problem.model.sections.is_empty();
    let mut out: Vec<(String, String)> = Vec::new();
    let mut named_sections = false;
    for r in ROWS.iter().filter(|r| r.stages.contains(&stage)) {
        if r.per_section && sections {
            if !named_sections {
                out.push((
                    "model.section[*]".to_string(),
                    format!(
                        "{} sections: their sizes and materials",
                        problem.model.sections.len()
                    ),
                ));
                named_sections = true;
            }
            continue;
        }
        out.push((
            r.key.to_string(),
            shown(r.key, (r.value)(problem), r.dimension),
        ));
    }
    let (wall, bit) = laws_enter(stage);
    let laws: [(bool, &dyn Law); 2] = [
        (wall, problem.model.wall.law()),
        (bit, problem.model.bit.law()),
    ];
    for (enters, law) in laws {
        if enters {
            for (i, spec) in law.parameters().iter().enumerate() {
                out.push((
                    spec.key.to_string(),
                    shown(spec.key, law.value(i), spec.dimension),
                ));
            }
        }
    }
    out
}

/// "`model.length` = 35 m, `mesh.elements` = 105, …": the keys of [`entering`] with their values.
pub fn describe_entering(problem: &Problem, stage: Stage) -> String {
    entering(problem, stage)
        .into_iter()
        .map(|(k, v)| format!("`{k}` = {v}"))
        .collect::<Vec<_>>()
        .join(", ")
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    fn seed() -> Problem {
        Problem::from_toml(
            include_str!("../../problems/seed_mc2014.toml"),
            Path::new("seed.toml"),
        )
        .unwrap()
    }

    #[test]
    fn each_stage_names_the_keys_of_its_matrices_with_their_values() {
        let p = seed();
        let mass: Vec<String> = entering(&p, MassMatrix).into_iter().map(|r| r.0).collect();
        // The keys the old hand-written list missed are here.
        for k in [
            "model.bit.inertia",
            "model.pipe.density",
            "model.fluid.density",
        ] {
            assert!(mass.iter().any(|m| m == k), "{k} missing: {mass:?}");
        }
        assert!(!mass.iter().any(|m| m == "model.pipe.youngs_modulus"));
        let stiffness: Vec<String> = entering(&p, StiffnessMatrix)
            .into_iter()
            .map(|r| r.0)
            .collect();
        for k in [
            "model.pipe.shear_factor",
            "model.pipe.torsion_factor",
            "model.pipe.youngs_modulus",
        ] {
            assert!(stiffness.iter().any(|m| m == k), "{k} missing");
        }
        let start = describe_entering(&p, Start);
        assert!(start.contains("`model.length` = 35 m"), "{start}");
        assert!(start.contains("`model.wall.friction`"), "{start}");
        assert!(
            start.contains("`operating_point.omega` = 60 rpm"),
            "{start}"
        );
        assert!(start.contains("`operating_point.v0` = 5 m/h"), "{start}");
        assert!(!start.contains("simulation.time_step"), "{start}");
        assert!(describe_entering(&p, Step).contains("`simulation.time_step`"));
        assert!(!describe_entering(&p, RestingShape).contains("model.bit."));
    }

    #[test]
    fn values_read_in_their_units_with_their_digits() {
        // The seed's wall stiffness and Young's modulus in exponent form; an impact speed in
        // m/s (it read 360 m/h), the feed and the bit's velocities in m/h.
        let start = describe_entering(&seed(), Start);
        assert!(
            start.contains("`model.wall.stiffness` = 1e10 N/m"),
            "{start}"
        );
        assert!(
            start.contains("`model.pipe.youngs_modulus` = 2.03e11 Pa"),
            "{start}"
        );
        assert_eq!(shown("model.wall.impact_speed", 0.1, Velocity), "0.1 m/s");
        assert_eq!(
            shown("model.bit.specific_energy", 1.5e8, Pressure),
            "1.5e8 Pa"
        );
        assert_eq!(
            shown("operating_point.v0", 20.0 / 3600.0, Velocity),
            "20 m/h"
        );
        assert_eq!(shown("mesh.elements", 162.0, Dimensionless), "162");
    }

    #[test]
    fn a_string_of_sections_points_at_its_sections() {
        let p = Problem::from_toml(
            include_str!("../../problems/bha_example.toml"),
            Path::new("bha.toml"),
        )
        .unwrap();
        let d = describe_entering(&p, StiffnessMatrix);
        assert!(d.contains("`model.section[*]`"), "{d}");
        assert!(!d.contains("model.pipe.outer_radius"), "{d}");
        assert_eq!(d.matches("model.section[*]").count(), 1, "{d}");
    }
}
