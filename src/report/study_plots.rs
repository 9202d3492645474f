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
//! [`write_atomic`], and text is SVG `<text>`, so no font files are needed.

use std::f64::consts::{PI, TAU};
use std::path::Path;

use plotters::coord::Shift;
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;
use plotters::style::colors::colormaps::{ColorMap, ViridisRGB};
use plotters::style::text_anchor::{HPos, Pos, VPos};

use crate::sim::TimeSeries;

use super::atomic::write_atomic;
use super::plots::{PLOT_BUCKETS, PlotError, axis_range, decimate_min_max, tick_label};

/// The box of operating points and the linear constraints on them, in plot units.
#[derive(Debug, Clone, PartialEq)]
pub struct Region {
    /// Bounds [low, high] of the rotational speed Ω, rpm.
    pub omega_rpm: [f64; 2],
    /// Bounds [low, high] of the rate of penetration V0, m/h.
    pub v0_m_per_h: [f64; 2],
    /// Linear constraints; the feasible set is the box where all hold.
    pub lines: Vec<ConstraintLine>,
}

/// The linear constraint `omega_coef`·Ω + `v0_coef`·V0 ≤ `upper` (Ω in rpm, V0 in m/h).
#[derive(Debug, Clone, PartialEq)]
pub struct ConstraintLine {
    /// Text drawn next to the line.
    pub label: String,
    /// Coefficient of Ω, per rpm (in the units of `upper`).
    pub omega_coef: f64,
    /// Coefficient of V0, per m/h (in the units of `upper`).
    pub v0_coef: f64,
    /// Right-hand side.
    pub upper: f64,
}

/// One operating point the optimizer evaluated.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EvaluatedPoint {
    /// Rotational speed Ω, rpm.
    pub omega_rpm: f64,
    /// Rate of penetration V0, m/h.
    pub v0_m_per_h: f64,
    /// Robust score (maximised); None when the evaluation failed.
    pub score: Option<f64>,
    /// Whether the point satisfies every constraint.
    pub feasible: bool,
}

/// Image width of the operating-point plots, px.
const WIDTH: u32 = 1100;
/// Image height of the operating-point plots, px.
const HEIGHT: u32 = 800;
/// Width of the column right of the plot holding the colour bar and the legend, px.
const SIDE_WIDTH: u32 = 240;
/// Height of the figure title strip, px (as in `plots`).
const TITLE_HEIGHT: u32 = 40;
/// Height of one metric row in [`plot_metric_samples`], px.
const METRIC_ROW_HEIGHT: u32 = 130;
/// Width of [`plot_metric_samples`] and [`plot_bit_speed_overlay`], px.
const WIDE_WIDTH: u32 = 1000;
/// Height of [`plot_bit_speed_overlay`], px.
const OVERLAY_HEIGHT: u32 = 520;
/// Number of colour steps in a colour bar.
const COLORBAR_STEPS: usize = 64;
/// At most this many iterates of a path get a number; longer paths number every k-th.
const MAX_PATH_NUMBERS: usize = 20;
const FONT: &str = "sans-serif";
const OMEGA_LABEL: &str = "\u{3a9} [rpm]";
const V0_LABEL: &str = "V0 [m/h]";
/// Title of [`plot_bit_speed_overlay`].
const OVERLAY_TITLE: &str = "Bit angular velocity \u{3b8}\u{307}x(L)";
/// rad/s → rpm.
const RPM_PER_RAD_S: f64 = 60.0 / TAU;

/// Points and cells without a value (failed, infeasible).
const NO_VALUE: RGBColor = RGBColor(150, 150, 150);
/// The infeasible part of the box.
const INFEASIBLE_FILL: RGBColor = RGBColor(225, 225, 225);
/// Cells without a value in a heat map.
const NO_VALUE_CELL: RGBColor = RGBColor(205, 205, 205);
const PATH_COLOR: RGBColor = RGBColor(200, 30, 45);
/// The optimum: red, which the viridis scale never shows.
const STAR_FILL: RGBColor = RGBColor(235, 20, 60);
/// Constraint lines, cycled.
const LINE_COLORS: [RGBColor; 5] = [
    RGBColor(180, 60, 0),
    RGBColor(110, 40, 150),
    RGBColor(0, 110, 110),
    RGBColor(140, 90, 20),
    RGBColor(40, 70, 160),
];
/// Distinct run colours (Tableau 10), cycled.
const RUN_COLORS: [RGBColor; 10] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
];

/// Draws the box of operating points with its infeasible part shaded grey and every constraint
/// line labelled, the `evaluated` points (circles coloured by score with a colour bar; failed or
/// infeasible points as grey crosses), the optimizer `path` of iterate centres (numbered, with
/// arrows) and the `optimum` (a star), all as (Ω in rpm, V0 in m/h). Non-finite coordinates are
/// skipped; the view covers the box and every point.
pub fn plot_optimizer_path(
    region: &Region,
    evaluated: &[EvaluatedPoint],
    path: &[(f64, f64)],
    optimum: Option<(f64, f64)>,
    title: &str,
    out: &Path,
) -> Result<(), PlotError> {
    render_and_write(out, (WIDTH, HEIGHT), |root| {
        draw_optimizer_path(root, region, evaluated, path, optimum, title)
    })
}

/// Draws `values` over the grid of cell centres `omega_rpm` × `v0_m_per_h` as filled cells
/// coloured by value, with a colour bar labelled `value_label` and its range; `None` (or
/// non-finite) cells are grey and hatched. `values[j * omega_rpm.len() + i]` belongs to
/// (Ω\[i\], V0\[j\]). Cell edges lie halfway between neighbouring nodes; the grid need not be
/// uniform. `optimum` (Ω in rpm, V0 in m/h) is marked with a star.
pub fn plot_heatmap(
    title: &str,
    value_label: &str,
    omega_rpm: &[f64],
    v0_m_per_h: &[f64],
    values: &[Option<f64>],
    optimum: Option<(f64, f64)>,
    out: &Path,
) -> Result<(), PlotError> {
    let expected = omega_rpm.len().checked_mul(v0_m_per_h.len());
    if expected != Some(values.len()) {
        return Err(PlotError::GridMismatch {
            path: out.to_owned(),
            len: values.len(),
            n_omega: omega_rpm.len(),
            n_v0: v0_m_per_h.len(),
        });
    }
    let grid = Grid {
        omega: omega_rpm,
        v0: v0_m_per_h,
        values,
    };
    render_and_write(out, (WIDTH, HEIGHT), |root| {
        draw_heatmap(root, title, value_label, &grid, optimum)
    })
}

/// Draws one row per metric `(name, samples)`: every Monte Carlo sample as a dot on the metric's
/// own value axis, and their mean as a red line, with the mean and sample count in the caption.
/// Non-finite samples are left out and counted.
pub fn plot_metric_samples(
    title: &str,
    metrics: &[(String, Vec<f64>)],
    out: &Path,
) -> Result<(), PlotError> {
    let rows = u32::try_from(metrics.len().max(1)).unwrap_or(u32::MAX);
    let height = TITLE_HEIGHT.saturating_add(METRIC_ROW_HEIGHT.saturating_mul(rows));
    render_and_write(out, (WIDE_WIDTH, height), |root| {
        draw_metric_samples(root, title, metrics)
    })
}

/// Draws the bit angular velocity θ̇x(L) in rpm against t in s of every run `(label, series)`
/// in its own colour, with a legend. Each curve is reduced by [`decimate_min_max`]; the y axis
/// always includes 0 so stick phases show. A run whose `bit_angular_velocity` does not match
/// its `t` is an error.
pub fn plot_bit_speed_overlay(runs: &[(String, &TimeSeries)], out: &Path) -> Result<(), PlotError> {
    if let Some((label, s)) = runs
        .iter()
        .find(|(_, s)| s.bit_angular_velocity.len() != s.t.len())
    {
        return Err(PlotError::LengthMismatch {
            path: out.to_owned(),
            channel: format!("{label}: bit_angular_velocity"),
            len: s.bit_angular_velocity.len(),
            t_len: s.t.len(),
        });
    }
    let curves: Vec<(&str, Vec<(f64, f64)>)> = runs
        .iter()
        .map(|(label, s)| {
            let mut points = decimate_min_max(&s.t, &s.bit_angular_velocity, PLOT_BUCKETS);
            points.iter_mut().for_each(|p| p.1 *= RPM_PER_RAD_S);
            (label.as_str(), points)
        })
        .collect();
    render_and_write(out, (WIDE_WIDTH, OVERLAY_HEIGHT), |root| {
        draw_overlay(root, &curves)
    })
}

