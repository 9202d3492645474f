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
    /// Speed of the block (the top of the string) along the axis ṡ, m/s: V0 under the imposed
    /// feed, the top law's otherwise (`[operating_point] top`).
    pub block_speed: Vec<f64>,
}

/// What the recorder knows at an accepted step: the time, the operating point, the observation
/// of the state and the work integrated so far.
pub struct Frame<'a> {
    /// Time, s.
    pub t: f64,
    pub op: crate::model::OperatingPoint,
    pub obs: &'a super::Observation,
    /// Cumulative work of the top drive, of the rock on the string, and dissipated energy, J.
    pub work_top: f64,
    pub work_bit: f64,
    pub dissipated: f64,
}

/// A real-valued per-step channel of [`TimeSeries`], declared once: its name, SI unit, meaning,
/// how the recorder computes it and where it is stored. The recorder, the CSV writer, the
/// metrics' sanity checks and [`TimeSeries::slice`] all iterate [`CHANNELS`].
pub struct Channel {
    /// Field name, also the stem of the CSV column (`bit_velocity` → `bit_velocity_m_s`).
    pub name: &'static str,
    /// SI unit as a driller reads it (`"m/s"`, `"N·m"`), `""` for a pure number.
    pub unit: &'static str,
    /// What it is, with sign convention.
    pub doc: &'static str,
    record: fn(&Frame) -> f64,
    get: fn(&TimeSeries) -> &Vec<f64>,
    get_mut: fn(&mut TimeSeries) -> &mut Vec<f64>,
}

impl Channel {
    /// The channel's values in `series`.
    pub fn values<'a>(&self, series: &'a TimeSeries) -> &'a [f64] {
        (self.get)(series)
    }

    /// The CSV header: name and unit (`/` and `·` written `_`), e.g. `torque_on_bit_N_m`.
    pub fn column_name(&self) -> String {
        if self.unit.is_empty() {
            self.name.to_string()
        } else {
            format!("{}_{}", self.name, self.unit.replace(['/', '·'], "_"))
        }
    }
}

macro_rules! channel {
    ($field:ident, $unit:literal, $doc:literal, $record:expr) => {
        Channel {
            name: stringify!($field),
            unit: $unit,
            doc: $doc,
            record: $record,
            get: |s| &s.$field,
            get_mut: |s| &mut s.$field,
        }
    };
}

/// Every real-valued per-step channel, in file order (the counts and probes follow them in CSV).
pub static CHANNELS: [Channel; 18] = [
    channel!(t, "s", "time", |f| f.t),
    channel!(
        bit_displacement,
        "m",
        "bit axial displacement u(L) = s + elastic part (s the block's position, V0 t under the imposed feed)",
        |f| f.obs.block_position + f.obs.bit_u_elastic
    ),
    channel!(
        bit_velocity,
        "m/s",
        "bit axial velocity u̇(L), > 0 advancing",
        |f| f.obs.bit_velocity
    ),
    channel!(
        bit_rotation,
        "rad",
        "bit rotation θx(L) = Ω t + elastic part",
        |f| f.op.omega * f.t + f.obs.bit_theta_elastic
    ),
    channel!(
        bit_angular_velocity,
        "rad/s",
        "bit angular velocity θ̇x(L)",
        |f| f.obs.bit_spin
    ),
    channel!(weight_on_bit, "N", "WOB = −F_BR ≥ 0", |f| -f
        .obs
        .bit
        .force),
    channel!(
        torque_on_bit,
        "N·m",
        "TOB = −T_BR, positive against positive spin",
        |f| -f.obs.bit.torque
    ),
    channel!(
        top_force,
        "N",
        "axial force of the top drive imposing V0",
        |f| f.obs.top_force
    ),
    channel!(
        top_torque,
        "N·m",
        "torque of the top drive imposing Ω",
        |f| f.obs.top_torque
    ),
    channel!(
        wall_force_total,
        "N",
        "sum over nodes of the wall normal force |F_FS|",
        |f| f.obs.wall_force_total
    ),
    channel!(
        wall_force_max,
        "N",
        "largest wall normal force at any node",
        |f| f.obs.wall_force_max
    ),
    channel!(
        max_radial_over_gap,
        "",
        "largest radial displacement over the gap (> 1: indentation)",
        |f| f.obs.max_radial_over_gap
    ),
    channel!(kinetic_energy, "J", "kinetic energy", |f| f
        .obs
        .kinetic_energy),
    channel!(
        potential_energy,
        "J",
        "strain + wall-contact elastic + gravity energy",
        |f| f.obs.potential_energy
    ),
    channel!(work_top, "J", "cumulative work of the top drive", |f| f
        .work_top),
    channel!(
        work_bit,
        "J",
        "cumulative work of the rock on the string (≤ 0 while drilling)",
        |f| f.work_bit
    ),
    channel!(
        dissipated,
        "J",
        "cumulative energy dissipated by damping and wall friction (≥ 0)",
        |f| f.dissipated
    ),
    channel!(
        block_speed,
        "m/s",
        "speed of the block (the top of the string) ṡ: V0 under the imposed feed",
        |f| f.obs.block_speed
    ),
];

