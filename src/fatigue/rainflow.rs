//! Rainflow cycle counting (ASTM E1049-85 (reapproved 2017), "Standard Practices for Cycle
//! Counting in Fatigue Analysis", §5.4.4), in two independent forms:
//!
//! - [`Rainflow`], the streaming counter the simulator runs at every accepted step: it finds the
//!   turning points (peaks and valleys) of the signal as the samples arrive and counts them by the
//!   **four-point** rule (four consecutive turning points S1..S4 with ranges ΔS1 = |S2 − S1|,
//!   ΔS2 = |S3 − S2|, ΔS3 = |S4 − S3|: if ΔS2 ≤ ΔS1 and ΔS2 ≤ ΔS3, ΔS2 is one full cycle and S2,
//!   S3 are discarded). What is never closed, the *residue*, is counted as half cycles, one per
//!   range between consecutive residue points, when the signal ends ([`Rainflow::finish`]).
//! - [`astm_cycles`], the standard's own **three-point** procedure on a whole history (the
//!   reference the tests compare the streaming counter with): X the most recent range, Y the one
//!   before it, S the starting point; X ≥ Y counts Y as a full cycle, or as a half cycle when Y
//!   contains S (then S moves on); the ranges left at the end are half cycles.
//!
//! The two give the same cycles (the four-point residue's diverging part is what the three-point
//! rule counts as half cycles on the way; the tests check the standard's example and random
//! histories). Ranges are absolute differences, in the unit of the signal.
//!
//! # Memory
//! The streaming counter keeps its turning points in a fixed array of [`RAINFLOW_CAPACITY`]; it
//! never allocates. The residue is a diverging-then-converging sequence and stays short in
//! practice (a few tens of points). Should it fill up, the oldest point is retired with its range
//! counted as a half cycle ([`Rainflow::overflows`] counts it). That is exact while the residue
//! still diverges at its start (the range |S1 − S0| < |S2 − S1| can never close again: the range
//! from S1 to its neighbour only grows as inner cycles are removed), and an approximation for a
//! residue that converges over its whole length (a long decaying ring-down).

/// Turning points the streaming counter keeps.
pub const RAINFLOW_CAPACITY: usize = 64;

/// A streaming rainflow counter of one signal (see the module documentation). Feed it samples
/// with [`push`](Self::push); every closed cycle is handed to the sink as (range, count), count
/// 1 for a full cycle and ½ for a half cycle.
#[derive(Debug, Clone, PartialEq)]
#[repr(C)] // what every sample touches first, in one cache line
pub struct Rainflow {
    /// The extreme of the current leg: the candidate turning point.
    extreme: f64,
    /// +1 rising, −1 falling, 0 before the signal has moved.
    trend: i8,
    started: bool,
    len: usize,
    overflows: u64,
    /// Turning points not yet closed (the residue), oldest first.
    stack: [f64; RAINFLOW_CAPACITY],
}

impl Default for Rainflow {
    fn default() -> Self {
        Rainflow {
            stack: [0.0; RAINFLOW_CAPACITY],
            len: 0,
            extreme: 0.0,
            trend: 0,
            started: false,
            overflows: 0,
        }
    }
}

impl Rainflow {
    /// An empty counter.
    pub fn new() -> Self {
        Self::default()
    }

    /// Add the next sample `x`; cycles it closes go to `sink(range, count)`.
    #[inline]
    pub fn push(&mut self, x: f64, sink: &mut impl FnMut(f64, f64)) {
        if !self.started {
            self.started = true;
            self.extreme = x;
            self.add_point(x, sink);
            return;
        }
        let step = x - self.extreme;
        match self.trend {
            0 => {
                if step != 0.0 {
                    self.trend = if step > 0.0 { 1 } else { -1 };
                    self.extreme = x;
                }
            }
            t => {
                if step * f64::from(t) >= 0.0 {
                    self.extreme = x;
                } else {
                    // The leg turned: its extreme is a peak or a valley.
                    self.add_point(self.extreme, sink);
                    self.trend = -t;
                    self.extreme = x;
                }
            }
        }
    }

    /// End of the signal: its last sample is the last turning point, and every range of the
    /// residue is counted as a half cycle. The counter is then empty (a new signal may start).
    pub fn finish(&mut self, sink: &mut impl FnMut(f64, f64)) {
        if self.trend != 0 {
            self.add_point(self.extreme, sink);
        }
        for k in 1..self.len {
            sink((self.stack[k] - self.stack[k - 1]).abs(), 0.5);
        }
        let overflows = self.overflows;
        *self = Self::default();
        self.overflows = overflows;
    }

