//! The lowest modes of the constrained linear drillstring, mass-normalised and labelled by family.
//!
//! The linear operators (7) and (9) do not couple the four families: axial (u), torsional (θx),
//! bending in the x–y plane (v, θz) and bending in the x–z plane (w, θy). Bending in y and in z
//! have the same frequencies, and a dense eigensolver would return arbitrary mixtures of such
//! degenerate pairs. So the free DOFs are split into the connected blocks of the (K, M) coupling
//! graph and each block is solved on its own; the modes are then merged by frequency. This is
//! general: a model that couples the families gives one block and still works. Each mode is
//! labelled by the family that holds most of its kinetic energy φᵢ (M φ)ᵢ.

use super::eigen::{EigenError, generalized_symmetric_eigen};
use crate::fem::{BoundaryConditions, DOF_PER_NODE, Dof, GlobalMatrices, assemble};
use crate::model::{BasisSpec, Drillstring, FamilySize};
use faer::{Mat, MatRef, Par, Side};
use serde::Serialize;
use std::fmt;

/// The vibration family of a mode.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Family {
    /// Axial (u).
    Axial,
    /// Torsional (θx).
    Torsional,
    /// Bending with lateral displacement v along y (horizontal), with θz.
    BendingY,
    /// Bending with lateral displacement w along z (vertical), with θy.
    BendingZ,
}

impl Family {
    pub const ALL: [Family; 4] = [
        Family::Axial,
        Family::Torsional,
        Family::BendingY,
        Family::BendingZ,
    ];

    /// The family a DOF kind belongs to.
    pub fn of(dof: Dof) -> Family {
        match dof {
            Dof::U => Family::Axial,
            Dof::ThetaX => Family::Torsional,
            Dof::V | Dof::ThetaZ => Family::BendingY,
            Dof::W | Dof::ThetaY => Family::BendingZ,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Family::Axial => "axial",
            Family::Torsional => "torsional",
            Family::BendingY => "bending_y",
            Family::BendingZ => "bending_z",
        }
    }
}

impl fmt::Display for Family {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        // pad, not write_str: table columns set a width.
        f.pad(self.name())
    }
}

/// What a basis vector is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ModeKind {
    /// An eigenvector of (K, M).
    #[serde(rename = "mode")]
    Normal,
    /// The static response to a unit bit load, M-orthogonalised against the kept normal modes
    /// (a Ritz vector: K- and M-orthogonal to them, with its Rayleigh quotient as ω²).
    StaticCorrection,
}

/// One vector of the reduced basis.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Mode {
    /// 1-based rank by frequency.
    pub index: usize,
    /// Natural frequency, Hz (for a static correction: √(ψᵀKψ)/2π, its Rayleigh quotient).
    pub freq_hz: f64,
    /// Natural circular frequency ω, rad/s.
    #[serde(skip)]
    pub omega: f64,
    pub family: Family,
    pub kind: ModeKind,
    /// Share of the modal kinetic energy in each family, in [`Family::ALL`] order (sums to 1).
    #[serde(skip)]
    pub energy_share: [f64; 4],
}

/// How many vectors of each family a basis holds: what `modes`, `simulate` and `summary.json`
/// report as `"basis"`. `bending` counts both planes (a problem file's `bending = 16` is per
/// plane: 32 here).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize)]
pub struct BasisCounts {
    pub bending: usize,
    pub torsional: usize,
    pub axial: usize,
    pub static_corrections: usize,
}

impl fmt::Display for BasisCounts {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} bending (both planes), {} torsional, {} axial, {} static correction{}",
            self.bending,
            self.torsional,
            self.axial,
            self.static_corrections,
            if self.static_corrections == 1 {
                ""
            } else {
                "s"
            }
        )
    }
}

/// Why a basis could not be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum BasisError {
    #[error(transparent)]
    Eigen(#[from] EigenError),
    /// A basis that leaves the torsional or axial family (or bending) without a mode cannot show
    /// that family's dynamics: refused.
    #[error(
        "the basis ({spec}) holds no {family} mode ({counts}); keep at least one mode of every family, e.g. with [mesh.basis]"
    )]
    EmptyFamily {
        spec: String,
        family: &'static str,
        counts: BasisCounts,
    },
}

/// The kept modes: frequencies, families and mass-normalised shapes on the full DOF set.
#[derive(Debug, Clone)]
pub struct ModalBasis {
    pub modes: Vec<Mode>,
    /// Mode shapes as columns, full 6(N+1) DOF (zero on constrained DOFs), Φᵀ M Φ = I and
    /// Φᵀ K Φ = diag(ω²).
    pub shapes: Mat<f64>,
}

/// A candidate basis vector on the free DOFs of one block.
struct Candidate {
    lambda: f64,
    family: Family,
    kind: ModeKind,
    /// (free-DOF index, value).
    entries: Vec<(usize, f64)>,
}

