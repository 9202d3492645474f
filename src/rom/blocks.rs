//! Φ as dense blocks, one per mode family: the products Φq and Φᵀf of every residual evaluation.
//!
//! The modes are computed per decoupled (K, M) block, so an axial or torsional mode lives on one
//! DOF kind of six and a bending mode on two: Φ is about 70 % zeros. Grouping the modes by family
//! and storing each group densely on the union of its rows keeps the products vectorised (dense
//! columns, no index per coefficient) while skipping the zeros: Φq costs a third of the dense
//! product. Nothing is assumed about the pattern beyond correctness: a group's block holds every
//! row where any of its modes is non-zero, so the products are exact whatever the grouping.

use super::Family;
use nalgebra::{DMatrix, DVector};

/// One group of modes: Φ restricted to `rows` × `modes`, stored densely (column-major).
#[derive(Debug, Clone)]
struct Block {
    rows: Vec<usize>,
    modes: Vec<usize>,
    values: DMatrix<f64>,
    /// The block for [`Block::expand`] and its transpose for [`Block::project`], column-major
    /// with the leading dimension padded with zeros to a multiple of [`PAD`].
    padded: Padded,
    padded_t: Padded,
}

/// Row padding of the product kernels: their row chunks are 32, 16, 8 or 4 long.
const PAD: usize = 4;

/// A column-major matrix whose rows are padded with zeros to a multiple of [`PAD`].
#[derive(Debug, Clone)]
struct Padded {
    values: Vec<f64>,
    ld: usize,
    cols: usize,
}

impl Padded {
    fn new(a: &DMatrix<f64>) -> Self {
        let ld = a.nrows().div_ceil(PAD) * PAD;
        let mut values = vec![0.0; ld * a.ncols()];
        for (j, column) in a.column_iter().enumerate() {
            values[j * ld..j * ld + a.nrows()].copy_from_slice(column.as_slice());
        }
        Padded {
            values,
            ld,
            cols: a.ncols(),
        }
    }

    /// y = A x (y: the padded rows). Rows in chunks held in registers over all columns, so each
    /// coefficient is loaded once and y stored once (nalgebra's gemv does one axpy per column).
    fn product(&self, x: &[f64], y: &mut [f64]) {
        debug_assert!(x.len() == self.cols && y.len() == self.ld);
        let mut start = 0;
        while start < self.ld {
            start += match self.ld - start {
                32.. => self.chunk::<32>(start, x, y),
                16.. => self.chunk::<16>(start, x, y),
                8.. => self.chunk::<8>(start, x, y),
                _ => self.chunk::<4>(start, x, y),
            };
        }
    }

    /// Rows start..start + R of A x; returns R.
    #[inline(always)]
    fn chunk<const R: usize>(&self, start: usize, x: &[f64], y: &mut [f64]) -> usize {
        let mut acc = [0.0; R];
        for (column, &xj) in self.values.chunks_exact(self.ld).zip(x) {
            let column: &[f64; R] = column[start..start + R].try_into().expect("R rows");
            for (a, &c) in acc.iter_mut().zip(column) {
                *a = c.mul_add(xj, *a);
            }
        }
        y[start..start + R].copy_from_slice(&acc);
        R
    }
}

/// Φ by family blocks.
#[derive(Debug, Clone)]
pub struct BlockBasis {
    blocks: Vec<Block>,
    dofs: usize,
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
        let mut blocks = Vec::new();
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
            blocks.push(Block {
                rows,
                modes,
                padded: Padded::new(&values),
                padded_t: Padded::new(&values.transpose()),
                values,
            });
        }
        BlockBasis {
            blocks,
            dofs: phi.nrows(),
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
        self.blocks.iter().map(|b| b.modes.len()).sum()
    }

    /// Stored coefficients (zeros inside a block included).
    pub fn stored(&self) -> usize {
        self.blocks.iter().map(|b| b.values.len()).sum()
    }

    /// y = Φ x (x: n modal coordinates, y: full DOF vector).
    pub fn expand(&self, x: &DVector<f64>, y: &mut DVector<f64>, work: &mut BlockWork) {
        debug_assert_eq!(y.len(), self.dofs);
        y.fill(0.0);
        for ((b, xm), yr) in self.blocks.iter().zip(&mut work.modal).zip(&mut work.rows) {
            block_product(&b.padded, (x, &b.modes, xm), (yr, &b.rows, y));
        }
    }

    /// out = Φᵀ f (f: full DOF vector, out: n modal coordinates).
    pub fn project(&self, f: &DVector<f64>, out: &mut DVector<f64>, work: &mut BlockWork) {
        debug_assert_eq!(f.len(), self.dofs);
        out.fill(0.0);
        for ((b, om), fr) in self.blocks.iter().zip(&mut work.modal).zip(&mut work.rows) {
            block_product(&b.padded_t, (f, &b.rows, fr), (om, &b.modes, out));
        }
    }
}

/// y[to] += A x[from]: gather x at `from` into the work vector `xs`, multiply into the work
/// vector `ys`, scatter-add at `to` (one block of Φ or of Φᵀ).
fn block_product(
    a: &Padded,
    (x, from, xs): (&DVector<f64>, &[usize], &mut [f64]),
    (ys, to, y): (&mut [f64], &[usize], &mut DVector<f64>),
) {
    for (g, &j) in xs.iter_mut().zip(from) {
        *g = x[j];
    }
    a.product(&xs[..from.len()], ys);
    for (&v, &i) in ys.iter().zip(to) {
        y[i] += v;
    }
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
}
