//! Φ as dense blocks, one per mode family: the products Φq and Φᵀf of every residual evaluation.
//!
//! The modes are computed per decoupled (K, M) block, so an axial or torsional mode lives on one
//! DOF kind of six and a bending mode on two: Φ is about 70 % zeros. Grouping the modes by family
//! and storing each group densely on the union of its rows keeps the products vectorised (dense
//! columns, no index per coefficient) while skipping the zeros: Φq costs a third of the dense
//! product. Nothing is assumed about the pattern beyond correctness: a group's block holds every
//! row where any of its modes is non-zero, so the products are exact whatever the grouping.

use super::Family;
use super::padded::Padded;
use nalgebra::{DMatrix, DVector};

/// One group of modes: Φ restricted to `rows` × `modes`, stored densely (column-major).
#[derive(Debug, Clone)]
struct Block {
    rows: Vec<usize>,
    modes: Vec<usize>,
    values: DMatrix<f64>,
    /// The block for [`BlockBasis::expand`] and its transpose for [`BlockBasis::project`],
    /// column-major with the leading dimension padded with zeros.
    padded: Padded,
    padded_t: Padded,
}

/// How the products visit the blocks: one at a time, or two that are the same matrix up to the
/// signs of rows and columns (the bending planes x–y and x–z: v ↔ w with θz ↔ −θy, same
/// frequencies), multiplied together through the first one's storage.
#[derive(Debug, Clone)]
enum Group {
    One(usize),
    /// Block `second` = diag(`row_sign`) · block `first` · diag(`mode_sign`), exactly.
    Twins {
        first: usize,
        second: usize,
        row_sign: Vec<f64>,
        mode_sign: Vec<f64>,
    },
}

/// Φ by family blocks.
#[derive(Debug, Clone)]
pub struct BlockBasis {
    blocks: Vec<Block>,
    groups: Vec<Group>,
    dofs: usize,
    /// When every column of Φ is a column of the identity (the unreduced model's nodal
    /// coordinates): the row of each column. The products are then a scatter and a gather
    /// (no blocks are stored).
    selection: Option<Vec<usize>>,
}

/// Work vectors of the block products (one set per user, so that a shared [`BlockBasis`] needs
/// no allocation per product): per block, the gathered modal coordinates and the block's rows.
#[derive(Debug, Clone)]
pub struct BlockWork {
    modal: Vec<Vec<f64>>,
    rows: Vec<Vec<f64>>,
    /// Per block: its rows of a full-DOF × n matrix, and their projection (modes × n).
    gathered: Vec<DMatrix<f64>>,
    projected: Vec<DMatrix<f64>>,
}

impl BlockBasis {
    /// Group the columns of `phi` by the family of each mode (`families[j]` for column j).
    pub fn new(phi: &DMatrix<f64>, families: &[Family]) -> Self {
        assert_eq!(families.len(), phi.ncols());
        if let Some(rows) = selection(phi) {
            return BlockBasis {
                blocks: Vec::new(),
                groups: Vec::new(),
                dofs: phi.nrows(),
                selection: Some(rows),
            };
        }
        let mut blocks: Vec<Block> = Vec::new();
        for family in Family::ALL {
            let modes: Vec<usize> = (0..phi.ncols())
                .filter(|&j| families[j] == family)
                .collect();
            if modes.is_empty() {
                continue;
            }
            let rows: Vec<usize> = (0..phi.nrows())
                .filter(|&i| modes.iter().any(|&j| phi[(i, j)] != 0.0))
                .collect();
            let values = DMatrix::from_fn(rows.len(), modes.len(), |r, c| phi[(rows[r], modes[c])]);
            let t = values.transpose();
            blocks.push(Block {
                padded: Padded::new(values.nrows(), values.ncols(), values.as_slice()),
                padded_t: Padded::new(t.nrows(), t.ncols(), t.as_slice()),
                rows,
                modes,
                values,
            });
        }
        let mut groups = Vec::new();
        let mut paired = vec![false; blocks.len()];
        for first in 0..blocks.len() {
            if paired[first] {
                continue;
            }
            let twin = (first + 1..blocks.len()).find_map(|second| {
                let signs = mirror_signs(&blocks[first].values, &blocks[second].values);
                signs.filter(|_| !paired[second]).map(|s| (second, s))
            });
            groups.push(match twin {
                Some((second, (row_sign, mode_sign))) => {
                    paired[second] = true;
                    Group::Twins {
                        first,
                        second,
                        row_sign,
                        mode_sign,
                    }
                }
                None => Group::One(first),
            });
        }
        BlockBasis {
            blocks,
            groups,
            dofs: phi.nrows(),
            selection: None,
        }
    }

