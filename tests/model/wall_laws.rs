//! Wall contact laws chosen in the problem file (issue 12): the seed paper's cubic law, the default,
//! and Hunt–Crossley's, each read and checked against its own parameter table, declared uncertain
//! by its own keys, keyed in the cache, and driving the simulator.

use crate::common;

use drillopt::problem::{Problem, ProblemError};
use drillopt::study::model_hash;
use std::path::Path;

const TINY: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/problems/regression/tiny_string.toml"
);
const SEED_WALL: &str = "[model.wall]
stiffness = \"1e10 N/m\"
cubic_stiffness = \"1e16 N/m^3\"
damping = 1e-9
friction = 1e-5
";

fn tiny() -> String {
    let t = std::fs::read_to_string(TINY).unwrap();
    assert!(
        t.contains(SEED_WALL),
        "the tiny string's wall table changed"
    );
    t
}

/// The tiny string with its `[model.wall]` table replaced by `wall`.
fn with_wall(wall: &str) -> String {
    tiny().replace(SEED_WALL, wall)
}

fn load(text: &str) -> Result<Problem, ProblemError> {
    Problem::from_toml(text, Path::new("cases/wall.toml"))
}

const HUNT_CROSSLEY: &str = "[model.wall]
law = \"hunt_crossley\"
stiffness = \"1e10 N/m\"
restitution = 0.8
impact_speed = \"0.1 m/s\"
friction = 1e-5
";

#[test]
fn the_law_is_chosen_by_name_with_its_defaults_and_the_default_is_the_papers() {
    let p = load(&with_wall(HUNT_CROSSLEY)).unwrap();
    let wall = &p.model.wall;
    assert_eq!(wall.law().name(), "hunt_crossley");
    assert_eq!(wall.get("restitution"), Some(0.8));
    assert_eq!(wall.get("impact_speed"), Some(0.1));
    assert_eq!(wall.get("sign_smoothing"), Some(1e-3), "default ε");
    assert_eq!(wall.get("cubic_stiffness"), None);
    // No law named: the paper's, and naming it changes nothing, not even the cache key.
    let seed = load(&tiny()).unwrap();
    assert_eq!(seed.model.wall.law().name(), "cubic");
    let named = load(&tiny().replace("[model.wall]\n", "[model.wall]\nlaw = \"cubic\"\n")).unwrap();
    assert_eq!(named.model, seed.model);
    assert_eq!(model_hash(&named), model_hash(&seed));
    assert_ne!(model_hash(&p), model_hash(&seed));
}

#[test]
fn unknown_laws_foreign_keys_and_missing_parameters_are_refused_by_key_in_one_pass() {
    let err = load(&with_wall(&HUNT_CROSSLEY.replace("hunt_crossley", "hertz"))).unwrap_err();
    assert_eq!(err.key(), Some("model.wall.law"), "{err}");
    for w in [
        "\"cubic\"",
        "\"hunt_crossley\"",
        "\"hertz\"",
        "cases/wall.toml",
    ] {
        assert!(err.to_string().contains(w), "{w}: {err}");
    }
    // A key of the cubic law under Hunt–Crossley, and Hunt–Crossley's restitution missing:
    // both reported, each naming what is allowed.
    let text = with_wall(
        &HUNT_CROSSLEY.replace("restitution = 0.8\n", "cubic_stiffness = \"1e16 N/m^3\"\n"),
    );
    let err = load(&text).unwrap_err();
    let keys: Vec<&str> = err.key_errors().iter().map(|e| e.key.as_str()).collect();
    assert_eq!(
        keys,
        ["model.wall.cubic_stiffness", "model.wall.restitution"],
        "{err}"
    );
    let msg = err.to_string();
    for w in [
        "the parameters of law = \"hunt_crossley\"",
        "restitution, impact_speed",
        "is required by law = \"hunt_crossley\"",
    ] {
        assert!(msg.contains(w), "{w}: {msg}");
    }
    // Out of range, with the range and its reason.
    let err = load(&with_wall(&HUNT_CROSSLEY.replace("0.8", "1.2"))).unwrap_err();
    assert_eq!(err.key(), Some("model.wall.restitution"));
    assert!(err.to_string().contains("in [0, 1]"), "{err}");
}

#[test]
fn uncertain_keys_are_those_of_the_chosen_law() {
    let uncertain = |wall: &str, key: &str| {
        format!(
            "{}\n[uncertain]\nsamples = 2\n[[uncertain.parameter]]\nkey = \"{key}\"\nlaw = \"uniform\"\nlow = 0.6\nhigh = 0.9\n",
            with_wall(wall)
        )
    };
    let p = load(&uncertain(HUNT_CROSSLEY, "model.wall.restitution")).unwrap();
    assert_eq!(p.study.uncertain[0].key.name(), "model.wall.restitution");
    let err = load(&uncertain(SEED_WALL, "model.wall.restitution")).unwrap_err();
    assert_eq!(err.key(), Some("uncertain.parameter[0].key"), "{err}");
    assert!(
        err.to_string().contains("model.wall.cubic_stiffness"),
        "{err}"
    );
}

/// Metrics of a 0.6 s run of the tiny string at 8 rad/s, 10 m/h.
fn run(p: &Problem) -> Vec<(&'static str, f64)> {
    common::tiny_run_metrics(p)
}

#[test]
fn hunt_crossley_without_damping_is_the_papers_law_without_its_cubic_and_damping_terms() {
    // e = 1: F = −Kδ, the cubic law with k₂ = c = 0; the runs agree to the last bit.
    let linear = "[model.wall]\nstiffness = \"1e10 N/m\"\ncubic_stiffness = 0\ndamping = 0\nfriction = 1e-5\n";
    let elastic = HUNT_CROSSLEY.replace("0.8", "1.0");
    let a = run(&load(&with_wall(linear)).unwrap());
    let b = run(&load(&with_wall(&elastic)).unwrap());
    for ((name, x), (_, y)) in a.iter().zip(&b) {
        assert!(x == y || (x.is_nan() && y.is_nan()), "{name}: {x} vs {y}");
    }
    // With damping (e = 0.8) the run drills and closes its energy balance as well as the
    // seed's law does.
    let damped = run(&load(&with_wall(HUNT_CROSSLEY)).unwrap());
    let get = |m: &[(&str, f64)], k: &str| m.iter().find(|(n, _)| *n == k).unwrap().1;
    let residual = get(&damped, "energy_balance_residual");
    assert!(
        residual < 2.0 * get(&a, "energy_balance_residual").max(1e-3),
        "{residual}"
    );
    assert!((get(&damped, "mean_rop_m_per_h") / 10.0 - 1.0).abs() < 0.05);
}
