//! A history for the plots of a run whose memory does not grow with its duration.
//!
//! The plots of a run draw, per time bucket, the lowest and the highest sample of each curve
//! (`report::decimate_min_max`); a run of a simulated day at the default 0.5 ms output interval
//! would otherwise hold 170 million rows (about 30 GB) only for them. [`PlotHistory`] cuts the
//! run's time `[0, duration]` into `buckets` equal intervals and keeps, per interval, the rows
//! that hold the lowest and the highest value of each plotted curve (the bit's four channels of
//! [`PLOTTED`] and every radial probe), and the interval's last row; the run's first row is
//! always kept. Plotted on `buckets / m` intervals (m a whole number), every interval's lowest and
//! highest sample is among the kept rows, so the plot is that of the whole history. A run short
//! enough that all its rows fit in the same bound keeps them all.
//!
//! Memory: at most `buckets × (2 × curves + 1)` rows, `curves` = 4 + probes; nothing is allocated
//! per row (the candidate rows are preallocated).

use super::series::{CHANNELS, Row, Sink, TimeSeries, at};

/// The channels the run plots draw (paper Figs. 3 and 4), besides the radial probes.
pub const PLOTTED: [usize; 4] = [
    at::BIT_DISPLACEMENT,
    at::BIT_VELOCITY,
    at::BIT_ROTATION,
    at::BIT_ANGULAR_VELOCITY,
];

/// An owned copy of a [`Row`], preallocated for the run's probes.
#[derive(Debug, Clone)]
struct Slot {
    values: [f64; CHANNELS.len()],
    nodes_in_contact: u32,
    contact_onsets: u64,
    probes: Vec<f64>,
    set: bool,
}

impl Slot {
    fn copy_from(&mut self, row: &Row<'_>) {
        self.values = row.values;
        self.nodes_in_contact = row.nodes_in_contact;
        self.contact_onsets = row.contact_onsets;
        for (slot, &r) in self.probes.iter_mut().zip(row.probe_radial) {
            *slot = r;
        }
        self.set = true;
    }

    fn row(&self) -> Row<'_> {
        Row {
            values: self.values,
            nodes_in_contact: self.nodes_in_contact,
            contact_onsets: self.contact_onsets,
            probe_radial: &self.probes,
        }
    }
}

/// The value of curve `c` in a row: the plotted channels first, then the probes.
fn curve(values: &[f64; CHANNELS.len()], probes: &[f64], c: usize) -> f64 {
    match PLOTTED.get(c) {
        Some(&k) => values[k],
        None => probes.get(c - PLOTTED.len()).copied().unwrap_or(f64::NAN),
    }
}

/// A [`Sink`] that keeps what the plots of a run need, in bounded memory (see the module doc).
#[derive(Debug, Clone)]
pub struct PlotHistory {
    series: TimeSeries,
    /// Width of a bucket, s; `None` keeps every row.
    width: Option<f64>,
    /// The bucket the candidates belong to.
    bucket: Option<u64>,
    /// Per curve, the rows of its lowest and highest value in the open bucket, then its last row.
    slots: Vec<Slot>,
    /// Scratch for the flush: the slots in time order.
    order: Vec<usize>,
}

impl PlotHistory {
    /// For a run of `duration` s with radial probes at `probes` (m), whose plots draw on
    /// `buckets` time intervals or a divisor of it. `expected_rows`, when the caller knows it
    /// (a fixed output interval), keeps every row if they fit within the bound.
    ///
    /// # Panics
    /// If `duration` is not positive and finite or `buckets` is 0 (a caller's bug: durations are
    /// validated at load).
    pub fn new(
        probes: &[f64],
        duration: f64,
        buckets: usize,
        expected_rows: Option<usize>,
    ) -> Self {
        assert!(duration > 0.0 && duration.is_finite() && buckets > 0);
        let curves = PLOTTED.len() + probes.len();
        let bound = buckets * (2 * curves + 1);
        let keep_all = expected_rows.is_some_and(|rows| rows <= bound);
        let slot = Slot {
            values: [0.0; CHANNELS.len()],
            nodes_in_contact: 0,
            contact_onsets: 0,
            probes: vec![0.0; probes.len()],
            set: false,
        };
        PlotHistory {
            series: TimeSeries::with_probes(probes, if keep_all { bound } else { 0 }),
            width: (!keep_all).then_some(duration / buckets as f64),
            bucket: None,
            slots: vec![slot; 2 * curves + 1],
            order: Vec::with_capacity(2 * curves + 1),
        }
    }

    /// The kept rows, in time order.
    pub fn into_series(mut self) -> TimeSeries {
        self.flush();
        self.series
    }

    /// Appends the open bucket's candidate rows in time order (each once), and empties it.
    fn flush(&mut self) {
        self.order.clear();
        self.order
            .extend((0..self.slots.len()).filter(|&i| self.slots[i].set));
        let slots = &self.slots;
        self.order
            .sort_unstable_by(|&a, &b| slots[a].values[at::T].total_cmp(&slots[b].values[at::T]));
        for &i in &self.order {
            let t = slots[i].values[at::T];
            if self.series.t.last().is_none_or(|&last| t > last) {
                self.series.push_row(&slots[i].row());
            }
        }
        for slot in &mut self.slots {
            slot.set = false;
        }
    }
}

