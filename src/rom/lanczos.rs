//! The lowest eigenpairs of a large sparse K φ = λ M φ without dense matrices: the spectral
//! transformation of Ericsson & Ruhe (1980) with faer's restarted (Krylov–Schur) Lanczos.
//!
//! With K − σM = L Lᵀ (sparse Cholesky in the natural order: the family blocks of a beam mesh are
//! banded, so L has no fill beyond the band), the pencil becomes the symmetric standard problem
//! A y = θ y, A = L⁻¹ M L⁻ᵀ, θ = 1/(λ − σ), φ = L⁻ᵀ y. The λ nearest σ (here the lowest: σ ≤ 0
//! below a positive semi-definite K) are the θ of largest magnitude, which Lanczos finds first
//! (Golub & Van Loan, Matrix Computations, 4th ed., §10.1 and §8.7.2; faer's
//! `partial_self_adjoint_eigen`, a Krylov–Schur restarted Lanczos with full reorthogonalisation).
//! A Rayleigh–Ritz step on (K, M) themselves then makes the vectors exactly M-orthonormal and the
//! λ accurate to the square of the vectors' error; each pair's backward error is checked.
//!
//! Only O(n · count) memory: the factor, the Krylov basis and the vectors.

use super::eigen::{EigenError, generalized_symmetric_eigen};
use crate::fem::SymmetricSparse;
use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::linalg::cholesky::llt::factor::{LltError, LltRegularization};
use faer::matrix_free::LinOp;
use faer::matrix_free::eigen::{
    PartialEigenParams, partial_self_adjoint_eigen, partial_self_adjoint_eigen_scratch,
};
use faer::sparse::linalg::cholesky::simplicial;
use faer::sparse::linalg::triangular_solve::{
    solve_lower_triangular_in_place, solve_lower_triangular_transpose_in_place,
};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, Mat, MatMut, MatRef, Par};

/// Largest backward error ‖Kφ − λMφ‖ / ((‖K‖₁ + |λ| ‖M‖₁) ‖φ‖) accepted for a returned pair
/// (round-off alone gives about 1e-16; a residual relative to ‖Kφ‖ would not do: ‖K‖ of a fine
/// beam mesh is 1e10 times the low modes' λ).
const RESIDUAL_TOLERANCE: f64 = 1e-10;
/// Lanczos locks a Ritz pair when its residual in θ is below this fraction of the largest θ.
const LANCZOS_TOLERANCE: f64 = 1e-13;
/// The smallest Krylov dimension faer's partial eigensolver uses.
const MIN_KRYLOV: usize = 64;
/// The largest block that falls back to the dense solver when Lanczos does not converge (a dense
/// generalized eigenproblem of 4000 DOFs: about 10 s and 0.5 GB).
const DENSE_FALLBACK: usize = 4000;

/// Whether [`sparse_generalized_eigen`] runs Lanczos on an n × n problem for `count` pairs, rather
/// than falling back to the dense solver (the Krylov space must be smaller than the problem).
pub fn lanczos_applies(n: usize, count: usize) -> bool {
    n > MIN_KRYLOV.max(2 * count) + 1
}

/// A sparse Cholesky factor L (A = L Lᵀ) in the natural order.
pub(super) struct SparseCholesky {
    symbolic: simplicial::SymbolicSimplicialCholesky<usize>,
    values: Vec<f64>,
}

impl SparseCholesky {
    /// Factor `a`; `Err(pivot)` is the row where a non-positive pivot appeared.
    pub(super) fn new(a: &SymmetricSparse) -> Result<Self, usize> {
        let n = a.size();
        // The upper triangle, which is all simplicial Cholesky reads.
        let (cp, ri, va) = a.parts();
        let (mut col_ptr, mut row_idx, mut values) = (vec![0usize], Vec::new(), Vec::new());
        for j in 0..n {
            for k in cp[j]..cp[j + 1] {
                if ri[k] <= j {
                    row_idx.push(ri[k]);
                    values.push(va[k]);
                }
            }
            col_ptr.push(row_idx.len());
        }
        let pattern = SymbolicSparseColMatRef::new_checked(n, n, &col_ptr, None, &row_idx);
        let matrix = SparseColMatRef::new(pattern, &values);
        let mut etree = vec![0isize; n];
        let mut col_counts = vec![0usize; n];
        let mut mem = MemBuffer::new(StackReq::any_of(&[
            simplicial::prefactorize_symbolic_cholesky_scratch::<usize>(n, row_idx.len()),
            simplicial::factorize_simplicial_symbolic_cholesky_scratch::<usize>(n),
            simplicial::factorize_simplicial_numeric_llt_scratch::<usize, f64>(n),
        ]));
        let stack = MemStack::new(&mut mem);
        let etree =
            simplicial::prefactorize_symbolic_cholesky(&mut etree, &mut col_counts, pattern, stack);
        let symbolic =
            simplicial::factorize_simplicial_symbolic_cholesky(pattern, etree, &col_counts, stack)
                .map_err(|_| 0usize)?;
        let mut l = vec![0.0; symbolic.len_val()];
        match simplicial::factorize_simplicial_numeric_llt(
            &mut l,
            matrix,
            LltRegularization::default(),
            &symbolic,
            stack,
        ) {
            Ok(_) => Ok(SparseCholesky {
                symbolic,
                values: l,
            }),
            // faer's simplicial factorisation reports the pivot 1-based.
            Err(LltError::NonPositivePivot { index }) => Err(index.saturating_sub(1)),
        }
    }

