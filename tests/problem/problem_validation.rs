//! The problem loader refuses every kind of bad input with an error that names the file, the dotted
//! key and what is allowed; and it reads the seed file and the optional keys' defaults exactly.
//!
//! Each case is the seed file `problems/seed_mc2014.toml` with exactly one line replaced, removed or
//! inserted, so a failure can only come from that one change.

use approx::assert_relative_eq;
use drillopt::model::{BasisSpec, FamilySize, Start};
use drillopt::problem::{Problem, ProblemError};
use std::f64::consts::PI;
use std::path::Path;

const SEED: &str = include_str!("../../problems/seed_mc2014.toml");
/// The path every edited text is "read from"; messages must name it.
const FILE: &str = "cases/edited_seed.toml";

// ---------------------------------------------------------------------------------------------
// Editing the seed text

/// Line range `[start, end)` of the body of `table` (`""` is the top level, before any header).
fn section(lines: &[&str], table: &str) -> (usize, usize) {
    let start = if table.is_empty() {
        0
    } else {
        let header = format!("[{table}]");
        lines
            .iter()
            .position(|l| l.trim() == header)
            .unwrap_or_else(|| panic!("the seed file has no table {header}"))
            + 1
    };
    let end = lines[start..]
        .iter()
        .position(|l| l.trim_start().starts_with('['))
        .map_or(lines.len(), |i| start + i);
    (start, end)
}

/// Index of the line that sets `key` in `table`, if there is one.
fn key_line(lines: &[&str], table: &str, key: &str) -> Option<usize> {
    let (start, end) = section(lines, table);
    let prefix = format!("{key} =");
    let found: Vec<usize> = (start..end)
        .filter(|&i| lines[i].trim_start().starts_with(&prefix))
        .collect();
    assert!(found.len() <= 1, "`{key}` is set twice in [{table}]");
    found.first().copied()
}

fn join(lines: &[String]) -> String {
    let mut text = lines.join("\n");
    text.push('\n');
    text
}

/// The seed with the line of `table.key` replaced by `key = value`.
fn set(table: &str, key: &str, value: &str) -> String {
    let lines: Vec<&str> = SEED.lines().collect();
    let i = key_line(&lines, table, key)
        .unwrap_or_else(|| panic!("the seed file does not set `{key}` in [{table}]"));
    let mut out: Vec<String> = lines.iter().map(|l| l.to_string()).collect();
    out[i] = format!("{key} = {value}");
    join(&out)
}

/// The seed with `key = value` added to `table`, which must not set `key` yet.
fn insert(table: &str, key: &str, value: &str) -> String {
    let lines: Vec<&str> = SEED.lines().collect();
    assert!(
        key_line(&lines, table, key).is_none(),
        "the seed file already sets `{key}` in [{table}]"
    );
    let (start, _) = section(&lines, table);
    let mut out: Vec<String> = lines.iter().map(|l| l.to_string()).collect();
    out.insert(start, format!("{key} = {value}"));
    join(&out)
}

/// The seed without the line of `table.key`.
fn remove(table: &str, key: &str) -> String {
    let lines: Vec<&str> = SEED.lines().collect();
    let i = key_line(&lines, table, key)
        .unwrap_or_else(|| panic!("the seed file does not set `{key}` in [{table}]"));
    let mut out: Vec<String> = lines.iter().map(|l| l.to_string()).collect();
    out.remove(i);
    join(&out)
}

/// 1-based line number of the line that sets `table.key` in `text`.
fn line_of(text: &str, table: &str, key: &str) -> usize {
    let lines: Vec<&str> = text.lines().collect();
    key_line(&lines, table, key).expect("key present") + 1
}

// ---------------------------------------------------------------------------------------------
// Loading and checking

fn load(text: &str) -> Result<Problem, ProblemError> {
    Problem::from_toml(text, Path::new(FILE))
}

#[track_caller]
fn accepted(text: &str) -> Problem {
    load(text).unwrap_or_else(|e| panic!("refused: {e}"))
}

/// `text` must be refused with an `Invalid` error about `key` whose message names the file, the key
/// and contains every one of `allowed` (words of what is allowed, or of what was wrong).
#[track_caller]
fn refused(text: &str, key: &str, allowed: &[&str]) -> ProblemError {
    let err = match load(text) {
        Ok(p) => panic!("accepted, but `{key}` should have been refused: {p:?}"),
        Err(e) => e,
    };
    let msg = err.to_string();
    assert!(
        matches!(err, ProblemError::Invalid { .. }),
        "expected an Invalid error about `{key}`, got {err:?}"
    );
    assert_eq!(err.key(), Some(key), "wrong key in: {msg}");
    assert!(msg.contains(FILE), "message does not name the file: {msg}");
    assert!(
        msg.contains(&format!("`{key}`")),
        "message does not name `{key}`: {msg}"
    );
    for word in allowed {
        assert!(msg.contains(word), "message lacks {word:?}: {msg}");
    }
    err
}

/// Cowper's shear factor of a hollow circle, MODEL.md §1.
fn cowper(nu: f64, m: f64) -> f64 {
    let m2 = m * m;
    let a = (1.0 + m2).powi(2);
    6.0 * (1.0 + nu) * a / ((7.0 + 6.0 * nu) * a + (20.0 + 12.0 * nu) * m2)
}

// ---------------------------------------------------------------------------------------------
// The seed file and the defaults

