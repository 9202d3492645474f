//! The known (cheap) feasible set of the optimisation variables: a box `lower ≤ x ≤ upper`
//! plus general linear inequalities `a_i · x ≤ b_i`.
//!
//! Every optimiser keeps its iterates inside this set (up to [`FEASIBILITY_TOL`]); only the
//! black-box constraints of [`crate::optimize::Evaluation`] may be violated. Violations are
//! measured as distances in variable units: `(a_i·x − b_i)/‖a_i‖₂` for a linear row.

use super::OptimizeError;
use super::qp::{QpProblem, dot, solve_dense, solve_qp};

/// Tolerance (variable units) within which a point counts as inside the feasible set; the
/// interior-point QP solver returns points this close to the boundary.
pub const FEASIBILITY_TOL: f64 = 1e-8;

/// Box bounds plus linear inequality constraints, validated.
#[derive(Clone, Debug, PartialEq)]
pub struct FeasibleSet {
    lower: Vec<f64>,
    upper: Vec<f64>,
    a: Vec<Vec<f64>>,
    b: Vec<f64>,
}

impl FeasibleSet {
    /// Validates finite bounds with `lower ≤ upper`, rows `a_i` of length `n` and `b` of the
    /// same count as `a`. An empty intersection is *not* detected here: call
    /// [`FeasibleSet::find_feasible_point`].
    pub fn new(
        lower: Vec<f64>,
        upper: Vec<f64>,
        a: Vec<Vec<f64>>,
        b: Vec<f64>,
    ) -> Result<Self, OptimizeError> {
        let n = lower.len();
        if upper.len() != n {
            return Err(OptimizeError::dimension("upper bounds", n, upper.len()));
        }
        if a.len() != b.len() {
            return Err(OptimizeError::dimension(
                "linear constraint right-hand sides b",
                a.len(),
                b.len(),
            ));
        }
        OptimizeError::check_finite("lower bounds", &lower)?;
        OptimizeError::check_finite("upper bounds", &upper)?;
        OptimizeError::check_finite("linear constraint right-hand sides b", &b)?;
        for (i, row) in a.iter().enumerate() {
            if row.len() != n {
                return Err(OptimizeError::dimension(
                    format!("linear constraint row {i}"),
                    n,
                    row.len(),
                ));
            }
            OptimizeError::check_finite(&format!("linear constraint row {i}"), row)?;
        }
        for i in 0..n {
            if lower[i] > upper[i] {
                return Err(OptimizeError::EmptyBound {
                    index: i,
                    lower: lower[i],
                    upper: upper[i],
                });
            }
        }
        Ok(FeasibleSet { lower, upper, a, b })
    }

    /// A box without linear constraints.
    pub fn from_box(lower: Vec<f64>, upper: Vec<f64>) -> Result<Self, OptimizeError> {
        FeasibleSet::new(lower, upper, Vec::new(), Vec::new())
    }

    /// Number of variables.
    pub fn dim(&self) -> usize {
        self.lower.len()
    }

    /// Lower bounds.
    pub fn lower(&self) -> &[f64] {
        &self.lower
    }

    /// Upper bounds.
    pub fn upper(&self) -> &[f64] {
        &self.upper
    }

    /// Linear constraint rows `a_i`.
    pub fn a(&self) -> &[Vec<f64>] {
        &self.a
    }

    /// Linear constraint right-hand sides `b_i`.
    pub fn b(&self) -> &[f64] {
        &self.b
    }

    /// Largest violation of a bound or row, as a distance in variable units (0 inside; +∞ for a
    /// point of the wrong dimension or with a NaN).
    pub fn violation(&self, x: &[f64]) -> f64 {
        if x.len() != self.dim() || x.iter().any(|v| v.is_nan()) {
            return f64::INFINITY;
        }
        let mut v = 0.0_f64;
        for ((xi, lo), hi) in x.iter().zip(&self.lower).zip(&self.upper) {
            v = v.max(lo - xi).max(xi - hi);
        }
        for (row, bi) in self.a.iter().zip(&self.b) {
            let norm = dot(row, row).sqrt();
            let r = dot(row, x) - bi;
            v = v.max(if norm > 0.0 { r / norm } else { r });
        }
        v
    }

    /// `x` is within `tol` (variable units) of satisfying every bound and row.
    pub fn contains(&self, x: &[f64], tol: f64) -> bool {
        self.violation(x) <= tol
    }

    /// Clips `x` to the box (not to the linear rows).
    pub fn clip_to_box(&self, x: &[f64]) -> Vec<f64> {
        x.iter()
            .zip(self.lower.iter().zip(&self.upper))
            .map(|(v, (lo, hi))| v.clamp(*lo, *hi))
            .collect()
    }