type Area<'a> = DrawingArea<SVGBackend<'a>, Shift>;
/// A point (Ω [rpm], V0 [m/h]) or (x, y) in plot units.
type Point = (f64, f64);
type DrawResult = Result<(), DrawingAreaErrorKind<std::io::Error>>;

/// Renders a `size` SVG with `draw` in memory and writes it atomically to `out`.
fn render_and_write(
    out: &Path,
    size: (u32, u32),
    draw: impl FnOnce(&Area<'_>) -> DrawResult,
) -> Result<(), PlotError> {
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
        draw(&root)
            .and_then(|()| root.present())
            .map_err(|e| PlotError::Draw {
                path: out.to_owned(),
                message: e.to_string(),
            })?;
    }
    write_atomic(out, svg.as_bytes()).map_err(|error| PlotError::Write {
        path: out.to_owned(),
        error,
    })
}

// ---- colours, markers, numbers ----

/// Viridis at `s` ∈ [0, 1] (clamped; NaN gives the low end), from plotters' `ViridisRGB`.
fn viridis(s: f64) -> RGBColor {
    // plotters clamps but turns NaN into an index it unwraps: sanitise first.
    let s = if s.is_nan() { 0.0 } else { s.clamp(0.0, 1.0) };
    ViridisRGB.get_color(s)
}

/// The colour of `value` on a scale over the data range [lo, hi]; a constant (lo = hi) maps to
/// the middle of the scale.
fn scale_color(value: f64, (lo, hi): (f64, f64)) -> RGBColor {
    if hi > lo {
        viridis((value - lo) / (hi - lo))
    } else {
        viridis(0.5)
    }
}

/// The smallest and largest of the finite `values`, or None without any.
fn value_range(values: impl IntoIterator<Item = f64>) -> Option<(f64, f64)> {
    values
        .into_iter()
        .filter(|v| v.is_finite())
        .fold(None, |acc, v| match acc {
            None => Some((v, v)),
            Some((lo, hi)) => Some((f64::min(lo, v), f64::max(hi, v))),
        })
}

/// `v` with about 4 significant digits, exponent form when very large or small.
fn fmt_sig(v: f64) -> String {
    if v == 0.0 {
        return "0".to_owned();
    }
    if !v.is_finite() {
        return format!("{v}");
    }
    let decade = v.abs().log10().floor() as i32;
    if !(-3..5).contains(&decade) {
        format!("{v:.3e}")
    } else {
        let decimals = (3 - decade).clamp(0, 6) as usize;
        format!("{v:.decimals$}")
    }
}

/// Vertices of a five-pointed star of outer radius `r` px centred on (0, 0), point up.
fn star(r: f64) -> Vec<(i32, i32)> {
    (0..10)
        .map(|k| {
            let radius = if k % 2 == 0 { r } else { 0.45 * r };
            let angle = k as f64 * PI / 5.0;
            (
                (radius * angle.sin()).round() as i32,
                (-radius * angle.cos()).round() as i32,
            )
        })
        .collect()
}

/// A red star with a black outline of outer radius `r` px at `at`.
fn star_marker<'a, DB: DrawingBackend + 'a, C: Clone + 'a>(at: C, r: f64) -> DynElement<'a, DB, C> {
    let vertices = star(r);
    let mut outline = vertices.clone();
    outline.push(vertices[0]);
    (EmptyElement::at(at)
        + Polygon::new(vertices, STAR_FILL.filled())
        + PathElement::new(outline, BLACK.stroke_width(1)))
    .into_dyn()
}

/// A text style of `size` px in `color`, anchored at `h`, `v`.
fn text_style(size: u32, color: RGBColor, h: HPos, v: VPos) -> TextStyle<'static> {
    (FONT, size).into_font().color(&color).pos(Pos::new(h, v))
}

/// Cell edges [lo, hi] of every node: halfway to the neighbours in sorted order, half a
/// spacing beyond the outermost nodes. A lone node gets a ±5 % cell (±1 at 0); a non-finite
/// node gets None.
fn cell_edges(nodes: &[f64]) -> Vec<Option<(f64, f64)>> {
    let mut order: Vec<usize> = (0..nodes.len()).filter(|&i| nodes[i].is_finite()).collect();
    order.sort_by(|&a, &b| nodes[a].total_cmp(&nodes[b]));
    let mut edges = vec![None; nodes.len()];
    if let [only] = order[..] {
        edges[only] = Some(axis_range([nodes[only]], 0.0));
        return edges;
    }
    let x = |k: usize| nodes[order[k]];
    let n = order.len();
    for (k, &i) in order.iter().enumerate() {
        let lo = if k == 0 {
            x(0) - 0.5 * (x(1) - x(0))
        } else {
            0.5 * (x(k - 1) + x(k))
        };
        let hi = if k + 1 == n {
            x(n - 1) + 0.5 * (x(n - 1) - x(n - 2))
        } else {
            0.5 * (x(k) + x(k + 1))
        };
        edges[i] = Some((lo, hi));
    }
    edges
}

// ---- region geometry ----

/// The part of the box [x0, x1] × [y0, y1] where a·x + b·y ≥ u (Sutherland–Hodgman against one
/// half-plane), or None if it has no area.
fn clip_box_to_halfplane(
    (x0, x1): (f64, f64),
    (y0, y1): (f64, f64),
    (a, b, u): (f64, f64, f64),
) -> Option<Vec<(f64, f64)>> {
    let corners = [(x0, y0), (x1, y0), (x1, y1), (x0, y1)];
    let f = |p: (f64, f64)| a * p.0 + b * p.1 - u;
    let mut poly = Vec::with_capacity(5);
    for k in 0..4 {
        let (p, q) = (corners[k], corners[(k + 1) % 4]);
        let (fp, fq) = (f(p), f(q));
        if fp >= 0.0 {
            poly.push(p);
        }
        // Strict signs: a vertex on the line is kept above and is no crossing.
        if (fp > 0.0 && fq < 0.0) || (fp < 0.0 && fq > 0.0) {
            let s = fp / (fp - fq);
            poly.push((p.0 + s * (q.0 - p.0), p.1 + s * (q.1 - p.1)));
        }
    }
    let twice_area: f64 = (0..poly.len())
        .map(|k| {
            let (p, q) = (poly[k], poly[(k + 1) % poly.len()]);
            p.0 * q.1 - q.0 * p.1
        })
        .sum();
    let box_area = (x1 - x0) * (y1 - y0);
    (poly.len() >= 3 && twice_area.abs() > 1e-9 * box_area).then_some(poly)
}

/// The segment of the line a·x + b·y = u inside [x0, x1] × [y0, y1], or None if it misses.
fn clip_line_to_box(
    (x0, x1): (f64, f64),
    (y0, y1): (f64, f64),
    (a, b, u): (f64, f64, f64),
) -> Option<((f64, f64), (f64, f64))> {
    let tol_x = 1e-9 * (x1 - x0);
    let tol_y = 1e-9 * (y1 - y0);
    let mut hits: Vec<(f64, f64)> = Vec::with_capacity(4);
    if b != 0.0 {
        for x in [x0, x1] {
            let y = (u - a * x) / b;
            if y >= y0 - tol_y && y <= y1 + tol_y {
                hits.push((x, y.clamp(y0, y1)));
            }
        }
    }
    if a != 0.0 {
        for y in [y0, y1] {
            let x = (u - b * y) / a;
            if x >= x0 - tol_x && x <= x1 + tol_x {
                hits.push((x.clamp(x0, x1), y));
            }
        }
    }
    // The two hits farthest apart (a line through a corner hits it twice).
    let mut best: Option<(Point, Point, f64)> = None;
    for (i, &p) in hits.iter().enumerate() {
        for &q in &hits[i + 1..] {
            let d = ((p.0 - q.0) / (x1 - x0)).hypot((p.1 - q.1) / (y1 - y0));
            if best.is_none_or(|(_, _, bd)| d > bd) {
                best = Some((p, q, d));
            }
        }
    }
    best.filter(|&(_, _, d)| d > 1e-9).map(|(p, q, _)| (p, q))
}