#[test]
fn the_seed_file_loads_with_the_exact_table_1_values() {
    let p = accepted(SEED);
    assert_eq!(p.name, "seed_mc2014");
    assert!(p.description.contains("Table 1"));
    assert_eq!(p.source, Path::new(FILE));

    let m = &p.model;
    assert_eq!(m.length, 35.0);
    assert_eq!(m.gravity, 9.81);
    assert_eq!(m.pipe.density, 7900.0);
    assert_eq!(m.pipe.youngs_modulus, 203e9);
    assert_eq!(m.pipe.poisson_ratio, 0.3);
    assert_eq!(m.pipe.inner_radius, 0.04);
    assert_eq!(m.pipe.outer_radius, 0.06);
    assert_eq!(m.borehole_radius, 0.07);
    assert_eq!(m.damping, 0.03);
    assert_eq!(m.fluid_density, 1200.0);
    let kappa = cowper(0.3, 2.0 / 3.0);
    assert_relative_eq!(m.pipe.shear_factor, kappa, max_relative = 1e-14);
    assert_relative_eq!(kappa, 0.5641, epsilon = 1e-4);
    assert_eq!(m.pipe.torsion_factor, m.pipe.shear_factor);
    assert_eq!(m.wall.get("stiffness"), Some(1e10));
    assert_eq!(m.wall.get("cubic_stiffness"), Some(1e16));
    assert_eq!(m.wall.get("damping"), Some(1e-9));
    assert_eq!(m.wall.get("friction"), Some(1e-5));
    assert_eq!(m.wall.get("sign_smoothing"), Some(1e-3));
    assert_eq!(m.bit.get("limit_force").unwrap(), 250e3);
    assert_eq!(m.bit.get("rate").unwrap(), 180.0);
    assert_eq!(m.bit.get("friction").unwrap(), 0.04);

    assert_eq!(p.mesh.elements, 105);
    assert_eq!(p.mesh.basis, BasisSpec::DEFAULT);
    assert_eq!(p.simulation.start, Start::Preloaded);
    assert_eq!(p.operating_point.omega, 2.0 * PI);
    assert_eq!(p.operating_point.v0, 1.0 / 720.0);
    assert_eq!(p.simulation.duration, 90.0);
    assert_eq!(p.simulation.time_step, 0.069);
    assert_eq!(p.simulation.settling_time, 4.0);
    assert_eq!(p.simulation.probes, vec![20.0]);
}

#[test]
fn omitted_optional_keys_take_the_documented_defaults() {
    let p = accepted(&remove("model", "gravity"));
    assert_eq!(p.model.gravity, 9.81);

    // shear_factor omitted: Cowper's value; torsion_factor = "shear" follows it.
    let p = accepted(&remove("model.pipe", "shear_factor"));
    assert_relative_eq!(
        p.model.pipe.shear_factor,
        cowper(0.3, 2.0 / 3.0),
        max_relative = 1e-14
    );
    assert_eq!(p.model.pipe.torsion_factor, p.model.pipe.shear_factor);

    // torsion_factor omitted: 1, exact St-Venant torsion (MODEL.md §3).
    let p = accepted(&remove("model.pipe", "torsion_factor"));
    assert_eq!(p.model.pipe.torsion_factor, 1.0);
    assert_relative_eq!(
        p.model.pipe.shear_factor,
        cowper(0.3, 2.0 / 3.0),
        max_relative = 1e-14
    );

    // settling_time and sign_smoothing have defaults.
    let p = accepted(&remove("simulation", "settling_time"));
    assert_eq!(p.simulation.settling_time, 0.0);
    assert_eq!(p.model.wall.get("sign_smoothing"), Some(1e-3));

    let p = accepted(&remove("simulation", "probes"));
    assert!(p.simulation.probes.is_empty());

    // No `name`: the file stem.
    let p = accepted(&remove("", "name"));
    assert_eq!(p.name, "edited_seed");
    let p = accepted(&remove("", "description"));
    assert_eq!(p.description, "");
}

#[test]
fn optional_keys_when_given_are_read() {
    let p = accepted(&set("simulation", "settling_time", "\"10 s\""));
    assert_eq!(p.simulation.settling_time, 10.0);
    // The paper's friction is smoothed by sign_smoothing; under the Coulomb friction (the
    // default) it would change nothing and is refused.
    let with_sign = insert("model.wall", "sign_smoothing", "\"0.6 rpm\"");
    refused(
        &with_sign,
        "model.wall.sign_smoothing",
        &["belongs to friction_law = \"paper\"", "slip_smoothing"],
    );
    let p = accepted(&with_sign.replace(
        "sign_smoothing = \"0.6 rpm\"",
        "sign_smoothing = \"0.6 rpm\"\nfriction_law = \"paper\"",
    ));
    assert_relative_eq!(
        p.model.wall.get("sign_smoothing").unwrap(),
        0.02 * PI,
        max_relative = 1e-14
    );
    let p = accepted(&set("model.pipe", "shear_factor", "0.9"));
    assert_eq!(p.model.pipe.shear_factor, 0.9);
    assert_eq!(
        p.model.pipe.torsion_factor, 0.9,
        "\"shear\" follows the given factor"
    );
    let p = accepted(&set("model.pipe", "shear_factor", "1"));
    assert_eq!(p.model.pipe.shear_factor, 1.0, "1 is in [0.1, 1]");
    let p = accepted(&set("model.pipe", "torsion_factor", "0.75"));
    assert_eq!(p.model.pipe.torsion_factor, 0.75);
    let p = accepted(&set("simulation", "probes", "[0, \"17.5 m\", \"35 m\"]"));
    assert_eq!(
        p.simulation.probes,
        vec![0.0, 17.5, 35.0],
        "the ends are allowed"
    );
    let p = accepted(&set("model", "gravity", "0"));
    assert_eq!(p.model.gravity, 0.0);
}

