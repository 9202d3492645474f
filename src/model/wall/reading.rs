//! How a wall law's stiffness and damping are read (`[model.wall] stiffness_per`, MODEL.md
//! §11.3).
//!
//! - [`WallStiffnessPer::Length`] (the default): the law's force is per metre of string, a Winkler
//!   foundation. The law's `stiffness` is in N/m per metre of string (N/m², the foundation
//!   modulus), its cubic stiffness in N/m³ per metre, its damping per metre. A node carries the
//!   force of the string it stands for, its tributary length ℓᵢ = (hᵢ₋₁ + hᵢ)/2 (h/2 at the two
//!   end nodes of a uniform mesh, h elsewhere): F_node = ℓᵢ F_law(δ, δ̇). Refining the mesh then
//!   leaves the wall as stiff as it was: a string lying along the wall under its weight per
//!   length w sinks δ = w/k′ whatever the mesh (`tests/model/wall_per_length.rs`).
//! - [`WallStiffnessPer::Node`] (the paper's reading, Cunha Jr, Soize & Sampaio 2014, Table 1):
//!   every node of the mesh is a spring of the law's stiffness, F_node = F_law(δ, δ̇). A mesh
//!   twice as fine is a wall twice as stiff per metre, and the string sinks half as deep.
//!
//! **Conversion.** On a uniform mesh of element length h the two readings give the same force
//! at every interior node when k′ = k/h (and likewise for the cubic stiffness and the damping):
//! the seed's k_FS1 = 1e10 N/m per node on 105 elements of 1/3 m is 3e10 N/m per metre of
//! string. The end nodes differ (ℓ = h/2), but the boundary conditions of MODEL.md §4 hold both
//! of them on the axis (v = w = 0), so they never touch the wall.

/// The reading of a wall law's stiffness and damping (see the module doc).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum WallStiffnessPer {
    /// Per metre of string (a Winkler foundation): a node carries its tributary length.
    #[default]
    Length,
    /// Per node of the mesh (the paper's reading).
    Node,
}

impl WallStiffnessPer {
    /// The names a problem file may give (`model.wall.stiffness_per`).
    pub const NAMES: [&'static str; 2] = ["length", "node"];

    /// The name used in problem files.
    pub fn name(self) -> &'static str {
        match self {
            WallStiffnessPer::Length => "length",
            WallStiffnessPer::Node => "node",
        }
    }

    /// The reading called `name` in a problem file.
    pub fn from_name(name: &str) -> Option<Self> {
        match name {
            "length" => Some(WallStiffnessPer::Length),
            "node" => Some(WallStiffnessPer::Node),
            _ => None,
        }
    }

    /// Whether this is the paper's per-node reading (left out of the serialised model, so that
    /// the model hash of a file that states it is the hash of the same file before the key
    /// existed, when per node was the only reading).
    pub fn is_node(&self) -> bool {
        *self == WallStiffnessPer::Node
    }

    /// The factor on the law's force at a node that stands for `tributary_length` m of string
    /// (half of each element it joins: [`crate::fem::ElementLayout::tributary_length`]): 1 per
    /// node (dimensionless), the tributary length in m per length.
    #[inline]
    pub fn factor(self, tributary_length: f64) -> f64 {
        match self {
            WallStiffnessPer::Node => 1.0,
            WallStiffnessPer::Length => tributary_length,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn per_length_a_node_carries_its_tributary_length_and_k_over_h_is_the_per_node_wall() {
        assert_eq!(WallStiffnessPer::Node.factor(0.25), 1.0);
        assert_eq!(WallStiffnessPer::Length.factor(0.25), 0.25);
        // An interior node of the seed's mesh stands for h = 1/3 m: k' = k/h carries k.
        approx::assert_relative_eq!(
            3e10 * WallStiffnessPer::Length.factor(35.0 / 105.0),
            1e10,
            max_relative = 1e-15
        );
    }

    #[test]
    fn names_round_trip() {
        for name in WallStiffnessPer::NAMES {
            assert_eq!(WallStiffnessPer::from_name(name).unwrap().name(), name);
        }
        assert_eq!(WallStiffnessPer::from_name("metre"), None);
        assert_eq!(WallStiffnessPer::default(), WallStiffnessPer::Length);
    }
}
