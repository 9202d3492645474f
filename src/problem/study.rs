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
    /// `[uncertain.sequential]`: the samples per point chosen by a stopping rule, `samples`
    /// being the most a point may use.
    pub sequential: Option<RawSequential>,
}

/// `[uncertain.sequential]` as written.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawSequential {
    pub min_samples: i64,
    pub score_half_width: f64,
    pub confidence: Option<f64>,
    pub resamples: Option<i64>,
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
    /// In the metric's unit or with a unit of its dimension (its row of the metric catalogue,
    /// [`crate::metrics::MetricSpec::unit`]).
    pub threshold: Option<RawQuantity>,
    pub weight: f64,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ConstraintsSection {
    pub omega: Vec<RawQuantity>,
    /// Bounds of the feed set-point (tops `feed`, `autodriller`).
    pub v0: Option<Vec<RawQuantity>>,
    /// Bounds of the hook load's WOB set-point (top `hook_load`).
    pub wob: Option<Vec<RawQuantity>>,
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
    /// Coefficient of V0 (feed tops), per m/s.
    pub v0: Option<f64>,
    /// Coefficient of the WOB (hook load), per N.
    pub wob: Option<f64>,
    pub upper: f64,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawChance {
    pub metric: String,
    /// In the metric's unit or with a unit of its dimension (its row of the metric catalogue,
    /// [`crate::metrics::MetricSpec::unit`]).
    pub threshold: RawQuantity,
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
    pub initial_design: Option<i64>,
    pub ego_share: Option<f64>,
    /// `[optimizer.explore]`: the cheap fidelity of a multi-fidelity solve.
    pub explore: Option<RawExplore>,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ExpectSection {
    pub omega: Vec<RawQuantity>,
    /// The feed set-point's range (feed tops).
    pub v0: Option<Vec<RawQuantity>>,
    /// The WOB set-point's range (hook load).
    pub wob: Option<Vec<RawQuantity>>,
    pub objective: Option<Vec<f64>>,
    pub reason: String,
    /// The constraints that hold the expected optimum: `"omega.min"`, `"omega.max"`, `"v0.min"`,
    /// `"v0.max"` (`"wob.min"`, `"wob.max"` under a hook load), `"max_depth_of_cut"`,
    /// `"chance.<metric>"`; `[]` for none.
    pub active: Option<Vec<String>>,
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

impl Quantity {
    /// The metric the score is a statistic of (its `summary.json` key).
    pub fn metric(self) -> &'static str {
        match self {
            Quantity::Rop => "mean_rop_m_per_h",
            Quantity::Efficiency => "efficiency",
        }
    }
}

/// A weighted risk term: weight · statistic(metric) is subtracted from the score.
#[derive(Debug, Clone, PartialEq)]
pub struct RiskTerm {
    pub metric: String,
    pub statistic: Statistic,
    pub weight: f64,
}

/// P(metric > threshold) ≤ max_probability, the threshold in the metric's unit (its key's:
/// [`crate::metrics::MetricSpec::unit`]).
#[derive(Debug, Clone, PartialEq)]
pub struct ChanceConstraint {
    pub metric: String,
    pub threshold: f64,
    pub max_probability: f64,
}

/// a_Ω Ω + a_s s ≤ upper (Ω in rad/s; the set-point s in SI: V0 in m/s, or the WOB in N).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinearConstraint {
    pub omega: f64,
    /// a_s, per unit of the set-point (per m/s or per N).
    pub set_point: f64,
    pub upper: f64,
    /// Where it came from, for reports (e.g. "max_depth_of_cut").
    pub label: &'static str,
}

/// Bounds and linear constraints on (Ω, set-point), plus chance constraints on metrics.
#[derive(Debug, Clone, PartialEq)]
pub struct Constraints {
    /// [min, max] of Ω, rad/s.
    pub omega: [f64; 2],
    /// What the second design variable is (the problem's top decides: V0 or the WOB).
    pub kind: crate::model::SetPoint,
    /// [min, max] of the set-point, SI (V0 in m/s, the WOB in N).
    pub set_point: [f64; 2],
    pub linear: Vec<LinearConstraint>,
    pub chance: Vec<ChanceConstraint>,
}

// The [optimizer] section: one settings struct (and builder) per method.
mod explore;
mod optimizer;
pub use explore::{
    CONFIRM, CONFIRM_RANGE, Explore, MARGIN_RANGE, MAX_CONFIRM_RANGE, MAX_CONFIRM_ROUNDS,
    REFINE_RANGE, RawExplore, SEPARATION, SEPARATION_RANGE,
};
pub use optimizer::{
    EgoSettings, EgoSettingsBuilder, EgoTrustRegionSettings, EgoTrustRegionSettingsBuilder,
    GRID_POINTS, GridSettings, GridSettingsBuilder, INITIAL_DESIGN, LocalSearchSettings,
    LocalSearchSettingsBuilder, MAX_EVALUATIONS, Method, NelderMeadSettings, OptimizerSettings,
    ParticleSwarmSettings, ParticleSwarmSettingsBuilder, SettingsError, TrustRegionSettings,
};

/// A constraint that holds a regression problem's expected optimum (`[expect] active`).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum ActiveConstraint {
    /// The lower bound of Ω (`"omega.min"`).
    OmegaMin,
    /// The upper bound of Ω (`"omega.max"`).
    OmegaMax,
    /// The lower bound of the set-point (`"v0.min"`, `"wob.min"`).
    SetPointMin,
    /// The upper bound of the set-point (`"v0.max"`, `"wob.max"`).
    SetPointMax,
    /// A linear constraint, by its label (`"max_depth_of_cut"`).
    Linear(&'static str),
    /// A chance constraint, by its metric (`"chance.buckling_utilization"`).
    Chance(String),
}

impl ActiveConstraint {
    /// Its name in `[expect] active` under the set-point `kind` (`"v0.max"`, or `"wob.max"`).
    pub fn name(&self, kind: crate::model::SetPoint) -> String {
        match self {
            ActiveConstraint::OmegaMin => "omega.min".into(),
            ActiveConstraint::OmegaMax => "omega.max".into(),
            ActiveConstraint::SetPointMin => format!("{}.min", kind.key()),
            ActiveConstraint::SetPointMax => format!("{}.max", kind.key()),
            ActiveConstraint::Linear(label) => (*label).to_string(),
            ActiveConstraint::Chance(metric) => format!("chance.{metric}"),
        }
    }
}

/// The optimum a regression problem is known to have: Ω in rad/s, the set-point in SI (V0 in
/// m/s or the WOB in N, by [`Constraints::kind`]), the score in the objective's unit, each a
/// closed range [min, max].
#[derive(Debug, Clone, PartialEq)]
pub struct Expect {
    pub omega: [f64; 2],
    pub set_point: [f64; 2],
    pub objective: Option<[f64; 2]>,
    pub reason: String,
    /// The constraints that hold the optimum, as declared (`None`: not declared; empty: an
    /// unconstrained optimum). Checked against the ranges: a bound is declared active exactly
    /// when the expected range reaches it.
    pub active: Option<Vec<ActiveConstraint>>,
}

/// Sequential sampling (`[uncertain.sequential]`): each point starts with `min_samples`
/// samples and doubles them (at most [`Study::samples`]) while the bootstrap confidence
/// interval of its score is wider than ± `score_half_width` (see [`crate::study::sequential`]).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Sequential {
    /// Samples every point starts with; in [2, `samples` − 1].
    pub min_samples: usize,
    /// Target half-width of the score's confidence interval, in the score's unit (m/h for
    /// `quantity = "rop"`, 1 for efficiency); finite, > 0.
    pub score_half_width: f64,
    /// Confidence level of the interval; in [0.5, 0.999], default [`CONFIDENCE`].
    pub confidence: f64,
    /// Bootstrap resamples per interval; in [`RESAMPLES_RANGE`], default [`RESAMPLES`].
    pub resamples: usize,
}

