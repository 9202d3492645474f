//! The axial force and the torque along a reduced model's string by force summation: from the
//! loads on the nodes below a section, not from the section's strain.
//!
//! A reduced model satisfies its equations only projected on its basis, Φᵀ R = 0, where
//! R = M Q̈ + C Q̇ + f(Q, Q̇, Q̈) − F is the full mesh's residual (f the elements' internal and
//! nonlinear inertial forces, F the wall's, the bit's and gravity's loads). The strains of Φq
//! carry what the basis can represent: along a string that bends at its section boundaries and
//! stabilisers, the membrane strain ½(v′² + w′²) of the bending shapes has no axial companion in
//! the basis, and the axial force read from the strain (the mode-displacement recovery) strays
//! by a quarter of the WOB near the bends of the 1 km well, while its finite-element model
//! holds the WOB to 0.02 % along the string. Summing the loads instead (the force-summation
//! method of loads recovery from a truncated modal model, the alternative to recovering them
//! from the modal displacements), derived here from equilibrium: the elements' internal forces
//! along u (or θx) at the nodes below element e sum to the
//! force (torque) element e exerts on its lower node, F_e = Σ_{k>e} f_int,k (each element's
//! internal forces cancel along u and θx: its strain energy is invariant under rigid translation
//! and spin), so the load that balances the external and inertial loads below e is
//!
//!   N_e = F_e − Σ_{k>e} R_k     (R_k the residual's u or θx entry at node k),
//!
//! the strain's reading less the equilibrium defect of the nodes below. For the unreduced model
//! R = 0 (to the Newton tolerance) and the two recoveries agree; the top drive's force and
//! torque ([`crate::sim::Dynamics::top_loads`]) are the same sum over every node.
//!
//! The residual's entries at u and θx need the rows of M and C at those DOFs, which couple only
//! the DOFs of a node and its neighbours: they are kept here, a few per node, when the model is
//! projected (the assembled matrices are dropped then).

use crate::fem::{DOF_PER_NODE, Dof};
use faer::{Col, Mat};

/// The DOFs whose loads are summed: the axial displacement and the spin.
pub const SUMMED: [Dof; 2] = [Dof::U, Dof::ThetaX];

/// The rows of M and C at each node's u and θx, and gravity's load there.
#[derive(Debug, Clone, PartialEq)]
pub struct ForceSummation {
    /// The non-zeros (column DOF, M entry, C entry) of the rows of M and C at each node's u and
    /// θx, kg or kg·m² and N·s/m or N·m·s/rad, row after row (node-major, [`SUMMED`] order).
    entries: Vec<(usize, f64, f64)>,
    /// Where each row's entries end in `entries` (row 2k + d: node k, DOF `SUMMED[d]`).
    ends: Vec<usize>,
    /// Per node and DOF: gravity's load (N, N·m) and the row's mass over the u columns (the
    /// inertia of the rigid axial acceleration per m/s², kg).
    constant: Vec<[(f64, f64); 2]>,
}

/// The full-mesh state and forces of one residual evaluation (node-major, 6 DOFs per node).
#[derive(Debug, Clone, Copy)]
pub struct FullState<'a> {
    /// f = internal + nonlinear inertial forces − wall − bit, N and N·m.
    pub forces: &'a [f64],
    /// Φq̈ (elastic), m/s² and rad/s².
    pub acceleration: &'a [f64],
    /// Absolute velocities (the rigid feed and spin included), m/s and rad/s.
    pub velocity: &'a [f64],
    /// The rigid axial acceleration s̈ (the free top's block), m/s².
    pub rigid_acceleration: f64,
    /// Whether the damping and the gravity terms are on (`sim::Effects`).
    pub damping: bool,
    pub gravity: bool,
}

impl ForceSummation {
    /// From the assembled mass `mass`, pipe mass `pipe_mass`, stiffness `stiffness` and gravity
    /// load `gravity` of a mesh of `nodes` nodes, with the damping C = c M_pipe + β K
    /// (`c` in 1/s, `beta` in s: `[model.pipe] damping`, `stiffness_damping`).
    pub fn new(
        [mass, pipe_mass, stiffness]: [&Mat<f64>; 3],
        [c, beta]: [f64; 2],
        gravity: &Col<f64>,
        nodes: usize,
    ) -> Self {
        let dof = DOF_PER_NODE * nodes;
        let (mut entries, mut ends, mut constant) = (Vec::new(), Vec::new(), Vec::new());
        for k in 0..nodes {
            constant.push(SUMMED.map(|d| {
                let i = d.at(k);
                // The element matrices couple a node with its neighbours only.
                let from = DOF_PER_NODE * k.saturating_sub(1);
                let to = (DOF_PER_NODE * (k + 2)).min(dof);
                let mut rigid = 0.0;
                for j in from..to {
                    let (m, damping) = (
                        mass[(i, j)],
                        c * pipe_mass[(i, j)] + beta * stiffness[(i, j)],
                    );
                    if m != 0.0 || damping != 0.0 {
                        entries.push((j, m, damping));
                    }
                    if Dof::of_index(j) == Dof::U {
                        rigid += m;
                    }
                }
                ends.push(entries.len());
                (gravity[i], rigid)
            }));
        }
        ForceSummation {
            entries,
            ends,
            constant,
        }
    }

