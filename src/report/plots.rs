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

use crate::model::OperatingPoint;
use crate::sim::TimeSeries;

use super::atomic::write_atomic;
use super::units::{M_PER_H_PER_M_PER_S, REV_PER_RAD, RPM_PER_RAD_S, operating_point_text, short};

/// Number of time buckets a curve is reduced to before plotting (≤ 2 points each).
pub const PLOT_BUCKETS: usize = 2000;

/// Image width, px.
const WIDTH: u32 = 1000;
/// Height of one panel, px.
const PANEL_HEIGHT: u32 = 340;
/// Height of the figure title strip, px.
const TITLE_HEIGHT: u32 = 40;
const FONT: &str = "sans-serif";
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
}

/// Bit displacement u(L) \[m\] and bit velocity u̇(L) \[m/h\] against t \[s\] (paper Fig. 3) of a
/// run at `op` (SI), with the imposed V0 as a reference line.
pub fn plot_bit_axial(
    series: &TimeSeries,
    op: &OperatingPoint,
    path: &Path,
) -> Result<(), PlotError> {
    let v0 = op.v0 * M_PER_H_PER_M_PER_S;
    let v0_label = format!("V0 = {} m/h (imposed at the top)", short(v0));
    plot_panels(
        path,
        &format!(
            "Drill-bit axial displacement and velocity, {}",
            operating_point_text(op)
        ),
        &series.t,
        &[
            Panel {
                caption: "Bit displacement u(L)",
                y_label: "u(L) [m]",
                y: &series.bit_displacement,
                scale: 1.0,
                reference: None,
            },
            Panel {
                caption: "Bit velocity u\u{307}(L)",
                y_label: "u\u{307}(L) [m/h]",
                y: &series.bit_velocity,
                scale: M_PER_H_PER_M_PER_S,
                reference: Some((v0, v0_label.as_str())),
            },
        ],
    )
}

/// Bit rotation θx(L) \[rev\] and angular velocity θ̇x(L) \[rpm\] against t \[s\] (paper
/// Fig. 4) of a run at `op` (SI), with the imposed Ω as a reference line.
pub fn plot_bit_rotation(
    series: &TimeSeries,
    op: &OperatingPoint,
    path: &Path,
) -> Result<(), PlotError> {
    let omega = op.omega * RPM_PER_RAD_S;
    let omega_label = format!("\u{3a9} = {} rpm (imposed at the top)", short(omega));
    plot_panels(
        path,
        &format!(
            "Drill-bit rotation and angular velocity, {}",
            operating_point_text(op)
        ),
        &series.t,
        &[
            Panel {
                caption: "Bit rotation \u{3b8}x(L)",
                y_label: "\u{3b8}x(L) [rev]",
                y: &series.bit_rotation,
                scale: REV_PER_RAD,
                reference: None,
            },
            Panel {
                caption: "Bit angular velocity \u{3b8}\u{307}x(L)",
                y_label: "\u{3b8}\u{307}x(L) [rpm]",
                y: &series.bit_angular_velocity,
                scale: RPM_PER_RAD_S,
                reference: Some((omega, omega_label.as_str())),
            },
        ],
    )
}

