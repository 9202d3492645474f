//! The Monte Carlo samples of each metric at one operating point, one row per metric.

use std::path::Path;

use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, VPos};

use crate::report::axes::{axis_range, tick_label, titled_figure};
use crate::report::plots::PlotError;

use super::style::{
    Area, DrawResult, FONT, METRIC_ROW_HEIGHT, RUN_COLORS, TITLE_HEIGHT, WIDE_WIDTH, fmt_sig,
    render_and_write, text_style,
};

/// One metric's row of [`plot_metric_samples`]: its samples and the values marked on its axis.
#[derive(Debug, Clone, PartialEq)]
pub struct MetricRow {
    /// Name and unit, e.g. "mean WOB \[kN\]".
    pub label: String,
    /// One value per Monte Carlo sample, in the unit of `label`.
    pub samples: Vec<f64>,
    /// Values marked across the axis (statistics, limits), in the unit of `label`.
    pub marks: Vec<Mark>,
}

impl MetricRow {
    /// A row marked with its sample mean (of the finite samples; no mark without any).
    pub fn with_mean(label: String, samples: Vec<f64>) -> Self {
        let finite: Vec<f64> = samples.iter().copied().filter(|v| v.is_finite()).collect();
        let marks = (!finite.is_empty())
            .then(|| Mark {
                name: "mean".to_owned(),
                value: finite.iter().sum::<f64>() / finite.len() as f64,
                kind: MarkKind::Statistic,
                note: String::new(),
            })
            .into_iter()
            .collect();
        MetricRow {
            label,
            samples,
            marks,
        }
    }
}

/// A value marked across a metric's axis.
#[derive(Debug, Clone, PartialEq)]
pub struct Mark {
    /// What the value is, e.g. "CVaR 90 % (objective)" or "chance limit".
    pub name: String,
    /// The value, in the unit of the row.
    pub value: f64,
    /// How it is drawn.
    pub kind: MarkKind,
    /// Said after the value in the caption, e.g. "P(above) = 20 %, at most 10 % allowed"; may
    /// be empty.
    pub note: String,
}

/// How a [`Mark`] is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MarkKind {
    /// A statistic of the samples (mean, CVaR, quantile…): a solid red line.
    Statistic,
    /// A limit the samples are held to (a chance constraint's threshold): a dashed black line.
    Limit,
}

impl MarkKind {
    fn line(self) -> &'static str {
        match self {
            MarkKind::Statistic => "red",
            MarkKind::Limit => "dashed",
        }
    }
}

/// Draws one row per metric: every Monte Carlo sample as a dot on the metric's own value axis
/// and every mark across it (statistics solid red, limits dashed black), with the marks' values
/// and the sample count in the caption. Non-finite samples are left out and counted; a mark
/// with a non-finite value is named in the caption but not drawn.
pub fn plot_metric_samples(title: &str, rows: &[MetricRow], out: &Path) -> Result<(), PlotError> {
    let n = u32::try_from(rows.len().max(1)).unwrap_or(u32::MAX);
    let height = TITLE_HEIGHT.saturating_add(METRIC_ROW_HEIGHT.saturating_mul(n));
    render_and_write(out, (WIDE_WIDTH, height), |root| {
        draw_metric_samples(root, title, rows)
    })
}

fn draw_metric_samples(root: &Area<'_>, title: &str, rows: &[MetricRow]) -> DrawResult {
    let body = titled_figure(root, title)?;
    if rows.is_empty() {
        body.draw(&Text::new(
            "no metrics",
            (40, 40),
            text_style(16, BLACK, HPos::Left, VPos::Center),
        ))?;
        return Ok(());
    }
    for (area, row) in body.split_evenly((rows.len(), 1)).iter().zip(rows) {
        draw_metric_row(area, row)?;
    }
    Ok(())
}

/// The caption of a row: its label, each mark with its value, the sample count.
fn row_caption(row: &MetricRow, finite: usize, skipped: usize) -> String {
    let mut parts: Vec<String> = row
        .marks
        .iter()
        .map(|m| {
            let note = if m.note.is_empty() {
                String::new()
            } else {
                format!(", {}", m.note)
            };
            format!(
                "{} = {} ({}){note}",
                m.name,
                fmt_sig(m.value),
                m.kind.line()
            )
        })
        .collect();
    parts.push(match finite {
        0 => "no finite samples".to_owned(),
        1 => "1 sample".to_owned(),
        n => format!("{n} samples"),
    });
    let mut caption = format!("{}: {}", row.label, parts.join("; "));
    if skipped > 0 {
        caption.push_str(&format!(", {skipped} non-finite left out"));
    }
    caption
}

