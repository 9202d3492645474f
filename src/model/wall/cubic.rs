//! The seed paper's wall contact law (Cunha Jr, Soize & Sampaio 2014, Eqs. (2), (3), (13);
//! MODEL.md §5), after Ritto, Soize & Sampaio (2009):
//!
//! F = −k₁δ − k₂δ³ − c|δ|³δ̇ for δ > 0 (linear and cubic springs, and a damping that grows with
//! the indentation, in the spirit of Hunt & Crossley (1975), so the force is continuous at the
//! onset of contact); T = −μ |F| R_bh tanh(θ̇x/ε) [MODEL.md: |F|, so friction always opposes the
//! spin; tanh is drillopt's smooth sign, ε small against Ω].

use super::{NormalForce, WallContactLaw, WallLawEntry, coulomb_torque};
use crate::model::law::law_with_fields;
use crate::model::parameters::ParameterSpec;
use crate::units::{Dimension, Range};

/// Parameters of the cubic law, SI.
#[derive(Debug, Clone, PartialEq)]
pub struct Cubic {
    /// Linear contact stiffness k_FS1, N/m.
    pub stiffness: f64,
    /// Cubic contact stiffness k_FS2, N/m³.
    pub cubic_stiffness: f64,
    /// Contact damping c_FS, N·s/m⁴ (the force is c_FS |δ|³ δ̇).
    pub damping: f64,
    /// Coulomb friction coefficient μ_FS, dimensionless.
    pub friction: f64,
    /// Angular velocity ε of the smooth sign, sgn(ω) ≈ tanh(ω/ε), rad/s.
    pub sign_smoothing: f64,
}

/// Default smoothing of the friction sign, rad/s: small against any drilling speed (≥ 10 rpm ≈
/// 1 rad/s).
pub const DEFAULT_SIGN_SMOOTHING: f64 = 1e-3;

/// The friction coefficient of the wall and the smoothing of its sign, shared by the laws here.
pub(super) const FRICTION: ParameterSpec = ParameterSpec {
    key: "model.wall.friction",
    dimension: Dimension::Dimensionless,
    range: Range::closed(0.0, 2.0, "a Coulomb friction coefficient"),
    default: None,
    example: 0.25,
    doc: "Coulomb friction coefficient μ_FS of the wall (seed: 1e-5)",
};
pub(super) const SIGN_SMOOTHING: ParameterSpec = ParameterSpec {
    key: "model.wall.sign_smoothing",
    dimension: Dimension::AngularVelocity,
    // The torque's slope μ|F|R_bh/ε at θ̇ = 0: below 1 µrad/s a step the Newton matrix cannot
    // follow (the Coulomb law's slip_smoothing has the same kind of lower end).
    range: Range::closed(
        1e-6,
        10.0,
        "small against the rotation speed, at least 1 µrad/s",
    ),
    default: Some(DEFAULT_SIGN_SMOOTHING),
    example: DEFAULT_SIGN_SMOOTHING,
    doc: "ε of the friction's smooth sign tanh(θ̇x/ε) (drillopt's regularisation)",
};

const PARAMETERS: [ParameterSpec; 5] = [
    ParameterSpec {
        key: "model.wall.stiffness",
        dimension: Dimension::Stiffness,
        range: Range::closed(0.0, 1e14, "contact stiffness of rock"),
        default: None,
        example: 1e10,
        doc: "linear contact stiffness k_FS1 of the borehole wall (seed: 1e10 N/m)",
    },
    ParameterSpec {
        key: "model.wall.cubic_stiffness",
        dimension: Dimension::CubicStiffness,
        range: Range::closed(0.0, 1e22, "cubic contact stiffness"),
        default: None,
        example: 1e16,
        doc: "cubic contact stiffness k_FS2 of the borehole wall (seed: 1e16 N/m³)",
    },
    ParameterSpec {
        key: "model.wall.damping",
        dimension: Dimension::Dimensionless,
        range: Range::closed(0.0, 1e15, "contact damping c_FS, a bare number in N·s/m⁴"),
        default: None,
        example: 1e8,
        doc: "contact damping c_FS, N·s/m⁴: the force c_FS |δ|³ δ̇ (seed: 1e-9)",
    },
    FRICTION,
    SIGN_SMOOTHING,
];

law_with_fields!(
    Cubic: WallLawEntry,
    "cubic",
    "the seed paper's law: F = −k₁δ − k₂δ³ − c|δ|³δ̇, T = −μ|F|R_bh sgn(θ̇) (Cunha Jr et al. 2014, Eqs. (2)-(3))",
    PARAMETERS,
    [
        stiffness,
        cubic_stiffness,
        damping,
        friction,
        sign_smoothing
    ]
);

impl WallContactLaw for Cubic {
    #[inline]
    fn normal(&self, delta: f64, delta_dot: f64) -> NormalForce {
        let d3 = delta * delta * delta;
        NormalForce {
            elastic: -self.stiffness * delta - self.cubic_stiffness * d3,
            dissipative: -self.damping * d3 * delta_dot,
            dforce_dindentation: -self.stiffness
                - 3.0 * self.cubic_stiffness * delta * delta
                - 3.0 * self.damping * delta * delta * delta_dot,
            dforce_drate: -self.damping * d3,
            energy: 0.5 * self.stiffness * delta * delta
                + 0.25 * self.cubic_stiffness * delta.powi(4),
        }
    }

    #[inline]
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

    #[test]
    fn closed_form_at_the_seed_values() {
        let law = Cubic {
            stiffness: 1e10,
            cubic_stiffness: 1e16,
            damping: 1e9,
            friction: 0.3,
            sign_smoothing: 1e-3,
        };
        let (d, v) = (1e-4_f64, 0.2);
        let f = law.normal(d, v);
        assert_eq!(f.elastic, -(1e10 * d + 1e16 * d.powi(3)));
        assert!((f.dissipative + 1e9 * d.powi(3) * v).abs() < 1e-12 * 1e9 * d.powi(3) * v);
        let e = 0.5 * 1e10 * d * d + 0.25 * 1e16 * d.powi(4);
        assert!((f.energy - e).abs() < 1e-12 * e);
        // Full slip: T = −μ|F|R.
        let t = law.friction_torque(-1000.0, 0.07, 6.0);
        assert!((t + 0.3 * 1000.0 * 0.07).abs() < 1e-9);
        super::super::tests::check_derivatives(&law, d, v, 1e-6);
    }
}
