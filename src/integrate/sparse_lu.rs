//! Sparse LU of Newton matrices with a fixed non-zero pattern, for the unreduced finite-element
//! model (issue 11): faer's sparse LU (column approximate minimum degree ordering, partial
//! pivoting), analysed once for the pattern and refactorised numerically at each Newton matrix,
//! with its work memory allocated once. The matrix is handed over in the integrator's dense
//! storage; only the entries of the pattern are read (the others must be zero).
//!
//! The reduced models keep the dense [`super::DenseLu`]: their Newton matrices are full.

use super::Singular;
use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::sparse::linalg::lu::{LuRef, NumericLu, SymbolicLu, factorize_symbolic_lu};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMat};
use faer::{Conj, MatMut, Par};
use nalgebra::{DMatrix, DVector};

/// Which entries of an n × n matrix may be non-zero: for each column, its rows (sorted).
#[derive(Debug, Clone, PartialEq)]
pub struct SparsityPattern {
    n: usize,
    columns: Vec<Vec<usize>>,
}

impl SparsityPattern {
    /// The pattern of n × n matrices whose column j may be non-zero in `rows(j)` (any order,
    /// duplicates allowed). The diagonal is always included.
    pub fn new(n: usize, mut rows: impl FnMut(usize) -> Vec<usize>) -> Self {
        let columns = (0..n)
            .map(|j| {
                let mut r = rows(j);
                r.push(j);
                r.retain(|&i| i < n);
                r.sort_unstable();
                r.dedup();
                r
            })
            .collect();
        SparsityPattern { n, columns }
    }

    /// The entries of the pattern.
    pub fn nnz(&self) -> usize {
        self.columns.iter().map(Vec::len).sum()
    }

    pub fn size(&self) -> usize {
        self.n
    }

    /// The (n + 1) × (n + 1) pattern with this one in its leading block and a full last row and
    /// column (an unknown coupled with all others, such as a free top's block position).
    pub fn bordered(&self) -> Self {
        let n = self.n;
        let mut columns: Vec<Vec<usize>> = self
            .columns
            .iter()
            .map(|rows| rows.iter().copied().chain([n]).collect())
            .collect();
        columns.push((0..=n).collect());
        SparsityPattern { n: n + 1, columns }
    }

    /// The rows of each column (sorted).
    pub fn columns(&self) -> impl Iterator<Item = &[usize]> {
        self.columns.iter().map(Vec::as_slice)
    }

    /// Whether (i, j) is in the pattern.
    pub fn contains(&self, i: usize, j: usize) -> bool {
        self.columns[j].binary_search(&i).is_ok()
    }

    fn symbolic(&self) -> SymbolicSparseColMat<usize> {
        let mut col_ptr = Vec::with_capacity(self.n + 1);
        let mut row_idx = Vec::with_capacity(self.nnz());
        col_ptr.push(0);
        for c in &self.columns {
            row_idx.extend_from_slice(c);
            col_ptr.push(row_idx.len());
        }
        SymbolicSparseColMat::new_checked(self.n, self.n, col_ptr, None, row_idx)
    }
}

/// A sparse LU factorisation that is refactorised in place.
pub struct SparseLu {
    pattern: SymbolicSparseColMat<usize>,
    symbolic: SymbolicLu<usize>,
    numeric: NumericLu<usize, f64>,
    values: Vec<f64>,
    memory: MemBuffer,
    factored: bool,
}

impl std::fmt::Debug for SparseLu {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SparseLu")
            .field("n", &self.pattern.ncols())
            .field("nnz", &self.values.len())
            .field("factored", &self.factored)
            .finish()
    }
}

impl SparseLu {
    /// Analyse `pattern` (the ordering is computed here, once).
    pub fn new(pattern: &SparsityPattern) -> Self {
        let pattern = pattern.symbolic();
        let symbolic = factorize_symbolic_lu(pattern.as_ref(), Default::default())
            .expect("the symbolic analysis of a square pattern with its diagonal cannot fail");
        let memory = MemBuffer::new(StackReq::any_of(&[
            symbolic.factorize_numeric_lu_scratch::<f64>(Par::Seq, Default::default()),
            symbolic.solve_in_place_scratch::<f64>(1, Par::Seq),
        ]));
        let nnz = pattern.row_idx().len();
        SparseLu {
            pattern,
            symbolic,
            numeric: NumericLu::new(),
            values: vec![0.0; nnz],
            memory,
            factored: false,
        }
    }

