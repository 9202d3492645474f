//! Why metrics could not be computed from a time series.

/// Why [`compute`](super::compute) refused a time series or a configuration. Each variant carries
/// the numbers needed to find the problem.
#[derive(Debug, Clone, thiserror::Error, PartialEq)]
pub enum MetricsError {
    #[error("the time series is empty: there is nothing to compute metrics from")]
    EmptySeries,
    #[error("channel `{channel}` has {len} samples but the time channel `t` has {expected}")]
    LengthMismatch {
        channel: String,
        len: usize,
        expected: usize,
    },
    #[error("channel `{channel}` is not finite ({value}) at t = {time} s (sample {index})")]
    NonFinite {
        channel: String,
        index: usize,
        time: f64,
        value: f64,
    },
    #[error(
        "sample times must increase strictly: t = {time} s at sample {index} follows t = {previous} s"
    )]
    TimeNotIncreasing {
        index: usize,
        time: f64,
        previous: f64,
    },
    #[error(
        "the analysis window after a settling time of {settling_time} s holds {samples} sample(s), \
         at least 2 are needed, but the run lasts only {run_length} s: \
         shorten the settling time or run longer"
    )]
    WindowTooShort {
        settling_time: f64,
        run_length: f64,
        samples: usize,
    },
    #[error(
        "a batch of the confidence intervals holds fewer than two samples (or the run did not end where its batches were laid out)"
    )]
    BatchTooShort,
    #[error("metrics configuration `{field}` = {value}: {expected}")]
    InvalidConfig {
        field: &'static str,
        value: f64,
        expected: &'static str,
    },
}