/// Positions of the channels in [`CHANNELS`] (and in [`Row::values`]) that metrics and the
/// sampler read by position; `channel_positions_match_names` checks them against the names.
pub mod at {
    pub const T: usize = 0;
    pub const BIT_DISPLACEMENT: usize = 1;
    pub const BIT_VELOCITY: usize = 2;
    pub const BIT_ROTATION: usize = 3;
    pub const BIT_ANGULAR_VELOCITY: usize = 4;
    pub const WEIGHT_ON_BIT: usize = 5;
    pub const TORQUE_ON_BIT: usize = 6;
    pub const TOP_FORCE: usize = 7;
    pub const TOP_TORQUE: usize = 8;
    pub const WALL_FORCE_TOTAL: usize = 9;
    pub const WALL_FORCE_MAX: usize = 10;
    pub const MAX_RADIAL_OVER_GAP: usize = 11;
    pub const KINETIC_ENERGY: usize = 12;
    pub const POTENTIAL_ENERGY: usize = 13;
    pub const WORK_TOP: usize = 14;
    pub const WORK_BIT: usize = 15;
    pub const DISSIPATED: usize = 16;
    pub const BLOCK_SPEED: usize = 17;
}

/// One recorded state: every real channel of [`CHANNELS`] in their order (SI units, `values[0]`
/// is the time in s), the contact counts and the radial displacement at each probe (m, in the
/// order of the run's probe positions).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Row<'a> {
    pub values: [f64; CHANNELS.len()],
    /// Nodes touching the wall.
    pub nodes_in_contact: u32,
    /// Cumulative impacts since t = 0.
    pub contact_onsets: u64,
    /// Radial displacement at each probe, m.
    pub probe_radial: &'a [f64],
}

impl Row<'_> {
    /// The time of the row, s.
    pub fn t(&self) -> f64 {
        self.values[at::T]
    }

    /// Every channel of [`CHANNELS`] evaluated on `frame` (the counts and probes are the
    /// caller's).
    pub fn values_of(frame: &Frame) -> [f64; CHANNELS.len()] {
        std::array::from_fn(|k| (CHANNELS[k].record)(frame))
    }
}

/// Where a run sends its recorded states: every accepted step, in time order, starting with the
/// initial state. A sink must not allocate per row in steady state (the time-step loop allocates
/// nothing); it returns `false` to stop the run (e.g. its output failed; it keeps the reason).
pub trait Sink {
    /// Take one recorded state; `false` stops the run.
    fn record(&mut self, row: &Row<'_>) -> bool;
}

/// Both sinks receive every row (the run stops if either asks).
impl<A: Sink, B: Sink> Sink for (A, B) {
    fn record(&mut self, row: &Row<'_>) -> bool {
        let a = self.0.record(row);
        self.1.record(row) && a
    }
}

impl<S: Sink + ?Sized> Sink for &mut S {
    fn record(&mut self, row: &Row<'_>) -> bool {
        (**self).record(row)
    }
}

/// The in-memory history: every row appended (probes beyond `probe_radial.len()` dropped).
impl Sink for TimeSeries {
    fn record(&mut self, row: &Row<'_>) -> bool {
        self.push_row(row);
        true
    }
}

impl TimeSeries {
    /// An empty series for a run with radial probes at `probes` (m), with room for `rows` rows.
    pub fn with_probes(probes: &[f64], rows: usize) -> Self {
        let mut s = TimeSeries {
            probe_positions: probes.to_vec(),
            probe_radial: vec![Vec::with_capacity(rows); probes.len()],
            nodes_in_contact: Vec::with_capacity(rows),
            contact_onsets: Vec::with_capacity(rows),
            ..Default::default()
        };
        for ch in &CHANNELS {
            (ch.get_mut)(&mut s).reserve_exact(rows);
        }
        s
    }

