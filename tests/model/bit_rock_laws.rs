//! Bit–rock laws chosen in the problem file (issue 12): the seed's exponential law and
//! Detournay's drag-bit law, each read and checked against its own parameter table, declared
//! uncertain by its own keys, and driving the simulator. References are closed forms written here
//! from the raw numbers of `problems/seed_detournay.toml`, not from the crate's law.

use crate::common;

use drillopt::model::OperatingPoint;
use drillopt::problem::{Problem, ProblemError};
use drillopt::rom::ReducedModel;
use drillopt::sim::{Effects, InitialState, RunSettings, preloaded_equilibrium, simulate};
use std::f64::consts::PI;
use std::path::Path;

const DETOURNAY: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/problems/seed_detournay.toml");

fn text() -> String {
    std::fs::read_to_string(DETOURNAY).unwrap()
}

fn load(text: &str) -> Result<Problem, ProblemError> {
    Problem::from_toml(text, Path::new("cases/bit.toml"))
}

fn refused(text: &str, key: &str, words: &[&str]) {
    let err = load(text).expect_err("should be refused");
    let msg = err.to_string();
    assert_eq!(err.key(), Some(key), "{msg}");
    for w in words {
        assert!(msg.contains(w), "message lacks {w:?}: {msg}");
    }
}

/// Detournay's phase-II law from the file's numbers: (WOB N, TOB N·m) at V (m/s) and Ω (rad/s),
/// with the file's regularisation ω_r = 0.5 rad/s and v_r = 1e-4 m/s (defaults).
fn detournay_closed_form(v: f64, omega: f64) -> (f64, f64) {
    let (a, eps, zeta, sigma, l, mu, gamma) = (0.07, 200e6, 0.7, 150e6, 3e-3, 0.6, 1.0);
    let d = 2.0 * PI * v / (omega * omega + 0.25).sqrt();
    let wf = sigma * a * l * (v / 1e-4).tanh();
    let s = (omega / 0.5).tanh();
    (
        zeta * eps * a * d + wf,
        (0.5 * eps * a * a * d + 0.5 * mu * gamma * a * wf) * s,
    )
}

#[test]
fn the_law_is_chosen_by_name_with_its_defaults() {
    let p = load(&text()).unwrap();
    let bit = &p.model.bit;
    assert_eq!(bit.law().name(), "detournay");
    assert_eq!(bit.get("radius"), Some(0.07));
    assert_eq!(bit.get("specific_energy"), Some(200e6));
    assert_eq!(bit.get("geometry"), Some(1.0), "default γ");
    assert_eq!(bit.get("spin_smoothing"), Some(0.5), "default ω_r");
    assert_eq!(bit.get("limit_force"), None);
    // The shipped seed names no law: the paper's exponential law.
    assert_eq!(common::seed().model.bit.law().name(), "exponential");
}

#[test]
fn unknown_laws_foreign_keys_and_missing_parameters_are_refused_by_key() {
    let t = text();
    refused(
        &t.replace("law = \"detournay\"", "law = \"drag\""),
        "model.bit.law",
        &["\"exponential\"", "\"detournay\"", "\"drag\""],
    );
    refused(
        &t.replace("friction = 0.6 ", "rate = \"180 s/m\"\nfriction = 0.6 "),
        "model.bit.rate",
        &[
            "unknown field",
            "parameters of law = \"detournay\"",
            "specific_energy",
            "inertia",
        ],
    );
    refused(
        &t.replace("wear_flat_length = \"3 mm\"", ""),
        "model.bit.wear_flat_length",
        &["is required by law = \"detournay\""],
    );
    refused(
        &t.replace("\"200 MPa\"", "\"200 GPa\""),
        "model.bit.specific_energy",
        &["[1e6, 2e9] Pa"],
    );
    // The exponential law refuses Detournay's keys just as well.
    let seed = std::fs::read_to_string(common::SEED).unwrap();
    refused(
        &seed.replace("[model.bit]", "[model.bit]\nradius = \"70 mm\""),
        "model.bit.radius",
        &["the parameters of law = \"exponential\"", "limit_force"],
    );
}

#[test]
fn uncertain_keys_are_those_of_the_chosen_law() {
    let uncertain = |key: &str| {
        format!(
            "{}\n[uncertain]\nsamples = 2\n[[uncertain.parameter]]\nkey = \"{key}\"\nlaw = \"gamma\"\nmean = {}\ncov = 0.1\n",
            text(),
            if key.ends_with("energy") {
                "\"200 MPa\""
            } else {
                "\"250 kN\""
            }
        )
    };
    let p = load(&uncertain("model.bit.specific_energy")).unwrap();
    assert_eq!(p.study.uncertain[0].key.name(), "model.bit.specific_energy");
    refused(
        &uncertain("model.bit.limit_force"),
        "uncertain.parameter[0].key",
        &["model.bit.specific_energy", "model.wall.friction"],
    );
}

#[test]
fn the_simulator_runs_the_chosen_law_from_its_steady_state() {
    let mut p = load(&text()).unwrap();
    p.mesh.elements = 30;
    p.mesh.basis = common::small_basis();
    let model = ReducedModel::new(&p.model, p.mesh.elements, &p.mesh.basis).unwrap();
    let op = OperatingPoint {
        omega: 2.0 * PI,
        v0: 5.0 / 3600.0,
        wob: 0.0,
    };
    // The pre-loaded state carries the law's WOB and TOB at (V0, Ω).
    let (q, _) = preloaded_equilibrium(&model, op, Effects::ALL).unwrap();
    let zero = nalgebra::DVector::zeros(model.size());
    let mut sys = drillopt::sim::Dynamics::new(&model, op, Effects::ALL);
    let obs = sys.observe(&q, &zero, &zero);
    let (wob, tob) = detournay_closed_form(op.v0, op.omega);
    assert!(
        (-obs.bit.force / wob - 1.0).abs() < 1e-12,
        "WOB {}",
        -obs.bit.force
    );
    assert!(
        (-obs.bit.torque / tob - 1.0).abs() < 1e-12,
        "TOB {}",
        -obs.bit.torque
    );
    assert!(
        (40e3..50e3).contains(&wob) && (1.2e3..1.5e3).contains(&tob),
        "{wob} {tob}"
    );
    // A short run from there drills at V0 and keeps the energy balance.
    let settings = RunSettings::new(1.0, p.simulation.time_step);
    let out = simulate(
        &model,
        op,
        Effects::ALL,
        &settings,
        InitialState::Preloaded,
        |_| {},
    );
    assert!(out.error.is_none(), "{:?}", out.error);
    let s = &out.series;
    let rop = (s.bit_displacement.last().unwrap() - s.bit_displacement[0])
        / (s.t.last().unwrap() - s.t[0]);
    assert!((rop / op.v0 - 1.0).abs() < 0.05, "ROP {} m/h", rop * 3600.0);
}
