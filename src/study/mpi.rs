//! Monte Carlo samples over MPI ranks (`--features mpi`; rsmpi over the system's Open MPI or
//! MPICH). `mpirun -n N drillopt solve|map|compare|batch …`: rank 0 runs the command as usual and
//! hands each batch of simulations to [`MpiExecutor`], which deals the jobs out one at a time to
//! ranks 1…N−1 (dynamic assignment: simulation times differ by 10× between operating points) and
//! gives a rank its next job as soon as it returns a result. Ranks 1…N−1 run [`serve`]: they
//! rebuild the evaluator of the problem rank 0 names (its TOML text, so every rank simulates the
//! same model) and simulate the jobs they are sent. Rank 0 alone reads and writes the cache and the
//! reports.
//!
//! Results are bitwise those of the threads executor: a job's result depends only on the job
//! (per-sample seeds come from the master seed and the sample index), and every value crosses
//! as its IEEE-754 bits, so ±∞ and NaN metrics survive. With one rank, the jobs run on rank 0.
//!
//! Protocol (tags): rank 0 → worker: BEGIN (problem path, NUL, TOML text), JOB (job id,
//! Ω bits, V0 bits, sample), STOP; worker → rank 0: RESULT (job id, encoded [`Simulated`]) or
//! FAILED (why the worker could not set the problem up).

use super::RobustEvaluator;
use super::executor::{OnResult, RunJob, SampleExecutor, SampleJob, Simulated};
use super::score::SampleOutcome;
use crate::model::OperatingPoint;
use crate::problem::Problem;
use mpi::point_to_point::{Destination, Source};
use mpi::topology::{Communicator, SimpleCommunicator};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

const BEGIN: i32 = 1;
const JOB: i32 = 2;
const RESULT: i32 = 3;
const STOP: i32 = 4;
const FAILED: i32 = 5;

/// Hash of the problem text the workers hold (rank 0's view), so a batch of a new problem
/// sends BEGIN first. Also serialises MPI calls from rank 0.
static WORKERS_HOLD: Mutex<Option<u64>> = Mutex::new(None);

/// Number of ranks of the MPI job (1 when not launched by mpirun).
pub fn ranks() -> i32 {
    SimpleCommunicator::world().size()
}

/// This process's rank.
pub fn rank() -> i32 {
    SimpleCommunicator::world().rank()
}

/// Rank 0's executor: the jobs of a batch dealt out to ranks 1…N−1.
#[derive(Debug, Clone)]
pub struct MpiExecutor {
    path: PathBuf,
    text: String,
}

impl MpiExecutor {
    /// The executor for the evaluations of `problem` (its file path and text go to the workers).
    pub fn new(problem: &Problem) -> Self {
        MpiExecutor {
            path: problem.source.clone(),
            text: problem.text.clone(),
        }
    }
}

impl SampleExecutor for MpiExecutor {
    fn execute(&self, jobs: &[SampleJob], run: &RunJob, done: &OnResult) -> Vec<Simulated> {
        let world = SimpleCommunicator::world();
        let workers = world.size() - 1;
        if workers < 1 || jobs.is_empty() {
            return super::Serial.execute(jobs, run, done);
        }
        let mut hold = WORKERS_HOLD.lock().unwrap_or_else(|e| e.into_inner());
        let hash = crate::hash::stable_hash(self.text.as_bytes())
            ^ crate::hash::stable_hash(self.path.as_os_str().as_encoded_bytes());
        if *hold != Some(hash) {
            let mut msg = self.path.as_os_str().as_encoded_bytes().to_vec();
            msg.push(0);
            msg.extend_from_slice(self.text.as_bytes());
            for w in 1..=workers {
                world.process_at_rank(w).send_with_tag(&msg[..], BEGIN);
            }
            *hold = Some(hash);
        }
        let mut results: Vec<Option<Simulated>> = vec![None; jobs.len()];
        let mut next = 0;
        let mut in_flight = 0;
        let send = |to: i32, id: usize| {
            world
                .process_at_rank(to)
                .send_with_tag(&encode_job(id, jobs[id])[..], JOB);
        };
        for w in 1..=workers {
            if next < jobs.len() {
                send(w, next);
                next += 1;
                in_flight += 1;
            }
        }
        while in_flight > 0 {
            let (msg, status) = world.any_process().receive_vec::<u8>();
            match status.tag() {
                RESULT => {
                    let (id, r) = decode_result(&msg);
                    done(id, &r);
                    results[id] = Some(r);
                    in_flight -= 1;
                    if next < jobs.len() {
                        send(status.source_rank(), next);
                        next += 1;
                        in_flight += 1;
                    }
                }
                FAILED => {
                    let why = String::from_utf8_lossy(&msg);
                    eprintln!("error: MPI rank {}: {why}", status.source_rank());
                    world.abort(2);
                }
                t => unreachable!("rank 0 got an unexpected MPI tag {t}"),
            }
        }
        results
            .into_iter()
            .map(|r| r.expect("a result for every job"))
            .collect()
    }

