//! Issue 14 item 7: the regression set (`problems/regression/`) is decided by physics. Read from the
//! files themselves: at least three problems, each with an `[expect]` that declares the constraints
//! holding its optimum (`active`, validated against the expected ranges); one optimum strictly
//! inside the Ω bounds; one held by a physical limit (a chance constraint) with the V0 bound and the
//! depth-of-cut line not the ones that stop it; each expected range at least one cell of the map it
//! names wide; one held by a damage limit other than buckling (stress, fatigue, stick-slip or
//! impacts). The buckling-limited optima are checked against Dawson & Paslay's closed form, the
//! fatigue-limited one against Miner's rule for the rotating bending stress (one cycle per
//! revolution), and `solve` must land in its map's ranges on the buckling- and fatigue-limited
//! problems.

use drillopt::problem::Problem;
use drillopt::problem::study::{ActiveConstraint, Expect};
use std::f64::consts::PI;
use std::path::{Path, PathBuf};

const DIR: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/problems/regression");

fn set() -> Vec<(PathBuf, Problem, Expect)> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(DIR)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    files.sort();
    files
        .into_iter()
        .map(|f| {
            let p = Problem::load(&f).unwrap_or_else(|e| panic!("{e}"));
            let e = p.study.expect.clone().unwrap_or_else(|| {
                panic!("{}: every regression problem has [expect]", f.display())
            });
            (f, p, e)
        })
        .collect()
}

fn active(f: &Path, e: &Expect) -> Vec<ActiveConstraint> {
    e.active
        .clone()
        .unwrap_or_else(|| panic!("{}: [expect] must declare `active`", f.display()))
}

/// `NxM` of the first "--grid NxM" in the file's text (the map its `[expect]` comes from).
fn map_grid(f: &Path) -> [usize; 2] {
    let text = std::fs::read_to_string(f).unwrap();
    let at = text
        .find("--grid ")
        .unwrap_or_else(|| panic!("{}: the [expect] comment names its map", f.display()));
    let word: String = text[at + 7..]
        .chars()
        .take_while(|c| c.is_ascii_alphanumeric())
        .collect();
    let (a, b) = word.split_once('x').expect("NxM");
    [a.parse().unwrap(), b.parse().unwrap()]
}

#[test]
fn the_set_has_an_interior_omega_optimum_and_one_held_by_a_physical_limit() {
    let set = set();
    assert!(set.len() >= 3, "at least three problems, got {}", set.len());
    let mut interior = Vec::new();
    let mut physical = Vec::new();
    let mut damage = Vec::new();
    for (f, p, e) in &set {
        let k = p.study.constraints.as_ref().unwrap();
        let act = active(f, e);
        // Validation ties `active` to the ranges; check it here from the numbers as well.
        let inside = e.omega[0] > k.omega[0] && e.omega[1] < k.omega[1];
        assert_eq!(
            inside,
            !act.contains(&ActiveConstraint::OmegaMin)
                && !act.contains(&ActiveConstraint::OmegaMax),
            "{}",
            f.display()
        );
        if inside {
            interior.push(p.name.clone());
        }
        let chance = act.iter().any(|a| matches!(a, ActiveConstraint::Chance(_)));
        if chance
            && !act.contains(&ActiveConstraint::SetPointMax)
            && e.set_point[1] < k.set_point[1]
        {
            physical.push(p.name.clone());
        }
        if act.iter().any(
            |a| matches!(a, ActiveConstraint::Chance(m) if DAMAGE_METRICS.contains(&m.as_str())),
        ) {
            damage.push(p.name.clone());
        }
        // Each range is at least one cell of its map wide (the map is finer than the tolerance).
        let [n, m] = map_grid(f);
        let cell = [
            (k.omega[1] - k.omega[0]) / (n - 1) as f64,
            (k.set_point[1] - k.set_point[0]) / (m - 1) as f64,
        ];
        assert!(
            e.omega[1] - e.omega[0] >= cell[0],
            "{}: Ω range narrower than a map cell",
            f.display()
        );
        assert!(
            e.set_point[1] - e.set_point[0] >= cell[1],
            "{}: V0 range narrower than a map cell",
            f.display()
        );
    }
    assert!(
        !interior.is_empty(),
        "no optimum strictly inside the Ω bounds"
    );
    assert!(
        !physical.is_empty(),
        "no optimum held by a chance constraint below the V0 bound"
    );
    assert!(
        !damage.is_empty(),
        "no optimum held by a stress, fatigue, stick-slip or impact limit (one of {DAMAGE_METRICS:?})"
    );
}

