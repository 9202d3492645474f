//! The optimisation study of a problem file: uncertain parameters, the robust objective, the
//! constraints, the optimizer and the expected optimum (issue 4). Sections are optional: without
//! them a problem is deterministic, scored by its mean ROP, and cannot be solved (no bounds).
//!
//! Conventions: the score is MAXIMISED. For `quantity = "rop"` it is in m/h:
//! score = statistic(ROP in m/h) − Σ weight_k · statistic_k(metric_k), weights in m/h per unit of
//! the metric's statistic; for `quantity = "efficiency"` it is dimensionless. Metrics are those of
//! `summary.json` (MODEL.md §8), in SI units as named.

use super::schema::RawQuantity;
use crate::stats::Distribution;
use crate::stats::Statistic;
use serde::Deserialize;

// ---------------------------------------------------------------- raw (as written) ------------

#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct UncertainSection {
    pub samples: i64,
    pub seed: Option<i64>,
    #[serde(default)]
    pub parameter: Vec<RawParameter>,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawParameter {
    pub key: String,
    pub law: String,
    pub mean: Option<RawQuantity>,
    pub cov: Option<f64>,
    pub std: Option<RawQuantity>,
    pub low: Option<RawQuantity>,
    pub high: Option<RawQuantity>,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ObjectiveSection {
    pub quantity: Option<String>,
    pub statistic: Option<String>,
    pub level: Option<f64>,
    pub threshold: Option<f64>,
    #[serde(default)]
    pub risk: Vec<RawRisk>,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawRisk {
    pub metric: String,
    pub statistic: Option<String>,
    pub level: Option<f64>,
    pub threshold: Option<f64>,
    pub weight: f64,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ConstraintsSection {
    pub omega: Vec<RawQuantity>,
    pub v0: Vec<RawQuantity>,
    pub max_depth_of_cut: Option<RawQuantity>,
    #[serde(default)]
    pub linear: Vec<RawLinear>,
    #[serde(default)]
    pub chance: Vec<RawChance>,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawLinear {
    pub omega: f64,
    pub v0: f64,
    pub upper: f64,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawChance {
    pub metric: String,
    pub threshold: f64,
    pub max_probability: f64,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OptimizerSection {
    pub method: Option<String>,
    pub max_evaluations: Option<i64>,
    pub grid: Option<Vec<i64>>,
    pub start: Option<Vec<RawQuantity>>,
    pub initial_radius: Option<f64>,
    pub min_radius: Option<f64>,
    pub seed: Option<i64>,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ExpectSection {
    pub omega: Vec<RawQuantity>,
    pub v0: Vec<RawQuantity>,
    pub objective: Option<Vec<f64>>,
    pub reason: String,
}

// ---------------------------------------------------------------- validated -------------------

pub use crate::model::ParameterKey;

/// One uncertain parameter and its law (SI units).
#[derive(Debug, Clone, PartialEq)]
pub struct UncertainParameter {
    pub key: ParameterKey,
    pub law: Distribution,
}

/// What the score is a statistic of.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Quantity {
    /// Mean rate of penetration, m/h.
    Rop,
    /// Drilling efficiency, dimensionless.
    Efficiency,
}

/// A weighted risk term: weight · statistic(metric) is subtracted from the score.
#[derive(Debug, Clone, PartialEq)]
pub struct RiskTerm {
    pub metric: String,
    pub statistic: Statistic,
    pub weight: f64,
}

/// P(metric > threshold) ≤ max_probability.
#[derive(Debug, Clone, PartialEq)]
pub struct ChanceConstraint {
    pub metric: String,
    pub threshold: f64,
    pub max_probability: f64,
}

/// a_Ω Ω + a_V V0 ≤ upper (Ω in rad/s, V0 in m/s).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinearConstraint {
    pub omega: f64,
    pub v0: f64,
    pub upper: f64,
    /// Where it came from, for reports (e.g. "max_depth_of_cut").
    pub label: &'static str,
}

/// Bounds and linear constraints on (Ω, V0), plus chance constraints on metrics.
#[derive(Debug, Clone, PartialEq)]
pub struct Constraints {
    /// [min, max] of Ω, rad/s.
    pub omega: [f64; 2],
    /// [min, max] of V0, m/s.
    pub v0: [f64; 2],
    pub linear: Vec<LinearConstraint>,
    pub chance: Vec<ChanceConstraint>,
}

// The [optimizer] section: one settings struct (and builder) per method.
mod optimizer;
pub use optimizer::{
    GRID_POINTS, GridSettings, GridSettingsBuilder, LocalSearchSettings,
    LocalSearchSettingsBuilder, MAX_EVALUATIONS, Method, NelderMeadSettings, OptimizerSettings,
    ParticleSwarmSettings, ParticleSwarmSettingsBuilder, SettingsError, TrustRegionSettings,
};

/// The optimum a regression problem is known to have.
#[derive(Debug, Clone, PartialEq)]
pub struct Expect {
    pub omega: [f64; 2],
    pub v0: [f64; 2],
    pub objective: Option<[f64; 2]>,
    pub reason: String,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Study {
    pub uncertain: Vec<UncertainParameter>,
    /// Monte Carlo samples per design point (1 and no parameters: deterministic).
    pub samples: usize,
    pub seed: u64,
    pub quantity: Quantity,
    /// Statistic of the quantity (a gain: mean, lower_cvar, quantile, min).
    pub statistic: Statistic,
    pub risk: Vec<RiskTerm>,
    pub constraints: Option<Constraints>,
    pub optimizer: OptimizerSettings,
    pub expect: Option<Expect>,
}

/// Metric names a risk term or chance constraint may use (the keys of `summary.json`'s metrics).
pub const METRICS: [&str; 26] = [
    "mean_rop_m_s",
    "mean_rop_m_per_h",
    "stick_slip_severity",
    "stick_slip_severity_raw",
    "stick_fraction",
    "max_bit_speed_ratio",
    "bit_bounce_fraction",
    "axial_velocity_fluctuation",
    "impacts_per_s",
    "peak_wall_force_n",
    "contact_impulse_ns",
    "max_radial_over_gap",
    "mean_wob_n",
    "mean_tob_nm",
    "mse_pa",
    "efficiency",
    "axial_power_share",
    "energy_balance_residual",
    "max_von_mises_pa",
    "max_von_mises_at_m",
    "von_mises_safety_factor",
    "von_mises_utilization",
    "max_compression_n",
    "max_torque_nm",
    "critical_speed_margin",
    "critical_speed_proximity",
];
