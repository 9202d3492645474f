//! Solution verification at one operating point (`drillopt verify`): is a decision metric a
//! property of the model, or of its discretisation?
//!
//! The problem is run as it stands (the *base*) and four or five times refined, one numerical
//! parameter at a time: every family of the basis enriched ([`BASIS_FACTOR`]), twice the elements,
//! the integrator's tolerances divided by [`TOLERANCE_DIVISOR`], an analysis window twice as long
//! (same settling time), and, for a string whose laws smooth a set-valued contact or friction
//! (every depth-of-cut bit, any wall with friction), those regularisation widths divided by
//! [`SMOOTHING_DIVISOR`] ([`crate::model::Drillstring::with_smoothing_refined`]). For each decision metric the largest relative change from the base,
//! |refined − base| / max(|base|, floor), is compared with its tolerance: 2 % for means (ROP, WOB,
//! TOB, MSE), 10 % for stick-slip statistics (SSI, stick fraction, peak bit speed ratio). The
//! floors keep a metric that is (nearly) zero from turning round-off into a large relative change.
//! Which metrics are compared, with which class and floor, is the metric catalogue's
//! ([`crate::metrics::METRICS`], [`decision_metrics`]).
//! This is a refinement study in the sense of Roache (*Verification and Validation in
//! Computational Science and Engineering*, 1998, ch. 5): one factor at a time, verdict per metric.
//!
//! A refinement study presumes that the metric is a function of the operating point. Near the
//! onset of stick-slip under a large WOB the response can be intermittent or chaotic: a relative
//! change of 1e-4 in Ω ([`PERTURBATION`]) then moves the statistics of a window of seconds by tens
//! of percent (issue 11: 61.75 rpm, 29.46 m/h, SSI 1.27 → 0.83 with 18 torsional modes), and the
//! change under a refinement says nothing about the discretisation. `verify` therefore also runs
//! the base model at the perturbed point (the trajectory's own sensitivity, the baseline of
//! Lorenz-type predictability arguments; cf. Roache §5.10 on "noise" in the refinement
//! sequence) and gives each metric one of three [`Verdict`]s: converged, not converged (a
//! refinement moves it beyond its limit while the perturbation does not: truncation), or
//! sensitive (the perturbation alone moves it beyond its limit: the window does not determine
//! it, and a longer window or a statistic over Monte Carlo samples is needed).
//!
//! A metric whose value at the point lies on a chance constraint's threshold (within its floor)
//! is where a study's optimum often sits: on the edge of the feasible set. There the relative
//! change is ill-posed (the steady growth rate at a stability edge is zero by construction, and
//! any refinement moves its sign), and what the decision needs is where the edge lies. Such a
//! metric is judged by its *edge shift*: how far along Ω each refinement moves the threshold's
//! crossing, |refined − base| / |∂m/∂ln Ω|, the slope taken from the perturbed run, against
//! [`EDGE_TOLERANCE`] of Ω. It applies only where the ordinary test fails and the perturbed run
//! gives a finite, non-zero slope; otherwise the ordinary verdict stands.

use crate::metrics::{self, Metrics, Source};
use crate::model::{BasisSpec, OperatingPoint};
use crate::problem::Problem;
use crate::rom::{BasisCounts, BasisError, ReducedModel};
use crate::sim::{Effects, InitialState, RunSettings, SimulationError, simulate};
use rayon::prelude::*;
use serde::Serialize;
use std::collections::BTreeMap;

/// Enrichment of every family of the basis (counts and cutoffs), ≥ 1.5 as `verify` promises.
pub const BASIS_FACTOR: f64 = 1.5;
/// The integrator's tolerances (absolute, relative, Newton) are divided by this.
pub const TOLERANCE_DIVISOR: f64 = 4.0;
/// The regularisation widths of the contact and friction laws (`…_smoothing`) are divided by this.
pub const SMOOTHING_DIVISOR: f64 = 2.0;
/// Relative change of Ω in the sensitivity run: far below any discretisation error of the
/// metrics (on the seed at 60 rpm, 5 m/h it moves SSI, stick fraction and peak bit speed ratio
/// by ≤ 0.1 %), so a larger change is the trajectory's, not the model's.
pub const PERTURBATION: f64 = 1e-4;
/// Largest shift of a chance constraint's edge along Ω, relative to Ω, that a refinement may
/// make for a metric at its threshold (module doc): 1 %, finer than any study's Ω grid (the
/// regression maps' cells are 5-9 % of Ω).
pub const EDGE_TOLERANCE: f64 = 0.01;

