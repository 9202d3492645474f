//! What a command will cost, before it runs: an estimate of its peak memory and CPU time from
//! the mesh, the basis, the simulated time, the number of simulations and of models held, and
//! the threads; refused beyond the machine's available memory (naming the input that drives the
//! estimate), warned beyond [`WARN_CPU_HOURS`].
//!
//! The memory terms, each measured on this code (`/usr/bin/time -f %M`):
//! * building a reduced model assembles three dense matrices of the D = 6(N + 1) DOFs and
//!   projects them: a peak of about 5 D² doubles while it is built (2000 elements: 5.9 GB
//!   measured, 5.8 GB estimated; 105 elements: 35 MB in all);
//! * a built model holds Φ (D × m) about four times (Φ, its family blocks, its non-zeros, the
//!   residual's scratch) and a few m × m operators;
//! * a study holds, per finished simulation, its metrics, its cache record and its share of the
//!   per-point results: [`BYTES_PER_RESULT`];
//! * a run's plots hold at most `PLOT_BUCKETS × (2 curves + 1)` rows ([`crate::sim::PlotHistory`]).
//!
//! The CPU time is an upper estimate, not a prediction: [`CPU_S_PER_ELEMENT_MODE`] is the cost of
//! the seed string's stick-slipping run with wall contact (65 CPU s for 90 s of 105 elements and
//! 50 vectors); a string at a steady state costs far less (the 1 km field well: 30× less).

use crate::model::{BasisSpec, FamilySize};

/// Bytes a study holds per finished simulation (metrics, cache record, per-point share).
pub const BYTES_PER_RESULT: f64 = 4096.0;

/// CPU seconds per element, per basis vector and per simulated second (the seed's
/// stick-slipping run: 65 s / (105 × 50 × 90 s)); an upper estimate (module doc).
pub const CPU_S_PER_ELEMENT_MODE: f64 = 1.4e-4;

/// The unreduced model's cost relative to the reduced one at the same mesh (docs/model.md).
pub const UNREDUCED_FACTOR: f64 = 100.0;

/// Beyond this many CPU hours a command says so before it starts.
pub const WARN_CPU_HOURS: f64 = 1.0;

/// What a command is about to do.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Work {
    /// Elements of the mesh the models are built on (the finest, for `verify`'s refinement).
    pub elements: usize,
    /// Basis vectors of a model.
    pub modes: usize,
    /// Simulations to run.
    pub simulations: u64,
    /// Simulated time of each, s.
    pub seconds_each: f64,
    /// Models held at once (one per sample when the samples change the linear operators).
    pub models_held: usize,
    /// Models built at the same time (the threads).
    pub concurrent: usize,
    /// Whether results are held per simulation (a study), or streamed (one `simulate`).
    pub holds_results: bool,
    /// Whether the model is the unreduced finite-element model.
    pub unreduced: bool,
}

/// The input that drives a memory term, for the refusal.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Driver {
    /// The mesh (`mesh.elements`).
    Mesh,
    /// The basis held per model (`mesh.basis`, the samples).
    Models,
    /// The results held (`uncertain.samples`, the points).
    Results,
}

/// The estimate of [`Work`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Estimate {
    /// Peak memory, bytes.
    pub peak_bytes: f64,
    /// The largest term and what drives it.
    pub largest: (Driver, f64),
    /// CPU seconds, an upper estimate (module doc).
    pub cpu_seconds: f64,
}

impl Work {
    /// DOFs of the mesh, 6(N + 1).
    pub fn dofs(&self) -> f64 {
        6.0 * (self.elements as f64 + 1.0)
    }

    /// The estimate (module doc).
    pub fn estimate(&self) -> Estimate {
        let d = self.dofs();
        let m = if self.unreduced { d } else { self.modes as f64 };
        let double = 8.0;
        let construction = 5.0 * d * d * double * self.concurrent.max(1) as f64;
        let per_model = (4.0 * d * m + 4.0 * m * m) * double;
        let models =
            per_model * self.models_held.max(1) as f64 + per_model * self.concurrent.max(1) as f64;
        let results = if self.holds_results {
            BYTES_PER_RESULT * self.simulations as f64
        } else {
            0.0
        };
        // The binary, its runtime and the problem: about 24 MB measured at rest.
        let base = 24e6;
        let terms = [
            (Driver::Mesh, construction),
            (Driver::Models, models),
            (Driver::Results, results),
        ];
        let largest = terms
            .into_iter()
            .fold((Driver::Mesh, 0.0), |a, b| if b.1 > a.1 { b } else { a });
        let factor = if self.unreduced {
            UNREDUCED_FACTOR
        } else {
            1.0
        };
        Estimate {
            // Construction is transient and the results come after it: the larger of the two
            // beside what stays.
            peak_bytes: base + models + construction.max(results),
            largest,
            cpu_seconds: CPU_S_PER_ELEMENT_MODE
                * factor
                * self.elements as f64
                * self.modes as f64
                * self.seconds_each
                * self.simulations as f64,
        }
    }
}

