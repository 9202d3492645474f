//! The driller's top (MODEL.md §11.8): a hook load and an autodriller, where the rock and the
//! string decide the rate of penetration. References, computed here from the raw numbers of
//! `problems/seed_detournay.toml` (not through the crate's bit law):
//!
//! - Detournay's drag-bit law in drillopt's rate form (`model::bit::detournay`'s module doc):
//!   W(V) = ζ ε a · 2π V / √(Ω² + ω_r²) + σ a ℓ tanh(V / v_r), so a string drilling steadily at
//!   V under a top force F has F = W(V) + c ρA L V + μ w_b L c_a (the damping of the translating
//!   pipe and the axial wall drag, Johancsik's soft string; c_a = V/√(V² + (Ω R_ext)²)). Solved
//!   for V by bisection: the steady ROP of a hook load F = W_set, or of an autodriller whose WOB
//!   limit binds.
//! - The autodriller's block, off its limits, obeys τ s̈ = V0 − ṡ: from rest,
//!   ṡ(t) = V0 (1 − e^(−t/τ)) whatever the string does.

use crate::common;

use drillopt::model::{Autodriller, OperatingPoint, TopDrive};
use drillopt::problem::Problem;
use drillopt::rom::ReducedModel;
use drillopt::sim::{
    Effects, InitialState, RunSettings, TimeSeries, preloaded_equilibrium, simulate,
};
use std::f64::consts::PI;

const SEED_DETOURNAY: &str = include_str!("../../problems/seed_detournay.toml");

/// The raw numbers of seed_detournay.toml, SI.
mod raw {
    pub const ZETA: f64 = 0.7;
    pub const EPS: f64 = 200e6;
    pub const A: f64 = 0.07;
    pub const SIGMA: f64 = 150e6;
    pub const ELL: f64 = 3e-3;
    /// The law's defaults (spin_smoothing, velocity_smoothing).
    pub const OMEGA_R: f64 = 0.5;
    pub const V_R: f64 = 1e-4;
    pub const RHO: f64 = 7900.0;
    pub const RHO_F: f64 = 1200.0;
    pub const R_EXT: f64 = 0.06;
    pub const R_INT: f64 = 0.04;
    pub const LENGTH: f64 = 35.0;
    pub const C: f64 = 0.03;
    pub const MU: f64 = 1e-5;
    pub const G: f64 = 9.81;
}

fn omega() -> f64 {
    2.0 * PI
}

/// The top force of steady drilling at ROP `v` (module doc).
fn top_force(v: f64) -> f64 {
    use raw::*;
    let w = omega();
    let wob = ZETA * EPS * A * 2.0 * PI * v / (w * w + OMEGA_R * OMEGA_R).sqrt()
        + SIGMA * A * ELL * (v / V_R).tanh();
    let area = PI * (R_EXT * R_EXT - R_INT * R_INT);
    let damping = C * RHO * area * LENGTH * v;
    let weight = (RHO * area + RHO_F * PI * R_INT * R_INT) * G;
    let drag = MU * weight * LENGTH * v / (v * v + (w * R_EXT).powi(2)).sqrt();
    wob + damping + drag
}

