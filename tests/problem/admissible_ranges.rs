//! Issue 34: inputs inside the old admissible ranges whose consequences validation did not see.
//! Each reproducer of the issue is refused at load (or before any work), naming the file or the
//! flag, the key and the admissible range; none panics, none exits 0 with an absurd number.

use drillopt::problem::{Problem, ProblemError};
use std::path::Path;
use std::process::{Command, Output};

const TINY: &str = include_str!("../../problems/regression/tiny_string.toml");
const FILE: &str = "p34.toml";

/// `TINY` with `old` (which must occur once) replaced by `new`.
fn edit(old: &str, new: &str) -> String {
    assert_eq!(TINY.matches(old).count(), 1, "`{old}` must occur once");
    TINY.replace(old, new)
}

/// `TINY` with a line added after the header `[table]`.
fn add(table: &str, line: &str) -> String {
    edit(&format!("[{table}]\n"), &format!("[{table}]\n{line}\n"))
}

/// The one or more refusals of `text`, checked to name the file and the key `key`, and to say
/// each of `words`.
fn refused(text: &str, key: &str, words: &[&str]) -> String {
    let err = Problem::from_toml(text, Path::new(FILE)).expect_err("must be refused");
    let msg = err.to_string();
    assert!(matches!(err, ProblemError::Invalid { .. }), "{msg}");
    let e = err
        .key_errors()
        .iter()
        .find(|e| e.key == key)
        .unwrap_or_else(|| panic!("no refusal of `{key}`: {msg}"))
        .clone();
    assert!(
        msg.contains(&format!("{FILE}: key `{key}`: ")),
        "file and key not named: {msg}"
    );
    for w in words {
        assert!(e.message.contains(w), "`{key}` lacks {w:?}: {}", e.message);
    }
    e.message
}

/// A gamma law on the bit's limit force (2 samples) with coefficient of variation `cov`.
fn gamma_cov(cov: &str) -> String {
    format!(
        "{TINY}\n[uncertain]\nsamples = 2\n[[uncertain.parameter]]\nkey = \"model.bit.limit_force\"\nlaw = \"gamma\"\nmean = \"250 kN\"\ncov = {cov}\n"
    )
}

fn drillopt(args: &[&str], dir: &Path, text: &str) -> Output {
    let file = dir.join(FILE);
    std::fs::write(&file, text).unwrap();
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_drillopt"));
    cmd.arg(args[0]).arg(&file).args(&args[1..]);
    if args[0] != "simulate" {
        cmd.arg("--quiet");
    }
    cmd.arg("--out").arg(dir.join("out")).output().unwrap()
}

/// Exit status 1 (not 101, not 0), and stderr saying each of `words`.
fn refused_by_binary(out: &Output, words: &[&str]) -> String {
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    for w in words {
        assert!(stderr.contains(w), "stderr lacks {w:?}: {stderr}");
    }
    stderr
}

#[test]
fn a_gamma_law_with_a_vanishing_cov_is_refused_at_load_not_in_the_sampler() {
    // 1e-163 panicked in the sampler ("ScaleTooSmall"); 1e-160 was refused at run time only.
    for cov in ["1e-163", "1e-160", "1e-7", "0.0"] {
        refused(
            &gamma_cov(cov),
            "uncertain.parameter[0].cov",
            &["[1e-6, 1]", "deterministic", "without a law"],
        );
    }
    refused(
        &gamma_cov("3.0"),
        "uncertain.parameter[0].cov",
        &["[1e-6, 1]"],
    );
    Problem::from_toml(&gamma_cov("1e-6"), Path::new(FILE)).expect("cov = 1e-6 is admissible");
    // Through the commands that panicked: exit status 1, the file and the key named.
    let dir = tempfile::tempdir().unwrap();
    for cmd in [
        &["compare", "--point", "60rpm,5m/h"][..],
        &["solve"][..],
        &["map"][..],
    ] {
        let out = drillopt(cmd, dir.path(), &gamma_cov("1e-163"));
        refused_by_binary(&out, &[FILE, "uncertain.parameter[0].cov", "[1e-6, 1]"]);
    }
}

