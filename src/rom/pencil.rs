//! The modal solve block by block, on dense or sparse (K, M).
//!
//! The free DOFs are split into the connected blocks of the (K, M) coupling graph (for the
//! drillstring: axial, torsional, bending in y, bending in z) and each block is solved on its own.
//! A block of at most [`LANCZOS_MIN_BLOCK`] DOFs is solved densely (all its eigenpairs, faer's
//! self-adjoint solver): this is every block of the shipped problems (the seed's largest is 209),
//! whose bases are pinned bitwise by `tests/study/cache_key.rs`. A larger block is solved by sparse
//! shift-invert Lanczos for the kept modes only ([`super::lanczos`]), so a long mesh needs neither
//! dense matrices nor all its eigenpairs. Both pencils give the same blocks and, for the dense
//! blocks, bitwise the same modes.

use super::eigen::generalized_symmetric_eigen;
use super::family::{BasisError, Candidate, Family, ModeKind};
use super::lanczos::{lanczos_applies, sparse_generalized_eigen, sparse_unit_response};
use super::resting::BlockRest;
use crate::fem::{DOF_PER_NODE, Dof, SymmetricSparse};
use crate::model::FamilySize;
use faer::{Mat, MatRef, Par, Side};

/// Blocks larger than this many DOFs go to sparse Lanczos (when the kept count allows a Krylov
/// space smaller than the block): the bending blocks of meshes of 400 elements and more. Below it
/// the dense solve is fast (`cargo bench -p drillopt-benches --bench fem -- modes_`).
pub const LANCZOS_MIN_BLOCK: usize = 800;

/// (K, M) restricted to the free DOFs, with the full mass for the energy shares.
pub(super) enum Pencil<'a> {
    Dense {
        k: Mat<f64>,
        m: Mat<f64>,
        full_mass: MatRef<'a, f64>,
    },
    Sparse {
        k: SymmetricSparse,
        m: SymmetricSparse,
        full_mass: &'a SymmetricSparse,
    },
}

/// One block's matrices.
enum Block {
    Dense(Mat<f64>, Mat<f64>),
    Sparse(SymmetricSparse, SymmetricSparse),
}

