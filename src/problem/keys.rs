//! Which problem keys enter each numerical stage of a run, with their values in a problem: what a
//! numerical failure names (the eigen-solve's mass or stiffness matrix, the resting shape, the
//! start, the time march), read from this one table rather than from lists written at each error.
//!
//! The rows are the string's keys (one section; a string of sections points at its
//! `[[model.section]]` tables), the operating point and the step; the wall contact and bit–rock
//! laws add their own parameter tables ([`crate::model::Law::parameters`]) to the stages they
//! enter.

use super::Problem;
use crate::model::{Law, ParameterSpec, WallFriction};
use crate::units::Dimension::{self, *};
use crate::units::Range;

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

/// What a problem takes when a file leaves a key out.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Omitted {
    /// The key is required.
    Required,
    /// The spec's default ([`ParameterSpec::default`]).
    Default,
    /// What happens otherwise, in words (a default computed from other keys, or none).
    Else(&'static str),
}

/// A scalar key of the problem file: its declaration (key, dimension, admissible range with its
/// reason, default, a typical value, meaning), what a file without it gets, the numerical
/// stages it enters and its value (SI) in a problem. Validation reads the range, dimension and
/// default from here, refusals quote the range, the numerical failures name the keys of their
/// stage ([`entering`]) and `drillopt keys` prints the table (docs/keys.md is its output).
pub struct Key {
    pub spec: ParameterSpec,
    pub omitted: Omitted,
    stages: &'static [Stage],
    /// Whether the key is a size or material of the pipe, given per section in a string of
    /// sections.
    per_section: bool,
    value: Option<fn(&Problem) -> f64>,
}

impl Key {
    /// What a file without the key gets, in words (SI values).
    pub fn when_omitted(&self) -> String {
        match (self.omitted, self.spec.default) {
            (Omitted::Required, _) => "required".to_string(),
            (Omitted::Default, Some(d)) => shown(self.spec.key, d, self.spec.dimension),
            (Omitted::Default, None) => "required".to_string(),
            (Omitted::Else(words), _) => words.to_string(),
        }
    }
}

/// A key that enters the numerical `stages` with its value in a problem; required unless its
/// spec has a default.
const fn key(spec: ParameterSpec, stages: &'static [Stage], value: fn(&Problem) -> f64) -> Key {
    Key {
        omitted: match spec.default {
            Some(_) => Omitted::Default,
            None => Omitted::Required,
        },
        spec,
        stages,
        per_section: false,
        value: Some(value),
    }
}

/// A [`key`] of the pipe's sizes and materials (given per section in a string of sections).
const fn pipe(spec: ParameterSpec, stages: &'static [Stage], value: fn(&Problem) -> f64) -> Key {
    Key {
        per_section: true,
        ..key(spec, stages, value)
    }
}

/// A key that enters no numerical stage's matrices (a limit, a reference value, an output).
const fn plain(spec: ParameterSpec, omitted: Omitted) -> Key {
    Key {
        spec,
        omitted,
        stages: &[],
        per_section: false,
        value: None,
    }
}

const fn closed(lo: f64, hi: f64, why: &'static str) -> Range {
    Range::closed(lo, hi, why)
}

/// The lowest feed that is drilling, m/h: the axial statistics are relative to V0 (a V0 of
/// 1e-300 m/h gave an axial velocity fluctuation of 1.7e288), and 0.1 m/h is slower than any
/// rock is drilled. 0 is off-bottom rotation, a state of its own.
pub const MIN_FEED_M_PER_H: f64 = 0.1;

/// Upper bound on the element count: far beyond any useful mesh, it keeps dense algebra bounded.
pub const MAX_ELEMENTS: usize = 2000;

use crate::model::parameters::{
    ANNULUS_DENSITY, BOREHOLE_RADIUS, FLUID_DENSITY, PIPE_DAMPING, PIPE_DENSITY,
    PIPE_STIFFNESS_DAMPING, PIPE_YOUNGS_MODULUS,
};
use crate::model::{
    AUTODRILLER_TIME_CONSTANT, POWER_LIMIT, TORQUE_LIMIT, WOB_LIMIT, WOB_SET_POINT,
};

