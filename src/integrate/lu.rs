//! In-place LU factorisation with partial pivoting for the small dense Newton systems, so that the
//! time-step loop allocates nothing (nalgebra's `lu()` takes ownership of a copy).
//!
//! Blocked right-looking LU, written for n ≈ 50 on AVX2 + FMA (safe Rust, laid out so that the
//! compiler keeps the arithmetic in 4-lane registers):
//! - the columns are taken in panels of `NB`; a panel is factorised column by column, with the
//!   dependency chain from one pivot to the next kept short (see `panel_lu`);
//! - the rest of the matrix then takes the panel's row interchanges, the triangular solve for the
//!   block row of U, and a single rank-`NB` update by register blocks of `MR` rows × `NR`
//!   columns, so that each trailing element is loaded and stored once per panel rather than once
//!   per pivot;
//! - the storage is column-major with the leading dimension padded to a multiple of the register
//!   width, so that every loop over rows runs over whole registers (the padding rows only ever
//!   feed padding rows, and hold zeros unless the matrix holds a non-finite value anyway).
//!
//! Later panels' interchanges are not applied to the columns of earlier panels (a strided pass
//! over L for nothing): `solve_in_place` interleaves the interchanges with the forward
//! substitution panel by panel instead. The pivot choice is that of the unblocked algorithm (the
//! element of largest magnitude, the first one on ties), so the factors agree with it to
//! rounding (FMA, and multiplication by the pivot's reciprocal, change the last bits).

use nalgebra::{DMatrix, DVector};

/// Panel width: the trailing matrix takes one rank-`NB` update per panel. A multiple of `LANES`.
const NB: usize = 8;
/// f64 lanes of an AVX2 register.
const LANES: usize = 4;

/// LU factors stored in place of the matrix, with the row permutation.
#[derive(Debug, Clone)]
pub struct DenseLu {
    n: usize,
    /// Leading dimension of `lu`: `n` rounded up to a multiple of `LANES`.
    ld: usize,
    /// Column-major factors (unit lower L below the diagonal, U on and above it), rows `n..ld`
    /// padding. Column j of L carries the interchanges of its own panel only.
    lu: Vec<f64>,
    /// Row interchanged with row k at step k.
    pivots: Vec<usize>,
    /// Reciprocals of the pivots (zero where that would overflow).
    inverses: Vec<f64>,
    /// Scratch: a panel's L21, packed for the trailing update.
    pack: Vec<Packed>,
}

/// The matrix is singular to working precision.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
#[error("singular Newton matrix (zero pivot in column {column})")]
pub struct Singular {
    pub column: usize,
}

impl DenseLu {
    pub fn new(n: usize) -> Self {
        let ld = n.next_multiple_of(LANES);
        DenseLu {
            n,
            ld,
            lu: vec![0.0; ld * n],
            pivots: vec![0; n],
            inverses: vec![0.0; n],
            pack: vec![[[0.0; MR]; NB]; ld.div_ceil(MR)],
        }
    }

    /// Factorise a copy of `a` (n × n) into the stored buffers.
    ///
    /// The pivot of column k is the element of largest magnitude on or below the diagonal (the
    /// first one on ties); `Singular { column: k }` if it is zero or the column holds a non-finite
    /// value.
    pub fn factor(&mut self, a: &DMatrix<f64>) -> Result<(), Singular> {
        let (n, ld) = (self.n, self.ld);
        assert_eq!(
            a.shape(),
            (n, n),
            "DenseLu::factor: matrix is not {n} × {n}"
        );
        if n == 0 {
            return Ok(());
        }
        for (dst, src) in self
            .lu
            .chunks_exact_mut(ld)
            .zip(a.as_slice().chunks_exact(n))
        {
            // Register-wide copies, the padding rows zeroed (a plain `copy_from_slice` of a
            // column is a call to `memcpy` per column).
            let (dst, _) = dst.as_chunks_mut::<LANES>();
            let (src, tail) = src.as_chunks::<LANES>();
            for (d, s) in dst.iter_mut().zip(src) {
                *d = *s;
            }
            if let Some(last) = dst.get_mut(src.len()) {
                *last = std::array::from_fn(|s| tail.get(s).copied().unwrap_or(0.0));
            }
        }
        let mut k0 = 0;
        while k0 < n {
            let kb = NB.min(n - k0);
            factor_panel(
                &mut self.lu,
                ld,
                k0,
                kb,
                &mut self.pivots[k0..k0 + kb],
                &mut self.inverses[k0..k0 + kb],
            )?;
            if k0 + kb < n {
                update_trailing(
                    &mut self.lu,
                    ld,
                    k0,
                    &self.pivots[k0..k0 + NB],
                    &mut self.pack,
                );
            }
            k0 += kb;
        }
        Ok(())
    }