/// The number of basis vectors of `spec` (a cutoff counts its minimum; the refinement a cutoff
/// adds is not known before the eigen-solve).
pub fn basis_size(spec: &BasisSpec) -> usize {
    let count = |f: FamilySize| match f {
        FamilySize::Count(n) => n,
        FamilySize::Cutoff { min, .. } => min,
    };
    match *spec {
        BasisSpec::Lowest(n) => n,
        BasisSpec::PerFamily {
            bending,
            torsional,
            axial,
            static_corrections,
        } => {
            2 * count(bending)
                + count(torsional)
                + count(axial)
                + if static_corrections { 4 } else { 0 }
        }
    }
}

/// The memory this machine has available now, bytes (`MemAvailable` of `/proc/meminfo`); `None`
/// where it cannot be read (then nothing is refused for memory).
pub fn available_memory() -> Option<f64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = text.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kb: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024.0)
}

/// Bytes as a driller reads them: `5.8 GB`, `35 MB`.
pub fn bytes_text(b: f64) -> String {
    if b >= 1e12 {
        format!("{:.1} TB", b / 1e12)
    } else if b >= 1e9 {
        format!("{:.1} GB", b / 1e9)
    } else {
        format!("{:.0} MB", (b / 1e6).max(1.0))
    }
}

/// A duration as a driller reads it: `40 s`, `12 min`, `3.5 h`, `2.1 days`.
pub fn seconds_text(s: f64) -> String {
    if s < 120.0 {
        format!("{s:.0} s")
    } else if s < 7200.0 {
        format!("{:.0} min", s / 60.0)
    } else if s < 3.0 * 86_400.0 {
        format!("{:.1} h", s / 3600.0)
    } else {
        format!("{:.1} days", s / 86_400.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn work(elements: usize) -> Work {
        Work {
            elements,
            modes: 50,
            simulations: 1,
            seconds_each: 90.0,
            models_held: 1,
            concurrent: 1,
            holds_results: false,
            unreduced: false,
        }
    }

    /// The terms against what was measured: the seed (105 elements, 50 vectors, 90 s) in
    /// 35 MB and 65 CPU s; 2000 elements' construction 5.9 GB.
    #[test]
    fn the_estimate_reproduces_the_measured_runs() {
        let seed = work(105).estimate();
        assert!(
            seed.peak_bytes > 30e6 && seed.peak_bytes < 120e6,
            "{seed:?}"
        );
        assert!((seed.cpu_seconds - 66.0).abs() < 5.0, "{seed:?}");
        let long = work(2000).estimate();
        assert!((long.peak_bytes / 5.9e9 - 1.0).abs() < 0.15, "{long:?}");
        assert_eq!(long.largest.0, Driver::Mesh);
    }

    #[test]
    fn a_study_holds_its_results_and_its_models() {
        let mut w = work(105);
        w.holds_results = true;
        w.simulations = 400 * 10_000;
        let e = w.estimate();
        assert_eq!(e.largest.0, Driver::Results);
        assert!(e.peak_bytes > 16e9, "{e:?}");
        w.simulations = 10;
        w.models_held = 100_000;
        assert_eq!(w.estimate().largest.0, Driver::Models);
    }

    #[test]
    fn basis_sizes_count_both_bending_planes_and_the_corrections() {
        assert_eq!(basis_size(&BasisSpec::DEFAULT), 2 * 16 + 8 + 4 + 4);
        assert_eq!(basis_size(&BasisSpec::Lowest(51)), 51);
    }

    #[test]
    fn sizes_and_times_read_as_a_driller_reads_them() {
        assert_eq!(bytes_text(5.86e9), "5.9 GB");
        assert_eq!(bytes_text(1.6389e12), "1.6 TB");
        assert_eq!(bytes_text(35e6), "35 MB");
        assert_eq!(seconds_text(40.2), "40 s");
        assert_eq!(seconds_text(720.0), "12 min");
        assert_eq!(seconds_text(12_600.0), "3.5 h");
        assert_eq!(seconds_text(181_440.0), "50.4 h");
        assert_eq!(seconds_text(1_615_680.0), "18.7 days");
    }
}
