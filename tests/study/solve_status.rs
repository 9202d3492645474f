//! A solve that runs out of evaluations says so: `solution.json` → `status` is
//! "budget_exhausted" (not an optimum) and the terminal does not call its point an optimum; a
//! converged one says "converged".

use serde_json::Value;
use std::process::Command;

fn solve(problem: &str, out: &std::path::Path) -> (Value, String) {
    let run = Command::new(env!("CARGO_BIN_EXE_drillopt"))
        .args(["solve", problem, "--quiet", "--out", out.to_str().unwrap()])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("drillopt runs");
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let json = std::fs::read_to_string(out.join("solution.json")).unwrap();
    (
        serde_json::from_str(&json).unwrap(),
        String::from_utf8_lossy(&run.stdout).into_owned(),
    )
}

#[test]
fn the_status_tells_a_spent_budget_from_convergence() {
    let dir = tempfile::tempdir().unwrap();
    let tiny = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/problems/regression/tiny_string.toml"
    ))
    .unwrap();
    assert!(tiny.contains("max_evaluations = 30"));
    let short = dir.path().join("tiny_budget.toml");
    std::fs::write(
        &short,
        tiny.replace("max_evaluations = 30", "max_evaluations = 3"),
    )
    .unwrap();
    let (json, stdout) = solve(short.to_str().unwrap(), &dir.path().join("budget"));
    assert_eq!(
        json["status"], "budget_exhausted",
        "{}",
        json["termination"]
    );
    assert!(stdout.contains("NOT an optimum"), "{stdout}");
    let (json, stdout) = solve(
        "problems/regression/tiny_string.toml",
        &dir.path().join("full"),
    );
    assert_eq!(json["status"], "converged", "{}", json["termination"]);
    // On the V0 bound near the vertex with the depth of cut (111.1 rpm): problems/regression.
    assert!(
        stdout.contains("optimum: Ω = 11") && stdout.contains("V0 = 20.00 m/h"),
        "{stdout}"
    );
    // The report records the problem file itself and its FNV-1a hash (computed here anew).
    assert_eq!(json["problem_toml"].as_str().unwrap(), tiny);
    let fnv = tiny.bytes().fold(0xcbf2_9ce4_8422_2325_u64, |h, b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    });
    assert_eq!(json["problem_hash"], format!("{fnv:016x}"));
}

#[test]
fn a_held_bound_whose_slope_cannot_be_estimated_says_so() {
    // A 3 x 3 grid: its neighbours lie half the box apart, none within the fit's 15 %, so the
    // score's slope at the optimum (on a bound) is not estimated, and the terminal says why.
    let dir = tempfile::tempdir().unwrap();
    let tiny = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/problems/regression/tiny_string.toml"
    ))
    .unwrap();
    let start = tiny.find("[optimizer]").unwrap();
    let end = start + tiny[start..].find("start = [").unwrap();
    let end = end + tiny[end..].find('\n').unwrap();
    let grid = format!(
        "{}[optimizer]\nmethod = \"grid\"\ngrid = [3, 3]{}",
        &tiny[..start],
        &tiny[end..]
    );
    let file = dir.path().join("tiny_grid.toml");
    std::fs::write(&file, grid).unwrap();
    let (json, stdout) = solve(file.to_str().unwrap(), &dir.path().join("grid"));
    assert_eq!(json["status"], "grid_complete", "{}", json["termination"]);
    assert!(stdout.contains("held by: "), "{stdout}");
    assert!(
        stdout.contains("what moving a bound would change is not estimated"),
        "{stdout}"
    );
    assert!(json["score_slope"].is_null(), "{}", json["score_slope"]);
}
