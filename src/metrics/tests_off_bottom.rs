//! Issue 13 item 13: the metrics of an off-bottom window (V0 = 0) are defined and documented.

use super::*;
use crate::sim::TimeSeries;
use std::f64::consts::PI;

const OMEGA: f64 = 10.0;

/// An off-bottom window: the top feeds nothing, the bit rotates at Ω with a small stick-slip
/// and vibrates axially by ±1 µm about its position, the rock carries no weight but the
/// instants the bit touches it.
fn off_bottom(t: &[f64]) -> TimeSeries {
    let n = t.len();
    let c = |v: f64| vec![v; n];
    let w = 2.0 * PI * 5.0;
    TimeSeries {
        t: t.to_vec(),
        bit_displacement: t.iter().map(|&t| 0.3 + 1e-6 * (w * t).sin()).collect(),
        bit_velocity: t.iter().map(|&t| 1e-6 * w * (w * t).cos()).collect(),
        bit_rotation: t
            .iter()
            .map(|&t| OMEGA * t - 0.5 * (2.0 * t).cos())
            .collect(),
        bit_angular_velocity: t.iter().map(|&t| OMEGA + (2.0 * t).sin()).collect(),
        weight_on_bit: t
            .iter()
            .map(|&t| if (w * t).cos() > 0.99 { 1.0 } else { 0.0 })
            .collect(),
        torque_on_bit: c(0.0),
        top_force: c(0.0),
        top_torque: c(200.0),
        probe_positions: vec![20.0],
        probe_radial: vec![c(0.01)],
        nodes_in_contact: vec![0; n],
        contact_onsets: vec![0; n],
        wall_force_total: c(0.0),
        wall_force_max: c(0.0),
        max_radial_over_gap: c(0.5),
        kinetic_energy: c(0.0),
        potential_energy: c(0.0),
        work_top: t.iter().map(|&t| 200.0 * OMEGA * t).collect(),
        work_bit: c(0.0),
        dissipated: t.iter().map(|&t| 200.0 * OMEGA * t).collect(),
        block_speed: c(0.0),
    }
}

#[test]
fn an_off_bottom_window_has_well_defined_metrics() {
    let t: Vec<f64> = (0..=4000).map(|i| i as f64 * 1e-3).collect();
    let config = MetricsConfig::new(OMEGA, 0.0, 0.1, 1.0);
    config.validate().expect("V0 = 0 is a valid configuration");
    let m = compute(&off_bottom(&t), &config).expect("metrics of an off-bottom window");
    // Every value is a number or +∞ by its documented rule, never NaN (the stress metrics come
    // from a run's envelope, the critical speed margin and the bit damping ratio from the model,
    // not from the series: NaN here by definition).
    for spec in super::METRICS {
        let v = (spec.get)(&m);
        let key = spec.key;
        assert!(
            spec.source != super::Source::Series || !v.is_nan(),
            "{key} is NaN"
        );
    }
    assert!(m.mean_rop_m_s.abs() < 1e-6, "elastic drift only");
    assert_eq!(m.mse_pa, f64::INFINITY, "no rock is cut");
    assert_eq!(m.axial_velocity_fluctuation, f64::INFINITY);
    assert_eq!(m.bit_bounce_fraction, 1.0, "off bottom by definition");
    // Stick-slip statistics stay relative to Ω: speed Ω ± 1 rad/s (10 ms average: ±0.99998).
    assert!(
        (m.stick_slip_severity - 0.1).abs() < 1e-3,
        "{}",
        m.stick_slip_severity
    );
    assert!((m.max_bit_speed_ratio - 1.1).abs() < 1e-3);
    assert_eq!(m.stick_fraction, 0.0);
    assert_eq!(m.efficiency, 0.0, "no work on the rock");
    // The bit touches the rock while moving down: its little work is all axial here.
    assert!((0.0..=1.0).contains(&m.axial_power_share));
    // A bit at rest axially: no fluctuation at all.
    let mut still = off_bottom(&t);
    still.bit_velocity = vec![0.0; t.len()];
    let m = compute(&still, &config).unwrap();
    assert_eq!(m.axial_velocity_fluctuation, 0.0);
    // A negative feed is still refused.
    let bad = MetricsConfig::new(OMEGA, -1e-6, 0.1, 1.0);
    assert!(matches!(
        bad.validate(),
        Err(MetricsError::InvalidConfig { field: "v0", .. })
    ));
}
