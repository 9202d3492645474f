//! `[[model.section]]`: a string of sections (MODEL.md §11.5), top drive to bit.
//!
//! Each section names itself and gives its length and its outer and inner size, as a radius or a
//! diameter (drill-pipe tables give OD and ID); its material keys (`density`,
//! `youngs_modulus`, `poisson_ratio`, `yield_strength`, `torsion_factor`) default to
//! `[model.pipe]`'s, its `shear_factor` to Cowper's for its own radii, and every section shares
//! `[model.pipe.fatigue]`. The lengths must add up to `[model] length`. Every refusal names the
//! section's key (`model.section[2].outer_diameter`) and the section by name, and all of them are
//! reported in one pass.

/// The thinnest pipe wall a section's linear weight may imply, m.
const MIN_WALL_M: f64 = 1e-4;

use super::Dimension;
use super::check::{Checker, yield_strength};
use super::schema::{RawQuantity, SectionTable};
use crate::model::{Pipe, StringSection, cowper_shear_factor};
use crate::units::{short, show};

/// At most this many sections: far beyond a real string's few (pipe, heavy-weight pipe, jars,
/// collars, stabilisers, motor).
pub const MAX_SECTIONS: usize = 200;

/// Tolerance on the sum of the section lengths against `[model] length`, m: the rounding of a
/// length written in feet or inches to two decimals (±0.005 ft = 1.5 mm over a section, a
/// few sections) is accepted, and the string is the sum of its sections.
pub const LENGTH_TOLERANCE_M: f64 = 0.01;

/// The sections of `tables` (empty when the file gives none), each refusal recorded in `c`.
pub(super) fn sections(
    c: &Checker,
    tables: &[SectionTable],
    pipe: &Pipe,
    length: f64,
    borehole_radius: f64,
) -> Vec<StringSection> {
    if tables.is_empty() {
        return Vec::new();
    }
    if tables.len() > MAX_SECTIONS {
        c.record(
            "model.section",
            format!("at most {MAX_SECTIONS} sections, got {}", tables.len()),
        );
        return Vec::new();
    }
    let sections: Vec<StringSection> = (tables.iter().enumerate())
        .map(|(i, t)| section(c, i, t, pipe, borehole_radius))
        .collect();
    for (i, s) in sections.iter().enumerate() {
        if let Some(j) = sections[..i].iter().position(|o| o.name == s.name) {
            c.record(
                &format!("model.section[{i}].name"),
                format!(
                    "\"{}\" is also the name of model.section[{j}]: each section needs its own name",
                    s.name
                ),
            );
        }
    }
    let given = tables.iter().filter(|t| t.elements.is_some()).count();
    if given > 0 && given < tables.len() {
        let missing = (tables.iter().position(|t| t.elements.is_none())).unwrap_or(0);
        c.record(
            &format!("model.section[{missing}].elements"),
            format!(
                "is required once any section gives its elements ({given} of {} do): a graded mesh gives every section's count, or none (then [mesh] elements is shared out by length)",
                tables.len()
            ),
        );
    }
    let total: f64 = sections.iter().map(|s| s.length).sum();
    if total.is_finite() && length.is_finite() && (total - length).abs() > LENGTH_TOLERANCE_M {
        let list: Vec<String> = (sections.iter())
            .map(|s| format!("{} {} m", s.name, short(s.length)))
            .collect();
        c.record(
            "model.length",
            format!(
                "must be the sum of the sections' lengths ({}: {} m, within {LENGTH_TOLERANCE_M} m), got {} m",
                list.join(" + "),
                short(total),
                short(length)
            ),
        );
    }
    sections
}

