//! Section loads and von Mises stresses along the string (issue 14, item 1), against closed forms:
//! a straight, weightless, undamped string drilling at its steady state carries the WOB as a
//! uniform compression and the TOB as a uniform torque, so every section has
//! σ = E(ε + ½ε² + ½(Rκ)²), ε = −WOB/EA, κ = TOB/(κ_t G J), τ = κ_t G R κ, σ_vM = √(σ² + 3τ²).

use crate::common;

use drillopt::metrics;
use drillopt::model::OperatingPoint;
use drillopt::model::bit::xi;
use drillopt::problem::Problem;
use drillopt::rom::ReducedModel;
use drillopt::sim::{Effects, InitialState, RunSettings, simulate};
use std::path::Path;

fn weightless_undamped_seed(extra_pipe: &str) -> Problem {
    let text = std::fs::read_to_string(common::SEED)
        .unwrap()
        .replace("gravity = \"9.81 m/s^2\"", "gravity = 0")
        .replace("damping = \"0.03 1/s\"", "damping = 0")
        .replace("friction = 1e-5 ", "friction = 0 ")
        .replace("[model.pipe]", &format!("[model.pipe]\n{extra_pipe}"));
    let mut p = Problem::from_toml(&text, Path::new("stress.toml")).unwrap();
    p.mesh.elements = 30;
    p.mesh.basis = common::small_basis();
    p
}

#[test]
fn steady_drilling_stresses_match_the_closed_form_along_the_whole_string() {
    let p = weightless_undamped_seed("yield_strength = \"S-135\"");
    assert_eq!(p.model.wall.get("friction"), Some(0.0));
    assert_eq!(p.model.gravity, 0.0);
    let model = ReducedModel::new(&p.model, p.mesh.elements, &p.mesh.basis).unwrap();
    let op = OperatingPoint {
        omega: 2.0 * std::f64::consts::PI,
        v0: 5.0 / 3600.0,
        wob: 0.0,
    };
    // 1 ms: the steady state is unstable (velocity-weakening bit, no damping), and the stick-slip
    // that grows out of it moves the torque by 1.7 % within 50 ms; the first millisecond is the
    // steady state to 1e-4. Newton is converged to 1e-9 of its default tolerance's scale: the
    // reduced model's axial force and torque sum the loads of the last Newton residual
    // (`rom::ForceSummation`), whose state differs from the accepted one by the last correction
    // (with the default 1e-3, up to 110 N of the 55 kN here, 2e-3, as the top drive's force).
    let mut settings = RunSettings::new(1e-3, p.simulation.time_step);
    settings.newmark.newton_tol = 1e-9;
    let out = simulate(
        &model,
        op,
        Effects::ALL,
        &settings,
        InitialState::Preloaded,
        |_| {},
    );
    assert!(out.error.is_none());
    // Closed form from the raw Table 1 numbers (common::Table1) and the seed bit law.
    let wob = 250e3 * (1.0 - (-180.0f64 * op.v0).exp());
    let tob = 0.04 * wob * xi(op.omega).0;
    let (e, g) = (common::Table1::E, common::Table1::shear_modulus());
    let (a, r) = (common::Table1::area(), common::Table1::R_EXT);
    let j = 2.0 * common::Table1::inertia();
    let kt = p.model.pipe.torsion_factor;
    let eps = -wob / (e * a);
    let kappa = tob / (kt * g * j);
    let sigma = e * (eps + 0.5 * eps * eps + 0.5 * (r * kappa).powi(2));
    let tau = kt * g * r * kappa;
    let von_mises = (sigma * sigma + 3.0 * tau * tau).sqrt();
    let env = &out.envelope;
    assert_eq!(env.position_m.len(), 30);
    // To 3e-4 and 5e-4 (the compression): the reduced model's axial force and torque are summed
    // from the loads (`rom::ForceSummation`) and carry the residual of its start, in equilibrium
    // to its own tolerance (22.7 N of the compression, 4.1e-4, at the bit's element at t = 0;
    // 2-6 N at the steps after it).
    for (k, s) in env.max_von_mises_pa.iter().enumerate() {
        assert!(
            (s / von_mises - 1.0).abs() < 3e-4,
            "element {k}: {s} Pa against {von_mises} Pa"
        );
        // N = E∫E_xx dA = EA(ε + ½ε²) + EI κ² (the helix of the twisted fibres).
        let compression = -(e * a * (eps + 0.5 * eps * eps) + e * (j / 2.0) * kappa * kappa);
        assert!(
            (env.max_compression_n[k] / compression - 1.0).abs() < 5e-4,
            "element {k}: {} N against {compression} N",
            env.max_compression_n[k]
        );
        assert!((env.max_torque_nm[k] / tob - 1.0).abs() < 1e-4);
    }
    // The metrics, with the S-135 grade's 135 ksi = 930.8 MPa.
    let m = metrics::of_run(&out, &p.model, op, 0.0, None).unwrap();
    assert!((m.max_von_mises_pa / von_mises - 1.0).abs() < 3e-4);
    assert!(
        (m.von_mises_safety_factor - 135.0 * 6.894757293168e6 / m.max_von_mises_pa).abs() < 1e-9
    );
    assert!((0.0..=35.0).contains(&m.max_von_mises_at_m));
}

