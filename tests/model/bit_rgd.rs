//! The depth-of-cut bit law with the blades' delay (`[model.bit] law = "rgd"`, MODEL.md §11.7)
//! in the simulator, end to end.
//!
//! Reference: steady drilling is a state of the delay law. At constant Ω and V the blades cut the
//! helix of pitch d = 2πV/Ω, and the rock answers with Detournay & Defourny's closed form
//! W = ζεa d + σaℓ, T = ½εa²d + ½μγa σaℓ (computed here from the raw numbers of
//! `problems/seed_detournay.toml`). A run started there (the start installs that bottom hole)
//! stays there until the delay's instability (Richard, Germay & Detournay 2007) has grown out of
//! round-off, a few tenths of a second: any error in where the rock is (the rigid motion
//! s + Ω t, the block's position of a free top, the read ahead of the blade, the cut behind it)
//! shows at once as a depth of cut that drifts.
//!
//! And the delay's instability itself, against the characteristic equation of the linearised
//! delay system computed here apart from the simulator (after Richard, Germay & Detournay 2007 and
//! Germay, Denoël & Detournay 2009, on the continuous string): see the module `delay`.

use crate::common;
mod delay;

use drillopt::model::{Autodriller, OperatingPoint, TopDrive};
use drillopt::problem::Problem;
use drillopt::rom::ReducedModel;
use drillopt::sim::{Effects, InitialState, RunSettings, TimeSeries, simulate};
use std::f64::consts::PI;

const SEED_DETOURNAY: &str = include_str!("../../problems/seed_detournay.toml");

/// seed_detournay.toml with its bit law `law` (4 blades for rgd).
fn problem(law: &str) -> Problem {
    let text = if law == "rgd" {
        SEED_DETOURNAY.replace("law = \"detournay\"", "law = \"rgd\"\nblades = 4")
    } else {
        SEED_DETOURNAY.to_string()
    };
    Problem::from_toml(&text, std::path::Path::new("seed_rgd.toml")).unwrap()
}

fn run(law: &str, top: TopDrive, op: OperatingPoint, duration: f64) -> TimeSeries {
    let mut string = problem(law).model;
    string.top = top;
    let model = ReducedModel::new(&string, 30, &common::small_basis()).unwrap();
    let out = simulate(
        &model,
        op,
        Effects::ALL,
        &RunSettings::new(duration, 1e-3),
        InitialState::Preloaded,
        |_| {},
    );
    assert!(out.error.is_none(), "{law}: {:?}", out.error);
    out.series
}

/// The largest drift of WOB, TOB (relative to their start) and of the bit's speed (relative to
/// its start) along a run.
fn worst_drift(s: &TimeSeries) -> f64 {
    let mut worst: f64 = 0.0;
    for k in 1..s.t.len() {
        for y in [&s.weight_on_bit, &s.torque_on_bit, &s.bit_velocity] {
            worst = worst.max((y[k] / y[0] - 1.0).abs());
        }
    }
    worst
}

/// Detournay & Defourny's steady WOB and TOB at ROP `v` and Ω `w` (module doc).
fn closed_form(v: f64, w: f64) -> (f64, f64) {
    let (zeta, eps, a, sigma, ell, mu) = (0.7, 200e6, 0.07, 150e6, 3e-3, 0.6);
    let d = 2.0 * PI * v / w;
    let flats = sigma * a * ell;
    (
        zeta * eps * a * d + flats,
        0.5 * eps * a * a * d + 0.5 * mu * a * flats,
    )
}

#[test]
fn under_the_imposed_feed_the_start_is_the_helix_of_steady_drilling() {
    let op = OperatingPoint {
        omega: 2.0 * PI,
        v0: 5.0 / 3600.0,
        wob: 0.0,
    };
    // 0.3 s is 1.2 blade periods: the blades cut the start's helix, then their own rock.
    let s = run("rgd", TopDrive::Feed, op, 0.3);
    assert!(s.t.len() > 100);
    let (wob, tob) = closed_form(op.v0, op.omega);
    assert!(
        (s.weight_on_bit[0] / wob - 1.0).abs() < 1e-9,
        "{}",
        s.weight_on_bit[0]
    );
    assert!(
        (s.torque_on_bit[0] / tob - 1.0).abs() < 1e-9,
        "{}",
        s.torque_on_bit[0]
    );
    let worst = worst_drift(&s);
    assert!(worst < 1e-6, "drift {worst:e}");
}

