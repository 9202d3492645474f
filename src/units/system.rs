//! The units of what drillopt shows a person: the terminal, the CSV tables and the plots.
//!
//! Two systems, chosen on the command line (`--units metric|field`):
//!
//! | quantity | [`UnitSystem::Metric`] (the driller's metric units) | [`UnitSystem::Field`] (oilfield units) |
//! |---|---|---|
//! | rotation speed | rpm | rpm |
//! | ROP, feed | m/h | ft/h |
//! | force (WOB, hook load, wall force) | kN | klbf |
//! | torque (TOB, top torque) | kN·m | kft·lbf |
//! | stress, MSE, pressure | MPa | psi |
//! | position along the string, length | m | ft |
//! | size (diameter, gap, depth of cut) | mm | in |
//! | power | kW | hp |
//! | impulse | kN·s | klbf·s |
//! | density | kg/m³ | ppg |
//! | mass per length | kg/m | lb/ft |
//! | force per length | N/m | lbf/ft |
//!
//! The factors are exact by definition (NIST SP 811, B.8: the international foot 0.3048 m, the
//! pound-force [`LBF_N`], the psi [`PSI_PA`], the mechanical horsepower 550 ft·lbf/s); every other
//! quantity (time, frequency, rates, pure numbers and shares) is the same in both. The result
//! files meant for programs (`summary.json`, `solution.json`, `map.json`, `compare.json`,
//! `timeseries.csv`) stay in SI in either system, with the unit in each key.

use super::dimension::{FT_LBF_NM, LBF_N, PPG_KG_M3, PSI_PA};
use super::{Dimension, M_PER_H_PER_M_PER_S, RPM_PER_RAD_S};

/// m per international foot (exact).
const FT_M: f64 = 0.3048;
/// m per inch (exact).
const IN_M: f64 = 0.0254;
/// W per mechanical horsepower: 550 ft·lbf/s (NIST SP 811, B.8: 7.456999 E+02).
const HP_W: f64 = 550.0 * FT_LBF_NM;
/// kg/m per lb/ft: the pound-mass (0.45359237 kg, exact) per foot.
const LB_PER_FT_KG_M: f64 = 0.453_592_37 / FT_M;

/// The system of units of the human-readable outputs.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum UnitSystem {
    /// rpm, m/h, kN, kN·m, MPa, m, mm, kW (the default).
    #[default]
    Metric,
    /// rpm, ft/h, klbf, kft·lbf, psi, ft, in, hp: the units of a US field report.
    Field,
}

/// A kind of quantity as a person reads it (the rows of the module's table).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Shown {
    /// Rotation speed: rpm in both systems (from rad/s).
    RotationSpeed,
    /// Rate of penetration, feed, axial speed: m/h or ft/h (from m/s).
    Rop,
    /// Force: kN or klbf (from N).
    Force,
    /// Torque: kN·m or kft·lbf (from N·m).
    Torque,
    /// Stress, MSE, pressure: MPa or psi (from Pa).
    Stress,
    /// A position along the string or a length: m or ft (from m).
    Position,
    /// A size across the string (diameter, gap, radial displacement, depth of cut): mm or in
    /// (from m).
    Size,
    /// Power: kW or hp (from W).
    Power,
    /// Impulse: kN·s or klbf·s (from N·s).
    Impulse,
    /// Mass density: kg/m³ or ppg (from kg/m³).
    Density,
    /// Mass per length: kg/m or lb/ft (from kg/m).
    LinearDensity,
    /// Force per length (a buoyed weight, a wall load): N/m or lbf/ft (from N/m).
    LineLoad,
}

