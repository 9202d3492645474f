//! The lowest modes of the constrained linear drillstring, mass-normalised and labelled by family.
//!
//! The linear operators (7) and (9) do not couple the four families: axial (u), torsional (θx),
//! bending in the x–y plane (v, θz) and bending in the x–z plane (w, θy). Bending in y and in z
//! have the same frequencies, and a dense eigensolver would return arbitrary mixtures of such
//! degenerate pairs. So the free DOFs are split into the connected blocks of the (K, M) coupling
//! graph and each block is solved on its own; the modes are then merged by frequency. This is
//! general: a model that couples the families gives one block and still works. Each mode is
//! labelled by the family that holds most of its kinetic energy φᵢ (M φ)ᵢ.

use super::eigen::EigenError;
use super::family::Candidate;
use super::family::{BasisCounts, BasisError, Family, Mode, ModeKind};
use super::pencil::{Pencil, RitzLoads, bit_loads, solve_block};
use super::resting::BlockRest;
use crate::fem::{
    BoundaryConditions, Dof, GlobalMatrices, Lateral, SparseGlobal, SymmetricSparse, assemble,
    assemble_sparse, geometric_stiffness, weight_load,
};
use crate::model::{BasisSpec, Drillstring, FamilySize, WallContactLaw};
use faer::{Mat, Par};

/// The kept modes: frequencies, families and mass-normalised shapes on the full DOF set.
#[derive(Debug, Clone)]
pub struct ModalBasis {
    pub modes: Vec<Mode>,
    /// Mode shapes as columns, full 6(N+1) DOF (zero on constrained DOFs), Φᵀ M Φ = I and
    /// Φᵀ K Φ = diag(ω²) (with steady-state shapes: ω² on the diagonal, and terms between them
    /// and the resting shapes off it).
    pub shapes: Mat<f64>,
}

impl ModalBasis {
    /// Whether the modes of a mesh of `elements` elements are computed from sparse matrices
    /// ([`crate::fem::assemble_sparse`]) by Lanczos: when its bending blocks (about 2N DOFs) pass
    /// [`super::LANCZOS_MIN_BLOCK`]. Smaller meshes (every shipped problem) keep the dense path.
    pub fn sparse_mesh(elements: usize) -> bool {
        2 * elements > super::LANCZOS_MIN_BLOCK
    }

    /// Assemble the model on `elements` elements under the drillstring's constraints and build
    /// the basis `spec` (sparse for long meshes, see [`Self::sparse_mesh`]); refused when a family
    /// is left without a vector.
    pub fn compute(
        string: &Drillstring,
        elements: usize,
        spec: &BasisSpec,
    ) -> Result<Self, BasisError> {
        let bc = BoundaryConditions::drillstring(elements);
        let rest = Rest::of(string, elements, None);
        let basis = if Self::sparse_mesh(elements) {
            let global = assemble_sparse(string, elements);
            build(
                &Self::sparse_pencil(&global, &bc),
                &bc,
                spec,
                Some(&rest),
                Par::Seq,
            )
        } else {
            Self::build(
                &assemble(string, elements),
                &bc,
                spec,
                Some(&rest),
                Par::Seq,
            )
        };
        basis?.check_families(spec)
    }

    /// [`Self::of`] with the resting shapes of `string` (when `spec` asks for static
    /// corrections): the basis [`Self::compute`] gives, on matrices already assembled; with
    /// `steady`, and when `spec` asks for them, also the steady drilling state's shapes
    /// ([`SteadyState`]).
    pub fn of_string(
        global: &GlobalMatrices,
        string: &Drillstring,
        bc: &BoundaryConditions,
        spec: &BasisSpec,
        steady: Option<SteadyState<'_>>,
        par: Par,
    ) -> Result<Self, BasisError> {
        let rest = Rest::of(
            string,
            global.elements,
            steady.filter(|_| spec.steady_shapes()),
        );
        Self::build(global, bc, spec, Some(&rest), par)?.check_families(spec)
    }

