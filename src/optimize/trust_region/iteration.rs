//! One model-based iteration about the centre (steps 1–6 of the module doc of [`super`]), as
//! named steps:
//!
//! 1. [`TrustRegion::needs_geometry`] / [`TrustRegion::geometry_step`]: a poorly poised sample set
//!    gets a geometry point (or a smaller radius) and the iteration ends;
//! 2. [`TrustRegion::build_models`]: quadratic models of `f` and every `c_j`;
//! 3. [`TrustRegion::solve_subproblem`]: the Sℓ1QP step (penalty steering, multipliers);
//! 4. [`TrustRegion::trial_point`]: the step turned into a point worth evaluating, or a
//!    shrink without evaluation (stationary model, infeasible projection, failure cut);
//! 5. [`TrustRegion::evaluate_trial`]: one evaluation; a failure shrinks the radius;
//! 6. [`TrustRegion::accept_or_reject`]: the ratio `ρ`, the new centre and the new radius.
//!
//! A step that ends the iteration early records what it did in `last_step` and the radius.

use argmin::core::{CostFunction, Error, Problem};

use super::subproblem::{Step, Subproblem};
use super::{POISED_RADIUS, SAMPLE_RADIUS, TrustRegion, norm_inf};
use crate::optimize::evaluation::Evaluation;
use crate::optimize::model::{QuadraticModel, fit_quadratics, poisedness};

/// A sub-problem step that passed the checks of [`TrustRegion::trial_point`].
pub(super) struct Trial {
    /// The point to evaluate (inside the feasible set).
    x: Vec<f64>,
    /// `‖d‖∞` of the sub-problem step.
    dnorm: f64,
    /// Predicted merit reduction `q(0) − q(d)` (> 0).
    predicted: f64,
    /// `‖d‖∞ < Δ/10`: the model is nearly stationary at this scale.
    short: bool,
}

impl TrustRegion {
    /// One model-based iteration about centre `c`: `ρ`, or NaN when no trust-region step was
    /// evaluated (geometry step, shrink, budget spent, failed trial).
    pub(super) fn model_iteration<O>(
        &mut self,
        problem: &mut Problem<O>,
        c: usize,
    ) -> Result<f64, Error>
    where
        O: CostFunction<Param = Vec<f64>, Output = Evaluation>,
    {
        let local = self.sample_set(c, POISED_RADIUS);
        if self.needs_geometry(c, &local) {
            self.geometry_step(problem, c, &local)?;
            return Ok(f64::NAN);
        }
        let models = self.build_models(c);
        let Some(step) = self.solve_subproblem(c, &models) else {
            return Ok(f64::NAN);
        };
        let Some(trial) = self.trial_point(c, &step) else {
            return Ok(f64::NAN);
        };
        let Some(t) = self.evaluate_trial(problem, &trial)? else {
            return Ok(f64::NAN);
        };
        Ok(self.accept_or_reject(c, t, &trial))
    }

    /// Fewer than `n+1` points within `POISED_RADIUS·Δ`, or `σ_min` of their scaled
    /// displacements below `poisedness_threshold`.
    fn needs_geometry(&self, c: usize, local: &[usize]) -> bool {
        let n = self.n();
        let sigma = poisedness(&self.displacements(c, local), n).sigma_min();
        local.len() < n + 1 || sigma < self.opts.poisedness_threshold
    }

    /// Evaluates the point that most improves the poisedness of `local` (it becomes the centre
    /// if it improves the merit), or halves `Δ` when no candidate improves it.
    fn geometry_step<O>(
        &mut self,
        problem: &mut Problem<O>,
        c: usize,
        local: &[usize],
    ) -> Result<(), Error>
    where
        O: CostFunction<Param = Vec<f64>, Output = Evaluation>,
    {
        match self.geometry_point(c, local) {
            Some(y) => {
                self.last_step = "geometry";
                if let Some(i) = self.evaluate_one(problem, y)?
                    && !self.history[i].1.failed
                    && self.merit(i) < self.merit(c)
                {
                    self.centre = Some(i);
                }
            }
            None => {
                self.last_step = "shrink (geometry blocked)";
                self.radius *= 0.5;
            }
        }
        Ok(())
    }

    /// Regression models of `f` then of each `c_j` on the successful points within
    /// `SAMPLE_RADIUS·Δ` of the centre.
    fn build_models(&self, c: usize) -> Vec<QuadraticModel> {
        let sample = self.sample_set(c, SAMPLE_RADIUS);
        let points: Vec<&[f64]> = sample
            .iter()
            .map(|&i| self.history[i].0.as_slice())
            .collect();
        let mut columns = vec![
            sample
                .iter()
                .map(|&i| self.history[i].1.objective)
                .collect(),
        ];
        for j in 0..self.m {
            columns.push(
                sample
                    .iter()
                    .map(|&i| self.history[i].1.constraints[j])
                    .collect(),
            );
        }
        fit_quadratics(&self.history[c].0, self.radius, &points, &columns)
    }

