//! Monte Carlo samples over MPI ranks (issue 15; built with `--features mpi`, needs `mpirun` of
//! Open MPI or MPICH on PATH): `mpirun -n 3 drillopt compare|batch …` gives bitwise the results of
//! the threads executor, and says which executor ran.

#![cfg(feature = "mpi")]

use serde_json::Value;
use std::path::Path;
use std::process::Command;

const EXE: &str = env!("CARGO_BIN_EXE_drillopt");
const TINY: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/problems/regression/tiny_string.toml"
);

/// `drillopt args…` under `mpirun -n ranks` (0: without mpirun). Open MPI refuses root and more
/// ranks than cores unless told; the environment tells it (MPICH ignores these variables).
fn drillopt(ranks: usize, args: &[&str]) {
    let mut cmd = if ranks == 0 {
        Command::new(EXE)
    } else {
        let mut c = Command::new("mpirun");
        c.args(["-n", &ranks.to_string(), EXE]);
        c
    };
    let out = cmd
        .args(args)
        .env("OMPI_ALLOW_RUN_AS_ROOT", "1")
        .env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
        .env("OMPI_MCA_rmaps_base_oversubscribe", "1")
        .output()
        .expect("mpirun is on PATH (install openmpi-bin)");
    assert!(
        out.status.success(),
        "{args:?} on {ranks} ranks: {}",
        String::from_utf8_lossy(&out.stderr)
    );
}

fn json(path: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// A two-sample study of the tiny string, so that every point has several jobs to deal out.
fn uncertain_tiny(dir: &Path) -> String {
    let text = std::fs::read_to_string(TINY).unwrap()
        + "\n[uncertain]\nsamples = 3\nseed = 11\n[[uncertain.parameter]]\nkey = \"model.bit.friction\"\nlaw = \"gamma\"\nmean = \"0.04 m\"\ncov = 0.2\n";
    let path = dir.join("tiny_uncertain.toml");
    std::fs::write(&path, text).unwrap();
    path.display().to_string()
}

#[test]
fn ranks_give_the_results_of_threads_bit_for_bit() {
    let dir = tempfile::tempdir().unwrap();
    let problem = uncertain_tiny(dir.path());
    let run = |ranks: usize, out: &str| {
        let out = dir.path().join(out);
        drillopt(
            ranks,
            &[
                "compare",
                &problem,
                "--point",
                "60rpm,10m/h",
                "--point",
                "90rpm,15m/h",
                "--point",
                "120rpm,18m/h",
                "--out",
                out.to_str().unwrap(),
                "--quiet",
            ],
        );
        json(&out.join("compare.json"))
    };
    let threads = run(0, "threads");
    let ranks = run(3, "ranks");
    assert_eq!(ranks["points"], threads["points"]);
    assert_eq!(threads["work"]["simulations_run"], 9);
    assert_eq!(ranks["work"]["simulations_run"], 9);
    assert_eq!(ranks["work"]["executor"], "3 MPI ranks");
    assert!(
        threads["work"]["executor"]
            .as_str()
            .unwrap()
            .contains(" thread"),
        "1 thread or n threads"
    );
}

#[test]
fn a_batch_over_ranks_switches_problems_and_lands_as_with_threads() {
    let dir = tempfile::tempdir().unwrap();
    let regression = concat!(env!("CARGO_MANIFEST_DIR"), "/problems/regression");
    let (a, b) = (dir.path().join("ranks"), dir.path().join("threads"));
    drillopt(
        2,
        &["batch", regression, "--out", a.to_str().unwrap(), "--quiet"],
    );
    drillopt(
        0,
        &["batch", regression, "--out", b.to_str().unwrap(), "--quiet"],
    );
    for name in ["tiny_string", "slim_pipe_buckling", "slim_pipe_wide_hole"] {
        let (mut x, mut y) = (
            json(&a.join(name).join("solution.json")),
            json(&b.join(name).join("solution.json")),
        );
        x.as_object_mut().unwrap().remove("work");
        y.as_object_mut().unwrap().remove("work");
        assert_eq!(x, y, "{name}");
    }
}
