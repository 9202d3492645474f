//! What every kind of law of the model shares (the bit–rock laws of [`super::bit`], the wall
//! contact laws of [`super::wall`]): a name, a parameter table, values read and set by index, a
//! registry entry per law, and [`Chosen`], the law a drillstring runs, chosen by name in the
//! problem file (`law = "…"` in its table).
//!
//! Each kind of law is one trait with [`Law`] as its supertrait (what it computes is its own);
//! a law is one type implementing it plus one [`LawEntry`] in its kind's registry. The problem
//! layer reads, checks and declares uncertain the parameters through [`LawEntry::parameters`]
//! alone, so a new law needs no change outside its file and its registry line.

use super::parameters::ParameterSpec;
use std::fmt;

/// Declares a law whose parameters are `f64` fields listed once, in table order: implements
/// [`Law`] for it, gives it `from_values` (the law from its values in that order) and defines its
/// registry entry `ENTRY` (of type `$entry`, named `$name`, described by `$doc`, with parameter
/// table `$table`), so that the order of the table, of [`Law::value`], of [`Law::set`] and of the
/// constructor cannot drift apart.
macro_rules! law_with_fields {
    ($ty:ident: $entry:ty, $name:literal, $doc:literal, $table:ident, [$($field:ident),+ $(,)?]) => {
        /// Registry entry.
        pub(super) const ENTRY: $entry = $crate::model::law::LawEntry {
            name: $name,
            doc: $doc,
            parameters: &$table,
            build: |v| Box::new($ty::from_values(v)),
        };

        impl $crate::model::law::Law for $ty {
            fn name(&self) -> &'static str {
                $name
            }

            fn parameters(&self) -> &'static [$crate::model::ParameterSpec] {
                &$table
            }

            fn value(&self, index: usize) -> f64 {
                [$(self.$field),+][index]
            }

            fn set(&mut self, index: usize, value: f64) {
                *[$(&mut self.$field),+][index] = value;
            }
        }

        impl $ty {
            /// The law from its parameter values in table order (SI).
            pub fn from_values(values: &[f64]) -> Self {
                let mut v = values.iter().copied();
                Self {
                    $($field: v.next().expect("one value per parameter")),+
                }
            }
        }
    };
}
pub(crate) use law_with_fields;

/// What every law of every kind provides: its name and its parameters.
pub trait Law: fmt::Debug + Send + Sync {
    /// The law's name in problem files (`law = "…"`).
    fn name(&self) -> &'static str;
    /// The law's parameters, in the order [`Self::value`] and [`Self::set`] index them.
    fn parameters(&self) -> &'static [ParameterSpec];
    /// The value (SI) of parameter `index`.
    fn value(&self, index: usize) -> f64;
    /// Set parameter `index` to `value` (SI); the caller has checked its range.
    fn set(&mut self, index: usize, value: f64);
}

/// A boxed copy of a law behind its kind's trait object, which `law_kind!` implements for
/// `dyn ItsTrait`: laws are cloned for every Monte Carlo sample.
pub trait CloneLaw {
    /// A boxed copy.
    fn clone_law(&self) -> Box<Self>;
}

/// Makes a kind of law cloneable behind its trait object: `law_kind!(Kind, CloneKind)` declares
/// the helper trait `CloneKind` (to be a supertrait of `Kind`), implements it for every `Kind`
/// that is `Clone`, and implements [`CloneLaw`] for `dyn Kind`, so that laws of the kind write
/// no cloning code and [`Chosen`] of the kind is `Clone`.
macro_rules! law_kind {
    ($kind:ident, $clone:ident) => {
        #[doc = concat!("A boxed copy of a [`", stringify!($kind), "`], for every law of the kind that is `Clone`.")]
        pub trait $clone {
            /// A boxed copy.
            fn clone_box(&self) -> Box<dyn $kind>;
        }

        impl<T: $kind + Clone + 'static> $clone for T {
            fn clone_box(&self) -> Box<dyn $kind> {
                Box::new(self.clone())
            }
        }

        impl $crate::model::law::CloneLaw for dyn $kind {
            fn clone_law(&self) -> Box<Self> {
                self.clone_box()
            }
        }
    };
}
pub(crate) use law_kind;

/// A law as its kind's registry knows it: name, description with source, parameters, constructor.
pub struct LawEntry<L: ?Sized> {
    /// Name in problem files.
    pub name: &'static str,
    /// One line: what the law is and where it comes from.
    pub doc: &'static str,
    /// Parameter table (full keys, `model.bit.…`, `model.wall.…`).
    pub parameters: &'static [ParameterSpec],
    /// Build the law from its parameter values in table order (SI, ranges already checked).
    pub build: fn(&[f64]) -> Box<L>,
}

/// The entry of `registry` called `name`.
pub fn find<L: ?Sized>(
    registry: &'static [LawEntry<L>],
    name: &str,
) -> Option<&'static LawEntry<L>> {
    registry.iter().find(|e| e.name == name)
}

/// The law of kind `L` (a trait object such as `dyn BitRockLaw`) that a drillstring runs:
/// cloneable, comparable by name and parameter values, its parameters addressable by name.
pub struct Chosen<L: ?Sized>(Box<L>);