/// Confidence level of the score's interval when the file does not give one (and of the
/// interval reported with a fixed sample count).
pub const CONFIDENCE: f64 = 0.95;
/// Largest `uncertain.sequential.score_half_width` (in the score's unit).
pub const SCORE_HALF_WIDTH_MAX: f64 = 1e6;
/// Legal range of `uncertain.sequential.confidence`.
pub const CONFIDENCE_RANGE: std::ops::RangeInclusive<f64> = 0.5..=0.999;
/// Bootstrap resamples of the score's interval when the file does not say.
pub const RESAMPLES: usize = 2000;
/// Legal range of `uncertain.sequential.resamples`.
pub const RESAMPLES_RANGE: std::ops::RangeInclusive<usize> = 200..=100_000;

/// How the confidence interval of a score is estimated: level and bootstrap resamples.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ScoreInterval {
    pub confidence: f64,
    pub resamples: usize,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Study {
    pub uncertain: Vec<UncertainParameter>,
    /// Monte Carlo samples per design point (1 and no parameters: deterministic); with
    /// `sequential`, the most a point may use.
    pub samples: usize,
    /// Sequential sampling; None: every point uses `samples` samples.
    pub sequential: Option<Sequential>,
    pub seed: u64,
    pub quantity: Quantity,
    /// Statistic of the quantity (a gain: mean, lower_cvar, quantile, min).
    pub statistic: Statistic,
    pub risk: Vec<RiskTerm>,
    pub constraints: Option<Constraints>,
    pub optimizer: OptimizerSettings,
    /// `[optimizer.explore]`: multi-fidelity `solve` (None: every evaluation at full fidelity).
    pub explore: Option<Explore>,
    pub expect: Option<Expect>,
    /// What the command line changed (`--samples`, `--budget`, `--threads`); none when read.
    pub overrides: Overrides,
}

