//! Writing results to disk: atomic file writes ([`write_atomic`], [`write_json_atomic`]), the time
//! history as CSV ([`timeseries_csv`]) and SVG plots after the seed paper's Figs. 3–5
//! ([`plot_bit_axial`], [`plot_bit_rotation`], [`plot_probe_radial`], built on [`plot_panels`]).
//!
//! Every file is written whole or not at all (temporary file, fsync, rename), so an interrupted
//! run never leaves a truncated CSV or SVG behind. Units are SI in files (m, s, rad, N, J); plots
//! show radial displacements in mm.

mod atomic;
mod csv;
mod plots;
mod study_json;
mod study_plots;
mod summary;
#[cfg(test)]
mod testdata;

pub use atomic::{write_atomic, write_json_atomic};
pub use csv::{probe_column_name, timeseries_csv, write_timeseries_csv};
pub use plots::{
    PLOT_BUCKETS, Panel, PlotError, decimate_min_max, plot_bit_axial, plot_bit_rotation,
    plot_panels, plot_probe_radial,
};
pub use study_json::{
    CompareJson, ConstraintsJson, EvaluationJson, LinearJson, MapJson, ObjectiveJson, PointJson,
    ProblemRecord, SolutionJson, StudyHeader, WorkJson,
};
pub use study_plots::{
    ConstraintLine, EvaluatedPoint, Region, plot_bit_speed_overlay, plot_heatmap,
    plot_metric_samples, plot_optimizer_path,
};
pub use summary::{OperatingPointJson, RunStatus, SummaryJson};
