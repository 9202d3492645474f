//! Fixed-interval output of a run: the recorded states at t = k·Δ (k = 0, 1, …) instead of at
//! every adaptive step, so that the written history has a known size (duration / Δ + 1 rows)
//! whatever the step does around impacts.
//!
//! Values between two accepted steps tₐ < s ≤ t_b are **linearly interpolated** between the two
//! recorded rows, y(s) = yₐ + w (y_b − yₐ) with w = (s − tₐ)/(t_b − tₐ), channel by channel (the
//! time channel is s itself); the integer counts (nodes in contact, cumulative impacts) are those of
//! the step at tₐ (held until the next accepted step). A sample time that coincides with an
//! accepted step takes that step's values exactly. Interpolation error: h²/8 · max |ÿ| over a
//! step h; the metrics never read the sampled rows (they see every accepted step).

use super::series::{CHANNELS, Row, Sink, at};
pub use crate::model::SampleInterval;

/// A [`Sink`] that passes the states at t = k·Δ to `sink`, interpolated between the accepted
/// steps it is given (see the module documentation). Its buffers are sized at construction.
pub struct Sampler<S> {
    /// Δ, s; NaN: every step passes through.
    interval: f64,
    /// Index k of the next sample time k·Δ.
    next: u64,
    /// The previous accepted step: values, counts and probes (`None` before the first).
    prev: Option<([f64; CHANNELS.len()], u32, u64)>,
    prev_probes: Vec<f64>,
    out_probes: Vec<f64>,
    sink: S,
}

impl<S: Sink> Sampler<S> {
    /// Samples at `interval` (a fixed Δ > 0, finite; or every step, passed through unchanged)
    /// for a run with `probes` radial probes.
    pub fn new(interval: SampleInterval, probes: usize, sink: S) -> Self {
        let interval = match interval {
            SampleInterval::Fixed(dt) => {
                assert!(dt > 0.0 && dt.is_finite(), "sample interval {dt}");
                dt
            }
            SampleInterval::EveryStep => f64::NAN,
        };
        Sampler {
            interval,
            next: 0,
            prev: None,
            prev_probes: vec![0.0; probes],
            out_probes: vec![0.0; probes],
            sink,
        }
    }

    fn time(&self, k: u64) -> f64 {
        k as f64 * self.interval
    }

    /// The sink, after emitting a last sample that rounding of k·Δ put just past the final step
    /// (within 10⁻⁹ Δ): it takes the final step's values and time.
    pub fn finish(mut self) -> S {
        if let (false, Some((values, nodes, onsets))) = (self.interval.is_nan(), self.prev) {
            let t_last = values[at::T];
            if self.time(self.next) <= t_last + 1e-9 * self.interval {
                self.sink.record(&Row {
                    values,
                    nodes_in_contact: nodes,
                    contact_onsets: onsets,
                    probe_radial: &self.prev_probes,
                });
            }
        }
        self.sink
    }
}

impl<S: Sink> Sink for Sampler<S> {
    fn record(&mut self, row: &Row<'_>) -> bool {
        if self.interval.is_nan() {
            return self.sink.record(row);
        }
        let t_b = row.t();
        let mut go_on = true;
        match self.prev {
            // The first state: samples from the first k·Δ at or after it.
            None => {
                self.next = (t_b / self.interval).ceil().max(0.0) as u64;
                if self.time(self.next) == t_b {
                    go_on = self.sink.record(row);
                    self.next += 1;
                }
            }
            Some((a, nodes, onsets)) => {
                let t_a = a[at::T];
                loop {
                    let s = self.time(self.next);
                    if s > t_b {
                        break;
                    }
                    self.next += 1;
                    if s == t_b {
                        go_on &= self.sink.record(row);
                        continue;
                    }
                    let w = (s - t_a) / (t_b - t_a);
                    let mut values: [f64; CHANNELS.len()] =
                        std::array::from_fn(|k| a[k] + w * (row.values[k] - a[k]));
                    values[at::T] = s;
                    for ((out, &pa), &pb) in self
                        .out_probes
                        .iter_mut()
                        .zip(&self.prev_probes)
                        .zip(row.probe_radial)
                    {
                        *out = pa + w * (pb - pa);
                    }
                    go_on &= self.sink.record(&Row {
                        values,
                        nodes_in_contact: nodes,
                        contact_onsets: onsets,
                        probe_radial: &self.out_probes,
                    });
                }
            }
        }
        self.prev = Some((row.values, row.nodes_in_contact, row.contact_onsets));
        for (p, &r) in self.prev_probes.iter_mut().zip(row.probe_radial) {
            *p = r;
        }
        go_on
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::TimeSeries;

    /// A row of the known signal: every channel k is y_k(t) = k + (k + 1) t (linear, so linear
    /// interpolation is exact up to rounding), the probe 2 − t, counts from the step index.
    fn row(t: f64, i: u64, probe: &[f64; 1]) -> Row<'_> {
        let mut values: [f64; CHANNELS.len()] =
            std::array::from_fn(|k| k as f64 + (k + 1) as f64 * t);
        values[at::T] = t;
        Row {
            values,
            nodes_in_contact: i as u32,
            contact_onsets: 10 * i,
            probe_radial: probe,
        }
    }

