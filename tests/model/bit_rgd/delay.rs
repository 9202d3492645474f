//! The delay's instability against the characteristic equation of the linearised delay system,
//! computed here apart from the simulator (after Richard, Germay & Detournay 2007 and Germay,
//! Denoël & Detournay 2009, on the continuous string instead of their lumped or modal one).
//!
//! On seed_detournay.toml's string (hard sandstone, light damping) steady drilling is unstable at
//! every rotation speed: the test checks the growth rate and frequency of the mode that grows. On a
//! soft rock with the damping of a string in mud (ε = 20 MPa, c = 15 /s: a decay of 7.5 /s, 3 % of
//! critical on the first axial mode) the growth of the delay and the damping balance, and the
//! rotation speeds where steady drilling is unstable form lobes: the test finds the edges of the
//! lobe at 114–124 rpm from the characteristic equation and the simulator's onset of growth there,
//! and checks that the bit leaves the rock inside the lobe and not outside.

use super::{SEED_DETOURNAY, common, problem};
use drillopt::model::OperatingPoint;
use drillopt::problem::Problem;
use drillopt::rom::ReducedModel;
use drillopt::sim::{
    Effects, InitialState, RunSettings, TimeSeries, preloaded_equilibrium, simulate,
};
use nalgebra::Complex;
use std::f64::consts::PI;

/// The linearised delay system of seed_detournay.toml's string with a 4-blade rgd bit under the
/// imposed feed, with the pipe's damping `c` (on the mass, 1/s), `beta` (on the stiffness, s) and
/// the rock's intrinsic specific energy `eps` (Pa).
///
/// The string is the continuous axial and torsional bar (ρA (ü + c u̇) = EA (u″ + β u̇″),
/// ρJ (θ̈ + c θ̇) = GJ (θ″ + β θ̇″)), clamped to the feed at the top (δu = δθ = 0), with the
/// bit's loads at x = L: EA δu′ = −ζεa δd, GJ δθ′ = −½εa² δd. The depth of cut with the
/// state-dependent delay, linearised about the helix (d = n (u(t) − u(t′)),
/// θ(t) − θ(t′) = 2π/n, t′ = t − τ + (δθ(t) − δθ(t − τ))/Ω): δd = n (1 − e^(−λτ)) (δu − (V/Ω) δθ),
/// τ = 2π/(nΩ). With the bar's dynamic stiffnesses at its end
/// D(λ) = EA (1 + βλ) k coth(kL), k² = λ(λ + c)/(c_w² (1 + βλ)), non-trivial solutions need
///
/// Δ(λ) = D_a D_t + n (1 − e^(−λτ)) (ζεa D_t − (V/Ω) ½εa² D_a) = 0.
///
/// (The wear flats and the torque's sign regularisation contribute derivatives of order
/// e^(−2V/v_r) and e^(−2Ω/ω_r): none at these operating points.)
#[derive(Clone, Copy)]
pub struct Linearised {
    pub c: f64,
    pub beta: f64,
    pub eps: f64,
}

impl Linearised {
    pub fn delta(&self, lambda: Complex<f64>, omega: f64, v: f64) -> Complex<f64> {
        let (rho, e, nu, length) = (7900.0, 203e9, 0.3, 35.0);
        let (ro, ri): (f64, f64) = (0.06, 0.04);
        let (zeta, a, blades) = (0.7, 0.07, 4.0);
        let g = e / (2.0 * (1.0 + nu));
        let area = PI * (ro * ro - ri * ri);
        let polar = 0.5 * PI * (ro.powi(4) - ri.powi(4));
        let kelvin = 1.0 + self.beta * lambda;
        let wave = (lambda * (lambda + self.c) / kelvin).sqrt();
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
        let eps = self.eps;
        da * dt
            + (1.0 - delay) * blades * (zeta * eps * a * dt - v / omega * 0.5 * eps * a * a * da)
    }

    /// Newton's method on Δ from `guess` (derivative by central differences).
    pub fn root_near(&self, guess: Complex<f64>, omega: f64, v: f64) -> Option<Complex<f64>> {
        let delta = |x| self.delta(x, omega, v);
        let mut x = guess;
        for _ in 0..100 {
            let h = 1e-6 * x.norm();
            let f = delta(x);
            let df = (delta(x + h) - delta(x - h)) / (2.0 * h);
            let step = f / df;
            x -= step;
            if !x.re.is_finite() || !x.im.is_finite() {
                return None;
            }
            if step.norm() < 1e-12 * x.norm() {
                return Some(x);
            }
        }
        None
    }