#[test]
fn yield_strength_is_a_pressure_or_an_api_grade() {
    let p = weightless_undamped_seed("yield_strength = \"g-105\"");
    assert!((p.model.pipe.yield_strength.unwrap() - 105.0 * 6.894757293168e6).abs() < 1e-3);
    let p = weightless_undamped_seed("yield_strength = \"G105\"");
    assert!((p.model.pipe.yield_strength.unwrap() - 105.0 * 6.894757293168e6).abs() < 1e-3);
    let p = weightless_undamped_seed("yield_strength = \"800 MPa\"");
    assert_eq!(p.model.pipe.yield_strength, Some(800e6));
    let text = std::fs::read_to_string(common::SEED)
        .unwrap()
        .replace("[model.pipe]", "[model.pipe]\nyield_strength = \"Q-125\"");
    let err = Problem::from_toml(&text, Path::new("stress.toml")).unwrap_err();
    assert_eq!(err.key(), Some("model.pipe.yield_strength"));
    assert!(err.to_string().contains("S-135"), "{err}");
    // Without a yield strength the safety factor is not defined.
    assert_eq!(common::seed().model.pipe.yield_strength, None);
}

#[test]
fn risks_use_the_utilization_which_needs_a_yield_strength() {
    let risk = |metric: &str| {
        format!("\n[objective]\n[[objective.risk]]\nmetric = \"{metric}\"\nweight = 1.0\n")
    };
    let seed = std::fs::read_to_string(common::SEED).unwrap();
    let with_grade = seed.replace("[model.pipe]", "[model.pipe]\nyield_strength = \"S-135\"");
    let load = |text: String| Problem::from_toml(&text, Path::new("stress.toml"));
    // The safety factor grows with safety: never a risk, with or without a yield strength.
    for base in [&seed, &with_grade] {
        let err = load(format!("{base}{}", risk("von_mises_safety_factor"))).unwrap_err();
        assert_eq!(err.key(), Some("objective.risk[0].metric"));
        assert!(err.to_string().contains("von_mises_utilization"), "{err}");
    }
    let err = load(format!("{seed}{}", risk("von_mises_utilization"))).unwrap_err();
    assert!(err.to_string().contains("yield_strength"), "{err}");
    load(format!("{with_grade}{}", risk("von_mises_utilization"))).unwrap();
}

#[test]
fn verify_checks_the_stress_when_the_problem_decides_on_it() {
    let keys = common::decision_keys;
    let seed = std::fs::read_to_string(common::SEED).unwrap();
    assert!(!keys(&common::seed()).contains(&"max_von_mises_pa"));
    let text = seed.replace("[model.pipe]", "[model.pipe]\nyield_strength = \"S-135\"")
        + "\n[objective]\n[[objective.risk]]\nmetric = \"von_mises_utilization\"\nweight = 1.0\n";
    let p = Problem::from_toml(&text, Path::new("stress.toml")).unwrap();
    assert!(keys(&p).contains(&"max_von_mises_pa"));
}

