//! The scalar parameters of the model that a study may vary, declared once: key, dimension,
//! admissible range, which operators they enter and how to set them. The problem layer reads
//! and checks them through this table, the Monte Carlo runner applies sampled values through it,
//! and the reduced-model cache asks it whether a sample needs its own modes.
//!
//! The parameters of the wall contact law and of the bit–rock law come from the laws themselves
//! ([`super::wall`], [`super::bit`]); [`ParameterKey`] resolves a key against all three.

use super::Drillstring;
use crate::units::{Dimension, Range};
use std::fmt;

/// One scalar input: its problem-file key, dimension, admissible range and meaning.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ParameterSpec {
    /// Full dotted key in the problem file (`model.wall.friction`).
    pub key: &'static str,
    /// Fixes the units the value may be written in.
    pub dimension: Dimension,
    /// Values a problem file (and every Monte Carlo sample) may take, SI.
    pub range: Range,
    /// Value (SI) when the problem file omits the key; `None`: the key is required.
    pub default: Option<f64>,
    /// A typical value (SI), inside the range: documentation and tests.
    pub example: f64,
    /// What the parameter is, with its symbol.
    pub doc: &'static str,
}

impl ParameterSpec {
    /// A declaration of a scalar input (the fields in order), for the tables of `const` rows.
    pub const fn new(
        key: &'static str,
        dimension: Dimension,
        range: Range,
        default: Option<f64>,
        example: f64,
        doc: &'static str,
    ) -> Self {
        ParameterSpec {
            key,
            dimension,
            range,
            default,
            example,
            doc,
        }
    }

    /// The last component of the key (`friction` for `model.wall.friction`).
    pub fn name(&self) -> &'static str {
        self.key.rsplit('.').next().unwrap_or(self.key)
    }
}

/// Which operators of the discretised model a parameter enters.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Enters {
    /// The linear operators K, M, C or the gravity load: a changed value needs its own reduced
    /// model.
    LinearOperators,
    /// Only the nonlinear forces (bit, wall contact, borehole gap): the modes are shared.
    NonlinearForces,
}

/// A parameter of the string (not of its wall or bit law).
pub struct StringParameter {
    pub spec: ParameterSpec,
    pub enters: Enters,
    field: fn(&mut Drillstring) -> &mut f64,
    /// A bound set by another property of the string: the value must exceed it.
    above: Option<Above>,
    /// Whether it enters the mass (the annulus fluid's confined added mass,
    /// [`super::Section::confined_added_mass`]) when the annulus holds fluid, whatever `enters`.
    added_mass: bool,
}

/// A lower bound that another property of the string sets, and its name for messages.
type Above = (fn(&Drillstring) -> f64, &'static str);

impl StringParameter {
    /// Whether this is a property of `[model.pipe]` that a string of sections holds per section
    /// (its density and Young's modulus): not a parameter of such a string, whose sections
    /// carry their own.
    fn per_section(&self, string: &Drillstring) -> bool {
        !string.sections.is_empty()
            && matches!(
                self.spec.key,
                "model.pipe.density" | "model.pipe.youngs_modulus"
            )
    }
}

impl fmt::Debug for StringParameter {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("StringParameter")
            .field("key", &self.spec.key)
            .field("enters", &self.enters)
            .finish()
    }
}

const fn row(
    spec: ParameterSpec,
    enters: Enters,
    field: fn(&mut Drillstring) -> &mut f64,
) -> StringParameter {
    StringParameter {
        spec,
        enters,
        field,
        above: None,
        added_mass: false,
    }
}

use Dimension as D;
use Enters::{LinearOperators as Linear, NonlinearForces as Nonlinear};

