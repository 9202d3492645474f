//! `[optimizer.explore]`: the cheap fidelity of a multi-fidelity `solve` (issue 16, item 2).
//!
//! The section gives the explore fidelity as overrides of the full one (the problem's own
//! `[simulation]`, `[mesh]` and `[uncertain]`): a shorter window (`duration`, optionally its own
//! `settling_time`), fewer Monte Carlo samples per point (`samples`: samples 0..n of the full
//! set, the same draws) and a smaller reduced basis (`[optimizer.explore.basis]`, the keys of
//! `[mesh.basis]`). The configured method runs on the explore fidelity; then the `confirm` best
//! distinct candidates (feasible first, by explore score) are evaluated at full fidelity and the
//! reported optimum is the best full-fidelity point ([`crate::solve`]). Validation
//! (`validate_explore.rs`) refuses every override that is not cheaper than the full fidelity.

use super::super::schema::{BasisSection, RawQuantity};
use crate::model::BasisSpec;
use crate::problem::Problem;
use serde::Deserialize;

/// `[optimizer.explore]` as written.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawExplore {
    /// Simulated time of an explore run (a time; shorter than `simulation.duration`).
    pub duration: Option<RawQuantity>,
    /// Start of the explore analysis window (a time; shorter than the explore duration).
    pub settling_time: Option<RawQuantity>,
    /// Monte Carlo samples per explore point (fewer than `uncertain.samples`).
    pub samples: Option<i64>,
    /// Explore candidates re-evaluated at full fidelity.
    pub confirm: Option<i64>,
    /// Most candidates confirmed in all, when none of the first `confirm` is feasible.
    pub max_confirm: Option<i64>,
    /// Least distance between two candidates, as a fraction of the box (unit-box coordinates).
    pub separation: Option<f64>,
    /// Fraction by which the chance constraints' thresholds are tightened at the explore fidelity.
    pub margin: Option<f64>,
    /// Full-fidelity design points of a trust-region refinement from the best confirmed point.
    pub refine: Option<i64>,
    /// `[optimizer.explore.basis]`: the explore basis, keys of `[mesh.basis]`.
    pub basis: Option<BasisSection>,
}

/// Candidates confirmed at full fidelity when `confirm` is not given.
pub const CONFIRM: usize = 3;
/// Legal range of `optimizer.explore.confirm`.
pub const CONFIRM_RANGE: std::ops::RangeInclusive<usize> = 1..=50;
/// Legal range of `optimizer.explore.max_confirm` (at least `confirm`).
pub const MAX_CONFIRM_RANGE: std::ops::RangeInclusive<usize> = 1..=50;
/// `max_confirm` when not given: `confirm` times this (one more round of candidates), at most
/// the end of [`MAX_CONFIRM_RANGE`].
pub const MAX_CONFIRM_ROUNDS: usize = 2;
/// `separation` when not given: 5 % of the box (4 rpm and 1.4 m/h on a 40–120 rpm × 2–30 m/h
/// box), about the trust region's `min_radius` scale, so one cluster gives one candidate.
pub const SEPARATION: f64 = 0.05;
/// Legal range of `optimizer.explore.separation` (0: exact duplicates only; the unit box's
/// diagonal is √2).
pub const SEPARATION_RANGE: std::ops::RangeInclusive<f64> = 0.0..=0.5;
/// Legal range of `optimizer.explore.margin` (0, the default: the thresholds as written).
pub const MARGIN_RANGE: std::ops::RangeInclusive<f64> = 0.0..=0.5;
/// Legal range of `optimizer.explore.refine` (0: no refinement, the default).
pub const REFINE_RANGE: std::ops::RangeInclusive<usize> = 0..=1000;

