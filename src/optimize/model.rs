//! Quadratic models fitted to scattered evaluations, and the poisedness measure of a point set.
//!
//! A model about the centre `x_c` with radius `Δ` is `m(d) = c + gᵀd + ½ dᵀHd`, `d = x − x_c`.
//! It is fitted in scaled coordinates `s = d/Δ` by weighted, regularised least squares on the
//! basis `{1, s_i, ½s_i², s_i s_j (i<j)}`: data rows weighted by `2/(1 + ‖s‖∞²)` (1 at the
//! trust-region boundary, ~0.1 at `4Δ`: far points inform the Hessian without dominating the
//! local fit) plus `√λ`·(Frobenius weights) rows on the Hessian coefficients, `λ = 1e-6` after
//! scaling the values to unit spread. Consequences:
//! - with `(n+1)(n+2)/2` or more well-spread points it is a least-squares full quadratic (noise
//!   is averaged rather than interpolated when there are more points than coefficients);
//! - with fewer points (e.g. the `2n+1` initial design) it approaches the minimum-Frobenius-norm
//!   Hessian interpolant (Powell's choice in NEWUOA/BOBYQA), e.g. a diagonal Hessian on `x_c ±
//!   Δe_i`.
//!
//! Poisedness of the linear part is measured by `σ_min` of the scaled displacements
//! `(y_k − x_c)/Δ` (Conn, Scheinberg & Vicente 2009, ch. 3–4): a set is well poised for a linear
//! model when `σ_min` is bounded away from zero.

use nalgebra::DMatrix;

/// `c + gᵀd + ½dᵀHd` about a centre, in unscaled displacement `d`.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct QuadraticModel {
    pub(crate) c: f64,
    pub(crate) g: Vec<f64>,
    pub(crate) h: Vec<Vec<f64>>,
}

impl QuadraticModel {
    /// Model value at displacement `d`.
    #[cfg(test)]
    pub(crate) fn value(&self, d: &[f64]) -> f64 {
        use super::qp::{dot, quad_form};
        self.c + dot(&self.g, d) + 0.5 * quad_form(&self.h, d)
    }
}

/// Relative weight of the Hessian regulariser (values scaled to unit spread, `s = d/Δ`).
const HESSIAN_REGULARISATION: f64 = 1e-6;

