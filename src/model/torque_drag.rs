//! Soft-string torque and drag of a horizontal string in steady drilling (Johancsik, Friesen &
//! Dawson, "Torque and drag in directional wells — prediction and measurement", JPT 36(6),
//! 987–992, 1984; Aadnøy, *Mechanics of Drilling*, 2006, ch. 6).
//!
//! The string is a cable lying on the low side of a horizontal hole, of buoyed weight w_b per
//! length ([`super::Section::weight_mass`] · g); its contact points slip with the rigid motion
//! s = (V0, Ω R_ext), and Coulomb friction μN acts against the slip, split in the ratio of its
//! components:
//!
//!   c_a = V0 / S,  c_t = Ω R_ext / S,  S = √(V0² + (Ω R_ext)² + ε²)
//!
//! (ε the friction law's regularisation, so that the estimate is that of the simulated law).
//! A pipe that turns climbs the wall against its spin until the weight's component along the
//! wall balances the circumferential friction: w_b sin φ = μ N c_t with N = w_b cos φ, so
//!
//!   tan φ = μ c_t,   N = w_b cos φ = w_b / √(1 + (μ c_t)²)
//!
//! per length (the classical result for a shaft turning in a journal, e.g. Jansen, *Nonlinear
//! rotor dynamics as applied to oilwell drillstring vibrations*, JSV 147, 1991). Johancsik's
//! soft string takes N = w_b (φ = 0): 4.2 % more friction at μ = 0.3 and 11.8 % at 0.5 than a
//! string that has climbed; the simulated string climbs, so the estimate here does too. The
//! rigid motion also meets the mass-proportional damping C = c M_pipe (pipe mass only: c ρA V0 and
//! c ρJ Ω per length; the stiffness-proportional part carries no load of a rigid motion). With
//! the bit's steady loads WOB = −F_BR(V0) and TOB = −T_BR(Ω), the axial compression and the
//! transmitted torque grow linearly from the bit to the top:
//!
//!   C(x) = WOB + d_a (L − x),  d_a = μ w_b c_a + c ρA V0,
//!   T(x) = TOB + d_t (L − x),  d_t = μ w_b R_ext c_t + c ρJ Ω,
//!
//! so the top drive pushes with F_top = C(0) and turns with T_top = T(0). The paper's friction
//! ([`WallFriction::Paper`]) is a torque μ |F| R_bh tanh(Ω/ε) with no axial drag. The elastic
//! displacements relative to the rigid motion follow: u(x) = −∫₀ˣ C/EA, θ(x) = −∫₀ˣ T/(κ_t G J).
//!
//! What the estimate leaves out, and so where a simulated string departs from it: the supported
//! ends (the top drive and the bit hold the string at the hole's axis, so the last metres near
//! each end hang off the wall and their weight does not rub; a few per cent of a long string),
//! buckling (a compressed string pressed into a sinusoid or helix presses the wall harder: at the
//! helical load the extra contact force is of the order of the weight, Mitchell 1988), and the
//! climbing of the rotating pipe up the wall (it tilts the contact force, not its magnitude).

use super::{Drillstring, OperatingPoint, Section, WallFriction};

/// The steady soft-string state of a horizontal string at an operating point (SI, see the
/// module doc for the formulas and signs: forces and torques positive as the top drive applies
/// them, displacements relative to the rigid motion).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SoftString {
    /// Weight on bit −F_BR(V0), N.
    pub wob: f64,
    /// Torque on bit −T_BR(Ω), N·m.
    pub tob: f64,
    /// The wall's normal force per length N = w_b cos φ, N/m (w_b the buoyed weight).
    pub normal_per_length: f64,
    /// Climbing angle φ of the turning pipe on the low side, tan φ = μ c_t, rad (0 without
    /// circumferential friction).
    pub climb_angle: f64,
    /// Axial load per length d_a (friction and damping), N/m.
    pub drag_per_length: f64,
    /// Torque per length d_t (friction and damping), N·m/m.
    pub torque_per_length: f64,
    /// The friction's share of d_a and d_t, N/m and N·m/m.
    pub friction_drag_per_length: f64,
    pub friction_torque_per_length: f64,
    /// Top force F_top = WOB + d_a L, N.
    pub top_force: f64,
    /// Top torque T_top = TOB + d_t L, N·m.
    pub top_torque: f64,
    /// Elastic axial displacement of the bit, m (≤ 0: the string shortens).
    pub bit_displacement: f64,
    /// Elastic twist of the bit, rad (≤ 0 for Ω > 0: the bit lags the top).
    pub bit_twist: f64,
}

