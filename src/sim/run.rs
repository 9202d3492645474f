//! One run: the starting state (the pre-loaded steady drilling state, or the paper's static
//! equilibrium under gravity with wall contact), then the adaptive Newmark march (MODEL.md §4, §7),
//! recording a [`TimeSeries`] and the stress envelope.
//!
//! Step control is the integrator's ([`crate::integrate::AdaptiveStepper`]: a step is accepted
//! when Newton converges and the local error estimate is ≤ 1; a PI controller sets the next one;
//! a failed Newton iteration halves it), never above the nominal step nor 1/20 of the lowest
//! torsional and axial periods ([`resolving_step`]). This refines automatically around impacts
//! (where the acceleration jumps) and coarsens again afterwards. A run that cannot go on (step
//! below the minimum, too many attempts, non-finite state, divergence) stops with an error and
//! keeps what it had recorded.

use super::envelope::StressEnvelope;
use super::series::{Frame, Row, Sink};
use super::{Dynamics, Effects, FreeTop, NodeContact, Observation, TimeSeries, WallGeometry};
use crate::fem::Dof;
use crate::fem::SectionStress;
use crate::integrate::{
    AdaptiveStepper, DenseLu, ImplicitSystem, JacobianCoefficients, LinearSolver, Newmark,
    NewmarkSettings, SparseLu, StepError, StepLimits,
};
use crate::model::OperatingPoint;
use crate::rom::{Operator, ReducedModel};
use nalgebra::{DMatrix, DVector};
use serde::Serialize;
use std::time::Instant;

/// Time window and step control of a run.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RunSettings {
    /// Simulated duration, s.
    pub duration: f64,
    /// Nominal (largest) time step, s.
    pub max_step: f64,
    /// Smallest step before the run is declared failed, s.
    pub min_step: f64,
    /// Radial-displacement probe positions, m.
    pub probes: Vec<f64>,
    pub newmark: NewmarkSettings,
    /// A lateral displacement beyond this many gaps means the run diverged.
    pub divergence_gaps: f64,
    /// Step attempts (accepted and rejected) after which the run stops: a step that collapses
    /// without reaching `min_step` would otherwise run for ever. Default: 10⁶ per simulated
    /// second (the converged seed run takes about 14 000), at least 10⁵.
    pub max_attempts: u64,
    /// Time from which the stress envelope is recorded (the analysis window's start), s.
    pub envelope_from: f64,
    /// A flag that stops the run after the step in progress (`drillopt simulate`'s Ctrl-C):
    /// [`SimulationError::Interrupted`], with what was computed kept. Not part of the run's
    /// settings for comparison or hashing.
    #[serde(skip)]
    pub stop: StopFlag,
}

/// A flag that asks a run to stop ([`RunSettings::stop`]); none by default. Equal to every other
/// flag: it does not change what a run computes, only where it ends.
#[derive(Debug, Clone, Copy, Default)]
pub struct StopFlag(pub Option<&'static std::sync::atomic::AtomicBool>);

impl StopFlag {
    /// Whether the run was asked to stop.
    pub fn raised(&self) -> bool {
        self.0
            .is_some_and(|f| f.load(std::sync::atomic::Ordering::Relaxed))
    }
}

impl PartialEq for StopFlag {
    fn eq(&self, _: &Self) -> bool {
        true
    }
}

impl RunSettings {
    pub fn new(duration: f64, max_step: f64) -> Self {
        RunSettings {
            duration,
            max_step,
            min_step: 1e-9,
            probes: Vec::new(),
            newmark: NewmarkSettings::default(),
            divergence_gaps: 50.0,
            max_attempts: (duration * MAX_ATTEMPTS_PER_SECOND).clamp(1e5, 1e12) as u64,
            envelope_from: 0.0,
            stop: StopFlag::default(),
        }
    }
}

/// Default step attempts allowed per simulated second (see [`RunSettings::max_attempts`]).
pub const MAX_ATTEMPTS_PER_SECOND: f64 = 1e6;

/// Where a run starts.
#[derive(Debug, Clone, PartialEq)]
pub enum InitialState {
    /// The paper's unloaded start: static equilibrium under gravity with wall contact (no bit
    /// load), then the rigid velocity field.
    StaticEquilibrium,
    /// The steady drilling state of the operating point (MODEL.md §4, pre-loaded): the elastic
    /// state at rest relative to the rigid motion (q̇ = 0) in equilibrium with gravity, wall
    /// contact and friction, the bit force at u̇ = V0 and torque at θ̇ = Ω, and the damping of the
    /// rigid motion: the compression and twist those loads make.
    Preloaded,
    /// Given modal displacements and velocities (relative to the rigid motion).
    Given { q: DVector<f64>, v: DVector<f64> },
}

impl From<crate::model::Start> for InitialState {
    fn from(start: crate::model::Start) -> Self {
        match start {
            crate::model::Start::Preloaded => InitialState::Preloaded,
            crate::model::Start::Unloaded => InitialState::StaticEquilibrium,
        }
    }
}

/// Counters of the integrator.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct SolverStats {
    pub steps: usize,
    pub rejected_steps: usize,
    pub newton_iterations: usize,
    pub min_dt: f64,
    pub max_dt: f64,
    pub static_iterations: usize,
    /// Residual evaluations and strain-tangent refreshes during the time march.
    pub residual_evaluations: usize,
    pub tangent_refreshes: usize,
    /// Gatherings of the wall's contact tangent kept apart in the Newton matrix (see
    /// `Dynamics::jacobian`).
    pub wall_tangent_refreshes: usize,
    /// Newton matrix factorisations during the time march.
    pub factorizations: usize,
    pub wall_time_s: f64,
}