/// Fits one quadratic model per value column. `points[k]` has values `values[j][k]` for column
/// `j`. Needs at least one point; the linear part is well determined only for a poised set.
pub(crate) fn fit_quadratics(
    centre: &[f64],
    radius: f64,
    points: &[&[f64]],
    values: &[Vec<f64>],
) -> Vec<QuadraticModel> {
    let n = centre.len();
    let nh = n * (n + 1) / 2;
    let q = 1 + n + nh;
    let m = points.len();
    let reg = HESSIAN_REGULARISATION.sqrt();
    let mut mat = DMatrix::<f64>::zeros(m + nh, q);
    let mut weights = Vec::with_capacity(m);
    for (k, y) in points.iter().enumerate() {
        let s: Vec<f64> = (0..n).map(|i| (y[i] - centre[i]) / radius).collect();
        let r = s.iter().fold(0.0_f64, |a, x| a.max(x.abs()));
        weights.push(2.0 / (1.0 + r * r));
        mat[(k, 0)] = 1.0;
        for i in 0..n {
            mat[(k, 1 + i)] = s[i];
        }
        let mut col = 1 + n;
        for i in 0..n {
            for j in i..n {
                mat[(k, col)] = if i == j {
                    0.5 * s[i] * s[i]
                } else {
                    s[i] * s[j]
                };
                if i == j {
                    mat[(m + col - 1 - n, col)] = reg;
                } else {
                    mat[(m + col - 1 - n, col)] = reg * 2f64.sqrt();
                }
                col += 1;
            }
        }
    }
    // Values scaled to unit spread so that the regulariser is relative.
    let ncols = values.len();
    let mut rhs = DMatrix::<f64>::zeros(m + nh, ncols);
    let mut shifts = vec![0.0; ncols];
    let mut scales = vec![1.0; ncols];
    for (j, v) in values.iter().enumerate() {
        let mean = v.iter().sum::<f64>() / m.max(1) as f64;
        let spread = v.iter().fold(0.0_f64, |a, x| a.max((x - mean).abs()));
        shifts[j] = mean;
        scales[j] = if spread > 0.0 { spread } else { 1.0 };
        for k in 0..m {
            rhs[(k, j)] = (v[k] - mean) / scales[j];
        }
    }
    for (k, w) in weights.iter().enumerate() {
        for j in 0..q {
            mat[(k, j)] *= w;
        }
        for j in 0..ncols {
            rhs[(k, j)] *= w;
        }
    }
    let svd = mat.svd(true, true);
    let smax = svd.singular_values.max();
    let coef = svd
        .solve(&rhs, 1e-12 * smax.max(f64::MIN_POSITIVE))
        .unwrap_or_else(|_| DMatrix::zeros(q, ncols));
    (0..ncols)
        .map(|j| {
            let sc = scales[j];
            let c = coef[(0, j)] * sc + shifts[j];
            let g = (0..n).map(|i| coef[(1 + i, j)] * sc / radius).collect();
            let mut h = vec![vec![0.0; n]; n];
            let upper = (0..n).flat_map(|i| (i..n).map(move |k| (i, k)));
            for ((i, k), col) in upper.zip(1 + n..) {
                let v = coef[(col, j)] * sc / (radius * radius);
                h[i][k] = v;
                h[k][i] = v;
            }
            QuadraticModel { c, g, h }
        })
        .collect()
}

/// Poisedness of scaled displacements (rows, each of length `n`).
#[derive(Clone, Debug)]
pub(crate) struct Poisedness {
    /// Singular values, largest first, padded with zeros to `n` when there are fewer rows.
    pub(crate) singular_values: Vec<f64>,
    /// Right singular vectors, from the smallest singular value up (the missing directions
    /// first when there are fewer than `n` rows).
    pub(crate) directions: Vec<Vec<f64>>,
}

impl Poisedness {
    /// `σ_min` over all `n` directions (0 with fewer than `n` rows).
    pub(crate) fn sigma_min(&self) -> f64 {
        self.singular_values.last().copied().unwrap_or(0.0)
    }

    /// The `k`-th largest singular value (1-based; 0 if `k` is 0 or beyond `n`): for `k` rows
    /// and `k ≤ n`, how well those rows span a `k`-dimensional subspace.
    pub(crate) fn kth(&self, k: usize) -> f64 {
        if k == 0 {
            return 0.0;
        }
        self.singular_values.get(k - 1).copied().unwrap_or(0.0)
    }
}

