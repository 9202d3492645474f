//! Detournay's drag-bit response: cutting plus wear-flat friction, in rate form.
//!
//! Detournay & Defourny (1992), "A phenomenological model for the drilling action of drag bits",
//! Int. J. Rock Mech. Min. Sci. 29(1):13–23, split WOB and TOB of a PDC (drag) bit of radius a
//! drilling a depth d per revolution into a cutting and a frictional part:
//!
//! W = W_c + W_f,  T = T_c + T_f,  W_c = ζ ε a d,  T_c = ½ ε a² d,  T_f = ½ μ γ a W_f,
//!
//! with ε the intrinsic specific energy of the rock, ζ the ratio of the normal to the tangential
//! cutting force, μ the friction coefficient on the wear flats and γ a bit-geometry factor. In the
//! regime where the wear flats' contact is fully mobilised (phase II of Detournay, Richard &
//! Shepherd 2008, "Drilling response of drag bits: theory and experiment", Int. J. Rock Mech. Min.
//! Sci. 45:1347–1360) W_f = σ a ℓ, σ the contact strength and ℓ the total wear-flat length. The
//! same law drives the stick-slip model of Richard, Germay & Detournay (2007), J. Sound Vib.
//! 305:432–456, where the coupling d = 2π u̇/θ̇ (depth per revolution from the bit's axial and
//! angular velocities) is what makes the torque fall as the spin rises: velocity weakening
//! without a fitted weakening function.
//!
//! drillopt's rate form (our regularisation, stated so it can be checked): the bit's depth of cut
//! per revolution is d = 2π u̇ / ω̂ with ω̂ = √(θ̇² + ω_r²), which stays finite when the bit sticks;
//! the wear flats engage smoothly, W_f = σ a ℓ tanh(u̇ / v_r); the torque's sign follows
//! tanh(θ̇ / ω_r). For θ̇ ≫ ω_r and u̇ ≫ v_r this is the phase-II law above. Off bottom (u̇ ≤ 0)
//! there is no load. ω_r and v_r are numerical and must stay small against the operating Ω and V0.

use super::{BitLawEntry, BitLoad, BitRockLaw};
use crate::model::law::law_with_fields;
use crate::model::parameters::ParameterSpec;
use crate::units::{Dimension, Range};
use std::f64::consts::PI;

/// Parameters of Detournay's drag-bit law, SI.
#[derive(Debug, Clone, PartialEq)]
pub struct Detournay {
    /// Bit radius a, m.
    pub radius: f64,
    /// Intrinsic specific energy ε, Pa.
    pub specific_energy: f64,
    /// Ratio ζ of normal to tangential cutting force, dimensionless.
    pub cutting_force_ratio: f64,
    /// Contact strength σ of the wear flats, Pa.
    pub contact_strength: f64,
    /// Total wear-flat length ℓ, m.
    pub wear_flat_length: f64,
    /// Friction coefficient μ on the wear flats, dimensionless.
    pub friction: f64,
    /// Bit-geometry factor γ (1 for a flat-faced bit), dimensionless.
    pub geometry: f64,
    /// Spin regularisation ω_r, rad/s.
    pub spin_smoothing: f64,
    /// Wear-flat engagement velocity v_r, m/s.
    pub velocity_smoothing: f64,
}

