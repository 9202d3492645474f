//! End-to-end checks of the robust optimisation on the smallest drillstring of the regression set
//! (`problems/regression/tiny_string.toml`: 8 m, 12 elements, 10 modes, 1.5 s windows).
//!
//! - `solve` (trust region) lands where an exhaustive map of the same problem says the optimum is.
//! - Killing `drillopt solve` part-way and running it again with `--resume` re-simulates nothing
//!   that had finished.
//! - The robust evaluation uses common random numbers and does not depend on the thread count.

use drillopt::cache::EvalCache;
use drillopt::model::OperatingPoint;
use drillopt::problem::Problem;
use drillopt::study::{
    OnResult, RobustEvaluator, RunJob, SampleExecutor, SampleJob, Serial, Simulated,
};
use std::path::PathBuf;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

fn tiny() -> (Problem, PathBuf) {
    let path = PathBuf::from(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/problems/regression/tiny_string.toml"
    ));
    (Problem::load(&path).unwrap(), path)
}

/// The map's best node and the score of its neighbourhood give the range the optimum must be in:
/// the trust-region optimum lies within one grid cell of the best node, and its score is at least
/// the best node's (less 1 % of the score range over the map: the scores are deterministic but
/// the simulator's adaptive steps make them piecewise smooth only).
#[test]
fn trust_region_solve_finds_the_optimum_an_exhaustive_map_gives() {
    let (problem, _) = tiny();
    let ev = RobustEvaluator::new(&problem, None).unwrap();
    let grid = [7, 7];
    let map = drillopt::solve::map(&problem, &ev, grid).unwrap();
    let best = map.best.clone().expect("feasible grid nodes");
    let scores: Vec<f64> = map
        .points
        .iter()
        .flatten()
        .filter_map(|p| p.objective)
        .collect();
    let range = scores.iter().cloned().fold(f64::MIN, f64::max)
        - scores.iter().cloned().fold(f64::MAX, f64::min);
    let ev = RobustEvaluator::new(&problem, None).unwrap();
    let outcome = drillopt::solve::solve(&problem, &ev, None).unwrap();
    let opt = outcome.best.clone().expect("an optimum");
    let cell_omega = map.omega[1] - map.omega[0];
    let cell_v0 = map.set_point[1] - map.set_point[0];
    println!(
        "map best: {:.1} rpm {:.2} m/h score {:.4}; solve: {:.1} rpm {:.2} m/h score {:.4} after {} points ({})",
        best.omega_rpm,
        best.op().shown_set_point(),
        best.objective.unwrap(),
        opt.omega_rpm,
        opt.op().shown_set_point(),
        opt.objective.unwrap(),
        outcome.evaluations.len(),
        outcome.termination
    );
    assert!(
        (opt.omega_rad_s - best.omega_rad_s).abs() <= cell_omega + 1e-9,
        "Ω: solve {} vs map {} rad/s (cell {cell_omega})",
        opt.omega_rad_s,
        best.omega_rad_s
    );
    assert!(
        (opt.op().v0 - best.op().v0).abs() <= cell_v0 + 1e-12,
        "V0: solve {} vs map {} m/s (cell {cell_v0})",
        opt.op().v0,
        best.op().v0
    );
    assert!(
        opt.objective.unwrap() >= best.objective.unwrap() - 0.01 * range,
        "solve's score {} is below the map's best {}",
        opt.objective.unwrap(),
        best.objective.unwrap()
    );
    assert!(
        outcome.evaluations.len() <= problem.study.optimizer.budget() + 5,
        "{} points for a budget of {}",
        outcome.evaluations.len(),
        problem.study.optimizer.budget()
    );
}

