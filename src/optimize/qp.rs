//! Small dense convex QPs and LPs solved by Clarabel 0.11.
//!
//! Problem form: minimise `½ xᵀ H x + gᵀ x` subject to `A x ≤ b` and `lower ≤ x ≤ upper`
//! (infinite bounds allowed and dropped). Clarabel takes `A x + s = b, s ∈ ℝ₊`; only the upper
//! triangle of `P = H` is passed.
//!
//! **Convexification.** A model Hessian may be indefinite. [`solve_qp`] first symmetrises `H` and
//! clips its negative eigenvalues to zero (`H⁺ = V max(Λ, 0) Vᵀ`, nalgebra's `SymmetricEigen`):
//! the closest positive semidefinite matrix in the Frobenius norm. Negative curvature is thus
//! dropped rather than shifted onto every direction, so a well-modelled positive direction keeps
//! its curvature. The trust-region box keeps the clipped problem bounded.
//!
//! Only `Solved` and `AlmostSolved` are accepted; every other Clarabel status is an
//! [`OptimizeError::Qp`] (or [`OptimizeError::Infeasible`] for a primal-infeasible problem).

use clarabel::algebra::CscMatrix;
use clarabel::solver::{
    DefaultSettings, DefaultSolver, IPSolver, NonnegativeConeT, SolverStatus, SupportedConeT,
};
use nalgebra::DMatrix;

use super::OptimizeError;

/// A dense QP `min ½xᵀHx + gᵀx  s.t.  A x ≤ b, lower ≤ x ≤ upper`.
#[derive(Clone, Copy, Debug)]
pub struct QpProblem<'a> {
    /// Hessian, `n × n` (symmetrised before use; may be empty for an LP).
    pub h: &'a [Vec<f64>],
    /// Linear term, length `n`.
    pub g: &'a [f64],
    /// Inequality rows, each of length `n`.
    pub a: &'a [Vec<f64>],
    /// Right-hand sides of the inequality rows.
    pub b: &'a [f64],
    /// Lower bounds (`-∞` allowed).
    pub lower: &'a [f64],
    /// Upper bounds (`+∞` allowed).
    pub upper: &'a [f64],
}

/// Solution of a [`QpProblem`].
#[derive(Clone, Debug)]
pub struct QpSolution {
    /// Minimiser.
    pub x: Vec<f64>,
    /// Lagrange multipliers (≥ 0) of the rows `A x ≤ b`, in order.
    pub multipliers: Vec<f64>,
    /// Objective value of the (convexified) problem at `x`.
    pub objective: f64,
    /// Clarabel reported `AlmostSolved` (reduced accuracy) rather than `Solved`.
    pub reduced_accuracy: bool,
    /// The Hessian had negative eigenvalues that were clipped to zero.
    pub convexified: bool,
}

/// Symmetrises `h` and clips negative eigenvalues to zero. Returns the matrix and whether any
/// eigenvalue was clipped (eigenvalues above `-1e-12·max|λ|` count as non-negative).
pub fn convexify(h: &[Vec<f64>]) -> (Vec<Vec<f64>>, bool) {
    let n = h.len();
    let m = DMatrix::from_fn(n, n, |i, j| 0.5 * (h[i][j] + h[j][i]));
    if n == 0 {
        return (Vec::new(), false);
    }
    let eig = m.clone().symmetric_eigen();
    let scale = eig.eigenvalues.iter().fold(0.0_f64, |a, l| a.max(l.abs()));
    if eig.eigenvalues.iter().all(|&l| l >= -1e-12 * scale) {
        return (to_rows(&m), false);
    }
    let clipped = eig.eigenvalues.map(|l| l.max(0.0));
    let v = &eig.eigenvectors;
    let psd = v * DMatrix::from_diagonal(&clipped) * v.transpose();
    (to_rows(&psd), true)
}

fn to_rows(m: &DMatrix<f64>) -> Vec<Vec<f64>> {
    (0..m.nrows())
        .map(|i| (0..m.ncols()).map(|j| m[(i, j)]).collect())
        .collect()
}

