//! Writing results to disk: atomic file writes ([`write_atomic`], [`write_json_atomic`]), the time
//! history as CSV ([`timeseries_csv`]), the stress envelope along the string as CSV and SVG
//! ([`envelope_csv`], [`plot_stress_envelope`]), every evaluation of a study as CSV ([`evaluations_csv`]),
//! the Campbell diagram of `drillopt campbell` ([`plot_campbell`], [`CampbellJson`]),
//! and SVG plots after the seed paper's Figs. 3–5 ([`plot_bit_axial`], [`plot_bit_rotation`], [`plot_probe_radial`], built on [`plot_panels`]).
//!
//! Every file is written whole or not at all (temporary file, fsync, rename), so an interrupted
//! run never leaves a truncated CSV or SVG behind. Units are SI in files (m, s, rad, N, J); plots
//! show the units a driller reads on the terminal ([`MetricDisplay`]: rpm, m/h, kN, kN·m, MPa;
//! radial displacements in mm).

mod atomic;
mod axes;
mod campbell;
mod csv;
mod envelope;
mod evaluations_csv;
mod fidelity_json;
mod plots;
mod study_json;
mod study_plots;
mod summary;
#[cfg(test)]
mod testdata;
mod units;

pub use atomic::{write_atomic, write_json_atomic};
pub use axes::{PLOT_BUCKETS, decimate_min_max};
pub use campbell::{
    CampbellJson, CampbellModeJson, CampbellPlot, CampbellPointJson, LinearisationJson,
    plot_campbell,
};
pub use csv::{CsvStream, probe_column_name, probe_label, timeseries_csv, write_timeseries_csv};
pub use envelope::{envelope_csv, plot_stress_envelope, write_envelope_csv};
pub use evaluations_csv::{evaluations_csv, write_evaluations_csv};
pub use fidelity_json::{
    ByFidelity, CandidateJson, ConfirmationJson, ExploreJson, FidelityWork, RefinementJson,
    explore_score_of,
};
pub use plots::{
    Panel, PlotError, plot_bit_axial, plot_bit_rotation, plot_panels, plot_panels_over,
    plot_probe_radial,
};
pub use study_json::{
    CompareJson, ConstraintsJson, EvaluationJson, LinearJson, MapJson, ObjectiveJson, PointJson,
    ProblemRecord, SolutionJson, StudyHeader, WorkJson,
};
pub use study_plots::{
    ConstraintLine, EvaluatedPoint, Mark, MarkKind, MetricRow, OverlayRun, Region, SetPointAxis,
    StarredPoint, plot_bit_speed_overlay, plot_heatmap, plot_metric_samples, plot_optimizer_path,
};
pub use summary::{NotStartedJson, RunStatus, SummaryJson};
pub use units::{
    M_PER_H_PER_M_PER_S, MetricDisplay, REV_PER_RAD, RPM_PER_RAD_S, fmt_sig, operating_point_text,
    short,
};