impl ModalBasis {
    /// Assemble the model on `elements` elements and build the basis `spec`.
    pub fn compute(
        string: &Drillstring,
        elements: usize,
        spec: &BasisSpec,
    ) -> Result<Self, BasisError> {
        let global = assemble(string, elements);
        Self::of(
            &global,
            &BoundaryConditions::drillstring(elements),
            spec,
            Par::Seq,
        )
    }

    /// The `count` lowest modes of assembled matrices (no family check).
    pub fn lowest(
        global: &GlobalMatrices,
        bc: &BoundaryConditions,
        count: usize,
        par: Par,
    ) -> Result<Self, EigenError> {
        match Self::build(global, bc, &BasisSpec::Lowest(count), par) {
            Ok(b) => Ok(b),
            Err(BasisError::Eigen(e)) => Err(e),
            Err(BasisError::EmptyFamily { .. }) => unreachable!("build does not check families"),
        }
    }

    /// The basis `spec` of assembled matrices under the given boundary conditions; refused when
    /// a family (bending, torsional, axial) is left without a vector.
    pub fn of(
        global: &GlobalMatrices,
        bc: &BoundaryConditions,
        spec: &BasisSpec,
        par: Par,
    ) -> Result<Self, BasisError> {
        let basis = Self::build(global, bc, spec, par)?;
        let counts = basis.counts();
        for (family, n) in [
            ("bending", counts.bending),
            ("torsional", counts.torsional),
            ("axial", counts.axial),
        ] {
            if n == 0 {
                return Err(BasisError::EmptyFamily {
                    spec: spec.to_string(),
                    family,
                    counts,
                });
            }
        }
        Ok(basis)
    }

    fn build(
        global: &GlobalMatrices,
        bc: &BoundaryConditions,
        spec: &BasisSpec,
        par: Par,
    ) -> Result<Self, BasisError> {
        let k = bc.reduce(&global.stiffness);
        let m = bc.reduce(&global.mass);
        let n = k.nrows();
        let free = bc.free_dofs();
        let family_of = |r: usize| Family::of(Dof::of_index(free[r]));
        if let BasisSpec::Lowest(count) = spec
            && *count > n
        {
            return Err(EigenError::TooMany {
                asked: *count,
                size: n,
            }
            .into());
        }
        let mut chosen: Vec<Candidate> = Vec::new();
        for block in coupled_blocks(k.as_ref(), m.as_ref()) {
            let sub = |a: &Mat<f64>| {
                Mat::from_fn(block.len(), block.len(), |i, j| a[(block[i], block[j])])
            };
            let (kb, mb) = (sub(&k), sub(&m));
            // A block whose DOFs are all of one family (the linear operators do not couple them).
            let family =
                Some(family_of(block[0])).filter(|f| block.iter().all(|&r| family_of(r) == *f));
            let size = match (spec, family) {
                (BasisSpec::Lowest(count), _) => FamilySize::Count(*count),
                (BasisSpec::PerFamily { .. }, None) => FamilySize::Count(block.len()),
                (
                    BasisSpec::PerFamily {
                        bending,
                        torsional,
                        axial,
                        ..
                    },
                    Some(f),
                ) => match f {
                    Family::Axial => *axial,
                    Family::Torsional => *torsional,
                    Family::BendingY | Family::BendingZ => *bending,
                },
            };
            let take = match size {
                FamilySize::Count(c) => c.min(block.len()),
                FamilySize::Cutoff { .. } => block.len(),
            };
            let (values, vectors) =
                generalized_symmetric_eigen(kb.as_ref(), mb.as_ref(), take, par)?;
            let keep = match size {
                FamilySize::Count(_) => take,
                FamilySize::Cutoff { hz, min } => {
                    let limit = (2.0 * std::f64::consts::PI * hz).powi(2);
                    values
                        .iter()
                        .filter(|&&l| l <= limit)
                        .count()
                        .max(min)
                        .min(take)
                }
            };
            let mut kept: Vec<Candidate> = (0..keep)
                .map(|c| {
                    let entries: Vec<(usize, f64)> = block
                        .iter()
                        .enumerate()
                        .map(|(r, &g)| (g, vectors[(r, c)]))
                        .collect();
                    Candidate {
                        lambda: values[c],
                        family: family
                            .unwrap_or_else(|| dominant_family(m.as_ref(), &entries, &family_of)),
                        kind: ModeKind::Normal,
                        entries,
                    }
                })
                .collect();
            if let BasisSpec::PerFamily {
                static_corrections: true,
                ..
            } = spec
            {
                let loads = [Dof::U, Dof::ThetaX].map(|d| d.at(bc.dof() / DOF_PER_NODE - 1));
                for g in loads {
                    if let Some(r) = block.iter().position(|&r| free[r] == g)
                        && let Some(c) =
                            static_correction(kb.as_ref(), mb.as_ref(), &vectors, keep, r)
                    {
                        kept.push(Candidate {
                            lambda: c.0,
                            family: family_of(block[r]),
                            kind: ModeKind::StaticCorrection,
                            entries: block
                                .iter()
                                .enumerate()
                                .map(|(i, &g)| (g, c.1[i]))
                                .collect(),
                        });
                    }
                }
            }
            chosen.extend(kept);
        }
        chosen.sort_by(|a, b| a.lambda.total_cmp(&b.lambda));
        if let BasisSpec::Lowest(count) = spec {
            chosen.truncate(*count);
        }
        let count = chosen.len();
        let mut reduced = Mat::zeros(n, count);
        for (c, cand) in chosen.iter().enumerate() {
            for &(r, v) in &cand.entries {
                reduced[(r, c)] = v;
            }
        }
        let shapes = bc.expand(&reduced);
        let modes = chosen
            .iter()
            .enumerate()
            .map(|(c, cand)| {
                let omega = cand.lambda.max(0.0).sqrt();
                let energy_share = energy_shares(global.mass.as_ref(), shapes.as_ref(), c);
                Mode {
                    index: c + 1,
                    freq_hz: omega / (2.0 * std::f64::consts::PI),
                    omega,
                    family: cand.family,
                    kind: cand.kind,
                    energy_share,
                }
            })
            .collect();
        Ok(ModalBasis { modes, shapes })
    }

