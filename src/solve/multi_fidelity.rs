//! Multi-fidelity solve (issue 16, item 2; `[optimizer.explore]`): the configured method
//! explores on the cheap fidelity (a shorter window, fewer samples, a smaller basis), then the
//! `confirm` best separated explore candidates (feasible first, by explore score; at least
//! `separation` apart in the unit box) are evaluated at the full fidelity in one batch. While
//! none of the confirmed candidates is feasible at full fidelity, the next `confirm` of the
//! ranking are confirmed, up to `max_confirm` in all (the cheap model may misjudge a constraint's
//! boundary: its best points then cluster where the full fidelity is infeasible). The optimum
//! reported is the best full-fidelity point, optionally refined by the trust region at full
//! fidelity (`refine`). The full fidelity's cost is known before the run: at most
//! (`max_confirm` + `refine`) × samples simulations.

use super::{
    Scaling, SolveError, SolveOutcome, SolveStatus, StudyBlackBox, best_point, constraints_of,
    feasible_set, solve,
};
use crate::model::OperatingPoint;
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
    /// Rounds of `confirm` candidates evaluated at full fidelity (more than one: the earlier
    /// rounds had no feasible candidate).
    pub rounds: usize,
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
    let (p, q) = (a.op(), b.op());
    p.omega.to_bits() == q.omega.to_bits()
        && p.v0.to_bits() == q.v0.to_bits()
        && p.wob.to_bits() == q.wob.to_bits()
}

/// The `n` best candidates of `points` in explore rank: feasible before infeasible, then by
/// score (highest first; ties keep the evaluation order); a point evaluated twice counts once
/// (its first evaluation), failed points (no score) are left out. A point closer than
/// `separation` (Euclidean, in `scaling`'s unit box) to a better-ranked pick is passed over while
/// separated points remain, then taken in rank order to fill the `n`.
pub fn candidates(
    points: &[PointEvaluation],
    n: usize,
    separation: f64,
    scaling: &Scaling,
) -> Vec<PointEvaluation> {
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
    let unit = |p: &PointEvaluation| scaling.to_unit(p.op());
    let mut picked: Vec<&PointEvaluation> = Vec::new();
    let mut passed_over = Vec::new();
    for p in distinct {
        let x = unit(p);
        let close = picked.iter().any(|q| {
            let y = unit(q);
            (x[0] - y[0]).hypot(x[1] - y[1]) < separation
        });
        if close {
            passed_over.push(p);
        } else {
            picked.push(p);
        }
    }
    picked
        .into_iter()
        .chain(passed_over)
        .take(n)
        .cloned()
        .collect()
}