/// The damage metrics of issue 14 item 7 (buckling aside): stress, fatigue, stick-slip, impacts.
const DAMAGE_METRICS: [&str; 7] = [
    "max_von_mises_pa",
    "von_mises_utilization",
    "fatigue_damage_per_h",
    "stick_slip_severity",
    "stick_fraction",
    "impacts_per_s",
    "peak_wall_force_n",
];

/// Dawson & Paslay's sinusoidal buckling load of a pipe lying in a horizontal hole,
/// F_sin = 2 √(E I w / r), w the buoyed weight per length, r the radial clearance (N).
fn f_sin(p: &Problem) -> f64 {
    let m = &p.model;
    let (ro, ri) = (m.pipe.outer_radius, m.pipe.inner_radius);
    let i = PI / 4.0 * (ro.powi(4) - ri.powi(4));
    let steel = m.pipe.density * PI * (ro * ro - ri * ri);
    let inside = m.fluid_density * PI * ri * ri;
    let outside = m.annulus_density * PI * ro * ro;
    let w = (steel + inside - outside) * m.gravity;
    2.0 * (m.pipe.youngs_modulus * i * w / (m.borehole_radius - ro)).sqrt()
}

#[test]
fn buckling_limited_optima_lie_below_the_closed_form_buckling_feed() {
    // The steady WOB at feed V0 is Γ(1 − e^(−α V0)); the peak compression is at least that, so an
    // optimum held by "no sinusoidal buckling" has WOB < F_sin at every V0 of its range.
    let mut limited = Vec::new();
    for (f, p, e) in set() {
        if !active(&f, &e).contains(&ActiveConstraint::Chance("buckling_utilization".into())) {
            continue;
        }
        let law = |name: &str| {
            p.model.bit.get(name).unwrap_or_else(|| {
                panic!("{}: the exponential bit law's {name} expected", f.display())
            })
        };
        let (gamma, alpha) = (law("limit_force"), law("rate"));
        let fs = f_sin(&p);
        let v_buckle = -(1.0 - fs / gamma).ln() / alpha;
        assert!(
            e.set_point[1] <= v_buckle,
            "{}: expected V0 up to {} m/h beyond the quasi-static buckling feed {} m/h (F_sin {} kN)",
            f.display(),
            e.set_point[1] * 3600.0,
            v_buckle * 3600.0,
            fs / 1e3
        );
        limited.push((fs, e.set_point, p.name.clone()));
    }
    assert!(limited.len() >= 2, "{limited:?}");
    // A lower buckling load stops the feed earlier: the ranges are ordered as the loads are.
    limited.sort_by(|a, b| a.0.total_cmp(&b.0));
    for w in limited.windows(2) {
        assert!(w[0].1[1] < w[1].1[0], "{w:?}");
    }
}

/// Run the drillopt binary with `args`; it must succeed (its stderr in the failure message).
fn drillopt(args: &[&str]) {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_drillopt"))
        .args(args)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "drillopt {}: {}",
        args.join(" "),
        String::from_utf8_lossy(&out.stderr)
    );
}

