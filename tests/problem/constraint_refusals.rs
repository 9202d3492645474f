//! Issue 13 item 9: refusals of the study constraints name the key and speak the user's units;
//! a linear coefficient of 1e308 is refused at load (not an optimizer NaN), and a problem whose
//! constraints leave no feasible point says which constraint, in words.

use drillopt::problem::Problem;
use std::path::Path;
use std::process::Command;

const TINY: &str = include_str!("../../problems/regression/tiny_string.toml");

/// `TINY` with each edit, and without its `[expect] active` line (these tests edit the
/// constraints that line names).
fn edit(edits: &[(&str, &str)]) -> String {
    let mut text: String = TINY
        .lines()
        .filter(|l| !l.starts_with("active = ") && !l.starts_with("start = "))
        .map(|l| format!("{l}\n"))
        .collect();
    for (old, new) in edits {
        assert_eq!(text.matches(old).count(), 1, "`{old}` must occur once");
        text = text.replace(old, new);
    }
    text
}

const DEPTH: &str = "max_depth_of_cut = \"3 mm\"";
const OMEGA: &str = "omega = [\"30 rpm\", \"150 rpm\"]";
const V0: &str = "v0 = [\"2 m/h\", \"20 m/h\"]";

/// The refusals of `text` as (key, message) pairs.
fn refusals(text: &str) -> Vec<(String, String)> {
    let err = Problem::from_toml(text, Path::new("c.toml")).expect_err("refused");
    err.key_errors()
        .iter()
        .map(|e| (e.key.clone(), e.message.clone()))
        .collect()
}

#[test]
fn huge_linear_coefficients_are_refused_naming_the_key_and_range() {
    let r = refusals(&edit(&[(
        DEPTH,
        "[[constraints.linear]]\nomega = 1e308\nv0 = 1.0\nupper = -1e308",
    )]));
    assert_eq!(r.len(), 2, "{r:?}");
    assert_eq!(r[0].0, "constraints.linear[0].omega");
    assert!(
        r[0].1.contains("[1e-9, 1e9]") && r[0].1.contains("got 1e308"),
        "{r:?}"
    );
    assert_eq!(r[1].0, "constraints.linear[0].upper");
    // A tiny non-zero coefficient would lose the row's norm to round-off.
    let r = refusals(&edit(&[(
        DEPTH,
        "[[constraints.linear]]\nomega = 0.0\nv0 = 1e-320\nupper = 1.0",
    )]));
    assert_eq!(r[0].0, "constraints.linear[0].v0", "{r:?}");
}

#[test]
fn inverted_bounds_are_echoed_in_the_units_typed() {
    let r = refusals(&edit(&[
        (OMEGA, "omega = [\"150 rpm\", \"30 rpm\"]"),
        (V0, "v0 = [\"20 m/h\", \"2 m/h\"]"),
    ]));
    assert_eq!(r[0].0, "constraints.omega");
    assert!(r[0].1.contains("[150 rpm, 30 rpm]"), "{r:?}");
    assert!(!r[0].1.contains("rad/s"), "{r:?}");
    assert_eq!(r[1].0, "constraints.v0");
    assert!(r[1].1.contains("[20 m/h, 2 m/h]"), "{r:?}");
}

#[test]
fn a_start_point_outside_the_bounds_is_refused_in_rpm_and_m_per_h() {
    // 80 rad/s = 764 rpm.
    let r = refusals(&edit(&[(
        "grid = [9, 9]",
        "grid = [9, 9]\nstart = [\"80 rad/s\", \"5 m/h\"]",
    )]));
    assert_eq!(r.len(), 1, "{r:?}");
    assert_eq!(r[0].0, "optimizer.start");
    assert!(
        r[0].1.contains("[30, 150] rpm") && r[0].1.contains("763.9437 rpm"),
        "{r:?}"
    );
}

/// `drillopt solve` on `text`: exit code and stderr (refused before anything is simulated).
fn solve(text: &str) -> (Option<i32>, String) {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("p.toml");
    std::fs::write(&file, text).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_drillopt"))
        .args(["solve", file.to_str().unwrap(), "--quiet", "--out"])
        .arg(dir.path().join("out"))
        .output()
        .expect("drillopt runs");
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn no_feasible_point_is_explained_in_words() {
    let (code, err) = solve(&edit(&[(DEPTH, "max_depth_of_cut = \"0.01 mm\"")]));
    assert_eq!(code, Some(1), "{err}");
    assert!(!err.contains("Some(") && !err.contains("row"), "{err}");
    assert!(
        err.contains("constraints.max_depth_of_cut")
            && err.contains("Ω ∈ [30, 150] rpm")
            && err.contains("V0 ∈ [2, 20] m/h")
            && err.contains("cuts 0.2222 mm per revolution"),
        "{err}"
    );
    let (code, err) = solve(&edit(&[(
        DEPTH,
        "[[constraints.linear]]\nomega = 0.0\nv0 = 1.0\nupper = 1e-4",
    )]));
    assert_eq!(code, Some(1), "{err}");
    assert!(!err.contains("Some("), "{err}");
    assert!(
        err.contains("constraints.linear[0] (0 Ω + 1 V0 ≤ 0.0001, SI)"),
        "{err}"
    );
}