    /// The `count` lowest modes of the drillstring on `elements` elements (no family check),
    /// sparse for long meshes as [`Self::compute`].
    pub fn compute_lowest(
        string: &Drillstring,
        elements: usize,
        count: usize,
    ) -> Result<Self, EigenError> {
        let bc = BoundaryConditions::drillstring(elements);
        let spec = BasisSpec::Lowest(count);
        let basis = if Self::sparse_mesh(elements) {
            let global = assemble_sparse(string, elements);
            build(
                &Self::sparse_pencil(&global, &bc),
                &bc,
                &spec,
                None,
                Par::Seq,
            )
        } else {
            Self::build(&assemble(string, elements), &bc, &spec, None, Par::Seq)
        };
        unwrap_eigen(basis)
    }

    /// The `count` lowest modes of assembled matrices (no family check).
    pub fn lowest(
        global: &GlobalMatrices,
        bc: &BoundaryConditions,
        count: usize,
        par: Par,
    ) -> Result<Self, EigenError> {
        unwrap_eigen(Self::build(
            global,
            bc,
            &BasisSpec::Lowest(count),
            None,
            par,
        ))
    }

    /// The basis `spec` of assembled matrices under the given boundary conditions, without the
    /// resting shapes (they need the wall: [`Self::of_string`]); refused when a family (bending,
    /// torsional, axial) is left without a vector.
    pub fn of(
        global: &GlobalMatrices,
        bc: &BoundaryConditions,
        spec: &BasisSpec,
        par: Par,
    ) -> Result<Self, BasisError> {
        Self::build(global, bc, spec, None, par)?.check_families(spec)
    }

    /// [`Self::of`] on sparse matrices: no dense storage; blocks above
    /// [`super::LANCZOS_MIN_BLOCK`] DOFs by Lanczos, the others densely (the same modes as
    /// [`Self::of`] on the same mesh).
    pub fn of_sparse(
        global: &SparseGlobal,
        bc: &BoundaryConditions,
        spec: &BasisSpec,
        par: Par,
    ) -> Result<Self, BasisError> {
        build(&Self::sparse_pencil(global, bc), bc, spec, None, par)?.check_families(spec)
    }

    fn sparse_pencil<'a>(global: &'a SparseGlobal, bc: &BoundaryConditions) -> Pencil<'a> {
        let free = bc.free_dofs();
        Pencil::Sparse {
            k: global.stiffness.submatrix(&free),
            m: global.mass.submatrix(&free),
            full_mass: &global.mass,
        }
    }

    fn check_families(self, spec: &BasisSpec) -> Result<Self, BasisError> {
        let counts = self.counts();
        for (family, n) in [
            ("bending", counts.bending),
            ("torsional", counts.torsional),
            ("axial", counts.axial),
        ] {
            if n == 0 {
                return Err(BasisError::EmptyFamily {
                    spec: spec.to_string(),
                    family,
                    counts,
                });
            }
        }
        Ok(self)
    }

    fn build(
        global: &GlobalMatrices,
        bc: &BoundaryConditions,
        spec: &BasisSpec,
        rest: Option<&Rest<'_>>,
        par: Par,
    ) -> Result<Self, BasisError> {
        let pencil = Pencil::Dense {
            k: bc.reduce(&global.stiffness),
            m: bc.reduce(&global.mass),
            full_mass: global.mass.as_ref(),
        };
        build(&pencil, bc, spec, rest, par)
    }

    /// Number of basis vectors.
    pub fn len(&self) -> usize {
        self.modes.len()
    }

    pub fn is_empty(&self) -> bool {
        self.modes.is_empty()
    }

    /// The modes of one family, in frequency order.
    pub fn family(&self, family: Family) -> impl Iterator<Item = &Mode> {
        self.modes.iter().filter(move |m| m.family == family)
    }

    /// How many vectors of each family the basis holds (normal modes by family; static
    /// corrections counted apart).
    pub fn counts(&self) -> BasisCounts {
        let mut c = BasisCounts::default();
        for m in &self.modes {
            match (m.kind, m.family) {
                (ModeKind::StaticCorrection, _) => c.static_corrections += 1,
                (ModeKind::RestingShape, _) => c.resting_shapes += 1,
                (ModeKind::SteadyShape, _) => c.steady_shapes += 1,
                (_, Family::Axial) => c.axial += 1,
                (_, Family::Torsional) => c.torsional += 1,
                (_, Family::BendingY | Family::BendingZ) => c.bending += 1,
            }
        }
        c
    }
}