    /// How many times the residue filled [`RAINFLOW_CAPACITY`] and its oldest point was retired
    /// (see the module documentation); 0 in every run seen so far.
    pub fn overflows(&self) -> u64 {
        self.overflows
    }

    /// Turning points held now.
    pub fn residue_len(&self) -> usize {
        self.len
    }

    fn add_point(&mut self, p: f64, sink: &mut impl FnMut(f64, f64)) {
        if self.len == RAINFLOW_CAPACITY {
            sink((self.stack[1] - self.stack[0]).abs(), 0.5);
            self.stack.copy_within(1.., 0);
            self.len -= 1;
            self.overflows += 1;
        }
        self.stack[self.len] = p;
        self.len += 1;
        // Four-point rule on the newest four points, repeated while it closes cycles (only
        // windows that hold the new point can close: the older ones were checked before).
        while self.len >= 4 {
            let n = self.len;
            let (a, b, c, d) = (
                self.stack[n - 4],
                self.stack[n - 3],
                self.stack[n - 2],
                self.stack[n - 1],
            );
            let inner = (c - b).abs();
            if inner <= (b - a).abs() && inner <= (d - c).abs() {
                sink(inner, 1.0);
                self.stack[n - 3] = d;
                self.len -= 2;
            } else {
                break;
            }
        }
    }
}

/// One counted cycle: its range and count (1 full, ½ half).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cycle {
    pub range: f64,
    pub count: f64,
}

/// The turning points of a history: its first and last samples and every sample where it turns
/// (plateaus collapsed), as ASTM E1049-85 §5.4.4 reads "peaks and valleys".
pub fn turning_points(history: &[f64]) -> Vec<f64> {
    let mut points: Vec<f64> = Vec::new();
    for &x in history {
        match points.len() {
            0 => points.push(x),
            1 => {
                if x != points[0] {
                    points.push(x);
                }
            }
            n => {
                let (a, b) = (points[n - 2], points[n - 1]);
                if x == b {
                    continue;
                }
                if (b - a) * (x - b) > 0.0 {
                    points[n - 1] = x; // same direction: the leg goes on
                } else {
                    points.push(x);
                }
            }
        }
    }
    points
}

/// Rainflow cycles of a whole history by the three-point procedure of ASTM E1049-85 §5.4.4,
/// steps (1)–(6), in the order the standard counts them.
pub fn astm_cycles(history: &[f64]) -> Vec<Cycle> {
    let mut cycles = Vec::new();
    let mut stack: Vec<f64> = Vec::new(); // stack[0] is the starting point S
    for p in turning_points(history) {
        stack.push(p);
        while stack.len() >= 3 {
            let n = stack.len();
            let x = (stack[n - 1] - stack[n - 2]).abs();
            let y = (stack[n - 2] - stack[n - 3]).abs();
            if x < y {
                break;
            }
            if n == 3 {
                // Y contains S: half a cycle, S moves to Y's second point.
                cycles.push(Cycle {
                    range: y,
                    count: 0.5,
                });
                stack.remove(0);
            } else {
                cycles.push(Cycle {
                    range: y,
                    count: 1.0,
                });
                stack.drain(n - 3..n - 1);
            }
        }
    }
    for w in stack.windows(2) {
        cycles.push(Cycle {
            range: (w[1] - w[0]).abs(),
            count: 0.5,
        });
    }
    cycles
}

