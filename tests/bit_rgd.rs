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
//! Germay, Denoël & Detournay 2009, on the continuous string): see
//! [`the_delay_destabilises_steady_drilling_as_its_characteristic_equation_says`].

mod common;

use drillopt::model::{Autodriller, OperatingPoint, TopDrive};
use drillopt::problem::Problem;
use drillopt::rom::ReducedModel;
use drillopt::sim::{Effects, InitialState, RunSettings, TimeSeries, simulate};
use nalgebra::Complex;
use std::f64::consts::PI;

const SEED_DETOURNAY: &str = include_str!("../problems/seed_detournay.toml");

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

/// The characteristic function of steady drilling on seed_detournay.toml's string with a 4-blade
/// rgd bit under the imposed feed, linearised: the string is the continuous axial and torsional
/// bar with the pipe's damping, c on the mass and β on the stiffness (ρA (ü + c u̇) =
/// EA (u″ + β u̇″), ρJ (θ̈ + c θ̇) = GJ (θ″ + β θ̇″)), clamped to the
/// feed at the top (δu = δθ = 0), with the bit's loads at x = L: EA δu′ = −ζεa δd,
/// GJ δθ′ = −½εa² δd. The depth of cut with the state-dependent delay, linearised about the
/// helix (d = n (u(t) − u(t′)), θ(t) − θ(t′) = 2π/n, t′ = t − τ + (δθ(t) − δθ(t − τ))/Ω):
/// δd = n (1 − e^(−λτ)) (δu − (V/Ω) δθ), τ = 2π/(nΩ). With the bar's dynamic stiffnesses at its
/// end D(λ) = EA (1 + βλ) k coth(kL), k² = λ(λ + c)/(c_w² (1 + βλ)), non-trivial solutions need
///
/// Δ(λ) = D_a D_t + n (1 − e^(−λτ)) (ζεa D_t − (V/Ω) ½εa² D_a) = 0.
///
/// (The wear flats and the torque's sign regularisation contribute derivatives of order
/// e^(−2V/v_r) and e^(−2Ω/ω_r): none at this operating point.)
fn characteristic(lambda: Complex<f64>, omega: f64, v: f64, beta: f64) -> Complex<f64> {
    let (rho, e, nu, c, length) = (7900.0, 203e9, 0.3, 0.03, 35.0);
    let (ro, ri): (f64, f64) = (0.06, 0.04);
    let (zeta, eps, a, blades) = (0.7, 200e6, 0.07, 4.0);
    let g = e / (2.0 * (1.0 + nu));
    let area = PI * (ro * ro - ri * ri);
    let polar = 0.5 * PI * (ro.powi(4) - ri.powi(4));
    let kelvin = 1.0 + beta * lambda;
    let wave = (lambda * (lambda + c) / kelvin).sqrt();
    let end = |stiffness: f64, speed: f64| {
        let k = wave / speed;
        k * kelvin * stiffness / (k * length).tanh()
    };
    let (da, dt) = (
        end(e * area, (e / rho).sqrt()),
        end(g * polar, (g / rho).sqrt()),
    );
    let tau = 2.0 * PI / (blades * omega);
    let delay = (-lambda * tau).exp();
    da * dt + (1.0 - delay) * blades * (zeta * eps * a * dt - v / omega * 0.5 * eps * a * a * da)
}

/// Newton's method on Δ from `guess` (derivative by central differences).
fn root_near(guess: Complex<f64>, omega: f64, v: f64, beta: f64) -> Option<Complex<f64>> {
    let delta = |x| characteristic(x, omega, v, beta);
    let mut x = guess;
    for _ in 0..100 {
        let h = 1e-6 * x.norm();
        let f = delta(x);
        let df = (delta(x + h) - delta(x - h)) / (2.0 * h);
        let step = f / df;
        x -= step;
        if !x.re.is_finite() {
            return None;
        }
        if step.norm() < 1e-12 * x.norm() {
            return Some(x);
        }
    }
    None
}

