//! The reduced-order model (MODEL.md §7, Eq. (20)): the full-mesh operators projected on the
//! lowest modes Φ (mass-normalised, zero on constrained DOFs), Q = Q_rigid(t) + Φ q.
//!
//! The rigid motion Q_rigid (u = V0 t, θx = Ω t at every node) carries no strain and no
//! acceleration, but the damping acts on absolute velocities (C = c M_pipe), so C Q̇_rigid projects
//! to a constant load; and the kinetic energy has cross terms Q̇_rigidᵀ M Φ q̇.
//!
//! The same equations hold for any basis Φ of full column rank once Φᵀ M Φ and Φᵀ K Φ are kept
//! as matrices: [`ReducedModel::unreduced`] takes Φ = the free DOFs themselves (the columns of the
//! identity), which is the finite-element model without reduction (issue 11: the reference the
//! reduced bases are checked against), with sparse operators and a sparse Newton matrix.

use super::{
    BasisError, BlockBasis, BlockWork, Family, ForceSummation, ModalBasis, Operator, SparseBasis,
    SteadyState,
};
use crate::fem::{
    AssembledMesh, BoundaryConditions, Dof, ElementInertia, ElementStrains, GlobalMatrices,
    StrainEnergy, assemble,
};
use crate::integrate::SparsityPattern;
use crate::model::{BasisSpec, Drillstring};
use faer::Par;
use nalgebra::{DMatrix, DVector};

/// Everything the simulator needs that does not change during a run.
#[derive(Debug, Clone)]
pub struct ReducedModel {
    pub string: Drillstring,
    /// The mesh (the assembled matrices are dropped after the projection).
    pub global: AssembledMesh,
    pub bc: BoundaryConditions,
    pub basis: ModalBasis,
    /// Φ, 6(N+1) × n.
    pub phi: DMatrix<f64>,
    /// Φ as dense per-family blocks: Φq and Φᵀf of the residual.
    pub blocks: BlockBasis,
    /// Φ by its non-zeros (each mode lives on its family's DOFs only).
    pub sparse: SparseBasis,
    /// ω² of the modes of `basis`, 1/s² (for the unreduced model: of every mode).
    pub omega2: DVector<f64>,
    /// Φᵀ M Φ: the identity for mass-normalised modes.
    pub mass: Operator,
    /// Φᵀ K Φ: Λ = diag(ω²) for modes.
    pub stiffness: Operator,
    /// c Φᵀ M_pipe Φ, 1/s (modal coordinates) or N·s/m and N·m·s/rad (nodal).
    pub damping: Operator,
    /// The non-zeros the Newton matrix can have, when it is sparse (the unreduced model).
    pub jacobian_pattern: Option<SparsityPattern>,
    /// Φᵀ F_gravity.
    pub gravity: DVector<f64>,
    /// Φᵀ C e_u and Φᵀ C e_θx (e: unit rigid axial / spin velocity): the damping of the rigid motion.
    pub rigid_damping: [DVector<f64>; 2],
    /// Φᵀ M e_u and Φᵀ M e_θx: kinetic-energy coupling of the rigid motion with the modes.
    pub rigid_mass: [DVector<f64>; 2],
    /// e_uᵀ C e_u, e_θᵀ C e_θ (pipe mass and polar inertia times c, for dissipation of the rigid motion).
    pub rigid_self_damping: [f64; 2],
    /// e_uᵀ M e_u, e_θᵀ M e_θ.
    pub rigid_self_mass: [f64; 2],
    /// Φᵀ G Φ, the gyroscopic matrix per unit spin rate (skew-symmetric).
    pub gyroscopic: DMatrix<f64>,
    /// The element kernels of each kind of element of the mesh (`global.layout`'s kinds, in
    /// their order): see [`Self::kernel`].
    pub kernels: Vec<ElementKernel>,
    /// The reduced model's recovery of the axial force and torque along the string from the
    /// loads below each section ([`ForceSummation`]); `None` for the unreduced model, whose
    /// strains carry them (its residual vanishes at every node).
    pub force_summation: Option<ForceSummation>,
    /// What became of the steady drilling state's shapes in the basis (set by
    /// `sim::reduced_model`, which finds the state; [`SteadyStatus::NotAsked`] otherwise).
    pub steady: SteadyStatus,
}