    /// The roots of Δ found from guesses on the imaginary axis every 1 Hz up to 1 kHz (upper
    /// half-plane, each once), sorted by decreasing real part: the first is the mode that grows
    /// first (or decays last).
    pub fn roots(&self, omega: f64, v: f64) -> Vec<Complex<f64>> {
        let mut roots: Vec<Complex<f64>> = Vec::new();
        for f in 1..1000 {
            let guess = Complex::new(0.0, 2.0 * PI * f as f64);
            let new = |r: &Complex<f64>| {
                r.im > 0.0 && roots.iter().all(|x| (x - r).norm() > 1e-6 * r.norm())
            };
            if let Some(r) = self.root_near(guess, omega, v).filter(new) {
                roots.push(r);
            }
        }
        roots.sort_by(|a, b| b.re.total_cmp(&a.re));
        roots
    }

    /// The rotation speed (rad/s) between `inside` and `outside` where the root that is dominant
    /// at `inside` crosses the imaginary axis: continuation in steps of 0.1 rpm, then bisection
    /// to 1e-10 rad/s, the root tracked by Newton from its last value.
    pub fn edge(&self, inside: f64, outside: f64, v: f64) -> f64 {
        let mut root = self.roots(inside, v)[0];
        assert!(root.re > 0.0, "unstable at {inside} rad/s: {root}");
        let step = (outside - inside).signum() * 0.1 * PI / 30.0;
        let (mut a, mut b) = (inside, inside);
        loop {
            b += step;
            assert!((b - inside).abs() <= (outside - inside).abs(), "no edge");
            let next = self.root_near(root, b, v).expect("the root is tracked");
            if next.re < 0.0 {
                break;
            }
            (a, root) = (b, next);
        }
        while (b - a).abs() > 1e-10 {
            let m = 0.5 * (a + b);
            let r = self.root_near(root, m, v).expect("the root is tracked");
            if r.re > 0.0 {
                (a, root) = (m, r);
            } else {
                b = m;
            }
        }
        0.5 * (a + b)
    }
}

/// The bit's axial velocity oscillation u̇ − V over the samples of `s` selected by `take`
/// (time, |u̇ − V|): its growth rate and frequency ([`common::growth_and_frequency`]).
fn growth_and_frequency(s: &TimeSeries, v: f64, take: impl Fn(f64, f64) -> bool) -> (f64, f64) {
    let y: Vec<f64> = s.bit_velocity.iter().map(|u| u - v).collect();
    common::growth_and_frequency(&s.t, &y, |k| take(s.t[k], y[k].abs()))
}

fn rpm(omega: f64) -> f64 {
    omega * 30.0 / PI
}

#[test]
fn the_delay_destabilises_steady_drilling_as_its_characteristic_equation_says() {
    // The finite-element model itself (30 elements, no reduction), and the problem's reduced
    // default basis with the stiffness-proportional damping of 10 µs that the README's converged
    // model uses: without it the basis has a spurious mode near 505 Hz (above its 4 axial modes,
    // where its static corrections stand in for the continuum) that the delay destabilises at
    // 7.7 /s, faster than the physical 47 Hz mode (docs/model.md, "A bit that cuts rock").
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
            wob: 0.0,
        };
        let line = Linearised {
            c: 0.03,
            beta,
            eps: 200e6,
        };
        // At 60 rpm: 47.13 Hz (the first axial mode stiffened by the cutting), σ = 7.52 /s
        // (7.42 /s with β), the next root 5.16 /s at 114 Hz; at 120 rpm: 46.59 Hz, 11.40 /s,
        // the next 6.03 /s.
        let dominant = line.roots(op.omega, op.v0)[0];
        let (sigma, frequency) = (dominant.re, dominant.im / (2.0 * PI));
        assert!(sigma > 0.0, "steady drilling is unstable: {dominant}");
        // The simulator from the steady start: round-off grows at the dominant root's rate,
        // measured while |u̇ − V| grows through [1e-9, 1e-5] m/s (out of round-off, still linear:
        // below 1 % of the feed). Steps of at most 0.2 ms resolve the mesh's axial and torsional
        // modes up to 1 kHz with at least 5 steps per period (with 1 ms steps the integrator's
        // numerical damping takes 0.7 % off the growth).
        let out = simulate(
            model,
            op,
            Effects::ALL,
            &RunSettings::new(duration, 2e-4),
            InitialState::Preloaded,
            |_| {},
        );
        assert!(out.error.is_none(), "{:?}", out.error);
        let (growth, f) =
            growth_and_frequency(&out.series, op.v0, |_, y| (1e-9..=1e-5).contains(&y));
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