#[test]
fn the_spread_of_normal_and_uniform_laws_has_a_lower_end() {
    let law = |body: &str| {
        format!(
            "{TINY}\n[uncertain]\nsamples = 2\n[[uncertain.parameter]]\nkey = \"model.bit.limit_force\"\n{body}\n"
        )
    };
    refused(
        &law("law = \"normal\"\nmean = \"250 kN\"\nstd = \"1e-300 N\""),
        "uncertain.parameter[0].std",
        &["[1e-6, 1]"],
    );
    refused(
        &law("law = \"uniform\"\nlow = \"250 kN\"\nhigh = \"250.0000000001 kN\""),
        "uncertain.parameter[0].high",
        &["1e-6"],
    );
}

/// Every value a study draws is checked at load: a law whose bulk (mean ± 4σ) is admissible but
/// whose tail is not is refused for some seed, naming the sample; and for every seed that loads,
/// the run's own draws are admissible (the evaluator would otherwise refuse them without the
/// file's name).
#[test]
fn every_draw_is_checked_where_the_law_is_loaded() {
    let mut refusals = 0;
    for seed in 0..40 {
        // model.pipe.density is admissible in [1000, 25000] kg/m³: mean + 4σ = 25000.
        let text = format!(
            "{TINY}\n[uncertain]\nsamples = 10000\nseed = {seed}\n[[uncertain.parameter]]\nkey = \"model.pipe.density\"\nlaw = \"normal\"\nmean = \"21000 kg/m^3\"\nstd = \"1000 kg/m^3\"\n"
        );
        match Problem::from_toml(&text, Path::new(FILE)) {
            Ok(p) => {
                let laws: Vec<_> = p.study.uncertain.iter().map(|u| u.law).collect();
                let set = drillopt::stats::SampleSet::draw(&laws, p.study.samples, p.study.seed);
                for s in &set.samples {
                    let key = &p.study.uncertain[0].key;
                    assert!(key.admissible(&p.model, s.values[0]).is_ok(), "seed {seed}");
                }
            }
            Err(e) => {
                refusals += 1;
                let msg = e.to_string();
                assert!(
                    msg.contains(&format!(
                        "{FILE}: key `uncertain.parameter[0].law`: sample "
                    )) && msg.contains("draws model.pipe.density = ")
                        && msg.contains("[1000, 25000] kg/m3"),
                    "{msg}"
                );
            }
        }
    }
    assert!(refusals > 0, "no seed drew beyond 4σ in 40 × 10000 draws");
}

#[test]
fn constraint_bounds_and_the_depth_of_cut_take_the_operating_point_ranges() {
    const OMEGA: &str = "omega = [\"30 rpm\", \"150 rpm\"]";
    const V0: &str = "v0 = [\"2 m/h\", \"20 m/h\"]";
    refused(
        &edit(OMEGA, "omega = [\"30 rpm\", \"1e12 rad/s\"]"),
        "constraints.omega[1]",
        &[
            "the range of operating_point.omega",
            "[1, 1000] rpm",
            "got ",
        ],
    );
    refused(
        &edit(OMEGA, "omega = [\"1e-300 rpm\", \"150 rpm\"]"),
        "constraints.omega[0]",
        &["[1, 1000] rpm", "got 1e-300 rpm"],
    );
    refused(
        &edit(V0, "v0 = [\"2 m/h\", \"2e8 m/h\"]"),
        "constraints.v0[1]",
        &["[0.1, 1000] m/h", "got 200000000 m/h"],
    );
    refused(
        &edit(V0, "v0 = [\"1e-300 m/h\", \"20 m/h\"]"),
        "constraints.v0[0]",
        &["[0.1, 1000] m/h"],
    );
    for d in ["\"1e-300 m\"", "\"2 m\""] {
        refused(
            &edit(
                "max_depth_of_cut = \"3 mm\"",
                &format!("max_depth_of_cut = {d}"),
            ),
            "constraints.max_depth_of_cut",
            &["[1e-6, 0.1] m"],
        );
    }
    // Refused before solve simulates anything (it simulated 2.4e12 rpm and called it feasible).
    let dir = tempfile::tempdir().unwrap();
    let out = drillopt(
        &["solve"],
        dir.path(),
        &edit(OMEGA, "omega = [\"30 rpm\", \"1e12 rad/s\"]"),
    );
    refused_by_binary(&out, &[FILE, "constraints.omega[1]", "[1, 1000] rpm"]);
}