/// Section `i` of the file, `[model.pipe]` supplying the material keys it does not give.
fn section(
    c: &Checker,
    i: usize,
    t: &SectionTable,
    pipe: &Pipe,
    borehole_radius: f64,
) -> StringSection {
    use Dimension::*;
    let key = |k: &str| format!("model.section[{i}].{k}");
    let name = match &t.name {
        Some(n) if !n.trim().is_empty() => n.trim().to_string(),
        _ => {
            c.record(
                &key("name"),
                "is required: a name for the section (\"drill pipe\", \"collars\", \"stabiliser\")"
                    .to_string(),
            );
            format!("section {i}")
        }
    };
    let of = format!("(section \"{name}\")");
    // A quantity the section must give, checked against the range of `range_key`.
    let required = |k: &str, raw: &Option<RawQuantity>, range_key: &str, dim: Dimension| match raw {
        Some(raw) => c.value_as(&key(k), range_key, raw, dim),
        None => c.record(&key(k), format!("is required {of}")),
    };
    // A size given as a radius or a diameter, exactly one of them.
    let size =
        |radius: &Option<RawQuantity>, diameter: &Option<RawQuantity>, which: &str| {
            let range_key = format!("model.pipe.{which}_radius");
            match (radius, diameter) {
            (Some(r), None) => c.value_as(&key(&format!("{which}_radius")), &range_key, r, Length),
            (None, Some(d)) => {
                // No range of its own: the radius it halves to is checked below.
                let v = c.value_as(&key(&format!("{which}_diameter")), "", d, Length);
                let r = 0.5 * v;
                match super::keys::range_of(&range_key) {
                    Some(range) if !r.is_nan() && !range.contains(r) => c.record(
                        &key(&format!("{which}_diameter")),
                        format!(
                            "must be twice a radius {} {of}, got {} m",
                            range.describe_in("m", 1.0),
                            show(v)
                        ),
                    ),
                    _ => r,
                }
            }
            (Some(_), Some(_)) => c.record(
                &key(&format!("{which}_diameter")),
                format!("give {which}_radius or {which}_diameter, not both {of}"),
            ),
            (None, None) => c.record(
                &key(&format!("{which}_radius")),
                format!(
                    "is required {of}: the {which} size as {which}_radius or {which}_diameter{}",
                    if which == "inner" { ", or the pipe body's linear_weight" } else { "" }
                ),
            ),
        }
        };
    let length = required("length", &t.length, "model.length", Length);
    if length <= 0.0 {
        c.record(
            &key("length"),
            format!("must be > 0 {of}, got {} m", short(length)),
        );
    }
    let outer_radius = size(&t.outer_radius, &t.outer_diameter, "outer");
    let outer_key = if t.outer_diameter.is_some() {
        key("outer_diameter")
    } else {
        key("outer_radius")
    };
    if outer_radius >= borehole_radius {
        c.record(
            &outer_key,
            format!(
                "the section must fit in the hole {of}: outer diameter {} mm, hole diameter {} mm (a stabiliser nearly fills it: give a full-gauge one 1/16 in under the hole size, 8 7/16 in in an 8 1/2 in hole; the model needs a gap)",
                short(2e3 * outer_radius),
                short(2e3 * borehole_radius)
            ),
        );
    }
    let material = |k: &str, raw: &Option<RawQuantity>, default: f64, dim: Dimension| match raw {
        Some(raw) => c.value_as(&key(k), &format!("model.pipe.{k}"), raw, dim),
        None => default,
    };
    let density = material("density", &t.density, pipe.density, Density);
    // The inner size, or the linear weight w of the pipe body: its steel area is w/ρ, so
    // R_int = √(R_ext² − w/(πρ)).
    let inner_radius = match (&t.linear_weight, &t.inner_radius, &t.inner_diameter) {
        (None, ..) => size(&t.inner_radius, &t.inner_diameter, "inner"),
        (Some(w), None, None) => {
            let w = c.value_as(&key("linear_weight"), "", w, LinearDensity);
            let solid = density * std::f64::consts::PI * outer_radius * outer_radius;
            let nominal = super::pipe_tables::nominal_weight_of(outer_radius, w);
            if let Some(size @ (od, nominal, id)) = nominal {
                // A drill-pipe table's nominal weight (tool joints included) read as the tube's
                // plain-end weight would give 5-10 % more steel than the pipe has.
                c.record(
                    &key("linear_weight"),
                    format!(
                        "is the nominal weight of API {} in drill pipe, {nominal:.2} lb/ft (the tube with its tool joints) {of}; this key takes the pipe body's plain-end weight, {:.2} lb/ft for its tube (ID {id:.3} in) in steel of {} kg/m³: give linear_weight = \"{:.2} lb/ft\" or inner_diameter = \"{id:.3} in\"",
                        short(od),
                        super::pipe_tables::plain_end_weight_lb_per_ft(size, density),
                        short(density),
                        super::pipe_tables::plain_end_weight_lb_per_ft(size, density),
                    ),
                )
            } else if w <= 0.0 {
                c.record(
                    &key("linear_weight"),
                    format!("must be > 0 {of}, got {} kg/m", short(w)),
                )
            } else if w >= solid {
                c.record(
                    &key("linear_weight"),
                    format!(
                        "is more than a solid bar of this outer size and density weighs ({} kg/m) {of}, got {} kg/m: the wall would be thicker than the pipe",
                        short(solid),
                        short(w)
                    ),
                )
            } else {
                let inner =
                    (outer_radius * outer_radius - w / (std::f64::consts::PI * density)).sqrt();
                // A weight so small that the wall vanishes (5e-324 lb/ft) is the weight's
                // fault, not the outer size's.
                if outer_radius - inner < MIN_WALL_M {
                    c.record(
                        &key("linear_weight"),
                        format!(
                            "implies a wall of {} mm {of}, got {} kg/m: no pipe's wall is thinner than {} mm",
                            crate::units::show(1e3 * (outer_radius - inner)),
                            crate::units::show(w),
                            1e3 * MIN_WALL_M
                        ),
                    )
                } else {
                    inner
                }
            }
        }
        (Some(_), ..) => c.record(
            &key("linear_weight"),
            format!("give the inner size or the linear weight, not both {of}"),
        ),
    };
    let youngs_modulus = material(
        "youngs_modulus",
        &t.youngs_modulus,
        pipe.youngs_modulus,
        Pressure,
    );
    let poisson_ratio = material(
        "poisson_ratio",
        &t.poisson_ratio,
        pipe.poisson_ratio,
        Dimensionless,
    );
    if inner_radius >= outer_radius {
        c.record(
            &outer_key,
            format!(
                "must exceed the inner size {of}: outer diameter {} mm, inner diameter {} mm",
                short(2e3 * outer_radius),
                short(2e3 * inner_radius)
            ),
        );
    }
    let cowper = cowper_shear_factor(poisson_ratio, inner_radius, outer_radius);
    let factor =
        |k: &str, raw: &Option<RawQuantity>, word: &str, word_value: f64, default| match raw {
            None => default,
            Some(RawQuantity::Text(t)) if t.trim() == word => word_value,
            Some(RawQuantity::Text(t)) => c.record(
                &key(k),
                format!("`{t}` is not allowed {of}; expected a number or \"{word}\""),
            ),
            Some(raw) => c.value_as(&key(k), &format!("model.pipe.{k}"), raw, Dimensionless),
        };
    let shear_factor = factor("shear_factor", &t.shear_factor, "cowper", cowper, cowper);
    // [model.pipe]'s torsion factor; its "shear" (NaN without [model.pipe] sizes) is this
    // section's shear factor.
    let default_torsion = if pipe.torsion_factor.is_nan() {
        shear_factor
    } else {
        pipe.torsion_factor
    };
    let torsion_factor = factor(
        "torsion_factor",
        &t.torsion_factor,
        "shear",
        shear_factor,
        default_torsion,
    );
    let yield_strength = match &t.yield_strength {
        None => pipe.yield_strength,
        Some(raw) => c
            .section(yield_strength(c, &key("yield_strength"), raw))
            .flatten(),
    };
    let elements = t.elements.and_then(|n| {
        if (1..=super::check::MAX_ELEMENTS).contains(&n) {
            Some(n as usize)
        } else {
            c.record(
                &key("elements"),
                format!(
                    "must be a whole number in [1, {}] {of}, got {n}",
                    super::check::MAX_ELEMENTS
                ),
            );
            None
        }
    });
    StringSection {
        name,
        length,
        elements,
        pipe: Pipe {
            density,
            youngs_modulus,
            poisson_ratio,
            inner_radius,
            outer_radius,
            shear_factor,
            torsion_factor,
            yield_strength,
            fatigue: pipe.fatigue.clone(),
        },
    }
}
