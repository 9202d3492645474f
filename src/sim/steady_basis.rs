//! The reduced model whose basis holds the steady drilling state (issue 30).
//!
//! A wall stiff enough to carry the string's weight on micrometres of indentation makes every
//! contact force of a reduced string depend on micrometre patterns of its displacement, which
//! modes and resting shapes resolve only where the string lies evenly. Near a stabiliser, a
//! section boundary or the clamped top, the friction's climb up the wall moves the contacts by
//! such patterns: on the shipped 1 km well the default basis put the steady peak wall force at
//! the stabiliser 42.6 % above the finite-element model's, on the 466 m collar string 268 % above
//! (at the top), and on a 1.6 km well it put 10 % more torque on the string. The remedy is the
//! load-dependent Ritz vector of the actual loads (Wilson, Yuan & Dickens 1982): the
//! finite-element steady state itself, in the span of the basis ([`crate::rom::SteadyState`]).
//!
//! [`reduced_model`] builds the plain basis, finds its steady drilling state at the operating
//! point (the pre-loaded start; for a free top its steady block speed), runs Newton on the
//! finite-element model of the same mesh from that state (full friction, no continuation: the
//! reduced state has already climbed), and builds the basis again with the state's lateral
//! shapes. When a step fails the plain model is returned with the reason
//! ([`SteadyStatus`]): the shapes improve a basis, and their absence is reported, not hidden.

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
    let unknowns = plain.bc.free_count();
    if unknowns > STEADY_SHAPES_MAX_UNKNOWNS {
        return Ok(with_status(
            plain,
            SteadyStatus::MeshTooLarge {
                unknowns,
                limit: STEADY_SHAPES_MAX_UNKNOWNS,
            },
        ));
    }
    // The operating point of the steady state: a free top's at the block speed of the plain
    // basis' start.
    let op = if string.top.is_free() {
        match free_top_start(&plain, op, Effects::ALL) {
            Ok((_, v0, _)) => OperatingPoint { v0, ..op },
            Err(_) => return Ok(with_status(plain, SteadyStatus::NoReducedStart)),
        }
    } else {
        op
    };
    // The plain basis' steady state without the wall's friction starts the finite-element
    // model's own pre-loaded start (Newton from the straight string crawls along the stiff wall
    // for hundreds of iterations on a 3 km string and did not converge); from the straight
    // string when that fails. Φ_fe is the free DOFs' columns of the identity: Φ_feᵀ x restricts
    // x to them.
    let Ok((q, _)) = preloaded_from(&plain, op, Effects::ALL, DVector::zeros(plain.size()), true)
    else {
        return Ok(with_status(plain, SteadyStatus::NoReducedStart));
    };
    let fe = ReducedModel::unreduced_for_statics(string, mesh.elements);
    let guess = fe.phi.transpose() * (&plain.phi * &q);
    let found = preloaded_from(&fe, op, Effects::ALL, guess, false)
        .or_else(|_| preloaded_equilibrium(&fe, op, Effects::ALL));
    match found {
        Ok((q_fe, iterations)) => {
            let state = &fe.phi * &q_fe;
            let mut model = ReducedModel::with_steady_state(
                string,
                mesh.elements,
                &mesh.basis,
                SteadyState(state.as_slice()),
            )?;
            model.steady = SteadyStatus::Added {
                omega: op.omega,
                v0: op.v0,
                iterations,
            };
            Ok(model)
        }
        Err(SimulationError::StaticEquilibrium { iterations, update }) => Ok(with_status(
            plain,
            SteadyStatus::NotConverged { iterations, update },
        )),
        Err(SimulationError::FrictionContinuation {
            reached,
            iterations,
            ..
        }) => Ok(with_status(
            plain,
            SteadyStatus::FrictionContinuation {
                reached,
                iterations,
            },
        )),
        Err(_) => Ok(with_status(plain, SteadyStatus::NoFiniteElementStart)),
    }
}

fn with_status(mut model: ReducedModel, status: SteadyStatus) -> ReducedModel {
    model.steady = status;
    model
}