    /// Solve A x = b in place (b becomes x).
    pub fn solve_in_place(&self, b: &mut DVector<f64>) {
        let (n, ld) = (self.n, self.ld);
        assert_eq!(
            b.len(),
            n,
            "DenseLu::solve_in_place: right-hand side is not of length {n}"
        );
        let b = b.as_mut_slice();
        // L y = P b, panel by panel: the panel's interchanges, its unit lower triangle, then the
        // rows below.
        for k0 in (0..n).step_by(NB) {
            let kb = NB.min(n - k0);
            for (k, &p) in (k0..k0 + kb).zip(&self.pivots[k0..k0 + kb]) {
                if p != k {
                    b.swap(k, p);
                }
            }
            let panel = &self.lu[k0 * ld..(k0 + kb) * ld];
            let (head, below) = b.split_at_mut(k0 + kb);
            if let Ok(y) = <&mut [f64; NB]>::try_from(&mut head[k0..]) {
                // A whole panel: the triangle in registers, then the rows below a register at a
                // time, each taking the panel's NB columns in turn.
                let mut columns = panel.chunks_exact(ld);
                let columns: [&[f64]; NB] = std::array::from_fn(|_| columns.next().unwrap());
                let mut v = *y;
                for k in 0..NB {
                    for i in k + 1..NB {
                        v[i] = sub_mul(v[i], columns[k][k0 + i], v[k]);
                    }
                }
                *y = v;
                let l: [&[[f64; LANES]]; NB] =
                    std::array::from_fn(|k| columns[k][k0 + NB..].as_chunks().0);
                let (chunks, tail) = below.as_chunks_mut::<LANES>();
                for (q, chunk) in chunks.iter_mut().enumerate() {
                    let mut acc = *chunk;
                    for k in 0..NB {
                        for s in 0..LANES {
                            acc[s] = sub_mul(acc[s], l[k][q][s], v[k]);
                        }
                    }
                    *chunk = acc;
                }
                let q = chunks.len();
                for (s, x) in tail.iter_mut().enumerate() {
                    for k in 0..NB {
                        *x = sub_mul(*x, l[k][q][s], v[k]);
                    }
                }
            } else {
                // The last, partial panel: nothing below.
                let y = &mut head[k0..];
                for (k, column) in panel.chunks_exact(ld).enumerate() {
                    for i in k + 1..kb {
                        y[i] = sub_mul(y[i], column[k0 + i], y[k]);
                    }
                }
            }
        }
        // U x = y, panels from the last: the triangle, then the rows above.
        for k0 in (0..n).step_by(NB).rev() {
            let kb = NB.min(n - k0);
            let panel = &self.lu[k0 * ld..(k0 + kb) * ld];
            let inverses = &self.inverses[k0..k0 + kb];
            let (above, rest) = b.split_at_mut(k0);
            let x = &mut rest[..kb];
            let scale = |x: f64, j: usize, diagonal: f64| {
                if inverses[j] != 0.0 {
                    x * inverses[j]
                } else {
                    x / diagonal
                }
            };
            // `above` is a whole number of registers.
            let (above, _) = above.as_chunks_mut::<LANES>();
            if let Ok(x) = <&mut [f64; NB]>::try_from(&mut *x) {
                let mut columns = panel.chunks_exact(ld);
                let columns: [&[f64]; NB] = std::array::from_fn(|_| columns.next().unwrap());
                let mut v = *x;
                for j in (0..NB).rev() {
                    v[j] = scale(v[j], j, columns[j][k0 + j]);
                    for i in 0..j {
                        v[i] = sub_mul(v[i], columns[j][k0 + i], v[j]);
                    }
                }
                *x = v;
                let u: [&[[f64; LANES]]; NB] =
                    std::array::from_fn(|j| columns[j][..k0].as_chunks().0);
                for (q, chunk) in above.iter_mut().enumerate() {
                    let mut acc = *chunk;
                    for j in (0..NB).rev() {
                        for s in 0..LANES {
                            acc[s] = sub_mul(acc[s], u[j][q][s], v[j]);
                        }
                    }
                    *chunk = acc;
                }
            } else {
                // The last, partial panel, one column at a time.
                for (j, column) in panel.chunks_exact(ld).enumerate().rev() {
                    x[j] = scale(x[j], j, column[k0 + j]);
                    let xj = x[j];
                    for i in 0..j {
                        x[i] = sub_mul(x[i], column[k0 + i], xj);
                    }
                    let (u, _) = column[..k0].as_chunks::<LANES>();
                    for (chunk, u) in above.iter_mut().zip(u) {
                        for s in 0..LANES {
                            chunk[s] = sub_mul(chunk[s], u[s], xj);
                        }
                    }
                }
            }
        }
    }
}