/// The range of log₁₀ ā of an S-N curve's branches (stress range in MPa).
const LOG_A_RANGE: Range = closed(5.0, 40.0, "every published steel curve lies within it");
/// The range of an S-N curve's inverse slopes m.
const SLOPE_RANGE: Range = closed(
    1.0,
    30.0,
    "the inverse slopes of published curves are 3 to 5",
);

/// The problem file's scalar keys, in the order of a file. The parameters of the wall contact
/// and bit–rock laws are in each law's own table ([`crate::model::Law::parameters`]). Every
/// range is closed and its lower end excludes the values that make the model meaningless: each
/// says why its ends are where they are (the comments: what a value outside did).
pub static KEYS: [Key; 37] = [
    // Lower ends: a string of a few nanometres (or a pipe 2 nm across) is a typo, and the
    // element shape functions and the mass matrix lose their meaning long before 0 (a 1e-300 m
    // string panicked in the shape functions; a 1e-300 m radius made the mass matrix singular,
    // reported under `mesh.basis`).
    key(
        ParameterSpec::new(
            "model.length",
            Length,
            closed(
                1.0,
                15e3,
                "from a 1 m laboratory string to the longest wells, about 15 km",
            ),
            None,
            35.0,
            "the string's length L from the top drive to the bit (the sum of its sections')",
        ),
        ALL,
        |p| p.model.length,
    ),
    // A gravity of 1e-300 printed a 150-digit buckling figure (the figures scale as a power of
    // 1/g): 0 is a weightless test of the bare dynamics, else at least 0.1 m/s², below the
    // gravity of any body a string is drilled on (the Moon's is 1.6 m/s²).
    key(
        ParameterSpec::new(
            "model.gravity",
            Acceleration,
            Range::zero_or(
                0.1,
                30.0,
                "0 (weightless) or 0.1 m/s² to a few g; a tiny gravity inflates the buckling figures",
            ),
            Some(STANDARD_GRAVITY),
            STANDARD_GRAVITY,
            "gravity g, across the horizontal hole (0: a weightless string)",
        ),
        STATIC,
        |p| p.model.gravity,
    ),
    Key {
        omitted: Omitted::Else("required, unless [[model.section]] give the sizes (then refused)"),
        ..pipe(
            ParameterSpec::new(
                "model.pipe.outer_radius",
                Length,
                closed(1e-3, 1.0, "a pipe 2 mm to 2 m across"),
                None,
                0.0635,
                "the pipe's outer radius R_ext (per section: outer_radius or outer_diameter)",
            ),
            ALL,
            |p| p.model.pipe.outer_radius,
        )
    },
    // 0 is a solid bar; a bore below it is a solid bar too (continuous in the radius).
    Key {
        omitted: Omitted::Else("required, unless [[model.section]] give the sizes (then refused)"),
        ..pipe(
            ParameterSpec::new(
                "model.pipe.inner_radius",
                Length,
                closed(0.0, 1.0, "a pipe bore of at most 2 m"),
                None,
                0.0543,
                "the pipe's bore radius R_int, below R_ext (0: a solid bar; per section also \
             inner_diameter or linear_weight)",
            ),
            ALL,
            |p| p.model.pipe.inner_radius,
        )
    },
    pipe(PIPE_DENSITY, MASS, |p| p.model.pipe.density),
    pipe(PIPE_YOUNGS_MODULUS, STIFFNESS, |p| {
        p.model.pipe.youngs_modulus
    }),
    // ν = −1 makes the shear modulus E/(2(1 + ν)) infinite and ν = 0.5 is incompressible.
    pipe(
        ParameterSpec::new(
            "model.pipe.poisson_ratio",
            Dimensionless,
            closed(
                -0.9,
                0.499,
                "from auxetic foams to nearly incompressible solids; −1 makes the shear modulus infinite",
            ),
            None,
            0.29,
            "Poisson's ratio ν (shear modulus G = E/(2(1 + ν)))",
        ),
        STIFFNESS,
        |p| p.model.pipe.poisson_ratio,
    ),
    // A factor of 1e-300 removed the shear (torsional) stiffness and failed in the eigen-solve
    // naming other keys. Cowper's factor of a thin-walled tube is about 0.5 (0.15 at ν = −0.9),
    // of a solid bar about 0.9.
    Key {
        omitted: Omitted::Else("\"cowper\": Cowper's factor of the section's radii and ν"),
        ..pipe(
            ParameterSpec::new(
                "model.pipe.shear_factor",
                Dimensionless,
                closed(
                    0.1,
                    1.0,
                    "a shear correction factor; Cowper's is 0.5 for a thin tube, 0.9 for a solid bar",
                ),
                None,
                0.53,
                "the shear correction factor κ_s of the Timoshenko beam (a number, or \"cowper\")",
            ),
            STIFFNESS,
            |p| p.model.pipe.shear_factor,
        )
    },
    pipe(
        ParameterSpec::new(
            "model.pipe.torsion_factor",
            Dimensionless,
            closed(
                0.1,
                1.0,
                "a torsional stiffness factor κ_t; the paper takes it equal to the shear factor",
            ),
            Some(1.0),
            1.0,
            "the torsional stiffness factor κ_t, GJκ_t (a number, or \"shear\" for κ_t = κ_s)",
        ),
        STIFFNESS,
        |p| p.model.pipe.torsion_factor,
    ),
    // The stresses are reported relative to it (1e-300 printed a 300-digit utilisation).
    plain(
        ParameterSpec::new(
            "model.pipe.yield_strength",
            Pressure,
            closed(
                10e6,
                3e9,
                "from a polymer pipe's 10 MPa to the strongest steels, 3 GPa",
            ),
            None,
            931e6,
            "the pipe's minimum yield strength (or an API 5DP grade: \"E-75\", \"X-95\", \
             \"G-105\", \"S-135\"): the reference of von_mises_safety_factor",
        ),
        Omitted::Else("none: the metrics relative to it are not computed"),
    ),
    // The S-N curve of the fatigue damage, `[model.pipe.fatigue]`: by name (`sn_curve`, a word)
    // or by these parameters; every published steel curve lies within the ranges.
    plain(
        ParameterSpec::new(
            "model.pipe.fatigue.log_a1",
            Dimensionless,
            LOG_A_RANGE,
            None,
            12.164,
            "log₁₀ ā₁ of the S-N curve N = ā₁ Δσ^(−m₁), Δσ in MPa (DNV-RP-C203)",
        ),
        Omitted::Else("required with m1 when the curve is given by its parameters"),
    ),
    plain(
        ParameterSpec::new(
            "model.pipe.fatigue.m1",
            Dimensionless,
            SLOPE_RANGE,
            None,
            3.0,
            "the inverse slope m₁ of the curve's first branch",
        ),
        Omitted::Else("required with log_a1 when the curve is given by its parameters"),
    ),
    plain(
        ParameterSpec::new(
            "model.pipe.fatigue.log_a2",
            Dimensionless,
            LOG_A_RANGE,
            None,
            15.606,
            "log₁₀ ā₂ of the branch beyond the knee",
        ),
        Omitted::Else("none: one branch (with m2 or not at all)"),
    ),
    plain(
        ParameterSpec::new(
            "model.pipe.fatigue.m2",
            Dimensionless,
            SLOPE_RANGE,
            None,
            5.0,
            "the inverse slope m₂ of the branch beyond the knee, greater than m1",
        ),
        Omitted::Else("none: one branch (with log_a2 or not at all)"),
    ),
    plain(
        ParameterSpec::new(
            "model.pipe.fatigue.endurance_limit",
            Pressure,
            closed(
                0.0,
                2e9,
                "0 (no cut-off, DNV's variable-amplitude reading) to beyond any steel's strength",
            ),
            None,
            52.63e6,
            "the stress range below which cycles do no damage",
        ),
        Omitted::Else(
            "the named curve's fatigue limit at 1e7 cycles, or the range at 1e7 cycles of a curve given by its parameters",
        ),
    ),
    plain(
        ParameterSpec::new(
            "model.pipe.fatigue.stress_concentration",
            Dimensionless,
            closed(
                1.0,
                20.0,
                "a stress concentration factor; a tool joint's is 1.5 to 3",
            ),
            Some(1.0),
            1.0,
            "the factor every stress range is multiplied by",
        ),
        Omitted::Default,
    ),
    key(PIPE_DAMPING, DYNAMIC, |p| p.model.damping),
    key(PIPE_STIFFNESS_DAMPING, DYNAMIC, |p| {
        p.model.stiffness_damping
    }),
    key(FLUID_DENSITY, MASS, |p| p.model.fluid_density),
    key(ANNULUS_DENSITY, MASS, |p| p.model.annulus_density),
    Key {
        omitted: Omitted::Else("required, unless diameter gives it"),
        ..key(BOREHOLE_RADIUS, STATIC, |p| p.model.borehole_radius)
    },
    // The wall law's own parameters are in its table; how its friction acts is the wall's.
    plain(
        ParameterSpec::new(
            "model.wall.slip_smoothing",
            WallFriction::SLIP_SMOOTHING_DIMENSION,
            WallFriction::SLIP_SMOOTHING_RANGE,
            Some(WallFriction::DEFAULT_SLIP_SMOOTHING),
            WallFriction::DEFAULT_SLIP_SMOOTHING,
            "ε of the Coulomb wall friction's smooth slip magnitude √(|s|² + ε²) (friction_law = \
             \"coulomb\", the default, only)",
        ),
        Omitted::Default,
    ),
    key(
        ParameterSpec::new(
            "model.bit.inertia",
            MomentOfInertia,
            closed(
                0.0,
                1e3,
                "at most 1000 kg·m² (a 12¼ in bit is about 1 kg·m², a whole BHA tens to hundreds)",
            ),
            Some(0.0),
            0.4,
            "the polar inertia of the bit and what turns with it below the last node, lumped \
             on the bit's spin (0: the paper's model)",
        ),
        INERTIA,
        |p| p.model.bit_inertia,
    ),
    key(
        ParameterSpec::new(
            "mesh.elements",
            Dimensionless,
            Range::integer(
                1.0,
                MAX_ELEMENTS as f64,
                "far beyond any useful mesh: it keeps the dense algebra bounded",
            ),
            None,
            105.0,
            "the number N of two-node beam elements, 6(N + 1) degrees of freedom",
        ),
        ALL,
        |p| p.mesh.elements as f64,
    ),
    key(
        ParameterSpec::new(
            "operating_point.omega",
            AngularVelocity,
            closed(
                crate::units::from_rpm(1.0),
                crate::units::from_rpm(1000.0),
                "1 to 1000 rpm: the stick-slip statistics are relative to Ω",
            ),
            None,
            std::f64::consts::TAU,
            "the top drive's rotation speed Ω",
        ),
        DYNAMIC,
        |p| p.operating_point.omega,
    ),
    Key {
        omitted: Omitted::Else("required unless top = \"hook_load\" (refused with it)"),
        ..key(
            ParameterSpec::new(
                "operating_point.v0",
                Velocity,
                Range::zero_or(
                    crate::units::from_m_per_h(MIN_FEED_M_PER_H),
                    crate::units::from_m_per_h(1000.0),
                    "0 is off-bottom rotation; else from 0.1 m/h, slower than any rock is drilled, to at most 1000 m/h",
                ),
                None,
                5.0 / 3600.0,
                "the feed V0: the top's imposed axial velocity (the autodriller's set-point)",
            ),
            DYNAMIC,
            |p| p.operating_point.v0,
        )
    },
    plain(
        WOB_SET_POINT,
        Omitted::Else("required with top = \"hook_load\", refused with another top"),
    ),
    plain(
        WOB_LIMIT,
        Omitted::Else("required with top = \"autodriller\", refused with another top"),
    ),
    plain(
        TORQUE_LIMIT,
        Omitted::Else("none (top = \"autodriller\" only)"),
    ),
    plain(
        POWER_LIMIT,
        Omitted::Else("none (top = \"autodriller\" only)"),
    ),
    plain(AUTODRILLER_TIME_CONSTANT, Omitted::Default),
    plain(
        ParameterSpec::new(
            "campbell.excitation_multiple",
            Dimensionless,
            closed(
                1.0,
                50.0,
                "1× to 50× the rotation frequency: 3 for a tri-cone bit, the blade count of a PDC bit",
            ),
            Some(3.0),
            3.0,
            "the second excitation line K×Ω of the Campbell diagram and critical_speed_margin",
        ),
        Omitted::Else("the bit's `model.bit.blades` under a depth-of-cut law (`rgd`), else 3"),
    ),
    // Depth of cut per revolution 2π V0/Ω: a limit below 1 µm is finer than any cutter's edge,
    // above 10 cm taller than any cutter (PDC cutters are 8-19 mm).
    plain(
        ParameterSpec::new(
            "constraints.max_depth_of_cut",
            Length,
            closed(
                1e-6,
                0.1,
                "a depth of cut per revolution from 1 µm to 10 cm",
            ),
            None,
            5e-3,
            "the largest depth of cut per revolution 2π V0/Ω: a linear limit on (Ω, V0)",
        ),
        Omitted::Else("none"),
    ),
    // At least the shortest time step: `--duration 1e-300` took no step and failed naming no
    // key; a run of one step ends with its metrics refused, said so.
    key(
        ParameterSpec::new(
            "simulation.duration",
            Time,
            closed(
                1e-6,
                86_400.0,
                "at least the shortest time step, 1 µs, at most a day of simulated time",
            ),
            None,
            90.0,
            "the simulated time of a run",
        ),
        &[Step],
        |p| p.simulation.duration,
    ),
    key(
        ParameterSpec::new(
            "simulation.time_step",
            Time,
            closed(1e-6, 1.0, "a nominal step between 1 µs and 1 s"),
            None,
            0.069,
            "the nominal (largest) step, never above 1/20 of the lowest torsional and axial periods",
        ),
        &[Step],
        |p| p.simulation.time_step,
    ),
    plain(
        ParameterSpec::new(
            "simulation.settling_time",
            Time,
            closed(
                0.0,
                43_200.0,
                "at most half the duration, so that the analysis window is never shorter than what it discards",
            ),
            Some(0.0),
            10.0,
            "the time discarded before the metrics' analysis window starts",
        ),
        Omitted::Default,
    ),
    plain(
        ParameterSpec::new(
            "simulation.sample_interval",
            Time,
            closed(
                1e-6,
                1.0,
                "an output interval between 1 µs and 1 s (or \"step\": every accepted step)",
            ),
            Some(5e-4),
            5e-4,
            "the interval of simulate's written time history (or \"step\"); no metric depends on it",
        ),
        Omitted::Default,
    ),
];