/// What became of the steady drilling state's shapes ([`SteadyState`]) in a reduced basis.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[serde(tag = "status", rename_all = "snake_case")]
pub enum SteadyStatus {
    /// Not asked for (`[mesh.basis] steady_shapes = false`, no static corrections, the N lowest
    /// modes, or a model built without a state).
    NotAsked,
    /// In the basis: the finite-element steady state at Ω (rad/s) and the feed V (m/s; a free
    /// top's steady block speed), found by `iterations` Newton iterations from the state of the
    /// basis without them.
    Added {
        omega: f64,
        v0: f64,
        iterations: usize,
    },
    /// Left out: the finite-element steady solve takes at most `limit` unknowns (dense Newton
    /// matrices) and the mesh has `unknowns`.
    MeshTooLarge { unknowns: usize, limit: usize },
    /// Left out: the basis without them has no steady drilling state at the operating point
    /// (a run from the pre-loaded start says why).
    NoReducedStart,
    /// Left out: Newton on the finite-element model's steady state without the wall's friction
    /// did not converge (`iterations`, the last lateral update in m).
    NotConverged { iterations: usize, update: f64 },
    /// Left out: the finite-element model's continuation in the wall's friction stopped at the
    /// share `reached` of it after `iterations` Newton iterations.
    FrictionContinuation { reached: f64, iterations: usize },
    /// Left out: the finite-element model's start failed otherwise (a non-finite state).
    NoFiniteElementStart,
}

/// What the residual evaluates on an element of one kind: its strain-energy law, the strain
/// operators at its quadrature points and its nonlinear inertia.
#[derive(Debug, Clone)]
pub struct ElementKernel {
    pub strain_law: StrainEnergy,
    pub strains: ElementStrains,
    pub inertia: ElementInertia,
}

fn to_na(m: &faer::Mat<f64>) -> DMatrix<f64> {
    DMatrix::from_fn(m.nrows(), m.ncols(), |i, j| m[(i, j)])
}

/// The operators that differ between modal and nodal coordinates.
struct Operators {
    mass: Operator,
    stiffness: Operator,
    damping: Operator,
    jacobian_pattern: Option<SparsityPattern>,
}

impl ReducedModel {
    /// Assemble, build the basis `spec` and project (without the steady state's shapes: see
    /// [`Self::with_steady_state`], and `sim::reduced_model` that finds the state).
    pub fn new(
        string: &Drillstring,
        elements: usize,
        spec: &BasisSpec,
    ) -> Result<Self, BasisError> {
        Self::build(string, elements, spec, None)
    }

    /// [`Self::new`] with the shapes of the steady drilling state `steady` in the basis, when
    /// `spec` asks for them ([`BasisSpec::steady_shapes`]).
    pub fn with_steady_state(
        string: &Drillstring,
        elements: usize,
        spec: &BasisSpec,
        steady: SteadyState<'_>,
    ) -> Result<Self, BasisError> {
        Self::build(string, elements, spec, Some(steady))
    }