impl Pencil<'_> {
    /// Order of the free-DOF problem.
    pub fn size(&self) -> usize {
        match self {
            Pencil::Dense { k, .. } => k.nrows(),
            Pencil::Sparse { k, .. } => k.size(),
        }
    }

    /// Connected blocks of the graph with an edge wherever K or M has a nonzero off-diagonal
    /// entry; each block ascending, blocks by their smallest DOF.
    pub fn blocks(&self) -> Vec<Vec<usize>> {
        let n = self.size();
        let mut edges: Vec<(usize, usize)> = Vec::new();
        match self {
            Pencil::Dense { k, m, .. } => {
                for j in 0..n {
                    for i in (j + 1)..n {
                        if k[(i, j)] != 0.0 || m[(i, j)] != 0.0 {
                            edges.push((i, j));
                        }
                    }
                }
            }
            Pencil::Sparse { k, m, .. } => {
                for a in [k, m] {
                    for j in 0..n {
                        edges.extend(a.column(j).filter(|&(i, _)| i > j).map(|(i, _)| (i, j)));
                    }
                }
            }
        }
        connected_blocks(n, edges)
    }

    /// The block's matrices: sparse when Lanczos will solve it.
    fn block(&self, block: &[usize], take: usize) -> Block {
        let sparse = block.len() > LANCZOS_MIN_BLOCK && lanczos_applies(block.len(), take);
        match self {
            Pencil::Dense { k, m, .. } => {
                let sub = |a: &Mat<f64>| {
                    Mat::from_fn(block.len(), block.len(), |i, j| a[(block[i], block[j])])
                };
                let (kb, mb) = (sub(k), sub(m));
                if sparse {
                    Block::Sparse(
                        SymmetricSparse::from_dense(kb.as_ref()),
                        SymmetricSparse::from_dense(mb.as_ref()),
                    )
                } else {
                    Block::Dense(kb, mb)
                }
            }
            Pencil::Sparse { k, m, .. } => {
                let (kb, mb) = (k.submatrix(block), m.submatrix(block));
                if sparse {
                    Block::Sparse(kb, mb)
                } else {
                    Block::Dense(kb.to_dense(), mb.to_dense())
                }
            }
        }
    }

    /// Entry (i, j) of the free-DOF mass.
    fn mass(&self, i: usize, j: usize) -> f64 {
        match self {
            Pencil::Dense { m, .. } => m[(i, j)],
            Pencil::Sparse { m, .. } => m.get(i, j),
        }
    }

    /// Kinetic-energy share of each family in mode column `c` of the full-DOF `shapes`:
    /// Σ_{i ∈ family} φᵢ (M φ)ᵢ, normalised.
    pub fn energy_shares(&self, shapes: MatRef<'_, f64>, c: usize) -> [f64; 4] {
        let phi = shapes.col(c);
        let m_phi: Vec<f64> = match self {
            Pencil::Dense { full_mass, .. } => {
                let m_phi = *full_mass * phi;
                (0..phi.nrows()).map(|i| m_phi[i]).collect()
            }
            Pencil::Sparse { full_mass, .. } => {
                let x: Vec<f64> = (0..phi.nrows()).map(|i| phi[i]).collect();
                let mut y = vec![0.0; x.len()];
                full_mass.mul_vec(&x, &mut y);
                y
            }
        };
        let mut share = [0.0; 4];
        for (i, mp) in m_phi.iter().enumerate() {
            let fam = Family::of(Dof::of_index(i));
            share[Family::ALL.iter().position(|f| *f == fam).unwrap_or(0)] += phi[i] * mp;
        }
        let total: f64 = share.iter().sum();
        if total > 0.0 {
            share.iter_mut().for_each(|s| *s /= total);
        }
        share
    }
}

/// The load-dependent Ritz vectors asked of a block, beside its normal modes.
#[derive(Clone, Copy)]
pub(super) struct RitzLoads<'a> {
    /// Free-DOF indices of the bit's u and θx, whose unit loads give the static corrections.
    pub bit: Option<[usize; 2]>,
    /// The block's resting-shape problem (bending blocks with a wall).
    pub rest: Option<&'a BlockRest<'a>>,
}

