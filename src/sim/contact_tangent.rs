//! The wall-contact part of the reduced Newton matrix: Σₙ Pₙ Wₙ Pₙᵀ over the touching nodes n,
//! with Pₙ = [φ(vₙ), φ(wₙ)] the rows of Φ for the node's lateral DOFs and
//! Wₙ = −(c_q ∂F/∂(v, w) + c_v ∂F/∂(v̇, ẇ)) its 2 × 2 contact tangent.
//!
//! Added node by node, each rank-two update streamed the whole n × n matrix through memory once
//! per touching node: on the study benchmark (`problems/bench/seed_study.toml`: 50 coordinates,
//! 71 of 106 nodes resting on the wall) the Jacobian took 14 % of a run (perf). Here the rows of
//! the touching nodes are gathered first, over the modes that move a lateral DOF only, and each
//! block of [`ROWS`] entries of two columns stays in registers while the nodes are added in
//! order; a row of a mode that moves one plane only takes that plane's term only (the other is an
//! exact zero). Measured: 8 % of the same run. Every entry receives the same non-zero terms as
//! node by node, `x += φᵢ(v) b₀ + φᵢ(w) b₁` with (b₀, b₁) row j of W Pᵀ, in the same order, so
//! the matrix equals the node-by-node one (an exact zero may differ in sign) and a simulation's
//! results are bitwise unchanged.

use crate::fem::Dof;
use crate::rom::SparseBasis;
use nalgebra::DMatrix;

/// Matrix entries (of one column) kept in registers while the touching nodes are added.
const ROWS: usize = 8;

/// Which lateral DOFs a group of modes moves: v only, w only, or both. The modes of a bending
/// plane move that plane's displacement only, so a row i of the v group has φᵢ(w) = 0 exactly and
/// its term φᵢ(v) b₀ + φᵢ(w) b₁ is φᵢ(v) b₀ (to the sign of an exact zero): half the work.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Moves {
    V,
    W,
    Both,
}

/// Gathered contact rows and the work buffers of [`Self::add_to`] (sized once: the time-step
/// loop allocates nothing).
#[derive(Debug, Clone)]
pub(super) struct ContactTangent {
    /// Per slot, the mode it holds (`usize::MAX` for padding): the modes that move v only, then
    /// those that move w only, then both, each group ascending and padded to a multiple of
    /// [`ROWS`] slots.
    modes: Vec<usize>,
    /// The slot of each mode (`usize::MAX` for a mode that moves no lateral DOF).
    slot: Vec<usize>,
    /// Per block of [`ROWS`] slots, what its modes move.
    blocks: Vec<Moves>,
    /// Upper bound of the touching nodes (the model's nodes).
    capacity: usize,
    /// Touching nodes gathered so far.
    count: usize,
    /// Per gathered node: φ(v) then φ(w) over the slots (zero at padding).
    rows: Vec<f64>,
    /// Per gathered node, its tangent W.
    tangents: Vec<[[f64; 2]; 2]>,
    /// Per gathered node, (b₀, b₁) = row j of W Pᵀ for the two columns j at work.
    coefficients: Vec<[f64; 4]>,
    /// Two columns of the matrix, gathered over the slots.
    column: Vec<f64>,
}

impl ContactTangent {
    pub(super) fn new(phi: &SparseBasis, nodes: usize, size: usize) -> Self {
        // Bit 0: the mode moves some v, bit 1: some w.
        let mut moves = vec![0u8; size];
        for node in 0..nodes {
            for (bit, dof) in [(1, Dof::V.at(node)), (2, Dof::W.at(node))] {
                for &j in phi.dof(dof).0 {
                    moves[j] |= bit;
                }
            }
        }
        let (mut modes, mut slot, mut blocks) = (Vec::new(), vec![usize::MAX; size], Vec::new());
        for (bits, kind) in [(1, Moves::V), (2, Moves::W), (3, Moves::Both)] {
            for j in (0..size).filter(|&j| moves[j] == bits) {
                slot[j] = modes.len();
                modes.push(j);
            }
            while modes.len() % ROWS != 0 {
                modes.push(usize::MAX);
            }
            blocks.resize(modes.len() / ROWS, kind);
        }
        let slots = modes.len();
        ContactTangent {
            modes,
            slot,
            blocks,
            capacity: nodes,
            count: 0,
            rows: vec![0.0; nodes * 2 * slots],
            tangents: vec![[[0.0; 2]; 2]; nodes],
            coefficients: vec![[0.0; 4]; nodes],
            column: vec![0.0; 2 * slots],
        }
    }

    /// Forget the gathered nodes.
    pub(super) fn clear(&mut self) {
        self.count = 0;
    }

    /// Gather a touching node with its 2 × 2 tangent `w` (nodes in ascending order: the order
    /// of the terms in each entry).
    pub(super) fn push(&mut self, phi: &SparseBasis, node: usize, w: [[f64; 2]; 2]) {
        let (c, p) = (self.count, self.modes.len());
        assert!(c < self.capacity, "more touching nodes than nodes");
        let rows = &mut self.rows[2 * p * c..2 * p * (c + 1)];
        rows.fill(0.0);
        let (pv, pw) = rows.split_at_mut(p);
        for (row, dof) in [(&mut *pv, Dof::V.at(node)), (&mut *pw, Dof::W.at(node))] {
            let (modes, values) = phi.dof(dof);
            for (&j, &x) in modes.iter().zip(values) {
                row[self.slot[j]] = x;
            }
        }
        self.tangents[c] = w;
        self.count += 1;
    }