/// `[lo, hi]` in order if both are finite.
fn finite_bounds([a, b]: [f64; 2]) -> Option<(f64, f64)> {
    (a.is_finite() && b.is_finite()).then(|| (a.min(b), a.max(b)))
}

fn is_finite_point(p: &(f64, f64)) -> bool {
    p.0.is_finite() && p.1.is_finite()
}

// ---- shared pieces: colour bar, legend ----

/// One row of a hand-drawn legend.
enum LegendEntry {
    ScoredPoint,
    NoValueCross,
    Path,
    Optimum,
    Infeasible,
    NoValueCell,
}

/// Draws `entries` with their `labels` top-down in `area` (pixel coordinates of the area).
fn draw_legend(area: &Area<'_>, entries: &[(LegendEntry, String)]) -> DrawResult {
    let x = 25;
    for (k, (entry, label)) in entries.iter().enumerate() {
        let y = 20 + 28 * k as i32;
        match entry {
            LegendEntry::ScoredPoint => {
                area.draw(&Circle::new((x, y), 5, viridis(0.6).filled()))?;
                area.draw(&Circle::new((x, y), 5, BLACK.stroke_width(1)))?;
            }
            LegendEntry::NoValueCross => {
                area.draw(&Cross::new((x, y), 5, NO_VALUE.stroke_width(2)))?;
            }
            LegendEntry::Path => {
                area.draw(&PathElement::new(
                    [(x - 12, y), (x + 12, y)],
                    PATH_COLOR.stroke_width(2),
                ))?;
                area.draw(&Circle::new((x, y), 3, PATH_COLOR.filled()))?;
            }
            LegendEntry::Optimum => {
                area.draw(&star_marker((x, y), 10.0))?;
            }
            LegendEntry::Infeasible | LegendEntry::NoValueCell => {
                let fill = match entry {
                    LegendEntry::Infeasible => INFEASIBLE_FILL,
                    _ => NO_VALUE_CELL,
                };
                area.draw(&Rectangle::new(
                    [(x - 8, y - 8), (x + 8, y + 8)],
                    fill.filled(),
                ))?;
                area.draw(&Rectangle::new(
                    [(x - 8, y - 8), (x + 8, y + 8)],
                    BLACK.mix(0.5).stroke_width(1),
                ))?;
                if let LegendEntry::NoValueCell = entry {
                    area.draw(&PathElement::new(
                        [(x - 8, y + 8), (x + 8, y - 8)],
                        BLACK.mix(0.35).stroke_width(1),
                    ))?;
                }
            }
        }
        area.draw(&Text::new(
            label.clone(),
            (x + 20, y),
            text_style(14, BLACK, HPos::Left, VPos::Center),
        ))?;
    }
    Ok(())
}

/// Draws a vertical colour bar for the data range [`min`, `max`] labelled `label`, with tick
/// labels and the exact minimum and maximum. A constant is shown on a bar padded around it.
fn draw_colorbar(area: &Area<'_>, label: &str, (min, max): (f64, f64)) -> DrawResult {
    let (lo, hi) = axis_range([min, max], 0.0);
    let (w, _) = area.dim_in_pixel();
    let bar = 28;
    let labels = 95;
    let mut chart = ChartBuilder::on(area)
        .margin_top(40)
        .margin_bottom(40)
        .margin_left(20)
        .margin_right(w.saturating_sub(20 + bar + labels))
        .x_label_area_size(0)
        .right_y_label_area_size(labels)
        .build_cartesian_2d(0.0..1.0, lo..hi)?;
    let y_fmt = |v: &f64| tick_label(*v, lo, hi);
    chart
        .configure_mesh()
        .disable_mesh()
        .disable_x_axis()
        .y_labels(8)
        .y_desc(label)
        .y_label_formatter(&y_fmt)
        .label_style((FONT, 13))
        .axis_desc_style((FONT, 15))
        .draw()?;
    let step = (hi - lo) / COLORBAR_STEPS as f64;
    chart.draw_series((0..COLORBAR_STEPS).map(|k| {
        let y0 = lo + step * k as f64;
        let color = viridis((k as f64 + 0.5) / COLORBAR_STEPS as f64);
        Rectangle::new([(0.0, y0), (1.0, y0 + step)], color.filled())
    }))?;
    chart.draw_series(std::iter::once(Rectangle::new(
        [(0.0, lo), (1.0, hi)],
        BLACK.stroke_width(1),
    )))?;
    let end_label = |at: f64, value: f64, prefix: &str, v: VPos, dy: i32| {
        EmptyElement::at((0.0, at))
            + Text::new(
                format!("{prefix} {}", fmt_sig(value)),
                (0, dy),
                text_style(13, BLACK, HPos::Left, v),
            )
    };
    chart.draw_series([
        end_label(hi, max, "max", VPos::Bottom, -6),
        end_label(lo, min, "min", VPos::Top, 6),
    ])?;
    Ok(())
}

/// Splits the figure body into the plot and the side column (colour bar above the legend).
fn split_body<'a>(body: &Area<'a>) -> (Area<'a>, Area<'a>, Area<'a>) {
    let (w, h) = body.dim_in_pixel();
    let (plot, side) = body.split_horizontally(w.saturating_sub(SIDE_WIDTH));
    let (bar, legend) = side.split_vertically(h * 3 / 5);
    (plot, bar, legend)
}

/// Caption text for an optimum, or an empty string.
fn optimum_caption(optimum: Option<(f64, f64)>) -> String {
    optimum
        .filter(is_finite_point)
        .map(|(o, v)| {
            format!(
                "optimum: \u{3a9} = {} rpm, V0 = {} m/h",
                fmt_sig(o),
                fmt_sig(v)
            )
        })
        .unwrap_or_default()
}

// ---- optimizer path ----

