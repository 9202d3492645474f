//! Global assembly of the element matrices on a uniform mesh of N elements.

use super::{BeamElement, DOF_PER_NODE, ELEMENT_DOF, Lateral};
use crate::model::{Drillstring, Section};
use faer::{Col, Mat};

/// Global linear operators of the unconstrained mesh, 6(N+1) DOF, dense.
#[derive(Debug, Clone)]
pub struct GlobalMatrices {
    /// Consistent mass M (pipe + fluid lateral mass + rotatory inertia), Eq. (7).
    pub mass: Mat<f64>,
    /// Pipe-only mass M_pipe; the damping matrix is C = c · M_pipe, Eq. (8).
    pub pipe_mass: Mat<f64>,
    /// Linear stiffness K, Eq. (9).
    pub stiffness: Mat<f64>,
    /// Gravity load vector, Eq. (15), N and N·m.
    pub gravity: Col<f64>,
    /// The element used on every span (uniform mesh), length L/N.
    pub element: BeamElement,
    /// Number of elements N.
    pub elements: usize,
}

impl GlobalMatrices {
    /// Total DOF count 6(N+1).
    pub fn dof(&self) -> usize {
        self.mass.nrows()
    }

    /// x-coordinate of node `i`, m.
    pub fn node_x(&self, i: usize) -> f64 {
        i as f64 * self.element.length
    }
}

/// Assemble M, M_pipe, K and the gravity load for `elements` equal elements along the string.
pub fn assemble(string: &Drillstring, elements: usize) -> GlobalMatrices {
    assert!(elements > 0, "a mesh needs at least one element");
    let element = BeamElement::new(string.length / elements as f64, Section::of(string));
    let n = DOF_PER_NODE * (elements + 1);
    let (me, mpe, ke) = (element.mass(), element.pipe_mass(), element.stiffness());
    let fe = element.gravity_load(string.gravity);
    let mut mass = Mat::zeros(n, n);
    let mut pipe_mass = Mat::zeros(n, n);
    let mut stiffness = Mat::zeros(n, n);
    let mut gravity = Col::zeros(n);
    for e in 0..elements {
        let base = DOF_PER_NODE * e;
        for i in 0..ELEMENT_DOF {
            gravity[base + i] += fe[i];
            for j in 0..ELEMENT_DOF {
                mass[(base + i, base + j)] += me[(i, j)];
                pipe_mass[(base + i, base + j)] += mpe[(i, j)];
                stiffness[(base + i, base + j)] += ke[(i, j)];
            }
        }
    }
    // The bit's polar inertia, lumped on θx of the bit node (not in the pipe mass: not damped).
    let bit_spin = DOF_PER_NODE * elements + crate::fem::Dof::ThetaX as usize;
    mass[(bit_spin, bit_spin)] += string.bit_inertia;
    GlobalMatrices {
        mass,
        pipe_mass,
        stiffness,
        gravity,
        element,
        elements,
    }
}

/// The consistent load of the string's buoyed weight acting along −`axis`, on the full
/// 6(N+1) DOF of `elements` equal elements ([`BeamElement::weight_load`]); along −z it equals
/// [`GlobalMatrices::gravity`]. N and N·m.
pub fn weight_load(string: &Drillstring, elements: usize, axis: Lateral) -> Vec<f64> {
    let element = BeamElement::new(string.length / elements as f64, Section::of(string));
    let fe = element.weight_load(string.gravity, axis);
    let mut load = vec![0.0; DOF_PER_NODE * (elements + 1)];
    for e in 0..elements {
        for (i, f) in fe.iter().enumerate() {
            load[DOF_PER_NODE * e + i] += f;
        }
    }
    load
}