/// Why a run stopped early.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SimulationError {
    #[error(
        "the starting equilibrium (static under gravity, or the pre-loaded drilling state) did not converge in {iterations} Newton iterations (last update {update:.2e} m)"
    )]
    StaticEquilibrium { iterations: usize, update: f64 },
    #[error(
        "the pre-loaded drilling state was found without wall friction, but the continuation in the friction coefficient stalled at {:.1} % of mu = {friction} after {iterations} Newton iterations in all; try a smaller model.wall.friction, a softer model.wall.stiffness, or [simulation] start = \"unloaded\"",
        100.0 * reached
    )]
    FrictionContinuation {
        reached: f64,
        friction: f64,
        iterations: usize,
    },
    #[error(
        "the run reached a state that no steel string survives: a von Mises stress of {stress_mpa:.0} MPa at x = {position_m:.2} m, above {limit_mpa:.0} MPa (10 times the yield strength and 2 % strain); check the inputs, the start and the basis (drillopt verify)"
    )]
    NonPhysicalStress {
        stress_mpa: f64,
        position_m: f64,
        limit_mpa: f64,
    },
    #[error(
        "the pre-loaded drilling state is not physical: its {quantity} is {} where the soft-string torque and drag of the string gives {} (allowed: within 5 % of it, or a friction part within 1/{factor} to {factor} times the estimate's); check the wall law's stiffness and friction and the bit law, or start from [simulation] start = \"unloaded\"",
        crate::units::sig(*state, 5),
        crate::units::sig(*estimate, 5)
    )]
    NonPhysicalStart {
        quantity: &'static str,
        state: f64,
        estimate: f64,
        factor: f64,
    },
    #[error(
        "no steady drilling state satisfies top = \"{top}\": {at} the top load is {load_ratio:.4} times its set-point or limit; lower the set-point or raise the limit, or choose another bit law"
    )]
    NoSteadyDrilling {
        top: &'static str,
        at: &'static str,
        load_ratio: f64,
    },
    #[error(
        "top = \"hook_load\" needs a positive, finite WOB set-point (the operating point's wob), got {wob} N"
    )]
    NoHookLoad { wob: f64 },
    #[error("at t = {time:.6} s the time step fell below {min_step:e} s ({reason})")]
    StepTooSmall {
        time: f64,
        min_step: f64,
        reason: String,
    },
    #[error(
        "at t = {time:.6} s the run had made {attempts} step attempts, its limit: the step keeps collapsing (last step {step:e} s)"
    )]
    TooManySteps { time: f64, attempts: u64, step: f64 },
    #[error("at t = {time:.6} s the recorder stopped the run (its output failed)")]
    RecordingStopped { time: f64 },
    #[error("at t = {time:.6} s the state became non-finite")]
    NonFinite { time: f64 },
    #[error("interrupted at t = {time:.6} s (a signal asked the run to stop)")]
    Interrupted { time: f64 },
    #[error(
        "at t = {time:.6} s the run diverged: lateral displacement {radial_over_gap:.1} times the gap"
    )]
    Diverged { time: f64, radial_over_gap: f64 },
}

impl From<StepError> for SimulationError {
    fn from(e: StepError) -> Self {
        match e {
            StepError::StepTooSmall { time, min_step } => SimulationError::StepTooSmall {
                time,
                min_step,
                reason: "Newton or the error test kept failing".into(),
            },
            StepError::TooManySteps {
                time,
                attempts,
                step,
            } => SimulationError::TooManySteps {
                time,
                attempts,
                step,
            },
            StepError::NonFinite { time } => SimulationError::NonFinite { time },
        }
    }
}

/// The outcome of a run: what was recorded (the sink it was given, by default the whole
/// [`TimeSeries`]), solver counters, and the error that stopped it, if any.
#[derive(Debug, Clone)]
pub struct RunOutput<S = TimeSeries> {
    pub series: S,
    pub stats: SolverStats,
    pub error: Option<SimulationError>,
    /// Final modal state (q, q̇).
    pub final_state: (DVector<f64>, DVector<f64>),
    /// The reduced basis the run used.
    pub basis: crate::rom::BasisCounts,
    /// The largest step allowed: the nominal step, or less (see [`resolving_step`]), s.
    pub max_step: f64,
    /// Section loads and von Mises stresses along the string, extremes and means from
    /// [`RunSettings::envelope_from`] on.
    pub envelope: StressEnvelope,
}

impl<S> RunOutput<S> {
    /// The sink, and the rest of the outcome.
    pub fn split(self) -> (S, RunOutput<()>) {
        let RunOutput {
            series,
            stats,
            error,
            final_state,
            basis,
            max_step,
            envelope,
        } = self;
        let rest = RunOutput {
            series: (),
            stats,
            error,
            final_state,
            basis,
            max_step,
            envelope,
        };
        (series, rest)
    }
}

/// Static equilibrium under gravity with wall contact (no motion, no bit): Newton on ∂r/∂q with
/// each update limited to half the radial gap at any node.
pub fn static_equilibrium(model: &ReducedModel) -> Result<(DVector<f64>, usize), SimulationError> {
    let effects = Effects {
        damping: false,
        gravity: true,
        wall: true,
        bit: false,
    };
    let rest = OperatingPoint {
        omega: 0.0,
        v0: 0.0,
        wob: 0.0,
    };
    equilibrium(model, rest, effects)
}

/// The steady drilling state at `op` (see [`InitialState::Preloaded`]): r(q, 0, 0) = 0 with every
/// load of `effects` at the rigid velocity field (MODEL.md §4, §11.6).
///
/// Found in two stages, so that it converges for any admissible friction: first without wall
/// friction (gravity, wall contact, the bit's steady loads and the damping of the rigid motion:
/// Newton from the straight string), then by continuation in the friction coefficient, μ_k
/// from 0 to μ, each stage a Newton solve from the last (the step in μ doubles after a stage
/// that converged in few iterations and halves after one that did not, down to 1/1024 of μ).
/// The friction of a string that turns and slides is a smooth function of the state (the slip of
/// its contact points is the rigid motion's), so the continuation path is smooth; Newton from
/// the straight string at full friction, with the friction's tangent left out, failed for
/// μ ≥ 0.05 on the 466 m collar string and erratically on the seed (issue "Friction as it is in
/// a well"). The state found is then checked against the soft-string torque and drag
/// ([`crate::model::SoftString`], see [`check_against_soft_string`]): a state that does not match
/// is an error, never a silent start.
pub fn preloaded_equilibrium(
    model: &ReducedModel,
    op: OperatingPoint,
    effects: Effects,
) -> Result<(DVector<f64>, usize), SimulationError> {
    preloaded_from(model, op, effects, DVector::zeros(model.size()), false)
}

