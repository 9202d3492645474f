/// Degrees of freedom per node.
pub const DOF_PER_NODE: usize = 6;

/// The six nodal unknowns, in their storage order within a node.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Dof {
    /// Axial displacement u, m.
    U = 0,
    /// Lateral displacement v along y (horizontal), m.
    V = 1,
    /// Lateral displacement w along z (vertical, up), m.
    W = 2,
    /// Rotation θx about the string axis (the spin), rad.
    ThetaX = 3,
    /// Rotation θy about y, rad.
    ThetaY = 4,
    /// Rotation θz about z, rad.
    ThetaZ = 5,
}

impl Dof {
    /// All six, in storage order.
    pub const ALL: [Dof; 6] = [
        Dof::U,
        Dof::V,
        Dof::W,
        Dof::ThetaX,
        Dof::ThetaY,
        Dof::ThetaZ,
    ];

    /// Global index of this DOF at `node`.
    pub const fn at(self, node: usize) -> usize {
        DOF_PER_NODE * node + self as usize
    }

    /// The kind of a global DOF index.
    pub const fn of_index(index: usize) -> Dof {
        Dof::ALL[index % DOF_PER_NODE]
    }
}
