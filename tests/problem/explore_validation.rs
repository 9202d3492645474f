//! `[optimizer.explore]` (multi-fidelity solve, issue 16 item 2): every key is read in SI,
//! every bad value is refused naming the file and the key and saying what is allowed, and an
//! explore fidelity that is not cheaper than the full one is refused.

use drillopt::model::{BasisSpec, FamilySize};
use drillopt::problem::Problem;
use std::path::Path;

/// `tiny_string.toml` without `[expect]`: 1.5 s window, 0.5 s settling, basis 4 / 2 / 2,
/// deterministic.
fn base() -> String {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/problems/regression/tiny_string.toml"
    ))
    .unwrap();
    text[..text.find("[expect]").unwrap()].to_string()
}

/// The base with four Monte Carlo samples of Γ_BR.
fn uncertain(extra: &str) -> String {
    r#"
[uncertain]
samples = 4
seed = 1
[[uncertain.parameter]]
key = "model.bit.limit_force"
law = "gamma"
mean = "250 kN"
cov = 0.1
"#
    .to_string()
        + extra
}

fn load(extra: &str) -> Result<Problem, String> {
    Problem::from_toml(&(base() + extra), Path::new("explore.toml")).map_err(|e| e.to_string())
}

fn error(extra: &str) -> String {
    match load(extra) {
        Ok(_) => panic!("accepted:\n{extra}"),
        Err(e) => e,
    }
}

fn assert_names(msg: &str, parts: &[&str]) {
    for p in parts {
        assert!(msg.contains(p), "{msg:?} lacks {p:?}");
    }
}

#[test]
fn an_explore_section_is_read_in_si_and_applied_to_the_full_problem() {
    let p = load(&uncertain(
        r#"
[optimizer.explore]
duration = "800 ms"
settling_time = "0.3 s"
samples = 2
[optimizer.explore.basis]
bending = 2
torsional = "300 Hz"
axial = 1
static_corrections = false
"#,
    ))
    .unwrap();
    let e = p.study.explore.clone().expect("the section");
    assert_eq!(e.duration, Some(0.8));
    assert_eq!(e.settling_time, Some(0.3));
    assert_eq!(e.samples, Some(2));
    assert_eq!(e.confirm, 3, "the default");
    assert_eq!(e.max_confirm, 6, "the default: two rounds of confirm");
    assert_eq!(e.separation, 0.05, "the default");
    let cheap = e.apply(&p);
    assert_eq!(cheap.simulation.duration, 0.8);
    assert_eq!(cheap.simulation.settling_time, 0.3);
    assert_eq!(cheap.study.samples, 2);
    assert_eq!(
        cheap.mesh.basis,
        BasisSpec::PerFamily {
            bending: FamilySize::Count(2),
            torsional: FamilySize::Cutoff { hz: 300.0, min: 1 },
            axial: FamilySize::Count(1),
            static_corrections: false,
            steady_shapes: false,
        }
    );
    assert!(cheap.study.explore.is_none());
    // Everything else is the full problem's.
    assert_eq!(cheap.simulation.time_step, p.simulation.time_step);
    assert_eq!(cheap.study.optimizer, p.study.optimizer);
    assert_eq!(cheap.model, p.model);
    // Only the window given: the settling time is the full one's.
    let p = load("[optimizer.explore]\nduration = \"1 s\"\nconfirm = 5\nseparation = 0\n").unwrap();
    let e = p.study.explore.clone().unwrap();
    assert_eq!(e.confirm, 5);
    assert_eq!((e.max_confirm, e.separation), (10, 0.0));
    // The default max_confirm stays in range; a given one is kept.
    assert_eq!(e.apply(&p).simulation.settling_time, 0.5);
    let read = |extra: &str| load(extra).unwrap().study.explore.unwrap();
    assert_eq!(
        read("[optimizer.explore]\nduration = \"1 s\"\nconfirm = 40\n").max_confirm,
        50
    );
    let given = read(
        "[optimizer.explore]\nduration = \"1 s\"\nconfirm = 2\nmax_confirm = 9\nseparation = 0.2\n",
    );
    assert_eq!(
        (given.confirm, given.max_confirm, given.separation),
        (2, 9, 0.2)
    );
    // Without the section: one fidelity.
    assert!(load("").unwrap().study.explore.is_none());
}

