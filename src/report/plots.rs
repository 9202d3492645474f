//! SVG plots of one run's time history, after the figures of the seed paper (Cunha Jr, Soize &
//! Sampaio 2014): Fig. 3, bit displacement u(L) and velocity u̇(L); Fig. 4, bit rotation θx(L)
//! and angular velocity θ̇x(L); Fig. 5, radial displacement r at a probe (x = 20 m there), with
//! the borehole wall r = gap drawn dashed. The paper puts each pair side by side; here the panels
//! are stacked so they share the time axis.
//!
//! Axes are in the units a driller reads on the terminal (see [`super::units`]): bit velocity in
//! m/h with the imposed V0 as a reference line, rotation in revolutions, angular velocity in rpm
//! with the imposed Ω as a reference line, radial displacement in mm. Every title states the
//! operating point.
//!
//! A run records 10⁵–10⁶ samples at adaptive, non-uniform times. Plotting every one would make
//! multi-megabyte SVGs with far more points than pixels, so each curve is first reduced by
//! [`decimate_min_max`]: the time axis is cut into [`PLOT_BUCKETS`] equal intervals and only the
//! lowest and highest sample of each is kept, so single-sample spikes (impacts, bit-bounce,
//! stick-slip bursts) stay visible. Non-finite samples are skipped; a constant curve gets a padded
//! axis range. The SVG is rendered in memory and written with [`write_atomic`]; text is SVG
//! `<text>`, so no font files are needed.

use std::path::{Path, PathBuf};

use plotters::coord::Shift;
use plotters::prelude::*;

use crate::model::{OperatingPoint, SetPoint};
use crate::sim::TimeSeries;

use super::atomic::write_atomic;
use super::axes::{
    PLOT_BUCKETS, TIME_LAYOUT, axis_range, decimate_min_max, draw_legend, draw_level,
    titled_figure, xy_chart,
};
use super::units::{REV_PER_RAD, operating_point_text, short};
use crate::units::{Shown, UnitSystem};

/// Image width, px.
const WIDTH: u32 = 1000;
/// Height of one panel, px.
const PANEL_HEIGHT: u32 = 340;
/// Height of the figure title strip, px.
const TITLE_HEIGHT: u32 = 40;
/// Relative padding of a y range beyond the data, so curves do not touch the frame.
const Y_PAD: f64 = 0.05;

/// Why a plot could not be made.
#[derive(Debug, thiserror::Error)]
pub enum PlotError {
    /// Plotters refused to draw (message of its error).
    #[error("drawing {}: {message}", .path.display())]
    Draw { path: PathBuf, message: String },
    /// The SVG could not be written; `error` names the path (see [`write_atomic`]), so it is
    /// the whole message and not a source, which would print it twice in an error chain.
    #[error("{error}")]
    Write {
        path: PathBuf,
        error: std::io::Error,
    },
    /// A channel does not have one value per sample time.
    #[error("plotting {}: '{channel}' has {len} samples but t has {t_len}", .path.display())]
    LengthMismatch {
        path: PathBuf,
        channel: String,
        len: usize,
        t_len: usize,
    },
    /// A grid of values does not have one value per node (row-major, V0 rows × Ω columns).
    #[error("plotting {}: {len} values for a grid of {n_v0} V0 × {n_omega} Ω nodes", .path.display())]
    GridMismatch {
        path: PathBuf,
        len: usize,
        n_omega: usize,
        n_v0: usize,
    },
    /// The requested radial probe does not exist.
    #[error("plotting {}: probe index {index} out of range, the series has {count} probes", .path.display())]
    NoSuchProbe {
        path: PathBuf,
        index: usize,
        count: usize,
    },
}