    /// Append one row.
    pub fn push_row(&mut self, row: &Row<'_>) {
        for (ch, &v) in CHANNELS.iter().zip(&row.values) {
            (ch.get_mut)(self).push(v);
        }
        for (k, probe) in self.probe_radial.iter_mut().enumerate() {
            probe.push(row.probe_radial.get(k).copied().unwrap_or(f64::NAN));
        }
        self.nodes_in_contact.push(row.nodes_in_contact);
        self.contact_onsets.push(row.contact_onsets);
    }

    /// Row `i` (its probes written into `probes`, which must hold one slot per probe).
    pub fn row<'a>(&self, i: usize, probes: &'a mut [f64]) -> Row<'a> {
        for (slot, probe) in probes.iter_mut().zip(&self.probe_radial) {
            *slot = probe[i];
        }
        Row {
            values: std::array::from_fn(|k| CHANNELS[k].values(self)[i]),
            nodes_in_contact: self.nodes_in_contact[i],
            contact_onsets: self.contact_onsets[i],
            probe_radial: probes,
        }
    }

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
        let mut out = TimeSeries {
            probe_positions: self.probe_positions.clone(),
            probe_radial: self.probe_radial.iter().map(cut).collect(),
            nodes_in_contact: self.nodes_in_contact[range.clone()].to_vec(),
            contact_onsets: self.contact_onsets[range.clone()].to_vec(),
            ..TimeSeries::default()
        };
        for ch in &CHANNELS {
            *(ch.get_mut)(&mut out) = cut((ch.get)(self));
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn channel_positions_match_names() {
        for (k, name) in [
            (at::T, "t"),
            (at::BIT_DISPLACEMENT, "bit_displacement"),
            (at::BIT_VELOCITY, "bit_velocity"),
            (at::BIT_ROTATION, "bit_rotation"),
            (at::BIT_ANGULAR_VELOCITY, "bit_angular_velocity"),
            (at::WEIGHT_ON_BIT, "weight_on_bit"),
            (at::TORQUE_ON_BIT, "torque_on_bit"),
            (at::TOP_FORCE, "top_force"),
            (at::TOP_TORQUE, "top_torque"),
            (at::WALL_FORCE_TOTAL, "wall_force_total"),
            (at::WALL_FORCE_MAX, "wall_force_max"),
            (at::MAX_RADIAL_OVER_GAP, "max_radial_over_gap"),
            (at::KINETIC_ENERGY, "kinetic_energy"),
            (at::POTENTIAL_ENERGY, "potential_energy"),
            (at::WORK_TOP, "work_top"),
            (at::WORK_BIT, "work_bit"),
            (at::DISSIPATED, "dissipated"),
            (at::BLOCK_SPEED, "block_speed"),
        ] {
            assert_eq!(CHANNELS[k].name, name);
        }
    }

    #[test]
    fn rows_round_trip_through_a_series() {
        let mut s = TimeSeries::with_probes(&[1.0, 2.0], 2);
        let values: [f64; CHANNELS.len()] = std::array::from_fn(|k| k as f64 + 0.5);
        let row = Row {
            values,
            nodes_in_contact: 3,
            contact_onsets: 7,
            probe_radial: &[0.25, 0.75],
        };
        assert!(s.record(&row));
        assert_eq!(s.len(), 1);
        let mut probes = [0.0; 2];
        assert_eq!(s.row(0, &mut probes), row);
    }
}
