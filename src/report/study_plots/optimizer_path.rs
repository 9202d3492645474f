//! The optimizer's path through the feasible region: the box of operating points with its
//! infeasible part shaded, constraint lines, evaluated points coloured by score, the numbered
//! iterates and the optimum.

use std::path::Path;

use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, VPos};

use crate::report::axes::{XyChart, axis_range};
use crate::report::plots::PlotError;

use super::geometry::{clip_box_to_halfplane, clip_line_to_box, finite_bounds, is_finite_point};
use super::side::{LegendEntry, draw_colorbar, draw_legend, draw_star, plane_chart, plane_figure};
use super::style::{
    Area, DrawResult, HEIGHT, INFEASIBLE_FILL, NO_VALUE, PATH_COLOR, WIDTH, render_and_write,
    scale_color, text_style, value_range,
};
use super::{ConstraintLine, EvaluatedPoint, Region};

/// At most this many iterates of a path get a number; longer paths number every k-th.
const MAX_PATH_NUMBERS: usize = 20;
/// Constraint lines, cycled.
const LINE_COLORS: [RGBColor; 5] = [
    RGBColor(180, 60, 0),
    RGBColor(110, 40, 150),
    RGBColor(0, 110, 110),
    RGBColor(140, 90, 20),
    RGBColor(40, 70, 160),
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

fn draw_optimizer_path(
    root: &Area<'_>,
    region: &Region,
    evaluated: &[EvaluatedPoint],
    path: &[(f64, f64)],
    optimum: Option<(f64, f64)>,
    title: &str,
) -> DrawResult {
    let (plot_area, bar_area, legend_area) = plane_figure(root, title)?;

    let bx = finite_bounds(region.omega_rpm);
    let by = finite_bounds(region.set_point);
    let the_box = bx.zip(by);
    let points: Vec<&EvaluatedPoint> = evaluated
        .iter()
        .filter(|p| p.omega_rpm.is_finite() && p.set_point.is_finite())
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
            .chain(points.iter().map(|p| (p.omega_rpm, p.set_point)))
            .chain(path_points.iter().map(|p| p.1))
            .chain(optimum)
    };
    let (x_lo, x_hi) = axis_range(all().map(|p| p.0), 0.04);
    let (y_lo, y_hi) = axis_range(all().map(|p| p.1), 0.04);

    let mut chart = plane_chart(
        &plot_area,
        "optimum",
        optimum,
        (x_lo, x_hi),
        (y_lo, y_hi),
        Some((0.04, 0.12)),
        region.kind,
    )?;

    let lines: Vec<&ConstraintLine> = region
        .lines
        .iter()
        .filter(|c| c.omega_coef.is_finite() && c.set_point_coef.is_finite() && c.upper.is_finite())
        .collect();
    let mut any_infeasible = false;
    if let Some((bx, by)) = the_box {
        let shaded: Vec<Vec<(f64, f64)>> = lines
            .iter()
            .filter_map(|c| {
                clip_box_to_halfplane(bx, by, (c.omega_coef, c.set_point_coef, c.upper))
            })
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
            (c.omega_coef, c.set_point_coef, c.upper),
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
            .map(|p| Cross::new((p.omega_rpm, p.set_point), 5, NO_VALUE.stroke_width(2))),
    )?;
    if let Some(range) = range {
        for p in points.iter().filter(|p| scored(p).is_some()) {
            let s = scored(p).unwrap_or(range.0);
            let at = (p.omega_rpm, p.set_point);
            chart.draw_series([
                Circle::new(at, 6, scale_color(s, range).filled()),
                Circle::new(at, 6, BLACK.mix(0.7).stroke_width(1)),
            ])?;
        }
    }

    draw_path(&mut chart, &path_points)?;
    draw_star(&chart, optimum)?;

    draw_colorbar(
        &bar_area,
        "score (higher is better)",
        range,
        "no scored points",
    )?;
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
        entries.push((LegendEntry::Star, "optimum".into()));
    }
    if any_infeasible {
        entries.push((LegendEntry::Infeasible, "infeasible (constraints)".into()));
    }
    draw_legend(&legend_area, &entries)
}

/// The iterate path: a line with an arrowhead mid-segment, a dot and a number per iterate
/// (every k-th when there are many). `points` are (original index, point).
fn draw_path(chart: &mut XyChart<'_, '_>, points: &[(usize, (f64, f64))]) -> DrawResult {
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::report::study_plots::style::{OMEGA_LABEL, STAR_FILL, set_point_label, viridis};
    use crate::report::study_plots::test_support::*;

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
                &set_point_label(crate::model::SetPoint::Feed.into()),
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
            set_point: [5.0, 30.0],
            kind: crate::model::SetPoint::Feed.into(),
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
            set_point: 1.0,
            score: Some(1.0),
            feasible: true,
        };
        let nan_score = EvaluatedPoint {
            omega_rpm: 50.0,
            set_point: 10.0,
            score: Some(f64::NAN),
            feasible: true,
        };
        let mut r = region();
        r.lines.push(ConstraintLine {
            label: "broken".into(),
            omega_coef: f64::NAN,
            set_point_coef: 1.0,
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
            set_point: [10.0, 20.0],
            kind: crate::model::SetPoint::Feed.into(),
            lines: vec![ConstraintLine {
                label: "impossible".into(),
                omega_coef: 0.0,
                set_point_coef: 0.0,
                upper: -1.0,
            }],
        };
        let p = EvaluatedPoint {
            omega_rpm: 100.0,
            set_point: 12.0,
            score: Some(3.0),
            feasible: true,
        };
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("one.svg");
        plot_optimizer_path(&r, &[p], &[(100.0, 12.0)], Some((100.0, 12.0)), "One", &out).unwrap();
        let svg = read(&out);
        assert_contains(&svg, &["One", "constant: 3.000"]);
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
}