impl UnitSystem {
    /// The unit `q` is shown in, e.g. "kN" or "klbf".
    pub fn unit(self, q: Shown) -> &'static str {
        self.unit_and_factor(q).0
    }

    /// The shown value of `si`, a value of `q` in SI (rad/s, m/s, N, N·m, Pa, m, W, N·s, kg/m³,
    /// kg/m).
    pub fn of(self, q: Shown, si: f64) -> f64 {
        si * self.unit_and_factor(q).1
    }

    /// The unit `q` is shown in and the factor from SI to it (shown = factor × SI).
    pub fn unit_and_factor(self, q: Shown) -> (&'static str, f64) {
        use Shown::*;
        match (self, q) {
            (_, RotationSpeed) => ("rpm", RPM_PER_RAD_S),
            (UnitSystem::Metric, Rop) => ("m/h", M_PER_H_PER_M_PER_S),
            (UnitSystem::Metric, Force) => ("kN", 1e-3),
            (UnitSystem::Metric, Torque) => ("kN\u{b7}m", 1e-3),
            (UnitSystem::Metric, Stress) => ("MPa", 1e-6),
            (UnitSystem::Metric, Position) => ("m", 1.0),
            (UnitSystem::Metric, Size) => ("mm", 1e3),
            (UnitSystem::Metric, Power) => ("kW", 1e-3),
            (UnitSystem::Metric, Impulse) => ("kN\u{b7}s", 1e-3),
            (UnitSystem::Metric, Density) => ("kg/m\u{b3}", 1.0),
            (UnitSystem::Metric, LinearDensity) => ("kg/m", 1.0),
            (UnitSystem::Metric, LineLoad) => ("N/m", 1.0),
            (UnitSystem::Field, Rop) => ("ft/h", 3600.0 / FT_M),
            (UnitSystem::Field, Force) => ("klbf", 1e-3 / LBF_N),
            (UnitSystem::Field, Torque) => ("kft\u{b7}lbf", 1e-3 / FT_LBF_NM),
            (UnitSystem::Field, Stress) => ("psi", 1.0 / PSI_PA),
            (UnitSystem::Field, Position) => ("ft", 1.0 / FT_M),
            (UnitSystem::Field, Size) => ("in", 1.0 / IN_M),
            (UnitSystem::Field, Power) => ("hp", 1.0 / HP_W),
            (UnitSystem::Field, Impulse) => ("klbf\u{b7}s", 1e-3 / LBF_N),
            (UnitSystem::Field, Density) => ("ppg", 1.0 / PPG_KG_M3),
            (UnitSystem::Field, LinearDensity) => ("lb/ft", 1.0 / LB_PER_FT_KG_M),
            (UnitSystem::Field, LineLoad) => ("lbf/ft", FT_M / LBF_N),
        }
    }

    /// `value`, given in the metric display unit `metric_unit` (one of the units of the
    /// [`Shown`] rows in [`UnitSystem::Metric`], e.g. "kN"), in this system: its unit and the
    /// value. A unit that is the same in both systems (rpm, %, 1/s, Hz, h, a pure number "") and
    /// any other unit come back as they are.
    pub fn from_metric(self, metric_unit: &'static str, value: f64) -> (&'static str, f64) {
        let (unit, factor) = self.convert_metric(metric_unit);
        (unit, factor * value)
    }

    /// The unit and the factor from a value in the metric display unit `metric_unit` to this
    /// system (1 and the same unit for a unit that is the same in both, or unknown).
    pub fn convert_metric(self, metric_unit: &'static str) -> (&'static str, f64) {
        let Some(q) = Shown::of_metric_unit(metric_unit) else {
            return (metric_unit, 1.0);
        };
        let (_, metric) = UnitSystem::Metric.unit_and_factor(q);
        let (unit, own) = self.unit_and_factor(q);
        (unit, own / metric)
    }

    /// The unit and factor from SI of a value of dimension `dim` (the problem's keys, the
    /// metrics by their dimension): the [`Shown`] row of the dimension; the SI unit otherwise
    /// ("1" for a pure number).
    pub fn for_dimension(self, dim: Dimension) -> (&'static str, f64) {
        let q = match dim {
            Dimension::AngularVelocity => Shown::RotationSpeed,
            Dimension::Velocity => Shown::Rop,
            Dimension::Force => Shown::Force,
            Dimension::Torque => Shown::Torque,
            Dimension::Pressure => Shown::Stress,
            Dimension::Impulse => Shown::Impulse,
            Dimension::Power => Shown::Power,
            Dimension::Dimensionless => return ("1", 1.0),
            Dimension::Length | Dimension::Density | Dimension::LinearDensity
                if self == UnitSystem::Metric =>
            {
                return (dim.si_unit(), 1.0);
            }
            Dimension::Length => Shown::Position,
            Dimension::Density => Shown::Density,
            Dimension::LinearDensity => Shown::LinearDensity,
            other => return (other.si_unit(), 1.0),
        };
        self.unit_and_factor(q)
    }

    /// The name used on the command line: "metric" or "field".
    pub fn name(self) -> &'static str {
        match self {
            UnitSystem::Metric => "metric",
            UnitSystem::Field => "field",
        }
    }
}

impl Shown {
    const ALL: [Shown; 12] = [
        Shown::RotationSpeed,
        Shown::Rop,
        Shown::Force,
        Shown::Torque,
        Shown::Stress,
        Shown::Position,
        Shown::Size,
        Shown::Power,
        Shown::Impulse,
        Shown::Density,
        Shown::LinearDensity,
        Shown::LineLoad,
    ];

