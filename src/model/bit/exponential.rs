//! The seed paper's bit–rock law (Cunha Jr, Soize & Sampaio 2014, Eqs. (4), (5); MODEL.md §6),
//! after Ritto, Soize & Sampaio (2009):
//!
//! F_BR = Γ (exp(−α u̇) − 1) for u̇ > 0, else 0 (F_BR ≤ 0: the rock resists the advance);
//! T_BR = −μ_BR |F_BR| ξ(θ̇), ξ(ω) = tanh ω + 2ω/(1 + ω²) (ω in rad/s as the paper writes it).
//! ξ is odd, rises to ≈ 1.8 near ω ≈ 1.4 rad/s and decays towards 1: velocity weakening.

use super::{BitLawEntry, BitLoad, BitRockLaw};
use crate::model::law::law_with_fields;
use crate::model::parameters::ParameterSpec;
use crate::units::{Dimension, Range};

/// Parameters of the exponential law, SI.
#[derive(Debug, Clone, PartialEq)]
pub struct Exponential {
    /// Limit force Γ_BR, N.
    pub limit_force: f64,
    /// Rate of change α_BR, s/m.
    pub rate: f64,
    /// Friction length μ_BR, m (torque = μ_BR |F_BR| ξ).
    pub friction: f64,
}

const PARAMETERS: [ParameterSpec; 3] = [
    ParameterSpec {
        key: "model.bit.limit_force",
        dimension: Dimension::Force,
        // Γ_BR is the rock's resistance: 0 (or 1e-300) drilled at any V0 with no weight on bit.
        range: Range::closed(1e3, 5e6, "from 1 kN to 5 MN on the bit"),
        default: None,
        example: 250e3,
        doc: "limit force Γ_BR, the WOB approached at high penetration rates",
    },
    ParameterSpec {
        key: "model.bit.rate",
        dimension: Dimension::InverseVelocity,
        // 1/α_BR is the feed at which the WOB reaches 63 % of Γ_BR: below 1 s/m that is beyond
        // 3600 m/h, and the bit offers no resistance at any admissible feed (1e-300 drilled at
        // 5 m/h with no weight on bit).
        range: Range::closed(
            1.0,
            1e5,
            "the bit law's α_BR; 1/α_BR, the feed of 63 % of Γ_BR, at most 3600 m/h",
        ),
        default: None,
        example: 180.0,
        doc: "rate of change α_BR of the force with the bit's axial velocity",
    },
    ParameterSpec {
        key: "model.bit.friction",
        dimension: Dimension::Length,
        range: Range::closed(0.0, 1.0, "μ_BR, a length of the order of the bit radius"),
        default: None,
        example: 0.04,
        doc: "friction length μ_BR: TOB = μ_BR · WOB · ξ(θ̇)",
    },
];

law_with_fields!(
    Exponential: BitLawEntry,
    "exponential",
    "the seed paper's law: WOB = Γ(1 − e^(−α u̇)), TOB = μ WOB ξ(θ̇) (Cunha Jr et al. 2014, Eqs. (4)-(5))",
    PARAMETERS,
    [limit_force, rate, friction]
);

/// The velocity-weakening function ξ(ω) and its derivative ξ′(ω).
pub fn xi(omega: f64) -> (f64, f64) {
    let t = omega.tanh();
    let d = 1.0 + omega * omega;
    (
        t + 2.0 * omega / d,
        1.0 - t * t + 2.0 * (1.0 - omega * omega) / (d * d),
    )
}

impl BitRockLaw for Exponential {
    fn load(&self, vel: f64, spin: f64) -> BitLoad {
        if vel <= 0.0 {
            return BitLoad::default();
        }
        let e = (-self.rate * vel).exp();
        let force = self.limit_force * (e - 1.0);
        let dforce_dvel = -self.limit_force * self.rate * e;
        let (x, dx) = xi(spin);
        let magnitude = -force;
        BitLoad {
            force,
            torque: -self.friction * magnitude * x,
            dforce_dvel,
            dforce_dspin: 0.0,
            dtorque_dvel: -self.friction * (-dforce_dvel) * x,
            dtorque_dspin: -self.friction * magnitude * dx,
            ..BitLoad::default()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn seed() -> Exponential {
        Exponential {
            limit_force: 250e3,
            rate: 180.0,
            friction: 0.04,
        }
    }

    #[test]
    fn seed_operating_point_values() {
        // V0 = 1/720 m/s: α u̇ = 0.25, F = −250 kN (1 − e^−0.25).
        let b = seed().load(1.0 / 720.0, 2.0 * std::f64::consts::PI);
        let f = -250e3 * (1.0 - (-0.25f64).exp());
        assert!((b.force - f).abs() < 1e-9 * f.abs());
        let (x, _) = xi(2.0 * std::f64::consts::PI);
        assert!((b.torque - 0.04 * f * x).abs() < 1e-9 * b.torque.abs());
        assert!(b.torque < 0.0, "the rock resists positive spin");
    }

    #[test]
    fn off_bottom_there_is_no_load() {
        assert_eq!(seed().load(0.0, 3.0), BitLoad::default());
        assert_eq!(seed().load(-1e-3, 3.0), BitLoad::default());
    }

    #[test]
    fn xi_is_odd_peaks_near_1_4_and_weakens_towards_one() {
        let (a, _) = xi(0.7);
        let (b, _) = xi(-0.7);
        assert_eq!(a, -b);
        let peak = (1..400)
            .map(|i| i as f64 * 0.01)
            .max_by(|p, q| xi(*p).0.total_cmp(&xi(*q).0))
            .unwrap();
        assert!((peak - 1.4).abs() < 0.2, "peak at {peak}");
        assert!(
            xi(2.0 * std::f64::consts::PI).1 < 0.0,
            "velocity weakening at 60 rpm"
        );
        assert!((xi(1e4).0 - 1.0).abs() < 1e-3);
    }

    #[test]
    fn derivatives_match_finite_differences() {
        super::super::tests::check_derivatives(&seed(), 1.3e-3, 2.1, 1e-6);
        let (w, h) = (2.1, 1e-6);
        let (x, dx) = xi(w);
        assert!(((xi(w + h).0 - xi(w - h).0) / (2.0 * h) - dx).abs() < 1e-8 && x > 1.0);
    }
}