/// Solves a convex QP/LP in Clarabel's form `min ½xᵀPx + qᵀx, G x ≤ h` with `P` given as full
/// dense rows (only its upper triangle is passed; empty for an LP). Returns `(x, z, reduced_accuracy)`.
pub(crate) fn solve_dense(
    p: &[Vec<f64>],
    q: &[f64],
    g: &[Vec<f64>],
    h: &[f64],
) -> Result<(Vec<f64>, Vec<f64>, bool), OptimizeError> {
    let n = q.len();
    // Clarabel's conversion from dense rows drops exact zeros; it takes the column count from
    // the first row, so an empty P or G is built with its size.
    let p_csc = if p.is_empty() {
        CscMatrix::zeros((n, n))
    } else {
        CscMatrix::from(p).to_triu()
    };
    let a_csc = if g.is_empty() {
        CscMatrix::zeros((0, n))
    } else {
        CscMatrix::from(g)
    };
    let cones: Vec<SupportedConeT<f64>> = if g.is_empty() {
        Vec::new()
    } else {
        vec![NonnegativeConeT(g.len())]
    };
    let settings = DefaultSettings {
        verbose: false,
        tol_gap_abs: 1e-10,
        tol_gap_rel: 1e-10,
        tol_feas: 1e-10,
        ..DefaultSettings::default()
    };
    let mut solver = DefaultSolver::new(&p_csc, q, &a_csc, h, &cones, settings).map_err(|e| {
        OptimizeError::Qp {
            status: format!("setup: {e:?}"),
        }
    })?;
    solver.solve();
    let sol = &solver.solution;
    match sol.status {
        SolverStatus::Solved | SolverStatus::AlmostSolved => Ok((
            sol.x.clone(),
            sol.z.clone(),
            sol.status == SolverStatus::AlmostSolved,
        )),
        SolverStatus::PrimalInfeasible | SolverStatus::AlmostPrimalInfeasible => {
            Err(OptimizeError::Infeasible {
                violation: f64::NAN,
                row: None,
            })
        }
        other => Err(OptimizeError::Qp {
            status: format!("{other:?}"),
        }),
    }
}

/// Solves a [`QpProblem`] after convexifying its Hessian (see the module doc).
pub fn solve_qp(qp: &QpProblem) -> Result<QpSolution, OptimizeError> {
    let n = qp.g.len();
    check_qp(qp)?;
    let (h, convexified) = if qp.h.is_empty() {
        (vec![vec![0.0; n]; n], false)
    } else {
        convexify(qp.h)
    };
    let mut rows: Vec<Vec<f64>> = qp.a.to_vec();
    let mut rhs: Vec<f64> = qp.b.to_vec();
    for i in 0..n {
        if qp.upper[i].is_finite() {
            let mut r = vec![0.0; n];
            r[i] = 1.0;
            rows.push(r);
            rhs.push(qp.upper[i]);
        }
        if qp.lower[i].is_finite() {
            let mut r = vec![0.0; n];
            r[i] = -1.0;
            rows.push(r);
            rhs.push(-qp.lower[i]);
        }
    }
    let (mut x, z, reduced_accuracy) = solve_dense(&h, qp.g, &rows, &rhs)?;
    // Interior-point solutions sit a hair inside or outside the bounds: clip to the box exactly.
    for ((xi, lo), hi) in x.iter_mut().zip(qp.lower).zip(qp.upper) {
        *xi = xi.clamp(*lo, *hi);
    }
    let objective = quad_form(&h, &x) * 0.5 + dot(qp.g, &x);
    Ok(QpSolution {
        x,
        multipliers: z[..qp.a.len()].iter().map(|&l| l.max(0.0)).collect(),
        objective,
        reduced_accuracy,
        convexified,
    })
}

fn check_qp(qp: &QpProblem) -> Result<(), OptimizeError> {
    let n = qp.g.len();
    let check = |what: &str, len: usize| {
        if len == n {
            Ok(())
        } else {
            Err(OptimizeError::dimension(what, n, len))
        }
    };
    if !qp.h.is_empty() {
        check("QP Hessian rows", qp.h.len())?;
        for row in qp.h {
            check("QP Hessian row", row.len())?;
        }
    }
    check("QP lower bounds", qp.lower.len())?;
    check("QP upper bounds", qp.upper.len())?;
    for row in qp.a {
        check("QP constraint row", row.len())?;
    }
    if qp.a.len() != qp.b.len() {
        return Err(OptimizeError::dimension(
            "QP right-hand side",
            qp.a.len(),
            qp.b.len(),
        ));
    }
    for (i, (lo, hi)) in qp.lower.iter().zip(qp.upper).enumerate() {
        if lo > hi || lo.is_nan() || hi.is_nan() {
            return Err(OptimizeError::EmptyBound {
                index: i,
                lower: *lo,
                upper: *hi,
            });
        }
    }
    Ok(())
}