    /// The residual's entries [R_u, R_θx] at node `node` of the state `s`, N and N·m.
    #[inline]
    pub fn residual_at(&self, node: usize, s: &FullState) -> [f64; 2] {
        let damping = if s.damping { 1.0 } else { 0.0 };
        let gravity = if s.gravity { 1.0 } else { 0.0 };
        std::array::from_fn(|k| {
            let row = 2 * node + k;
            let from = if row == 0 { 0 } else { self.ends[row - 1] };
            let (load, rigid_mass) = self.constant[node][k];
            let mut inertia = rigid_mass * s.rigid_acceleration;
            let mut dissipative = 0.0;
            for &(j, m, c) in &self.entries[from..self.ends[row]] {
                inertia += m * s.acceleration[j];
                dissipative += c * s.velocity[j];
            }
            s.forces[SUMMED[k].at(node)] + inertia + damping * dissipative - gravity * load
        })
    }

    /// The equilibrium defects Σ_{k>e} R_k of each element e (top to bit) into `out`
    /// (`out.len()` = elements), [N, N·m]: what the force-summation recovery subtracts from the
    /// strain's axial force and torque.
    pub fn defects(&self, s: &FullState, out: &mut [[f64; 2]]) {
        let mut sum = [0.0; 2];
        for e in (0..out.len()).rev() {
            let r = self.residual_at(e + 1, s);
            sum = [sum[0] + r[0], sum[1] + r[1]];
            out[e] = sum;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    /// The seed's string with stiffness damping β = 10 µs, on 10 elements of 3.5 m.
    fn rows() -> (ForceSummation, crate::model::Drillstring, f64) {
        let mut string = crate::problem::Problem::load(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/problems/seed_mc2014.toml"
        ))
        .unwrap()
        .model;
        string.stiffness_damping = 1e-5;
        let g = crate::fem::assemble(&string, 10);
        let s = ForceSummation::new(
            [&g.mass, &g.pipe_mass, &g.stiffness],
            [string.damping, string.stiffness_damping],
            &g.gravity,
            11,
        );
        let h = string.length / 10.0;
        (s, string, h)
    }

    #[test]
    fn an_interior_nodes_axial_row_is_the_consistent_bar_mass_and_rayleigh_damping() {
        // Linear bar elements: M = ρAh/6 (1, 4, 1), K = EA/h (−1, 2, −1) on u of nodes 4, 5, 6
        // (the raw Table 1 numbers, not the crate's section); C = c M + β K.
        let (s, string, h) = rows();
        let p = &string.pipe;
        let area = PI * (p.outer_radius.powi(2) - p.inner_radius.powi(2));
        let (m, k) = (p.density * area * h / 6.0, p.youngs_modulus * area / h);
        let row = 2 * 5;
        let entries = &s.entries[s.ends[row - 1]..s.ends[row]];
        let expected = [(-1, 1.0, -1.0), (0, 4.0, 2.0), (1, 1.0, -1.0)];
        assert_eq!(entries.len(), 3, "{entries:?}");
        for (&(j, mass, damping), (offset, mm, kk)) in entries.iter().zip(expected) {
            assert_eq!(j as i64, Dof::U.at(5) as i64 + offset * DOF_PER_NODE as i64);
            assert!((mass / (mm * m) - 1.0).abs() < 1e-12, "{mass} {}", mm * m);
            let c = string.damping * mm * m + string.stiffness_damping * kk * k;
            assert!((damping / c - 1.0).abs() < 1e-12, "{damping} {c}");
        }
        // The rigid translation's inertia on the row: the row sum of M, ρAh.
        assert!((s.constant[5][0].1 / (6.0 * m) - 1.0).abs() < 1e-12);
    }

    #[test]
    fn the_defects_sum_the_nodes_below_each_element() {
        // A state with only the external loads f at the nodes (no motion): element e's defect is
        // Σ_{k>e} f_k, exactly.
        let (s, _, _) = rows();
        let n = 11 * DOF_PER_NODE;
        let forces: Vec<f64> = (0..n).map(|i| (i as f64 * 0.37).sin()).collect();
        let zero = vec![0.0; n];
        let state = FullState {
            forces: &forces,
            acceleration: &zero,
            velocity: &zero,
            rigid_acceleration: 0.0,
            damping: true,
            gravity: false,
        };
        let mut out = [[0.0; 2]; 10];
        s.defects(&state, &mut out);
        for (e, d) in out.iter().enumerate() {
            for (k, dof) in SUMMED.iter().enumerate() {
                let sum: f64 = (e + 1..11).map(|node| forces[dof.at(node)]).sum();
                assert!((d[k] - sum).abs() < 1e-12, "element {e}: {} {sum}", d[k]);
            }
        }
    }
}
