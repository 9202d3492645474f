//! The metric catalogue: one row ([`MetricSpec`]) per metric of [`Metrics`](super::Metrics), in
//! the order of `summary.json`. `summary.json`'s keys, the terminal's names and units, the CSV
//! columns, the metric names and threshold units of risk terms and chance constraints, the
//! metrics `verify` and `solve`'s numerical check compare, and the batch-means intervals all read
//! it.
//!
//! A new metric is a field of [`Metrics`](super::Metrics) with its computation, and one row here
//! (`tests_catalogue.rs` checks that the two agree).
//!
//! Floors of the relative change under refinement (`verify`) are in the metric's unit: a value
//! below its floor is judged by its absolute change. Those of the metrics compared only when a
//! problem uses them: a share of time below 5 % (as the stick fraction), a radial displacement
//! below 5 % of the gap, a contact impulse below 1 kN·s (the 1 kN floor of the wall force over a
//! second), a ratio below 0.01, an energy-balance residual below 0.1 % are judged absolutely.

use super::spec::{Direction::*, MetricClass, MetricClass::*, MetricSpec, Source, Verification::*};
use crate::units::Dimension::*;
use crate::units::M_PER_H_PER_M_PER_S;

/// Seconds per hour: the unit of the keys that name hours.
const S_PER_H: f64 = 3600.0;
/// The mean loads and ROP that MSE (Teale 1965) is computed from, and that the drilling
/// efficiency's works rest on.
const MECHANICS: &[&str] = &["mean_rop_m_per_h", "mean_wob_n", "mean_tob_nm"];
const VON_MISES: &[&str] = &["max_von_mises_pa"];
const FATIGUE: &[&str] = &["fatigue_damage_per_h"];
const BUCKLING: &[&str] = &["buckling_utilization"];

