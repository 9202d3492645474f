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

/// The least CPU seconds per simulated second of any run: the step's fixed work (the Newton
/// solve, the recorder) dominates a small model (the 12-element string with 16 vectors: 0.28 s
/// per simulated second over 30 s, 0.056 s over runs of 1.5 s).
pub const MIN_CPU_S_PER_SECOND: f64 = 0.3;

/// The unreduced model's cost relative to the reduced one at the same mesh (docs/model.md).
pub const UNREDUCED_FACTOR: f64 = 100.0;

/// CPU seconds of one eigen-solve of the Campbell diagram's first-order form, per cubed state
/// size s = 2n (faer's general real eigendecomposition with the labelling of its modes): 2.8 s per
/// rotation speed at s ≈ 600 (the 8 m string on 50 elements, unreduced; 12.1 s for 4 speeds,
/// 23.3 s for 8) and 73 s for 2 speeds and the crossings at s ≈ 1200 (100 elements).
pub const CPU_S_PER_STATE_CUBED: f64 = 1.3e-8;

/// Bytes held per squared state size of that eigen-solve (the first-order matrix, its Schur form
/// and the complex eigenvectors): 120 MB measured at s ≈ 1200.
pub const BYTES_PER_STATE_SQUARED: f64 = 96.0;

/// Eigen-solves a Campbell diagram adds to its rotation speeds to refine the critical speeds
/// (an allowance: 1.2 measured for two crossings at 100 elements).
pub const CAMPBELL_REFINEMENT_SOLVES: u64 = 8;

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
    /// Dense eigen-solves of the first-order form of the model's linearisation (the Campbell
    /// diagram's rotation speeds and refinements; 0 for a simulation command). Their state size
    /// is twice the basis, or twice the DOFs when `unreduced`.
    pub eigensolves: u64,
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
    /// The dense eigen-solve of the Campbell diagram (`--unreduced`, `mesh.elements`).
    Eigensolve,
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

    /// The state size of the first-order eigenproblem, 2n (n: the basis, or the DOFs unreduced).
    pub fn states(&self) -> f64 {
        2.0 * if self.unreduced {
            self.dofs()
        } else {
            self.modes as f64
        }
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
        let s = self.states();
        let eigen = if self.eigensolves > 0 {
            BYTES_PER_STATE_SQUARED * s * s
        } else {
            0.0
        };
        let terms = [
            (Driver::Mesh, construction),
            (Driver::Models, models),
            (Driver::Results, results),
            (Driver::Eigensolve, eigen),
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
            peak_bytes: base + models + construction.max(results).max(eigen),
            largest,
            cpu_seconds: (CPU_S_PER_ELEMENT_MODE * self.elements as f64 * self.modes as f64)
                .max(MIN_CPU_S_PER_SECOND)
                * factor
                * self.seconds_each
                * self.simulations as f64
                + CPU_S_PER_STATE_CUBED * s * s * s * self.eigensolves as f64,
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
            steady_shapes,
        } => {
            // The bit's two static corrections and two resting shapes per plane; up to two
            // steady-state shapes per plane.
            2 * count(bending)
                + count(torsional)
                + count(axial)
                + match (static_corrections, steady_shapes) {
                    (false, _) => 0,
                    (true, false) => 6,
                    (true, true) => 10,
                }
        }
    }
}

/// The memory this process may use now, bytes: what the machine has available (`MemAvailable`
/// of `/proc/meminfo`), or less when the process's address space is limited (`ulimit -v`,
/// `prlimit --as`: a 2000-element build then failed in an allocation instead of being refused);
/// `None` where neither can be read (then nothing is refused for memory).
pub fn available_memory() -> Option<f64> {
    let machine = std::fs::read_to_string("/proc/meminfo")
        .ok()
        .and_then(|text| {
            let line = text.lines().find(|l| l.starts_with("MemAvailable:"))?;
            let kb: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
            Some(kb * 1024.0)
        });
    match (machine, address_space_limit()) {
        (Some(m), Some(l)) => Some(m.min(l)),
        (m, l) => m.or(l),
    }
}

/// The soft limit of the process's address space, bytes; `None` when unlimited or unknown.
#[cfg(unix)]
fn address_space_limit() -> Option<f64> {
    let mut limit = std::mem::MaybeUninit::<libc::rlimit>::uninit();
    // SAFETY: getrlimit fills the struct on success (return 0); it is read only then.
    let ok = unsafe { libc::getrlimit(libc::RLIMIT_AS, limit.as_mut_ptr()) } == 0;
    if !ok {
        return None;
    }
    // SAFETY: initialised by the successful call above.
    let limit = unsafe { limit.assume_init() };
    if limit.rlim_cur == libc::RLIM_INFINITY {
        return None;
    }
    // What is mapped already (the binary, the thread stacks) counts against the limit.
    let mapped = std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| {
            let line = s.lines().find(|l| l.starts_with("VmSize:"))?;
            line.split_whitespace().nth(1)?.parse::<f64>().ok()
        })
        .map_or(0.0, |kb| kb * 1024.0);
    Some((limit.rlim_cur as f64 - mapped).max(0.0))
}

