//! The metrics of a run computed while it runs: every accepted step goes through
//! [`OnlineMetrics`] (a [`Sink`]) once, in time order, and nothing per step is kept but the last
//! τ of bit rotation (the averaged bit speed looks back τ) and, for the time-weighted standard
//! deviation of the bit axial velocity (a two-pass formula: the mean first), the window's times
//! and axial velocities (16 bytes per accepted step: 11 MB for the 704k steps of the 90 s seed),
//! up to [`MAX_TWO_PASS_SAMPLES`]; a longer window (a simulated day) gives them up for one-pass
//! sums shifted by the window's first velocity, so that the memory stays bounded in the duration.
//!
//! [`super::compute`] and [`super::batch_means`] feed a recorded series through the same
//! accumulators, so the streamed and the recorded metrics are one computation: the sums are
//! taken in the same order (left to right, from −0.0 as `Iterator::sum`) and are equal bit for
//! bit. The batches of the confidence intervals are laid out from the run's end time, which a
//! stream knows only at its end: they are laid out from `expected_end` and given only when the
//! run ends exactly there (a run that stops early has no intervals).

use super::batch_means::{BATCHES, BatchInterval, intervals};
use super::{ENERGY_FLOOR_J, Metrics, MetricsConfig, MetricsError, relative_to_feed};
use crate::sim::{CHANNELS, Row, Sink, at};
use std::collections::{BTreeMap, VecDeque};
use std::f64::consts::PI;

/// The values at a window's ends that the metrics difference.
#[derive(Debug, Clone, Copy)]
struct Ends {
    t: f64,
    u: f64,
    work_top: f64,
    work_bit: f64,
    kinetic: f64,
    potential: f64,
    dissipated: f64,
    onsets: u64,
}

impl Ends {
    fn of(row: &Row) -> Self {
        let v = &row.values;
        Ends {
            t: v[at::T],
            u: v[at::BIT_DISPLACEMENT],
            work_top: v[at::WORK_TOP],
            work_bit: v[at::WORK_BIT],
            kinetic: v[at::KINETIC_ENERGY],
            potential: v[at::POTENTIAL_ENERGY],
            dissipated: v[at::DISSIPATED],
            onsets: row.contact_onsets,
        }
    }
}

/// Integrands of the trapezoid sums, in the order of [`Window::sums`].
const WOB: usize = 0;
const TOB: usize = 1;
const STICK: usize = 2;
const BOUNCE: usize = 3;
const WALL: usize = 4;
const AXIAL: usize = 5;
const TORSIONAL: usize = 6;
const TOP_TORQUE: usize = 7;
const TOP_FORCE: usize = 8;
const WOB_LIMIT: usize = 9;
const TORQUE_LIMIT: usize = 10;
/// Number of integrands.
const SUMS: usize = 11;

/// The metrics of one sub-series (the whole run, or one batch with the τ before it): the
/// samples from the first at or after `from` to the last at or before `until`, its analysis
/// window from t₀ = t_first + settling on.
#[derive(Debug, Clone)]
struct Window {
    from: f64,
    until: f64,
    /// For a batch: its start, the settling time being start − t_first (≥ 0). NaN: `settling`.
    start: f64,
    settling: f64,
    /// The sub-series' first sample (t, θ) and its energies; t₀ of its window.
    origin: Option<(f64, f64)>,
    run_first: Option<Ends>,
    t0: f64,
    samples: usize,
    first: Option<Ends>,
    last: Option<Ends>,
    prev: Option<(f64, [f64; SUMS])>,
    sums: [f64; SUMS],
    spin: (f64, f64),
    raw: (f64, f64),
    wall_force_max: f64,
    radial_max: f64,
    /// Times and bit axial velocities of the window (the run's window only), while it holds
    /// at most [`MAX_TWO_PASS_SAMPLES`]; `None` beyond (the one-pass sums then give the deviation).
    velocity: Option<(Vec<f64>, Vec<f64>)>,
    /// Whether the window computes the velocity's deviation at all (the run's window).
    keep_velocity: bool,
    /// One-pass sums of the velocity shifted by its first value s: (s, ∫(u − s) dt,
    /// ∫(u − s)² dt, the previous sample (t, u − s)), trapezoid rule.
    shifted: Option<(f64, f64, f64, (f64, f64))>,
    /// [`MAX_TWO_PASS_SAMPLES`] (smaller in a test of the one-pass sums).
    two_pass_cap: usize,
}

