//! In-place LU factorisation with partial pivoting for the small dense Newton systems, so that the
//! time-step loop allocates nothing (nalgebra's `lu()` takes ownership of a copy).

use nalgebra::{DMatrix, DVector};

/// LU factors stored in place of the matrix, with the row permutation.
#[derive(Debug, Clone)]
pub struct DenseLu {
    lu: DMatrix<f64>,
    pivots: Vec<usize>,
}

/// The matrix is singular to working precision.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
#[error("singular Newton matrix (zero pivot in column {column})")]
pub struct Singular {
    pub column: usize,
}

impl DenseLu {
    pub fn new(n: usize) -> Self {
        DenseLu {
            lu: DMatrix::zeros(n, n),
            pivots: vec![0; n],
        }
    }

    /// Factorise a copy of `a` (n × n) into the stored buffers.
    pub fn factor(&mut self, a: &DMatrix<f64>) -> Result<(), Singular> {
        self.lu.copy_from(a);
        let n = self.lu.nrows();
        let lu = &mut self.lu;
        for k in 0..n {
            let (mut p, mut best) = (k, lu[(k, k)].abs());
            for i in (k + 1)..n {
                if lu[(i, k)].abs() > best {
                    best = lu[(i, k)].abs();
                    p = i;
                }
            }
            if best == 0.0 || !best.is_finite() {
                return Err(Singular { column: k });
            }
            self.pivots[k] = p;
            if p != k {
                lu.swap_rows(k, p);
            }
            let pivot = lu[(k, k)];
            // Column-major storage: column k below the diagonal becomes the multipliers, then
            // each later column takes an axpy with them (contiguous slices: vectorised).
            let data = lu.as_mut_slice();
            let (left, right) = data.split_at_mut((k + 1) * n);
            let multipliers = &mut left[k * n + k + 1..];
            for m in multipliers.iter_mut() {
                *m /= pivot;
            }
            for column in right.chunks_exact_mut(n) {
                let ukj = column[k];
                if ukj != 0.0 {
                    for (x, &m) in column[k + 1..].iter_mut().zip(multipliers.iter()) {
                        *x -= m * ukj;
                    }
                }
            }
        }
        Ok(())
    }

    /// Solve A x = b in place (b becomes x).
    pub fn solve_in_place(&self, b: &mut DVector<f64>) {
        let n = self.lu.nrows();
        for k in 0..n {
            b.swap_rows(k, self.pivots[k]);
        }
        for j in 0..n {
            let bj = b[j];
            for i in (j + 1)..n {
                b[i] -= self.lu[(i, j)] * bj;
            }
        }
        for j in (0..n).rev() {
            b[j] /= self.lu[(j, j)];
            let bj = b[j];
            for i in 0..j {
                b[i] -= self.lu[(i, j)] * bj;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn solves_a_nonsymmetric_system_needing_pivoting() {
        let a = DMatrix::from_row_slice(3, 3, &[0.0, 2.0, 1.0, 1.0, 1.0, 0.0, 3.0, 0.0, 1.0]);
        let x = DVector::from_vec(vec![1.0, -2.0, 0.5]);
        let mut b = &a * &x;
        let mut lu = DenseLu::new(3);
        lu.factor(&a).unwrap();
        lu.solve_in_place(&mut b);
        assert!((b - x).norm() < 1e-14);
        assert_eq!(
            lu.factor(&DMatrix::zeros(3, 3)),
            Err(Singular { column: 0 })
        );
    }
}