/// Every metric of `summary.json`, in its order (see [`MetricSpec`] for the columns).
pub const METRICS: &[MetricSpec] = &[
    MetricSpec::new("mean_rop_m_s", Velocity, Through, |m| m.mean_rop_m_s)
        .shown("mean ROP", "m/h", M_PER_H_PER_M_PER_S)
        .direction(Better)
        .derives_from(&["mean_rop_m_per_h"]),
    MetricSpec::new("mean_rop_m_per_h", Velocity, Always(Mean, 0.01), |m| {
        m.mean_rop_m_per_h
    })
    .in_unit("m/h", S_PER_H)
    .shown("mean ROP", "m/h", 1.0)
    .direction(Better)
    .batch_interval(),
    MetricSpec::new(
        "stick_slip_severity",
        Dimensionless,
        Always(StickSlip, 0.1),
        |m| m.stick_slip_severity,
    )
    .shown("stick-slip severity (10 ms average)", "", 1.0)
    .direction(Worse),
    MetricSpec::new(
        "stick_slip_severity_raw",
        Dimensionless,
        WhenUsed(StickSlip, 0.1),
        |m| m.stick_slip_severity_raw,
    )
    .shown("stick-slip severity (raw bit speed)", "", 1.0)
    .direction(Worse),
    MetricSpec::new("stick_fraction", Dimensionless, Always(StickSlip, 0.05), |m| {
        m.stick_fraction
    })
    .shown("time stuck", "%", 100.0)
    .direction(Worse)
    .batch_interval(),
    MetricSpec::new(
        "max_bit_speed_ratio",
        Dimensionless,
        Always(StickSlip, 1.0),
        |m| m.max_bit_speed_ratio,
    )
    .shown("peak bit speed / \u{3a9}", "", 1.0)
    .direction(Worse),
    MetricSpec::new(
        "bit_bounce_fraction",
        Dimensionless,
        WhenUsed(StickSlip, 0.05),
        |m| m.bit_bounce_fraction,
    )
    .shown("time off bottom (bit-bounce)", "%", 100.0)
    .direction(Worse)
    .batch_interval(),
    MetricSpec::new(
        "axial_velocity_fluctuation",
        Dimensionless,
        WhenUsed(StickSlip, 0.1),
        |m| m.axial_velocity_fluctuation,
    )
    .shown("axial velocity fluctuation / V0", "", 1.0)
    .direction(Worse),
    // An impact rate below 1 per second is a rare event whose count moves with any perturbation
    // of the trajectory; a wall force below 1 kN is the weight of a few metres of pipe. Impacts
    // and contact peaks come from the free spans between supports, which a basis without the
    // string's resting shape does not hold still (issue 11: the seed's lowest 51 modes gave 952
    // impacts/s, the finite-element model none).
    MetricSpec::new("impacts_per_s", Rate, WhenUsed(Peak, 1.0), |m| m.impacts_per_s)
        .shown("wall impacts", "1/s", 1.0)
        .direction(Worse)
        .batch_interval(),
    MetricSpec::new("peak_wall_force_n", Force, WhenUsed(Peak, 1000.0), |m| {
        m.peak_wall_force_n
    })
    .shown("peak wall force", "kN", 1e-3)
    .direction(Worse),
    MetricSpec::new("contact_impulse_ns", Impulse, WhenUsed(Peak, 1000.0), |m| {
        m.contact_impulse_ns
    })
    .shown("wall contact impulse", "kN\u{b7}s", 1e-3)
    .direction(Worse),
    MetricSpec::new(
        "max_radial_over_gap",
        Dimensionless,
        WhenUsed(Peak, 0.05),
        |m| m.max_radial_over_gap,
    )
    .shown("peak radial displacement / gap", "", 1.0)
    .direction(Worse),
    MetricSpec::new("mean_wob_n", Force, Always(Mean, 100.0), |m| m.mean_wob_n)
        .shown("mean WOB", "kN", 1e-3)
        .batch_interval(),
    MetricSpec::new("mean_tob_nm", Torque, Always(Mean, 10.0), |m| m.mean_tob_nm)
        .shown("mean TOB", "kN\u{b7}m", 1e-3)
        .batch_interval(),
    MetricSpec::new("mse_pa", Pressure, Always(Mean, 1e6), |m| m.mse_pa)
        .shown("mechanical specific energy", "MPa", 1e-6)
        .direction(Worse)
        .derives_from(MECHANICS),
    MetricSpec::new("efficiency", Dimensionless, WhenUsed(Mean, 0.01), |m| {
        m.efficiency
    })
    .shown("drilling efficiency", "", 1.0)
    .direction(Better)
    .derives_from(MECHANICS),
    MetricSpec::new(
        "axial_power_share",
        Dimensionless,
        WhenUsed(Mean, 0.01),
        |m| m.axial_power_share,
    )
    .shown("axial power share", "", 1.0)
    .direction(Better)
    .batch_interval(),
    MetricSpec::new(
        "energy_balance_residual",
        Dimensionless,
        WhenUsed(Peak, 1e-3),
        |m| m.energy_balance_residual,
    )
    .shown("energy balance residual", "", 1.0)
    .direction(Worse),
    // Stresses are recovered from the basis by mode displacement and converge more slowly than
    // the motion (on the seed at 60 rpm the basis ×1.5 moves the peak 10.2 %).
    MetricSpec::new("max_von_mises_pa", Pressure, WhenUsed(Peak, 1e6), |m| {
        m.max_von_mises_pa
    })
    .shown("largest von Mises stress", "MPa", 1e-6)
    .direction(Worse)
    .source(Source::Envelope),
    MetricSpec::new("max_von_mises_at_m", Length, Through, |m| m.max_von_mises_at_m)
        .shown("where the von Mises stress peaks", "m", 1.0)
        .derives_from(VON_MISES)
        .source(Source::Envelope),
    MetricSpec::new("von_mises_safety_factor", Dimensionless, Through, |m| {
        m.von_mises_safety_factor
    })
    .shown("von Mises safety factor (yield / peak)", "", 1.0)
    .direction(Safer {
        inverse: "von_mises_utilization",
        hint: "(peak stress / yield strength = 1 / safety factor), e.g. a chance constraint with threshold 0.5 for a safety factor of at least 2",
    })
    .derives_from(VON_MISES)
    .source(Source::Envelope),
    MetricSpec::new("von_mises_utilization", Dimensionless, Through, |m| {
        m.von_mises_utilization
    })
    .shown("von Mises utilization (peak / yield)", "%", 100.0)
    .direction(Worse)
    .derives_from(VON_MISES)
    .source(Source::Envelope),
    MetricSpec::new("max_compression_n", Force, Through, |m| m.max_compression_n)
        .shown("largest compression", "kN", 1e-3)
        .direction(Worse)
        .derives_from(VON_MISES)
        .source(Source::Envelope),
    MetricSpec::new("max_torque_nm", Torque, Through, |m| m.max_torque_nm)
        .shown("largest torque in the string", "kN·m", 1e-3)
        .direction(Worse)
        .derives_from(VON_MISES)
        .source(Source::Envelope),
    // A damage rate below 1e-6 per hour (a life of 10⁶ h, over a century of drilling) is no
    // damage: the floor keeps round-off cycles from deciding the verdict.
    MetricSpec::new("fatigue_damage_per_h", Rate, WhenUsed(Fatigue, 1e-6), |m| {
        m.fatigue_damage_per_h
    })
    .in_unit("1/h", S_PER_H)
    .shown("fatigue damage rate (Miner, worst section)", "1/h", 1.0)
    .direction(Worse)
    .source(Source::Envelope),
    MetricSpec::new("fatigue_life_h", Time, Through, |m| m.fatigue_life_h)
        .in_unit("h", 1.0 / S_PER_H)
        .shown("fatigue life (worst section)", "h", 1.0)
        .direction(Safer {
            inverse: "fatigue_damage_per_h",
            hint: "(Miner damage per hour = 1 / life), e.g. a chance constraint with threshold \"1e-3 1/h\" for a life of at least 1000 h",
        })
        .derives_from(FATIGUE)
        .source(Source::Envelope),
    MetricSpec::new("fatigue_worst_at_m", Length, Through, |m| m.fatigue_worst_at_m)
        .shown("where fatigue damage is largest", "m", 1.0)
        .derives_from(FATIGUE)
        .source(Source::Envelope),
    MetricSpec::new(
        "buckling_utilization",
        Dimensionless,
        WhenUsed(Peak, 0.01),
        |m| m.buckling_utilization,
    )
    .shown("compression / sinusoidal buckling load", "%", 100.0)
    .direction(Worse)
    .source(Source::Envelope),
    MetricSpec::new("helical_buckling_utilization", Dimensionless, Through, |m| {
        m.helical_buckling_utilization
    })
    .shown("compression / helical buckling load", "%", 100.0)
    .direction(Worse)
    .derives_from(BUCKLING)
    .source(Source::Envelope),
    MetricSpec::new("buckling_margin", Dimensionless, Through, |m| m.buckling_margin)
        .shown(
            "buckling margin (1 \u{2212} compression / sinusoidal load)",
            "",
            1.0,
        )
        .direction(Safer {
            inverse: "buckling_utilization",
            hint: "(compression / sinusoidal buckling load = 1 − margin), e.g. a chance constraint with threshold 0.5 for a margin of at least 0.5",
        })
        .derives_from(BUCKLING)
        .source(Source::Envelope),
    MetricSpec::new("buckling_at_m", Length, Through, |m| m.buckling_at_m)
        .shown("where compression is closest to buckling", "m", 1.0)
        .derives_from(BUCKLING)
        .source(Source::Envelope),
    MetricSpec::new("critical_speed_margin", Dimensionless, Through, |m| {
        m.critical_speed_margin
    })
    .shown("distance from the nearest critical speed", "%", 100.0)
    .direction(Safer {
        inverse: "critical_speed_proximity",
        hint: "(1 / margin), e.g. a chance constraint with threshold 10 for a margin of at least 10 % from every critical speed",
    })
    .derives_from(&["critical_speed_proximity"])
    .source(Source::Model),
    MetricSpec::new(
        "critical_speed_proximity",
        Dimensionless,
        WhenUsed(MetricClass::Model, 1.0),
        |m| m.critical_speed_proximity,
    )
    .shown("critical speed proximity (1 / margin)", "", 1.0)
    .direction(Worse)
    .source(Source::Model),
    MetricSpec::new(
        "bit_damping_ratio",
        Dimensionless,
        WhenUsed(MetricClass::Model, 0.01),
        |m| m.bit_damping_ratio,
    )
    .shown("bit negative damping / pipe torsional impedance", "", 1.0)
    .direction(Worse)
    .source(Source::Model),
    MetricSpec::new(
        "steady_growth_rate_per_s",
        Rate,
        WhenUsed(MetricClass::Model, 0.01),
        |m| m.steady_growth_rate_per_s,
    )
    .shown("growth rate of steady drilling (dominant eigenvalue)", "1/s", 1.0)
    .direction(Worse)
    .source(Source::Model),
    MetricSpec::new("mean_top_torque_nm", Torque, WhenUsed(Mean, 10.0), |m| {
        m.mean_top_torque_nm
    })
    .shown("mean top-drive torque", "kN\u{b7}m", 1e-3)
    .batch_interval(),
    MetricSpec::new("mean_top_force_n", Force, WhenUsed(Mean, 100.0), |m| {
        m.mean_top_force_n
    })
    .shown("mean top-drive force", "kN", 1e-3)
    .batch_interval(),
    MetricSpec::new(
        "rop_set_point_ratio",
        Dimensionless,
        WhenUsed(Mean, 0.01),
        |m| m.rop_set_point_ratio,
    )
    .shown("mean ROP / V0", "", 1.0)
    .direction(Better)
    .derives_from(&["mean_rop_m_per_h"]),
    MetricSpec::new(
        "set_point_shortfall",
        Dimensionless,
        WhenUsed(Mean, 0.01),
        |m| m.set_point_shortfall,
    )
    .shown("set-point not drilled", "%", 100.0)
    .derives_from(&["mean_rop_m_per_h"]),
    MetricSpec::new(
        "wob_limit_fraction",
        Dimensionless,
        WhenUsed(Mean, 0.05),
        |m| m.wob_limit_fraction,
    )
    .shown("time at the WOB limit", "%", 100.0),
    MetricSpec::new(
        "torque_limit_fraction",
        Dimensionless,
        WhenUsed(Mean, 0.05),
        |m| m.torque_limit_fraction,
    )
    .shown("time at the torque limit", "%", 100.0),
];