/// c − a b: one fused multiply-add where the target has FMA (as with `target-cpu=native` on this
/// machine), else a multiplication and a subtraction (without hardware FMA, `mul_add` is a call
/// to the C library's `fma`).
#[inline(always)]
fn sub_mul(c: f64, a: f64, b: f64) -> f64 {
    if cfg!(target_feature = "fma") {
        (-a).mul_add(b, c)
    } else {
        c - a * b
    }
}

/// Factorise columns `k0..k0 + kb` from row `k0` down, with partial pivoting (right-looking
/// inside the panel); the interchanges are applied across the panel's columns only.
fn factor_panel(
    lu: &mut [f64],
    ld: usize,
    k0: usize,
    kb: usize,
    pivots: &mut [usize],
    inverses: &mut [f64],
) -> Result<(), Singular> {
    const { assert!(NB == 8) };
    let panel = &mut lu[k0 * ld..(k0 + kb) * ld];
    match kb {
        8 => panel_lu::<8>(panel, ld, k0, pivots, inverses),
        7 => panel_lu::<7>(panel, ld, k0, pivots, inverses),
        6 => panel_lu::<6>(panel, ld, k0, pivots, inverses),
        5 => panel_lu::<5>(panel, ld, k0, pivots, inverses),
        4 => panel_lu::<4>(panel, ld, k0, pivots, inverses),
        3 => panel_lu::<3>(panel, ld, k0, pivots, inverses),
        2 => panel_lu::<2>(panel, ld, k0, pivots, inverses),
        1 => panel_lu::<1>(panel, ld, k0, pivots, inverses),
        _ => unreachable!(),
    }
}

/// `x` where `keep`, else zero, without a branch.
#[inline(always)]
fn masked(x: f64, keep: bool) -> f64 {
    f64::from_bits(x.to_bits() & u64::from(keep).wrapping_neg())
}

