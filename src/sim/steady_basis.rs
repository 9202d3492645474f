//! The reduced model whose basis holds the steady drilling state (issue 30).
//!
//! A wall stiff enough to carry the string's weight on micrometres of indentation makes every
//! contact force of a reduced string depend on micrometre patterns of its displacement, which
//! modes and resting shapes resolve only where the string lies evenly. Near a stabiliser, a
//! section boundary or the clamped top, the friction's climb up the wall moves the contacts by
//! such patterns: on the shipped 1 km well the default basis put the steady peak wall force at
//! the stabiliser 42.6 % above the finite-element model's, on the 466 m collar string 268 % above
//! (at the top), and on a 1.6 km well 62 % above, with the torque up to 10 % off along the
//! string. The remedy is the
//! load-dependent Ritz vector of the actual loads (Wilson, Yuan & Dickens 1982): the
//! finite-element steady state itself, in the span of the basis ([`crate::rom::SteadyState`]).
//!
//! [`reduced_model`] builds the plain basis, finds its steady drilling state without the wall's
//! friction at the operating point (for a free top at the steady block speed of its pre-loaded
//! start), runs the finite-element model's own pre-loaded start of the same mesh from it (the
//! frictionless stage, then the continuation in the friction; from the straight string when
//! that fails), and builds the basis again with the state's lateral shapes. When a step fails
//! the plain model is returned with the reason ([`SteadyStatus`]): the shapes improve a basis,
//! and the commands report their absence (`simulate`, `verify`, `modes`, `campbell`, the
//! studies). A file asks for them (`[mesh.basis] steady_shapes = true`, off by default): on a
//! coarse basis they can leave the dynamics unstable where the finite-element model is not
//! (docs/model.md, "Converged model").

use super::run::preloaded_from;
use super::{Effects, SimulationError, free_top_start, preloaded_equilibrium};
use crate::model::{Drillstring, Mesh, OperatingPoint};
use crate::rom::{BasisError, ReducedModel, SteadyState, SteadyStatus};
use nalgebra::DVector;

/// The largest number of free DOFs (6 per node below the clamped top, less the bit's two lateral
/// translations) whose finite-element steady state [`reduced_model`] solves: twice
/// [`super::MAX_UNKNOWNS`], so that `verify`'s doubled mesh of any file whose base mesh has a
/// finite-element reference keeps the shapes. The finite-element Newton matrices are assembled
/// densely (n² entries; 1582 unknowns, a 264-element mesh: 26 s, one core).
pub const STEADY_SHAPES_MAX_UNKNOWNS: usize = 2600;

/// The finite-element steady drilling state that a basis takes its shapes from.
#[derive(Debug, Clone, PartialEq)]
pub struct FiniteElementSteadyState {
    /// The state on every DOF of the mesh, 6(N+1), m and rad (zero on the constrained ones).
    pub state: Vec<f64>,
    /// Ω (rad/s) and the feed V (m/s) it is the steady state of: the problem's operating point,
    /// with a free top's steady block speed found by the basis without the shapes.
    pub omega: f64,
    pub v0: f64,
    /// Newton iterations of the finite-element start.
    pub iterations: usize,
}

impl FiniteElementSteadyState {
    /// The status of a basis that holds its shapes.
    pub fn status(&self) -> SteadyStatus {
        SteadyStatus::Added {
            omega: self.omega,
            v0: self.v0,
            iterations: self.iterations,
        }
    }
}

/// The reduced model of `string` on `mesh` whose basis holds the shapes of the finite-element
/// steady drilling state at `op` when `mesh.basis` asks for them (see the module doc);
/// `model.steady` says what became of them.
///
/// Errors: those of the basis ([`ReducedModel::new`]); a steady state that cannot be found is not
/// an error (the plain model, with the reason in `model.steady`).
pub fn reduced_model(
    string: &Drillstring,
    mesh: &Mesh,
    op: OperatingPoint,
) -> Result<ReducedModel, BasisError> {
    let plain = ReducedModel::new(string, mesh.elements, &mesh.basis)?;
    if !mesh.basis.steady_shapes() {
        return Ok(plain);
    }
    match finite_element_steady_state(&plain, op) {
        Ok(steady) => reduced_model_with(string, mesh, &steady),
        Err(status) => Ok(with_status(plain, status)),
    }
}