#[test]
fn under_an_autodriller_the_rock_is_fixed_while_the_block_moves() {
    // At the WOB limit the block runs at the ROP the rock allows (20.9 m/h at 120 rpm, against a
    // 30 m/h set-point): the block's position, not V0 t, carries the bit over the rock.
    let op = OperatingPoint {
        omega: 4.0 * PI,
        v0: 30.0 / 3600.0,
        wob: 0.0,
    };
    let top = TopDrive::Autodriller(Autodriller {
        wob_limit: 60e3,
        torque_limit: None,
        power_limit: None,
        time_constant: 1.0,
    });
    let s = run("rgd", top, op, 0.3);
    let speed = s.block_speed[s.t.len() - 1];
    assert!(speed < 0.75 * op.v0, "the limit binds: {speed}");
    // The bit's TOB is the closed form's at the bit's own speed.
    let (_, tob) = closed_form(s.bit_velocity[0], op.omega);
    assert!(
        (s.torque_on_bit[0] / tob - 1.0).abs() < 1e-9,
        "{}",
        s.torque_on_bit[0]
    );
    let worst = worst_drift(&s);
    assert!(worst < 1e-6, "drift {worst:e}");
}

#[test]
fn the_blade_count_is_a_whole_number_and_never_uncertain() {
    let text = |extra: &str| {
        SEED_DETOURNAY.replace("law = \"detournay\"", "law = \"rgd\"\nblades = 4") + extra
    };
    let refused = |extra: &str| {
        Problem::from_toml(&text(extra), std::path::Path::new("seed_rgd.toml"))
            .expect_err("refused")
            .to_string()
    };
    let uncertain = |key: &str| {
        format!(
            "\n[uncertain]\nsamples = 2\n\n[[uncertain.parameter]]\nkey = \"{key}\"\nlaw = \"uniform\"\nlow = 3\nhigh = 5\n"
        )
    };
    let m = refused(&uncertain("model.bit.blades"));
    assert!(m.contains("model.bit.blades") && m.contains("count"), "{m}");
    // An unknown key lists what can be uncertain: the rgd keys, not the blade count.
    let m = refused(&uncertain("model.bit.bladez"));
    assert!(m.contains("model.bit.contact_smoothing"), "{m}");
    assert!(!m.contains("model.bit.blades"), "{m}");
    let m = Problem::from_toml(
        &SEED_DETOURNAY.replace("law = \"detournay\"", "law = \"rgd\"\nblades = 4.5"),
        std::path::Path::new("seed_rgd.toml"),
    )
    .expect_err("refused")
    .to_string();
    assert!(
        m.contains("model.bit.blades") && m.contains("whole number"),
        "{m}"
    );
}

/// `verify`'s smoothing refinement halves the regularisation widths that act, and nothing else:
/// the depth-of-cut bit's three and the Coulomb wall's slip smoothing; the paper's torque-only
/// wall friction has its sign smoothing instead; a frictionless wall and the paper's bit law none.
#[test]
fn the_smoothing_refinement_halves_the_widths_that_act_and_nothing_else() {
    let p = problem("rgd");
    let (refined, keys) = p.model.with_smoothing_refined(2.0);
    assert_eq!(
        keys,
        [
            "model.bit.spin_smoothing",
            "model.bit.velocity_smoothing",
            "model.bit.contact_smoothing",
            "model.wall.slip_smoothing"
        ]
    );
    for spec in p.model.bit.law().parameters() {
        let (before, after) = (
            p.model.bit.get(spec.key).unwrap(),
            refined.bit.get(spec.key).unwrap(),
        );
        let expected = if keys.contains(&spec.key) {
            before / 2.0
        } else {
            before
        };
        assert_eq!(after, expected, "{}", spec.key);
    }
    assert_eq!(
        refined.wall_friction,
        drillopt::model::WallFriction::Coulomb {
            slip_smoothing: drillopt::model::WallFriction::DEFAULT_SLIP_SMOOTHING / 2.0
        }
    );
    let mut rest = refined.clone();
    rest.bit = p.model.bit.clone();
    rest.wall_friction = p.model.wall_friction;
    assert_eq!(
        serde_json::to_string(&rest).unwrap(),
        serde_json::to_string(&p.model).unwrap(),
        "nothing else changes"
    );
    // The paper's own file: the paper's bit (no widths) and torque-only wall friction.
    let paper = Problem::load(common::SEED_PAPER).unwrap();
    let (refined, keys) = paper.model.with_smoothing_refined(2.0);
    assert_eq!(keys, ["model.wall.sign_smoothing"]);
    let sign = |s: &drillopt::model::Drillstring| s.wall.get("model.wall.sign_smoothing").unwrap();
    assert_eq!(sign(&refined), sign(&paper.model) / 2.0);
    // A frictionless wall: nothing.
    let mut frictionless = paper.model.clone();
    let i = frictionless.wall.index_of("model.wall.friction").unwrap();
    frictionless.wall.set(i, 0.0);
    assert!(frictionless.with_smoothing_refined(2.0).1.is_empty());
}
