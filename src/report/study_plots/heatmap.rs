//! A score or metric over a grid of operating points, as filled cells with a colour bar.

use std::path::Path;

use plotters::prelude::*;

use crate::report::axes::axis_range;
use crate::report::plots::PlotError;

use super::geometry::{cell_edges, is_finite_point};
use super::side::{LegendEntry, draw_colorbar, draw_legend, draw_star, plane_chart, plane_figure};
use super::style::{
    Area, DrawResult, HEIGHT, NO_VALUE_CELL, Point, WIDTH, render_and_write, scale_color,
    value_range,
};
use super::{SetPointAxis, StarredPoint};

/// Draws `values` over the grid of cell centres `omega_rpm` × `set_point` as filled cells
/// coloured by value, with a colour bar labelled `value_label` and its range; `None` (or
/// non-finite) cells are grey and hatched. `values[j * omega_rpm.len() + i]` belongs to
/// (Ω\[i\], V0\[j\]). Cell edges lie halfway between neighbouring nodes; the grid need not be
/// uniform. A field with one value everywhere gets that value, said to be constant, instead of
/// a colour bar. `star` is marked with a star, named in the legend and the caption by its
/// label (e.g. "best map node": say which point it is, an optimum or a grid node).
// The grid's two axes, its values, the star, the set-point kind and the file: one argument each
// (a struct would only rename them at the one call site in `cli::study_plots`).
#[allow(clippy::too_many_arguments)]
pub fn plot_heatmap(
    title: &str,
    value_label: &str,
    omega_rpm: &[f64],
    set_point: &[f64],
    values: &[Option<f64>],
    star: Option<&StarredPoint>,
    kind: SetPointAxis,
    out: &Path,
) -> Result<(), PlotError> {
    let expected = omega_rpm.len().checked_mul(set_point.len());
    if expected != Some(values.len()) {
        return Err(PlotError::GridMismatch {
            path: out.to_owned(),
            len: values.len(),
            n_omega: omega_rpm.len(),
            n_v0: set_point.len(),
        });
    }
    let grid = Grid {
        omega: omega_rpm,
        set_point,
        values,
        kind,
    };
    render_and_write(out, (WIDTH, HEIGHT), |root| {
        draw_heatmap(root, title, value_label, &grid, star)
    })
}

/// Node coordinates and row-major values of a heat map.
struct Grid<'a> {
    omega: &'a [f64],
    set_point: &'a [f64],
    values: &'a [Option<f64>],
    kind: SetPointAxis,
}