#[test]
fn an_explore_window_must_be_shorter_with_its_settling_inside() {
    let e = error("[optimizer.explore]\nduration = \"2 s\"\n");
    assert_names(
        &e,
        &[
            "explore.toml",
            "optimizer.explore.duration",
            "shorter than simulation.duration (1.5 s)",
            "got 2 s",
        ],
    );
    let e = error("[optimizer.explore]\nduration = \"1.5 s\"\n");
    assert_names(&e, &["optimizer.explore.duration", "shorter than"]);
    // The full settling (0.5 s) would take more than half of a 0.9 s window.
    let e = error("[optimizer.explore]\nduration = \"0.9 s\"\n");
    assert_names(
        &e,
        &[
            "optimizer.explore.duration",
            "at least twice simulation.settling_time (0.5 s)",
            "optimizer.explore.settling_time",
        ],
    );
    let e = error("[optimizer.explore]\nduration = \"0.8 s\"\nsettling_time = \"0.5 s\"\n");
    assert_names(
        &e,
        &["optimizer.explore.settling_time", "[0, 0.4 s]", "got 0.5 s"],
    );
    // Exactly half is allowed.
    load("[optimizer.explore]\nduration = \"1 s\"\n").unwrap();
    let e = error("[optimizer.explore]\nduration = \"-1 s\"\n");
    assert_names(
        &e,
        &[
            "optimizer.explore.duration",
            "in [1e-6, 86400] s",
            "the range of simulation.duration, got -1 s",
        ],
    );
    let e = error("[optimizer.explore]\nduration = \"1 kN\"\n");
    assert_names(&e, &["optimizer.explore.duration", "kN"]);
    // Shorter than one nominal step (10 ms).
    let e = error("[optimizer.explore]\nduration = \"5 ms\"\nsettling_time = 0.0\n");
    assert_names(
        &e,
        &[
            "optimizer.explore.duration",
            "simulation.time_step (0.01 s)",
        ],
    );
}

#[test]
fn explore_samples_must_be_fewer_than_the_full_count() {
    let e = error(&uncertain("[optimizer.explore]\nsamples = 4\n"));
    assert_names(
        &e,
        &[
            "explore.toml",
            "optimizer.explore.samples",
            "[1, 3]",
            "fewer than uncertain.samples = 4",
            "got 4",
        ],
    );
    let e = error(&uncertain("[optimizer.explore]\nsamples = 0\n"));
    assert_names(&e, &["optimizer.explore.samples", "[1, 3]", "got 0"]);
    let e = error("[optimizer.explore]\nsamples = 1\n");
    assert_names(&e, &["optimizer.explore.samples", "deterministic"]);
    // With sequential sampling an explore point starts with min_samples too.
    let seq = uncertain("[uncertain.sequential]\nmin_samples = 2\nscore_half_width = 1.0\n");
    let seq = seq.replace("samples = 4", "samples = 8");
    let e = error(&(seq.clone() + "[optimizer.explore]\nsamples = 2\n"));
    assert_names(
        &e,
        &[
            "optimizer.explore.samples",
            "[3, 7]",
            "uncertain.sequential.min_samples = 2",
        ],
    );
    assert!(load(&(seq + "[optimizer.explore]\nsamples = 4\n")).is_ok());
}

#[test]
fn the_samples_override_must_stay_above_the_explore_samples() {
    let mut p = load(&uncertain("[optimizer.explore]\nsamples = 3\n")).unwrap();
    let why = p.study.override_samples(3).unwrap_err();
    assert_names(&why, &["optimizer.explore.samples = 3", "got 3"]);
    p.study.override_samples(16).unwrap();
    assert_eq!(p.study.samples, 16);
}

