//! The problem file's model tables as written (the whole file is [`super::file::ProblemFile`],
//! the study's tables [`super::study`]): serde structs that mirror the TOML, nothing checked but
//! the shape.
//!
//! Every table denies unknown keys, so a misspelled key is an error rather than a silent default.
//! Dimensional values are [`RawQuantity`]: a bare number in SI units or a string with a unit.
//! [`super::validate`] turns these into the runtime structs of [`crate::model`].

use serde::Deserialize;
use serde::de::{self, Deserializer, Visitor};
use std::fmt;

/// A value as written: a number (SI units) or a string such as `"60 rpm"`, `"cowper"`.
#[derive(Debug, Clone, PartialEq)]
pub enum RawQuantity {
    Number(f64),
    Text(String),
}

impl<'de> Deserialize<'de> for RawQuantity {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct QuantityVisitor;
        impl Visitor<'_> for QuantityVisitor {
            type Value = RawQuantity;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str("a number in SI units or a string with a unit such as \"60 rpm\"")
            }
            fn visit_f64<E: de::Error>(self, v: f64) -> Result<RawQuantity, E> {
                Ok(RawQuantity::Number(v))
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<RawQuantity, E> {
                Ok(RawQuantity::Number(v as f64))
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<RawQuantity, E> {
                Ok(RawQuantity::Number(v as f64))
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<RawQuantity, E> {
                Ok(RawQuantity::Text(v.to_string()))
            }
        }
        deserializer.deserialize_any(QuantityVisitor)
    }
}

/// `[campbell]`: the excitation the critical speeds are sought against.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CampbellSection {
    /// The bit's multiple of the rotation frequency (3 for a tri-cone bit).
    pub excitation_multiple: Option<RawQuantity>,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ModelSection {
    pub length: RawQuantity,
    pub gravity: Option<RawQuantity>,
    pub pipe: PipeSection,
    pub fluid: FluidSection,
    pub borehole: BoreholeSection,
    pub wall: LawSection,
    pub bit: LawSection,
    /// `[[model.section]]`: the string's sections, top drive to bit (none: one section of
    /// `[model.pipe]`).
    #[serde(default)]
    pub section: Vec<SectionTable>,
}

/// One `[[model.section]]`: its name and length, its outer and inner size (radius or
/// diameter), and material keys that default to `[model.pipe]`'s.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SectionTable {
    pub name: Option<String>,
    pub length: Option<RawQuantity>,
    pub outer_radius: Option<RawQuantity>,
    pub outer_diameter: Option<RawQuantity>,
    pub inner_radius: Option<RawQuantity>,
    pub inner_diameter: Option<RawQuantity>,
    /// The pipe body's mass per length (its plain-end weight), instead of the inner size.
    pub linear_weight: Option<RawQuantity>,
    pub density: Option<RawQuantity>,
    pub youngs_modulus: Option<RawQuantity>,
    pub poisson_ratio: Option<RawQuantity>,
    pub shear_factor: Option<RawQuantity>,
    pub torsion_factor: Option<RawQuantity>,
    pub yield_strength: Option<RawQuantity>,
    /// The section's share of the mesh (a graded mesh).
    pub elements: Option<i64>,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PipeSection {
    pub density: RawQuantity,
    pub youngs_modulus: RawQuantity,
    pub poisson_ratio: RawQuantity,
    /// The pipe's sizes: required for a string of one section, refused beside
    /// `[[model.section]]` (each section gives its own).
    pub inner_radius: Option<RawQuantity>,
    pub outer_radius: Option<RawQuantity>,
    pub damping: RawQuantity,
    /// Stiffness-proportional damping β (s): C = c M_pipe + β K.
    pub stiffness_damping: Option<RawQuantity>,
    pub shear_factor: Option<RawQuantity>,
    pub torsion_factor: Option<RawQuantity>,
    /// Minimum yield strength: a pressure (`"931 MPa"`) or an API 5DP grade (`"S-135"`).
    pub yield_strength: Option<RawQuantity>,
    /// `[model.pipe.fatigue]`: the S-N curve of the fatigue damage.
    pub fatigue: Option<FatigueSection>,
}

