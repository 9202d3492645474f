//! Natural frequencies of the rotating string against the spin rate Ω (the Campbell diagram),
//! forward and backward whirl, and critical speeds (MODEL.md §10, issue 14 item 4).
//!
//! The string is linearised about its resting state, in the problem's own coordinates (the
//! reduced basis Φ, or every free DOF for the unreduced model), as [`linear`] details:
//!
//!   q̈ + Ω G q̇ + (K_t + K_w) q = 0      (modal coordinates; + D q̇ with damping),
//!
//! K_t the strain tangent at rest (Λ = diag(ω²) plus the sag's geometric part), K_w the wall's
//! linearised contact stiffness at the nodes resting on it, G the gyroscopic matrix per unit
//! spin. Its eigenvalues at each Ω ([`spectrum`]) are labelled axial, torsional or bending and,
//! for bending, forward or backward whirl; a sweep over Ω follows each mode by its shape
//! ([`diagram`]); critical speeds are where a mode's frequency meets 1× and k× the rotation
//! frequency (bending modes; axial and torsional modes against k× only), refined on the
//! eigenvalue ([`critical`]).
//!
//! The classical references for gyroscopic rotors and their Campbell diagrams are Genta,
//! *Dynamics of Rotating Systems* (Springer, 2005) and Lalanne & Ferraris, *Rotordynamics
//! Prediction in Engineering* (Wiley, 1998); for drillstrings, Jansen, *Nonlinear rotor dynamics
//! as applied to oilwell drillstring vibrations* (J. Sound Vib. 147, 1991) and Spanos,
//! Chevallier, Politis & Payne (Shock Vib. Digest 35, 2003), who note that a tri-cone bit excites
//! the string at 3× the rotation frequency.
//!
//! Units: Ω in rad/s (rpm in reports), frequencies in Hz. Sign convention: Ω > 0 spins the string
//! about +x, turning +y towards +z (MODEL.md §2).

mod critical;
mod diagram;
mod linear;
mod spectrum;

pub use critical::{
    CRITICAL_SPEED_RULE, CriticalSpeed, MARGIN_CAP, MarginTable, REFINE_TOLERANCE, SEARCH_RATIO,
    crossings, geometric_grid, margin, margin_window, multiples, multiples_for, refine_root,
    sign_changes,
};
pub use diagram::{CampbellDiagram, Curve};
pub use linear::{LinearSystem, Linearisation, RestingState};
pub use spectrum::{
    EigenMode, ModeFamily, PLANAR, Spectrum, StateEigen, Whirl, circularity, classify, spectrum,
    state_eigen,
};

use crate::rom::ReducedModel;

/// Why a Campbell computation failed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CampbellError {
    #[error("the resting state to linearise about: {0}")]
    Rest(#[from] crate::sim::SimulationError),
    #[error("the mass matrix is not positive definite (Cholesky failed)")]
    Mass,
    #[error("the eigensolver did not converge at Ω = {omega_rpm:.4} rpm")]
    Eigen { omega_rpm: f64 },
}

/// `critical_speed_margin` at `omega` (rad/s > 0) of `model` with the default linearisation
/// (resting state, contact, undamped), against 1× and `multiple`: see [`margin`].
pub fn critical_speed_margin(
    model: &ReducedModel,
    multiple: f64,
    omega: f64,
) -> Result<f64, CampbellError> {
    let sys = LinearSystem::about_rest(model, Linearisation::default())?;
    let table = MarginTable::search(&sys, multiple, [omega, omega])?;
    Ok(table.margin(omega).unwrap_or(MARGIN_CAP))
}
