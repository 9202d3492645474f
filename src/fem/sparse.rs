//! Sparse storage of the global mass and stiffness, for meshes whose dense 6(N+1) × 6(N+1)
//! matrices would not fit (issue 13 item 6: 2000 elements are 12 006 DOF, 1.15 GB per dense
//! matrix). A node couples with its two neighbours only, so a column holds at most 18 entries.
//!
//! The entries are summed element by element in the same order as [`super::assemble`], so each
//! stored value is bitwise the dense one; exact zeros are not stored (the family blocks of the
//! modal solve are read off the pattern).

use super::{
    BeamElement, DOF_PER_NODE, Dof, ELEMENT_DOF, ElementLayout, ElementMatrix, ElementStrains,
    ElementVector,
};
use crate::model::Drillstring;

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
    let layout = ElementLayout::of(string, elements);
    let bit_spin = Dof::ThetaX.at(elements);
    let of_kinds = |f: fn(&BeamElement) -> ElementMatrix| -> Vec<ElementMatrix> {
        layout.kinds().iter().map(|k| f(&k.element)).collect()
    };
    SparseGlobal {
        mass: assemble_band(
            &layout,
            &of_kinds(BeamElement::mass),
            Some((bit_spin, string.bit_inertia)),
        ),
        stiffness: assemble_band(&layout, &of_kinds(BeamElement::stiffness), None),
        elements,
    }
}

/// The geometric stiffness K_σ = ∂K_t/∂N of the string under a uniform axial force N (tension
/// positive), on all 6(N+1) DOFs, 1/m (N/m per N of axial force): the tangent stiffness of the
/// string in uniform tension or compression N is K + N K_σ to first order. On the bending DOFs it
/// is the classical beam-column matrix (∫ N v′ δv′ dx of the Green–Lagrange axial strain;
/// Przemieniecki, *Theory of Matrix Structural Analysis*, 1968, §15.3), which the strain energy of
/// [`StrainEnergy`] holds; it is read off that energy's exact (automatic-differentiation) tangent
/// by a central difference in a uniform axial strain of ±1e-6, which is exact for the quadratic
/// dependence of the tangent on the axial strain up to round-off.
pub fn geometric_stiffness(string: &Drillstring, elements: usize) -> SymmetricSparse {
    let layout = ElementLayout::of(string, elements);
    const STRAIN: f64 = 1e-6;
    let k_sigma: Vec<ElementMatrix> = layout
        .kinds()
        .iter()
        .map(|kind| {
            let h = kind.element.length;
            let strains = ElementStrains::new(&kind.element);
            // Node 2's axial DOF (u2) carries the element's axial force N.
            let stretched = |sign: f64| {
                let mut d = ElementVector::zeros();
                d[DOF_PER_NODE + Dof::U as usize] = sign * STRAIN * h;
                let (f, k) = strains.internal_force_and_tangent(&kind.strain_law, &d);
                (f[DOF_PER_NODE + Dof::U as usize], k)
            };
            let ((tension, k_plus), (compression, k_minus)) = (stretched(1.0), stretched(-1.0));
            (k_plus - k_minus) / (tension - compression)
        })
        .collect();
    assemble_band(&layout, &k_sigma, None)
}

/// Sum the element matrices of `layout` (`kinds[k]` for the elements of kind k) into a banded
/// symmetric matrix (a node couples with its neighbours only), plus an optional value on one
/// diagonal entry.
fn assemble_band(
    layout: &ElementLayout,
    kinds: &[ElementMatrix],
    diagonal: Option<(usize, f64)>,
) -> SymmetricSparse {
    let elements = layout.elements();
    let n = DOF_PER_NODE * (elements + 1);
    // Column j may be non-zero on the DOFs of nodes node(j) − 1 ..= node(j) + 1: a band of
    // 3 × 6 rows starting at `first(j)`.
    const BAND: usize = 3 * DOF_PER_NODE;
    let first = |j: usize| DOF_PER_NODE * (j / DOF_PER_NODE).saturating_sub(1);
    let mut band = vec![[0.0; BAND]; n];
    for e in 0..elements {
        let element_matrix = &kinds[layout.kind(e)];
        let base = DOF_PER_NODE * e;
        for i in 0..ELEMENT_DOF {
            for j in 0..ELEMENT_DOF {
                let (r, c) = (base + i, base + j);
                band[c][r - first(c)] += element_matrix[(i, j)];
            }
        }
    }
    if let Some((d, value)) = diagonal {
        band[d][d - first(d)] += value;
    }
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

    /// Euler's buckling load of a pinned–pinned column, π²EI/L² (with Engesser's shear
    /// correction 1/(1 + P_E/(κGA)), negligible here), from K x = P K_σ x in one bending plane.
    #[test]
    fn the_geometric_stiffness_buckles_a_pinned_column_at_the_euler_load() {
        let p = crate::problem::Problem::load(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/problems/seed_mc2014.toml"
        ))
        .unwrap();
        let elements = 24;
        let k = assemble_sparse(&p.model, elements).stiffness.to_dense();
        let g = geometric_stiffness(&p.model, elements).to_dense();
        // The x–y plane: v and θz of every node, v fixed at both ends.
        let rows: Vec<usize> = (0..=elements)
            .flat_map(|n| [Dof::V.at(n), Dof::ThetaZ.at(n)])
            .filter(|&r| r != Dof::V.at(0) && r != Dof::V.at(elements))
            .collect();
        let pick = |a: &faer::Mat<f64>| {
            faer::Mat::from_fn(rows.len(), rows.len(), |i, j| a[(rows[i], rows[j])])
        };
        let (k, g) = (pick(&k), pick(&g));
        // Inverse iteration on K⁻¹ K_σ: its largest eigenvalue is 1 / P_cr.
        use faer::linalg::solvers::Solve;
        let llt = k.llt(faer::Side::Lower).unwrap();
        let mut x = faer::Mat::<f64>::from_fn(rows.len(), 1, |i, _| 1.0 + (i as f64).sin() * 0.1);
        let mut mu = 0.0;
        for _ in 0..200 {
            let y = llt.solve(&g * &x);
            mu = (x.transpose() * &g * &y)[(0, 0)] / (x.transpose() * &g * &x)[(0, 0)];
            x = &y * (1.0 / y.norm_l2());
        }
        let section = crate::model::Section::of(&p.model);
        let euler = std::f64::consts::PI.powi(2) * section.ei / p.model.length.powi(2);
        let engesser = euler / (1.0 + euler / section.shear_rigidity);
        assert!(
            (1.0 / mu / engesser - 1.0).abs() < 1e-4,
            "P_cr {} N, closed form {engesser} N",
            1.0 / mu
        );
    }
}
