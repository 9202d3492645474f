//! Energy checks of the nonlinear reduced-order simulator, and its Newton Jacobian against finite
//! differences of the residual.
//!
//! - Free vibration (damping, wall, bit, gravity off; no imposed motion) conserves the total
//!   energy T + U (with the nonlinear kinetic and strain energies) over 100 periods of the first
//!   bending mode: average-acceleration Newmark is energy-conserving up to the nonlinearity.
//! - With everything on, the work put in by the top drive and the rock equals the change of
//!   energy plus what damping, wall damping and friction dissipated (the balance is computed from
//!   independently integrated powers, so it checks forces, energies and integration together).

use crate::common;

use drillopt::integrate::{ImplicitSystem, JacobianCoefficients};
use drillopt::model::BasisSpec;
use drillopt::model::OperatingPoint;
use drillopt::rom::{Family, ReducedModel};
use drillopt::sim::{Dynamics, Effects, InitialState, RunSettings, simulate};
use nalgebra::{DMatrix, DVector};

/// The seed section and materials on a 10 m string (30 elements, 24 modes: bending in both
/// planes, torsion and axial), so that 100 periods of the first bending mode (4.2 Hz) fit in the
/// test suite: on the 35 m seed string the same check passes too (drift 2.2e-7) but takes ~6 min,
/// because the error control resolves the axial modes over 290 s.
#[test]
fn free_vibration_conserves_energy_over_100_bending_periods() {
    let mut string = common::seed().model;
    string.length = 10.0;
    let model = ReducedModel::new(&string, 30, &BasisSpec::Lowest(24)).unwrap();
    for family in [Family::Axial, Family::Torsional] {
        assert!(
            model.basis.modes.iter().any(|m| m.family == family),
            "{family} modes must take part"
        );
    }
    let n = model.size();
    let first_bending = model
        .basis
        .modes
        .iter()
        .position(|m| m.family == Family::BendingZ)
        .unwrap();
    let period = 2.0 * std::f64::consts::PI / model.basis.modes[first_bending].omega;
    // Excite the first two bending modes of both planes (amplitudes of a few mm at midspan, so
    // that the geometric and gyroscopic nonlinearities couple in the axial and torsional modes).
    let mut q = DVector::zeros(n);
    let mut amplitude = |family: Family, count: usize, size: f64| {
        for (i, _) in model
            .basis
            .modes
            .iter()
            .enumerate()
            .filter(|(_, m)| m.family == family)
            .take(count)
        {
            q[i] = size;
        }
    };
    amplitude(Family::BendingZ, 2, 0.02);
    amplitude(Family::BendingY, 2, 0.01);
    // Nominal step T₁/40 under a tightened error control (which refines for the axial and
    // torsional modes that the nonlinearity excites) and a tight Newton tolerance.
    let mut settings = RunSettings::new(100.0 * period, period / 40.0);
    settings.newmark.newton_tol = 1e-9;
    settings.newmark.rtol = 1e-5;
    let out = simulate(
        &model,
        OperatingPoint {
            omega: 0.0,
            v0: 0.0,
            wob: 0.0,
        },
        Effects::NONE,
        &settings,
        InitialState::Given {
            q,
            v: DVector::zeros(n),
        },
        |_| {},
    );
    assert!(out.error.is_none(), "{:?}", out.error);
    let s = &out.series;
    let energy: Vec<f64> = s
        .kinetic_energy
        .iter()
        .zip(&s.potential_energy)
        .map(|(k, u)| k + u)
        .collect();
    let e0 = energy[0];
    let drift = energy.iter().map(|e| (e - e0).abs()).fold(0.0, f64::max) / e0;
    eprintln!(
        "free vibration: E0 = {e0:.6e} J over {:.1} s ({} steps), max relative drift {drift:.2e}",
        s.t.last().unwrap(),
        out.stats.steps
    );
    assert!(e0 > 1.0, "the test must carry real energy: {e0} J");
    let lateral = s.max_radial_over_gap.iter().cloned().fold(0.0, f64::max) * model.string.gap();
    eprintln!("largest lateral displacement {:.2} mm", lateral * 1e3);
    assert!(
        lateral > 1e-3,
        "millimetre-scale motion, so that the nonlinear terms take part"
    );
    assert!(drift < 1e-6, "energy drift {drift:e}");
}

#[test]
fn seed_run_closes_its_energy_balance() {
    let p = common::seed();
    let model = ReducedModel::new(&p.model, p.mesh.elements, &BasisSpec::Lowest(51)).unwrap();
    let mut settings = RunSettings::new(0.3, p.simulation.time_step);
    settings.probes = vec![20.0];
    let out = simulate(
        &model,
        p.operating_point,
        Effects::ALL,
        &settings,
        InitialState::StaticEquilibrium,
        |_| {},
    );
    assert!(out.error.is_none(), "{:?}", out.error);
    let s = &out.series;
    let k = s.len() - 1;
    let work_in = s.work_top[k] + s.work_bit[k];
    let stored =
        s.kinetic_energy[k] + s.potential_energy[k] - s.kinetic_energy[0] - s.potential_energy[0];
    let residual = (work_in - stored - s.dissipated[k]).abs() / s.work_top[k].abs();
    eprintln!(
        "seed 0.3 s: work by top {:.3} J, by rock {:.3} J, stored {:.3} J, dissipated {:.3} J, residual {residual:.2e}",
        s.work_top[k], s.work_bit[k], stored, s.dissipated[k]
    );
    assert!(
        s.work_top[k] > 10.0 && s.work_bit[k] < -10.0,
        "the top drive drives and the rock resists"
    );
    assert!(residual < 1e-4, "energy balance residual {residual:e}");
}