    /// Work vectors for [`Self::expand`] and [`Self::project`].
    pub fn workspace(&self) -> BlockWork {
        BlockWork {
            modal: self
                .blocks
                .iter()
                .map(|b| vec![0.0; b.padded_t.ld])
                .collect(),
            rows: self.blocks.iter().map(|b| vec![0.0; b.padded.ld]).collect(),
            gathered: self
                .blocks
                .iter()
                .map(|b| DMatrix::zeros(b.rows.len(), self.modes()))
                .collect(),
            projected: self
                .blocks
                .iter()
                .map(|b| DMatrix::zeros(b.modes.len(), self.modes()))
                .collect(),
        }
    }

    /// Number of modes n.
    pub fn modes(&self) -> usize {
        match &self.selection {
            Some(rows) => rows.len(),
            None => self.blocks.iter().map(|b| b.modes.len()).sum(),
        }
    }

    /// Stored coefficients (zeros inside a block included).
    pub fn stored(&self) -> usize {
        self.blocks.iter().map(|b| b.values.len()).sum()
    }

    /// Pairs of blocks multiplied through one storage.
    pub fn twins(&self) -> usize {
        let twins = |g: &&Group| matches!(g, Group::Twins { .. });
        self.groups.iter().filter(twins).count()
    }

    /// y = Φ x (x: n modal coordinates, y: full DOF vector).
    pub fn expand(&self, x: &DVector<f64>, y: &mut DVector<f64>, work: &mut BlockWork) {
        debug_assert_eq!(y.len(), self.dofs);
        if let Some(rows) = &self.selection {
            y.as_mut_slice().fill(0.0);
            for (&i, &x) in rows.iter().zip(x.as_slice()) {
                y[i] = x;
            }
            return;
        }
        self.product(Way::Expand, x.as_slice(), y.as_mut_slice(), work);
    }

    /// out = Φᵀ f (f: full DOF vector, out: n modal coordinates).
    pub fn project(&self, f: &DVector<f64>, out: &mut DVector<f64>, work: &mut BlockWork) {
        debug_assert_eq!(f.len(), self.dofs);
        if let Some(rows) = &self.selection {
            for (o, &i) in out.as_mut_slice().iter_mut().zip(rows) {
                *o = f[i];
            }
            return;
        }
        self.product(Way::Project, f.as_slice(), out.as_mut_slice(), work);
    }

    /// y = Φ x or Φᵀ x, block by block: gather x, multiply, scatter-add into y (twins together).
    fn product(&self, way: Way, x: &[f64], y: &mut [f64], work: &mut BlockWork) {
        y.fill(0.0);
        let (ins, outs) = match way {
            Way::Expand => (&mut work.modal, &mut work.rows),
            Way::Project => (&mut work.rows, &mut work.modal),
        };
        for group in &self.groups {
            match group {
                &Group::One(b) => {
                    let (a, from, to) = self.blocks[b].way(way);
                    let xs = gather(x, from, None, &mut ins[b]);
                    a.product(xs, &mut outs[b]);
                    scatter_add(&outs[b], to, None, y);
                }
                Group::Twins {
                    first,
                    second,
                    row_sign,
                    mode_sign,
                } => {
                    let (sign_in, sign_out) = match way {
                        Way::Expand => (mode_sign, row_sign),
                        Way::Project => (row_sign, mode_sign),
                    };
                    let (a, from1, to1) = self.blocks[*first].way(way);
                    let (_, from2, to2) = self.blocks[*second].way(way);
                    let [x1, x2] = ins.get_disjoint_mut([*first, *second]).expect("two");
                    let [y1, y2] = outs.get_disjoint_mut([*first, *second]).expect("two");
                    let x1 = gather(x, from1, None, x1);
                    let x2 = gather(x, from2, Some(sign_in), x2);
                    a.product2([x1, x2], [&mut *y1, &mut *y2]);
                    scatter_add(y1, to1, None, y);
                    scatter_add(y2, to2, Some(sign_out), y);
                }
            }
        }
    }
}