/// [`preloaded_equilibrium`] from the state `q` instead of the straight string; with
/// `frictionless`, only its first stage (the steady state without the wall's friction).
pub(super) fn preloaded_from(
    model: &ReducedModel,
    op: OperatingPoint,
    effects: Effects,
    mut q: DVector<f64>,
    frictionless: bool,
) -> Result<(DVector<f64>, usize), SimulationError> {
    let mut sys = Dynamics::new(model, op, effects);
    let mut newton = EquilibriumNewton::new(model);
    let friction = model.string.wall.law().friction();
    let slipping = op.omega != 0.0 || op.v0 != 0.0;
    if !(effects.wall && friction > 0.0 && slipping) {
        let iterations = newton
            .solve(&mut sys, &mut q, STATIC_ITERATIONS)
            .map_err(not_converged)?;
        return Ok((q, iterations));
    }
    sys.set_friction_scale(0.0);
    let mut total = newton
        .solve(&mut sys, &mut q, STATIC_ITERATIONS)
        .map_err(not_converged)?;
    if frictionless {
        return Ok((q, total));
    }
    let climb = ClimbPredictor::new(model, op);
    let (mut reached, mut step) = (0.0_f64, 1.0_f64);
    let mut trial = q.clone();
    while reached < 1.0 {
        let target = (reached + step).min(1.0);
        sys.set_friction_scale(target);
        climb.predict(&q, reached, target, &mut trial);
        let outcome = newton.solve(&mut sys, &mut trial, CONTINUATION_ITERATIONS);
        match outcome {
            Ok(iterations) => {
                total += iterations;
                q.copy_from(&trial);
                reached = target;
                if iterations <= CONTINUATION_ITERATIONS / 4 {
                    step *= 2.0;
                }
            }
            Err((iterations, _)) => {
                total += iterations;
                step *= 0.5;
                if step < 1.0 / 1024.0 || total > CONTINUATION_BUDGET {
                    return Err(SimulationError::FrictionContinuation {
                        reached,
                        friction,
                        iterations: total,
                    });
                }
            }
        }
    }
    Ok((q, total))
}

/// The predictor of the friction continuation: a string lying on the low side of the hole that
/// turns climbs the wall until the weight's component along the wall balances the friction,
/// tan φ = μ c_t (per contact point: the normal force N = w cos φ, the friction μ N c_t along the
/// wall; c_t = Ω R_ext / S the circumferential share of the slip, [`crate::model::SoftString`]).
/// Raising the friction from μ_a to μ_b turns the resting shape about the hole's axis by
/// φ(μ_b) − φ(μ_a), against the spin. Newton alone cannot take that step: a lateral update
/// along the wall is a chord of the hole's circle, and the penalty wall's stiffness turns the
/// chord's radial error (Δ²/(2 gap)) into forces as large as the weight for Δ of 0.1 mm, so
/// Newton crept at 0.1 mm per iteration. The predictor turns every node's (v, w) and (θy, θz)
/// by the angle (a rotation keeps the radii) and projects back on the basis (least squares);
/// Newton then corrects what the uniform turn misses (the hanging ends, the twist and the
/// compression of the new friction).
struct ClimbPredictor<'m> {
    model: &'m ReducedModel,
    /// tan φ of the full friction, μ c_t ([`crate::model::SoftString::climb_angle`]).
    slope: f64,
    /// Thin QR of Φ (Q, R) for the least-squares projection (None when the law has no lateral
    /// friction).
    qr: Option<(DMatrix<f64>, DMatrix<f64>)>,
}

impl<'m> ClimbPredictor<'m> {
    fn new(model: &'m ReducedModel, op: OperatingPoint) -> Self {
        // tan φ of the full friction; a share λ of it climbs to tan φ_λ = λ tan φ.
        let slope = crate::model::SoftString::steady(&model.string, op)
            .climb_angle
            .tan();
        let qr = (slope != 0.0).then(|| {
            let qr = model.phi.clone().qr();
            (qr.q(), qr.r())
        });
        ClimbPredictor { model, slope, qr }
    }

    /// `out` = `q` turned from the climb of friction share `from` to that of `to`.
    fn predict(&self, q: &DVector<f64>, from: f64, to: f64, out: &mut DVector<f64>) {
        let Some((qm, rm)) = &self.qr else {
            out.copy_from(q);
            return;
        };
        // Turn by −(φ_b − φ_a) for Ω > 0: the pipe climbs against its spin (see the doc).
        let angle = -((to * self.slope).atan() - (from * self.slope).atan());
        let (sin, cos) = angle.sin_cos();
        let mut full = &self.model.phi * q;
        for node in 0..self.model.nodes() {
            let (iv, iw) = (Dof::V.at(node), Dof::W.at(node));
            let (ty, tz) = (Dof::ThetaY.at(node), Dof::ThetaZ.at(node));
            let (v, w) = (full[iv], full[iw]);
            full[iv] = cos * v - sin * w;
            full[iw] = sin * v + cos * w;
            let (a, b) = (full[ty], full[tz]);
            full[ty] = cos * a - sin * b;
            full[tz] = sin * a + cos * b;
        }
        // min ‖Φ x − full‖: R x = Qᵀ full.
        match rm.solve_upper_triangular(&(qm.transpose() * &full)) {
            Some(x) if x.iter().all(|v| v.is_finite()) => out.copy_from(&x),
            _ => out.copy_from(q),
        }
    }
}

/// The error of a Newton solve of the starting state that did not converge.
fn not_converged((iterations, update): (usize, f64)) -> SimulationError {
    SimulationError::StaticEquilibrium { iterations, update }
}

/// r(q, 0, 0) = 0 at `op` with `effects`, from the straight string: see [`EquilibriumNewton`].
fn equilibrium(
    model: &ReducedModel,
    op: OperatingPoint,
    effects: Effects,
) -> Result<(DVector<f64>, usize), SimulationError> {
    let mut sys = Dynamics::new(model, op, effects);
    let mut q = DVector::zeros(model.size());
    let iterations = EquilibriumNewton::new(model)
        .solve(&mut sys, &mut q, STATIC_ITERATIONS)
        .map_err(not_converged)?;
    Ok((q, iterations))
}

/// Newton on r(q, 0, 0) = 0 with each lateral update limited to half the gap at any node and a
/// backtracking line search on the residual norm; its buffers sized once.
struct EquilibriumNewton<'m> {
    model: &'m ReducedModel,
    lu: LinearSolver,
    r: DVector<f64>,
    j: DMatrix<f64>,
    dq_full: DVector<f64>,
    trial: DVector<f64>,
    r_trial: DVector<f64>,
    dir: DVector<f64>,
    zero: DVector<f64>,
}

impl<'m> EquilibriumNewton<'m> {
    fn new(model: &'m ReducedModel) -> Self {
        let n = model.size();
        EquilibriumNewton {
            model,
            lu: match &model.jacobian_pattern {
                Some(pattern) => LinearSolver::Sparse(Box::new(SparseLu::new(pattern))),
                None => LinearSolver::Dense(DenseLu::new(n)),
            },
            r: DVector::zeros(n),
            j: DMatrix::zeros(n, n),
            dq_full: DVector::zeros(model.phi.nrows()),
            trial: DVector::zeros(n),
            r_trial: DVector::zeros(n),
            dir: DVector::zeros(n),
            zero: DVector::zeros(n),
        }
    }

