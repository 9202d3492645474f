//! The bit's velocity-weakening torque against the pipe's torsional impedance.
//!
//! Linearised about steady drilling (u̇ = V0, θ̇ = Ω), a bit law's torque on the string changes
//! with the bit's spin as δT = c δθ̇, c = ∂T_BR/∂θ̇ (N·m·s): c > 0 when the torque weakens with
//! speed, a negative damping that feeds torsional motion. A semi-infinite pipe carries a
//! disturbance of the bit's spin away as a torsional wave, with the reaction −Z δθ̇ of its
//! characteristic impedance Z = √(κ_t G J · ρ J) (N·m·s; Graff, *Wave Motion in Elastic Solids*,
//! 1975, §2.1, for the impedance of a rod). The bit with its polar inertia J_b then obeys
//! J_b δω̇ = (c − Z) δω: it is stable on its own when c < Z and grows at the rate (c − Z)/J_b
//! otherwise, feeding waves of every length into the string. A wave reflected at the bit returns
//! |(Z + c + iωJ_b)/(Z − c + iωJ_b)| times larger: above 1 at every frequency when c > 0, and
//! unbounded at low frequency as c → Z. The ratio c/Z is reported as the metric
//! `bit_damping_ratio`: above 1 the answer of the model is set by the shortest torsional waves it
//! holds (docs/model.md, "Converged model": at 40 rpm and 20 m/h on the seed, ratio 1.97, 8 to 32
//! torsional modes give stick fractions from 11 % to 0 %). The excess gain of a reflection falls
//! as ω⁻² at high frequency (|R|² − 1 ≈ 4Zc/(ωJ_b)²), so a damping that grows as ω², the
//! stiffness-proportional β K of `[model.pipe] stiffness_damping` (a modal decay rate βω²/2),
//! bounds the waves the bit feeds and restores a converged answer.

use crate::model::{Drillstring, OperatingPoint, Section};

/// The characteristic torsional impedance of the string's pipe at the bit (its last section's),
/// √(κ_t G J · ρ J), N·m·s.
pub fn torsional_impedance(string: &Drillstring) -> f64 {
    let s = Section::of(&string.bit_section());
    (s.torsional_rigidity * s.polar_inertia).sqrt()
}

/// c / Z: the bit law's ∂T_BR/∂θ̇ at u̇ = V0, θ̇ = Ω over the pipe's torsional impedance
/// (dimensionless; positive for a torque that weakens with speed; 0 off bottom, V0 ≤ 0).
pub fn bit_damping_ratio(string: &Drillstring, op: OperatingPoint) -> f64 {
    string.bit.load(op.v0, op.omega).dtorque_dspin / torsional_impedance(string)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::problem::Problem;
    use std::f64::consts::PI;

    fn seed() -> Drillstring {
        Problem::load(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/problems/seed_mc2014.toml"
        ))
        .expect("the seed loads")
        .model
    }

    /// The seed's ratio from its data by hand: Cowper's κ for R_int/R_ext = 2/3, ν = 0.3, the
    /// paper's κ_t = κ_s, and TOB = μ WOB ξ(Ω) with WOB = Γ(1 − e^(−α V0)).
    #[test]
    fn seed_ratio_from_its_data() {
        let string = seed();
        let (ro, ri, e, nu, rho) = (0.06_f64, 0.04_f64, 203e9, 0.3, 7900.0);
        let m2 = (ri / ro).powi(2);
        let a = (1.0 + m2).powi(2);
        let kappa = 6.0 * (1.0 + nu) * a / ((7.0 + 6.0 * nu) * a + (20.0 + 12.0 * nu) * m2);
        let j = PI / 2.0 * (ro.powi(4) - ri.powi(4));
        let g = e / (2.0 * (1.0 + nu));
        let z = (kappa * g * j * rho * j).sqrt();
        assert!((torsional_impedance(&string) / z - 1.0).abs() < 1e-12);
        assert!((z - 304.8).abs() < 0.5, "Z = {z}");
        for (rpm, m_per_h) in [(60.0, 5.0), (61.75, 29.46), (40.0, 20.0), (100.0, 20.0)] {
            let op = OperatingPoint {
                omega: rpm * PI / 30.0,
                v0: m_per_h / 3600.0,
                wob: 0.0,
            };
            let wob = 250e3 * (1.0 - (-180.0 * op.v0).exp());
            let w = op.omega;
            let dxi = 1.0 - w.tanh().powi(2) + 2.0 * (1.0 - w * w) / (1.0 + w * w).powi(2);
            let expected = -0.04 * wob * dxi / z;
            let ratio = bit_damping_ratio(&string, op);
            assert!(
                (ratio / expected - 1.0).abs() < 1e-12,
                "{rpm} rpm: {ratio} vs {expected}"
            );
        }
        // The seed's point: 0.34; the high-feed and low-speed points of docs/model.md ("Converged model"): above 1.
        let at = |rpm: f64, m_per_h: f64| {
            bit_damping_ratio(
                &string,
                OperatingPoint {
                    omega: rpm * PI / 30.0,
                    v0: m_per_h / 3600.0,
                    wob: 0.0,
                },
            )
        };
        assert!((at(60.0, 5.0) - 0.341).abs() < 0.002, "{}", at(60.0, 5.0));
        assert!(at(61.75, 29.46) > 1.0 && at(40.0, 20.0) > 1.9);
    }

    #[test]
    fn off_bottom_there_is_no_negative_damping() {
        let op = OperatingPoint {
            omega: 2.0 * PI,
            v0: 0.0,
            wob: 0.0,
        };
        assert_eq!(bit_damping_ratio(&seed(), op), 0.0);
    }
}