    fn factor(&self) -> SparseColMatRef<'_, usize, f64> {
        SparseColMatRef::new(self.symbolic.factor(), &self.values)
    }

    /// x ← L⁻¹ x.
    fn solve_l(&self, x: MatMut<'_, f64>) {
        solve_lower_triangular_in_place(self.factor(), Conj::No, x, Par::Seq);
    }

    /// x ← L⁻ᵀ x.
    fn solve_lt(&self, x: MatMut<'_, f64>) {
        solve_lower_triangular_transpose_in_place(self.factor(), Conj::No, x, Par::Seq);
    }

    /// x ← A⁻¹ x.
    pub fn solve(&self, mut x: MatMut<'_, f64>) {
        self.solve_l(x.as_mut());
        self.solve_lt(x);
    }
}

/// A = L⁻¹ M L⁻ᵀ, symmetric: the spectral transformation of the pencil.
#[derive(Debug)]
struct ShiftInvert<'a> {
    l: &'a SparseCholesky,
    m: &'a SymmetricSparse,
}

impl std::fmt::Debug for SparseCholesky {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "SparseCholesky({} × {})",
            self.symbolic.nrows(),
            self.symbolic.nrows()
        )
    }
}

impl LinOp<f64> for ShiftInvert<'_> {
    fn apply_scratch(&self, _rhs_ncols: usize, _par: Par) -> StackReq {
        StackReq::EMPTY
    }

    fn nrows(&self) -> usize {
        self.m.size()
    }

    fn ncols(&self) -> usize {
        self.m.size()
    }

    fn apply(&self, mut out: MatMut<'_, f64>, rhs: MatRef<'_, f64>, _par: Par, _: &mut MemStack) {
        let n = self.m.size();
        let mut x = Mat::<f64>::zeros(n, 1);
        let mut y = vec![0.0; n];
        for c in 0..rhs.ncols() {
            x.col_mut(0).copy_from(rhs.col(c));
            self.l.solve_lt(x.as_mut());
            self.m.mul_vec(x.col_as_slice(0), &mut y);
            let mut o = out.rb_mut().col_mut(c);
            for i in 0..n {
                o[i] = y[i];
            }
            self.l.solve_l(o.as_mat_mut());
        }
    }

    fn conj_apply(&self, out: MatMut<'_, f64>, rhs: MatRef<'_, f64>, par: Par, s: &mut MemStack) {
        self.apply(out, rhs, par, s);
    }
}

use faer::reborrow::ReborrowMut;