    fn run(times: &[f64], dt: f64) -> TimeSeries {
        let mut sampler = Sampler::new(
            SampleInterval::Fixed(dt),
            1,
            TimeSeries::with_probes(&[5.0], 0),
        );
        for (i, &t) in times.iter().enumerate() {
            assert!(sampler.record(&row(t, i as u64, &[2.0 - t])));
        }
        sampler.finish()
    }

    #[test]
    fn samples_a_linear_signal_exactly_at_k_dt() {
        // Uneven steps, one landing on a sample time (0.5), several samples inside one step.
        let times = [0.0, 0.13, 0.5, 0.52, 1.37, 2.0];
        let s = run(&times, 0.25);
        assert_eq!(s.len(), 9); // 0, 0.25, …, 2.0
        for (k, &t) in s.t.iter().enumerate() {
            assert_eq!(t, k as f64 * 0.25);
            for (c, ch) in CHANNELS.iter().enumerate().skip(1) {
                let want = c as f64 + (c + 1) as f64 * t;
                let got = ch.values(&s)[k];
                assert!(
                    (got - want).abs() <= 1e-14 * want.abs(),
                    "{} at {t}: {got} vs {want}",
                    ch.name
                );
            }
            assert!((s.probe_radial[0][k] - (2.0 - t)).abs() < 1e-15);
        }
        // The first and last samples are the first and last steps, exactly.
        assert_eq!(
            s.bit_velocity[0],
            row(0.0, 0, &[2.0]).values[at::BIT_VELOCITY]
        );
        assert_eq!(
            s.bit_velocity[8],
            row(2.0, 5, &[0.0]).values[at::BIT_VELOCITY]
        );
        // Counts held from the step at or before the sample: t = 0.75 lies in [0.52, 1.37).
        assert_eq!(s.nodes_in_contact[3], 3);
        assert_eq!(s.contact_onsets[3], 30);
        // 0.5 is an accepted step: its own counts.
        assert_eq!(s.nodes_in_contact[2], 2);
    }

    #[test]
    fn a_last_sample_rounded_past_the_end_takes_the_final_step() {
        // 0.1 · 3 = 0.30000000000000004 > 0.3: the sample at k = 3 is the final step.
        let s = run(&[0.0, 0.05, 0.2, 0.3], 0.1);
        assert_eq!(s.len(), 4);
        assert_eq!(s.t[3], 0.3);
        assert_eq!(SampleInterval::Fixed(0.1).rows(0.3), Some(4));
        assert_eq!(SampleInterval::Fixed(0.25).rows(2.0), Some(9));
        assert_eq!(SampleInterval::EveryStep.rows(2.0), None);
        // A day at 1 µs: exactly 86 400 000 000 intervals (was 87 rows more).
        assert_eq!(
            SampleInterval::Fixed(1e-6).rows(86_400.0),
            Some(86_400_000_001)
        );
        assert_eq!(SampleInterval::Fixed(0.3).rows(1.0), Some(4));
    }

    #[test]
    fn every_step_passes_each_row_through() {
        let mut sampler = Sampler::new(
            SampleInterval::EveryStep,
            1,
            TimeSeries::with_probes(&[5.0], 0),
        );
        for (i, t) in [0.0, 0.13, 0.5].into_iter().enumerate() {
            sampler.record(&row(t, i as u64, &[2.0 - t]));
        }
        assert_eq!(sampler.finish().t, vec![0.0, 0.13, 0.5]);
    }

    #[test]
    fn interpolates_a_quadratic_within_the_linear_bound() {
        // y = t² on steps of 0.1: linear interpolation errs by at most h²/8 · 2 = 0.0025.
        let mut sampler = Sampler::new(
            SampleInterval::Fixed(0.03),
            0,
            TimeSeries::with_probes(&[], 0),
        );
        for i in 0..=10 {
            let t = i as f64 * 0.1;
            let mut r = row(t, 0, &[0.0]);
            r.values[at::BIT_VELOCITY] = t * t;
            r.probe_radial = &[];
            sampler.record(&r);
        }
        let s = sampler.finish();
        assert_eq!(s.len(), 34); // 0, 0.03, …, 0.99
        let worst =
            s.t.iter()
                .zip(&s.bit_velocity)
                .map(|(t, y)| (y - t * t).abs())
                .fold(0.0, f64::max);
        assert!(worst <= 0.0025 + 1e-15 && worst > 0.001, "{worst}");
    }
}