/// Legal range of Monte Carlo samples per point (`uncertain.samples`, `--samples`).
pub const SAMPLES: std::ops::RangeInclusive<usize> = 1..=10_000;
/// Legal range of `--threads`.
pub const THREADS: std::ops::RangeInclusive<usize> = 1..=1024;

/// Command-line overrides of a study, recorded in every study report's header (`overrides`) so
/// that a result says what ran; `None`: the problem file's value (threads: all cores, or
/// `RAYON_NUM_THREADS`). None of them enters the evaluation-cache key: a simulation depends on
/// the point, the sample's index and seed and the model, not on how many samples, design
/// points or threads a run has (sample i is the same draw whatever the number of samples).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize)]
pub struct Overrides {
    /// Monte Carlo samples per point, instead of `uncertain.samples`.
    pub samples: Option<usize>,
    /// Design points of the optimizer, instead of `optimizer.max_evaluations` (solve only).
    pub budget: Option<usize>,
    /// Threads that run the simulations.
    pub threads: Option<usize>,
}

impl Study {
    /// The metrics the score and the constraints are made of: the quantity's, every risk term's
    /// and every chance constraint's, in that order (repeats kept).
    pub fn metrics_named(&self) -> Vec<&str> {
        let chance = self.constraints.iter().flat_map(|k| &k.chance);
        std::iter::once(self.quantity.metric())
            .chain(self.risk.iter().map(|r| r.metric.as_str()))
            .chain(chance.map(|c| c.metric.as_str()))
            .collect()
    }

    /// The level and resamples of the score's confidence interval: the sequential rule's, else
    /// the defaults ([`CONFIDENCE`], [`RESAMPLES`]).
    pub fn score_interval(&self) -> ScoreInterval {
        self.sequential.map_or(
            ScoreInterval {
                confidence: CONFIDENCE,
                resamples: RESAMPLES,
            },
            |s| ScoreInterval {
                confidence: s.confidence,
                resamples: s.resamples,
            },
        )
    }