    fn build(
        string: &Drillstring,
        elements: usize,
        spec: &BasisSpec,
        steady: Option<SteadyState<'_>>,
    ) -> Result<Self, BasisError> {
        let global = assemble(string, elements);
        let bc = BoundaryConditions::drillstring(elements);
        let basis = ModalBasis::of_string(&global, string, &bc, spec, steady, Par::Seq)?;
        let phi = to_na(&basis.shapes);
        let families: Vec<_> = basis.modes.iter().map(|m| m.family).collect();
        let omega2 =
            DVector::from_iterator(basis.len(), basis.modes.iter().map(|m| m.omega * m.omega));
        // The dense copies are dropped before the projection makes its own (peak memory).
        let damping = {
            let pipe_mass = to_na(&global.pipe_mass);
            let mut damping = phi.transpose() * (&pipe_mass * &phi) * string.damping;
            drop(pipe_mass);
            if string.stiffness_damping > 0.0 {
                // β Φᵀ K Φ as a product (not β Λ): the static corrections and resting shapes of
                // the basis are not eigenvectors of K.
                let stiffness = to_na(&global.stiffness);
                damping += phi.transpose() * (&stiffness * &phi) * string.stiffness_damping;
            }
            damping
        };
        let damping = Operator::Dense(damping);
        // Φᵀ K Φ is diag(ω²) for modes, static corrections and resting shapes (each block's
        // Ritz step keeps it so); the steady-state shapes are M-orthogonal to the resting
        // shapes but not K-orthogonal (resting shapes are not eigenvectors), so a basis with
        // them keeps the full product (its diagonal is ω²).
        let stiffness = if basis.counts().steady_shapes > 0 {
            let k = to_na(&global.stiffness);
            Operator::Dense(phi.transpose() * (&k * &phi))
        } else {
            Operator::Diagonal(omega2.clone())
        };
        let operators = Operators {
            mass: Operator::Identity,
            stiffness,
            damping,
            jacobian_pattern: None,
        };
        Ok(Self::project(
            string, global, bc, basis, phi, &families, omega2, operators,
        ))
    }

    /// The finite-element model without reduction: the generalised coordinates are the free
    /// DOFs (Φ = their columns of the identity, node-major), the mass and stiffness are the
    /// assembled ones restricted to them, and the Newton matrix is sparse (the DOFs of
    /// neighbouring nodes only). `basis` holds every mode of the mesh, for the frequencies the step
    /// rule needs and for the reports (it does not enter the equations).
    pub fn unreduced(string: &Drillstring, elements: usize) -> Result<Self, BasisError> {
        Self::nodal(string, elements, true)
    }

    /// [`Self::unreduced`] without its modes (`basis` empty, `omega2` zero): for static solves
    /// only (the steady state of `sim::reduced_model`), which use neither; a time integration
    /// needs the modes' frequencies (its step rule and error weights) and must not be given it.
    pub fn unreduced_for_statics(string: &Drillstring, elements: usize) -> Self {
        Self::nodal(string, elements, false).expect("no eigen-solve, no basis error")
    }

    fn nodal(string: &Drillstring, elements: usize, modes: bool) -> Result<Self, BasisError> {
        let global = assemble(string, elements);
        let bc = BoundaryConditions::drillstring(elements);
        let free = bc.free_dofs();
        let n = free.len();
        let (basis, omega2) = if modes {
            let basis = ModalBasis::of(&global, &bc, &BasisSpec::Lowest(n), Par::Seq)?;
            let omega2 = DVector::from_iterator(n, basis.modes.iter().map(|m| m.omega * m.omega));
            (basis, omega2)
        } else {
            let basis = ModalBasis {
                modes: Vec::new(),
                shapes: faer::Mat::zeros(global.dof(), 0),
            };
            (basis, DVector::zeros(n))
        };
        let mut phi = DMatrix::zeros(global.dof(), n);
        for (j, &i) in free.iter().enumerate() {
            phi[(i, j)] = 1.0;
        }
        let families: Vec<Family> = free.iter().map(|&i| Family::of(Dof::of_index(i))).collect();
        let restrict = |a: &faer::Mat<f64>| DMatrix::from_fn(n, n, |r, c| a[(free[r], free[c])]);
        let node = |j: usize| free[j] / crate::fem::DOF_PER_NODE;
        // Column j couples with the DOFs of its own node and of the neighbouring nodes.
        let pattern = SparsityPattern::new(n, |j| {
            (0..n).filter(|&i| node(i).abs_diff(node(j)) <= 1).collect()
        });
        let operators = Operators {
            mass: Operator::sparse_from(&restrict(&global.mass)),
            stiffness: Operator::sparse_from(&restrict(&global.stiffness)),
            damping: Operator::sparse_from(
                &(restrict(&global.pipe_mass) * string.damping
                    + restrict(&global.stiffness) * string.stiffness_damping),
            ),
            jacobian_pattern: Some(pattern),
        };
        Ok(Self::project(
            string, global, bc, basis, phi, &families, omega2, operators,
        ))
    }