/// The `count` smallest eigenpairs of K φ = λ M φ for sparse symmetric K (positive
/// semi-definite) and M (positive definite): eigenvalues ascending, 1/s² for the drillstring;
/// M-orthonormal vectors as columns (n × count). Problems too small for a Krylov space of
/// max(64, 2·count) + 2 vectors are handed to the dense [`generalized_symmetric_eigen`].
///
/// Errors: [`EigenError::MassNotPositiveDefinite`] with the row of the failed pivot,
/// [`EigenError::StiffnessNotPositive`] when neither K nor K − σM (σ < 0) factors,
/// [`EigenError::NoConvergence`] when fewer pairs converged than asked or a backward error is
/// above 1e-10, [`EigenError::TooMany`].
pub fn sparse_generalized_eigen(
    k: &SymmetricSparse,
    m: &SymmetricSparse,
    count: usize,
    par: Par,
) -> Result<(Vec<f64>, Mat<f64>), EigenError> {
    let n = k.size();
    if count > n {
        return Err(EigenError::TooMany {
            asked: count,
            size: n,
        });
    }
    if !lanczos_applies(n, count) {
        return generalized_symmetric_eigen(
            k.to_dense().as_ref(),
            m.to_dense().as_ref(),
            count,
            par,
        );
    }
    SparseCholesky::new(m).map_err(|pivot| EigenError::MassNotPositiveDefinite { pivot })?;
    // σ = 0 when K is positive definite (the drillstring's constraints); else a small negative
    // shift below the rigid-body modes.
    let l = match SparseCholesky::new(k) {
        Ok(l) => l,
        Err(_) => {
            let diag_max = |a: &SymmetricSparse| (0..n).map(|i| a.get(i, i)).fold(0.0, f64::max);
            let sigma = -1e-8 * diag_max(k) / diag_max(m);
            let shifted = shifted(k, m, sigma);
            SparseCholesky::new(&shifted)
                .map_err(|pivot| EigenError::StiffnessNotPositive { pivot })?
        }
    };
    let op = ShiftInvert { l: &l, m };
    // A deterministic start without a special direction, and the scale of θ from a few power
    // iterations (the absolute Lanczos tolerance is relative to the largest θ = 1/(λ₁ − σ)).
    let mut v0 = Mat::<f64>::from_fn(n, 1, |i, _| 1.0 + (0.618_033_988_7 * i as f64).fract());
    let mut w = Mat::<f64>::zeros(n, 1);
    let mut theta = 0.0;
    let mut empty = MemBuffer::new(StackReq::EMPTY);
    for _ in 0..8 {
        let norm = v0.norm_l2();
        v0 /= norm;
        op.apply(w.as_mut(), v0.as_ref(), par, MemStack::new(&mut empty));
        theta = (v0.transpose() * &w)[(0, 0)];
        std::mem::swap(&mut v0, &mut w);
    }
    // faer's default Krylov–Schur space (twice the pairs asked) first; when it does not converge
    // (hundreds of pairs of a long string's bending block, clustered in twin planes), a wider
    // space and more restarts; then the dense solver, while the block is small enough for it.
    // The problems that converged the first way keep their bits.
    let mut y = Mat::<f64>::zeros(n, count);
    let mut converged = 0;
    for widened in [false, true] {
        let mut params = PartialEigenParams::default();
        if widened {
            params.max_dim = (4 * count).max(2 * MIN_KRYLOV).min(n - 1);
            params.max_restarts *= 4;
        }
        let mut mem = MemBuffer::new(partial_self_adjoint_eigen_scratch(&op, count, par, params));
        let mut thetas = vec![0.0; count];
        let info = partial_self_adjoint_eigen(
            y.as_mut(),
            &mut thetas,
            &op,
            v0.col(0),
            LANCZOS_TOLERANCE * theta.abs(),
            par,
            MemStack::new(&mut mem),
            params,
        );
        converged = info.n_converged_eigen;
        if converged >= count {
            break;
        }
    }
    // The dense solver for a family Lanczos left short, while it is small enough; else the count
    // reached.
    let fallback = |converged: usize| {
        if n <= DENSE_FALLBACK {
            generalized_symmetric_eigen(k.to_dense().as_ref(), m.to_dense().as_ref(), count, par)
        } else {
            Err(EigenError::NoConvergence {
                converged,
                asked: count,
            })
        }
    };
    if converged < count {
        return fallback(converged);
    }
    // φ = L⁻ᵀ y, then Rayleigh–Ritz on (K, M) in span φ.
    l.solve_lt(y.as_mut());
    let (kx, mx) = (apply_columns(k, y.as_ref()), apply_columns(m, y.as_ref()));
    let sym = |a: Mat<f64>| Mat::from_fn(count, count, |i, j| 0.5 * (a[(i, j)] + a[(j, i)]));
    let kr = sym(y.transpose() * &kx);
    let mr = sym(y.transpose() * &mx);
    let (values, z) = generalized_symmetric_eigen(kr.as_ref(), mr.as_ref(), count, par)?;
    let vectors = &y * &z;
    let (kphi, mphi) = (&kx * &z, &mx * &z);
    let (norm_k, norm_m) = (norm_1(k), norm_1(m));
    for (j, &lambda) in values.iter().enumerate() {
        let r = (kphi.col(j) - mphi.col(j) * lambda).norm_l2();
        let scale = (norm_k + lambda.abs() * norm_m) * vectors.col(j).norm_l2();
        // NaN fails too. The tolerance of Lanczos is relative to the largest θ = 1/λ₁, so the
        // highest of hundreds of pairs may miss it: then the dense solver, as above.
        if r.is_nan() || r > RESIDUAL_TOLERANCE * scale {
            return fallback(j);
        }
    }
    Ok((values, vectors))
}

/// The 1-norm (largest column sum of magnitudes) of a sparse matrix.
fn norm_1(a: &SymmetricSparse) -> f64 {
    (0..a.size())
        .map(|j| a.column(j).map(|(_, v)| v.abs()).sum::<f64>())
        .fold(0.0, f64::max)
}