    /// Use `n` Monte Carlo samples per point instead of `uncertain.samples`, under the key's
    /// rules: `n` in [`SAMPLES`], more than one only with uncertain parameters, and, with
    /// sequential sampling, more than `min_samples` (`n` is then the most a point may use). Err:
    /// what is allowed, in words.
    pub fn override_samples(&mut self, n: usize) -> Result<(), String> {
        if !SAMPLES.contains(&n) {
            return Err(format!("must be an integer in [1, 10000], got {n}"));
        }
        if n > 1 && self.uncertain.is_empty() {
            return Err(format!(
                "the problem has no [[uncertain.parameter]], so the {n} samples would all be the same; declare one or use 1"
            ));
        }
        if let Some(e) = self.explore.as_ref().and_then(|e| e.samples)
            && n <= e
        {
            return Err(format!(
                "must exceed optimizer.explore.samples = {e}, the explore fidelity's samples per point (the full fidelity must be the richer one), got {n}"
            ));
        }
        if let Some(s) = &self.sequential
            && n <= s.min_samples
        {
            return Err(format!(
                "with [uncertain.sequential] it is the most samples a point may use and must exceed uncertain.sequential.min_samples = {}, got {n}",
                s.min_samples
            ));
        }
        self.samples = n;
        self.overrides.samples = Some(n);
        Ok(())
    }

    /// The first of this study's draws (samples 0..`samples` under `seed`) outside its
    /// parameter's admissible range in `model`, if any: checked at load, and again when
    /// `--samples` draws more.
    pub fn inadmissible_draw(&self, model: &crate::model::Drillstring) -> Option<InadmissibleDraw> {
        inadmissible_draw(&self.uncertain, self.samples, self.seed, model)
    }

    /// Evaluate at most `n` design points instead of `optimizer.max_evaluations`, under the
    /// key's rules (see [`OptimizerSettings::with_max_evaluations`]).
    pub fn override_budget(&mut self, n: usize) -> Result<(), SettingsError> {
        self.optimizer = self.optimizer.with_max_evaluations(n)?;
        self.overrides.budget = Some(n);
        Ok(())
    }
}

/// A value drawn by a study's samples outside its parameter's admissible range.
#[derive(Debug, Clone, PartialEq)]
pub struct InadmissibleDraw {
    /// Index of the uncertain parameter (`uncertain.parameter[i]`).
    pub parameter: usize,
    pub key: &'static str,
    pub sample: usize,
    pub value: f64,
    /// What is allowed, in words ("must be in [1000, 5e6] N (…)").
    pub why: String,
}

impl std::fmt::Display for InadmissibleDraw {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "sample {} draws {} = {}, which is not admissible: it {}",
            self.sample,
            self.key,
            crate::units::show(self.value),
            self.why
        )
    }
}

/// The first value that samples 0..`samples` under `seed` (the draws the study makes, see
/// [`crate::stats::SampleSet`]) give a parameter outside its admissible range in `model`, if
/// any. The laws must have passed [`crate::stats::Distribution::validate`]. Cheap: 10 000
/// samples of a few laws draw in milliseconds.
pub fn inadmissible_draw(
    params: &[UncertainParameter],
    samples: usize,
    seed: u64,
    model: &crate::model::Drillstring,
) -> Option<InadmissibleDraw> {
    let laws: Vec<crate::stats::Distribution> = params.iter().map(|p| p.law).collect();
    if laws.is_empty() {
        return None;
    }
    (0..samples).find_map(|i| {
        let sample = crate::stats::Sample::draw(&laws, i, seed);
        params
            .iter()
            .zip(&sample.values)
            .enumerate()
            .find_map(|(j, (p, &value))| {
                p.key
                    .admissible(model, value)
                    .err()
                    .map(|why| InadmissibleDraw {
                        parameter: j,
                        key: p.key.name(),
                        sample: i,
                        value,
                        why,
                    })
            })
    })
}