impl SoftString {
    /// The estimate for `string` at `op` (see the module doc). A string of sections
    /// ([`Drillstring::section_strings`]) is integrated section by section from the bit up: the
    /// top loads sum each section's drag and torque over its length, the bit's displacement and
    /// twist each section's compression and torque over its own EA and κ_t G J; the per-length
    /// fields and the climbing angle are then the length-weighted means over the sections.
    pub fn steady(string: &Drillstring, op: OperatingPoint) -> Self {
        if string.sections.is_empty() {
            return Self::uniform(string, op);
        }
        let sections: Vec<(Drillstring, SoftString)> = (string.section_strings().into_iter())
            .map(|s| {
                let estimate = Self::uniform(&s, op);
                (s, estimate)
            })
            .collect();
        let first = sections[0].1;
        let (mut force, mut torque) = (first.wob, first.tob);
        let (mut displacement, mut twist) = (0.0, 0.0);
        let mut mean = [0.0; 6];
        // From the bit up: `force` and `torque` are the loads at the section's lower end.
        for (sub, e) in sections.iter().rev() {
            let (l, sec) = (sub.length, Section::of(sub));
            displacement -= (force * l + 0.5 * e.drag_per_length * l * l) / sec.ea;
            twist -= (torque * l + 0.5 * e.torque_per_length * l * l) / sec.torsional_rigidity;
            force += e.drag_per_length * l;
            torque += e.torque_per_length * l;
            let fields = [
                e.normal_per_length,
                e.climb_angle,
                e.drag_per_length,
                e.torque_per_length,
                e.friction_drag_per_length,
                e.friction_torque_per_length,
            ];
            for (m, f) in mean.iter_mut().zip(fields) {
                *m += f * l / string.length;
            }
        }
        SoftString {
            wob: first.wob,
            tob: first.tob,
            normal_per_length: mean[0],
            climb_angle: mean[1],
            drag_per_length: mean[2],
            torque_per_length: mean[3],
            friction_drag_per_length: mean[4],
            friction_torque_per_length: mean[5],
            top_force: force,
            top_torque: torque,
            bit_displacement: displacement,
            bit_twist: twist,
        }
    }

