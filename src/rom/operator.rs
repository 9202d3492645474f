//! A linear operator of the reduced equations (n × n, n the number of generalised coordinates),
//! stored as its structure allows: the identity and a diagonal for mass-normalised modal
//! coordinates (Φᵀ M Φ = I, Φᵀ K Φ = Λ), dense for the modal damping, sparse for the unreduced
//! finite-element model in nodal coordinates (banded: each element couples two nodes).

use faer::sparse::{SparseColMat, Triplet};
use nalgebra::{DMatrix, DVector};

#[derive(Debug, Clone)]
pub enum Operator {
    Identity,
    Diagonal(DVector<f64>),
    Dense(DMatrix<f64>),
    Sparse(SparseColMat<usize, f64>),
}

impl Operator {
    /// The non-zeros of a dense symmetric or general matrix as a sparse operator (exact zeros
    /// dropped).
    pub fn sparse_from(a: &DMatrix<f64>) -> Operator {
        let mut triplets = Vec::new();
        for j in 0..a.ncols() {
            for i in 0..a.nrows() {
                if a[(i, j)] != 0.0 {
                    triplets.push(Triplet::new(i, j, a[(i, j)]));
                }
            }
        }
        Operator::Sparse(
            SparseColMat::try_new_from_triplets(a.nrows(), a.ncols(), &triplets)
                .expect("triplets within the matrix's shape"),
        )
    }

    /// out += α A x.
    pub fn mul_add(&self, alpha: f64, x: &DVector<f64>, out: &mut DVector<f64>) {
        match self {
            Operator::Identity if alpha == 1.0 => *out += x,
            Operator::Identity => out.axpy(alpha, x, 1.0),
            Operator::Diagonal(d) => {
                for ((o, d), x) in out.iter_mut().zip(d.iter()).zip(x.iter()) {
                    *o += alpha * d * x;
                }
            }
            Operator::Dense(a) => out.gemv(alpha, a, x, 1.0),
            Operator::Sparse(a) => {
                let (col_ptr, row_idx, values) =
                    (a.symbolic().col_ptr(), a.symbolic().row_idx(), a.val());
                let (x, out) = (x.as_slice(), out.as_mut_slice());
                for (j, &xj) in x.iter().enumerate() {
                    let s = alpha * xj;
                    for k in col_ptr[j]..col_ptr[j + 1] {
                        out[row_idx[k]] += values[k] * s;
                    }
                }
            }
        }
    }

    /// xᵀ A x.
    pub fn quadratic(&self, x: &DVector<f64>) -> f64 {
        match self {
            Operator::Identity => x.norm_squared(),
            Operator::Diagonal(d) => x.iter().zip(d.iter()).map(|(x, d)| d * x * x).sum(),
            // Column by column (no temporary vector).
            Operator::Dense(a) => x
                .iter()
                .enumerate()
                .map(|(j, xj)| xj * a.column(j).dot(x))
                .sum(),
            Operator::Sparse(a) => crate::integrate::quadratic_form(a, x.as_slice()),
        }
    }

    /// out += α A (out: n × n dense).
    pub fn add_to(&self, alpha: f64, out: &mut DMatrix<f64>) {
        match self {
            Operator::Identity => {
                for i in 0..out.nrows() {
                    out[(i, i)] += alpha;
                }
            }
            Operator::Diagonal(d) => {
                for (i, d) in d.iter().enumerate() {
                    out[(i, i)] += alpha * d;
                }
            }
            Operator::Dense(a) => *out += a * alpha,
            Operator::Sparse(a) => {
                for t in a.triplet_iter() {
                    out[(t.row, t.col)] += alpha * t.val;
                }
            }
        }
    }

    /// The operator as an n × n dense matrix.
    pub fn to_dense(&self, n: usize) -> DMatrix<f64> {
        let mut out = DMatrix::zeros(n, n);
        self.add_to(1.0, &mut out);
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_storage_gives_the_same_products() {
        let dense = DMatrix::from_fn(5, 5, |i, j| {
            if i.abs_diff(j) <= 1 {
                (1 + i + 2 * j) as f64
            } else {
                0.0
            }
        });
        let x = DVector::from_fn(5, |i, _| (i as f64) - 1.5);
        let ops = [
            Operator::Dense(dense.clone()),
            Operator::sparse_from(&dense),
        ];
        for op in &ops {
            let mut y = DVector::from_element(5, 1.0);
            op.mul_add(2.0, &x, &mut y);
            let expected = DVector::from_element(5, 1.0) + &dense * &x * 2.0;
            assert!((y - expected).norm() < 1e-12);
            assert!((op.quadratic(&x) - x.dot(&(&dense * &x))).abs() < 1e-12);
            assert_eq!(op.to_dense(5), dense);
        }
        let d = DVector::from_fn(5, |i, _| i as f64 + 1.0);
        let diag = Operator::Diagonal(d.clone());
        assert_eq!(diag.to_dense(5), DMatrix::from_diagonal(&d));
        assert!((diag.quadratic(&x) - x.dot(&d.component_mul(&x))).abs() < 1e-12);
        assert_eq!(Operator::Identity.to_dense(3), DMatrix::identity(3, 3));
        assert_eq!(Operator::Identity.quadratic(&x), x.norm_squared());
    }
}
