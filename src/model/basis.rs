//! Which modes the reduced-order model keeps (MODEL.md §7, "basis per family").
//!
//! The lowest N modes of a long string are almost all bending (seed: 51 lowest = 46 bending,
//! 3 torsional, 2 axial; a 466 m string: no torsional or axial mode at all), so the basis is chosen
//! per family: bending (the same count in both planes, kept as exact twins), torsional and axial,
//! each by count or by a cutoff frequency, plus static-correction (attachment) vectors for the
//! bit force and torque. The paper's "N lowest" stays expressible as [`BasisSpec::Lowest`].

use std::fmt;

/// How many modes of one family to keep.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub enum FamilySize {
    /// The `n` lowest modes of the family (for bending: per plane), n ≥ 1.
    Count(usize),
    /// Every mode of the family below `hz` (Hz), and at least `min` of them (≥ 1).
    Cutoff { hz: f64, min: usize },
}

impl FamilySize {
    /// The same selection enriched by `factor` (> 1): counts and cutoffs multiplied, rounded up.
    pub fn enriched(self, factor: f64) -> FamilySize {
        match self {
            FamilySize::Count(n) => FamilySize::Count((n as f64 * factor).ceil() as usize),
            FamilySize::Cutoff { hz, min } => FamilySize::Cutoff {
                hz: hz * factor,
                min: (min as f64 * factor).ceil() as usize,
            },
        }
    }
}

impl fmt::Display for FamilySize {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            FamilySize::Count(n) => write!(f, "{n}"),
            FamilySize::Cutoff { hz, min } => write!(f, "below {hz} Hz (at least {min})"),
        }
    }
}

/// The reduced basis of a problem.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub enum BasisSpec {
    /// The `N` lowest modes whatever their family (the seed paper's choice, `mesh.reduced_modes`).
    Lowest(usize),
    /// Modes chosen per family (`[mesh.basis]`).
    PerFamily {
        /// Bending modes per plane (x–y and x–z get the same count).
        bending: FamilySize,
        torsional: FamilySize,
        axial: FamilySize,
        /// Add the static corrections of a unit bit force (axial) and bit torque (torsional),
        /// M-orthogonalised against the kept modes (Craig & Kurdila, *Fundamentals of Structural
        /// Dynamics*, 2nd ed., §14.4: the mode-acceleration / attachment-mode correction), and
        /// the resting shape of each bending plane (the static deflection under the string's
        /// weight with the wall's contact, `rom::resting`): four vectors.
        static_corrections: bool,
        /// With the static corrections, add the lateral shapes of the finite-element model's
        /// steady drilling state at the problem's operating point (`rom::SteadyState`, built by
        /// `sim::reduced_model`): up to two vectors per plane, so that the reduced string's
        /// steady contacts, wall forces and torque are the finite-element ones. Off by default:
        /// on a coarse basis they can leave the dynamics unstable where the finite-element model
        /// is not (docs/model.md, "Converged model"). Left out of the canonical form (the cache
        /// key) when false, so that the keys of files without it keep their revision's values.
        #[serde(skip_serializing_if = "std::ops::Not::not")]
        steady_shapes: bool,
    },
}

impl BasisSpec {
    /// Default basis, the same at any length (MODEL.md §7): 16 bending modes per plane, 8
    /// torsional, 4 axial, and the two bit static corrections. Counts, not cutoffs: what the
    /// metrics need is the resolution of the waves along the string, and a cutoff in Hz would keep
    /// hundreds of bending modes of a long string. Established by the refinement study in the
    /// docs/model.md ("Converged model"): against 32 / 16 / 8 the decision metrics of a 40 s seed
    /// window move less than their `verify` tolerances.
    pub const DEFAULT: BasisSpec = BasisSpec::PerFamily {
        bending: FamilySize::Count(16),
        torsional: FamilySize::Count(8),
        axial: FamilySize::Count(4),
        static_corrections: true,
        steady_shapes: false,
    };

    /// Whether the basis takes the steady drilling state's shapes (they need the static
    /// corrections' resting shapes beside them).
    pub fn steady_shapes(&self) -> bool {
        matches!(
            self,
            BasisSpec::PerFamily {
                static_corrections: true,
                steady_shapes: true,
                ..
            }
        )
    }

    /// The basis with every family enriched by `factor` (> 1), for solution verification; the
    /// lowest-N basis becomes the lowest ⌈factor N⌉.
    pub fn enriched(&self, factor: f64) -> BasisSpec {
        match *self {
            BasisSpec::Lowest(n) => BasisSpec::Lowest((n as f64 * factor).ceil() as usize),
            BasisSpec::PerFamily {
                bending,
                torsional,
                axial,
                static_corrections,
                steady_shapes,
            } => BasisSpec::PerFamily {
                bending: bending.enriched(factor),
                torsional: torsional.enriched(factor),
                axial: axial.enriched(factor),
                static_corrections,
                steady_shapes,
            },
        }
    }
}

impl fmt::Display for BasisSpec {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            BasisSpec::Lowest(n) => write!(f, "{n} lowest modes"),
            BasisSpec::PerFamily {
                bending,
                torsional,
                axial,
                static_corrections,
                steady_shapes,
            } => write!(
                f,
                "per family: bending {bending} per plane, torsional {torsional}, axial {axial}{}{}",
                if *static_corrections {
                    ", bit static corrections"
                } else {
                    ""
                },
                if *static_corrections && *steady_shapes {
                    ", steady-state shapes"
                } else {
                    ""
                }
            ),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn enrichment_multiplies_counts_and_cutoffs() {
        assert_eq!(BasisSpec::Lowest(51).enriched(1.5), BasisSpec::Lowest(77));
        let BasisSpec::PerFamily {
            bending, torsional, ..
        } = BasisSpec::DEFAULT.enriched(2.0)
        else {
            panic!("the default is per family")
        };
        assert_eq!(bending, FamilySize::Count(32));
        assert_eq!(torsional, FamilySize::Count(16));
        let cutoff = FamilySize::Cutoff { hz: 60.0, min: 3 };
        assert_eq!(
            cutoff.enriched(2.0),
            FamilySize::Cutoff { hz: 120.0, min: 6 }
        );
        assert_eq!(FamilySize::Count(3).enriched(1.5), FamilySize::Count(5));
    }
}
