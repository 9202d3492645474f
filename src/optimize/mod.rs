//! Derivative-free optimisation of an expensive, noisy, possibly failing black box inside
//! linear constraints. This layer knows nothing about drillstrings.
//!
//! Conventions (shared by every method):
//! - variables `x ∈ ℝⁿ` are assumed scaled by the caller so that the feasible box is `O(1)`
//!   (e.g. the unit box); radii, steps and tolerances are in these units;
//! - the known feasible set is a [`FeasibleSet`] (box + `a_i·x ≤ b_i`); every evaluated point lies
//!   in it (up to [`FEASIBILITY_TOL`]);
//! - the black box ([`BlackBox`]) returns an [`Evaluation`]: an objective to **minimise** and
//!   constraints `c_j(x) ≤ 0`; a `failed` (or non-finite) evaluation is infeasible and worse than
//!   any successful one, and never stops a run;
//! - every method returns the same [`OptimizeResult`] (best point, full history, path).
//!
//! Methods: [`minimize_trust_region`] (the main one: model-based trust region, an argmin
//! `Solver`, sub-problems solved by Clarabel), [`minimize_nelder_mead`] (argmin's Nelder–Mead
//! on a projected penalty, with a simplex-size test and restarts), [`minimize_particle_swarm`]
//! (argmin's seeded particle swarm on the same penalty), [`grid_search`] (exhaustive),
//! [`minimize_ego`] (efficient global optimisation on egobox's Gaussian processes) and
//! [`minimize_ego_trust_region`] (EGO, then the trust region from its best point).

mod ego;
mod error;
mod evaluation;
mod feasible;
mod grid;
mod model;
mod nelder_mead;
mod observer;
mod particle_swarm;
mod penalized;
pub mod qp;
mod result;
mod trust_region;

pub use ego::{
    EgoOptions, EgoTrustRegionOptions, LINEAR_MARGIN, minimize_ego, minimize_ego_trust_region,
};
pub use error::OptimizeError;
pub use evaluation::{BlackBox, Evaluation};
pub use feasible::{FEASIBILITY_TOL, FeasibleSet};
pub use grid::grid_search;
pub use nelder_mead::{NelderMeadOptions, minimize_nelder_mead};
pub use observer::{Iterate, IterateCallback, PathLog, PathObserver};
pub use particle_swarm::{SwarmOptions, minimize_particle_swarm};
pub use penalized::FAILURE_COST;
pub use result::{OptimizeResult, Stop};
pub use trust_region::{
    BlackBoxProblem, TrustRegion, TrustRegionOptions, TrustRegionState, minimize_trust_region,
    minimize_trust_region_after,
};