#[test]
fn units_convert_to_si() {
    let omega = |v: &str| {
        accepted(&set("operating_point", "omega", v))
            .operating_point
            .omega
    };
    assert_relative_eq!(omega("\"120 rpm\""), 4.0 * PI, max_relative = 1e-14);
    assert_relative_eq!(omega("\"30rpm\""), PI, max_relative = 1e-14);
    assert_relative_eq!(omega("\"1.5 rev/s\""), 3.0 * PI, max_relative = 1e-14);
    assert_eq!(omega("\"5 rad/s\""), 5.0);
    assert_eq!(omega("\"4.5 rad/s\""), 4.5);

    let v0 = |v: &str| {
        accepted(&set("operating_point", "v0", v))
            .operating_point
            .v0
    };
    assert_relative_eq!(v0("\"18 m/h\""), 0.005, max_relative = 1e-14);
    assert_relative_eq!(v0("\"3 mm/s\""), 0.003, max_relative = 1e-14);
    assert_relative_eq!(v0("\"0.6 m/min\""), 0.01, max_relative = 1e-14);
    assert_eq!(v0("\"1e-3 m/s\""), 1e-3);

    let p = accepted(&set("model.pipe", "inner_radius", "\"38.5 mm\""));
    assert_relative_eq!(p.model.pipe.inner_radius, 0.0385, max_relative = 1e-14);
    let p = accepted(&set("model.pipe", "outer_radius", "\"6.5 cm\""));
    assert_relative_eq!(p.model.pipe.outer_radius, 0.065, max_relative = 1e-14);
    let p = accepted(&set("model", "length", "\"1.2 km\""));
    assert_relative_eq!(p.model.length, 1200.0, max_relative = 1e-14);
    let p = accepted(&set("model", "length", "\"40_000 mm\""));
    assert_relative_eq!(p.model.length, 40.0, max_relative = 1e-14);
    let p = accepted(&set("model.pipe", "youngs_modulus", "\"210000 MPa\""));
    assert_relative_eq!(p.model.pipe.youngs_modulus, 210e9, max_relative = 1e-14);
    let p = accepted(&set("model.pipe", "density", "\"7.85 g/cm^3\""));
    assert_relative_eq!(p.model.pipe.density, 7850.0, max_relative = 1e-14);
    let p = accepted(&set("simulation", "duration", "\"2 min\""));
    assert_eq!(p.simulation.duration, 120.0);
    let p = accepted(&set("simulation", "time_step", "\"500 us\""));
    assert_relative_eq!(p.simulation.time_step, 5e-4, max_relative = 1e-14);
    let p = accepted(&set("model.bit", "limit_force", "\"0.3 MN\""));
    assert_relative_eq!(
        p.model.bit.get("limit_force").unwrap(),
        3e5,
        max_relative = 1e-14
    );
}

#[test]
fn a_file_on_disk_loads_and_takes_its_stem_as_default_name() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("my_study.toml");
    std::fs::write(&path, remove("", "name")).unwrap();
    let p = Problem::load(&path).unwrap();
    assert_eq!(p.name, "my_study");
    assert_eq!(p.source, path);
    assert_eq!(p.model.length, 35.0);
}

// ---------------------------------------------------------------------------------------------
// Files that cannot be read or parsed

#[test]
fn a_missing_file_is_refused_naming_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("no_such_problem.toml");
    let err = Problem::load(&path).unwrap_err();
    assert!(matches!(err, ProblemError::Io { .. }), "{err:?}");
    assert_eq!(err.key(), None);
    let msg = err.to_string();
    assert!(msg.contains(&path.display().to_string()), "{msg}");
    assert!(msg.contains("cannot read"), "{msg}");
    // As the binary prints it (the whole error chain): the OS error once, not twice.
    let chain = format!("{:#}", anyhow::Error::from(err));
    assert_eq!(chain.matches("os error 2").count(), 1, "{chain}");
}

#[test]
fn an_unreadable_path_is_refused_naming_the_file() {
    // A directory cannot be read as a file, whoever runs the test (root ignores permissions).
    let dir = tempfile::tempdir().unwrap();
    let err = Problem::load(dir.path()).unwrap_err();
    assert!(matches!(err, ProblemError::Io { .. }), "{err:?}");
    assert!(err.to_string().contains(&dir.path().display().to_string()));
}

#[track_caller]
fn syntax_error_at(text: &str, expected_line: usize) {
    let err = load(text).expect_err("a TOML syntax error must be refused");
    let msg = err.to_string();
    match err {
        ProblemError::Syntax { line, ref file, .. } => {
            assert_eq!(line, expected_line, "{msg}");
            assert_eq!(file, Path::new(FILE));
        }
        ref other => panic!("expected a Syntax error, got {other:?}"),
    }
    assert!(
        msg.starts_with(&format!("{FILE}:{expected_line}:")),
        "message does not start with file:line: {msg}"
    );
    assert!(msg.contains("not valid TOML"), "{msg}");
}

#[test]
fn a_toml_syntax_error_is_refused_with_its_line_number() {
    let text = set("mesh", "elements", "105 106");
    syntax_error_at(&text, line_of(&text, "mesh", "elements"));
    let text = set("operating_point", "omega", "\"60 rpm");
    syntax_error_at(&text, line_of(&text, "operating_point", "omega"));
    let text = set("model.pipe", "density", "");
    syntax_error_at(&text, line_of(&text, "model.pipe", "density"));
}