impl<L: ?Sized + Law> Chosen<L> {
    /// Wrap a boxed law.
    pub fn from_box(law: Box<L>) -> Self {
        Chosen(law)
    }

    /// Build a registered law from its parameter values in table order.
    pub fn from_entry(entry: &LawEntry<L>, values: &[f64]) -> Self {
        Chosen((entry.build)(values))
    }

    /// The law itself.
    #[inline]
    pub fn law(&self) -> &L {
        self.0.as_ref()
    }

    /// Index of the parameter called `name`: its full key (`model.bit.rate`) or its name in its
    /// table (`rate`).
    pub fn index_of(&self, name: &str) -> Option<usize> {
        self.0
            .parameters()
            .iter()
            .position(|p| p.key == name || p.name() == name)
    }

    /// Value (SI) of the parameter called `name` (full key or name in its table).
    pub fn get(&self, name: &str) -> Option<f64> {
        self.index_of(name).map(|i| self.0.value(i))
    }

    /// Set parameter `index` (SI).
    pub fn set(&mut self, index: usize, value: f64) {
        self.0.set(index, value);
    }

    /// Divide every regularisation width of the law (the parameters whose key ends in
    /// `_smoothing`: the widths of its tanh and square-root smoothings of set-valued contact and
    /// friction laws) by `divisor`, and say which keys.
    pub fn refine_smoothing(&mut self, divisor: f64) -> Vec<&'static str> {
        let mut keys = Vec::new();
        for (i, p) in self.0.parameters().iter().enumerate() {
            if p.key.ends_with("_smoothing") {
                let value = self.0.value(i);
                self.0.set(i, value / divisor);
                keys.push(p.key);
            }
        }
        keys
    }

    /// Canonical form `{"law": name, "parameters": {key: value, …}}`, full keys in table order
    /// (cache keys).
    pub(super) fn serialize_named<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeStruct;
        let mut st = s.serialize_struct("Law", 2)?;
        st.serialize_field("law", self.0.name())?;
        st.serialize_field("parameters", &Values(self.law(), Keys::Full))?;
        st.end()
    }

    /// Canonical form `{name: value, …}`: the parameters alone, by their names in the table, in
    /// table order (the form of a law that was the only one of its kind).
    pub(super) fn serialize_flat<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        serde::Serialize::serialize(&Values(self.law(), Keys::Name), s)
    }
}

/// How [`Values`] names the parameters.
#[derive(Clone, Copy)]
enum Keys {
    Full,
    Name,
}

/// A law's parameters as a map, in table order.
struct Values<'a, L: ?Sized>(&'a L, Keys);

impl<L: ?Sized + Law> serde::Serialize for Values<'_, L> {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeMap;
        let specs = self.0.parameters();
        let mut m = s.serialize_map(Some(specs.len()))?;
        for (i, p) in specs.iter().enumerate() {
            let key = match self.1 {
                Keys::Full => p.key,
                Keys::Name => p.name(),
            };
            m.serialize_entry(key, &self.0.value(i))?;
        }
        m.end()
    }
}

impl<L: ?Sized + CloneLaw> Clone for Chosen<L> {
    fn clone(&self) -> Self {
        Chosen(self.0.clone_law())
    }
}

impl<L: ?Sized + Law> fmt::Debug for Chosen<L> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        self.0.fmt(f)
    }
}

impl<L: ?Sized + Law> PartialEq for Chosen<L> {
    fn eq(&self, other: &Self) -> bool {
        let n = self.0.parameters().len();
        self.0.name() == other.0.name() && (0..n).all(|i| self.0.value(i) == other.0.value(i))
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// Every law of `registry` builds from its defaults (or examples), reports its name, round
    /// trips its values through `value`/`set`, and compares and clones by value; every example
    /// lies in its range. Returns each law built from its defaults, for the kind's own checks.
    pub(crate) fn check_registry<L: ?Sized + Law + CloneLaw>(
        registry: &'static [LawEntry<L>],
    ) -> Vec<Chosen<L>> {
        registry
            .iter()
            .map(|entry| {
                let values: Vec<f64> = entry
                    .parameters
                    .iter()
                    .map(|p| p.default.unwrap_or(p.example))
                    .collect();
                for p in entry.parameters {
                    assert!(p.range.contains(p.example), "{} {}", entry.name, p.key);
                    if let Some(d) = p.default {
                        assert!(p.range.contains(d), "{} {} default", entry.name, p.key);
                    }
                }
                assert!(std::ptr::eq(find(registry, entry.name).unwrap(), entry));
                let mut law = Chosen::from_entry(entry, &values);
                assert_eq!(law.law().name(), entry.name);
                for (i, v) in values.iter().enumerate() {
                    assert_eq!(law.law().value(i), *v, "{} {i}", entry.name);
                    assert_eq!(law.get(entry.parameters[i].name()), Some(*v));
                    law.set(i, 2.0 * v);
                    assert_eq!(law.law().value(i), 2.0 * v);
                }
                assert!(law != Chosen::from_entry(entry, &values));
                assert!(law.clone() == law);
                Chosen::from_entry(entry, &values)
            })
            .collect()
    }
}