/// The candidates of one block: its kept normal modes and (when asked) the static corrections of
/// unit loads on the bit's DOFs and the block's resting shape.
pub(super) fn solve_block(
    pencil: &Pencil<'_>,
    block: &[usize],
    family: Option<Family>,
    size: FamilySize,
    ritz: RitzLoads<'_>,
    family_of: &impl Fn(usize) -> Family,
    par: Par,
) -> Result<Vec<Candidate>, BasisError> {
    let RitzLoads { bit: loads, rest } = ritz;
    let all = block.len();
    let take = match size {
        FamilySize::Count(c) => c.min(all),
        FamilySize::Cutoff { .. } => all,
    };
    let limit = |hz: f64| (2.0 * std::f64::consts::PI * hz).powi(2);
    let (values, vectors, matrices) = match pencil.block(
        block,
        match size {
            FamilySize::Count(_) => take,
            FamilySize::Cutoff { min, .. } => min.max(16),
        },
    ) {
        Block::Dense(kb, mb) => {
            let (v, x) = generalized_symmetric_eigen(kb.as_ref(), mb.as_ref(), take, par)?;
            (v, x, Block::Dense(kb, mb))
        }
        Block::Sparse(kb, mb) => {
            let (v, x) = match size {
                FamilySize::Count(_) => sparse_generalized_eigen(&kb, &mb, take, par)?,
                // Enough modes to pass the cutoff: double the count until the last is above it.
                FamilySize::Cutoff { hz, min } => {
                    let mut t = min.max(16).min(all);
                    loop {
                        let (v, x) = sparse_generalized_eigen(&kb, &mb, t, par)?;
                        if t == all || v.last().is_some_and(|&l| l > limit(hz)) {
                            break (v, x);
                        }
                        t = (2 * t).min(all);
                    }
                }
            };
            (v, x, Block::Sparse(kb, mb))
        }
    };
    let keep = match size {
        FamilySize::Count(_) => values.len(),
        FamilySize::Cutoff { hz, min } => values
            .iter()
            .filter(|&&l| l <= limit(hz))
            .count()
            .max(min)
            .min(values.len()),
    };
    let entries_of = |col: &dyn Fn(usize) -> f64| -> Vec<(usize, f64)> {
        block
            .iter()
            .enumerate()
            .map(|(r, &g)| (g, col(r)))
            .collect()
    };
    let mut kept: Vec<Candidate> = (0..keep)
        .map(|c| {
            let entries = entries_of(&|r| vectors[(r, c)]);
            Candidate {
                lambda: values[c],
                family: family.unwrap_or_else(|| dominant_family(pencil, &entries, family_of)),
                kind: ModeKind::Normal,
                entries,
                block: 0,
            }
        })
        .collect();
    for g in loads.into_iter().flatten() {
        let Some(r) = block.iter().position(|&b| b == g) else {
            continue;
        };
        let correction = match &matrices {
            Block::Dense(kb, mb) => static_correction(kb.as_ref(), mb.as_ref(), &vectors, keep, r),
            Block::Sparse(kb, mb) => sparse_static_correction(kb, mb, &vectors, keep, r),
        };
        if let Some((lambda, psi)) = correction {
            kept.push(Candidate {
                lambda,
                family: family_of(block[r]),
                kind: ModeKind::StaticCorrection,
                entries: entries_of(&|i| psi[i]),
                block: 0,
            });
        }
    }
    if let (Some(rest), Some(family)) = (rest, family) {
        // The resting shape and its compression sensitivity, as Ritz vectors of the block. A
        // weightless block has none; a weighted one whose shape does not converge is refused
        // (a basis without it lets the string bounce off the wall it should lie on).
        let shapes = |k: &SymmetricSparse| -> Result<Vec<Vec<f64>>, BasisError> {
            if rest.load.iter().all(|&b| b == 0.0) {
                return Ok(Vec::new());
            }
            let x = rest.shape(k).ok_or(BasisError::RestingShape {
                family: family.name(),
            })?;
            let dx = rest
                .geometric
                .as_ref()
                .and_then(|g| rest.compression_sensitivity(k, g, &x));
            Ok(std::iter::once(x).chain(dx).collect())
        };
        let resting = match &matrices {
            Block::Dense(kb, mb) => dense_ritz(
                kb.as_ref(),
                mb.as_ref(),
                &vectors,
                keep,
                shapes(&SymmetricSparse::from_dense(kb.as_ref()))?,
            ),
            Block::Sparse(kb, mb) => sparse_ritz(kb, mb, &vectors, keep, shapes(kb)?),
        };
        // The steady state's shapes, a second Ritz step against the kept modes and the resting
        // shapes (which stay what they are without them).
        let steady = if rest.steady.is_empty() {
            Vec::new()
        } else {
            let against = Mat::<f64>::from_fn(all, keep + resting.len(), |i, c| {
                if c < keep {
                    vectors[(i, c)]
                } else {
                    resting[c - keep].1[i]
                }
            });
            let psi = rest.steady.clone();
            match &matrices {
                Block::Dense(kb, mb) => {
                    dense_ritz(kb.as_ref(), mb.as_ref(), &against, against.ncols(), psi)
                }
                Block::Sparse(kb, mb) => sparse_ritz(kb, mb, &against, against.ncols(), psi),
            }
        };
        let kinds = (resting.into_iter().map(|v| (ModeKind::RestingShape, v)))
            .chain(steady.into_iter().map(|v| (ModeKind::SteadyShape, v)));
        for (kind, (lambda, psi)) in kinds {
            kept.push(Candidate {
                lambda,
                family,
                kind,
                entries: entries_of(&|i| psi[i]),
                block: 0,
            });
        }
    }
    Ok(kept)
}