/// The reduced model of `string` on `mesh` with the shapes of `steady` (found for this string or
/// another on the same mesh: a study's samples share their nominal string's, so that a sample's
/// basis does not depend on which other keys are uncertain); `model.steady` is
/// [`SteadyStatus::Added`].
///
/// Errors: those of the basis ([`ReducedModel::with_steady_state`]).
pub fn reduced_model_with(
    string: &Drillstring,
    mesh: &Mesh,
    steady: &FiniteElementSteadyState,
) -> Result<ReducedModel, BasisError> {
    let mut model = ReducedModel::with_steady_state(
        string,
        mesh.elements,
        &mesh.basis,
        SteadyState(&steady.state),
    )?;
    model.steady = steady.status();
    Ok(model)
}

/// The finite-element steady drilling state of `plain`'s string and mesh at `op`, started from
/// `plain`'s (a reduced model of them without the shapes); the reason when it cannot be found.
pub fn finite_element_steady_state(
    plain: &ReducedModel,
    op: OperatingPoint,
) -> Result<FiniteElementSteadyState, SteadyStatus> {
    let string = &plain.string;
    let unknowns = plain.bc.free_count();
    if unknowns > STEADY_SHAPES_MAX_UNKNOWNS {
        return Err(SteadyStatus::MeshTooLarge {
            unknowns,
            limit: STEADY_SHAPES_MAX_UNKNOWNS,
        });
    }
    // The operating point of the steady state: a free top's at the block speed of the plain
    // basis' start.
    let op = if string.top.is_free() {
        match free_top_start(plain, op, Effects::ALL) {
            Ok((_, v0, _)) => OperatingPoint { v0, ..op },
            Err(_) => return Err(SteadyStatus::NoReducedStart),
        }
    } else {
        op
    };
    // The plain basis' steady state without the wall's friction starts the finite-element
    // model's own pre-loaded start (its frictionless stage, then the continuation in the
    // friction); Newton from the straight string crawls along the stiff wall for hundreds of
    // iterations on a 3 km string. From the straight string when that fails; when both fail, the
    // first failure is the one reported. Φ_fe is the free DOFs' columns of the identity: Φ_feᵀ x
    // restricts x to them.
    let Ok((q, _)) = preloaded_from(plain, op, Effects::ALL, DVector::zeros(plain.size()), true)
    else {
        return Err(SteadyStatus::NoReducedStart);
    };
    let fe = ReducedModel::unreduced_for_statics(string, plain.elements());
    let guess = fe.phi.transpose() * (&plain.phi * &q);
    let found = match preloaded_from(&fe, op, Effects::ALL, guess, false) {
        Ok(found) => Ok(found),
        Err(first) => preloaded_equilibrium(&fe, op, Effects::ALL).map_err(|_| first),
    };
    match found {
        Ok((q_fe, iterations)) => Ok(FiniteElementSteadyState {
            state: (&fe.phi * &q_fe).as_slice().to_vec(),
            omega: op.omega,
            v0: op.v0,
            iterations,
        }),
        Err(SimulationError::StaticEquilibrium { iterations, update }) => {
            Err(SteadyStatus::NotConverged { iterations, update })
        }
        Err(SimulationError::FrictionContinuation {
            reached,
            iterations,
            ..
        }) => Err(SteadyStatus::FrictionContinuation {
            reached,
            iterations,
        }),
        Err(_) => Err(SteadyStatus::NoFiniteElementStart),
    }
}

/// `model` with `status`.
pub fn with_status(mut model: ReducedModel, status: SteadyStatus) -> ReducedModel {
    model.steady = status;
    model
}