fn draw_heatmap(
    root: &Area<'_>,
    title: &str,
    value_label: &str,
    grid: &Grid<'_>,
    star: Option<&StarredPoint>,
) -> DrawResult {
    let (plot_area, bar_area, legend_area) = plane_figure(root, title)?;

    let x_edges = cell_edges(grid.omega);
    let y_edges = cell_edges(grid.set_point);
    let optimum = star
        .map(|s| (s.omega_rpm, s.set_point))
        .filter(is_finite_point);
    let star_label = star.map_or("", |s| s.label.as_str());
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

    let mut chart = plane_chart(
        &plot_area,
        star_label,
        optimum,
        (x_lo, x_hi),
        (y_lo, y_hi),
        None,
        grid.kind,
    )?;

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
    draw_star(&chart, optimum)?;

    let none = format!("{value_label}: no values");
    draw_colorbar(&bar_area, value_label, range, &none)?;
    let mut entries = Vec::new();
    if any_missing {
        entries.push((
            LegendEntry::NoValueCell,
            "no value (infeasible/failed)".into(),
        ));
    }
    if optimum.is_some() {
        entries.push((LegendEntry::Star, star_label.to_owned()));
    }
    draw_legend(&legend_area, &entries)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::report::study_plots::style::{
        COLORBAR_STEPS, OMEGA_LABEL, STAR_FILL, set_point_label, viridis,
    };
    use crate::report::study_plots::test_support::*;

    fn starred(omega_rpm: f64, set_point: f64) -> StarredPoint {
        StarredPoint {
            omega_rpm,
            set_point,
            label: "best map node".to_owned(),
        }
    }

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
            Some(&starred(70.0, 15.0)),
            crate::model::SetPoint::Feed.into(),
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
                &set_point_label(crate::model::SetPoint::Feed.into()),
                "max 4.000",
                "min -1.000",
                "no value (infeasible/failed)",
                "best map node: \u{3a9} = 70.00 rpm, V0 = 15.00 m/h",
            ],
        );
        assert!(!svg.contains("optimum") && !svg.contains("constant"));
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
            crate::model::SetPoint::Feed.into(),
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
    fn a_hook_loads_map_has_a_wob_axis() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("heat.svg");
        let star = StarredPoint {
            omega_rpm: 45.0,
            set_point: 58.3,
            label: "best map node".into(),
        };
        plot_heatmap(
            "Hook load",
            "score J",
            &[30.0, 60.0],
            &[40.0, 60.0, 80.0],
            &[Some(1.0), Some(2.0), Some(3.0), None, Some(0.5), Some(2.5)],
            Some(&star),
            crate::model::SetPoint::Wob.into(),
            &out,
        )
        .unwrap();
        let svg = read(&out);
        assert_contains(
            &svg,
            &[
                "WOB [kN]",
                "best map node: \u{3a9} = 45.00 rpm, WOB = 58.30 kN",
            ],
        );
        assert!(!svg.contains("V0"));
    }

    #[test]
    fn heatmap_with_empty_missing_or_degenerate_grids_still_plots() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("heat.svg");
        plot_heatmap(
            "Empty",
            "J",
            &[],
            &[],
            &[],
            None,
            crate::model::SetPoint::Feed.into(),
            &out,
        )
        .unwrap();
        let svg = read(&out);
        assert_svg(&svg);
        assert_contains(&svg, &["Empty", "J: no values"]);

        plot_heatmap(
            "All missing",
            "J",
            &[1.0, 2.0],
            &[3.0],
            &[None, None],
            Some(&starred(9.0, 9.0)),
            crate::model::SetPoint::Feed.into(),
            &out,
        )
        .unwrap();
        let svg = read(&out);
        assert_contains(&svg, &["All missing", "J: no values", "best map node"]);
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
            crate::model::SetPoint::Feed.into(),
            &out,
        )
        .unwrap();
        let svg = read(&out);
        assert_contains(&svg, &["One", "constant: 2.000"]);
        assert!(!svg.contains("no value"));
    }

    #[test]
    fn a_constant_field_shows_its_value_not_an_invented_range() {
        // Zero everywhere (no wall impacts at any node): once a −1…1 colour bar.
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("zero.svg");
        plot_heatmap(
            "Impacts",
            "wall impacts [1/s]",
            &[40.0, 80.0, 120.0],
            &[2.0, 20.0],
            &[Some(0.0), Some(0.0), None, Some(0.0), Some(0.0), Some(-0.0)],
            None,
            crate::model::SetPoint::Feed.into(),
            &out,
        )
        .unwrap();
        let svg = read(&out);
        let t = texts(&svg);
        for text in [
            "wall impacts [1/s]",
            "constant: 0",
            "the same at every point",
        ] {
            assert!(t.contains(&text), "{text:?} in {t:?}");
        }
        assert!(
            !t.iter()
                .any(|t| t.starts_with("max ") || t.starts_with("min "))
        );
        // No tick of a colour bar: the only numbers are the Ω and V0 ticks of the axes.
        assert!(!t.contains(&"-1.0") && !t.contains(&"-1"), "{t:?}");
        // Five cells in the middle colour, and the swatch.
        assert_eq!(
            count_with(&svg, "rect", &format!("fill={}", hex(viridis(0.5)))),
            5 + 1
        );
        // Nothing starred, nothing said about a star.
        assert!(!svg.contains("best") && !svg.contains("optimum"));
    }
}