/// The most window samples whose axial velocities are kept for the two-pass standard deviation
/// (2²³: 134 MB); beyond, the one-pass shifted sums (the same trapezoid integrals, equal in exact
/// arithmetic: ∫(u − ū)² = ∫(u − s)² − (∫(u − s))²/T). Every shipped run stays below it (the
/// 90 s seed: 704k samples), so its numbers are those of the two-pass formula.
pub const MAX_TWO_PASS_SAMPLES: usize = 1 << 23;

impl Window {
    fn new(from: f64, until: f64, start: f64, settling: f64, keep_velocity: bool) -> Self {
        Window {
            from,
            until,
            start,
            settling,
            origin: None,
            run_first: None,
            t0: f64::NAN,
            samples: 0,
            first: None,
            last: None,
            prev: None,
            sums: [-0.0; SUMS],
            spin: (f64::NEG_INFINITY, f64::INFINITY),
            raw: (f64::NEG_INFINITY, f64::INFINITY),
            wall_force_max: f64::NEG_INFINITY,
            radial_max: f64::NEG_INFINITY,
            velocity: keep_velocity.then(|| (Vec::new(), Vec::new())),
            keep_velocity,
            shifted: None,
            two_pass_cap: MAX_TWO_PASS_SAMPLES,
        }
    }

    /// Start the sub-series at the sample (t, θ).
    fn begin(&mut self, t: f64, theta: f64) {
        if !self.start.is_nan() {
            self.settling = (self.start - t).max(0.0);
        }
        self.origin = Some((t, theta));
        self.t0 = t + self.settling;
    }

    /// Take `row` (already in `history`); `tau` the averaging time, `config` the thresholds.
    fn record(&mut self, row: &Row, history: &VecDeque<(f64, f64)>, config: &MetricsConfig) {
        let v = &row.values;
        let t = v[at::T];
        if t < self.from || t > self.until {
            return;
        }
        if self.origin.is_none() {
            self.begin(t, v[at::BIT_ROTATION]);
            self.run_first = Some(Ends::of(row));
        }
        if t < self.t0 {
            return;
        }
        let (t_o, theta_o) = self.origin.expect("begun");
        let raw = v[at::BIT_ANGULAR_VELOCITY];
        let spin = averaged_speed(
            history,
            (t_o, theta_o),
            t,
            v[at::BIT_ROTATION],
            raw,
            config.speed_average,
        );
        // Which of the autodriller's laws commands the block (1: the WOB limit, 2: the torque
        // limit), from the recorded block speed and top loads.
        let limit = match config.top {
            crate::model::TopDrive::Autodriller(ad) => {
                let (_, slope) = crate::model::autodriller_acceleration(
                    &ad,
                    config.v0,
                    v[at::BLOCK_SPEED],
                    v[at::TOP_FORCE],
                    v[at::TOP_TORQUE],
                );
                slope.iter().position(|&d| d != 0.0).filter(|&k| k > 0)
            }
            _ => None,
        };
        self.samples += 1;
        let ends = Ends::of(row);
        self.first.get_or_insert(ends);
        self.last = Some(ends);
        let indicator = |b: bool| if b { 1.0 } else { 0.0 };
        let wob = v[at::WEIGHT_ON_BIT];
        let y = [
            wob,
            v[at::TORQUE_ON_BIT],
            indicator(spin < config.stick_threshold * config.omega),
            indicator(wob <= 0.0),
            v[at::WALL_FORCE_TOTAL],
            wob * v[at::BIT_VELOCITY],
            v[at::TORQUE_ON_BIT] * raw,
            v[at::TOP_TORQUE],
            v[at::TOP_FORCE],
            indicator(limit == Some(1)),
            indicator(limit == Some(2)),
        ];
        if let Some((t_prev, y_prev)) = &self.prev {
            let h = t - t_prev;
            for ((sum, a), b) in self.sums.iter_mut().zip(y_prev).zip(&y) {
                *sum += 0.5 * h * (a + b);
            }
        }
        self.prev = Some((t, y));
        self.spin = (self.spin.0.max(spin), self.spin.1.min(spin));
        self.raw = (self.raw.0.max(raw), self.raw.1.min(raw));
        self.wall_force_max = self.wall_force_max.max(v[at::WALL_FORCE_MAX]);
        self.radial_max = self.radial_max.max(v[at::MAX_RADIAL_OVER_GAP]);
        if self.keep_velocity {
            let u = v[at::BIT_VELOCITY];
            match &mut self.shifted {
                None => self.shifted = Some((u, 0.0, 0.0, (t, 0.0))),
                Some((shift, i1, i2, (t_prev, d_prev))) => {
                    let (h, d) = (t - *t_prev, u - *shift);
                    *i1 += 0.5 * h * (*d_prev + d);
                    *i2 += 0.5 * h * (*d_prev * *d_prev + d * d);
                    (*t_prev, *d_prev) = (t, d);
                }
            }
            let full = self
                .velocity
                .as_ref()
                .is_some_and(|(ts, _)| ts.len() >= self.two_pass_cap);
            if full {
                // Bounded memory: the one-pass sums from here on.
                self.velocity = None;
            } else if let Some((ts, us)) = &mut self.velocity {
                ts.push(t);
                us.push(u);
            }
        }
    }

