//! `drillopt modes problems/seed_mc2014_paper.toml --json` (the seed's pipe and mesh, without the
//! bit inertia of `seed_mc2014.toml`) against the closed forms for this beam:
//! fixed–free axial and torsional rods, clamped–pinned bending with the fluid's added mass.

use crate::common;

use common::*;
use serde_json::Value;
use std::process::Command;

fn modes_json(count: usize) -> Value {
    let out = Command::new(env!("CARGO_BIN_EXE_drillopt"))
        .args(["modes", SEED_PAPER, "--json", "--count", &count.to_string()])
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