    /// Iterate from `q` (updated in place) for at most `limit` iterations: the iterations taken,
    /// or (the iterations, the last lateral update in m) when it did not converge.
    fn solve(
        &mut self,
        sys: &mut Dynamics,
        q: &mut DVector<f64>,
        limit: usize,
    ) -> Result<usize, (usize, f64)> {
        let model = self.model;
        let gap = model.string.gap();
        // A string of sections caps each node's update at half of its own gap (a near-gauge
        // stabiliser's 1.6 mm must not hold the drill pipe's 44 mm descent to the low side to
        // 0.8 mm a step); one section keeps the one gap's arithmetic, bit for bit.
        let gaps: Option<Vec<f64>> = (!model.string.sections.is_empty())
            .then(|| (0..model.nodes()).map(|k| sys.node_gap(k)).collect());
        let coefficients = JacobianCoefficients {
            ca: 0.0,
            cv: 0.0,
            cq: 1.0,
        };
        let zero = &self.zero;
        let mut update = f64::INFINITY;
        sys.residual(0.0, q, zero, zero, &mut self.r);
        for it in 1..=limit {
            let r_norm = self.r.norm();
            sys.jacobian(0.0, q, zero, zero, coefficients, true, &mut self.j);
            if self.lu.factor(&self.j).is_err() {
                return Err((it, update));
            }
            let dir = &mut self.dir;
            dir.copy_from(&self.r);
            self.lu.solve_in_place(dir);
            self.dq_full.gemv(1.0, &model.phi, dir, 0.0);
            let largest = (0..model.nodes())
                .map(|k| self.dq_full[Dof::V.at(k)].hypot(self.dq_full[Dof::W.at(k)]))
                .fold(0.0, f64::max);
            // Limit the lateral update to half the gap, then backtrack until the residual falls.
            let mut alpha = match &gaps {
                None if largest > 0.5 * gap => 0.5 * gap / largest,
                None => 1.0,
                Some(gaps) => {
                    let relative = (0..model.nodes())
                        .map(|k| {
                            self.dq_full[Dof::V.at(k)].hypot(self.dq_full[Dof::W.at(k)]) / gaps[k]
                        })
                        .fold(0.0, f64::max);
                    if relative > 0.5 { 0.5 / relative } else { 1.0 }
                }
            };
            loop {
                self.trial.copy_from(q);
                self.trial.axpy(-alpha, dir, 1.0);
                sys.residual(0.0, &self.trial, zero, zero, &mut self.r_trial);
                if self.r_trial.norm() < r_norm || alpha < 1e-3 {
                    break;
                }
                alpha *= 0.5;
            }
            q.copy_from(&self.trial);
            self.r.copy_from(&self.r_trial);
            update = alpha * largest;
            if !update.is_finite() {
                return Err((it, update));
            }
            // Converged when the full Newton update is below a picometre (at round-off the line
            // search may shorten a step that no longer changes anything).
            if largest < 1e-12 {
                return Ok(it);
            }
        }
        Err((limit, update))
    }
}

/// How far the pre-loaded state's friction may depart from the soft-string estimate's before
/// the start is refused: a factor of 4 either way. The estimate leaves out what a real state
/// has (the supported ends: a few per cent of a long string's weight, 21 % of the seed's 35 m;
/// buckling: at the helical load the extra contact force is of the order of the weight), so a
/// physical state lies within a factor of 2 of it; the non-physical states this catches were
/// off by 20 to 40 times (a 13.8 MN wall force on a 466 m string weighing 0.7 MN).
pub const SOFT_STRING_FACTOR: f64 = 4.0;

/// Whether the pre-loaded state observed as `obs` (at rest relative to the rigid motion, every
/// effect on) matches the soft-string torque and drag of the string ([`crate::model::SoftString`]):
/// its top torque and top force each within 5 % of the estimate (and a round-off floor of 1e-9
/// of the string's weight on the wall, the WOB or the TOB over the hole's radius, whichever is
/// largest, and of its moment at the hole's radius), or with a friction part (the
/// top load less the bit's and the damping's) within [`SOFT_STRING_FACTOR`] of the estimate's
/// either way; and the bit's elastic displacement and twist within that factor of the
/// estimate's (plus a gap and 0.1 rad, for strings whose estimate is near zero).
pub fn check_against_soft_string(
    model: &ReducedModel,
    op: OperatingPoint,
    obs: &Observation,
) -> Result<(), SimulationError> {
    let string = &model.string;
    let ss = crate::model::SoftString::steady(string, op);
    let (fa, ft) = ss.friction_part(string.length);
    let k = SOFT_STRING_FACTOR;
    // A round-off floor for an estimate of 0 (off bottom without an axial slip: a top force of
    // −3e-14 N is 0): 1e-9 of the largest of the string's weight on the wall, the WOB and the
    // TOB over the hole's radius, and of its moment at the hole's radius.
    let weight = (ss.normal_per_length.abs() * string.length)
        .max(ss.wob.abs())
        .max(ss.tob.abs() / string.borehole_radius);
    let load = |state: f64, estimate: f64, friction: f64, floor: f64| {
        let part = state - (estimate - friction);
        (state - estimate).abs() <= 0.05 * estimate.abs() + floor
            || (friction > 0.0 && part >= friction / k && part <= friction * k)
    };
    let displacement =
        |state: f64, estimate: f64, floor: f64| state.abs() <= k * estimate.abs() + floor;
    // (quantity, state, estimate, whether it passes), the first that fails refused.
    let checks = [
        (
            "top torque (N m)",
            obs.top_torque,
            ss.top_torque,
            load(
                obs.top_torque,
                ss.top_torque,
                ft,
                1e-9 * weight * string.borehole_radius,
            ),
        ),
        (
            "top force (N)",
            obs.top_force,
            ss.top_force,
            load(obs.top_force, ss.top_force, fa, 1e-9 * weight),
        ),
        (
            "elastic bit displacement (m)",
            obs.bit_u_elastic,
            ss.bit_displacement,
            displacement(obs.bit_u_elastic, ss.bit_displacement, string.gap()),
        ),
        (
            "elastic bit twist (rad)",
            obs.bit_theta_elastic,
            ss.bit_twist,
            displacement(obs.bit_theta_elastic, ss.bit_twist, 0.1),
        ),
    ];
    match checks.into_iter().find(|c| !c.3) {
        None => Ok(()),
        Some((quantity, state, estimate, _)) => Err(SimulationError::NonPhysicalStart {
            quantity,
            state,
            estimate,
            factor: k,
        }),
    }
}

