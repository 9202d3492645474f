//! Issue 13's fresh-user refusals of a problem file: one refusal per fault (no second message
//! for the same entry), serde's type words replaced by what a key must be, every key a law table
//! accepts listed, a unit of the wrong dimension said to be one, and the admissible range printed
//! whatever the sign check.

use drillopt::problem::Problem;
use std::path::Path;

fn base() -> String {
    let text = shipped("regression/tiny_string.toml");
    text[..text.find("[objective]").unwrap()].to_string()
}

/// The text of the shipped problem file `problems/{path}`.
fn shipped(path: &str) -> String {
    let file = format!("{}/problems/{path}", env!("CARGO_MANIFEST_DIR"));
    std::fs::read_to_string(&file).unwrap_or_else(|e| panic!("{file}: {e}"))
}

/// The refusal lines of `text` (one per refused key).
fn refusals(text: &str) -> Vec<String> {
    match Problem::from_toml(text, Path::new("p.toml")) {
        Ok(_) => panic!("accepted:\n{text}"),
        Err(e) => e.to_string().lines().map(str::to_string).collect(),
    }
}

fn one_refusal(text: &str, key: &str, parts: &[&str]) {
    let lines = refusals(text);
    assert_eq!(lines.len(), 1, "one refusal expected: {lines:#?}");
    let line = &lines[0];
    assert!(
        line.contains("p.toml") && line.contains(&format!("`{key}`")),
        "{line}"
    );
    for p in parts {
        assert!(line.contains(p), "{line:?} lacks {p:?}");
    }
}

const PARAMETER: &str = "[[uncertain.parameter]]\nkey = \"model.bit.rate\"\nlaw = \"gamma\"\n";

#[test]
fn a_refused_uncertain_parameter_is_not_also_called_empty() {
    // A value of the only parameter refused: one line, not a second "is empty" for the same entry.
    one_refusal(
        &(base()
            + "[uncertain]\nsamples = 4\n"
            + PARAMETER
            + "mean = \"180 furlongs\"\ncov = 0.1\n"),
        "uncertain.parameter[0].mean",
        &["unknown unit `furlongs`", "s/m"],
    );
    one_refusal(
        &(base() + "[uncertain]\nsamples = 4\n" + PARAMETER + "mean = \"180 s/m\"\ncov = \"x\"\n"),
        "uncertain.parameter[0].cov",
        &["must be a number", "\"x\""],
    );
    // The entries misspelt as a whole.
    one_refusal(
        &(base()
            + "[uncertain]\nsamples = 4\n[[uncertain.parameters]]\nkey = \"model.bit.rate\"\n"),
        "uncertain.parameters",
        &["unknown field", "parameter"],
    );
    // Truly empty is still refused.
    one_refusal(
        &(base() + "[uncertain]\nsamples = 4\n"),
        "uncertain.parameter",
        &["is empty", "at least one"],
    );
}

#[test]
fn a_misshapen_uncertain_section_is_refused_in_the_words_of_a_problem_file() {
    one_refusal(
        &(base() + "[[uncertain]]\nsamples = 4\n"),
        "uncertain",
        &[
            "is written [[uncertain]], an array of tables",
            "write [uncertain]",
        ],
    );
    one_refusal(
        &(base()
            + "[uncertain]\nsamples = 4\n[uncertain.parameter]\nkey = \"model.bit.rate\"\nlaw = \"gamma\"\nmean = 180\ncov = 0.1\n"),
        "uncertain.parameter",
        &["one table", "write [[uncertain.parameter]]"],
    );
    one_refusal(
        &(base() + "[uncertain]\nsamples = \"four\"\n"),
        "uncertain.samples",
        &["must be an integer, got string \"four\""],
    );
    one_refusal(
        &(base() + "[[uncertan]]\nsamples = 4\n"),
        "uncertan",
        &["unknown field", "`uncertain`"],
    );
    for lines in [
        refusals(&(base() + "[[uncertain]]\nsamples = 4\n")),
        refusals(&(base() + "[uncertain]\nsamples = 2.5\n")),
    ] {
        assert!(
            lines
                .iter()
                .all(|l| !l.contains("i64") && !l.contains("f64")),
            "{lines:#?}"
        );
    }
}

