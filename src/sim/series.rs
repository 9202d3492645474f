//! The time history of one simulation: what the simulator records at every accepted step and what
//! metrics, reports and plots read. All values SI; the sample times are not uniformly spaced (the
//! step is adaptive), so any average over time must be weighted by the step lengths.
//!
//! Sign conventions: x from the top (x = 0) to the bit (x = L); the bit advances with u̇ > 0 and
//! spins with θ̇x > 0. Weight on bit and torque on bit are reported positive when the rock resists
//! (WOB = −F_BR ≥ 0, TOB = −T_BR, positive against positive spin). Top force and top torque are
//! the reactions the top drive applies to impose V0 and Ω (positive when pushing and turning).

use serde::Serialize;

/// Time series of one run, one entry per accepted time step (index 0 is the initial state).
#[derive(Debug, Clone, Default, Serialize)]
pub struct TimeSeries {
    /// Time, s.
    pub t: Vec<f64>,
    /// Bit axial displacement u(L), m.
    pub bit_displacement: Vec<f64>,
    /// Bit axial velocity u̇(L), m/s.
    pub bit_velocity: Vec<f64>,
    /// Bit rotation θx(L), rad.
    pub bit_rotation: Vec<f64>,
    /// Bit angular velocity θ̇x(L), rad/s.
    pub bit_angular_velocity: Vec<f64>,
    /// Weight on bit −F_BR ≥ 0, N (0 when the bit is off bottom).
    pub weight_on_bit: Vec<f64>,
    /// Torque on bit −T_BR, N·m.
    pub torque_on_bit: Vec<f64>,
    /// Axial force applied by the top drive, N.
    pub top_force: Vec<f64>,
    /// Torque applied by the top drive, N·m.
    pub top_torque: Vec<f64>,
    /// Positions of the radial-displacement probes, m.
    pub probe_positions: Vec<f64>,
    /// Radial displacement r = √(v² + w²) at each probe: `probe_radial[k][step]`, m.
    pub probe_radial: Vec<Vec<f64>>,
    /// Number of nodes touching the wall (δ > 0).
    pub nodes_in_contact: Vec<u32>,
    /// Cumulative count of impacts over all nodes since t = 0: a node touching the wall after
    /// having separated from it by more than 1 % of the gap (see `sim::IMPACT_SEPARATION`).
    pub contact_onsets: Vec<u64>,
    /// Sum over nodes of the wall normal force magnitude |F_FS|, N.
    pub wall_force_total: Vec<f64>,
    /// Largest wall normal force magnitude at any node, N.
    pub wall_force_max: Vec<f64>,
    /// Largest r / gap over all nodes (> 1 means indentation into the wall).
    pub max_radial_over_gap: Vec<f64>,
    /// Kinetic energy, J.
    pub kinetic_energy: Vec<f64>,
    /// Potential energy: strain + wall-contact elastic + gravity, J.
    pub potential_energy: Vec<f64>,
    /// Cumulative work done by the top drive, J.
    pub work_top: Vec<f64>,
    /// Cumulative work done by the rock on the string (F_BR u̇ + T_BR θ̇; ≤ 0 while drilling), J.
    pub work_bit: Vec<f64>,
    /// Cumulative energy dissipated by damping, wall-contact damping and wall friction (≥ 0), J.
    pub dissipated: Vec<f64>,
}

impl TimeSeries {
    /// Number of recorded samples.
    pub fn len(&self) -> usize {
        self.t.len()
    }

    pub fn is_empty(&self) -> bool {
        self.t.is_empty()
    }

    /// The samples `range` of every channel (probe positions kept), as a new series.
    pub fn slice(&self, range: std::ops::Range<usize>) -> TimeSeries {
        let cut = |v: &Vec<f64>| v[range.clone()].to_vec();
        TimeSeries {
            t: cut(&self.t),
            bit_displacement: cut(&self.bit_displacement),
            bit_velocity: cut(&self.bit_velocity),
            bit_rotation: cut(&self.bit_rotation),
            bit_angular_velocity: cut(&self.bit_angular_velocity),
            weight_on_bit: cut(&self.weight_on_bit),
            torque_on_bit: cut(&self.torque_on_bit),
            top_force: cut(&self.top_force),
            top_torque: cut(&self.top_torque),
            probe_positions: self.probe_positions.clone(),
            probe_radial: self.probe_radial.iter().map(cut).collect(),
            nodes_in_contact: self.nodes_in_contact[range.clone()].to_vec(),
            contact_onsets: self.contact_onsets[range.clone()].to_vec(),
            wall_force_total: cut(&self.wall_force_total),
            wall_force_max: cut(&self.wall_force_max),
            max_radial_over_gap: cut(&self.max_radial_over_gap),
            kinetic_energy: cut(&self.kinetic_energy),
            potential_energy: cut(&self.potential_energy),
            work_top: cut(&self.work_top),
            work_bit: cut(&self.work_bit),
            dissipated: cut(&self.dissipated),
        }
    }
}