    /// Number of basis vectors.
    pub fn len(&self) -> usize {
        self.modes.len()
    }

    pub fn is_empty(&self) -> bool {
        self.modes.is_empty()
    }

    /// The modes of one family, in frequency order.
    pub fn family(&self, family: Family) -> impl Iterator<Item = &Mode> {
        self.modes.iter().filter(move |m| m.family == family)
    }

    /// How many vectors of each family the basis holds (normal modes by family; static
    /// corrections counted apart).
    pub fn counts(&self) -> BasisCounts {
        let mut c = BasisCounts::default();
        for m in &self.modes {
            match (m.kind, m.family) {
                (ModeKind::StaticCorrection, _) => c.static_corrections += 1,
                (_, Family::Axial) => c.axial += 1,
                (_, Family::Torsional) => c.torsional += 1,
                (_, Family::BendingY | Family::BendingZ) => c.bending += 1,
            }
        }
        c
    }
}

/// The family holding most of the kinetic energy of a free-DOF vector.
fn dominant_family(
    m: MatRef<'_, f64>,
    entries: &[(usize, f64)],
    family_of: &impl Fn(usize) -> Family,
) -> Family {
    let mut share = [0.0; 4];
    for &(i, a) in entries {
        let mi: f64 = entries.iter().map(|&(j, b)| m[(i, j)] * b).sum();
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
    let mut psi: Vec<f64> = (0..n).map(|i| psi[(i, 0)]).collect();
    let m_norm = |x: &[f64]| -> f64 {
        let mx = m * faer::ColRef::from_slice(x);
        (0..n).map(|i| x[i] * mx[i]).sum::<f64>().sqrt()
    };
    let initial = m_norm(&psi);
    for _ in 0..2 {
        let mpsi = m * faer::ColRef::from_slice(&psi);
        for c in 0..keep {
            let dot: f64 = (0..n).map(|i| modes[(i, c)] * mpsi[i]).sum();
            for (i, p) in psi.iter_mut().enumerate() {
                *p -= dot * modes[(i, c)];
            }
        }
    }
    let norm = m_norm(&psi);
    if norm.is_nan() || norm <= 1e-8 * initial {
        return None;
    }
    psi.iter_mut().for_each(|p| *p /= norm);
    let kpsi = k * faer::ColRef::from_slice(&psi);
    let lambda = (0..n).map(|i| psi[i] * kpsi[i]).sum();
    Some((lambda, psi))
}

/// Kinetic-energy share of each family in mode column `c`: Σ_{i ∈ family} φᵢ (M φ)ᵢ, normalised.
fn energy_shares(mass: MatRef<'_, f64>, shapes: MatRef<'_, f64>, c: usize) -> [f64; 4] {
    let phi = shapes.col(c);
    let m_phi = mass * phi;
    let mut share = [0.0; 4];
    for i in 0..phi.nrows() {
        let fam = Family::of(Dof::of_index(i));
        share[Family::ALL.iter().position(|f| *f == fam).unwrap_or(0)] += phi[i] * m_phi[i];
    }
    let total: f64 = share.iter().sum();
    if total > 0.0 {
        share.iter_mut().for_each(|s| *s /= total);
    }
    share
}

/// Connected blocks of the graph with an edge wherever K or M has a nonzero off-diagonal entry.
fn coupled_blocks(k: MatRef<'_, f64>, m: MatRef<'_, f64>) -> Vec<Vec<usize>> {
    let n = k.nrows();
    let mut parent: Vec<usize> = (0..n).collect();
    fn root(parent: &mut [usize], mut i: usize) -> usize {
        while parent[i] != i {
            parent[i] = parent[parent[i]];
            i = parent[i];
        }
        i
    }
    for j in 0..n {
        for i in (j + 1)..n {
            if k[(i, j)] != 0.0 || m[(i, j)] != 0.0 {
                let (a, b) = (root(&mut parent, i), root(&mut parent, j));
                if a != b {
                    parent[a.max(b)] = a.min(b);
                }
            }
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