/// One metric: samples as dots at a deterministic vertical jitter, marks as vertical lines.
fn draw_metric_row(area: &Area<'_>, row: &MetricRow) -> DrawResult {
    let finite: Vec<f64> = row
        .samples
        .iter()
        .copied()
        .filter(|v| v.is_finite())
        .collect();
    let caption = row_caption(row, finite.len(), row.samples.len() - finite.len());
    let marks: Vec<&Mark> = row.marks.iter().filter(|m| m.value.is_finite()).collect();
    let (lo, hi) = axis_range(
        finite.iter().copied().chain(marks.iter().map(|m| m.value)),
        0.05,
    );
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
    for m in marks {
        let ends = [(m.value, 0.02), (m.value, 0.98)];
        match m.kind {
            MarkKind::Statistic => {
                chart.draw_series(std::iter::once(PathElement::new(ends, RED.stroke_width(2))))?;
            }
            MarkKind::Limit => {
                chart.draw_series(DashedLineSeries::new(ends, 6, 4, BLACK.stroke_width(2)))?;
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::report::study_plots::test_support::*;

    #[test]
    fn metric_samples_show_every_finite_sample_and_the_mean() {
        let rows = vec![
            MetricRow::with_mean("ROP [m/h]".to_owned(), vec![10.0, 12.0, 11.0, 13.0, 14.0]),
            MetricRow::with_mean("stick-slip severity".to_owned(), vec![0.25]),
            MetricRow::with_mean("impacts [1/s]".to_owned(), vec![1.0, f64::NAN, 3.0]),
            MetricRow::with_mean("torque [kN m]".to_owned(), vec![f64::INFINITY]),
        ];
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("metrics.svg");
        plot_metric_samples("Metrics at the optimum", &rows, &out).unwrap();
        let svg = read(&out);
        assert_svg(&svg);
        assert_contains(
            &svg,
            &[
                "Metrics at the optimum",
                "ROP [m/h]: mean = 12.00 (red); 5 samples",
                "stick-slip severity: mean = 0.2500 (red); 1 sample",
                "impacts [1/s]: mean = 2.000 (red); 2 samples, 1 non-finite left out",
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
    fn the_objective_statistic_and_limits_are_drawn_not_the_mean() {
        // Ten samples with a heavy tail: mean 1.45, CVaR 0.9 = 6 (the worst one), limit 4.
        let samples = vec![1.0, 1.0, 0.5, 1.0, 0.5, 0.5, 1.0, 0.5, 2.5, 6.0];
        let row = MetricRow {
            label: "stick-slip severity".to_owned(),
            samples,
            marks: vec![
                Mark {
                    name: "CVaR 90 % (objective)".to_owned(),
                    value: 6.0,
                    kind: MarkKind::Statistic,
                    note: String::new(),
                },
                Mark {
                    name: "chance limit".to_owned(),
                    value: 4.0,
                    kind: MarkKind::Limit,
                    note: "P(above) = 10 %, at most 5 % allowed: violated".to_owned(),
                },
                Mark {
                    name: "not finite".to_owned(),
                    value: f64::NAN,
                    kind: MarkKind::Limit,
                    note: String::new(),
                },
            ],
        };
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("metrics.svg");
        plot_metric_samples("At the optimum", &[row], &out).unwrap();
        let svg = read(&out);
        assert_contains(
            &svg,
            &[
                "stick-slip severity: CVaR 90 % (objective) = 6.000 (red); chance limit = 4.000 \
               (dashed), P(above) = 10 %, at most 5 % allowed: violated; not finite = NaN \
               (dashed); 10 samples",
            ],
        );
        assert!(!svg.contains("mean"));
        // One solid red line at the CVaR, the dashed limit as many short black segments.
        assert_eq!(count_with(&svg, "polyline", "stroke=\"#FF0000\""), 1);
        assert!(count_with(&svg, "polyline", "stroke=\"#000000\" stroke-width=\"2\"") > 5);
    }

    #[test]
    fn plots_are_written_whole_and_replace_the_old_file() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("new/dir/metrics.svg");
        let metrics = vec![MetricRow::with_mean("m".to_owned(), vec![1.0, 2.0])];
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
