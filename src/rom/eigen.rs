//! The generalized symmetric eigenproblem K φ = λ M φ with M positive definite.
//!
//! faer has no symmetric generalized solver, so reduce to a self-adjoint one by Cholesky and two
//! triangular solves: in inverse form when K is positive definite (K = L Lᵀ, B = L⁻¹ M L⁻ᵀ,
//! B y = μ y, λ = 1/μ, φ = L⁻ᵀ y / √μ), whose round-off of the lowest modes is relative to
//! themselves; else in standard form (M = L Lᵀ, A = L⁻¹ K L⁻ᵀ, A y = λ y, φ = L⁻ᵀ y). The φ are
//! M-orthonormal: φᵢᵀ M φⱼ = δᵢⱼ.

use faer::linalg::cholesky::llt::factor::LltError;
use faer::linalg::triangular_solve::{
    solve_lower_triangular_in_place, solve_upper_triangular_in_place,
};
use faer::{Mat, MatRef, Par, Side};

/// Why an eigen-solve failed.
#[derive(Debug, Clone, thiserror::Error, PartialEq)]
pub enum EigenError {
    /// Cholesky of M met a pivot ≤ 0 at row `pivot` (of the matrix solved).
    #[error(
        "the mass matrix is not positive definite (Cholesky pivot {pivot} not positive): check densities and constraints"
    )]
    MassNotPositiveDefinite { pivot: usize },
    /// Neither K nor K − σM (σ < 0) could be factored: a negative stiffness (sparse solver only).
    #[error("the stiffness matrix is not positive semi-definite (Cholesky pivot {pivot})")]
    StiffnessNotPositive { pivot: usize },
    /// `converged` of the `asked` eigenpairs converged.
    #[error("the symmetric eigensolver did not converge ({converged} of {asked} eigenpairs)")]
    NoConvergence { converged: usize, asked: usize },
    #[error("asked for {asked} eigenpairs of a {size}×{size} problem")]
    TooMany { asked: usize, size: usize },
}

/// The `count` smallest eigenpairs of K φ = λ M φ: eigenvalues ascending, M-normalised vectors as
/// columns. `par` is the parallelism faer may use (use `Par::Seq` inside rayon tasks).
///
/// Solved in inverse form when K is positive definite, as the string's constraints make it:
/// K = L Lᵀ (Cholesky), B = L⁻¹ M L⁻ᵀ, B y = μ y, λ = 1/μ, φ = L⁻ᵀ y / √μ. The lowest modes are the
/// largest μ, so their round-off is relative to themselves (ε·n·μ_max), not to the highest
/// eigenvalue of the mesh as in the standard form L_M⁻¹ K L_M⁻ᵀ: a beam of short Timoshenko
/// elements has rotary-inertia modes at 1e10–1e11 1/s² against mHz bending modes of a long span
/// (1e-3 1/s²), which the standard form gets wrong or non-positive (Parlett, The Symmetric
/// Eigenvalue Problem, SIAM 1998, §15.2–15.3; Ericsson & Ruhe, Math. Comp. 35, 1980). A K that
/// is singular (rigid-body modes) or indefinite takes the standard form (a small negative shift
/// would make the round-off of every other mode relative to the shift's 1/|σ|), and so do the
/// pairs whose μ is below B's round-off, n ε μ_max (the highest of a nearly complete set). A K
/// that factors with a tiny pivot (nearly singular) is not detected: the string's constraints
/// keep K well away from that.
///
/// Errors: [`EigenError::TooMany`]; [`EigenError::MassNotPositiveDefinite`] with the pivot's row;
/// [`EigenError::NoConvergence`] when faer's self-adjoint solver fails.
pub fn generalized_symmetric_eigen(
    k: MatRef<'_, f64>,
    m: MatRef<'_, f64>,
    count: usize,
    par: Par,
) -> Result<(Vec<f64>, Mat<f64>), EigenError> {
    let n = k.nrows();
    if count > n {
        return Err(EigenError::TooMany {
            asked: count,
            size: n,
        });
    }
    let llt_m = m.llt(Side::Lower).map_err(|e| match e {
        LltError::NonPositivePivot { index } => {
            EigenError::MassNotPositiveDefinite { pivot: index }
        }
    })?;
    if count == 0 {
        return Ok((Vec::new(), Mat::zeros(n, 0)));
    }
    let Ok(llt_k) = k.llt(Side::Lower) else {
        return standard_form(k, llt_m.L(), count, par);
    };
    let l = llt_k.L();
    let evd = congruent_eigen(l, m, count, par)?;
    // μ ascending: the largest `count`, taken from the top, are the lowest λ in ascending order.
    let s = evd.S().column_vector();
    let mu_max = s[n - 1];
    if mu_max.is_nan() || mu_max <= 0.0 {
        return standard_form(k, llt_m.L(), count, par);
    }
    // The pairs whose μ stands above the round-off of B (n ε μ_max) come from the inverse form;
    // the rest, the highest λ of a nearly complete set (a cutoff family, a block solved whole),
    // from the standard form, whose round-off is relative to them.
    let floor = n as f64 * f64::EPSILON * mu_max;
    let good = (0..count).take_while(|&i| s[n - 1 - i] > floor).count();
    let mu: Vec<f64> = (0..good).map(|i| s[n - 1 - i]).collect();
    let u = evd.U();
    let mut low = Mat::from_fn(n, good, |i, j| u[(i, n - 1 - j)] / mu[j].sqrt());
    solve_upper_triangular_in_place(l.transpose(), low.as_mut(), par);
    let mut values: Vec<f64> = mu.iter().map(|&v| 1.0 / v).collect();
    if good == count {
        return Ok((values, low));
    }
    let (high_values, high) = standard_form(k, llt_m.L(), count, par)?;
    values.extend_from_slice(&high_values[good..]);
    let vectors = Mat::from_fn(
        n,
        count,
        |i, j| {
            if j < good { low[(i, j)] } else { high[(i, j)] }
        },
    );
    Ok((values, vectors))
}

