//! Hunt–Crossley contact: a spring with damping proportional to it, the damping set by a
//! coefficient of restitution.
//!
//! Hunt & Crossley (1975), "Coefficient of restitution interpreted as damping in vibroimpact",
//! J. Appl. Mech. 42(2):440–445, write F = −K δⁿ (1 + λ δ̇); here n = 1, a line contact (the pipe
//! lies along the wall; Hertz's n = 3/2 is a point contact), so K is a stiffness in N/m:
//!
//! F = −K δ (1 + λ δ̇)  for δ > 0,   λ = 3(1 − e) / (2 v_i),
//!
//! with e the coefficient of restitution of an impact at normal speed v_i. The damping vanishes
//! with δ, so the force is continuous at the onset of contact, unlike a spring–dashpot's. The
//! relation between λ and e is Hunt and Crossley's, to first order in 1 − e: the energy the
//! damping takes from an impact at v_i along the elastic path through the contact is
//! ΔE = (4/3) λ v_i E (for any n), and 1 − e² ≈ 2(1 − e); it is also Marhefka & Orin's (1999,
//! IEEE Trans. SMC-A 29(6):566–572) α = (2/3)λ, e ≈ 1 − α v_i. An impact at another speed v
//! rebounds with e ≈ 1 − (1 − e) v/v_i: the restitution falls with the impact speed, as measured
//! (Goldsmith 1960, *Impact*). Friction is Coulomb's with a smooth sign, as in the seed's law:
//! T = −μ |F| R_bh tanh(θ̇x/ε).

use super::cubic::{FRICTION, SIGN_SMOOTHING};
use super::{NormalForce, WallContactLaw, WallLawEntry, coulomb_torque};
use crate::model::law::law_with_fields;
use crate::model::parameters::ParameterSpec;
use crate::units::{Dimension, Range};

/// Parameters of the Hunt–Crossley law, SI.
#[derive(Debug, Clone, PartialEq)]
pub struct HuntCrossley {
    /// Contact stiffness K, N/m.
    pub stiffness: f64,
    /// Coefficient of restitution e at the impact speed v_i, dimensionless.
    pub restitution: f64,
    /// Normal impact speed v_i at which the restitution is e, m/s.
    pub impact_speed: f64,
    /// Coulomb friction coefficient μ, dimensionless.
    pub friction: f64,
    /// Angular velocity ε of the smooth sign, rad/s.
    pub sign_smoothing: f64,
}

const PARAMETERS: [ParameterSpec; 5] = [
    ParameterSpec {
        key: "model.wall.stiffness",
        dimension: Dimension::Stiffness,
        // A node resting on the wall under a few hundred newtons of weight sinks millimetres into
        // a wall of 1e5 N/m; softer is no wall (the cubic law's stiffness may be 0: its cubic
        // term holds the string).
        range: Range::closed(1e5, 1e14, "contact stiffness of rock, at least 100 kN/m"),
        default: None,
        example: 1e10,
        doc: "contact stiffness K of the borehole wall",
    },
    ParameterSpec {
        key: "model.wall.restitution",
        dimension: Dimension::Dimensionless,
        range: Range::closed(
            0.0,
            1.0,
            "a coefficient of restitution; the law is first order in 1 − e",
        ),
        default: None,
        example: 0.8,
        doc: "coefficient of restitution e of an impact at model.wall.impact_speed",
    },
    ParameterSpec {
        key: "model.wall.impact_speed",
        dimension: Dimension::Velocity,
        // λ = 3(1 − e)/(2 v_i): below 1 mm/s the damping makes a wall of tar.
        range: Range::closed(1e-3, 100.0, "a lateral impact speed, 1 mm/s to 100 m/s"),
        default: None,
        example: 0.1,
        doc: "normal impact speed v_i at which the restitution is e",
    },
    FRICTION,
    SIGN_SMOOTHING,
];

law_with_fields!(
    HuntCrossley: WallLawEntry,
    "hunt_crossley",
    "Hunt-Crossley contact F = −Kδ(1 + 3(1 − e)δ̇/(2v_i)), Coulomb friction (Hunt & Crossley 1975)",
    PARAMETERS,
    [
        stiffness,
        restitution,
        impact_speed,
        friction,
        sign_smoothing
    ]
);

impl HuntCrossley {
    /// The damping factor λ = 3(1 − e)/(2 v_i), s/m.
    pub fn damping_factor(&self) -> f64 {
        1.5 * (1.0 - self.restitution) / self.impact_speed
    }
}

