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

/// A metric's `summary.json` key and how to read it.
type Reader = (&'static str, fn(&Metrics) -> f64);

/// The metrics that are time means or shares of time (the ones batch means apply to).
const MEAN_METRICS: [Reader; 7] = [
    ("mean_rop_m_per_h", |m| m.mean_rop_m_per_h),
    ("mean_wob_n", |m| m.mean_wob_n),
    ("mean_tob_nm", |m| m.mean_tob_nm),
    ("stick_fraction", |m| m.stick_fraction),
    ("bit_bounce_fraction", |m| m.bit_bounce_fraction),
    ("impacts_per_s", |m| m.impacts_per_s),
    ("axial_power_share", |m| m.axial_power_share),
];

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
    let t = &series.t;
    let t_s = t[t.partition_point(|&x| x < t[0] + config.settling_time)];
    let t_end = t[t.len() - 1];
    let length = (t_end - t_s) / BATCHES as f64;
    let mut values: Vec<Metrics> = Vec::with_capacity(BATCHES);
    for b in 0..BATCHES {
        let (start, end) = (t_s + b as f64 * length, t_s + (b + 1) as f64 * length);
        // From τ before the batch (the averaged bit speed looks back), to its end.
        let first = t.partition_point(|&x| x < start - config.speed_average);
        let last = t
            .partition_point(|&x| x <= end * (1.0 + 1e-15))
            .max(first + 1);
        let sub = series.slice(first..last);
        let batch = MetricsConfig {
            settling_time: (start - sub.t[0]).max(0.0),
            ..config.clone()
        };
        values.push(compute(&sub, &batch)?);
    }
    let n = BATCHES as f64;
    Ok(MEAN_METRICS
        .iter()
        .map(|&(key, get)| {
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
        .collect())
}