/// Newton iterations allowed for the static equilibrium (and for the frictionless stage of the
/// pre-loaded start).
const STATIC_ITERATIONS: usize = 300;

/// Newton iterations allowed for one stage of the friction continuation, and for all of them.
const CONTINUATION_ITERATIONS: usize = 40;
const CONTINUATION_BUDGET: usize = 2000;

/// A node counts as having left the wall once its indentation is below −this × gap; its next
/// contact may then be an impact. Without this hysteresis, nodes resting on the wall chatter across
/// δ = 0 at sub-micrometre amplitude and every crossing would count as an impact.
pub const IMPACT_SEPARATION: f64 = 0.01;

/// Normal approach speed above which a touch-down counts as an impact, m/s. A node that lifts
/// off by a tenth of a millimetre and settles back under gravity arrives at √(2 g · 0.1 mm) ≈
/// 0.044 m/s; chatter of a resting node (sub-micrometre at a few hundred Hz) at ~1e-3 m/s. A
/// touch-down slower than 1 cm/s transfers little momentum and is not counted.
pub const IMPACT_SPEED: f64 = 0.01;

/// Count the impacts of one recorded state and update each node's separation flag: a node
/// that touches the wall after having left it (see [`IMPACT_SEPARATION`]) at a normal speed of
/// at least [`IMPACT_SPEED`] makes one impact. `first`: the initial state, which counts none.
fn count_impacts(
    separated: &mut [bool],
    contacts: &[NodeContact],
    gaps: &[f64],
    first: bool,
) -> u64 {
    let mut impacts = 0;
    for ((flag, c), &gap) in separated.iter_mut().zip(contacts).zip(gaps) {
        if c.active {
            if *flag && !first && c.approach_speed >= IMPACT_SPEED {
                impacts += 1;
            }
            *flag = false;
        } else if c.indentation < -IMPACT_SEPARATION * gap {
            *flag = true;
        }
    }
    impacts
}

/// Turns each accepted step into a [`Row`] for the run's sink, with the cumulative work and
/// impact count it carries, and records the stress envelope. Its buffers are sized once.
struct Recorder<S> {
    sink: S,
    /// Per node: separated from the wall by more than IMPACT_SEPARATION × gap since its last contact.
    separated: Vec<bool>,
    onsets: u64,
    /// The previous recorded time (s) and observation, and the cumulative works of the last row, J.
    last: Option<(f64, Observation)>,
    work: (f64, f64, f64),
    /// The radial gap at each node, m.
    gaps: Vec<f64>,
    envelope: StressEnvelope,
    stress: Vec<SectionStress>,
    /// The force-summation defects of each element ([`Dynamics::force_summation_defects`]).
    defects: Vec<[f64; 2]>,
    /// Radial displacement at each probe of the current row, m.
    probe_radial: Vec<f64>,
}

impl<S: Sink> Recorder<S> {
    /// Record the state at `t`; `false` when the sink asks to stop.
    fn push(
        &mut self,
        t: f64,
        op: &OperatingPoint,
        obs: Observation,
        sys: &Dynamics,
        probes: &[f64],
    ) -> bool {
        let first = self.last.is_none();
        self.onsets += count_impacts(&mut self.separated, &sys.contacts, &self.gaps, first);
        // Trapezoid rule on the powers between the previous and this recorded state.
        let (work_top, work_bit, dissipated) = match &self.last {
            Some((t0, prev)) => {
                let h = t - t0;
                let (wt, wb, d) = self.work;
                (
                    wt + 0.5 * h * (prev.power_top + obs.power_top),
                    wb + 0.5 * h * (prev.power_bit + obs.power_bit),
                    d + 0.5 * h * (prev.dissipation + obs.dissipation),
                )
            }
            None => (0.0, 0.0, 0.0),
        };
        self.work = (work_top, work_bit, dissipated);
        let values = Row::values_of(&Frame {
            t,
            op: *op,
            obs: &obs,
            work_top,
            work_bit,
            dissipated,
        });
        for (r, &x) in self.probe_radial.iter_mut().zip(probes) {
            *r = sys.radial_at(x);
        }
        let go_on = self.sink.record(&Row {
            values,
            nodes_in_contact: obs.nodes_in_contact,
            contact_onsets: self.onsets,
            probe_radial: &self.probe_radial,
        });
        // The rigid spin Ω t: with the elastic θx, the sections' absolute rotation (fatigue).
        // (Not before the envelope's window: it records nothing there.)
        let defects: &[[f64; 2]] =
            if t >= self.envelope.from_s && sys.force_summation_defects(&mut self.defects) {
                &self.defects
            } else {
                &[]
            };
        self.envelope.record(
            t,
            sys.displacement_full(),
            op.omega * t,
            &self.stress,
            defects,
        );
        self.last = Some((t, obs));
        go_on
    }
}

/// Steps per period of the lowest torsional and lowest axial mode that the step never falls
/// below (see [`resolving_step`]).
pub const STEPS_PER_PERIOD: f64 = 20.0;

/// The largest step that resolves the lowest torsional and axial modes with
/// [`STEPS_PER_PERIOD`] steps per period, s. The local error estimate cannot ask for this: from
/// the pre-loaded steady state, stick-slip and bit-bounce grow out of round-off, where the error
/// of any step is at round-off too; with steps longer than the period (the paper's 69 ms against
/// the seed's 59 ms first torsional period) average acceleration shrinks the growth rate of the
/// unstable torsional mode to almost nothing (by (ωh/2)⁻² per unit time) and the steady state
/// survives for ever. ∞ when the basis has neither family.
pub fn resolving_step(model: &ReducedModel) -> f64 {
    let lowest = |family| {
        model
            .basis
            .family(family)
            .map(|m| m.freq_hz)
            .fold(f64::INFINITY, f64::min)
    };
    // The higher of the two lowest frequencies: both modes get at least STEPS_PER_PERIOD steps.
    let f = [crate::rom::Family::Torsional, crate::rom::Family::Axial]
        .map(lowest)
        .into_iter()
        .filter(|f| f.is_finite())
        .fold(0.0, f64::max);
    if f > 0.0 {
        1.0 / (STEPS_PER_PERIOD * f)
    } else {
        f64::INFINITY
    }
}

