//! Confidence intervals of the time-mean metrics by batch means: is a window long enough for its
//! means to be properties of the operating point rather than of the window?
//!
//! The analysis window [t_s, t_end] is cut into [`BATCHES`] batches of equal length; each
//! batch's metrics are computed as for a window of its own (the averaged bit speed reads the
//! samples before the batch, so nothing is lost at its start). For a metric that is a time mean
//! or a share of time, the window's value is the mean of the batch values, and the 95 % confidence
//! half-width is t₀.₉₇₅,B−1 · s_B / √B with s_B the standard deviation of the batch values (Law &
//! Kelton, *Simulation Modeling and Analysis*, 3rd ed., §9.5.3: non-overlapping batch means).
//! Batches shorter than the correlation time (a few stick-slip cycles) understate the width; the
//! 10 batches of a 10 s seed window hold about 16 stick-slip cycles each (16.3 cycles/s).

use super::{Metrics, MetricsConfig, MetricsError, compute};
use crate::sim::TimeSeries;
use serde::Serialize;
use std::collections::BTreeMap;

/// Number of batches.
pub const BATCHES: usize = 10;

/// Student's t quantile t₀.₉₇₅ with BATCHES − 1 = 9 degrees of freedom.
const T_975_9: f64 = 2.262_157;

/// A batch-means interval of one metric.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct BatchInterval {
    /// Mean of the batch values.
    pub mean: f64,
    /// Half-width of the 95 % confidence interval, in the metric's unit.
    pub half_width: f64,
}

/// 95 % batch-means intervals of the time-mean metrics over the analysis window of `config`.
/// Errors as [`compute`], and when a batch holds fewer than two samples.
pub fn batch_means(
    series: &TimeSeries,
    config: &MetricsConfig,
) -> Result<BTreeMap<&'static str, BatchInterval>, MetricsError> {
    compute(series, config)?; // the same checks as the window's own metrics
    let t_end = series.t[series.len() - 1];
    let mut online = super::OnlineMetrics::new(config.clone(), t_end)?;
    super::feed(series, &mut online);
    online.batch_intervals().ok_or(MetricsError::BatchTooShort)
}

/// The intervals of the time-mean metrics (those of the catalogue with
/// [`super::MetricSpec::batch_interval`]) from the metrics of the [`BATCHES`] batches.
pub(super) fn intervals(values: &[Metrics]) -> BTreeMap<&'static str, BatchInterval> {
    let n = BATCHES as f64;
    super::METRICS
        .iter()
        .filter(|s| s.batch_interval)
        .map(|s| {
            let (key, get) = (s.key, s.get);
            let v: Vec<f64> = values.iter().map(get).collect();
            let mean = v.iter().sum::<f64>() / n;
            let var = v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0);
            (
                key,
                BatchInterval {
                    mean,
                    half_width: T_975_9 * (var / n).sqrt(),
                },
            )
        })
        .collect()
}