/// `factor_panel` for a panel of `KB` columns, rows counted from `k0`.
///
/// Written for the dependency chain from one pivot to the next: every loop over rows runs over
/// whole registers (the diagonal block, then the rest of the padded column), so that trip
/// counts do not change from pivot to pivot and every row is stored and reloaded as part of the
/// same register; the rows of the diagonal block above the pivot are masked instead. The next
/// column is updated first with the unscaled pivot column and `u / pivot`, its pivot search
/// (which takes in the padding rows: they stay zero unless the column holds a non-finite value
/// anyway) is fused with that update, and the reciprocal of the pivot is taken from its
/// magnitude while its row is being located.
#[inline(always)]
fn panel_lu<const KB: usize>(
    panel: &mut [f64],
    ld: usize,
    k0: usize,
    pivots: &mut [usize],
    inverses: &mut [f64],
) -> Result<(), Singular> {
    // Registers of the diagonal block.
    let tq = KB.div_ceil(LANES);
    let mut columns = panel.chunks_exact_mut(ld);
    let mut columns: [&mut [[f64; LANES]]; KB] = std::array::from_fn(|_| {
        let (chunks, rest) = columns.next().unwrap()[k0..].as_chunks_mut::<LANES>();
        debug_assert!(rest.is_empty());
        chunks
    });
    let mut search = {
        let mut acc = MaxAbs::new();
        let (pairs, rest) = columns[0].as_chunks::<2>();
        for [x0, x1] in pairs {
            acc.add(0, x0);
            acc.add(1, x1);
        }
        if let [x] = rest {
            acc.add(1, x);
        }
        acc.locate(columns[0], 0)
    };
    for jj in 0..KB {
        let Some(Pivot {
            row: p,
            value: pivot,
            inverse,
        }) = search
        else {
            return Err(Singular { column: k0 + jj });
        };
        pivots[jj] = k0 + p;
        inverses[jj] = inverse;
        let (qj, sj) = (jj / LANES, jj % LANES);
        if p != jj {
            let (qp, sp) = (p / LANES, p % LANES);
            for column in columns.iter_mut() {
                let a = column[qj][sj];
                column[qj][sj] = column[qp][sp];
                column[qp][sp] = a;
            }
        }
        let (done, rest) = columns.split_at_mut(jj + 1);
        let column = &mut *done[jj];
        // The pivot column below the pivot, the diagonal block's rows masked.
        let mut top = [[0.0; LANES]; 2];
        for q in 0..tq {
            for s in 0..LANES {
                top[q][s] = masked(column[q][s], q * LANES + s > jj);
            }
        }
        let factor = |u: f64| {
            if inverse != 0.0 {
                u * inverse
            } else {
                u / pivot
            }
        };
        if let Some((next, others)) = rest.split_first_mut() {
            let u = factor(next[qj][sj]);
            search = eliminate::<true>(column, &top[..tq], u, next, jj);
            for other in others {
                let u = factor(other[qj][sj]);
                eliminate::<false>(column, &top[..tq], u, other, jj);
            }
        }
        // The multipliers, off the chain.
        let (head, body) = column.split_at_mut(tq);
        if inverse != 0.0 {
            for (q, chunk) in head.iter_mut().enumerate() {
                for (s, x) in chunk.iter_mut().enumerate() {
                    let below = q * LANES + s > jj;
                    *x = masked(*x * inverse, below) + masked(*x, !below);
                }
            }
            for chunk in body {
                *chunk = chunk.map(|x| x * inverse);
            }
        } else {
            for (q, chunk) in head.iter_mut().enumerate() {
                for (s, x) in chunk.iter_mut().enumerate() {
                    if q * LANES + s > jj {
                        *x /= pivot;
                    }
                }
            }
            for chunk in body {
                *chunk = chunk.map(|x| x / pivot);
            }
        }
    }
    Ok(())
}

/// A pivot: its row, its value and its reciprocal (zero if that would overflow).
struct Pivot {
    row: usize,
    value: f64,
    inverse: f64,
}

/// y -= l u, whole registers (`top`: the first registers of `l`, masked above the pivot `jj`);
/// with `SEARCH`, the pivot search in the updated rows below `jj`.
#[inline(always)]
fn eliminate<const SEARCH: bool>(
    l: &[[f64; LANES]],
    top: &[[f64; LANES]],
    u: f64,
    y: &mut [[f64; LANES]],
    jj: usize,
) -> Option<Pivot> {
    #[inline(always)]
    fn step(l: &[f64; LANES], u: f64, y: &mut [f64; LANES]) -> [f64; LANES] {
        // All loads before the stores: no aliasing question for the vectoriser.
        let mut x = *y;
        for s in 0..LANES {
            x[s] = sub_mul(x[s], l[s], u);
        }
        *y = x;
        x
    }
    let mut acc = MaxAbs::new();
    let (head, body) = y.split_at_mut(top.len());
    for (q, (yc, lc)) in head.iter_mut().zip(top).enumerate() {
        let x = step(lc, u, yc);
        if SEARCH {
            let mut a = [0.0; LANES];
            for s in 0..LANES {
                a[s] = masked(x[s], q * LANES + s > jj);
            }
            acc.add(0, &a);
        }
    }
    let l = &l[top.len()..];
    let (pairs, rest) = body.as_chunks_mut::<2>();
    let (lpairs, lrest) = l.as_chunks::<2>();
    for ([y0, y1], [l0, l1]) in pairs.iter_mut().zip(lpairs) {
        let x0 = step(l0, u, y0);
        let x1 = step(l1, u, y1);
        if SEARCH {
            acc.add(0, &x0);
            acc.add(1, &x1);
        }
    }
    if let ([yc], [lc, ..]) = (rest, lrest) {
        let x = step(lc, u, yc);
        if SEARCH {
            acc.add(1, &x);
        }
    }
    if SEARCH { acc.locate(y, jj + 1) } else { None }
}