/// What `verify` concludes about one metric.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Verdict {
    /// Every refinement and the perturbation move it by at most its limit.
    Converged,
    /// A refinement moves it beyond its limit, the perturbation does not: truncation error.
    NotConverged,
    /// A relative change of [`PERTURBATION`] in Ω alone moves it beyond its limit: the window
    /// does not determine the metric (intermittent or chaotic response).
    Sensitive,
}

impl Verdict {
    /// The verdict from the largest relative change under the refinements, the relative change
    /// under the perturbation (`None`: not run) and the limit. A NaN change is not converged.
    pub fn of(max_rel_change: f64, sensitivity: Option<f64>, limit: f64) -> Verdict {
        match sensitivity {
            Some(s) if s.is_nan() || s > limit => Verdict::Sensitive,
            _ if max_rel_change.is_nan() || max_rel_change > limit => Verdict::NotConverged,
            _ => Verdict::Converged,
        }
    }

    /// As the terminal says it.
    pub fn text(self) -> &'static str {
        match self {
            Verdict::Converged => "converged",
            Verdict::NotConverged => "NOT converged",
            Verdict::Sensitive => "sensitive",
        }
    }
}

pub use crate::metrics::MetricClass;

/// A decision metric: its `summary.json` key, class, absolute floor of the relative change, and
/// how to read it (from its row of the metric catalogue, [`crate::metrics::METRICS`]).
#[derive(Debug, Clone, Copy)]
pub struct DecisionMetric {
    pub key: &'static str,
    pub class: MetricClass,
    /// Denominator floor, in the metric's unit.
    pub floor: f64,
    pub get: fn(&Metrics) -> f64,
    /// What it is computed from: a metric of the model ([`Source::Model`]) is computed for each
    /// run from that run's model.
    pub source: Source,
}

/// The metrics `problem` decides on, in the catalogue's order: those every verification compares
/// ([`Verification::Always`](crate::metrics::Verification::Always): ROP, WOB, TOB, MSE and the
/// stick-slip statistics), and those its objective, risk terms and chance constraints use,
/// itself or through the metrics it is computed from
/// ([`crate::metrics::catalogue::compared_for`]; e.g. the von Mises utilization brings the
/// peak stress: stresses are recovered from the basis by mode displacement and converge more
/// slowly than the motion).
pub fn decision_metrics(problem: &Problem) -> Vec<DecisionMetric> {
    crate::metrics::catalogue::compared_for(problem.study.metrics_named())
        .into_iter()
        .filter_map(|spec| {
            let (class, floor) = spec.compared()?;
            Some(DecisionMetric {
                key: spec.key,
                class,
                floor,
                get: spec.get,
                source: spec.source,
            })
        })
        .collect()
}

/// One numerical parameter refined.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Refinement {
    Basis,
    Mesh,
    Tolerance,
    Window,
    /// The regularisation widths of the laws divided by [`SMOOTHING_DIVISOR`] (only for a string
    /// that has some: [`refinements`]).
    Smoothing,
    /// The finite-element model without reduction, on the problem's mesh (opt-in: `verify
    /// --unreduced`; it costs about 100× the reduced run).
    Unreduced,
    /// Not a refinement: the base model at Ω·(1 + [`PERTURBATION`]), the sensitivity baseline.
    /// Its change is reported as `sensitivity`, apart from the refinements.
    Perturbed,
}

impl Refinement {
    pub const ALL: [Refinement; 4] = [
        Refinement::Basis,
        Refinement::Mesh,
        Refinement::Tolerance,
        Refinement::Window,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Refinement::Basis => "basis",
            Refinement::Mesh => "mesh",
            Refinement::Tolerance => "tolerance",
            Refinement::Window => "window",
            Refinement::Smoothing => "smoothing",
            Refinement::Unreduced => "unreduced",
            Refinement::Perturbed => "perturbed",
        }
    }
}

