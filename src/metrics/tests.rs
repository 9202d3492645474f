//! Metrics against hand-computed values on small synthetic series with uneven time steps.

use super::*;
use approx::assert_relative_eq;
use std::f64::consts::PI;

const OMEGA: f64 = 10.0;
const V0: f64 = 0.01;
const R_BH: f64 = 0.1;
/// Uneven steps: 0.1, 0.15, 0.05, 0.4, 0.3, 0.6, 0.4.
const UNEVEN: [f64; 8] = [0.0, 0.1, 0.25, 0.3, 0.7, 1.0, 1.6, 2.0];

/// The raw bit speed (no averaging): the formulas on exact synthetic signals.
fn config(settling_time: f64) -> MetricsConfig {
    MetricsConfig {
        speed_average: 0.0,
        ..MetricsConfig::new(OMEGA, V0, R_BH, settling_time)
    }
}

#[test]
fn averaged_speed_removes_a_spike_and_keeps_a_slow_oscillation() {
    // θ̇ = Ω (1 + a sin(2π t / P)) with P ≫ τ, plus a spike of height 3Ω and width w ≪ τ at
    // t = 1.2 s. The τ-average of the sine is Ω (1 + a sinc-weighted sine): its extremes are
    // Ω (1 ± a sin(πτ/P)/(πτ/P)); the spike adds at most 3Ω w / τ to the average.
    let (a, period, tau, w) = (0.5, 0.5, 0.01, 1e-4);
    let n = 200_000;
    let t: Vec<f64> = (0..=n).map(|i| 2.0 * i as f64 / n as f64).collect();
    let mut s = steady(&t);
    let spike = |t: f64| {
        if (t - 1.2).abs() < 0.5 * w {
            3.0 * OMEGA
        } else {
            0.0
        }
    };
    s.bit_angular_velocity = t
        .iter()
        .map(|&t| OMEGA * (1.0 + a * (2.0 * PI * t / period).sin()) + spike(t))
        .collect();
    // θ(t) = ∫ θ̇: exact for the sine, the spike's area 3Ω w added once it has passed.
    s.bit_rotation = t
        .iter()
        .map(|&t| {
            let sine =
                OMEGA * (t - a * period / (2.0 * PI) * ((2.0 * PI * t / period).cos() - 1.0));
            let passed = ((t - (1.2 - 0.5 * w)) / w).clamp(0.0, 1.0);
            sine + 3.0 * OMEGA * w * passed
        })
        .collect();
    let raw = compute(&s, &config(0.1)).unwrap();
    assert!(
        raw.max_bit_speed_ratio > 3.5,
        "the raw speed sees the spike"
    );
    let cfg = MetricsConfig {
        speed_average: tau,
        ..config(0.1)
    };
    let m = compute(&s, &cfg).unwrap();
    // The raw SSI (MODEL.md §8 on the raw speed) keeps the spike whatever the averaging.
    assert!(
        m.stick_slip_severity_raw > 1.4,
        "{}",
        m.stick_slip_severity_raw
    );
    assert_eq!(m.stick_slip_severity_raw, raw.stick_slip_severity);
    let x = PI * tau / period;
    let amplitude = a * x.sin() / x;
    assert_relative_eq!(m.stick_slip_severity, amplitude, max_relative = 2e-3);
    assert!(m.max_bit_speed_ratio <= 1.0 + amplitude + 3.0 * w / tau + 1e-6);
    assert!(m.max_bit_speed_ratio >= 1.0 + amplitude - 1e-3);
}

/// A bit drilling steadily, sampled at `t`: u = 0.3 + V0 t, θ̇ = Ω, constant WOB and TOB, no wall
/// contact, all energies and works zero.
fn steady(t: &[f64]) -> TimeSeries {
    let n = t.len();
    let c = |v: f64| vec![v; n];
    TimeSeries {
        t: t.to_vec(),
        bit_displacement: t.iter().map(|&t| 0.3 + V0 * t).collect(),
        bit_velocity: c(V0),
        bit_rotation: t.iter().map(|&t| OMEGA * t).collect(),
        bit_angular_velocity: c(OMEGA),
        weight_on_bit: c(2.0e4),
        torque_on_bit: c(1.5e3),
        top_force: c(2.0e4),
        top_torque: c(1.5e3),
        probe_positions: vec![20.0],
        probe_radial: vec![c(0.01)],
        nodes_in_contact: vec![0; n],
        contact_onsets: vec![0; n],
        wall_force_total: c(0.0),
        wall_force_max: c(0.0),
        max_radial_over_gap: c(0.5),
        kinetic_energy: c(0.0),
        potential_energy: c(0.0),
        work_top: c(0.0),
        work_bit: c(0.0),
        dissipated: c(0.0),
        block_speed: c(V0),
    }
}

