//! The frame of the operating-point plots: the split of the figure into the chart of the Ω–V0
//! plane and a side column, the chart with the caption of its starred point, and in the side
//! column a colour bar with its range (or the value of a constant field) and a hand-drawn legend.

use super::SetPointAxis;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, VPos};

use crate::report::axes::{Layout, XyChart, axis_range, tick_label, titled_figure, xy_chart};

use super::geometry::is_finite_point;
use super::style::{
    Area, COLORBAR_STEPS, DrawResult, FONT, INFEASIBLE_FILL, NO_VALUE, NO_VALUE_CELL, OMEGA_LABEL,
    PATH_COLOR, SIDE_WIDTH, fmt_sig, is_constant, set_point_label, star_marker, text_style,
    viridis,
};

/// One row of a hand-drawn legend.
pub(super) enum LegendEntry {
    ScoredPoint,
    NoValueCross,
    Path,
    /// The starred point (the optimum, the best map node).
    Star,
    Infeasible,
    NoValueCell,
}

/// Draws `entries` with their `labels` top-down in `area` (pixel coordinates of the area).
pub(super) fn draw_legend(area: &Area<'_>, entries: &[(LegendEntry, String)]) -> DrawResult {
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
            LegendEntry::Star => {
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

/// Draws a vertical colour bar for the data range `range` = [`min`, `max`] labelled `label`, with
/// tick labels and the exact minimum and maximum. A constant field gets no bar (a padded one
/// would show a range the data do not have) but one swatch with its value, said to be constant;
/// no range at all (no value to colour) gets the text `none`.
pub(super) fn draw_colorbar(
    area: &Area<'_>,
    label: &str,
    range: Option<(f64, f64)>,
    none: &str,
) -> DrawResult {
    let Some((min, max)) = range else {
        area.draw(&Text::new(
            none.to_owned(),
            (20, 40),
            text_style(14, BLACK, HPos::Left, VPos::Center),
        ))?;
        return Ok(());
    };
    if is_constant((min, max)) {
        return draw_constant(area, label, min);
    }
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

/// The colour of a constant field (the middle of the scale, as `scale_color` gives it) and its
/// value.
fn draw_constant(area: &Area<'_>, label: &str, value: f64) -> DrawResult {
    let (x, y) = (20, 40);
    area.draw(&Text::new(
        label.to_owned(),
        (x, y),
        text_style(15, BLACK, HPos::Left, VPos::Center),
    ))?;
    let swatch = [(x, y + 20), (x + 28, y + 48)];
    area.draw(&Rectangle::new(swatch, viridis(0.5).filled()))?;
    area.draw(&Rectangle::new(swatch, BLACK.stroke_width(1)))?;
    area.draw(&Text::new(
        format!("constant: {}", fmt_sig(value)),
        (x + 38, y + 34),
        text_style(14, BLACK, HPos::Left, VPos::Center),
    ))?;
    area.draw(&Text::new(
        "the same at every point",
        (x, y + 68),
        text_style(13, BLACK, HPos::Left, VPos::Center),
    ))?;
    Ok(())
}

/// The operating-point figure on `root`: titled `title`, split into the chart of the plane on the
/// left and the side column right of it, [`SIDE_WIDTH`] px wide, its upper three fifths for the
/// colour bar and the rest for the legend: (plot, bar, legend).
pub(super) fn plane_figure<'a>(
    root: &Area<'a>,
    title: &str,
) -> Result<(Area<'a>, Area<'a>, Area<'a>), DrawingAreaErrorKind<std::io::Error>> {
    let body = titled_figure(root, title)?;
    let (w, h) = body.dim_in_pixel();
    let (plot, side) = body.split_horizontally(w.saturating_sub(SIDE_WIDTH));
    let (bar, legend) = side.split_vertically(h * 3 / 5);
    Ok((plot, bar, legend))
}

/// The starred point (if any, in plot units) as a star on `chart`.
pub(super) fn draw_star(chart: &XyChart<'_, '_>, point: Option<(f64, f64)>) -> DrawResult {
    match point {
        Some(p) => chart.plotting_area().draw(&star_marker(p, 13.0)),
        None => Ok(()),
    }
}

/// The chart of the Ω–V0 plane over `x` × `y` (rpm, m/h) on `area`, captioned with the starred
/// `point` named `what` (see [`star_caption`]), with the operating-point plots' layout and the
/// `grid` of [`Layout`].
pub(super) fn plane_chart<'a, 'b>(
    area: &'a Area<'b>,
    what: &str,
    point: Option<(f64, f64)>,
    x: (f64, f64),
    y: (f64, f64),
    grid: Option<(f64, f64)>,
    kind: SetPointAxis,
) -> Result<XyChart<'a, 'b>, DrawingAreaErrorKind<std::io::Error>> {
    let layout = Layout {
        margin_right: 20,
        y_label_area: 75,
        grid,
    };
    let caption = star_caption(what, point, kind);
    let y_label = set_point_label(kind);
    xy_chart(
        area,
        Some((&caption, 17)),
        (OMEGA_LABEL, x),
        (y_label.as_str(), y),
        layout,
    )
}

/// Caption text "`what`: Ω = … rpm, V0 = … m/h" (or "WOB = … kN") for a starred point, or an
/// empty string.
pub(super) fn star_caption(what: &str, point: Option<(f64, f64)>, kind: SetPointAxis) -> String {
    point
        .filter(is_finite_point)
        .map(|(o, v)| {
            format!(
                "{what}: \u{3a9} = {} rpm, {} = {} {}",
                fmt_sig(o),
                kind.symbol(),
                fmt_sig(v),
                kind.unit()
            )
        })
        .unwrap_or_default()
}
