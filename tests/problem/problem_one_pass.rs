//! Issue 13 item 12: oilfield units in problem files, and every refusal of a file reported in one
//! pass (unknown keys, units, ranges), one line per refused key, each naming the file and the key.

use drillopt::problem::{Problem, ProblemError};
use std::path::Path;

const TINY: &str = include_str!("../../problems/regression/tiny_string.toml");
const FILE: &str = "cases/one_pass.toml";

/// `TINY` without its optimizer `start` (some edits set their own) and with each `(old line,
/// new line)` substituted (each old line must occur exactly once).
fn edit(edits: &[(&str, &str)]) -> String {
    let mut text: String = TINY
        .lines()
        .filter(|l| !l.starts_with("start = "))
        .map(|l| format!("{l}\n"))
        .collect();
    for (old, new) in edits {
        assert_eq!(text.matches(old).count(), 1, "`{old}` must occur once");
        text = text.replace(old, new);
    }
    text
}

fn load(text: &str) -> Result<Problem, ProblemError> {
    Problem::from_toml(text, Path::new(FILE))
}

#[test]
fn oilfield_units_are_read_in_problem_files() {
    let p = load(&edit(&[
        (
            "youngs_modulus = \"203 GPa\"",
            "youngs_modulus = \"29.4e6 psi\"",
        ),
        ("density = \"1200 kg/m^3\"", "density = \"10 ppg\""),
        ("density = \"7900 kg/m^3\"", "density = \"7.9 sg\""),
        ("limit_force = \"250 kN\"", "limit_force = \"56.2 klbf\""),
        ("radius = \"70 mm\"", "radius = \"5.5 in\""),
    ]))
    .unwrap_or_else(|e| panic!("{e}"));
    let rel = |a: f64, b: f64| (a - b).abs() <= 1e-14 * b.abs();
    assert!(rel(p.model.pipe.youngs_modulus, 29.4e6 * 6894.757293168));
    assert!(rel(p.model.fluid_density, 10.0 * 119.826427));
    assert!(rel(p.model.pipe.density, 7900.0));
    assert!(rel(p.model.borehole_radius, 5.5 * 0.0254));
    let limit = p.model.bit.get("limit_force").unwrap();
    assert!(rel(limit, 56.2e3 * 4.4482216152605), "{limit}");
}

#[test]
fn every_refusal_of_a_file_is_reported_in_one_pass() {
    let text = edit(&[
        ("length = \"8 m\"", "length = \"8 furlongs\""),
        (
            "poisson_ratio = 0.3",
            "poisson_ratio = 0.3\ncolour = \"red\"",
        ),
        ("friction = 1e-5", "friction = 1e308"),
        ("omega = \"60 rpm\"", "omega = \"60 rps\""),
        ("duration = \"1.5 s\"", "duration = \"1e9 s\""),
        (
            "v0 = [\"2 m/h\", \"20 m/h\"]",
            "v0 = [\"2 m/h\", \"20 knots\"]",
        ),
        ("grid = [9, 9]", "grid = [9, 9]\nstep = 3"),
    ]);
    let err = load(&text).expect_err("seven refusals");
    assert!(matches!(err, ProblemError::Invalid { .. }), "{err:?}");
    let keys: Vec<&str> = err.key_errors().iter().map(|e| e.key.as_str()).collect();
    assert_eq!(
        keys,
        [
            "model.pipe.colour",
            "optimizer.step",
            "model.length",
            "model.wall.friction",
            "operating_point.omega",
            "simulation.duration",
            "constraints.v0[1]",
        ],
        "{err}"
    );
    // The first-error accessor still works, and Display gives one line per refusal, each with
    // the file and the key.
    assert_eq!(err.key(), Some("model.pipe.colour"));
    let msg = err.to_string();
    let lines: Vec<&str> = msg.lines().collect();
    assert_eq!(lines.len(), keys.len(), "{msg}");
    for (line, key) in lines.iter().zip(&keys) {
        assert!(
            line.starts_with(&format!("{FILE}: key `{key}`: ")),
            "{line}"
        );
    }
    assert!(lines[2].contains("unknown unit `furlongs`"), "{msg}");
    assert!(lines[3].contains("[0, 2]"), "{msg}");
    assert!(lines[5].contains("at most a day"), "{msg}");
}