/// The bit's axial velocity oscillation while |u̇ − V| grows through [1e-9, 1e-5] m/s (out of
/// round-off, still linear: below 1 % of the feed): its growth rate (least squares on the log of
/// the peaks of |u̇ − V|) and its frequency (zero crossings).
fn growth_and_frequency(s: &TimeSeries, v: f64) -> (f64, f64) {
    let y: Vec<f64> = s.bit_velocity.iter().map(|u| u - v).collect();
    let band = |x: f64| (1e-9..=1e-5).contains(&x);
    let mut peaks = Vec::new();
    for k in 1..s.t.len() - 1 {
        if y[k].abs() >= y[k - 1].abs() && y[k].abs() >= y[k + 1].abs() && band(y[k].abs()) {
            peaks.push((s.t[k], y[k].abs().ln()));
        }
    }
    let (from, to) = (peaks[0].0, peaks[peaks.len() - 1].0);
    let mut crossings = Vec::new();
    for k in 1..s.t.len() {
        if s.t[k] >= from && s.t[k] <= to && y[k] * y[k - 1] < 0.0 {
            crossings.push(s.t[k - 1] + (s.t[k] - s.t[k - 1]) * y[k - 1] / (y[k - 1] - y[k]));
        }
    }
    assert!(peaks.len() > 20, "{} peaks in the band", peaks.len());
    let n = peaks.len() as f64;
    let (mt, ml) = (
        peaks.iter().map(|p| p.0).sum::<f64>() / n,
        peaks.iter().map(|p| p.1).sum::<f64>() / n,
    );
    let slope = peaks.iter().map(|p| (p.0 - mt) * (p.1 - ml)).sum::<f64>()
        / peaks.iter().map(|p| (p.0 - mt).powi(2)).sum::<f64>();
    let span = crossings[crossings.len() - 1] - crossings[0];
    (slope, (crossings.len() - 1) as f64 / (2.0 * span))
}

#[test]
fn the_delay_destabilises_steady_drilling_as_its_characteristic_equation_says() {
    // The finite-element model itself (30 elements, no reduction), and the problem's reduced
    // default basis with the stiffness-proportional damping of 10 µs that the README's converged
    // model uses: without it the basis has a spurious mode near 505 Hz (above its 4 axial modes,
    // where its static corrections stand in for the continuum) that the delay destabilises at
    // 7.7 /s, faster than the physical 47 Hz mode (README, "A bit that cuts rock").
    let plain = problem("rgd");
    let damped = Problem::from_toml(
        &SEED_DETOURNAY
            .replace("law = \"detournay\"", "law = \"rgd\"\nblades = 4")
            .replace(
                "damping = \"0.03 1/s\"",
                "damping = \"0.03 1/s\"\nstiffness_damping = \"10 us\"",
            ),
        std::path::Path::new("seed_rgd_damped.toml"),
    )
    .unwrap();
    let unreduced = ReducedModel::unreduced(&plain.model, 30).unwrap();
    let reduced =
        ReducedModel::new(&damped.model, damped.mesh.elements, &damped.mesh.basis).unwrap();
    // (model, β, Ω, V, duration): 60 rpm and 5 m/h, the seed's point; 120 rpm and 30 m/h.
    let cases = [
        ("unreduced", &unreduced, 0.0, 60.0, 5.0, 3.6),
        ("unreduced", &unreduced, 0.0, 120.0, 30.0, 2.6),
        ("reduced, β = 10 µs", &reduced, 1e-5, 60.0, 5.0, 3.6),
    ];
    for (name, model, beta, rpm, m_per_h, duration) in cases {
        let op = OperatingPoint {
            omega: rpm * PI / 30.0,
            v0: m_per_h / 3600.0,
        };
        // The roots of Δ from guesses on the imaginary axis every 1 Hz up to 1 kHz: the one of
        // largest real part is the mode that grows first. At 60 rpm: 47.13 Hz (the first axial
        // mode stiffened by the cutting), σ = 7.52 /s (7.42 /s with β), the next root 5.16 /s
        // at 114 Hz; at 120 rpm: 46.59 Hz, 11.40 /s, the next 6.03 /s.
        let roots: Vec<Complex<f64>> = (1..1000)
            .filter_map(|f| {
                root_near(
                    Complex::new(0.0, 2.0 * PI * f as f64),
                    op.omega,
                    op.v0,
                    beta,
                )
            })
            .collect();
        let dominant = roots
            .iter()
            .copied()
            .max_by(|a, b| a.re.total_cmp(&b.re))
            .unwrap();
        let (sigma, frequency) = (dominant.re, dominant.im / (2.0 * PI));
        assert!(sigma > 0.0, "steady drilling is unstable: {dominant}");
        // The simulator from the steady start: round-off grows at the dominant root's rate.
        // Steps of at most 0.2 ms resolve the mesh's axial and torsional modes up to 1 kHz with
        // at least 5 steps per period (with 1 ms steps the integrator's numerical damping takes
        // 0.7 % off the growth).
        let out = simulate(
            model,
            op,
            Effects::ALL,
            &RunSettings::new(duration, 2e-4),
            InitialState::Preloaded,
            |_| {},
        );
        assert!(out.error.is_none(), "{:?}", out.error);
        let (growth, f) = growth_and_frequency(&out.series, op.v0);
        eprintln!(
            "{name}, {rpm} rpm, {m_per_h} m/h: characteristic σ = {sigma:.4} /s at \
             {frequency:.3} Hz; simulator σ = {growth:.4} /s at {f:.3} Hz"
        );
        assert!(
            (f / frequency - 1.0).abs() < 1e-3,
            "{f} Hz vs {frequency} Hz"
        );
        assert!(
            (growth / sigma - 1.0).abs() < 5e-3,
            "{growth} /s vs {sigma} /s"
        );
    }
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
