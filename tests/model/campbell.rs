//! The Campbell diagram against independent references (issue 14 item 4): the modes of the basis
//! at rest, the wall's stiffening of the resting plane, the gyroscopic split of a spinning
//! simply supported beam and of an isotropic two-degree-of-freedom rotor in closed form, and the
//! critical speeds of that rotor.

use crate::common;

use drillopt::campbell::*;
use drillopt::rom::{Family, ReducedModel};
use nalgebra::DMatrix;
use std::f64::consts::{PI, TAU};

fn seed_model() -> ReducedModel {
    let p = common::seed();
    ReducedModel::new(&p.model, p.mesh.elements, &p.mesh.basis).unwrap()
}

const NO_WALL: Linearisation = Linearisation {
    contact: false,
    damping: false,
};

fn rpm(x: f64) -> f64 {
    drillopt::units::from_rpm(x)
}

#[test]
fn at_rest_without_the_wall_the_frequencies_are_those_of_drillopt_modes() {
    let model = seed_model();
    let sys = LinearSystem::about_rest(&model, NO_WALL).unwrap();
    let s = spectrum(&sys, 0.0).unwrap();
    let mut expected: Vec<f64> = model.basis.modes.iter().map(|m| m.freq_hz).collect();
    expected.sort_by(f64::total_cmp);
    assert_eq!(s.modes.len(), expected.len());
    assert_eq!(s.non_oscillatory, 0);
    for (m, f) in s.modes.iter().zip(&expected) {
        assert!(
            (m.freq_hz - f).abs() < 1e-9 * f,
            "{} Hz vs {f} Hz",
            m.freq_hz
        );
        assert_eq!(m.whirl, Whirl::None, "no spin, no whirl sense");
    }
    // Families as `drillopt modes` counts them (static corrections and resting shapes with
    // their family).
    let count = |f: ModeFamily| s.modes.iter().filter(|m| m.family == f).count();
    let c = model.basis.counts();
    assert_eq!(count(ModeFamily::Bending), c.bending + c.resting_shapes);
    assert_eq!(
        count(ModeFamily::Torsional) + count(ModeFamily::Axial),
        c.torsional + c.axial + 2
    );
}

#[test]
fn the_wall_raises_every_frequency_and_the_resting_plane_most() {
    let model = seed_model();
    let free = spectrum(&LinearSystem::about_rest(&model, NO_WALL).unwrap(), 0.0).unwrap();
    let sys = LinearSystem::about_rest(&model, Linearisation::default()).unwrap();
    let rest = sys.resting.as_ref().unwrap();
    assert!(rest.contact_nodes > 0);
    // The wall carries most of the string's weight, the supports at the ends the rest (the
    // unreduced model: 15.2 kN of 19.1 kN, the same as this basis).
    let weight = common::Table1::lateral_mass() * 9.81 * common::Table1::L;
    assert!(
        rest.wall_force_n > 0.5 * weight && rest.wall_force_n < weight,
        "{rest:?}"
    );
    let walled = spectrum(&sys, 0.0).unwrap();
    // K + K_wall with K_wall positive semi-definite (normal and tangential parts): every
    // eigenvalue rises (Courant–Fischer), to round-off and the sag's tiny geometric stiffness.
    for (a, b) in free.modes.iter().zip(&walled.modes) {
        assert!(
            b.freq_hz >= a.freq_hz * (1.0 - 1e-6),
            "{} < {}",
            b.freq_hz,
            a.freq_hz
        );
    }
    let lowest = |s: &Spectrum, vertical: bool| {
        s.modes
            .iter()
            .find(|m| m.family == ModeFamily::Bending && (m.vertical_share > 0.5) == vertical)
            .unwrap()
            .freq_hz
    };
    // The vertical plane rests on the wall: its lowest mode rises more than tenfold (0.35 Hz to
    // about 15 Hz); the horizontal plane gains the "pendulum" stiffness of the weight on the
    // curved wall, about √(g/gap)/2π ≈ 5 Hz for its lowest mode.
    assert!(lowest(&walled, true) > 10.0 * lowest(&free, true));
    let pendulum = (9.81 / model.string.gap()).sqrt() / TAU;
    let horizontal = lowest(&walled, false);
    assert!(
        horizontal > pendulum && horizontal < 1.1 * pendulum,
        "{horizontal} Hz vs √(g/gap)/2π = {pendulum} Hz"
    );
}

/// The bending pairs of a spectrum without the wall: (forward, backward) frequencies in Hz.
fn pairs(s: &Spectrum, count: usize) -> Vec<(f64, f64)> {
    let bending: Vec<&EigenMode> = s
        .modes
        .iter()
        .filter(|m| m.family == ModeFamily::Bending)
        .collect();
    bending[..2 * count]
        .chunks(2)
        .map(|p| {
            let fwd = p.iter().find(|m| m.whirl == Whirl::Forward);
            let bwd = p.iter().find(|m| m.whirl == Whirl::Backward);
            match (fwd, bwd) {
                (Some(f), Some(b)) => (f.freq_hz, b.freq_hz),
                // At Ω = 0 neither has a whirl sense.
                _ => (p[0].freq_hz, p[1].freq_hz),
            }
        })
        .collect()
}

