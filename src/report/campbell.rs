//! `campbell.json` and `campbell.svg` of `drillopt campbell`: the natural frequencies of the
//! linearised string against the rotation speed, with the excitation lines 1× and k× and the
//! critical speeds where modes meet them. Frequencies in Hz, rotation speeds in rpm (and rad/s
//! where the field says so).

use std::path::{Path, PathBuf};

use plotters::prelude::*;
use serde::Serialize;

use super::ProblemRecord;
use super::atomic::write_atomic;
use super::axes::{FONT, draw_legend, tick_label};
use super::plots::PlotError;
use super::units::short;
use crate::campbell::{
    CampbellDiagram, CriticalSpeed, Linearisation, ModeFamily, RestingState, Whirl,
};

/// What the linearisation held, for the record.
#[derive(Debug, Clone, Serialize)]
pub struct LinearisationJson {
    /// "resting state (static equilibrium under gravity with wall contact)" or "straight
    /// unloaded string, no wall".
    pub about: &'static str,
    #[serde(flatten)]
    pub options: Linearisation,
    /// Terms of the model that are in it.
    pub includes: Vec<&'static str>,
    /// Terms of the model that are not.
    pub leaves_out: Vec<&'static str>,
    /// The resting state (without contact: none).
    pub resting: Option<RestingState>,
}

impl LinearisationJson {
    pub fn of(options: Linearisation, resting: Option<RestingState>) -> Self {
        let mut includes = vec![
            "strain stiffness (tangent at the state linearised about)",
            "gyroscopic coupling Omega G",
        ];
        if options.contact {
            includes.push("wall contact stiffness at the resting nodes: normal k1 + 3 k2 delta^2, tangential |F|/r");
        }
        if options.damping {
            includes.push("structural damping c M_pipe");
        }
        let mut leaves_out = vec![
            "wall friction",
            "wall contact damping",
            "bit-rock interaction (off bottom at rest)",
            "drilling loads (WOB compression, torque)",
        ];
        if !options.damping {
            leaves_out.push("structural damping");
        }
        LinearisationJson {
            about: if options.contact {
                "resting state (static equilibrium under gravity with wall contact)"
            } else {
                "straight unloaded string, no wall"
            },
            options,
            includes,
            leaves_out,
            resting,
        }
    }
}

/// One mode followed over the rotation speeds.
#[derive(Debug, Clone, Serialize)]
pub struct CampbellModeJson {
    /// 1-based, by frequency at the lowest rotation speed.
    pub mode: usize,
    pub family: ModeFamily,
    pub whirl: Whirl,
    /// Natural frequency at each rotation speed of `omega_rpm`, Hz (null where not followed).
    pub freq_hz: Vec<Option<f64>>,
    /// Circularity κ ∈ [−1, 1] of the orbit: +1 circular forward, −1 circular backward, 0 planar.
    pub circularity: Vec<Option<f64>>,
    /// Share of the lateral motion in the vertical plane.
    pub vertical_share: Vec<Option<f64>>,
    /// Damping ratio (with damping only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub damping_ratio: Option<Vec<Option<f64>>>,
}

impl CampbellModeJson {
    /// Every curve of `diagram`.
    pub fn all(diagram: &CampbellDiagram, damped: bool) -> Vec<Self> {
        let finite = |x: f64| x.is_finite().then_some(x);
        (0..diagram.curves.len())
            .map(|c| {
                let at = |f: &dyn Fn(&crate::campbell::EigenMode) -> f64| -> Vec<Option<f64>> {
                    (0..diagram.omegas.len())
                        .map(|i| diagram.mode(c, i).and_then(|m| finite(f(m))))
                        .collect()
                };
                let curve = &diagram.curves[c];
                CampbellModeJson {
                    mode: curve.index,
                    family: curve.family,
                    whirl: curve.whirl,
                    freq_hz: at(&|m| m.freq_hz),
                    circularity: at(&|m| m.circularity),
                    vertical_share: at(&|m| m.vertical_share),
                    damping_ratio: damped.then(|| at(&|m| m.damping_ratio)),
                }
            })
            .collect()
    }
}

/// The margin of the problem's operating point.
#[derive(Debug, Clone, Serialize)]
pub struct CampbellPointJson {
    pub omega_rpm: f64,
    /// min |Ω − Ω_c| / Ω_c over the critical speeds of 1× and k×, capped at 0.5.
    pub critical_speed_margin: f64,
    /// The nearest critical speed within [Ω/1.5, 2Ω], rpm (None: none there).
    pub nearest_critical_rpm: Option<f64>,
}