    /// The metrics of the window (see [`Metrics`]); the stress and critical-speed metrics NaN.
    fn finish(&self, config: &MetricsConfig, run_last: f64) -> Result<Metrics, MetricsError> {
        let (Some(first), Some(last), true) = (self.first, self.last, self.samples >= 2) else {
            return Err(MetricsError::WindowTooShort {
                settling_time: self.settling,
                run_length: run_last - self.run_first.map_or(run_last, |e| e.t),
                samples: self.samples,
            });
        };
        let window = last.t - first.t;
        let omega = config.omega;
        let mean_rop = (last.u - first.u) / window;
        let mean_wob = self.sums[WOB] / window;
        let mean_tob = self.sums[TOB] / window;
        let bit_area = PI * config.borehole_radius * config.borehole_radius;
        // A hook load has no feed set-point: it is on bottom (its WOB set-point is > 0, the
        // simulator refuses 0), and its feed is the ROP it drills.
        let hook_load = matches!(config.top, crate::model::TopDrive::HookLoad);
        let on_bottom = config.v0 > 0.0 || hook_load;
        let feed = if hook_load { mean_rop } else { config.v0 };
        // No feed, no rock cut: an off-bottom window's elastic axial motion is not drilling.
        let mse = if on_bottom && mean_rop > 0.0 {
            let revs_per_s = omega / (2.0 * PI);
            mean_wob / bit_area + 2.0 * PI * revs_per_s * mean_tob / (bit_area * mean_rop)
        } else {
            f64::INFINITY
        };
        let top_work = last.work_top - first.work_top;
        let rock_work = -(last.work_bit - first.work_bit);
        let stored = (last.kinetic + last.potential) - (first.kinetic + first.potential);
        let spent = top_work - stored;
        let efficiency = if spent > 0.0 { rock_work / spent } else { 0.0 };
        let axial_work = self.sums[AXIAL];
        let bit_work = axial_work + self.sums[TORSIONAL];
        let axial_power_share = if bit_work > 0.0 {
            axial_work / bit_work
        } else {
            0.0
        };
        let onsets = last.onsets as f64 - first.onsets as f64;
        let fluctuation = match (&self.velocity, &self.shifted) {
            (Some((t, u)), _) => relative_to_feed(super::time_average::std_dev(t, u), feed),
            (None, Some((_, i1, i2, _))) if self.keep_velocity => {
                let span = last.t - first.t;
                let variance = i2 / span - (i1 / span) * (i1 / span);
                relative_to_feed(variance.max(0.0).sqrt(), feed)
            }
            _ => f64::NAN,
        };
        let (max_spin, min_spin) = self.spin;
        Ok(Metrics {
            mean_rop_m_s: mean_rop,
            mean_rop_m_per_h: crate::units::to_m_per_h(mean_rop),
            stick_slip_severity: (max_spin - min_spin) / (2.0 * omega),
            stick_slip_severity_raw: (self.raw.0 - self.raw.1) / (2.0 * omega),
            stick_fraction: self.sums[STICK] / window,
            max_bit_speed_ratio: max_spin / omega,
            // Off-bottom rotation is off bottom by definition: the WOB of its elastic axial
            // motion is round-off (1e-9 N on the tiny string), and its sign would decide the share.
            bit_bounce_fraction: if on_bottom {
                self.sums[BOUNCE] / window
            } else {
                1.0
            },
            axial_velocity_fluctuation: fluctuation,
            impacts_per_s: onsets / window,
            peak_wall_force_n: self.wall_force_max,
            contact_impulse_ns: self.sums[WALL],
            max_radial_over_gap: self.radial_max,
            mean_wob_n: mean_wob,
            mean_tob_nm: mean_tob,
            mse_pa: mse,
            efficiency,
            axial_power_share,
            // The whole sub-series (from its first sample); a batch begun from the history
            // has no energies of its first sample and needs none.
            energy_balance_residual: self
                .run_first
                .map_or(f64::NAN, |a| energy_balance_residual(&a, &last)),
            mean_top_torque_nm: self.sums[TOP_TORQUE] / window,
            mean_top_force_n: self.sums[TOP_FORCE] / window,
            // No set-point: 0 by definition (a series metric is never NaN, see tests_off_bottom).
            rop_set_point_ratio: if config.v0 > 0.0 {
                mean_rop / config.v0
            } else {
                0.0
            },
            set_point_shortfall: if config.v0 > 0.0 {
                1.0 - mean_rop / config.v0
            } else {
                0.0
            },
            wob_limit_fraction: self.sums[WOB_LIMIT] / window,
            torque_limit_fraction: self.sums[TORQUE_LIMIT] / window,
            ..Metrics::unset()
        })
    }
}