#[test]
fn command_line_quantities_take_the_ranges_of_their_keys() {
    let dir = tempfile::tempdir().unwrap();
    for (point, key, range) in [
        ("1e-300rpm,5m/h", "operating_point.omega", "[1, 1000] rpm"),
        ("1e308rpm,5m/h", "operating_point.omega", "[1, 1000] rpm"),
        (
            "60rpm,1e-300m/h",
            "operating_point.v0",
            "0 or in [0.1, 1000] m/h",
        ),
    ] {
        let out = drillopt(&["compare", "--point", point], dir.path(), TINY);
        refused_by_binary(&out, &[&format!("--point {point}"), key, range]);
    }
    for (flag, value, words) in [
        (
            "--v0",
            "1e-300m/h",
            &["`operating_point.v0`", "0 or in [0.1, 1000] m/h"][..],
        ),
        (
            "--omega",
            "1e-300rpm",
            &["`operating_point.omega`", "[1, 1000] rpm"][..],
        ),
        (
            "--duration",
            "1e-300",
            &["`simulation.duration`", "[1e-6, 86400] s"][..],
        ),
    ] {
        let out = drillopt(&["simulate", flag, value, "--quiet"], dir.path(), TINY);
        let stderr = refused_by_binary(&out, words);
        assert!(stderr.contains(flag), "{stderr}");
    }
}

#[test]
fn open_lower_ends_no_longer_admit_vanishing_values() {
    // Each was (0, x] or [0, x] and ran to an absurd number with exit status 0.
    refused(
        &edit("v0 = \"5 m/h\"", "v0 = \"1e-300 m/h\""),
        "operating_point.v0",
        &["0 or in [0.1, 1000] m/h", "off-bottom"],
    );
    refused(
        &add("model.pipe", "yield_strength = \"1e-300 Pa\""),
        "model.pipe.yield_strength",
        &["[1e7, 3e9] Pa"],
    );
    for key in ["shear_factor", "torsion_factor"] {
        // The file's own line of the key, whatever its value, is replaced.
        let old = TINY
            .lines()
            .find(|l| l.starts_with(&format!("{key} =")))
            .map(|l| format!("{l}\n"));
        let text = match old {
            Some(old) => edit(&old, &format!("{key} = 1e-300\n")),
            None => add("model.pipe", &format!("{key} = 1e-300")),
        };
        refused(&text, &format!("model.pipe.{key}"), &["[0.1, 1]"]);
    }
    refused(
        &edit("rate = \"180 s/m\"", "rate = \"1e-300 s/m\""),
        "model.bit.rate",
        &["[1, 100000] s/m"],
    );
    refused(
        &edit("limit_force = \"250 kN\"", "limit_force = \"1e-300 N\""),
        "model.bit.limit_force",
        &["[1000, 5e6] N"],
    );
    refused(
        &edit("gravity = \"9.81 m/s^2\"", "gravity = \"1e-300 m/s^2\""),
        "model.gravity",
        &["0 or in [0.1, 30]"],
    );
    // The isolated zeros stay: off-bottom rotation and a weightless string.
    let p = Problem::from_toml(&edit("v0 = \"5 m/h\"", "v0 = 0"), Path::new(FILE)).unwrap();
    assert_eq!(p.operating_point.v0, 0.0);
    let p = Problem::from_toml(
        &edit("gravity = \"9.81 m/s^2\"", "gravity = 0"),
        Path::new(FILE),
    )
    .unwrap();
    assert_eq!(p.model.gravity, 0.0);
    // And through the binary, before anything runs.
    let dir = tempfile::tempdir().unwrap();
    let out = drillopt(
        &["simulate", "--quiet"],
        dir.path(),
        &edit("rate = \"180 s/m\"", "rate = \"1e-300 s/m\""),
    );
    refused_by_binary(&out, &[FILE, "model.bit.rate", "[1, 100000] s/m"]);
}

