//! A synthetic run for the report tests: the shapes of the paper's Figs. 3–5 (steady advance with
//! bit-bounce spikes, steady rotation with stick-slip bursts, a probe that strikes the wall) at
//! adaptive, non-uniform sample times.

use std::f64::consts::TAU;

use crate::model::OperatingPoint;
use crate::sim::TimeSeries;

/// Wall gap used by the tests, m.
pub const GAP: f64 = 0.005;
/// Position of the single probe, m.
pub const PROBE_X: f64 = 20.0;

/// The operating point of [`synthetic_series`]: Ω = 10 rad/s (95.49 rpm), V0 = 0.01 m/s (36 m/h).
pub const OP: OperatingPoint = OperatingPoint {
    omega: 10.0,
    v0: 0.01,
    wob: 0.0,
};

/// `n` samples over about `n` × 10⁻⁴ s.
pub fn synthetic_series(n: usize) -> TimeSeries {
    let mut s = TimeSeries {
        probe_positions: vec![PROBE_X],
        probe_radial: vec![Vec::with_capacity(n)],
        ..TimeSeries::default()
    };
    let (v0, omega) = (OP.v0, OP.omega);
    let mut t = 0.0;
    for i in 0..n {
        let bounce = if i % 9_973 == 500 { 0.05 } else { 0.0 };
        let slip = if (i / 2_000) % 7 == 3 {
            4.0 * (TAU * 30.0 * t).sin().abs()
        } else {
            0.0
        };
        let impact = if i % 7_919 == 100 {
            1.04 * GAP
        } else {
            0.6 * GAP * (TAU * 2.0 * t).sin().abs()
        };
        s.t.push(t);
        s.bit_displacement
            .push(v0 * t + 1e-4 * (TAU * 5.0 * t).sin());
        s.bit_velocity
            .push(v0 + 1e-4 * TAU * 5.0 * (TAU * 5.0 * t).cos() + bounce);
        s.bit_rotation.push(omega * t);
        s.bit_angular_velocity.push(omega + slip);
        s.weight_on_bit.push(1e4);
        s.torque_on_bit.push(1e3);
        s.top_force.push(2e4);
        s.top_torque.push(3e3);
        s.probe_radial[0].push(impact);
        s.nodes_in_contact.push(u32::from(impact > GAP));
        s.contact_onsets.push((i / 7_919) as u64);
        s.wall_force_total.push(0.0);
        s.wall_force_max.push(0.0);
        s.max_radial_over_gap.push(impact / GAP);
        s.kinetic_energy.push(1.0);
        s.potential_energy.push(2.0);
        s.work_top.push(3.0 * t);
        s.work_bit.push(-t);
        s.dissipated.push(2.0 * t);
        t += 1e-4 * (1.0 + 0.5 * (i as f64 * 0.1).sin());
    }
    s
}