/// The verdict on one metric.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MetricVerdict {
    pub class: MetricClass,
    /// Largest relative change accepted (0.02 for means, 0.10 for stick-slip statistics).
    pub limit: f64,
    /// Denominator floor of the relative change, in the metric's unit.
    pub floor: f64,
    /// The base run's value.
    pub value: f64,
    /// The value of each refined run.
    pub refined: BTreeMap<&'static str, f64>,
    /// Largest |refined − value| / max(|value|, floor) over the refinements.
    pub max_rel_change: f64,
    /// The value at Ω·(1 + [`PERTURBATION`]), when that run was made.
    pub perturbed: Option<f64>,
    /// |perturbed − value| / max(|value|, floor).
    pub sensitivity: Option<f64>,
    pub verdict: Verdict,
    /// The refinement that moved it most.
    pub worst: &'static str,
    /// Every refinement that moved it beyond `limit`.
    pub beyond_limit: Vec<&'static str>,
    /// For a metric at a chance constraint's threshold judged by its edge (module doc): the
    /// largest shift of the threshold's crossing along Ω over the refinements, relative to Ω
    /// (limit [`EDGE_TOLERANCE`]); `None` where the ordinary test decides.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub edge_shift: Option<f64>,
    /// `verdict == Converged`.
    pub converged: bool,
}

/// One run of the study: what it was, its cost and its basis.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct VerifyRun {
    pub name: &'static str,
    pub elements: usize,
    pub basis: BasisCounts,
    /// What became of the steady drilling state's shapes in the run's basis.
    pub steady_shapes: crate::rom::SteadyStatus,
    pub duration_s: f64,
    pub steps: usize,
    pub wall_time_s: f64,
    /// The base run's steady-state stability ([`crate::sim::steady_stability`]); `None` for the
    /// other runs and where it is not computed.
    #[serde(skip)]
    pub steady_state: Option<crate::sim::SteadyStability>,
    /// The same of the finite-element model on the run's mesh (every free DOF), for the reduced
    /// base run and mesh refinement whose mesh is small enough ([`unreduced_steady_state`]).
    #[serde(skip)]
    pub steady_state_unreduced: Option<crate::sim::SteadyStability>,
    /// The steady drilling state's loads of the run's model and of the finite-element model on
    /// its mesh ([`steady_loads`]), for the reduced base run whose mesh is small enough.
    #[serde(skip)]
    pub steady_loads: Option<[SteadyLoads; 2]>,
    /// Why the base run has no `steady_loads` when the reference was asked for.
    #[serde(skip)]
    pub steady_loads_missing: Option<SteadyLoadsMissing>,
}

/// Why `verify` has no finite-element steady loads to set beside the basis' (outcome as data:
/// the CLI says it instead of leaving the line out; `steady_loads_missing` in the JSON).
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "reason", rename_all = "snake_case")]
pub enum SteadyLoadsMissing {
    /// The mesh has more free DOFs than the finite-element reference is built for
    /// ([`crate::sim::MAX_UNKNOWNS`]).
    MeshTooLarge { unknowns: usize, limit: usize },
    /// The finite-element model could not be assembled.
    NotBuilt { error: String },
    /// The basis' own 10 ms run from the pre-loaded start failed.
    Basis { error: String },
    /// The finite-element model's 10 ms run from its pre-loaded start failed (most often its
    /// start did not converge on this mesh).
    FiniteElement { error: String },
}

/// The loads of the steady drilling state: the first [`STEADY_LOADS_WINDOW_S`] of a run from
/// the pre-loaded start, as `simulate` computes them (SI).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SteadyLoads {
    /// The top drive's torque and force, N·m and N.
    pub top_torque_nm: f64,
    pub top_force_n: f64,
    /// The largest wall force at a node, N.
    pub peak_wall_force_n: f64,
    /// The largest compression and torque along the string, N and N·m.
    pub max_compression_n: f64,
    pub max_torque_nm: f64,
    /// The largest von Mises stress along the string, Pa.
    pub max_von_mises_pa: f64,
}

