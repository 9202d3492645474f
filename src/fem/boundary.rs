//! Homogeneous boundary conditions, applied by eliminating constrained DOFs (MODEL.md §4).

use super::{DOF_PER_NODE, Dof};
use faer::Mat;

/// Which global DOFs are held at zero; the others are free.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct BoundaryConditions {
    dof: usize,
    constrained: Vec<bool>,
}

impl BoundaryConditions {
    /// No constraint on a mesh of `elements` elements.
    pub fn free(elements: usize) -> Self {
        let dof = DOF_PER_NODE * (elements + 1);
        BoundaryConditions {
            dof,
            constrained: vec![false; dof],
        }
    }

    /// The drillstring's homogeneous conditions: at x = 0 (node 0) v = w = θy = θz = 0 and the
    /// imposed u, θx lifted out (so u = θx = 0 in the homogeneous form); at x = L, v = w = 0.
    pub fn drillstring(elements: usize) -> Self {
        Self::free(elements)
            .fix(0, &Dof::ALL)
            .fix(elements, &[Dof::V, Dof::W])
    }

    /// Also hold `dofs` at `node`.
    pub fn fix(mut self, node: usize, dofs: &[Dof]) -> Self {
        for d in dofs {
            self.constrained[d.at(node)] = true;
        }
        self
    }

    /// Total DOF count of the mesh.
    pub fn dof(&self) -> usize {
        self.dof
    }

    pub fn is_constrained(&self, index: usize) -> bool {
        self.constrained[index]
    }

    /// Number of free DOFs.
    pub fn free_count(&self) -> usize {
        self.constrained.iter().filter(|c| !**c).count()
    }

    /// Global indices of the free DOFs, ascending.
    pub fn free_dofs(&self) -> Vec<usize> {
        (0..self.dof).filter(|&i| !self.constrained[i]).collect()
    }

    /// The free–free block of a global matrix.
    pub fn reduce(&self, global: &Mat<f64>) -> Mat<f64> {
        let free = self.free_dofs();
        Mat::from_fn(free.len(), free.len(), |i, j| global[(free[i], free[j])])
    }

    /// A free-DOF vector (or matrix of column vectors) scattered into the full DOF set, zeros elsewhere.
    pub fn expand(&self, reduced: &Mat<f64>) -> Mat<f64> {
        let free = self.free_dofs();
        let mut full = Mat::zeros(self.dof, reduced.ncols());
        for (r, &g) in free.iter().enumerate() {
            for c in 0..reduced.ncols() {
                full[(g, c)] = reduced[(r, c)];
            }
        }
        full
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_seed_mesh_keeps_628_of_636_dofs() {
        let bc = BoundaryConditions::drillstring(105);
        assert_eq!(bc.dof(), 636);
        assert_eq!(bc.free_count(), 628);
        assert!(bc.is_constrained(Dof::ThetaX.at(0)));
        assert!(bc.is_constrained(Dof::W.at(105)));
        assert!(!bc.is_constrained(Dof::U.at(105)));
        assert!(!bc.is_constrained(Dof::ThetaY.at(105)));
    }
}
