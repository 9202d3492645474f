//! The annulus mud's confined added mass (issue 28 item 5, MODEL.md §11.4): with
//! `[model.fluid] annulus_density` ρ_a the lateral motion (v, w) carries, per unit length,
//!
//!   m_a = ρ_a π R_ext² (R_bh² + R_ext²) / (R_bh² − R_ext²)
//!
//! (Chen, Wambsganss & Jendrzejczyk, J. Appl. Mech. 43, 1976, inviscid limit), on top of the
//! pipe and the mud inside it, and nothing else: not the axial or torsional inertia, not the
//! weight. References are computed here from the raw numbers of the seed's Table 1 (R_bh = 70 mm),
//! not from the crate's `Section`.

use crate::common;

use common::{SEED, Table1, clamped_pinned_hz};
use drillopt::fem::Dof;
use drillopt::model::Drillstring;
use drillopt::problem::Problem;
use drillopt::rom::{Family, ModalBasis, ReducedModel};
use drillopt::sim::{Dynamics, Effects, static_equilibrium};
use std::f64::consts::PI;
use std::path::Path;

/// The seed's borehole radius, m.
const R_BH: f64 = 0.070;
/// Annulus mud density, kg/m³ (the density of the mud inside the seed's pipe).
const RHO_A: f64 = 1200.0;

/// m_a from the raw numbers, kg/m.
fn added_mass() -> f64 {
    let (a2, b2) = (Table1::R_EXT.powi(2), R_BH.powi(2));
    RHO_A * PI * a2 * (b2 + a2) / (b2 - a2)
}

/// The seed problem (as shipped), with `annulus_density` in `[model.fluid]` when given, and its
/// length replaced when given.
fn seed(annulus: Option<&str>, length: Option<&str>) -> Problem {
    let mut text = std::fs::read_to_string(SEED).unwrap();
    if let Some(value) = annulus {
        text = text.replacen(
            "[model.fluid]\n",
            &format!("[model.fluid]\nannulus_density = {value}\n"),
            1,
        );
    }
    if let Some(value) = length {
        text = text.replacen("length = \"35 m\"", &format!("length = \"{value}\""), 1);
    }
    Problem::from_toml(&text, Path::new("cases/mud.toml")).unwrap()
}

/// The lowest `count` modes of the seed's mesh (the modes `drillopt modes` lists), Hz, by family.
fn frequencies(string: &Drillstring, elements: usize, count: usize, family: Family) -> Vec<f64> {
    ModalBasis::compute_lowest(string, elements, count)
        .unwrap()
        .modes
        .iter()
        .filter(|m| m.family == family)
        .map(|m| m.freq_hz)
        .collect()
}

#[test]
fn the_seeds_added_mass_is_89_kg_per_m_against_56_of_pipe_and_inner_mud() {
    let m = Table1::lateral_mass();
    let m_a = added_mass();
    println!("m = {m:.3} kg/m, m_a = {m_a:.3} kg/m");
    assert!((m - 55.67).abs() < 0.01, "{m}");
    assert!((m_a - 88.74).abs() < 0.01, "{m_a}");
    // The key in the problem file puts it (and only it) in the lateral mass per length.
    let (dry, mud) = (seed(None, None), seed(Some("\"1.2 sg\""), None));
    let section = |p: &Problem| drillopt::model::Section::of(&p.model);
    assert_eq!(section(&dry).added_mass, 0.0);
    assert!((section(&mud).added_mass / m_a - 1.0).abs() < 1e-14);
    assert!((section(&mud).lateral_mass() / (m + m_a) - 1.0).abs() < 1e-14);
    let displaced = RHO_A * PI * Table1::R_EXT.powi(2);
    let weight_drop = section(&dry).weight_mass() - section(&mud).weight_mass();
    assert!(
        (weight_drop / displaced - 1.0).abs() < 1e-12,
        "{weight_drop}"
    );
}

/// Bending: f_mud / f_dry = √(m / (m + m_a)), m = ρA + ρ_f A_f, exact for an Euler–Bernoulli
/// beam whose whole lateral mass is scaled. The element also has rotatory inertia ρI (not
/// scaled by the mud) and shear: on the 35 m seed they lower the first five bending frequencies
/// by (k r_g)²-sized terms (r_g = √(I/A) = 36 mm, k = β_n/L), 1.6e-5 to 3e-4 (the FE sits 7e-5 to
/// 9e-4 below Euler–Bernoulli, README), so the ratio is exact to about 1e-4: slender enough for
/// the 1e-3 asked. Also each mud frequency against the clamped–pinned Euler–Bernoulli closed form
/// with the mass m + m_a, to the 5e-3 of `tests/model/modes_closed_form.rs`.
#[test]
fn bending_frequencies_fall_by_the_square_root_of_the_mass_ratio() {
    let (dry, mud) = (seed(None, None), seed(Some("\"1200 kg/m^3\""), None));
    let elements = dry.mesh.elements;
    assert_eq!(elements, 105);
    let (m, m_a) = (Table1::lateral_mass(), added_mass());
    let ratio = (m / (m + m_a)).sqrt();
    let ei = Table1::E * Table1::inertia();
    let mut worst: f64 = 0.0;
    for family in [Family::BendingY, Family::BendingZ] {
        let f_dry = frequencies(&dry.model, elements, 40, family);
        let f_mud = frequencies(&mud.model, elements, 40, family);
        assert!(f_dry.len() >= 5 && f_mud.len() >= 5);
        for n in 1..=5 {
            let (fd, fm) = (f_dry[n - 1], f_mud[n - 1]);
            let err = (fm / fd / ratio - 1.0).abs();
            let exact = clamped_pinned_hz(n, ei, m + m_a, Table1::L);
            let err_eb = (fm / exact - 1.0).abs();
            println!(
                "{family} mode {n}: dry {fd:.6} Hz, mud {fm:.6} Hz, ratio {:.7} vs √(m/(m+m_a)) \
                 {ratio:.7} (rel. error {err:.1e}); Euler–Bernoulli {exact:.6} Hz ({err_eb:.1e})",
                fm / fd
            );
            assert!(err < 1e-3, "{family} mode {n}: ratio error {err:e}");
            assert!(
                err_eb < 5e-3,
                "{family} mode {n}: closed-form error {err_eb:e}"
            );
            worst = worst.max(err);
        }
    }
    println!("largest ratio error {worst:.2e}");
}