/// |W_in − (ΔE_k + ΔE_p + ΔD)| / max(|ΔW_top|, |ΔW_bit|, floor) from `a` to `b`.
fn energy_balance_residual(a: &Ends, b: &Ends) -> f64 {
    let (d_top, d_bit) = (b.work_top - a.work_top, b.work_bit - a.work_bit);
    let work_in = d_top + d_bit;
    let stored_and_lost =
        (b.kinetic - a.kinetic) + (b.potential - a.potential) + (b.dissipated - a.dissipated);
    let gross = d_top.abs().max(d_bit.abs());
    (work_in - stored_and_lost).abs() / gross.max(ENERGY_FLOOR_J)
}

/// The bit speed averaged over the last τ at (t, θ): ω̄ = (θ(t) − θ(t − τ)) / τ, θ interpolated
/// linearly between the two samples of `history` around t − τ (its front two); from the
/// sub-series' first sample `origin` = (t₀, θ₀) when t − τ precedes it, (θ − θ₀)/(t − t₀); the raw
/// speed when τ = 0 or at the first sample itself.
fn averaged_speed(
    history: &VecDeque<(f64, f64)>,
    origin: (f64, f64),
    t: f64,
    theta: f64,
    raw: f64,
    tau: f64,
) -> f64 {
    if tau == 0.0 {
        return raw;
    }
    let back = t - tau;
    if back <= origin.0 {
        return if t == origin.0 {
            raw
        } else {
            (theta - origin.1) / (t - origin.0)
        };
    }
    let ((tj, thj), (tk, thk)) = (history[0], history[1]);
    let w = (back - tj) / (tk - tj);
    let theta_back = thj + w * (thk - thj);
    (theta - theta_back) / tau
}

/// The metrics of a run fed one accepted step at a time (a [`Sink`]; see the module
/// documentation), and the batch-means intervals when it ends at `expected_end`.
#[derive(Debug, Clone)]
pub struct OnlineMetrics {
    config: MetricsConfig,
    expected_end: f64,
    /// (t, θ) of the samples from the last at or before t − τ on.
    history: VecDeque<(f64, f64)>,
    run: Window,
    batches: Vec<Window>,
    samples: usize,
    last_t: f64,
    error: Option<MetricsError>,
}

impl OnlineMetrics {
    /// Metrics by `config` for a run expected to end at `expected_end` s (the batches are laid
    /// out from it; NaN: no batches). Refuses an invalid configuration.
    /// The run window's two-pass cap lowered to `cap` samples (a test of the one-pass sums).
    #[cfg(test)]
    pub(crate) fn with_two_pass_cap(mut self, cap: usize) -> Self {
        self.run.two_pass_cap = cap;
        self
    }