/// Running maxima and sums of magnitudes, two registers wide (the sums turn NaN with any NaN).
struct MaxAbs {
    max: [[f64; LANES]; 2],
    sum: [[f64; LANES]; 2],
}

impl MaxAbs {
    #[inline(always)]
    fn new() -> Self {
        MaxAbs {
            max: [[0.0; LANES]; 2],
            sum: [[0.0; LANES]; 2],
        }
    }

    #[inline(always)]
    fn add(&mut self, h: usize, x: &[f64; LANES]) {
        let (max, sum) = (&mut self.max[h], &mut self.sum[h]);
        for ((max, sum), x) in max.iter_mut().zip(sum.iter_mut()).zip(x) {
            let a = x.abs();
            *max = if a > *max { a } else { *max };
            *sum += a;
        }
    }

    /// The pivot: the first row from `from` on holding the largest magnitude; `None` if that is
    /// zero or not finite or if a NaN was seen.
    #[inline(always)]
    fn locate(&self, x: &[[f64; LANES]], from: usize) -> Option<Pivot> {
        let (mut m, mut sum) = ([0.0; LANES], [0.0; LANES]);
        for s in 0..LANES {
            m[s] = if self.max[1][s] > self.max[0][s] {
                self.max[1][s]
            } else {
                self.max[0][s]
            };
            sum[s] = self.sum[0][s] + self.sum[1][s];
        }
        let (m0, m1) = (
            if m[2] > m[0] { m[2] } else { m[0] },
            if m[3] > m[1] { m[3] } else { m[1] },
        );
        let best = if m1 > m0 { m1 } else { m0 };
        if ((sum[0] + sum[2]) + (sum[1] + sum[3])).is_nan() || best == 0.0 || !best.is_finite() {
            return None;
        }
        // Taken now, so that the division overlaps the search for the row.
        let inverse = if best >= f64::MIN_POSITIVE {
            1.0 / best
        } else {
            0.0
        };
        let q0 = from / LANES;
        // Rows of the first register above `from` are not candidates.
        let mut skip = !(!0u32 << (from % LANES));
        for (q, chunk) in x.iter().enumerate().skip(q0) {
            let mut mask = 0u32;
            for (s, v) in chunk.iter().enumerate() {
                mask |= u32::from(v.abs() == best) << s;
            }
            mask &= !skip;
            skip = 0;
            if mask != 0 {
                let s = mask.trailing_zeros() as usize;
                let value = chunk[s];
                return Some(Pivot {
                    row: q * LANES + s,
                    value,
                    inverse: inverse.copysign(value),
                });
            }
        }
        unreachable!()
    }
}

/// Rows of the trailing update's register block (two registers).
const MR: usize = 2 * LANES;
/// Columns of the trailing update's register block.
const NR: usize = 4;

/// L21 of a panel, packed by blocks of `MR` rows: block q holds rows `q MR..(q + 1) MR` of the
/// panel's `NB` columns, so that the kernel reads it with unit stride.
type Packed = [[f64; MR]; NB];

