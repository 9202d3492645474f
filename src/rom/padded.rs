//! The product kernels of the blocks of Φ: a column-major matrix with its rows zero-padded to a
//! multiple of [`PAD`], multiplied by one or two vectors with the rows in register chunks.
//!
//! Every row accumulates `a[r][j] x[j]` over the columns j in order with one fused multiply-add
//! each, whatever the chunk length and whether one or two vectors are multiplied: the results
//! are bitwise those of the plain loop (tested).

/// Row padding of the product kernels: their row chunks are 32, 16, 8 or 4 long.
pub(super) const PAD: usize = 4;

/// A column-major matrix whose rows are padded with zeros to a multiple of [`PAD`].
#[derive(Debug, Clone)]
pub(super) struct Padded {
    values: Vec<f64>,
    /// Leading dimension (padded rows).
    pub(super) ld: usize,
    cols: usize,
}

impl Padded {
    /// `rows` × `cols` from a column-major slice.
    pub(super) fn new(rows: usize, cols: usize, column_major: &[f64]) -> Self {
        assert_eq!(column_major.len(), rows * cols);
        let ld = rows.div_ceil(PAD) * PAD;
        let mut values = vec![0.0; ld * cols];
        for (j, column) in column_major
            .chunks_exact(rows.max(1))
            .enumerate()
            .take(cols)
        {
            values[j * ld..j * ld + rows].copy_from_slice(column);
        }
        Padded { values, ld, cols }
    }

    /// y = A x (y: the padded rows). Rows in chunks held in registers over all columns, so each
    /// coefficient is loaded once and y stored once (nalgebra's gemv does one axpy per column).
    pub(super) fn product(&self, x: &[f64], y: &mut [f64]) {
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

    /// (y1, y2) = (A x1, A x2): each coefficient loaded once for both products (the two
    /// bending planes share their block of Φ, see [`super::BlockBasis`]).
    pub(super) fn product2(&self, x: [&[f64]; 2], y: [&mut [f64]; 2]) {
        debug_assert!(x.iter().all(|x| x.len() == self.cols));
        debug_assert!(y.iter().all(|y| y.len() == self.ld));
        let [y1, y2] = y;
        let mut start = 0;
        while start < self.ld {
            start += match self.ld - start {
                16.. => self.chunk2::<16>(start, x, [&mut *y1, &mut *y2]),
                8.. => self.chunk2::<8>(start, x, [&mut *y1, &mut *y2]),
                _ => self.chunk2::<4>(start, x, [&mut *y1, &mut *y2]),
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

    /// Rows start..start + R of A x1 and A x2; returns R.
    #[inline(always)]
    fn chunk2<const R: usize>(&self, start: usize, x: [&[f64]; 2], y: [&mut [f64]; 2]) -> usize {
        let (mut acc1, mut acc2) = ([0.0; R], [0.0; R]);
        let columns = self.values.chunks_exact(self.ld).zip(x[0].iter().zip(x[1]));
        for (column, (&x1, &x2)) in columns {
            let column: &[f64; R] = column[start..start + R].try_into().expect("R rows");
            for ((a1, a2), &c) in acc1.iter_mut().zip(&mut acc2).zip(column) {
                *a1 = c.mul_add(x1, *a1);
                *a2 = c.mul_add(x2, *a2);
            }
        }
        let [y1, y2] = y;
        y1[start..start + R].copy_from_slice(&acc1);
        y2[start..start + R].copy_from_slice(&acc2);
        R
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The plain loop the kernels must reproduce bitwise.
    fn reference(rows: usize, a: &[f64], x: &[f64]) -> Vec<f64> {
        (0..rows)
            .map(|r| {
                x.iter()
                    .enumerate()
                    .fold(0.0, |acc, (j, &xj)| a[j * rows + r].mul_add(xj, acc))
            })
            .collect()
    }

    #[test]
    fn one_and_two_vector_products_are_bitwise_the_plain_loop_for_every_chunk_length() {
        for (rows, cols) in [
            (1, 1),
            (3, 2),
            (9, 5),
            (30, 7),
            (75, 37),
            (64, 33),
            (212, 23),
        ] {
            let a: Vec<f64> = (0..rows * cols)
                .map(|k| ((k * 31 + 7) as f64 * 0.37).sin() * 10f64.powi((k % 7) as i32 - 3))
                .collect();
            let x1: Vec<f64> = (0..cols).map(|j| (j as f64 * 0.9 + 0.2).cos()).collect();
            let x2: Vec<f64> = (0..cols)
                .map(|j| (j as f64 * 1.7 - 0.4).sin() * 1e3)
                .collect();
            let p = Padded::new(rows, cols, &a);
            assert_eq!(p.ld % PAD, 0);
            let mut y = vec![f64::NAN; p.ld];
            p.product(&x1, &mut y);
            let (mut z1, mut z2) = (vec![f64::NAN; p.ld], vec![f64::NAN; p.ld]);
            p.product2([&x1, &x2], [&mut z1, &mut z2]);
            let (e1, e2) = (reference(rows, &a, &x1), reference(rows, &a, &x2));
            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&y[..rows]), bits(&e1), "{rows}x{cols}");
            assert_eq!(bits(&z1[..rows]), bits(&e1), "{rows}x{cols}");
            assert_eq!(bits(&z2[..rows]), bits(&e2), "{rows}x{cols}");
            // The padding rows are zeros times x: zero.
            assert!(y[rows..].iter().chain(&z2[rows..]).all(|&v| v == 0.0));
        }
    }
}