/// Samples are drawn once and reused at every point, and the result does not depend on how many
/// threads run them.
#[test]
fn robust_evaluation_is_reproducible_across_thread_counts() {
    let (mut problem, _) = tiny();
    problem.simulation.duration = 0.6;
    problem.simulation.settling_time = 0.2;
    let text = r#"
[uncertain]
samples = 3
seed = 7
[[uncertain.parameter]]
key = "model.bit.friction"
law = "gamma"
mean = "0.04 m"
cov = 0.2
"#;
    let extra = Problem::from_toml(
        &(std::fs::read_to_string(&problem.source).unwrap() + text),
        &problem.source,
    )
    .unwrap();
    problem.study = extra.study;
    let op = [
        OperatingPoint {
            omega: 8.0,
            v0: 10.0 / 3600.0,
            wob: 0.0,
        },
        OperatingPoint {
            omega: 10.0,
            v0: 12.0 / 3600.0,
            wob: 0.0,
        },
    ];
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| RobustEvaluator::new(&problem, None).unwrap().evaluate(&op))
    };
    let (one, two) = (run(1), run(2));
    assert_eq!(one, two);
    // Any executor, in any order of work, gives the same results in the same order.
    struct Reversed;
    impl SampleExecutor for Reversed {
        fn execute(&self, jobs: &[SampleJob], run: &RunJob, done: &OnResult) -> Vec<Simulated> {
            let mut out: Vec<Simulated> = (0..jobs.len())
                .rev()
                .map(|i| {
                    let r = run(jobs[i]);
                    done(i, &r);
                    r
                })
                .collect();
            out.reverse();
            out
        }
        fn describe(&self) -> String {
            "reversed".into()
        }
    }
    let with = |e: Box<dyn Fn(RobustEvaluator) -> RobustEvaluator>| {
        e(RobustEvaluator::new(&problem, None).unwrap()).evaluate(&op)
    };
    assert_eq!(with(Box::new(|ev| ev.with_executor(Serial))), one);
    assert_eq!(with(Box::new(|ev| ev.with_executor(Reversed))), one);
    assert_ne!(one[0], one[1], "two different points");
    let rops: Vec<f64> = one[0]
        .samples
        .iter()
        .map(|s| match &s.outcome {
            drillopt::study::SampleOutcome::Metrics(m) => m["mean_tob_nm"],
            _ => panic!("sample failed"),
        })
        .collect();
    assert!(
        rops[0] != rops[1] && rops[1] != rops[2],
        "the samples differ: {rops:?}"
    );
}

/// Start `drillopt solve`, kill it once some simulations are in the cache, resume it, and check
/// that exactly the unfinished work is simulated, compared with an uninterrupted run: it runs exactly the simulations the killed run had not finished, and takes
/// every one it had finished from the cache.
#[test]
fn resume_after_a_kill_resimulates_nothing_finished() {
    let (_, path) = tiny();
    let dir = tempfile::tempdir().unwrap();
    let exe = env!("CARGO_BIN_EXE_drillopt");
    let solve = |out: &std::path::Path, resume: bool| {
        let mut cmd = Command::new(exe);
        cmd.arg("solve")
            .arg(&path)
            .arg("--out")
            .arg(out)
            .arg("--quiet");
        if resume {
            cmd.arg("--resume");
        }
        cmd.stdout(Stdio::null()).stderr(Stdio::piped());
        cmd
    };
    let work = |out: &std::path::Path| -> serde_json::Value {
        let text = std::fs::read_to_string(out.join("solution.json")).unwrap();
        serde_json::from_str::<serde_json::Value>(&text).unwrap()["work"].clone()
    };
    // Reference: an uninterrupted run.
    let full = dir.path().join("full");
    let status = solve(&full, false).status().unwrap();
    assert!(status.success());
    let total = work(&full)["simulations_run"].as_u64().unwrap();
    // Points the optimizer asks for twice are answered by the cache within a run too.
    let repeats = work(&full)["simulations_from_cache"].as_u64().unwrap();
    assert!(
        total >= 8,
        "the reference run simulated only {total} points"
    );

    // Interrupted run: kill it once a third of the simulations are cached.
    let cut = dir.path().join("cut");
    let mut child = solve(&cut, false).spawn().unwrap();
    let cache_file = cut.join("cache.jsonl");
    let clock = Instant::now();
    loop {
        let lines = std::fs::read_to_string(&cache_file)
            .map(|t| t.lines().count())
            .unwrap_or(0);
        if lines as u64 >= total / 3 {
            break;
        }
        assert!(clock.elapsed() < Duration::from_secs(300), "no progress");
        assert!(
            child.try_wait().unwrap().is_none(),
            "finished before the kill"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
    child.kill().unwrap();
    child.wait().unwrap();
    assert!(!cut.join("solution.json").exists());
    let finished = EvalCache::open(&cache_file).unwrap().len() as u64;
    assert!(finished >= total / 3 && finished < total);

    let status = solve(&cut, true).status().unwrap();
    assert!(status.success());
    let w = work(&cut);
    let (run, cached) = (
        w["simulations_run"].as_u64().unwrap(),
        w["simulations_from_cache"].as_u64().unwrap(),
    );
    println!("total {total}; killed after {finished}; resumed: {run} run, {cached} from cache");
    assert_eq!(
        run,
        total - finished,
        "only the unfinished simulations are run"
    );
    assert_eq!(
        cached,
        finished + repeats,
        "every finished simulation is reused"
    );
    // Same optimum as the uninterrupted run.
    let opt = |out: &std::path::Path| {
        let text = std::fs::read_to_string(out.join("solution.json")).unwrap();
        serde_json::from_str::<serde_json::Value>(&text).unwrap()["optimum"].clone()
    };
    assert_eq!(opt(&full), opt(&cut));
}