/// The free-DOF indices of the bit node's u and θx, when free.
pub(super) fn bit_loads(free: &[usize], dof: usize) -> [usize; 2] {
    let node = dof / DOF_PER_NODE - 1;
    [Dof::U, Dof::ThetaX].map(|d| {
        free.iter()
            .position(|&f| f == d.at(node))
            .unwrap_or(usize::MAX)
    })
}

/// The family holding most of the kinetic energy of a free-DOF vector.
fn dominant_family(
    pencil: &Pencil<'_>,
    entries: &[(usize, f64)],
    family_of: &impl Fn(usize) -> Family,
) -> Family {
    let mut share = [0.0; 4];
    for &(i, a) in entries {
        let mi: f64 = entries.iter().map(|&(j, b)| pencil.mass(i, j) * b).sum();
        share[Family::ALL
            .iter()
            .position(|f| *f == family_of(i))
            .unwrap_or(0)] += a * mi;
    }
    Family::ALL[(0..4)
        .max_by(|&a, &b| share[a].total_cmp(&share[b]))
        .unwrap_or(0)]
}

/// The static correction of a unit load on block DOF `r`: ψ = K⁻¹ e_r, M-orthogonalised (twice,
/// classical Gram–Schmidt) against the first `keep` columns of the M-orthonormal `modes`, then
/// M-normalised. Because K φ = λ M φ, ψ is then K-orthogonal to the modes as well, and (ψᵀKψ, ψ)
/// extends the diagonal reduced operators. `None` when the kept modes already span ψ (relative
/// M-norm of the remainder below 1e-8) or K is singular.
fn static_correction(
    k: MatRef<'_, f64>,
    m: MatRef<'_, f64>,
    modes: &Mat<f64>,
    keep: usize,
    r: usize,
) -> Option<(f64, Vec<f64>)> {
    let n = k.nrows();
    use faer::linalg::solvers::Solve;
    let llt = k.llt(Side::Lower).ok()?;
    let mut e = Mat::<f64>::zeros(n, 1);
    e[(r, 0)] = 1.0;
    let psi = llt.solve(e.as_ref());
    let psi: Vec<f64> = (0..n).map(|i| psi[(i, 0)]).collect();
    dense_ritz(k, m, modes, keep, vec![psi]).pop()
}

/// Vectors ψ of a dense block as Ritz vectors: [`ritz_vectors`] against the first `keep` modes.
fn dense_ritz(
    k: MatRef<'_, f64>,
    m: MatRef<'_, f64>,
    modes: &Mat<f64>,
    keep: usize,
    psi: Vec<Vec<f64>>,
) -> Vec<(f64, Vec<f64>)> {
    let n = k.nrows();
    ritz_vectors(
        psi,
        |x| {
            let y = m * faer::ColRef::from_slice(x);
            (0..n).map(|i| y[i]).collect()
        },
        |x| {
            let y = k * faer::ColRef::from_slice(x);
            (0..n).map(|i| y[i]).collect()
        },
        modes,
        keep,
    )
}

/// [`static_correction`] on sparse block matrices.
fn sparse_static_correction(
    k: &SymmetricSparse,
    m: &SymmetricSparse,
    modes: &Mat<f64>,
    keep: usize,
    r: usize,
) -> Option<(f64, Vec<f64>)> {
    let psi = sparse_unit_response(k, r)?;
    sparse_ritz(k, m, modes, keep, vec![psi]).pop()
}

/// [`dense_ritz`] on sparse block matrices.
fn sparse_ritz(
    k: &SymmetricSparse,
    m: &SymmetricSparse,
    modes: &Mat<f64>,
    keep: usize,
    psi: Vec<Vec<f64>>,
) -> Vec<(f64, Vec<f64>)> {
    fn times(a: &SymmetricSparse) -> impl Fn(&[f64]) -> Vec<f64> + '_ {
        move |x: &[f64]| {
            let mut y = vec![0.0; x.len()];
            a.mul_vec(x, &mut y);
            y
        }
    }
    ritz_vectors(psi, times(m), times(k), modes, keep)
}

