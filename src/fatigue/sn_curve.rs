//! S-N curves and Miner's rule.
//!
//! A curve is one or two straight lines in log-log form, as DNV-RP-C203 writes them (DNV GL,
//! *Fatigue design of offshore steel structures*, edition April 2016, §2.4.1, Eq. (2.4.1)):
//!
//!   log₁₀ N = log₁₀ ā₁ − m₁ log₁₀ Δσ   for N ≤ N_knee,
//!   log₁₀ N = log₁₀ ā₂ − m₂ log₁₀ Δσ   for N > N_knee,
//!
//! with N the cycles to failure at the constant stress range Δσ **in MPa** and N_knee where the
//! two lines meet (10⁷ cycles for the curves in air). An endurance limit Δσ_e (a stress range)
//! cuts the curve off: cycles of a smaller range do no damage. A stress concentration factor
//! multiplies every range before it is read on the curve.
//!
//! Damage is Miner's rule (Palmgren–Miner, linear accumulation): D = Σ nᵢ / N(Δσᵢ), failure at
//! D = 1. No mean-stress correction is applied (the DNV curves are curves of stress range, and
//! Goodman's correction is not built): a cycle's damage depends on its range alone.
//!
//! The named curves are DNV-RP-C203 (2016) Table 2-1, "S-N curves in air", with the table's
//! "fatigue limit at 10⁷ cycles" as their default endurance limit (the classical endurance limit
//! of the constant-amplitude test that a rotating pipe under a steady bend repeats). DNV itself
//! reads the small cycles of a variable-amplitude spectrum on the m₂ = 5 branch, without a
//! cut-off: set the endurance limit to 0 to do the same. The default, DNV-B1, is the curve of
//! non-welded base material (DNV-RP-C203 App. A, Table A-1), the pipe body away from its tool
//! joints and upsets.

use serde::Serialize;

/// One row of DNV-RP-C203 (April 2016) Table 2-1, S-N curves in air: name, m₁, log₁₀ ā₁ (N ≤ 10⁷),
/// log₁₀ ā₂ (N > 10⁷, m₂ = 5), fatigue limit at 10⁷ cycles (MPa).
pub const DNV_AIR: [(&str, f64, f64, f64, f64); 14] = [
    ("DNV-B1", 4.0, 15.117, 17.146, 106.97),
    ("DNV-B2", 4.0, 14.885, 16.856, 93.59),
    ("DNV-C", 3.0, 12.592, 16.320, 73.10),
    ("DNV-C1", 3.0, 12.449, 16.081, 65.50),
    ("DNV-C2", 3.0, 12.301, 15.835, 58.48),
    ("DNV-D", 3.0, 12.164, 15.606, 52.63),
    ("DNV-E", 3.0, 12.010, 15.350, 46.78),
    ("DNV-F", 3.0, 11.855, 15.091, 41.52),
    ("DNV-F1", 3.0, 11.699, 14.832, 36.84),
    ("DNV-F3", 3.0, 11.546, 14.576, 32.75),
    ("DNV-G", 3.0, 11.398, 14.330, 29.24),
    ("DNV-W1", 3.0, 11.261, 14.101, 26.32),
    ("DNV-W2", 3.0, 11.107, 13.845, 23.39),
    ("DNV-W3", 3.0, 10.970, 13.617, 21.05),
];

/// Slope of the second branch of every DNV curve in air.
pub const DNV_M2: f64 = 5.0;

/// The curve used when a problem names none.
pub const DEFAULT_SN_CURVE: &str = "DNV-B1";

/// Pa per MPa: the curves are written in MPa.
const PA_PER_MPA: f64 = 1e6;

/// An S-N curve with its endurance limit and stress concentration (see the module documentation).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SnCurve {
    /// A name of [`DNV_AIR`], or "custom" for a curve given by its parameters.
    pub name: &'static str,
    /// log₁₀ ā₁ of the first branch (Δσ in MPa).
    pub log_a1: f64,
    /// Inverse slope m₁ of the first branch, > 0.
    pub m1: f64,
    /// (log₁₀ ā₂, m₂) of the branch beyond the knee, m₂ > m₁; None: one straight line.
    pub second: Option<(f64, f64)>,
    /// Endurance limit Δσ_e: ranges (after the stress concentration) below it do no damage, Pa
    /// (≥ 0; 0: no cut-off).
    pub endurance_limit: f64,
    /// Stress concentration factor multiplying every range, ≥ 1.
    pub stress_concentration: f64,
}

impl Default for SnCurve {
    fn default() -> Self {
        SnCurve::named(DEFAULT_SN_CURVE).expect("the default curve is in the table")
    }
}

impl SnCurve {
    /// The curve of [`DNV_AIR`] called `name` (case ignored), with the table's fatigue limit as its
    /// endurance limit and no stress concentration.
    pub fn named(name: &str) -> Option<Self> {
        let &(name, m1, log_a1, log_a2, limit) = DNV_AIR
            .iter()
            .find(|row| row.0.eq_ignore_ascii_case(name.trim()))?;
        Some(SnCurve {
            name,
            log_a1,
            m1,
            second: Some((log_a2, DNV_M2)),
            endurance_limit: limit * PA_PER_MPA,
            stress_concentration: 1.0,
        })
    }