    /// The estimate for a string of one section (its `pipe` over its `length`).
    fn uniform(string: &Drillstring, op: OperatingPoint) -> Self {
        let section = Section::of(string);
        let length = string.length;
        let bit = string.bit.load(op.v0, op.omega);
        let (wob, tob) = (-bit.force, -bit.torque);
        let w_b = section.weight_mass() * string.gravity;
        let mu = string.wall.law().friction();
        let rext = string.pipe.outer_radius;
        let (normal, climb_angle, friction_drag, friction_torque) = match string.wall_friction {
            WallFriction::Coulomb { slip_smoothing } => {
                let slip = [op.v0, op.omega * rext];
                let s = (slip[0] * slip[0] + slip[1] * slip[1] + slip_smoothing * slip_smoothing)
                    .sqrt();
                let climb = (mu * slip[1] / s).atan();
                let normal = w_b * climb.cos();
                (
                    normal,
                    climb,
                    mu * normal * slip[0] / s,
                    mu * normal * rext * slip[1] / s,
                )
            }
            WallFriction::Paper => {
                let law = string.wall.law();
                let torque = law.friction_torque(-w_b, string.borehole_radius, op.omega);
                (w_b, 0.0, 0.0, -torque)
            }
        };
        let drag = friction_drag + string.damping * section.pipe_mass * op.v0;
        let torque = friction_torque + string.damping * section.polar_inertia * op.omega;
        // ∫₀ᴸ (a + d (L − x)) dx = a L + d L²/2.
        let integral = |a: f64, d: f64| a * length + 0.5 * d * length * length;
        SoftString {
            wob,
            tob,
            normal_per_length: normal,
            climb_angle,
            drag_per_length: drag,
            torque_per_length: torque,
            friction_drag_per_length: friction_drag,
            friction_torque_per_length: friction_torque,
            top_force: wob + drag * length,
            top_torque: tob + torque * length,
            bit_displacement: -integral(wob, drag) / section.ea,
            bit_twist: -integral(tob, torque) / section.torsional_rigidity,
        }
    }

    /// The friction's part of the top force and of the top torque, N and N·m.
    pub fn friction_part(&self, length: f64) -> (f64, f64) {
        (
            self.friction_drag_per_length * length,
            self.friction_torque_per_length * length,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rotation_turns_drag_into_torque_in_the_ratio_of_the_slip() {
        let mut string = crate::problem::Problem::load(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/problems/seed_mc2014.toml"
        ))
        .unwrap()
        .model;
        string.damping = 0.0;
        // The seed's cubic wall with a field friction μ = 0.3.
        let wall = &crate::model::wall::WALL_LAWS[0];
        string.wall = crate::model::WallContact::from_entry(wall, &[1e10, 1e16, 1e-9, 0.3, 1e-3]);
        let op = OperatingPoint {
            omega: 2.0 * std::f64::consts::PI,
            v0: 1.0 / 720.0,
            wob: 0.0,
        };
        let s = SoftString::steady(&string, op);
        let w_b = Section::of(&string).weight_mass() * string.gravity;
        let mu = string.wall.law().friction();
        // The turning pipe climbs: tan φ = μ c_t, N = w_b cos φ; the friction per length is μN
        // in magnitude (ε ≪ the slip).
        let r = string.pipe.outer_radius;
        let c_t = op.omega * r / op.v0.hypot(op.omega * r);
        assert!((s.climb_angle.tan() - mu * c_t).abs() < 1e-6 * mu);
        let normal = w_b / (1.0 + (mu * c_t).powi(2)).sqrt();
        // (the law's ε enters c_t as ε²/(2|s|²) ≈ 4e-8 here)
        assert!((s.normal_per_length - normal).abs() < 1e-7 * normal);
        let total = s
            .friction_drag_per_length
            .hypot(s.friction_torque_per_length / r);
        assert!(
            (total - mu * normal).abs() < 1e-6 * mu * w_b,
            "{total} vs {}",
            mu * normal
        );
        let ratio = s.friction_drag_per_length / (s.friction_torque_per_length / r);
        assert!((ratio - op.v0 / (op.omega * r)).abs() < 1e-9);
        // Not turning: all of it is drag, none is torque, and the pipe does not climb.
        let sliding = SoftString::steady(&string, OperatingPoint { omega: 0.0, ..op });
        assert_eq!(sliding.climb_angle, 0.0);
        assert!((sliding.friction_drag_per_length - mu * w_b).abs() < 1e-2 * mu * w_b);
        assert_eq!(sliding.friction_torque_per_length, 0.0);
        // Top loads: bit loads plus the integral of the distributed ones.
        let l = string.length;
        assert!((s.top_torque - s.tob - s.torque_per_length * l).abs() < 1e-9 * s.top_torque);
        assert!(s.bit_twist < 0.0 && s.bit_displacement < 0.0);
    }
}