/// seed_detournay.toml with a 4-blade rgd bit in a soft rock (ε = 20 MPa) and the damping
/// c = 15 /s of a string in mud, β = `beta` seconds of stiffness damping (none at 0).
fn soft_rock(beta: f64) -> Problem {
    Problem::from_toml(
        &soft_rock_text(beta),
        std::path::Path::new("soft_rock.toml"),
    )
    .unwrap()
}

/// The text of [`soft_rock`].
fn soft_rock_text(beta: f64) -> String {
    let mut text = SEED_DETOURNAY
        .replace("law = \"detournay\"", "law = \"rgd\"\nblades = 4")
        .replace("\"200 MPa\"", "\"20 MPa\"")
        .replace("damping = \"0.03 1/s\"", "damping = \"15 1/s\"");
    if beta > 0.0 {
        text = text.replace(
            "damping = \"15 1/s\"",
            &format!(
                "damping = \"15 1/s\"\nstiffness_damping = \"{} us\"",
                beta * 1e6
            ),
        );
    }
    text
}

/// A run of `duration` s at `op` from the steady state disturbed by a velocity proportional to
/// its elastic state, q̇ = `kick` · q (the compression and twist of the loads, mostly the first
/// axial and torsional modes; and the sag, a lateral disturbance that must stay small: at 0.3 /s
/// the string's wall contacts keep a broadband vibration of 1e-5 m/s going), steps of at most
/// 0.2 ms.
fn kicked(model: &ReducedModel, op: OperatingPoint, kick: f64, duration: f64) -> TimeSeries {
    let (q, _) = preloaded_equilibrium(model, op, Effects::ALL).expect("the steady start");
    let v = &q * kick;
    run_from(model, op, q, v, duration)
}

/// A run of `duration` s at `op`, started from the steady state of the feed `factor` · V0 on the
/// helix of V0, at rest: the string is compressed and twisted for the wrong feed, a large axial
/// and torsional disturbance with no lateral part. Steps of at most 0.2 ms.
fn released(model: &ReducedModel, op: OperatingPoint, factor: f64, duration: f64) -> TimeSeries {
    let other = OperatingPoint {
        v0: op.v0 * factor,
        ..op
    };
    let (q, _) = preloaded_equilibrium(model, other, Effects::ALL).expect("the steady start");
    let v = q.map(|_| 0.0);
    run_from(model, op, q, v, duration)
}

/// A run of `duration` s at `op` from the modal state (q, q̇), steps of at most 0.2 ms.
fn run_from(
    model: &ReducedModel,
    op: OperatingPoint,
    q: nalgebra::DVector<f64>,
    v: nalgebra::DVector<f64>,
    duration: f64,
) -> TimeSeries {
    let out = simulate(
        model,
        op,
        Effects::ALL,
        &RunSettings::new(duration, 2e-4),
        InitialState::Given { q, v },
        |_| {},
    );
    assert!(out.error.is_none(), "{:?}", out.error);
    out.series
}

#[test]
fn the_simulator_starts_to_grow_where_the_characteristic_equation_says() {
    let v = 5.0 / 3600.0;
    let unreduced = ReducedModel::unreduced(&soft_rock(0.0).model, 30).unwrap();
    let damped = soft_rock(1e-5);
    let reduced =
        ReducedModel::new(&damped.model, damped.mesh.elements, &damped.mesh.basis).unwrap();
    for (name, model, beta) in [("unreduced", &unreduced, 0.0), ("reduced", &reduced, 1e-5)] {
        let line = Linearised {
            c: 15.0,
            beta,
            eps: 20e6,
        };
        // The lobe around 118 rpm (σ = 0.73 /s at 37.5 Hz, the next root −3.6 /s): steady
        // drilling is stable at 110 and 130 rpm (σ = −1.56 and −3.08 /s).
        let middle = 118.0 * PI / 30.0;
        for outside in [110.0 * PI / 30.0, 130.0 * PI / 30.0] {
            let edge = line.edge(middle, outside, v);
            let roots = line.roots(edge, v);
            assert!(
                roots[0].re.abs() < 1e-6 && roots[1].re < -1.0,
                "at the edge the root that crosses is the only one near the axis: {:?}",
                &roots[..2]
            );
            // The simulator 1 % either side of the edge: the rate at which a disturbance grows
            // or decays, from 0.5 s (the other modes have decayed by e^(−1.8)) to 5 s, and the
            // rotation speed where it changes sign (linear interpolation).
            let mut rates = Vec::new();
            for factor in [0.99, 1.01] {
                let op = OperatingPoint {
                    omega: edge * factor,
                    v0: v,
                    wob: 0.0,
                };
                let s = kicked(model, op, 1e-3, 5.0);
                let (growth, f) = growth_and_frequency(&s, v, |t, _| t >= 0.5);
                let sigma = line.root_near(roots[0], op.omega, v).unwrap();
                eprintln!(
                    "soft rock, {name}, {:.3} rpm: characteristic σ = {:.4} /s at {:.3} Hz; \
                     simulator σ = {growth:.4} /s at {f:.3} Hz",
                    rpm(op.omega),
                    sigma.re,
                    sigma.im / (2.0 * PI)
                );
                assert!((growth - sigma.re).abs() < 0.05, "{growth} vs {sigma}");
                rates.push((op.omega, growth));
            }
            let [(w0, g0), (w1, g1)] = [rates[0], rates[1]];
            assert!(g0 * g1 < 0.0, "the growth changes sign: {rates:?}");
            let onset = w0 - g0 * (w1 - w0) / (g1 - g0);
            eprintln!(
                "soft rock, {name}: edge of the lobe {:.3} rpm (characteristic), onset of \
                 growth {:.3} rpm (simulator), {:+.3} %",
                rpm(edge),
                rpm(onset),
                100.0 * (onset / edge - 1.0)
            );
            // Issue 29 asks for 2 %; the linear interpolation of σ between the two runs costs
            // about 0.1 % (σ is not linear in Ω), the simulator's rates agree to 0.01 /s.
            assert!((onset / edge - 1.0).abs() < 5e-3);
        }
    }
}