    /// The projections common to every basis.
    #[allow(clippy::too_many_arguments)]
    fn project(
        string: &Drillstring,
        global: GlobalMatrices,
        bc: BoundaryConditions,
        basis: ModalBasis,
        phi: DMatrix<f64>,
        families: &[Family],
        omega2: DVector<f64>,
        operators: Operators,
    ) -> Self {
        let elements = global.elements;
        let modes = phi.ncols();
        let dof = global.dof();
        let gravity = phi.transpose() * DVector::from_fn(dof, |i, _| global.gravity[i]);
        let force_summation = operators.jacobian_pattern.is_none().then(|| {
            ForceSummation::new(
                [&global.mass, &global.pipe_mass, &global.stiffness],
                [string.damping, string.stiffness_damping],
                &global.gravity,
                elements + 1,
            )
        });
        // Each dense matrix is dropped as soon as it is used (peak memory on long meshes).
        let GlobalMatrices {
            mass: full_mass,
            pipe_mass: full_pipe_mass,
            stiffness,
            layout,
            ..
        } = global;
        drop(stiffness);
        let unit = |dof_kind: Dof| {
            DVector::from_fn(dof, |i, _| {
                if Dof::of_index(i) == dof_kind {
                    1.0
                } else {
                    0.0
                }
            })
        };
        let (eu, et) = (unit(Dof::U), unit(Dof::ThetaX));
        let (rigid_damping, rigid_self_damping) = {
            let c = to_na(&full_pipe_mass) * string.damping;
            drop(full_pipe_mass);
            (
                [phi.transpose() * (&c * &eu), phi.transpose() * (&c * &et)],
                [eu.dot(&(&c * &eu)), et.dot(&(&c * &et))],
            )
        };
        let (rigid_mass, rigid_self_mass) = {
            let mass = to_na(&full_mass);
            drop(full_mass);
            (
                [
                    phi.transpose() * (&mass * &eu),
                    phi.transpose() * (&mass * &et),
                ],
                [eu.dot(&(&mass * &eu)), et.dot(&(&mass * &et))],
            )
        };
        let global = AssembledMesh { layout, elements };
        let kernels: Vec<ElementKernel> = (global.layout.kinds().iter())
            .map(|kind| ElementKernel {
                strain_law: kind.strain_law,
                strains: ElementStrains::new(&kind.element),
                inertia: ElementInertia::new(&kind.element),
            })
            .collect();
        let g_kinds: Vec<_> = kernels.iter().map(|k| k.inertia.gyroscopic()).collect();
        let mut gyroscopic = DMatrix::zeros(modes, modes);
        for e in 0..elements {
            let g_e = &g_kinds[global.layout.kind(e)];
            let phi_e = phi.rows(6 * e, 12);
            gyroscopic += phi_e.transpose() * (g_e * phi_e);
        }
        let Operators {
            mass: reduced_mass,
            stiffness,
            damping,
            jacobian_pattern,
        } = operators;
        ReducedModel {
            string: string.clone(),
            global,
            bc,
            basis,
            blocks: BlockBasis::new(&phi, families),
            sparse: SparseBasis::new(&phi),
            phi,
            omega2,
            mass: reduced_mass,
            stiffness,
            damping,
            jacobian_pattern,
            gravity,
            rigid_damping,
            rigid_mass,
            rigid_self_damping,
            rigid_self_mass,
            gyroscopic,
            kernels,
            force_summation,
            steady: SteadyStatus::NotAsked,
        }
    }

    /// The kernels of element `e`.
    #[inline]
    pub fn kernel(&self, e: usize) -> &ElementKernel {
        &self.kernels[self.global.layout.kind(e)]
    }

    /// Whether the coordinates are the free DOFs themselves (no reduction).
    pub fn is_unreduced(&self) -> bool {
        self.jacobian_pattern.is_some()
    }

    /// Number of reduced coordinates n.
    pub fn size(&self) -> usize {
        self.phi.ncols()
    }

    /// Number of elements N.
    pub fn elements(&self) -> usize {
        self.global.elements
    }

    /// Number of nodes N + 1.
    pub fn nodes(&self) -> usize {
        self.global.elements + 1
    }