/// The ROP V (m/s) at which steady drilling needs the top force `force`.
fn steady_rop(force: f64) -> f64 {
    let (mut lo, mut hi) = (0.0, 1.0);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if top_force(mid) > force {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    0.5 * (lo + hi)
}

fn problem() -> Problem {
    Problem::from_toml(SEED_DETOURNAY, std::path::Path::new("seed_detournay.toml")).unwrap()
}

/// The problem's reduced model with the top `top` (a smaller basis than the file's: the steady
/// state needs no high modes).
fn model(top: TopDrive) -> ReducedModel {
    let mut string = problem().model;
    string.top = top;
    ReducedModel::new(&string, 30, &common::small_basis()).unwrap()
}

/// Mean of `y` over t in [from, to] (trapezoids on the adaptive steps).
fn mean(s: &TimeSeries, y: &[f64], from: f64, to: f64) -> f64 {
    let (mut sum, mut span) = (0.0, 0.0);
    for k in 1..s.t.len() {
        let (t0, t1) = (s.t[k - 1], s.t[k]);
        if t0 >= from && t1 <= to {
            sum += 0.5 * (y[k - 1] + y[k]) * (t1 - t0);
            span += t1 - t0;
        }
    }
    sum / span
}

/// Mean ROP over [from, to] from the bit's advance.
fn rop(s: &TimeSeries, from: f64, to: f64) -> f64 {
    let at = |t: f64| s.t.iter().position(|&x| x >= t).unwrap();
    let (i, j) = (at(from), at(to));
    (s.bit_displacement[j] - s.bit_displacement[i]) / (s.t[j] - s.t[i])
}

const SET_POINT: f64 = 40e3;

#[test]
fn a_hook_load_drills_at_the_rop_the_bit_law_gives_its_weight() {
    let expected = steady_rop(SET_POINT);
    // About 3.1 m/h: the cutting takes 8.5 kN of the 40 kN, the wear flats 31.5 kN.
    assert!(
        (expected * 3600.0 - 3.13).abs() < 0.01,
        "{}",
        expected * 3600.0
    );
    let m = model(TopDrive::HookLoad);
    let op = OperatingPoint::hook_load(omega(), SET_POINT);
    // The pre-loaded start finds the steady feed itself.
    let out = simulate(
        &m,
        op,
        Effects::ALL,
        &RunSettings::new(1.0, 1e-3),
        InitialState::Preloaded,
        |_| {},
    );
    assert!(out.error.is_none(), "{:?}", out.error);
    let s = &out.series;
    assert!(
        (s.block_speed[0] / expected - 1.0).abs() < 1e-4,
        "start at {} m/h, closed form {} m/h",
        s.block_speed[0] * 3600.0,
        expected * 3600.0
    );
    let simulated = rop(s, 0.2, 1.0);
    assert!(
        (simulated / expected - 1.0).abs() < 1e-4,
        "ROP {} m/h against {} m/h",
        simulated * 3600.0,
        expected * 3600.0
    );
    assert!((mean(s, &s.top_force, 0.0, 1.0) / SET_POINT - 1.0).abs() < 1e-6);

    // Started at half the steady feed (the steady state of the imposed feed V/2, the block
    // moving at V/2), the block finds the steady ROP by itself: the top force is the set-point
    // at every step, the WOB builds until it matches.
    // (V0 is the given start's block speed and the feed of its equilibrium; W the hook load.)
    let half = OperatingPoint {
        omega: omega(),
        v0: 0.5 * expected,
        wob: SET_POINT,
    };
    let (q, _) = preloaded_equilibrium(&m, half, Effects::ALL).unwrap();
    let v = nalgebra::DVector::zeros(m.size());
    let out = simulate(
        &m,
        half,
        Effects::ALL,
        &RunSettings::new(5.0, 1e-3),
        InitialState::Given { q, v },
        |_| {},
    );
    assert!(out.error.is_none(), "{:?}", out.error);
    let s = &out.series;
    assert!((s.block_speed[0] / (0.5 * expected) - 1.0).abs() < 1e-12);
    // The jump of the WOB leaves an axial vibration that the bit reflects (its damping is 40
    // times the pipe's axial impedance) and c = 0.03 1/s barely damps: a 4 s window.
    let settled = rop(s, 1.0, 5.0);
    assert!(
        (settled / expected - 1.0).abs() < 1e-3,
        "from half the feed: ROP {} m/h against {} m/h",
        settled * 3600.0,
        expected * 3600.0
    );
    // (The recorded loads are those of a step's last Newton residual, the state before its last
    // update: in the first violent steps, when the WOB jumps by 4 kN, 0.2 % off.)
    assert!((mean(s, &s.top_force, 0.0, 5.0) / SET_POINT - 1.0).abs() < 1e-5);
    for k in (1..s.t.len()).filter(|&k| s.t[k] > 0.5) {
        assert!(
            (s.top_force[k] / SET_POINT - 1.0).abs() < 1e-4,
            "top force {} N at t = {}",
            s.top_force[k],
            s.t[k]
        );
    }
    // The energy balance holds with the block's work F_top ṡ.
    let k = s.t.len() - 1;
    let stored =
        s.kinetic_energy[k] + s.potential_energy[k] - (s.kinetic_energy[0] + s.potential_energy[0]);
    let balance = s.work_top[k] + s.work_bit[k] - stored - s.dissipated[k];
    assert!(
        balance.abs() < 1e-3 * s.work_top[k].abs(),
        "energy residual {balance} J of {} J",
        s.work_top[k]
    );
}

fn autodriller(wob_limit: f64, time_constant: f64) -> TopDrive {
    TopDrive::Autodriller(Autodriller {
        wob_limit,
        torque_limit: None,
        power_limit: None,
        time_constant,
    })
}

#[test]
fn an_autodriller_below_its_limit_feeds_at_v0_with_its_time_constant() {
    let tau = 0.2;
    let m = model(autodriller(1e6, tau));
    let op = OperatingPoint {
        omega: omega(),
        v0: 10.0 / 3600.0,
        wob: 0.0,
    };
    // From the static equilibrium: the block at rest, the bit off bottom.
    let out = simulate(
        &m,
        op,
        Effects::ALL,
        &RunSettings::new(1.0, 1e-3),
        InitialState::StaticEquilibrium,
        |_| {},
    );
    assert!(out.error.is_none(), "{:?}", out.error);
    let s = &out.series;
    let mut worst: f64 = 0.0;
    for (t, speed) in s.t.iter().zip(&s.block_speed) {
        let exact = op.v0 * (1.0 - (-t / tau).exp());
        worst = worst.max((speed - exact).abs() / op.v0);
    }
    assert!(
        worst < 1e-4,
        "block speed off the first-order law by {worst} V0"
    );
    // Pre-loaded below its limit: the imposed feed's steady state, ROP = V0.
    let out = simulate(
        &m,
        op,
        Effects::ALL,
        &RunSettings::new(0.5, 1e-3),
        InitialState::Preloaded,
        |_| {},
    );
    assert!(out.error.is_none(), "{:?}", out.error);
    assert!((rop(&out.series, 0.1, 0.5) / op.v0 - 1.0).abs() < 1e-4);
}

#[test]
fn an_autodriller_at_its_wob_limit_drills_at_the_rop_the_rock_allows() {
    let m = model(autodriller(SET_POINT, 1.0));
    // V0 = 10 m/h would need about 59 kN: the 40 kN limit binds.
    let op = OperatingPoint {
        omega: omega(),
        v0: 10.0 / 3600.0,
        wob: 0.0,
    };
    assert!(top_force(op.v0) > 1.4 * SET_POINT);
    let expected = steady_rop(SET_POINT);
    let out = simulate(
        &m,
        op,
        Effects::ALL,
        &RunSettings::new(1.0, 1e-3),
        InitialState::Preloaded,
        |_| {},
    );
    assert!(out.error.is_none(), "{:?}", out.error);
    let s = &out.series;
    let simulated = rop(s, 0.2, 1.0);
    assert!(
        (simulated / expected - 1.0).abs() < 1e-4,
        "ROP {} m/h against {} m/h",
        simulated * 3600.0,
        expected * 3600.0
    );
    assert!((mean(s, &s.top_force, 0.2, 1.0) / SET_POINT - 1.0).abs() < 1e-5);

    // The bit's negative damping is that of the feed it drills, not of the set-point: Detournay's
    // torque ½εa² · 2πV/√(Ω² + ω_r²) (+ the flats' part, which does not depend on Ω) weakens
    // with Ω at the rate ½εa² · 2πV Ω/(Ω² + ω_r²)^(3/2), over the pipe's torsional impedance
    // J √(Gρ) (St Venant torsion, κ_t = 1).
    let terms = drillopt::metrics::ModelTerms {
        critical_speed_margin: f64::NAN,
        steady_state: None,
    };
    let metrics = drillopt::metrics::of_run(&out, &m.string, op, 0.2, Some(terms)).unwrap();
    let ratio_at = |v: f64| {
        use raw::*;
        let w = omega();
        let slope = 0.5 * EPS * A * A * 2.0 * PI * v * w / (w * w + OMEGA_R * OMEGA_R).powf(1.5);
        let g = 203e9 / (2.0 * 1.3);
        let j = 0.5 * PI * (R_EXT.powi(4) - R_INT.powi(4));
        slope / (j * (g * RHO).sqrt())
    };
    let drilled = ratio_at(expected);
    assert!(
        (metrics.bit_damping_ratio / drilled - 1.0).abs() < 1e-3,
        "{} against {drilled} at the ROP drilled ({} at the set-point)",
        metrics.bit_damping_ratio,
        ratio_at(op.v0)
    );
    assert!(ratio_at(op.v0) > 1.4 * drilled);

    // From rest, the block speeds up to V0 until the WOB reaches its limit, then the integral
    // law brings it down to the rock's ROP and holds the WOB there.
    let out = simulate(
        &m,
        op,
        Effects::ALL,
        &RunSettings::new(12.0, 2e-3),
        InitialState::StaticEquilibrium,
        |_| {},
    );
    assert!(out.error.is_none(), "{:?}", out.error);
    let s = &out.series;
    let peak = s.top_force.iter().cloned().fold(0.0, f64::max);
    assert!(peak > SET_POINT, "the limit was reached ({peak} N)");
    let settled = rop(s, 10.0, 12.0);
    assert!(
        (settled / expected - 1.0).abs() < 1e-2,
        "from rest: ROP {} m/h against {} m/h",
        settled * 3600.0,
        expected * 3600.0
    );
    assert!((mean(s, &s.top_force, 10.0, 12.0) / SET_POINT - 1.0).abs() < 1e-2);
}

#[test]
fn the_top_keys_are_refused_where_they_mean_nothing() {
    let edit = |from: &str, to: &str| {
        let text = SEED_DETOURNAY.replace(from, to);
        assert_ne!(text, SEED_DETOURNAY, "the edit took");
        Problem::from_toml(&text, std::path::Path::new("edited.toml"))
    };
    let v0 = "v0 = \"5 m/h\"                    # 1/720 m/s";
    let message =
        |r: Result<Problem, drillopt::problem::ProblemError>| r.expect_err("refused").to_string();
    let m = message(edit(v0, "v0 = \"5 m/h\"\nwob_limit = \"50 kN\""));
    assert!(
        m.contains("operating_point.wob_limit") && m.contains("autodriller"),
        "{m}"
    );
    let m = message(edit(v0, "v0 = \"5 m/h\"\ntop = \"autodriller\""));
    assert!(
        m.contains("operating_point.wob_limit") && m.contains("required"),
        "{m}"
    );
    let m = message(edit(
        v0,
        "v0 = \"5 m/h\"\ntop = \"autodriller\"\nwob_limit = \"5 MN\"",
    ));
    assert!(
        m.contains("operating_point.wob_limit") && m.contains("2 MN"),
        "{m}"
    );
    let m = message(edit(v0, "v0 = \"5 m/h\"\ntop = \"winch\""));
    assert!(
        m.contains("operating_point.top") && m.contains("\"autodriller\""),
        "{m}"
    );
    // A misspelt top beside its keys: the top's refusal is the one shown, and it offers only
    // the tops a file can choose.
    let m = message(edit(
        v0,
        "v0 = \"5 m/h\"\ntop = \"autodriler\"\nwob_limit = \"60 kN\"",
    ));
    assert!(
        m.contains("operating_point.top") && m.contains("\"autodriler\""),
        "{m}"
    );
    // A hook load's set-point is its WOB: the feed is refused beside it, the WOB required, and
    // the WOB refused under the other tops.
    let m = message(edit(
        v0,
        "v0 = \"5 m/h\"\ntop = \"hook_load\"\nwob = \"50 kN\"",
    ));
    assert!(
        m.contains("operating_point.v0") && m.contains("hook_load") && m.contains("wob"),
        "{m}"
    );
    let m = message(edit(v0, "top = \"hook_load\""));
    assert!(
        m.contains("operating_point.wob") && m.contains("required"),
        "{m}"
    );
    let m = message(edit(v0, "v0 = \"5 m/h\"\nwob = \"50 kN\""));
    assert!(
        m.contains("operating_point.wob") && m.contains("hook_load"),
        "{m}"
    );
    let m = message(edit(v0, "top = \"hook_load\"\nwob = \"3 MN\""));
    assert!(
        m.contains("operating_point.wob") && m.contains("2 MN"),
        "{m}"
    );
    let p = edit(v0, "top = \"hook_load\"\nwob = \"11.24 klbf\"").expect("a hook-load file");
    assert_eq!(p.model.top, TopDrive::HookLoad);
    assert_eq!(p.operating_point.v0, 0.0);
    assert!((p.operating_point.wob - 11.24 * 4448.2216152605).abs() < 1e-6);
    let m = message(edit(
        v0,
        "v0 = \"5 m/h\"\ntop = \"autodriller\"\nwob_limit = \"60 kN\"\npower_limit = \"20 MW\"",
    ));
    assert!(
        m.contains("operating_point.power_limit") && m.contains("10 MW"),
        "{m}"
    );
    let m = message(edit(v0, "v0 = \"5 m/h\"\npower_limit = \"500 hp\""));
    assert!(
        m.contains("operating_point.power_limit") && m.contains("autodriller"),
        "{m}"
    );
    // Accepted: the autodriller with its limits, in field units.
    let p = edit(
        v0,
        "v0 = \"5 m/h\"\ntop = \"autodriller\"\nwob_limit = \"10 klbf\"\ntorque_limit = \"5 kft.lbf\"\npower_limit = \"800 hp\"\nautodriller_time_constant = \"2 s\"",
    )
    .unwrap();
    let TopDrive::Autodriller(a) = p.model.top else {
        panic!("{:?}", p.model.top)
    };
    assert!(
        (a.wob_limit / 44482.2 - 1.0).abs() < 1e-5,
        "{}",
        a.wob_limit
    );
    assert!((a.torque_limit.unwrap() / 6779.09 - 1.0).abs() < 1e-5);
    assert!((a.power_limit.unwrap() / 596_559.9 - 1.0).abs() < 1e-6);
    assert_eq!(a.time_constant, 2.0);
}

#[test]
fn the_unreduced_model_drills_at_the_same_rop_under_an_autodriller() {
    // The finite-element model itself (a sparse Newton matrix bordered by the block's row and
    // column) against the same closed form.
    let mut string = problem().model;
    string.top = autodriller(SET_POINT, 1.0);
    let m = ReducedModel::unreduced(&string, 8).unwrap();
    let op = OperatingPoint {
        omega: omega(),
        v0: 10.0 / 3600.0,
        wob: 0.0,
    };
    let out = simulate(
        &m,
        op,
        Effects::ALL,
        &RunSettings::new(0.5, 1e-3),
        InitialState::Preloaded,
        |_| {},
    );
    assert!(out.error.is_none(), "{:?}", out.error);
    let (simulated, expected) = (rop(&out.series, 0.1, 0.5), steady_rop(SET_POINT));
    assert!(
        (simulated / expected - 1.0).abs() < 1e-4,
        "ROP {} m/h against {} m/h",
        simulated * 3600.0,
        expected * 3600.0
    );
}

#[test]
fn a_power_rating_limits_the_torque_to_power_over_omega() {
    // A 5 kW top drive at 60 rpm (2π rad/s) can give 795.8 N·m, below the torque of drilling at
    // V0 = 10 m/h (the WOB limit of 1 MN never binds): the block slows until the top torque is
    // P/Ω, exactly as under the torque limit P/Ω itself (the same run, bit for bit).
    let power = 5e3;
    let op = OperatingPoint {
        omega: omega(),
        v0: 10.0 / 3600.0,
        wob: 0.0,
    };
    let limited = |torque_limit: Option<f64>, power_limit: Option<f64>| {
        let m = model(TopDrive::Autodriller(Autodriller {
            wob_limit: 1e6,
            torque_limit,
            power_limit,
            time_constant: 1.0,
        }));
        let out = simulate(
            &m,
            op,
            Effects::ALL,
            &RunSettings::new(2.0, 1e-3),
            InitialState::Preloaded,
            |_| {},
        );
        assert!(out.error.is_none(), "{:?}", out.error);
        out.series
    };
    let by_power = limited(None, Some(power));
    let by_torque = limited(Some(power / op.omega), None);
    assert_eq!(by_power.top_torque, by_torque.top_torque);
    assert_eq!(by_power.block_speed, by_torque.block_speed);
    let held = mean(&by_power, &by_power.top_torque, 0.5, 2.0);
    assert!(
        (held * op.omega / power - 1.0).abs() < 1e-4,
        "top torque {held} N·m, P/Ω = {}",
        power / op.omega
    );
    assert!(rop(&by_power, 0.5, 2.0) < 0.9 * op.v0, "the limit binds");
    // A tighter torque limit rules over the power.
    let both = limited(Some(0.5 * power / op.omega), Some(power));
    let held = mean(&both, &both.top_torque, 0.5, 2.0);
    assert!(
        (held * op.omega / (0.5 * power) - 1.0).abs() < 1e-4,
        "{held}"
    );
}