/// Axial and torsional frequencies do not see the mud's added mass: equal to round-off.
#[test]
fn axial_and_torsional_frequencies_do_not_change() {
    let (dry, mud) = (seed(None, None), seed(Some("\"1200 kg/m^3\""), None));
    let elements = dry.mesh.elements;
    for family in [Family::Axial, Family::Torsional] {
        // 200 of the 628 modes: the mud lowers the bending ones, so more of them come first.
        let f_dry = frequencies(&dry.model, elements, 200, family);
        let f_mud = frequencies(&mud.model, elements, 200, family);
        assert!(f_dry.len() >= 3 && f_mud.len() >= 3, "{family}");
        for (n, (a, b)) in f_dry.iter().zip(&f_mud).take(3).enumerate() {
            let err = (b / a - 1.0).abs();
            println!(
                "{family} mode {}: dry {a} Hz, mud {b} Hz ({err:.1e})",
                n + 1
            );
            assert!(err < 1e-12, "{family} mode {}: {a} vs {b}", n + 1);
        }
    }
}

/// The resting state depends on the weight, the stiffness and the wall, not on the mass: the
/// 100 m seed pipe with 1200 kg/m³ of annulus mud (lateral mass m + m_a, buoyed weight w_b)
/// rests exactly where the same pipe without annulus mud rests under a gravity scaled to give it
/// the same weight (lateral mass m). Unreduced finite-element model (every DOF), so that no
/// mass-dependent basis enters; the wall then carries w_b per length in the middle of the string
/// (closed form from the raw numbers; see `tests/model/buoyancy.rs` for why the middle).
#[test]
fn the_resting_state_is_that_of_the_buoyed_weight_whatever_the_added_mass() {
    let mud = seed(Some("\"1200 kg/m^3\""), Some("100 m"));
    let mut dry = seed(None, Some("100 m"));
    let elements = 100;
    let (ro, ri) = (Table1::R_EXT, Table1::R_INT);
    let (steel, inside) = (
        Table1::RHO * PI * (ro * ro - ri * ri),
        Table1::RHO_F * PI * ri * ri,
    );
    let buoyed = steel + inside - RHO_A * PI * ro * ro;
    dry.model.gravity = 9.81 * buoyed / (steel + inside);
    let rest = |p: &Problem| {
        let model = ReducedModel::unreduced(&p.model, elements).unwrap();
        let (q, _) = static_equilibrium(&model).unwrap();
        let statics = Effects {
            damping: false,
            bit: false,
            ..Effects::ALL
        };
        let op = drillopt::model::OperatingPoint {
            omega: 0.0,
            v0: 0.0,
            wob: 0.0,
        };
        let mut sys = Dynamics::new(&model, op, statics);
        let zero = nalgebra::DVector::zeros(model.size());
        sys.observe(&q, &zero, &zero);
        let middle = &sys.contacts[30..=70];
        assert!(
            middle.iter().all(|c| c.active),
            "every middle node on the wall"
        );
        let reaction = middle.iter().map(|c| c.normal.abs()).sum::<f64>() / middle.len() as f64;
        let mut full = nalgebra::DVector::zeros(model.phi.nrows());
        full.gemv(1.0, &model.phi, &q, 0.0);
        (full, reaction)
    };
    let ((q_mud, r_mud), (q_dry, r_dry)) = (rest(&mud), rest(&dry));
    let sag = (0..=elements)
        .map(|k| q_mud[Dof::W.at(k)].abs())
        .fold(0.0, f64::max);
    let diff = (&q_mud - &q_dry).amax() / q_mud.amax();
    let w_b = buoyed * 9.81;
    println!(
        "largest sag {sag:.4e} m; resting states differ by {diff:.1e} (relative); wall reaction \
         {r_mud} N/m with mud, {r_dry} N/m dry with the same weight, w_b = {w_b} N/m"
    );
    assert!(sag > 1e-3, "the string sags onto the wall");
    assert!(diff < 1e-9, "resting states differ by {diff:e}");
    assert!((r_mud / w_b - 1.0).abs() < 1e-9, "{r_mud} vs {w_b}");
    assert!((r_dry / w_b - 1.0).abs() < 1e-9, "{r_dry} vs {w_b}");
}
