//! The bit's polar inertia (`[model.bit] inertia`), lumped on the bit node's spin: its frequency
//! equation in closed form, its parsing and refusals, and the model hash of a problem without it.

use crate::common;

use common::Table1;
use drillopt::model::{BasisSpec, FamilySize};
use drillopt::rom::{Family, ModalBasis, ModeKind};
use std::io::Write;

/// A fixed–free torsional rod with a tip inertia J_tip: β L tan(β L) = J_rod / J_tip, with
/// J_rod = ρ J L and ω = β c, c = √(κ_t G / ρ) (the model's torsional stiffness κ_t G J,
/// MODEL.md §1) — e.g. Rao, *Vibration of Continuous Systems*, 2nd ed., §8.6 (the shaft with a
/// disc at its free end).
#[test]
fn the_lowest_torsional_frequency_with_a_bit_inertia_is_the_closed_form() {
    let mut p = common::seed();
    let j_rod = Table1::RHO * 2.0 * Table1::inertia() * Table1::L;
    let c = (Table1::cowper() * Table1::shear_modulus() / Table1::RHO).sqrt();
    let spec = BasisSpec::PerFamily {
        bending: FamilySize::Count(1),
        torsional: FamilySize::Count(2),
        axial: FamilySize::Count(1),
        static_corrections: false,
        steady_shapes: false,
    };
    for ratio in [f64::INFINITY, 1.0, 0.1] {
        // J_rod / J_tip = ratio (∞: no tip inertia, β L = π/2).
        p.model.bit_inertia = if ratio.is_infinite() {
            0.0
        } else {
            j_rod / ratio
        };
        let f = |x: f64| {
            if ratio.is_infinite() {
                x.cos()
            } else {
                x * x.tan() - ratio
            }
        };
        // The lowest root in (0, π/2): bisection.
        let (mut a, mut b) = (1e-9, std::f64::consts::FRAC_PI_2 - 1e-12);
        for _ in 0..200 {
            let m = 0.5 * (a + b);
            if (f(a) < 0.0) == (f(m) < 0.0) {
                a = m
            } else {
                b = m
            }
        }
        let exact_hz = 0.5 * (a + b) * c / Table1::L / (2.0 * std::f64::consts::PI);
        let basis = ModalBasis::compute(&p.model, 105, &spec).unwrap();
        let fe_hz = basis
            .family(Family::Torsional)
            .filter(|m| m.kind == ModeKind::Normal)
            .map(|m| m.freq_hz)
            .fold(f64::INFINITY, f64::min);
        println!("J_rod/J_tip = {ratio}: FE {fe_hz:.6} Hz, closed form {exact_hz:.6} Hz");
        // Linear elements of 1/105 of the length: O(h²) ≈ 1e-5 on the first mode.
        assert!(
            (fe_hz - exact_hz).abs() < 1e-4 * exact_hz,
            "{fe_hz} against {exact_hz}"
        );
    }
}

fn load(inertia: &str) -> Result<drillopt::problem::Problem, String> {
    let text = std::fs::read_to_string(common::SEED)
        .unwrap()
        .replace("inertia = \"0.4 kg m^2\"", &format!("inertia = {inertia}"));
    let mut file = tempfile::NamedTempFile::new().unwrap();
    file.write_all(text.as_bytes()).unwrap();
    drillopt::problem::Problem::load(file.path()).map_err(|e| e.to_string())
}

#[test]
fn the_bit_inertia_is_read_with_its_unit_and_refused_outside_its_range() {
    assert_eq!(load("\"0.4 kg m^2\"").unwrap().model.bit_inertia, 0.4);
    assert!((load("\"10 lbm ft^2\"").unwrap().model.bit_inertia - 0.4214011).abs() < 1e-6);
    for bad in ["\"-1 kg m^2\"", "\"5000 kg m^2\"", "\"0.4 kg\""] {
        let e = load(bad).unwrap_err();
        assert!(e.contains("model.bit.inertia"), "{bad}: {e}");
    }
}
