//! The units a driller reads, for plots: the terminal's units (rpm, m/h, kN, kN·m, MPa, %)
//! instead of the SI of the result files (rad/s, m/s, N, N·m, Pa, fractions), and a human name
//! for every decision metric key of `summary.json` (`mean_wob_n` → "mean WOB [kN]").

use std::f64::consts::TAU;

use crate::model::OperatingPoint;
use crate::units::UnitSystem;

pub use crate::units::{M_PER_H_PER_M_PER_S, RPM_PER_RAD_S};
/// rad → revolutions.
pub const REV_PER_RAD: f64 = 1.0 / TAU;

/// How a metric is shown: its name, its display unit and the factor from its value (as
/// `summary.json` holds it: SI but for the keys that name another unit, e.g. m/h).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MetricDisplay<'a> {
    /// Human name, e.g. "mean WOB".
    pub name: &'a str,
    /// Display unit, e.g. "kN"; empty for a dimensionless number.
    pub unit: &'static str,
    /// Display value = `scale` × value (e.g. 1e-3 for N → kN).
    pub scale: f64,
}

impl<'a> MetricDisplay<'a> {
    /// The display of the metric `key` (a key of `summary.json`, its row of the metric
    /// catalogue); an unknown key is shown as itself, unscaled and without unit.
    pub fn of(key: &'a str) -> Self {
        match crate::metrics::catalogue::find(key) {
            Some(s) => MetricDisplay {
                name: s.name,
                unit: s.display_unit,
                scale: s.display_scale,
            },
            None => MetricDisplay {
                name: key,
                unit: "",
                scale: 1.0,
            },
        }
    }

    /// The same display in `units`: a metric in a unit of the metric system (kN, m/h, MPa, …)
    /// shown in that system's unit (klbf, ft/h, psi, …); the rest as it is.
    pub fn in_system(self, units: UnitSystem) -> Self {
        let (unit, factor) = units.convert_metric(self.unit);
        MetricDisplay {
            unit,
            scale: factor * self.scale,
            ..self
        }
    }

    /// The display of the metric `key` in `units` ([`Self::of`], then [`Self::in_system`]).
    pub fn of_in(key: &'a str, units: UnitSystem) -> Self {
        Self::of(key).in_system(units)
    }

    /// "name [unit]", or the name alone for a dimensionless metric.
    pub fn label(&self) -> String {
        if self.unit.is_empty() {
            self.name.to_owned()
        } else {
            format!("{} [{}]", self.name, self.unit)
        }
    }

    /// `si` in the display unit.
    pub fn value(&self, si: f64) -> f64 {
        self.scale * si
    }
}

/// "Ω = 60 rpm, V0 = 5 m/h" (a hook load's "Ω = 60 rpm, WOB = 50 kN"; in field units "V0 =
/// 16.4 ft/h", "WOB = 11.24 klbf") for an operating point given in SI (rad/s, m/s, N), with at
/// most two decimals and no trailing zeros.
pub fn operating_point_text(op: &OperatingPoint, units: UnitSystem) -> String {
    let kind = op.kind();
    let (unit, value) = units.from_metric(kind.unit(), op.shown_set_point());
    format!(
        "\u{3a9} = {} rpm, {} = {} {unit}",
        short(op.omega * RPM_PER_RAD_S),
        kind.symbol(),
        short(value),
    )
}

/// `v` with about 4 significant digits, exponent form when very large or small.
pub fn fmt_sig(v: f64) -> String {
    if v == 0.0 {
        return "0".to_owned();
    }
    if !v.is_finite() {
        return format!("{v}");
    }
    let decade = v.abs().log10().floor() as i32;
    if !(-3..5).contains(&decade) {
        format!("{v:.3e}")
    } else {
        let decimals = (3 - decade).clamp(0, 6) as usize;
        format!("{v:.decimals$}")
    }
}