/// The eigendecomposition (eigenvalues ascending) of L⁻¹ A L⁻ᵀ for a lower-triangular L and a
/// symmetric A: X = L⁻¹ A, then L⁻¹ Xᵀ by two triangular solves, symmetrised against round-off
/// before faer's self-adjoint solver. `count` is what the caller asked for (its error's).
fn congruent_eigen(
    l: MatRef<'_, f64>,
    a: MatRef<'_, f64>,
    count: usize,
    par: Par,
) -> Result<faer::linalg::solvers::SelfAdjointEigen<f64>, EigenError> {
    let n = a.nrows();
    let mut x = a.to_owned();
    solve_lower_triangular_in_place(l, x.as_mut(), par);
    let mut c = x.transpose().to_owned();
    solve_lower_triangular_in_place(l, c.as_mut(), par);
    let c = Mat::from_fn(n, n, |i, j| 0.5 * (c[(i, j)] + c[(j, i)]));
    c.self_adjoint_eigen(Side::Lower)
        .map_err(|_| EigenError::NoConvergence {
            converged: 0,
            asked: count,
        })
}

/// The standard form with M = L Lᵀ: A = L⁻¹ K L⁻ᵀ, A y = λ y, φ = L⁻ᵀ y (for a singular or
/// indefinite K, and the highest pairs of a nearly complete set).
fn standard_form(
    k: MatRef<'_, f64>,
    l: MatRef<'_, f64>,
    count: usize,
    par: Par,
) -> Result<(Vec<f64>, Mat<f64>), EigenError> {
    let evd = congruent_eigen(l, k, count, par)?;
    let s = evd.S().column_vector();
    let values: Vec<f64> = (0..count).map(|i| s[i]).collect();
    let mut vectors = evd.U().subcols(0, count).to_owned();
    solve_upper_triangular_in_place(l.transpose(), vectors.as_mut(), par);
    Ok((values, vectors))
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn solves_a_two_mass_chain_exactly() {
        // Masses m, 2m; springs k (to ground), k (between): λ = (k/m)(2 ∓ √2)/2 ... check residuals.
        let k = Mat::from_fn(2, 2, |i, j| [[2.0, -1.0], [-1.0, 1.0]][i][j]);
        let m = Mat::from_fn(2, 2, |i, j| [[1.0, 0.0], [0.0, 2.0]][i][j]);
        let (values, vectors) =
            generalized_symmetric_eigen(k.as_ref(), m.as_ref(), 2, Par::Seq).unwrap();
        // det(K − λM) = 2λ² − 5λ + 1 = 0.
        let disc = (25.0f64 - 8.0).sqrt();
        assert_relative_eq!(values[0], (5.0 - disc) / 4.0, max_relative = 1e-14);
        assert_relative_eq!(values[1], (5.0 + disc) / 4.0, max_relative = 1e-14);
        let gram = vectors.transpose() * &m * &vectors;
        let residual = &k * &vectors
            - &m * &vectors * Mat::from_fn(2, 2, |i, j| if i == j { values[i] } else { 0.0 });
        for i in 0..2 {
            for j in 0..2 {
                assert_relative_eq!(
                    gram[(i, j)],
                    if i == j { 1.0 } else { 0.0 },
                    epsilon = 1e-14
                );
                assert_relative_eq!(residual[(i, j)], 0.0, epsilon = 1e-13);
            }
        }
    }

    #[test]
    fn a_singular_stiffness_takes_the_standard_form() {
        // A free two-mass chain: K singular (λ = 0, 2 k/m).
        let k = Mat::from_fn(2, 2, |i, j| [[1.0, -1.0], [-1.0, 1.0]][i][j]);
        let m = Mat::<f64>::identity(2, 2);
        let (values, vectors) =
            generalized_symmetric_eigen(k.as_ref(), m.as_ref(), 2, Par::Seq).unwrap();
        assert!(values[0].abs() < 1e-12, "rigid-body λ {}", values[0]);
        assert_relative_eq!(values[1], 2.0, max_relative = 1e-12);
        let gram = vectors.transpose() * &m * &vectors;
        assert_relative_eq!(gram[(0, 0)], 1.0, epsilon = 1e-12);
        assert_relative_eq!(gram[(1, 1)], 1.0, epsilon = 1e-12);
        assert_relative_eq!(gram[(0, 1)], 0.0, epsilon = 1e-12);
        // The rigid-body vector is (1, 1)/√2.
        assert_relative_eq!(vectors[(0, 0)], vectors[(1, 0)], epsilon = 1e-12);
    }

    #[test]
    fn an_indefinite_stiffness_takes_the_standard_form() {
        let k = Mat::from_fn(2, 2, |i, j| [[-1.0, 0.5], [0.5, 2.0]][i][j]);
        let m = Mat::<f64>::identity(2, 2);
        let (values, _) = generalized_symmetric_eigen(k.as_ref(), m.as_ref(), 2, Par::Seq).unwrap();
        // λ = (1 ∓ √(9 + 1))/2.
        let root = 10.0f64.sqrt();
        assert_relative_eq!(values[0], (1.0 - root) / 2.0, max_relative = 1e-12);
        assert_relative_eq!(values[1], (1.0 + root) / 2.0, max_relative = 1e-12);
    }

    #[test]
    fn a_complete_set_of_a_widely_spread_pencil_is_exact_at_both_ends() {
        // μ = 1e3, 1, 1e-14: the last is below B's round-off (3 ε 1e3), so it comes from the
        // standard form; the first from the inverse form.
        let k = Mat::from_fn(3, 3, |i, j| if i == j { [1e-3, 1.0, 1e14][i] } else { 0.0 });
        let m = Mat::<f64>::identity(3, 3);
        let (values, vectors) =
            generalized_symmetric_eigen(k.as_ref(), m.as_ref(), 3, Par::Seq).unwrap();
        for (v, exact) in values.iter().zip([1e-3, 1.0, 1e14]) {
            assert_relative_eq!(*v, exact, max_relative = 1e-12);
        }
        let gram = vectors.transpose() * &m * &vectors;
        for i in 0..3 {
            for j in 0..3 {
                let id = if i == j { 1.0 } else { 0.0 };
                assert_relative_eq!(gram[(i, j)], id, epsilon = 1e-12);
            }
        }
    }

    #[test]
    fn refuses_a_singular_mass() {
        let k = Mat::<f64>::identity(2, 2);
        let m = Mat::from_fn(2, 2, |i, j| if i == 0 && j == 0 { 1.0 } else { 0.0 });
        let err = generalized_symmetric_eigen(k.as_ref(), m.as_ref(), 1, Par::Seq).unwrap_err();
        assert_eq!(err, EigenError::MassNotPositiveDefinite { pivot: 1 });
    }
}
