//! Multi-fidelity solve (issue 16, item 2; `[optimizer.explore]`): the configured method
//! explores on the cheap fidelity (a shorter window, fewer samples, a smaller basis), then the
//! `confirm` best distinct explore candidates (feasible first, by explore score) are evaluated at
//! the full fidelity in one batch, and the optimum reported is the best of those full-fidelity
//! points. No refinement runs at full fidelity after the confirmation (not even for the trust
//! region): the full fidelity evaluates exactly the confirmed candidates, so its cost is
//! `confirm` × samples simulations, known before the run.

use super::{
    SolveError, SolveOutcome, SolveStatus, StudyBlackBox, best_point, constraints_of, feasible_set,
    solve,
};
use crate::optimize::{IterateCallback, TrustRegionOptions, minimize_trust_region_after};
use crate::problem::Problem;
use crate::problem::study::Explore;
use crate::study::{Fidelity, PointEvaluation, RobustEvaluator};

/// The full-fidelity confirmation of a multi-fidelity solve.
#[derive(Debug, Clone)]
pub struct Confirmation {
    /// The explore fidelity (`[optimizer.explore]`).
    pub explore: Explore,
    /// How the exploration ended (its method's status at the explore fidelity).
    pub explore_status: SolveStatus,
    /// The explore's best point (None: no explore point was feasible).
    pub explore_best: Option<PointEvaluation>,
    /// The candidates in explore rank: each explore evaluation with its full-fidelity one.
    pub candidates: Vec<Candidate>,
    /// The full-fidelity trust-region refinement (None: `refine = 0`, or no confirmed candidate
    /// feasible to start from).
    pub refinement: Option<Refinement>,
}

/// The full-fidelity trust-region refinement of a multi-fidelity solve (`refine > 0`).
#[derive(Debug, Clone)]
pub struct Refinement {
    /// Design points it evaluated (at most `refine`), all at full fidelity.
    pub evaluations: usize,
    /// How it ended: converged or budget_exhausted.
    pub status: SolveStatus,
    pub termination: String,
}

/// One explore candidate and its confirmation at full fidelity (the same operating point).
#[derive(Debug, Clone)]
pub struct Candidate {
    pub explore: PointEvaluation,
    pub full: PointEvaluation,
}

impl Confirmation {
    /// The explore evaluation of the point of `full` (a confirmed candidate), if it is one.
    pub fn explore_of(&self, full: &PointEvaluation) -> Option<&PointEvaluation> {
        self.candidates
            .iter()
            .find(|c| same_point(&c.full, full))
            .map(|c| &c.explore)
    }
}

fn same_point(a: &PointEvaluation, b: &PointEvaluation) -> bool {
    a.omega_rad_s.to_bits() == b.omega_rad_s.to_bits() && a.v0_m_s.to_bits() == b.v0_m_s.to_bits()
}

/// The `n` best distinct scored points of `points`: feasible before infeasible, then by score
/// (highest first); a point evaluated twice counts once (its first evaluation), failed points
/// (no score) are left out. Ties keep the evaluation order.
pub fn candidates(points: &[PointEvaluation], n: usize) -> Vec<PointEvaluation> {
    let mut distinct: Vec<&PointEvaluation> = Vec::new();
    for p in points.iter().filter(|p| p.objective.is_some()) {
        if !distinct.iter().any(|q| same_point(q, p)) {
            distinct.push(p);
        }
    }
    distinct.sort_by(|a, b| {
        b.feasible.cmp(&a.feasible).then(
            b.objective
                .partial_cmp(&a.objective)
                .unwrap_or(std::cmp::Ordering::Equal),
        )
    });
    distinct.into_iter().take(n).cloned().collect()
}

