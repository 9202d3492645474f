//! From [`ProblemFile`] to [`Problem`]: every value parsed to SI and checked against its legal range.

use super::check::{Checker, MAX_ELEMENTS, family_size, shown_in, yield_strength};
use super::error::KeyError;
use super::file::ProblemFile;
use super::schema::*;
use super::{Dimension, Problem, ProblemError};
use crate::model::bit::BIT_LAWS;
use crate::model::law::{Chosen, Law, LawEntry, find};
use crate::model::wall::{WALL_LAWS, WallFriction, WallStiffnessPer};
use crate::model::{
    BasisSpec, CampbellSettings, Drillstring, Mesh, MultipleSource, OperatingPoint, Pipe,
    SampleInterval, Simulation, Start, cowper_shear_factor,
};
use serde::Deserialize;
use std::path::Path;

/// Most shape errors reported at once: each one the parse meets is recorded and its key taken
/// out of the table before parsing again, up to this many.
const MAX_SHAPE_ERRORS: usize = 100;

/// Values that stand in for a required key of the wrong type, tried in turn until the parse gets
/// past the key: a value of some type the key takes, so that the rest of the file is read and
/// checked in the same pass (the refusals of keys under a stand-in are not reported: they would
/// be about the stand-in).
fn stand_ins() -> [toml::Value; 6] {
    [
        toml::Value::Integer(1),
        toml::Value::Float(1.0),
        toml::Value::String("1".into()),
        toml::Value::Boolean(false),
        toml::Value::Array(Vec::new()),
        toml::Value::Table(toml::Table::new()),
    ]
}

/// What [`parse`] read: the file (when it could be read with only unknown keys taken out and
/// mistyped required keys stood in for), the shape errors met on the way, and the keys that hold
/// a stand-in (whose later refusals are about the stand-in).
pub(super) type Parsed = (Option<ProblemFile>, Vec<KeyError>, Vec<String>);

/// Deserialize the file, reporting the dotted path of every key that is unknown or has the wrong
/// shape. An unknown key, or a table key of the wrong type, is recorded and removed, and the parse
/// runs again, so that one pass reports them all; a required key of the wrong type is recorded
/// and given a stand-in value ([`stand_ins`]) so that the parse reads on. A missing required key
/// or a mistyped array element ends the pass. Returns the errors met on the way, and the file
/// when it could be read with only unknown keys taken out or mistyped keys stood in for (its
/// values are then checked too, in the same pass, but for those under a stand-in).
pub(super) fn parse(text: &str, file: &Path) -> Result<Parsed, ProblemError> {
    // The document parser, for line and column of syntax errors; then a table to edit.
    let de = toml::Deserializer::parse(text).map_err(|e| syntax(text, file, &e))?;
    let mut table = match toml::Table::deserialize(de) {
        Ok(t) => toml::Value::Table(t),
        Err(e) => return Err(syntax(text, file, &e)),
    };
    let mut errors: Vec<KeyError> = Vec::new();
    let mut removed: Vec<String> = Vec::new();
    // The keys given a stand-in, with the index of the one they hold.
    let mut stood_in: Vec<(String, Vec<String>, usize)> = Vec::new();
    // Keys of the wrong type taken out or stood in for: their later refusals are not theirs.
    let mut mistyped: Vec<String> = Vec::new();
    let mut only_unknown = true;
    // A bound on the re-parses: every error, and every stand-in tried, is one.
    for _ in 0..MAX_SHAPE_ERRORS * (1 + stand_ins().len()) {
        if errors.len() >= MAX_SHAPE_ERRORS {
            break;
        }
        let e = match serde_path_to_error::deserialize::<_, ProblemFile>(table.clone()) {
            Ok(raw) if only_unknown => return Ok((Some(raw), errors, mistyped)),
            Ok(_) => break,
            Err(e) => e,
        };
        let segments: Vec<String> = e
            .path()
            .iter()
            .map(|s| match s {
                serde_path_to_error::Segment::Map { key } => key.clone(),
                serde_path_to_error::Segment::Seq { index } => format!("[{index}]"),
                other => other.to_string(),
            })
            .collect();
        let (key, message) = shape_error(e, text);
        let mut at: Vec<String> = segments.clone();
        if !at.last().is_some_and(|k| key.ends_with(k.as_str())) {
            // A top-level key: the path is empty and the key comes from the message.
            at.push(key.rsplit('.').next().unwrap_or(&key).to_string());
        }
        // A stand-in of the wrong type too: the next one.
        if let Some((_, path, index)) = stood_in.iter_mut().find(|(k, ..)| *k == key) {
            *index += 1;
            let Some(next) = stand_ins().into_iter().nth(*index) else {
                break;
            };
            let path: Vec<&str> = path.iter().map(String::as_str).collect();
            if !insert_key(&mut table, &path, next) {
                break;
            }
            continue;
        }
        if message.starts_with("missing field") {
            // Missing because a mistyped value was taken out (already reported), or a required
            // key the file lacks (a misspelt one among the unknown keys): reported, and a
            // stand-in so that the rest of the file is read and checked in the same pass.
            if !removed.contains(&key) {
                // What the key takes, when the tables know it.
                let message = match (
                    super::keys::range_of(&key),
                    super::keys::dimension_of(&key),
                ) {
                    (Some(r), Some(dim)) => {
                        let (unit, factor) = shown_in(&key, dim);
                        // "a whole number in [1, 2000]" says what it is by itself.
                        let a_value = if r.integer { "" } else { "a value " };
                        format!("is required: {a_value}{}", r.describe_in(unit, factor))
                    }
                    _ => required(&key).unwrap_or_else(|| {
                        // A whole table left out: `[model.wall]`.
                        if message.starts_with("missing field") && TABLES.contains(&key.as_str()) {
                            format!("is required: the table [{key}] (see the problem-file reference for its keys)")
                        } else {
                            message
                        }
                    }),
                };
                errors.push(KeyError {
                    key: key.clone(),
                    message,
                });
                mistyped.push(key.clone());
            }
            let path: Vec<&str> = at.iter().map(String::as_str).collect();
            let [first, ..] = stand_ins();
            if !insert_key(&mut table, &path, first) {
                break;
            }
            stood_in.push((key, at, 0));
            continue;
        }
        // A key of the wrong type is taken out (its default, if any, stands in): the rest of the
        // file is still read and checked.
        if message.starts_with("must be ") {
            mistyped.push(key.clone());
        }
        only_unknown &= message.starts_with("unknown field") || message.starts_with("must be ");
        let at: Vec<&str> = at.iter().map(String::as_str).collect();
        let gone = remove_key(&mut table, &at);
        removed.push(key.clone());
        errors.push(KeyError { key, message });
        if !gone {
            break;
        }
    }
    Ok((None, errors, mistyped))
}