    pub fn new(config: MetricsConfig, expected_end: f64) -> Result<Self, MetricsError> {
        config.validate()?;
        Ok(OnlineMetrics {
            run: Window::new(
                f64::NEG_INFINITY,
                f64::INFINITY,
                f64::NAN,
                config.settling_time,
                true,
            ),
            config,
            expected_end,
            history: VecDeque::with_capacity(4096),
            batches: Vec::new(),
            samples: 0,
            last_t: f64::NAN,
            error: None,
        })
    }

    /// The metrics of the run (the stress and critical-speed metrics NaN, see
    /// [`Metrics::with_stresses`]). Errors as [`super::compute`]: non-finite samples, times not
    /// increasing, a window of fewer than two samples.
    pub fn metrics(&self) -> Result<Metrics, MetricsError> {
        if let Some(e) = &self.error {
            return Err(e.clone());
        }
        if self.samples == 0 {
            return Err(MetricsError::EmptySeries);
        }
        self.run.finish(&self.config, self.last_t)
    }

    /// The 95 % batch-means intervals (see [`super::batch_means`]); `None` when the run did not
    /// end at `expected_end`, its metrics failed, or a batch holds fewer than two samples.
    pub fn batch_intervals(&self) -> Option<BTreeMap<&'static str, BatchInterval>> {
        self.metrics().ok()?;
        if self.last_t != self.expected_end || self.batches.len() != BATCHES {
            return None;
        }
        let values: Vec<Metrics> = self
            .batches
            .iter()
            .map(|b| b.finish(&self.config, self.last_t))
            .collect::<Result<_, _>>()
            .ok()?;
        Some(intervals(&values))
    }

    /// Lay the batches out from the window's first sample `t_s`; each batch reads from τ before
    /// its start, so those that begin in the past start from `history`.
    fn lay_out_batches(&mut self, t_s: f64) {
        let length = (self.expected_end - t_s) / BATCHES as f64;
        for b in 0..BATCHES {
            let (start, end) = (t_s + b as f64 * length, t_s + (b + 1) as f64 * length);
            let from = start - self.config.speed_average;
            let mut w = Window::new(from, end * (1.0 + 1e-15), start, f64::NAN, false);
            // The current sample is begun by `record`; an earlier first sample comes from history.
            if let Some(&(t, theta)) = self.history.iter().find(|(t, _)| *t >= from)
                && t < t_s
            {
                w.begin(t, theta);
                w.run_first = None;
            }
            self.batches.push(w);
        }
    }

    fn check(&mut self, row: &Row) {
        let index = self.samples;
        let time = row.t();
        let non_finite = CHANNELS
            .iter()
            .zip(&row.values)
            .map(|(ch, &v)| (ch.name.to_string(), v))
            .find(|(_, v)| !v.is_finite())
            .or_else(|| {
                (row.probe_radial.iter().enumerate())
                    .find(|(_, v)| !v.is_finite())
                    .map(|(k, &v)| (format!("probe_radial[{k}]"), v))
            });
        if let Some((channel, value)) = non_finite {
            self.error = Some(MetricsError::NonFinite {
                channel,
                index,
                time,
                value,
            });
        } else if index > 0 && time <= self.last_t {
            self.error = Some(MetricsError::TimeNotIncreasing {
                index,
                time,
                previous: self.last_t,
            });
        }
    }
}

impl Sink for OnlineMetrics {
    /// Never stops the run: a sample the metrics refuse is reported by [`OnlineMetrics::metrics`].
    fn record(&mut self, row: &Row<'_>) -> bool {
        if self.error.is_some() {
            return true;
        }
        // Only a finite row reaches the accumulators (`check` records the refusal).
        if row
            .values
            .iter()
            .chain(row.probe_radial)
            .any(|v| !v.is_finite())
            || (self.samples > 0 && row.t() <= self.last_t)
        {
            self.check(row);
            return true;
        }
        let (t, theta) = (row.t(), row.values[at::BIT_ROTATION]);
        self.history.push_back((t, theta));
        let back = t - self.config.speed_average;
        while self.history.len() >= 2 && self.history[1].0 <= back {
            self.history.pop_front();
        }
        let in_window = self.run.samples;
        self.run.record(row, &self.history, &self.config);
        if in_window == 0 && self.run.samples == 1 && !self.expected_end.is_nan() {
            self.lay_out_batches(t);
        }
        for b in &mut self.batches {
            b.record(row, &self.history, &self.config);
        }
        self.samples += 1;
        self.last_t = t;
        true
    }
}