impl SteadyLoads {
    /// The loads by the keys of the metrics they are (the metric catalogue's names and units).
    pub fn named(&self) -> [(&'static str, f64); 6] {
        [
            ("mean_top_torque_nm", self.top_torque_nm),
            ("mean_top_force_n", self.top_force_n),
            ("peak_wall_force_n", self.peak_wall_force_n),
            ("max_compression_n", self.max_compression_n),
            ("max_torque_nm", self.max_torque_nm),
            ("max_von_mises_pa", self.max_von_mises_pa),
        ]
    }
}

/// The window of [`steady_loads`], s: a few steps from the pre-loaded start.
pub const STEADY_LOADS_WINDOW_S: f64 = 0.01;

/// The loads of the steady drilling state of `model` (of `string`) at `op` ([`SteadyLoads`]),
/// with the nominal step `time_step` (s); the error's text when the start or the run fails. The reduced
/// model's against the finite-element model's tell whether the basis places the string's
/// contacts, and with them the torque and the wall forces, where the mesh does: the basis
/// refinement cannot tell when the refined basis misses them as well.
pub fn steady_loads(
    model: &ReducedModel,
    string: &crate::model::Drillstring,
    op: OperatingPoint,
    time_step: f64,
) -> Result<SteadyLoads, String> {
    let out = simulate(
        model,
        op,
        Effects::ALL,
        &RunSettings::new(STEADY_LOADS_WINDOW_S, time_step),
        InitialState::Preloaded,
        |_| {},
    );
    if let Some(e) = &out.error {
        return Err(e.to_string());
    }
    let m = metrics::of_run(&out, string, op, 0.0, None).map_err(|e| e.to_string())?;
    Ok(SteadyLoads {
        top_torque_nm: m.mean_top_torque_nm,
        top_force_n: m.mean_top_force_n,
        peak_wall_force_n: m.peak_wall_force_n,
        max_compression_n: m.max_compression_n,
        max_torque_nm: m.max_torque_nm,
        max_von_mises_pa: m.max_von_mises_pa,
    })
}

/// The steady-state stability of the finite-element model of `string` on `elements` elements at
/// `op` (every free DOF: the reference of a basis' growth rate, which the bit's negative
/// damping can read off a truncation's residual mode, docs/model.md "Linear stability of steady
/// drilling"); `None` above [`crate::sim::MAX_UNKNOWNS`] free DOFs (not built), for a
/// depth-of-cut bit, or when it cannot be computed.
pub fn unreduced_steady_state(
    string: &crate::model::Drillstring,
    elements: usize,
    op: OperatingPoint,
) -> Option<crate::sim::SteadyStability> {
    // 6 DOFs per node, the top's clamped: the free DOFs of the unreduced model.
    if 6 * elements > crate::sim::MAX_UNKNOWNS || string.bit.blades().is_some() {
        return None;
    }
    let model = ReducedModel::unreduced(string, elements).ok()?;
    crate::sim::steady_stability(&model, op, Effects::ALL)
        .ok()
        .flatten()
}

/// The outcome of `verify`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct VerifyReport {
    pub metrics: BTreeMap<&'static str, MetricVerdict>,
    /// [`crate::model::bit_damping_ratio`] at the operating point: above 1, without
    /// stiffness-proportional damping, the stick-slip statistics are set by the shortest
    /// torsional waves the basis holds and do not converge.
    pub bit_damping_ratio: f64,
    /// Length of the base run's analysis window (duration − settling), s.
    pub window_s: f64,
    /// Revolutions of the top drive in the analysis window, Ω·window/2π: fatigue counts one
    /// bending cycle per revolution and a stick-slip cycle is as long as a few revolutions, so
    /// below 1 the metrics of the window say little, whatever the verdict (the CLI warns).
    pub window_revolutions: f64,
    pub converged: bool,
    pub basis: BasisCounts,
    pub refined_basis: BasisCounts,
    /// What became of the steady drilling state's shapes in the base run's basis.
    pub steady_shapes: crate::rom::SteadyStatus,
    /// The regularisation widths the smoothing refinement divided by [`SMOOTHING_DIVISOR`]
    /// (empty when it was not run).
    pub smoothing_keys: Vec<&'static str>,
    /// The dominant eigenvalue of steady drilling at the point (the base model): an unstable
    /// steady state is left by the run only once a disturbance has grown, so the window
    /// refinement may be what tells; `None` where it is not computed.
    pub steady_state: Option<crate::sim::SteadyStability>,
    /// The same eigenvalue of the finite-element model on the base mesh and on the refined one
    /// (twice the elements), where affordable ([`unreduced_steady_state`]): when the two agree
    /// the model's own answer is converged in the mesh, and a basis that differs from it does
    /// not hold the mode that decides stability (or holds a spurious one).
    pub steady_state_unreduced: Option<crate::sim::SteadyStability>,
    pub steady_state_unreduced_refined_mesh: Option<crate::sim::SteadyStability>,
    /// The steady drilling state's loads of the base model and of the finite-element model on
    /// the base mesh, where affordable ([`steady_loads`]).
    pub steady_loads: Option<[SteadyLoads; 2]>,
    /// Why `steady_loads` is missing when `verify` asked for it.
    pub steady_loads_missing: Option<SteadyLoadsMissing>,
    pub runs: Vec<VerifyRun>,
}