/// `model.pipe.damping`: the declaration the problem's key table ([`crate::problem::keys`]) and
/// [`STRING_PARAMETERS`] share, as for the six below.
pub const PIPE_DAMPING: ParameterSpec = ParameterSpec::new(
    "model.pipe.damping",
    D::Rate,
    Range::closed(0.0, 1e3, "mass-proportional damping c"),
    None,
    0.01,
    "mass-proportional damping c (C = c M)",
);
pub const PIPE_STIFFNESS_DAMPING: ParameterSpec = ParameterSpec::new(
    "model.pipe.stiffness_damping",
    D::Time,
    Range::closed(
        0.0,
        1e-3,
        "a damping ratio πβf of at most 31 % at 100 Hz (1e-3 s); 1e-5 s is 1 % at 318 Hz",
    ),
    Some(0.0),
    1e-5,
    "stiffness-proportional damping β (C = c M_pipe + β K); 0, the paper's, by default",
);
pub const PIPE_DENSITY: ParameterSpec = ParameterSpec::new(
    "model.pipe.density",
    D::Density,
    Range::closed(1e3, 25e3, "from light alloys to tungsten"),
    None,
    7850.0,
    "steel density ρ",
);
pub const PIPE_YOUNGS_MODULUS: ParameterSpec = ParameterSpec::new(
    "model.pipe.youngs_modulus",
    D::Pressure,
    Range::closed(1e9, 1e12, "from polymers to tungsten carbide"),
    None,
    203e9,
    "Young's modulus E",
);
pub const FLUID_DENSITY: ParameterSpec = ParameterSpec::new(
    "model.fluid.density",
    D::Density,
    Range::closed(0.0, 3e3, "from air to the heaviest muds"),
    None,
    1200.0,
    "drilling-fluid density ρ_f inside the pipe (lateral mass and weight)",
);
pub const ANNULUS_DENSITY: ParameterSpec = ParameterSpec::new(
    "model.fluid.annulus_density",
    D::Density,
    Range::closed(0.0, 3e3, "from none (0) to the heaviest muds"),
    Some(0.0),
    1200.0,
    "density ρ_a of the fluid in the annulus (buoyancy: gravity load; confined added mass); \
     none (0), the paper's model, by default",
);
pub const BOREHOLE_RADIUS: ParameterSpec = ParameterSpec::new(
    "model.borehole.radius",
    D::Length,
    // It must also exceed the pipe's outer radius, at least 1 mm.
    Range::closed(1e-3, 2.0, "a hole 2 mm to 4 m across"),
    None,
    0.1,
    "borehole radius R_bh (greater than the pipe's largest outer radius; or `diameter`, the hole \
     size 2 R_bh, as drillers give it; a bit law with a radius must fit it, the hole at most 1.5 \
     times the bit)",
);

/// The largest hole a bit of radius a is taken to drill, as a multiple of a: a reamer above the
/// bit or a washout widens the hole, by up to about a third of a for common reamer sizes (an
/// 8½ in bit under a 9⅞ or 10⅝ in reamer: 1.16, 1.25); twice a is a diameter typed as a radius.
/// Checked on the file (`problem::validate`) and on every sampled hole or bit radius.
pub const MAX_HOLE_OVER_BIT: f64 = 1.5;

/// The string's parameters a study may declare uncertain.
pub static STRING_PARAMETERS: [StringParameter; 7] = [
    row(PIPE_DAMPING, Linear, |s| &mut s.damping),
    row(PIPE_STIFFNESS_DAMPING, Linear, |s| &mut s.stiffness_damping),
    row(PIPE_DENSITY, Linear, |s| &mut s.pipe.density),
    row(PIPE_YOUNGS_MODULUS, Linear, |s| &mut s.pipe.youngs_modulus),
    row(FLUID_DENSITY, Linear, |s| &mut s.fluid_density),
    row(ANNULUS_DENSITY, Linear, |s| &mut s.annulus_density),
    StringParameter {
        above: Some((
            |s| s.max_outer_radius(),
            "the pipe's (largest) outer radius",
        )),
        added_mass: true,
        ..row(BOREHOLE_RADIUS, Nonlinear, |s| &mut s.borehole_radius)
    },
];

/// A model parameter a study can vary: a row of [`STRING_PARAMETERS`] or a parameter of the
/// string's wall contact law or bit–rock law.
#[derive(Debug, Clone, Copy)]
pub struct ParameterKey {
    spec: &'static ParameterSpec,
    target: Target,
}

