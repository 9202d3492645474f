//! Who runs the simulations of a batch: the [`SampleExecutor`] trait and its in-process
//! implementations. As argmin keeps a solver apart from how its costs are evaluated, the robust
//! evaluator only forms the batch of (operating point, sample) jobs and hands it over; threads on
//! one machine ([`Threads`]) or, later, ranks of an MPI job run them.
//!
//! The evaluator answers what it can from the evaluation cache first; an executor only runs
//! simulations. Contract: `execute` returns one result per job, in job order, and each result
//! depends only on its job (per-sample seeds come from the master seed and the sample index), so every executor
//! gives bitwise the same results whatever its parallelism or order of work.

use super::score::SampleOutcome;
use crate::model::OperatingPoint;
use rayon::prelude::*;

/// One simulation of a robust evaluation: an operating point and the index of a sample.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SampleJob {
    pub op: OperatingPoint,
    /// Index into the evaluator's sample set.
    pub sample: usize,
}

/// What one simulation gives: the metrics (or why it failed) and how long it took.
#[derive(Debug, Clone, PartialEq)]
pub struct Simulated {
    pub outcome: SampleOutcome,
    /// Wall time of the simulation, s (for the cache's records, not for any result).
    pub wall_time_s: f64,
}

/// The work of one job, as the evaluator gives it to an executor.
pub type RunJob<'a> = dyn Fn(SampleJob) -> Simulated + Sync + 'a;
/// Called on the calling process once per job as its result arrives: (job index, result).
pub type OnResult<'a> = dyn Fn(usize, &Simulated) + Sync + 'a;

/// Runs a batch of simulations.
pub trait SampleExecutor: Send + Sync {
    /// Run every job and return the results in job order, calling `done` for each as it
    /// arrives. An executor may call `run` on any of its threads, in any order, or hand the job
    /// to another process that runs the same work on its own copy of the problem.
    fn execute(&self, jobs: &[SampleJob], run: &RunJob, done: &OnResult) -> Vec<Simulated>;

    /// What runs the jobs, for the terminal and reports ("4 threads").
    fn describe(&self) -> String;
}

/// Job `i` run here, reported through `done`.
fn run_one(i: usize, job: SampleJob, run: &RunJob, done: &OnResult) -> Simulated {
    let r = run(job);
    done(i, &r);
    r
}

/// rayon's thread pool (all cores unless `RAYON_NUM_THREADS` says otherwise): the default.
#[derive(Debug, Clone, Copy, Default)]
pub struct Threads;

impl SampleExecutor for Threads {
    fn execute(&self, jobs: &[SampleJob], run: &RunJob, done: &OnResult) -> Vec<Simulated> {
        jobs.par_iter()
            .enumerate()
            .map(|(i, &job)| run_one(i, job, run, done))
            .collect()
    }

    fn describe(&self) -> String {
        crate::units::count(rayon::current_num_threads(), "thread")
    }
}

/// One job after the other on the calling thread: a reference for tests and for profiling.
#[derive(Debug, Clone, Copy, Default)]
pub struct Serial;

impl SampleExecutor for Serial {
    fn execute(&self, jobs: &[SampleJob], run: &RunJob, done: &OnResult) -> Vec<Simulated> {
        jobs.iter()
            .enumerate()
            .map(|(i, &job)| run_one(i, job, run, done))
            .collect()
    }

    fn describe(&self) -> String {
        "1 thread".to_string()
    }
}
