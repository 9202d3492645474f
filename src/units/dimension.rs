//! Physical quantities written with units, as users think of them.
//!
//! A problem file may give any dimensional value either as a bare number, read in SI units, or as a
//! string `"<number> <unit>"` (the space is optional): `"60 rpm"`, `"5 m/h"`, `"40 mm"`, `"250 kN"`.
//! [`Dimension::parse`] converts such a string to SI, and is also what the command line uses for
//! `--omega 60rpm` and `--v0 5m/h`.
//!
//! Oilfield units are accepted beside SI: `psi`, `ksi` (pressure, modulus), `lbf`, `klbf`
//! (force), `ppg` (mud weight, lbm/US gal) and `sg` (specific gravity, × 1000 kg/m³) for
//! densities, `in`, `ft` and `ft/h`; `ft·lbf` for torques (the thresholds of torque metrics).

use std::fmt;

/// Pound-force in N: the standard pound (0.45359237 kg, exact) times standard gravity
/// (9.80665 m/s², exact), so exact to the digits given (NIST SP 811, B.8).
pub const LBF_N: f64 = 4.448_221_615_260_5;
/// Pound-force per square inch in Pa: [`LBF_N`] over (0.0254 m)² (NIST SP 811, B.8).
pub const PSI_PA: f64 = 6_894.757_293_168;
/// Foot-pound-force in N·m: 0.3048 m (exact) times [`LBF_N`] (NIST SP 811, B.8: 1.355818).
pub const FT_LBF_NM: f64 = 0.3048 * LBF_N;
/// Pound-mass per US gallon (`ppg`, mud weight) in kg/m³: 0.45359237 kg / 3.785411784 L
/// (NIST SP 811, B.8: 1.198264 E+02).
pub const PPG_KG_M3: f64 = 119.826_427;

/// The physical dimension of a value, which fixes the units it may be written in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Dimension {
    /// Pure number.
    Dimensionless,
    /// Length, SI unit m.
    Length,
    /// Time, SI unit s.
    Time,
    /// Linear velocity, SI unit m/s.
    Velocity,
    /// Angular velocity, SI unit rad/s.
    AngularVelocity,
    /// Force, SI unit N.
    Force,
    /// Pressure or elastic modulus, SI unit Pa.
    Pressure,
    /// Mass density, SI unit kg/m³.
    Density,
    /// Acceleration, SI unit m/s².
    Acceleration,
    /// Inverse time (rates, mass-proportional damping), SI unit 1/s.
    Rate,
    /// Frequency of vibration, Hz (cutoff frequencies of the basis).
    Frequency,
    /// Inverse velocity, SI unit s/m (the bit–rock rate α_BR).
    InverseVelocity,
    /// Linear stiffness, SI unit N/m.
    Stiffness,
    /// Cubic stiffness, SI unit N/m³.
    CubicStiffness,
    /// Mass moment of inertia, SI unit kg·m².
    MomentOfInertia,
    /// Torque (moment), SI unit N·m.
    Torque,
    /// Impulse, SI unit N·s.
    Impulse,
    /// Power, SI unit W (a top drive's rating).
    Power,
    /// Mass per length, SI unit kg/m (a pipe's linear weight, as drill-pipe tables give it).
    LinearDensity,
}

/// `value` in a unit of `factor` SI units, in SI. A decimal sub-unit (mm, ms, us: factor 10⁻ᵏ)
/// divides by 10ᵏ, which is exact in floating point, so the result is the double nearest the
/// decimal the user typed: `"10 us"` is 1e-5 s, where 10 × 1e-6 is 9.999999999999999e-6 (the
/// factor 1e-6 itself is not exact).
fn to_si(value: f64, factor: f64) -> f64 {
    let inverse = (1.0 / factor).round();
    let decimal =
        factor < 1.0 && inverse <= 1e15 && 10f64.powi(inverse.log10().round() as i32) == inverse;
    if decimal && (factor * inverse - 1.0).abs() < 1e-15 {
        value / inverse
    } else {
        value * factor
    }
}

