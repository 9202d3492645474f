//! `drillopt keys`: the key reference the tables give is docs/keys.md, and a range it prints is
//! the one a problem file is refused against.

use crate::common::drillopt;

#[test]
fn keys_prints_the_committed_reference() {
    let out = drillopt(&["keys"]);
    assert!(out.status.success(), "{out:?}");
    let printed = String::from_utf8(out.stdout).unwrap();
    let committed =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/docs/keys.md")).unwrap();
    assert_eq!(
        printed, committed,
        "regenerate: drillopt keys > docs/keys.md"
    );
}

#[test]
fn the_printed_range_is_the_one_a_file_is_refused_against() {
    let printed = String::from_utf8(drillopt(&["keys"]).stdout).unwrap();
    let row = printed
        .lines()
        .find(|l| l.starts_with("| `model.pipe.poisson_ratio` |"))
        .expect("a row for the Poisson ratio");
    assert!(row.contains("in [-0.9, 0.499]"), "{row}");
    // A seed with ν = 0.6 is refused quoting the same range.
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/problems/seed_mc2014.toml"
    ))
    .unwrap();
    let line = text
        .lines()
        .find(|l| l.trim_start().starts_with("poisson_ratio"))
        .expect("the seed gives ν");
    let bad = dir.path().join("bad.toml");
    std::fs::write(&bad, text.replace(line, "poisson_ratio = 0.6")).unwrap();
    let out = drillopt(&["modes", bad.to_str().unwrap()]);
    assert!(!out.status.success());
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(
        err.contains("model.pipe.poisson_ratio") && err.contains("in [-0.9, 0.499]"),
        "{err}"
    );
}

#[test]
fn the_command_lines_help_quotes_the_key_tables_range() {
    let out = drillopt(&["simulate", "--help"]);
    assert!(out.status.success());
    let help = String::from_utf8(out.stdout).unwrap();
    assert!(help.contains("admissible: in [1, 1000] rpm"), "{help}");
    assert!(
        help.contains("admissible: 0 or in [0.1, 1000] m/h"),
        "{help}"
    );
}