#[test]
fn confirm_is_checked_against_its_range() {
    for bad in ["0", "51", "-2"] {
        let e = error(&format!(
            "[optimizer.explore]\nduration = \"1 s\"\nconfirm = {bad}\n"
        ));
        assert_names(
            &e,
            &[
                "explore.toml",
                "optimizer.explore.confirm",
                "[1, 50]",
                &format!("got {bad}"),
            ],
        );
    }
}

#[test]
fn max_confirm_and_separation_are_checked_against_their_ranges() {
    for (bad, range) in [("2", "[3, 50]"), ("51", "[3, 50]"), ("-1", "[3, 50]")] {
        let e = error(&format!(
            "[optimizer.explore]\nduration = \"1 s\"\nconfirm = 3\nmax_confirm = {bad}\n"
        ));
        assert_names(
            &e,
            &[
                "explore.toml",
                "optimizer.explore.max_confirm",
                range,
                "at least confirm = 3",
                &format!("got {bad}"),
            ],
        );
    }
    for bad in ["-0.1", "0.6", "nan", "inf"] {
        let e = error(&format!(
            "[optimizer.explore]\nduration = \"1 s\"\nseparation = {bad}\n"
        ));
        assert_names(
            &e,
            &[
                "explore.toml",
                "optimizer.explore.separation",
                "[0, 0.5]",
                "fraction of the box",
            ],
        );
    }
}

#[test]
fn a_margin_tightens_the_chance_thresholds_at_the_explore_fidelity_only() {
    let chance = r#"
[[constraints.chance]]
metric = "max_von_mises_pa"
threshold = "200 MPa"
max_probability = 0.1
[[constraints.chance]]
metric = "impacts_per_s"
threshold = 0
max_probability = 0.5
"#;
    let p = load(&format!(
        "{chance}[optimizer.explore]\nduration = \"1 s\"\nmargin = 0.1\n"
    ))
    .unwrap();
    let e = p.study.explore.clone().unwrap();
    assert_eq!(e.margin, 0.1);
    let thresholds = |p: &Problem| -> Vec<f64> {
        let c = p.study.constraints.as_ref().unwrap();
        c.chance.iter().map(|c| c.threshold).collect()
    };
    // 200 MPa − 10 % = 180 MPa at the explore fidelity; 0 stays 0; the full problem unchanged.
    let explore = thresholds(&e.apply(&p));
    assert!((explore[0] - 180e6).abs() < 1e-6, "{explore:?}");
    assert_eq!(explore[1], 0.0);
    assert_eq!(thresholds(&p), [200e6, 0.0]);
    // The default: the thresholds as written.
    let p = load(&format!(
        "{chance}[optimizer.explore]\nduration = \"1 s\"\n"
    ))
    .unwrap();
    let e = p.study.explore.clone().unwrap();
    assert_eq!(e.margin, 0.0);
    assert_eq!(thresholds(&e.apply(&p)), [200e6, 0.0]);
    // Out of range, or with nothing to tighten: refused, naming the key.
    for bad in ["-0.1", "0.6", "nan"] {
        let msg = error(&format!(
            "{chance}[optimizer.explore]\nduration = \"1 s\"\nmargin = {bad}\n"
        ));
        assert_names(
            &msg,
            &[
                "explore.toml",
                "optimizer.explore.margin",
                "[0, 0.5]",
                "tightened",
            ],
        );
    }
    let msg = error("[optimizer.explore]\nduration = \"1 s\"\nmargin = 0.1\n");
    assert_names(
        &msg,
        &[
            "optimizer.explore.margin",
            "no [[constraints.chance]]",
            "got 0.1",
        ],
    );
}

