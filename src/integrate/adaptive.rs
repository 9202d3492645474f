//! Adaptive time stepping: Newmark step attempts under a PI step-size controller, with the guards
//! that end a run whose step collapses. The integrator owns its step control, as diffsol's solvers
//! do: [`AdaptiveStepper::step`] attempts steps until one is accepted and says why it stopped
//! otherwise; the caller records the accepted state and decides what else ends the run.

use super::{ImplicitSystem, Newmark, StepOutcome};

/// After an accepted step, a PI controller (Gustafsson 1991) on the local error estimate err
/// (accept when ≤ 1; the error of the average-acceleration rule is O(h³)):
/// h ← h · 0.9 err^(−0.7/3) (err_prev/err)^(0.4/3), clamped to [0.3, 2]; the proportional part
/// damps the accept/reject oscillation of the elementary rule h ← h · 0.9 err^(−1/3), which
/// rejected 30 % of the steps of the seed run. After a rejection, the elementary rule.
/// An accepted step is followed by one of the same length when the controller would lengthen
/// it by less than this factor.
const KEEP_STEP: f64 = 1.2;

#[derive(Debug, Clone, Copy, Default)]
struct StepController {
    /// Error estimate of the last accepted step.
    previous: Option<f64>,
}

impl StepController {
    /// Factor on h after an accepted step with error estimate err ≤ 1.
    fn accepted(&mut self, err: f64) -> f64 {
        let err = err.max(1e-10);
        let factor = match self.previous {
            Some(prev) => 0.9 * err.powf(-0.7 / 3.0) * (prev / err).powf(0.4 / 3.0),
            None => 0.9 * err.powf(-1.0 / 3.0),
        };
        self.previous = Some(err);
        if (1.0..KEEP_STEP).contains(&factor) {
            // Keep h: the Newton matrix of the last step can be reused (Hairer & Wanner, RADAU5).
            1.0
        } else {
            factor.clamp(0.3, 2.0)
        }
    }

    /// Factor on h after a step rejected with error estimate err > 1.
    fn rejected(&mut self, err: f64) -> f64 {
        (0.9 * err.powf(-1.0 / 3.0)).clamp(0.1, 0.7)
    }
}

/// Where the march ends and what it may not do, s.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepLimits {
    /// Time at which the march ends.
    pub end_time: f64,
    /// Largest step.
    pub max_step: f64,
    /// Smallest step: below it the run stops.
    pub min_step: f64,
    /// Step attempts (accepted and rejected) after which the run stops.
    pub max_attempts: u64,
}

/// Why the stepper stopped before the end.
#[derive(Debug, Clone, PartialEq)]
pub enum StepError {
    /// The step fell below `min_step` (Newton or the error test kept failing).
    StepTooSmall { time: f64, min_step: f64 },
    /// `attempts` step attempts were made, the limit; `step` is the last step tried.
    TooManySteps { time: f64, attempts: u64, step: f64 },
    /// The state is no longer finite.
    NonFinite { time: f64 },
}

/// Work counters of the march.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepCounters {
    pub steps: usize,
    pub rejected_steps: usize,
    pub newton_iterations: usize,
    /// Shortest and longest accepted step, s (∞ and 0 before the first).
    pub min_dt: f64,
    pub max_dt: f64,
}

impl Default for StepCounters {
    fn default() -> Self {
        StepCounters {
            steps: 0,
            rejected_steps: 0,
            newton_iterations: 0,
            min_dt: f64::INFINITY,
            max_dt: 0.0,
        }
    }
}

/// Newmark under step-size control: the state (`nm`), the next step length and the counters.
pub struct AdaptiveStepper {
    pub nm: Newmark,
    /// Length of the next attempt, s.
    h: f64,
    controller: StepController,
    limits: StepLimits,
    pub counters: StepCounters,
}

impl AdaptiveStepper {
    /// Start from `nm` with a first attempt of `h0` s.
    pub fn new(nm: Newmark, h0: f64, limits: StepLimits) -> Self {
        AdaptiveStepper {
            nm,
            h: h0,
            controller: StepController::default(),
            limits,
            counters: StepCounters::default(),
        }
    }

    /// Whether the march has reached its end time (to a relative 1e-12).
    pub fn finished(&self) -> bool {
        self.nm.t >= self.limits.end_time * (1.0 - 1e-12)
    }

    /// Attempt steps until one is accepted (`Ok`, state advanced) or a guard stops the run.
    pub fn step<S: ImplicitSystem>(&mut self, sys: &mut S) -> Result<(), StepError> {
        loop {
            let h = self
                .h
                .min(self.limits.max_step)
                .min(self.limits.end_time - self.nm.t);
            let c = &mut self.counters;
            match self.nm.attempt(sys, h) {
                StepOutcome::Converged { iterations, error } if error <= 1.0 => {
                    c.newton_iterations += iterations;
                    self.nm.accept(h);
                    c.steps += 1;
                    c.min_dt = c.min_dt.min(h);
                    c.max_dt = c.max_dt.max(h);
                    self.h = h * self.controller.accepted(error);
                    return Ok(());
                }
                StepOutcome::Converged { iterations, error } => {
                    c.newton_iterations += iterations;
                    c.rejected_steps += 1;
                    self.h = h * self.controller.rejected(error);
                }
                StepOutcome::TooLarge { error } => {
                    c.newton_iterations += 1;
                    c.rejected_steps += 1;
                    self.h = h * self.controller.rejected(error);
                }
                StepOutcome::Failed { iterations } => {
                    c.newton_iterations += iterations;
                    c.rejected_steps += 1;
                    // Halving (not quartering) after a Newton failure: measured on a 1 s seed
                    // window, 43 % fewer rejected steps and 13 % less wall time, same metrics.
                    self.h = h * 0.5;
                    self.nm.mark_stale();
                }
            }
            self.check()?;
        }
    }

    /// The guards, checked after every attempt: the attempt limit, the smallest step, a finite state.
    pub fn check(&self) -> Result<(), StepError> {
        let c = &self.counters;
        let time = self.nm.t;
        if (c.steps + c.rejected_steps) as u64 >= self.limits.max_attempts {
            return Err(StepError::TooManySteps {
                time,
                attempts: self.limits.max_attempts,
                step: self.h,
            });
        }
        if self.h < self.limits.min_step {
            return Err(StepError::StepTooSmall {
                time,
                min_step: self.limits.min_step,
            });
        }
        if !self
            .nm
            .q
            .iter()
            .chain(self.nm.v.iter())
            .all(|x| x.is_finite())
        {
            return Err(StepError::NonFinite { time });
        }
        Ok(())
    }
}
