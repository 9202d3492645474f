//! Thresholds of risk terms and chance constraints, read in the unit of their metric (its row of
//! the metric catalogue, [`crate::metrics::MetricSpec`]): a bare number is the metric's own
//! value, a string carries a unit of the metric's dimension (`"500 MPa"`, `"20 kN"`, `"1e-4 1/h"`).

use super::ProblemError;
use super::check::Checker;
use super::schema::RawQuantity;

/// A threshold on `metric`, in the metric's unit ([`crate::metrics::MetricSpec::unit`]): a bare
/// number as it is (the metric's own value, SI but for the few keys that name another unit), a
/// string with a unit of the metric's dimension converted; a unit of another dimension, or any
/// unit on a dimensionless metric, is refused naming the metric's unit (recorded: the value reads
/// as NaN).
pub(super) fn threshold(
    c: &Checker,
    key: &str,
    metric: &str,
    raw: &RawQuantity,
) -> Result<f64, ProblemError> {
    let spec = crate::metrics::catalogue::find(metric).expect("a metric of the catalogue");
    let (dim, per_si) = (spec.dimension, spec.per_si);
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
                        spec.unit(),
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