/// The vectors ψ as Ritz vectors of the block: each M-orthogonalised (twice) against the first
/// `keep` modes and the vectors accepted before it, M-normalised (a vector with less than 1e-8 of
/// its M-norm left is dropped: the others already span it), then combined by a Rayleigh–Ritz
/// step on their span (the eigenvectors of the small matrix VᵀKV, V M-orthonormal), so that the
/// block's basis stays M-orthonormal and K-orthogonal (Φᵀ M Φ = I, Φᵀ K Φ = diag). Returns
/// (ψᵀKψ, ψ) in ascending order of ψᵀKψ.
fn ritz_vectors(
    psis: Vec<Vec<f64>>,
    m: impl Fn(&[f64]) -> Vec<f64>,
    k: impl Fn(&[f64]) -> Vec<f64>,
    modes: &Mat<f64>,
    keep: usize,
) -> Vec<(f64, Vec<f64>)> {
    let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
    let mut accepted: Vec<Vec<f64>> = Vec::new();
    for mut psi in psis {
        let n = psi.len();
        let initial = dot(&psi, &m(&psi)).sqrt();
        for _ in 0..2 {
            let mpsi = m(&psi);
            for c in 0..keep {
                let d: f64 = (0..n).map(|i| modes[(i, c)] * mpsi[i]).sum();
                for (i, p) in psi.iter_mut().enumerate() {
                    *p -= d * modes[(i, c)];
                }
            }
            for a in &accepted {
                let d = dot(a, &mpsi);
                for (p, ai) in psi.iter_mut().zip(a) {
                    *p -= d * ai;
                }
            }
        }
        let norm = dot(&psi, &m(&psi)).sqrt();
        if norm.is_nan() || norm <= 1e-8 * initial {
            continue;
        }
        psi.iter_mut().for_each(|p| *p /= norm);
        accepted.push(psi);
    }
    let r = accepted.len();
    let kv: Vec<Vec<f64>> = accepted.iter().map(|v| k(v)).collect();
    if r == 1 {
        let lambda = dot(&accepted[0], &kv[0]);
        return vec![(lambda, accepted.pop().unwrap_or_default())];
    }
    let reduced = Mat::<f64>::from_fn(r, r, |i, j| {
        0.5 * (dot(&accepted[i], &kv[j]) + dot(&accepted[j], &kv[i]))
    });
    let Ok(eigen) = reduced.self_adjoint_eigen(Side::Lower) else {
        return Vec::new();
    };
    let (values, vectors) = (eigen.S().column_vector(), eigen.U());
    (0..r)
        .map(|c| {
            let n = accepted[0].len();
            let psi: Vec<f64> = (0..n)
                .map(|i| (0..r).map(|a| accepted[a][i] * vectors[(a, c)]).sum())
                .collect();
            (values[c], psi)
        })
        .collect()
}

/// Connected components of the graph on 0..n with the given edges (union–find).
fn connected_blocks(n: usize, edges: Vec<(usize, usize)>) -> Vec<Vec<usize>> {
    let mut parent: Vec<usize> = (0..n).collect();
    fn root(parent: &mut [usize], mut i: usize) -> usize {
        while parent[i] != i {
            parent[i] = parent[parent[i]];
            i = parent[i];
        }
        i
    }
    for (i, j) in edges {
        let (a, b) = (root(&mut parent, i), root(&mut parent, j));
        if a != b {
            parent[a.max(b)] = a.min(b);
        }
    }
    let mut blocks: Vec<Vec<usize>> = Vec::new();
    let mut block_of_root = vec![usize::MAX; n];
    for i in 0..n {
        let r = root(&mut parent, i);
        if block_of_root[r] == usize::MAX {
            block_of_root[r] = blocks.len();
            blocks.push(Vec::new());
        }
        blocks[block_of_root[r]].push(i);
    }
    blocks
}