impl Dimension {
    /// Units accepted for this dimension, with their factor to SI.
    pub fn units(self) -> &'static [(&'static str, f64)] {
        use std::f64::consts::PI;
        match self {
            Dimension::Dimensionless => &[],
            Dimension::Length => &[
                ("m", 1.0),
                ("mm", 1e-3),
                ("cm", 1e-2),
                ("km", 1e3),
                ("in", 0.0254),
                ("ft", 0.3048),
                // Spellings of field reports (issue 33 item 7).
                ("inch", 0.0254),
                ("inches", 0.0254),
                ("foot", 0.3048),
                ("feet", 0.3048),
            ],
            Dimension::Time => &[
                ("s", 1.0),
                ("ms", 1e-3),
                ("us", 1e-6),
                ("µs", 1e-6),
                ("μs", 1e-6),
                ("min", 60.0),
                ("h", 3600.0),
            ],
            Dimension::Velocity => &[
                ("m/s", 1.0),
                ("mm/s", 1e-3),
                ("m/min", 1.0 / 60.0),
                ("m/h", super::M_S_PER_M_PER_H),
                ("ft/h", 0.3048 / 3600.0),
                ("m/hr", super::M_S_PER_M_PER_H),
                ("ft/hr", 0.3048 / 3600.0),
            ],
            Dimension::AngularVelocity => &[
                ("rad/s", 1.0),
                ("rpm", super::RAD_S_PER_RPM),
                ("rev/s", 2.0 * PI),
                ("Hz", 2.0 * PI),
            ],
            Dimension::Force => &[
                ("N", 1.0),
                ("kN", 1e3),
                ("MN", 1e6),
                ("lbf", LBF_N),
                ("klbf", 1e3 * LBF_N),
                // A kip is 1000 lbf; "klb" is the field's spelling of the same.
                ("kip", 1e3 * LBF_N),
                ("kips", 1e3 * LBF_N),
                ("klb", 1e3 * LBF_N),
            ],
            Dimension::Pressure => &[
                ("Pa", 1.0),
                ("kPa", 1e3),
                ("bar", 1e5),
                ("MPa", 1e6),
                ("GPa", 1e9),
                ("psi", PSI_PA),
                ("ksi", 1e3 * PSI_PA),
            ],
            Dimension::Density => &[
                ("kg/m3", 1.0),
                ("kg/m^3", 1.0),
                ("g/cm3", 1e3),
                ("g/cm^3", 1e3),
                ("ppg", PPG_KG_M3),
                ("sg", 1e3),
                ("lb/gal", PPG_KG_M3),
            ],
            Dimension::Acceleration => &[("m/s2", 1.0), ("m/s^2", 1.0)],
            Dimension::Rate => &[
                ("1/s", 1.0),
                ("Hz", 1.0),
                ("1/min", 1.0 / 60.0),
                ("1/h", 1.0 / 3600.0),
            ],
            Dimension::Frequency => &[("Hz", 1.0), ("kHz", 1e3)],
            Dimension::InverseVelocity => &[("s/m", 1.0), ("s/ft", 1.0 / 0.3048)],
            Dimension::Stiffness => &[("N/m", 1.0), ("kN/m", 1e3), ("MN/m", 1e6)],
            Dimension::CubicStiffness => &[("N/m3", 1.0), ("N/m^3", 1.0)],
            Dimension::MomentOfInertia => &[
                ("kg m^2", 1.0),
                ("kg*m^2", 1.0),
                ("kg·m²", 1.0),
                ("kg m2", 1.0),
                // lbm·ft²: 0.45359237 kg × 0.3048² m² (NIST SP 811, B.8: 4.214011 E−02).
                ("lbm ft^2", 0.045_359_237 * 0.929_030_4),
            ],
            Dimension::Torque => &[
                ("N·m", 1.0),
                ("N.m", 1.0),
                ("Nm", 1.0),
                ("kN·m", 1e3),
                ("kN.m", 1e3),
                ("kNm", 1e3),
                ("ft·lbf", FT_LBF_NM),
                ("ft.lbf", FT_LBF_NM),
                ("kft·lbf", 1e3 * FT_LBF_NM),
                ("kft.lbf", 1e3 * FT_LBF_NM),
            ],
            Dimension::Impulse => &[
                ("N·s", 1.0),
                ("N.s", 1.0),
                ("Ns", 1.0),
                ("kN·s", 1e3),
                ("kN.s", 1e3),
            ],
            Dimension::Power => &[
                ("W", 1.0),
                ("kW", 1e3),
                ("MW", 1e6),
                // Mechanical horsepower, 550 ft·lbf/s (NIST SP 811, B.8: 7.456999 E+02 W).
                ("hp", 550.0 * FT_LBF_NM),
            ],
            // 1 lb = 0.45359237 kg, 1 ft = 0.3048 m (exact, NIST SP 811); "ppf", pounds per foot,
            // is the field's spelling.
            Dimension::LinearDensity => &[
                ("kg/m", 1.0),
                ("lb/ft", 0.453_592_37 / 0.3048),
                ("lbm/ft", 0.453_592_37 / 0.3048),
                ("ppf", 0.453_592_37 / 0.3048),
            ],
        }
    }

    /// The SI unit, for messages.
    pub fn si_unit(self) -> &'static str {
        self.units().first().map_or("(no unit)", |(u, _)| u)
    }

    /// Parse `"<number> <unit>"` (or a bare number, read as SI) into SI units.
    /// A size may be written as the tables do, `"8 1/2 in"`, `"8½ in"` ([`super::fraction`]).
    pub fn parse(self, text: &str) -> Result<f64, UnitError> {
        let text = text.trim();
        let (value, unit) = match super::fraction::leading_fraction(text) {
            Some(read) => read,
            None => {
                let split = text
                    .char_indices()
                    .find(|&(i, c)| !is_number_char(text, i, c))
                    .map_or(text.len(), |(i, _)| i);
                let (number, unit) = text.split_at(split);
                let value: f64 = number
                    .replace('_', "")
                    .parse()
                    .map_err(|_| UnitError::new(self, text, "does not start with a number"))?;
                (value, unit)
            }
        };
        let unit = unit.trim();
        // `-0` is 0 (no negative zero reaches a result: `--v0 -0m/h` wrote "v0_m_s": -0.0).
        if unit.is_empty() {
            return Ok(value + 0.0);
        }
        // The exact spelling first; else a unit that matches ignoring case, if only one does
        // ("80 RPM", "5 M/H"), so that no spelling can mean two units.
        let exact = self.units().iter().find(|(name, _)| *name == unit);
        let folded = || {
            let mut m = self
                .units()
                .iter()
                .filter(|(name, _)| name.eq_ignore_ascii_case(unit));
            match (m.next(), m.next()) {
                (Some(one), None) => Some(one),
                _ => None,
            }
        };
        exact
            .or_else(folded)
            .map(|(_, factor)| to_si(value, *factor) + 0.0)
            .ok_or_else(|| UnitError::new(self, text, &self.not_a_unit_of(unit)))
    }

    /// Every dimension, for messages.
    pub const ALL: [Dimension; 19] = [
        Dimension::Dimensionless,
        Dimension::Length,
        Dimension::Time,
        Dimension::Velocity,
        Dimension::AngularVelocity,
        Dimension::Force,
        Dimension::Pressure,
        Dimension::Density,
        Dimension::Acceleration,
        Dimension::Rate,
        Dimension::Frequency,
        Dimension::InverseVelocity,
        Dimension::Stiffness,
        Dimension::CubicStiffness,
        Dimension::MomentOfInertia,
        Dimension::Torque,
        Dimension::Impulse,
        Dimension::Power,
        Dimension::LinearDensity,
    ];

    /// "a force", "a stress (pressure)": the dimension in words, for messages.
    pub fn name(self) -> &'static str {
        use Dimension::*;
        match self {
            Dimensionless => "dimensionless",
            Length => "a length",
            Time => "a time",
            Velocity => "a velocity",
            AngularVelocity => "an angular velocity",
            Force => "a force",
            Pressure => "a stress (pressure)",
            Density => "a density",
            Acceleration => "an acceleration",
            Rate => "a rate",
            Frequency => "a frequency",
            InverseVelocity => "an inverse velocity",
            Stiffness => "a stiffness",
            CubicStiffness => "a cubic stiffness",
            Torque => "a torque",
            Impulse => "an impulse",
            Power => "a power",
            LinearDensity => "a mass per length",
            MomentOfInertia => "a moment of inertia",
        }
    }

    /// Why `unit` is refused for this dimension: a unit of another dimension is named as such
    /// ("`MPa` is a unit of a stress (pressure), not of a force"), anything else is unknown.
    fn not_a_unit_of(self, unit: &str) -> String {
        let other = Dimension::ALL.iter().find(|d| {
            d.units()
                .iter()
                .any(|(name, _)| *name == unit || name.eq_ignore_ascii_case(unit))
        });
        match other {
            Some(d) if self == Dimension::Dimensionless => {
                format!(
                    "has the unit `{unit}` of {}, but the value is dimensionless",
                    d.name()
                )
            }
            Some(d) => format!(
                "has the unit `{unit}` of {}, the wrong dimension: the value is {}",
                d.name(),
                self.name()
            ),
            None => format!("unknown unit `{unit}`"),
        }
    }
}