/// `campbell.json`.
#[derive(Debug, Clone, Serialize)]
pub struct CampbellJson<'a> {
    /// Problem name, file, hash, text and drillopt's version.
    #[serde(flatten)]
    pub record: ProblemRecord<'a>,
    /// "reduced" (the problem's basis) or "unreduced" (every free DOF).
    pub model: crate::sim::ModelKind,
    pub elements: usize,
    pub basis: crate::rom::BasisCounts,
    /// Number of coordinates n of the eigenproblem (2n first-order).
    pub coordinates: usize,
    pub linearisation: LinearisationJson,
    /// k of the excitation lines 1× and k×.
    pub excitation_multiple: f64,
    /// The rotation speeds, rpm.
    pub omega_rpm: Vec<f64>,
    pub modes: Vec<CampbellModeJson>,
    /// Where a mode meets 1× or k× the rotation frequency, by increasing rotation speed.
    pub critical_speeds: &'a [CriticalSpeed],
    pub operating_point: CampbellPointJson,
    /// Eigenvalues without an oscillating part, over all rotation speeds (0 for a stable,
    /// undamped string).
    pub non_oscillatory: usize,
}

/// What `campbell.svg` shows.
#[derive(Debug, Clone)]
pub struct CampbellPlot<'a> {
    pub title: &'a str,
    /// Rotation speeds, rpm.
    pub omega_rpm: &'a [f64],
    pub modes: &'a [CampbellModeJson],
    pub multiple: f64,
    pub critical_speeds: &'a [CriticalSpeed],
    /// Operating rotation speed to mark, rpm.
    pub operating_rpm: Option<f64>,
}

const WIDTH: u32 = 1100;
const HEIGHT: u32 = 750;

fn style_of(family: ModeFamily, whirl: Whirl) -> (RGBColor, bool, &'static str) {
    match (family, whirl) {
        (ModeFamily::Bending, Whirl::Forward) => {
            (RGBColor(31, 90, 200), false, "bending, forward whirl")
        }
        (ModeFamily::Bending, Whirl::Backward) => {
            (RGBColor(210, 50, 40), true, "bending, backward whirl")
        }
        (ModeFamily::Bending, Whirl::Planar) => (
            RGBColor(230, 140, 20),
            false,
            "bending, planar orbit (|\u{3ba}| \u{2264} 1e-3)",
        ),
        (ModeFamily::Bending, Whirl::None) => {
            (RGBColor(120, 120, 120), false, "bending, no whirl sense")
        }
        (ModeFamily::Torsional, _) => (RGBColor(30, 150, 60), false, "torsional"),
        (ModeFamily::Axial, _) => (RGBColor(150, 60, 170), false, "axial"),
    }
}

/// The polyline pieces of (x, y) below `top`: broken at missing values and cut where the curve
/// leaves the range (the crossing point interpolated).
fn clipped(x: &[f64], y: &[Option<f64>], top: f64) -> Vec<Vec<(f64, f64)>> {
    let mut pieces = Vec::new();
    let mut cur: Vec<(f64, f64)> = Vec::new();
    for i in 0..x.len() {
        let here = y[i].map(|v| (x[i], v));
        let prev = if i > 0 {
            y[i - 1].map(|v| (x[i - 1], v))
        } else {
            None
        };
        match (prev, here) {
            (Some(p), Some(h)) if (p.1 <= top) != (h.1 <= top) => {
                let t = (top - p.1) / (h.1 - p.1);
                let cut = (p.0 + t * (h.0 - p.0), top);
                if h.1 <= top {
                    cur.push(cut);
                    cur.push(h);
                } else {
                    cur.push(cut);
                    pieces.push(std::mem::take(&mut cur));
                }
            }
            (_, Some(h)) if h.1 <= top => cur.push(h),
            _ => {
                if !cur.is_empty() {
                    pieces.push(std::mem::take(&mut cur));
                }
            }
        }
    }
    if !cur.is_empty() {
        pieces.push(cur);
    }
    pieces
}

/// Writes `campbell.svg`: frequency [Hz] against rotation speed [rpm], each mode coloured by
/// family and whirl (backward whirl dashed), the lines 1× and k× the rotation frequency, the
/// critical speeds as circles (filled on 1×, open on k×) labelled in rpm, and the operating
/// rotation speed as a vertical dotted line. The frequency axis ends 15 % above the k× line at
/// the highest speed: higher modes meet no line in the range.
pub fn plot_campbell(path: &Path, plot: &CampbellPlot<'_>) -> Result<(), PlotError> {
    let draw_error = |message: String| PlotError::Draw {
        path: PathBuf::from(path),
        message,
    };
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (WIDTH, HEIGHT)).into_drawing_area();
        draw(&root, plot).map_err(|e| draw_error(e.to_string()))?;
        root.present().map_err(|e| draw_error(e.to_string()))?;
    }
    write_atomic(path, svg.as_bytes()).map_err(|error| PlotError::Write {
        path: path.to_owned(),
        error,
    })
}