/// The key and message of a deserialization error.
fn shape_error(e: serde_path_to_error::Error<toml::de::Error>, text: &str) -> (String, String) {
    let path = e.path().to_string();
    let message = e.into_inner().message().to_string();
    let key = if path == "." || path.is_empty() {
        // A missing or unknown top-level table: toml's message already names it.
        missing_or_unknown_key(&message).unwrap_or_else(|| "(top level)".into())
    } else {
        match missing_or_unknown_key(&message) {
            Some(k) if message.starts_with("missing field") => format!("{path}.{k}"),
            _ => path,
        }
    };
    plain_shape(key, message, text)
}

/// serde's "invalid type: map, expected i64" in the words of a problem file: what the key must
/// be (an integer, a number, a string, an array, a table) and what was written. A table written
/// as an array of tables (`[[uncertain]]` for `[uncertain]`), or the other way round, is said so
/// with the header to write (when `text`, the file, has that header). Other messages pass
/// unchanged.
fn plain_shape(key: String, message: String, text: &str) -> (String, String) {
    let Some((got, expected)) = message
        .strip_prefix("invalid type: ")
        .and_then(|m| m.split_once(", expected "))
    else {
        return (key, message);
    };
    // serde writes a float in full (1e300 with 301 digits): as a message shows a number.
    let float = got
        .strip_prefix("floating point `")
        .and_then(|n| n.strip_suffix('`'))
        .filter(|n| n.len() > 17)
        .and_then(|n| n.parse::<f64>().ok())
        .map(|x| format!("floating point `{}`", crate::units::show(x)));
    let got = match got {
        "map" => "a table",
        "sequence" => "an array",
        other => float.as_deref().unwrap_or(other),
    };
    let expected_words = match expected {
        "i64" | "i32" | "u64" | "u32" | "usize" => "an integer",
        "f64" | "f32" => "a number",
        "a sequence" => "an array",
        e if e.starts_with("struct ") || e == "a map" => "a table",
        e => e,
    };
    // `[[name]]` makes `name` an array of tables; serde then reads its first element `name[0]`
    // where one table's first field was expected.
    if let Some(parent) = key.strip_suffix("[0]")
        && got == "a table"
        && text.contains(&format!("[[{parent}]]"))
    {
        return (
            parent.to_string(),
            format!(
                "is written [[{parent}]], an array of tables, but `{parent}` is one table: write [{parent}]"
            ),
        );
    }
    if got == "a table" && expected_words == "an array" && text.contains(&format!("[{key}]")) {
        return (
            key.clone(),
            format!(
                "is written [{key}], one table, but `{key}` is an array of tables: write [[{key}]] before each entry"
            ),
        );
    }
    // A count with a range in the key table says it ("a whole number in [1, 2000] (…)").
    let expected_words = match super::keys::range_of(&key) {
        Some(r) if r.integer && expected_words == "an integer" => format!(
            "an integer {}",
            r.describe_in("", 1.0).trim_start_matches("a whole number ")
        ),
        _ => expected_words.to_string(),
    };
    (key, format!("must be {expected_words}, got {got}"))
}