/// The robust optimum of `problem` with `[optimizer.explore]`: its method on `explore` (the
/// evaluator of [`Explore::apply`]`(problem)`, tagged [`Fidelity::Explore`]), then the best
/// candidates on `full` (the problem's own evaluator). The outcome's `evaluations` are the
/// explore evaluations followed by the full ones, `best` the best full-fidelity point, `path`
/// the explore path; `confirmation` holds the candidates side by side. The status is the
/// exploration's, except `no_feasible_point` when no confirmed candidate is feasible at full
/// fidelity, and `budget_exhausted` (not an optimum) when the exploration found no feasible point
/// but a candidate is feasible at full fidelity.
pub fn solve_multi_fidelity(
    problem: &Problem,
    full: &RobustEvaluator,
    explore: &RobustEvaluator,
    on_iterate: Option<IterateCallback>,
) -> Result<SolveOutcome, SolveError> {
    let file = problem.source.display().to_string();
    let settings = problem
        .study
        .explore
        .clone()
        .ok_or_else(|| SolveError::NoExplore { file: file.clone() })?;
    if full.fidelity() != Fidelity::Full || explore.fidelity() != Fidelity::Explore {
        return Err(SolveError::Explore {
            file,
            key: "optimizer.explore",
            message: "the evaluators are not tagged full and explore (an error of the caller)"
                .into(),
        });
    }
    // A basis given by cutoffs or by the lowest modes is compared by size once the modes exist.
    let (small, large) = (explore.basis_size(), full.basis_size());
    if settings.basis.is_some() && small >= large {
        return Err(SolveError::Explore {
            file,
            key: "optimizer.explore.basis",
            message: format!(
                "must give a smaller reduced model than the full basis ({}: {large} generalised coordinates), got {small}",
                problem.mesh.basis
            ),
        });
    }
    let explored = solve(explore.problem, explore, on_iterate)?;
    let picks = candidates(&explored.evaluations, settings.confirm);
    let ops: Vec<_> = picks.iter().map(PointEvaluation::op).collect();
    let confirmed = if ops.is_empty() {
        Vec::new()
    } else {
        full.evaluate(&ops)
    };
    let mut best = best_point(&confirmed);
    let mut status = match (&best, explored.status) {
        (None, _) => SolveStatus::NoFeasiblePoint,
        (Some(_), SolveStatus::NoFeasiblePoint) => SolveStatus::BudgetExhausted,
        (Some(_), s) => s,
    };
    let feasible = confirmed.iter().filter(|p| p.feasible).count();
    let mut termination = format!(
        "{} (explore fidelity); {} of the best explore candidates confirmed at full fidelity, {feasible} feasible",
        explored.termination,
        picks.len()
    );
    let radii = problem.study.optimizer.trust_radii();
    let (refined, refinement) = match (&best, radii) {
        (Some(start), Some(radii)) if settings.refine > 0 => {
            let (refined, r) = refine(problem, full, &confirmed, start, settings.refine, radii)?;
            termination = format!(
                "{termination}; then the trust region at full fidelity from the best of them: {} ({} evaluations)",
                r.termination, r.evaluations
            );
            let all: Vec<PointEvaluation> = confirmed.iter().chain(&refined).cloned().collect();
            best = best_point(&all);
            status = r.status;
            (refined, Some(r))
        }
        _ => (Vec::new(), None),
    };
    let candidates = picks
        .into_iter()
        .zip(confirmed.iter().cloned())
        .map(|(explore, full)| Candidate { explore, full })
        .collect();
    let mut evaluations = explored.evaluations;
    evaluations.extend(confirmed);
    evaluations.extend(refined);
    Ok(SolveOutcome {
        method: explored.method,
        best,
        evaluations,
        path: explored.path,
        termination,
        status,
        confirmation: Some(Confirmation {
            explore: settings,
            explore_status: explored.status,
            explore_best: explored.best,
            candidates,
            refinement,
        }),
    })
}

/// The trust region at full fidelity from `start` (the best confirmed point), with the
/// `confirmed` evaluations in its models, on at most `budget` design points, with the method's
/// `(initial_radius, min_radius)`: its evaluations (tagged full) and how it ended.
fn refine(
    problem: &Problem,
    full: &RobustEvaluator,
    confirmed: &[PointEvaluation],
    start: &PointEvaluation,
    budget: usize,
    (initial_radius, min_radius): (f64, f64),
) -> Result<(Vec<PointEvaluation>, Refinement), SolveError> {
    let constraints = constraints_of(problem)?;
    let set = feasible_set(problem)?;
    let bb = StudyBlackBox::new(full, constraints);
    let prior = confirmed
        .iter()
        .map(|p| (bb.scaling.to_unit(p.op()), bb.to_evaluation(p)))
        .collect();
    let x0 = set.project(&bb.scaling.to_unit(start.op()))?;
    let opts = TrustRegionOptions {
        initial_radius,
        min_radius,
        max_radius: 0.5_f64.max(initial_radius),
        max_evaluations: budget,
        ..TrustRegionOptions::default()
    };
    let r = minimize_trust_region_after(&bb, &set, &x0, &opts, prior, None)?;
    let evaluations = bb.log.into_inner().unwrap_or_else(|e| e.into_inner());
    let status = SolveStatus::of(r.stop, Some(start));
    Ok((
        evaluations.clone(),
        Refinement {
            evaluations: evaluations.len(),
            status,
            termination: r.termination,
        },
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A scored point at (`omega` rad/s, 0.005 m/s): its score and feasibility set by hand.
    fn point(omega: f64, score: Option<f64>, feasible: bool) -> PointEvaluation {
        PointEvaluation {
            omega_rad_s: omega,
            v0_m_s: 0.005,
            omega_rpm: crate::units::to_rpm(omega),
            v0_m_per_h: 18.0,
            objective: score,
            quantity: score,
            risk: Vec::new(),
            chance: Vec::new(),
            feasible,
            failure: None,
            mean_metrics: Default::default(),
            samples_used: 1,
            score_half_width: None,
            score_interval: None,
            samples: Vec::new(),
            fidelity: Fidelity::Explore,
        }
    }

    #[test]
    fn candidates_are_feasible_first_by_score_and_distinct() {
        let points = vec![
            point(10.0, Some(1.0), true),
            point(11.0, Some(9.0), false),
            point(12.0, Some(3.0), true),
            point(12.0, Some(3.5), true), // the same point again: counted once
            point(13.0, None, false),     // failed: never a candidate
            point(14.0, Some(2.0), true),
        ];
        let omegas = |n| {
            candidates(&points, n)
                .iter()
                .map(|p| p.omega_rad_s)
                .collect::<Vec<_>>()
        };
        assert_eq!(omegas(3), [12.0, 14.0, 10.0]);
        // Feasible points exhausted: the infeasible one comes next, the failed one never.
        assert_eq!(omegas(10), [12.0, 14.0, 10.0, 11.0]);
        assert_eq!(candidates(&points, 4)[0].objective, Some(3.0));
    }
}