    /// out += Σ Pₙ Wₙ Pₙᵀ over the gathered nodes. Two columns at a time: each node's rows
    /// are loaded once for both, and the four running sums of a block keep the floating-point
    /// units busy (one column alone waits on the latency of its additions).
    pub(super) fn add_to(&mut self, out: &mut DMatrix<f64>) {
        if self.count == 0 {
            return;
        }
        let (p, count) = (self.modes.len(), self.count);
        let rows = &self.rows[..2 * p * count];
        for k in (0..p).step_by(2) {
            let pair = [self.modes[k], self.modes[k + 1]];
            let (first, second) = self.column.split_at_mut(p);
            for (&j, column) in pair.iter().zip([&mut *first, &mut *second]) {
                if j != usize::MAX {
                    let target = out.column(j);
                    for (x, &i) in column.iter_mut().zip(&self.modes) {
                        if i != usize::MAX {
                            *x = target[i];
                        }
                    }
                }
            }
            let b = &mut self.coefficients[..count];
            for ((b, w), node) in b
                .iter_mut()
                .zip(&self.tangents)
                .zip(rows.chunks_exact(2 * p))
            {
                for (i, &(v, w_)) in [(node[k], node[p + k]), (node[k + 1], node[p + k + 1])]
                    .iter()
                    .enumerate()
                {
                    b[2 * i] = w[0][0] * v + w[0][1] * w_;
                    b[2 * i + 1] = w[1][0] * v + w[1][1] * w_;
                }
            }
            let b = &*b;
            let blocks = (first.chunks_exact_mut(ROWS))
                .zip(second.chunks_exact_mut(ROWS))
                .zip(&self.blocks);
            for (block, ((acc0, acc1), &moves)) in blocks.enumerate() {
                let mut s0: [f64; ROWS] = (*acc0).try_into().expect("ROWS entries");
                let mut s1: [f64; ROWS] = (*acc1).try_into().expect("ROWS entries");
                let nodes = rows.chunks_exact(2 * p).zip(b);
                let (v, w) = (block * ROWS, p + block * ROWS);
                match moves {
                    Moves::V => {
                        for (node, b) in nodes {
                            let pv = &node[v..v + ROWS];
                            for r in 0..ROWS {
                                s0[r] += pv[r] * b[0];
                                s1[r] += pv[r] * b[2];
                            }
                        }
                    }
                    Moves::W => {
                        for (node, b) in nodes {
                            let pw = &node[w..w + ROWS];
                            for r in 0..ROWS {
                                s0[r] += pw[r] * b[1];
                                s1[r] += pw[r] * b[3];
                            }
                        }
                    }
                    Moves::Both => {
                        for (node, b) in nodes {
                            let (pv, pw) = (&node[v..v + ROWS], &node[w..w + ROWS]);
                            for r in 0..ROWS {
                                s0[r] += pv[r] * b[0] + pw[r] * b[1];
                                s1[r] += pv[r] * b[2] + pw[r] * b[3];
                            }
                        }
                    }
                }
                acc0.copy_from_slice(&s0);
                acc1.copy_from_slice(&s1);
            }
            for (&j, column) in pair.iter().zip([&*first, &*second]) {
                if j != usize::MAX {
                    let mut target = out.column_mut(j);
                    for (&x, &i) in column.iter().zip(&self.modes) {
                        if i != usize::MAX {
                            target[i] = x;
                        }
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The node-by-node update this replaces.
    fn node_by_node(
        phi: &SparseBasis,
        touching: &[(usize, [[f64; 2]; 2])],
        out: &mut DMatrix<f64>,
    ) {
        let n = out.nrows();
        for &(node, w) in touching {
            let row = |dof: usize| {
                let mut p = vec![0.0; n];
                let (modes, values) = phi.dof(dof);
                for (&j, &x) in modes.iter().zip(values) {
                    p[j] = x;
                }
                p
            };
            let (pv, pw) = (row(Dof::V.at(node)), row(Dof::W.at(node)));
            for j in 0..n {
                let b0 = w[0][0] * pv[j] + w[0][1] * pw[j];
                let b1 = w[1][0] * pv[j] + w[1][1] * pw[j];
                if b0 != 0.0 || b1 != 0.0 {
                    for i in 0..n {
                        out[(i, j)] += pv[i] * b0 + pw[i] * b1;
                    }
                }
            }
        }
    }

    #[test]
    fn gathered_update_equals_the_node_by_node_one_bitwise() {
        // 7 nodes, 13 modes: v only (0, 3, 4, …), w only, both planes (11), neither (2, 12).
        let (nodes, n) = (7, 13);
        let mut seed = 12345u64;
        let mut random = move || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        let phi = DMatrix::from_fn(6 * nodes, n, |i, j| {
            let dof = i % 6;
            let lateral = match j {
                2 | 12 => false,
                11 => dof == 1 || dof == 2,
                _ if j % 2 == 0 || j == 3 => dof == 1,
                _ => dof == 2,
            };
            if lateral || (dof == 3 && j % 5 == 2) {
                random()
            } else {
                0.0
            }
        });
        let sparse = SparseBasis::new(&phi);
        let touching: Vec<_> = [0, 2, 3, 6]
            .map(|node| {
                (
                    node,
                    [[random() * 1e9, random()], [random(), random() * 1e9]],
                )
            })
            .to_vec();
        let start = DMatrix::from_fn(n, n, |_, _| random());
        let mut expected = start.clone();
        node_by_node(&sparse, &touching, &mut expected);
        let mut gathered = ContactTangent::new(&sparse, nodes, n);
        for _ in 0..2 {
            let mut out = start.clone();
            gathered.clear();
            for &(node, w) in &touching {
                gathered.push(&sparse, node, w);
            }
            gathered.add_to(&mut out);
            assert_eq!(out.as_slice(), expected.as_slice());
        }
    }
}