    /// Φᵀ K_t(Φq) Φ: the projected tangent of the internal force at the elastic state `q_full`
    /// (Φq on the full mesh), added into `out` (n × n). `scratch` (full DOF × n) receives K_t Φ,
    /// built element by element from the non-zeros of Φ only; Φᵀ (K_t Φ) then projects it with
    /// one dense product per family block of Φ. Nothing is allocated. `exact` selects the
    /// automatic-differentiation tangent instead of the fast finite-difference one.
    pub fn add_strain_tangent(
        &self,
        q_full: &DVector<f64>,
        out: &mut DMatrix<f64>,
        scratch: &mut DMatrix<f64>,
        work: &mut BlockWork,
        exact: bool,
    ) {
        scratch.fill(0.0);
        let rows = scratch.nrows();
        for e in 0..self.elements() {
            let d = crate::fem::ElementVector::from_fn(|i, _| q_full[6 * e + i]);
            let kernel = self.kernel(e);
            let k = if exact {
                (kernel.strains)
                    .internal_force_and_tangent(&kernel.strain_law, &d)
                    .1
            } else {
                kernel.strains.tangent_fast(&kernel.strain_law, &d)
            };
            // scratch[6e.., j] += K_e[.., c] Φ[6e + c, j] over the non-zeros of Φ's rows.
            let data = scratch.as_mut_slice();
            for c in 0..12 {
                let (modes, values) = self.sparse.dof(6 * e + c);
                let k_col = k.column(c);
                for (&j, &p) in modes.iter().zip(values) {
                    let col = &mut data[j * rows + 6 * e..j * rows + 6 * e + 12];
                    for (y, kr) in col.iter_mut().zip(k_col.iter()) {
                        *y += kr * p;
                    }
                }
            }
        }
        self.blocks.add_projected_columns(scratch, out, work);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn projected_operators_are_consistent() {
        let p = crate::problem::Problem::load(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/problems/seed_mc2014.toml"
        ))
        .unwrap();
        let r = ReducedModel::new(&p.model, 30, &BasisSpec::Lowest(51)).unwrap();
        // Tangent at rest = Φᵀ K Φ = Λ.
        let mut kt = DMatrix::zeros(51, 51);
        let mut scratch = DMatrix::zeros(r.phi.nrows(), 51);
        let mut work = r.blocks.workspace();
        r.add_strain_tangent(
            &DVector::zeros(r.phi.nrows()),
            &mut kt,
            &mut scratch,
            &mut work,
            true,
        );
        for i in 0..51 {
            for j in 0..51 {
                let expected = if i == j { r.omega2[i] } else { 0.0 };
                assert!(
                    (kt[(i, j)] - expected).abs() < 1e-8 * r.omega2.max(),
                    "Kt[{i},{j}] = {}",
                    kt[(i, j)]
                );
            }
        }
        // The two bending planes have the same modes up to signs, so one block of Φ serves both,
        // unless the mode count splits a pair (the 51 lowest of 30 elements hold 23 x–y and 22
        // x–z modes; the 52 lowest, 23 of each: one pair of twin blocks).
        assert_eq!(r.blocks.twins(), 0);
        assert_eq!(
            ReducedModel::new(&p.model, 30, &BasisSpec::Lowest(52))
                .unwrap()
                .blocks
                .twins(),
            1
        );
        // Gyroscopic matrix is skew; the rigid masses are the string's mass and polar inertia,
        // the latter with the bit's (lumped at the bit node).
        assert!(
            (&r.gyroscopic + r.gyroscopic.transpose()).abs().max()
                < 1e-12 * r.gyroscopic.abs().max().max(1e-30)
        );
        let l = p.model.length;
        let sec = crate::model::Section::of(&p.model);
        assert!((r.rigid_self_mass[0] - sec.pipe_mass * l).abs() < 1e-10 * sec.pipe_mass * l);
        let spin = sec.polar_inertia * l + p.model.bit_inertia;
        assert!(p.model.bit_inertia > 0.0);
        assert!((r.rigid_self_mass[1] - spin).abs() < 1e-10 * spin);
    }
}