#[test]
fn constant_velocity_bit() {
    let m = compute(&steady(&UNEVEN), &config(0.2)).unwrap();
    assert_relative_eq!(m.mean_rop_m_s, V0, max_relative = 1e-12);
    assert_relative_eq!(m.mean_rop_m_per_h, 36.0, max_relative = 1e-12);
    assert_eq!(m.stick_slip_severity, 0.0);
    assert_eq!(m.stick_fraction, 0.0);
    assert_relative_eq!(m.max_bit_speed_ratio, 1.0, max_relative = 1e-15);
    assert_eq!(m.bit_bounce_fraction, 0.0);
    assert_relative_eq!(m.axial_velocity_fluctuation, 0.0, epsilon = 1e-12);
    assert_relative_eq!(m.mean_wob_n, 2.0e4, max_relative = 1e-14);
    assert_relative_eq!(m.mean_tob_nm, 1.5e3, max_relative = 1e-14);
    assert_eq!(m.impacts_per_s, 0.0);
    assert_eq!(m.contact_impulse_ns, 0.0);
    assert_eq!(m.max_radial_over_gap, 0.5);
    assert_eq!(m.efficiency, 0.0);
    assert_eq!(m.energy_balance_residual, 0.0);
}

#[test]
fn window_starts_at_first_sample_at_or_after_settling_time() {
    let mut s = steady(&UNEVEN);
    s.bit_displacement = UNEVEN.iter().map(|&t| t * t).collect();
    // t0 = 0.2 falls between samples: the window starts at t = 0.25 (u = 0.0625), not at an
    // interpolated u(0.2) = 0.045 (which would give 3.955 / 1.8 = 2.197…).
    let m = compute(&s, &config(0.2)).unwrap();
    assert_relative_eq!(m.mean_rop_m_s, (4.0 - 0.0625) / 1.75, max_relative = 1e-14);
    // t0 = 0.3 is a sample: it belongs to the window.
    let m = compute(&s, &config(0.3)).unwrap();
    assert_relative_eq!(m.mean_rop_m_s, (4.0 - 0.09) / 1.7, max_relative = 1e-14);
    // The window is measured from t[0], not from t = 0.
    let shifted: Vec<f64> = UNEVEN.iter().map(|&t| t + 100.0).collect();
    s.t = shifted;
    let m = compute(&s, &config(0.2)).unwrap();
    assert_relative_eq!(m.mean_rop_m_s, (4.0 - 0.0625) / 1.75, max_relative = 1e-12);
}

#[test]
fn time_means_weight_by_uneven_steps() {
    let t = [0.0, 1.0, 4.0];
    let mut s = steady(&t);
    s.weight_on_bit = vec![2.0, 4.0, 10.0];
    s.torque_on_bit = vec![-1.0, 1.0, 3.0];
    s.bit_velocity = vec![0.0, 0.04, 0.01];
    let m = compute(&s, &config(0.0)).unwrap();
    // (1·3 + 3·7)/4 = 6 (a sample mean would give 16/3).
    assert_relative_eq!(m.mean_wob_n, 6.0, max_relative = 1e-15);
    // (1·0 + 3·2)/4 = 1.5 (a sample mean would give 1).
    assert_relative_eq!(m.mean_tob_nm, 1.5, max_relative = 1e-15);
    // mean u̇ = 0.02375; ∫(u̇ − mean)² dt = 10.9375e-4 m²/s; std = √(10.9375e-4 / 4); ÷ V0.
    assert_relative_eq!(
        m.axial_velocity_fluctuation,
        (10.9375e-4f64 / 4.0).sqrt() / V0,
        max_relative = 1e-13
    );
}