/// The rows of the columns of `phi` if each is a column of the identity, distinct.
fn selection(phi: &DMatrix<f64>) -> Option<Vec<usize>> {
    let mut rows = Vec::with_capacity(phi.ncols());
    let mut used = vec![false; phi.nrows()];
    for column in phi.column_iter() {
        let mut nonzero = column.iter().enumerate().filter(|(_, x)| **x != 0.0);
        match (nonzero.next(), nonzero.next()) {
            (Some((i, &x)), None) if x == 1.0 && !used[i] => {
                used[i] = true;
                rows.push(i);
            }
            _ => return None,
        }
    }
    Some(rows)
}

/// Which way a product goes: Φ x (modes → rows) or Φᵀ f (rows → modes).
#[derive(Debug, Clone, Copy)]
enum Way {
    Expand,
    Project,
}

impl Block {
    /// The padded matrix of the product, the indices gathered from and scattered to.
    fn way(&self, way: Way) -> (&Padded, &[usize], &[usize]) {
        match way {
            Way::Expand => (&self.padded, &self.modes, &self.rows),
            Way::Project => (&self.padded_t, &self.rows, &self.modes),
        }
    }
}

/// x at `from` (times `sign`, ±1) into the work vector `xs`; returns the gathered part. On
/// slices: indexing a DVector goes through nalgebra's generic (row, column) indexing, several
/// times slower here.
fn gather<'w>(x: &[f64], from: &[usize], sign: Option<&[f64]>, xs: &'w mut [f64]) -> &'w [f64] {
    let xs = &mut xs[..from.len()];
    match sign {
        None => xs.iter_mut().zip(from).for_each(|(g, &j)| *g = x[j]),
        Some(s) => (xs.iter_mut().zip(from).zip(s)).for_each(|((g, &j), &s)| *g = s * x[j]),
    }
    xs
}

/// y[to] += ys (times `sign`, ±1).
fn scatter_add(ys: &[f64], to: &[usize], sign: Option<&[f64]>, y: &mut [f64]) {
    match sign {
        None => ys.iter().zip(to).for_each(|(&v, &i)| y[i] += v),
        Some(s) => (ys.iter().zip(to).zip(s)).for_each(|((&v, &i), &s)| y[i] += s * v),
    }
}

/// Signs (per row, per column) with b = diag(row) · a · diag(column) exactly, if there are such.
/// The signs are propagated along the non-zeros of a (a sign per connected row–column set, the
/// first column of each set taken +1); rows and columns of zeros get +1.
fn mirror_signs(a: &DMatrix<f64>, b: &DMatrix<f64>) -> Option<(Vec<f64>, Vec<f64>)> {
    if a.shape() != b.shape() {
        return None;
    }
    let (mut row, mut col) = (vec![0.0; a.nrows()], vec![0.0; a.ncols()]);
    for seed in 0..a.ncols() {
        if col[seed] != 0.0 {
            continue;
        }
        col[seed] = 1.0;
        let mut changed = true;
        while changed {
            changed = false;
            for j in 0..a.ncols() {
                for i in 0..a.nrows() {
                    let (x, y) = (a[(i, j)], b[(i, j)]);
                    if x == 0.0 || y.abs() != x.abs() {
                        continue;
                    }
                    let ratio = if y == x { 1.0 } else { -1.0 };
                    if col[j] != 0.0 && row[i] == 0.0 {
                        row[i] = ratio * col[j];
                        changed = true;
                    } else if row[i] != 0.0 && col[j] == 0.0 {
                        col[j] = ratio * row[i];
                        changed = true;
                    }
                }
            }
        }
    }
    for s in row.iter_mut().chain(&mut col) {
        if *s == 0.0 {
            *s = 1.0;
        }
    }
    let exact =
        (0..a.ncols()).all(|j| (0..a.nrows()).all(|i| b[(i, j)] == row[i] * a[(i, j)] * col[j]));
    exact.then_some((row, col))
}

