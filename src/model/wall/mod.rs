//! Wall contact laws: the force and friction torque the borehole wall puts on a node of the
//! string that touches it (MODEL.md §5).
//!
//! A law is one type implementing [`WallContactLaw`] plus one [`WallLawEntry`] in [`WALL_LAWS`];
//! the problem file chooses it by name (`[model.wall] law = "…"`, the paper's `"cubic"` when
//! omitted), its parameters are read, checked and declared uncertain through the law's own
//! [`ParameterSpec`](super::ParameterSpec) table, and the simulator ([`crate::sim::wall_contact`])
//! calls [`WallContactLaw::normal`] and [`WallContactLaw::friction_torque`]. The geometry is the
//! simulator's, the same for every law: r = √(v² + w²), indentation δ = r − gap, the force acts
//! along the radius, and the wall never pulls (the caller clamps the normal force to ≤ 0).
//!
//! Sign conventions (all laws): δ > 0 is the node pressed into the wall, δ̇ > 0 moving further
//! in; the normal force on the string is F ≤ 0 (pushing the node back towards the axis); the
//! friction torque on θx opposes the spin θ̇x.

mod cubic;
mod friction;
mod hunt_crossley;
mod reading;

pub use cubic::Cubic;
pub use friction::WallFriction;
pub use hunt_crossley::HuntCrossley;
pub use reading::WallStiffnessPer;

use super::law::{Chosen, Law, LawEntry, law_kind};

/// The normal force of a law at one indentation and rate, split into its elastic and dissipative
/// parts, with its derivatives (SI), before the caller's clamp F ≤ 0.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct NormalForce {
    /// Elastic (conservative) part F_e(δ) ≤ 0, N.
    pub elastic: f64,
    /// Dissipative part F_d(δ, δ̇), N: opposes δ̇, so its power −F_d δ̇ is ≥ 0.
    pub dissipative: f64,
    /// ∂(F_e + F_d)/∂δ, N/m.
    pub dforce_dindentation: f64,
    /// ∂F_d/∂δ̇, N·s/m.
    pub dforce_drate: f64,
    /// Elastic energy stored in the wall, −∫₀^δ F_e dδ, J.
    pub energy: f64,
}

impl NormalForce {
    /// Every part and derivative multiplied by `factor` (the node's share of a per-length law,
    /// [`WallStiffnessPer::factor`]).
    #[inline]
    pub fn scaled(self, factor: f64) -> Self {
        NormalForce {
            elastic: factor * self.elastic,
            dissipative: factor * self.dissipative,
            dforce_dindentation: factor * self.dforce_dindentation,
            dforce_drate: factor * self.dforce_drate,
            energy: factor * self.energy,
        }
    }
}

/// A wall contact law: its name and parameters ([`Law`]), the normal force against the
/// indentation and its rate, and the friction torque.
pub trait WallContactLaw: Law + CloneWallContactLaw {
    /// Normal force at indentation `indentation` δ > 0 (m) changing at `rate` δ̇ (m/s).
    fn normal(&self, indentation: f64, rate: f64) -> NormalForce;
    /// Friction torque on θx, N·m, of a node pressed with normal force `normal` (≤ 0, N) on a
    /// wall of radius `radius` (the lever arm, m), spinning at `spin` θ̇x (rad/s). The simulator's
    /// Newton tangent leaves this torque out (it is small against the bit torque and smooth).
    fn friction_torque(&self, normal: f64, radius: f64, spin: f64) -> f64;
    /// The Coulomb friction coefficient μ of the wall, dimensionless (used by
    /// [`WallFriction::Coulomb`] on the slip of the contact point).
    fn friction(&self) -> f64;
}

law_kind!(WallContactLaw, CloneWallContactLaw);

/// Coulomb friction with a smooth sign, the friction of every law here (MODEL.md §5, Eq. (3)
/// with |F| so that friction always opposes the spin):
/// T = −μ |F| R tanh(θ̇x/ε), N·m.
#[inline]
pub fn coulomb_torque(friction: f64, smoothing: f64, normal: f64, radius: f64, spin: f64) -> f64 {
    let slip = (spin / smoothing).tanh();
    -friction * normal.abs() * radius * slip
}

/// A wall contact law as the registry knows it.
pub type WallLawEntry = LawEntry<dyn WallContactLaw>;

/// Every wall contact law drillopt knows; the first, the seed paper's, is the default when a
/// file names none.
pub const WALL_LAWS: &[WallLawEntry] = &[cubic::ENTRY, hunt_crossley::ENTRY];