/// Uneven grid of n + 1 points on [0, T]: t = T (s + 0.3 sin(6π s)/(6π)), s = i/n, so the step
/// varies between 0.7 and 1.3 times T/n.
fn uneven_grid(n: usize, duration: f64) -> Vec<f64> {
    let k = 6.0 * PI;
    (0..=n)
        .map(|i| {
            let s = i as f64 / n as f64;
            duration * (s + 0.3 * (k * s).sin() / k)
        })
        .collect()
}

#[test]
fn sinusoidal_bit_speed() {
    // θ̇ = Ω (1 + a sin(2π t / P)) over 5 whole periods. θ̇ < c Ω ⇔ sin φ < −(1 − c)/a, which holds
    // for a share 1/2 − asin((1 − c)/a)/π of each period (0 if (1 − c)/a ≥ 1). With the
    // trapezoid rule on the indicator each of the 10 crossings errs by at most half a step
    // (≤ 0.65 T/n), so the share errs by at most 6.5/n = 3.25e-4 for n = 20 000.
    let n = 20_000;
    let period = 0.5;
    let t = uneven_grid(n, 5.0 * period);
    for (a, c) in [(0.5, 0.1), (0.95, 0.1), (1.2, 0.1), (0.95, 0.5)] {
        let mut s = steady(&t);
        s.bit_angular_velocity = t
            .iter()
            .map(|&t| OMEGA * (1.0 + a * (2.0 * PI * t / period).sin()))
            .collect();
        let cfg = MetricsConfig {
            stick_threshold: c,
            ..config(0.0)
        };
        let m = compute(&s, &cfg).unwrap();
        assert_relative_eq!(m.stick_slip_severity, a, max_relative = 1e-5);
        assert_relative_eq!(m.max_bit_speed_ratio, 1.0 + a, max_relative = 1e-5);
        let x: f64 = (1.0 - c) / a;
        let expected = if x >= 1.0 { 0.0 } else { 0.5 - x.asin() / PI };
        assert!(
            (m.stick_fraction - expected).abs() < 3.25e-4,
            "a = {a}, c = {c}: stick fraction {} vs analytic {expected}",
            m.stick_fraction
        );
    }
}

#[test]
fn default_stick_threshold_is_a_tenth_of_omega() {
    assert_eq!(config(0.0).stick_threshold, 0.1);
    // θ̇ = 0.09 Ω is stuck, 0.11 Ω is not.
    let t = [0.0, 1.0, 3.0, 3.5];
    let mut s = steady(&t);
    s.bit_angular_velocity = vec![0.09 * OMEGA, 0.09 * OMEGA, 0.11 * OMEGA, 0.11 * OMEGA];
    let m = compute(&s, &config(0.0)).unwrap();
    // [0,1] stuck, [1,3] half, [3,3.5] free → 2 / 3.5.
    assert_relative_eq!(m.stick_fraction, 2.0 / 3.5, max_relative = 1e-15);
    assert_relative_eq!(m.stick_slip_severity, 0.01, max_relative = 1e-12);
}

#[test]
fn piecewise_bounce() {
    let t = [0.0, 0.5, 1.0, 1.2, 2.0, 2.3, 3.0, 4.0];
    let mut s = steady(&t);
    s.weight_on_bit = [5.0, 5.0, 0.0, 0.0, 0.0, 5.0, 5.0, 5.0]
        .iter()
        .map(|w| w * 1e3)
        .collect();
    let m = compute(&s, &config(0.0)).unwrap();
    // Off bottom: [0.5,1] half (0.25) + [1,1.2] (0.2) + [1.2,2] (0.8) + [2,2.3] half (0.15).
    assert_relative_eq!(m.bit_bounce_fraction, 1.4 / 4.0, max_relative = 1e-14);
    // ∫ WOB dt = (2.5 + 1.25 + 0 + 0 + 0.75 + 3.5 + 5) kN·s = 13 kN·s over 4 s.
    assert_relative_eq!(m.mean_wob_n, 3.25e3, max_relative = 1e-14);
    // Window from t = 1.2: [1.2,2] (0.8) + [2,2.3] half (0.15) over 2.8 s.
    let m = compute(&s, &config(1.1)).unwrap();
    assert_relative_eq!(m.bit_bounce_fraction, 0.95 / 2.8, max_relative = 1e-14);
}