/// The Newmark integrator of `model` from (q0, q̇0) at t = 0, with the energy norm in its error
/// and Newton tests (modal coordinates: weights ω_i, floored at the lowest mode's so that no
/// coordinate is ignored; nodal coordinates: √(qᵀ K q), the same norm) and, for the unreduced
/// model, a sparse LU of its Newton matrices.
/// With a free top (q0 one longer than the basis) the block's coordinate s weighs like a modal
/// coordinate of the lowest frequency and the string's axial mass, ω_min √M_s (in a sparse energy
/// norm, the diagonal entry ω_min² M_s), and the Newton matrix gains a full last row and column.
fn integrator(
    model: &ReducedModel,
    settings: crate::integrate::NewmarkSettings,
    q0: DVector<f64>,
    v0: DVector<f64>,
) -> Newmark {
    let n = model.size();
    let size = q0.len();
    let block = size > n;
    let floor = model.omega2.min().max(1e-12).sqrt();
    let block_weight2 = floor * floor * model.rigid_self_mass[0];
    let nm = Newmark::new(settings, 0.0, q0, v0, DVector::zeros(size));
    let nm = match &model.stiffness {
        Operator::Sparse(k) if block => nm.with_energy_norm(bordered(k, block_weight2)),
        Operator::Sparse(k) => nm.with_energy_norm(k.clone()),
        _ => {
            let mut weights = model.omega2.map(|w2| w2.sqrt().max(floor));
            if block {
                weights = weights.push(block_weight2.sqrt());
            }
            nm.with_weights(weights)
        }
    };
    match &model.jacobian_pattern {
        Some(pattern) if block => nm.with_sparse_jacobian(&pattern.bordered()),
        Some(pattern) => nm.with_sparse_jacobian(pattern),
        None => nm,
    }
}

/// `k` (n × n) with a last row and column that are zero but for `corner` on the diagonal.
fn bordered(
    k: &faer::sparse::SparseColMat<usize, f64>,
    corner: f64,
) -> faer::sparse::SparseColMat<usize, f64> {
    let n = k.nrows();
    let mut triplets: Vec<faer::sparse::Triplet<usize, usize, f64>> = Vec::new();
    let (col_ptr, row_idx, values) = (k.symbolic().col_ptr(), k.symbolic().row_idx(), k.val());
    for j in 0..n {
        for p in col_ptr[j]..col_ptr[j + 1] {
            triplets.push(faer::sparse::Triplet::new(row_idx[p], j, values[p]));
        }
    }
    triplets.push(faer::sparse::Triplet::new(n, n, corner));
    faer::sparse::SparseColMat::try_new_from_triplets(n + 1, n + 1, &triplets)
        .expect("a valid bordered pattern")
}

/// The system a run integrates: the string under the imposed feed, or with the block free.
// One per run, on the stack of the run: the variants' sizes do not matter.
#[allow(clippy::large_enum_variant)]
pub(super) enum Driven<'m> {
    Feed(Dynamics<'m>),
    Free(FreeTop<'m>),
}

impl<'m> Driven<'m> {
    pub(super) fn new(model: &'m ReducedModel, op: OperatingPoint, effects: Effects) -> Self {
        let dynamics = Dynamics::new(model, op, effects);
        match model.string.top {
            crate::model::TopDrive::Feed => Driven::Feed(dynamics),
            top => Driven::Free(FreeTop::new(dynamics, top)),
        }
    }

    fn dynamics(&self) -> &Dynamics<'m> {
        match self {
            Driven::Feed(d) => d,
            Driven::Free(f) => &f.dynamics,
        }
    }

    /// The string's modal part of an unknown vector, and the dynamics with the block's
    /// position set for a free top.
    fn string_part<'a>(&'a mut self, q: &'a DVector<f64>) -> (&'a mut Dynamics<'m>, &'a [f64]) {
        match self {
            Driven::Feed(d) => (d, q.as_slice()),
            Driven::Free(f) => {
                let n = q.len() - 1;
                f.dynamics.set_block_position(q[n]);
                (&mut f.dynamics, &q.as_slice()[..n])
            }
        }
    }

    /// [`Dynamics::start_surface`] at the state (q, q̇) of time `t` (the block's speed is V0 for
    /// the imposed feed, unknown n + 1 of q̇ for a free top).
    fn start_surface(&mut self, t: f64, q: &DVector<f64>, v: &DVector<f64>) {
        let speed = match self {
            Driven::Feed(d) => d.op().v0,
            Driven::Free(_) => v[v.len() - 1],
        };
        let (d, part) = self.string_part(q);
        d.start_surface(part, t, speed);
    }

    /// [`Dynamics::advance_surface`] to the accepted state q of time `t`.
    fn advance_surface(&mut self, t: f64, q: &DVector<f64>) {
        let (d, part) = self.string_part(q);
        d.advance_surface(part, t);
    }

    /// [`Dynamics::observe`] at time `t`, with the block's position and speed.
    fn observe(
        &mut self,
        t: f64,
        q: &DVector<f64>,
        v: &DVector<f64>,
        a: &DVector<f64>,
    ) -> Observation {
        match self {
            Driven::Feed(d) => {
                d.set_time(t);
                let mut obs = d.observe(q, v, a);
                obs.block_position = d.op().v0 * t;
                obs
            }
            Driven::Free(f) => {
                let mut r = DVector::zeros(q.len());
                f.residual(t, q, v, a, &mut r);
                f.observe_step(q, v, a)
            }
        }
    }

    /// [`Dynamics::observe_step`] at time `t`, with the block's position and speed.
    fn observe_step(
        &mut self,
        t: f64,
        q: &DVector<f64>,
        v: &DVector<f64>,
        a: &DVector<f64>,
    ) -> Observation {
        match self {
            Driven::Feed(d) => {
                let mut obs = d.observe_step(q, v, a);
                obs.block_position = d.op().v0 * t;
                obs
            }
            Driven::Free(f) => f.observe_step(q, v, a),
        }
    }
}

impl ImplicitSystem for Driven<'_> {
    fn size(&self) -> usize {
        match self {
            Driven::Feed(d) => d.size(),
            Driven::Free(f) => f.size(),
        }
    }

    fn begin_attempt(&mut self, qp: &DVector<f64>, vp: &DVector<f64>, cq: f64, cv: f64) {
        match self {
            Driven::Feed(d) => d.begin_attempt(qp, vp, cq, cv),
            Driven::Free(f) => f.begin_attempt(qp, vp, cq, cv),
        }
    }

    fn jacobian_reusable(&self) -> bool {
        match self {
            Driven::Feed(d) => d.jacobian_reusable(),
            Driven::Free(f) => f.jacobian_reusable(),
        }
    }

    fn residual(
        &mut self,
        t: f64,
        q: &DVector<f64>,
        v: &DVector<f64>,
        a: &DVector<f64>,
        out: &mut DVector<f64>,
    ) {
        match self {
            Driven::Feed(d) => d.residual(t, q, v, a, out),
            Driven::Free(f) => f.residual(t, q, v, a, out),
        }
    }

    fn jacobian(
        &mut self,
        t: f64,
        q: &DVector<f64>,
        v: &DVector<f64>,
        a: &DVector<f64>,
        c: JacobianCoefficients,
        refresh: bool,
        out: &mut DMatrix<f64>,
    ) {
        match self {
            Driven::Feed(d) => d.jacobian(t, q, v, a, c, refresh, out),
            Driven::Free(f) => f.jacobian(t, q, v, a, c, refresh, out),
        }
    }
}