/// One panel of a figure: a curve y(t) with its caption and axis label.
#[derive(Debug, Clone, Copy)]
pub struct Panel<'a> {
    /// Caption above the panel, e.g. "Bit velocity u̇(L)".
    pub caption: &'a str,
    /// Y axis label with unit, e.g. "u̇(L) [m/s]".
    pub y_label: &'a str,
    /// One value per sample time, in the series' own (SI) units.
    pub y: &'a [f64],
    /// Factor from the values of `y` to the units of `y_label` (1 when they agree).
    pub scale: f64,
    /// Optional horizontal reference line (value in the units of `y_label`, legend text), drawn
    /// dashed and always inside the y range.
    pub reference: Option<(f64, &'a str)>,
    /// Optional reference curve, one value per abscissa in the series' units (scaled like `y`),
    /// with its legend text: a limit that changes along the abscissa (the buckling load of each
    /// section of a string), drawn in red and always inside the y range.
    pub reference_curve: Option<(&'a [f64], &'a str)>,
}

/// Bit displacement u(L) \[m or ft\] and bit velocity u̇(L) \[m/h or ft/h\] against t \[s\]
/// (paper Fig. 3) of a run at `op` (SI) under the top drive `top`, with V0 as a reference line:
/// imposed at the top by a feed, the set-point of an autodriller (none for a hook load).
pub fn plot_bit_axial(
    series: &TimeSeries,
    op: &OperatingPoint,
    top: crate::model::TopDrive,
    units: UnitSystem,
    path: &Path,
) -> Result<(), PlotError> {
    let role = match top {
        crate::model::TopDrive::Autodriller(_) => "the autodriller's set-point",
        _ => IMPOSED,
    };
    plot_bit_figure(&BIT_AXIAL, series, op, role, units, path)
}

/// What the reference line of a bit figure is, by default.
const IMPOSED: &str = "imposed at the top";

/// Bit rotation θx(L) \[rev\] and angular velocity θ̇x(L) \[rpm\] against t \[s\] (paper
/// Fig. 4) of a run at `op` (SI), with the imposed Ω as a reference line.
pub fn plot_bit_rotation(
    series: &TimeSeries,
    op: &OperatingPoint,
    units: UnitSystem,
    path: &Path,
) -> Result<(), PlotError> {
    plot_bit_figure(&BIT_ROTATION, series, op, IMPOSED, units, path)
}