#[test]
fn contacts_counted_inside_the_window_only() {
    let t = [0.0, 1.0, 2.0, 2.5, 3.0, 4.0, 5.0];
    let mut s = steady(&t);
    s.contact_onsets = vec![0, 3, 7, 8, 10, 10, 15];
    s.wall_force_max = vec![900.0, 50.0, 10.0, 20.0, 70.0, 30.0, 0.0];
    s.wall_force_total = vec![1000.0, 60.0, 10.0, 20.0, 100.0, 40.0, 0.0];
    s.max_radial_over_gap = vec![1.3, 0.9, 0.9, 0.8, 1.05, 0.7, 0.6];
    // t0 = 2.2: the window is [2.5, 5].
    let m = compute(&s, &config(2.2)).unwrap();
    assert_relative_eq!(m.impacts_per_s, (15.0 - 8.0) / 2.5, max_relative = 1e-15);
    assert_eq!(m.peak_wall_force_n, 70.0);
    // 0.5·(20+100)/2 + 1·(100+40)/2 + 1·(40+0)/2 = 30 + 70 + 20.
    assert_relative_eq!(m.contact_impulse_ns, 120.0, max_relative = 1e-15);
    assert_eq!(m.max_radial_over_gap, 1.05);
    // The whole run counts the early contacts too.
    let m = compute(&s, &config(0.0)).unwrap();
    assert_relative_eq!(m.impacts_per_s, 3.0, max_relative = 1e-15);
    assert_eq!(m.peak_wall_force_n, 900.0);
    assert_eq!(m.max_radial_over_gap, 1.3);
}

#[test]
fn mechanical_specific_energy() {
    let mut s = steady(&UNEVEN);
    s.weight_on_bit = vec![1.0e5; UNEVEN.len()];
    s.torque_on_bit = vec![2.0e3; UNEVEN.len()];
    let cfg = MetricsConfig::new(12.0, V0, 0.1, 0.2);
    let m = compute(&s, &cfg).unwrap();
    // A_b = 0.01π m²; N = 12/(2π) rev/s; ROP = 0.01 m/s:
    // 1e5/(0.01π) + 2π·(12/2π)·2000/(0.01π·0.01) = (1e5 + 2.4e6)/(0.01π) = 2.5e8/π Pa.
    assert_relative_eq!(m.mse_pa, 79_577_471.545_947_67, max_relative = 1e-13);
}

#[test]
fn mse_is_infinite_when_the_bit_does_not_advance_and_serializes_as_null() {
    let mut s = steady(&UNEVEN);
    s.bit_displacement = vec![0.3; UNEVEN.len()];
    let m = compute(&s, &config(0.0)).unwrap();
    assert_eq!(m.mean_rop_m_s, 0.0);
    assert_eq!(m.mse_pa, f64::INFINITY);
    let json = serde_json::to_value(&m).unwrap();
    assert!(json["mse_pa"].is_null());
    // Backwards: still infinite, not negative.
    s.bit_displacement = UNEVEN.iter().map(|&t| 1.0 - t).collect();
    let m = compute(&s, &config(0.0)).unwrap();
    assert_relative_eq!(m.mean_rop_m_s, -1.0, max_relative = 1e-15);
    assert_eq!(m.mse_pa, f64::INFINITY);
}