    /// Euclidean projection `argmin_y ‖y − x‖₂` over the set (a Clarabel QP). A point already
    /// inside is returned unchanged; an empty set is [`OptimizeError::Infeasible`].
    pub fn project(&self, x: &[f64]) -> Result<Vec<f64>, OptimizeError> {
        if x.len() != self.dim() {
            return Err(OptimizeError::dimension(
                "point to project",
                self.dim(),
                x.len(),
            ));
        }
        OptimizeError::check_finite("point to project", x)?;
        if self.contains(x, 0.0) {
            return Ok(x.to_vec());
        }
        if self.a.is_empty() {
            return Ok(self.clip_to_box(x));
        }
        let n = self.dim();
        let identity: Vec<Vec<f64>> = (0..n)
            .map(|i| (0..n).map(|j| if i == j { 1.0 } else { 0.0 }).collect())
            .collect();
        let g: Vec<f64> = x.iter().map(|v| -v).collect();
        let sol = solve_qp(&QpProblem {
            h: &identity,
            g: &g,
            a: &self.a,
            b: &self.b,
            lower: &self.lower,
            upper: &self.upper,
        })
        .map_err(|e| match e {
            OptimizeError::Infeasible { .. } => self.infeasibility_error(),
            other => other,
        })?;
        Ok(sol.x)
    }

    /// Chebyshev centre: the centre `x` and radius `r` of the largest ∞-ball-in-the-box /
    /// 2-ball-in-the-rows, from the LP `max r  s.t.  a_i·x + ‖a_i‖ r ≤ b_i, lo + r ≤ x ≤ hi − r`
    /// with `r` free. `r < 0` means the set is empty (−r is how far it is from being non-empty).
    pub fn chebyshev_centre(&self) -> Result<(Vec<f64>, f64), OptimizeError> {
        let n = self.dim();
        let empty_row =
            (0..self.a.len()).find(|&i| self.a[i].iter().all(|&v| v == 0.0) && self.b[i] < 0.0);
        if let Some(i) = empty_row {
            return Err(OptimizeError::Infeasible {
                violation: -self.b[i],
                row: Some(i),
            });
        }
        let mut rows = Vec::new();
        let mut rhs = Vec::new();
        for (row, bi) in self.a.iter().zip(&self.b) {
            let norm = dot(row, row).sqrt();
            if norm == 0.0 {
                continue;
            }
            let mut r = row.clone();
            r.push(norm);
            rows.push(r);
            rhs.push(*bi);
        }
        for i in 0..n {
            let mut up = vec![0.0; n + 1];
            up[i] = 1.0;
            up[n] = 1.0;
            rows.push(up);
            rhs.push(self.upper[i]);
            let mut lo = vec![0.0; n + 1];
            lo[i] = -1.0;
            lo[n] = 1.0;
            rows.push(lo);
            rhs.push(-self.lower[i]);
        }
        let mut q = vec![0.0; n + 1];
        q[n] = -1.0;
        let (z, _, _) = solve_dense(&[], &q, &rows, &rhs)?;
        Ok((z[..n].to_vec(), z[n]))
    }

    /// A point of the set (the Chebyshev centre, clipped to the box), or
    /// [`OptimizeError::Infeasible`] when the set is empty.
    pub fn find_feasible_point(&self) -> Result<Vec<f64>, OptimizeError> {
        let (x, r) = self.chebyshev_centre()?;
        let x = self.clip_to_box(&x);
        if r < -FEASIBILITY_TOL || !self.contains(&x, FEASIBILITY_TOL) {
            return Err(self.infeasibility_error());
        }
        Ok(x)
    }

    fn infeasibility_error(&self) -> OptimizeError {
        match self.chebyshev_centre() {
            Ok((x, r)) => {
                let x = self.clip_to_box(&x);
                let row = (0..self.a.len()).max_by(|&i, &j| {
                    let vi = dot(&self.a[i], &x) - self.b[i];
                    let vj = dot(&self.a[j], &x) - self.b[j];
                    vi.total_cmp(&vj)
                });
                OptimizeError::Infeasible {
                    violation: (-r).max(self.violation(&x)),
                    row,
                }
            }
            Err(e) => e,
        }
    }