fn draw_optimizer_path(
    root: &Area<'_>,
    region: &Region,
    evaluated: &[EvaluatedPoint],
    path: &[(f64, f64)],
    optimum: Option<(f64, f64)>,
    title: &str,
) -> DrawResult {
    root.fill(&WHITE)?;
    let body = root.titled(title, (FONT, 26))?;
    let (plot_area, bar_area, legend_area) = split_body(&body);

    let bx = finite_bounds(region.omega_rpm);
    let by = finite_bounds(region.v0_m_per_h);
    let the_box = bx.zip(by);
    let points: Vec<&EvaluatedPoint> = evaluated
        .iter()
        .filter(|p| p.omega_rpm.is_finite() && p.v0_m_per_h.is_finite())
        .collect();
    let path_points: Vec<(usize, (f64, f64))> = path
        .iter()
        .copied()
        .enumerate()
        .filter(|(_, p)| is_finite_point(p))
        .collect();
    let optimum = optimum.filter(is_finite_point);
    let all = || {
        the_box
            .into_iter()
            .flat_map(|((x0, x1), (y0, y1))| [(x0, y0), (x1, y1)])
            .chain(points.iter().map(|p| (p.omega_rpm, p.v0_m_per_h)))
            .chain(path_points.iter().map(|p| p.1))
            .chain(optimum)
    };
    let (x_lo, x_hi) = axis_range(all().map(|p| p.0), 0.04);
    let (y_lo, y_hi) = axis_range(all().map(|p| p.1), 0.04);

    let mut chart = ChartBuilder::on(&plot_area)
        .caption(optimum_caption(optimum), (FONT, 17))
        .margin(10)
        .margin_right(20)
        .x_label_area_size(50)
        .y_label_area_size(75)
        .build_cartesian_2d(x_lo..x_hi, y_lo..y_hi)?;
    let x_fmt = |v: &f64| tick_label(*v, x_lo, x_hi);
    let y_fmt = |v: &f64| tick_label(*v, y_lo, y_hi);
    chart
        .configure_mesh()
        .x_desc(OMEGA_LABEL)
        .y_desc(V0_LABEL)
        .x_label_formatter(&x_fmt)
        .y_label_formatter(&y_fmt)
        .label_style((FONT, 15))
        .axis_desc_style((FONT, 17))
        .light_line_style(BLACK.mix(0.04))
        .bold_line_style(BLACK.mix(0.12))
        .draw()?;

    let lines: Vec<&ConstraintLine> = region
        .lines
        .iter()
        .filter(|c| c.omega_coef.is_finite() && c.v0_coef.is_finite() && c.upper.is_finite())
        .collect();
    let mut any_infeasible = false;
    if let Some((bx, by)) = the_box {
        let shaded: Vec<Vec<(f64, f64)>> = lines
            .iter()
            .filter_map(|c| clip_box_to_halfplane(bx, by, (c.omega_coef, c.v0_coef, c.upper)))
            .collect();
        any_infeasible = !shaded.is_empty();
        chart.draw_series(
            shaded
                .into_iter()
                .map(|poly| Polygon::new(poly, INFEASIBLE_FILL.filled())),
        )?;
        chart.draw_series(std::iter::once(Rectangle::new(
            [(bx.0, by.0), (bx.1, by.1)],
            BLACK.stroke_width(2),
        )))?;
    }
    for (k, c) in lines.iter().enumerate() {
        let Some((p, q)) = clip_line_to_box(
            (x_lo, x_hi),
            (y_lo, y_hi),
            (c.omega_coef, c.v0_coef, c.upper),
        ) else {
            continue;
        };
        let color = LINE_COLORS[k % LINE_COLORS.len()];
        chart.draw_series(LineSeries::new([p, q], color.stroke_width(2)))?;
        // Spread the labels of several lines along them so they do not sit on each other.
        let f = (k + 1) as f64 / (lines.len() + 1) as f64;
        let at = (p.0 + f * (q.0 - p.0), p.1 + f * (q.1 - p.1));
        chart.draw_series(std::iter::once(
            EmptyElement::at(at)
                + Text::new(
                    c.label.clone(),
                    (4, -4),
                    text_style(14, color, HPos::Left, VPos::Bottom),
                ),
        ))?;
    }

    let scored = |p: &EvaluatedPoint| p.score.filter(|s| p.feasible && s.is_finite());
    let range = value_range(points.iter().filter_map(|p| scored(p)));
    chart.draw_series(
        points
            .iter()
            .filter(|p| scored(p).is_none())
            .map(|p| Cross::new((p.omega_rpm, p.v0_m_per_h), 5, NO_VALUE.stroke_width(2))),
    )?;
    if let Some(range) = range {
        for p in points.iter().filter(|p| scored(p).is_some()) {
            let s = scored(p).unwrap_or(range.0);
            let at = (p.omega_rpm, p.v0_m_per_h);
            chart.draw_series([
                Circle::new(at, 6, scale_color(s, range).filled()),
                Circle::new(at, 6, BLACK.mix(0.7).stroke_width(1)),
            ])?;
        }
    }

    draw_path(&mut chart, &path_points)?;
    if let Some(opt) = optimum {
        chart.plotting_area().draw(&star_marker(opt, 13.0))?;
    }

    match range {
        Some(range) => draw_colorbar(&bar_area, "score (higher is better)", range)?,
        None => {
            bar_area.draw(&Text::new(
                "no scored points",
                (20, 40),
                text_style(14, BLACK, HPos::Left, VPos::Center),
            ))?;
        }
    }
    let mut entries = Vec::new();
    if range.is_some() {
        entries.push((
            LegendEntry::ScoredPoint,
            "evaluated, coloured by score".into(),
        ));
    }
    if points.iter().any(|p| scored(p).is_none()) {
        entries.push((LegendEntry::NoValueCross, "failed or infeasible".into()));
    }
    if !path_points.is_empty() {
        entries.push((LegendEntry::Path, "optimizer path (iterates)".into()));
    }
    if optimum.is_some() {
        entries.push((LegendEntry::Optimum, "optimum".into()));
    }
    if any_infeasible {
        entries.push((LegendEntry::Infeasible, "infeasible (constraints)".into()));
    }
    draw_legend(&legend_area, &entries)
}

type Chart<'a, 'b> = ChartContext<'a, SVGBackend<'b>, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

/// The iterate path: a line with an arrowhead mid-segment, a dot and a number per iterate
/// (every k-th when there are many). `points` are (original index, point).
fn draw_path(chart: &mut Chart<'_, '_>, points: &[(usize, (f64, f64))]) -> DrawResult {
    if points.is_empty() {
        return Ok(());
    }
    chart.draw_series(LineSeries::new(
        points.iter().map(|p| p.1),
        PATH_COLOR.stroke_width(2),
    ))?;
    let mut arrows = Vec::new();
    for w in points.windows(2) {
        let (p, q) = (w[0].1, w[1].1);
        let (bp, bq) = (chart.backend_coord(&p), chart.backend_coord(&q));
        let (dx, dy) = (f64::from(bq.0 - bp.0), f64::from(bq.1 - bp.1));
        let len = dx.hypot(dy);
        // Too short a segment would be hidden under its arrowhead.
        if len < 24.0 {
            continue;
        }
        let (ux, uy) = (dx / len, dy / len);
        let px = |along: f64, across: f64| {
            (
                (along * ux - across * uy).round() as i32,
                (along * uy + across * ux).round() as i32,
            )
        };
        let mid = (0.5 * (p.0 + q.0), 0.5 * (p.1 + q.1));
        arrows.push(
            EmptyElement::at(mid)
                + Polygon::new(
                    vec![px(7.0, 0.0), px(-6.0, 5.0), px(-6.0, -5.0)],
                    PATH_COLOR.filled(),
                ),
        );
    }
    chart.draw_series(arrows)?;
    chart.draw_series(
        points
            .iter()
            .map(|p| Circle::new(p.1, 3, PATH_COLOR.filled())),
    )?;
    let every = points.len().div_ceil(MAX_PATH_NUMBERS).max(1);
    let last = points.len() - 1;
    chart.draw_series(
        points
            .iter()
            .enumerate()
            .filter(|&(k, _)| k % every == 0 || k == last)
            .map(|(_, &(index, at))| {
                EmptyElement::at(at)
                    + Text::new(
                        index.to_string(),
                        (6, -5),
                        text_style(13, BLACK, HPos::Left, VPos::Bottom),
                    )
            }),
    )?;
    Ok(())
}

// ---- heat map ----

/// Node coordinates and row-major values of a heat map.
struct Grid<'a> {
    omega: &'a [f64],
    v0: &'a [f64],
    values: &'a [Option<f64>],
}