#[test]
fn efficiency_from_cumulative_work_over_the_window() {
    let t = [0.0, 1.0, 2.0, 3.0];
    let mut s = steady(&t);
    s.work_top = vec![0.0, 10.0, 30.0, 60.0];
    s.work_bit = vec![0.0, -2.0, -10.0, -22.0];
    // Window from t = 1: 20 J to the rock over 50 J in (the whole run would give 22/60).
    let m = compute(&s, &config(0.5)).unwrap();
    assert_relative_eq!(m.efficiency, 0.4, max_relative = 1e-15);
    // The string stores 10 J over the window (kinetic +4 J, potential +6 J): those were not
    // spent, so 20 J of 40 J reached the rock.
    s.kinetic_energy = vec![1.0, 1.0, 3.0, 5.0];
    s.potential_energy = vec![2.0, 2.0, 5.0, 8.0];
    assert_relative_eq!(
        compute(&s, &config(0.5)).unwrap().efficiency,
        0.5,
        max_relative = 1e-15
    );
    // Released energy counts as spent: a string that gives back 30 J of its storage while the
    // top does 50 J delivers 20 J of 80 J.
    s.kinetic_energy = vec![31.0, 31.0, 10.0, 1.0];
    s.potential_energy = vec![0.0; 4];
    assert_relative_eq!(
        compute(&s, &config(0.5)).unwrap().efficiency,
        0.25,
        max_relative = 1e-15
    );
    s.kinetic_energy = vec![0.0; 4];
    // No positive top work: 0, not NaN or ±∞.
    s.work_top = vec![5.0; 4];
    assert_eq!(compute(&s, &config(0.5)).unwrap().efficiency, 0.0);
    s.work_top = vec![0.0, 0.0, -1.0, -3.0];
    assert_eq!(compute(&s, &config(0.5)).unwrap().efficiency, 0.0);
}

/// ∫ WOB u̇ / ∫ (WOB u̇ + TOB θ̇): constant loads and speeds give WOB V / (WOB V + TOB Ω).
#[test]
fn axial_power_share_of_the_bit_work() {
    let t = [0.0, 1.0, 2.0, 3.0];
    let mut s = steady(&t);
    s.weight_on_bit = vec![50e3; 4];
    s.bit_velocity = vec![1e-3; 4];
    s.torque_on_bit = vec![2e3; 4];
    s.bit_angular_velocity = vec![6.0; 4];
    let m = compute(&s, &config(0.0)).unwrap();
    assert_relative_eq!(
        m.axial_power_share,
        50.0 / (50.0 + 12e3),
        max_relative = 1e-14
    );
    // Off bottom: no bit work, share 0 (not NaN).
    s.weight_on_bit = vec![0.0; 4];
    s.torque_on_bit = vec![0.0; 4];
    assert_eq!(compute(&s, &config(0.0)).unwrap().axial_power_share, 0.0);
}

#[test]
fn energy_balance_residual_over_the_whole_run() {
    let t = [0.0, 1.0, 2.0, 3.0];
    let mut s = steady(&t);
    s.work_top = vec![5.0, 45.0, 75.0, 105.0];
    s.work_bit = vec![0.0, -5.0, -15.0, -20.0];
    s.kinetic_energy = vec![1.0, 11.0, 6.0, 9.0];
    s.potential_energy = vec![100.0, 120.0, 130.0, 140.0];
    s.dissipated = vec![0.0, 10.0, 20.0, 32.0];
    // W_in = 100 − 20 = 80 J = ΔE_k 8 + ΔE_p 40 + ΔD 32.
    let m = compute(&s, &config(1.5)).unwrap();
    assert_relative_eq!(m.energy_balance_residual, 0.0, epsilon = 1e-15);
    // 4 J go missing in the first step, before the window [2, 3] (which on its own balances:
    // 25 J in = 3 + 10 + 12): the residual is taken from sample 0 and relative to the gross flow,
    // the 100 J put in by the top drive (not the net 80 J), so it is 4/100.
    s.dissipated = vec![0.0, 6.0, 16.0, 28.0];
    let m = compute(&s, &config(1.5)).unwrap();
    assert_relative_eq!(m.energy_balance_residual, 0.04, max_relative = 1e-14);
    // Too much stored counts the same as too little.
    s.dissipated = vec![0.0, 14.0, 24.0, 36.0];
    let m = compute(&s, &config(1.5)).unwrap();
    assert_relative_eq!(m.energy_balance_residual, 0.04, max_relative = 1e-14);
}

#[test]
fn energy_balance_residual_without_input_is_finite() {
    let mut s = steady(&UNEVEN);
    assert_eq!(
        compute(&s, &config(0.0)).unwrap().energy_balance_residual,
        0.0
    );
    // No input but 1e-15 J of imbalance: divided by the floor, not by zero.
    s.kinetic_energy[UNEVEN.len() - 1] = 1e-15;
    let r = compute(&s, &config(0.0)).unwrap().energy_balance_residual;
    assert_relative_eq!(r, 1e-15 / ENERGY_FLOOR_J, max_relative = 1e-12);
}