/// Whether the character `c` at byte `i` still belongs to the leading number of `text`.
fn is_number_char(text: &str, i: usize, c: char) -> bool {
    let exponent = matches!(c, 'e' | 'E') && exponent_follows(text, i);
    c.is_ascii_digit() || matches!(c, '.' | '+' | '-' | '_') || exponent
}

/// Whether the `e`/`E` at byte `i` of `text` starts an exponent (`1e10`, `2.5E-3`), not a unit.
fn exponent_follows(text: &str, i: usize) -> bool {
    let rest = &text[i + 1..];
    let rest = rest.strip_prefix(['+', '-']).unwrap_or(rest);
    i > 0 && rest.starts_with(|c: char| c.is_ascii_digit())
}

/// A quantity that could not be read: what was written and what is allowed.
#[derive(Debug, Clone, PartialEq)]
pub struct UnitError {
    pub text: String,
    pub reason: String,
    pub allowed: String,
}

impl UnitError {
    fn new(dim: Dimension, text: &str, reason: &str) -> Self {
        let units: Vec<&str> = dim.units().iter().map(|(u, _)| *u).collect();
        let allowed = if units.is_empty() {
            "a plain number".to_string()
        } else {
            format!("a number with one of the units {}", units.join(", "))
        };
        UnitError {
            text: text.to_string(),
            reason: reason.to_string(),
            allowed,
        }
    }
}