#[cfg(not(unix))]
fn address_space_limit() -> Option<f64> {
    None
}

/// Bytes of `timeseries.csv` per row: every channel, the contact counts and each probe, about
/// 18 characters each (the seed's 30 s at 0.5 ms with one probe: 21.5 MB for 60 001 rows, 358 B
/// per row; this gives 378).
pub fn csv_bytes_per_row(probes: usize) -> f64 {
    18.0 * (crate::sim::CHANNELS.len() + 2 + probes) as f64
}

/// Free space for `dir` (the filesystem of its nearest existing ancestor), bytes; `None` where it
/// cannot be read (then nothing is refused for disk).
pub fn available_disk(dir: &std::path::Path) -> Option<f64> {
    let existing = dir
        .ancestors()
        .find(|a| a.exists() && !a.as_os_str().is_empty())?;
    free_space(existing)
}

#[cfg(unix)]
fn free_space(path: &std::path::Path) -> Option<f64> {
    use std::os::unix::ffi::OsStrExt;
    let c = std::ffi::CString::new(path.as_os_str().as_bytes()).ok()?;
    let mut stat = std::mem::MaybeUninit::<libc::statvfs>::uninit();
    // SAFETY: a NUL-terminated path and a buffer of the struct's size; statvfs fills it on
    // success (return 0) and we read it only then.
    let ok = unsafe { libc::statvfs(c.as_ptr(), stat.as_mut_ptr()) } == 0;
    ok.then(|| {
        // SAFETY: initialised by the successful call above.
        let stat = unsafe { stat.assume_init() };
        stat.f_bavail as f64 * stat.f_frsize as f64
    })
}

#[cfg(not(unix))]
fn free_space(_: &std::path::Path) -> Option<f64> {
    None
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
            eigensolves: 0,
        }
    }

    /// A Campbell diagram: the unreduced 100-element string (2 speeds, 73 s, 120 MB measured)
    /// and the 200-element one that ran beyond 11 CPU min for 5 speeds; the 2000-element one
    /// cannot be held (about 55 GB).
    #[test]
    fn a_campbell_diagram_costs_its_dense_eigen_solves() {
        let campbell = |elements, points| Work {
            simulations: 0,
            seconds_each: 0.0,
            unreduced: true,
            eigensolves: points + CAMPBELL_REFINEMENT_SOLVES,
            ..work(elements)
        };
        let e = campbell(100, 2).estimate();
        assert!(e.cpu_seconds > 73.0 && e.cpu_seconds < 4.0 * 73.0, "{e:?}");
        assert!(e.peak_bytes > 120e6 && e.peak_bytes < 3.0 * 120e6, "{e:?}");
        assert!(campbell(200, 5).estimate().cpu_seconds > 11.0 * 60.0);
        let long = campbell(2000, 91).estimate();
        assert_eq!(long.largest.0, Driver::Eigensolve);
        assert!(long.peak_bytes > 50e9, "{long:?}");
        // The reduced seed's diagram: 0.34 s measured for 91 speeds.
        let reduced = Work {
            unreduced: false,
            ..campbell(105, 91)
        };
        let t = reduced.estimate().cpu_seconds;
        assert!(t > 0.34 && t < 5.0, "{t}");
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
        let mut small = work(12);
        small.modes = 16;
        small.seconds_each = 1.5;
        small.simulations = 30_012;
        // 42 min measured on one thread (the second campaign's 10 000-sample solve); 8.47 CPU s
        // for 30 s of the same string.
        let t = small.estimate().cpu_seconds;
        assert!(t > 2520.0 && t < 10.0 * 2520.0, "{t}");
        small.simulations = 1;
        small.seconds_each = 30.0;
        assert!(small.estimate().cpu_seconds >= 8.47);
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
    fn the_csv_row_estimate_is_near_the_measured_one_and_disk_space_is_read() {
        assert!((csv_bytes_per_row(1) / 358.0 - 1.0).abs() < 0.1);
        #[cfg(unix)]
        {
            let free = available_disk(std::path::Path::new("target/does/not/exist")).unwrap();
            assert!(free > 0.0);
        }
    }

    #[test]
    fn basis_sizes_count_both_bending_planes_and_the_corrections() {
        // 32 bending, 8 torsional, 4 axial, 2 static corrections and 4 resting shapes: the 50
        // vectors `drillopt modes` lists for the seed; 4 steady-state shapes more when asked.
        assert_eq!(basis_size(&BasisSpec::DEFAULT), 50);
        let BasisSpec::PerFamily {
            bending,
            torsional,
            axial,
            ..
        } = BasisSpec::DEFAULT
        else {
            unreachable!("the default is per family")
        };
        let steady = BasisSpec::PerFamily {
            bending,
            torsional,
            axial,
            static_corrections: true,
            steady_shapes: true,
        };
        assert_eq!(basis_size(&steady), 54);
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