/// Every shipped problem file stays valid under the new ranges.
#[test]
fn every_shipped_problem_still_loads() {
    fn walk(dir: &Path, n: &mut usize) {
        for entry in std::fs::read_dir(dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                walk(&path, n);
            } else if path.extension().is_some_and(|x| x == "toml") {
                let p = Problem::load(&path).unwrap_or_else(|e| panic!("{e}"));
                assert!(p.study.inadmissible_draw(&p.model).is_none());
                *n += 1;
            }
        }
    }
    let mut n = 0;
    walk(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("problems"),
        &mut n,
    );
    assert!(n >= 11);
}

/// Issue 33: `omega = 60` in a file ran at 572.96 rpm (read as rad/s) while the command line
/// refuses `--omega 60`. A bare number for a quantity with a unit is refused in files too, with
/// the SI spelling to write and the units accepted; zero needs no unit; dimensionless keys stay
/// bare.
#[test]
fn a_bare_number_for_a_quantity_with_a_unit_is_refused() {
    let m = refused(
        &edit("omega = \"60 rpm\"", "omega = 60"),
        "operating_point.omega",
        &[
            "needs its unit",
            "\"60 rad/s\" or \"60 rpm\"",
            "write the one meant",
        ],
    );
    assert!(m.contains("angular velocity"), "{m}");
    // Quoted, it is the same ambiguity (a fresh user's `omega = "60"` ran at 572.96 rpm).
    refused(
        &edit("omega = \"60 rpm\"", "omega = \"60\""),
        "operating_point.omega",
        &["needs its unit", "\"60 rad/s\" or \"60 rpm\""],
    );
    // "0" needs no unit, quoted or not.
    assert_eq!(
        Problem::from_toml(&edit("v0 = \"5 m/h\"", "v0 = \"0\""), Path::new(FILE))
            .unwrap()
            .operating_point
            .v0,
        0.0
    );
    refused(
        &edit("limit_force = \"250 kN\"", "limit_force = 250"),
        "model.bit.limit_force",
        &["needs its unit", "\"250 N\" or \"250 kN\"", "lbf"],
    );
    // Every such key of the file in one pass.
    let err = Problem::from_toml(
        &edit("omega = \"60 rpm\"", "omega = 60").replace("length = \"8 m\"", "length = 8"),
        Path::new(FILE),
    )
    .expect_err("refused");
    let keys: Vec<String> = err.key_errors().iter().map(|e| e.key.clone()).collect();
    assert!(
        keys.contains(&"operating_point.omega".to_string())
            && keys.contains(&"model.length".to_string()),
        "{keys:?}"
    );
    // Through the binary: no run, the file and the key named, a non-zero exit status.
    let dir = tempfile::tempdir().unwrap();
    let out = drillopt(
        &["simulate", "--duration", "0.01"],
        dir.path(),
        &edit("omega = \"60 rpm\"", "omega = 60"),
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "{stderr}");
    assert!(
        stderr.contains("key `operating_point.omega`") && stderr.contains("needs its unit"),
        "{stderr}"
    );
    assert!(!dir.path().join("out").join("summary.json").exists());
    // Dimensionless keys stay bare numbers.
    Problem::from_toml(TINY, Path::new(FILE)).expect("the tiny string loads");
    assert!(TINY.contains("poisson_ratio = 0.3"));
}

