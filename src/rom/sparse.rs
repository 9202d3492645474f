//! The modal basis Φ stored by its non-zeros.
//!
//! The modes are computed per decoupled (K, M) block (axial, torsion, bending in y, bending in z),
//! so each mode is exactly zero outside its family's DOFs: an axial or torsional mode lives on one
//! DOF of six, a bending mode on two. Φ is about 70 % zeros; the tangent refresh (Φᵀ K_t Φ) and the
//! contact and bit terms of the Jacobian skip them here. (Φq and Φᵀf at every residual stay dense:
//! the vectorised dense products measured faster than a gather over the non-zeros.) Nothing is
//! assumed about the pattern: a coefficient is stored when it is not exactly zero.

use nalgebra::DMatrix;

/// Φ in compressed-column (per mode) and compressed-row (per DOF) form.
#[derive(Debug, Clone)]
pub struct SparseBasis {
    /// Per mode j: `col_start[j]..col_start[j+1]` indexes `col_rows`, `col_values`.
    col_start: Vec<usize>,
    col_rows: Vec<usize>,
    col_values: Vec<f64>,
    /// Per DOF i: `row_start[i]..row_start[i+1]` indexes `row_modes`, `row_values`.
    row_start: Vec<usize>,
    row_modes: Vec<usize>,
    row_values: Vec<f64>,
}

impl SparseBasis {
    pub fn new(phi: &DMatrix<f64>) -> Self {
        let (rows, cols) = phi.shape();
        let mut col_start = vec![0];
        let (mut col_rows, mut col_values) = (Vec::new(), Vec::new());
        for j in 0..cols {
            for i in 0..rows {
                if phi[(i, j)] != 0.0 {
                    col_rows.push(i);
                    col_values.push(phi[(i, j)]);
                }
            }
            col_start.push(col_rows.len());
        }
        let mut row_start = vec![0];
        let (mut row_modes, mut row_values) = (Vec::new(), Vec::new());
        for i in 0..rows {
            for j in 0..cols {
                if phi[(i, j)] != 0.0 {
                    row_modes.push(j);
                    row_values.push(phi[(i, j)]);
                }
            }
            row_start.push(row_modes.len());
        }
        SparseBasis {
            col_start,
            col_rows,
            col_values,
            row_start,
            row_modes,
            row_values,
        }
    }

    /// Number of modes n.
    pub fn modes(&self) -> usize {
        self.col_start.len() - 1
    }

    /// Stored coefficients.
    pub fn nonzeros(&self) -> usize {
        self.col_values.len()
    }

    /// (rows, values) of mode j.
    pub fn mode(&self, j: usize) -> (&[usize], &[f64]) {
        let r = self.col_start[j]..self.col_start[j + 1];
        (&self.col_rows[r.clone()], &self.col_values[r])
    }

    /// (modes, values) of the row of Φ for DOF i.
    pub fn dof(&self, i: usize) -> (&[usize], &[f64]) {
        let r = self.row_start[i]..self.row_start[i + 1];
        (&self.row_modes[r.clone()], &self.row_values[r])
    }

    /// Φ_iᵀ y for the column y of a full-DOF matrix.
    pub fn dot_mode(&self, i: usize, y: &[f64]) -> f64 {
        let (rows, values) = self.mode(i);
        rows.iter().zip(values).map(|(&r, &p)| p * y[r]).sum()
    }

    /// out += w φ(a) φ(b)ᵀ, with φ(i) the row of Φ for DOF i (a rank-one update on the modes
    /// that move DOFs a and b only).
    pub fn add_dof_outer(&self, w: f64, a: usize, b: usize, out: &mut DMatrix<f64>) {
        let (ma, va) = self.dof(a);
        let (mb, vb) = self.dof(b);
        for (&j, &pb) in mb.iter().zip(vb) {
            let s = w * pb;
            for (&i, &pa) in ma.iter().zip(va) {
                out[(i, j)] += pa * s;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::DVector;

    fn pattern() -> DMatrix<f64> {
        // 8 DOFs, 3 modes with disjoint-ish supports and exact zeros.
        DMatrix::from_fn(8, 3, |i, j| match (i + j) % 3 {
            0 => 0.0,
            _ => (i as f64 + 1.0) * (j as f64 - 1.3),
        })
    }

    #[test]
    fn sparse_products_equal_the_dense_ones() {
        let phi = pattern();
        let s = SparseBasis::new(&phi);
        assert!(s.nonzeros() < 24);
        let f = DVector::from_fn(8, |i, _| (i as f64).sin());
        let mut outer = DMatrix::zeros(3, 3);
        s.add_dof_outer(0.7, 2, 5, &mut outer);
        let dense = phi.row(2).transpose() * phi.row(5) * 0.7;
        assert!((&outer - dense).norm() < 1e-14);
        for i in 0..3 {
            let y: Vec<f64> = f.iter().copied().collect();
            assert!((s.dot_mode(i, &y) - phi.column(i).dot(&f)).abs() < 1e-14);
        }
    }
}