    /// Stress range at which the two branches meet, Pa (∞ for one branch).
    pub fn knee_range(&self) -> f64 {
        match self.second {
            Some((log_a2, m2)) => 10f64.powf((log_a2 - self.log_a1) / (m2 - self.m1)) * PA_PER_MPA,
            None => f64::INFINITY,
        }
    }

    /// Stress range with `cycles` cycles to failure on the curve (no cut-off), Pa.
    pub fn range_at(&self, cycles: f64) -> f64 {
        let log_n = cycles.log10();
        let first = (self.log_a1 - log_n) / self.m1;
        let s = match self.second {
            Some((log_a2, m2)) if 10f64.powf(first) * PA_PER_MPA < self.knee_range() => {
                (log_a2 - log_n) / m2
            }
            _ => first,
        };
        10f64.powf(s) * PA_PER_MPA
    }

    /// Cycles to failure N at the stress range `range` (Pa, before the stress concentration):
    /// +∞ below the endurance limit or for a zero range.
    pub fn cycles_to_failure(&self, range: f64) -> f64 {
        let s = self.stress_concentration * range;
        // A NaN range is no cycle either.
        if s.is_nan() || s <= 0.0 || s < self.endurance_limit {
            return f64::INFINITY;
        }
        let log_s = (s / PA_PER_MPA).log10();
        let (log_a, m) = match self.second {
            Some(branch) if s < self.knee_range() => branch,
            _ => (self.log_a1, self.m1),
        };
        10f64.powf(log_a - m * log_s)
    }

    /// Miner damage of `count` cycles (1 a full cycle, ½ a half cycle) of range `range` (Pa):
    /// count / N(range).
    #[inline]
    pub fn damage(&self, range: f64, count: f64) -> f64 {
        // Most cycles of a run are far below the endurance limit: no logarithm for them.
        if self.stress_concentration * range < self.endurance_limit {
            return 0.0;
        }
        count / self.cycles_to_failure(range)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_table_meets_its_knee_at_ten_million_cycles_at_its_fatigue_limit() {
        for &(name, m1, log_a1, log_a2, limit) in &DNV_AIR {
            let c = SnCurve::named(name).unwrap();
            // Both branches through (10⁷, limit): the table's three figures agree to its
            // rounding (3 decimals of log ā: 0.2 % of the range at m = 3).
            let s1 = 10f64.powf((log_a1 - 7.0) / m1);
            let s2 = 10f64.powf((log_a2 - 7.0) / DNV_M2);
            assert!((s1 / limit - 1.0).abs() < 2e-3, "{name}: {s1} vs {limit}");
            assert!((s2 / limit - 1.0).abs() < 2e-3, "{name}: {s2} vs {limit}");
            assert!(
                (c.knee_range() / (limit * 1e6) - 1.0).abs() < 5e-3,
                "{name}"
            );
            assert!(
                (c.range_at(1e7) / (limit * 1e6) - 1.0).abs() < 5e-3,
                "{name}"
            );
        }
        assert_eq!(SnCurve::default().name, "DNV-B1");
        assert_eq!(SnCurve::named("dnv-c").unwrap().name, "DNV-C");
        assert!(SnCurve::named("DNV-Z").is_none());
    }

    /// Miner's rule on a constant-amplitude history: n cycles of range Δσ do n / N(Δσ), with
    /// N(Δσ) = ā Δσ^(−m) read by hand from Table 2-1 (B1: log ā₁ = 15.117, m₁ = 4).
    #[test]
    fn miner_damage_of_constant_amplitude_is_n_over_n_of_the_curve() {
        let c = SnCurve::default();
        // 200 MPa: first branch. N = 10^(15.117 − 4 log₁₀ 200) = 10^(15.117 − 9.204120) = 818 239.
        let n = 10f64.powf(15.117 - 4.0 * 200f64.log10());
        assert!((n / 818_239.0 - 1.0).abs() < 1e-5, "{n}");
        assert!((c.cycles_to_failure(200e6) / n - 1.0).abs() < 1e-12);
        let cycles = 12_345.0;
        let damage: f64 = (0..12_345).map(|_| c.damage(200e6, 1.0)).sum();
        assert!((damage / (cycles / n) - 1.0).abs() < 1e-9);
        // Two half cycles are one cycle.
        assert_eq!(c.damage(200e6, 0.5) * 2.0, c.damage(200e6, 1.0));
        // Below the endurance limit (106.97 MPa): no damage at all.
        assert_eq!(c.damage(106e6, 1.0), 0.0);
        assert_eq!(c.cycles_to_failure(50e6), f64::INFINITY);
        // Without a cut-off the second branch counts: 100 MPa, N = 10^(17.146 − 5 · 2).
        let open = SnCurve {
            endurance_limit: 0.0,
            ..SnCurve::default()
        };
        assert!((open.cycles_to_failure(100e6) / 10f64.powf(7.146) - 1.0).abs() < 1e-12);
        // A stress concentration of 2 reads 100 MPa as 200 MPa.
        let notched = SnCurve {
            stress_concentration: 2.0,
            ..SnCurve::default()
        };
        assert!((notched.cycles_to_failure(100e6) / n - 1.0).abs() < 1e-12);
        assert_eq!(c.damage(0.0, 1.0), 0.0);
    }
}
