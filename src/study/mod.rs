//! The robust study of operating points (issue 4): Monte Carlo samples of the uncertain
//! parameters are simulated at every point by a [`SampleExecutor`], and their metrics are
//! combined into a score and chance constraints.
//!
//! * [`evaluator`]: [`RobustEvaluator`] draws the samples, builds the reduced models, forms each
//!   batch of (point, sample) jobs and goes through the evaluation cache;
//! * [`executor`]: who runs a batch ([`Threads`] by default, [`Serial`] as a reference);
//! * [`score`]: statistic of the quantity minus risk penalties, its bootstrap confidence
//!   interval, chance constraints, feasibility;
//! * [`sequential`]: the samples per point chosen by a stopping rule on that interval.
//!
//! The statistics themselves live in [`crate::stats`], shared with the problem layer.

pub mod cost;
pub mod evaluator;
pub mod executor;
pub mod fidelity;
#[cfg(feature = "mpi")]
pub mod mpi;
pub mod score;
pub mod sequential;

pub use evaluator::{RobustEvaluator, SetupError, WorkCounters, model_hash};
pub use executor::{OnResult, RunJob, SampleExecutor, SampleJob, Serial, Simulated, Threads};
pub use fidelity::Fidelity;
pub use score::{
    ChanceValue, PointEvaluation, RiskValue, SampleOutcome, SampleResult, bootstrap_seed,
    deterministic_violations, metric_map, score, score_interval,
};
pub use sequential::{evaluate_in_rounds, next_count};