/// After the panel `k0..k0 + NB`: its interchanges and U12 = L11⁻¹ A12 on the columns right of
/// it, then A22 -= L21 U12 by register blocks of `MR` rows × `NR` columns (each element of A22
/// loaded and stored once per panel; per multiplier, `MR` rows at a time against `NR` broadcast
/// U12 values).
fn update_trailing(lu: &mut [f64], ld: usize, k0: usize, pivots: &[usize], pack: &mut [Packed]) {
    let (left, right) = lu.split_at_mut((k0 + NB) * ld);
    let panel = &left[k0 * ld..];
    let r0 = k0 + NB;
    // Columns of L11 below the diagonal, zero on and above it.
    let l11: [[f64; NB]; NB] = std::array::from_fn(|k| {
        let column: &[f64; NB] = panel[k * ld + k0..k * ld + r0].try_into().unwrap();
        std::array::from_fn(|i| masked(column[i], i > k))
    });
    // The panel's interchanges as one permutation of the rows they touch: the NB rows of the
    // block row of U take their values from rows `sources`, and rows `moved[..count]` below it
    // from rows `moved_sources`. Applied per column by loads of the old values and one store
    // each, not by NB swaps in turn: a register loaded right after scalar stores into it would
    // wait for them (a stall per column).
    let mut sources: [usize; NB] = std::array::from_fn(|i| k0 + i);
    let mut moved = [0; NB];
    let mut moved_sources = [0; NB];
    let mut count = 0;
    for (k, &p) in pivots.iter().enumerate() {
        if p < r0 {
            sources.swap(k, p - k0);
        } else if let Some(m) = moved[..count].iter().position(|&row| row == p) {
            std::mem::swap(&mut sources[k], &mut moved_sources[m]);
        } else {
            moved[count] = p;
            moved_sources[count] = sources[k];
            sources[k] = p;
            count += 1;
        }
    }
    // (Two loops, so that the gathered rows are assembled in registers: through the stack, the
    // register load would wait for the scalar stores.)
    if sources.iter().enumerate().all(|(i, &row)| row == k0 + i) {
        for column in right.chunks_exact_mut(ld) {
            let x: &mut [f64; NB] = (&mut column[k0..r0]).try_into().unwrap();
            *x = unit_lower_solve(&l11, *x);
        }
    } else {
        let moved = &moved[..count];
        let moved_sources = &moved_sources[..count];
        for column in right.chunks_exact_mut(ld) {
            let mut x = [0.0; NB];
            for i in 0..NB {
                x[i] = column[sources[i]];
            }
            let mut values = [0.0; NB];
            for (value, &row) in values.iter_mut().zip(moved_sources) {
                *value = column[row];
            }
            for (&row, &value) in moved.iter().zip(&values) {
                column[row] = value;
            }
            let x = unit_lower_solve(&l11, x);
            column[k0..r0].copy_from_slice(&x);
        }
    }
    // L21 in blocks of MR rows (the last block may have only LANES).
    let m = ld - r0;
    let pack = &mut pack[..m.div_ceil(MR)];
    for (k, column) in panel.chunks_exact(ld).enumerate() {
        let (blocks, rest) = column[r0..].as_chunks::<MR>();
        for (packed, block) in pack.iter_mut().zip(blocks) {
            packed[k] = *block;
        }
        if let Ok(rest) = <&[f64; LANES]>::try_from(rest) {
            pack[blocks.len()][k][..LANES].copy_from_slice(rest);
        }
    }
    let mut groups = right.chunks_exact_mut(NR * ld);
    for group in &mut groups {
        update_group::<NR>(group, ld, k0, pack);
    }
    let rest = groups.into_remainder();
    match rest.len() / ld {
        0 => {}
        1 => update_group::<1>(rest, ld, k0, pack),
        2 => update_group::<2>(rest, ld, k0, pack),
        3 => update_group::<3>(rest, ld, k0, pack),
        _ => unreachable!(),
    }
}

/// L⁻¹ x for the unit lower triangular L (`l`: its columns below the diagonal, zero elsewhere),
/// by forward substitution in registers.
#[inline(always)]
fn unit_lower_solve(l: &[[f64; NB]; NB], mut x: [f64; NB]) -> [f64; NB] {
    for (k, l) in l.iter().enumerate().take(NB - 1) {
        let xk = x[k];
        for i in 0..NB {
            x[i] = sub_mul(x[i], l[i], xk);
        }
    }
    x
}