#[test]
fn serializes_with_exactly_the_documented_keys() {
    // The stress metrics come from the run's envelope: NaN (null in JSON) without one.
    let bare = serde_json::to_value(compute(&steady(&UNEVEN), &config(0.0)).unwrap()).unwrap();
    assert!(bare["max_von_mises_pa"].is_null());
    let mut envelope = crate::sim::StressEnvelope::new(2, 1.0, 0.0);
    envelope.max_von_mises_pa = vec![1e8, 3e8];
    envelope.max_compression_n = vec![5e4, 4e4];
    envelope.max_torque_nm = vec![2e3, 3e3];
    envelope.fatigue_damage_per_h = vec![2e-4, 1e-4];
    envelope.buckling = Some(crate::model::BucklingLoads {
        weight_per_length: 500.0,
        clearance: 0.01,
        sinusoidal: 1e5,
        helical: 1e5 * std::f64::consts::SQRT_2,
    });
    envelope.buckling_utilization = vec![0.5, 0.4];
    let m = compute(&steady(&UNEVEN), &config(0.0))
        .unwrap()
        .with_stresses(&envelope, Some(930e6));
    // Fatigue and buckling: the worst section and where (element midpoints 0.5 and 1.5 m).
    assert_eq!((m.fatigue_damage_per_h, m.fatigue_worst_at_m), (2e-4, 0.5));
    assert!((m.fatigue_life_h - 5000.0).abs() < 1e-9);
    assert_eq!((m.buckling_utilization, m.buckling_at_m), (0.5, 0.5));
    assert!((m.buckling_margin - 0.5).abs() < 1e-15);
    assert!((m.helical_buckling_utilization - 0.5 / std::f64::consts::SQRT_2).abs() < 1e-15);
    assert_eq!(
        (
            m.max_von_mises_pa,
            m.max_von_mises_at_m,
            m.max_compression_n,
            m.max_torque_nm
        ),
        (3e8, 1.5, 5e4, 3e3)
    );
    assert!((m.von_mises_safety_factor - 3.1).abs() < 1e-12);
    assert!((m.von_mises_utilization - 3e8 / 930e6).abs() < 1e-15);
    let m = m.with_critical_speed_margin(0.25);
    assert_eq!(
        (m.critical_speed_margin, m.critical_speed_proximity),
        (0.25, 4.0)
    );
    let m = m.with_bit_damping_ratio(0.34);
    assert_eq!(m.bit_damping_ratio, 0.34);
    let m = m.with_steady_state(Some(crate::sim::SteadyStability {
        growth_rate_per_s: -0.5,
        frequency_hz: 3.0,
    }));
    assert_eq!(m.steady_growth_rate_per_s, -0.5);
    let json = serde_json::to_value(&m).unwrap();
    let mut keys: Vec<&str> = json
        .as_object()
        .unwrap()
        .keys()
        .map(String::as_str)
        .collect();
    keys.sort_unstable();
    // The catalogue the problem files' risk terms and chance constraints are validated against.
    let mut expected: Vec<&str> = super::catalogue::keys().collect();
    expected.sort_unstable();
    assert_eq!(keys, expected);
    assert!(json.as_object().unwrap().values().all(|v| v.is_f64()));
}

/// No damage anywhere: an infinite life (null in JSON) and no worst section.
#[test]
fn zero_fatigue_damage_is_an_infinite_life_without_a_worst_section() {
    let mut envelope = crate::sim::StressEnvelope::new(2, 1.0, 0.0);
    envelope.fatigue_damage_per_h = vec![0.0, 0.0];
    let m = compute(&steady(&UNEVEN), &config(0.0))
        .unwrap()
        .with_stresses(&envelope, None);
    assert_eq!(m.fatigue_damage_per_h, 0.0);
    assert_eq!(m.fatigue_life_h, f64::INFINITY);
    assert!(m.fatigue_worst_at_m.is_nan());
    assert!(
        m.buckling_utilization.is_nan(),
        "no buckling loads: undefined"
    );
}

