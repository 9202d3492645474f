//! Sparse storage of the global mass and stiffness, for meshes whose dense 6(N+1) × 6(N+1)
//! matrices would not fit (issue 13 item 6: 2000 elements are 12 006 DOF, 1.15 GB per dense
//! matrix). A node couples with its two neighbours only, so a column holds at most 18 entries.
//!
//! The entries are summed element by element in the same order as [`super::assemble`], so each
//! stored value is bitwise the dense one; exact zeros are not stored (the family blocks of the
//! modal solve are read off the pattern).

use super::{BeamElement, DOF_PER_NODE, Dof, ELEMENT_DOF};
use crate::model::{Drillstring, Section};

/// A symmetric sparse matrix in compressed-column form, both triangles stored, rows sorted in
/// each column.
#[derive(Debug, Clone, PartialEq)]
pub struct SymmetricSparse {
    n: usize,
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    values: Vec<f64>,
}

impl SymmetricSparse {
    /// The n × n matrix whose column j holds the (row, value) pairs `column(j)` (rows sorted and
    /// distinct; the pattern must be symmetric).
    pub fn from_column_fn(n: usize, column: impl FnMut(usize) -> Vec<(usize, f64)>) -> Self {
        Self::from_columns(n, (0..n).map(column))
    }

    /// From columns of (row, value), rows sorted and distinct, exact zeros already dropped.
    fn from_columns(n: usize, columns: impl IntoIterator<Item = Vec<(usize, f64)>>) -> Self {
        let mut col_ptr = vec![0];
        let (mut row_idx, mut values) = (Vec::new(), Vec::new());
        for col in columns {
            for (i, v) in col {
                row_idx.push(i);
                values.push(v);
            }
            col_ptr.push(row_idx.len());
        }
        debug_assert_eq!(col_ptr.len(), n + 1);
        SymmetricSparse {
            n,
            col_ptr,
            row_idx,
            values,
        }
    }

    /// Order n of the matrix.
    pub fn size(&self) -> usize {
        self.n
    }

    /// Stored entries (both triangles).
    pub fn nonzeros(&self) -> usize {
        self.values.len()
    }

    /// Column pointers (n + 1), row indices and values, compressed-column form.
    pub fn parts(&self) -> (&[usize], &[usize], &[f64]) {
        (&self.col_ptr, &self.row_idx, &self.values)
    }

    /// (row, value) of the stored entries of column j.
    pub fn column(&self, j: usize) -> impl Iterator<Item = (usize, f64)> + '_ {
        let r = self.col_ptr[j]..self.col_ptr[j + 1];
        self.row_idx[r.clone()]
            .iter()
            .copied()
            .zip(self.values[r].iter().copied())
    }

    /// Entry (i, j), zero when not stored.
    pub fn get(&self, i: usize, j: usize) -> f64 {
        let r = self.col_ptr[j]..self.col_ptr[j + 1];
        match self.row_idx[r.clone()].binary_search(&i) {
            Ok(k) => self.values[r.start + k],
            Err(_) => 0.0,
        }
    }

    /// y = A x (x, y of length n).
    pub fn mul_vec(&self, x: &[f64], y: &mut [f64]) {
        // A is symmetric, so row i of A x is column i of A dotted with x.
        for (i, yi) in y.iter_mut().enumerate().take(self.n) {
            *yi = self.column(i).map(|(r, v)| v * x[r]).sum();
        }
    }

    /// The principal submatrix on `rows` (ascending indices): entry (a, b) is A[rows[a], rows[b]].
    pub fn submatrix(&self, rows: &[usize]) -> SymmetricSparse {
        let mut local = vec![usize::MAX; self.n];
        for (a, &r) in rows.iter().enumerate() {
            local[r] = a;
        }
        SymmetricSparse::from_columns(
            rows.len(),
            rows.iter().map(|&j| {
                self.column(j)
                    .filter(|&(i, _)| local[i] != usize::MAX)
                    .map(|(i, v)| (local[i], v))
                    .collect()
            }),
        )
    }

    /// The dense copy (for small blocks).
    pub fn to_dense(&self) -> faer::Mat<f64> {
        let mut a = faer::Mat::zeros(self.n, self.n);
        for j in 0..self.n {
            for (i, v) in self.column(j) {
                a[(i, j)] = v;
            }
        }
        a
    }

    /// The sparse matrix of `dense`'s non-zero entries (dense must be symmetric).
    pub fn from_dense(dense: faer::MatRef<'_, f64>) -> Self {
        let n = dense.nrows();
        SymmetricSparse::from_columns(
            n,
            (0..n).map(|j| {
                (0..n)
                    .filter(|&i| dense[(i, j)] != 0.0)
                    .map(|i| (i, dense[(i, j)]))
                    .collect()
            }),
        )
    }
}

