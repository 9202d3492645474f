//! The linear finite-element model of the drillstring (MODEL.md §3, §4, §7).
//!
//! 2-node, 12-DOF Timoshenko beam elements with interdependent interpolation (Reddy 1997): linear
//! for u and θx, the exact static Timoshenko fields (cubic v, w with interdependent quadratic
//! rotations) for bending, so the element is free of shear locking. Per node the DOFs are
//! (u, v, w, θx, θy, θz) in that order (see [`Dof`]); node 0 is the top drive (x = 0), node N the bit.
//!
//! Sign conventions: the transverse shear strains are γ_xy = v′ − θz and γ_xz = w′ + θy, so in the
//! Euler–Bernoulli limit θz = v′ and θy = −w′ (MODEL.md §2, the quadratic part of the strain energy).

mod assembly;
mod boundary;
mod dof;
mod element;
mod inertia;
mod lanes;
mod layout;
mod shape;
mod sparse;
mod strain_energy;
mod stress;
#[cfg(test)]
mod test_support;

pub use assembly::{AssembledMesh, GlobalMatrices, assemble, weight_load};
pub use boundary::BoundaryConditions;
pub use dof::{DOF_PER_NODE, Dof};
pub use element::{BeamElement, ELEMENT_DOF, ElementMatrix, ElementVector, Lateral};
pub use inertia::ElementInertia;
pub use layout::{ElementKind, ElementLayout};
pub use shape::{Interpolation, gauss_legendre_4};
pub use sparse::{SparseGlobal, SymmetricSparse, assemble_sparse, geometric_stiffness};
pub use strain_energy::{ElementStrains, STRAIN_VARS, StrainEnergy, Strains};
pub use stress::{AxialStressField, SectionLoads, SectionStrains, SectionStress};