/// `[model.pipe.fatigue]`: a named S-N curve (`sn_curve = "DNV-B1"`) or its parameters
/// (`log_a1`, `m1` and optionally `log_a2`, `m2`), the endurance limit (a stress range) and a
/// stress concentration factor.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FatigueSection {
    pub sn_curve: Option<String>,
    pub log_a1: Option<RawQuantity>,
    pub m1: Option<RawQuantity>,
    pub log_a2: Option<RawQuantity>,
    pub m2: Option<RawQuantity>,
    pub endurance_limit: Option<RawQuantity>,
    pub stress_concentration: Option<RawQuantity>,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FluidSection {
    /// The drilling fluid inside the pipe.
    pub density: RawQuantity,
    /// The fluid in the annulus, outside the pipe (buoyancy); none when omitted.
    pub annulus_density: Option<RawQuantity>,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BoreholeSection {
    /// The hole's radius; or its `diameter` (the bit size, as drillers give it), not both.
    pub radius: Option<RawQuantity>,
    pub diameter: Option<RawQuantity>,
}

/// A table that names a law and gives its parameters (`[model.wall]`, `[model.bit]`), checked
/// against the law's own table ([`crate::model::wall::WALL_LAWS`], [`crate::model::bit::BIT_LAWS`])
/// in validation, so unknown keys are still refused.
///
/// Read key by key (not with a flattened map, whose errors name only the table: `diameter =
/// true` was refused under `model.bit`): a value that is neither a number nor a string is kept
/// in `invalid` for validation to refuse under its own key.
#[derive(Debug, Clone, Default)]
pub struct LawSection {
    /// The law's name; the registry's first (the seed paper's law) when omitted.
    pub law: Option<String>,
    /// Every other key of the table: the law's parameters by name.
    pub parameters: std::collections::BTreeMap<String, RawQuantity>,
    /// The keys whose value is neither a number nor a string, with what it was (`"boolean
    /// `true`"`), `law` among them when it is not a string.
    pub invalid: Vec<(String, String)>,
}

impl<'de> Deserialize<'de> for LawSection {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let table = std::collections::BTreeMap::<String, toml::Value>::deserialize(deserializer)?;
        let mut section = LawSection::default();
        for (key, value) in table {
            match (key.as_str(), value) {
                ("law", toml::Value::String(name)) => section.law = Some(name),
                ("law", other) => section.invalid.push((key, describe(&other))),
                (_, toml::Value::String(text)) => {
                    section.parameters.insert(key, RawQuantity::Text(text));
                }
                (_, toml::Value::Float(x)) => {
                    section.parameters.insert(key, RawQuantity::Number(x));
                }
                (_, toml::Value::Integer(i)) => {
                    section
                        .parameters
                        .insert(key, RawQuantity::Number(i as f64));
                }
                (_, other) => section.invalid.push((key, describe(&other))),
            }
        }
        Ok(section)
    }
}

/// What a TOML value is, for a refusal: "boolean `true`", "an array", "integer `5`".
fn describe(value: &toml::Value) -> String {
    match value {
        toml::Value::Boolean(b) => format!("boolean `{b}`"),
        toml::Value::Integer(i) => format!("integer `{i}`"),
        toml::Value::Float(x) => format!("float `{x}`"),
        toml::Value::Array(_) => "an array".to_string(),
        toml::Value::Table(_) => "a table".to_string(),
        other => format!("`{other}`"),
    }
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MeshSection {
    pub elements: i64,
    /// The paper's "N lowest modes"; exclusive with `basis`.
    pub reduced_modes: Option<i64>,
    /// Modes per family; when neither this nor `reduced_modes` is given, the default basis.
    pub basis: Option<BasisSection>,
}

/// `[mesh.basis]`: each family by count (an integer) or cutoff frequency (`"60 Hz"`).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BasisSection {
    pub bending: RawQuantity,
    pub torsional: RawQuantity,
    pub axial: RawQuantity,
    pub static_corrections: Option<bool>,
    pub steady_shapes: Option<bool>,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OperatingPointSection {
    pub omega: RawQuantity,
    /// The feed (tops `feed`, `autodriller`; required there, refused under a hook load).
    pub v0: Option<RawQuantity>,
    /// `"feed"` (default), `"hook_load"` or `"autodriller"` (MODEL.md §11.8).
    pub top: Option<RawQuantity>,
    /// The hook-load top's surface WOB set-point.
    pub wob: Option<RawQuantity>,
    /// The autodriller's surface WOB limit.
    pub wob_limit: Option<RawQuantity>,
    /// The autodriller's surface torque limit (none when absent).
    pub torque_limit: Option<RawQuantity>,
    /// The top drive's power rating: a torque limit P/Ω (none when absent).
    pub power_limit: Option<RawQuantity>,
    /// The autodriller's time constant τ.
    pub autodriller_time_constant: Option<RawQuantity>,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SimulationSection {
    pub duration: RawQuantity,
    pub time_step: RawQuantity,
    pub settling_time: Option<RawQuantity>,
    #[serde(default)]
    pub probes: Vec<RawQuantity>,
    /// `"preloaded"` (default) or `"unloaded"` (the paper's).
    pub start: Option<String>,
    /// Interval of the written time history: a time such as `"0.5 ms"`, or `"step"` (every
    /// accepted step); default 0.5 ms.
    pub sample_interval: Option<RawQuantity>,
}