#[test]
fn a_key_set_twice_is_refused() {
    // Not one edit but a copy of one line: `elements` appears twice in [mesh].
    let text = SEED.replace("elements = 105", "elements = 105\nelements = 105");
    let second = SEED
        .lines()
        .position(|l| l.starts_with("elements = 105"))
        .unwrap()
        + 2;
    let err = load(&text).expect_err("a duplicate key must be refused");
    let msg = err.to_string();
    // toml's message is only "duplicate key": the key is named from the span it points at.
    assert!(msg.contains(FILE), "{msg}");
    assert!(
        msg.contains("duplicate key `elements`: a key is given once per table"),
        "{msg}"
    );
    match err {
        ProblemError::Syntax { line, .. } => assert_eq!(line, second, "{msg}"),
        other => panic!("expected a Syntax error, got {other:?}"),
    }
    // A table header given twice.
    let text = format!("{SEED}\n[mesh]\nelements = 105\n");
    let msg = load(&text).expect_err("refused").to_string();
    assert!(
        msg.contains("duplicate key `mesh`: this table header is given twice"),
        "{msg}"
    );
}

#[test]
fn an_integer_beyond_64_bits_is_said_so() {
    let text = SEED.replace("elements = 105", "elements = 99999999999999999999");
    let msg = load(&text).expect_err("refused").to_string();
    assert!(
        msg.contains("the integer 99999999999999999999 is beyond TOML's 64-bit integers"),
        "{msg}"
    );
}

#[test]
fn a_missing_table_and_a_laws_missing_parameter_say_what_they_take() {
    let lines: Vec<&str> = SEED.lines().collect();
    let (start, end) = section(&lines, "model.wall");
    let text = join(
        &lines[..start - 1]
            .iter()
            .chain(&lines[end..])
            .map(|l| l.to_string())
            .collect::<Vec<_>>(),
    );
    refused(
        &text,
        "model.wall",
        &["is required: the table [model.wall]"],
    );
    refused(
        &remove("model.wall", "cubic_stiffness"),
        "model.wall.cubic_stiffness",
        &[
            "is required by law = \"cubic\"",
            "a value in [0, 1e22] N/m3",
        ],
    );
}

// ---------------------------------------------------------------------------------------------
// Shape: unknown, missing and mistyped keys

#[test]
fn an_unknown_top_level_key_is_refused() {
    refused(
        &insert("", "nmae", "\"x\""),
        "nmae",
        &["unknown field", "name"],
    );
}

#[test]
fn an_unknown_nested_key_is_refused() {
    refused(
        &insert("model.pipe", "outer_radiuss", "\"60 mm\""),
        "model.pipe.outer_radiuss",
        &["unknown field", "outer_radius"],
    );
    refused(
        &insert("operating_point", "rpm", "\"60 rpm\""),
        "operating_point.rpm",
        &["unknown field", "omega", "v0"],
    );
    refused(
        &insert("model.wall", "sign_smothing", "1e-3"),
        "model.wall.sign_smothing",
        &["unknown field", "sign_smoothing"],
    );
}

#[test]
fn an_unknown_table_is_refused() {
    let text = format!("{SEED}\n[solver]\ntolerance = 1e-6\n");
    refused(&text, "solver", &["unknown field", "simulation"]);
    let text = format!("{SEED}\n[model.rock]\nstrength = \"50 MPa\"\n");
    refused(&text, "model.rock", &["unknown field", "borehole"]);
}

#[test]
fn a_missing_required_key_is_refused() {
    // The pipe's sizes are optional beside [[model.section]], so the refusal is validation's.
    refused(
        &remove("model.pipe", "outer_radius"),
        "model.pipe.outer_radius",
        &["is required", "[[model.section]]"],
    );
    refused(
        &remove("model", "length"),
        "model.length",
        // What it takes, from the table of ranges (was serde's "missing field `length`").
        &["is required: a value in [1, 15000] m"],
    );
    // Required by the feed tops (a hook load takes `wob` instead), so refused by the checker.
    refused(
        &remove("operating_point", "v0"),
        "operating_point.v0",
        &["is required", "hook_load"],
    );
    refused(
        &remove("model.bit", "rate"),
        "model.bit.rate",
        &["is required by law = \"exponential\"", "α_BR"],
    );
}

#[test]
fn a_missing_required_table_is_refused() {
    let text = SEED.replace("[model.fluid]\ndensity = \"1200 kg/m^3\"\n", "");
    assert_ne!(text, SEED);
    refused(
        &text,
        "model.fluid",
        &["is required: the table [model.fluid]"],
    );
    let start = SEED.find("[simulation]").unwrap();
    refused(
        &SEED[..start],
        "simulation",
        &["is required: the table [simulation]"],
    );
}