impl fmt::Display for UnitError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "`{}` {}; expected {}",
            self.text, self.reason, self.allowed
        )
    }
}

impl std::error::Error for UnitError {}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;
    use std::f64::consts::PI;

    #[test]
    fn minus_zero_reads_as_zero() {
        for text in ["-0", "-0 m/h", "-0.0rpm"] {
            let dim = if text.contains("rpm") {
                Dimension::AngularVelocity
            } else {
                Dimension::Velocity
            };
            let v = dim.parse(text).unwrap();
            assert!(v == 0.0 && v.is_sign_positive(), "{text}: {v:?}");
        }
    }

    /// A decimal sub-unit gives the double nearest the typed decimal (a review found `"10 us"`
    /// read as 9.999999999999999e-6 s, a different model hash from `1e-5` and, through the
    /// chaos of stick-slip, a different run); other factors multiply as before.
    #[test]
    fn decimal_sub_units_are_exact_to_the_typed_decimal() {
        assert_eq!(Dimension::Time.parse("10 us").unwrap(), 1e-5);
        assert_eq!(Dimension::Time.parse("0.01 ms").unwrap(), 1e-5);
        // The micro sign (U+00B5) and the Greek mu (U+03BC), as the README writes µs.
        assert_eq!(Dimension::Time.parse("10 µs").unwrap(), 1e-5);
        assert_eq!(Dimension::Time.parse("10 μs").unwrap(), 1e-5);
        assert_eq!(Dimension::Time.parse("69 ms").unwrap(), 0.069);
        assert_eq!(Dimension::Length.parse("40 mm").unwrap(), 0.04);
        assert_eq!(Dimension::Length.parse("7 cm").unwrap(), 0.07);
        assert_eq!(Dimension::Length.parse("2 km").unwrap(), 2000.0);
        assert_eq!(Dimension::Length.parse("1 ft").unwrap(), 0.3048);
        // 1 bar = 100 kPa (ISO 80000-4).
        assert_eq!(Dimension::Pressure.parse("200 bar").unwrap(), 2e7);
        for v in [1.0, 3.0, 10.0, 20.0, 30.0, 40.0, 105.0, 123.456] {
            assert_eq!(
                Dimension::Time.parse(&format!("{v} us")).unwrap(),
                v / 1e6,
                "{v}"
            );
        }
    }

    #[test]
    fn converts_the_units_drillers_use() {
        assert_relative_eq!(
            Dimension::AngularVelocity.parse("60 rpm").unwrap(),
            2.0 * PI
        );
        assert_relative_eq!(Dimension::AngularVelocity.parse("60rpm").unwrap(), 2.0 * PI);
        assert_relative_eq!(Dimension::Velocity.parse("5 m/h").unwrap(), 1.0 / 720.0);
        assert_relative_eq!(Dimension::Length.parse("40 mm").unwrap(), 0.04);
        assert_relative_eq!(Dimension::Force.parse("250 kN").unwrap(), 250e3);
        assert_relative_eq!(Dimension::Pressure.parse("203 GPa").unwrap(), 203e9);
        assert_relative_eq!(Dimension::Stiffness.parse("1e10 N/m").unwrap(), 1e10);
        assert_relative_eq!(Dimension::Velocity.parse("1.5e-3").unwrap(), 1.5e-3);
        assert_relative_eq!(Dimension::Time.parse("69 ms").unwrap(), 0.069);
        // Case is forgiven when only one unit matches.
        assert_relative_eq!(
            Dimension::AngularVelocity.parse("60 RPM").unwrap(),
            2.0 * PI
        );
        assert_relative_eq!(Dimension::Velocity.parse("5 M/H").unwrap(), 1.0 / 720.0);
        assert_relative_eq!(Dimension::Force.parse("250 KN").unwrap(), 250e3);
    }

    /// Issue 13 item 12: the oilfield units, against the published conversion factors (NIST SP 811
    /// appendix B.8; 1 lbf = 0.45359237 kg × 9.80665 m/s² exactly).
    #[test]
    fn converts_oilfield_units_with_the_published_factors() {
        let close = |got: f64, want: f64| {
            assert!((got - want).abs() <= 1e-14 * want.abs(), "{got} != {want}");
        };
        close(Dimension::Force.parse("1 lbf").unwrap(), 4.4482216152605);
        close(
            Dimension::Force.parse("56.2 klbf").unwrap(),
            56.2e3 * 4.4482216152605,
        );
        close(
            Dimension::Force.parse("1 lbf").unwrap(),
            0.45359237 * 9.80665,
        );
        close(Dimension::Pressure.parse("1 psi").unwrap(), 6894.757293168);
        close(
            Dimension::Pressure.parse("29.4e6 psi").unwrap(),
            29.4e6 * 6894.757293168,
        );
        close(
            Dimension::Pressure.parse("1 ksi").unwrap(),
            6894.757293168e3,
        );
        // psi is lbf/in²: the two factors agree to their printed digits.
        let psi = 4.4482216152605 / (0.0254 * 0.0254);
        assert!((Dimension::Pressure.parse("1 psi").unwrap() - psi).abs() < 1e-12 * psi);
        close(Dimension::Density.parse("1 ppg").unwrap(), 119.826427);
        close(Dimension::Density.parse("10 ppg").unwrap(), 1198.26427);
        // lbm / US gal = 0.45359237 kg / 3.785411784e-3 m³, to the published 9 digits.
        let ppg = 0.45359237 / 3.785411784e-3;
        assert!((Dimension::Density.parse("1 ppg").unwrap() - ppg).abs() < 1e-6);
        close(Dimension::Density.parse("1.2 sg").unwrap(), 1200.0);
        close(Dimension::Density.parse("1.2 SG").unwrap(), 1200.0);
        close(Dimension::Length.parse("6.75 in").unwrap(), 0.17145);
        close(
            Dimension::Velocity.parse("100 ft/h").unwrap(),
            30.48 / 3600.0,
        );
        // Torques (thresholds of torque metrics): 1 ft·lbf = 0.3048 m × 1 lbf (NIST SP 811, B.8:
        // 1.355818 N·m).
        close(
            Dimension::Torque.parse("1 ft·lbf").unwrap(),
            1.3558179483314004,
        );
        assert!((Dimension::Torque.parse("1 ft.lbf").unwrap() - 1.355818).abs() < 1e-6);
        close(Dimension::Torque.parse("2.5 kN·m").unwrap(), 2500.0);
        close(Dimension::Impulse.parse("3 kN·s").unwrap(), 3000.0);
        close(Dimension::Power.parse("25 kW").unwrap(), 25e3);
        // 19.81 lb/ft (the plain-end weight of 5½ in 21.90 lb/ft drill pipe) is 29.48 kg/m.
        close(
            Dimension::LinearDensity.parse("19.81 lb/ft").unwrap(),
            19.81 * 1.488_163_943_569_553_8,
        );
        close(Dimension::LinearDensity.parse("29.5 kg/m").unwrap(), 29.5);
        // 1000 hp: a mid-size top drive (NIST: 1 hp = 745.6999 W).
        assert!((Dimension::Power.parse("1000 hp").unwrap() - 745_699.9).abs() < 0.1);
        close(Dimension::Rate.parse("7.2 1/h").unwrap(), 0.002);
        // A unit of another dimension is refused as such, listing the oilfield units too.
        let err = Dimension::Density.parse("10 psi").unwrap_err().to_string();
        assert!(
            err.contains(
                "unit `psi` of a stress (pressure), the wrong dimension: the value is a density"
            ) && err.contains("ppg, sg"),
            "{err}"
        );
        let err = Dimension::Force.parse("20 MPa").unwrap_err().to_string();
        assert!(
            err.contains("wrong dimension: the value is a force") && err.contains("kN"),
            "{err}"
        );
        let err = Dimension::Dimensionless
            .parse("3 m")
            .unwrap_err()
            .to_string();
        assert!(err.contains("but the value is dimensionless"), "{err}");
    }

    #[test]
    fn rejects_unknown_units_and_garbage_with_the_allowed_units() {
        let err = Dimension::AngularVelocity.parse("60 rps").unwrap_err();
        assert!(err.to_string().contains("unknown unit `rps`"), "{err}");
        assert!(err.to_string().contains("rpm"), "{err}");
        let err = Dimension::Velocity.parse("fast").unwrap_err();
        assert!(
            err.to_string().contains("does not start with a number"),
            "{err}"
        );
        assert!(Dimension::Dimensionless.parse("3 m").is_err());
    }

    /// The spellings of field reports (issue 33 item 7) read as their canonical units.
    #[test]
    fn field_spellings_are_read() {
        let close = |a: f64, b: f64| assert_relative_eq!(a, b, max_relative = 1e-15);
        close(Dimension::Length.parse("300 feet").unwrap(), 91.44);
        close(Dimension::Length.parse("1 foot").unwrap(), 0.3048);
        close(Dimension::Length.parse("8.5 inches").unwrap(), 8.5 * 0.0254);
        close(
            Dimension::Velocity.parse("60 ft/hr").unwrap(),
            Dimension::Velocity.parse("60 ft/h").unwrap(),
        );
        close(
            Dimension::Velocity.parse("20 m/hr").unwrap(),
            Dimension::Velocity.parse("20 m/h").unwrap(),
        );
        for k in ["kip", "kips", "klb"] {
            close(
                Dimension::Force.parse(&format!("25 {k}")).unwrap(),
                25e3 * 0.453_592_37 * 9.806_65,
            );
        }
        close(
            Dimension::Density.parse("10 lb/gal").unwrap(),
            Dimension::Density.parse("10 ppg").unwrap(),
        );
        close(
            Dimension::InverseVelocity.parse("100 s/ft").unwrap(),
            100.0 / 0.3048,
        );
    }
}