#[derive(Debug, Clone, Copy)]
enum Target {
    String(&'static StringParameter),
    Wall(usize),
    Bit(usize),
}

impl PartialEq for ParameterKey {
    fn eq(&self, other: &Self) -> bool {
        self.spec.key == other.spec.key
    }
}

impl Eq for ParameterKey {}

impl ParameterKey {
    /// The parameter called `key` in a string with these laws, if it can be varied.
    pub fn resolve(key: &str, string: &Drillstring) -> Option<Self> {
        if let Some(row) = (STRING_PARAMETERS.iter())
            .filter(|r| !r.per_section(string))
            .find(|r| r.spec.key == key)
        {
            return Some(ParameterKey {
                spec: &row.spec,
                target: Target::String(row),
            });
        }
        let in_law = |specs: &'static [ParameterSpec], target: fn(usize) -> Target| {
            let index = specs.iter().position(|p| p.key == key)?;
            Some(ParameterKey {
                spec: &specs[index],
                target: target(index),
            })
        };
        in_law(string.wall.law().parameters(), Target::Wall)
            .or_else(|| in_law(string.bit.law().parameters(), Target::Bit))
    }

    /// Every key that can be varied in this string: the string's own, its wall law's, its bit
    /// law's, counts (whole numbers, such as a bit's blades) excepted.
    pub fn available(string: &Drillstring) -> Vec<&'static str> {
        let fixed = (STRING_PARAMETERS.iter())
            .filter(|r| !r.per_section(string))
            .map(|r| &r.spec);
        let laws = [
            string.wall.law().parameters(),
            string.bit.law().parameters(),
        ];
        fixed
            .chain(laws.into_iter().flatten())
            .filter(|p| !p.range.integer)
            .map(|p| p.key)
            .collect()
    }

    /// The key as written in the problem file.
    pub fn name(&self) -> &'static str {
        self.spec.key
    }

    /// Dimension, range and meaning.
    pub fn spec(&self) -> &'static ParameterSpec {
        self.spec
    }

    /// Which operators the parameter enters in `string` (the laws' parameters act in the forces
    /// only; the borehole radius enters the mass too when the annulus holds fluid, through the
    /// confined added mass).
    pub fn enters(&self, string: &Drillstring) -> Enters {
        match self.target {
            Target::String(row) if row.added_mass && string.annulus_density > 0.0 => {
                Enters::LinearOperators
            }
            Target::String(row) => row.enters,
            Target::Wall(_) | Target::Bit(_) => Enters::NonlinearForces,
        }
    }

    /// Set the parameter in a drillstring (SI value).
    pub fn apply(&self, string: &mut Drillstring, value: f64) {
        match self.target {
            Target::String(row) => *(row.field)(string) = value,
            Target::Wall(index) => string.wall.set(index, value),
            Target::Bit(index) => string.bit.set(index, value),
        }
    }

    /// `Ok` if `value` is admissible in `string` (its range and any bound set by the string),
    /// else what is allowed, in words.
    pub fn admissible(&self, string: &Drillstring, value: f64) -> Result<(), String> {
        let range = self.spec.range;
        if !range.contains(value) {
            return Err(format!("must be {}", range.describe(self.spec.dimension)));
        }
        if let Target::String(StringParameter {
            above: Some((bound, what)),
            ..
        }) = self.target
        {
            let b = bound(string);
            if value <= b {
                return Err(format!(
                    "must exceed {what}, {b} {}",
                    self.spec.dimension.si_unit()
                ));
            }
        }
        // A sampled hole or bit must keep the bit in its hole, as a file must
        // (`problem::validate`: the bit at most the hole, the hole at most 1.5 times the bit).
        let (hole, bit) = match self.spec.key {
            "model.borehole.radius" => (value, string.bit.radius()),
            "model.bit.radius" => (string.borehole_radius, Some(value)),
            _ => return Ok(()),
        };
        if let Some(bit) = bit {
            if bit > hole * (1.0 + 1e-9) {
                return Err(format!(
                    "must keep the bit (radius {bit} m) within the hole (radius {hole} m)"
                ));
            }
            if hole > MAX_HOLE_OVER_BIT * bit {
                return Err(format!(
                    "must keep the hole (radius {hole} m) at most {} times the bit (radius \
                     {bit} m)",
                    MAX_HOLE_OVER_BIT
                ));
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn seed() -> Drillstring {
        crate::problem::Problem::load(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/problems/seed_mc2014.toml"
        ))
        .unwrap()
        .model
    }

    #[test]
    fn a_sampled_hole_or_bit_keeps_the_bit_in_its_hole() {
        // seed_detournay: a 70 mm bit in a 70 mm hole (radii).
        let s = crate::problem::Problem::load(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/problems/seed_detournay.toml"
        ))
        .unwrap()
        .model;
        let hole = ParameterKey::resolve("model.borehole.radius", &s).unwrap();
        let bit = ParameterKey::resolve("model.bit.radius", &s).unwrap();
        assert!(hole.admissible(&s, 0.075).is_ok());
        assert!(hole.admissible(&s, 0.105).is_ok(), "1.5 times the bit");
        let wide = hole.admissible(&s, 0.11).unwrap_err();
        assert!(wide.contains("at most 1.5 times the bit"), "{wide}");
        let tight = hole.admissible(&s, 0.069).unwrap_err();
        assert!(tight.contains("within the hole"), "{tight}");
        assert!(bit.admissible(&s, 0.065).is_ok());
        assert!(
            bit.admissible(&s, 0.071)
                .unwrap_err()
                .contains("within the hole")
        );
        assert!(bit.admissible(&s, 0.04).unwrap_err().contains("1.5 times"));
    }

    #[test]
    fn every_key_resolves_sets_its_own_field_and_nothing_else() {
        let s = seed();
        for key in ParameterKey::available(&s) {
            let k = ParameterKey::resolve(key, &s).unwrap();
            assert_eq!(k.name(), key);
            let mut t = s.clone();
            let value = k.spec().example * 1.01;
            k.apply(&mut t, value);
            assert_ne!(t, s, "{key} changed nothing");
            // Setting it back restores the string exactly: the setter touched one field.
            let mut back = t.clone();
            let original = match k.target {
                Target::String(row) => *(row.field)(&mut s.clone()),
                Target::Wall(i) => s.wall.law().value(i),
                Target::Bit(i) => s.bit.law().value(i),
            };
            k.apply(&mut back, original);
            assert_eq!(back, s, "{key}");
        }
        assert!(ParameterKey::resolve("model.bit.limit_force", &s).is_some());
        assert!(ParameterKey::resolve("model.wall.cubic_stiffness", &s).is_some());
        assert!(ParameterKey::resolve("model.wall.restitution", &s).is_none());
        assert!(ParameterKey::resolve("model.bit.radius", &s).is_none());
        assert!(ParameterKey::resolve("model.length", &s).is_none());
    }

    #[test]
    fn operators_and_admissibility() {
        let s = seed();
        let k = |key| ParameterKey::resolve(key, &s).unwrap();
        assert_eq!(k("model.pipe.density").enters(&s), Enters::LinearOperators);
        assert_eq!(
            k("model.fluid.annulus_density").enters(&s),
            Enters::LinearOperators
        );
        assert_eq!(k("model.bit.rate").enters(&s), Enters::NonlinearForces);
        assert_eq!(
            k("model.borehole.radius").enters(&s),
            Enters::NonlinearForces
        );
        assert_eq!(
            k("model.wall.stiffness").enters(&s),
            Enters::NonlinearForces
        );
        // With annulus fluid the hole's radius sets the confined added mass: own modes.
        let mud = Drillstring {
            annulus_density: 1200.0,
            ..s.clone()
        };
        assert_eq!(
            k("model.borehole.radius").enters(&mud),
            Enters::LinearOperators
        );
        let r = k("model.borehole.radius");
        assert!(r.admissible(&s, s.pipe.outer_radius).is_err());
        assert!(r.admissible(&s, s.pipe.outer_radius * 1.1).is_ok());
        assert!(k("model.wall.friction").admissible(&s, 3.0).is_err());
        assert!(k("model.wall.friction").admissible(&s, f64::NAN).is_err());
    }
}