fn draw_heatmap(
    root: &Area<'_>,
    title: &str,
    value_label: &str,
    grid: &Grid<'_>,
    optimum: Option<(f64, f64)>,
) -> DrawResult {
    root.fill(&WHITE)?;
    let body = root.titled(title, (FONT, 26))?;
    let (plot_area, bar_area, legend_area) = split_body(&body);

    let x_edges = cell_edges(grid.omega);
    let y_edges = cell_edges(grid.v0);
    let optimum = optimum.filter(is_finite_point);
    let view = |edges: &[Option<(f64, f64)>], opt: Option<f64>| {
        let cells = axis_range(edges.iter().flatten().flat_map(|e| [e.0, e.1]), 0.0);
        match opt {
            // An optimum off the grid gets some room so its star is not cut.
            Some(o) if !(cells.0..=cells.1).contains(&o) => axis_range([cells.0, cells.1, o], 0.04),
            _ => cells,
        }
    };
    let (x_lo, x_hi) = view(&x_edges, optimum.map(|o| o.0));
    let (y_lo, y_hi) = view(&y_edges, optimum.map(|o| o.1));

    let mut chart = ChartBuilder::on(&plot_area)
        .caption(optimum_caption(optimum), (FONT, 17))
        .margin(10)
        .margin_right(20)
        .x_label_area_size(50)
        .y_label_area_size(75)
        .build_cartesian_2d(x_lo..x_hi, y_lo..y_hi)?;
    let x_fmt = |v: &f64| tick_label(*v, x_lo, x_hi);
    let y_fmt = |v: &f64| tick_label(*v, y_lo, y_hi);
    chart
        .configure_mesh()
        .disable_mesh()
        .x_desc(OMEGA_LABEL)
        .y_desc(V0_LABEL)
        .x_label_formatter(&x_fmt)
        .y_label_formatter(&y_fmt)
        .label_style((FONT, 15))
        .axis_desc_style((FONT, 17))
        .draw()?;

    // Cells at non-finite nodes are not drawn, so their values do not set the colour range.
    let n_omega = grid.omega.len();
    let drawn: Vec<([Point; 2], Option<f64>)> = y_edges
        .iter()
        .enumerate()
        .flat_map(|(j, ye)| {
            x_edges
                .iter()
                .enumerate()
                .map(move |(i, xe)| (i, j, *xe, *ye))
        })
        .filter_map(|(i, j, xe, ye)| {
            let ((x0, x1), (y0, y1)) = xe.zip(ye)?;
            let value = grid.values[j * n_omega + i].filter(|v| v.is_finite());
            Some(([(x0, y0), (x1, y1)], value))
        })
        .collect();
    let range = value_range(drawn.iter().filter_map(|c| c.1));
    let mut cells = Vec::with_capacity(drawn.len());
    let mut hatches = Vec::new();
    for (corners, value) in drawn {
        match value.zip(range) {
            Some((v, range)) => {
                cells.push(Rectangle::new(corners, scale_color(v, range).filled()));
            }
            None => {
                cells.push(Rectangle::new(corners, NO_VALUE_CELL.filled()));
                hatches.push(PathElement::new(corners, BLACK.mix(0.35).stroke_width(1)));
            }
        }
    }
    let any_missing = !hatches.is_empty();
    chart.draw_series(cells)?;
    chart.draw_series(hatches)?;
    if let Some(opt) = optimum {
        chart.plotting_area().draw(&star_marker(opt, 13.0))?;
    }

    match range {
        Some(range) => draw_colorbar(&bar_area, value_label, range)?,
        None => {
            bar_area.draw(&Text::new(
                format!("{value_label}: no values"),
                (20, 40),
                text_style(14, BLACK, HPos::Left, VPos::Center),
            ))?;
        }
    }
    let mut entries = Vec::new();
    if any_missing {
        entries.push((
            LegendEntry::NoValueCell,
            "no value (infeasible/failed)".into(),
        ));
    }
    if optimum.is_some() {
        entries.push((LegendEntry::Optimum, "optimum".into()));
    }
    draw_legend(&legend_area, &entries)
}

// ---- metric samples ----

fn draw_metric_samples(root: &Area<'_>, title: &str, metrics: &[(String, Vec<f64>)]) -> DrawResult {
    root.fill(&WHITE)?;
    let body = root.titled(title, (FONT, 26))?;
    if metrics.is_empty() {
        body.draw(&Text::new(
            "no metrics",
            (40, 40),
            text_style(16, BLACK, HPos::Left, VPos::Center),
        ))?;
        return Ok(());
    }
    for (area, (name, samples)) in body.split_evenly((metrics.len(), 1)).iter().zip(metrics) {
        draw_metric_row(area, name, samples)?;
    }
    Ok(())
}

/// One metric: samples as dots at a deterministic vertical jitter, the mean as a red line.
fn draw_metric_row(area: &Area<'_>, name: &str, samples: &[f64]) -> DrawResult {
    let finite: Vec<f64> = samples.iter().copied().filter(|v| v.is_finite()).collect();
    let skipped = samples.len() - finite.len();
    let mean = (!finite.is_empty()).then(|| finite.iter().sum::<f64>() / finite.len() as f64);
    let mut caption = match mean {
        Some(m) => format!(
            "{name}: mean {} (red line), {} sample{}",
            fmt_sig(m),
            finite.len(),
            if finite.len() == 1 { "" } else { "s" }
        ),
        None => format!("{name}: no finite samples"),
    };
    if skipped > 0 {
        caption.push_str(&format!(", {skipped} non-finite left out"));
    }
    let (lo, hi) = axis_range(finite.iter().copied(), 0.05);
    let mut chart = ChartBuilder::on(area)
        .caption(caption, (FONT, 16))
        .margin(8)
        .margin_right(30)
        .margin_left(20)
        .x_label_area_size(28)
        .y_label_area_size(0)
        .build_cartesian_2d(lo..hi, 0.0..1.0)?;
    let x_fmt = |v: &f64| tick_label(*v, lo, hi);
    chart
        .configure_mesh()
        .disable_y_mesh()
        .y_labels(0)
        .x_label_formatter(&x_fmt)
        .label_style((FONT, 13))
        .light_line_style(BLACK.mix(0.04))
        .bold_line_style(BLACK.mix(0.12))
        .draw()?;
    // Golden-ratio jitter: deterministic, evenly spread, the first sample in the middle.
    let golden = 0.5 * (5f64.sqrt() - 1.0);
    chart.draw_series(finite.iter().enumerate().map(|(k, &v)| {
        let y = 0.1 + 0.8 * (0.5 + k as f64 * golden).fract();
        Circle::new((v, y), 4, RUN_COLORS[0].mix(0.65).filled())
    }))?;
    if let Some(m) = mean {
        chart.draw_series(std::iter::once(PathElement::new(
            [(m, 0.02), (m, 0.98)],
            RED.stroke_width(2),
        )))?;
    }
    Ok(())
}

// ---- bit speed overlay ----