/// The table that holds the last key of `path` (table keys and `[i]` array indices on the way)
/// in `value`, and that key; `None` when the way is not there or does not end at a table.
fn parent_table<'v, 'p>(
    value: &'v mut toml::Value,
    path: &[&'p str],
) -> Option<(&'v mut toml::Table, &'p str)> {
    let (last, parents) = path.split_last()?;
    let mut v = value;
    for seg in parents {
        v = match (v, seg.strip_prefix('[').and_then(|s| s.strip_suffix(']'))) {
            (toml::Value::Array(a), Some(i)) => i.parse::<usize>().ok().and_then(|i| a.get_mut(i)),
            (toml::Value::Table(t), None) => t.get_mut(*seg),
            _ => None,
        }?;
    }
    match v {
        toml::Value::Table(t) => Some((t, *last)),
        _ => None,
    }
}

/// Remove the table key at `path` from `value` ([`parent_table`]); whether it was there. An array
/// element is not removed: the indices after it would shift.
fn remove_key(value: &mut toml::Value, path: &[&str]) -> bool {
    parent_table(value, path).is_some_and(|(t, key)| t.remove(key).is_some())
}

/// Insert `new` as the table key at `path` in `value` ([`parent_table`]); whether it could.
fn insert_key(value: &mut toml::Value, path: &[&str], new: toml::Value) -> bool {
    parent_table(value, path)
        .map(|(t, key)| t.insert(key.to_string(), new))
        .is_some()
}

/// The tables of a problem file (a missing one is said to be a table).
const TABLES: &[&str] = &[
    "model",
    "model.pipe",
    "model.fluid",
    "model.borehole",
    "model.wall",
    "model.bit",
    "mesh",
    "mesh.basis",
    "operating_point",
    "simulation",
    "objective",
    "constraints",
    "uncertain",
    "uncertain.sequential",
    "optimizer",
    "optimizer.explore",
    "expect",
    "campbell",
];

/// What a required key without a range in the tables takes, for its "missing" refusal (array
/// indices read as `[*]`).
fn required(key: &str) -> Option<String> {
    let mut general = String::with_capacity(key.len());
    let mut in_index = false;
    for ch in key.chars() {
        match ch {
            '[' => {
                in_index = true;
                general.push_str("[*");
            }
            ']' => {
                in_index = false;
                general.push(']');
            }
            _ if in_index => {}
            _ => general.push(ch),
        }
    }
    if matches!(
        general.as_str(),
        "objective.risk[*].metric" | "constraints.chance[*].metric"
    ) {
        let keys: Vec<&str> = crate::metrics::catalogue::keys().collect();
        return Some(format!(
            "is required: the metric, one of {}",
            keys.join(", ")
        ));
    }
    Some(match general.as_str() {
        "constraints.omega" => {
            "is required: the range [min, max] of Ω (e.g. [\"40 rpm\", \"200 rpm\"]), each end in [1, 1000] rpm"
        }
        "expect.omega" => {
            "is required: the range [min, max] of Ω the optimum is known to lie in (e.g. [\"100 rpm\", \"140 rpm\"])"
        }
        "expect.reason" => "is required: why the optimum lies in the expected range (a sentence)",
        "uncertain.sequential.score_half_width" => {
            "is required (missing): the target half-width of the score's confidence interval, a number > 0 in the score's unit"
        }
        "mesh.elements" => "is required: the number of beam elements, an integer in [1, 2000]",
        "mesh.basis.bending" | "mesh.basis.torsional" | "mesh.basis.axial" => {
            "is required: the family's modes, an integer count in [1, mesh.elements] or a cutoff frequency such as \"60 Hz\""
        }
        "uncertain.samples" => {
            "is required: the Monte Carlo samples per point, an integer in [1, 10000]"
        }
        "uncertain.parameter[*].key" => {
            "is required: the problem key the law varies (e.g. \"model.wall.friction\")"
        }
        "uncertain.parameter[*].law" => {
            "is required: the sampling law, one of \"gamma\", \"lognormal\", \"normal\", \"uniform\""
        }
        "objective.risk[*].weight" => {
            "is required: the penalty's weight, a finite number >= 0 (score units per metric unit)"
        }
        "constraints.chance[*].threshold" => {
            "is required: the metric's limit, in the metric's unit (e.g. 1.5 for stick_slip_severity)"
        }
        "constraints.chance[*].max_probability" => {
            "is required: the largest admissible probability of exceeding the threshold, in [0, 1)"
        }
        _ => return None,
    }
    .to_string())
}

/// The key named in serde's "missing field `x`" / "unknown field `x`" messages.
fn missing_or_unknown_key(message: &str) -> Option<String> {
    let rest = message
        .strip_prefix("missing field `")
        .or_else(|| message.strip_prefix("unknown field `"))?;
    rest.split('`').next().map(str::to_string)
}

fn syntax(text: &str, file: &Path, e: &toml::de::Error) -> ProblemError {
    let (line, column) = e.span().map_or((0, 0), |span| {
        let before = &text[..span.start.min(text.len())];
        let line = before.matches('\n').count() + 1;
        let column = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
        (line, column)
    });
    let mut message = e.message().to_string();
    // toml says "duplicate key" and points at it: name it, and the rule.
    if message.trim_end() == "duplicate key"
        && let Some(key) = e
            .span()
            .and_then(|span| text.get(span))
            .map(|k| k.trim().trim_matches('"'))
            .filter(|k| !k.is_empty() && k.len() <= 100 && !k.contains('\n'))
    {
        let header = text
            .lines()
            .nth(line.saturating_sub(1))
            .is_some_and(|l| l.trim_start().starts_with('['));
        message = if header {
            format!(
                "duplicate key `{key}`: this table header is given twice (merge the two tables)"
            )
        } else {
            format!(
                "duplicate key `{key}`: a key is given once per table (remove one of the two lines)"
            )
        };
    }
    // toml reads integers beyond 64 bits as "invalid type: integer `…` as i128".
    if let Some(digits) = message
        .strip_prefix("invalid type: integer `")
        .and_then(|rest| rest.split('`').next())
        .filter(|_| message.contains(" as i128"))
    {
        message = format!(
            "the integer {digits} is beyond TOML's 64-bit integers (at most {}): write a smaller value, or a float such as 1e20 where a number is meant",
            i64::MAX
        );
    }
    ProblemError::Syntax {
        file: file.to_path_buf(),
        line,
        column,
        message,
    }
}

/// The longest problem name, in bytes: a folder name of the usual filesystems.
const MAX_NAME_BYTES: usize = 200;

/// Check every section of `raw`, recording every refusal (see [`Checker`]); `shape` holds the
/// refusals of the parse.
pub(super) fn problem(
    raw: ProblemFile,
    file: &Path,
    shape: Vec<KeyError>,
    masked: Vec<String>,
) -> Result<Problem, ProblemError> {
    let c = Checker::new(file, shape, masked);
    let model = c.section(drillstring(&c, &raw.model));
    let mesh = c.section(mesh(&c, &raw.mesh));
    let graded: Option<usize> = model.as_ref().and_then(|m| {
        (m.sections.iter())
            .map(|s| s.elements)
            .sum::<Option<usize>>()
            .filter(|_| !m.sections.is_empty())
    });
    if let (Some(sum), Some(mesh)) = (graded, &mesh)
        && mesh.elements != sum
    {
        c.record(
            "mesh.elements",
            format!(
                "must be the sum of the sections' elements ({sum}) when they give them, got {}",
                mesh.elements
            ),
        );
    }
    if let (Some(m), Some(mesh)) = (&model, &mesh)
        && mesh.elements < m.sections.len()
    {
        c.record(
            "mesh.elements",
            format!(
                "must be at least the number of [[model.section]] ({}): every section needs an element, got {}",
                m.sections.len(),
                mesh.elements
            ),
        );
    }
    let top = c.section(super::validate_top::top(&c, &raw.operating_point));
    let operating_point = c.section(operating_point(&c, &raw.operating_point, top));
    let mut model = model;
    if let (Some(m), Some(top)) = (model.as_mut(), top) {
        m.top = top;
    }
    let length = model.as_ref().map_or(f64::NAN, |m| m.length);
    let simulation = c.section(simulation(&c, &raw.simulation, length));
    let mut study = model
        .as_ref()
        .and_then(|m| c.section(super::validate_study::study(&c, &raw, m)));
    // [optimizer.explore] overrides the window, the basis and the samples: read against them.
    if let (Some(s), Some(e)) = (
        study.as_mut(),
        raw.optimizer.as_ref().and_then(|o| o.explore.as_ref()),
    ) {
        s.explore = super::validate_explore::explore(&c, e, mesh.as_ref(), simulation.as_ref(), s);
    }
    let blades = model.as_ref().and_then(|m| m.bit.blades());
    let campbell = c.section(campbell(&c, raw.campbell.as_ref(), blades));
    // The name is a folder of results/: what a filesystem takes as one folder name (at most 255
    // bytes on the usual ones; a NUL or a 300-character name failed only when the output was made).
    let name = match raw.name {
        Some(n)
            if n.trim().is_empty()
                || n.contains(['/', '\\'])
                || n.chars().any(char::is_control)
                || n.len() > MAX_NAME_BYTES
                || n == "."
                || n == ".." =>
        {
            let got = if n.len() > MAX_NAME_BYTES {
                format!("a name of {} bytes", n.len())
            } else {
                format!("{n:?}")
            };
            c.record(
                "name",
                format!(
                    "must be a non-empty name without path separators or control characters, at \
                     most {MAX_NAME_BYTES} bytes, not `.` or `..` (it names the results folder), got {got}"
                ),
            );
            n
        }
        Some(n) => n,
        None => file
            .file_stem()
            .map_or_else(|| "problem".into(), |s| s.to_string_lossy().into_owned()),
    };
    c.finish()?;
    let missing = "a section without refusals";
    Ok(Problem {
        name,
        description: raw.description.unwrap_or_default(),
        source: file.to_path_buf(),
        text: String::new(),
        model: model.expect(missing),
        mesh: mesh.expect(missing),
        operating_point: operating_point.expect(missing),
        simulation: simulation.expect(missing),
        study: study.expect(missing),
        campbell: campbell.expect(missing),
    })
}

/// `[campbell]`: the excitation multiple, a number in [1, 50]; without it the bit's blade count
/// `blades` of a depth-of-cut law, else 3 (a tri-cone bit).
fn campbell(
    c: &Checker,
    s: Option<&CampbellSection>,
    blades: Option<u32>,
) -> Result<CampbellSettings, ProblemError> {
    let raw = s.and_then(|s| s.excitation_multiple.as_ref());
    let excitation_multiple = c.key_value("campbell.excitation_multiple", raw)?;
    Ok(match (raw, blades) {
        (Some(_), _) => CampbellSettings {
            excitation_multiple,
            source: MultipleSource::File,
        },
        (None, Some(n)) => CampbellSettings {
            excitation_multiple: f64::from(n),
            source: MultipleSource::Blades,
        },
        (None, None) => CampbellSettings {
            excitation_multiple,
            source: MultipleSource::Default,
        },
    })
}

fn drillstring(c: &Checker, m: &ModelSection) -> Result<Drillstring, ProblemError> {
    use Dimension::*;
    let length = c.positive("model.length", &m.length, Length)?;
    let gravity = c.key_value("model.gravity", m.gravity.as_ref())?;
    let mut pipe = pipe(c, &m.pipe)?;
    let fluid_density = c.non_negative("model.fluid.density", &m.fluid.density, Density)?;
    let annulus_density = c.key_value(
        "model.fluid.annulus_density",
        m.fluid.annulus_density.as_ref(),
    )?;
    let (borehole_radius, hole_key) = borehole_radius(c, &m.borehole)?;
    let sections =
        super::validate_sections::sections(c, &m.section, &pipe, length, borehole_radius);
    // Within the rounding the check allows, the string is the sum of its sections (the length
    // as written when the two agree to round-off).
    let total: f64 = sections.iter().map(|s| s.length).sum();
    let length = if sections.is_empty() || (total - length).abs() <= 1e-9 * length {
        length
    } else {
        total
    };
    // The sizes: [model.pipe]'s for a string of one section, each section's otherwise (the
    // first section's then stand in [model.pipe], whose sizes nothing else reads).
    for (key, given) in [
        ("model.pipe.inner_radius", m.pipe.inner_radius.is_some()),
        ("model.pipe.outer_radius", m.pipe.outer_radius.is_some()),
    ] {
        match (given, sections.is_empty()) {
            (false, true) => {
                c.record(
                    key,
                    "is required (or give the string's [[model.section]], each with its own sizes)"
                        .to_string(),
                );
            }
            (true, false) => {
                c.record(key, "is not used beside [[model.section]]: each section gives its own sizes (outer_radius or outer_diameter, inner_radius, inner_diameter or linear_weight); remove it".to_string());
            }
            _ => {}
        }
    }
    if let Some(first) = sections.first() {
        pipe.inner_radius = first.pipe.inner_radius;
        pipe.outer_radius = first.pipe.outer_radius;
        if pipe.shear_factor.is_nan() {
            pipe.shear_factor = first.pipe.shear_factor;
        }
        if pipe.torsion_factor.is_nan() {
            pipe.torsion_factor = first.pipe.torsion_factor;
        }
    }
    // With sections, each section's fit in the hole is checked with the section.
    if sections.is_empty() {
        c.check(
            hole_key,
            borehole_radius,
            borehole_radius > pipe.outer_radius || pipe.outer_radius.is_nan(),
            &format!(
                "greater than model.pipe.outer_radius ({} m): the pipe must fit in the hole",
                pipe.outer_radius
            ),
            Length,
        )?;
    }
    let damping = c.non_negative("model.pipe.damping", &m.pipe.damping, Rate)?;
    let stiffness_damping = c.key_value(
        "model.pipe.stiffness_damping",
        m.pipe.stiffness_damping.as_ref(),
    )?;
    // `friction_law` and `slip_smoothing` say how the law's friction acts, whatever the law:
    // taken out before the law's table is checked.
    let mut wall_section = m.wall.clone();
    let wall_friction = wall_friction(
        c,
        wall_section.parameters.remove("friction_law"),
        wall_section.parameters.remove("slip_smoothing"),
    )?;
    // The laws' `sign_smoothing` smooths the paper's torque-only friction: under the Coulomb
    // friction it would be read and change nothing.
    if matches!(wall_friction, WallFriction::Coulomb { .. })
        && wall_section.parameters.contains_key("sign_smoothing")
    {
        c.record(
            "model.wall.sign_smoothing",
            "belongs to friction_law = \"paper\" (the paper's torque-only friction, smoothed in \
             the spin); the Coulomb friction (the default friction_law) is smoothed by \
             slip_smoothing: remove it, or set friction_law = \"paper\""
                .to_string(),
        );
    }
    let wall_stiffness_per = wall_stiffness_per(c, wall_section.parameters.remove("stiffness_per"));
    let wall = chosen_law(
        c,
        "model.wall",
        &wall_section,
        WALL_LAWS,
        &["law", "friction_law", "slip_smoothing", "stiffness_per"],
    )?;
    // `inertia` belongs to the bit, not to its law: taken out before the law's table is checked.
    let mut bit_section = m.bit.clone();
    let inertia = bit_section.parameters.remove("inertia");
    let bit = chosen_law(c, "model.bit", &bit_section, BIT_LAWS, &["law", "inertia"])?;
    let bit_key = if bit_section.parameters.contains_key("diameter") {
        "model.bit.diameter"
    } else {
        "model.bit.radius"
    };
    bit_in_its_hole(c, bit.radius(), borehole_radius, hole_key, bit_key);
    let bit_inertia = c.key_value("model.bit.inertia", inertia.as_ref())?;
    Ok(Drillstring {
        bit_inertia,
        length,
        pipe,
        sections,
        fluid_density,
        annulus_density,
        borehole_radius,
        damping,
        stiffness_damping,
        gravity,
        wall,
        wall_friction,
        wall_stiffness_per,
        bit,
        // Set from `[operating_point]` by `problem`.
        top: crate::model::TopDrive::Feed,
    })
}

/// `[model.borehole]`: the hole's `radius`, or its `diameter` (the bit size a driller gives,
/// "8½ in"), halved and checked against the radius' range; exactly one of the two. Returns the
/// radius and the key the file gave it by, which the later checks of the hole name.
fn borehole_radius(c: &Checker, b: &BoreholeSection) -> Result<(f64, &'static str), ProblemError> {
    let key = "model.borehole.radius";
    let dkey = "model.borehole.diameter";
    match (&b.radius, &b.diameter) {
        (Some(r), None) => Ok((c.positive(key, r, Dimension::Length)?, key)),
        (None, Some(d)) => {
            let v = c.value_as(dkey, "", d, Dimension::Length);
            let r = match super::keys::range_of(key) {
                Some(range) => half_of_diameter(c, dkey, v, d, range),
                None => 0.5 * v,
            };
            Ok((r, dkey))
        }
        (Some(_), Some(_)) => Ok((
            c.record(dkey, "give radius or diameter, not both".to_string()),
            dkey,
        )),
        // A key of the two refused as written (a wrong type) is not also called missing.
        (None, None) if c.refused_under(key) || c.refused_under(dkey) => Ok((f64::NAN, key)),
        (None, None) => Ok((
            c.record(
                key,
                "is required: the hole's size as radius or diameter (an 8½ in hole: diameter = \
                 \"8.5 in\")"
                    .to_string(),
            ),
            key,
        )),
    }
}

/// A bit law with a size (`[model.bit] radius` or `diameter`) must drill the hole it is in: its
/// radius at most the hole's, and the hole at most
/// [`crate::model::parameters::MAX_HOLE_OVER_BIT`] times the bit's (each recorded under the key
/// the file gave it by, `hole_key` and `bit_key`, in mm and in).
fn bit_in_its_hole(
    c: &Checker,
    bit_radius: Option<f64>,
    borehole_radius: f64,
    hole_key: &str,
    bit_key: &str,
) {
    let Some(a) = bit_radius else { return };
    if !(a.is_finite() && borehole_radius.is_finite()) {
        return;
    }
    let sizes = format!(
        "a bit {} mm ({} in) across in a hole {} mm ({} in) across",
        crate::units::short(2e3 * a),
        crate::units::short(2.0 * a / 0.0254),
        crate::units::short(2e3 * borehole_radius),
        crate::units::short(2.0 * borehole_radius / 0.0254)
    );
    if a > borehole_radius * (1.0 + 1e-9) {
        let (size, advice) = if bit_key.ends_with("diameter") {
            ("diameter", "")
        } else {
            ("radius", " (a radius is half the bit size)")
        };
        c.record(
            bit_key,
            format!(
                "must be at most the hole's {size}: the bit drills the hole it is in, got \
                 {sizes}{advice}"
            ),
        );
    } else if borehole_radius > crate::model::parameters::MAX_HOLE_OVER_BIT * a {
        let advice = if bit_key.ends_with("diameter") {
            "the hole's and the bit's sizes are their diameters (an 8½ in bit in its hole: \
             diameter = \"8.5 in\" for both)"
        } else if hole_key.ends_with("diameter") {
            "a bit's radius is half its size (an 8½ in bit: radius = \"4.25 in\", or \
             diameter = \"8.5 in\")"
        } else {
            "a radius is half the hole size (an 8½ in hole: radius = \"4.25 in\", or diameter = \
             \"8.5 in\")"
        };
        c.record(
            hole_key,
            format!(
                "must be at most {} times the bit's {} (a hole widened by a reamer or a \
                 washout), got {sizes}: {advice}",
                crate::model::parameters::MAX_HOLE_OVER_BIT,
                if hole_key.ends_with("diameter") {
                    "diameter"
                } else {
                    "radius"
                }
            ),
        );
    }
}

/// `[model.wall] stiffness_per` (`"length"`, the default, or `"node"`, the paper's reading; see
/// [`WallStiffnessPer`]). A bad value is recorded and read as the default, so the rest of the
/// file is still checked.
fn wall_stiffness_per(c: &Checker, raw: Option<RawQuantity>) -> WallStiffnessPer {
    let key = "model.wall.stiffness_per";
    let allowed = "\"length\" (the law's stiffness and damping per metre of string, each node carrying its tributary length) or \"node\" (per node of the mesh, the paper's reading)";
    match &raw {
        None => WallStiffnessPer::default(),
        Some(RawQuantity::Text(t)) => WallStiffnessPer::from_name(t.trim()).unwrap_or_else(|| {
            c.record(key, format!("must be {allowed}, got \"{}\"", t.trim()));
            WallStiffnessPer::default()
        }),
        Some(RawQuantity::Number(x)) => {
            c.record(
                key,
                format!(
                    "must be a string, {allowed}, got the number {}",
                    crate::units::show(*x)
                ),
            );
            WallStiffnessPer::default()
        }
    }
}

/// `[model.wall] friction_law` (`"coulomb"`, the default, or `"paper"`) and the Coulomb law's
/// `slip_smoothing` (m/s; refused with the paper's friction, which has none).
fn wall_friction(
    c: &Checker,
    law: Option<RawQuantity>,
    smoothing: Option<RawQuantity>,
) -> Result<WallFriction, ProblemError> {
    let key = "model.wall.friction_law";
    let name = match &law {
        None => "coulomb".to_string(),
        Some(RawQuantity::Text(t)) => t.trim().to_string(),
        Some(RawQuantity::Number(x)) => {
            c.record(
                key,
                format!(
                    "must be a string, \"coulomb\" or \"paper\", got the number {}",
                    crate::units::show(*x)
                ),
            );
            return Ok(WallFriction::COULOMB);
        }
    };
    let smoothing_key = "model.wall.slip_smoothing";
    match name.as_str() {
        "coulomb" => {
            let slip_smoothing = c.key_value(smoothing_key, smoothing.as_ref())?;
            Ok(WallFriction::Coulomb { slip_smoothing })
        }
        "paper" => {
            if smoothing.is_some() {
                c.record(
                    smoothing_key,
                    "belongs to friction_law = \"coulomb\"; the paper's friction is smoothed by sign_smoothing".to_string(),
                );
            }
            Ok(WallFriction::Paper)
        }
        other => {
            c.record(
                key,
                format!(
                    "must be \"coulomb\" (Coulomb friction on the slip of the contact point: axial drag, torque with lever R_ext, the circumferential force) or \"paper\" (the paper's torque-only friction with lever R_bh), got \"{other}\""
                ),
            );
            Ok(WallFriction::COULOMB)
        }
    }
}

/// A law table (`[model.wall]`, `[model.bit]`, named `table`): the law of `registry` named by
/// `law` (the registry's first when omitted), every parameter of its table read and checked
/// against its range. Unknown keys and missing required parameters are recorded, each with every
/// key the table accepts named (`own`: the table's keys besides the law's parameters, such as
/// `law` and the bit's `inertia`), and the rest is still checked; an unknown law ends the table.
/// A law with a `radius` (a bit's) also takes it as `diameter` (the bit size a driller gives,
/// "8½ in"), halved and checked against the radius' range; not both.
fn chosen_law<L: ?Sized + Law>(
    c: &Checker,
    table: &str,
    section: &LawSection,
    registry: &'static [LawEntry<L>],
    own: &[&str],
) -> Result<Chosen<L>, ProblemError> {
    // A law's name that is not a string ends the table, as an unknown name does.
    if let Some((_, what)) = section.invalid.iter().find(|(k, _)| k == "law") {
        return Err(c.fail(
            &format!("{table}.law"),
            format!("must be a law's name as a string, got {what}"),
        ));
    }
    let entry = match &section.law {
        None => &registry[0],
        Some(name) => find(registry, name).ok_or_else(|| {
            let names: Vec<String> = registry.iter().map(|e| format!("{:?}", e.name)).collect();
            c.fail(
                &format!("{table}.law"),
                format!("must be one of {}, got {name:?}", names.join(", ")),
            )
        })?,
    };
    for (key, what) in &section.invalid {
        c.record(
            &format!("{table}.{key}"),
            format!(
                "must be a number in SI units or a string with a unit such as \"60 rpm\", got \
                 {what}"
            ),
        );
    }
    let refused = |name: &str| section.invalid.iter().any(|(k, _)| k == name);
    let names: Vec<&str> = entry.parameters.iter().map(|p| p.name()).collect();
    let sized = names.contains(&"radius");
    for unknown in section.parameters.keys() {
        let accepted = names.contains(&unknown.as_str()) || (sized && unknown == "diameter");
        if !accepted {
            c.record(
                &format!("{table}.{unknown}"),
                format!(
                    "unknown field: [{table}] accepts {} and the parameters of law = {:?}: {}{}",
                    own.join(", "),
                    entry.name,
                    names.join(", "),
                    size_hint(registry, sized, unknown)
                ),
            );
        }
    }
    let values = entry
        .parameters
        .iter()
        .map(|p| match (section.parameters.get(p.name()), p.default) {
            _ if p.name() == "radius" && section.parameters.contains_key("diameter") => {
                Ok(law_radius_from_diameter(c, table, section, p))
            }
            (Some(raw), _) => c.spec_value(p, raw),
            (None, Some(default)) => Ok(default),
            // Refused as written above: not also called missing.
            (None, None) if refused(p.name()) || (p.name() == "radius" && refused("diameter")) => {
                Ok(f64::NAN)
            }
            (None, None) => Ok(c.record(
                p.key,
                format!(
                    "is required by law = {:?} ({}): a value {}",
                    entry.name,
                    p.doc,
                    p.range.describe(p.dimension)
                ),
            )),
        })
        .collect::<Result<Vec<f64>, _>>()?;
    Ok(Chosen::from_entry(entry, &values))
}

/// The end of an unknown-key refusal of a law table: that `diameter` may stand for the law's
/// `radius`, or, for a size given to a law without one, which laws of the registry have one.
fn size_hint<L: ?Sized + Law>(registry: &[LawEntry<L>], sized: bool, unknown: &str) -> String {
    if sized {
        return " (or diameter for radius)".to_string();
    }
    if !matches!(unknown, "diameter" | "radius") {
        return String::new();
    }
    let with_size: Vec<String> = (registry.iter())
        .filter(|e| e.parameters.iter().any(|p| p.name() == "radius"))
        .map(|e| format!("{:?}", e.name))
        .collect();
    if with_size.is_empty() {
        String::new()
    } else {
        format!(
            "; a size (radius or diameter) belongs to law = {}",
            with_size.join(" or ")
        )
    }
}

/// The `radius` parameter `spec` of a law table given as its `diameter` (present in `section`):
/// half of it, within the radius' range (recorded under `{table}.diameter` otherwise, or when the
/// table gives both).
fn law_radius_from_diameter(
    c: &Checker,
    table: &str,
    section: &LawSection,
    spec: &crate::model::ParameterSpec,
) -> f64 {
    let dkey = format!("{table}.diameter");
    if section.parameters.contains_key("radius") {
        return c.record(&dkey, "give radius or diameter, not both".to_string());
    }
    let raw = &section.parameters["diameter"];
    let v = c.value_as(&dkey, "", raw, spec.dimension);
    half_of_diameter(c, &dkey, v, raw, spec.range)
}

/// The radius of the diameter `v` (m) read under `dkey` from `raw`, when it lies within twice
/// the radius' `range`; refused under `dkey` otherwise, with the diameters' range and the value
/// as written.
fn half_of_diameter(
    c: &Checker,
    dkey: &str,
    v: f64,
    raw: &RawQuantity,
    range: crate::units::Range,
) -> f64 {
    let r = 0.5 * v;
    if r.is_nan() || range.contains(r) {
        return r;
    }
    let diameters = crate::units::Range {
        lo: 2.0 * range.lo,
        hi: 2.0 * range.hi,
        ..range
    };
    c.record(
        dkey,
        format!(
            "must be {} as a diameter, twice the radius', got {}",
            diameters.describe_in("m", 1.0),
            super::check::got(v, "m", 1.0, raw)
        ),
    )
}

fn pipe(c: &Checker, p: &PipeSection) -> Result<Pipe, ProblemError> {
    use Dimension::*;
    let density = c.positive("model.pipe.density", &p.density, Density)?;
    let youngs_modulus = c.positive("model.pipe.youngs_modulus", &p.youngs_modulus, Pressure)?;
    let poisson_ratio = c.value("model.pipe.poisson_ratio", &p.poisson_ratio, Dimensionless)?;
    // Absent: NaN here, required or taken from the first section by `drillstring`.
    let inner_radius = match &p.inner_radius {
        Some(raw) => c.non_negative("model.pipe.inner_radius", raw, Length)?,
        None => f64::NAN,
    };
    let outer_radius = match &p.outer_radius {
        Some(raw) => c.positive("model.pipe.outer_radius", raw, Length)?,
        None => f64::NAN,
    };
    c.check(
        "model.pipe.outer_radius",
        outer_radius,
        outer_radius > inner_radius || inner_radius.is_nan(),
        &format!("greater than model.pipe.inner_radius ({inner_radius} m)"),
        Length,
    )?;
    let cowper = cowper_shear_factor(poisson_ratio, inner_radius, outer_radius);
    // The factors' range (keys::range_of) excludes 1e-300, which removed the section's shear
    // stiffness and failed in the eigen-solve naming other keys.
    let factor =
        |key: &str, raw: &Option<RawQuantity>, word: &str, word_value: f64, default: f64| {
            let range = super::keys::range_of(key).expect("the factors have a range");
            let allowed = format!("a number {} or \"{word}\"", range.describe_in("", 1.0));
            match raw {
                None => Ok(default),
                Some(RawQuantity::Text(t)) if t == word => Ok(word_value),
                Some(RawQuantity::Text(t)) => {
                    Ok(c.record(key, format!("`{t}` is not allowed; expected {allowed}")))
                }
                // `check` passes a NaN as refused already; this one comes from the file.
                Some(RawQuantity::Number(v)) if v.is_nan() => {
                    Ok(c.record(key, format!("must be {allowed}, got NaN")))
                }
                Some(RawQuantity::Number(v)) => {
                    c.check(key, *v, range.contains(*v), &allowed, Dimensionless)
                }
            }
        };
    let shear_factor = factor(
        "model.pipe.shear_factor",
        &p.shear_factor,
        "cowper",
        cowper,
        cowper,
    )?;
    let torsion_factor = factor(
        "model.pipe.torsion_factor",
        &p.torsion_factor,
        "shear",
        shear_factor,
        1.0,
    )?;
    let yield_strength = match &p.yield_strength {
        None => None,
        Some(raw) => yield_strength(c, "model.pipe.yield_strength", raw)?,
    };
    let fatigue = super::validate_fatigue::fatigue(c, p.fatigue.as_ref())?;
    Ok(Pipe {
        density,
        youngs_modulus,
        poisson_ratio,
        inner_radius,
        outer_radius,
        shear_factor,
        torsion_factor,
        yield_strength,
        fatigue,
    })
}

/// The most radial probes a run records (`simulation.probes`).
pub const MAX_PROBES: usize = 32;

fn mesh(c: &Checker, m: &MeshSection) -> Result<Mesh, ProblemError> {
    if !(1..=MAX_ELEMENTS).contains(&m.elements) {
        return Err(c.fail(
            "mesh.elements",
            format!(
                "must be an integer in [1, {MAX_ELEMENTS}], got {}",
                m.elements
            ),
        ));
    }
    let elements = m.elements as usize;
    let free = 6 * elements - 2; // 6(N+1) DOFs less the 8 constrained (MODEL.md §4)
    let basis = match (&m.reduced_modes, &m.basis) {
        (Some(_), Some(_)) => {
            return Err(c.fail(
                "mesh.basis",
                "give either mesh.reduced_modes (the N lowest modes) or [mesh.basis] (modes per family), not both".into(),
            ));
        }
        (Some(n), None) => {
            if *n < 1 || *n as usize > free {
                return Err(c.fail(
                    "mesh.reduced_modes",
                    format!(
                        "must be an integer in [1, {free}] (the free DOFs of {elements} elements), got {n}"
                    ),
                ));
            }
            BasisSpec::Lowest(*n as usize)
        }
        (None, Some(b)) => {
            let static_corrections = b.static_corrections.unwrap_or(true);
            if b.steady_shapes == Some(true) && !static_corrections {
                return Err(c.fail(
                    "mesh.basis.steady_shapes",
                    "needs the static corrections (the steady state's shapes join the resting shapes): set static_corrections = true or leave steady_shapes out, got true".into(),
                ));
            }
            BasisSpec::PerFamily {
                bending: family_size(c, "mesh.basis.bending", &b.bending, elements)?,
                torsional: family_size(c, "mesh.basis.torsional", &b.torsional, elements)?,
                axial: family_size(c, "mesh.basis.axial", &b.axial, elements)?,
                static_corrections,
                steady_shapes: b.steady_shapes.unwrap_or(false),
            }
        }
        (None, None) => BasisSpec::DEFAULT,
    };
    Ok(Mesh { elements, basis })
}

/// The operating point of `[operating_point]` under `top` (the feed when the top was refused):
/// Ω with the feed V0 (tops `feed`, `autodriller`) or the hook load's WOB set-point; the
/// other top's set-point is refused, not ignored.
fn operating_point(
    c: &Checker,
    o: &OperatingPointSection,
    top: Option<crate::model::TopDrive>,
) -> Result<OperatingPoint, ProblemError> {
    let omega = c.positive(
        "operating_point.omega",
        &o.omega,
        Dimension::AngularVelocity,
    )?;
    if matches!(top, Some(crate::model::TopDrive::HookLoad)) {
        if o.v0.is_some() {
            c.record(
                "operating_point.v0",
                "is the feed of the other tops: under top = \"hook_load\" the set-point is wob \
                 and the rock and the string decide the feed; remove it"
                    .into(),
            );
        }
        let wob = match &o.wob {
            Some(raw) => c.value_as(
                "operating_point.wob",
                "operating_point.wob",
                raw,
                Dimension::Force,
            ),
            None => c.record(
                "operating_point.wob",
                "is required with top = \"hook_load\": the surface WOB set-point (e.g. \"50 kN\")"
                    .into(),
            ),
        };
        return Ok(OperatingPoint::hook_load(omega, wob));
    }
    let v0 = match &o.v0 {
        // V0 = 0 is off-bottom rotation, a normal drilling state.
        Some(raw) => c.non_negative("operating_point.v0", raw, Dimension::Velocity)?,
        None => c.record(
            "operating_point.v0",
            "is required: the feed V0 (e.g. \"5 m/h\"; with top = \"hook_load\" the set-point is wob instead)"
                .into(),
        ),
    };
    Ok(OperatingPoint::feed(omega, v0))
}

fn simulation(c: &Checker, s: &SimulationSection, length: f64) -> Result<Simulation, ProblemError> {
    use Dimension::*;
    let duration = c.positive("simulation.duration", &s.duration, Time)?;
    let time_step = c.positive("simulation.time_step", &s.time_step, Time)?;
    c.check(
        "simulation.time_step",
        time_step,
        time_step <= duration || duration.is_nan(),
        &format!("no longer than simulation.duration ({duration} s)"),
        Time,
    )?;
    let settling_time = match &s.settling_time {
        Some(t) => {
            let t = c.non_negative("simulation.settling_time", t, Time)?;
            c.check(
                "simulation.settling_time",
                t,
                t <= 0.5 * duration || duration.is_nan(),
                &format!(
                    "at most half of simulation.duration ({duration} s): the metrics are read \
                     over the window after it, which must be no shorter than what it discards"
                ),
                Time,
            )?
        }
        None => 0.0,
    };
    if s.probes.len() > MAX_PROBES {
        // Each probe is a column of the time series and a plot of its own: 100 000 probes took
        // 40 s for 0.01 s of simulated time.
        c.record(
            "simulation.probes",
            format!(
                "{} positions: at most {MAX_PROBES} radial probes (each is a column of timeseries.csv and a plot); the stress envelope covers every element",
                s.probes.len()
            ),
        );
    }
    let probes = s
        .probes
        .iter()
        .take(MAX_PROBES)
        .enumerate()
        .map(|(i, p)| {
            let key = format!("simulation.probes[{i}]");
            let x = c.value(&key, p, Length)?;
            c.check(
                &key,
                x,
                (0.0..=length).contains(&x) || length.is_nan(),
                &format!("in [0, model.length = {length} m]"),
                Length,
            )
        })
        .collect::<Result<Vec<f64>, _>>()?;
    // Each probe is a column of timeseries.csv and a plot named by its position: a repeated
    // position would write two columns of one name and one plot over the other.
    for (j, x) in probes.iter().enumerate() {
        if let Some(i) = probes[..j].iter().position(|y| y == x) {
            c.record(
                &format!("simulation.probes[{j}]"),
                format!(
                    "{} m repeats simulation.probes[{i}]: each probe is a column of timeseries.csv and a plot named by its position, so positions must differ",
                    crate::units::short(*x)
                ),
            );
        }
    }
    let start = match s.start.as_deref() {
        None | Some("preloaded") => Start::Preloaded,
        Some("unloaded") => Start::Unloaded,
        Some(other) => {
            return Err(c.fail(
                "simulation.start",
                format!(
                    "must be \"preloaded\" (the steady drilling state of the operating point) or \"unloaded\" (the paper's static state without bit load), got \"{other}\""
                ),
            ));
        }
    };
    let sample_interval = match &s.sample_interval {
        None => SampleInterval::DEFAULT,
        Some(RawQuantity::Text(t)) if t.trim() == "step" => SampleInterval::EveryStep,
        Some(raw) => {
            let key = "simulation.sample_interval";
            let dt = c.positive(key, raw, Time)?;
            let dt = c.check(
                key,
                dt,
                dt <= duration || duration.is_nan(),
                &format!("no longer than simulation.duration ({duration} s), or \"step\""),
                Time,
            )?;
            SampleInterval::Fixed(dt)
        }
    };
    Ok(Simulation {
        duration,
        time_step,
        settling_time,
        probes,
        start,
        sample_interval,
    })
}