// ---- refusals ----

#[test]
fn refuses_an_empty_series() {
    assert_eq!(
        compute(&TimeSeries::default(), &config(0.0)),
        Err(MetricsError::EmptySeries)
    );
}

#[test]
fn refuses_channels_of_unequal_length() {
    let mut s = steady(&UNEVEN);
    s.torque_on_bit.pop();
    assert_eq!(
        compute(&s, &config(0.0)),
        Err(MetricsError::LengthMismatch {
            channel: "torque_on_bit".into(),
            len: 7,
            expected: 8
        })
    );
    let mut s = steady(&UNEVEN);
    s.contact_onsets.push(0);
    let err = compute(&s, &config(0.0)).unwrap_err();
    assert_eq!(
        err,
        MetricsError::LengthMismatch {
            channel: "contact_onsets".into(),
            len: 9,
            expected: 8
        }
    );
    assert!(err.to_string().contains("`contact_onsets` has 9 samples"));
    let mut s = steady(&UNEVEN);
    s.probe_radial[0].truncate(3);
    assert!(matches!(
        compute(&s, &config(0.0)),
        Err(MetricsError::LengthMismatch { channel, len: 3, .. }) if channel == "probe_radial[0]"
    ));
}

#[test]
fn refuses_non_finite_samples_naming_channel_and_time() {
    let mut s = steady(&UNEVEN);
    s.bit_velocity[4] = f64::NAN;
    let err = compute(&s, &config(0.0)).unwrap_err();
    assert!(matches!(
        &err,
        MetricsError::NonFinite { channel, index: 4, time, .. }
            if channel == "bit_velocity" && *time == 0.7
    ));
    assert!(err.to_string().contains("`bit_velocity`"));
    assert!(err.to_string().contains("t = 0.7 s"));
    // Before the window still counts: a run that blew up is refused as a whole.
    let mut s = steady(&UNEVEN);
    s.work_top[1] = f64::INFINITY;
    assert!(matches!(
        compute(&s, &config(1.0)),
        Err(MetricsError::NonFinite { channel, index: 1, time, .. })
            if channel == "work_top" && time == 0.1
    ));
}

#[test]
fn refuses_times_that_do_not_increase() {
    let mut s = steady(&UNEVEN);
    s.t[3] = s.t[2];
    assert_eq!(
        compute(&s, &config(0.0)),
        Err(MetricsError::TimeNotIncreasing {
            index: 3,
            time: 0.25,
            previous: 0.25
        })
    );
}

#[test]
fn refuses_a_window_with_fewer_than_two_samples() {
    let s = steady(&UNEVEN);
    let err = compute(&s, &config(1.9)).unwrap_err();
    assert_eq!(
        err,
        MetricsError::WindowTooShort {
            settling_time: 1.9,
            run_length: 2.0,
            samples: 1
        }
    );
    let text = err.to_string();
    assert!(text.contains("settling time of 1.9 s") && text.contains("lasts only 2 s"));
    assert!(matches!(
        compute(&s, &config(5.0)),
        Err(MetricsError::WindowTooShort { samples: 0, .. })
    ));
    // A single sample cannot make a window whatever the settling time.
    assert!(matches!(
        compute(&steady(&[0.0]), &config(0.0)),
        Err(MetricsError::WindowTooShort { samples: 1, .. })
    ));
    // The last two samples are enough.
    assert!(compute(&s, &config(1.6)).is_ok());
}

#[test]
fn refuses_an_invalid_configuration() {
    let s = steady(&UNEVEN);
    let bad = [
        ("omega", MetricsConfig::new(0.0, V0, R_BH, 0.0)),
        ("v0", MetricsConfig::new(OMEGA, -1.0, R_BH, 0.0)),
        (
            "borehole_radius",
            MetricsConfig::new(OMEGA, V0, f64::NAN, 0.0),
        ),
        ("settling_time", MetricsConfig::new(OMEGA, V0, R_BH, -0.1)),
        (
            "stick_threshold",
            MetricsConfig {
                stick_threshold: 1.0,
                ..config(0.0)
            },
        ),
        (
            "speed_average",
            MetricsConfig {
                speed_average: -0.01,
                ..config(0.0)
            },
        ),
    ];
    for (name, cfg) in bad {
        assert!(
            matches!(
                compute(&s, &cfg),
                Err(MetricsError::InvalidConfig { field, .. }) if field == name
            ),
            "{name} should be refused"
        );
    }
}

