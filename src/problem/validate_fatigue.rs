//! `[model.pipe.fatigue]`: the S-N curve of the fatigue damage ([`crate::fatigue::SnCurve`]).
//!
//! Either a named curve, `sn_curve = "DNV-B1"` (DNV-RP-C203 (2016) Table 2-1, in air; the
//! default), or its parameters: `log_a1` and `m1` (log₁₀ ā₁ with the stress range in MPa, and
//! the inverse slope), optionally `log_a2` and `m2` for the branch beyond the knee. Then
//! `endurance_limit`, a stress range below which cycles do no damage (default: the named curve's
//! fatigue limit at 10⁷ cycles, or the range at 10⁷ cycles on a curve given by its parameters;
//! 0: no cut-off), and `stress_concentration` (default 1).

use super::ProblemError;
use super::check::Checker;
use super::schema::{FatigueSection, RawQuantity};
use crate::fatigue::{DNV_AIR, SnCurve};
use crate::units::show;

const KEY: &str = "model.pipe.fatigue";

pub(super) fn fatigue(c: &Checker, f: Option<&FatigueSection>) -> Result<SnCurve, ProblemError> {
    let Some(f) = f else {
        return Ok(SnCurve::default());
    };
    let explicit = [
        ("log_a1", f.log_a1.is_some()),
        ("m1", f.m1.is_some()),
        ("log_a2", f.log_a2.is_some()),
        ("m2", f.m2.is_some()),
    ];
    // A refused name or a name given with parameters is recorded and the default curve stands
    // in, so that the other keys of the table are checked in the same pass.
    let mut curve = match &f.sn_curve {
        Some(name) => {
            if let Some((key, _)) = explicit.iter().find(|(_, set)| *set) {
                c.record(
                    &format!("{KEY}.{key}"),
                    format!(
                        "a curve is given either by name (sn_curve = {name:?}) or by its parameters (log_a1, m1, log_a2, m2), not both"
                    ),
                );
            }
            SnCurve::named(name).unwrap_or_else(|| {
                let names: Vec<&str> = DNV_AIR.iter().map(|r| r.0).collect();
                c.record(
                    &format!("{KEY}.sn_curve"),
                    format!(
                        "`{name}` is not a known S-N curve; expected one of {} (DNV-RP-C203 (2016) Table 2-1, in air) or the parameters log_a1, m1 (and log_a2, m2)",
                        names.join(", ")
                    ),
                );
                SnCurve::default()
            })
        }
        None if explicit.iter().any(|(_, set)| *set) => custom(c, f)?,
        None => SnCurve::default(),
    };
    // The ranges are the key table's (super::keys::KEYS).
    if let Some(raw) = &f.endurance_limit {
        curve.endurance_limit = c.key_value("model.pipe.fatigue.endurance_limit", Some(raw))?;
    }
    curve.stress_concentration = c.key_value(
        "model.pipe.fatigue.stress_concentration",
        f.stress_concentration.as_ref(),
    )?;
    Ok(curve)
}

/// A curve given by its parameters: `log_a1` and `m1` together, `log_a2` and `m2` together, the
/// second branch flatter than the first (m₂ > m₁).
fn custom(c: &Checker, f: &FatigueSection) -> Result<SnCurve, ProblemError> {
    // The ranges are the key table's (super::keys::KEYS).
    let read = |name: &str, raw: &Option<RawQuantity>| {
        let key = format!("{KEY}.{name}");
        match raw {
            None => Err(c.fail(
                &key,
                "is required when the curve is given by its parameters (log_a1 and m1, and log_a2 with m2)".into(),
            )),
            Some(raw) => Ok(c.key_value(&key, Some(raw)).unwrap_or(f64::NAN)),
        }
    };
    let log_a1 = read("log_a1", &f.log_a1)?;
    let m1 = read("m1", &f.m1)?;
    let second = if f.log_a2.is_some() || f.m2.is_some() {
        let log_a2 = read("log_a2", &f.log_a2)?;
        let m2 = read("m2", &f.m2)?;
        if m2 <= m1 {
            return Err(c.fail(
                &format!("{KEY}.m2"),
                format!(
                    "must be greater than m1 ({}): the branch beyond the knee is the flatter one, got {}",
                    show(m1),
                    show(m2)
                ),
            ));
        }
        Some((log_a2, m2))
    } else {
        None
    };
    let mut curve = SnCurve {
        name: "custom",
        log_a1,
        m1,
        second,
        endurance_limit: 0.0,
        stress_concentration: 1.0,
    };
    curve.endurance_limit = if log_a1.is_nan() || m1.is_nan() {
        f64::NAN
    } else {
        curve.range_at(1e7)
    };
    Ok(curve)
}
