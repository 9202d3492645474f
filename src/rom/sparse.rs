//! The rows of the modal basis Φ stored by their non-zeros.
//!
//! The modes are computed per decoupled (K, M) block (axial, torsion, bending in y, bending in z),
//! so each mode is exactly zero outside its family's DOFs: the row of Φ for one DOF holds only
//! the modes of that DOF's family. The contact and bit terms of the Jacobian, rank-one updates
//! φ(a) φ(b)ᵀ at one node, and the element-by-element K_t Φ of the tangent refresh touch only
//! those. Nothing is assumed about the pattern: a coefficient is stored when it is not exactly
//! zero.

use nalgebra::DMatrix;

/// Φ in compressed-row (per DOF) form.
#[derive(Debug, Clone)]
pub struct SparseBasis {
    /// Per DOF i: `row_start[i]..row_start[i+1]` indexes `row_modes`, `row_values`.
    row_start: Vec<usize>,
    row_modes: Vec<usize>,
    row_values: Vec<f64>,
}

impl SparseBasis {
    pub fn new(phi: &DMatrix<f64>) -> Self {
        let (rows, cols) = phi.shape();
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
            row_start,
            row_modes,
            row_values,
        }
    }

    /// Stored coefficients.
    pub fn nonzeros(&self) -> usize {
        self.row_values.len()
    }

    /// (modes, values) of the row of Φ for DOF i.
    pub fn dof(&self, i: usize) -> (&[usize], &[f64]) {
        let r = self.row_start[i]..self.row_start[i + 1];
        (&self.row_modes[r.clone()], &self.row_values[r])
    }

    /// out += w φ(a) φ(b)ᵀ, with φ(i) the row of Φ for DOF i (a rank-one update on the modes
    /// that move DOFs a and b only).
    pub fn add_dof_outer(&self, w: f64, a: usize, b: usize, out: &mut DMatrix<f64>) {
        let (ma, va) = self.dof(a);
        let (mb, vb) = self.dof(b);
        let n = out.nrows();
        let data = out.as_mut_slice();
        for (&j, &pb) in mb.iter().zip(vb) {
            let s = w * pb;
            let column = &mut data[j * n..(j + 1) * n];
            for (&i, &pa) in ma.iter().zip(va) {
                column[i] += pa * s;
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
        let mut outer = DMatrix::zeros(3, 3);
        s.add_dof_outer(0.7, 2, 5, &mut outer);
        let dense = phi.row(2).transpose() * phi.row(5) * 0.7;
        assert!((&outer - dense).norm() < 1e-14);
        for i in 0..8 {
            let (modes, values) = s.dof(i);
            let row = DVector::from_fn(3, |j, _| {
                modes
                    .iter()
                    .position(|&m| m == j)
                    .map_or(0.0, |k| values[k])
            });
            assert_eq!(row, phi.row(i).transpose());
        }
    }
}