/// The unit of a channel: a quantity of the unit system, or a fixed unit with its factor from
/// SI (revolutions).
#[derive(Clone, Copy)]
enum ChannelUnit {
    System(Shown),
    Fixed(&'static str, f64),
}

impl ChannelUnit {
    fn in_system(self, units: UnitSystem) -> (&'static str, f64) {
        match self {
            ChannelUnit::System(q) => units.unit_and_factor(q),
            ChannelUnit::Fixed(unit, factor) => (unit, factor),
        }
    }
}

/// A panel of a bit figure: caption, symbol of the y axis, the channel, its unit.
type Channel = (
    &'static str,
    &'static str,
    fn(&TimeSeries) -> &[f64],
    ChannelUnit,
);

/// The rate a top imposes at an operating point (SI), none where it imposes none.
type ImposedRate = fn(&OperatingPoint) -> Option<f64>;

/// One of the paper's bit figures (Figs. 3, 4): a coordinate of the bit above, its rate below
/// with the rate imposed at the top as the reference line.
struct BitFigure {
    title: &'static str,
    coordinate: Channel,
    rate: Channel,
    /// The imposed rate: its symbol and its value (SI) at an operating point (none where the top
    /// does not impose it: a hook load's feed); shown in the rate's unit.
    imposed: (&'static str, ImposedRate),
}

const BIT_AXIAL: BitFigure = BitFigure {
    title: "Drill-bit axial displacement and velocity",
    coordinate: (
        "Bit displacement u(L)",
        "u(L)",
        |s| &s.bit_displacement,
        ChannelUnit::System(Shown::Position),
    ),
    rate: (
        "Bit velocity u\u{307}(L)",
        "u\u{307}(L)",
        |s| &s.bit_velocity,
        ChannelUnit::System(Shown::Rop),
    ),
    imposed: ("V0", |op| (op.kind() == SetPoint::Feed).then_some(op.v0)),
};

const BIT_ROTATION: BitFigure = BitFigure {
    title: "Drill-bit rotation and angular velocity",
    coordinate: (
        "Bit rotation \u{3b8}x(L)",
        "\u{3b8}x(L)",
        |s| &s.bit_rotation,
        ChannelUnit::Fixed("rev", REV_PER_RAD),
    ),
    rate: (
        "Bit angular velocity \u{3b8}\u{307}x(L)",
        "\u{3b8}\u{307}x(L)",
        |s| &s.bit_angular_velocity,
        ChannelUnit::System(Shown::RotationSpeed),
    ),
    imposed: ("\u{3a9}", |op| Some(op.omega)),
};

fn plot_bit_figure(
    figure: &BitFigure,
    series: &TimeSeries,
    op: &OperatingPoint,
    role: &str,
    units: UnitSystem,
    path: &Path,
) -> Result<(), PlotError> {
    let (symbol, imposed) = figure.imposed;
    let (rate_unit, rate_factor) = figure.rate.3.in_system(units);
    let value = imposed(op).map(|v| v * rate_factor);
    let label = value.map(|v| format!("{symbol} = {} {rate_unit} ({role})", short(v)));
    let reference = value.zip(label.as_deref());
    let labels = [figure.coordinate, figure.rate].map(|(_, symbol, _, unit)| {
        let (unit, factor) = unit.in_system(units);
        (format!("{symbol} [{unit}]"), factor)
    });
    let panels = [(figure.coordinate, None), (figure.rate, reference)];
    let panels: Vec<Panel<'_>> = (panels.iter().zip(&labels))
        .map(
            |(((caption, _, y, _), reference), (y_label, scale))| Panel {
                caption,
                y_label,
                y: y(series),
                scale: *scale,
                reference: *reference,
                reference_curve: None,
            },
        )
        .collect();
    plot_panels(
        path,
        &format!("{}, {}", figure.title, operating_point_text(op, units)),
        &series.t,
        &panels,
    )
}

/// Radial displacement r \[mm or in\] at probe `probe_index` against t \[s\] of a run at `op`
/// (SI), with the wall r = `gap` (given in m) dashed (paper Fig. 5). A non-finite or
/// non-positive `gap` draws no wall.
pub fn plot_probe_radial(
    series: &TimeSeries,
    probe_index: usize,
    gap: f64,
    op: &OperatingPoint,
    units: UnitSystem,
    path: &Path,
) -> Result<(), PlotError> {
    let count = series.probe_positions.len().min(series.probe_radial.len());
    if probe_index >= count {
        return Err(PlotError::NoSuchProbe {
            path: path.to_owned(),
            index: probe_index,
            count,
        });
    }
    let x = series.probe_positions[probe_index];
    let (size_unit, size_factor) = units.unit_and_factor(Shown::Size);
    let wall = gap * size_factor;
    let wall_label = format!("wall, r = gap = {wall:.4} {size_unit}");
    let title = match units {
        // The probe's position as the problem gives it (SI).
        // The position to the mm (457.20000000000005 m is 457.2 m).
        UnitSystem::Metric => format!(
            "Radial displacement at x = {} m, {}",
            super::probe_label(x),
            operating_point_text(op, units)
        ),
        UnitSystem::Field => format!(
            "Radial displacement at x = {} ft ({} m), {}",
            short(units.of(Shown::Position, x)),
            super::probe_label(x),
            operating_point_text(op, units)
        ),
    };
    let caption = format!("Probe {probe_index}: r = \u{221a}(v\u{b2} + w\u{b2})");
    let y_label = format!("r [{size_unit}]");
    plot_panels(
        path,
        &title,
        &series.t,
        &[Panel {
            caption: &caption,
            y_label: &y_label,
            y: &series.probe_radial[probe_index],
            scale: size_factor,
            reference: (wall.is_finite() && wall > 0.0).then_some((wall, wall_label.as_str())),
            reference_curve: None,
        }],
    )
}

/// Writes an SVG figure titled `title` with `panels` stacked top to bottom, each `scale`·y(t)
/// against the shared sample times `t` \[s\]. Every panel must have one value per entry of `t`.
pub fn plot_panels(
    path: &Path,
    title: &str,
    t: &[f64],
    panels: &[Panel<'_>],
) -> Result<(), PlotError> {
    plot_panels_over(path, title, t, "t [s]", panels, &[])
}

/// [`plot_panels`] against any abscissa `x` (e.g. the position along the string), labelled
/// `x_label` with its unit.
pub fn plot_panels_over(
    path: &Path,
    title: &str,
    t: &[f64],
    x_label: &str,
    panels: &[Panel<'_>],
    marks: &[f64],
) -> Result<(), PlotError> {
    let lengths = |p: &Panel<'_>| {
        p.y.len() != t.len() || p.reference_curve.is_some_and(|(c, _)| c.len() != t.len())
    };
    if let Some(p) = panels.iter().find(|p| lengths(p)) {
        return Err(PlotError::LengthMismatch {
            path: path.to_owned(),
            channel: p.y_label.to_owned(),
            len: p.y.len(),
            t_len: t.len(),
        });
    }
    let svg = render_svg(title, t, x_label, panels, marks).map_err(|message| PlotError::Draw {
        path: path.to_owned(),
        message,
    })?;
    write_atomic(path, svg.as_bytes()).map_err(|error| PlotError::Write {
        path: path.to_owned(),
        error,
    })
}

fn render_svg(
    title: &str,
    t: &[f64],
    x_label: &str,
    panels: &[Panel<'_>],
    marks: &[f64],
) -> Result<String, String> {
    let rows = u32::try_from(panels.len().max(1)).unwrap_or(u32::MAX);
    let height = TITLE_HEIGHT.saturating_add(PANEL_HEIGHT.saturating_mul(rows));
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (WIDTH, height)).into_drawing_area();
        draw_figure(&root, title, t, x_label, panels, marks).map_err(|e| e.to_string())?;
        root.present().map_err(|e| e.to_string())?;
    }
    Ok(svg)
}

type DrawResult = Result<(), DrawingAreaErrorKind<std::io::Error>>;

fn draw_figure(
    root: &DrawingArea<SVGBackend<'_>, Shift>,
    title: &str,
    t: &[f64],
    x_label: &str,
    panels: &[Panel<'_>],
    marks: &[f64],
) -> DrawResult {
    let body = titled_figure(root, title)?;
    if panels.is_empty() {
        return Ok(());
    }
    for (area, panel) in body.split_evenly((panels.len(), 1)).iter().zip(panels) {
        draw_panel(area, t, x_label, panel, marks)?;
    }
    Ok(())
}

/// `panel` over `t`, with a dotted grey vertical line at each abscissa of `marks` (the section
/// boundaries of a string) inside the range.
fn draw_panel(
    area: &DrawingArea<SVGBackend<'_>, Shift>,
    t: &[f64],
    x_label: &str,
    panel: &Panel<'_>,
    marks: &[f64],
) -> DrawResult {
    let mut points = decimate_min_max(t, panel.y, PLOT_BUCKETS);
    points.iter_mut().for_each(|p| p.1 *= panel.scale);
    let (t_lo, t_hi) = axis_range(points.iter().map(|p| p.0), 0.0);
    let reference = panel.reference.filter(|(v, _)| v.is_finite());
    let curve: Vec<(f64, f64)> = panel.reference_curve.map_or(Vec::new(), |(c, _)| {
        (t.iter().zip(c))
            .filter(|(_, v)| v.is_finite())
            .map(|(&x, &v)| (x, v * panel.scale))
            .collect()
    });
    // The curve's lowest value is always in range (the weakest section's limit); higher parts
    // may leave the top (a short stabiliser's buckling load is meganewtons above the pipe's).
    let lowest_limit = curve.iter().map(|p| p.1).reduce(f64::min);
    let (y_lo, y_hi) = axis_range(
        (points.iter().map(|p| p.1))
            .chain(reference.map(|(v, _)| v))
            .chain(lowest_limit),
        Y_PAD,
    );

    let mut chart = xy_chart(
        area,
        Some((panel.caption, 20)),
        (x_label, (t_lo, t_hi)),
        (panel.y_label, (y_lo, y_hi)),
        TIME_LAYOUT,
    )?;
    chart.draw_series(LineSeries::new(points, BLUE.stroke_width(1)))?;
    let grey = BLACK.mix(0.35).stroke_width(1);
    for &x in marks.iter().filter(|&&x| x > t_lo && x < t_hi) {
        chart.draw_series(DashedLineSeries::new([(x, y_lo), (x, y_hi)], 3, 3, grey))?;
    }
    if let (false, Some((_, label))) = (curve.is_empty(), panel.reference_curve) {
        let style = RED.stroke_width(2);
        // The runs of the curve inside the axis, each its own line (a part above the top is
        // not drawn, rather than drawn across the frame); the first carries the legend.
        let runs = curve
            .split(|p| p.1 > y_hi)
            .filter(|run| !run.is_empty())
            .collect::<Vec<_>>();
        for (k, run) in runs.into_iter().enumerate() {
            let series = chart.draw_series(LineSeries::new(run.iter().copied(), style))?;
            if k == 0 {
                series
                    .label(label)
                    .legend(move |(x, y)| PathElement::new([(x, y), (x + 24, y)], style));
            }
        }
        draw_legend(&mut chart, SeriesLabelPosition::LowerRight)?;
    }
    if let Some((value, label)) = reference {
        let style = RED.stroke_width(2);
        draw_level(&mut chart, (t_lo, t_hi), value, style)?
            .label(label)
            .legend(move |(x, y)| PathElement::new([(x, y), (x + 24, y)], style));
        draw_legend(&mut chart, SeriesLabelPosition::LowerRight)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::TopDrive;
    use crate::report::testdata::{GAP, OP, PROBE_X, synthetic_series};

    fn read(path: &Path) -> String {
        std::fs::read_to_string(path).unwrap()
    }

    /// Points of every `<polyline>` in the SVG.
    fn polyline_point_counts(svg: &str) -> Vec<usize> {
        svg.split("<polyline")
            .skip(1)
            .map(|s| {
                let start = s.find("points=\"").unwrap() + 8;
                let end = start + s[start..].find('"').unwrap();
                s[start..end].split_whitespace().count()
            })
            .collect()
    }

    #[test]
    fn bit_axial_plot_is_a_small_svg_with_its_labels() {
        let s = synthetic_series(100_000);
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("fig/bit_axial.svg");
        plot_bit_axial(&s, &OP, TopDrive::Feed, UnitSystem::Metric, &path).unwrap();
        let svg = read(&path);
        assert!(svg.starts_with("<svg"), "{}", &svg[..svg.len().min(200)]);
        assert!(svg.trim_end().ends_with("</svg>"));
        for text in [
            // The synthetic run's operating point: 10 rad/s, 0.01 m/s.
            "Drill-bit axial displacement and velocity, \u{3a9} = 95.49 rpm, V0 = 36 m/h",
            "Bit displacement u(L)",
            "Bit velocity u\u{307}(L)",
            "u(L) [m]",
            "u\u{307}(L) [m/h]",
            "V0 = 36 m/h (imposed at the top)",
            "t [s]",
        ] {
            assert!(svg.contains(text), "missing {text:?}");
        }
        // Two data curves, decimated: 10^5 points each would be ~1.6 MB of SVG.
        let counts = polyline_point_counts(&svg);
        let data: Vec<usize> = counts.iter().copied().filter(|&c| c > 100).collect();
        assert_eq!(data.len(), 2, "{counts:?}");
        assert!(data.iter().all(|&c| c <= 2 * PLOT_BUCKETS + 2), "{data:?}");
        assert!(svg.len() < 300_000, "{} bytes", svg.len());
    }

    #[test]
    fn field_units_label_the_axial_plot_in_feet_and_the_radial_one_in_inches() {
        // The synthetic run: V0 = 0.01 m/s = 36 m/h = 118.11 ft/h.
        let mut s = synthetic_series(2_000);
        s.bit_velocity.iter_mut().for_each(|v| *v = OP.v0);
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("bit_axial.svg");
        plot_bit_axial(&s, &OP, TopDrive::Feed, UnitSystem::Field, &path).unwrap();
        let svg = read(&path);
        for text in [
            "\u{3a9} = 95.49 rpm, V0 = 118.11 ft/h",
            "u(L) [ft]",
            "u\u{307}(L) [ft/h]",
            "V0 = 118.11 ft/h (imposed at the top)",
        ] {
            assert!(svg.contains(text), "missing {text:?}");
        }
        assert!(!svg.contains("m/h") && !svg.contains("[m]"));
        // The ticks of a bit at V0 are near 118 ft/h, none near 36 (m/h).
        let ticks = numbers(&svg);
        assert!(ticks.iter().any(|&v| (v - 118.1).abs() < 0.6), "{ticks:?}");
        assert!(!ticks.iter().any(|&v| (v - 36.0).abs() < 0.6), "{ticks:?}");
        let radial = dir.path().join("radial.svg");
        plot_probe_radial(&s, 0, GAP, &OP, UnitSystem::Field, &radial).unwrap();
        let svg = read(&radial);
        assert!(svg.contains("r [in]"), "no inch axis");
        assert!(svg.contains(&format!("wall, r = gap = {:.4} in", GAP / 0.0254)));
    }

    #[test]
    fn a_hook_loads_bit_axial_plot_names_its_wob_and_draws_no_feed_line() {
        let s = synthetic_series(1_000);
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("bit_axial.svg");
        let hook = OperatingPoint::hook_load(OP.omega, 50e3);
        plot_bit_axial(&s, &hook, TopDrive::HookLoad, UnitSystem::Metric, &path).unwrap();
        let svg = read(&path);
        assert!(svg.contains("\u{3a9} = 95.49 rpm, WOB = 50 kN"));
        assert!(!svg.contains("imposed at the top"));
    }

    #[test]
    fn an_autodrillers_bit_axial_plot_calls_v0_its_set_point() {
        // helper-29: "V0 = 60 ft/h (imposed at the top)" under an autodriller, which holds V0
        // only while the surface WOB and torque stay below their limits.
        let s = synthetic_series(1_000);
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("bit_axial.svg");
        let top = TopDrive::Autodriller(crate::model::Autodriller {
            wob_limit: 80e3,
            torque_limit: None,
            power_limit: None,
            time_constant: 1.0,
        });
        plot_bit_axial(&s, &OP, top, UnitSystem::Metric, &path).unwrap();
        let svg = read(&path);
        assert!(
            svg.contains("V0 = 36 m/h (the autodriller&apos;s set-point)"),
            "{svg}"
        );
        assert!(!svg.contains("imposed at the top"));
    }

    #[test]
    fn bit_rotation_plot_has_its_labels() {
        let s = synthetic_series(100_000);
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("bit_rotation.svg");
        plot_bit_rotation(&s, &OP, UnitSystem::Metric, &path).unwrap();
        let svg = read(&path);
        for text in [
            "Drill-bit rotation and angular velocity, \u{3a9} = 95.49 rpm, V0 = 36 m/h",
            "Bit rotation \u{3b8}x(L)",
            "\u{3b8}x(L) [rev]",
            "\u{3b8}\u{307}x(L) [rpm]",
            "\u{3a9} = 95.49 rpm (imposed at the top)",
            "t [s]",
        ] {
            assert!(svg.contains(text), "missing {text:?}");
        }
        assert!(!svg.contains("rad/s") && !svg.contains("[rad]"));
        assert_eq!(
            polyline_point_counts(&svg)
                .iter()
                .filter(|&&c| c > 100)
                .count(),
            2
        );
    }

    /// The contents of every `<text>` element that is a number.
    fn numbers(svg: &str) -> Vec<f64> {
        svg.split("<text ")
            .skip(1)
            .filter_map(|s| s[s.find('>')? + 1..s.find("</text>")?].trim().parse().ok())
            .collect()
    }

    #[test]
    fn bit_speed_is_in_rpm_with_a_dashed_line_at_omega() {
        // A bit turning steadily at Ω = 10 rad/s: ticks near 95.5 rpm, none near 10 (rad/s),
        // and the dashed red reference line at Ω with its legend.
        let mut s = synthetic_series(3_000);
        s.bit_angular_velocity
            .iter_mut()
            .for_each(|w| *w = OP.omega);
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("rotation.svg");
        plot_bit_rotation(&s, &OP, UnitSystem::Metric, &path).unwrap();
        let svg = read(&path);
        let ticks = numbers(&svg);
        assert!(ticks.iter().any(|&v| (v - 95.5).abs() < 0.6), "{ticks:?}");
        assert!(!ticks.iter().any(|&v| (v - 10.0).abs() < 0.6), "{ticks:?}");
        assert!(svg.contains("\u{3a9} = 95.49 rpm (imposed at the top)"));
        let red = svg.matches("stroke=\"#FF0000\"").count();
        assert!(red > 20, "{red} red strokes");
    }

    #[test]
    fn probe_radial_plot_has_position_units_and_wall() {
        let s = synthetic_series(100_000);
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("radial.svg");
        plot_probe_radial(&s, 0, GAP, &OP, UnitSystem::Metric, &path).unwrap();
        let svg = read(&path);
        assert!(svg.contains(&format!(
            "Radial displacement at x = {PROBE_X} m, \u{3a9} = 95.49 rpm, V0 = 36 m/h"
        )));
        assert!(svg.contains("r [mm]"));
        assert!(svg.contains(&format!("wall, r = gap = {:.4} mm", GAP * 1e3)));
        // The dashed wall is many short segments in red, besides the legend sample.
        let red_paths = svg.matches("stroke=\"#FF0000\"").count();
        assert!(red_paths > 20, "{red_paths} red strokes");

        let no_wall = dir.path().join("radial_no_wall.svg");
        plot_probe_radial(&s, 0, f64::NAN, &OP, UnitSystem::Metric, &no_wall).unwrap();
        let svg = read(&no_wall);
        assert!(!svg.contains("wall"));
        assert_eq!(svg.matches("stroke=\"#FF0000\"").count(), 0);
    }

    #[test]
    fn probe_out_of_range_is_an_error_and_writes_nothing() {
        let s = synthetic_series(100);
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("radial.svg");
        let err = plot_probe_radial(&s, 1, GAP, &OP, UnitSystem::Metric, &path).unwrap_err();
        assert!(
            matches!(
                err,
                PlotError::NoSuchProbe {
                    index: 1,
                    count: 1,
                    ..
                }
            ),
            "{err}"
        );
        assert!(err.to_string().contains("radial.svg"), "{err}");
        assert!(!path.exists());
    }

    #[test]
    fn mismatched_lengths_are_an_error() {
        let mut s = synthetic_series(100);
        s.bit_velocity.pop();
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("axial.svg");
        let err = plot_bit_axial(&s, &OP, TopDrive::Feed, UnitSystem::Metric, &path).unwrap_err();
        assert!(
            matches!(
                err,
                PlotError::LengthMismatch {
                    len: 99,
                    t_len: 100,
                    ..
                }
            ),
            "{err}"
        );
        assert!(!path.exists());
    }

    #[test]
    fn constant_and_non_finite_channels_still_plot() {
        let mut s = synthetic_series(3_000);
        s.bit_displacement.iter_mut().for_each(|u| *u = 0.25);
        s.bit_velocity.iter_mut().for_each(|v| *v = 0.0);
        s.bit_velocity[10] = f64::NAN;
        s.bit_velocity[20] = f64::INFINITY;
        s.bit_rotation.iter_mut().for_each(|v| *v = f64::NAN);
        let dir = tempfile::tempdir().unwrap();
        let axial = dir.path().join("axial.svg");
        plot_bit_axial(&s, &OP, TopDrive::Feed, UnitSystem::Metric, &axial).unwrap();
        let svg = read(&axial);
        assert!(svg.contains("Bit velocity"));
        // Both constant curves are drawn with their finite points (3000 minus the 2 skipped): 3000 is below the decimation threshold.
        let counts = polyline_point_counts(&svg);
        assert!(
            counts.contains(&3000) && counts.contains(&2998),
            "{counts:?}"
        );
        let rotation = dir.path().join("rotation.svg");
        plot_bit_rotation(&s, &OP, UnitSystem::Metric, &rotation).unwrap();
        assert!(read(&rotation).contains("Bit rotation"));
    }
}
