//! `drillopt modes problems/seed_mc2014_paper.toml --json` (the seed's pipe and mesh, without the
//! bit inertia of `seed_mc2014.toml`) against the closed forms for this beam:
//! fixed–free axial and torsional rods, clamped–pinned bending with the fluid's added mass.

use crate::common;

use common::*;
use serde_json::Value;
use std::f64::consts::PI;
use std::process::Command;

fn modes_json(count: usize) -> Value {
    modes_json_of(SEED_PAPER, count)
}

/// `drillopt modes FILE --json --count N`, which must succeed.
fn modes_json_of(file: &str, count: usize) -> Value {
    let out = Command::new(env!("CARGO_BIN_EXE_drillopt"))
        .args(["modes", file, "--json", "--count", &count.to_string()])
        .output()
        .expect("drillopt runs");
    assert!(
        out.status.success(),
        "drillopt modes failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("valid JSON")
}

fn family(json: &Value, name: &str) -> Vec<f64> {
    json["modes"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|m| m["family"] == name)
        .map(|m| m["freq_hz"].as_f64().unwrap())
        .collect()
}

fn check(
    label: &str,
    computed: &[f64],
    reference: impl Fn(usize) -> f64,
    count: usize,
    tolerance: f64,
) {
    assert!(
        computed.len() >= count,
        "{label}: only {} modes found",
        computed.len()
    );
    for n in 1..=count {
        let (fe, exact) = (computed[n - 1], reference(n));
        let err = (fe - exact).abs() / exact;
        eprintln!(
            "{label} mode {n}: FE {fe:.6} Hz, closed form {exact:.6} Hz, rel. error {err:.2e}"
        );
        assert!(
            err < tolerance,
            "{label} mode {n}: FE {fe} Hz vs closed form {exact} Hz ({err:.2e} > {tolerance})"
        );
    }
}

#[test]
fn seed_modes_match_the_closed_forms_to_half_a_percent() {
    let json = modes_json(160);
    assert_eq!(json["dof"], 636, "the seed mesh has 105 elements, 636 DOF");
    let indices: Vec<u64> = json["modes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| m["index"].as_u64().unwrap())
        .collect();
    assert_eq!(indices, (1..=160).collect::<Vec<u64>>());

    let l = Table1::L;
    let axial_speed = (Table1::E / Table1::RHO).sqrt();
    // Seed: κ_t = κ_s (Cowper); torsional stiffness κ_t G J over polar inertia ρ J.
    let torsion_speed = (Table1::cowper() * Table1::shear_modulus() / Table1::RHO).sqrt();
    let ei = Table1::E * Table1::inertia();
    let m = Table1::lateral_mass();
    let tol = 5e-3;
    check(
        "axial",
        &family(&json, "axial"),
        |n| fixed_free_rod_hz(n, axial_speed, l),
        3,
        tol,
    );
    check(
        "torsional",
        &family(&json, "torsional"),
        |n| fixed_free_rod_hz(n, torsion_speed, l),
        3,
        tol,
    );
    check(
        "bending_y",
        &family(&json, "bending_y"),
        |n| clamped_pinned_hz(n, ei, m, l),
        5,
        tol,
    );
    check(
        "bending_z",
        &family(&json, "bending_z"),
        |n| clamped_pinned_hz(n, ei, m, l),
        5,
        tol,
    );
}

#[test]
fn frequencies_are_ascending_and_both_bending_planes_agree() {
    let json = modes_json(51);
    let f: Vec<f64> = json["modes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| m["freq_hz"].as_f64().unwrap())
        .collect();
    assert!(
        f.windows(2).all(|w| w[0] <= w[1]),
        "frequencies must ascend"
    );
    let (y, z) = (family(&json, "bending_y"), family(&json, "bending_z"));
    assert_eq!(y.len(), z.len());
    for (a, b) in y.iter().zip(&z) {
        assert!(
            (a - b).abs() <= 1e-9 * a,
            "bending planes differ: {a} vs {b}"
        );
    }
    // The seed's 51 modes cover all four families (MODEL.md §7).
    for name in ["axial", "torsional", "bending_y", "bending_z"] {
        assert!(
            !family(&json, name).is_empty(),
            "no {name} mode among the lowest 51"
        );
    }
}

#[test]
fn modes_table_and_bad_count_on_the_command_line() {
    let out = Command::new(env!("CARGO_BIN_EXE_drillopt"))
        .args(["modes", SEED, "--count", "4"])
        .output()
        .unwrap();
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("636 DOF") && text.contains("bending_y"),
        "{text}"
    );
    // The header, the note that these are the modes without the wall, the column names.
    assert_eq!(text.lines().count(), 3 + 4, "{text}");

    let out = Command::new(env!("CARGO_BIN_EXE_drillopt"))
        .args(["modes", SEED, "--count", "0"])
        .output()
        .unwrap();
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("--count must be in [1, 628]"));
}

/// A 200 m string of 6½ in collars in air whose lowest 4 m are meshed with 250 elements of
/// 1.6 cm (a BHA meshed finely, as a graded field mesh and `verify`'s doubled mesh make it). The
/// bending blocks (699 DOFs per plane) stay below the 800 DOFs from which the Lanczos path (shift-
/// invert, accurate at the low end either way) takes over: this test guards the dense solve.
/// Its bending modes are at 14 mHz and up (ω² ≈ 8e-3 1/s²) while its shortest elements' rotary
/// inertia and shear modes are above 1e11 1/s²: an eigen-solve whose round-off is relative to the
/// highest eigenvalue (the standard form L_M⁻¹ K L_M⁻ᵀ) put the lowest 4.7e-4 off here (0.21 %
/// with 1.3 cm elements) and, on the lateral's graded mesh, returned 0 Hz. The clamped–pinned
/// closed form (Timoshenko's corrections are below 1e-6 for a 200 m span) holds to 1e-4 for the
/// lowest five (3.8e-5 measured: the discretisation error of 100 elements of 1.96 m along the
/// rest), the fixed–free rod's first two axial modes to 3e-4 (8.5e-5; the standard form 5e-5
/// here, 1.1e-3 with 1.3 cm elements).
#[test]
fn a_finely_meshed_bha_keeps_the_long_span_modes() {
    let (outer, inner, length) = (6.5 * 0.0254, 2.8125 * 0.0254, 200.0);
    let (rho, e) = (7850.0, 204e9);
    let file = format!(
        r#"name = "fine_bha_mesh"
[model]
length = "{length} m"
gravity = "9.81 m/s^2"
[model.pipe]
density = "{rho} kg/m^3"
youngs_modulus = "{e} Pa"
poisson_ratio = 0.3
damping = "0.03 1/s"
torsion_factor = 1
[model.fluid]
density = "0 kg/m^3"
[model.borehole]
radius = "4.25 in"
[model.wall]
law = "hunt_crossley"
stiffness = "3e9 N/m"
restitution = 0.5
impact_speed = "0.1 m/s"
friction = 0.25
[model.bit]
limit_force = "250 kN"
rate = "180 s/m"
friction = "0.04 m"
[mesh]
elements = 350
[operating_point]
omega = "60 rpm"
v0 = "10 m/h"
[simulation]
duration = "1 s"
time_step = "10 ms"
settling_time = "0.5 s"
[[model.section]]
name = "collars"
length = "196 m"
outer_diameter = "{outer} m"
inner_diameter = "{inner} m"
elements = 100
[[model.section]]
name = "near-bit collars"
length = "4 m"
outer_diameter = "{outer} m"
inner_diameter = "{inner} m"
elements = 250
"#
    );
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("fine_bha_mesh.toml");
    std::fs::write(&path, file).unwrap();
    let json = modes_json_of(path.to_str().unwrap(), 120);
    let area = PI / 4.0 * (outer * outer - inner * inner);
    let ei = e * PI / 64.0 * (outer.powi(4) - inner.powi(4));
    for plane in ["bending_y", "bending_z"] {
        check(
            plane,
            &family(&json, plane),
            |n| clamped_pinned_hz(n, ei, rho * area, length),
            5,
            1e-4,
        );
    }
    check(
        "axial",
        &family(&json, "axial"),
        |n| fixed_free_rod_hz(n, (e / rho).sqrt(), length),
        2,
        3e-4,
    );
}