impl Sink for PlotHistory {
    fn record(&mut self, row: &Row<'_>) -> bool {
        let Some(width) = self.width else {
            self.series.push_row(row);
            return true;
        };
        if self.series.is_empty() && self.bucket.is_none() {
            // The first row is where every curve starts.
            self.series.push_row(row);
        }
        let bucket = (row.t() / width).floor().max(0.0) as u64;
        if self.bucket != Some(bucket) {
            self.flush();
            self.bucket = Some(bucket);
        }
        let last = self.slots.len() - 1;
        for c in 0..last / 2 {
            let y = curve(&row.values, row.probe_radial, c);
            if !y.is_finite() {
                continue;
            }
            let [lo, hi] = [2 * c, 2 * c + 1];
            let value = |s: &Slot| curve(&s.values, &s.probes, c);
            if !self.slots[lo].set || y < value(&self.slots[lo]) {
                self.slots[lo].copy_from(row);
            }
            if !self.slots[hi].set || y > value(&self.slots[hi]) {
                self.slots[hi].copy_from(row);
            }
        }
        self.slots[last].copy_from(row);
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A row at `t` whose bit channels and probe follow distinct signals with spikes.
    fn row_values(t: f64) -> ([f64; CHANNELS.len()], [f64; 1]) {
        let mut values = [0.0; CHANNELS.len()];
        values[at::T] = t;
        values[at::BIT_DISPLACEMENT] = t * 0.01 + (37.0 * t).sin() * 1e-4;
        values[at::BIT_VELOCITY] = (5.0 * t).sin()
            + if ((t * 1e3).round() as u64).is_multiple_of(997) {
                3.0
            } else {
                0.0
            };
        values[at::BIT_ROTATION] = 6.0 * t;
        values[at::BIT_ANGULAR_VELOCITY] = 6.0 + (11.0 * t).cos() * (t * 0.3).sin();
        (values, [1e-3 * (23.0 * t).sin().abs()])
    }

    fn record_all(sink: &mut impl Sink, n: usize, dt: f64) {
        for i in 0..=n {
            let (values, probe) = row_values(i as f64 * dt);
            let row = Row {
                values,
                nodes_in_contact: 0,
                contact_onsets: i as u64,
                probe_radial: &probe,
            };
            assert!(sink.record(&row));
        }
    }

    /// The extremes per plot interval of the bounded history are those of the whole history
    /// (the reference: every row kept), for each plotted curve, and so are the first and last
    /// samples; it holds far fewer rows.
    #[test]
    fn the_extremes_per_plot_interval_are_those_of_the_whole_history() {
        let (n, dt) = (200_000, 5e-4);
        let duration = n as f64 * dt;
        let mut full = TimeSeries::with_probes(&[1.0], 0);
        record_all(&mut full, n, dt);
        let mut bounded = PlotHistory::new(&[1.0], duration, 400, None);
        record_all(&mut bounded, n, dt);
        let kept = bounded.into_series();
        assert!(kept.len() <= 400 * 11 + 2, "{}", kept.len());
        assert!(kept.len() < n / 20);
        assert_eq!(kept.t[0], 0.0);
        assert_eq!(*kept.t.last().unwrap(), *full.t.last().unwrap());
        assert!(kept.t.windows(2).all(|w| w[0] < w[1]));
        let plot_intervals = 100;
        let extremes = |s: &TimeSeries, y: &[f64]| -> Vec<(f64, f64)> {
            let mut out = vec![(f64::INFINITY, f64::NEG_INFINITY); plot_intervals + 1];
            for (t, v) in s.t.iter().zip(y) {
                let b = (t / (duration / plot_intervals as f64)).floor() as usize;
                out[b] = (out[b].0.min(*v), out[b].1.max(*v));
            }
            out
        };
        for k in PLOTTED {
            assert_eq!(
                extremes(&kept, CHANNELS[k].values(&kept)),
                extremes(&full, CHANNELS[k].values(&full)),
                "{}",
                CHANNELS[k].name
            );
        }
        assert_eq!(
            extremes(&kept, &kept.probe_radial[0]),
            extremes(&full, &full.probe_radial[0])
        );
        // Every kept row is a row of the run, whole.
        let i = kept.len() / 2;
        let j = (kept.t[i] / dt).round() as usize;
        let mut a = [0.0];
        let mut b = [0.0];
        assert_eq!(kept.row(i, &mut a), full.row(j, &mut b));
    }

    #[test]
    fn a_short_run_keeps_every_row() {
        let mut bounded = PlotHistory::new(&[1.0], 1.0, 400, Some(1001));
        record_all(&mut bounded, 1000, 1e-3);
        let mut full = TimeSeries::with_probes(&[1.0], 0);
        record_all(&mut full, 1000, 1e-3);
        let kept = bounded.into_series();
        assert_eq!(kept.t, full.t);
        assert_eq!(kept.bit_velocity, full.bit_velocity);
        assert_eq!(kept.probe_radial, full.probe_radial);
    }
}
