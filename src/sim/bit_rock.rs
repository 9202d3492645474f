//! Bit–rock interaction at x = L (MODEL.md §6, Eqs. (4), (5)).
//!
//! F_BR = Γ (exp(−α u̇) − 1) for u̇ > 0, else 0 (F_BR ≤ 0: the rock resists the advance);
//! T_BR = −μ_BR |F_BR| ξ(θ̇), ξ(ω) = tanh ω + 2ω/(1 + ω²) (ω in rad/s as the paper writes it).
//! ξ is odd, rises to ≈ 1.8 near ω ≈ 1.4 rad/s and decays towards 1: velocity weakening.
//! u̇ ≤ 0 (bit off bottom) gives neither force nor torque: bit-bounce.

use crate::model::BitRock;

/// Bit force and torque with their derivatives.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct BitLoad {
    /// Axial force on the string F_BR ≤ 0, N.
    pub force: f64,
    /// Torque on the string T_BR, N·m (opposes positive spin).
    pub torque: f64,
    /// ∂F_BR/∂u̇, N·s/m.
    pub dforce_dvel: f64,
    /// ∂T_BR/∂u̇, N·s.
    pub dtorque_dvel: f64,
    /// ∂T_BR/∂θ̇, N·m·s.
    pub dtorque_dspin: f64,
}

/// The velocity-weakening function ξ(ω) and its derivative ξ′(ω).
pub fn xi(omega: f64) -> (f64, f64) {
    let t = omega.tanh();
    let d = 1.0 + omega * omega;
    (
        t + 2.0 * omega / d,
        1.0 - t * t + 2.0 * (1.0 - omega * omega) / (d * d),
    )
}

/// Force and torque for bit axial velocity `vel` (m/s) and spin rate `spin` (rad/s).
pub fn bit_rock(law: &BitRock, vel: f64, spin: f64) -> BitLoad {
    if vel <= 0.0 {
        return BitLoad::default();
    }
    let e = (-law.rate * vel).exp();
    let force = law.limit_force * (e - 1.0);
    let dforce_dvel = -law.limit_force * law.rate * e;
    let (x, dx) = xi(spin);
    let magnitude = -force;
    BitLoad {
        force,
        torque: -law.friction * magnitude * x,
        dforce_dvel,
        dtorque_dvel: -law.friction * (-dforce_dvel) * x,
        dtorque_dspin: -law.friction * magnitude * dx,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn seed() -> BitRock {
        BitRock {
            limit_force: 250e3,
            rate: 180.0,
            friction: 0.04,
        }
    }

    #[test]
    fn seed_operating_point_values() {
        // V0 = 1/720 m/s: α u̇ = 0.25, F = −250 kN (1 − e^−0.25).
        let b = bit_rock(&seed(), 1.0 / 720.0, 2.0 * std::f64::consts::PI);
        let f = -250e3 * (1.0 - (-0.25f64).exp());
        assert!((b.force - f).abs() < 1e-9 * f.abs());
        let (x, _) = xi(2.0 * std::f64::consts::PI);
        assert!((b.torque - 0.04 * f * x).abs() < 1e-9 * b.torque.abs());
        assert!(b.torque < 0.0, "the rock resists positive spin");
    }

    #[test]
    fn off_bottom_there_is_no_load() {
        assert_eq!(bit_rock(&seed(), 0.0, 3.0), BitLoad::default());
        assert_eq!(bit_rock(&seed(), -1e-3, 3.0), BitLoad::default());
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
        let (v, w) = (1.3e-3, 2.1);
        let b = bit_rock(&seed(), v, w);
        let h = 1e-9;
        let (p, m) = (bit_rock(&seed(), v + h, w), bit_rock(&seed(), v - h, w));
        assert!(
            ((p.force - m.force) / (2.0 * h) - b.dforce_dvel).abs() < 1e-5 * b.dforce_dvel.abs()
        );
        assert!(
            ((p.torque - m.torque) / (2.0 * h) - b.dtorque_dvel).abs()
                < 1e-5 * b.dtorque_dvel.abs()
        );
        let h = 1e-6;
        let (p, m) = (bit_rock(&seed(), v, w + h), bit_rock(&seed(), v, w - h));
        assert!(
            ((p.torque - m.torque) / (2.0 * h) - b.dtorque_dspin).abs() < 1e-6 * b.torque.abs()
        );
        let (x, dx) = xi(w);
        assert!(((xi(w + h).0 - xi(w - h).0) / (2.0 * h) - dx).abs() < 1e-8 && x > 1.0);
    }
}