fn draw_overlay(root: &Area<'_>, curves: &[(&str, Vec<(f64, f64)>)]) -> DrawResult {
    root.fill(&WHITE)?;
    let body = root.titled(OVERLAY_TITLE, (FONT, 26))?;
    let points = || curves.iter().flat_map(|c| c.1.iter());
    let (t_lo, t_hi) = axis_range(points().map(|p| p.0), 0.0);
    let (y_lo, y_hi) = axis_range(points().map(|p| p.1).chain([0.0]), 0.05);
    let mut chart = ChartBuilder::on(&body)
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
        .y_desc("\u{3b8}\u{307}x(L) [rpm]")
        .x_label_formatter(&x_fmt)
        .y_label_formatter(&y_fmt)
        .label_style((FONT, 15))
        .axis_desc_style((FONT, 17))
        .light_line_style(BLACK.mix(0.05))
        .bold_line_style(BLACK.mix(0.15))
        .draw()?;
    for (k, (label, points)) in curves.iter().enumerate() {
        let style = RUN_COLORS[k % RUN_COLORS.len()].stroke_width(1);
        chart
            .draw_series(LineSeries::new(points.iter().copied(), style))?
            .label(*label)
            .legend(move |(x, y)| PathElement::new([(x, y), (x + 24, y)], style.stroke_width(2)));
    }
    if !curves.is_empty() {
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperRight)
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
    use crate::report::testdata::synthetic_series;

    fn read(path: &Path) -> String {
        std::fs::read_to_string(path).unwrap()
    }

    fn assert_svg(svg: &str) {
        assert!(svg.starts_with("<svg"), "{}", &svg[..svg.len().min(200)]);
        assert!(svg.trim_end().ends_with("</svg>"));
    }

    /// The contents of every `<text>` element, trimmed.
    fn texts(svg: &str) -> Vec<&str> {
        svg.split("<text ")
            .skip(1)
            .map(|s| {
                let start = s.find('>').unwrap() + 1;
                s[start..start + s[start..].find("</text>").unwrap()].trim()
            })
            .collect()
    }

    fn assert_contains(svg: &str, texts: &[&str]) {
        for text in texts {
            assert!(svg.contains(text), "missing {text:?}");
        }
    }

    /// Elements `<tag ...>` whose attributes contain `attr`.
    fn count_with(svg: &str, tag: &str, attr: &str) -> usize {
        svg.split(&format!("<{tag} "))
            .skip(1)
            .filter(|s| s[..s.find('>').unwrap()].contains(attr))
            .count()
    }

    fn hex(c: RGBColor) -> String {
        format!("\"#{:02X}{:02X}{:02X}\"", c.0, c.1, c.2)
    }

    /// Ω ∈ [40, 160] rpm, V0 ∈ [5, 30] m/h; a torque limit cuts the upper right corner and a
    /// minimum V0/Ω ratio the lower right.
    fn region() -> Region {
        Region {
            omega_rpm: [40.0, 160.0],
            v0_m_per_h: [5.0, 30.0],
            lines: vec![
                ConstraintLine {
                    label: "torque limit".into(),
                    omega_coef: 0.2,
                    v0_coef: 1.0,
                    upper: 45.0,
                },
                ConstraintLine {
                    label: "min V0/\u{3a9}".into(),
                    omega_coef: 0.1,
                    v0_coef: -1.0,
                    upper: 0.0,
                },
            ],
        }
    }

    fn feasible(r: &Region, (o, v): (f64, f64)) -> bool {
        r.lines
            .iter()
            .all(|c| c.omega_coef * o + c.v0_coef * v <= c.upper)
    }

    /// A 5 × 4 grid of evaluated points, two of which failed.
    fn evaluated(r: &Region) -> Vec<EvaluatedPoint> {
        let mut out = Vec::new();
        for j in 0..4 {
            for i in 0..5 {
                let (o, v) = (40.0 + 30.0 * i as f64, 5.0 + 25.0 / 3.0 * j as f64);
                let failed = (i, j) == (1, 2) || (i, j) == (3, 0);
                out.push(EvaluatedPoint {
                    omega_rpm: o,
                    v0_m_per_h: v,
                    score: (!failed)
                        .then(|| -((o - 110.0) / 50.0).powi(2) - ((v - 15.0) / 10.0).powi(2)),
                    feasible: feasible(r, (o, v)),
                });
            }
        }
        out
    }

    const PATH: [(f64, f64); 5] = [
        (60.0, 25.0),
        (90.0, 10.0),
        (130.0, 20.0),
        (105.0, 13.0),
        (110.0, 15.0),
    ];

    // ---- optimizer path ----

    #[test]
    fn optimizer_path_plot_has_labels_markers_and_shading() {
        let r = region();
        let points = evaluated(&r);
        let scored = points
            .iter()
            .filter(|p| p.feasible && p.score.is_some())
            .count();
        let crosses = points.len() - scored;
        assert_eq!((scored, crosses), (9, 11));
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("path.svg");
        plot_optimizer_path(
            &r,
            &points,
            &PATH,
            Some((110.0, 15.0)),
            "Trust-region path",
            &out,
        )
        .unwrap();
        let svg = read(&out);
        assert_svg(&svg);
        assert_contains(
            &svg,
            &[
                "Trust-region path",
                OMEGA_LABEL,
                V0_LABEL,
                "torque limit",
                "min V0/\u{3a9}",
                "score (higher is better)",
                "evaluated, coloured by score",
                "failed or infeasible",
                "optimizer path (iterates)",
                "infeasible (constraints)",
                "optimum: \u{3a9} = 110.0 rpm, V0 = 15.00 m/h",
            ],
        );
        // Every iterate is numbered.
        let labels = texts(&svg);
        for k in ["0", "1", "2", "3", "4"] {
            assert!(labels.contains(&k), "iterate {k}: {labels:?}");
        }
        // Scored points: a filled circle and an outline each; iterates: one dot each; legend:
        // the scored sample (2) and the path sample (1).
        assert_eq!(
            svg.matches("<circle").count(),
            2 * scored + PATH.len() + 3,
            "circles"
        );
        // A cross is two lines; one more cross in the legend.
        assert_eq!(
            count_with(&svg, "line", &format!("stroke={}", hex(NO_VALUE))),
            2 * (crosses + 1)
        );
        // Both constraints cut the box: two shaded polygons (+ the legend swatch, a rect).
        assert_eq!(
            count_with(&svg, "polygon", &format!("fill={}", hex(INFEASIBLE_FILL))),
            2
        );
        // Four arrowheads (every segment is long), stars on the plot and in the legend.
        assert_eq!(
            count_with(&svg, "polygon", &format!("fill={}", hex(PATH_COLOR))),
            PATH.len() - 1
        );
        assert_eq!(
            count_with(&svg, "polygon", &format!("fill={}", hex(STAR_FILL))),
            2
        );
        assert_eq!(
            count_with(&svg, "rect", &format!("fill={}", hex(viridis(1.0)))),
            0,
            "the colour bar's top step is a mix, not the end colour"
        );
        assert!(svg.len() < 100_000, "{} bytes", svg.len());
    }

    #[test]
    fn optimizer_path_with_empty_or_non_finite_input_still_plots() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("empty.svg");
        let empty = Region {
            omega_rpm: [f64::NAN, 100.0],
            v0_m_per_h: [5.0, 30.0],
            lines: vec![],
        };
        plot_optimizer_path(&empty, &[], &[], None, "Nothing yet", &out).unwrap();
        let svg = read(&out);
        assert_svg(&svg);
        assert_contains(&svg, &["Nothing yet", "no scored points"]);
        assert_eq!(svg.matches("<circle").count(), 0);
        assert!(!svg.contains("optimum"));

        let nan_point = EvaluatedPoint {
            omega_rpm: f64::NAN,
            v0_m_per_h: 1.0,
            score: Some(1.0),
            feasible: true,
        };
        let nan_score = EvaluatedPoint {
            omega_rpm: 50.0,
            v0_m_per_h: 10.0,
            score: Some(f64::NAN),
            feasible: true,
        };
        let mut r = region();
        r.lines.push(ConstraintLine {
            label: "broken".into(),
            omega_coef: f64::NAN,
            v0_coef: 1.0,
            upper: 1.0,
        });
        plot_optimizer_path(
            &r,
            &[nan_point, nan_score],
            &[(f64::NAN, 1.0), (60.0, 20.0), (f64::INFINITY, 3.0)],
            Some((f64::NAN, 2.0)),
            "Non-finite",
            &out,
        )
        .unwrap();
        let svg = read(&out);
        assert_contains(
            &svg,
            &["Non-finite", "no scored points", "failed or infeasible"],
        );
        assert!(!svg.contains("broken") && !svg.contains("optimum"));
        // The NaN score is a cross (+ legend cross); the one finite iterate is a dot (+ legend).
        assert_eq!(
            count_with(&svg, "line", &format!("stroke={}", hex(NO_VALUE))),
            4
        );
        assert_eq!(svg.matches("<circle").count(), 2);
    }

    #[test]
    fn a_single_scored_point_and_an_all_infeasible_box_plot() {
        let r = Region {
            omega_rpm: [100.0, 100.0],
            v0_m_per_h: [10.0, 20.0],
            lines: vec![ConstraintLine {
                label: "impossible".into(),
                omega_coef: 0.0,
                v0_coef: 0.0,
                upper: -1.0,
            }],
        };
        let p = EvaluatedPoint {
            omega_rpm: 100.0,
            v0_m_per_h: 12.0,
            score: Some(3.0),
            feasible: true,
        };
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("one.svg");
        plot_optimizer_path(&r, &[p], &[(100.0, 12.0)], Some((100.0, 12.0)), "One", &out).unwrap();
        let svg = read(&out);
        assert_contains(&svg, &["One", "max 3.000", "min 3.000"]);
        // A zero-width box has no area to shade; the constraint has no line to draw.
        assert!(!svg.contains("impossible"));
        assert_eq!(svg.matches("<circle").count(), 2 + 1 + 3);
    }

    #[test]
    fn a_long_path_numbers_every_kth_iterate_and_skips_short_arrows() {
        // 60 iterates: every 3rd is numbered, and the last. The first 31 segments are long; the
        // rest creep by 0.01 rpm and 0.01 m/h and get no arrowhead.
        let path: Vec<(f64, f64)> = (0..60)
            .map(|k| {
                let f = k as f64;
                if k <= 30 {
                    (40.0 + 4.0 * f, 5.0 + 25.0 * (k % 2) as f64)
                } else {
                    (160.0 - 0.01 * (f - 30.0), 30.0 - 0.01 * (f - 30.0))
                }
            })
            .collect();
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("long.svg");
        plot_optimizer_path(&region(), &[], &path, None, "Long", &out).unwrap();
        let svg = read(&out);
        let labels = texts(&svg);
        for k in ["0", "3", "57", "59"] {
            assert!(labels.contains(&k), "iterate {k} numbered: {labels:?}");
        }
        for k in ["1", "2", "58"] {
            assert!(!labels.contains(&k), "iterate {k} not numbered: {labels:?}");
        }
        assert_eq!(
            count_with(&svg, "polygon", &format!("fill={}", hex(PATH_COLOR))),
            31
        );
        assert_eq!(svg.matches("<circle").count(), path.len() + 1);
    }

    #[test]
    fn box_clipped_to_a_half_plane() {
        let (bx, by) = ((0.0, 2.0), (0.0, 1.0));
        // x + y ≥ 2: the triangle (2, 0), (2, 1), (1, 1).
        let tri = clip_box_to_halfplane(bx, by, (1.0, 1.0, 2.0)).unwrap();
        assert_eq!(tri.len(), 3, "{tri:?}");
        for v in [(2.0, 0.0), (2.0, 1.0), (1.0, 1.0)] {
            assert!(tri.contains(&v), "{tri:?}");
        }
        // 0 ≥ -1 everywhere: the whole box; 0 ≥ 1 nowhere.
        assert_eq!(
            clip_box_to_halfplane(bx, by, (0.0, 0.0, -1.0))
                .unwrap()
                .len(),
            4
        );
        assert!(clip_box_to_halfplane(bx, by, (0.0, 0.0, 1.0)).is_none());
        // A constraint active only on the box's edge leaves nothing of area.
        assert!(clip_box_to_halfplane(bx, by, (1.0, 0.0, 2.0)).is_none());
        assert!(clip_box_to_halfplane(bx, by, (1.0, 0.0, 3.0)).is_none());
    }

    #[test]
    fn line_clipped_to_a_box() {
        let (bx, by) = ((0.0, 2.0), (0.0, 1.0));
        let sorted = |(p, q): ((f64, f64), (f64, f64))| if p <= q { (p, q) } else { (q, p) };
        assert_eq!(
            clip_line_to_box(bx, by, (1.0, 1.0, 2.0)).map(sorted),
            Some(((1.0, 1.0), (2.0, 0.0)))
        );
        assert_eq!(
            clip_line_to_box(bx, by, (1.0, 0.0, 0.5)).map(sorted),
            Some(((0.5, 0.0), (0.5, 1.0)))
        );
        assert_eq!(
            clip_line_to_box(bx, by, (0.0, 2.0, 1.0)).map(sorted),
            Some(((0.0, 0.5), (2.0, 0.5)))
        );
        // Through the corner (2, 1) and the corner (0, 0): the diagonal.
        assert_eq!(
            clip_line_to_box(bx, by, (1.0, -2.0, 0.0)).map(sorted),
            Some(((0.0, 0.0), (2.0, 1.0)))
        );
        assert_eq!(clip_line_to_box(bx, by, (1.0, 1.0, 5.0)), None);
        // Touching a single corner is no segment.
        assert_eq!(clip_line_to_box(bx, by, (1.0, 1.0, 3.0)), None);
        assert_eq!(clip_line_to_box(bx, by, (0.0, 0.0, 1.0)), None);
    }

    // ---- heat map ----

    #[test]
    fn heatmap_has_one_cell_per_node_and_grey_missing_cells() {
        let omega = [40.0, 70.0, 100.0, 130.0];
        let v0 = [5.0, 15.0, 30.0];
        let mut values: Vec<Option<f64>> = (0..12).map(|k| Some(k as f64 * 0.5 - 1.0)).collect();
        values[3] = None;
        values[7] = Some(f64::NAN);
        values[11] = None;
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("heat.svg");
        plot_heatmap(
            "Robust score over the grid",
            "score J",
            &omega,
            &v0,
            &values,
            Some((70.0, 15.0)),
            &out,
        )
        .unwrap();
        let svg = read(&out);
        assert_svg(&svg);
        assert_contains(
            &svg,
            &[
                "Robust score over the grid",
                "score J",
                OMEGA_LABEL,
                V0_LABEL,
                "max 4.000",
                "min -1.000",
                "no value (infeasible/failed)",
                "optimum: \u{3a9} = 70.00 rpm, V0 = 15.00 m/h",
            ],
        );
        // Three missing cells and the legend swatch.
        assert_eq!(
            count_with(&svg, "rect", &format!("fill={}", hex(NO_VALUE_CELL))),
            4
        );
        // Coloured rects: 9 cells and the colour bar's steps; the lowest and highest cells
        // have the scale's end colours.
        let coloured = count_with(&svg, "rect", "fill=\"#")
            - count_with(&svg, "rect", "fill=\"#FFFFFF\"")
            - count_with(&svg, "rect", &format!("fill={}", hex(NO_VALUE_CELL)));
        assert_eq!(coloured, 9 + COLORBAR_STEPS);
        assert_eq!(
            count_with(&svg, "rect", &format!("fill={}", hex(viridis(0.0)))),
            1
        );
        assert_eq!(
            count_with(&svg, "rect", &format!("fill={}", hex(viridis(1.0)))),
            1
        );
        assert_eq!(
            count_with(&svg, "polygon", &format!("fill={}", hex(STAR_FILL))),
            2
        );
    }

    #[test]
    fn heatmap_grid_mismatch_is_an_error_and_writes_nothing() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("heat.svg");
        let err = plot_heatmap(
            "t",
            "v",
            &[1.0, 2.0],
            &[1.0, 2.0, 3.0],
            &[Some(1.0); 5],
            None,
            &out,
        )
        .unwrap_err();
        assert!(
            matches!(
                err,
                PlotError::GridMismatch {
                    len: 5,
                    n_omega: 2,
                    n_v0: 3,
                    ..
                }
            ),
            "{err}"
        );
        assert!(err.to_string().contains("heat.svg"), "{err}");
        assert!(!out.exists());
    }

    #[test]
    fn heatmap_with_empty_missing_or_degenerate_grids_still_plots() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("heat.svg");
        plot_heatmap("Empty", "J", &[], &[], &[], None, &out).unwrap();
        let svg = read(&out);
        assert_svg(&svg);
        assert_contains(&svg, &["Empty", "J: no values"]);

        plot_heatmap(
            "All missing",
            "J",
            &[1.0, 2.0],
            &[3.0],
            &[None, None],
            Some((9.0, 9.0)),
            &out,
        )
        .unwrap();
        let svg = read(&out);
        assert_contains(&svg, &["All missing", "J: no values", "optimum"]);
        assert_eq!(
            count_with(&svg, "rect", &format!("fill={}", hex(NO_VALUE_CELL))),
            3
        );

        // One node, and a NaN node whose cells are left out.
        plot_heatmap(
            "One",
            "J",
            &[100.0, f64::NAN],
            &[10.0],
            &[Some(2.0), Some(5.0)],
            None,
            &out,
        )
        .unwrap();
        let svg = read(&out);
        assert_contains(&svg, &["One", "max 2.000", "min 2.000"]);
        assert!(!svg.contains("no value"));
    }

    #[test]
    fn cell_edges_lie_halfway_between_nodes() {
        assert_eq!(
            cell_edges(&[0.0, 1.0, 3.0]),
            vec![Some((-0.5, 0.5)), Some((0.5, 2.0)), Some((2.0, 4.0))]
        );
        // Unsorted and non-finite nodes.
        assert_eq!(
            cell_edges(&[3.0, f64::NAN, 0.0, 1.0]),
            vec![Some((2.0, 4.0)), None, Some((-0.5, 0.5)), Some((0.5, 2.0))]
        );
        assert_eq!(cell_edges(&[10.0]), vec![Some((9.5, 10.5))]);
        assert_eq!(cell_edges(&[0.0]), vec![Some((-1.0, 1.0))]);
        assert!(cell_edges(&[]).is_empty());
    }

    // ---- metric samples ----

    #[test]
    fn metric_samples_show_every_finite_sample_and_the_mean() {
        let metrics = vec![
            ("ROP [m/h]".to_owned(), vec![10.0, 12.0, 11.0, 13.0, 14.0]),
            ("stick-slip severity [-]".to_owned(), vec![0.25]),
            ("impacts [1/s]".to_owned(), vec![1.0, f64::NAN, 3.0]),
            ("torque [kN m]".to_owned(), vec![f64::INFINITY]),
        ];
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("metrics.svg");
        plot_metric_samples("Metrics at the optimum", &metrics, &out).unwrap();
        let svg = read(&out);
        assert_svg(&svg);
        assert_contains(
            &svg,
            &[
                "Metrics at the optimum",
                "ROP [m/h]: mean 12.00 (red line), 5 samples",
                "stick-slip severity [-]: mean 0.2500 (red line), 1 sample",
                "impacts [1/s]: mean 2.000 (red line), 2 samples, 1 non-finite left out",
                "torque [kN m]: no finite samples, 1 non-finite left out",
            ],
        );
        assert_eq!(svg.matches("<circle").count(), 5 + 1 + 2);
        // Three mean lines.
        assert_eq!(count_with(&svg, "polyline", "stroke=\"#FF0000\""), 3);

        plot_metric_samples("No metrics", &[], &out).unwrap();
        let svg = read(&out);
        assert_contains(&svg, &["No metrics", "no metrics"]);
        assert_eq!(svg.matches("<circle").count(), 0);
    }

    // ---- bit speed overlay ----

    #[test]
    fn bit_speed_overlay_draws_one_decimated_curve_per_run_in_rpm() {
        let a = synthetic_series(20_000);
        let mut b = synthetic_series(5_000);
        b.bit_angular_velocity.iter_mut().for_each(|w| *w *= 0.5);
        let runs = [("nominal".to_owned(), &a), ("half speed".to_owned(), &b)];
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("overlay.svg");
        plot_bit_speed_overlay(&runs, &out).unwrap();
        let svg = read(&out);
        assert_svg(&svg);
        assert_contains(
            &svg,
            &[
                OVERLAY_TITLE,
                "\u{3b8}\u{307}x(L) [rpm]",
                "t [s]",
                "nominal",
                "half speed",
            ],
        );
        // One data curve per run in the run's colour, decimated (+ a legend sample each).
        for (k, n) in [(0, 20_000), (1, 5_000)] {
            let color = hex(RUN_COLORS[k]);
            assert_eq!(count_with(&svg, "polyline", &format!("stroke={color}")), 2);
            let curve = svg
                .split("<polyline ")
                .find(|s| s.contains(&format!("stroke={color}")) && s.len() > 1000)
                .unwrap();
            let points = curve[..curve.find("/>").unwrap()]
                .split_whitespace()
                .count();
            assert!(points <= 2 * PLOT_BUCKETS + 8 && points < n, "{points}");
        }
        assert!(svg.len() < 400_000, "{} bytes", svg.len());
    }

    #[test]
    fn bit_speed_is_converted_to_rpm() {
        let mut s = synthetic_series(10);
        s.bit_angular_velocity.iter_mut().for_each(|w| *w = TAU);
        let points = decimate_min_max(&s.t, &s.bit_angular_velocity, PLOT_BUCKETS);
        let rpm: Vec<f64> = points.iter().map(|p| p.1 * RPM_PER_RAD_S).collect();
        assert!(rpm.iter().all(|&r| (r - 60.0).abs() < 1e-12), "{rpm:?}");
    }

    #[test]
    fn bit_speed_overlay_rejects_mismatched_runs_and_plots_empty_ones() {
        let mut bad = synthetic_series(50);
        bad.bit_angular_velocity.pop();
        let good = synthetic_series(50);
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("overlay.svg");
        let err = plot_bit_speed_overlay(&[("ok".into(), &good), ("bad".into(), &bad)], &out)
            .unwrap_err();
        assert!(
            matches!(&err, PlotError::LengthMismatch { len: 49, t_len: 50, channel, .. } if channel.starts_with("bad")),
            "{err}"
        );
        assert!(!out.exists());

        plot_bit_speed_overlay(&[], &out).unwrap();
        assert!(read(&out).contains(OVERLAY_TITLE));
        let nan = TimeSeries {
            t: vec![0.0, 1.0],
            bit_angular_velocity: vec![f64::NAN; 2],
            ..TimeSeries::default()
        };
        let empty = TimeSeries::default();
        plot_bit_speed_overlay(&[("nan".into(), &nan), ("empty".into(), &empty)], &out).unwrap();
        assert_contains(&read(&out), &["nan", "empty"]);
    }

    // ---- writing ----

    #[test]
    fn plots_are_written_whole_and_replace_the_old_file() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("new/dir/metrics.svg");
        let metrics = vec![("m".to_owned(), vec![1.0, 2.0])];
        plot_metric_samples("First", &metrics, &out).unwrap();
        plot_metric_samples("Second", &metrics, &out).unwrap();
        let svg = read(&out);
        assert_svg(&svg);
        assert!(svg.contains("Second") && !svg.contains("First"));
        // No temporary file is left next to it.
        let names: Vec<_> = std::fs::read_dir(out.parent().unwrap())
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(names, vec![std::ffi::OsString::from("metrics.svg")]);

        // A path that cannot be a file: an error naming it, and the old file is untouched.
        let err = plot_metric_samples("Third", &metrics, dir.path()).unwrap_err();
        assert!(matches!(err, PlotError::Write { .. }), "{err}");
        // The path once and the cause once, also through an error chain.
        let chain = format!("{:#}", anyhow::Error::from(err));
        let path = dir.path().display().to_string();
        assert_eq!(chain.matches(&path).count(), 1, "{chain}");
        assert_eq!(chain.matches("os error").count(), 1, "{chain}");
        assert!(read(&out).contains("Second"));
    }

    // ---- helpers ----

    /// Within `tol` units per channel of the colour `hex` ("#rrggbb").
    fn near(c: RGBColor, hex: &str, tol: u8) -> bool {
        let channel = |k: usize| u8::from_str_radix(&hex[1 + 2 * k..3 + 2 * k], 16).unwrap();
        [c.0, c.1, c.2]
            .iter()
            .enumerate()
            .all(|(k, &v)| v.abs_diff(channel(k)) <= tol)
    }

    #[test]
    fn viridis_matches_the_published_map_and_clamps() {
        // matplotlib's viridis: #440154 at 0, #21918c at 0.5, #fde725 at 1.
        assert!(near(viridis(0.0), "#440154", 3), "{:?}", viridis(0.0));
        assert!(near(viridis(0.5), "#21918c", 3), "{:?}", viridis(0.5));
        assert!(near(viridis(1.0), "#fde725", 3), "{:?}", viridis(1.0));
        assert_eq!(viridis(-3.0), viridis(0.0));
        assert_eq!(viridis(7.0), viridis(1.0));
        assert_eq!(viridis(f64::NAN), viridis(0.0));
        assert_eq!(viridis(f64::INFINITY), viridis(1.0));
        assert_eq!(scale_color(5.0, (0.0, 10.0)), viridis(0.5));
        assert_eq!(scale_color(2.0, (0.0, 10.0)), viridis(0.2));
        assert_eq!(scale_color(3.0, (3.0, 3.0)), viridis(0.5));
        assert_eq!(
            value_range([2.0, f64::NAN, -1.0, f64::INFINITY]),
            Some((-1.0, 2.0))
        );
        assert_eq!(value_range([f64::NAN]), None);
    }

    #[test]
    fn numbers_have_four_significant_digits() {
        assert_eq!(fmt_sig(0.0), "0");
        assert_eq!(fmt_sig(123.456), "123.5");
        assert_eq!(fmt_sig(-0.012345), "-0.01235");
        assert_eq!(fmt_sig(2.0), "2.000");
        assert_eq!(fmt_sig(1.5e-5), "1.500e-5");
        assert_eq!(fmt_sig(2.5e6), "2.500e6");
        assert_eq!(fmt_sig(f64::NAN), "NaN");
    }
}