/// Run the model at operating point `op` with the given effects, keeping every accepted step
/// in memory ([`TimeSeries`]).
pub fn simulate(
    model: &ReducedModel,
    op: OperatingPoint,
    effects: Effects,
    settings: &RunSettings,
    initial: InitialState,
    progress: impl FnMut(f64),
) -> RunOutput {
    let series = TimeSeries::with_probes(&settings.probes, 0);
    simulate_into(model, op, effects, settings, initial, series, progress)
}

/// [`simulate`], sending each accepted step (the initial state first) to `sink` as it is
/// accepted instead of keeping them: the run's memory does not grow with its duration unless the
/// sink's does. A sink that returns `false` stops the run with
/// [`SimulationError::RecordingStopped`].
pub fn simulate_into<S: Sink>(
    model: &ReducedModel,
    op: OperatingPoint,
    effects: Effects,
    settings: &RunSettings,
    initial: InitialState,
    sink: S,
    mut progress: impl FnMut(f64),
) -> RunOutput<S> {
    let clock = Instant::now();
    let n = model.size();
    let mut stats = SolverStats {
        min_dt: f64::INFINITY,
        ..Default::default()
    };
    let mut rec = Recorder {
        sink,
        separated: vec![false; model.nodes()],
        onsets: 0,
        last: None,
        work: (0.0, 0.0, 0.0),
        probe_radial: vec![0.0; settings.probes.len()],
        gaps: (WallGeometry::per_node(&model.string, &model.global.layout).iter())
            .map(|w| w.gap)
            .collect(),
        envelope: StressEnvelope::for_string(
            &model.string,
            &model.global.layout,
            settings.envelope_from,
        ),
        stress: {
            let sections = model.string.section_strings();
            (model.global.layout.kinds().iter())
                .map(|kind| SectionStress::new(&sections[kind.section], kind.element.length))
                .collect()
        },
        defects: vec![[0.0; 2]; model.elements()],
    };
    let preloaded = matches!(initial, InitialState::Preloaded);
    let free = model.string.top.is_free();
    // With a free top the block's position s is unknown n + 1 (s = 0 at the start), its speed
    // the steady one of the pre-loaded start, else 0 (the block at rest).
    let with_block = |(q, v, i): (DVector<f64>, DVector<f64>, usize), speed: f64| {
        if free && q.len() == n {
            (q.push(0.0), v.push(speed), i)
        } else {
            (q, v, i)
        }
    };
    // The steady block speed of a free top's pre-loaded start: the operating point's feed for
    // the soft-string check.
    let mut start_op = op;
    let equilibrium = match initial {
        InitialState::Given { q, v } => Ok(with_block((q, v, 0), op.v0)),
        InitialState::StaticEquilibrium => {
            static_equilibrium(model).map(|(q, i)| with_block((q, DVector::zeros(n), i), 0.0))
        }
        InitialState::Preloaded if free => {
            super::free_top_start(model, op, effects).map(|(q, speed, i)| {
                start_op.v0 = speed;
                with_block((q, DVector::zeros(n), i), speed)
            })
        }
        InitialState::Preloaded => {
            preloaded_equilibrium(model, op, effects).map(|(q, i)| (q, DVector::zeros(n), i))
        }
    };
    let (q0, v0) = match equilibrium {
        Ok((q, v, iterations)) => {
            stats.static_iterations = iterations;
            (q, v)
        }
        Err(e) => {
            stats.wall_time_s = clock.elapsed().as_secs_f64();
            let z = DVector::zeros(n + usize::from(free));
            return RunOutput {
                series: rec.sink,
                stats,
                error: Some(e),
                final_state: (z.clone(), z),
                basis: model.basis.counts(),
                max_step: settings.max_step.min(resolving_step(model)),
                envelope: rec.envelope,
            };
        }
    };
    let mut sys = Driven::new(model, op, effects);
    // A depth-of-cut bit: the bottom hole the start's steady drilling has cut.
    sys.start_surface(0.0, &q0, &v0);
    let mut nm = integrator(model, settings.newmark, q0, v0);
    let mut error = None;
    if preloaded && effects == Effects::ALL {
        let at_rest = DVector::zeros(n);
        let string_q = DVector::from_column_slice(&nm.q.as_slice()[..n]);
        let mut check = Dynamics::new(model, start_op, effects);
        let obs = check.observe(&string_q, &at_rest, &at_rest);
        error = check_against_soft_string(model, start_op, &obs).err();
    }
    if error.is_none() && !nm.consistent_acceleration(&mut sys) {
        error = Some(SimulationError::NonFinite { time: 0.0 });
    }
    let obs = sys.observe(0.0, &nm.q, &nm.v, &nm.a);
    if !rec.push(0.0, &op, obs, sys.dynamics(), &settings.probes) {
        error = Some(SimulationError::RecordingStopped { time: 0.0 });
    }
    let max_step = settings.max_step.min(resolving_step(model));
    let h0 = (max_step.min(settings.duration) * 0.01).max(settings.min_step);
    let limits = StepLimits {
        end_time: settings.duration,
        max_step,
        min_step: settings.min_step,
        max_attempts: settings.max_attempts,
    };
    let mut stepper = AdaptiveStepper::new(nm, h0, limits);
    while error.is_none() && !stepper.finished() {
        if let Err(e) = stepper.step(&mut sys) {
            error = Some(e.into());
            break;
        }
        let nm = &stepper.nm;
        let obs = sys.observe_step(nm.t, &nm.q, &nm.v, &nm.a);
        sys.advance_surface(nm.t, &nm.q);
        let ratio = obs.max_radial_over_gap;
        if !rec.push(nm.t, &op, obs, sys.dynamics(), &settings.probes) {
            error = Some(SimulationError::RecordingStopped { time: nm.t });
            break;
        }
        if ratio > settings.divergence_gaps {
            error = Some(SimulationError::Diverged {
                time: nm.t,
                radial_over_gap: ratio,
            });
            break;
        }
        progress(nm.t);
        error = stepper.check().err().map(SimulationError::from);
        if error.is_none() && settings.stop.raised() {
            error = Some(SimulationError::Interrupted { time: nm.t });
        }
    }
    let nm = &stepper.nm;
    let c = stepper.counters;
    (stats.steps, stats.rejected_steps, stats.newton_iterations) =
        (c.steps, c.rejected_steps, c.newton_iterations);
    (stats.min_dt, stats.max_dt) = (c.min_dt, c.max_dt);
    stats.wall_time_s = clock.elapsed().as_secs_f64();
    stats.residual_evaluations = sys.dynamics().residual_evaluations;
    stats.tangent_refreshes = sys.dynamics().tangent_refreshes;
    stats.wall_tangent_refreshes = sys.dynamics().wall_tangent_refreshes;
    stats.factorizations = nm.factorizations;
    if stats.steps == 0 {
        stats.min_dt = 0.0;
    }
    RunOutput {
        series: rec.sink,
        stats,
        final_state: (nm.q.clone(), nm.v.clone()),
        basis: model.basis.counts(),
        max_step,
        envelope: {
            rec.envelope.finish();
            if error.is_none() {
                error = non_physical_stress(&model.string, &rec.envelope).err();
            }
            rec.envelope
        },
        error,
    }
}