impl WallContactLaw for HuntCrossley {
    fn normal(&self, delta: f64, delta_dot: f64) -> NormalForce {
        let lambda = self.damping_factor();
        let elastic = -self.stiffness * delta;
        NormalForce {
            elastic,
            dissipative: elastic * lambda * delta_dot,
            dforce_dindentation: -self.stiffness * (1.0 + lambda * delta_dot),
            dforce_drate: elastic * lambda,
            energy: 0.5 * self.stiffness * delta * delta,
        }
    }

    fn friction_torque(&self, normal: f64, radius: f64, spin: f64) -> f64 {
        coulomb_torque(self.friction, self.sign_smoothing, normal, radius, spin)
    }

    fn friction(&self) -> f64 {
        self.friction
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn law(restitution: f64) -> HuntCrossley {
        HuntCrossley {
            stiffness: 1e10,
            restitution,
            impact_speed: 0.2,
            friction: 0.3,
            sign_smoothing: 1e-3,
        }
    }

    #[test]
    fn closed_form_force_energy_and_derivatives() {
        let l = law(0.8);
        let (d, v) = (2e-4_f64, 0.1);
        let f = l.normal(d, v);
        let lambda = 1.5 * 0.2 / 0.2;
        assert_eq!(f.elastic, -1e10 * d);
        let fd = -1e10 * d * lambda * v;
        assert!((f.dissipative - fd).abs() < 1e-12 * fd.abs());
        assert!((f.energy - 0.5e10 * d * d).abs() < 1e-12 * f.energy);
        super::super::tests::check_derivatives(&l, d, v, 1e-6);
        super::super::tests::check_derivatives(&l, 3e-5, -0.4, 1e-6);
        // e = 1: no damping at all.
        assert_eq!(law(1.0).normal(1e-4, 0.3).dissipative, 0.0);
    }

    /// A mass m hitting the wall at v_i leaves it at e·v_i (to first order in 1 − e): the
    /// law's restitution, checked by integrating m δ̈ = F(δ, δ̇) through the contact (RK4,
    /// 20 000 steps per contact time; the force clamped at 0 as the simulator clamps it).
    fn rebound_speed(l: &HuntCrossley, mass: f64, v_in: f64) -> f64 {
        let accel = |d: f64, v: f64| {
            if d <= 0.0 {
                return 0.0;
            }
            let f = l.normal(d, v);
            (f.elastic + f.dissipative).min(0.0) / mass
        };
        // The contact time of the undamped spring is π√(m/K).
        let h = std::f64::consts::PI * (mass / l.stiffness).sqrt() / 20_000.0;
        let (mut d, mut v) = (0.0, v_in);
        for _ in 0..2_000_000 {
            let k1 = (v, accel(d, v));
            let k2 = (
                v + 0.5 * h * k1.1,
                accel(d + 0.5 * h * k1.0, v + 0.5 * h * k1.1),
            );
            let k3 = (
                v + 0.5 * h * k2.1,
                accel(d + 0.5 * h * k2.0, v + 0.5 * h * k2.1),
            );
            let k4 = (v + h * k3.1, accel(d + h * k3.0, v + h * k3.1));
            d += h / 6.0 * (k1.0 + 2.0 * k2.0 + 2.0 * k3.0 + k4.0);
            v += h / 6.0 * (k1.1 + 2.0 * k2.1 + 2.0 * k3.1 + k4.1);
            if d <= 0.0 && v < 0.0 {
                return -v;
            }
        }
        panic!("no rebound");
    }

    #[test]
    fn an_impact_at_the_reference_speed_rebounds_with_the_restitution() {
        for e in [0.95, 0.8] {
            let l = law(e);
            let v = rebound_speed(&l, 50.0, l.impact_speed);
            let e_sim = v / l.impact_speed;
            // First order in 1 − e: the error is O((1 − e)²) (0.9 (1 − e)² here).
            assert!(
                (e_sim - e).abs() < (1.0 - e) * (1.0 - e),
                "e = {e}: rebound {e_sim}"
            );
            // A restitution: the same whatever the mass that hits.
            let heavy = rebound_speed(&l, 5000.0, l.impact_speed) / l.impact_speed;
            assert!((heavy - e_sim).abs() < 1e-6, "{heavy} vs {e_sim}");
        }
        // Elastic: the speed comes back whole.
        let l = law(1.0);
        let v = rebound_speed(&l, 50.0, 0.2);
        assert!((v - 0.2).abs() < 1e-9, "{v}");
    }
}
