//! What the study plots share: figure sizes, fonts, axis labels and colours, the viridis scale,
//! the optimum's star, number formatting, and rendering an SVG in memory then writing it
//! atomically.

use super::SetPointAxis;
use std::f64::consts::PI;
use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::colors::colormaps::{ColorMap, ViridisRGB};
use plotters::style::text_anchor::{HPos, Pos, VPos};

use crate::report::atomic::write_atomic;
use crate::report::plots::PlotError;
pub(super) use crate::report::units::fmt_sig;

/// Image width of the operating-point plots, px.
pub(super) const WIDTH: u32 = 1100;
/// Image height of the operating-point plots, px.
pub(super) const HEIGHT: u32 = 800;
/// Width of the column right of the plot holding the colour bar and the legend, px.
pub(super) const SIDE_WIDTH: u32 = 240;
/// Height of the figure title strip, px (as in `plots`).
pub(super) const TITLE_HEIGHT: u32 = 40;
/// Height of one metric row in [`super::plot_metric_samples`], px.
pub(super) const METRIC_ROW_HEIGHT: u32 = 130;
/// Width of [`super::plot_metric_samples`] and [`super::plot_bit_speed_overlay`], px.
pub(super) const WIDE_WIDTH: u32 = 1000;
/// Number of colour steps in a colour bar.
pub(super) const COLORBAR_STEPS: usize = 64;
pub(super) use crate::report::axes::FONT;
pub(super) const OMEGA_LABEL: &str = "\u{3a9} [rpm]";
/// The label of the set-point axis: "V0 [m/h]", or "WOB [kN]" under a hook load.
pub(super) fn set_point_label(kind: SetPointAxis) -> String {
    format!("{} [{}]", kind.symbol(), kind.unit())
}

/// Points and cells without a value (failed, infeasible).
pub(super) const NO_VALUE: RGBColor = RGBColor(150, 150, 150);
/// The infeasible part of the box.
pub(super) const INFEASIBLE_FILL: RGBColor = RGBColor(225, 225, 225);
/// Cells without a value in a heat map.
pub(super) const NO_VALUE_CELL: RGBColor = RGBColor(205, 205, 205);
pub(super) const PATH_COLOR: RGBColor = RGBColor(200, 30, 45);
/// The optimum: red, which the viridis scale never shows.
pub(super) const STAR_FILL: RGBColor = RGBColor(235, 20, 60);
/// Distinct run colours (Tableau 10), cycled.
pub(super) const RUN_COLORS: [RGBColor; 10] = [
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

pub(super) type Area<'a> = DrawingArea<SVGBackend<'a>, Shift>;
/// A point (Ω [rpm], V0 [m/h]) or (x, y) in plot units.
pub(super) type Point = (f64, f64);
pub(super) type DrawResult = Result<(), DrawingAreaErrorKind<std::io::Error>>;

/// Renders a `size` SVG with `draw` in memory and writes it atomically to `out`.
pub(super) fn render_and_write(
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

/// Viridis at `s` ∈ [0, 1] (clamped; NaN gives the low end), from plotters' `ViridisRGB`.
pub(super) fn viridis(s: f64) -> RGBColor {
    // plotters clamps but turns NaN into an index it unwraps: sanitise first.
    let s = if s.is_nan() { 0.0 } else { s.clamp(0.0, 1.0) };
    ViridisRGB.get_color(s)
}

/// The colour of `value` on a scale over the data range [lo, hi]; a constant (lo = hi up to
/// round-off, see [`is_constant`]) maps to the middle of the scale.
pub(super) fn scale_color(value: f64, (lo, hi): (f64, f64)) -> RGBColor {
    if !is_constant((lo, hi)) {
        viridis((value - lo) / (hi - lo))
    } else {
        viridis(0.5)
    }
}

/// Whether [`min`, `max`] is a single value up to round-off (the test of `axis_range`).
pub(super) fn is_constant((min, max): (f64, f64)) -> bool {
    let span = max - min;
    span.is_nan() || span <= 1e-12 * min.abs().max(max.abs())
}

/// The smallest and largest of the finite `values`, or None without any.
pub(super) fn value_range(values: impl IntoIterator<Item = f64>) -> Option<(f64, f64)> {
    values
        .into_iter()
        .filter(|v| v.is_finite())
        .fold(None, |acc, v| match acc {
            None => Some((v, v)),
            Some((lo, hi)) => Some((f64::min(lo, v), f64::max(hi, v))),
        })
}

/// Vertices of a five-pointed star of outer radius `r` px centred on (0, 0), point up.
pub(super) fn star(r: f64) -> Vec<(i32, i32)> {
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
pub(super) fn star_marker<'a, DB: DrawingBackend + 'a, C: Clone + 'a>(
    at: C,
    r: f64,
) -> DynElement<'a, DB, C> {
    let vertices = star(r);
    let mut outline = vertices.clone();
    outline.push(vertices[0]);
    (EmptyElement::at(at)
        + Polygon::new(vertices, STAR_FILL.filled())
        + PathElement::new(outline, BLACK.stroke_width(1)))
    .into_dyn()
}

/// A text style of `size` px in `color`, anchored at `h`, `v`.
pub(super) fn text_style(size: u32, color: RGBColor, h: HPos, v: VPos) -> TextStyle<'static> {
    (FONT, size).into_font().color(&color).pos(Pos::new(h, v))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::report::study_plots::test_support::near;

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
        assert_eq!(scale_color(1.0, (1.0, 1.0 + 1e-15)), viridis(0.5));
        assert!(is_constant((0.0, 0.0)) && is_constant((5.0, 5.0 + 1e-14)));
        assert!(!is_constant((0.0, 1e-300)) && !is_constant((1.0, 1.0 + 1e-9)));
        assert_eq!(
            value_range([2.0, f64::NAN, -1.0, f64::INFINITY]),
            Some((-1.0, 2.0))
        );
        assert_eq!(value_range([f64::NAN]), None);
    }
}