#[test]
fn the_whirl_split_is_zero_at_rest_and_grows_with_the_spin() {
    let model = seed_model();
    let sys = LinearSystem::about_rest(&model, NO_WALL).unwrap();
    let omegas: Vec<f64> = (0..=10).map(|i| rpm(20.0 * i as f64)).collect();
    let splits: Vec<Vec<f64>> = omegas
        .iter()
        .map(|&w| {
            let s = spectrum(&sys, w).unwrap();
            if w > 0.0 {
                // Circular orbits, one of each sense per pair.
                for m in s
                    .modes
                    .iter()
                    .filter(|m| m.family == ModeFamily::Bending)
                    .take(6)
                {
                    assert!(
                        (m.circularity.abs() - 1.0).abs() < 1e-6,
                        "{}",
                        m.circularity
                    );
                }
            }
            pairs(&s, 3).iter().map(|(f, b)| (f - b).abs()).collect()
        })
        .collect();
    for pair in 0..3 {
        let f0 = model.basis.modes[2 * pair].freq_hz;
        let split: Vec<f64> = splits.iter().map(|s| s[pair]).collect();
        assert!(split[0] < 1e-9 * f0, "split at rest {}", split[0]);
        for (i, w) in split.windows(2).enumerate() {
            assert!(w[1] > w[0], "pair {pair} at {}", i + 1);
        }
        // Linear in Ω to first order: the split at 200 rpm is 10 × that at 20 rpm.
        let ratio = split[10] / split[1];
        assert!((ratio - 10.0).abs() < 1e-3, "{ratio}");
    }
}

/// The model's kinetic energy (MODEL.md §3 [settled, turn 3]) holds the spin as
/// (θ̇x − θy θ̇z)² with θy = −w', θz = v' (§2): the spin about the axis of the section tilted by
/// (v', w'), θ̇x − ½(v' ẇ' − w' v̇') up to a time derivative (rotation-vector kinematics). So,
/// as in a rigid rotor (Genta 2005, §4.4; Lalanne & Ferraris 1998, §2.3), the mode whose orbit
/// turns with the spin (forward) is the higher of a pair. (The paper's Eq. (11), from
/// (θ̇x + θy θ̇z)², made it the lower; `tests/model/spinning_shaft.rs` checks both branches against
/// the closed form of a spinning shaft.)
#[test]
fn forward_whirl_is_the_higher_of_a_pair() {
    let model = seed_model();
    let sys = LinearSystem::about_rest(&model, NO_WALL).unwrap();
    let s = spectrum(&sys, rpm(200.0)).unwrap();
    for (fwd, bwd) in pairs(&s, 3) {
        assert!(fwd > bwd, "forward {fwd} Hz, backward {bwd} Hz");
    }
}

/// An isotropic rotor of two coordinates (a, b) = (v, w): ä − gΩ ḃ + s a = 0,
/// b̈ + gΩ ȧ + s b = 0. Its orbits are circles; the one turning from +y to +z solves
/// ω² + gΩω − s = 0, the other ω² − gΩω − s = 0.
fn rotor(s: f64, g: f64) -> LinearSystem {
    let k = DMatrix::from_diagonal_element(2, 2, s);
    let gyro = DMatrix::from_row_slice(2, 2, &[0.0, -g, g, 0.0]);
    LinearSystem::from_parts(
        DMatrix::identity(2, 2),
        k,
        gyro,
        None,
        vec![Family::BendingY, Family::BendingZ],
        [
            DMatrix::from_row_slice(1, 2, &[1.0, 0.0]),
            DMatrix::from_row_slice(1, 2, &[0.0, 1.0]),
        ],
    )
    .unwrap()
}

#[test]
fn an_isotropic_rotor_has_its_closed_form_whirl_frequencies() {
    let (s, g) = (400.0, 0.3);
    for omega in [0.0, 5.0, 40.0, -7.0] {
        let sys = rotor(s, g);
        let (values, _) = state_eigen(&sys, omega).unwrap();
        // Conjugate pairs on the imaginary axis.
        for l in &values {
            assert!(l.re.abs() < 1e-12 * l.norm(), "{l}");
            assert!(
                values
                    .iter()
                    .any(|m| (m - l.conj()).norm() < 1e-12 * l.norm())
            );
        }
        let spec = spectrum(&sys, omega).unwrap();
        let root = |sign: f64| (sign * g * omega + (g * g * omega * omega + 4.0 * s).sqrt()) / 2.0;
        let with_spin = spec.modes.iter().find(|m| m.circularity > 0.5);
        if omega == 0.0 {
            assert!(spec.modes.iter().all(|m| m.whirl == Whirl::None));
            continue;
        }
        // The orbit turning +y → +z: ω² + gΩω − s = 0, forward when Ω > 0.
        let m = with_spin.unwrap();
        assert!((m.eigenvalue.im - root(-1.0)).abs() < 1e-12 * root(1.0));
        assert_eq!(
            m.whirl,
            if omega > 0.0 {
                Whirl::Forward
            } else {
                Whirl::Backward
            }
        );
        assert!((m.circularity - 1.0).abs() < 1e-12);
        let other = spec.modes.iter().find(|m| m.circularity < -0.5).unwrap();
        assert!((other.eigenvalue.im - root(1.0)).abs() < 1e-12 * root(1.0));
        assert_eq!(
            other.whirl,
            if omega > 0.0 {
                Whirl::Backward
            } else {
                Whirl::Forward
            }
        );
    }
}