#[test]
fn a_value_of_the_wrong_type_is_refused() {
    // What the key must be in a problem file's words, not serde's ("expected i64").
    refused(
        &set("mesh", "elements", "\"many\""),
        "mesh.elements",
        &["must be an integer in [1, 2000]", "got string \"many\""],
    );
    refused(
        &set("mesh", "elements", "105.0"),
        "mesh.elements",
        &[
            "must be an integer in [1, 2000]",
            "got floating point `105.0`",
        ],
    );
    refused(
        &set("model.pipe", "poisson_ratio", "true"),
        "model.pipe.poisson_ratio",
        &["must be", "a number", "got boolean `true`"],
    );
    refused(
        &set("operating_point", "omega", "[60]"),
        "operating_point.omega",
        &["must be", "\"60 rpm\"", "got an array"],
    );
    refused(
        &set("", "name", "42"),
        "name",
        &["must be a string, got integer `42`"],
    );
    refused(
        &set("simulation", "probes", "\"20 m\""),
        "simulation.probes",
        &["must be an array, got string \"20 m\""],
    );
    refused(
        &set("simulation", "probes", "[\"20 m\", true]"),
        "simulation.probes[1]",
        &["must be", "a number", "got boolean `true`"],
    );
}

// ---------------------------------------------------------------------------------------------
// Quantities: units and numbers

#[test]
fn an_unknown_unit_is_refused_listing_the_allowed_units() {
    refused(
        &set("operating_point", "omega", "\"60 rps\""),
        "operating_point.omega",
        &["unknown unit `rps`", "rpm", "rad/s"],
    );
    refused(
        &set("operating_point", "v0", "\"5 m/day\""),
        "operating_point.v0",
        &["unknown unit `m/day`", "m/h", "m/s"],
    );
    // A known unit of the wrong dimension is said to be one, with the units of the right one.
    refused(
        &set("model.pipe", "outer_radius", "\"60 kN\""),
        "model.pipe.outer_radius",
        &[
            "the unit `kN` of a force, the wrong dimension: the value is a length",
            "mm",
        ],
    );
    // Dimensionless values take no unit.
    refused(
        &set("model.pipe", "poisson_ratio", "\"0.3 m\""),
        "model.pipe.poisson_ratio",
        &[
            "unit `m` of a length, but the value is dimensionless",
            "a plain number",
        ],
    );
}

#[test]
fn a_malformed_quantity_is_refused() {
    refused(
        &set("operating_point", "omega", "\"fast\""),
        "operating_point.omega",
        &["does not start with a number", "rpm"],
    );
    refused(
        &set("model", "length", "\"\""),
        "model.length",
        &["does not start with a number", "m"],
    );
    refused(
        &set("model", "length", "\"3.5.1 m\""),
        "model.length",
        &["does not start with a number"],
    );
    refused(
        &set("simulation", "duration", "\"s 90\""),
        "simulation.duration",
        &["does not start with a number"],
    );
}

#[test]
fn a_non_finite_value_is_refused() {
    refused(&set("model", "length", "nan"), "model.length", &["finite"]);
    refused(&set("model", "length", "inf"), "model.length", &["finite"]);
    refused(
        &set("model", "gravity", "-inf"),
        "model.gravity",
        &["finite"],
    );
    refused(
        &set("operating_point", "omega", "+inf"),
        "operating_point.omega",
        &["finite"],
    );
    refused(
        &set("model.pipe", "poisson_ratio", "nan"),
        "model.pipe.poisson_ratio",
        &["finite"],
    );
    refused(
        &set("model.pipe", "shear_factor", "nan"),
        "model.pipe.shear_factor",
        &["[0.1, 1]"],
    );
    // Overflow in a unit string is not finite either.
    refused(
        &set("model", "length", "\"1e999 m\""),
        "model.length",
        &["finite"],
    );
    refused(
        &set("simulation", "probes", "[nan]"),
        "simulation.probes[0]",
        &["finite"],
    );
}

// ---------------------------------------------------------------------------------------------
// Ranges: geometry and material

#[test]
fn a_non_positive_length_is_refused() {
    refused(
        &set("model", "length", "\"-35 m\""),
        "model.length",
        &["must be in "],
    );
    refused(
        &set("model", "length", "0"),
        "model.length",
        &["must be in "],
    );
}

#[test]
fn a_negative_radius_is_refused() {
    refused(
        &set("model.pipe", "inner_radius", "\"-40 mm\""),
        "model.pipe.inner_radius",
        &["must be in "],
    );
    refused(
        &set("model.pipe", "outer_radius", "\"-60 mm\""),
        "model.pipe.outer_radius",
        &["must be in "],
    );
    refused(
        &set("model.borehole", "radius", "\"-0.07 m\""),
        "model.borehole.radius",
        &["must be in "],
    );
}

#[test]
fn a_solid_pipe_is_accepted() {
    let p = accepted(&set("model.pipe", "inner_radius", "0"));
    assert_eq!(p.model.pipe.inner_radius, 0.0);
    assert_relative_eq!(
        p.model.pipe.shear_factor,
        cowper(0.3, 0.0),
        max_relative = 1e-14
    );
}

#[test]
fn outer_radius_not_above_inner_radius_is_refused() {
    refused(
        &set("model.pipe", "outer_radius", "\"40 mm\""),
        "model.pipe.outer_radius",
        &["greater than model.pipe.inner_radius"],
    );
    refused(
        &set("model.pipe", "inner_radius", "\"65 mm\""),
        "model.pipe.outer_radius",
        &["greater than model.pipe.inner_radius"],
    );
}

#[test]
fn a_pipe_that_does_not_fit_the_borehole_is_refused() {
    refused(
        &set("model.borehole", "radius", "\"60 mm\""),
        "model.borehole.radius",
        &["greater than model.pipe.outer_radius"],
    );
    refused(
        &set("model.borehole", "radius", "\"50 mm\""),
        "model.borehole.radius",
        &["greater than model.pipe.outer_radius"],
    );
    refused(
        &set("model.pipe", "outer_radius", "\"75 mm\""),
        "model.borehole.radius",
        &["greater than model.pipe.outer_radius"],
    );
}