#[test]
fn an_unknown_key_of_the_bit_table_lists_every_accepted_key() {
    let text = base().replace(
        "friction = \"0.04 m\"",
        "friction = \"0.04 m\"\ninertai = 0.4",
    );
    one_refusal(
        &text,
        "model.bit.inertai",
        &["law, inertia", "limit_force, rate, friction"],
    );
    let text = base().replace("friction = 1e-5", "friction = 1e-5\nstiffnes = 1");
    one_refusal(
        &text,
        "model.wall.stiffnes",
        &[
            "accepts law, friction_law, slip_smoothing, stiffness_per and the parameters",
            "stiffness",
        ],
    );
}

#[test]
fn a_negative_value_gets_the_admissible_range_of_its_key() {
    let text = base().replace("inertia = \"0.05 kg m^2\"", "inertia = \"-1 kg m^2\"");
    one_refusal(
        &text,
        "model.bit.inertia",
        &["must be in [0, 1000] kg m^2", "got -1"],
    );
    let text = base().replace(
        "density = \"1200 kg/m^3\"",
        "density = \"1200 kg/m^3\"\nannulus_density = \"-5 kg/m^3\"",
    );
    one_refusal(
        &text,
        "model.fluid.annulus_density",
        &["must be in [0, 3000] kg/m3", "got -5"],
    );
    // A key whose range starts above 0: the sign and the range, in one refusal.
    let text = base().replace("length = \"8 m\"", "length = \"-8 m\"");
    one_refusal(
        &text,
        "model.length",
        &["must be in [1, 15000] m", "got -8"],
    );
}

#[test]
fn a_threshold_unit_of_the_wrong_dimension_is_called_so() {
    let text = base()
        + "[constraints]\nomega = [\"30 rpm\", \"150 rpm\"]\nv0 = [\"2 m/h\", \"20 m/h\"]\n[[constraints.chance]]\nmetric = \"mean_wob_n\"\nthreshold = \"20 MPa\"\nmax_probability = 0.1\n";
    one_refusal(
        &text,
        "constraints.chance[0].threshold",
        &[
            "unit `MPa` of a stress (pressure), the wrong dimension: the value is a force",
            "mean_wob_n is a force",
            "kN",
        ],
    );
    assert!(!refusals(&text)[0].contains("unknown unit"));
}

#[test]
fn a_string_or_a_pipe_too_small_to_mesh_is_refused_under_its_key() {
    // Issue 13 item 6: a 1e-300 m string panicked in the element shape functions; a pipe of
    // 1e-300 m radius made the mass matrix singular, reported under `mesh.basis`.
    let text = base()
        .replace("length = \"8 m\"", "length = \"1e-300 m\"")
        .replace("probes = [\"4 m\"]", "probes = []");
    one_refusal(&text, "model.length", &["[1, 15000] m", "1e-300"]);
    let text = base()
        .replace("inner_radius = \"40 mm\"", "inner_radius = \"0 m\"")
        .replace("outer_radius = \"60 mm\"", "outer_radius = \"1e-300 m\"");
    one_refusal(
        &text,
        "model.pipe.outer_radius",
        &["[0.001, 1] m", "1e-300"],
    );
}