/// `v` with at most two decimals, trailing zeros (and a bare point) removed; no "-0".
pub fn short(v: f64) -> String {
    let text = format!("{v:.2}");
    let text = if text.contains('.') {
        text.trim_end_matches('0').trim_end_matches('.')
    } else {
        &text
    };
    if text == "-0" { "0" } else { text }.to_owned()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn metrics_are_shown_in_driller_units_with_human_names() {
        let wob = MetricDisplay::of("mean_wob_n");
        assert_eq!(wob.label(), "mean WOB [kN]");
        assert!((wob.value(55_300.0) - 55.3).abs() < 1e-12);
        assert_eq!(
            MetricDisplay::of("mean_tob_nm").label(),
            "mean TOB [kN\u{b7}m]"
        );
        let mse = MetricDisplay::of("mse_pa");
        assert_eq!(mse.label(), "mechanical specific energy [MPa]");
        assert!((mse.value(7.37e8) - 737.0).abs() < 1e-9);
        assert_eq!(MetricDisplay::of("mean_rop_m_s").value(5.0 / 3600.0), 5.0);
        assert_eq!(MetricDisplay::of("stick_fraction").value(0.35), 35.0);
        assert_eq!(
            MetricDisplay::of("stick_slip_severity").label(),
            "stick-slip severity (10 ms average)"
        );
        // No code key survives as a label of a known metric.
        for key in [
            "mean_rop_m_per_h",
            "stick_slip_severity",
            "stick_fraction",
            "max_bit_speed_ratio",
            "impacts_per_s",
            "peak_wall_force_n",
            "mean_wob_n",
            "mean_tob_nm",
            "mse_pa",
            "efficiency",
            "axial_power_share",
            "fatigue_damage_per_h",
            "fatigue_life_h",
            "buckling_utilization",
            "helical_buckling_utilization",
            "buckling_margin",
        ] {
            assert!(!MetricDisplay::of(key).label().contains('_'), "{key}");
        }
        // Every metric of summary.json has a human name (no key shown as itself).
        for key in crate::metrics::catalogue::keys() {
            assert_ne!(MetricDisplay::of(key).name, key, "{key}");
        }
        assert_eq!(
            MetricDisplay::of("fatigue_life_h").label(),
            "fatigue life (worst section) [h]"
        );
        let unknown = MetricDisplay::of("new_metric");
        assert_eq!(
            (unknown.label().as_str(), unknown.scale),
            ("new_metric", 1.0)
        );
    }

    #[test]
    fn metrics_convert_to_field_units() {
        let wob = MetricDisplay::of_in("mean_wob_n", UnitSystem::Field);
        assert_eq!(wob.label(), "mean WOB [klbf]");
        // 100 kN = 22.48089 klbf (NIST SP 811).
        assert!((wob.value(100e3) - 22.480_89).abs() < 1e-5);
        let rop = MetricDisplay::of_in("mean_rop_m_per_h", UnitSystem::Field);
        assert_eq!(rop.label(), "mean ROP [ft/h]");
        assert!((rop.value(10.0) - 32.808_399).abs() < 1e-6);
        assert_eq!(
            MetricDisplay::of_in("mse_pa", UnitSystem::Field).unit,
            "psi"
        );
        // Units the two systems share stay as they are.
        let stick = MetricDisplay::of_in("stick_fraction", UnitSystem::Field);
        assert_eq!((stick.unit, stick.value(0.35)), ("%", 35.0));
        assert_eq!(
            MetricDisplay::of_in("mean_tob_nm", UnitSystem::Metric),
            MetricDisplay::of("mean_tob_nm")
        );
    }

    #[test]
    fn numbers_have_four_significant_digits() {
        assert_eq!(fmt_sig(0.0), "0");
        assert_eq!(fmt_sig(123.456), "123.5");
        assert_eq!(fmt_sig(-0.012345), "-0.01235");
        assert_eq!(fmt_sig(2.0), "2.000");
        assert_eq!(fmt_sig(1.5e-5), "1.500e-5");
        assert_eq!(fmt_sig(2.5e6), "2.500e6");
        assert_eq!(fmt_sig(f64::NAN), "NaN");
    }

    #[test]
    fn operating_points_read_in_rpm_and_m_per_h() {
        let op = OperatingPoint {
            omega: TAU,
            v0: 5.0 / 3600.0,
            wob: 0.0,
        };
        let metric = UnitSystem::Metric;
        assert_eq!(
            operating_point_text(&op, metric),
            "\u{3a9} = 60 rpm, V0 = 5 m/h"
        );
        let hook = OperatingPoint::hook_load(op.omega, 47_500.0);
        assert_eq!(
            operating_point_text(&hook, metric),
            "\u{3a9} = 60 rpm, WOB = 47.5 kN"
        );
        // Field units: 5 m/h = 16.404 ft/h, 47.5 kN = 10.678 klbf.
        let field = UnitSystem::Field;
        assert_eq!(
            operating_point_text(&op, field),
            "\u{3a9} = 60 rpm, V0 = 16.4 ft/h"
        );
        assert_eq!(
            operating_point_text(&hook, field),
            "\u{3a9} = 60 rpm, WOB = 10.68 klbf"
        );
        assert_eq!(short(111.111), "111.11");
        assert_eq!(short(2.5), "2.5");
        assert_eq!(short(-0.001), "0");
        assert_eq!(short(f64::INFINITY), "inf");
    }
}