fn draw(
    root: &DrawingArea<SVGBackend<'_>, plotters::coord::Shift>,
    plot: &CampbellPlot<'_>,
) -> Result<(), DrawingAreaErrorKind<std::io::Error>> {
    root.fill(&WHITE)?;
    let (x_lo, x_hi) = (
        plot.omega_rpm.first().copied().unwrap_or(0.0),
        plot.omega_rpm.last().copied().unwrap_or(1.0),
    );
    let line = |k: f64, rpm: f64| k * rpm / 60.0;
    let y_hi = (1.15 * line(plot.multiple.max(1.0), x_hi)).max(1e-3);
    let mut chart = ChartBuilder::on(root)
        .caption(plot.title, (FONT, 24))
        .margin(15)
        .margin_right(30)
        .x_label_area_size(55)
        .y_label_area_size(75)
        .build_cartesian_2d(x_lo..x_hi, 0.0..y_hi)?;
    let x_fmt = |v: &f64| tick_label(*v, x_lo, x_hi);
    let y_fmt = |v: &f64| tick_label(*v, 0.0, y_hi);
    chart
        .configure_mesh()
        .x_desc("rotation speed \u{3a9} [rpm]")
        .y_desc("natural frequency [Hz]")
        .x_label_formatter(&x_fmt)
        .y_label_formatter(&y_fmt)
        .label_style((FONT, 15))
        .axis_desc_style((FONT, 17))
        .light_line_style(BLACK.mix(0.05))
        .bold_line_style(BLACK.mix(0.15))
        .draw()?;
    let mut labelled = std::collections::HashSet::new();
    for m in plot.modes {
        let (color, dashed, label) = style_of(m.family, m.whirl);
        let style = color.stroke_width(2);
        for piece in clipped(plot.omega_rpm, &m.freq_hz, y_hi) {
            let series = if dashed {
                chart.draw_series(DashedLineSeries::new(piece, 8, 5, style))?
            } else {
                chart.draw_series(LineSeries::new(piece, style))?
            };
            if labelled.insert(label) {
                series
                    .label(label)
                    .legend(move |(x, y)| PathElement::new([(x, y), (x + 24, y)], style));
            }
        }
    }
    let lines = crate::campbell::multiples(plot.multiple);
    for &k in &lines {
        let style = BLACK.mix(0.8).stroke_width(if k == 1.0 { 2 } else { 1 });
        let ends = [(x_lo, line(k, x_lo)), (x_hi, line(k, x_hi))];
        let label = format!(
            "{}\u{d7} rotation frequency{}",
            short(k),
            if k == 1.0 { "" } else { " (bit)" }
        );
        let series = if k == 1.0 {
            chart.draw_series(LineSeries::new(ends, style))?
        } else {
            chart.draw_series(DashedLineSeries::new(ends, 12, 6, style))?
        };
        series
            .label(label)
            .legend(move |(x, y)| PathElement::new([(x, y), (x + 24, y)], style));
    }
    if let Some(rpm) = plot.operating_rpm.filter(|r| (x_lo..=x_hi).contains(r)) {
        let style = BLACK.mix(0.5).stroke_width(1);
        chart
            .draw_series(DashedLineSeries::new(
                [(rpm, 0.0), (rpm, y_hi)],
                3,
                4,
                style,
            ))?
            .label(format!("operating \u{3a9} = {} rpm", short(rpm)))
            .legend(move |(x, y)| PathElement::new([(x, y), (x + 24, y)], style));
    }
    let on_range = |c: &&CriticalSpeed| c.freq_hz <= y_hi && (x_lo..=x_hi).contains(&c.omega_rpm);
    for c in plot.critical_speeds.iter().filter(on_range) {
        let at = (c.omega_rpm, c.freq_hz);
        let style = if c.multiple == 1.0 {
            BLACK.filled()
        } else {
            BLACK.stroke_width(2)
        };
        chart.draw_series([Circle::new(at, 5, style)])?;
        chart
            .draw_series([EmptyElement::at(at)
                + Text::new(format!("{:.0}", c.omega_rpm), (-12, -20), (FONT, 12))])?;
    }
    draw_legend(&mut chart, SeriesLabelPosition::UpperLeft)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn curves_are_cut_at_the_top_and_at_gaps() {
        let x = [0.0, 1.0, 2.0, 3.0, 4.0, 5.0];
        let y = [Some(1.0), Some(3.0), Some(1.0), None, Some(1.0), Some(1.5)];
        let pieces = clipped(&x, &y, 2.0);
        assert_eq!(
            pieces,
            vec![
                vec![(0.0, 1.0), (0.5, 2.0)],
                vec![(1.5, 2.0), (2.0, 1.0)],
                vec![(4.0, 1.0), (5.0, 1.5)]
            ]
        );
        assert!(clipped(&x, &[None; 6], 2.0).is_empty());
    }
}