    /// The row whose metric unit is `unit` ("kN" → [`Shown::Force`]).
    fn of_metric_unit(unit: &str) -> Option<Shown> {
        Shown::ALL
            .into_iter()
            .find(|&q| UnitSystem::Metric.unit(q) == unit)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64, rel: f64) -> bool {
        (a - b).abs() <= rel * b.abs()
    }

    #[test]
    fn field_factors_match_published_conversions() {
        // NIST SP 811 (2008), Appendix B.8, to the digits it prints.
        let f = UnitSystem::Field;
        // 1 lbf = 4.448222 N, so 100 kN = 22.48089 klbf.
        assert!(close(f.of(Shown::Force, 100e3), 22.480_89, 1e-6));
        // 1 ft·lbf = 1.355818 N·m: 10 kN·m = 7.375621 kft·lbf.
        assert!(close(f.of(Shown::Torque, 10e3), 7.375_621, 1e-6));
        // 1 psi = 6.894757 kPa: 100 MPa = 14 503.77 psi.
        assert!(close(f.of(Shown::Stress, 100e6), 14_503.77, 1e-6));
        // 10 m/h = 32.808 ft/h.
        assert!(close(f.of(Shown::Rop, 10.0 / 3600.0), 32.808_398_95, 1e-9));
        assert!(close(f.of(Shown::Position, 1000.0), 3_280.839_895, 1e-9));
        assert!(close(f.of(Shown::Size, 0.1397), 5.5, 1e-12));
        // 1 hp = 745.6999 W.
        assert!(close(f.of(Shown::Power, 745.6999), 1.0, 1e-7));
        // 1 ppg = 119.8264 kg/m³: 1200 kg/m³ = 10.01449 ppg.
        assert!(close(f.of(Shown::Density, 1200.0), 10.014_49, 1e-6));
        // 19.5 lb/ft = 29.0193 kg/m.
        assert!(close(f.of(Shown::LinearDensity, 29.019_3), 19.5, 1e-5));
        // 1 lbf/ft = 14.59390 N/m.
        assert!(close(f.of(Shown::LineLoad, 14.593_90), 1.0, 1e-6));
        // Rotation speed: rpm in both.
        assert_eq!(f.unit(Shown::RotationSpeed), "rpm");
        assert!(close(
            f.of(Shown::RotationSpeed, std::f64::consts::TAU),
            60.0,
            1e-15
        ));
    }

    #[test]
    fn metric_is_the_driller_units_of_the_terminal() {
        let m = UnitSystem::Metric;
        assert_eq!(m.unit_and_factor(Shown::Force), ("kN", 1e-3));
        assert_eq!(m.unit(Shown::Torque), "kN\u{b7}m");
        assert_eq!(m.unit(Shown::Rop), "m/h");
        assert!(close(m.of(Shown::Rop, 5.0 / 3600.0), 5.0, 1e-15));
        assert_eq!(m.of(Shown::Stress, 7.37e8), 737.0);
        // A value in a metric display unit converts to the field one, and the round trip
        // through SI agrees.
        for q in Shown::ALL {
            let metric_unit = m.unit(q);
            let (unit, v) = UnitSystem::Field.from_metric(metric_unit, 1.0);
            assert_eq!(unit, UnitSystem::Field.unit(q), "{q:?}");
            let si = 1.0 / m.of(q, 1.0);
            assert!(close(v, UnitSystem::Field.of(q, si), 1e-14), "{q:?}");
            assert_eq!(m.from_metric(metric_unit, 2.5), (metric_unit, 2.5));
        }
        // Units that are the same in both systems come back unchanged.
        for unit in ["rpm", "%", "1/s", "Hz", "h", "", "1/h"] {
            assert_eq!(UnitSystem::Field.from_metric(unit, 3.0), (unit, 3.0));
        }
    }

    #[test]
    fn dimensions_map_to_their_rows() {
        let f = UnitSystem::Field;
        assert_eq!(f.for_dimension(Dimension::Force).0, "klbf");
        assert_eq!(f.for_dimension(Dimension::Length).0, "ft");
        assert_eq!(f.for_dimension(Dimension::Time), ("s", 1.0));
        assert_eq!(f.for_dimension(Dimension::Dimensionless), ("1", 1.0));
        let m = UnitSystem::Metric;
        assert_eq!(m.for_dimension(Dimension::Length), ("m", 1.0));
        assert_eq!(m.for_dimension(Dimension::Pressure), ("MPa", 1e-6));
        assert_eq!(m.for_dimension(Dimension::AngularVelocity).0, "rpm");
    }
}