/// The global mass M and stiffness K of the unconstrained mesh in sparse form: what the modal
/// solve of a long mesh needs (the damping mass and gravity stay with [`super::GlobalMatrices`]).
#[derive(Debug, Clone)]
pub struct SparseGlobal {
    /// Consistent mass M, Eq. (7), with the bit's polar inertia on θx of the bit node; kg, kg·m².
    pub mass: SymmetricSparse,
    /// Linear stiffness K, Eq. (9); N/m, N·m/rad.
    pub stiffness: SymmetricSparse,
    /// Number of elements N.
    pub elements: usize,
}

/// Assemble M and K for `elements` equal elements along the string, in sparse form: the same
/// values as [`super::assemble`] (bitwise), in O(N) memory.
pub fn assemble_sparse(string: &Drillstring, elements: usize) -> SparseGlobal {
    assert!(elements > 0, "a mesh needs at least one element");
    let element = BeamElement::new(string.length / elements as f64, Section::of(string));
    let n = DOF_PER_NODE * (elements + 1);
    let (me, ke) = (element.mass(), element.stiffness());
    // Column j may be non-zero on the DOFs of nodes node(j) − 1 ..= node(j) + 1: a band of
    // 3 × 6 rows starting at `first(j)`.
    const BAND: usize = 3 * DOF_PER_NODE;
    let first = |j: usize| DOF_PER_NODE * (j / DOF_PER_NODE).saturating_sub(1);
    let mut mass = vec![[0.0; BAND]; n];
    let mut stiffness = vec![[0.0; BAND]; n];
    for e in 0..elements {
        let base = DOF_PER_NODE * e;
        for i in 0..ELEMENT_DOF {
            for j in 0..ELEMENT_DOF {
                let (r, c) = (base + i, base + j);
                mass[c][r - first(c)] += me[(i, j)];
                stiffness[c][r - first(c)] += ke[(i, j)];
            }
        }
    }
    let bit_spin = Dof::ThetaX.at(elements);
    mass[bit_spin][bit_spin - first(bit_spin)] += string.bit_inertia;
    let compress = |band: Vec<[f64; BAND]>| {
        SymmetricSparse::from_columns(
            n,
            band.into_iter().enumerate().map(|(c, col)| {
                col.iter()
                    .enumerate()
                    .map(|(k, &v)| (first(c) + k, v))
                    .filter(|&(r, v)| r < n && v != 0.0)
                    .collect()
            }),
        )
    };
    SparseGlobal {
        mass: compress(mass),
        stiffness: compress(stiffness),
        elements,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sparse_assembly_is_bitwise_the_dense_one() {
        let p = crate::problem::Problem::load(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/problems/seed_mc2014.toml"
        ))
        .unwrap();
        let dense = super::super::assemble(&p.model, 7);
        let sparse = assemble_sparse(&p.model, 7);
        for (d, s) in [
            (&dense.mass, &sparse.mass),
            (&dense.stiffness, &sparse.stiffness),
        ] {
            assert_eq!(s.to_dense(), *d);
            assert_eq!(*s, SymmetricSparse::from_dense(d.as_ref()));
            // At most the 18 DOFs of three nodes per column.
            assert!((0..s.size()).all(|j| s.column(j).count() <= 18));
            let x: Vec<f64> = (0..s.size()).map(|i| (i as f64 * 0.37).sin()).collect();
            let mut y = vec![0.0; s.size()];
            s.mul_vec(&x, &mut y);
            let yd = d * faer::ColRef::from_slice(&x);
            for i in 0..s.size() {
                assert!((y[i] - yd[i]).abs() <= 1e-12 * yd.norm_max());
            }
        }
        let rows = [1, 4, 7, 30];
        let sub = sparse.stiffness.submatrix(&rows);
        for (a, &i) in rows.iter().enumerate() {
            for (b, &j) in rows.iter().enumerate() {
                assert_eq!(sub.get(a, b), dense.stiffness[(i, j)]);
            }
        }
    }
}