/// Every cycle of a history by the streaming counter, in the order it counts them.
pub fn streaming_cycles(history: &[f64]) -> Vec<Cycle> {
    let mut cycles = Vec::new();
    let mut counter = Rainflow::new();
    let mut sink = |range, count| cycles.push(Cycle { range, count });
    for &x in history {
        counter.push(x, &mut sink);
    }
    counter.finish(&mut sink);
    cycles
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{RngExt, SeedableRng};

    /// Total count per range, ranges sorted (exact ranges: differences of the same samples).
    fn table(cycles: &[Cycle]) -> Vec<(f64, f64)> {
        let mut sorted = cycles.to_vec();
        sorted.sort_by(|a, b| a.range.total_cmp(&b.range));
        let mut out: Vec<(f64, f64)> = Vec::new();
        for c in sorted {
            match out.last_mut() {
                Some(last) if last.0 == c.range => last.1 += c.count,
                _ => out.push((c.range, c.count)),
            }
        }
        out
    }

    /// ASTM E1049-85, §5.4.4 and its Fig. 6: the history −2, 1, −3, 5, −1, 3, −4, 4, −2 counts
    /// (by hand, steps (1)–(6)): ½ of 3 (−2→1, S), ½ of 4 (1→−3, S), 1 of 4 (−1→3), ½ of 8
    /// (−3→5, S), then the residue 5, −4, 4, −2 as ½ of 9, ½ of 8, ½ of 6. The standard's table:
    /// range 3: 0.5, 4: 1.5, 6: 0.5, 8: 1.0, 9: 0.5, none of 10, 7 or 5.
    #[test]
    fn the_standards_example_gives_its_published_table() {
        let history = [-2.0, 1.0, -3.0, 5.0, -1.0, 3.0, -4.0, 4.0, -2.0];
        let published = vec![(3.0, 0.5), (4.0, 1.5), (6.0, 0.5), (8.0, 1.0), (9.0, 0.5)];
        assert_eq!(table(&astm_cycles(&history)), published);
        assert_eq!(table(&streaming_cycles(&history)), published);
        // The same history sampled finely (straight lines between the points) counts the same.
        let mut fine = Vec::new();
        for w in history.windows(2) {
            for k in 0..10 {
                fine.push(w[0] + (w[1] - w[0]) * k as f64 / 10.0);
            }
        }
        fine.push(-2.0);
        assert_eq!(table(&streaming_cycles(&fine)), published);
    }

    #[test]
    fn streaming_equals_the_standards_procedure_on_random_histories() {
        let mut rng = rand_chacha::ChaCha20Rng::seed_from_u64(14);
        for trial in 0..300 {
            let n = rng.random_range(2..400);
            // A random walk with occasional large jumps: long residues and nested cycles.
            let mut x = 0.0;
            let history: Vec<f64> = (0..n)
                .map(|_| {
                    let scale = if rng.random_range(0.0..1.0) < 0.05 {
                        20.0
                    } else {
                        1.0
                    };
                    x += scale * rng.random_range(-1.0..1.0);
                    x
                })
                .collect();
            let (a, s) = (astm_cycles(&history), streaming_cycles(&history));
            assert_eq!(table(&a), table(&s), "trial {trial}");
            // Every range is counted once over the history: twice the counts over all cycles
            // equals the number of turning-point ranges closed as full cycles (2 each) and half
            // cycles (1 each), which is the number of turning points less one.
            let halves: f64 = s.iter().map(|c| 2.0 * c.count).sum();
            assert_eq!(halves as usize, turning_points(&history).len() - 1);
        }
    }

    #[test]
    fn a_sine_counts_one_full_cycle_of_twice_its_amplitude_per_period() {
        let (amplitude, periods, per_period) = (3.0, 20, 64);
        let history: Vec<f64> = (0..=periods * per_period)
            .map(|k| {
                let phase = std::f64::consts::TAU * k as f64 / per_period as f64;
                amplitude * (phase + 0.3).sin()
            })
            .collect();
        let cycles = streaming_cycles(&history);
        let full: f64 = cycles
            .iter()
            .filter(|c| c.count == 1.0)
            .map(|c| c.count)
            .sum();
        let total: f64 = cycles.iter().map(|c| c.count).sum();
        // The largest peak and valley stay in the residue (two half cycles of the full range),
        // with the partial legs at the ends: every other period closes as a full cycle.
        assert!(full >= (periods - 2) as f64, "{full}");
        assert!((total - periods as f64).abs() <= 1.0, "{total}");
        for c in cycles.iter().filter(|c| c.count == 1.0) {
            // Sampled every 1/64 period: the sampled peak is within cos(π/64) of the true one.
            assert!((c.range / (2.0 * amplitude) - 1.0).abs() < 2e-3, "{c:?}");
        }
    }

    #[test]
    fn a_full_residue_retires_its_oldest_point_without_allocating() {
        // A diverging history longer than the capacity: every retired range is a half cycle
        // that the standard's procedure counts too (exact for a diverging residue).
        let history: Vec<f64> = (0..3 * RAINFLOW_CAPACITY)
            .map(|k| if k % 2 == 0 { 1.0 } else { -1.0 } * (k + 1) as f64)
            .collect();
        let mut counter = Rainflow::new();
        let mut cycles = Vec::new();
        let mut sink = |range, count| cycles.push(Cycle { range, count });
        for &x in &history {
            counter.push(x, &mut sink);
        }
        assert!(counter.overflows() > 0);
        assert!(counter.residue_len() <= RAINFLOW_CAPACITY);
        counter.finish(&mut sink);
        assert_eq!(table(&cycles), table(&astm_cycles(&history)));
    }
}
