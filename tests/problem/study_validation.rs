//! The study sections of a problem file ([uncertain], [objective], [constraints], [optimizer],
//! [expect]): bad input is refused with the file, the dotted key and what is allowed.

use drillopt::problem::Problem;
use drillopt::problem::study::{
    EgoSettings, EgoTrustRegionSettings, GridSettings, Method, NelderMeadSettings,
    OptimizerSettings, ParticleSwarmSettings, TrustRegionSettings,
};
use std::path::Path;

fn base() -> String {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/problems/regression/tiny_string.toml"
    ))
    .unwrap();
    // Everything up to the study sections.
    text[..text.find("[objective]").unwrap()].to_string()
}

fn error(extra: &str) -> String {
    match Problem::from_toml(&(base() + extra), Path::new("study.toml")) {
        Ok(_) => panic!("accepted:\n{extra}"),
        Err(e) => e.to_string(),
    }
}

fn assert_names(msg: &str, parts: &[&str]) {
    for p in parts {
        assert!(msg.contains(p), "{msg:?} lacks {p:?}");
    }
}

#[test]
fn a_complete_study_is_read_in_si_units() {
    let p = Problem::from_toml(
        &(base()
            + r#"
[uncertain]
samples = 8
seed = 3
[[uncertain.parameter]]
key = "model.bit.limit_force"
law = "gamma"
mean = "250 kN"
cov = 0.1
[objective]
quantity = "rop"
statistic = "lower_cvar"
level = 0.8
[[objective.risk]]
metric = "impacts_per_s"
statistic = "cvar"
level = 0.9
weight = 0.01
[constraints]
omega = ["30 rpm", "150 rpm"]
v0 = ["2 m/h", "20 m/h"]
max_depth_of_cut = "3 mm"
[[constraints.chance]]
metric = "stick_slip_severity"
threshold = 2.0
max_probability = 0.1
[optimizer]
method = "nelder_mead"
max_evaluations = 20
"#),
        Path::new("study.toml"),
    )
    .unwrap();
    let s = &p.study;
    assert_eq!((s.samples, s.seed), (8, 3));
    assert_eq!(s.uncertain[0].law.mean(), 250e3);
    let c = s.constraints.as_ref().unwrap();
    assert!((c.set_point[1] - 20.0 / 3600.0).abs() < 1e-15);
    // 2π V0 − d Ω ≤ 0 with d = 3 mm.
    assert_eq!(c.linear[0].omega, -3e-3);
    assert_eq!(c.chance[0].max_probability, 0.1);
}

#[test]
fn misspelled_and_unknown_keys_are_refused() {
    assert_names(
        &error("[objective]\nquantitty = \"rop\"\n"),
        &["study.toml", "quantitty"],
    );
    assert_names(
        &error("[optimiser]\nmethod = \"grid\"\n"),
        &["study.toml", "optimiser"],
    );
}

#[test]
fn bad_values_name_the_key_and_what_is_allowed() {
    let cases: [(&str, &[&str]); 8] = [
        (
            "[uncertain]\nsamples = 4\n[[uncertain.parameter]]\nkey = \"model.bit.colour\"\nlaw = \"gamma\"\nmean = 1\ncov = 0.1\n",
            &["uncertain.parameter[0].key", "model.bit.limit_force"],
        ),
        (
            "[uncertain]\nsamples = 4\n[[uncertain.parameter]]\nkey = \"model.bit.rate\"\nlaw = \"weibull\"\nmean = 1\ncov = 0.1\n",
            &["uncertain.parameter[0].law", "gamma"],
        ),
        (
            "[uncertain]\nsamples = 4\n[[uncertain.parameter]]\nkey = \"model.bit.rate\"\nlaw = \"normal\"\nmean = \"180 s/m\"\nstd = \"100 s/m\"\n",
            &["uncertain.parameter[0].law", "inadmissible"],
        ),
        (
            "[uncertain]\nsamples = 4\n",
            &["uncertain.parameter", "at least one"],
        ),
        (
            "[objective]\n[[objective.risk]]\nmetric = \"vibes\"\nweight = 1.0\n",
            &["objective.risk[0].metric", "stick_slip_severity"],
        ),
        (
            "[objective]\n[[objective.risk]]\nmetric = \"impacts_per_s\"\nstatistic = \"cvar\"\nweight = 1.0\n",
            &["objective.risk[0].level", "required"],
        ),
        (
            "[constraints]\nomega = [\"30 rpm\"]\nv0 = [\"2 m/h\", \"20 m/h\"]\n",
            &["constraints.omega", "pair"],
        ),
        (
            "[constraints]\nomega = [\"30 rpm\", \"150 rpm\"]\nv0 = [\"2 m/h\", \"20 m/h\"]\n[[constraints.chance]]\nmetric = \"impacts_per_s\"\nthreshold = 1.0\nmax_probability = 1.5\n",
            &["constraints.chance[0].max_probability", "[0, 1)"],
        ),
    ];
    for (extra, parts) in cases {
        let msg = error(extra);
        assert_names(&msg, &["study.toml"]);
        assert_names(&msg, parts);
    }
}

#[test]
fn constraints_that_leave_no_feasible_point_are_refused() {
    // Depth of cut 0.1 mm/rev at ≤ 40 rpm allows V0 ≤ 0.24 m/h, below the 20 m/h lower bound.
    let p = Problem::from_toml(
        &(base()
            + "[constraints]\nomega = [\"30 rpm\", \"40 rpm\"]\nv0 = [\"20 m/h\", \"30 m/h\"]\nmax_depth_of_cut = \"0.1 mm\"\n"),
        Path::new("study.toml"),
    )
    .unwrap();
    let ev = drillopt::study::RobustEvaluator::new(&p, None).unwrap();
    let err = drillopt::solve::solve(&p, &ev, None)
        .unwrap_err()
        .to_string();
    assert_names(&err, &["study.toml", "constraints", "no feasible"]);
    assert_eq!(
        ev.counters
            .simulated
            .load(std::sync::atomic::Ordering::Relaxed),
        0,
        "nothing is simulated for an infeasible problem"
    );
}

fn optimizer_of(section: &str) -> OptimizerSettings {
    Problem::from_toml(&(base() + section), Path::new("study.toml"))
        .unwrap_or_else(|e| panic!("refused:\n{section}\n{e}"))
        .study
        .optimizer
}

/// Each method holds only the settings it reads; absent keys take the documented defaults.
#[test]
fn optimizer_settings_per_method_with_defaults() {
    assert_eq!(
        optimizer_of(""),
        OptimizerSettings::TrustRegion(TrustRegionSettings {
            max_evaluations: 30,
            start: None,
            initial_radius: 0.25,
            min_radius: 0.02,
            grid: [9, 9],
        })
    );
    assert_eq!(
        optimizer_of(
            "[optimizer]\nmethod = \"nelder_mead\"\nmax_evaluations = 20\nstart = [\"60 rpm\", \"18 m/h\"]\n"
        ),
        OptimizerSettings::NelderMead(NelderMeadSettings {
            max_evaluations: 20,
            start: Some([2.0 * std::f64::consts::PI, 0.005]),
            ..NelderMeadSettings::default()
        })
    );
    assert_eq!(
        optimizer_of("[optimizer]\nmethod = \"particle_swarm\"\nseed = 7\nmin_radius = 0.5\n"),
        OptimizerSettings::ParticleSwarm(ParticleSwarmSettings {
            max_evaluations: 30,
            min_radius: 0.5,
            seed: 7,
            grid: [9, 9],
        })
    );
    // `grid` is every method's key: it is also `drillopt map`'s default grid.
    let tr = optimizer_of("[optimizer]\ngrid = [5, 7]\n");
    assert_eq!(
        (tr.method(), tr.grid(), tr.budget()),
        (Method::TrustRegion, [5, 7], 30)
    );
    let grid = optimizer_of("[optimizer]\nmethod = \"grid\"\ngrid = [5, 7]\n");
    assert_eq!(grid, OptimizerSettings::Grid(GridSettings { grid: [5, 7] }));
    assert_eq!((grid.start(), grid.budget()), (None, 49));
}

/// A key the chosen method does not read is refused, with the key, the method and its keys.
#[test]
fn optimizer_keys_the_method_does_not_read_are_refused() {
    let cases: [(&str, &[&str]); 5] = [
        (
            "method = \"trust_region\"\nseed = 3\n",
            &[
                "optimizer.seed",
                "not used by method \"trust_region\"",
                "min_radius",
            ],
        ),
        (
            "method = \"nelder_mead\"\nseed = 3\n",
            &["optimizer.seed", "\"nelder_mead\""],
        ),
        (
            "method = \"particle_swarm\"\nstart = [\"60 rpm\", \"5 m/h\"]\n",
            &[
                "optimizer.start",
                "\"particle_swarm\"",
                "max_evaluations, min_radius, seed, grid",
            ],
        ),
        (
            "method = \"particle_swarm\"\ninitial_radius = 0.1\n",
            &["optimizer.initial_radius", "\"particle_swarm\""],
        ),
        (
            "method = \"grid\"\nmax_evaluations = 20\n",
            &["optimizer.max_evaluations", "\"grid\"", "(its keys: grid)"],
        ),
    ];
    for (section, parts) in cases {
        let msg = error(&format!("[optimizer]\n{section}"));
        assert_names(&msg, &["study.toml"]);
        assert_names(&msg, parts);
    }
    // The value checks are unchanged.
    assert_names(
        &error("[optimizer]\ninitial_radius = 0.1\nmin_radius = 0.2\n"),
        &[
            "optimizer.min_radius",
            "smaller than optimizer.initial_radius (0.1), got 0.2",
        ],
    );
    assert_names(
        &error("[optimizer]\nmax_evaluations = -4\n"),
        &["optimizer.max_evaluations", "[3, 100000], got -4"],
    );
    assert_names(
        &error("[optimizer]\nmethod = \"grid\"\ngrid = [1, 9]\n"),
        &["optimizer.grid", "each in [2, 200], got [1, 9]"],
    );
}

/// The builders start from the defaults and check every field as the problem file does.
#[test]
fn optimizer_settings_builders_check_ranges() {
    let tr = TrustRegionSettings::builder()
        .max_evaluations(12)
        .initial_radius(0.3)
        .build()
        .unwrap();
    assert_eq!(
        tr,
        TrustRegionSettings {
            max_evaluations: 12,
            initial_radius: 0.3,
            ..TrustRegionSettings::default()
        }
    );
    let e = TrustRegionSettings::builder()
        .min_radius(0.3)
        .build()
        .unwrap_err();
    assert_eq!(e.key, "min_radius");
    assert_eq!(
        e.to_string(),
        "optimizer.min_radius: must be smaller than optimizer.initial_radius (0.25), got 0.3"
    );
    assert_eq!(
        NelderMeadSettings::builder()
            .max_evaluations(2)
            .build()
            .unwrap_err()
            .key,
        "max_evaluations"
    );
    assert_eq!(
        NelderMeadSettings::builder()
            .start(Some([f64::NAN, 0.001]))
            .build()
            .unwrap_err()
            .key,
        "start"
    );
    assert_eq!(
        ParticleSwarmSettings::builder()
            .seed(4)
            .build()
            .unwrap()
            .seed,
        4
    );
    assert_eq!(
        ParticleSwarmSettings::builder()
            .min_radius(0.0)
            .build()
            .unwrap_err()
            .key,
        "min_radius"
    );
    assert_eq!(
        GridSettings::builder()
            .grid([1, 5])
            .build()
            .unwrap_err()
            .key,
        "grid"
    );
    assert_eq!(OptimizerSettings::default().method(), Method::TrustRegion);
}

/// `method = "ego"` and `"ego+trust_region"`: their keys with the documented defaults, every
/// value checked against its range, the file and the key named.
#[test]
fn ego_settings_defaults_and_refusals() {
    assert_eq!(
        optimizer_of("[optimizer]\nmethod = \"ego\"\n"),
        OptimizerSettings::Ego(EgoSettings {
            max_evaluations: 40,
            initial_design: 10,
            seed: 0,
            grid: [9, 9],
        })
    );
    let hybrid = optimizer_of(
        "[optimizer]\nmethod = \"ego+trust_region\"\nmax_evaluations = 30\nseed = 5\nego_share = 0.5\n",
    );
    assert_eq!(
        hybrid,
        OptimizerSettings::EgoTrustRegion(EgoTrustRegionSettings {
            max_evaluations: 30,
            seed: 5,
            ego_share: 0.5,
            ..EgoTrustRegionSettings::default()
        })
    );
    assert_eq!(
        (hybrid.method().name(), hybrid.budget(), hybrid.start()),
        ("ego+trust_region", 30, None)
    );
    let cases: [(&str, &[&str]); 6] = [
        (
            "method = \"ego\"\nstart = [\"60 rpm\", \"5 m/h\"]\n",
            &[
                "optimizer.start",
                "not used by method \"ego\"",
                "max_evaluations, initial_design, seed, grid",
            ],
        ),
        (
            "method = \"ego\"\nego_share = 0.5\n",
            &["optimizer.ego_share", "\"ego\""],
        ),
        (
            "method = \"trust_region\"\ninitial_design = 8\n",
            &["optimizer.initial_design", "\"trust_region\""],
        ),
        (
            "method = \"ego\"\ninitial_design = 2\n",
            &["optimizer.initial_design", "[3, 1000], got 2"],
        ),
        (
            "method = \"ego\"\nmax_evaluations = 10\n",
            &[
                "optimizer.initial_design",
                "below EGO's evaluations (10)",
                "got 10",
            ],
        ),
        (
            "method = \"ego+trust_region\"\nego_share = 1.0\n",
            &["optimizer.ego_share", "(0, 1), got 1"],
        ),
    ];
    for (section, parts) in cases {
        let msg = error(&format!("[optimizer]\n{section}"));
        assert_names(&msg, &["study.toml"]);
        assert_names(&msg, parts);
    }
    // EGO's share ⌊0.3 · 30⌋ = 9 is below the default initial design of 10.
    assert_names(
        &error(
            "[optimizer]\nmethod = \"ego+trust_region\"\nmax_evaluations = 30\nego_share = 0.3\n",
        ),
        &["optimizer.initial_design", "below EGO's evaluations (9)"],
    );
    assert_eq!(
        EgoTrustRegionSettings::builder()
            .min_radius(0.2)
            .build()
            .unwrap_err()
            .key,
        "min_radius"
    );
}

/// `[uncertain.sequential]` (issue 16 item 3): read with its defaults, and every key refused
/// outside its range naming the file, the key and what is allowed, all in one pass.
#[test]
fn sequential_sampling_keys_are_read_and_checked() {
    const PARAM: &str = "[[uncertain.parameter]]\nkey = \"model.bit.limit_force\"\nlaw = \"gamma\"\nmean = \"250 kN\"\ncov = 0.1\n";
    let read = |section: &str| {
        Problem::from_toml(
            &(base() + "[uncertain]\nsamples = 64\n" + section + PARAM),
            Path::new("study.toml"),
        )
    };
    let s = read("[uncertain.sequential]\nmin_samples = 8\nscore_half_width = 0.5\n")
        .unwrap()
        .study;
    let rule = s.sequential.unwrap();
    assert_eq!(
        (s.samples, rule.min_samples, rule.score_half_width),
        (64, 8, 0.5)
    );
    assert_eq!((rule.confidence, rule.resamples), (0.95, 2000), "defaults");
    let s = read(
        "[uncertain.sequential]\nmin_samples = 2\nscore_half_width = 1e-3\nconfidence = 0.9\nresamples = 500\n",
    )
    .unwrap()
    .study;
    assert_eq!(s.score_interval().confidence, 0.9);
    assert_eq!(s.sequential.unwrap().resamples, 500);
    // Without the section: the fixed count, the interval at the default level.
    let s = read("").unwrap().study;
    assert_eq!((s.sequential, s.score_interval().confidence), (None, 0.95));

    let refused = |section: &str| read(section).unwrap_err().to_string();
    let cases: [(&str, &[&str]); 8] = [
        (
            "[uncertain.sequential]\nmin_samples = 64\nscore_half_width = 0.5\n",
            &[
                "uncertain.sequential.min_samples",
                "[2, 63]",
                "uncertain.samples = 64",
                "got 64",
            ],
        ),
        (
            "[uncertain.sequential]\nmin_samples = 1\nscore_half_width = 0.5\n",
            &["uncertain.sequential.min_samples", "[2, 63]", "got 1"],
        ),
        (
            "[uncertain.sequential]\nmin_samples = 8\nscore_half_width = 0.0\n",
            &[
                "uncertain.sequential.score_half_width",
                "(0, 1e6]",
                "m/h",
                "got 0",
            ],
        ),
        (
            "[uncertain.sequential]\nmin_samples = 8\nscore_half_width = -1.0\n",
            &["uncertain.sequential.score_half_width", "got -1"],
        ),
        (
            "[uncertain.sequential]\nmin_samples = 8\nscore_half_width = 0.5\nconfidence = 1.0\n",
            &["uncertain.sequential.confidence", "[0.5, 0.999]", "got 1"],
        ),
        (
            "[uncertain.sequential]\nmin_samples = 8\nscore_half_width = 0.5\nresamples = 10\n",
            &["uncertain.sequential.resamples", "[200, 100000]", "got 10"],
        ),
        (
            "[uncertain.sequential]\nmin_samples = 8\nscore_half_width = 0.5\nmax_samples = 64\n",
            &["uncertain.sequential", "max_samples"],
        ),
        (
            "[uncertain.sequential]\nmin_samples = 8\n",
            &["uncertain.sequential.score_half_width", "missing"],
        ),
    ];
    for (section, parts) in cases {
        let msg = refused(section);
        assert_names(&msg, &["study.toml"]);
        assert_names(&msg, parts);
    }
    // Three bad keys, three lines.
    let msg = refused(
        "[uncertain.sequential]\nmin_samples = 0\nscore_half_width = 0.0\nconfidence = 0.2\n",
    );
    assert_eq!(msg.lines().count(), 3, "{msg}");
    // Too few samples to leave room for a stopping rule.
    let msg = Problem::from_toml(
        &(base()
            + "[uncertain]\nsamples = 2\n[uncertain.sequential]\nmin_samples = 2\nscore_half_width = 0.5\n"
            + PARAM),
        Path::new("study.toml"),
    )
    .unwrap_err()
    .to_string();
    assert_names(
        &msg,
        &[
            "study.toml",
            "uncertain.sequential.min_samples",
            "uncertain.samples = 2",
            "at least 3",
        ],
    );
}

/// `--samples` with sequential sampling sets the most samples a point may use: it must exceed
/// `min_samples`.
#[test]
fn the_samples_override_is_the_sequential_maximum() {
    let text = base()
        + "[uncertain]\nsamples = 16\n[uncertain.sequential]\nmin_samples = 8\nscore_half_width = 0.5\n\
           [[uncertain.parameter]]\nkey = \"model.bit.rate\"\nlaw = \"gamma\"\nmean = \"180 s/m\"\ncov = 0.1\n";
    let mut study = Problem::from_toml(&text, Path::new("study.toml"))
        .unwrap()
        .study;
    let why = study.override_samples(8).unwrap_err();
    assert!(
        why.contains("min_samples = 8") && why.contains("got 8"),
        "{why}"
    );
    study.override_samples(32).unwrap();
    assert_eq!(study.samples, 32);
}
