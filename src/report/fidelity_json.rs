//! The multi-fidelity parts of `solution.json` (`[optimizer.explore]`, issue 16 item 2): the
//! explore overrides in the header (`explore`), the candidates with their explore and full
//! scores and the full-fidelity refinement (`confirmation`), and the simulations per fidelity (`work.by_fidelity`). Every field
//! is null (or absent from `work`) for a solve at one fidelity.

use crate::model::SetPoint;
use crate::problem::study::Explore;
use crate::solve::{Confirmation, SolveStatus};
use crate::study::{PointEvaluation, RobustEvaluator};
use serde::Serialize;

/// `explore` in the header: the explore fidelity as overrides of the full one (null: the full
/// fidelity's value).
#[derive(Debug, Clone, Serialize)]
pub struct ExploreJson {
    /// Simulated time of an explore run, s.
    pub duration_s: Option<f64>,
    /// Start of the explore analysis window, s.
    pub settling_time_s: Option<f64>,
    /// Monte Carlo samples per explore point.
    pub samples: Option<usize>,
    /// The explore basis, in words (as `numerical_check.basis`).
    pub basis: Option<String>,
    /// Explore candidates re-evaluated at full fidelity per round.
    pub confirm: usize,
    /// Most candidates confirmed in all (a further round only while none is feasible).
    pub max_confirm: usize,
    /// Least distance between two candidates, as a fraction of the box.
    pub separation: f64,
    /// Fraction by which the chance thresholds are tightened at the explore fidelity.
    pub margin: f64,
    /// Most full-fidelity trust-region points after the confirmation (0: none).
    pub refine: usize,
}

impl ExploreJson {
    pub fn of(e: &Explore) -> Self {
        ExploreJson {
            duration_s: e.duration,
            settling_time_s: e.settling_time,
            samples: e.samples,
            basis: e.basis.as_ref().map(|b| b.to_string()),
            confirm: e.confirm,
            max_confirm: e.max_confirm,
            separation: e.separation,
            margin: e.margin,
            refine: e.refine,
        }
    }
}

/// One confirmed candidate: its point, explore score and full-fidelity score.
#[derive(Debug, Clone, Serialize)]
pub struct CandidateJson {
    pub omega_rpm: f64,
    /// The set-point: V0 or a hook load's WOB.
    #[serde(flatten)]
    pub set_point: crate::model::SetPointValue,
    /// Score at the explore fidelity (the rank it was chosen by).
    pub explore_score: Option<f64>,
    pub explore_feasible: bool,
    /// Score at the full fidelity (null: a sample failed).
    pub full_score: Option<f64>,
    pub full_feasible: bool,
    /// full − explore: how far the cheap model was off at this point.
    pub score_difference: Option<f64>,
}

/// `confirmation`: how the exploration ended and the candidates confirmed, in explore rank.
#[derive(Debug, Clone, Serialize)]
pub struct ConfirmationJson {
    /// The status of the method at the explore fidelity.
    pub explore_status: SolveStatus,
    /// The explore's best point and score (null: none feasible at the explore fidelity).
    pub explore_best_omega_rpm: Option<f64>,
    /// (null under a hook load, whose set-point is `explore_best_wob_kn`)
    pub explore_best_v0_m_per_h: Option<f64>,
    /// A hook load's WOB set-point of the explore's best point, kN.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub explore_best_wob_kn: Option<f64>,
    pub explore_best_score: Option<f64>,
    pub candidates: Vec<CandidateJson>,
    /// Rounds of confirmation (more than one: the earlier rounds had no feasible candidate).
    pub rounds: usize,
    /// The full-fidelity trust-region refinement (`refine > 0`; null: none ran).
    pub refinement: Option<RefinementJson>,
}

/// `confirmation.refinement`: the trust region at full fidelity from the best confirmed point.
#[derive(Debug, Clone, Serialize)]
pub struct RefinementJson {
    /// Design points it evaluated (full fidelity; in `evaluations` after the confirmations).
    pub evaluations: usize,
    pub status: SolveStatus,
    pub termination: String,
}

impl ConfirmationJson {
    pub fn of(c: &Confirmation) -> Self {
        let best = c.explore_best.as_ref();
        ConfirmationJson {
            explore_status: c.explore_status,
            explore_best_omega_rpm: best.map(|b| b.omega_rpm),
            explore_best_v0_m_per_h: best
                .map(|b| b.op())
                .filter(|op| op.kind() == SetPoint::Feed)
                .map(|op| op.shown_set_point()),
            explore_best_wob_kn: best
                .map(|b| b.op())
                .filter(|op| op.kind() == SetPoint::Wob)
                .map(|op| op.shown_set_point()),
            explore_best_score: best.and_then(|b| b.objective),
            candidates: c
                .candidates
                .iter()
                .map(|k| CandidateJson {
                    omega_rpm: k.full.omega_rpm,
                    set_point: k.full.set_point,
                    explore_score: k.explore.objective,
                    explore_feasible: k.explore.feasible,
                    full_score: k.full.objective,
                    full_feasible: k.full.feasible,
                    score_difference: k
                        .full
                        .objective
                        .zip(k.explore.objective)
                        .map(|(f, e)| f - e),
                })
                .collect(),
            rounds: c.rounds,
            refinement: c.refinement.as_ref().map(|r| RefinementJson {
                evaluations: r.evaluations,
                status: r.status,
                termination: r.termination.clone(),
            }),
        }
    }
}

/// The explore score of the optimum's point (a confirmed candidate), for `objective`.
pub fn explore_score_of(c: Option<&Confirmation>, best: &PointEvaluation) -> Option<f64> {
    c?.explore_of(best)?.objective
}

/// Simulations of one fidelity.
#[derive(Debug, Clone, Serialize)]
pub struct FidelityWork {
    pub simulations_run: usize,
    pub simulations_from_cache: usize,
    pub simulations_failed: usize,
    /// Samples per point at this fidelity (with sequential sampling, the most a point may use).
    pub samples_per_point: usize,
}

impl FidelityWork {
    pub fn of(ev: &RobustEvaluator) -> Self {
        use std::sync::atomic::Ordering::Relaxed;
        FidelityWork {
            simulations_run: ev.counters.simulated.load(Relaxed),
            simulations_from_cache: ev.counters.cached.load(Relaxed),
            simulations_failed: ev.counters.failed.load(Relaxed),
            samples_per_point: ev.samples_per_point(),
        }
    }
}

/// `work.by_fidelity` of a multi-fidelity solve.
#[derive(Debug, Clone, Serialize)]
pub struct ByFidelity {
    pub explore: FidelityWork,
    pub full: FidelityWork,
}