/// The share of the samples of `s` after `from` seconds with the bit off the rock (WOB ≤ 0, the
/// definition of `bit_bounce_fraction`), and the largest |u̇ − V| there.
fn bounce_after(s: &TimeSeries, v: f64, from: f64) -> (f64, f64) {
    let (mut off, mut all, mut swing) = (0usize, 0usize, 0.0_f64);
    for k in 0..s.t.len() {
        if s.t[k] >= from {
            all += 1;
            off += usize::from(s.weight_on_bit[k] <= 0.0);
            swing = swing.max((s.bit_velocity[k] - v).abs());
        }
    }
    (off as f64 / all as f64, swing)
}

#[test]
fn the_bit_leaves_the_rock_where_the_delay_makes_steady_drilling_unstable() {
    // Released from the steady state of three times the feed (the bit's axial speed swings by
    // 8 V0 in the first milliseconds), on the soft rock's reduced model. A sharp bit (no wear
    // flats, the same characteristic equation: the flats add nothing to it here): at 110 and
    // 130 rpm, outside the lobe (σ = −1.56 and −3.08 /s), the disturbance dies out and the bit
    // never leaves the rock; at 118 rpm, inside it (σ = 0.73 /s), it grows until the depth of cut
    // of a blade pass is no longer positive, and the bit leaves the rock and lands again, a
    // limit cycle of bit-bounce (about 29 % of the time off the rock, peak WOB 1.7 kN). The worn
    // bit at 118 rpm: the same growth saturates on the rock (a swing of 0.7 V0; a supercritical
    // Hopf bifurcation, held by the wear flats' contact).
    let v = 5.0 / 3600.0;
    let model = |flats: &str| {
        let p = Problem::from_toml(
            &soft_rock_text(1e-5).replace("\"3 mm\"", flats),
            std::path::Path::new("soft_rock.toml"),
        )
        .unwrap();
        ReducedModel::new(&p.model, p.mesh.elements, &p.mesh.basis).unwrap()
    };
    let (sharp, worn) = (model("\"0 mm\""), model("\"3 mm\""));
    for (name, model, rpm) in [
        ("sharp", &sharp, 110.0),
        ("sharp", &sharp, 118.0),
        ("sharp", &sharp, 130.0),
        ("worn", &worn, 118.0),
    ] {
        let op = OperatingPoint {
            omega: rpm * PI / 30.0,
            v0: v,
            wob: 0.0,
        };
        let s = released(model, op, 3.0, 12.0);
        let (_, first) = bounce_after(&s, v, 0.0);
        let (share, swing) = bounce_after(&s, v, 8.0);
        eprintln!(
            "soft rock, {name} bit, {rpm} rpm: first swing {:.2} V0; from 8 s swing {:.2e} V0, \
             off the rock {:.1} % of the time",
            first / v,
            swing / v,
            100.0 * share
        );
        match (name, rpm) {
            ("sharp", 118.0) => assert!(share > 0.1, "{share}"),
            ("worn", _) => assert!(share == 0.0 && swing > 0.3 * v, "{share} {swing}"),
            _ => assert!(share == 0.0 && swing < 1e-4 * v, "{share} {swing}"),
        }
    }
}
