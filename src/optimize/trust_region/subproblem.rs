//! The trust-region sub-problem: an elastic (Sℓ1QP) QP in the step `d` and slacks `t`,
//!
//! `min gᵀd + ½dᵀWd + μ Σ t_j  s.t.  c_j + ∇c_jᵀd ≤ t_j, t ≥ 0,  A(x_c + d) ≤ b,  uᵀd ≤ h (cuts),
//! max(−Δ, lo − x_c) ≤ d ≤ min(Δ, hi − x_c)`,
//!
//! with `W = ∇²m_f + Σ λ_j ∇²m_cj` (convexified in `qp.rs`). Steering: while the step leaves
//! more slack than the LP `min Σt` over the same constraints, `μ ← 10μ` (≤ `max_penalty`).

use crate::optimize::OptimizeError;
use crate::optimize::evaluation::Evaluation;
use crate::optimize::feasible::FeasibleSet;
use crate::optimize::model::QuadraticModel;
use crate::optimize::qp::{QpProblem, solve_qp};

/// Everything the sub-problem needs about the current iterate.
pub(super) struct Subproblem<'a> {
    pub(super) set: &'a FeasibleSet,
    /// Centre.
    pub(super) xc: &'a [f64],
    /// Evaluation at the centre (its constraint values are used, not the models').
    pub(super) centre: &'a Evaluation,
    /// Models of `f` then of each `c_j`.
    pub(super) models: &'a [QuadraticModel],
    /// Multipliers `λ_j` for the Lagrangian Hessian.
    pub(super) multipliers: &'a [f64],
    /// Failure cuts `uᵀd ≤ h`.
    pub(super) cuts: &'a [(Vec<f64>, f64)],
    /// Trust-region radius (∞-norm).
    pub(super) radius: f64,
}

/// The step, its predicted merit reduction `q(0) − q(d)`, the (possibly raised) penalty and the
/// updated multipliers.
pub(super) struct Step {
    pub(super) d: Vec<f64>,
    pub(super) predicted: f64,
    pub(super) penalty: f64,
    pub(super) multipliers: Vec<f64>,
}