/// Batch means of a linear trend WOB = a + b t over [0, 10] s: batch j has mean a + b (j + ½),
/// so the interval is centred on a + 5b with half-width t₀.₉₇₅,₉ · b · sd(0..9) / √10.
#[test]
fn batch_means_of_a_linear_trend() {
    let n = 10_001;
    let t: Vec<f64> = (0..n).map(|i| 10.0 * i as f64 / (n - 1) as f64).collect();
    let mut s = steady(&t);
    let (a, b) = (50e3, 1e3);
    s.weight_on_bit = t.iter().map(|&t| a + b * t).collect();
    let ci = super::batch_means(&s, &config(0.0)).unwrap();
    let wob = ci["mean_wob_n"];
    assert_relative_eq!(wob.mean, a + 5.0 * b, max_relative = 1e-9);
    let sd = (0..10).map(|j| (j as f64 - 4.5).powi(2)).sum::<f64>() / 9.0;
    let expected = 2.262_157 * b * sd.sqrt() / 10f64.sqrt();
    assert_relative_eq!(wob.half_width, expected, max_relative = 1e-6);
    // A steady channel has no width (round-off only).
    let rop = ci["mean_rop_m_per_h"];
    assert!(rop.half_width < 1e-12 * rop.mean, "{rop:?}");
}

/// `named_values` lists every field under its serde name, in order, and keeps ±∞.
#[test]
fn named_values_match_the_serialised_keys_and_keep_infinity() {
    let t = [0.0, 1.0, 2.0];
    let mut s = steady(&t);
    s.bit_displacement = vec![0.0; 3]; // no progress: MSE = +∞
    let m = compute(&s, &config(0.0)).unwrap();
    assert_eq!(m.mse_pa, f64::INFINITY);
    let json = serde_json::to_value(&m).unwrap();
    let keys: Vec<&str> = json
        .as_object()
        .unwrap()
        .keys()
        .map(|k| k.as_str())
        .collect();
    let named = m.named_values();
    let mut names: Vec<&str> = named.iter().map(|(k, _)| *k).collect();
    names.sort();
    let mut sorted = keys.clone();
    sorted.sort();
    assert_eq!(names, sorted);
    let mse = named.iter().find(|(k, _)| *k == "mse_pa").unwrap().1;
    assert_eq!(mse, f64::INFINITY);
    let map = crate::study::metric_map(&m);
    assert_eq!(map["mse_pa"], f64::INFINITY);
}

/// Beyond the two-pass cap the window keeps no velocities: the one-pass sums, shifted by the
/// first velocity, give the same deviation (equal in exact arithmetic) on a long uneven series
/// whose fluctuation is small beside its mean (the case a plain sum of squares would lose).
#[test]
fn the_one_pass_deviation_beyond_the_cap_equals_the_two_pass_one() {
    let t = uneven_grid(4001, 40.0);
    let mut s = steady(&t);
    s.bit_velocity = t
        .iter()
        .map(|&t| V0 * (1.0 + 1e-3 * (7.0 * t).sin() + 2e-4 * (31.0 * t).cos()))
        .collect();
    let two_pass = compute(&s, &config(5.0)).unwrap();
    let mut online = online::OnlineMetrics::new(config(5.0), f64::NAN)
        .unwrap()
        .with_two_pass_cap(100);
    feed(&s, &mut online);
    let one_pass = online.metrics().unwrap();
    assert!(two_pass.axial_velocity_fluctuation > 5e-4);
    assert_relative_eq!(
        one_pass.axial_velocity_fluctuation,
        two_pass.axial_velocity_fluctuation,
        max_relative = 1e-9
    );
    // Everything else is untouched by the cap.
    assert_eq!(one_pass.mean_rop_m_s, two_pass.mean_rop_m_s);
    assert_eq!(one_pass.mean_wob_n, two_pass.mean_wob_n);
}