/// `simulate` prints the safety factor beside the peak stress when the problem gives a yield
/// strength, and warns on stderr when the stress reaches it.
#[test]
fn simulate_shows_the_safety_factor_and_warns_at_yield() {
    let tiny = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/problems/regression/tiny_string.toml"
    ))
    .unwrap();
    let dir = tempfile::tempdir().unwrap();
    let run = |yield_strength: &str| {
        let file = dir.path().join(format!("y{}.toml", yield_strength.len()));
        let text = tiny.replace(
            "[model.pipe]",
            &format!("[model.pipe]\nyield_strength = \"{yield_strength}\""),
        );
        std::fs::write(&file, text).unwrap();
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_drillopt"))
            .args([
                "simulate",
                file.to_str().unwrap(),
                "--quiet",
                "--duration",
                "1",
            ])
            .arg("--out")
            .arg(dir.path().join("out"))
            .output()
            .unwrap();
        assert!(out.status.success(), "{out:?}");
        let stdout = String::from_utf8(out.stdout).unwrap();
        let stderr = String::from_utf8(out.stderr).unwrap();
        let summary: serde_json::Value = serde_json::from_str(
            &std::fs::read_to_string(dir.path().join("out/summary.json")).unwrap(),
        )
        .unwrap();
        let sf = summary["metrics"]["von_mises_safety_factor"]
            .as_f64()
            .unwrap();
        (stdout, stderr, sf)
    };
    // S-135 (930.8 MPa): far from yield, the factor shown, no warning.
    let (stdout, stderr, sf) = run("S-135");
    assert!(sf > 1.0, "{sf}");
    assert!(
        stdout.contains(&format!("(safety factor {sf:.2})")),
        "{stdout}"
    );
    assert!(!stderr.contains("yield strength"), "{stderr}");
    // 10 MPa, the lowest admissible yield strength (a polymer pipe's): the peak stress (tens of
    // MPa) is beyond it.
    let (stdout, stderr, sf) = run("10 MPa");
    assert!(sf < 1.0, "{sf}");
    assert!(
        stdout.contains(&format!("(safety factor {sf:.2})")),
        "{stdout}"
    );
    assert!(
        stderr.contains("warning: the peak von Mises stress")
            && stderr.contains("reaches the yield strength"),
        "{stderr}"
    );
}

/// The axial force along a string of sections at its steady drilling state against equilibrium:
/// the string turns, so the wall's friction is almost all tangential, and the axial force can
/// only run from the WOB at the bit to the top push (0.6 % apart on the 1 km well).
/// - The finite-element model without reduction: where the string bends (its section boundaries
///   and the stabiliser, on 12 m drill-pipe elements), the membrane strain taken at the element's
///   midpoint fell short of the average the nodes carry by EA(κL)²/24 and read 83.3-88.5 kN; the
///   element average (`fem::stress`) is within 0.02 % of the band.
/// - The reduced model (the file's default basis): its strains read 65.2-91.6 kN (the bending
///   shapes' membrane strain has no axial companion in the basis); the force-summation recovery
///   (`rom::ForceSummation`) is within 0.02 % of the band, and its torque at the top element is
///   the top drive's torque less the friction of the top node's half element.
#[test]
fn the_axial_force_along_a_string_of_sections_stays_between_the_wob_and_the_top_push() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("problems/field/well_1km.toml");
    let p = Problem::load(&path).unwrap();
    for kind in [
        drillopt::sim::ModelKind::Unreduced,
        drillopt::sim::ModelKind::Reduced,
    ] {
        let model = kind.build(&p.model, &p.mesh, p.operating_point).unwrap();
        let op = p.operating_point;
        let out = simulate(
            &model,
            op,
            Effects::ALL,
            &RunSettings::new(0.01, p.simulation.time_step),
            InitialState::Preloaded,
            |_| {},
        );
        assert!(out.error.is_none(), "{kind:?}: {:?}", out.error);
        let m = metrics::of_run(&out, &p.model, op, 0.0, None).unwrap();
        let (wob, top) = (m.mean_wob_n, m.mean_top_force_n);
        assert!(wob > 80e3 && (top / wob - 1.0).abs() < 0.01, "{wob} {top}");
        let (low, high) = (wob.min(top) * (1.0 - 1e-3), wob.max(top) * (1.0 + 1e-3));
        let env = &out.envelope;
        for (x, &n) in env.position_m.iter().zip(&env.max_compression_n) {
            assert!(
                (low..=high).contains(&n),
                "{kind:?}: {n} N of compression at {x:.1} m, outside [{low}, {high}] N"
            );
        }
        // The torque of the top element: the top drive's, less the wall's friction torque on
        // the top node's half element (μ w R_ext per metre, about 0.1 kN·m here).
        let top_torque = m.mean_top_torque_nm;
        assert!(
            (env.max_torque_nm[0] / top_torque - 1.0).abs() < 0.03,
            "{kind:?}: {} N·m at the top element, {top_torque} N·m at the top drive",
            env.max_torque_nm[0]
        );
    }
}