/// Rounds of `confirm` candidates of `ranking` evaluated by `evaluate` (the full fidelity), in
/// rank order, until a confirmed one is feasible or the ranking is exhausted: the candidates
/// confirmed, their full evaluations (in the same order) and the rounds run.
fn confirm_in_rounds(
    ranking: &[PointEvaluation],
    confirm: usize,
    mut evaluate: impl FnMut(&[OperatingPoint]) -> Vec<PointEvaluation>,
) -> (Vec<PointEvaluation>, Vec<PointEvaluation>, usize) {
    let mut confirmed: Vec<PointEvaluation> = Vec::new();
    let mut rounds = 0;
    let mut taken = 0;
    while taken < ranking.len() && !confirmed.iter().any(|p| p.feasible) {
        let round = &ranking[taken..(taken + confirm.max(1)).min(ranking.len())];
        let ops: Vec<OperatingPoint> = round.iter().map(PointEvaluation::op).collect();
        confirmed.extend(evaluate(&ops));
        taken += round.len();
        rounds += 1;
    }
    (ranking[..taken].to_vec(), confirmed, rounds)
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
    let scaling = Scaling::of(constraints_of(problem)?);
    let ranking = candidates(
        &explored.evaluations,
        settings.max_confirm,
        settings.separation,
        &scaling,
    );
    let (picks, confirmed, rounds) =
        confirm_in_rounds(&ranking, settings.confirm, |ops| full.evaluate(ops));
    let mut best = best_point(&confirmed);
    let mut status = match (&best, explored.status) {
        (None, _) => SolveStatus::NoFeasiblePoint,
        (Some(_), SolveStatus::NoFeasiblePoint) => SolveStatus::BudgetExhausted,
        (Some(_), s) => s,
    };
    let feasible = confirmed.iter().filter(|p| p.feasible).count();
    let mut termination = format!(
        "{} (explore fidelity); {} of the best explore candidates confirmed at full fidelity{}, {feasible} feasible",
        explored.termination,
        picks.len(),
        if rounds > 1 {
            format!(
                " in {rounds} rounds, {} per round (a further round only while none was feasible)",
                settings.confirm
            )
        } else {
            String::new()
        }
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
            rounds,
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
            omega_rpm: crate::units::to_rpm(omega),
            set_point: crate::model::SetPointValue::Feed {
                v0_m_s: 0.005,
                v0_m_per_h: 18.0,
            },
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

    /// The unit box of `point`'s Ω (rad/s) over [10, 20] and V0 over [0, 0.01] m/s.
    fn box10() -> Scaling {
        Scaling {
            omega: [10.0, 20.0],
            kind: crate::model::SetPoint::Feed,
            set_point: [0.0, 0.01],
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
            candidates(&points, n, 0.0, &box10())
                .iter()
                .map(|p| p.omega_rad_s)
                .collect::<Vec<_>>()
        };
        assert_eq!(omegas(3), [12.0, 14.0, 10.0]);
        // Feasible points exhausted: the infeasible one comes next, the failed one never.
        assert_eq!(omegas(10), [12.0, 14.0, 10.0, 11.0]);
        assert_eq!(
            candidates(&points, 4, 0.0, &box10())[0].objective,
            Some(3.0)
        );
    }

    #[test]
    fn candidates_closer_than_the_separation_come_after_the_separated_ones() {
        // A cluster at 12–12.35 rad/s (unit x 0.2–0.235) and two points apart.
        let points = vec![
            point(12.0, Some(5.0), true),
            point(12.2, Some(4.9), true),
            point(12.35, Some(4.8), true),
            point(16.0, Some(3.0), true),
            point(19.0, Some(1.0), true),
        ];
        let omegas = |n, separation| {
            candidates(&points, n, separation, &box10())
                .iter()
                .map(|p| p.omega_rad_s)
                .collect::<Vec<_>>()
        };
        // 0.05 of the box = 0.5 rad/s: the cluster gives its best point, then 16 and 19.
        assert_eq!(omegas(3, 0.05), [12.0, 16.0, 19.0]);
        // Then the passed-over points in rank order fill the count.
        assert_eq!(omegas(5, 0.05), [12.0, 16.0, 19.0, 12.2, 12.35]);
        // 0.01 (0.1 rad/s): 12.2 is 0.02 from 12.0, 12.35 0.015 from 12.2: all kept.
        assert_eq!(omegas(3, 0.01), [12.0, 12.2, 12.35]);
        // 0.35: 16 is 0.4 from 12, 19 only 0.3 from 16: passed over.
        assert_eq!(omegas(3, 0.35), [12.0, 16.0, 12.2]);
    }

    /// A full fidelity that finds the points below `limit` rad/s infeasible.
    fn full_feasible_from(limit: f64) -> impl FnMut(&[OperatingPoint]) -> Vec<PointEvaluation> {
        move |ops| {
            ops.iter()
                .map(|op| {
                    let mut p = point(op.omega, Some(0.5), op.omega >= limit);
                    p.fidelity = Fidelity::Full;
                    p
                })
                .collect()
        }
    }

    #[test]
    fn further_rounds_are_confirmed_only_while_none_is_feasible() {
        let ranking: Vec<_> = (0..7)
            .map(|i| point(10.0 + i as f64, Some(9.0 - i as f64), true))
            .collect();
        // Feasible at full fidelity in the first round: one round.
        let (picks, full, rounds) = confirm_in_rounds(&ranking, 3, full_feasible_from(0.0));
        assert_eq!((picks.len(), full.len(), rounds), (3, 3, 1));
        // The first round (10, 11, 12) infeasible, 13 feasible: a second round of 3, then stop.
        let (picks, full, rounds) = confirm_in_rounds(&ranking, 3, full_feasible_from(13.0));
        assert_eq!((picks.len(), full.len(), rounds), (6, 6, 2));
        assert!(picks.iter().zip(&full).all(|(e, f)| same_point(e, f)));
        assert_eq!(full.iter().filter(|p| p.feasible).count(), 3);
        // Nothing feasible: the whole ranking (the last round short), and no more.
        let (picks, full, rounds) = confirm_in_rounds(&ranking, 3, full_feasible_from(99.0));
        assert_eq!((picks.len(), full.len(), rounds), (7, 7, 3));
        // An empty ranking: no round.
        let (_, full, rounds) = confirm_in_rounds(&[], 3, full_feasible_from(0.0));
        assert_eq!((full.len(), rounds), (0, 0));
    }
}
