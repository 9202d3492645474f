//! Sanity checks on a recorded time series before any metric is computed from it.

use super::MetricsError;
use crate::sim::{CHANNELS, TimeSeries};

/// Refuse an empty series, per-step channels whose length differs from `t`, non-finite samples
/// (in any real-valued per-step channel, over the whole run) and sample times that do not
/// increase strictly.
pub(crate) fn check_series(s: &TimeSeries) -> Result<(), MetricsError> {
    if s.is_empty() {
        return Err(MetricsError::EmptySeries);
    }
    let n = s.len();
    let mut real: Vec<(String, &[f64])> = CHANNELS
        .iter()
        .map(|ch| (ch.name.to_string(), ch.values(s)))
        .collect();
    for (k, probe) in s.probe_radial.iter().enumerate() {
        real.push((format!("probe_radial[{k}]"), probe));
    }

    let lengths = real
        .iter()
        .map(|(name, ch)| (name.clone(), ch.len()))
        .chain([
            ("nodes_in_contact".to_string(), s.nodes_in_contact.len()),
            ("contact_onsets".to_string(), s.contact_onsets.len()),
        ]);
    for (channel, len) in lengths {
        if len != n {
            return Err(MetricsError::LengthMismatch {
                channel,
                len,
                expected: n,
            });
        }
    }

    for (name, ch) in &real {
        if let Some(index) = ch.iter().position(|v| !v.is_finite()) {
            return Err(MetricsError::NonFinite {
                channel: name.clone(),
                index,
                time: s.t[index],
                value: ch[index],
            });
        }
    }

    for (index, w) in s.t.windows(2).enumerate() {
        if w[1] <= w[0] {
            return Err(MetricsError::TimeNotIncreasing {
                index: index + 1,
                time: w[1],
                previous: w[0],
            });
        }
    }
    Ok(())
}
