//! `summary.json`, the report of one simulated operating point (`drillopt simulate`).

use super::ProblemRecord;
use serde::Serialize;

/// How a run ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum RunStatus {
    /// The whole window was simulated and its metrics computed.
    #[serde(rename = "completed")]
    Completed,
    /// The run stopped early; `error` says when and why (what was computed is kept).
    #[serde(rename = "failed")]
    Failed,
    /// The run finished but its metrics could not be computed (`metrics_error` says why).
    #[serde(rename = "no metrics")]
    NoMetrics,
    /// A signal (Ctrl-C, SIGTERM) stopped the run; `error` says when, and the metrics are those
    /// of the window up to then (when it holds any of the analysis window).
    #[serde(rename = "interrupted")]
    Interrupted,
    /// The model could not be built (the eigen-solve, the resting shape): nothing was simulated;
    /// `error` says why and names the keys that enter the stage.
    #[serde(rename = "not started")]
    NotStarted,
}

/// `summary.json` of a `drillopt simulate` whose model could not be built: it replaces an
/// earlier run's summary in the folder, so that no stale result reads as this run's.
#[derive(Debug, Clone, Serialize)]
pub struct NotStartedJson<'a> {
    /// Problem name, file, text, hash and drillopt's version.
    #[serde(flatten)]
    pub record: ProblemRecord<'a>,
    pub operating_point: super::PointJson,
    pub duration_s: f64,
    pub elements: usize,
    /// Always [`RunStatus::NotStarted`].
    pub status: RunStatus,
    /// Why, with the stage and the keys entering it.
    pub error: String,
}

/// `summary.json` of `drillopt simulate`.
#[derive(Debug, Clone, Serialize)]
pub struct SummaryJson<'a> {
    /// Problem name, file, text, hash and drillopt's version.
    #[serde(flatten)]
    pub record: ProblemRecord<'a>,
    pub operating_point: super::PointJson,
    pub duration_s: f64,
    /// Start of the analysis window (the problem's settling time, at most half the run), s.
    pub settling_time_s: f64,
    /// "preloaded" or "unloaded".
    pub start: &'a str,
    pub elements: usize,
    /// Vectors of the reduced basis by family.
    /// Reduced on the basis below, or unreduced (then `basis` counts every mode of the mesh).
    pub model: crate::sim::ModelKind,
    pub basis: crate::rom::BasisCounts,
    /// What became of the steady drilling state's shapes in the basis (`[mesh.basis]
    /// steady_shapes`; `not_asked` for the unreduced model).
    pub steady_shapes: crate::rom::SteadyStatus,
    /// The problem's nominal step and the largest step the run allowed (capped at 1/20 of the
    /// lowest torsional and axial periods), s.
    pub nominal_step_s: f64,
    pub max_step_s: f64,
    pub status: RunStatus,
    pub error: Option<String>,
    pub metrics: Option<crate::metrics::Metrics>,
    /// 95 % batch-means intervals of the time-mean metrics (10 batches of the analysis window).
    pub confidence_95:
        Option<std::collections::BTreeMap<&'static str, crate::metrics::BatchInterval>>,
    pub metrics_error: Option<String>,
    /// The dominant eigenvalue of steady drilling at the operating point
    /// ([`crate::sim::steady_stability`]); null for a depth-of-cut bit (a delay equation) or a
    /// steady state that could not be found.
    pub steady_state: Option<crate::sim::SteadyStability>,
    pub solver: &'a crate::sim::SolverStats,
}