/// `drillopt solve` on `file` lands in the ranges its map gave, with every chance constraint
/// satisfied (`drillopt batch problems` in CI checks every problem of the set the same way).
fn solve_lands_in_the_expected_ranges(file: &Path) -> serde_json::Value {
    let e = Problem::load(file).unwrap().study.expect.unwrap();
    let dir = tempfile::tempdir().unwrap();
    drillopt(&[
        "solve",
        file.to_str().unwrap(),
        "--quiet",
        "--out",
        dir.path().to_str().unwrap(),
    ]);
    let text = std::fs::read_to_string(dir.path().join("solution.json")).unwrap();
    let s: serde_json::Value = serde_json::from_str(&text).unwrap();
    let omega = s["optimum"]["omega_rad_s"].as_f64().unwrap();
    let v0 = s["optimum"]["v0_m_s"].as_f64().unwrap();
    let score = s["objective"]["score"].as_f64().unwrap();
    assert!(
        (e.omega[0]..=e.omega[1]).contains(&omega),
        "{}: Ω {} rpm",
        file.display(),
        omega * 30.0 / PI
    );
    assert!(
        (e.set_point[0]..=e.set_point[1]).contains(&v0),
        "{}: V0 {} m/h",
        file.display(),
        v0 * 3600.0
    );
    let [lo, hi] = e.objective.unwrap();
    assert!(
        (lo..=hi).contains(&score),
        "{}: score {score}",
        file.display()
    );
    // The limits hold the optimum: feasible.
    for c in s["constraints"]["chance"].as_array().unwrap() {
        assert_eq!(c["satisfied"], true, "{}: {c}", file.display());
        let metric = c["metric"].as_str().unwrap();
        let checked = &s["numerical_check"]["metrics"][metric];
        assert_eq!(checked["used"], true, "{}: {metric}", file.display());
    }
    // The optimum rests on numbers the basis check found converged (the unused stick-slip
    // statistics of the slim strings are not: they are reported, not used).
    let check = &s["numerical_check"];
    assert_eq!(check["converged"], true, "{}: {check}", file.display());
    // What `verify` runs, not the basis alone: every refinement and the perturbation, with the
    // value of every metric under each.
    let runs: Vec<&str> = check["runs"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| r.as_str().unwrap())
        .collect();
    for r in ["basis", "mesh", "tolerance", "window", "perturbed"] {
        assert!(runs.contains(&r), "{}: {runs:?}", file.display());
    }
    for (key, m) in check["metrics"].as_object().unwrap() {
        let refined = m["refined"].as_object().unwrap();
        assert_eq!(refined.len(), runs.len() - 1, "{}: {key}", file.display());
        assert!(m["perturbed"].is_number(), "{}: {key}", file.display());
    }
    for (key, m) in check["metrics"].as_object().unwrap() {
        if m["used"] == true {
            assert_eq!(m["converged"], true, "{}: {key}", file.display());
        }
    }
    s
}

#[test]
fn solve_reaches_the_maps_optimum_of_the_buckling_limited_problem() {
    solve_lands_in_the_expected_ranges(&Path::new(DIR).join("slim_pipe_buckling.toml"));
}

#[test]
fn solve_reaches_the_maps_optimum_of_the_fatigue_limited_problem() {
    let s = solve_lands_in_the_expected_ranges(&Path::new(DIR).join("slim_pipe_fatigue.toml"));
    let line = s["constraints"]["linear"].as_array().unwrap();
    assert!(
        line.iter()
            .any(|c| c["label"] == "max_depth_of_cut" && c["active"] == true),
        "{line:?}"
    );
}

/// DNV-RP-C203 (2016) Table 2-1, S-N curves in air for N ≤ 10⁷: (name, m₁, log₁₀ ā₁), Δσ in MPa.
/// Typed here from the standard, independently of `fatigue::SnCurve`.
const DNV_AIR_FIRST_BRANCH: [(&str, f64, f64); 3] = [
    ("DNV-B1", 4.0, 15.117),
    ("DNV-C", 3.0, 12.592),
    ("DNV-D", 3.0, 12.164),
];

