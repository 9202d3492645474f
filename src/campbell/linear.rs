//! The drillstring linearised about its resting state, in the coordinates of a [`ReducedModel`]:
//!
//!   M q̈ + (Ω G + D) q̇ + (K_t + K_w) q = 0,
//!
//! with (n × n, n the number of reduced coordinates; modal coordinates for a reduced basis, where
//! M = Φᵀ M Φ = I):
//! - K_t = Φᵀ K_t(Φ q_s) Φ, the tangent stiffness of the strain energy (MODEL.md §3) at the resting
//!   state q_s, the static equilibrium under gravity with wall contact of
//!   [`crate::sim::static_equilibrium`] (no bit load, no motion). It is Φᵀ K Φ = Λ plus the
//!   geometric stiffness of the sag, computed as Λ + Φᵀ (K_t(Φq_s) − K_t(0)) Φ so that without
//!   contact it is Λ exactly;
//! - K_w = Σ over the nodes touching the wall at rest of P_mᵀ k_m P_m, P_m the rows of Φ of the
//!   node's (v, w), k_m = −∂F_FS/∂(v, w) the tangent of the wall law (MODEL.md §5) at rest:
//!   (k₁ + 3 k₂ δ²) n nᵀ along the contact normal n = (v, w)/r (the normal stiffness of the law),
//!   plus |F_FS|/r (I − n nᵀ) across it (the wall force turning with the contact point: the
//!   restoring "pendulum" stiffness of a pipe lying on the low side of the hole, w/r_c per unit
//!   length in Dawson & Paslay, *Drillpipe buckling in inclined holes*, JPT 36, 1984);
//! - G = Φᵀ G Φ per unit spin rate (skew-symmetric, [`ReducedModel::gyroscopic`]): the
//!   gyroscopic coupling −2ρI θ̇x θy θ̇z of the kinetic energy (MODEL.md §3) about the rigid spin
//!   θ̇x = Ω, which makes forward whirl stiffen with Ω. The nonlinear inertia has no stiffness
//!   term at rest (no Ω² term: the kinetic energy holds θ̇x only through (θ̇x − θy θ̇z)²), so
//!   nothing else depends on Ω;
//! - D = Φᵀ (c M_pipe + β K) Φ, the structural damping (β: `[model.pipe] stiffness_damping`),
//!   only when [`Linearisation::damping`] is set.
//!
//! Left out, to be said with every result: wall friction (its torque μ_FS |F_FS| R_bh sgn θ̇x
//! couples torsion to the lateral motion through |F_FS|, and its smoothed sign has a slope
//! 1/ε at rest), the wall's Hunt–Crossley damping (c_FS |δ|³ δ̇, zero to first order at δ = 0),
//! the bit (off bottom at rest), and the drilling loads (WOB compression and torque of the
//! pre-loaded state, which lower the bending frequencies; see the buckling margin).
//!
//! Without contact ([`Linearisation::contact`] false) the string is linearised about its straight
//! unloaded state (q = 0, no wall): K = Λ, and at Ω = 0 the frequencies are those of the basis.

use super::CampbellError;
use crate::fem::Dof;
use crate::rom::{Family, Operator, ReducedModel};
use crate::sim::{static_equilibrium, wall_contact};
use nalgebra::{DMatrix, DVector};
use serde::Serialize;

/// What the linearisation holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct Linearisation {
    /// About the resting state with the wall's contact stiffness (true, the default), or about
    /// the straight unloaded string without the wall (false).
    pub contact: bool,
    /// With the structural damping D = Φᵀ (c M_pipe + β K) Φ (default false: undamped, so the
    /// eigenvalues are ±iω).
    pub damping: bool,
}

impl Default for Linearisation {
    fn default() -> Self {
        Linearisation {
            contact: true,
            damping: false,
        }
    }
}

/// The resting state the string is linearised about.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RestingState {
    /// Nodes touching the wall.
    pub contact_nodes: usize,
    /// Position x of the first and last of them, m (None when none touches).
    pub contact_span_m: Option<[f64; 2]>,
    /// Sum of the wall normal forces, N: the weight the wall carries.
    pub wall_force_n: f64,
    /// Largest indentation into the wall, m.
    pub max_indentation_m: f64,
    /// Newton iterations of the static equilibrium.
    pub iterations: usize,
}

/// The linear system M q̈ + (Ω G + D) q̇ + K q = 0 and what labels its eigenvectors.
#[derive(Debug, Clone)]
pub struct LinearSystem {
    pub options: Linearisation,
    /// M, n × n (the identity in modal coordinates).
    pub mass: DMatrix<f64>,
    /// K = K_t + K_w, n × n, symmetric, N/m per coordinate unit (1/s² in modal coordinates).
    pub stiffness: DMatrix<f64>,
    /// G per unit spin rate, n × n, skew-symmetric.
    pub gyroscopic: DMatrix<f64>,
    /// D, n × n, when [`Linearisation::damping`] is set.
    pub damping: Option<DMatrix<f64>>,
    /// The family of each coordinate (a mode, a static correction or a free DOF lives on one).
    pub families: Vec<Family>,
    /// Rows of Φ for the lateral displacements v and w at every node, (N + 1) × n each.
    pub lateral: [DMatrix<f64>; 2],
    /// The resting state (None without contact).
    pub resting: Option<RestingState>,
    /// Whether M is the identity (modal coordinates).
    pub(super) mass_is_identity: bool,
    /// M⁻¹ K, M⁻¹ G and M⁻¹ D, for the first-order form.
    pub(super) inv_mass: [DMatrix<f64>; 3],
}