#[test]
fn poisson_ratio_must_lie_in_minus_one_to_one_half() {
    for v in ["0.5", "-1.0", "0.7", "-1.5"] {
        refused(
            &set("model.pipe", "poisson_ratio", v),
            "model.pipe.poisson_ratio",
            &["[-0.9, 0.499]"],
        );
    }
    let p = accepted(&set("model.pipe", "poisson_ratio", "0.49"));
    assert_eq!(p.model.pipe.poisson_ratio, 0.49);
    let p = accepted(&set("model.pipe", "poisson_ratio", "-0.2"));
    assert_eq!(p.model.pipe.poisson_ratio, -0.2);
}

#[test]
fn a_negative_density_is_refused() {
    refused(
        &set("model.pipe", "density", "\"-7900 kg/m^3\""),
        "model.pipe.density",
        &["must be in "],
    );
    refused(
        &set("model.pipe", "density", "0"),
        "model.pipe.density",
        &["must be in "],
    );
    refused(
        &set("model.fluid", "density", "\"-1200 kg/m^3\""),
        "model.fluid.density",
        &["must be in "],
    );
    // No fluid is allowed.
    assert_eq!(
        accepted(&set("model.fluid", "density", "0"))
            .model
            .fluid_density,
        0.0
    );
}

#[test]
fn a_non_positive_youngs_modulus_is_refused() {
    refused(
        &set("model.pipe", "youngs_modulus", "0"),
        "model.pipe.youngs_modulus",
        &["must be in "],
    );
    refused(
        &set("model.pipe", "youngs_modulus", "\"-203 GPa\""),
        "model.pipe.youngs_modulus",
        &["must be in "],
    );
}

#[test]
fn a_negative_damping_is_refused() {
    refused(
        &set("model.pipe", "damping", "\"-0.03 1/s\""),
        "model.pipe.damping",
        &["must be in "],
    );
    refused(
        &set("model.wall", "damping", "-1e-9"),
        "model.wall.damping",
        &["in [0, 1e15]"],
    );
    assert_eq!(
        accepted(&set("model.pipe", "damping", "0")).model.damping,
        0.0
    );
}

#[test]
fn negative_contact_and_bit_parameters_are_refused() {
    refused(
        &set("model.wall", "stiffness", "\"-1e10 N/m\""),
        "model.wall.stiffness",
        &["in [0, 1e14] N/m"],
    );
    refused(
        &set("model.wall", "cubic_stiffness", "\"-1e16 N/m^3\""),
        "model.wall.cubic_stiffness",
        &["in [0, 1e22] N/m3"],
    );
    refused(
        &set("model.wall", "friction", "-1e-5"),
        "model.wall.friction",
        &["in [0, 2]"],
    );
    refused(
        &insert("model.wall", "sign_smoothing", "0"),
        "model.wall.sign_smoothing",
        &["in [1e-6, 10] rad/s"],
    );
    refused(
        &set("model.bit", "limit_force", "\"-250 kN\""),
        "model.bit.limit_force",
        &["in [1000, 5e6] N"],
    );
    refused(
        &set("model.bit", "rate", "0"),
        "model.bit.rate",
        &["in [1, 100000] s/m"],
    );
    refused(
        &set("model.bit", "friction", "\"-0.04 m\""),
        "model.bit.friction",
        &["in [0, 1] m"],
    );
    refused(
        &set("model", "gravity", "\"-9.81 m/s^2\""),
        "model.gravity",
        &["must be 0 or in [0.1, 30] m/s2"],
    );
}

#[test]
fn a_shear_factor_outside_zero_to_one_is_refused() {
    for v in ["0", "-0.5", "1.01", "2"] {
        refused(
            &set("model.pipe", "shear_factor", v),
            "model.pipe.shear_factor",
            &["[0.1, 1]", "\"cowper\""],
        );
    }
    refused(
        &set("model.pipe", "torsion_factor", "1.5"),
        "model.pipe.torsion_factor",
        &["[0.1, 1]", "\"shear\""],
    );
}

#[test]
fn an_unknown_word_for_a_factor_is_refused() {
    refused(
        &set("model.pipe", "shear_factor", "\"timoshenko\""),
        "model.pipe.shear_factor",
        &["`timoshenko` is not allowed", "[0.1, 1]", "\"cowper\""],
    );
    // Each factor has its own word.
    refused(
        &set("model.pipe", "shear_factor", "\"shear\""),
        "model.pipe.shear_factor",
        &["\"cowper\""],
    );
    refused(
        &set("model.pipe", "torsion_factor", "\"cowper\""),
        "model.pipe.torsion_factor",
        &["\"shear\""],
    );
}

// ---------------------------------------------------------------------------------------------
// Ranges: mesh, operating point, simulation window

#[test]
fn zero_or_too_many_elements_are_refused() {
    refused(
        &set("mesh", "elements", "0"),
        "mesh.elements",
        &["[1, 2000]"],
    );
    refused(
        &set("mesh", "elements", "-3"),
        "mesh.elements",
        &["[1, 2000]"],
    );
    refused(
        &set("mesh", "elements", "2001"),
        "mesh.elements",
        &["[1, 2000]"],
    );
}