#[test]
fn critical_speeds_of_the_rotor_are_found_in_closed_form() {
    // The forward branch meets kΩ where k²Ω² + gkΩ² = s, the backward one where
    // k²Ω² − gkΩ² = s.
    let (s, g) = (400.0, 0.3);
    let sys = rotor(s, g);
    let omegas: Vec<f64> = (0..=40).map(|i| 0.5 + i as f64).collect();
    let diagram = CampbellDiagram::sweep(&sys, &omegas, |_| {}).unwrap();
    assert_eq!(diagram.curves.len(), 2);
    let speeds = crossings(&sys, &diagram, 3.0).unwrap();
    let mut expected = vec![
        ((s / (1.0 + g)).sqrt(), 1.0, Whirl::Forward),
        ((s / (1.0 - g)).sqrt(), 1.0, Whirl::Backward),
        ((s / (9.0 + 3.0 * g)).sqrt(), 3.0, Whirl::Forward),
        ((s / (9.0 - 3.0 * g)).sqrt(), 3.0, Whirl::Backward),
    ];
    expected.sort_by(|a, b| a.0.total_cmp(&b.0));
    assert_eq!(speeds.len(), 4, "{speeds:?}");
    for (c, (w, k, whirl)) in speeds.iter().zip(expected) {
        assert!(
            (c.omega_rad_s - w).abs() < 1e-8 * w,
            "{} vs {w}",
            c.omega_rad_s
        );
        assert_eq!((c.multiple, c.whirl), (k, whirl));
        assert!((c.freq_hz - k * w / TAU).abs() < 1e-8 * c.freq_hz);
    }
    // The margin of an operating speed between two of them.
    let op = 0.5 * (speeds[0].omega_rad_s + speeds[1].omega_rad_s);
    let (below, above) = (speeds[0].omega_rad_s, speeds[1].omega_rad_s);
    let near = ((op - below) / below).min((above - op) / above);
    assert!((margin(op, &speeds) - near.min(MARGIN_CAP)).abs() < 1e-12);
    let table = MarginTable::search(&sys, 3.0, [op, op]).unwrap();
    assert!((table.margin(op).unwrap() - margin(op, &speeds)).abs() < 1e-9);
}

/// A simply supported spinning beam (the seed's section, 35 m, 30 elements): its modes are sines,
/// which the gyroscopic matrix does not couple, so each pair n splits as an isolated one:
/// ω_f − ω_b = Ω · 2ρI k² / (ρA + ρ_f A_f + ρI k²), k = nπ/L (Rayleigh beam, e.g. Genta 2005
/// §5.4, with the fluid adding lateral mass only), and ω_f ω_b = ω₀² exactly.
#[test]
fn a_spinning_simply_supported_beam_splits_as_the_rayleigh_beam() {
    let p = common::seed();
    let m = common::simply_supported(&p.model, 30);
    let sys = LinearSystem::from_parts(
        m.mass,
        m.stiffness,
        m.gyroscopic,
        None,
        m.families,
        m.lateral,
    )
    .unwrap();
    let (rho, l) = (common::Table1::RHO, common::Table1::L);
    let rho_i = rho * common::Table1::inertia();
    let omega = 30.0;
    let at_rest = pairs(&spectrum(&sys, 0.0).unwrap(), 3);
    let spinning = pairs(&spectrum(&sys, omega).unwrap(), 3);
    for (k, ((f, b), (r0, _))) in spinning.iter().zip(&at_rest).enumerate() {
        let wave = (k + 1) as f64 * PI / l;
        let expected = omega * 2.0 * rho_i * wave * wave
            / (common::Table1::lateral_mass() + rho_i * wave * wave);
        // Forward minus backward: positive, forward whirl stiffens (MODEL.md §3).
        let split = TAU * (f - b);
        assert!(
            (split - expected).abs() < 1e-3 * expected,
            "mode {}: split {split} rad/s vs {expected}",
            k + 1
        );
        assert!(((f * b).sqrt() - r0).abs() < 1e-8 * r0, "ω_f ω_b = ω₀²");
    }
}