pub(super) const PARAMETERS: [ParameterSpec; 9] = [
    ParameterSpec {
        key: "model.bit.radius",
        dimension: Dimension::Length,
        range: Range::closed(5e-3, 0.5, "a bit 1 cm to 1 m across"),
        default: None,
        example: 0.108,
        doc: "bit radius a (0.108 m: an 8½ in bit); or give `diameter`, the bit size (\"8.5 in\")",
    },
    ParameterSpec {
        key: "model.bit.specific_energy",
        dimension: Dimension::Pressure,
        // Below 1 MPa (softer than chalk) the bit would cut with no weight on it.
        range: Range::closed(
            1e6,
            2e9,
            "ε, of the order of the rock's compressive strength: 1 MPa to 2 GPa",
        ),
        default: None,
        example: 100e6,
        doc: "intrinsic specific energy ε (Detournay et al. 2008: 30-250 MPa in their tests)",
    },
    ParameterSpec {
        key: "model.bit.cutting_force_ratio",
        dimension: Dimension::Dimensionless,
        // Below 0.1 the cutters would cut without pressing on the rock.
        range: Range::closed(0.1, 5.0, "ζ, typically 0.5-0.9"),
        default: None,
        example: 0.6,
        doc: "ζ, normal over tangential cutting force",
    },
    ParameterSpec {
        key: "model.bit.contact_strength",
        dimension: Dimension::Pressure,
        range: Range::closed(0.0, 2e9, "σ, of the order of ε"),
        default: None,
        example: 60e6,
        doc: "contact strength σ of the wear flats",
    },
    ParameterSpec {
        key: "model.bit.wear_flat_length",
        dimension: Dimension::Length,
        range: Range::closed(0.0, 0.1, "ℓ, a few mm for a worn bit, 0 for a sharp one"),
        default: None,
        example: 1e-3,
        doc: "total wear-flat length ℓ",
    },
    ParameterSpec {
        key: "model.bit.friction",
        dimension: Dimension::Dimensionless,
        range: Range::closed(0.0, 2.0, "a Coulomb friction coefficient"),
        default: None,
        example: 0.6,
        doc: "friction coefficient μ on the wear flats",
    },
    ParameterSpec {
        key: "model.bit.geometry",
        dimension: Dimension::Dimensionless,
        range: Range::closed(0.1, 5.0, "γ, about 1 (1 to 4/3 for most bits)"),
        default: Some(1.0),
        example: 1.0,
        doc: "bit-geometry factor γ (1: flat-faced bit)",
    },
    ParameterSpec {
        key: "model.bit.spin_smoothing",
        dimension: Dimension::AngularVelocity,
        // A sticking bit cuts 2π u̇/ω_r per revolution: below 1 mrad/s that is metres at any feed.
        range: Range::closed(
            1e-3,
            10.0,
            "small against the rotation speed, at least 1 mrad/s",
        ),
        default: Some(0.5),
        example: 0.5,
        doc: "ω_r: the depth of cut is 2π u̇/√(θ̇² + ω_r²), finite when the bit sticks",
    },
    ParameterSpec {
        key: "model.bit.velocity_smoothing",
        dimension: Dimension::Velocity,
        // The wear flats' force σaℓ tanh(u̇/v_r) has the slope σaℓ/v_r: below 1 µm/s (3.6 mm/h,
        // far below the slowest feed, 0.1 m/h) a step function the Newton matrix cannot follow.
        range: Range::closed(1e-6, 0.01, "small against V0, at least 1 µm/s"),
        default: Some(1e-4),
        example: 1e-4,
        doc: "v_r: the wear flats engage as tanh(u̇/v_r)",
    },
];

law_with_fields!(
    Detournay: BitLawEntry,
    "detournay",
    "drag-bit cutting and wear-flat friction, W = ζεad + σaℓ, T = ½εa²d + ½μγaσaℓ, d = 2πu̇/θ̇ (Detournay & Defourny 1992; Detournay et al. 2008)",
    PARAMETERS,
    [
        radius,
        specific_energy,
        cutting_force_ratio,
        contact_strength,
        wear_flat_length,
        friction,
        geometry,
        spin_smoothing,
        velocity_smoothing,
    ]
);

impl Detournay {
    /// Depth of cut per revolution d = 2π u̇/ω̂, m, at the given velocities (u̇ > 0).
    pub fn depth_of_cut(&self, vel: f64, spin: f64) -> f64 {
        2.0 * PI * vel / spin.hypot(self.spin_smoothing)
    }
}

impl BitRockLaw for Detournay {
    fn radius(&self) -> Option<f64> {
        Some(self.radius)
    }