/// One `drillopt simulate` at Ω and the set-point flag (`--v0=…m/h`, or `--wob=…kN` under a hook
/// load); the worst section of `stress_envelope.csv` as (fatigue damage per hour, its largest
/// bending moment in N·m).
fn worst_section(file: &Path, omega_rpm: f64, set_point: &str) -> (f64, f64) {
    let dir = tempfile::tempdir().unwrap();
    drillopt(&[
        "simulate",
        file.to_str().unwrap(),
        "--quiet",
        &format!("--omega={omega_rpm}rpm"),
        set_point,
        "--out",
        dir.path().to_str().unwrap(),
    ]);
    let text = std::fs::read_to_string(dir.path().join("stress_envelope.csv")).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let (cd, cm) = (col("fatigue_damage_per_h"), col("max_bending_moment_N_m"));
    lines
        .map(|l| {
            let v: Vec<f64> = l.split(',').map(|x| x.parse().unwrap()).collect();
            (v[cd], v[cm])
        })
        .max_by(|a, b| a.0.total_cmp(&b.0))
        .unwrap()
}

/// The fatigue-limited optimum is where the rotating bending stress of the worst section uses up
/// the allowed damage rate: a material point of the spinning pipe sees one cycle of range
/// Δσ = 2·SCF·M·c/I per revolution, so D = (Ω/2π · 3600 s/h) · Δσ^m / ā (Miner, constant
/// amplitude) should match the rainflow count of the simulation, and the threshold should be
/// crossed inside the expected V0 range along the depth-of-cut line.
#[test]
fn fatigue_limited_optimum_is_the_rotating_bending_damage_reaching_its_limit() {
    let mut checked = 0;
    for (f, p, e) in set() {
        if !active(&f, &e).contains(&ActiveConstraint::Chance("fatigue_damage_per_h".into())) {
            continue;
        }
        let text = std::fs::read_to_string(&f).unwrap();
        let doc: toml::Table = text.parse().unwrap();
        let fatigue = doc["model"]["pipe"]["fatigue"].as_table().unwrap();
        let curve = fatigue["sn_curve"].as_str().unwrap();
        let scf = fatigue["stress_concentration"].as_integer().unwrap() as f64;
        let (_, m, log_a) = DNV_AIR_FIRST_BRANCH
            .iter()
            .find(|c| c.0 == curve)
            .unwrap_or_else(|| panic!("{}: curve {curve} not in the test's table", f.display()));
        let k = p.study.constraints.as_ref().unwrap();
        let threshold = k
            .chance
            .iter()
            .find(|c| c.metric == "fatigue_damage_per_h")
            .unwrap()
            .threshold;
        let (ro, ri) = (p.model.pipe.outer_radius, p.model.pipe.inner_radius);
        let c_over_i = ro / (PI / 4.0 * (ro.powi(4) - ri.powi(4)));
        // The line the optimum lies on, where the damage crosses its limit inside the expected
        // ranges: the depth-of-cut line Ω = 2π V0 / δ (−δ Ω + 2π V0 ≤ 0), walked through the
        // expected V0 range; or, without one, the autodriller's WOB-limit line (the bit cuts the
        // depth the limit allows, ROP ∝ Ω), walked through the expected Ω range with the
        // set-point at the top of the expected V0 range, above what the limit lets the bit drill
        // there.
        // Under a hook load: the expected Ω range at the middle of the expected WOB range, across
        // the fatigue limit, whose Ω falls as the WOB bends the pipe more.
        let v0 = |m_per_h: f64| format!("--v0={m_per_h}m/h");
        let points: Vec<(f64, String)> = match k
            .linear
            .iter()
            .find(|c| c.label == "max_depth_of_cut")
        {
            Some(line) => {
                let depth = -line.omega * 2.0 * PI / line.set_point;
                e.set_point
                    .iter()
                    .map(|&v| (2.0 * PI * v / depth * 30.0 / PI * 1.0001, v0(v * 3600.0)))
                    .collect()
            }
            None if p.model.top == drillopt::model::TopDrive::HookLoad => {
                let wob_kn = 0.5 * (e.set_point[0] + e.set_point[1]) / 1e3;
                e.omega
                    .iter()
                    .map(|&w| (w * 30.0 / PI, format!("--wob={wob_kn}kN")))
                    .collect()
            }
            None => {
                assert!(
                    matches!(p.model.top, drillopt::model::TopDrive::Autodriller(_)),
                    "{}: a depth-of-cut line, an autodriller's WOB limit or a hook load expected",
                    f.display()
                );
                e.omega
                    .iter()
                    .map(|&w| (w * 30.0 / PI, v0(e.set_point[1] * 3600.0)))
                    .collect()
            }
        };
        let mut damage = Vec::new();
        for (rpm, set_point) in points {
            let omega = rpm * PI / 30.0;
            let (d, moment) = worst_section(&f, rpm, &set_point);
            let range_mpa = 2.0 * scf * moment * c_over_i / 1e6;
            let per_hour = omega / (2.0 * PI) * 3600.0;
            let closed = per_hour * range_mpa.powf(*m) / 10f64.powf(*log_a);
            assert!(
                (d / closed - 1.0).abs() < 0.15,
                "{}: at {rpm:.1} rpm, {set_point} the simulated damage {d:.4}/h vs Miner's \
                 {closed:.4}/h (M = {moment:.0} N·m, Δσ = {range_mpa:.0} MPa)",
                f.display()
            );
            damage.push(d);
        }
        assert!(
            damage[0] < threshold && threshold < damage[1],
            "{}: the limit {threshold}/h is not crossed inside the expected range: {damage:?}",
            f.display()
        );
        checked += 1;
    }
    assert!(
        checked >= 2,
        "the fatigue-limited problems of the set: {checked}"
    );
}