/// The validated explore fidelity: each `None` keeps the full fidelity's value.
#[derive(Debug, Clone, PartialEq)]
pub struct Explore {
    /// Simulated time of an explore run, s; in (settling time, `simulation.duration`).
    pub duration: Option<f64>,
    /// Start of the explore analysis window, s; in [0, explore duration).
    pub settling_time: Option<f64>,
    /// Monte Carlo samples per explore point; in [1, `uncertain.samples` − 1] (above
    /// `uncertain.sequential.min_samples` with sequential sampling, where it is the most an
    /// explore point may use).
    pub samples: Option<usize>,
    /// The explore basis; no family larger than the full basis's, and the explore reduced model
    /// strictly smaller (checked when the models are built, see [`crate::solve`]).
    pub basis: Option<BasisSpec>,
    /// Distinct explore candidates re-evaluated at full fidelity; default [`CONFIRM`], in
    /// [`CONFIRM_RANGE`].
    pub confirm: usize,
    /// Most candidates confirmed in all: while no confirmed candidate is feasible at full
    /// fidelity, the next `confirm` of the explore ranking are confirmed, until `max_confirm`.
    /// Default `confirm` × [`MAX_CONFIRM_ROUNDS`] (at most 50); in [`confirm`, 50].
    pub max_confirm: usize,
    /// Least Euclidean distance between two candidates in the unit box (Ω and V0 scaled by
    /// their bounds): a point closer than this to a better-ranked candidate is confirmed only
    /// after every separated one. Default [`SEPARATION`], in [`SEPARATION_RANGE`].
    pub separation: f64,
    /// Feasibility margin of the exploration: each chance constraint P(metric > threshold) ≤ p
    /// is judged at the explore fidelity against threshold − margin·|threshold| (the full
    /// fidelity keeps the threshold as written). A few explore samples estimate a probability
    /// of 0.1 coarsely (with 4 samples only "none exceeds" passes, which a point with p = 0.16
    /// does half the time), so the explore ranking is kept away from the boundary. Default 0, in
    /// [`MARGIN_RANGE`]; a threshold of 0 is not moved.
    pub margin: f64,
    /// Full-fidelity design points of a trust-region refinement from the best confirmed point
    /// (the confirmed candidates in its models, the method's `initial_radius` and `min_radius`);
    /// 0 (the default): none. In [`REFINE_RANGE`]; above 0 only for `method = "trust_region"` or
    /// `"ego+trust_region"`.
    pub refine: usize,
}

impl Explore {
    /// `full` at the explore fidelity: its window, samples and basis replaced by the overrides
    /// given, and without `[optimizer.explore]` (the explore problem has one fidelity). The
    /// evaluation-cache key of its simulations ([`crate::study::model_hash`]) differs from the
    /// full problem's whenever the window or the basis does; with only fewer samples the
    /// simulations are the full fidelity's own (sample i is the same draw) and share its cache
    /// entries (the `margin` moves the chance thresholds, which no simulation depends on).
    pub fn apply(&self, full: &Problem) -> Problem {
        let mut p = full.clone();
        if let Some(d) = self.duration {
            p.simulation.duration = d;
        }
        if let Some(t) = self.settling_time {
            p.simulation.settling_time = t;
        }
        if let Some(n) = self.samples {
            p.study.samples = n;
        }
        if let Some(b) = &self.basis {
            p.mesh.basis = b.clone();
        }
        if let Some(c) = p.study.constraints.as_mut() {
            for chance in &mut c.chance {
                chance.threshold -= self.margin * chance.threshold.abs();
            }
        }
        p.study.explore = None;
        p
    }

    /// The overrides in words, for the terminal: `duration 0.8 s, samples 4, basis …`.
    pub fn describe(&self) -> String {
        let mut parts = Vec::new();
        if let Some(d) = self.duration {
            parts.push(format!("duration {} s", crate::units::short(d)));
        }
        if let Some(t) = self.settling_time {
            parts.push(format!("settling_time {} s", crate::units::short(t)));
        }
        if let Some(n) = self.samples {
            parts.push(format!("samples {n}"));
        }
        if let Some(b) = &self.basis {
            parts.push(format!("basis {b}"));
        }
        parts.push(format!("{} confirmed", self.confirm));
        if self.max_confirm > self.confirm {
            parts.push(format!("up to {} if none is feasible", self.max_confirm));
        }
        if self.margin > 0.0 {
            parts.push(format!(
                "chance thresholds tightened by {} %",
                crate::units::short(100.0 * self.margin)
            ));
        }
        if self.separation > 0.0 {
            parts.push(format!(
                "candidates {} % of the box apart",
                crate::units::short(100.0 * self.separation)
            ));
        }
        if self.refine > 0 {
            parts.push(format!(
                "then at most {} full-fidelity trust-region points",
                self.refine
            ));
        }
        parts.join(", ")
    }
}