/// The row of the metric `key` (a key of `summary.json`).
pub fn find(key: &str) -> Option<&'static MetricSpec> {
    METRICS.iter().find(|s| s.key == key)
}

/// Every key, in the order of `summary.json`.
pub fn keys() -> impl Iterator<Item = &'static str> {
    METRICS.iter().map(|s| s.key)
}

/// The compared metrics (those `verify` compares itself) that a use of `key` brings into a
/// verification: the metric itself when it is compared, and those it derives from. Empty for an
/// unknown key.
pub fn checked_through(key: &str) -> Vec<&'static str> {
    let Some(spec) = find(key) else {
        return Vec::new();
    };
    let own = spec.compared().map(|_| spec.key);
    own.into_iter()
        .chain(spec.derives_from.iter().copied())
        .filter(|k| find(k).is_some_and(|s| s.compared().is_some()))
        .collect()
}

/// The metrics a verification of a problem that uses `used` compares, in catalogue order: every
/// metric compared always, and those that a use brings ([`checked_through`]).
pub fn compared_for<'a>(used: impl IntoIterator<Item = &'a str>) -> Vec<&'static MetricSpec> {
    let brought: Vec<&str> = used.into_iter().flat_map(checked_through).collect();
    METRICS
        .iter()
        .filter(|s| matches!(s.verification, Always(..)) || brought.contains(&s.key))
        .collect()
}
