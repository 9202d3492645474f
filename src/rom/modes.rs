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
use crate::fem::{BoundaryConditions, Dof, GlobalMatrices, assemble};
use crate::model::Drillstring;
use faer::{Mat, MatRef, Par};
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
        f.write_str(self.name())
    }
}

/// One mode of the constrained system.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Mode {
    /// 1-based rank by frequency.
    pub index: usize,
    /// Natural frequency, Hz.
    pub freq_hz: f64,
    /// Natural circular frequency ω, rad/s.
    #[serde(skip)]
    pub omega: f64,
    pub family: Family,
    /// Share of the modal kinetic energy in each family, in [`Family::ALL`] order (sums to 1).
    #[serde(skip)]
    pub energy_share: [f64; 4],
}

/// The lowest modes: frequencies, families and mass-normalised shapes on the full DOF set.
#[derive(Debug, Clone)]
pub struct ModalBasis {
    pub modes: Vec<Mode>,
    /// Mode shapes as columns, full 6(N+1) DOF (zero on constrained DOFs), Φᵀ M Φ = I.
    pub shapes: Mat<f64>,
}

impl ModalBasis {
    /// Assemble the model on `elements` elements and take its `count` lowest modes.
    pub fn compute(
        string: &Drillstring,
        elements: usize,
        count: usize,
    ) -> Result<Self, EigenError> {
        let global = assemble(string, elements);
        Self::of(
            &global,
            &BoundaryConditions::drillstring(elements),
            count,
            Par::Seq,
        )
    }

    /// The `count` lowest modes of assembled matrices under the given boundary conditions.
    pub fn of(
        global: &GlobalMatrices,
        bc: &BoundaryConditions,
        count: usize,
        par: Par,
    ) -> Result<Self, EigenError> {
        let k = bc.reduce(&global.stiffness);
        let m = bc.reduce(&global.mass);
        let n = k.nrows();
        if count > n {
            return Err(EigenError::TooMany {
                asked: count,
                size: n,
            });
        }
        let mut pairs: Vec<(f64, Vec<(usize, f64)>)> = Vec::new();
        for block in coupled_blocks(k.as_ref(), m.as_ref()) {
            let sub = |a: &Mat<f64>| {
                Mat::from_fn(block.len(), block.len(), |i, j| a[(block[i], block[j])])
            };
            let (kb, mb) = (sub(&k), sub(&m));
            let take = count.min(block.len());
            let (values, vectors) =
                generalized_symmetric_eigen(kb.as_ref(), mb.as_ref(), take, par)?;
            for (c, &lambda) in values.iter().enumerate() {
                let entries = block
                    .iter()
                    .enumerate()
                    .map(|(r, &g)| (g, vectors[(r, c)]))
                    .collect();
                pairs.push((lambda, entries));
            }
        }
        pairs.sort_by(|a, b| a.0.total_cmp(&b.0));
        pairs.truncate(count);
        let mut reduced = Mat::zeros(n, count);
        for (c, (_, entries)) in pairs.iter().enumerate() {
            for &(r, v) in entries {
                reduced[(r, c)] = v;
            }
        }
        let shapes = bc.expand(&reduced);
        let modes = pairs
            .iter()
            .enumerate()
            .map(|(c, (lambda, _))| {
                let omega = lambda.max(0.0).sqrt();
                let energy_share = energy_shares(global.mass.as_ref(), shapes.as_ref(), c);
                let family = Family::ALL[(0..4)
                    .max_by(|&a, &b| energy_share[a].total_cmp(&energy_share[b]))
                    .unwrap_or(0)];
                Mode {
                    index: c + 1,
                    freq_hz: omega / (2.0 * std::f64::consts::PI),
                    omega,
                    family,
                    energy_share,
                }
            })
            .collect();
        Ok(ModalBasis { modes, shapes })
    }

    /// Number of modes.
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
