//! What the axes of every plot share: a long curve reduced to its extremes per time bucket
//! ([`decimate_min_max`]), the range of an axis padded around its data ([`axis_range`]), and
//! tick labels with just the digits their step needs ([`tick_label`]), the font, the titled
//! figure ([`titled_figure`]), the Cartesian chart with its frame, labelled axes and grid
//! ([`xy_chart`]), a dashed level line across it
//! ([`draw_level`]) and the legend box ([`draw_legend`]).

use plotters::chart::SeriesAnno;
use plotters::coord::CoordTranslate;
use plotters::coord::Shift;
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;

/// The font of every plot.
pub(super) const FONT: &str = "sans-serif";

/// A Cartesian chart of the SVG plots, in plot units on both axes.
pub(super) type XyChart<'a, 'b> =
    ChartContext<'a, SVGBackend<'b>, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

/// What drawing on an SVG area may fail with.
pub(super) type SvgError = DrawingAreaErrorKind<std::io::Error>;

/// The whole of `root` filled white with `title` across its top (26 px); returns the area below
/// the title, where the figure goes.
pub(super) fn titled_figure<'b>(
    root: &DrawingArea<SVGBackend<'b>, Shift>,
    title: &str,
) -> Result<DrawingArea<SVGBackend<'b>, Shift>, SvgError> {
    root.fill(&WHITE)?;
    root.titled(title, (FONT, 26))
}

/// How a kind of chart is laid out: the right margin and the width of the y tick labels (px), and
/// the grid as the opacities of its light and bold lines (`None`: no grid).
#[derive(Debug, Clone, Copy)]
pub(super) struct Layout {
    pub margin_right: u32,
    pub y_label_area: u32,
    pub grid: Option<(f64, f64)>,
}

/// Time histories: wide y tick labels, a faint grid.
pub(super) const TIME_LAYOUT: Layout = Layout {
    margin_right: 25,
    y_label_area: 85,
    grid: Some((0.05, 0.15)),
};

/// One axis of an [`xy_chart`]: its description (with unit) and its range.
pub(super) type Axis<'a> = (&'a str, (f64, f64));

/// A chart on `area` over `x` × `y`, laid out as `layout`, with the optional `caption` (text,
/// font size) above it, the frame, both axes described and ticked by [`tick_label`], and the
/// grid; ready for its series.
pub(super) fn xy_chart<'a, 'b>(
    area: &'a DrawingArea<SVGBackend<'b>, Shift>,
    caption: Option<(&str, u32)>,
    (x_desc, (x_lo, x_hi)): Axis<'_>,
    (y_desc, (y_lo, y_hi)): Axis<'_>,
    layout: Layout,
) -> Result<XyChart<'a, 'b>, SvgError> {
    let mut builder = ChartBuilder::on(area);
    if let Some((text, size)) = caption {
        builder.caption(text, (FONT, size));
    }
    let mut chart = builder
        .margin(10)
        .margin_right(layout.margin_right)
        .x_label_area_size(50)
        .y_label_area_size(layout.y_label_area)
        .build_cartesian_2d(x_lo..x_hi, y_lo..y_hi)?;
    let x_fmt = |v: &f64| tick_label(*v, x_lo, x_hi);
    let y_fmt = |v: &f64| tick_label(*v, y_lo, y_hi);
    let mut mesh = chart.configure_mesh();
    mesh.x_desc(x_desc)
        .y_desc(y_desc)
        .x_label_formatter(&x_fmt)
        .y_label_formatter(&y_fmt)
        .label_style((FONT, 15))
        .axis_desc_style((FONT, 17));
    match layout.grid {
        Some((light, bold)) => mesh
            .light_line_style(BLACK.mix(light))
            .bold_line_style(BLACK.mix(bold)),
        None => mesh.disable_mesh(),
    };
    mesh.draw()?;
    Ok(chart)
}

/// A dashed horizontal line at `value` across `x` (dashes of 10 px, gaps of 6 px), in `style`:
/// an imposed or limiting value. Label its annotation to give it a legend entry.
pub(super) fn draw_level<'c, 'a: 'c, 'b: 'c>(
    chart: &'c mut XyChart<'a, 'b>,
    (x_lo, x_hi): (f64, f64),
    value: f64,
    style: ShapeStyle,
) -> Result<&'c mut SeriesAnno<'a, SVGBackend<'b>>, SvgError> {
    chart.draw_series(DashedLineSeries::new(
        [(x_lo, value), (x_hi, value)],
        10,
        6,
        style,
    ))
}

/// The legend of every plot: a translucent white box with a grey border at `position`.
pub(super) fn draw_legend<'a, DB: DrawingBackend + 'a, CT: CoordTranslate>(
    chart: &mut ChartContext<'a, DB, CT>,
    position: SeriesLabelPosition,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    chart
        .configure_series_labels()
        .position(position)
        .label_font((FONT, 15))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK.mix(0.4))
        .draw()
}

/// Number of time buckets a curve is reduced to before plotting (≤ 2 points each).
pub const PLOT_BUCKETS: usize = 2000;

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
    // A span below a millionth of the values is round-off on a constant signal (a bit turning
    // steadily at 59.99999999950 rpm): drawn as a constant, not over ticks of 12 digits.
    if !span.is_finite() || span <= 1e-6 * magnitude {
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

#[cfg(test)]
mod tests {
    use super::*;

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
        // Round-off on a steady 60 rpm: padded as a constant (ticks of a few digits).
        let (lo, hi) = axis_range([59.9999999995, 60.0000000001], 0.05);
        assert!(lo < 57.1 && hi > 62.9, "{lo} {hi}");
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
}
