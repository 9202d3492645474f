//! The depth-of-cut law of a drag bit with the state-dependent delay of Richard, Germay &
//! Detournay (MODEL.md §11.7).
//!
//! Richard, Germay & Detournay (2007), "A simplified model to explore the root cause of
//! stick–slip vibrations in drilling systems with drag bits", J. Sound Vib. 305:432–456, and
//! Germay, Denoël & Detournay (2009), "Multiple mode analysis of the self-excited vibrations of
//! rotary drilling systems", J. Sound Vib. 325:362–381: a bit of n identical blades, each
//! cutting the rock the blade ahead of it left, cuts a depth per revolution
//!
//! d(t) = n (u(t) − u(t − t_n)),  t_n the time the bit took to turn the last 2π/n,
//!
//! and the rock answers with Detournay & Defourny's (1992) cutting and wear-flat forces
//! ([`super::Detournay`]):
//!
//! W = ζ ε a d + W_f,  T = ½ ε a² d + ½ μ γ a W_f,  W_f = σ a ℓ while the flats press on the rock.
//!
//! The delay is where the bit was one blade period ago, so the rock surface the blades left is
//! state: the simulator keeps it ([`crate::sim::RockSurface`], a function of the bit's angle
//! that also gives genuine bit-bounce: when the bit is above the surface, d ≤ 0, there is
//! neither force nor torque, and the bit lands again where the surface is).
//!
//! drillopt's regularisation of the set-valued contacts (stated so it can be checked): the wear
//! flats press with W_f = σ a ℓ · h(u̇) · g(d), h = ½ (1 + tanh(u̇/v_r)) (the set [0, σaℓ] of
//! the flats' force while the bit stands still axially, smoothly: σaℓ/2 at u̇ = 0, the whole of
//! it advancing, none rising; a smooth h matters because the delay makes the axial motion
//! unstable and the bit spends whole phases near u̇ = 0) and g = tanh(d/d_r) (the flats touch
//! the rock smoothly as the bit lands); the
//! torque's sign follows tanh(θ̇/ω_r). The cutting force ζ ε a d acts whenever d > 0: a bit
//! pressed into the rock without turning meets a stiffness n ζ ε a per metre of axial motion
//! instead of cutting. For d ≫ d_r, u̇ ≫ v_r and θ̇ ≫ ω_r this is the law above, and at constant
//! Ω and V (d = 2π V/Ω) it is Detournay & Defourny's law, the quasi-static law
//! [`super::Detournay`] without its regularised depth (tested).

use super::detournay::PARAMETERS as DETOURNAY;
use super::{BitLawEntry, BitLoad, BitRockLaw};
use crate::model::law::law_with_fields;
use crate::model::parameters::ParameterSpec;
use crate::units::{Dimension, Range};
use std::f64::consts::PI;

/// Parameters of the depth-of-cut law, SI.
#[derive(Debug, Clone, PartialEq)]
pub struct Rgd {
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
    /// Bit-geometry factor γ, dimensionless.
    pub geometry: f64,
    /// Number of blades n (a whole number).
    pub blades: f64,
    /// Spin regularisation ω_r, rad/s.
    pub spin_smoothing: f64,
    /// Wear-flat engagement velocity v_r, m/s.
    pub velocity_smoothing: f64,
    /// Wear-flat landing depth d_r (per revolution), m.
    pub contact_smoothing: f64,
}

const PARAMETERS: [ParameterSpec; 11] = [
    DETOURNAY[0],
    DETOURNAY[1],
    DETOURNAY[2],
    DETOURNAY[3],
    DETOURNAY[4],
    DETOURNAY[5],
    DETOURNAY[6],
    ParameterSpec {
        key: "model.bit.blades",
        dimension: Dimension::Dimensionless,
        range: Range::integer(
            1.0,
            16.0,
            "the blades of a PDC bit: 3 to 8 for most, 1 for a single cutter",
        ),
        default: None,
        example: 4.0,
        doc: "number of blades n: each cuts the rock the one ahead of it left, 2π/n earlier",
    },
    DETOURNAY[7],
    DETOURNAY[8],
    ParameterSpec {
        key: "model.bit.contact_smoothing",
        dimension: Dimension::Length,
        // The flats' force σaℓ tanh(d/d_r) has the slope σaℓ/d_r at landing: below 0.1 µm per
        // revolution a step the Newton matrix cannot follow; above 0.1 mm comparable with the
        // depth of cut of slow drilling (1 m/h at 200 rpm cuts 0.08 mm per revolution).
        range: Range::closed(
            1e-7,
            1e-4,
            "small against the depth of cut per revolution, at least 0.1 µm",
        ),
        default: Some(1e-5),
        example: 1e-5,
        doc: "d_r: the wear flats land as tanh(d/d_r), d the depth of cut per revolution",
    },
];

