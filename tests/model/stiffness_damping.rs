//! Stiffness-proportional damping: `[model.pipe] stiffness_damping` = β, C = c M_pipe + β K
//! (Rayleigh damping). Read in any time unit and refused outside [0, 1 ms] by name; absent, the
//! paper's model and its cache key; present, a different key and a run that dissipates more.
//! The closed-form modal damping ratio ζ = βω/2 and the decay of a torsional mode are checked in
//! `campbell::spectrum` and `tests/model/simulator_physics.rs`.

use crate::common;

use drillopt::problem::{Problem, ProblemError};
use drillopt::study::model_hash;
use std::path::Path;

fn seed_text() -> String {
    std::fs::read_to_string(common::SEED).unwrap()
}

/// The seed with `stiffness_damping = value` in `[model.pipe]`.
fn with_beta(value: &str) -> String {
    seed_text().replacen(
        "[model.pipe]\n",
        &format!("[model.pipe]\nstiffness_damping = {value}\n"),
        1,
    )
}

fn load(text: &str) -> Result<Problem, ProblemError> {
    Problem::from_toml(text, Path::new("cases/damped.toml"))
}

#[test]
fn the_key_is_read_in_any_time_unit_and_refused_outside_its_range_by_name() {
    assert_eq!(load(&seed_text()).unwrap().model.stiffness_damping, 0.0);
    for (value, beta) in [
        ("\"10 us\"", 1e-5),
        ("\"0.01 ms\"", 1e-5),
        ("\"1e-5 s\"", 1e-5),
    ] {
        let p = load(&with_beta(value)).unwrap();
        assert!(
            (p.model.stiffness_damping / beta - 1.0).abs() < 1e-12,
            "{value}: {}",
            p.model.stiffness_damping
        );
    }
    for (value, words) in [
        ("\"2 ms\"", "must be in [0, 0.001] s"),
        ("\"-1e-6 s\"", "must be in [0, 0.001] s"),
        ("\"10 kg\"", "unknown unit"),
        ("\"nan s\"", "model.pipe.stiffness_damping"),
    ] {
        let err = load(&with_beta(value)).unwrap_err();
        let msg = err.to_string();
        assert_eq!(err.key(), Some("model.pipe.stiffness_damping"), "{msg}");
        assert!(
            msg.contains(words) && msg.contains("cases/damped.toml"),
            "{value}: {msg}"
        );
    }
}

#[test]
fn the_cache_key_changes_only_with_damping() {
    let seed = model_hash(&load(&seed_text()).unwrap());
    assert_eq!(model_hash(&load(&with_beta("0")).unwrap()), seed);
    assert_ne!(model_hash(&load(&with_beta("\"10 us\"")).unwrap()), seed);
}

/// An uncertain β whose law reaches beyond the key's range (1 ms) is refused when the problem is
/// read, at either end, not at the sample that draws it (a fresh user's review: a uniform law up to
/// 2 ms loaded and failed at sample 0 of `compare`).
#[test]
fn an_uncertain_beta_whose_law_leaves_the_range_is_refused_at_load() {
    let with_law = |law: &str| {
        format!(
            "{}\n[uncertain]\nsamples = 4\nseed = 1\n\n[[uncertain.parameter]]\nkey = \"model.pipe.stiffness_damping\"\n{law}\n",
            seed_text()
        )
    };
    for (law, words) in [
        (
            "law = \"uniform\"\nlow = \"0.5 ms\"\nhigh = \"2 ms\"",
            "upper end = 0.002",
        ),
        (
            "law = \"gamma\"\nmean = \"0.9 ms\"\ncov = 0.05",
            "mean + 4σ or the upper end",
        ),
        (
            "law = \"normal\"\nmean = \"10 us\"\nstd = \"5 us\"",
            "mean − 4σ or the lower end",
        ),
    ] {
        let err = load(&with_law(law)).unwrap_err();
        let msg = err.to_string();
        assert_eq!(err.key(), Some("uncertain.parameter[0].law"), "{msg}");
        assert!(msg.contains(words), "{law}: {msg}");
    }
    let p = load(&with_law("law = \"gamma\"\nmean = \"10 us\"\ncov = 0.1")).unwrap();
    assert_eq!((p.study.samples, p.study.uncertain.len()), (4, 1));
}
