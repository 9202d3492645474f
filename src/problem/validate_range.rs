//! Ranges of operating points in the study sections (an `[optimizer]` box, an `[expect]` range,
//! a set-point range), shared by [`super::validate_study`] and [`super::validate_expect`].

use super::ProblemError;
use super::check::Checker;
use super::schema::RawQuantity;
use crate::model::SetPoint;

/// A pair `[min, max]` under `key`, each end within the admissible range of `range_key` (the
/// operating point's key: `omega = ["30 rpm", 1e12]` simulated 2.4e12 rpm and called it feasible).
pub(super) fn range(
    c: &Checker,
    key: &str,
    range_key: &str,
    raw: &[RawQuantity],
    dim: super::Dimension,
) -> Result<[f64; 2], ProblemError> {
    if raw.len() != 2 {
        return Err(c.fail(
            key,
            format!("must be a pair [min, max], got {} values", raw.len()),
        ));
    }
    let lo = c.value_as(&format!("{key}[0]"), range_key, &raw[0], dim);
    let hi = c.value_as(&format!("{key}[1]"), range_key, &raw[1], dim);
    let read = !lo.is_nan() && !hi.is_nan(); // else refused where read
    if read && !(lo > 0.0 && hi > lo) {
        // Echoed as typed (`"150 rpm"`), so the user sees their own units.
        c.record(
            key,
            format!(
                "must satisfy 0 < min < max, got [{}, {}]",
                as_typed(&raw[0], dim),
                as_typed(&raw[1], dim)
            ),
        );
        return Ok([f64::NAN; 2]);
    }
    Ok([lo, hi])
}

/// The pair `[min, max]` of the set-point under `{section}.v0` or `{section}.wob`, by `kind` (the
/// problem's top): the other top's key is refused, the kind's own is required.
pub(super) fn set_point_range(
    c: &Checker,
    section: &str,
    kind: SetPoint,
    v0: &Option<Vec<RawQuantity>>,
    wob: &Option<Vec<RawQuantity>>,
) -> Result<[f64; 2], ProblemError> {
    let (own, other) = match kind {
        SetPoint::Feed => (v0, wob),
        SetPoint::Wob => (wob, v0),
    };
    let other_kind = match kind {
        SetPoint::Feed => SetPoint::Wob,
        SetPoint::Wob => SetPoint::Feed,
    };
    if other.is_some() {
        c.record(
            &format!("{section}.{}", other_kind.key()),
            format!(
                "belongs to {}: this problem's top makes the set-point {} ({section}.{}); remove it",
                match other_kind {
                    SetPoint::Wob => "top = \"hook_load\"",
                    SetPoint::Feed => "the feed tops (\"feed\", \"autodriller\")",
                },
                kind.symbol(),
                kind.key()
            ),
        );
    }
    let key = format!("{section}.{}", kind.key());
    match own {
        Some(raw) => range(
            c,
            &key,
            &format!("operating_point.{}", kind.key()),
            raw,
            kind.dimension(),
        ),
        None => Err(c.fail(
            &key,
            format!(
                "is required: the range [min, max] of {} (e.g. {})",
                kind.symbol(),
                match kind {
                    SetPoint::Feed => "[\"2 m/h\", \"20 m/h\"]",
                    SetPoint::Wob => "[\"20 kN\", \"120 kN\"]",
                }
            ),
        )),
    }
}

/// A value as the file has it: a string as typed, a bare number with its SI unit.
pub(super) fn as_typed(raw: &RawQuantity, dim: super::Dimension) -> String {
    match raw {
        RawQuantity::Text(t) => t.clone(),
        RawQuantity::Number(v) => format!("{v} {}", dim.si_unit()),
    }
}
