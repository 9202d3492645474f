//! The Monte Carlo samples of each metric at one operating point, one row per metric.

use std::path::Path;

use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, VPos};

use crate::report::plots::{PlotError, axis_range, tick_label};

use super::style::{
    Area, DrawResult, FONT, METRIC_ROW_HEIGHT, RUN_COLORS, TITLE_HEIGHT, WIDE_WIDTH, fmt_sig,
    render_and_write, text_style,
};

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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::report::study_plots::test_support::*;

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
}