    /// Solves the sub-problem about centre `c` and keeps its (possibly raised) penalty and its
    /// multipliers; a sub-problem that Clarabel cannot solve halves `Δ` (`None`).
    fn solve_subproblem(&mut self, c: usize, models: &[QuadraticModel]) -> Option<Step> {
        let xc = &self.history[c].0;
        let cuts = self.failure_cuts(xc);
        let solved = Subproblem {
            set: &self.set,
            xc,
            centre: &self.history[c].1,
            models,
            multipliers: &self.multipliers,
            cuts: &cuts,
            radius: self.radius,
        }
        .solve(self.penalty, self.opts.max_penalty);
        match solved {
            Ok(s) => {
                self.penalty = s.penalty;
                self.multipliers.clone_from(&s.multipliers);
                Some(s)
            }
            Err(_) => {
                self.last_step = "shrink (sub-problem failed)";
                self.radius *= 0.5;
                None
            }
        }
    }

    /// The point `x_c + d` to evaluate, or `None` after shrinking `Δ` when the step is not
    /// worth an evaluation: negligible predicted reduction or `‖d‖∞ < min_radius/2` (halve),
    /// no feasible version of the point (halve), or a projection that crossed a failure cut
    /// (`Δ ← ½ min(Δ, ‖d‖∞)`).
    fn trial_point(&mut self, c: usize, step: &Step) -> Option<Trial> {
        let phi_c = self.merit(c);
        let dnorm = norm_inf(&step.d);
        if step.predicted <= 1e-12 * phi_c.abs().max(1.0) || dnorm < 0.5 * self.opts.min_radius {
            self.last_step = "shrink (model stationary)";
            self.radius *= 0.5;
            return None;
        }
        let xc = &self.history[c].0;
        let x: Vec<f64> = xc.iter().zip(&step.d).map(|(x, d)| x + d).collect();
        let Some(x) = self.feasible(&x) else {
            self.radius *= 0.5;
            return None;
        };
        if self.beyond_cut(&x, xc) {
            // Only after a projection moved the step across a cut.
            self.last_step = "shrink (step towards a failed point)";
            self.radius = 0.5 * self.radius.min(dnorm);
            return None;
        }
        Some(Trial {
            x,
            dnorm,
            predicted: step.predicted,
            short: dnorm < 0.1 * self.radius,
        })
    }

    /// Evaluates the trial point: its history index, or `None` when the budget is spent or
    /// the evaluation failed (then `Δ ← ½ min(Δ, ‖d‖∞)`: a failure is a hidden constraint).
    fn evaluate_trial<O>(
        &mut self,
        problem: &mut Problem<O>,
        trial: &Trial,
    ) -> Result<Option<usize>, Error>
    where
        O: CostFunction<Param = Vec<f64>, Output = Evaluation>,
    {
        self.last_step = if trial.short {
            "trust region (short step)"
        } else {
            "trust region"
        };
        let Some(t) = self.evaluate_one(problem, trial.x.clone())? else {
            return Ok(None);
        };
        if self.history[t].1.failed {
            self.last_step = "trust region (failed evaluation)";
            self.radius = 0.5 * self.radius.min(trial.dnorm);
            return Ok(None);
        }
        Ok(Some(t))
    }

    /// Ratio `ρ = (φ(x_c) − φ(x_t)) / (q(0) − q(d))`; the trial `t` becomes the centre if
    /// `ρ ≥ 0.1` or merely `φ(x_t) < φ(x_c)`; the radius follows NEWUOA's rule (a short step
    /// continues at the step's scale). Returns `ρ`.
    fn accept_or_reject(&mut self, c: usize, t: usize, trial: &Trial) -> f64 {
        let (phi_c, phi_t) = (self.merit(c), self.merit(t));
        let rho = (phi_c - phi_t) / trial.predicted;
        if rho >= 0.1 || phi_t < phi_c {
            self.centre = Some(t);
        }
        self.radius = if trial.short {
            // The model is nearly stationary at this scale: continue at the step's scale.
            (0.25 * self.radius).max(2.0 * trial.dnorm)
        } else if rho < 0.1 {
            0.5 * self.radius
        } else if rho < 0.7 {
            (0.5 * self.radius).max(trial.dnorm)
        } else {
            self.radius.max(2.0 * trial.dnorm).min(self.opts.max_radius)
        };
        rho
    }
}