#[test]
fn refine_is_a_trust_region_budget_in_range() {
    let p = load("[optimizer.explore]\nduration = \"1 s\"\nrefine = 6\n").unwrap();
    assert_eq!(p.study.explore.unwrap().refine, 6);
    assert_eq!(
        load("[optimizer.explore]\nduration = \"1 s\"\n")
            .unwrap()
            .study
            .explore
            .unwrap()
            .refine,
        0,
        "no refinement by default"
    );
    for bad in ["1001", "-1"] {
        let e = error(&format!(
            "[optimizer.explore]\nduration = \"1 s\"\nrefine = {bad}\n"
        ));
        assert_names(
            &e,
            &[
                "explore.toml",
                "optimizer.explore.refine",
                "[0, 1000]",
                &format!("got {bad}"),
            ],
        );
    }
    // A method without a trust region has no radii to refine with.
    let grid = base()
        .replace("method = \"trust_region\"", "method = \"grid\"")
        .lines()
        .filter(|l| !l.starts_with("start = ") && !l.starts_with("max_evaluations"))
        .map(|l| format!("{l}\n"))
        .collect::<String>();
    let text = grid.clone() + "[optimizer.explore]\nduration = \"1 s\"\nrefine = 4\n";
    let e = Problem::from_toml(&text, Path::new("explore.toml"))
        .unwrap_err()
        .to_string();
    assert_names(
        &e,
        &[
            "optimizer.explore.refine",
            "\"trust_region\" or \"ego+trust_region\"",
            "not \"grid\"",
        ],
    );
    assert!(
        Problem::from_toml(
            &(grid + "[optimizer.explore]\nduration = \"1 s\"\nrefine = 0\n"),
            Path::new("explore.toml")
        )
        .is_ok()
    );
}

#[test]
fn an_explore_basis_must_be_smaller_than_the_full_one() {
    let basis = |b: &str| error(&format!("[optimizer.explore.basis]\n{b}\n"));
    let e = basis("bending = 6\ntorsional = 2\naxial = 2");
    assert_names(
        &e,
        &[
            "explore.toml",
            "optimizer.explore.basis.bending",
            "not keep more bending modes than the full basis",
            "got 6",
        ],
    );
    let e = basis("bending = 4\ntorsional = 2\naxial = 2");
    assert_names(&e, &["optimizer.explore.basis", "is the full basis"]);
    let e = basis("bending = 2\ntorsional = \"60 kN\"\naxial = 2");
    assert_names(
        &e,
        &["optimizer.explore.basis.torsional", "cutoff frequency"],
    );
    let e = basis("bending = 13\ntorsional = 1\naxial = 1");
    assert_names(&e, &["optimizer.explore.basis.bending", "[1, 12]"]);
    let e = basis("bending = 2\ntorsional = 1");
    assert_names(&e, &["optimizer.explore.basis", "axial"]);
    // The full basis without static corrections: the explore basis may not add them.
    let text = base().replace("axial = 2\n", "axial = 2\nstatic_corrections = false\n")
        + "[optimizer.explore.basis]\nbending = 2\ntorsional = 1\naxial = 1\n";
    let e = Problem::from_toml(&text, Path::new("explore.toml"))
        .unwrap_err()
        .to_string();
    assert_names(&e, &["optimizer.explore.basis.static_corrections", "false"]);
}

#[test]
fn an_explore_section_that_saves_nothing_or_has_unknown_keys_is_refused() {
    let e = error("[optimizer.explore]\nconfirm = 2\n");
    assert_names(
        &e,
        &[
            "explore.toml",
            "optimizer.explore",
            "at least one of duration",
        ],
    );
    let e = error("[optimizer.explore]\nsettling_time = \"0.2 s\"\n");
    assert_names(&e, &["optimizer.explore", "cheaper"]);
    let e = error("[optimizer.explore]\nduration = \"1 s\"\nwindow = \"1 s\"\n");
    assert_names(&e, &["explore.toml", "window"]);
}

#[test]
fn every_refusal_of_the_section_is_reported_in_one_pass() {
    let e = error(&uncertain(
        "[optimizer.explore]\nduration = \"3 s\"\nsamples = 9\nconfirm = 0\n",
    ));
    assert_names(
        &e,
        &[
            "optimizer.explore.duration",
            "optimizer.explore.samples",
            "optimizer.explore.confirm",
        ],
    );
}