/// A von Mises stress above this many times the yield strength, and above 2 % strain times E
/// (ten times the 0.2 % yield strain of steel: a limit that a made-up yield strength cannot
/// lower), is not a state of a steel string: the run is refused with
/// [`SimulationError::NonPhysicalStress`] (it kept what it recorded).
pub const NON_PHYSICAL_STRESS_FACTOR: f64 = 10.0;

/// Whether the peak von Mises stress of a run is physical (see [`NON_PHYSICAL_STRESS_FACTOR`]).
fn non_physical_stress(
    string: &crate::model::Drillstring,
    envelope: &StressEnvelope,
) -> Result<(), SimulationError> {
    let pipe = &string.pipe;
    let strain_limit = 0.02 * pipe.youngs_modulus;
    let limit = pipe.yield_strength.map_or(strain_limit, |y| {
        (NON_PHYSICAL_STRESS_FACTOR * y).max(strain_limit)
    });
    match envelope.peak() {
        Some((stress, position)) if stress > limit => Err(SimulationError::NonPhysicalStress {
            stress_mpa: stress * 1e-6,
            position_m: position,
            limit_mpa: limit * 1e-6,
        }),
        _ => Ok(()),
    }
}

/// Which model of a problem runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ModelKind {
    /// Reduced on the problem's basis (`[mesh.basis]` or `mesh.reduced_modes`): every study.
    Reduced,
    /// The finite-element model without reduction (all free DOFs, sparse Newton matrices): the
    /// reference the reduced bases are checked against, affordable for windows of seconds.
    Unreduced,
}

impl ModelKind {
    /// The model of this kind of `string` on `mesh` (a problem's `[model]` and `[mesh]`); the
    /// reduced basis takes the steady drilling state at `op` (the problem's operating point:
    /// [`super::reduced_model`]).
    /// Errors: those of the basis ([`ReducedModel::new`], [`ReducedModel::unreduced`]).
    pub fn build(
        self,
        string: &crate::model::Drillstring,
        mesh: &crate::model::Mesh,
        op: OperatingPoint,
    ) -> Result<ReducedModel, crate::rom::BasisError> {
        match self {
            ModelKind::Reduced => super::reduced_model(string, mesh, op),
            ModelKind::Unreduced => ReducedModel::unreduced(string, mesh.elements),
        }
    }
}

/// Run `model` at `op` for `duration` seconds with every effect, as `simulation` (a problem's
/// `[simulation]`) says: its nominal step, probes and start, and the stress envelope from the
/// analysis window's start ([`crate::model::Simulation::settling_for`]). Each accepted step
/// goes to `sink` (see [`simulate_into`]); once `stop` is raised the run ends early with
/// [`SimulationError::Interrupted`] and what was computed (never, with `StopFlag::default()`).
pub fn run_model_until<S: Sink>(
    simulation: &crate::model::Simulation,
    model: &ReducedModel,
    op: OperatingPoint,
    duration: f64,
    sink: S,
    progress: impl FnMut(f64),
    stop: StopFlag,
) -> RunOutput<S> {
    let mut settings = RunSettings::new(duration, simulation.time_step);
    settings.probes = simulation.probes.clone();
    settings.envelope_from = simulation.settling_for(duration);
    settings.stop = stop;
    simulate_into(
        model,
        op,
        Effects::ALL,
        &settings,
        InitialState::from(simulation.start),
        sink,
        progress,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn touching(speed: f64) -> NodeContact {
        NodeContact {
            active: true,
            indentation: 1e-7,
            approach_speed: speed,
            ..Default::default()
        }
    }

    fn free(indentation: f64) -> NodeContact {
        NodeContact {
            indentation,
            ..Default::default()
        }
    }

    /// An impact needs a separation of more than 1 % of the gap first, then a touch-down at
    /// 1 cm/s or more; chatter across δ = 0 and slow settling count nothing.
    #[test]
    fn impacts_need_a_separation_and_a_fast_touch_down() {
        let gap = &[0.01; 3];
        let mut separated = vec![false; 3];
        // Initial state: node 0 resting, node 1 lifted, node 2 barely off the wall.
        let start = [touching(0.0), free(-2e-4), free(-1e-6)];
        assert_eq!(count_impacts(&mut separated, &start, gap, true), 0);
        assert_eq!(separated, vec![false, true, false]);
        // Node 1 lands at 5 cm/s: an impact; node 2 chatters back at 5 cm/s: not separated.
        let next = [touching(0.0), touching(0.05), touching(0.05)];
        assert_eq!(count_impacts(&mut separated, &next, gap, false), 1);
        // Node 1 lifts off again and settles back at 1 mm/s: no impact.
        count_impacts(
            &mut separated,
            &[touching(0.0), free(-5e-4), touching(0.0)],
            gap,
            false,
        );
        let slow = [touching(0.0), touching(0.001), touching(0.0)];
        assert_eq!(count_impacts(&mut separated, &slow, gap, false), 0);
        // At exactly the threshold it counts.
        count_impacts(
            &mut separated,
            &[free(-5e-4), free(-5e-4), free(-5e-4)],
            gap,
            false,
        );
        let at = [
            touching(IMPACT_SPEED),
            touching(0.5 * IMPACT_SPEED),
            touching(1.0),
        ];
        assert_eq!(count_impacts(&mut separated, &at, gap, false), 2);
    }
}
