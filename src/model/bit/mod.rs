//! Bit–rock interaction laws: the force and torque the rock puts on the bit (MODEL.md §6).
//!
//! A law is one type implementing [`BitRockLaw`] plus one [`BitLawEntry`] in [`BIT_LAWS`]; the
//! problem file chooses it by name (`[model.bit] law = "…"`), its parameters are read, checked and
//! declared uncertain through the law's own [`ParameterSpec`](super::ParameterSpec) table, and the simulator calls
//! [`BitRockLaw::load`]. Nothing else in drillopt knows which law runs.
//!
//! Sign conventions (all laws): the axial coordinate u points from the top drive to the bit, so
//! u̇ > 0 is the bit advancing into the rock; θ̇ > 0 is the top drive's sense of rotation. The
//! force on the string is F ≤ 0 (WOB = −F) and the torque T opposes positive spin (TOB = −T).
//! Off bottom (u̇ ≤ 0) every law gives neither force nor torque: bit-bounce.

mod detournay;
mod exponential;
mod impedance;

pub use detournay::Detournay;
pub use exponential::{Exponential, xi};
pub use impedance::{bit_damping_ratio, torsional_impedance};

use super::law::{Chosen, Law, LawEntry, law_kind};

/// Bit force and torque on the string with their derivatives (SI).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct BitLoad {
    /// Axial force on the string F_BR ≤ 0, N.
    pub force: f64,
    /// Torque on the string T_BR, N·m (opposes positive spin).
    pub torque: f64,
    /// ∂F_BR/∂u̇, N·s/m.
    pub dforce_dvel: f64,
    /// ∂F_BR/∂θ̇, N·s (zero for laws whose WOB does not depend on the spin).
    pub dforce_dspin: f64,
    /// ∂T_BR/∂u̇, N·s.
    pub dtorque_dvel: f64,
    /// ∂T_BR/∂θ̇, N·m·s.
    pub dtorque_dspin: f64,
}

/// A bit–rock interaction law: its name and parameters ([`Law`]), and the load it puts on the
/// string.
pub trait BitRockLaw: Law + CloneBitRockLaw {
    /// Force and torque on the string at bit axial velocity `vel` (m/s) and spin `spin` (rad/s).
    fn load(&self, vel: f64, spin: f64) -> BitLoad;
}

law_kind!(BitRockLaw, CloneBitRockLaw);

/// A bit–rock law as the registry knows it.
pub type BitLawEntry = LawEntry<dyn BitRockLaw>;

/// Every bit–rock law drillopt knows; the first is the default when a file names none.
pub const BIT_LAWS: &[BitLawEntry] = &[exponential::ENTRY, detournay::ENTRY];

/// The registry entry of the law called `name`.
pub fn bit_law(name: &str) -> Option<&'static BitLawEntry> {
    super::law::find(BIT_LAWS, name)
}

/// The bit–rock law of a drillstring: any [`BitRockLaw`], cloneable and comparable.
pub type BitRock = Chosen<dyn BitRockLaw>;

impl BitRock {
    /// Force and torque with derivatives; see [`BitRockLaw::load`].
    #[inline]
    pub fn load(&self, vel: f64, spin: f64) -> BitLoad {
        self.law().load(vel, spin)
    }
}

/// Canonical form: `{"law": name, "parameters": {key: value, …}}` in table order (cache keys).
impl serde::Serialize for BitRock {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        self.serialize_named(serializer)
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// Central differences of every derivative of `law` at (vel, spin), relative to the scale of
    /// the load, within `tol`.
    pub(crate) fn check_derivatives(law: &dyn BitRockLaw, vel: f64, spin: f64, tol: f64) {
        let b = law.load(vel, spin);
        let (hv, hw) = (1e-7 * vel.abs().max(1e-6), 1e-6 * spin.abs().max(1e-3));
        let (pv, mv) = (law.load(vel + hv, spin), law.load(vel - hv, spin));
        let (pw, mw) = (law.load(vel, spin + hw), law.load(vel, spin - hw));
        let d = |p: f64, m: f64, h: f64| (p - m) / (2.0 * h);
        let cases = [
            (
                "dF/du̇",
                d(pv.force, mv.force, hv),
                b.dforce_dvel,
                b.force / vel,
            ),
            (
                "dF/dθ̇",
                d(pw.force, mw.force, hw),
                b.dforce_dspin,
                b.force / spin,
            ),
            (
                "dT/du̇",
                d(pv.torque, mv.torque, hv),
                b.dtorque_dvel,
                b.torque / vel,
            ),
            (
                "dT/dθ̇",
                d(pw.torque, mw.torque, hw),
                b.dtorque_dspin,
                b.torque / spin,
            ),
        ];
        for (name, fd, exact, scale) in cases {
            assert!(
                (fd - exact).abs() <= tol * scale.abs().max(exact.abs()),
                "{} {name}: finite difference {fd}, derivative {exact}",
                law.name()
            );
        }
    }

    #[test]
    fn every_registered_law_builds_from_its_defaults_and_round_trips_its_values() {
        for law in crate::model::law::tests::check_registry(BIT_LAWS) {
            // Off bottom nothing, whatever the spin.
            assert_eq!(law.load(0.0, 3.0), BitLoad::default());
            assert_eq!(law.load(-1e-3, -3.0), BitLoad::default());
        }
    }
}
