//! `ego+trust_region`: EGO explores, the trust region refines.
//!
//! EGO ([`super::minimize_ego`]) runs on its share of the budget, `ego_evaluations`. The trust
//! region ([`super::super::trust_region`]) then starts at EGO's best point (feasibility-first
//! order of [`Evaluation::better_than`]) with every EGO evaluation in its history
//! ([`TrustRegion::with_history`](crate::optimize::TrustRegion::with_history)): they enter its
//! models, are never evaluated again, and the trust region spends only what is left of the one
//! budget, `max_evaluations − (evaluations EGO made)`. The simulations themselves are shared too:
//! both phases evaluate through the same black box (in `drillopt solve`, the same disk cache).
//!
//! The result is the trust region's (its centre, its stop: converged or budget exhausted), with
//! the history and path of both phases in order, the trust region's iterations numbered after
//! EGO's and its evaluation counts offset by EGO's.

use super::{EgoOptions, minimize_ego};
use crate::optimize::evaluation::{BlackBox, best_index};
use crate::optimize::feasible::FeasibleSet;
use crate::optimize::observer::{IterateCallback, SharedCallback};
use crate::optimize::trust_region::{TrustRegionOptions, minimize_trust_region_after};
use crate::optimize::{OptimizeError, OptimizeResult, Stop};
use std::sync::{Arc, Mutex};

/// Options of [`minimize_ego_trust_region`].
#[derive(Clone, Debug, PartialEq)]
pub struct EgoTrustRegionOptions {
    /// The EGO phase; its `max_evaluations` is EGO's share of the budget.
    pub ego: EgoOptions,
    /// The trust-region phase; its `max_evaluations` is the whole budget (EGO's share included).
    pub trust_region: TrustRegionOptions,
}

/// EGO, then the trust region from EGO's best point (see the module doc).
pub fn minimize_ego_trust_region<B: BlackBox + ?Sized>(
    bb: &B,
    set: &FeasibleSet,
    opts: &EgoTrustRegionOptions,
    callback: Option<IterateCallback>,
) -> Result<OptimizeResult, OptimizeError> {
    let total = opts.trust_region.max_evaluations;
    if opts.ego.max_evaluations >= total {
        return Err(OptimizeError::InvalidOption {
            name: "ego_evaluations",
            value: opts.ego.max_evaluations as f64,
            reason: "must be below max_evaluations (the trust region needs some of the budget)",
        });
    }
    opts.trust_region.validate()?;
    let shared = SharedCallback(Arc::new(Mutex::new(callback)));
    let ego = minimize_ego(bb, set, &opts.ego, shared.boxed())?;
    let start = best_index(&ego.history, opts.ego.constraint_tol)
        .map_or_else(|| ego.x.clone(), |i| ego.history[i].0.clone());
    let offset = ego.evaluations;
    let first_iteration = ego.path.len();
    let tr_opts = TrustRegionOptions {
        max_evaluations: total - offset,
        ..opts.trust_region.clone()
    };
    let shift = move |it: &mut crate::optimize::Iterate| {
        it.iteration += first_iteration;
        it.evaluations += offset;
    };
    let tr_callback: Option<IterateCallback> = shared.boxed().map(|mut cb| {
        Box::new(move |it: &crate::optimize::Iterate| {
            let mut it = it.clone();
            shift(&mut it);
            cb(&it);
        }) as IterateCallback
    });
    let tr =
        minimize_trust_region_after(bb, set, &start, &tr_opts, ego.history.clone(), tr_callback)?;
    let mut history = ego.history;
    history.extend(tr.history);
    let mut path = ego.path;
    path.extend(tr.path.into_iter().map(|mut it| {
        shift(&mut it);
        it
    }));
    let stop = if history.iter().all(|(_, e)| e.failed) {
        Stop::AllFailed
    } else {
        tr.stop
    };
    Ok(OptimizeResult {
        x: tr.x,
        evaluation: tr.evaluation,
        evaluations: history.len(),
        history,
        path,
        termination: format!(
            "{} ({offset} evaluations); then the trust region from EGO's best point: {} ({} evaluations)",
            ego.termination, tr.termination, tr.evaluations
        ),
        stop,
    })
}