impl LinearSystem {
    /// Linearise `model` as `options` say (see the module documentation). Fails when the
    /// resting state does not converge or the mass is not positive definite.
    pub fn about_rest(model: &ReducedModel, options: Linearisation) -> Result<Self, CampbellError> {
        let n = model.size();
        let ndof = model.phi.nrows();
        let mut stiffness = model.stiffness.to_dense(n);
        let mut resting = None;
        if options.contact {
            let (q, iterations) = static_equilibrium(model)?;
            let q_full = &model.phi * &q;
            // The geometric stiffness of the sag: K_t(Φq_s) − K_t(0), projected.
            let mut scratch = DMatrix::zeros(ndof, n);
            let mut work = model.blocks.workspace();
            let mut at_rest = DMatrix::zeros(n, n);
            model.add_strain_tangent(&q_full, &mut at_rest, &mut scratch, &mut work, true);
            let mut straight = DMatrix::zeros(n, n);
            let zero = DVector::zeros(ndof);
            model.add_strain_tangent(&zero, &mut straight, &mut scratch, &mut work, true);
            stiffness += at_rest - straight;
            let string = &model.string;
            let mut state = RestingState {
                contact_nodes: 0,
                contact_span_m: None,
                wall_force_n: 0.0,
                max_indentation_m: 0.0,
                iterations,
            };
            let walls = crate::sim::WallGeometry::per_node(string, &model.global.layout);
            for (node, &wall) in walls.iter().enumerate() {
                let (iv, iw) = (Dof::V.at(node), Dof::W.at(node));
                // At rest: no slip, so no friction, whatever its law.
                let c = wall_contact(
                    string.wall.law(),
                    string.wall_friction,
                    wall,
                    crate::sim::NodeMotion {
                        position: [q_full[iv], q_full[iw]],
                        ..Default::default()
                    },
                );
                if !c.active {
                    continue;
                }
                let x = model.global.node_x(node);
                state.contact_nodes += 1;
                state.contact_span_m = Some(state.contact_span_m.map_or([x, x], |s| [s[0], x]));
                state.wall_force_n += c.normal.abs();
                state.max_indentation_m = state.max_indentation_m.max(c.indentation);
                let rows = [model.phi.row(iv), model.phi.row(iw)];
                for a in 0..2 {
                    for b in 0..2 {
                        let k = -c.stiffness[a][b];
                        if k != 0.0 {
                            stiffness.ger(k, &rows[a].transpose(), &rows[b].transpose(), 1.0);
                        }
                    }
                }
            }
            resting = Some(state);
        }
        let stiffness = 0.5 * (&stiffness + stiffness.transpose());
        let families = if model.is_unreduced() {
            let free = model.bc.free_dofs();
            free.iter().map(|&i| Family::of(Dof::of_index(i))).collect()
        } else {
            model.basis.modes.iter().map(|m| m.family).collect()
        };
        let rows_of =
            |dof: Dof| DMatrix::from_fn(model.nodes(), n, |node, j| model.phi[(dof.at(node), j)]);
        let damping = options.damping.then(|| model.damping.to_dense(n));
        let mass = match &model.mass {
            Operator::Identity => DMatrix::identity(n, n),
            m => m.to_dense(n),
        };
        let mut system = Self::from_parts(
            mass,
            stiffness,
            model.gyroscopic.clone(),
            damping,
            families,
            [rows_of(Dof::V), rows_of(Dof::W)],
        )?;
        system.options = options;
        system.resting = resting;
        Ok(system)
    }

    /// A system from its matrices (n × n each; `lateral`: (nodes × n) rows giving v and w),
    /// e.g. a finite-element model under other supports, or a rotor of a textbook.
    pub fn from_parts(
        mass: DMatrix<f64>,
        stiffness: DMatrix<f64>,
        gyroscopic: DMatrix<f64>,
        damping: Option<DMatrix<f64>>,
        families: Vec<Family>,
        lateral: [DMatrix<f64>; 2],
    ) -> Result<Self, CampbellError> {
        let n = mass.nrows();
        let identity = mass == DMatrix::identity(n, n);
        let zero = DMatrix::zeros(n, n);
        let inv_mass = if identity {
            [
                stiffness.clone(),
                gyroscopic.clone(),
                damping.clone().unwrap_or(zero),
            ]
        } else {
            let chol = mass.clone().cholesky().ok_or(CampbellError::Mass)?;
            [
                chol.solve(&stiffness),
                chol.solve(&gyroscopic),
                damping.as_ref().map_or(zero, |d| chol.solve(d)),
            ]
        };
        Ok(LinearSystem {
            options: Linearisation {
                contact: false,
                damping: damping.is_some(),
            },
            mass,
            stiffness,
            gyroscopic,
            damping,
            families,
            lateral,
            resting: None,
            mass_is_identity: identity,
            inv_mass,
        })
    }

    /// Number of coordinates n.
    pub fn size(&self) -> usize {
        self.mass.nrows()
    }
}