/// A22 -= L21 U12 on the `C` columns of `group` (U12 in rows `k0..k0 + NB`, A22 below), by
/// register blocks of `MR` rows.
#[inline(always)]
fn update_group<const C: usize>(group: &mut [f64], ld: usize, k0: usize, pack: &[Packed]) {
    let r0 = k0 + NB;
    let full = (ld - r0) / MR;
    for (q, l) in pack[..full].iter().enumerate() {
        block::<MR, C>(group, ld, k0, r0 + q * MR, l);
    }
    if let Some(l) = pack.get(full) {
        block::<LANES, C>(group, ld, k0, r0 + full * MR, l);
    }
}

/// Rows `r..r + R` of the `C` columns of `group` -= L21 U12: the register block. Not inlined,
/// so that the broadcasts of U12 stay inside rather than being hoisted out of the loop over
/// blocks, where they would not fit in registers.
#[inline(never)]
fn block<const R: usize, const C: usize>(
    group: &mut [f64],
    ld: usize,
    k0: usize,
    r: usize,
    l: &Packed,
) {
    // References, not copies: the broadcasts are then loads from memory, not shuffles.
    let u: [&[f64; NB]; C] =
        std::array::from_fn(|j| group[j * ld + k0..j * ld + k0 + NB].try_into().unwrap());
    let mut acc: [[f64; R]; C] =
        std::array::from_fn(|j| group[j * ld + r..j * ld + r + R].try_into().unwrap());
    for k in 0..NB {
        let lk = l[k];
        for (a, u) in acc.iter_mut().zip(&u) {
            for i in 0..R {
                a[i] = sub_mul(a[i], lk[i], u[k]);
            }
        }
    }
    for (j, a) in acc.iter().enumerate() {
        group[j * ld + r..j * ld + r + R].copy_from_slice(a);
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

    /// xorshift64: uniform in [-1, 1).
    struct Rng(u64);

    impl Rng {
        fn next(&mut self) -> f64 {
            self.0 ^= self.0 << 13;
            self.0 ^= self.0 >> 7;
            self.0 ^= self.0 << 17;
            (self.0 >> 11) as f64 / (1u64 << 52) as f64 - 1.0
        }

        fn matrix(&mut self, n: usize) -> DMatrix<f64> {
            DMatrix::from_fn(n, n, |_, _| self.next())
        }

        fn vector(&mut self, n: usize) -> DVector<f64> {
            DVector::from_fn(n, |_, _| self.next())
        }
    }

    /// The unblocked right-looking factorisation this module replaced, as the reference for the
    /// pivot sequence: `Err(column)` on a zero or non-finite pivot.
    fn reference_pivots(a: &DMatrix<f64>) -> Result<Vec<usize>, usize> {
        let n = a.nrows();
        let mut lu = a.clone();
        let mut pivots = vec![0; n];
        for k in 0..n {
            let (mut p, mut best) = (k, lu[(k, k)].abs());
            for i in k + 1..n {
                if lu[(i, k)].abs() > best {
                    best = lu[(i, k)].abs();
                    p = i;
                }
            }
            if best == 0.0 || !best.is_finite() {
                return Err(k);
            }
            pivots[k] = p;
            lu.swap_rows(k, p);
            for i in k + 1..n {
                lu[(i, k)] /= lu[(k, k)];
            }
            for j in k + 1..n {
                for i in k + 1..n {
                    lu[(i, j)] -= lu[(i, k)] * lu[(k, j)];
                }
            }
        }
        Ok(pivots)
    }

    /// Factor and solve; the relative residual ‖A x − b‖ / (‖A‖ ‖x‖) is checked, and x against
    /// nalgebra's LU. Returns x.
    fn check_solve(lu: &mut DenseLu, a: &DMatrix<f64>, b: &DVector<f64>) -> DVector<f64> {
        lu.factor(a).unwrap();
        let mut x = b.clone();
        lu.solve_in_place(&mut x);
        let residual = (a * &x - b).norm() / (a.norm() * x.norm());
        assert!(residual < 1e-13, "n = {}: residual {residual:e}", a.nrows());
        let reference = a.clone().lu().solve(b).unwrap();
        let difference = (&x - &reference).norm() / reference.norm();
        assert!(
            difference < 1e-10,
            "n = {}: x differs by {difference:e}",
            a.nrows()
        );
        x
    }

    const SIZES: [usize; 15] = [1, 2, 3, 4, 5, 7, 8, 9, 12, 16, 17, 31, 51, 64, 77];

    #[test]
    fn random_nonsymmetric_systems() {
        let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
        for n in SIZES {
            let mut lu = DenseLu::new(n);
            for _ in 0..3 {
                let a = rng.matrix(n);
                let b = rng.vector(n);
                check_solve(&mut lu, &a, &b);
            }
        }
    }

    #[test]
    fn pivots_agree_with_the_unblocked_factorisation() {
        let mut rng = Rng(0x2545_f491_4f6c_dd1d);
        for n in (1..=40).chain([51, 63, 64, 65, 77, 100]) {
            let a = rng.matrix(n);
            let mut lu = DenseLu::new(n);
            lu.factor(&a).unwrap();
            assert_eq!(Ok(lu.pivots.clone()), reference_pivots(&a), "n = {n}");
            // A diagonally dominant matrix takes no interchange.
            let d = &a + DMatrix::from_diagonal_element(n, n, 2.0 * n as f64);
            lu.factor(&d).unwrap();
            assert_eq!(lu.pivots, (0..n).collect::<Vec<_>>(), "n = {n}");
        }
    }

    #[test]
    fn pivots_at_every_step() {
        // A cyclic shift plus small entries everywhere (the diagonal among them): the pivot of
        // column k is row k + 1 at every step but the last.
        let mut rng = Rng(0xdead_beef_cafe_f00d);
        for n in [2, 3, 8, 9, 13, 51, 77] {
            let a = DMatrix::from_fn(n, n, |i, j| {
                let small = 1e-3 * rng.next();
                if i == (j + 1) % n { 1.0 + small } else { small }
            });
            let mut lu = DenseLu::new(n);
            let x = check_solve(&mut lu, &a, &rng.vector(n));
            assert!(x.iter().all(|v| v.is_finite()));
            let expected: Vec<usize> = (1..n).chain([n - 1]).collect();
            assert_eq!(lu.pivots, expected, "n = {n}");
        }
    }

    #[test]
    fn reuses_its_buffers() {
        let mut rng = Rng(7);
        let mut lu = DenseLu::new(23);
        for _ in 0..5 {
            let a = rng.matrix(23);
            let b = rng.vector(23);
            check_solve(&mut lu, &a, &b);
        }
        let mut empty = DenseLu::new(0);
        empty.factor(&DMatrix::zeros(0, 0)).unwrap();
        empty.solve_in_place(&mut DVector::zeros(0));
    }

    #[test]
    fn singular_matrices_report_the_column() {
        let mut rng = Rng(42);
        for n in [1, 2, 5, 8, 9, 20, 51] {
            let mut lu = DenseLu::new(n);
            assert_eq!(
                lu.factor(&DMatrix::zeros(n, n)),
                Err(Singular { column: 0 })
            );
            for j in [0, n / 3, n / 2, n - 1] {
                // A zero column stays exactly zero through the elimination.
                let mut a = rng.matrix(n);
                a.column_mut(j).fill(0.0);
                assert_eq!(
                    lu.factor(&a),
                    Err(Singular { column: j }),
                    "n = {n}, j = {j}"
                );
                assert_eq!(reference_pivots(&a), Err(j));
                // So does a non-finite entry on or below the diagonal of that column.
                for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
                    let mut a = rng.matrix(n);
                    a[(n - 1, j)] = bad;
                    assert_eq!(
                        lu.factor(&a),
                        Err(Singular { column: j }),
                        "n = {n}, j = {j}"
                    );
                }
                // And the factorisation recovers afterwards.
                check_solve(&mut lu, &rng.matrix(n), &rng.vector(n));
            }
        }
    }
}