/// Singular values and right singular vectors of the scaled displacements.
pub(crate) fn poisedness(displacements: &[Vec<f64>], n: usize) -> Poisedness {
    let rows = displacements.len().max(n);
    let mut d = DMatrix::<f64>::zeros(rows, n);
    for (k, row) in displacements.iter().enumerate() {
        for i in 0..n {
            d[(k, i)] = row[i];
        }
    }
    let svd = d.svd(false, true);
    let mut order: Vec<usize> = (0..svd.singular_values.len()).collect();
    order.sort_by(|&a, &b| svd.singular_values[b].total_cmp(&svd.singular_values[a]));
    let singular_values = order.iter().map(|&k| svd.singular_values[k]).collect();
    let directions = match svd.v_t.as_ref() {
        Some(vt) => order
            .iter()
            .rev()
            .map(|&k| (0..n).map(|i| vt[(k, i)]).collect())
            .collect(),
        None => Vec::new(),
    };
    Poisedness {
        singular_values,
        directions,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn quadratic(x: &[f64]) -> f64 {
        1.0 + 2.0 * x[0] - 3.0 * x[1]
            + 0.5 * (4.0 * x[0] * x[0] + 2.0 * x[1] * x[1])
            + 1.5 * x[0] * x[1]
    }

    /// Six or more points determine a full quadratic exactly.
    #[test]
    fn full_quadratic_is_recovered() {
        let centre = [0.3, -0.2];
        let pts: Vec<Vec<f64>> = vec![
            vec![0.3, -0.2],
            vec![0.4, -0.2],
            vec![0.2, -0.2],
            vec![0.3, -0.1],
            vec![0.3, -0.3],
            vec![0.4, -0.1],
            vec![0.25, -0.28],
        ];
        let refs: Vec<&[f64]> = pts.iter().map(|p| p.as_slice()).collect();
        let vals: Vec<f64> = pts.iter().map(|p| quadratic(p)).collect();
        let m = &fit_quadratics(&centre, 0.1, &refs, &[vals])[0];
        // Gradient at the centre: (2 + 4x + 1.5y, −3 + 2y + 1.5x).
        let g = [2.0 + 4.0 * 0.3 - 1.5 * 0.2, -3.0 - 0.4 + 1.5 * 0.3];
        assert!(
            (m.g[0] - g[0]).abs() < 1e-6 && (m.g[1] - g[1]).abs() < 1e-6,
            "{m:?}"
        );
        assert!((m.h[0][0] - 4.0).abs() < 1e-4 && (m.h[1][1] - 2.0).abs() < 1e-4);
        assert!((m.h[0][1] - 1.5).abs() < 1e-4);
        assert!((m.value(&[0.05, 0.05]) - quadratic(&[0.35, -0.15])).abs() < 1e-6);
    }

    /// The 2n+1 axis design gives a diagonal (minimum-norm) Hessian and exact central
    /// differences for the gradient.
    #[test]
    fn axis_design_gives_diagonal_hessian() {
        let centre = [0.0, 0.0];
        let pts: Vec<Vec<f64>> = vec![
            vec![0.0, 0.0],
            vec![0.1, 0.0],
            vec![-0.1, 0.0],
            vec![0.0, 0.1],
            vec![0.0, -0.1],
        ];
        let refs: Vec<&[f64]> = pts.iter().map(|p| p.as_slice()).collect();
        let vals: Vec<f64> = pts.iter().map(|p| quadratic(p)).collect();
        let m = &fit_quadratics(&centre, 0.1, &refs, &[vals])[0];
        assert!(
            (m.g[0] - 2.0).abs() < 1e-6 && (m.g[1] + 3.0).abs() < 1e-6,
            "{m:?}"
        );
        assert!((m.h[0][0] - 4.0).abs() < 1e-3 && (m.h[1][1] - 2.0).abs() < 1e-3);
        assert!(m.h[0][1].abs() < 1e-6);
    }

    #[test]
    fn poisedness_of_degenerate_sets() {
        let p = poisedness(&[vec![1.0, 0.0], vec![-1.0, 0.0]], 2);
        assert!(p.sigma_min().abs() < 1e-12);
        assert!((p.kth(1) - 2f64.sqrt()).abs() < 1e-12);
        assert!(
            p.directions[0][1].abs() > 0.999,
            "missing direction is e2: {p:?}"
        );
        let p = poisedness(&[vec![1.0, 0.0], vec![0.0, 1.0]], 2);
        assert!((p.sigma_min() - 1.0).abs() < 1e-12);
        let p = poisedness(&[vec![1.0, 1.0]], 2);
        assert_eq!(p.sigma_min(), 0.0);
        assert!((p.kth(1) - 2f64.sqrt()).abs() < 1e-12);
        let v = &p.directions[0];
        assert!((v[0] + v[1]).abs() < 1e-12, "{v:?}");
        assert_eq!(poisedness(&[], 2).kth(1), 0.0);
    }
}