/// The registry entry of the law called `name`.
pub fn wall_law(name: &str) -> Option<&'static WallLawEntry> {
    super::law::find(WALL_LAWS, name)
}

/// The wall contact law of a drillstring: any [`WallContactLaw`], cloneable and comparable.
pub type WallContact = Chosen<dyn WallContactLaw>;

/// Canonical form (cache keys). The default law is written as its parameters alone,
/// `{"stiffness": …, "cubic_stiffness": …, …}`, the form the wall had when it was the only law,
/// so that the model hash of every problem file written then is unchanged; any other law as
/// `{"law": name, "parameters": {key: value, …}}`, as the bit laws are.
impl serde::Serialize for WallContact {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        if self.law().name() == WALL_LAWS[0].name {
            self.serialize_flat(serializer)
        } else {
            self.serialize_named(serializer)
        }
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// Central differences of ∂F/∂δ and ∂F/∂δ̇ of `law` at (δ, δ̇), and of the elastic energy
    /// (−dE/dδ = F_e), relative to the scale of each, within `tol`.
    pub(crate) fn check_derivatives(law: &dyn WallContactLaw, delta: f64, rate: f64, tol: f64) {
        let f = law.normal(delta, rate);
        let total = |n: NormalForce| n.elastic + n.dissipative;
        let (hd, hr) = (1e-6 * delta, 1e-6 * rate.abs().max(1e-3));
        let (pd, md) = (law.normal(delta + hd, rate), law.normal(delta - hd, rate));
        let (pr, mr) = (law.normal(delta, rate + hr), law.normal(delta, rate - hr));
        let cases = [
            (
                "dF/dδ",
                (total(pd) - total(md)) / (2.0 * hd),
                f.dforce_dindentation,
            ),
            // The elastic part does not depend on δ̇: difference the dissipative part alone.
            (
                "dF/dδ̇",
                (pr.dissipative - mr.dissipative) / (2.0 * hr),
                f.dforce_drate,
            ),
            ("-dE/dδ", -(pd.energy - md.energy) / (2.0 * hd), f.elastic),
        ];
        for (name, fd, exact) in cases {
            assert!(
                (fd - exact).abs() <= tol * exact.abs().max(1e-300),
                "{} {name}: finite difference {fd}, derivative {exact}",
                law.name()
            );
        }
    }

    #[test]
    fn every_registered_law_builds_from_its_defaults_and_pushes_and_dissipates() {
        for law in crate::model::law::tests::check_registry(WALL_LAWS) {
            let law = law.law();
            let name = law.name();
            // Pressed in and approaching: the wall pushes back and absorbs energy.
            let f = law.normal(1e-4, 0.1);
            assert!(f.elastic < 0.0 && f.dissipative <= 0.0, "{name}: {f:?}");
            assert!(f.energy > 0.0 && f.dforce_dindentation < 0.0, "{name}");
            // Leaving: the dissipative part still opposes the motion.
            assert!(law.normal(1e-4, -0.1).dissipative >= 0.0, "{name}");
            // Friction opposes the spin, whatever the sign of the normal force given.
            let t = law.friction_torque(f.elastic, 0.07, 6.0);
            assert!(t <= 0.0, "{name}");
            assert_eq!(law.friction_torque(f.elastic, 0.07, -6.0), -t, "{name}");
            check_derivatives(law, 1e-4, 0.1, 1e-6);
            check_derivatives(law, 3e-3, -0.2, 1e-6);
        }
    }

    #[test]
    fn the_default_law_keeps_the_canonical_form_of_the_only_law_it_was() {
        let values: Vec<f64> = WALL_LAWS[0]
            .parameters
            .iter()
            .map(|p| p.default.unwrap_or(p.example))
            .collect();
        let wall = WallContact::from_entry(&WALL_LAWS[0], &values);
        let json = serde_json::to_string(&wall).unwrap();
        assert_eq!(
            json,
            r#"{"stiffness":10000000000.0,"cubic_stiffness":1e+16,"damping":100000000.0,"friction":0.25,"sign_smoothing":0.001}"#
        );
        let hc = &WALL_LAWS[1];
        let values: Vec<f64> = hc
            .parameters
            .iter()
            .map(|p| p.default.unwrap_or(p.example))
            .collect();
        let json = serde_json::to_string(&WallContact::from_entry(hc, &values)).unwrap();
        assert!(
            json.starts_with(r#"{"law":"hunt_crossley","parameters":{"model.wall.stiffness":"#),
            "{json}"
        );
    }
}
