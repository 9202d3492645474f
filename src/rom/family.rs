//! The vocabulary of a reduced basis: the vibration family and kind of each vector, the counts
//! `modes` and `summary.json` report, and why a basis could not be built. Shared by the basis's
//! construction ([`super::modes`]) and the block solves ([`super::pencil`]), which depend on it
//! and not on each other's vocabulary.

use super::eigen::EigenError;
use crate::fem::Dof;
use serde::Serialize;
use std::fmt;

/// The vibration family of a mode.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Family {
    /// Axial (u).
    Axial,
    /// Torsional (θx).
    Torsional,
    /// Bending with lateral displacement v along y (horizontal), with θz.
    BendingY,
    /// Bending with lateral displacement w along z (vertical), with θy.
    BendingZ,
}

impl Family {
    pub const ALL: [Family; 4] = [
        Family::Axial,
        Family::Torsional,
        Family::BendingY,
        Family::BendingZ,
    ];

    /// The family a DOF kind belongs to.
    pub fn of(dof: Dof) -> Family {
        match dof {
            Dof::U => Family::Axial,
            Dof::ThetaX => Family::Torsional,
            Dof::V | Dof::ThetaZ => Family::BendingY,
            Dof::W | Dof::ThetaY => Family::BendingZ,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Family::Axial => "axial",
            Family::Torsional => "torsional",
            Family::BendingY => "bending_y",
            Family::BendingZ => "bending_z",
        }
    }
}

impl fmt::Display for Family {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        // pad, not write_str: table columns set a width.
        f.pad(self.name())
    }
}

/// What a basis vector is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ModeKind {
    /// An eigenvector of (K, M).
    #[serde(rename = "mode")]
    Normal,
    /// The static response to a unit bit load, M-orthogonalised against the kept normal modes
    /// (a Ritz vector: K- and M-orthogonal to them, with its Rayleigh quotient as ω²).
    StaticCorrection,
    /// The string's resting shape in one bending plane, its static deflection under its weight
    /// with the wall's contact, and that shape's derivative with respect to an axial compression
    /// ([`super::resting`]): two Ritz vectors per plane, M-orthogonalised against the plane's kept
    /// modes and combined by Rayleigh–Ritz. Part of the basis when the static corrections are
    /// asked for.
    RestingShape,
    /// The steady drilling state's lateral shape in one bending plane, from the finite-element
    /// model at the problem's operating point ([`super::SteadyState`]): up to two Ritz vectors
    /// per plane, M-orthogonalised against the plane's kept modes and resting shapes.
    SteadyShape,
}

/// One vector of the reduced basis.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Mode {
    /// 1-based rank by frequency.
    pub index: usize,
    /// Natural frequency, Hz (for a static correction: √(ψᵀKψ)/2π, its Rayleigh quotient).
    pub freq_hz: f64,
    /// Natural circular frequency ω, rad/s.
    #[serde(skip)]
    pub omega: f64,
    pub family: Family,
    pub kind: ModeKind,
    /// Share of the modal kinetic energy in each family, in [`Family::ALL`] order (sums to 1).
    #[serde(skip)]
    pub energy_share: [f64; 4],
}

/// How many vectors of each family a basis holds: what `modes`, `simulate` and `summary.json`
/// report as `"basis"`. `bending` counts both planes (a problem file's `bending = 16` is per
/// plane: 32 here).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize)]
pub struct BasisCounts {
    pub bending: usize,
    pub torsional: usize,
    pub axial: usize,
    /// Static responses to the unit bit force and torque.
    pub static_corrections: usize,
    /// Resting shapes of the bending planes and their compression sensitivities
    /// ([`ModeKind::RestingShape`]; two per plane).
    pub resting_shapes: usize,
    /// Shapes of the steady drilling state ([`ModeKind::SteadyShape`]; up to two per plane).
    pub steady_shapes: usize,
}

impl fmt::Display for BasisCounts {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let plural = |n: usize| if n == 1 { "" } else { "s" };
        write!(
            f,
            "{} bending (both planes), {} torsional, {} axial, {} static correction{}",
            self.bending,
            self.torsional,
            self.axial,
            self.static_corrections,
            plural(self.static_corrections)
        )?;
        if self.resting_shapes > 0 {
            write!(
                f,
                ", {} resting shape{}",
                self.resting_shapes,
                plural(self.resting_shapes)
            )?;
        }
        if self.steady_shapes > 0 {
            write!(
                f,
                ", {} steady-state shape{}",
                self.steady_shapes,
                plural(self.steady_shapes)
            )?;
        }
        Ok(())
    }
}

/// Why a basis could not be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum BasisError {
    #[error(transparent)]
    Eigen(#[from] EigenError),
    /// A basis that leaves the torsional or axial family (or bending) without a mode cannot show
    /// that family's dynamics: refused.
    #[error(
        "the basis ({spec}) holds no {family} mode ({counts}); keep at least one mode of every family, e.g. with [mesh.basis]"
    )]
    EmptyFamily {
        spec: String,
        family: &'static str,
        counts: BasisCounts,
    },
    /// The resting shape of a bending plane (the string's static deflection under its weight
    /// against the wall, [`super::resting`]) did not converge: refused rather than left out, as
    /// a basis without it lets the reduced string bounce off the wall it lies on.
    #[error(
        "the resting shape of the {family} plane (the string's static deflection under its weight against the wall) did not converge: Newton on its energy found no minimum from the unloaded string nor from the string lying on the wall"
    )]
    RestingShape { family: &'static str },
}

/// A candidate basis vector on the free DOFs of one block.
pub(super) struct Candidate {
    pub lambda: f64,
    pub family: Family,
    pub kind: ModeKind,
    /// (free-DOF index, value).
    pub entries: Vec<(usize, f64)>,
    /// The coupled block it comes from (blocks in order of their first free DOF).
    pub block: usize,
}