/// Standard gravity, m/s², when the file omits `model.gravity`.
pub const STANDARD_GRAVITY: f64 = 9.81;

/// The row of `key` in [`KEYS`].
pub fn find(key: &str) -> Option<&'static Key> {
    KEYS.iter().find(|r| r.spec.key == key)
}

/// The admissible range of a problem-file key of [`KEYS`]. The operating point's ranges are
/// also those of the bounds of `[constraints]`, of `optimizer.start` and of the command line's
/// `--omega`, `--v0`, `--point` and `--duration`. The parameters of the wall contact and bit–rock
/// laws are checked against the law's own table.
pub fn range_of(key: &str) -> Option<Range> {
    find(key).map(|r| r.spec.range)
}

/// The dimension of a problem-file key of [`KEYS`] (for the range a message gives); `None` for
/// other keys.
pub fn dimension_of(key: &str) -> Option<Dimension> {
    find(key).map(|r| r.spec.dimension)
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

/// The value of `key` with its unit, as a message shows it ([`display_unit`]).
pub fn shown(key: &str, value: f64, dimension: Dimension) -> String {
    let (unit, factor) = display_unit(key, dimension);
    if matches!(dimension, Dimensionless) || unit.is_empty() {
        digits(value / factor)
    } else {
        format!("{} {unit}", digits(value / factor))
    }
}

/// The unit a key's values and range are shown in, and its size in SI: the operating point in
/// the driller's rpm and m/h (`omega = "1e-300 rpm"` was refused as "must be in
/// [0.10471975511965977, 104.71975511965977] rad/s … got 1.0471975511965978e-301 rad/s"), every
/// other key in SI (the laws' smoothing speeds too). Refusals, the error hints, `drillopt keys`
/// and the command line's help all show a key in this unit.
pub fn display_unit(key: &str, dimension: Dimension) -> (&'static str, f64) {
    match (key, dimension) {
        ("operating_point.omega", _) => ("rpm", crate::units::from_rpm(1.0)),
        ("operating_point.v0", _) => ("m/h", crate::units::from_m_per_h(1.0)),
        (_, Dimensionless) => ("", 1.0),
        _ => (dimension.si_unit(), 1.0),
    }
}

/// The keys that enter `stage`, in table order: (key, value with its unit). The pipe's keys of a
/// string of sections are named once, as its sections' (`model.section[*]`).
pub fn entering(problem: &Problem, stage: Stage) -> Vec<(String, String)> {
    let sections = !problem.model.sections.is_empty();
    let mut out: Vec<(String, String)> = Vec::new();
    let mut named_sections = false;
    for r in KEYS.iter().filter(|r| r.stages.contains(&stage)) {
        let Some(value) = r.value else { continue };
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
        let (key, value) = as_given(problem, r.spec.key, value(problem));
        out.push((key, shown(r.spec.key, value, r.spec.dimension)));
    }
    let (wall, bit) = laws_enter(stage);
    let laws: [(bool, &dyn Law); 2] = [
        (wall, problem.model.wall.law()),
        (bit, problem.model.bit.law()),
    ];
    for (enters, law) in laws {
        if enters {
            for (i, spec) in law.parameters().iter().enumerate() {
                let (key, value) = as_given(problem, spec.key, law.value(i));
                out.push((key, shown(spec.key, value, spec.dimension)));
            }
        }
    }
    out
}

/// A radius the file gave by its diameter (`[model.borehole]`, `[model.bit]`: the size as drillers
/// type it), named and valued as the file gave it; any other key as it is.
fn as_given(problem: &Problem, key: &str, value: f64) -> (String, f64) {
    match key.strip_suffix(".radius") {
        Some(table @ ("model.borehole" | "model.bit")) if gives(problem, table, "diameter") => {
            (format!("{table}.diameter"), 2.0 * value)
        }
        _ => (key.to_string(), value),
    }
}

/// Whether the problem file's text gives `key` in its table `table` ("model.bit").
fn gives(problem: &Problem, table: &str, key: &str) -> bool {
    let Ok(doc) = problem.text.parse::<toml::Table>() else {
        return false;
    };
    let mut t = &doc;
    for part in table.split('.') {
        match t.get(part).and_then(toml::Value::as_table) {
            Some(inner) => t = inner,
            None => return false,
        }
    }
    t.contains_key(key)
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

    /// A hole and a bit the file gave by their diameters are named so, with the diameters.
    #[test]
    fn a_size_given_as_a_diameter_is_named_as_given() {
        let text = include_str!("../../problems/seed_detournay.toml")
            .replace(
                "[model.borehole]\nradius = \"70 mm\"",
                "[model.borehole]\ndiameter = \"140 mm\"",
            )
            .replace(
                "radius = \"70 mm\"                # a: the bit drills the 70 mm-radius hole",
                "diameter = \"0.13 m\"",
            );
        let p = Problem::from_toml(&text, Path::new("d.toml")).unwrap();
        let keys = describe_entering(&p, Start);
        for (named, unnamed) in [
            (
                "`model.borehole.diameter` = 0.14 m",
                "model.borehole.radius",
            ),
            ("`model.bit.diameter` = 0.13 m", "model.bit.radius"),
        ] {
            assert!(keys.contains(named), "{named} missing: {keys}");
            assert!(!keys.contains(unnamed), "{unnamed} named: {keys}");
        }
        // Given by its radius, the radius.
        let p = Problem::from_toml(
            include_str!("../../problems/seed_detournay.toml"),
            Path::new("r.toml"),
        )
        .unwrap();
        let keys = describe_entering(&p, Start);
        assert!(keys.contains("`model.bit.radius` = 0.07 m"), "{keys}");
        assert!(keys.contains("`model.borehole.radius` = 0.07 m"), "{keys}");
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
        // The element count is a whole number.
        assert!(range_of("mesh.elements").unwrap().contains(105.0));
        assert!(!range_of("mesh.elements").unwrap().contains(10.5));
    }
}