law_with_fields!(
    Rgd: BitLawEntry,
    "rgd",
    "drag-bit depth of cut with the blades' delay, d = n (u(t) − u(t − t_n)), W = ζεad + σaℓ, T = ½εa²d + ½μγaσaℓ, none off bottom (Richard, Germay & Detournay 2007)",
    PARAMETERS,
    [
        radius,
        specific_energy,
        cutting_force_ratio,
        contact_strength,
        wear_flat_length,
        friction,
        geometry,
        blades,
        spin_smoothing,
        velocity_smoothing,
        contact_smoothing,
    ]
);

impl BitRockLaw for Rgd {
    fn radius(&self) -> Option<f64> {
        Some(self.radius)
    }

    /// The quasi-static form: the depth of cut of steady drilling, the pitch of the helix the
    /// blades cut, d = 2π u̇/max(|θ̇|, ω_r) (geometric, so that a run started on it is a steady
    /// state of the delay law; ω_r only keeps it finite for a bit that does not turn).
    fn load(&self, vel: f64, spin: f64) -> BitLoad {
        if vel <= 0.0 {
            return BitLoad::default();
        }
        let w_hat = spin.abs().max(self.spin_smoothing);
        let d = 2.0 * PI * vel / w_hat;
        let dd_dvel = 2.0 * PI / w_hat;
        let dd_dspin = if spin.abs() > self.spin_smoothing {
            -d * spin.signum() / w_hat
        } else {
            0.0
        };
        let b = self.load_at_depth(d, vel, spin);
        BitLoad {
            force: b.force,
            torque: b.torque,
            dforce_dvel: b.dforce_dvel + b.dforce_ddepth * dd_dvel,
            dforce_dspin: b.dforce_dspin + b.dforce_ddepth * dd_dspin,
            dtorque_dvel: b.dtorque_dvel + b.dtorque_ddepth * dd_dvel,
            dtorque_dspin: b.dtorque_dspin + b.dtorque_ddepth * dd_dspin,
            ..BitLoad::default()
        }
    }

    fn blades(&self) -> Option<u32> {
        Some(self.blades as u32)
    }

    fn load_at_depth(&self, depth: f64, vel: f64, spin: f64) -> BitLoad {
        if depth <= 0.0 {
            return BitLoad::default();
        }
        let (a, eps) = (self.radius, self.specific_energy);
        let g = (depth / self.contact_smoothing).tanh();
        let dg = (1.0 - g * g) / self.contact_smoothing;
        let x = (vel / self.velocity_smoothing).tanh();
        let (h, dh) = (
            0.5 * (1.0 + x),
            0.5 * (1.0 - x * x) / self.velocity_smoothing,
        );
        let s = (spin / self.spin_smoothing).tanh();
        let ds = (1.0 - s * s) / self.spin_smoothing;
        let flats = self.contact_strength * a * self.wear_flat_length;
        let arm = 0.5 * self.friction * self.geometry * a;
        let (cut_w, cut_t) = (self.cutting_force_ratio * eps * a, 0.5 * eps * a * a);
        let wf = flats * h * g;
        let wob = cut_w * depth + wf;
        let tob = cut_t * depth + arm * wf;
        BitLoad {
            force: -wob,
            torque: -tob * s,
            dforce_dvel: -flats * dh * g,
            dforce_dspin: 0.0,
            dtorque_dvel: -s * arm * flats * dh * g,
            dtorque_dspin: -tob * ds,
            dforce_ddepth: -(cut_w + flats * h * dg),
            dtorque_ddepth: -s * (cut_t + arm * flats * h * dg),
        }
    }

    fn steady_depth(&self, vel: f64, spin: f64) -> f64 {
        2.0 * PI * vel.max(0.0) / spin.abs().max(self.spin_smoothing)
    }
}

#[cfg(test)]
mod tests {
    use super::super::Detournay;
    use super::*;

    fn example() -> Rgd {
        let v: Vec<f64> = PARAMETERS.iter().map(|p| p.example).collect();
        Rgd::from_values(&v)
    }

    fn detournay() -> Detournay {
        let v: Vec<f64> = DETOURNAY.iter().map(|p| p.example).collect();
        Detournay::from_values(&v)
    }