/// K − σM on the union of the patterns.
fn shifted(k: &SymmetricSparse, m: &SymmetricSparse, sigma: f64) -> SymmetricSparse {
    let n = k.size();
    SymmetricSparse::from_column_fn(n, |j| {
        let mut col: Vec<(usize, f64)> = k.column(j).collect();
        for (i, v) in m.column(j) {
            match col.binary_search_by_key(&i, |e| e.0) {
                Ok(p) => col[p].1 -= sigma * v,
                Err(p) => col.insert(p, (i, -sigma * v)),
            }
        }
        col
    })
}

/// A X, column by column (X n × c).
fn apply_columns(a: &SymmetricSparse, x: MatRef<'_, f64>) -> Mat<f64> {
    let n = a.size();
    let mut out = Mat::<f64>::zeros(n, x.ncols());
    let mut xc = vec![0.0; n];
    let mut yc = vec![0.0; n];
    for c in 0..x.ncols() {
        for i in 0..n {
            xc[i] = x[(i, c)];
        }
        a.mul_vec(&xc, &mut yc);
        for i in 0..n {
            out[(i, c)] = yc[i];
        }
    }
    out
}

/// Solve K ψ = e_r with a sparse Cholesky of K: the static response to a unit load on DOF `r`.
/// `None` when K is not positive definite.
pub fn sparse_unit_response(k: &SymmetricSparse, r: usize) -> Option<Vec<f64>> {
    let l = SparseCholesky::new(k).ok()?;
    let mut e = Mat::<f64>::zeros(k.size(), 1);
    e[(r, 0)] = 1.0;
    l.solve(e.as_mut());
    Some(e.col_as_slice(0).to_vec())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The fixed–free string of n equal linear elements (unit stiffness and mass per length):
    /// its eigenvalues approach ((2k − 1)π/2)² as the mesh is refined; here the discrete ones are
    /// compared against the dense solver.
    fn string(n: usize) -> (SymmetricSparse, SymmetricSparse) {
        let h = 1.0 / n as f64;
        let ke = [[1.0 / h, -1.0 / h], [-1.0 / h, 1.0 / h]];
        let me = [[h / 3.0, h / 6.0], [h / 6.0, h / 3.0]];
        let mut k = Mat::<f64>::zeros(n + 1, n + 1);
        let mut m = Mat::<f64>::zeros(n + 1, n + 1);
        for e in 0..n {
            for i in 0..2 {
                for j in 0..2 {
                    k[(e + i, e + j)] += ke[i][j];
                    m[(e + i, e + j)] += me[i][j];
                }
            }
        }
        // Fix node 0.
        let sub = |a: &Mat<f64>| Mat::from_fn(n, n, |i, j| a[(i + 1, j + 1)]);
        (
            SymmetricSparse::from_dense(sub(&k).as_ref()),
            SymmetricSparse::from_dense(sub(&m).as_ref()),
        )
    }

    #[test]
    fn lanczos_matches_the_dense_solver_on_a_string() {
        let (k, m) = string(400);
        assert!(lanczos_applies(400, 20));
        let (sparse, phi) = sparse_generalized_eigen(&k, &m, 20, Par::Seq).unwrap();
        let (dense, _) =
            generalized_symmetric_eigen(k.to_dense().as_ref(), m.to_dense().as_ref(), 20, Par::Seq)
                .unwrap();
        for (s, d) in sparse.iter().zip(&dense) {
            assert!((s - d).abs() <= 1e-10 * d, "{s} vs {d}");
        }
        // Mesh-converged lowest value against the continuum ((2k − 1)π/2)².
        let exact = (std::f64::consts::PI / 2.0).powi(2);
        assert!((sparse[0] - exact).abs() < 1e-5 * exact);
        let gram = phi.transpose() * m.to_dense() * &phi;
        for i in 0..20 {
            for j in 0..20 {
                let e = if i == j { 1.0 } else { 0.0 };
                assert!((gram[(i, j)] - e).abs() < 1e-12);
            }
        }
    }

    #[test]
    fn a_singular_mass_is_refused_with_its_pivot() {
        let (k, m) = string(300);
        let mut d = m.to_dense();
        for j in 0..300 {
            d[(120, j)] = 0.0;
            d[(j, 120)] = 0.0;
        }
        let m = SymmetricSparse::from_dense(d.as_ref());
        assert_eq!(
            sparse_generalized_eigen(&k, &m, 4, Par::Seq).unwrap_err(),
            EigenError::MassNotPositiveDefinite { pivot: 120 }
        );
    }

    #[test]
    fn static_response_solves_k() {
        let (k, _) = string(50);
        let psi = sparse_unit_response(&k, 49).unwrap();
        // Unit tip load on a fixed–free string of unit stiffness: u(x) = x.
        for (i, p) in psi.iter().enumerate() {
            assert!((p - (i + 1) as f64 / 50.0).abs() < 1e-12);
        }
    }
}