pub(crate) fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// `xᵀ H x`.
pub(crate) fn quad_form(h: &[Vec<f64>], x: &[f64]) -> f64 {
    h.iter().zip(x).map(|(row, xi)| xi * dot(row, x)).sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    const INF: f64 = f64::INFINITY;

    fn close(a: &[f64], b: &[f64], tol: f64) -> bool {
        a.iter().zip(b).all(|(x, y)| (x - y).abs() <= tol)
    }

    /// min ½(x²+y²) − x − y, unconstrained optimum (1, 1); with x + y ≤ 1 the optimum is
    /// (½, ½) with multiplier ½ (KKT: 1 − x = λ, 1 − y = λ, x + y = 1).
    #[test]
    fn active_linear_constraint() {
        let h = vec![vec![1.0, 0.0], vec![0.0, 1.0]];
        let g = [-1.0, -1.0];
        let a = vec![vec![1.0, 1.0]];
        let qp = QpProblem {
            h: &h,
            g: &g,
            a: &a,
            b: &[1.0],
            lower: &[-INF, -INF],
            upper: &[INF, INF],
        };
        let s = solve_qp(&qp).unwrap();
        assert!(close(&s.x, &[0.5, 0.5], 1e-7), "{:?}", s.x);
        assert!((s.multipliers[0] - 0.5).abs() < 1e-7);
        assert!((s.objective - (0.25 - 1.0)).abs() < 1e-7);
        assert!(!s.convexified);
        // Inactive constraint: unconstrained optimum, zero multiplier.
        let qp = QpProblem { b: &[3.0], ..qp };
        let s = solve_qp(&qp).unwrap();
        assert!(close(&s.x, &[1.0, 1.0], 1e-7));
        assert!(s.multipliers[0].abs() < 1e-7);
    }

    /// min ½·2x² + ½·4y² − 8x − 8y on the box [0, 1]×[0, 3]: x would be 4 (clipped to 1), y = 2.
    #[test]
    fn active_box_bound() {
        let h = vec![vec![2.0, 0.0], vec![0.0, 4.0]];
        let s = solve_qp(&QpProblem {
            h: &h,
            g: &[-8.0, -8.0],
            a: &[],
            b: &[],
            lower: &[0.0, 0.0],
            upper: &[1.0, 3.0],
        })
        .unwrap();
        assert!(close(&s.x, &[1.0, 2.0], 1e-7), "{:?}", s.x);
    }

    /// H = [[1, 0], [0, −1]] is clipped to diag(1, 0). With g = (−½, −1) on [−1, 1]²: the
    /// clipped problem ½x² − ½x − y has its minimum at x = ½, y = 1.
    #[test]
    fn indefinite_hessian_is_clipped() {
        let h = vec![vec![1.0, 0.0], vec![0.0, -1.0]];
        let s = solve_qp(&QpProblem {
            h: &h,
            g: &[-0.5, -1.0],
            a: &[],
            b: &[],
            lower: &[-1.0, -1.0],
            upper: &[1.0, 1.0],
        })
        .unwrap();
        assert!(s.convexified);
        assert!(close(&s.x, &[0.5, 1.0], 1e-7), "{:?}", s.x);
        assert!((s.objective - (0.125 - 0.25 - 1.0)).abs() < 1e-7);
    }

    /// A rotated indefinite matrix: eigenvalues 3 and −1 with eigenvectors (1, 1)/√2 and
    /// (1, −1)/√2; clipping gives 1.5·[[1, 1], [1, 1]].
    #[test]
    fn convexify_rotated() {
        let (c, clipped) = convexify(&[vec![1.0, 2.0], vec![2.0, 1.0]]);
        assert!(clipped);
        assert!(close(&c[0], &[1.5, 1.5], 1e-12) && close(&c[1], &[1.5, 1.5], 1e-12));
        let (c, clipped) = convexify(&[vec![2.0, 1.0], vec![1.0, 2.0]]);
        assert!(!clipped);
        assert!(close(&c[0], &[2.0, 1.0], 1e-12));
    }

    /// No rows at all (G is 0×n) and a diagonal P: min ½(x² + 2y²) − x − y at (1, ½).
    #[test]
    fn unconstrained_qp_without_rows() {
        let h = vec![vec![1.0, 0.0], vec![0.0, 2.0]];
        let s = solve_qp(&QpProblem {
            h: &h,
            g: &[-1.0, -1.0],
            a: &[],
            b: &[],
            lower: &[-INF, -INF],
            upper: &[INF, INF],
        })
        .unwrap();
        assert!(close(&s.x, &[1.0, 0.5], 1e-7), "{:?}", s.x);
        assert!(s.multipliers.is_empty());
    }

    #[test]
    fn infeasible_qp_is_an_error() {
        let r = solve_qp(&QpProblem {
            h: &[],
            g: &[1.0, 0.0],
            a: &[vec![1.0, 1.0]],
            b: &[-1.0],
            lower: &[0.0, 0.0],
            upper: &[1.0, 1.0],
        });
        assert!(matches!(r, Err(OptimizeError::Infeasible { .. })), "{r:?}");
    }

    #[test]
    fn lp_vertex() {
        // max x + 2y on x + y ≤ 1, box [0, 1]²: vertex (0, 1).
        let s = solve_qp(&QpProblem {
            h: &[],
            g: &[-1.0, -2.0],
            a: &[vec![1.0, 1.0]],
            b: &[1.0],
            lower: &[0.0, 0.0],
            upper: &[1.0, 1.0],
        })
        .unwrap();
        assert!(close(&s.x, &[0.0, 1.0], 1e-7), "{:?}", s.x);
    }
}