/// The steady drilling state of the finite-element model on the basis' mesh (every DOF,
/// 6(N+1), m and rad; zero on the constrained ones), from which the basis takes Ritz vectors:
/// in each bending plane its own lateral part and the other plane's part turned into it
/// (v ← w, θz ← −θy and w ← v, θy ← −θz), so that the twin planes keep twin bases and the
/// state, turned by the climb of the wall's friction, is in their span.
///
/// Why: the wall is stiff (micrometres of indentation carry the weight), so a reduced string's
/// contact forces are only as good as its basis resolves micrometre patterns of displacement.
/// The resting shape and its compression sensitivity hold the string at rest and under a WOB,
/// but not the friction's climb near a stabiliser or the clamped top: there the basis put the
/// steady peak wall force 40-270 % above the finite-element model's (issue 30, `verify`'s
/// steady loads). With these vectors the steady state is in the span, and the reduced steady
/// loads are the finite-element ones (`tests/model/steady_shapes.rs`).
#[derive(Debug, Clone, Copy)]
pub struct SteadyState<'a>(pub &'a [f64]);

/// What the resting shapes need beyond (K, M): the weight loads along −y and −z on the full
/// DOF set, and the wall.
pub(super) struct Rest<'a> {
    weight: [Vec<f64>; 2],
    /// Geometric stiffness of a unit axial force on the full DOF set.
    geometric: SymmetricSparse,
    law: &'a dyn WallContactLaw,
    gap: f64,
    /// The wall law's factor at each node ([`crate::fem::ElementLayout::wall_factors`]).
    factors: Vec<f64>,
    /// The radial gap at each node, m.
    gaps: Vec<f64>,
    /// The steady drilling state whose shapes join the resting shapes.
    steady: Option<SteadyState<'a>>,
}

impl<'a> Rest<'a> {
    fn of(string: &'a Drillstring, elements: usize, steady: Option<SteadyState<'a>>) -> Self {
        let layout = crate::fem::ElementLayout::of(string, elements);
        Rest {
            steady,
            weight: [Lateral::Y, Lateral::Z].map(|axis| weight_load(string, elements, axis)),
            geometric: geometric_stiffness(string, elements),
            law: string.wall.law(),
            gap: string.gap(),
            factors: layout.wall_factors(string.wall_stiffness_per),
            gaps: layout.node_gaps(string.borehole_radius),
        }
    }
}

fn unwrap_eigen(basis: Result<ModalBasis, BasisError>) -> Result<ModalBasis, EigenError> {
    match basis {
        Ok(b) => Ok(b),
        Err(BasisError::Eigen(e)) => Err(e),
        Err(BasisError::EmptyFamily { .. }) => unreachable!("build does not check families"),
        Err(BasisError::RestingShape { .. }) => unreachable!("without a wall there is no shape"),
    }
}