#[test]
fn reduced_modes_must_be_between_one_and_the_free_dofs() {
    // 105 elements: 6 × 106 = 636 DOF, less the 6 at the top and v, w at the bit: 628 free.
    let lowest = |n: &str| insert("mesh", "reduced_modes", n);
    refused(&lowest("0"), "mesh.reduced_modes", &["[1, 628]"]);
    refused(&lowest("-1"), "mesh.reduced_modes", &["[1, 628]"]);
    refused(&lowest("629"), "mesh.reduced_modes", &["[1, 628]"]);
    refused(&lowest("636"), "mesh.reduced_modes", &["free DOFs"]);
    assert_eq!(accepted(&lowest("628")).mesh.basis, BasisSpec::Lowest(628));
    assert_eq!(accepted(&lowest("1")).mesh.basis, BasisSpec::Lowest(1));
}

/// `[mesh.basis]`: counts in [1, elements] or cutoff frequencies in Hz; exclusive with
/// `reduced_modes`.
#[test]
fn basis_per_family_is_read_and_checked() {
    let with_basis = |bending: &str, torsional: &str, extra: &str| {
        SEED.replace(
            "[operating_point]",
            &format!(
                "[mesh.basis]\nbending = {bending}\ntorsional = {torsional}\naxial = 3\n{extra}\n[operating_point]"
            ),
        )
    };
    assert_eq!(
        accepted(&with_basis(
            "20",
            "\"150 Hz\"",
            "static_corrections = false"
        ))
        .mesh
        .basis,
        BasisSpec::PerFamily {
            bending: FamilySize::Count(20),
            torsional: FamilySize::Cutoff { hz: 150.0, min: 1 },
            axial: FamilySize::Count(3),
            static_corrections: false,
            steady_shapes: false,
        }
    );
    // The steady state's shapes only when asked for.
    for (extra, steady) in [("", false), ("steady_shapes = true", true)] {
        assert_eq!(
            accepted(&with_basis("20", "8", extra))
                .mesh
                .basis
                .steady_shapes(),
            steady,
            "{extra}"
        );
    }
    // They join the resting shapes of the static corrections: refused without them.
    refused(
        &with_basis(
            "20",
            "8",
            "static_corrections = false\nsteady_shapes = true",
        ),
        "mesh.basis.steady_shapes",
        &["static_corrections = true", "got true"],
    );
    refused(
        &with_basis("0", "8", ""),
        "mesh.basis.bending",
        &["[1, 105]"],
    );
    refused(
        &with_basis("2.5", "8", ""),
        "mesh.basis.bending",
        &["integer"],
    );
    refused(
        &with_basis("20", "\"150 rpm\"", ""),
        "mesh.basis.torsional",
        &["Hz"],
    );
    // A quantity of another kind: the message says what the key takes.
    refused(
        &with_basis("20", "\"60 kN\"", ""),
        "mesh.basis.torsional",
        &["mode count", "cutoff frequency", "got \"60 kN\""],
    );
    refused(
        &with_basis("20", "\"1e6 Hz\"", ""),
        "mesh.basis.torsional",
        &["(0, 100000] Hz"],
    );
    refused(
        &with_basis("20", "8", "").replace("elements = 105", "elements = 105\nreduced_modes = 51"),
        "mesh.basis",
        &["not both"],
    );
    refused(
        &with_basis("20", "8", "modes = 3"),
        "mesh.basis.modes",
        &["unknown field"],
    );
}

#[test]
fn the_start_is_preloaded_or_unloaded() {
    assert_eq!(
        accepted(&insert("simulation", "start", "\"unloaded\""))
            .simulation
            .start,
        Start::Unloaded
    );
    refused(
        &insert("simulation", "start", "\"loaded\""),
        "simulation.start",
        &["preloaded", "unloaded"],
    );
}

#[test]
fn a_non_positive_rotation_speed_is_refused() {
    refused(
        &set("operating_point", "omega", "0"),
        "operating_point.omega",
        &["must be in "],
    );
    refused(
        &set("operating_point", "omega", "\"-60 rpm\""),
        "operating_point.omega",
        &["must be in [1, 1000] rpm", "got -60 rpm"],
    );
}

/// Issue 13 item 13: V0 = 0 is off-bottom rotation, accepted; a negative V0 is refused.
#[test]
fn a_negative_rate_of_penetration_is_refused_and_zero_is_off_bottom() {
    let p = accepted(&set("operating_point", "v0", "\"0 m/h\""));
    assert_eq!(p.operating_point.v0, 0.0);
    refused(
        &set("operating_point", "v0", "\"-1e-3 m/s\""),
        "operating_point.v0",
        &[
            "must be 0 or in [0.1, 1000] m/h",
            "off-bottom",
            "got -3.6 m/h",
        ],
    );
}

#[test]
fn a_non_positive_duration_or_time_step_is_refused() {
    refused(
        &set("simulation", "duration", "0"),
        "simulation.duration",
        &["must be in "],
    );
    refused(
        &set("simulation", "time_step", "\"-1 ms\""),
        "simulation.time_step",
        &["must be in "],
    );
}

#[test]
fn a_time_step_longer_than_the_duration_is_refused() {
    let short = SEED
        .replace("duration = \"90 s\"", "duration = \"0.5 s\"")
        .replace("settling_time = \"4 s\"", "settling_time = \"0.1 s\"")
        .replace("time_step = \"69 ms\"", "time_step = \"0.8 s\"");
    refused(
        &short,
        "simulation.time_step",
        &["no longer than simulation.duration"],
    );
    // A step as long as the window is allowed.
    let p = accepted(&short.replace("time_step = \"0.8 s\"", "time_step = \"0.5 s\""));
    assert_eq!(p.simulation.time_step, 0.5);
}