    /// Tensor grid with `per_dim` points per variable (endpoints included; 1 gives the box
    /// midpoint), keeping only points inside the set. Ordered with the last variable fastest.
    pub fn grid(&self, per_dim: usize) -> Vec<Vec<f64>> {
        let n = self.dim();
        let per_dim = per_dim.max(1);
        let coord = |i: usize, k: usize| {
            if per_dim == 1 {
                0.5 * (self.lower[i] + self.upper[i])
            } else {
                let t = k as f64 / (per_dim - 1) as f64;
                self.lower[i] + t * (self.upper[i] - self.lower[i])
            }
        };
        let total = per_dim.pow(n as u32);
        let mut points = Vec::new();
        for mut idx in 0..total {
            let mut x = vec![0.0; n];
            for i in (0..n).rev() {
                x[i] = coord(i, idx % per_dim);
                idx /= per_dim;
            }
            if self.contains(&x, 1e-12) {
                points.push(x);
            }
        }
        points
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn triangle() -> FeasibleSet {
        // Unit box cut by x + y ≤ 1.
        FeasibleSet::new(
            vec![0.0, 0.0],
            vec![1.0, 1.0],
            vec![vec![1.0, 1.0]],
            vec![1.0],
        )
        .unwrap()
    }

    #[test]
    fn validation() {
        assert!(matches!(
            FeasibleSet::from_box(vec![0.0, 2.0], vec![1.0, 1.0]),
            Err(OptimizeError::EmptyBound { index: 1, .. })
        ));
        assert!(matches!(
            FeasibleSet::from_box(vec![0.0], vec![f64::NAN]),
            Err(OptimizeError::NonFinite { .. })
        ));
        assert!(matches!(
            FeasibleSet::new(vec![0.0], vec![1.0], vec![vec![1.0, 2.0]], vec![1.0]),
            Err(OptimizeError::Dimension { .. })
        ));
    }

    #[test]
    fn violation_is_a_distance() {
        let s = triangle();
        assert_eq!(s.violation(&[0.2, 0.2]), 0.0);
        assert!((s.violation(&[1.0, 1.0]) - 1.0 / 2f64.sqrt()).abs() < 1e-15);
        assert!((s.violation(&[-0.5, 0.5]) - 0.5).abs() < 1e-15);
        assert!(s.contains(&[0.5, 0.5], 0.0));
        assert!(!s.contains(&[0.6, 0.5], 1e-3));
    }

    /// Projection of (1, 1) onto x + y ≤ 1 is (½, ½); of (2, −1) onto the triangle is the
    /// vertex (1, 0) (box clip gives (1, 0) which also satisfies the row).
    #[test]
    fn projection() {
        let s = triangle();
        let p = s.project(&[1.0, 1.0]).unwrap();
        assert!(
            (p[0] - 0.5).abs() < 1e-7 && (p[1] - 0.5).abs() < 1e-7,
            "{p:?}"
        );
        assert!(s.contains(&p, FEASIBILITY_TOL));
        let p = s.project(&[2.0, -1.0]).unwrap();
        assert!((p[0] - 1.0).abs() < 1e-7 && p[1].abs() < 1e-7, "{p:?}");
        // (0.9, 0.6): nearest point on x + y = 1 is (0.65, 0.35), inside the box.
        let p = s.project(&[0.9, 0.6]).unwrap();
        assert!(
            (p[0] - 0.65).abs() < 1e-7 && (p[1] - 0.35).abs() < 1e-7,
            "{p:?}"
        );
        // An interior point is returned unchanged.
        assert_eq!(s.project(&[0.1, 0.2]).unwrap(), vec![0.1, 0.2]);
    }

    /// The triangle's inscribed circle: centre (r, r) with r = 1/(2 + √2).
    #[test]
    fn chebyshev_centre_of_triangle() {
        let (x, r) = triangle().chebyshev_centre().unwrap();
        let expected = 1.0 / (2.0 + 2f64.sqrt());
        assert!((r - expected).abs() < 1e-7, "r = {r}");
        assert!((x[0] - expected).abs() < 1e-6 && (x[1] - expected).abs() < 1e-6);
        assert!(triangle().find_feasible_point().is_ok());
    }

    /// x + y ≤ −0.5 on the unit box is empty; the error says by how much.
    #[test]
    fn empty_set_is_detected() {
        let s = FeasibleSet::new(
            vec![0.0, 0.0],
            vec![1.0, 1.0],
            vec![vec![1.0, 1.0]],
            vec![-0.5],
        )
        .unwrap();
        match s.find_feasible_point() {
            Err(OptimizeError::Infeasible { violation, row }) => {
                assert!(violation > 0.1, "violation {violation}");
                assert_eq!(row, Some(0));
            }
            other => panic!("expected Infeasible, got {other:?}"),
        }
        assert!(matches!(
            s.project(&[0.5, 0.5]),
            Err(OptimizeError::Infeasible { .. })
        ));
        let zero_row = FeasibleSet::new(vec![0.0], vec![1.0], vec![vec![0.0]], vec![-1.0]).unwrap();
        assert!(matches!(
            zero_row.find_feasible_point(),
            Err(OptimizeError::Infeasible { row: Some(0), .. })
        ));
    }

    #[test]
    fn grid_skips_infeasible_points() {
        let g = triangle().grid(3);
        // (0,0) (0,½) (0,1) (½,0) (½,½) (1,0): 6 of 9.
        assert_eq!(g.len(), 6);
        assert_eq!(g[0], vec![0.0, 0.0]);
        assert_eq!(
            FeasibleSet::from_box(vec![0.0], vec![2.0]).unwrap().grid(1),
            vec![vec![1.0]]
        );
    }
}