/// The basis `spec` of a pencil (no family check): each coupled block solved on its own
/// ([`super::pencil`]), the candidates merged by frequency.
fn build(
    pencil: &Pencil<'_>,
    bc: &BoundaryConditions,
    spec: &BasisSpec,
    rest: Option<&Rest<'_>>,
    par: Par,
) -> Result<ModalBasis, BasisError> {
    let n = pencil.size();
    let free = bc.free_dofs();
    let family_of = |r: usize| Family::of(Dof::of_index(free[r]));
    if let BasisSpec::Lowest(count) = spec
        && *count > n
    {
        return Err(EigenError::TooMany {
            asked: *count,
            size: n,
        }
        .into());
    }
    let corrections = matches!(
        spec,
        BasisSpec::PerFamily {
            static_corrections: true,
            ..
        }
    );
    let loads = corrections.then(|| bit_loads(&free, bc.dof()));
    let rest = rest.filter(|_| corrections);
    // The resting-shape problem of a bending block: its weight load and the rows of its nodes'
    // lateral translations.
    let block_rest = |block: &[usize], family: Option<Family>| {
        let rest = rest?;
        let (translation, load) = match family? {
            Family::BendingY => (Dof::V, &rest.weight[0]),
            Family::BendingZ => (Dof::W, &rest.weight[1]),
            Family::Axial | Family::Torsional => return None,
        };
        let contact: Vec<usize> = (0..block.len())
            .filter(|&i| Dof::of_index(free[block[i]]) == translation)
            .collect();
        // The steady state's own part in this plane and the other plane's part turned into it.
        let steady = rest.steady.map_or_else(Vec::new, |SteadyState(x)| {
            let own = block.iter().map(|&r| x[free[r]]).collect();
            let turned = block
                .iter()
                .map(|&r| {
                    let node = free[r] / crate::fem::DOF_PER_NODE;
                    match Dof::of_index(free[r]) {
                        Dof::V => x[Dof::W.at(node)],
                        Dof::ThetaZ => -x[Dof::ThetaY.at(node)],
                        Dof::W => x[Dof::V.at(node)],
                        Dof::ThetaY => -x[Dof::ThetaZ.at(node)],
                        Dof::U | Dof::ThetaX => 0.0,
                    }
                })
                .collect();
            vec![own, turned]
        });
        Some(BlockRest {
            steady,
            load: block.iter().map(|&r| load[free[r]]).collect(),
            factors: contact
                .iter()
                .map(|&i| rest.factors[free[block[i]] / crate::fem::DOF_PER_NODE])
                .collect(),
            gaps: contact
                .iter()
                .map(|&i| rest.gaps[free[block[i]] / crate::fem::DOF_PER_NODE])
                .collect(),
            contact,
            law: rest.law,
            gap: rest.gap,
            geometric: Some(
                rest.geometric
                    .submatrix(&block.iter().map(|&r| free[r]).collect::<Vec<_>>()),
            ),
        })
    };
    let mut chosen: Vec<Candidate> = Vec::new();
    for (b, block) in pencil.blocks().into_iter().enumerate() {
        // A block whose DOFs are all of one family (the linear operators do not couple them).
        let family =
            Some(family_of(block[0])).filter(|f| block.iter().all(|&r| family_of(r) == *f));
        let size = match (spec, family) {
            (BasisSpec::Lowest(count), _) => FamilySize::Count(*count),
            (BasisSpec::PerFamily { .. }, None) => FamilySize::Count(block.len()),
            (
                BasisSpec::PerFamily {
                    bending,
                    torsional,
                    axial,
                    ..
                },
                Some(f),
            ) => match f {
                Family::Axial => *axial,
                Family::Torsional => *torsional,
                Family::BendingY | Family::BendingZ => *bending,
            },
        };
        let rest = block_rest(&block, family);
        chosen.extend(
            solve_block(
                pencil,
                &block,
                family,
                size,
                RitzLoads {
                    bit: loads,
                    rest: rest.as_ref(),
                },
                &family_of,
                par,
            )?
            .into_iter()
            .map(|c| Candidate { block: b, ..c }),
        );
    }
    chosen.sort_by(|a, b| a.lambda.total_cmp(&b.lambda));
    // Twin blocks (the two bending planes) have the same λ up to round-off, which Lanczos does
    // not reproduce bit for bit: keep such pairs in block order (y before z), as the dense solve
    // gives them.
    for i in 1..chosen.len() {
        let (a, b) = (&chosen[i - 1], &chosen[i]);
        if (b.lambda - a.lambda).abs() <= 1e-9 * a.lambda.abs().max(b.lambda.abs())
            && a.block > b.block
        {
            chosen.swap(i - 1, i);
        }
    }
    if let BasisSpec::Lowest(count) = spec {
        chosen.truncate(*count);
    }
    let count = chosen.len();
    let mut reduced = Mat::zeros(n, count);
    for (c, cand) in chosen.iter().enumerate() {
        for &(r, v) in &cand.entries {
            reduced[(r, c)] = v;
        }
    }
    let shapes = bc.expand(&reduced);
    let modes = chosen
        .iter()
        .enumerate()
        .map(|(c, cand)| {
            let omega = cand.lambda.max(0.0).sqrt();
            Mode {
                index: c + 1,
                freq_hz: omega / (2.0 * std::f64::consts::PI),
                omega,
                family: cand.family,
                kind: cand.kind,
                energy_share: pencil.energy_shares(shapes.as_ref(), c),
            }
        })
        .collect();
    Ok(ModalBasis { modes, shapes })
}