    /// Factorise `a` (n × n; only the pattern's entries are read). `Singular` if the matrix holds
    /// a non-finite value (in the column reported) or faer finds the pattern structurally
    /// singular (column n). A numerically singular matrix is not detected here: the solutions
    /// are then non-finite, which the integrator and the equilibrium solver treat as a failure.
    pub fn factor(&mut self, a: &DMatrix<f64>) -> Result<(), Singular> {
        self.factored = false;
        let n = a.nrows();
        let (col_ptr, row_idx) = (self.pattern.col_ptr(), self.pattern.row_idx());
        for j in 0..n {
            let column = a.column(j);
            for k in col_ptr[j]..col_ptr[j + 1] {
                let x = column[row_idx[k]];
                if !x.is_finite() {
                    return Err(Singular { column: j });
                }
                self.values[k] = x;
            }
        }
        let matrix = SparseColMatRef::new(self.pattern.as_ref(), &self.values);
        self.symbolic
            .factorize_numeric_lu(
                &mut self.numeric,
                matrix,
                Par::Seq,
                MemStack::new(&mut self.memory),
                Default::default(),
            )
            .map_err(|_| Singular { column: n })?;
        self.factored = true;
        Ok(())
    }

    /// b ← A⁻¹ b with the last factorisation.
    pub fn solve_in_place(&mut self, b: &mut DVector<f64>) {
        assert!(self.factored, "solve without a factorisation");
        let n = b.len();
        let rhs = MatMut::from_column_major_slice_mut(b.as_mut_slice(), n, 1);
        LuRef::new_unchecked(&self.symbolic, &self.numeric).solve_in_place_with_conj(
            Conj::No,
            rhs,
            Par::Seq,
            MemStack::new(&mut self.memory),
        );
    }
}

/// The linear solver of the Newton iterations: dense for the reduced models, sparse for the
/// unreduced one.
#[derive(Debug)]
pub enum LinearSolver {
    Dense(super::DenseLu),
    Sparse(Box<SparseLu>),
}

impl LinearSolver {
    pub fn factor(&mut self, a: &DMatrix<f64>) -> Result<(), Singular> {
        match self {
            LinearSolver::Dense(lu) => lu.factor(a),
            LinearSolver::Sparse(lu) => lu.factor(a),
        }
    }

    pub fn solve_in_place(&mut self, b: &mut DVector<f64>) {
        match self {
            LinearSolver::Dense(lu) => lu.solve_in_place(b),
            LinearSolver::Sparse(lu) => lu.solve_in_place(b),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A banded, non-symmetric, diagonally weak matrix that needs pivoting in places.
    fn banded(n: usize, half: usize) -> (SparsityPattern, DMatrix<f64>) {
        let pattern = SparsityPattern::new(n, |j| {
            (j.saturating_sub(half)..=(j + half).min(n - 1)).collect()
        });
        let a = DMatrix::from_fn(n, n, |i, j| {
            if pattern.contains(i, j) {
                let x = ((3 * i + 7 * j) % 11) as f64 - 5.0;
                if i == j { 0.1 * x } else { x }
            } else {
                0.0
            }
        });
        (pattern, a)
    }

    #[test]
    fn solves_like_the_dense_lu() {
        let (pattern, a) = banded(60, 11);
        assert_eq!(pattern.nnz(), 60 * 23 - 2 * (11 * 12 / 2));
        let b = DVector::from_fn(60, |i, _| (i as f64).sin());
        let mut sparse = SparseLu::new(&pattern);
        sparse.factor(&a).unwrap();
        let mut x = b.clone();
        sparse.solve_in_place(&mut x);
        assert!((&a * &x - &b).norm() < 1e-10 * b.norm());
        // Refactorised in place with other values: still right.
        let a2 = a.map(|x| 2.0 * x + 0.0);
        sparse.factor(&a2).unwrap();
        let mut x2 = b.clone();
        sparse.solve_in_place(&mut x2);
        assert!((&x2 * 2.0 - &x).norm() < 1e-10 * x.norm());
    }

    #[test]
    fn a_singular_or_non_finite_matrix_is_refused() {
        let (pattern, mut a) = banded(10, 2);
        let mut lu = SparseLu::new(&pattern);
        a[(3, 4)] = f64::NAN;
        assert!(lu.factor(&a).is_err());
        // A zero matrix: the solution is not finite.
        let zero = DMatrix::zeros(10, 10);
        let mut x = DVector::from_element(10, 1.0);
        if lu.factor(&zero).is_ok() {
            lu.solve_in_place(&mut x);
            assert!(x.iter().any(|x| !x.is_finite()));
        }
    }
}
