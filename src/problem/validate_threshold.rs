//! Thresholds of risk terms and chance constraints, read in the unit of their metric
//! ([`super::study::metric_unit`]): a bare number is the metric's own value, a string carries a
//! unit of the metric's dimension (`"500 MPa"`, `"20 kN"`, `"1e-4 1/h"`).

use super::ProblemError;
use super::schema::RawQuantity;
use super::study::metric_unit;
use super::validate::Checker;

/// A threshold on `metric`, in the metric's unit ([`metric_unit`]): a bare number as it is (the
/// metric's own value, SI but for the few keys that name another unit), a string with a unit of
/// the metric's dimension converted; a unit of another dimension, or any unit on a dimensionless
/// metric, is refused naming the metric's unit (recorded: the value reads as NaN).
pub(super) fn threshold(
    c: &Checker,
    key: &str,
    metric: &str,
    raw: &RawQuantity,
) -> Result<f64, ProblemError> {
    let (dim, per_si) = metric_unit(metric).expect("every metric has a unit");
    let value = match raw {
        RawQuantity::Number(v) => *v,
        RawQuantity::Text(t) => match dim.parse(t) {
            Ok(si) => si * per_si,
            Err(e) => {
                let what = if dim == super::Dimension::Dimensionless {
                    format!("{metric} is dimensionless: a plain number")
                } else {
                    let units: Vec<&str> = dim.units().iter().map(|u| u.0).collect();
                    format!(
                        "{metric} is {}: a number in {} or a string with one of the units {}",
                        dim.name(),
                        own_unit(metric, dim),
                        units.join(", ")
                    )
                };
                // Recorded, so that the other thresholds and keys are checked in the same pass.
                return Ok(c.record(key, format!("`{t}` is not allowed ({}); {what}", e.reason)));
            }
        },
    };
    if !value.is_finite() {
        return Ok(c.record(key, format!("must be finite, got {value}")));
    }
    Ok(value)
}

/// The unit a bare threshold of `metric` is read in: the one its key names.
fn own_unit(metric: &str, dim: super::Dimension) -> &'static str {
    match metric {
        "mean_rop_m_per_h" => "m/h",
        "fatigue_damage_per_h" => "1/h",
        "fatigue_life_h" => "h",
        _ => dim.si_unit(),
    }
}