    fn describe(&self) -> String {
        crate::units::count(usize::try_from(ranks()).unwrap_or(0), "MPI rank")
    }
}

/// Rank 0, at the end of the program: release the workers.
pub fn stop_workers() {
    let world = SimpleCommunicator::world();
    let _hold = WORKERS_HOLD.lock().unwrap_or_else(|e| e.into_inner());
    for w in 1..world.size() {
        world.process_at_rank(w).send_with_tag(&[0u8][..], STOP);
    }
}

/// Ranks 1…N−1: simulate what rank 0 sends until it says STOP.
pub fn serve() {
    let world = SimpleCommunicator::world();
    let root = world.process_at_rank(0);
    let mut next = root.receive_vec::<u8>();
    loop {
        let (msg, status) = next;
        match status.tag() {
            STOP => return,
            BEGIN => next = serve_problem(&world, &msg),
            t => unreachable!("worker got an unexpected MPI tag {t} before BEGIN"),
        }
    }
}

/// Serve the jobs of one problem; returns the message that ends it (BEGIN or STOP).
fn serve_problem(
    world: &SimpleCommunicator,
    begin: &[u8],
) -> (Vec<u8>, mpi::point_to_point::Status) {
    let root = world.process_at_rank(0);
    let split = begin.iter().position(|&b| b == 0).unwrap_or(begin.len());
    let path = PathBuf::from(String::from_utf8_lossy(&begin[..split]).into_owned());
    let text = String::from_utf8_lossy(begin.get(split + 1..).unwrap_or(&[])).into_owned();
    let setup = Problem::from_toml(&text, &path)
        .map_err(|e| e.to_string())
        .map(|mut p| {
            p.text = text.clone();
            p
        });
    let problem = match setup {
        Ok(p) => p,
        Err(e) => return fail(world, &path, &e),
    };
    let evaluator = match RobustEvaluator::new(&problem, None) {
        Ok(ev) => ev,
        Err(e) => return fail(world, &path, &e.to_string()),
    };
    loop {
        let (msg, status) = root.receive_vec::<u8>();
        if status.tag() != JOB {
            return (msg, status);
        }
        let (id, job) = decode_job(&msg);
        let r = evaluator.simulate_job(job);
        root.send_with_tag(&encode_result(id, &r)[..], RESULT);
    }
}

fn fail(
    world: &SimpleCommunicator,
    path: &Path,
    why: &str,
) -> (Vec<u8>, mpi::point_to_point::Status) {
    let root = world.process_at_rank(0);
    let msg = format!("{}: {why}", path.display());
    root.send_with_tag(msg.as_bytes(), FAILED);
    // Wait for rank 0 to abort or stop.
    loop {
        let (m, s) = root.receive_vec::<u8>();
        if s.tag() != JOB {
            return (m, s);
        }
    }
}

// ---------------------------------------------------------------- wire format -----------------

fn put_u64(out: &mut Vec<u8>, x: u64) {
    out.extend_from_slice(&x.to_le_bytes());
}

struct Reader<'a>(&'a [u8]);

