//! The bit angular velocity of several runs overlaid, in rpm.

use std::f64::consts::TAU;
use std::path::Path;

use plotters::prelude::*;

use crate::report::plots::{PLOT_BUCKETS, PlotError, axis_range, decimate_min_max, tick_label};
use crate::sim::TimeSeries;

use super::style::{Area, DrawResult, FONT, RUN_COLORS, WIDE_WIDTH, render_and_write};

/// Height of [`plot_bit_speed_overlay`], px.
const OVERLAY_HEIGHT: u32 = 520;
/// Title of [`plot_bit_speed_overlay`].
const OVERLAY_TITLE: &str = "Bit angular velocity \u{3b8}\u{307}x(L)";
/// rad/s → rpm.
const RPM_PER_RAD_S: f64 = 60.0 / TAU;

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
    use crate::report::study_plots::test_support::*;
    use crate::report::testdata::synthetic_series;

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
}