/// A bit law with a size must drill the hole it is in (helper-33 typed an 8½ in bit's size as
/// its radius, and the hole's, and both ran): a bit wider than the hole, and a hole more than 1.5
/// times the bit (a diameter typed as a radius), are refused naming the key and both sizes.
#[test]
fn a_bit_and_its_hole_must_match() {
    let detournay = shipped("seed_detournay.toml");
    let bit = "radius = \"70 mm\"                # a: the bit drills the 70 mm-radius hole";
    assert!(detournay.contains(bit));
    let text = detournay.replace(bit, "radius = \"140 mm\"");
    one_refusal(
        &text,
        "model.bit.radius",
        &[
            "must be at most the hole's radius",
            "a bit 280 mm (11.0236 in) across in a hole 140 mm (5.5118 in) across",
        ],
    );
    let text = detournay.replace(bit, "radius = \"45 mm\"");
    one_refusal(
        &text,
        "model.borehole.radius",
        &["must be at most 1.5 times the bit's radius", "a bit 90 mm"],
    );
    // 1.5 times is allowed (a reamer's hole).
    let text = detournay.replace(bit, "radius = \"46.67 mm\"");
    Problem::from_toml(&text, Path::new("p.toml")).expect("a hole 1.5 times the bit is allowed");
}

/// `[model.borehole] diameter`, the hole size as drillers give it (helper-33 typed "8.5 in" as
/// the radius): the same problem as half of it given as the radius; both, neither, or a diameter
/// whose half leaves the radius' range refused naming the key.
#[test]
fn the_hole_can_be_given_by_its_diameter() {
    let text = base();
    let hole = "[model.borehole]\nradius = \"70 mm\"";
    assert!(text.contains(hole), "{text}");
    let by_radius = Problem::from_toml(&text, Path::new("p.toml")).unwrap();
    let by_diameter = Problem::from_toml(
        &text.replace(hole, "[model.borehole]\ndiameter = \"140 mm\""),
        Path::new("p.toml"),
    )
    .unwrap();
    assert_eq!(
        by_radius.model.borehole_radius.to_bits(),
        by_diameter.model.borehole_radius.to_bits()
    );
    assert_eq!(
        drillopt::study::model_hash(&by_radius),
        drillopt::study::model_hash(&by_diameter)
    );
    one_refusal(
        &text.replace(
            hole,
            "[model.borehole]\nradius = \"70 mm\"\ndiameter = \"140 mm\"",
        ),
        "model.borehole.diameter",
        &["give radius or diameter, not both"],
    );
    one_refusal(
        &text.replace(hole, "[model.borehole]"),
        "model.borehole.radius",
        &["is required", "diameter = \"8.5 in\""],
    );
    one_refusal(
        &text.replace(hole, "[model.borehole]\ndiameter = \"5 m\""),
        "model.borehole.diameter",
        &[
            "must be in [0.002, 4] m",
            "as a diameter, twice the radius'",
            "got 5 m",
        ],
    );
    // A diameter of the wrong type: one refusal, not also "radius is required".
    let lines = refusals(&text.replace(hole, "[model.borehole]\ndiameter = true"));
    assert_eq!(lines.len(), 1, "{lines:#?}");
    assert!(lines[0].contains("model.borehole.diameter"), "{lines:#?}");
    // The later checks of the hole name the key the file gave it by.
    one_refusal(
        &text.replace(hole, "[model.borehole]\ndiameter = \"100 mm\""),
        "model.borehole.diameter",
        &["the pipe must fit in the hole"],
    );
}

