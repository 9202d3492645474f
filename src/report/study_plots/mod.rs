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

/// The set-point axis of a study plot: which set-point (V0 or a hook load's WOB) and the unit
/// system it is shown in (m/h or ft/h; kN or klbf).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SetPointAxis {
    pub kind: crate::model::SetPoint,
    pub units: crate::units::UnitSystem,
}

impl SetPointAxis {
    /// "V0" or "WOB".
    pub fn symbol(self) -> &'static str {
        self.kind.symbol()
    }

    /// The axis' unit: m/h, ft/h, kN or klbf.
    pub fn unit(self) -> &'static str {
        self.units.convert_metric(self.kind.unit()).0
    }

    /// A set-point in SI (m/s or N) in the axis' unit.
    pub fn of_si(self, si: f64) -> f64 {
        self.units
            .from_metric(self.kind.unit(), self.kind.to_unit(si))
            .1
    }
}

/// The axis of `kind` in the metric units (m/h, kN).
impl From<crate::model::SetPoint> for SetPointAxis {
    fn from(kind: crate::model::SetPoint) -> Self {
        SetPointAxis {
            kind,
            units: crate::units::UnitSystem::Metric,
        }
    }
}

/// The box of operating points and the linear constraints on them, in plot units.
#[derive(Debug, Clone, PartialEq)]
pub struct Region {
    /// Bounds [low, high] of the rotational speed Ω, rpm.
    pub omega_rpm: [f64; 2],
    /// Bounds [low, high] of the set-point in the unit of `kind`: V0 in m/h (ft/h), or the WOB
    /// in kN (klbf) under a hook load.
    pub set_point: [f64; 2],
    /// What the set-point axis is.
    pub kind: SetPointAxis,
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