    #[test]
    fn its_quasi_static_form_is_detournay_and_defournys_law() {
        // At constant Ω and V the blades cut the helix d = 2πV/Ω per revolution whatever their
        // number, and the rock answers with Detournay & Defourny's phase-II law (the flats fully
        // engaged: V ≫ v_r, d ≫ d_r), computed here from the raw numbers.
        let r = example();
        let (a, eps, zeta, sigma, ell, mu) = (0.108, 100e6, 0.6, 60e6, 1e-3, 0.6);
        // (Ω ≥ 8 rad/s: the torque's sign tanh(Ω/ω_r) is 1 to 1e-13.)
        for (v, w) in [
            (10.0 / 3600.0, 4.0 * PI),
            (30.0 / 3600.0, 8.0),
            (2e-3, 20.0),
        ] {
            let d = 2.0 * PI * v / w;
            let wob = zeta * eps * a * d + sigma * a * ell;
            let tob = 0.5 * eps * a * a * d + 0.5 * mu * a * sigma * a * ell;
            let l = r.load(v, w);
            assert!((-l.force / wob - 1.0).abs() < 1e-12, "WOB at ({v}, {w})");
            assert!((-l.torque / tob - 1.0).abs() < 1e-12, "TOB at ({v}, {w})");
            // The depth form at the steady depth is the same load.
            let c = r.load_at_depth(r.steady_depth(v, w), v, w);
            assert_eq!((c.force, c.torque), (l.force, l.torque));
        }
        // And Detournay's rate law, whose depth 2πV/√(Ω² + ω_r²) is regularised, differs from it
        // by (ω_r/Ω)²/2 of the cutting part at most.
        let det = detournay();
        let (v, w) = (10.0 / 3600.0, 4.0 * PI);
        let gap = (r.load(v, w).force / det.load(v, w).force - 1.0).abs();
        assert!(gap < 0.5 * (0.5 / w) * (0.5 / w), "{gap}");
    }

    #[test]
    fn the_load_follows_the_depth_of_cut_and_vanishes_above_the_rock() {
        let r = example();
        let (v, w) = (5.0 / 3600.0, 12.0);
        let (a, eps, zeta) = (0.108, 100e6, 0.6);
        // Well below the flats' landing depth nothing but the cutting force: continuous at 0.
        let tiny = r.load_at_depth(1e-12, v, w);
        assert!(tiny.force.abs() < 1e-2, "{tiny:?}");
        // On bottom: an increment of depth is pure cutting, ΔW = ζεa Δd, ΔT/ΔW = a/(2ζ).
        let (l1, l2) = (r.load_at_depth(1e-3, v, w), r.load_at_depth(2e-3, v, w));
        let dw = -(l2.force - l1.force);
        assert!((dw / (zeta * eps * a * 1e-3) - 1.0).abs() < 1e-12, "{dw}");
        let ratio = (l2.torque - l1.torque) / (l2.force - l1.force);
        assert!((ratio * 2.0 * zeta / a - 1.0).abs() < 1e-3, "{ratio}");
        // Rising (u̇ = −10 v_r): the flats let go, the cutters still bite.
        let up = r.load_at_depth(1e-3, -1e-3, w);
        assert!((-up.force - zeta * eps * a * 1e-3).abs() < 1e-3, "{up:?}");
        // Standing still axially: half the flats' force, the middle of the set [0, σaℓ].
        let still = r.load_at_depth(1e-3, 0.0, w);
        let flats = 60e6 * a * 1e-3;
        assert!((-still.force - zeta * eps * a * 1e-3 - 0.5 * flats).abs() < 1e-6);
    }

    #[test]
    fn derivatives_match_finite_differences() {
        let r = example();
        for (v, w) in [(1.4e-3, 6.3), (2e-4, 0.3), (3e-3, 12.0)] {
            super::super::tests::check_derivatives(&r, v, w, 1e-6);
        }
        for (d, v, w) in [(1e-3, 1e-3, 6.0), (2e-5, 5e-5, 0.2), (4e-6, -1e-4, -0.3)] {
            let b = r.load_at_depth(d, v, w);
            let h = 1e-6 * d;
            let (p, m) = (r.load_at_depth(d + h, v, w), r.load_at_depth(d - h, v, w));
            let fd = |x: f64, y: f64| (x - y) / (2.0 * h);
            let close = |x: f64, y: f64| (x - y).abs() <= 1e-6 * y.abs().max(1.0);
            assert!(close(fd(p.force, m.force), b.dforce_ddepth), "{d}");
            assert!(close(fd(p.torque, m.torque), b.dtorque_ddepth), "{d}");
        }
    }

    #[test]
    fn blades_are_a_whole_number() {
        let spec = &PARAMETERS[7];
        assert_eq!(spec.key, "model.bit.blades");
        assert!(spec.range.contains(6.0) && !spec.range.contains(4.5));
        assert_eq!(example().blades(), Some(4));
    }
}