/// Unbounded work on admissible inputs: 100 000 probes took 40 s for 0.01 s of simulated time
/// (each a column and a plot); refused above 32 with the count.
#[test]
fn more_probes_than_the_cap_are_refused_with_the_count() {
    let many = vec!["\"1 m\""; 33].join(", ");
    let msg = refused(
        &edit("probes = [\"4 m\"]", &format!("probes = [{many}]")),
        "simulation.probes",
        &["33 positions", "at most 32"],
    );
    assert!(!msg.contains("NaN"), "{msg}");
    let ok = (0..32)
        .map(|i| format!("\"{} m\"", 0.25 * i as f64))
        .collect::<Vec<_>>()
        .join(", ");
    Problem::from_toml(
        &edit("probes = [\"4 m\"]", &format!("probes = [{ok}]")),
        Path::new(FILE),
    )
    .unwrap();
}

/// A value that overflows its unit's conversion ("1e300 GPa") said "got inf" and nothing else:
/// the range is given too.
#[test]
fn an_overflowing_value_is_refused_with_its_range() {
    refused(
        &edit(
            "youngs_modulus = \"203 GPa\"",
            "youngs_modulus = \"1e300 GPa\"",
        ),
        "model.pipe.youngs_modulus",
        &[
            "must be a finite number in [1e9, 1e12] Pa",
            "\"1e300 GPa\" is beyond the largest double",
        ],
    );
}

/// Two probes at one position wrote two columns of one name and one plot over the other: the
/// repeat is refused naming both.
#[test]
fn a_repeated_probe_position_is_refused() {
    let msg = refused(
        &edit(
            "probes = [\"4 m\"]",
            "probes = [\"2 m\", \"4 m\", \"400 cm\"]",
        ),
        "simulation.probes[2]",
        &["4 m repeats simulation.probes[1]", "positions must differ"],
    );
    assert!(!msg.contains("probes[0]"), "{msg}");
}

/// `drillopt modes /dev/zero` read 1.2 GB in 4 s before failing: a problem file is read to at
/// most 1 MiB, and a longer one is refused naming the file.
#[test]
fn a_file_larger_than_a_mebibyte_is_refused_without_reading_it_all() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("huge.toml");
    let mut text = TINY.to_string();
    text.push_str(&format!("\n# {}\n", "x".repeat(1 << 20)));
    std::fs::write(&path, &text).unwrap();
    let msg = Problem::load(&path).unwrap_err().to_string();
    assert!(
        msg.contains("huge.toml") && msg.contains("larger than 1 MiB"),
        "{msg}"
    );
    #[cfg(unix)]
    {
        let out = Command::new(env!("CARGO_BIN_EXE_drillopt"))
            .args(["modes", "/dev/zero"])
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success());
        assert!(
            stderr.contains("/dev/zero") && stderr.contains("larger than 1 MiB"),
            "{stderr}"
        );
    }
    // The shipped size is far below it.
    assert!(TINY.len() < 64 * 1024);
}

/// Unbounded work: `map --grid 200x200` with 10 000 samples grew 0.5 GB/s to out-of-memory. The
/// cost model refuses it before any work (nothing written), with its estimate, what drives it
/// and the flags that change it; a study that fits goes on.
#[test]
fn a_study_beyond_the_machines_memory_is_refused_before_any_work() {
    let dir = tempfile::tempdir().unwrap();
    let file = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/problems/bench/tiny_multi_fidelity.toml"
    );
    let out = Command::new(env!("CARGO_BIN_EXE_drillopt"))
        .args([
            "map",
            file,
            "--grid",
            "200x200",
            "--samples",
            "10000",
            "--quiet",
            "--out",
        ])
        .arg(dir.path().join("map"))
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "{stderr}");
    for w in [
        "tiny_multi_fidelity.toml",
        "map would need about 1.6 TB of memory",
        "the results of 400000000 simulations",
        "--samples",
        "--grid",
    ] {
        assert!(stderr.contains(w), "{w:?} missing: {stderr}");
    }
    assert!(!dir.path().join("map").exists(), "refused before any work");
}

