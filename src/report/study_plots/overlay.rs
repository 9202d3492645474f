//! The bit angular velocity of several runs overlaid, in rpm.

use std::path::Path;

use plotters::prelude::*;

use crate::report::axes::{
    PLOT_BUCKETS, TIME_LAYOUT, axis_range, decimate_min_max, draw_legend, draw_level,
    titled_figure, xy_chart,
};
use crate::report::plots::PlotError;
use crate::report::units::{RPM_PER_RAD_S, short};
use crate::sim::TimeSeries;

use super::style::{Area, DrawResult, RUN_COLORS, WIDE_WIDTH, render_and_write};

/// Height of [`plot_bit_speed_overlay`], px.
const OVERLAY_HEIGHT: u32 = 520;
/// Title of [`plot_bit_speed_overlay`].
const OVERLAY_TITLE: &str = "Bit angular velocity \u{3b8}\u{307}x(L)";

/// One run of [`plot_bit_speed_overlay`].
#[derive(Debug, Clone, Copy)]
pub struct OverlayRun<'a> {
    /// Legend text, e.g. "60 rpm, 5.0 m/h".
    pub label: &'a str,
    /// The run's history (SI: t in s, bit angular velocity in rad/s).
    pub series: &'a TimeSeries,
    /// The rotation speed Ω imposed at the top, rad/s.
    pub omega_rad_s: f64,
}

/// Draws the bit angular velocity θ̇x(L) in rpm against t in s of every run in its own colour,
/// with the run's imposed Ω as a dashed line of the same colour, and a legend. Each curve is
/// reduced by [`decimate_min_max`]; the y axis always includes 0 so stick phases show. A run
/// whose `bit_angular_velocity` does not match its `t` is an error.
pub fn plot_bit_speed_overlay(runs: &[OverlayRun<'_>], out: &Path) -> Result<(), PlotError> {
    if let Some(run) = runs
        .iter()
        .find(|r| r.series.bit_angular_velocity.len() != r.series.t.len())
    {
        return Err(PlotError::LengthMismatch {
            path: out.to_owned(),
            channel: format!("{}: bit_angular_velocity", run.label),
            len: run.series.bit_angular_velocity.len(),
            t_len: run.series.t.len(),
        });
    }
    let curves: Vec<Curve<'_>> = runs
        .iter()
        .map(|r| {
            let s = r.series;
            let mut points = decimate_min_max(&s.t, &s.bit_angular_velocity, PLOT_BUCKETS);
            points.iter_mut().for_each(|p| p.1 *= RPM_PER_RAD_S);
            let omega = r.omega_rad_s * RPM_PER_RAD_S;
            Curve {
                label: r.label,
                points,
                omega_rpm: omega.is_finite().then_some(omega),
            }
        })
        .collect();
    render_and_write(out, (WIDE_WIDTH, OVERLAY_HEIGHT), |root| {
        draw_overlay(root, &curves)
    })
}

/// A run as drawn: its decimated curve (t in s, rpm) and its Ω in rpm.
struct Curve<'a> {
    label: &'a str,
    points: Vec<(f64, f64)>,
    omega_rpm: Option<f64>,
}

fn draw_overlay(root: &Area<'_>, curves: &[Curve<'_>]) -> DrawResult {
    let body = titled_figure(root, OVERLAY_TITLE)?;
    let points = || curves.iter().flat_map(|c| c.points.iter());
    let (t_lo, t_hi) = axis_range(points().map(|p| p.0), 0.0);
    let omegas = || curves.iter().filter_map(|c| c.omega_rpm);
    let (y_lo, y_hi) = axis_range(points().map(|p| p.1).chain(omegas()).chain([0.0]), 0.05);
    let mut chart = xy_chart(
        &body,
        None,
        ("t [s]", (t_lo, t_hi)),
        ("\u{3b8}\u{307}x(L) [rpm]", (y_lo, y_hi)),
        TIME_LAYOUT,
    )?;
    for (k, c) in curves.iter().enumerate() {
        let color = RUN_COLORS[k % RUN_COLORS.len()];
        let style = color.stroke_width(1);
        chart
            .draw_series(LineSeries::new(c.points.iter().copied(), style))?
            .label(c.label)
            .legend(move |(x, y)| PathElement::new([(x, y), (x + 24, y)], style.stroke_width(2)));
        if let Some(omega) = c.omega_rpm {
            let dashed = color.stroke_width(2);
            draw_level(&mut chart, (t_lo, t_hi), omega, dashed)?
                .label(format!("\u{3a9} = {} rpm (imposed)", short(omega)))
                .legend(move |at| {
                    EmptyElement::at(at)
                        + PathElement::new([(0, 0), (9, 0)], dashed)
                        + PathElement::new([(15, 0), (24, 0)], dashed)
                });
        }
    }
    if !curves.is_empty() {
        draw_legend(&mut chart, SeriesLabelPosition::UpperRight)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::report::study_plots::test_support::*;
    use crate::report::testdata::{OP, synthetic_series};
    use std::f64::consts::TAU;

    fn run<'a>(label: &'a str, series: &'a TimeSeries, omega_rad_s: f64) -> OverlayRun<'a> {
        OverlayRun {
            label,
            series,
            omega_rad_s,
        }
    }

    #[test]
    fn bit_speed_overlay_draws_one_decimated_curve_per_run_in_rpm_and_its_omega() {
        let a = synthetic_series(20_000);
        let mut b = synthetic_series(5_000);
        b.bit_angular_velocity.iter_mut().for_each(|w| *w *= 0.5);
        let runs = [
            run("nominal", &a, OP.omega),
            run("half speed", &b, 0.5 * OP.omega),
        ];
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
                // 10 rad/s and 5 rad/s.
                "\u{3a9} = 95.49 rpm (imposed)",
                "\u{3a9} = 47.75 rpm (imposed)",
            ],
        );
        for (k, n) in [(0, 20_000), (1, 5_000)] {
            let color = format!("stroke={}", hex(RUN_COLORS[k]));
            let lines: Vec<&str> = svg
                .split("<polyline ")
                .skip(1)
                .filter(|s| s[..s.find("/>").unwrap()].contains(&color))
                .collect();
            // One decimated data curve per run in the run's colour.
            let curves: Vec<&&str> = lines.iter().filter(|s| s.len() > 1000).collect();
            assert_eq!(curves.len(), 1);
            let points = curves[0][..curves[0].find("/>").unwrap()]
                .split_whitespace()
                .count();
            assert!(points <= 2 * PLOT_BUCKETS + 8 && points < n, "{points}");
            // Its Ω: a dashed line of short two-point segments in the same colour, width 2.
            let dashes = lines
                .iter()
                .filter(|s| s.contains("stroke-width=\"2\"") && s.len() < 300)
                .count();
            assert!(dashes > 20, "{dashes} dashes");
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
        let err = plot_bit_speed_overlay(&[run("ok", &good, 1.0), run("bad", &bad, 1.0)], &out)
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
        let runs = [run("nan", &nan, f64::NAN), run("empty", &empty, 1.0)];
        plot_bit_speed_overlay(&runs, &out).unwrap();
        let svg = read(&out);
        assert_contains(&svg, &["nan", "empty", "\u{3a9} = 9.55 rpm (imposed)"]);
        assert!(!svg.contains("NaN rpm"));
    }
}