/// `[expect] active` is refused, naming the file and the key, when it names no constraint of the
/// problem or disagrees with the expected ranges.
#[test]
fn expect_active_is_validated_against_the_constraints_and_ranges() {
    let tiny = include_str!("../../problems/regression/tiny_string.toml");
    let line = "active = [\"v0.max\", \"max_depth_of_cut\"]";
    assert_eq!(tiny.matches(line).count(), 1);
    let load = |active: &str| {
        Problem::from_toml(&tiny.replace(line, active), Path::new("cases/active.toml"))
            .map(|p| p.study.expect.unwrap().active)
            .map_err(|e| e.to_string())
    };
    assert_eq!(
        load(line).unwrap(),
        Some(vec![
            ActiveConstraint::SetPointMax,
            ActiveConstraint::Linear("max_depth_of_cut")
        ])
    );
    let refusals = [
        // no such constraint in this problem (it has no chance constraint)
        (
            "active = [\"v0.max\", \"chance.stick_slip_severity\"]",
            "expect.active[1]",
            "not a constraint of this problem",
        ),
        (
            "active = [\"v0.max\", \"v0.max\"]",
            "expect.active[1]",
            "twice",
        ),
        // the V0 range [17, 20] m/h reaches the bound: it must be declared
        ("active = [\"max_depth_of_cut\"]", "expect.active", "v0.max"),
        // the Ω range [105, 135] rpm is inside the bounds: the lower bound cannot hold the optimum
        (
            "active = [\"v0.max\", \"omega.min\"]",
            "expect.active",
            "does not reach",
        ),
    ];
    for (active, key, why) in refusals {
        let e = load(active).unwrap_err();
        assert!(
            e.contains("cases/active.toml") && e.contains(&format!("`{key}`")) && e.contains(why),
            "{active}: {e}"
        );
    }
}