#[test]
fn a_settling_time_longer_than_half_the_duration_is_refused() {
    // It was silently cut to half the run (issue 33 item 8); both keys are named.
    for v in ["\"46 s\"", "\"90 s\"", "\"2 min\""] {
        refused(
            &set("simulation", "settling_time", v),
            "simulation.settling_time",
            &["at most half of simulation.duration (90 s)"],
        );
    }
    let p = accepted(&set("simulation", "settling_time", "\"45 s\""));
    assert_eq!(p.simulation.settling_time, 45.0, "half the run is allowed");
    refused(
        &set("simulation", "settling_time", "\"-1 s\""),
        "simulation.settling_time",
        &[
            "must be in [0, 43200] s (at most half the duration",
            "got -1 s",
        ],
    );
}

#[test]
fn a_probe_outside_the_string_is_refused() {
    refused(
        &set("simulation", "probes", "[\"36 m\"]"),
        "simulation.probes[0]",
        &["in [0, model.length = 35 m]"],
    );
    refused(
        &set("simulation", "probes", "[\"20 m\", \"-0.5 m\"]"),
        "simulation.probes[1]",
        &["in [0, model.length = 35 m]"],
    );
    refused(
        &set("simulation", "probes", "[\"20 rpm\"]"),
        "simulation.probes[0]",
        &["the unit `rpm` of an angular velocity, the wrong dimension"],
    );
}

// ---------------------------------------------------------------------------------------------
// Name

#[test]
fn a_name_that_is_not_a_plain_folder_name_is_refused() {
    // Used as the results folder: no separators, and not a folder that points elsewhere.
    for v in [
        "\"runs/seed\"",
        "\"..\\\\seed\"",
        "\"\"",
        "\"   \"",
        "\".\"",
        "\"..\"",
    ] {
        refused(&set("", "name", v), "name", &["without path separators"]);
    }
    assert_eq!(
        accepted(&set("", "name", "\"seed-v2_b\"")).name,
        "seed-v2_b"
    );
}

#[test]
fn a_name_no_folder_can_have_is_refused_at_load() {
    // Issue 13 item 8: a NUL or a 300-character name failed only when the output folder was made.
    refused(
        &set("", "name", "\"a\\u0000b\""),
        "name",
        &["control characters"],
    );
    let long = format!("\"{}\"", "a".repeat(300));
    refused(
        &set("", "name", &long),
        "name",
        &["at most 200 bytes", "300 bytes"],
    );
    let ok = "b".repeat(200);
    assert_eq!(accepted(&set("", "name", &format!("\"{ok}\""))).name, ok);
}

/// Issue 13: every physical input has an admissible range; a typo far outside it (an exponent
/// too many, a missing unit) is refused naming the key and the range, before anything runs.
#[test]
fn physical_inputs_have_admissible_ranges() {
    for (table, key, value, allowed) in [
        ("model", "length", "\"1e308 m\"", "[1, 15000] m"),
        (
            "model.pipe",
            "density",
            "\"1e-300 kg/m^3\"",
            "[1000, 25000] kg/m3",
        ),
        (
            "model.pipe",
            "youngs_modulus",
            "\"203 kPa\"",
            "[1e9, 1e12] Pa",
        ),
        ("model.wall", "friction", "1e308", "[0, 2]"),
        ("model.bit", "limit_force", "\"250 GN\"", "unknown unit"),
        ("model.bit", "limit_force", "\"2.5e11 N\"", "[1000, 5e6] N"),
        // The operating point in the driller's units, not in rad/s and m/s with 17 digits.
        (
            "operating_point",
            "v0",
            "\"1e308 m/h\"",
            "0 or in [0.1, 1000] m/h (0 is off-bottom rotation; else from 0.1 m/h, slower than any rock is drilled, to at most 1000 m/h), got 1e308 m/h",
        ),
        (
            "operating_point",
            "omega",
            "\"1e-300 rpm\"",
            "in [1, 1000] rpm (1 to 1000 rpm: the stick-slip statistics are relative to Ω), got 1e-300 rpm",
        ),
        ("simulation", "duration", "\"1e9 s\"", "at most a day"),
        ("simulation", "time_step", "\"1e-300 s\"", "[1e-6, 1] s"),
    ] {
        refused(
            &set(table, key, value),
            &format!("{table}.{key}"),
            &[allowed],
        );
    }
}

/// Every key of the shipped problems, taken out one at a time: a refusal says what the key takes
/// (its range, or what it is), never serde's bare "missing field".
#[test]
fn every_missing_key_says_what_it_takes() {
    for text in [
        SEED,
        include_str!("../../problems/regression/tiny_string.toml"),
        include_str!("../../problems/seed_robust.toml"),
        include_str!("../../problems/bha_example.toml"),
    ] {
        let lines: Vec<&str> = text.lines().collect();
        for (i, line) in lines.iter().enumerate() {
            if !line.starts_with(|c: char| c.is_ascii_lowercase()) || !line.contains('=') {
                continue;
            }
            let edited: Vec<&str> = lines
                .iter()
                .enumerate()
                .filter(|(j, _)| *j != i)
                .map(|(_, l)| *l)
                .collect();
            if let Err(e) = Problem::from_toml(&edited.join("\n"), Path::new(FILE)) {
                let msg = e.to_string();
                assert!(!msg.contains("missing field"), "without `{line}`: {msg}");
            }
        }
    }
}
