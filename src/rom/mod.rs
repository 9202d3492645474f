//! Reduced-order modelling: the lowest modes of (K, M) on the constrained system (MODEL.md §7).

mod blocks;
mod eigen;
mod family;
mod force_summation;
mod lanczos;
mod modes;
mod operator;
mod padded;
mod pencil;
mod reduced;
mod resting;
mod sparse;

pub use blocks::{BlockBasis, BlockWork};
pub use eigen::{EigenError, generalized_symmetric_eigen};
pub use family::{BasisCounts, BasisError, Family, Mode, ModeKind};
pub use force_summation::{ForceSummation, FullState};
pub use lanczos::{lanczos_applies, sparse_generalized_eigen};
pub use modes::{ModalBasis, SteadyState};
pub use operator::Operator;
pub use pencil::LANCZOS_MIN_BLOCK;
pub use reduced::{ElementKernel, ReducedModel, SteadyStatus};
pub use sparse::SparseBasis;