/// Why the study could not be done.
#[derive(Debug, thiserror::Error)]
pub enum VerifyError {
    #[error("{run} run: {source}")]
    Basis {
        run: &'static str,
        #[source]
        source: BasisError,
    },
    #[error("{run} run stopped: {source}")]
    Simulation {
        run: &'static str,
        #[source]
        source: SimulationError,
    },
    #[error("{run} run: metrics: {source}")]
    Metrics {
        run: &'static str,
        #[source]
        source: crate::metrics::MetricsError,
    },
}

/// What to verify: the operating point and the window.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VerifySettings {
    pub op: OperatingPoint,
    /// Simulated duration of the base run, s.
    pub duration: f64,
    /// Settling time before the analysis window, s (< duration).
    pub settling: f64,
    /// Whether to compute the finite-element model's steady-state eigenvalue on the base and
    /// the refined mesh ([`unreduced_steady_state`]; `verify` does, `solve`'s check does not:
    /// up to a minute of dense eigenvalues on twice a field well's mesh).
    pub stability_reference: bool,
}

/// One run's description.
struct Variant {
    name: &'static str,
    unreduced: bool,
    /// Factor on Ω (1 but for the perturbed run).
    omega_factor: f64,
    elements: usize,
    basis: BasisSpec,
    duration: f64,
    tolerance_divisor: f64,
    smoothing_divisor: f64,
}

/// The refinements `verify` makes for `problem`: [`Refinement::ALL`], and
/// [`Refinement::Smoothing`] when its string has regularisation widths that act.
pub fn refinements(problem: &Problem) -> Vec<Refinement> {
    let mut list = Refinement::ALL.to_vec();
    if !smoothing_keys(problem).is_empty() {
        list.push(Refinement::Smoothing);
    }
    list
}

/// The keys of the regularisation widths the smoothing refinement divides (empty: none act).
pub fn smoothing_keys(problem: &Problem) -> Vec<&'static str> {
    problem.model.with_smoothing_refined(SMOOTHING_DIVISOR).1
}

/// Run the base, the problem's [`refinements`] and the perturbed run (in parallel) and judge each
/// decision metric. `progress` is told the name of each run as it finishes.
pub fn verify(
    problem: &Problem,
    settings: VerifySettings,
    progress: impl Fn(&str) + Sync,
) -> Result<VerifyReport, VerifyError> {
    let mut runs = refinements(problem);
    runs.push(Refinement::Perturbed);
    verify_with(problem, settings, &runs, progress)
}

