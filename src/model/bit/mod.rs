//! Bit–rock interaction laws: the force and torque the rock puts on the bit (MODEL.md §6).
//!
//! A law is one type implementing [`BitRockLaw`] plus one [`BitLawEntry`] in [`BIT_LAWS`]; the
//! problem file chooses it by name (`[model.bit] law = "…"`), its parameters are read, checked and
//! declared uncertain through the law's own [`ParameterSpec`] table, and the simulator calls
//! [`BitRockLaw::load`]. Nothing else in drillopt knows which law runs.
//!
//! Sign conventions (all laws): the axial coordinate u points from the top drive to the bit, so
//! u̇ > 0 is the bit advancing into the rock; θ̇ > 0 is the top drive's sense of rotation. The
//! force on the string is F ≤ 0 (WOB = −F) and the torque T opposes positive spin (TOB = −T).
//! Off bottom (u̇ ≤ 0) every law gives neither force nor torque: bit-bounce.

mod detournay;
mod exponential;

pub use detournay::Detournay;
pub use exponential::{Exponential, xi};

use super::parameters::ParameterSpec;
use std::fmt;

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

/// A bit–rock interaction law.
pub trait BitRockLaw: fmt::Debug + Send + Sync {
    /// The law's name in problem files (`model.bit.law`).
    fn name(&self) -> &'static str;
    /// The law's parameters, in the order [`Self::value`] and [`Self::set`] index them.
    fn parameters(&self) -> &'static [ParameterSpec];
    /// The value (SI) of parameter `index`.
    fn value(&self, index: usize) -> f64;
    /// Set parameter `index` to `value` (SI); the caller has checked its range.
    fn set(&mut self, index: usize, value: f64);
    /// Force and torque on the string at bit axial velocity `vel` (m/s) and spin `spin` (rad/s).
    fn load(&self, vel: f64, spin: f64) -> BitLoad;
    /// A boxed copy (the law is cloned for every Monte Carlo sample).
    fn clone_box(&self) -> Box<dyn BitRockLaw>;
}

/// A law as the registry knows it: name, description with source, parameters, constructor.
pub struct BitLawEntry {
    /// Name in problem files.
    pub name: &'static str,
    /// One line: what the law is and where it comes from.
    pub doc: &'static str,
    /// Parameter table (full keys, `model.bit.…`).
    pub parameters: &'static [ParameterSpec],
    /// Build the law from its parameter values in table order (SI, ranges already checked).
    pub build: fn(&[f64]) -> Box<dyn BitRockLaw>,
}

/// Every bit–rock law drillopt knows; the first is the default when a file names none.
pub const BIT_LAWS: &[BitLawEntry] = &[exponential::ENTRY, detournay::ENTRY];

/// The registry entry of the law called `name`.
pub fn bit_law(name: &str) -> Option<&'static BitLawEntry> {
    BIT_LAWS.iter().find(|e| e.name == name)
}

/// The bit–rock law of a drillstring: any [`BitRockLaw`], cloneable and comparable.
pub struct BitRock(Box<dyn BitRockLaw>);

impl BitRock {
    /// Wrap a law.
    pub fn new(law: impl BitRockLaw + 'static) -> Self {
        BitRock(Box::new(law))
    }

    /// Build a registered law from its parameter values in table order.
    pub fn from_entry(entry: &BitLawEntry, values: &[f64]) -> Self {
        BitRock((entry.build)(values))
    }

    /// The law itself.
    pub fn law(&self) -> &dyn BitRockLaw {
        self.0.as_ref()
    }

    /// Force and torque with derivatives; see [`BitRockLaw::load`].
    #[inline]
    pub fn load(&self, vel: f64, spin: f64) -> BitLoad {
        self.0.load(vel, spin)
    }

    /// Index of the parameter called `name`: its full key (`model.bit.rate`) or its name in
    /// `[model.bit]` (`rate`).
    pub fn index_of(&self, name: &str) -> Option<usize> {
        self.0
            .parameters()
            .iter()
            .position(|p| p.key == name || p.name() == name)
    }

    /// Value (SI) of the parameter called `name` (full key or name in `[model.bit]`).
    pub fn get(&self, name: &str) -> Option<f64> {
        self.index_of(name).map(|i| self.0.value(i))
    }

    /// Set parameter `index` (SI).
    pub fn set(&mut self, index: usize, value: f64) {
        self.0.set(index, value);
    }
}

impl Clone for BitRock {
    fn clone(&self) -> Self {
        BitRock(self.0.clone_box())
    }
}

impl fmt::Debug for BitRock {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        self.0.fmt(f)
    }
}

/// Canonical form: `{"law": name, "parameters": {key: value, …}}` in table order (cache keys).
impl serde::Serialize for BitRock {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        use serde::ser::{SerializeMap, SerializeStruct};
        struct Parameters<'a>(&'a dyn BitRockLaw);
        impl serde::Serialize for Parameters<'_> {
            fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
                let specs = self.0.parameters();
                let mut m = s.serialize_map(Some(specs.len()))?;
                for (i, p) in specs.iter().enumerate() {
                    m.serialize_entry(p.key, &self.0.value(i))?;
                }
                m.end()
            }
        }
        let mut st = serializer.serialize_struct("BitRock", 2)?;
        st.serialize_field("law", self.0.name())?;
        st.serialize_field("parameters", &Parameters(self.0.as_ref()))?;
        st.end()
    }
}

impl PartialEq for BitRock {
    fn eq(&self, other: &Self) -> bool {
        let n = self.0.parameters().len();
        self.0.name() == other.0.name() && (0..n).all(|i| self.0.value(i) == other.0.value(i))
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
        for entry in BIT_LAWS {
            let values: Vec<f64> = entry
                .parameters
                .iter()
                .map(|p| p.default.unwrap_or(p.example))
                .collect();
            for p in entry.parameters {
                assert!(p.range.contains(p.example), "{} {}", entry.name, p.key);
            }
            let mut law = BitRock::from_entry(entry, &values);
            assert_eq!(law.law().name(), entry.name);
            for (i, v) in values.iter().enumerate() {
                assert_eq!(law.law().value(i), *v, "{} {i}", entry.name);
                law.set(i, 2.0 * v);
                assert_eq!(law.law().value(i), 2.0 * v);
            }
            assert_ne!(law, BitRock::from_entry(entry, &values));
            assert_eq!(law.clone(), law);
            // Off bottom nothing, whatever the spin.
            let law = BitRock::from_entry(entry, &values);
            assert_eq!(law.load(0.0, 3.0), BitLoad::default());
            assert_eq!(law.load(-1e-3, -3.0), BitLoad::default());
        }
    }
}
