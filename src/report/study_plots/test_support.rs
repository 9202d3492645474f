//! Reading the SVG text of the study plots in tests.

use std::path::Path;

use plotters::style::RGBColor;

use super::{ConstraintLine, EvaluatedPoint, Region};

pub(super) fn read(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap()
}

pub(super) fn assert_svg(svg: &str) {
    assert!(svg.starts_with("<svg"), "{}", &svg[..svg.len().min(200)]);
    assert!(svg.trim_end().ends_with("</svg>"));
}

/// The contents of every `<text>` element, trimmed.
pub(super) fn texts(svg: &str) -> Vec<&str> {
    svg.split("<text ")
        .skip(1)
        .map(|s| {
            let start = s.find('>').unwrap() + 1;
            s[start..start + s[start..].find("</text>").unwrap()].trim()
        })
        .collect()
}

pub(super) fn assert_contains(svg: &str, texts: &[&str]) {
    for text in texts {
        assert!(svg.contains(text), "missing {text:?}");
    }
}

/// Elements `<tag ...>` whose attributes contain `attr`.
pub(super) fn count_with(svg: &str, tag: &str, attr: &str) -> usize {
    svg.split(&format!("<{tag} "))
        .skip(1)
        .filter(|s| s[..s.find('>').unwrap()].contains(attr))
        .count()
}

pub(super) fn hex(c: RGBColor) -> String {
    format!("\"#{:02X}{:02X}{:02X}\"", c.0, c.1, c.2)
}

/// Within `tol` units per channel of the colour `hex` ("#rrggbb").
pub(super) fn near(c: RGBColor, hex: &str, tol: u8) -> bool {
    let channel = |k: usize| u8::from_str_radix(&hex[1 + 2 * k..3 + 2 * k], 16).unwrap();
    [c.0, c.1, c.2]
        .iter()
        .enumerate()
        .all(|(k, &v)| v.abs_diff(channel(k)) <= tol)
}

/// Ω ∈ [40, 160] rpm, V0 ∈ [5, 30] m/h; a torque limit cuts the upper right corner and a
/// minimum V0/Ω ratio the lower right.
pub(super) fn region() -> Region {
    Region {
        omega_rpm: [40.0, 160.0],
        set_point: [5.0, 30.0],
        kind: crate::model::SetPoint::Feed.into(),
        lines: vec![
            ConstraintLine {
                label: "torque limit".into(),
                omega_coef: 0.2,
                set_point_coef: 1.0,
                upper: 45.0,
            },
            ConstraintLine {
                label: "min V0/\u{3a9}".into(),
                omega_coef: 0.1,
                set_point_coef: -1.0,
                upper: 0.0,
            },
        ],
    }
}

pub(super) fn feasible(r: &Region, (o, v): (f64, f64)) -> bool {
    r.lines
        .iter()
        .all(|c| c.omega_coef * o + c.set_point_coef * v <= c.upper)
}

/// A 5 × 4 grid of evaluated points, two of which failed.
pub(super) fn evaluated(r: &Region) -> Vec<EvaluatedPoint> {
    let mut out = Vec::new();
    for j in 0..4 {
        for i in 0..5 {
            let (o, v) = (40.0 + 30.0 * i as f64, 5.0 + 25.0 / 3.0 * j as f64);
            let failed = (i, j) == (1, 2) || (i, j) == (3, 0);
            out.push(EvaluatedPoint {
                omega_rpm: o,
                set_point: v,
                score: (!failed)
                    .then(|| -((o - 110.0) / 50.0).powi(2) - ((v - 15.0) / 10.0).powi(2)),
                feasible: feasible(r, (o, v)),
            });
        }
    }
    out
}

pub(super) const PATH: [(f64, f64); 5] = [
    (60.0, 25.0),
    (90.0, 10.0),
    (130.0, 20.0),
    (105.0, 13.0),
    (110.0, 15.0),
];
