//! SVG plots of an optimisation study over the operating point (Ω, V0): the optimizer's path
//! through the feasible region ([`plot_optimizer_path`]), a score or metric over a grid
//! ([`plot_heatmap`]), the Monte Carlo samples of each metric at the optimum
//! ([`plot_metric_samples`]) and the bit speed of several runs overlaid
//! ([`plot_bit_speed_overlay`]).
//!
//! Axes show Ω in rpm and V0 in m/h; the caller converts from SI and passes constraint lines in
//! those units too (ω·Ω + v·V0 ≤ upper). Scores are maximised, so the colour scale (plotters'
//! viridis, `ViridisRGB`) runs from dark purple (low) to yellow (high). Points or cells without
//! a value are grey. Like [`super::plots`], each SVG is rendered in memory and written with
//! [`super::write_atomic`], and text is SVG `<text>`, so no font files are needed.
//!
//! One file per plot kind (`optimizer_path`, `heatmap`, `metric_samples`, `overlay`) on shared
//! pieces: sizes, colours, markers, numbers and the SVG writer (`style`), heat-map cells and
//! region clipping (`geometry`), colour bar, legend and layout of the side column (`side`).

mod geometry;
mod heatmap;
mod metric_samples;
mod optimizer_path;
mod overlay;
mod side;
mod style;
#[cfg(test)]
mod test_support;

pub use heatmap::plot_heatmap;
pub use metric_samples::{Mark, MarkKind, MetricRow, plot_metric_samples};
pub use optimizer_path::plot_optimizer_path;
pub use overlay::{OverlayRun, plot_bit_speed_overlay};

/// The box of operating points and the linear constraints on them, in plot units.
#[derive(Debug, Clone, PartialEq)]
pub struct Region {
    /// Bounds [low, high] of the rotational speed Ω, rpm.
    pub omega_rpm: [f64; 2],
    /// Bounds [low, high] of the set-point: V0 in m/h, or the WOB in kN under a hook load.
    pub set_point: [f64; 2],
    /// What the set-point axis is.
    pub kind: crate::model::SetPoint,
    /// Linear constraints; the feasible set is the box where all hold.
    pub lines: Vec<ConstraintLine>,
}

/// The linear constraint `omega_coef`·Ω + `set_point_coef`·s ≤ `upper` (Ω in rpm, the set-point s
/// in its plot unit, m/h or kN).
#[derive(Debug, Clone, PartialEq)]
pub struct ConstraintLine {
    /// Text drawn next to the line.
    pub label: String,
    /// Coefficient of Ω, per rpm (in the units of `upper`).
    pub omega_coef: f64,
    /// Coefficient of the set-point, per m/h or per kN (in the units of `upper`).
    pub set_point_coef: f64,
    /// Right-hand side.
    pub upper: f64,
}

/// A point marked with a star (Ω in rpm, V0 in m/h), and what it is, e.g. "best map node".
#[derive(Debug, Clone, PartialEq)]
pub struct StarredPoint {
    /// Rotational speed Ω, rpm.
    pub omega_rpm: f64,
    /// The set-point: V0 in m/h, or the WOB in kN.
    pub set_point: f64,
    /// What the point is, for the legend and the caption.
    pub label: String,
}

/// One operating point the optimizer evaluated.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EvaluatedPoint {
    /// Rotational speed Ω, rpm.
    pub omega_rpm: f64,
    /// The set-point: V0 in m/h, or the WOB in kN.
    pub set_point: f64,
    /// Robust score (maximised); None when the evaluation failed.
    pub score: Option<f64>,
    /// Whether the point satisfies every constraint.
    pub feasible: bool,
}