/// ∂r/∂q and ∂r/∂q̇ by central differences against the Jacobian blocks, at a state with the
/// string on the wall and the bit drilling.
#[test]
fn jacobian_matches_finite_differences_of_the_residual() {
    let p = common::seed();
    let model = ReducedModel::new(&p.model, 30, &common::small_basis()).unwrap();
    let n = model.size();
    let (q0, _) = drillopt::sim::static_equilibrium(&model).unwrap();
    let mut v = DVector::from_fn(n, |i, _| 1e-3 * ((i as f64) * 0.7).sin());
    v[0] += 1e-3;
    let a = DVector::zeros(n);
    let mut sys = Dynamics::new(&model, p.operating_point, Effects::ALL);
    let mut r0 = DVector::zeros(n);
    sys.residual(0.0, &q0, &v, &a, &mut r0);
    assert!(
        sys.contacts.iter().filter(|c| c.active).count() > 3,
        "the state must touch the wall"
    );
    assert!(sys.bit.force < 0.0, "the bit must be drilling");
    for (label, c) in [
        (
            "dr/dq",
            JacobianCoefficients {
                ca: 0.0,
                cv: 0.0,
                cq: 1.0,
            },
        ),
        (
            "dr/dv",
            JacobianCoefficients {
                ca: 0.0,
                cv: 1.0,
                cq: 0.0,
            },
        ),
    ] {
        let mut j = DMatrix::zeros(n, n);
        sys.residual(0.0, &q0, &v, &a, &mut r0);
        sys.jacobian(0.0, &q0, &v, &a, c, true, &mut j);
        let mut fd = DMatrix::zeros(n, n);
        for k in 0..n {
            let h = if c.cq > 0.0 { 1e-9 } else { 1e-7 };
            let (mut rp, mut rm) = (DVector::zeros(n), DVector::zeros(n));
            let (mut qp, mut qm, mut vp, mut vm) = (q0.clone(), q0.clone(), v.clone(), v.clone());
            if c.cq > 0.0 {
                qp[k] += h;
                qm[k] -= h;
            } else {
                vp[k] += h;
                vm[k] -= h;
            }
            sys.residual(0.0, &qp, &vp, &a, &mut rp);
            sys.residual(0.0, &qm, &vm, &a, &mut rm);
            fd.set_column(k, &((rp - rm) / (2.0 * h)));
        }
        let err = (&j - &fd).norm() / fd.norm();
        eprintln!("{label}: ‖J − FD‖ / ‖FD‖ = {err:.2e}");
        // The Jacobian neglects only small terms: the inertia tangents beyond the gyroscopic
        // ΩG and the friction-torque derivatives.
        assert!(err < 1e-3, "{label}: relative error {err:e}");
    }
}

/// A residual evaluated through the integrator's announced attempt (Φq̈ expanded once, Φq and Φq̇
/// from the attempt's base) equals the one from expanding q, q̇, q̈; and a state that is not of
/// the announced form is evaluated in full, not through the base.
#[test]
fn residual_on_an_announced_attempt_equals_the_full_evaluation() {
    let p = common::seed();
    let model = ReducedModel::new(&p.model, 30, &common::small_basis()).unwrap();
    let n = model.size();
    let (q0, _) = drillopt::sim::static_equilibrium(&model).unwrap();
    let v0 = DVector::from_fn(n, |i, _| 1e-3 * ((i as f64) * 0.7).sin());
    let a = DVector::from_fn(n, |i, _| 0.3 * ((i as f64) * 1.3).cos());
    let (cq, cv) = (0.25 * 1e-8, 0.5 * 1e-4);
    let state = |a: &DVector<f64>| {
        let q = DVector::from_fn(n, |i, _| q0[i] + cq * a[i]);
        let v = DVector::from_fn(n, |i, _| v0[i] + cv * a[i]);
        (q, v)
    };
    let full = |q: &DVector<f64>, v: &DVector<f64>, a: &DVector<f64>| {
        let mut sys = Dynamics::new(&model, p.operating_point, Effects::ALL);
        let mut r = DVector::zeros(n);
        sys.residual(0.0, q, v, a, &mut r);
        r
    };
    let mut sys = Dynamics::new(&model, p.operating_point, Effects::ALL);
    sys.begin_attempt(&q0, &v0, cq, cv);
    let mut r = DVector::zeros(n);
    for k in 0..3 {
        let a_k = &a * (1.0 + k as f64);
        let (q, v) = state(&a_k);
        sys.residual(0.0, &q, &v, &a_k, &mut r);
        let reference = full(&q, &v, &a_k);
        let error = (&r - &reference).norm() / reference.norm();
        // Round-off only (the wall stiffness, 1e10 N/m, amplifies the last bits of Φq).
        assert!(error < 1e-10, "attempt path differs by {error:e}");
    }
    assert!(
        sys.contacts.iter().any(|c| c.active),
        "the state must touch the wall"
    );
    // Off the announced form (q shifted): the full evaluation, not the base.
    let (mut q, v) = state(&a);
    q[0] += 1e-4;
    sys.residual(0.0, &q, &v, &a, &mut r);
    let reference = full(&q, &v, &a);
    assert!((&r - &reference).norm() <= 1e-14 * reference.norm());
}