    fn load(&self, vel: f64, spin: f64) -> BitLoad {
        if vel <= 0.0 {
            return BitLoad::default();
        }
        let a = self.radius;
        let eps = self.specific_energy;
        let w_hat = spin.hypot(self.spin_smoothing);
        let d = 2.0 * PI * vel / w_hat;
        let dd_dvel = 2.0 * PI / w_hat;
        let dd_dspin = -d * spin / (w_hat * w_hat);
        let h = (vel / self.velocity_smoothing).tanh();
        let dh_dvel = (1.0 - h * h) / self.velocity_smoothing;
        let s = (spin / self.spin_smoothing).tanh();
        let ds_dspin = (1.0 - s * s) / self.spin_smoothing;
        let flats = self.contact_strength * a * self.wear_flat_length;
        let flats_torque_arm = 0.5 * self.friction * self.geometry * a;
        // WOB and TOB magnitudes and their derivatives.
        let wob = self.cutting_force_ratio * eps * a * d + flats * h;
        let cut_t = 0.5 * eps * a * a;
        let tob = cut_t * d + flats_torque_arm * flats * h;
        let dtob_dvel = cut_t * dd_dvel + flats_torque_arm * flats * dh_dvel;
        BitLoad {
            force: -wob,
            torque: -tob * s,
            dforce_dvel: -(self.cutting_force_ratio * eps * a * dd_dvel + flats * dh_dvel),
            dforce_dspin: -self.cutting_force_ratio * eps * a * dd_dspin,
            dtorque_dvel: -s * dtob_dvel,
            dtorque_dspin: -(s * cut_t * dd_dspin + tob * ds_dspin),
            ..BitLoad::default()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn example() -> Detournay {
        let v: Vec<f64> = PARAMETERS.iter().map(|p| p.example).collect();
        Detournay::from_values(&v)
    }

    #[test]
    fn far_from_the_regularisation_it_is_detournay_and_defournys_phase_two() {
        // 120 rpm, 10 m/h: d = 2π V/Ω = 1.389 mm per revolution.
        let b = example();
        let (omega, v) = (4.0 * PI, 10.0 / 3600.0);
        let d = 2.0 * PI * v / omega;
        let (a, eps, zeta) = (0.108, 100e6, 0.6);
        let wf = 60e6 * a * 1e-3;
        let wob = zeta * eps * a * d + wf;
        let tob = 0.5 * eps * a * a * d + 0.5 * 0.6 * 1.0 * a * wf;
        let l = b.load(v, omega);
        let rel = |x: f64, y: f64| (x - y).abs() / y.abs();
        // ω_r = 0.5 rad/s against Ω = 12.6 rad/s: d is (1 + (ω_r/Ω)²)^(-1/2) ≈ 1 − 8e-4 of 2πV/Ω.
        assert!(rel(-l.force, wob) < 1e-3, "WOB {} vs {wob}", -l.force);
        assert!(rel(-l.torque, tob) < 1e-3, "TOB {} vs {tob}", -l.torque);
        // In phase II the wear-flat part is constant, so an increment of depth of cut is pure
        // cutting: ΔT/ΔW = T_c/W_c = a/(2ζ) (Detournay & Defourny 1992).
        let l2 = b.load(2.0 * v, omega);
        let ratio = (l2.torque - l.torque) / (l2.force - l.force);
        assert!(rel(ratio, a / (2.0 * zeta)) < 1e-3, "ΔT/ΔW = {ratio}");
    }

    #[test]
    fn torque_weakens_with_spin_and_the_rock_resists_rotation() {
        let b = example();
        let v = 5.0 / 3600.0;
        let t = |w: f64| b.load(v, w).torque;
        assert!(t(2.0) < 0.0 && t(-2.0) > 0.0);
        assert!(t(2.0).abs() > t(4.0).abs() && t(4.0).abs() > t(8.0).abs());
        assert!(b.load(v, 4.0).dtorque_dspin > 0.0, "velocity weakening");
        // Sticking: depth of cut bounded by the regularisation, torque zero, WOB large but finite.
        let stuck = b.load(v, 0.0);
        assert_eq!(stuck.torque, 0.0);
        assert!((b.depth_of_cut(v, 0.0) - 2.0 * PI * v / 0.5).abs() < 1e-15);
        assert!(stuck.force.is_finite() && -stuck.force > -b.load(v, 2.0 * PI).force);
    }

    #[test]
    fn derivatives_match_finite_differences() {
        let b = example();
        for (v, w) in [(1.4e-3, 6.3), (2e-4, 0.3), (5e-5, -1.0), (3e-3, 12.0)] {
            super::super::tests::check_derivatives(&b, v, w, 1e-6);
        }
    }

    #[test]
    fn continuous_at_the_onset_of_contact() {
        let b = example();
        let l = b.load(1e-12, 6.0);
        assert!(l.force.abs() < 1e-3 && l.torque.abs() < 1e-3, "{l:?}");
    }
}
