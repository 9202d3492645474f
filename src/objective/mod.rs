//! The robust objective (issue 4): statistics of metrics over Monte Carlo samples, and the robust
//! evaluation of operating points that combines them into a score and chance constraints.

pub mod robust;
pub mod statistic;

pub use robust::{PointEvaluation, RobustEvaluator, SampleOutcome, SampleResult, SetupError};