/// `[model.bit] diameter`, the bit size as drillers give it ("8½ in PDC"), for a law with a
/// radius: the same problem as half of it given as the radius; both, a half outside the radius'
/// range, a bit wider than its hole, or a diameter for a law without a size refused naming the
/// key the file used.
#[test]
fn a_bit_can_be_given_by_its_diameter() {
    let detournay = shipped("seed_detournay.toml");
    let bit = "radius = \"70 mm\"                # a: the bit drills the 70 mm-radius hole";
    assert!(detournay.contains(bit));
    let by_radius = Problem::from_toml(&detournay, Path::new("p.toml")).unwrap();
    let by_diameter = Problem::from_toml(
        &detournay.replace(bit, "diameter = \"140 mm\""),
        Path::new("p.toml"),
    )
    .unwrap();
    assert_eq!(
        by_radius.model.bit.radius().map(f64::to_bits),
        by_diameter.model.bit.radius().map(f64::to_bits)
    );
    assert_eq!(
        drillopt::study::model_hash(&by_radius),
        drillopt::study::model_hash(&by_diameter)
    );
    one_refusal(
        &detournay.replace(bit, "radius = \"70 mm\"\ndiameter = \"140 mm\""),
        "model.bit.diameter",
        &["give radius or diameter, not both"],
    );
    one_refusal(
        &detournay.replace(bit, "diameter = \"2 m\""),
        "model.bit.diameter",
        &["must be in [0.01, 1] m", "as a diameter", "got 2 m"],
    );
    // The half is checked, not the diameter: 9 mm is a diameter of 4.5 mm's radius, below 5 mm.
    one_refusal(
        &detournay.replace(bit, "diameter = \"9 mm\""),
        "model.bit.diameter",
        &["must be in [0.01, 1] m", "got 0.009 m (written \"9 mm\")"],
    );
    // A wrong type is refused once, under its own key (not the table's), and not also as
    // "radius is required"; so is a law's name that is not a string.
    one_refusal(
        &detournay.replace(bit, "diameter = true"),
        "model.bit.diameter",
        &[
            "must be a number in SI units or a string with a unit",
            "got boolean `true`",
        ],
    );
    one_refusal(
        &detournay.replace(bit, "radius = [70]"),
        "model.bit.radius",
        &["got an array"],
    );
    one_refusal(
        &detournay.replace("law = \"detournay\"", "law = 5"),
        "model.bit.law",
        &["must be a law's name as a string, got integer `5`"],
    );
    one_refusal(
        &detournay.replace(bit, "diameter = \"150 mm\""),
        "model.bit.diameter",
        &[
            "must be at most the hole's diameter",
            "a bit 150 mm (5.9055 in) across in a hole 140 mm (5.5118 in) across",
        ],
    );
    // The hole more than 1.5 times a bit given by its diameter: the advice speaks of diameters.
    one_refusal(
        &detournay.replace(bit, "diameter = \"90 mm\""),
        "model.borehole.radius",
        &[
            "must be at most 1.5 times the bit's radius",
            "diameter = \"8.5 in\" for both",
        ],
    );
    // The paper's law has no size: a diameter there is an unknown key.
    let seed = shipped("seed_mc2014.toml");
    let law = "limit_force = \"250 kN\"";
    assert!(seed.contains(law));
    one_refusal(
        &seed.replace(law, &format!("{law}\ndiameter = \"140 mm\"")),
        "model.bit.diameter",
        &[
            "unknown field",
            "a size (radius or diameter) belongs to law = \"detournay\" or \"rgd\"",
        ],
    );
}

/// Sizes as the tables write them (helper-35 typed the hole as "8 1/2 in" and was told of an
/// unknown unit `1/2 in`): a mixed number or a vulgar fraction is the same model as its decimal;
/// an improper "81/2 in" (a mistyped 8 1/2) is still refused.
#[test]
fn sizes_are_read_as_the_tables_write_them() {
    let text = shipped("field/well_1km.toml");
    let hole = "[model.borehole]\ndiameter = \"8.5 in\"";
    assert!(text.contains(hole));
    let decimal = Problem::from_toml(&text, Path::new("p.toml")).unwrap();
    for written in ["8 1/2 in", "8-1/2 in", "8½ in"] {
        let p = Problem::from_toml(
            &text.replace(hole, &format!("[model.borehole]\ndiameter = \"{written}\"")),
            Path::new("p.toml"),
        )
        .unwrap_or_else(|e| panic!("{written}: {e}"));
        assert_eq!(
            drillopt::study::model_hash(&p),
            drillopt::study::model_hash(&decimal),
            "{written}"
        );
    }
    one_refusal(
        &text.replace(hole, "[model.borehole]\ndiameter = \"81/2 in\""),
        "model.borehole.diameter",
        &["unknown unit"],
    );
}