impl BlockBasis {
    /// out += Φᵀ y (y: full DOF × n, out: n × n), one dense product per block.
    pub fn add_projected_columns(
        &self,
        y: &DMatrix<f64>,
        out: &mut DMatrix<f64>,
        work: &mut BlockWork,
    ) {
        debug_assert_eq!(y.nrows(), self.dofs);
        if let Some(rows) = &self.selection {
            for j in 0..y.ncols() {
                let (src, mut dst) = (y.column(j), out.column_mut(j));
                for (o, &i) in dst.iter_mut().zip(rows) {
                    *o += src[i];
                }
            }
            return;
        }
        for ((b, g), p) in self
            .blocks
            .iter()
            .zip(&mut work.gathered)
            .zip(&mut work.projected)
        {
            for j in 0..y.ncols() {
                let (src, dst) = (y.column(j), g.column_mut(j));
                for (x, &i) in dst.into_iter().zip(&b.rows) {
                    *x = src[i];
                }
            }
            p.gemm_tr(1.0, &b.values, g, 0.0);
            for (k, &i) in b.modes.iter().enumerate() {
                for j in 0..out.ncols() {
                    out[(i, j)] += p[(k, j)];
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn block_products_equal_the_dense_ones_for_any_grouping() {
        // 9 DOFs, 4 modes; supports overlap between groups and one mode has an interior zero.
        let phi = DMatrix::from_fn(9, 4, |i, j| match (i % 3, j) {
            (0, 0) | (0, 1) => 1.0 + i as f64 * 0.3 - j as f64,
            (1, 2) if i != 4 => 0.5 * i as f64 - 1.0,
            (_, 3) if i > 2 => (i as f64).cos(),
            _ => 0.0,
        });
        let families = [
            Family::Axial,
            Family::Axial,
            Family::BendingY,
            Family::Torsional,
        ];
        let blocks = BlockBasis::new(&phi, &families);
        let mut work = blocks.workspace();
        assert!(blocks.stored() < phi.len());
        let x = DVector::from_fn(4, |j, _| (j as f64 + 0.7).sin());
        let f = DVector::from_fn(9, |i, _| (i as f64 * 1.3).cos());
        let (mut y, mut p) = (DVector::zeros(9), DVector::zeros(4));
        blocks.expand(&x, &mut y, &mut work);
        blocks.project(&f, &mut p, &mut work);
        assert!((&y - &phi * &x).norm() < 1e-14, "{y} vs {}", &phi * &x);
        assert!((&p - phi.transpose() * &f).norm() < 1e-14);
        let y = DMatrix::from_fn(9, 4, |i, j| (i as f64 * 0.7 + j as f64).sin());
        let mut out = DMatrix::from_element(4, 4, 1.0);
        blocks.add_projected_columns(&y, &mut out, &mut work);
        let expected = phi.transpose() * &y + DMatrix::from_element(4, 4, 1.0);
        assert!((&out - expected).norm() < 1e-14);
    }

    #[test]
    fn mirrored_blocks_are_multiplied_together_and_exactly() {
        // Modes 0, 1 (axial) on rows 0–4; modes 2, 3 (torsional) on rows 5–9 with the same
        // values up to the signs of row 7 and of mode 3: one twin pair.
        let base = DMatrix::from_fn(5, 2, |i, j| ((i * 3 + j) as f64 * 0.71).sin() + 0.1);
        let (row_sign, mode_sign) = ([1.0, 1.0, -1.0, 1.0, 1.0], [1.0, -1.0]);
        let phi = |perturb: f64| {
            DMatrix::from_fn(10, 4, |i, j| match (i / 5, j / 2) {
                (0, 0) => base[(i, j)],
                (1, 1) => row_sign[i - 5] * base[(i - 5, j - 2)] * mode_sign[j - 2] + perturb,
                _ => 0.0,
            })
        };
        let families = [
            Family::Axial,
            Family::Axial,
            Family::Torsional,
            Family::Torsional,
        ];
        let x = DVector::from_fn(4, |j, _| (j as f64 * 1.3 + 0.4).cos());
        let f = DVector::from_fn(10, |i, _| (i as f64 * 0.9 - 2.0).sin());
        for (perturb, twins) in [(0.0, 1), (1e-15, 0)] {
            let phi = phi(perturb);
            let blocks = BlockBasis::new(&phi, &families);
            assert_eq!(blocks.twins(), twins, "perturbation {perturb}");
            let mut work = blocks.workspace();
            let (mut y, mut p) = (DVector::zeros(10), DVector::zeros(4));
            blocks.expand(&x, &mut y, &mut work);
            blocks.project(&f, &mut p, &mut work);
            assert!((&y - &phi * &x).norm() < 1e-14);
            assert!((&p - phi.transpose() * &f).norm() < 1e-14);
        }
        // Signs spread along the non-zeros; a mismatch anywhere, zeros included, is no twin.
        let a = DMatrix::from_row_slice(2, 2, &[1.0, 2.0, 0.0, 3.0]);
        let b = DMatrix::from_row_slice(2, 2, &[-1.0, -2.0, 0.0, 3.0]);
        let (rows, cols) = mirror_signs(&a, &b).expect("b = diag(-1, 1) a");
        assert_eq!((rows, cols), (vec![-1.0, 1.0], vec![1.0, 1.0]));
        let c = DMatrix::from_row_slice(2, 2, &[-1.0, -2.0, 1e-300, 3.0]);
        assert!(mirror_signs(&a, &c).is_none());
        assert!(mirror_signs(&a, &DMatrix::zeros(2, 3)).is_none());
    }

    #[test]
    fn padded_kernels_cover_every_chunk_length() {
        // Blocks of 1 to 75 rows and 1 to 37 modes: every chunk length (32, 16, 8, 4) and padding.
        for (rows, modes) in [(1, 1), (3, 2), (9, 5), (30, 7), (75, 37), (64, 33)] {
            let phi = DMatrix::from_fn(rows, modes, |i, j| {
                let x = ((i * 31 + j * 17) as f64 * 0.37).sin();
                if x.abs() < 0.2 { 0.0 } else { x }
            });
            let families: Vec<Family> = (0..modes).map(|j| Family::ALL[j % 3]).collect();
            let blocks = BlockBasis::new(&phi, &families);
            let mut work = blocks.workspace();
            let x = DVector::from_fn(modes, |j, _| (j as f64 * 0.9 + 0.2).cos());
            let f = DVector::from_fn(rows, |i, _| (i as f64 * 0.4 - 1.0).sin());
            let (mut y, mut p) = (DVector::from_element(rows, 9.0), DVector::zeros(modes));
            blocks.expand(&x, &mut y, &mut work);
            blocks.project(&f, &mut p, &mut work);
            let (ye, pe) = (&phi * &x, phi.transpose() * &f);
            assert!(
                (&y - &ye).norm() < 1e-13 * (1.0 + ye.norm()),
                "{rows}x{modes}"
            );
            assert!(
                (&p - &pe).norm() < 1e-13 * (1.0 + pe.norm()),
                "{rows}x{modes}"
            );
        }
    }

    /// Columns of the identity (the unreduced model): scatter and gather, equal to the dense
    /// products; a matrix that is not a selection keeps the blocks.
    #[test]
    fn a_selection_of_dofs_is_a_scatter_and_a_gather() {
        let rows = [0usize, 2, 3, 7];
        let phi = DMatrix::from_fn(9, 4, |i, j| if rows[j] == i { 1.0 } else { 0.0 });
        let families = [
            Family::Axial,
            Family::BendingY,
            Family::Torsional,
            Family::Axial,
        ];
        let blocks = BlockBasis::new(&phi, &families);
        assert_eq!(blocks.selection.as_deref(), Some(&rows[..]));
        assert_eq!(blocks.modes(), 4);
        let mut work = blocks.workspace();
        let x = DVector::from_fn(4, |j, _| j as f64 + 0.5);
        let f = DVector::from_fn(9, |i, _| (i as f64).sin());
        let (mut y, mut p) = (DVector::from_element(9, 9.0), DVector::zeros(4));
        blocks.expand(&x, &mut y, &mut work);
        blocks.project(&f, &mut p, &mut work);
        assert_eq!(y, &phi * &x);
        assert_eq!(p, phi.transpose() * &f);
        let scratch = DMatrix::from_fn(9, 4, |i, j| (i * 4 + j) as f64);
        let mut out = DMatrix::from_element(4, 4, 1.0);
        blocks.add_projected_columns(&scratch, &mut out, &mut work);
        assert_eq!(
            out,
            DMatrix::from_element(4, 4, 1.0) + phi.transpose() * &scratch
        );
        let mut scaled = phi.clone();
        scaled[(7, 3)] = 2.0;
        assert!(BlockBasis::new(&scaled, &families).selection.is_none());
    }
}
