//! Global assembly of the element matrices over the mesh's elements ([`ElementLayout`]).

use super::{DOF_PER_NODE, ELEMENT_DOF, ElementLayout, ElementMatrix, ElementVector, Lateral};
use crate::model::Drillstring;
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
    /// The mesh: each element's length and section, the nodes' positions.
    pub layout: ElementLayout,
    /// Number of elements N.
    pub elements: usize,
}

/// What a model keeps of its assembly once it is projected: the mesh, without the matrices (a
/// 2000-element string's three dense matrices hold 3.5 GB; a reduced model needs none of them
/// after its projection).
#[derive(Debug, Clone)]
pub struct AssembledMesh {
    /// The mesh: each element's length and section, the nodes' positions.
    pub layout: ElementLayout,
    /// Number of elements N.
    pub elements: usize,
}

impl AssembledMesh {
    /// Total DOF count 6(N+1).
    pub fn dof(&self) -> usize {
        DOF_PER_NODE * (self.elements + 1)
    }

    /// x-coordinate of node `i`, m.
    pub fn node_x(&self, i: usize) -> f64 {
        self.layout.node_x(i)
    }
}

impl GlobalMatrices {
    /// Total DOF count 6(N+1).
    pub fn dof(&self) -> usize {
        self.mass.nrows()
    }

    /// The mesh, without the matrices.
    pub fn into_mesh(self) -> AssembledMesh {
        AssembledMesh {
            layout: self.layout,
            elements: self.elements,
        }
    }

    /// x-coordinate of node `i`, m.
    pub fn node_x(&self, i: usize) -> f64 {
        self.layout.node_x(i)
    }
}

/// The element matrices of each kind of `layout`: mass, pipe mass, stiffness and gravity load.
type KindMatrices = (ElementMatrix, ElementMatrix, ElementMatrix, ElementVector);

/// Assemble M, M_pipe, K and the gravity load over the elements of `string`'s mesh of
/// `elements` elements ([`ElementLayout::of`]).
pub fn assemble(string: &Drillstring, elements: usize) -> GlobalMatrices {
    let layout = ElementLayout::of(string, elements);
    let n = DOF_PER_NODE * (elements + 1);
    let kinds: Vec<KindMatrices> = layout
        .kinds()
        .iter()
        .map(|k| {
            let element = &k.element;
            (
                element.mass(),
                element.pipe_mass(),
                element.stiffness(),
                element.gravity_load(string.gravity),
            )
        })
        .collect();
    let mut mass = Mat::zeros(n, n);
    let mut pipe_mass = Mat::zeros(n, n);
    let mut stiffness = Mat::zeros(n, n);
    let mut gravity = Col::zeros(n);
    for e in 0..elements {
        let (me, mpe, ke, fe) = &kinds[layout.kind(e)];
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
        layout,
        elements,
    }
}

/// The consistent load of the string's buoyed weight acting along −`axis`, on the full
/// 6(N+1) DOF of the mesh of `elements` elements ([`super::BeamElement::weight_load`]); along
/// −z it equals [`GlobalMatrices::gravity`]. N and N·m.
pub fn weight_load(string: &Drillstring, elements: usize, axis: Lateral) -> Vec<f64> {
    let layout = ElementLayout::of(string, elements);
    let kinds: Vec<ElementVector> = (layout.kinds().iter())
        .map(|k| k.element.weight_load(string.gravity, axis))
        .collect();
    let mut load = vec![0.0; DOF_PER_NODE * (elements + 1)];
    for e in 0..elements {
        for (i, f) in kinds[layout.kind(e)].iter().enumerate() {
            load[DOF_PER_NODE * e + i] += f;
        }
    }
    load
}