/// [`verify`] with only the given refinements (`solve` checks the basis alone at its optimum).
pub fn verify_with(
    problem: &Problem,
    settings: VerifySettings,
    refinements: &[Refinement],
    progress: impl Fn(&str) + Sync,
) -> Result<VerifyReport, VerifyError> {
    let base = Variant {
        name: "base",
        unreduced: false,
        omega_factor: 1.0,
        elements: problem.mesh.elements,
        basis: problem.mesh.basis.clone(),
        duration: settings.duration,
        tolerance_divisor: 1.0,
        smoothing_divisor: 1.0,
    };
    let window = settings.duration - settings.settling;
    let variants: Vec<Variant> = std::iter::once(base)
        .chain(refinements.iter().map(|&r| {
            let mut v = Variant {
                name: r.name(),
                unreduced: false,
                omega_factor: 1.0,
                elements: problem.mesh.elements,
                basis: problem.mesh.basis.clone(),
                duration: settings.duration,
                tolerance_divisor: 1.0,
                smoothing_divisor: 1.0,
            };
            match r {
                Refinement::Basis => v.basis = v.basis.enriched(BASIS_FACTOR),
                Refinement::Mesh => v.elements *= 2,
                Refinement::Tolerance => v.tolerance_divisor = TOLERANCE_DIVISOR,
                Refinement::Window => v.duration = settings.settling + 2.0 * window,
                Refinement::Smoothing => v.smoothing_divisor = SMOOTHING_DIVISOR,
                Refinement::Unreduced => v.unreduced = true,
                Refinement::Perturbed => v.omega_factor = 1.0 + PERTURBATION,
            }
            v
        }))
        .collect();
    let decisions = decision_metrics(problem);
    let model_metrics = decisions.iter().any(|d| d.source == Source::Model);
    let results: Vec<(VerifyRun, Metrics)> = variants
        .par_iter()
        .map(|v| {
            let r = run_variant(problem, &settings, v, model_metrics);
            progress(v.name);
            r
        })
        .collect::<Result<_, _>>()?;
    let (base_run, base_metrics) = &results[0];
    let mut verdicts = BTreeMap::new();
    for d in &decisions {
        let value = (d.get)(base_metrics);
        let mut refined = BTreeMap::new();
        let (mut max_rel_change, mut worst) = (0.0_f64, "none");
        let mut beyond_limit = Vec::new();
        let (mut perturbed, mut sensitivity) = (None, None);
        for (run, m) in &results[1..] {
            let r = (d.get)(m);
            let change = relative_change(r, value, d.floor);
            if run.name == Refinement::Perturbed.name() {
                (perturbed, sensitivity) = (Some(r), Some(change));
                continue;
            }
            refined.insert(run.name, r);
            // A NaN change (a non-finite metric) counts as not converged.
            if change.is_nan() || change > max_rel_change {
                max_rel_change = change;
                worst = run.name;
            }
            if change.is_nan() || change > d.class.tolerance() {
                beyond_limit.push(run.name);
            }
        }
        let mut verdict = Verdict::of(max_rel_change, sensitivity, d.class.tolerance());
        let edge_shift = match (verdict, perturbed) {
            (Verdict::Converged, _) | (_, None) => None,
            (_, Some(p)) => edge_shift(
                value,
                p,
                &refined,
                d.floor,
                chance_thresholds(problem, d.key),
            ),
        };
        if let Some(shift) = edge_shift {
            verdict = if shift <= EDGE_TOLERANCE {
                Verdict::Converged
            } else {
                Verdict::NotConverged
            };
        }
        verdicts.insert(
            d.key,
            MetricVerdict {
                class: d.class,
                limit: d.class.tolerance(),
                floor: d.floor,
                value,
                refined,
                max_rel_change,
                perturbed,
                sensitivity,
                verdict,
                worst,
                beyond_limit,
                edge_shift,
                converged: verdict == Verdict::Converged,
            },
        );
    }
    let refined_basis = results
        .iter()
        .find(|(r, _)| r.name == Refinement::Basis.name())
        .map_or(base_run.basis, |(r, _)| r.basis);
    Ok(VerifyReport {
        steady_state: base_run.steady_state,
        steady_state_unreduced: base_run.steady_state_unreduced,
        steady_loads: base_run.steady_loads,
        steady_loads_missing: base_run.steady_loads_missing.clone(),
        steady_state_unreduced_refined_mesh: results
            .iter()
            .find(|(r, _)| r.name == Refinement::Mesh.name())
            .and_then(|(r, _)| r.steady_state_unreduced),
        bit_damping_ratio: base_metrics
            .clone()
            .with_drilled_bit_damping_ratio(&problem.model, settings.op)
            .bit_damping_ratio,
        window_s: window,
        window_revolutions: settings.op.omega * window / (2.0 * std::f64::consts::PI),
        converged: verdicts.values().all(|v| v.converged),
        metrics: verdicts,
        basis: base_run.basis,
        steady_shapes: base_run.steady_shapes,
        refined_basis,
        smoothing_keys: if refinements.contains(&Refinement::Smoothing) {
            smoothing_keys(problem)
        } else {
            Vec::new()
        },
        runs: results.into_iter().map(|(r, _)| r).collect(),
    })
}

/// The thresholds of the problem's chance constraints on `key`.
fn chance_thresholds(problem: &Problem, key: &str) -> Vec<f64> {
    problem
        .study
        .constraints
        .as_ref()
        .map(|k| {
            k.chance
                .iter()
                .filter(|c| c.metric == key)
                .map(|c| c.threshold)
                .collect()
        })
        .unwrap_or_default()
}

/// The edge shift of a metric at a chance threshold (module doc): with `value` within `floor` of
/// one of `thresholds` and the slope ∂m/∂ln Ω = (`perturbed` − `value`) / [`PERTURBATION`] finite
/// and non-zero, the largest |refined − value| / |slope| (relative to Ω; NaN for a non-finite
/// refined value); `None` otherwise.
pub fn edge_shift(
    value: f64,
    perturbed: f64,
    refined: &BTreeMap<&'static str, f64>,
    floor: f64,
    thresholds: Vec<f64>,
) -> Option<f64> {
    if !thresholds.iter().any(|t| (value - t).abs() <= floor) {
        return None;
    }
    let slope = (perturbed - value) / PERTURBATION;
    if !(slope.is_finite() && slope != 0.0) {
        return None;
    }
    let shift = refined.values().fold(0.0_f64, |worst, &r| {
        let s = (r - value).abs() / slope.abs();
        if s.is_nan() || worst.is_nan() {
            f64::NAN
        } else {
            worst.max(s)
        }
    });
    Some(shift)
}