/// Second campaign's findings (14 000 mutated files): a linear weight so small that the wall
/// vanishes was refused under the outer size; it is refused under its own key.
#[test]
fn a_vanishing_linear_weight_is_refused_under_its_own_key() {
    let bha = include_str!("../../problems/bha_example.toml");
    let text = bha.replacen(
        "linear_weight = \"19.81 lb/ft\"",
        "linear_weight = \"5e-324 lb/ft\"",
        1,
    );
    assert_ne!(text, bha);
    let err = Problem::from_toml(&text, Path::new("bha.toml")).unwrap_err();
    let e = err
        .key_errors()
        .iter()
        .find(|e| e.key.ends_with("linear_weight"))
        .unwrap_or_else(|| panic!("not refused under linear_weight: {err}"))
        .clone();
    assert!(e.message.contains("implies a wall of"), "{}", e.message);
    assert!(
        !err.key_errors()
            .iter()
            .any(|e| e.key.ends_with("outer_diameter")),
        "{err}"
    );
}

/// The command line: a subnormal V0 underflowed to off-bottom 0 and ran; `-0` printed
/// `V0 = -0.000 m/h` and the off-bottom ROP `-0.000`; a negative value was read as an option.
#[test]
fn command_line_values_that_underflow_are_refused_and_no_negative_zero_is_printed() {
    let dir = tempfile::tempdir().unwrap();
    let out = drillopt(
        &["simulate", "--v0", "5e-324m/h", "--duration", "0.01"],
        dir.path(),
        TINY,
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(
        stderr.contains("--v0") && stderr.contains("underflows to 0"),
        "{stderr}"
    );
    let out = drillopt(
        &["simulate", "--v0", "-0", "--duration", "0.02"],
        dir.path(),
        TINY,
    );
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(stdout.contains("V0 = 0.000 m/h"), "{stdout}");
    assert!(!stdout.contains("-0.0"), "{stdout}");
    let out = drillopt(&["compare", "--point", "-60rpm,10m/h"], dir.path(), TINY);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("--point -60rpm,10m/h") && stderr.contains("[1, 1000] rpm"),
        "{stderr}"
    );
}

/// A weightless string (gravity 0, admissible) printed "compression inf % of sinusoidal
/// buckling"; it says there is no such figure.
#[test]
fn a_weightless_string_prints_no_infinite_buckling_figure() {
    let dir = tempfile::tempdir().unwrap();
    let text = edit("gravity = \"9.81 m/s^2\"", "gravity = 0");
    let out = drillopt(&["simulate", "--duration", "0.02"], dir.path(), &text);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(!stdout.contains("inf"), "{stdout}");
    assert!(stdout.contains("buckling: no figure"), "{stdout}");
}