impl Subproblem<'_> {
    /// Solves the sub-problem with penalty `penalty`, steering it up to `max_penalty`.
    pub(super) fn solve(&self, penalty: f64, max_penalty: f64) -> Result<Step, OptimizeError> {
        let n = self.xc.len();
        let m = self.centre.constraints.len();
        let (xc, ev, models) = (self.xc, self.centre, self.models);
        let nv = n + m;
        let mut h = vec![vec![0.0; nv]; nv];
        for (i, row) in h.iter_mut().enumerate().take(n) {
            for (k, hik) in row.iter_mut().enumerate().take(n) {
                *hik = models[0].h[i][k]
                    + (0..m)
                        .map(|j| self.multipliers[j] * models[1 + j].h[i][k])
                        .sum::<f64>();
            }
        }
        let mut rows = Vec::new();
        let mut rhs = Vec::new();
        for (a, b) in self.set.a().iter().zip(self.set.b()) {
            let mut r = a.clone();
            r.resize(nv, 0.0);
            rows.push(r);
            rhs.push(b - a.iter().zip(xc).map(|(ai, xi)| ai * xi).sum::<f64>());
        }
        for (u, h) in self.cuts {
            let mut r = u.clone();
            r.resize(nv, 0.0);
            rows.push(r);
            rhs.push(*h);
        }
        for j in 0..m {
            let mut r = models[1 + j].g.clone();
            r.resize(nv, 0.0);
            r[n + j] = -1.0;
            rows.push(r);
            rhs.push(-ev.constraints[j]);
        }
        let mut lower = vec![0.0; nv];
        let mut upper = vec![f64::INFINITY; nv];
        for i in 0..n {
            lower[i] = (-self.radius).max(self.set.lower()[i] - xc[i]).min(0.0);
            upper[i] = self.radius.min(self.set.upper()[i] - xc[i]).max(0.0);
        }
        let violation0 = ev.violation();
        let mut penalty = penalty;
        let mut min_slack: Option<f64> = None;
        loop {
            let mut g = models[0].g.clone();
            g.resize(nv, penalty);
            let sol = solve_qp(&QpProblem {
                h: &h,
                g: &g,
                a: &rows,
                b: &rhs,
                lower: &lower,
                upper: &upper,
            })?;
            let slack: f64 = sol.x[n..].iter().sum();
            if slack > 1e-10 && penalty < max_penalty {
                let t_min = match min_slack {
                    Some(t) => t,
                    None => {
                        let mut gl = vec![0.0; nv];
                        gl[n..].iter_mut().for_each(|v| *v = 1.0);
                        let lp = solve_qp(&QpProblem {
                            h: &[],
                            g: &gl,
                            a: &rows,
                            b: &rhs,
                            lower: &lower,
                            upper: &upper,
                        })?;
                        let t: f64 = lp.x[n..].iter().sum();
                        min_slack = Some(t);
                        t
                    }
                };
                if slack > t_min + 1e-8 * (1.0 + t_min) {
                    penalty = (10.0 * penalty).min(max_penalty);
                    continue;
                }
            }
            // Multipliers of constraints satisfied by the linearisation (an elastic one sits at
            // μ and says nothing about curvature weights).
            let lam_rows = &sol.multipliers[rows.len() - m..];
            let multipliers = (0..m)
                .map(|j| {
                    if sol.x[n + j] <= 1e-9 {
                        lam_rows[j]
                    } else {
                        self.multipliers[j]
                    }
                })
                .collect();
            return Ok(Step {
                d: sol.x[..n].to_vec(),
                predicted: penalty * violation0 - sol.objective,
                penalty,
                multipliers,
            });
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// min (x−1)² + (y−1)² modelled exactly, with c(x) = x + y − 1 ≤ 0 modelled exactly, centre
    /// 0, Δ = 2 on the box [−2, 2]²: the step is (½, ½) with multiplier 1 and no slack; with
    /// Δ = 0.2 the step is (0.2, 0.2).
    #[test]
    fn linearised_constraint_and_radius() {
        let set = FeasibleSet::from_box(vec![-2.0, -2.0], vec![2.0, 2.0]).unwrap();
        let f = QuadraticModel {
            c: 2.0,
            g: vec![-2.0, -2.0],
            h: vec![vec![2.0, 0.0], vec![0.0, 2.0]],
        };
        let c = QuadraticModel {
            c: -1.0,
            g: vec![1.0, 1.0],
            h: vec![vec![0.0, 0.0], vec![0.0, 0.0]],
        };
        let centre = Evaluation::new(2.0, vec![-1.0]);
        let models = [f, c];
        let mut sp = Subproblem {
            set: &set,
            xc: &[0.0, 0.0],
            centre: &centre,
            models: &models,
            multipliers: &[0.0],
            cuts: &[],
            radius: 2.0,
        };
        let s = sp.solve(10.0, 1e6).unwrap();
        assert!(
            (s.d[0] - 0.5).abs() < 1e-6 && (s.d[1] - 0.5).abs() < 1e-6,
            "{:?}",
            s.d
        );
        assert!((s.multipliers[0] - 1.0).abs() < 1e-6);
        // q(0) − q(d) = f(0) − f(½, ½) = 2 − 0.5.
        assert!((s.predicted - 1.5).abs() < 1e-6);
        assert_eq!(s.penalty, 10.0);
        sp.radius = 0.2;
        let s = sp.solve(10.0, 1e6).unwrap();
        assert!((s.d[0] - 0.2).abs() < 1e-6 && (s.d[1] - 0.2).abs() < 1e-6);
    }

    /// Infeasible centre c = 1 with a tiny penalty: the QP would keep slack although the trust
    /// region allows feasibility, so steering raises μ until the step restores c ≤ 0.
    #[test]
    fn steering_raises_the_penalty() {
        let set = FeasibleSet::from_box(vec![-2.0, -2.0], vec![2.0, 2.0]).unwrap();
        let f = QuadraticModel {
            c: 0.0,
            g: vec![-1.0, 0.0],
            h: vec![vec![0.0, 0.0], vec![0.0, 0.0]],
        };
        // c(x) = 1 + x ≤ 0 needs d_x ≤ −1.
        let c = QuadraticModel {
            c: 1.0,
            g: vec![1.0, 0.0],
            h: vec![vec![0.0, 0.0], vec![0.0, 0.0]],
        };
        let centre = Evaluation::new(0.0, vec![1.0]);
        let models = [f, c];
        let sp = Subproblem {
            set: &set,
            xc: &[0.0, 0.0],
            centre: &centre,
            models: &models,
            multipliers: &[0.0],
            cuts: &[],
            radius: 1.5,
        };
        let s = sp.solve(0.1, 1e6).unwrap();
        assert!(s.penalty > 1.0, "penalty {}", s.penalty);
        assert!(s.d[0] <= -1.0 + 1e-6, "{:?}", s.d);
    }

    /// A failure cut uᵀd ≤ h stops the step short of the failed point.
    #[test]
    fn failure_cut_limits_the_step() {
        let set = FeasibleSet::from_box(vec![-2.0, -2.0], vec![2.0, 2.0]).unwrap();
        let f = QuadraticModel {
            c: 0.0,
            g: vec![-1.0, 0.0],
            h: vec![vec![0.0, 0.0], vec![0.0, 0.0]],
        };
        let centre = Evaluation::new(0.0, vec![]);
        let models = [f];
        let cuts = [(vec![1.0, 0.0], 0.25)];
        let sp = Subproblem {
            set: &set,
            xc: &[0.0, 0.0],
            centre: &centre,
            models: &models,
            multipliers: &[],
            cuts: &cuts,
            radius: 1.0,
        };
        let s = sp.solve(10.0, 1e6).unwrap();
        assert!((s.d[0] - 0.25).abs() < 1e-6, "{:?}", s.d);
    }
}
