//! The stress envelope of a run along the string ([`StressEnvelope`]): `stress_envelope.csv`, one
//! row per element midpoint (SI units, the unit at the end of each column name), and
//! `stress_envelope.svg`, its curves against x in the units a driller reads (MPa, kN, 1/h).

use std::io;
use std::path::Path;

use crate::model::OperatingPoint;
use crate::sim::StressEnvelope;

use super::atomic::write_atomic;
use super::plots::{Panel, PlotError, plot_panels_over};
use super::units::operating_point_text;
use crate::units::{Shown, UnitSystem};

/// The columns of `stress_envelope.csv`: name and values.
fn columns(e: &StressEnvelope) -> [(&'static str, &[f64]); 9] {
    [
        ("x_m", &e.position_m),
        ("max_von_mises_Pa", &e.max_von_mises_pa),
        ("mean_von_mises_Pa", &e.mean_von_mises_pa),
        ("max_compression_N", &e.max_compression_n),
        ("max_tension_N", &e.max_tension_n),
        ("max_torque_N_m", &e.max_torque_nm),
        ("max_bending_moment_N_m", &e.max_bending_moment_nm),
        ("fatigue_damage_per_h", &e.fatigue_damage_per_h),
        ("buckling_utilization", &e.buckling_utilization),
    ]
}

/// `stress_envelope.csv` as text: a header, then one row per element, top drive to bit. Reals in
/// their shortest round-trip form (as the time series CSV); NaN (not tracked) as `NaN`.
///
/// A string of sections has a last column `section`, the element's section by name (quoted as
/// RFC 4180 says when it holds a comma or a quote).
pub fn envelope_csv(e: &StressEnvelope) -> String {
    let cols = columns(e);
    let mut out = cols.map(|c| c.0).join(",");
    let sections = !e.sections.is_empty();
    if sections {
        out.push_str(",section");
    }
    out.push('\n');
    for i in 0..e.position_m.len() {
        for (k, (_, values)) in cols.iter().enumerate() {
            if k > 0 {
                out.push(',');
            }
            if let Some(&v) = values.get(i) {
                out.push_str(zmij::Buffer::new().format(v));
            }
        }
        if sections {
            out.push(',');
            let name = e.section_of(i).unwrap_or("");
            if name.contains([',', '"', '\n']) {
                out.push('"');
                out.push_str(&name.replace('"', "\"\""));
                out.push('"');
            } else {
                out.push_str(name);
            }
        }
        out.push('\n');
    }
    out
}

/// Writes [`envelope_csv`] to `path` (atomically).
pub fn write_envelope_csv(path: &Path, e: &StressEnvelope) -> io::Result<()> {
    write_atomic(path, envelope_csv(e).as_bytes())
}

/// `stress_envelope.svg`: the largest and the mean von Mises stress [MPa or psi], the largest
/// compression [kN or klbf] with the sinusoidal buckling load dashed, the largest torque
/// [kN·m or kft·lbf] (the torque-and-drag check: the TOB at the bit plus the wall's friction
/// above) and the fatigue damage rate [1/h], against x [m or ft], for a run at `op`, in `units`.
pub fn plot_stress_envelope(
    e: &StressEnvelope,
    op: &OperatingPoint,
    units: UnitSystem,
    path: &Path,
) -> Result<(), PlotError> {
    let (stress_unit, stress) = units.unit_and_factor(Shown::Stress);
    let (force_unit, force) = units.unit_and_factor(Shown::Force);
    let (torque_unit, torque) = units.unit_and_factor(Shown::Torque);
    let (at_unit, at) = units.unit_and_factor(Shown::Position);
    // A string of sections: each section's own sinusoidal buckling load, a step along the
    // string; one section: one load, a level line.
    let loads = e.sinusoidal_buckling_n();
    let per_section_buckling = (!e.sections.is_empty() && !loads.is_empty()).then_some((
        loads.as_slice(),
        "sinusoidal buckling load of each section (Dawson & Paslay; a section's above the axis is off it)",
    ));
    let buckling = e.buckling.map(|b| {
        (
            b.sinusoidal * force,
            format!(
                "sinusoidal buckling load {:.1} {force_unit} (Dawson & Paslay)",
                b.sinusoidal * force
            ),
        )
    });
    let curve = e.sn_curve.as_ref().map_or("", |c| c.name);
    let fatigue_caption = format!("Fatigue damage rate of the worst fibre (Miner, {curve})");
    // A string of sections says where each is, under the first panel.
    let spans: Vec<String> = (e.sections.iter())
        .map(|s| {
            format!(
                "{} {:.0}-{:.0} {at_unit}",
                s.name,
                at * s.from_m,
                at * s.to_m
            )
        })
        .collect();
    let stress_caption = if spans.is_empty() {
        "Largest von Mises stress at the outer fibre".to_string()
    } else {
        format!(
            "Largest von Mises stress at the outer fibre; sections: {}",
            spans.join(", ")
        )
    };
    // The abscissa in its unit (metric: the positions themselves); the boundaries between
    // sections marked in every panel.
    let x: Vec<f64> = e.position_m.iter().map(|x| at * x).collect();
    let marks: Vec<f64> = e.sections.iter().skip(1).map(|s| at * s.from_m).collect();
    plot_panels_over(
        path,
        &format!(
            "Stresses along the string, {}",
            operating_point_text(op, units)
        ),
        &x,
        &format!("x from the top drive [{at_unit}]"),
        &[
            Panel {
                caption: &stress_caption,
                y_label: &format!("max \u{3c3}_vM [{stress_unit}]"),
                y: &e.max_von_mises_pa,
                scale: stress,
                reference: None,
                reference_curve: None,
            },
            Panel {
                caption: "Time mean of the von Mises stress",
                y_label: &format!("mean \u{3c3}_vM [{stress_unit}]"),
                y: &e.mean_von_mises_pa,
                scale: stress,
                reference: None,
                reference_curve: None,
            },
            Panel {
                caption: "Largest compression",
                y_label: &format!("compression [{force_unit}]"),
                y: &e.max_compression_n,
                scale: force,
                reference: buckling.as_ref().map(|(v, l)| (*v, l.as_str())),
                reference_curve: per_section_buckling,
            },
            Panel {
                caption: "Largest torque (the TOB at the bit plus the wall's friction torque above)",
                y_label: &format!("torque [{torque_unit}]"),
                y: &e.max_torque_nm,
                scale: torque,
                reference: None,
                reference_curve: None,
            },
            Panel {
                caption: &fatigue_caption,
                y_label: "damage [1/h]",
                y: &e.fatigue_damage_per_h,
                scale: 1.0,
                reference: None,
                reference_curve: None,
            },
        ],
        &marks,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_string_of_sections_names_each_element_s_section() {
        let p = crate::problem::Problem::load(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/problems/bha_example.toml"
        ))
        .unwrap();
        let layout = crate::fem::ElementLayout::of(&p.model, p.mesh.elements);
        let e = StressEnvelope::for_string(&p.model, &layout, 0.0);
        let csv = envelope_csv(&e);
        let lines: Vec<&str> = csv.lines().collect();
        assert!(lines[0].ends_with(",section"), "{}", lines[0]);
        assert_eq!(lines.len(), 1 + p.mesh.elements);
        // The file's graded mesh: 27 elements of drill pipe, then 25 of heavy-weight pipe.
        assert!(lines[27].ends_with(",drill pipe"), "{}", lines[27]);
        assert!(lines[28].ends_with(",heavy-weight pipe"), "{}", lines[28]);
        assert!(lines[98].ends_with(",near-bit collar"), "{}", lines[98]);
        assert_eq!(e.sections.len(), 5);
        assert_eq!((e.sections[1].from_m, e.sections[1].to_m), (270.0, 370.0));
        // One section: no such column.
        let one = StressEnvelope::new(3, 2.0, 0.0);
        assert!(!envelope_csv(&one).contains("section"));
    }

    #[test]
    fn a_string_of_sections_is_plotted_against_each_section_s_own_buckling_load() {
        let p = crate::problem::Problem::load(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/problems/bha_example.toml"
        ))
        .unwrap();
        let layout = crate::fem::ElementLayout::of(&p.model, p.mesh.elements);
        let e = StressEnvelope::for_string(&p.model, &layout, 0.0);
        let loads = e.sinusoidal_buckling_n();
        assert_eq!(loads.len(), p.mesh.elements);
        // Dawson & Paslay by hand, F = 2 √(E I w / r), w the buoyed weight per metre (steel
        // 7900, mud 1200 kg/m³ inside and out), r = R_bh − R_ext: the heavy-weight pipe's
        // (element 27 on; 5.5 x 3.375 in) and the collars' (element 52 on; 6.75 x 2.8125 in).
        let by_hand = |od_in: f64, id_in: f64| {
            let (ro, ri) = (0.0254 * od_in / 2.0, 0.0254 * id_in / 2.0);
            let pi = std::f64::consts::PI;
            let (a, ai, ao) = (pi * (ro * ro - ri * ri), pi * ri * ri, pi * ro * ro);
            let w = (7900.0 * a + 1200.0 * ai - 1200.0 * ao) * 9.81;
            let i = pi / 4.0 * (ro.powi(4) - ri.powi(4));
            2.0 * (203e9 * i * w / (0.108 - ro)).sqrt()
        };
        for (e_index, od, id) in [(27, 5.5, 3.375), (60, 6.75, 2.8125)] {
            let want = by_hand(od, id);
            assert!(
                (loads[e_index] / want - 1.0).abs() < 1e-9,
                "element {e_index}: {} N against {want} N",
                loads[e_index]
            );
        }
        assert!(
            loads[27] < loads[60],
            "the collars buckle later than the HWDP"
        );
        let dir = tempfile::tempdir().unwrap();
        let op = OperatingPoint {
            omega: 6.0,
            v0: 1e-3,
            wob: 0.0,
        };
        let path = dir.path().join("e.svg");
        plot_stress_envelope(&e, &op, UnitSystem::Metric, &path).unwrap();
        let svg = std::fs::read_to_string(&path).unwrap();
        assert!(svg.contains("sinusoidal buckling load of each section"));
        // The axis holds the weakest section's load, not the stabiliser's meganewtons (which
        // would flatten the pipe's compression against the axis).
        let highest = loads.iter().copied().fold(0.0, f64::max);
        let weakest = loads.iter().copied().fold(f64::INFINITY, f64::min);
        assert!(highest > 5.0 * weakest, "{highest} vs {weakest}");
        let ticks: Vec<f64> = (svg.split('>'))
            .filter_map(|t| t.split('<').next()?.trim().parse::<f64>().ok())
            .collect();
        assert!(
            ticks.iter().all(|&v| v < 0.5 * highest / 1e3),
            "a tick near the stabiliser's {} kN: {ticks:?}",
            highest / 1e3
        );
        assert!(ticks.iter().any(|&v| v >= 0.5 * weakest / 1e3), "{ticks:?}");
        // The boundaries, dashed in each of the four panels: more dashed lines than without.
        let one = StressEnvelope::for_string(&p.model, &layout, 0.0);
        let mut plain = one.clone();
        plain.sections.clear();
        let plain_path = dir.path().join("plain.svg");
        plot_stress_envelope(&plain, &op, UnitSystem::Metric, &plain_path).unwrap();
        let plain_svg = std::fs::read_to_string(&plain_path).unwrap();
        assert!(!plain_svg.contains("of each section"));
        let lines = |s: &str| s.matches("<polyline").count() + s.matches("<line").count();
        assert!(
            lines(&svg) > lines(&plain_svg) + 4 * 4,
            "{} vs {}",
            lines(&svg),
            lines(&plain_svg)
        );
    }

    #[test]
    fn the_csv_has_one_row_per_element_and_reads_back() {
        let mut e = StressEnvelope::new(3, 2.0, 0.0);
        e.max_von_mises_pa = vec![1e8, 2.5e8, 3e8];
        e.fatigue_damage_per_h = vec![0.0, 1.5e-7, 0.0];
        let csv = envelope_csv(&e);
        let lines: Vec<&str> = csv.lines().collect();
        assert_eq!(lines.len(), 4);
        assert!(lines[0].starts_with("x_m,max_von_mises_Pa,"));
        let row: Vec<f64> = lines[2].split(',').map(|v| v.parse().unwrap()).collect();
        assert_eq!((row[0], row[1], row[7]), (3.0, 2.5e8, 1.5e-7));
        assert!(row[8].is_nan(), "no buckling loads: NaN");
        let dir = tempfile::tempdir().unwrap();
        let op = OperatingPoint {
            omega: 6.0,
            v0: 1e-3,
            wob: 0.0,
        };
        plot_stress_envelope(&e, &op, UnitSystem::Metric, &dir.path().join("e.svg")).unwrap();
        let svg = std::fs::read_to_string(dir.path().join("e.svg")).unwrap();
        assert!(svg.contains("x from the top drive [m]") && svg.contains("damage [1/h]"));
        assert!(svg.contains("max \u{3c3}_vM [MPa]") && svg.contains("compression [kN]"));
        // In field units: feet along the string, psi and klbf; 300 MPa = 43 511 psi at the top.
        plot_stress_envelope(&e, &op, UnitSystem::Field, &dir.path().join("f.svg")).unwrap();
        let svg = std::fs::read_to_string(dir.path().join("f.svg")).unwrap();
        for text in [
            "x from the top drive [ft]",
            "max \u{3c3}_vM [psi]",
            "compression [klbf]",
            "V0 = 11.81 ft/h",
        ] {
            assert!(svg.contains(text), "missing {text:?}");
        }
        assert!(!svg.contains("MPa") && !svg.contains("[m]"));
    }
}