/// Radial displacement r \[mm\] at probe `probe_index` against t \[s\] of a run at `op` (SI), with
/// the wall r = `gap` (given in m) dashed (paper Fig. 5). A non-finite or non-positive `gap`
/// draws no wall.
pub fn plot_probe_radial(
    series: &TimeSeries,
    probe_index: usize,
    gap: f64,
    op: &OperatingPoint,
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
    let gap_mm = gap * 1e3;
    let wall_label = format!("wall, r = gap = {gap_mm:.4} mm");
    let title = format!(
        "Radial displacement at x = {x} m, {}",
        operating_point_text(op)
    );
    let caption = format!("Probe {probe_index}: r = \u{221a}(v\u{b2} + w\u{b2})");
    plot_panels(
        path,
        &title,
        &series.t,
        &[Panel {
            caption: &caption,
            y_label: "r [mm]",
            y: &series.probe_radial[probe_index],
            scale: 1e3,
            reference: (gap_mm.is_finite() && gap_mm > 0.0)
                .then_some((gap_mm, wall_label.as_str())),
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
    if let Some(p) = panels.iter().find(|p| p.y.len() != t.len()) {
        return Err(PlotError::LengthMismatch {
            path: path.to_owned(),
            channel: p.y_label.to_owned(),
            len: p.y.len(),
            t_len: t.len(),
        });
    }
    let svg = render_svg(title, t, panels).map_err(|message| PlotError::Draw {
        path: path.to_owned(),
        message,
    })?;
    write_atomic(path, svg.as_bytes()).map_err(|error| PlotError::Write {
        path: path.to_owned(),
        error,
    })
}

/// Reduces the curve (t, y) to at most `2 * buckets + 2` points for plotting: the first and last
/// finite samples, and in each of `buckets` equal time intervals between them the lowest and the
/// highest sample. Points keep their sample order; samples with a non-finite t or y are skipped.
/// A curve that already has at most `2 * buckets + 2` finite samples is returned whole. Pairs
/// beyond the shorter of `t` and `y` are ignored.
pub fn decimate_min_max(t: &[f64], y: &[f64], buckets: usize) -> Vec<(f64, f64)> {
    let buckets = buckets.max(1);
    let n = t.len().min(y.len());
    let finite: Vec<usize> = (0..n)
        .filter(|&i| t[i].is_finite() && y[i].is_finite())
        .collect();
    let (Some(&first), Some(&last)) = (finite.first(), finite.last()) else {
        return Vec::new();
    };
    if finite.len() <= 2 * buckets + 2 {
        return finite.iter().map(|&i| (t[i], y[i])).collect();
    }
    // t is non-decreasing in a TimeSeries, but min/max keeps this correct for any order.
    let (t0, t1) = finite
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &i| {
            (lo.min(t[i]), hi.max(t[i]))
        });
    let width = t1 - t0;
    let bucket_of = |ti: f64| -> usize {
        if width > 0.0 {
            // `as` saturates; the min puts t1 itself in the last bucket.
            (((ti - t0) / width * buckets as f64) as usize).min(buckets - 1)
        } else {
            0
        }
    };
    let mut lowest: Vec<Option<usize>> = vec![None; buckets];
    let mut highest: Vec<Option<usize>> = vec![None; buckets];
    for &i in &finite {
        let b = bucket_of(t[i]);
        if lowest[b].is_none_or(|j| y[i] < y[j]) {
            lowest[b] = Some(i);
        }
        if highest[b].is_none_or(|j| y[i] > y[j]) {
            highest[b] = Some(i);
        }
    }
    let mut keep: Vec<usize> = Vec::with_capacity(2 * buckets + 2);
    keep.push(first);
    keep.push(last);
    keep.extend(lowest.into_iter().flatten());
    keep.extend(highest.into_iter().flatten());
    keep.sort_unstable();
    keep.dedup();
    keep.into_iter().map(|i| (t[i], y[i])).collect()
}

/// The range [lo, hi] (lo < hi, both finite) of the finite `values`, widened by `pad` times the
/// span on each side. A constant (or numerically constant) set is widened by 5 % of its
/// magnitude, or by 1 if it is zero; no finite value at all gives [0, 1].
pub(super) fn axis_range(values: impl IntoIterator<Item = f64>, pad: f64) -> (f64, f64) {
    let (lo, hi) = values
        .into_iter()
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    if lo > hi {
        return (0.0, 1.0);
    }
    let span = hi - lo;
    let magnitude = lo.abs().max(hi.abs());
    if !span.is_finite() || span <= 1e-12 * magnitude {
        let half = if magnitude > 0.0 {
            0.05 * magnitude
        } else {
            1.0
        };
        return (lo - half, hi + half);
    }
    (lo - pad * span, hi + pad * span)
}

/// Formats tick value `v` of an axis spanning [lo, hi] with just enough digits for the tick step.
/// Plotters places at most ~11 ticks at multiples of 1, 2 or 5 × 10ᵏ, so the step is at least
/// span / 12 and its decade fixes the digits. Very large or very small axes use exponents.
pub(super) fn tick_label(v: f64, lo: f64, hi: f64) -> String {
    let step = (hi - lo).abs() / 12.0;
    if !step.is_finite() || step <= 0.0 || !v.is_finite() {
        return format!("{v}");
    }
    // A tick at zero computed as lo + k·step may come out as ±1e-17.
    let v = if v.abs() < step * 1e-6 { 0.0 } else { v };
    let step_decade = step.log10().floor() as i32;
    let magnitude = lo.abs().max(hi.abs());
    if !(1e-3..1e5).contains(&magnitude) {
        if v == 0.0 {
            return "0".to_owned();
        }
        let digits = (v.abs().log10().floor() as i32 - step_decade).clamp(0, 8) as usize;
        format!("{v:.digits$e}")
    } else {
        let decimals = (-step_decade).clamp(0, 12) as usize;
        format!("{v:.decimals$}")
    }
}

/// Draws the figure into an SVG string.
fn render_svg(title: &str, t: &[f64], panels: &[Panel<'_>]) -> Result<String, String> {
    let rows = u32::try_from(panels.len().max(1)).unwrap_or(u32::MAX);
    let height = TITLE_HEIGHT.saturating_add(PANEL_HEIGHT.saturating_mul(rows));
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (WIDTH, height)).into_drawing_area();
        draw_figure(&root, title, t, panels).map_err(|e| e.to_string())?;
        root.present().map_err(|e| e.to_string())?;
    }
    Ok(svg)
}

type DrawResult = Result<(), DrawingAreaErrorKind<std::io::Error>>;

fn draw_figure(
    root: &DrawingArea<SVGBackend<'_>, Shift>,
    title: &str,
    t: &[f64],
    panels: &[Panel<'_>],
) -> DrawResult {
    root.fill(&WHITE)?;
    let body = root.titled(title, (FONT, 26))?;
    if panels.is_empty() {
        return Ok(());
    }
    for (area, panel) in body.split_evenly((panels.len(), 1)).iter().zip(panels) {
        draw_panel(area, t, panel)?;
    }
    Ok(())
}

fn draw_panel(
    area: &DrawingArea<SVGBackend<'_>, Shift>,
    t: &[f64],
    panel: &Panel<'_>,
) -> DrawResult {
    let mut points = decimate_min_max(t, panel.y, PLOT_BUCKETS);
    points.iter_mut().for_each(|p| p.1 *= panel.scale);
    let (t_lo, t_hi) = axis_range(points.iter().map(|p| p.0), 0.0);
    let reference = panel.reference.filter(|(v, _)| v.is_finite());
    let (y_lo, y_hi) = axis_range(
        points.iter().map(|p| p.1).chain(reference.map(|(v, _)| v)),
        Y_PAD,
    );

    let mut chart = ChartBuilder::on(area)
        .caption(panel.caption, (FONT, 20))
        .margin(10)
        .margin_right(25)
        .x_label_area_size(50)
        .y_label_area_size(85)
        .build_cartesian_2d(t_lo..t_hi, y_lo..y_hi)?;
    let x_fmt = |v: &f64| tick_label(*v, t_lo, t_hi);
    let y_fmt = |v: &f64| tick_label(*v, y_lo, y_hi);
    chart
        .configure_mesh()
        .x_desc("t [s]")
        .y_desc(panel.y_label)
        .x_label_formatter(&x_fmt)
        .y_label_formatter(&y_fmt)
        .label_style((FONT, 15))
        .axis_desc_style((FONT, 17))
        .light_line_style(BLACK.mix(0.05))
        .bold_line_style(BLACK.mix(0.15))
        .draw()?;
    chart.draw_series(LineSeries::new(points, BLUE.stroke_width(1)))?;

    if let Some((value, label)) = reference {
        let style = RED.stroke_width(2);
        chart
            .draw_series(DashedLineSeries::new(
                [(t_lo, value), (t_hi, value)],
                10,
                6,
                style,
            ))?
            .label(label)
            .legend(move |(x, y)| PathElement::new([(x, y), (x + 24, y)], style));
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::LowerRight)
            .label_font((FONT, 15))
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK.mix(0.4))
            .draw()?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
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

    // ---- decimation ----

    #[test]
    fn decimation_keeps_extremes_and_ends_and_bounds_length() {
        let n = 100_000;
        // Non-uniform times, a sine, and single-sample spikes of both signs.
        let mut t = Vec::with_capacity(n);
        let mut acc = 0.0;
        for i in 0..n {
            t.push(acc);
            acc += 1e-4 * (1.0 + 0.9 * (i as f64 * 0.37).sin());
        }
        let mut y: Vec<f64> = t.iter().map(|&ti| (40.0 * ti).sin()).collect();
        y[12_345] = 7.5;
        y[67_890] = -9.25;
        y[n - 1] = 0.123;
        y[0] = -0.456;
        let out = decimate_min_max(&t, &y, 500);
        assert!(out.len() <= 2 * 500 + 2, "{}", out.len());
        assert!(out.len() >= 500, "{}", out.len());
        assert_eq!(out[0], (t[0], y[0]));
        assert_eq!(*out.last().unwrap(), (t[n - 1], y[n - 1]));
        assert!(out.contains(&(t[12_345], 7.5)));
        assert!(out.contains(&(t[67_890], -9.25)));
        assert!(out.windows(2).all(|w| w[0].0 <= w[1].0), "order kept");
        // Nothing outside the data is invented: the extremes of the output are the spikes.
        let max_in_out = out.iter().map(|p| p.1).fold(f64::MIN, f64::max);
        let min_in_out = out.iter().map(|p| p.1).fold(f64::MAX, f64::min);
        assert_eq!(max_in_out, 7.5);
        assert_eq!(min_in_out, -9.25);
    }

    #[test]
    fn decimation_keeps_every_bucket_extreme() {
        // Samples at t = i; 10 buckets of 100 samples each. Each bucket has a unique max at a
        // different offset, which must appear.
        let n = 1000;
        let t: Vec<f64> = (0..n).map(|i| i as f64).collect();
        let mut y = vec![0.0; n];
        for b in 0..10 {
            y[b * 100 + 3 * b + 1] = 1.0 + b as f64;
            y[b * 100 + 97 - b] = -1.0 - b as f64;
        }
        let out = decimate_min_max(&t, &y, 10);
        assert!(out.len() <= 22);
        for b in 0..10 {
            assert!(
                out.contains(&(t[b * 100 + 3 * b + 1], 1.0 + b as f64)),
                "max {b}"
            );
            assert!(
                out.contains(&(t[b * 100 + 97 - b], -1.0 - b as f64)),
                "min {b}"
            );
        }
    }

    #[test]
    fn decimation_skips_non_finite_samples() {
        let n = 10_000;
        let t: Vec<f64> = (0..n).map(|i| i as f64 * 1e-3).collect();
        let mut y: Vec<f64> = t.iter().map(|x| x.cos()).collect();
        y[0] = f64::NAN;
        y[5000] = f64::INFINITY;
        y[n - 1] = f64::NEG_INFINITY;
        let mut t2 = t.clone();
        t2[7000] = f64::NAN;
        let out = decimate_min_max(&t2, &y, 100);
        assert!(out.iter().all(|p| p.0.is_finite() && p.1.is_finite()));
        assert_eq!(out[0], (t[1], y[1]), "first finite sample");
        assert_eq!(
            *out.last().unwrap(),
            (t[n - 2], y[n - 2]),
            "last finite sample"
        );
        // Short input: returned whole, minus the non-finite samples.
        let short = decimate_min_max(&[0.0, 1.0, 2.0, 3.0], &[1.0, f64::NAN, 3.0, 4.0], 100);
        assert_eq!(short, vec![(0.0, 1.0), (2.0, 3.0), (3.0, 4.0)]);
        assert!(decimate_min_max(&[0.0, 1.0], &[f64::NAN, f64::NAN], 10).is_empty());
        assert!(decimate_min_max(&[], &[], 10).is_empty());
    }

    #[test]
    fn decimation_of_a_single_instant_keeps_its_extremes() {
        let t = vec![2.0; 100];
        let y: Vec<f64> = (0..100).map(|i| ((i * 37) % 100) as f64).collect();
        let out = decimate_min_max(&t, &y, 3);
        assert!(out.len() <= 8);
        assert!(out.contains(&(2.0, 0.0)));
        assert!(out.contains(&(2.0, 99.0)));
    }

    // ---- axis ranges and ticks ----

    #[test]
    fn axis_range_pads_degenerate_and_ignores_non_finite() {
        assert_eq!(
            axis_range([1.0, 3.0, f64::NAN, f64::INFINITY], 0.0),
            (1.0, 3.0)
        );
        assert_eq!(axis_range([1.0, 3.0], 0.05), (0.9, 3.1));
        assert_eq!(axis_range([0.0, 0.0], 0.05), (-1.0, 1.0));
        let (lo, hi) = axis_range([5.0; 3], 0.05);
        assert!(lo < 5.0 && hi > 5.0 && hi - lo < 1.0, "{lo} {hi}");
        let (lo, hi) = axis_range([-2e-9, -2e-9], 0.05);
        assert!(lo < -2e-9 && hi > -2e-9 && hi < 0.0, "{lo} {hi}");
        assert_eq!(axis_range([f64::NAN], 0.05), (0.0, 1.0));
        assert_eq!(axis_range(std::iter::empty(), 0.05), (0.0, 1.0));
    }

    #[test]
    fn tick_labels_have_digits_for_the_step_and_no_negative_zero() {
        assert_eq!(tick_label(2.5, 0.0, 5.0), "2.5");
        assert_eq!(tick_label(0.0015, 0.0, 0.005), "0.0015");
        assert_eq!(tick_label(-1e-18, -1.0, 1.0), "0.0");
        assert_eq!(tick_label(3.0, 0.0, 100.0), "3");
        assert_eq!(tick_label(1.5e-4, 0.0, 3e-4), "1.5e-4");
        assert_eq!(tick_label(250_000.0, 0.0, 1e6), "2.5e5");
        assert_eq!(tick_label(0.0, -3e-4, 3e-4), "0");
    }

    // ---- figures ----

    #[test]
    fn bit_axial_plot_is_a_small_svg_with_its_labels() {
        let s = synthetic_series(100_000);
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("fig/bit_axial.svg");
        plot_bit_axial(&s, &OP, &path).unwrap();
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
    fn bit_rotation_plot_has_its_labels() {
        let s = synthetic_series(100_000);
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("bit_rotation.svg");
        plot_bit_rotation(&s, &OP, &path).unwrap();
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
        plot_bit_rotation(&s, &OP, &path).unwrap();
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
        plot_probe_radial(&s, 0, GAP, &OP, &path).unwrap();
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
        plot_probe_radial(&s, 0, f64::NAN, &OP, &no_wall).unwrap();
        let svg = read(&no_wall);
        assert!(!svg.contains("wall"));
        assert_eq!(svg.matches("stroke=\"#FF0000\"").count(), 0);
    }

    #[test]
    fn probe_out_of_range_is_an_error_and_writes_nothing() {
        let s = synthetic_series(100);
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("radial.svg");
        let err = plot_probe_radial(&s, 1, GAP, &OP, &path).unwrap_err();
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
        let err = plot_bit_axial(&s, &OP, &path).unwrap_err();
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
        plot_bit_axial(&s, &OP, &axial).unwrap();
        let svg = read(&axial);
        assert!(svg.contains("Bit velocity"));
        // Both constant curves are drawn with their finite points (3000 minus the 2 skipped): 3000 is below the decimation threshold.
        let counts = polyline_point_counts(&svg);
        assert!(
            counts.contains(&3000) && counts.contains(&2998),
            "{counts:?}"
        );
        let rotation = dir.path().join("rotation.svg");
        plot_bit_rotation(&s, &OP, &rotation).unwrap();
        assert!(read(&rotation).contains("Bit rotation"));
    }
}
