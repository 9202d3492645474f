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
//! Off bottom every law gives neither force nor torque: bit-bounce. For the rate laws off bottom
//! is u̇ ≤ 0; for a depth-of-cut law ([`Rgd`]) it is a position: the bit above the rock its
//! blades left (depth of cut d ≤ 0).
//!
//! Two kinds of law share the trait. A *rate law* gives the load from the bit's velocities
//! ([`BitRockLaw::load`]). A *depth-of-cut law* ([`BitRockLaw::blades`] is `Some`) gives it from
//! the depth of cut d per revolution that the simulator reads off the rock surface the blades left
//! ([`crate::sim::RockSurface`], state of the run), [`BitRockLaw::load_at_depth`]; its
//! [`BitRockLaw::load`] is its quasi-static form (d = 2π u̇/θ̇), which the soft-string estimate and
//! the starting state use.

mod detournay;
mod exponential;
mod impedance;
mod rgd;

pub use detournay::Detournay;
pub use exponential::{Exponential, xi};
pub use impedance::{bit_damping_ratio, torsional_impedance};
pub use rgd::Rgd;

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
    /// ∂F_BR/∂d, N/m, d the depth of cut per revolution (zero for rate laws).
    pub dforce_ddepth: f64,
    /// ∂T_BR/∂d, N·m/m (zero for rate laws).
    pub dtorque_ddepth: f64,
}

/// A bit–rock interaction law: its name and parameters ([`Law`]), and the load it puts on the
/// string.
pub trait BitRockLaw: Law + CloneBitRockLaw {
    /// Force and torque on the string at bit axial velocity `vel` (m/s) and spin `spin` (rad/s).
    fn load(&self, vel: f64, spin: f64) -> BitLoad;

    /// The number of blades n of a depth-of-cut law, whose load depends on the rock surface the
    /// blades left (the simulator keeps it as state); `None` (the default) for a rate law.
    fn blades(&self) -> Option<u32> {
        None
    }

    /// The bit's radius a, m, for a law that has one (Detournay's, the depth-of-cut law);
    /// `None` (the default) for a law without a size (the paper's exponential law). Checked
    /// against the hole's radius when the file is read.
    fn radius(&self) -> Option<f64> {
        None
    }

    /// Force and torque on the string when the rock surface gives a depth of cut `depth` per
    /// revolution (m; ≤ 0: off bottom) at bit axial velocity `vel` (m/s) and spin `spin` (rad/s),
    /// with the derivatives in `depth` in [`BitLoad::dforce_ddepth`] and
    /// [`BitLoad::dtorque_ddepth`]. A rate law ignores `depth` (the default).
    fn load_at_depth(&self, depth: f64, vel: f64, spin: f64) -> BitLoad {
        let _ = depth;
        self.load(vel, spin)
    }

    /// The depth of cut per revolution of steady drilling at (vel, spin), m: the pitch of the
    /// helical bottom hole on which a depth-of-cut law's run starts, chosen so that
    /// `load_at_depth(steady_depth(v, w), v, w) == load(v, w)`. Rate laws: 2π v/|w| (unused).
    fn steady_depth(&self, vel: f64, spin: f64) -> f64 {
        2.0 * std::f64::consts::PI * vel.max(0.0) / spin.abs().max(f64::MIN_POSITIVE)
    }
}

law_kind!(BitRockLaw, CloneBitRockLaw);

/// A bit–rock law as the registry knows it.
pub type BitLawEntry = LawEntry<dyn BitRockLaw>;

/// Every bit–rock law drillopt knows; the first is the default when a file names none.
pub const BIT_LAWS: &[BitLawEntry] = &[exponential::ENTRY, detournay::ENTRY, rgd::ENTRY];

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

    /// See [`BitRockLaw::load_at_depth`].
    #[inline]
    pub fn load_at_depth(&self, depth: f64, vel: f64, spin: f64) -> BitLoad {
        self.law().load_at_depth(depth, vel, spin)
    }

    /// See [`BitRockLaw::blades`].
    pub fn blades(&self) -> Option<u32> {
        self.law().blades()
    }

    /// See [`BitRockLaw::radius`].
    pub fn radius(&self) -> Option<f64> {
        self.law().radius()
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
            // Off bottom nothing, whatever the spin (and, for a depth-of-cut law, whatever the
            // velocity when the bit is above the rock).
            assert_eq!(law.load(0.0, 3.0), BitLoad::default());
            assert_eq!(law.load(-1e-3, -3.0), BitLoad::default());
            if law.blades().is_some() {
                assert_eq!(law.load_at_depth(0.0, 1e-3, 3.0), BitLoad::default());
                assert_eq!(law.load_at_depth(-1e-4, 1e-3, 3.0), BitLoad::default());
            }
        }
    }
}