/// `compare` whose every simulation failed (an 8 km string on 12 elements: the start does not
/// converge) printed a row of NaN and exited 0; a missing result is not a success. An
/// off-bottom point (a score of −∞, said so) is a result and is not refused.
#[test]
fn compare_with_failed_simulations_exits_non_zero() {
    let dir = tempfile::tempdir().unwrap();
    let long = edit("length = \"8 m\"", "length = \"8000 m\"");
    let out = drillopt(&["compare", "--point", "60rpm,5m/h"], dir.path(), &long);
    let stderr = String::from_utf8_lossy(&out.stderr);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(!out.status.success(), "{stdout}");
    assert!(
        stderr.contains("1 of 1 points have no result: a simulation failed"),
        "{stderr}"
    );
    // The failed row shows dashes for the metrics it lacks, not NaN.
    let row = stdout
        .lines()
        .find(|l| l.trim_start().starts_with("60.0"))
        .unwrap_or_else(|| panic!("no row: {stdout}"));
    assert!(row.contains("failed") && row.contains(" - "), "{row}");
    assert!(!stdout.contains("NaN"), "{stdout}");
    assert!(dir.path().join("out/compare.json").exists());
    let out = drillopt(&["compare", "--point", "60rpm,0m/h"], dir.path(), TINY);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// The second campaign ran `mesh.elements = 2000` (the documented maximum) under a 4 GB
/// address-space limit: the dense assembly's 5.8 GB failed in an allocation (a panic). The cost
/// model reads the process's limit beside the machine's free memory and refuses it before any
/// work, naming the key.
#[cfg(unix)]
#[test]
fn a_mesh_beyond_the_processs_memory_limit_is_refused_not_a_panic() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("fine.toml");
    std::fs::write(&file, edit("elements = 12", "elements = 2000")).unwrap();
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_drillopt"));
    cmd.args(["simulate"])
        .arg(&file)
        .args(["--duration", "0.05", "--quiet", "--out"])
        .arg(dir.path().join("out"));
    let out = under_4_gb(cmd).output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    for w in [
        "fine.toml",
        "simulate would need about 5.8 GB",
        "2000-element mesh",
        "mesh.elements",
    ] {
        assert!(stderr.contains(w), "{w:?} missing: {stderr}");
    }
}

/// `cmd` run under a 4 GB address-space limit (`prlimit --as`).
#[cfg(unix)]
fn under_4_gb(mut cmd: Command) -> Command {
    use std::os::unix::process::CommandExt;
    // SAFETY: setrlimit only, between fork and exec.
    unsafe {
        cmd.pre_exec(|| {
            let limit = libc::rlimit {
                rlim_cur: 4_000_000_000,
                rlim_max: 4_000_000_000,
            };
            if libc::setrlimit(libc::RLIMIT_AS, &limit) != 0 {
                return Err(std::io::Error::last_os_error());
            }
            Ok(())
        });
    }
    cmd
}

/// `campbell --unreduced` on a long mesh ran for hours (200 elements: beyond 11 CPU min for five
/// speeds) or past the memory: the dense eigen-solve of the first-order form is estimated before
/// any work and refused beyond the memory, naming the flag.
#[cfg(unix)]
#[test]
fn an_unreduced_campbell_diagram_beyond_the_memory_is_refused_before_any_work() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("fine.toml");
    std::fs::write(&file, edit("elements = 12", "elements = 600")).unwrap();
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_drillopt"));
    cmd.args(["campbell"])
        .arg(&file)
        .args(["--unreduced", "--quiet", "--out"])
        .arg(dir.path().join("out"));
    let out = under_4_gb(cmd).output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    for w in [
        "fine.toml",
        "campbell would need about",
        "dense eigen-solve of 7212 states",
        "unreduced 600-element model",
        "drop --unreduced",
    ] {
        assert!(stderr.contains(w), "{w:?} missing: {stderr}");
    }
    assert!(!dir.path().join("out").exists(), "refused before any work");
}

/// A day of simulated time at a 1 µs output interval would write 33 TB of time series: refused
/// before any work, naming the flags that change it.
#[test]
fn a_time_series_larger_than_the_disk_is_refused_before_any_work() {
    let dir = tempfile::tempdir().unwrap();
    let out = drillopt(
        &[
            "simulate",
            "--duration",
            "86400",
            "--sample-interval",
            "1 us",
        ],
        dir.path(),
        TINY,
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    for w in [
        "timeseries.csv would take about",
        "TB",
        "--sample-interval",
        "--duration",
    ] {
        assert!(stderr.contains(w), "{w:?} missing: {stderr}");
    }
    assert!(!dir.path().join("out").exists(), "refused before any work");
}

/// serde wrote a float given to an integer key in full: 1e300 as 301 digits.
#[test]
fn a_huge_float_for_an_integer_key_is_echoed_in_exponent_form() {
    let msg = refused(
        &edit("elements = 12", "elements = 1e300"),
        "mesh.elements",
        &["must be an integer", "1e300"],
    );
    assert!(!msg.contains("000000000"), "{msg}");
}