impl Reader<'_> {
    fn u64(&mut self) -> u64 {
        let (head, rest) = self.0.split_at(8);
        self.0 = rest;
        u64::from_le_bytes(head.try_into().expect("8 bytes"))
    }
    fn f64(&mut self) -> f64 {
        f64::from_bits(self.u64())
    }
    fn text(&mut self) -> String {
        let n = self.u64() as usize;
        let (head, rest) = self.0.split_at(n);
        self.0 = rest;
        String::from_utf8_lossy(head).into_owned()
    }
}

fn put_text(out: &mut Vec<u8>, s: &str) {
    put_u64(out, s.len() as u64);
    out.extend_from_slice(s.as_bytes());
}

fn encode_job(id: usize, job: SampleJob) -> Vec<u8> {
    let mut out = Vec::with_capacity(40);
    put_u64(&mut out, id as u64);
    put_u64(&mut out, job.op.omega.to_bits());
    put_u64(&mut out, job.op.v0.to_bits());
    put_u64(&mut out, job.op.wob.to_bits());
    put_u64(&mut out, job.sample as u64);
    out
}

fn decode_job(msg: &[u8]) -> (usize, SampleJob) {
    let mut r = Reader(msg);
    let id = r.u64() as usize;
    let op = OperatingPoint {
        omega: r.f64(),
        v0: r.f64(),
        wob: r.f64(),
    };
    let sample = r.u64() as usize;
    (id, SampleJob { op, sample })
}

fn encode_result(id: usize, s: &Simulated) -> Vec<u8> {
    let mut out = Vec::new();
    put_u64(&mut out, id as u64);
    put_u64(&mut out, s.wall_time_s.to_bits());
    match &s.outcome {
        SampleOutcome::Metrics(m) => {
            put_u64(&mut out, 0);
            put_u64(&mut out, m.len() as u64);
            for (k, v) in m {
                put_text(&mut out, k);
                put_u64(&mut out, v.to_bits());
            }
        }
        SampleOutcome::Failed(why) => {
            put_u64(&mut out, 1);
            put_text(&mut out, why);
        }
    }
    out
}

fn decode_result(msg: &[u8]) -> (usize, Simulated) {
    let mut r = Reader(msg);
    let id = r.u64() as usize;
    let wall_time_s = r.f64();
    let outcome = if r.u64() == 0 {
        let n = r.u64() as usize;
        let mut m = BTreeMap::new();
        for _ in 0..n {
            let k = r.text();
            m.insert(k, r.f64());
        }
        SampleOutcome::Metrics(m)
    } else {
        SampleOutcome::Failed(r.text())
    };
    (
        id,
        Simulated {
            outcome,
            wall_time_s,
        },
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn jobs_and_results_cross_as_their_bits() {
        let job = SampleJob {
            op: OperatingPoint {
                omega: 1.0 / 3.0,
                v0: 5.0 / 3600.0,
                wob: 0.0,
            },
            sample: 7,
        };
        assert_eq!(decode_job(&encode_job(42, job)), (42, job));
        // A hook load's point carries its WOB.
        let hook = SampleJob {
            op: OperatingPoint::hook_load(1.0 / 3.0, 47_123.5),
            sample: 2,
        };
        assert_eq!(decode_job(&encode_job(9, hook)), (9, hook));
        let mut m = BTreeMap::new();
        m.insert("mse_pa".to_string(), f64::INFINITY);
        m.insert("efficiency".to_string(), f64::NAN);
        m.insert("mean_wob_n".to_string(), -0.0);
        m.insert("stick_fraction".to_string(), 0.1 + 0.2);
        let s = Simulated {
            outcome: SampleOutcome::Metrics(m.clone()),
            wall_time_s: 1.5,
        };
        let (id, back) = decode_result(&encode_result(3, &s));
        assert_eq!(id, 3);
        let SampleOutcome::Metrics(b) = back.outcome else {
            panic!("metrics expected")
        };
        for (k, v) in &m {
            assert_eq!(b[k].to_bits(), v.to_bits(), "{k}");
        }
        let f = Simulated {
            outcome: SampleOutcome::Failed("diverged at t = 1 s".into()),
            wall_time_s: 0.25,
        };
        assert_eq!(decode_result(&encode_result(9, &f)), (9, f));
    }
}
