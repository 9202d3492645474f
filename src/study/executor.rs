//! Who runs the simulations of a batch: the [`SampleExecutor`] trait and its in-process
//! implementations. As argmin keeps a solver apart from how its costs are evaluated, the robust
//! evaluator only forms the batch of (operating point, sample) jobs and hands it over; threads on
//! one machine ([`Threads`]) or, later, ranks of an MPI job run them.
//!
//! Contract: `execute` returns one result per job, in job order, and each result depends only on
//! its job (per-sample seeds come from the master seed and the sample index), so every executor
//! gives bitwise the same results whatever its parallelism or order of work.

use super::score::SampleResult;
use crate::model::OperatingPoint;
use rayon::prelude::*;

/// One simulation of a robust evaluation: an operating point and the index of a sample.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SampleJob {
    pub op: OperatingPoint,
    /// Index into the evaluator's sample set.
    pub sample: usize,
}

/// Runs a batch of simulations.
pub trait SampleExecutor: Send + Sync {
    /// Run every job with `run` and return the results in job order. An executor may call `run`
    /// on any of its threads, in any order.
    fn execute(
        &self,
        jobs: &[SampleJob],
        run: &(dyn Fn(SampleJob) -> SampleResult + Sync),
    ) -> Vec<SampleResult>;

    /// What runs the jobs, for the terminal and reports ("4 threads").
    fn describe(&self) -> String;
}

/// rayon's thread pool (all cores unless `RAYON_NUM_THREADS` says otherwise): the default.
#[derive(Debug, Clone, Copy, Default)]
pub struct Threads;

impl SampleExecutor for Threads {
    fn execute(
        &self,
        jobs: &[SampleJob],
        run: &(dyn Fn(SampleJob) -> SampleResult + Sync),
    ) -> Vec<SampleResult> {
        jobs.par_iter().map(|&job| run(job)).collect()
    }

    fn describe(&self) -> String {
        format!("{} threads", rayon::current_num_threads())
    }
}

/// One job after the other on the calling thread: a reference for tests and for profiling.
#[derive(Debug, Clone, Copy, Default)]
pub struct Serial;

impl SampleExecutor for Serial {
    fn execute(
        &self,
        jobs: &[SampleJob],
        run: &(dyn Fn(SampleJob) -> SampleResult + Sync),
    ) -> Vec<SampleResult> {
        jobs.iter().map(|&job| run(job)).collect()
    }

    fn describe(&self) -> String {
        "1 thread".to_string()
    }
}