#[test]
fn a_refused_value_does_not_cause_refusals_of_the_values_checked_against_it() {
    // The outer radius is refused; the borehole and inner-radius checks that compare with it
    // must not add refusals of their own.
    let text = edit(&[("outer_radius = \"60 mm\"", "outer_radius = \"60 mmm\"")]);
    let err = load(&text).expect_err("refused");
    let keys: Vec<&str> = err.key_errors().iter().map(|e| e.key.as_str()).collect();
    assert_eq!(keys, ["model.pipe.outer_radius"], "{err}");
    // A bound refused: the start point and the range check are not judged against it.
    let text = edit(&[
        (
            "omega = [\"30 rpm\", \"150 rpm\"]",
            "omega = [\"30 rpm\", \"150 rmp\"]",
        ),
        (
            "grid = [9, 9]",
            "grid = [9, 9]\nstart = [\"60 rpm\", \"5 m/h\"]",
        ),
    ]);
    let err = load(&text).expect_err("refused");
    let keys: Vec<&str> = err.key_errors().iter().map(|e| e.key.as_str()).collect();
    assert_eq!(keys, ["constraints.omega[1]"], "{err}");
}

#[test]
fn a_value_of_the_wrong_type_does_not_hide_the_other_refusals() {
    // A required key of the wrong type (`mesh.elements` a string), an optional one (`poisson_ratio`
    // a boolean), an unknown choice and a value out of range: all four in one pass, and nothing
    // about the stand-ins (the basis is checked against the element count, which is refused).
    let text = edit(&[
        ("elements = 12", "elements = \"twelve\""),
        ("poisson_ratio = 0.3", "poisson_ratio = true"),
        ("duration = \"1.5 s\"", "duration = \"-1 s\""),
    ])
    .replace("[model.bit]\n", "[model.bit]\nlaw = \"expo\"\n");
    let err = load(&text).expect_err("refused");
    let keys: Vec<&str> = err.key_errors().iter().map(|e| e.key.as_str()).collect();
    assert_eq!(
        keys,
        [
            "mesh.elements",
            "model.pipe.poisson_ratio",
            "model.bit.law",
            "simulation.duration"
        ],
        "{err}"
    );
    let text = err.to_string();
    assert!(
        text.contains("must be an integer in [1, 2000] (far beyond any useful mesh")
            && text.contains("got string \"twelve\""),
        "{text}"
    );
    assert!(text.contains("got \"expo\""), "{text}");
    // Two required keys of the wrong type, one a table: both said, and the file's other values
    // still checked.
    let text = edit(&[
        ("elements = 12", "elements = 12.5"),
        ("time_step = \"10 ms\"", "time_step = [1]"),
        ("duration = \"1.5 s\"", "duration = \"1.5 ss\""),
    ]);
    let err = load(&text).expect_err("refused");
    let keys: Vec<&str> = err.key_errors().iter().map(|e| e.key.as_str()).collect();
    assert_eq!(
        keys,
        [
            "mesh.elements",
            "simulation.time_step",
            "simulation.duration"
        ],
        "{err}"
    );
}

#[test]
fn a_misspelt_required_key_does_not_hide_the_other_refusals() {
    // `max_probabilty` for `max_probability` in a chance constraint: the unknown key, the
    // missing one, and the file's other mistakes (a value of the wrong type, one out of range)
    // in one pass.
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/problems/regression/slim_pipe_fatigue.toml"
    ))
    .unwrap();
    let first = "threshold = \"0.05 1/h\"\nmax_probability = 0.1";
    assert_eq!(text.matches(first).count(), 1);
    let poisson = "poisson_ratio = 0.3";
    assert_eq!(text.matches(poisson).count(), 1);
    let text = text
        .replace(first, "threshold = \"0.05 1/h\"\nmax_probabilty = 0.1")
        .replace(poisson, "poisson_ratio = 0.7");
    let text = text.replacen("elements = ", "elements = \"many\" # ", 1);
    let err = Problem::from_toml(&text, Path::new(FILE)).expect_err("refused");
    let keys: Vec<&str> = err.key_errors().iter().map(|e| e.key.as_str()).collect();
    for key in [
        "constraints.chance[0].max_probabilty",
        "constraints.chance[0].max_probability",
        "mesh.elements",
        "model.pipe.poisson_ratio",
    ] {
        assert!(keys.contains(&key), "{key}: {err}");
    }
    assert!(
        err.to_string()
            .contains("max_probability`: is required: the largest admissible probability"),
        "{err}"
    );
}