/// |r − value| / max(|value|, floor); 0 when the two are equal, infinities included (off bottom
/// the MSE is +∞ in every run: no change, not ∞ − ∞ = NaN); NaN when either is NaN.
pub fn relative_change(r: f64, value: f64, floor: f64) -> f64 {
    if r == value {
        0.0
    } else {
        (r - value).abs() / value.abs().max(floor)
    }
}

/// One run and its metrics; with `model_metrics`, also those of its model at its operating point
/// (critical speed margin, bit damping ratio: NaN otherwise).
fn run_variant(
    problem: &Problem,
    settings: &VerifySettings,
    v: &Variant,
    model_metrics: bool,
) -> Result<(VerifyRun, Metrics), VerifyError> {
    let smoothed;
    let string = if v.smoothing_divisor == 1.0 {
        &problem.model
    } else {
        smoothed = problem.model.with_smoothing_refined(v.smoothing_divisor).0;
        &smoothed
    };
    let model = if v.unreduced {
        ReducedModel::unreduced(string, v.elements)
    } else {
        // The basis the optimizer's model has: its steady-state shapes at the problem's
        // operating point.
        let mesh = crate::model::Mesh {
            elements: v.elements,
            basis: v.basis.clone(),
        };
        crate::sim::reduced_model(string, &mesh, problem.operating_point)
    }
    .map_err(|source| VerifyError::Basis {
        run: v.name,
        source,
    })?;
    let mut run = RunSettings::new(v.duration, problem.simulation.time_step);
    run.envelope_from = settings.settling;
    run.newmark.atol /= v.tolerance_divisor;
    run.newmark.rtol /= v.tolerance_divisor;
    run.newmark.newton_tol /= v.tolerance_divisor;
    let op = OperatingPoint {
        omega: settings.op.omega * v.omega_factor,
        ..settings.op
    };
    let out = simulate(
        &model,
        op,
        Effects::ALL,
        &run,
        InitialState::from(problem.simulation.start),
        |_| {},
    );
    if let Some(source) = out.error {
        return Err(VerifyError::Simulation {
            run: v.name,
            source,
        });
    }
    // As `simulate` and the studies compute them; a string without a resting state has no
    // margin (NaN: not converged).
    let terms = model_metrics.then(|| metrics::ModelTerms {
        critical_speed_margin: crate::campbell::critical_speed_margin(
            &model,
            problem.campbell.excitation_multiple,
            op.omega,
        )
        .unwrap_or(f64::NAN),
        steady_state: crate::sim::steady_stability(&model, op, Effects::ALL)
            .ok()
            .flatten(),
    });
    let metrics =
        metrics::of_run(&out, &problem.model, op, settings.settling, terms).map_err(|source| {
            VerifyError::Metrics {
                run: v.name,
                source,
            }
        })?;
    // The steady loads of the basis beside the finite-element model's on the same mesh, or why
    // there are none (the base run of `verify`, not `solve`'s check).
    let reference = (settings.stability_reference && v.name == "base" && !v.unreduced).then(|| {
        let unknowns = 6 * v.elements;
        if unknowns > crate::sim::MAX_UNKNOWNS {
            return Err(SteadyLoadsMissing::MeshTooLarge {
                unknowns,
                limit: crate::sim::MAX_UNKNOWNS,
            });
        }
        let step = problem.simulation.time_step;
        let fe = ReducedModel::unreduced(string, v.elements).map_err(|e| {
            SteadyLoadsMissing::NotBuilt {
                error: e.to_string(),
            }
        })?;
        let basis = steady_loads(&model, string, op, step)
            .map_err(|error| SteadyLoadsMissing::Basis { error })?;
        let fe = steady_loads(&fe, string, op, step)
            .map_err(|error| SteadyLoadsMissing::FiniteElement { error })?;
        Ok([basis, fe])
    });
    Ok((
        VerifyRun {
            name: v.name,
            elements: v.elements,
            basis: model.basis.counts(),
            steady_shapes: model.steady,
            duration_s: v.duration,
            steps: out.stats.steps,
            wall_time_s: out.stats.wall_time_s,
            steady_state: if v.name == "base" {
                crate::sim::steady_stability(&model, op, Effects::ALL)
                    .ok()
                    .flatten()
            } else {
                None
            },
            steady_state_unreduced: if settings.stability_reference
                && (v.name == "base" || v.name == Refinement::Mesh.name())
                && !v.unreduced
            {
                unreduced_steady_state(string, v.elements, op)
            } else {
                None
            },
            steady_loads: reference.as_ref().and_then(|r| r.as_ref().ok().copied()),
            steady_loads_missing: reference.and_then(Result::err),
        },
        metrics,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_metric_at_its_threshold_is_judged_by_where_its_edge_lies() {
        // m(Ω) = −0.8 (ln Ω − ln Ω_e) + δ: at Ω_e the base reads δ = −1e-5 (on the threshold 0,
        // floor 0.01), the perturbed run −0.8e-4 more, so the slope is −0.8 per unit ln Ω; a
        // refinement that adds 4e-3 moves the crossing by 4e-3 / 0.8 = 0.5 % of Ω.
        let base = -1e-5;
        let perturbed = base - 0.8 * PERTURBATION;
        let refined = |r: f64| BTreeMap::from([("basis", base), ("mesh", r)]);
        let shift = edge_shift(base, perturbed, &refined(base + 4e-3), 0.01, vec![0.0]).unwrap();
        assert!((shift - 5e-3).abs() < 1e-9, "{shift}");
        assert!(shift <= EDGE_TOLERANCE);
        let far = edge_shift(base, perturbed, &refined(base - 2e-2), 0.01, vec![0.0]).unwrap();
        assert!((far - 0.025).abs() < 1e-9 && far > EDGE_TOLERANCE, "{far}");
        // Away from every threshold, or with no slope to read, the ordinary test decides.
        assert_eq!(edge_shift(0.5, 0.6, &refined(0.7), 0.01, vec![0.0]), None);
        assert_eq!(edge_shift(base, base, &refined(0.0), 0.01, vec![0.0]), None);
        assert_eq!(
            edge_shift(base, perturbed, &refined(0.0), 0.01, vec![]),
            None
        );
        // A refinement that did not give a number is not converged.
        assert!(
            edge_shift(base, perturbed, &refined(f64::NAN), 0.01, vec![0.0])
                .unwrap()
                .is_nan()
        );
    }

    #[test]
    fn verdict_tells_truncation_from_sensitivity() {
        // Within the limit everywhere: converged, with or without the perturbed run.
        assert_eq!(Verdict::of(0.05, Some(0.01), 0.1), Verdict::Converged);
        assert_eq!(Verdict::of(0.1, None, 0.1), Verdict::Converged);
        // A refinement beyond the limit, the perturbation within: truncation.
        assert_eq!(Verdict::of(0.3, Some(0.001), 0.1), Verdict::NotConverged);
        assert_eq!(Verdict::of(0.3, None, 0.1), Verdict::NotConverged);
        // The perturbation alone beyond the limit: sensitive, whatever the refinements did.
        assert_eq!(Verdict::of(0.3, Some(0.2), 0.1), Verdict::Sensitive);
        assert_eq!(Verdict::of(0.0, Some(0.2), 0.1), Verdict::Sensitive);
        // Non-finite changes are never converged.
        assert_eq!(Verdict::of(f64::NAN, Some(0.0), 0.1), Verdict::NotConverged);
        assert_eq!(Verdict::of(0.0, Some(f64::NAN), 0.1), Verdict::Sensitive);
    }

    #[test]
    fn equal_infinities_do_not_change() {
        assert_eq!(relative_change(f64::INFINITY, f64::INFINITY, 1e6), 0.0);
        assert_eq!(relative_change(1.1, 1.0, 0.1), (1.1_f64 - 1.0).abs());
        assert_eq!(relative_change(f64::INFINITY, 1.0, 0.1), f64::INFINITY);
        assert!(relative_change(f64::NAN, 1.0, 0.1).is_nan());
        assert!(relative_change(f64::NAN, f64::NAN, 0.1).is_nan());
    }

    #[test]
    fn the_perturbation_is_no_refinement() {
        assert!(!Refinement::ALL.contains(&Refinement::Perturbed));
        assert_eq!(Refinement::Perturbed.name(), "perturbed");
    }
}
