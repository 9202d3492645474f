//! Time integration: Newmark average acceleration (γ = ½, β = ¼) with Newton iterations on the
//! end-of-step acceleration, a local error estimate, and the adaptive stepper that controls the
//! step size from it (MODEL.md §7).

mod adaptive;
mod lu;
mod newmark;
mod sparse_lu;

pub use adaptive::{AdaptiveStepper, StepCounters, StepError, StepLimits};
pub use lu::{DenseLu, Singular};
pub use newmark::{ErrorNorm, Newmark, NewmarkSettings, StepOutcome, quadratic_form};
pub use sparse_lu::{LinearSolver, SparseLu, SparsityPattern};

use nalgebra::{DMatrix, DVector};

/// to = from, on slices: nalgebra's `copy_from` goes through its generic iterators, which do not
/// vectorise (the time-step loop copies vectors several times per residual).
pub fn copy_vector(to: &mut DVector<f64>, from: &DVector<f64>) {
    to.as_mut_slice().copy_from_slice(from.as_slice());
}

/// Weights of the Jacobian blocks: ca ∂r/∂q̈ + cv ∂r/∂q̇ + cq ∂r/∂q.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JacobianCoefficients {
    pub ca: f64,
    pub cv: f64,
    pub cq: f64,
}

/// A second-order system written as a residual r(t, q, q̇, q̈) = 0 in n unknowns.
pub trait ImplicitSystem {
    /// Number of unknowns n.
    fn size(&self) -> usize;
    /// r(t, q, q̇, q̈) into `out`.
    fn residual(
        &mut self,
        t: f64,
        q: &DVector<f64>,
        v: &DVector<f64>,
        a: &DVector<f64>,
        out: &mut DVector<f64>,
    );
    /// ca ∂r/∂q̈ + cv ∂r/∂q̇ + cq ∂r/∂q into `out` (may be approximate: Newton then converges
    /// linearly). `refresh` asks for the expensive parts to be recomputed.
    #[allow(clippy::too_many_arguments)]
    fn jacobian(
        &mut self,
        t: f64,
        q: &DVector<f64>,
        v: &DVector<f64>,
        a: &DVector<f64>,
        coefficients: JacobianCoefficients,
        refresh: bool,
        out: &mut DMatrix<f64>,
    );

    /// Called by Newmark before the residual evaluations of a step attempt: they will be at
    /// q = q_p + c_q q̈ and q̇ = v_p + c_v q̈, computed exactly so (bitwise: `q_p[i] + c_q * a[i]`),
    /// for varying q̈. A system may use this to evaluate faster; it must still check that the
    /// state it gets is of that form (the default ignores the announcement).
    fn begin_attempt(&mut self, _qp: &DVector<f64>, _vp: &DVector<f64>, _cq: f64, _cv: f64) {}

    /// Whether the last Jacobian is still good for the state of the last residual evaluation
    /// (e.g. no contact opened or closed since it was built), so that Newton may reuse its
    /// factorisation. The default, `false`, rebuilds it at every iteration.
    fn jacobian_reusable(&self) -> bool {
        false
    }
}
