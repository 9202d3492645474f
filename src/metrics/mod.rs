//! Metrics of one simulation (`MODEL.md` §8): turn the recorded [`TimeSeries`] into the numbers
//! that objectives and reports read — rate of penetration, stick-slip, bit-bounce, wall impacts,
//! weight and torque on bit, mechanical specific energy, drilling efficiency and an energy-balance
//! self-check; the stress metrics of the run's envelope; and the distance from the critical
//! speeds, which depends on the model and Ω alone ([`Metrics::with_critical_speed_margin`]).
//!
//! # Analysis window
//! With t₀ = t\[0\] + `settling_time`, the window is the samples with t ≥ t₀. Its start t_s is the
//! **first recorded sample at or after t₀** (not a value interpolated at t₀), so that every metric
//! — cumulative counters, cumulative work, extremes, integrals — refers to the same recorded
//! states; the window length is T_w = t_end − t_s (≤ t_end − t₀). With `settling_time` = 0 the
//! window is the whole run. The energy-balance residual alone is taken over the whole run.
//!
//! # Time weighting
//! The sample times are not uniformly spaced (the step is adaptive). Every time integral uses the
//! trapezoid rule on the samples: interval [tᵢ, tᵢ₊₁] contributes (tᵢ₊₁ − tᵢ)(yᵢ + yᵢ₊₁)/2.
//! Time means are integrals divided by T_w. Shares of time (stick, off bottom) are the same rule
//! applied to the 0/1 indicator of the condition, so an interval whose ends disagree counts for
//! half its length. Extremes (max/min) are over the window's sample values.
//!
//! # Sign conventions
//! Those of [`TimeSeries`]: the bit advances with u̇ > 0 and spins with θ̇ > 0; WOB ≥ 0 and TOB are
//! positive when the rock resists; `work_top` is the work done by the top drive on the string,
//! `work_bit` the work done by the rock on the string (≤ 0 while drilling).

mod batch_means;
pub mod catalogue;
mod check;
mod error;
mod online;
mod spec;
mod time_average;

#[cfg(test)]
mod tests;
#[cfg(test)]
mod tests_catalogue;
#[cfg(test)]
mod tests_off_bottom;

pub use batch_means::{BATCHES, BatchInterval, batch_means};
pub use catalogue::METRICS;
pub use error::MetricsError;
pub use online::OnlineMetrics;
pub use spec::{Direction, MetricClass, MetricSpec, Source, Verification};

use crate::sim::TimeSeries;
use serde::Serialize;

/// Energy floor in the denominator of the energy-balance residual, J: far below any drilling
/// energy, it only keeps a run with no net input work from dividing by zero.
pub const ENERGY_FLOOR_J: f64 = 1e-12;

/// What the metrics need besides the time series: the operating point and the analysis window.
#[derive(Debug, Clone, PartialEq)]
pub struct MetricsConfig {
    /// Imposed rotation speed Ω at the top, rad/s; > 0.
    pub omega: f64,
    /// Imposed axial velocity V0 at the top, m/s; ≥ 0 (0: off-bottom rotation, see [`Metrics`]).
    pub v0: f64,
    /// Borehole radius R_bh, m; > 0. The bit area is A_b = π R_bh².
    pub borehole_radius: f64,
    /// Settling time, s; ≥ 0. Metrics use only samples with t ≥ t\[0\] + settling_time.
    pub settling_time: f64,
    /// Fraction of Ω below which the bit counts as stuck (θ̇_bit < stick_threshold · Ω); in
    /// [0, 1). Default [`MetricsConfig::DEFAULT_STICK_THRESHOLD`] = 0.1.
    pub stick_threshold: f64,
    /// Averaging time τ of the bit speed that the stick-slip statistics read, s; ≥ 0 (0: the raw
    /// speed). Default [`MetricsConfig::DEFAULT_SPEED_AVERAGE`] = 10 ms. See [`Metrics`].
    pub speed_average: f64,
    /// The top law of the run ([`crate::model::TopDrive`]; the imposed feed by default): the
    /// autodriller's limit shares are read from it.
    pub top: crate::model::TopDrive,
}

impl MetricsConfig {
    /// Default stick threshold: the bit is stuck while it turns slower than 10 % of Ω.
    pub const DEFAULT_STICK_THRESHOLD: f64 = 0.1;

    /// Default averaging time of the bit speed, s: the resolution of a downhole recorder sampling
    /// at 100 Hz, and a sixth of the seed string's first torsional period (59 ms).
    pub const DEFAULT_SPEED_AVERAGE: f64 = 0.01;

    /// A configuration with the default stick threshold (0.1).
    pub fn new(omega: f64, v0: f64, borehole_radius: f64, settling_time: f64) -> Self {
        Self {
            omega,
            v0,
            borehole_radius,
            settling_time,
            stick_threshold: Self::DEFAULT_STICK_THRESHOLD,
            speed_average: Self::DEFAULT_SPEED_AVERAGE,
            top: crate::model::TopDrive::Feed,
        }
    }

    /// The configuration of a run of `string` at `op` whose analysis window starts `settling` s
    /// after its first sample (the problem's [`crate::model::Simulation::settling_for`] its
    /// duration): Ω and V0 of `op`, the string's borehole radius and top law, the default stick
    /// threshold and speed average. Every command and study reads a run's metrics through it
    /// ([`of_run`], or `OnlineMetrics` for a streamed run).
    pub fn for_run(
        string: &crate::model::Drillstring,
        op: crate::model::OperatingPoint,
        settling: f64,
    ) -> Self {
        Self::new(op.omega, op.v0, string.borehole_radius, settling).with_top(string.top)
    }

    /// This configuration for a run under the top law `top` (an autodriller's power limit read
    /// as the torque limit it sets at this configuration's Ω).
    pub fn with_top(self, top: crate::model::TopDrive) -> Self {
        Self {
            top: top.at_speed(self.omega),
            ..self
        }
    }

    /// Check the ranges documented on each field.
    pub fn validate(&self) -> Result<(), MetricsError> {
        let positive = |field, value: f64| {
            if value.is_finite() && value > 0.0 {
                Ok(())
            } else {
                Err(MetricsError::InvalidConfig {
                    field,
                    value,
                    expected: "expected a finite value > 0",
                })
            }
        };
        positive("omega", self.omega)?;
        if !(self.v0.is_finite() && self.v0 >= 0.0) {
            return Err(MetricsError::InvalidConfig {
                field: "v0",
                value: self.v0,
                expected: "expected a finite value >= 0",
            });
        }
        positive("borehole_radius", self.borehole_radius)?;
        if !(self.settling_time.is_finite() && self.settling_time >= 0.0) {
            return Err(MetricsError::InvalidConfig {
                field: "settling_time",
                value: self.settling_time,
                expected: "expected a finite value >= 0",
            });
        }
        if !(self.speed_average.is_finite() && self.speed_average >= 0.0) {
            return Err(MetricsError::InvalidConfig {
                field: "speed_average",
                value: self.speed_average,
                expected: "expected a finite averaging time >= 0 s",
            });
        }
        if !(self.stick_threshold >= 0.0 && self.stick_threshold < 1.0) {
            return Err(MetricsError::InvalidConfig {
                field: "stick_threshold",
                value: self.stick_threshold,
                expected: "expected a fraction of omega in [0, 1)",
            });
        }
        Ok(())
    }
}

/// The metrics of one run (`MODEL.md` §8). Unless stated otherwise, each is taken over the
/// analysis window [t_s, t_end] of the module documentation (length T_w), time-weighted by the
/// trapezoid rule.
///
/// The stick-slip statistics (SSI, stick fraction, peak bit speed ratio) read the bit speed
/// averaged over τ = `speed_average` (10 ms by default), ω̄(t) = (θ(t) − θ(t − τ))/τ, as a
/// downhole recorder does. The raw bit speed of this model has torsional wave fronts (the bit is
/// the string's end, with no inertia of its own, under a torque that drops when it slips), so its
/// extremes carry the Gibbs overshoot of the truncated modal series and do not converge as modes
/// are added: on a 10 s seed window, SSI 1.30 / 2.75 / 2.44 / 2.99 for 3, 3 + static correction,
/// 8 + static correction and 16 + static correction torsional modes, against 0.95 / 1.31 / 1.03 /
/// 1.11 for the 10 ms average (docs/model.md, "Converged model").
///
/// # Off-bottom rotation (V0 = 0)
/// Every metric is defined at V0 = 0: the mean ROP is the bit's elastic axial drift (≈ 0), the
/// stick-slip statistics are relative to Ω as always, `bit_bounce_fraction` is the share of time
/// the bit is off bottom, 1 by definition (the WOB of the elastic axial motion is round-off, about
/// 1e-9 N on the tiny string, and its sign would decide the share), `mse_pa` is +∞ (no rock is cut, whatever the drift),
/// `axial_velocity_fluctuation` is +∞ (0 if the bit is at rest axially: there is no feed to
/// compare with), `efficiency` and `axial_power_share` are the same ratios (≈ 0: the bit does
/// almost no work), and the depth of cut 2π V0/Ω of the constraints is 0.
///
/// Each field has its row in the catalogue ([`METRICS`]: unit, display, verification), in the
/// same order.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[cfg_attr(test, derive(serde::Deserialize))]
pub struct Metrics {
    /// Mean rate of penetration (u_bit(t_end) − u_bit(t_s)) / T_w, m/s.
    pub mean_rop_m_s: f64,
    /// The same mean rate of penetration in m/h (× 3600).
    pub mean_rop_m_per_h: f64,
    /// Stick-slip severity (max ω̄ − min ω̄) / (2Ω) of the averaged bit speed ω̄, dimensionless;
    /// 0 for steady rotation.
    pub stick_slip_severity: f64,
    /// SSI by MODEL.md §8's formula on the raw (not averaged) bit speed, dimensionless: the
    /// paper's definition, kept for comparison; not converged in the basis (see above).
    pub stick_slip_severity_raw: f64,
    /// Share of time in [0, 1] with ω̄ < stick_threshold · Ω (bit stuck), dimensionless.
    pub stick_fraction: f64,
    /// Peak bit speed ratio max ω̄ / Ω of the averaged bit speed, dimensionless.
    pub max_bit_speed_ratio: f64,
    /// Share of time in [0, 1] with the bit off bottom (weight on bit = 0; tested as ≤ 0 so that a
    /// rounding-level negative value also counts), dimensionless; 1 at V0 = 0 (off-bottom rotation;
    /// a hook load, which has no V0, is on bottom).
    pub bit_bounce_fraction: f64,
    /// Time-weighted standard deviation of the bit axial velocity u̇_bit divided by V0 (under a
    /// hook load by the mean ROP), dimensionless; at V0 = 0, +∞ (0 for a bit at rest axially).
    pub axial_velocity_fluctuation: f64,
    /// Wall impacts over all nodes per second (touch-downs after a separation of more than 1 % of
    /// the gap at a normal speed of at least `sim::IMPACT_SPEED` = 1 cm/s), 1/s.
    pub impacts_per_s: f64,
    /// Largest wall normal force at any node and sample, N.
    pub peak_wall_force_n: f64,
    /// Contact impulse ∫ (Σ_nodes |F_FS|) dt, N·s.
    pub contact_impulse_ns: f64,
    /// Largest radial displacement over radial gap at any node and sample (> 1: indentation),
    /// dimensionless.
    pub max_radial_over_gap: f64,
    /// Time-weighted mean weight on bit, N.
    pub mean_wob_n: f64,
    /// Time-weighted mean torque on bit, N·m.
    pub mean_tob_nm: f64,
    /// Mechanical specific energy (Teale) WOB/A_b + 2π N TOB / (A_b ROP), Pa (= J/m³), with the
    /// mean WOB and TOB, N = Ω/(2π) in rev/s, A_b = π R_bh² and ROP the mean ROP in m/s.
    /// +∞ when V0 = 0 or the mean ROP is ≤ 0 (no rock cut); serde_json writes it as `null`.
    pub mse_pa: f64,
    /// Drilling efficiency: energy delivered to the rock over the energy the top drive spent on
    /// the window, net of what the string stored, W_rock / (W_top − ΔE), with W_rock =
    /// −Δwork_bit, W_top = Δwork_top and ΔE = Δ(kinetic + potential) energy of the string over the
    /// window; dimensionless. By the energy balance W_top − ΔE = W_rock + D (D ≥ 0 dissipated in
    /// the string and at the wall), so it lies in [0, 1] up to the energy-balance residual,
    /// whatever the phase of the stick-slip cycle at the window's ends (MODEL.md §8, turn 2; the
    /// plain ratio W_rock / W_top exceeded 1 at a fifth of a 15×15 map). 0 when the denominator
    /// is not positive.
    pub efficiency: f64,
    /// Share of the bit's power spent in the axial (penetrating) direction,
    /// ∫ WOB u̇ dt / ∫ (WOB u̇ + TOB θ̇) dt over the window, dimensionless in [0, 1]. The bit law of
    /// MODEL.md §6 cuts axially and rubs in torsion (T = μ WOB ξ(θ̇)), so this is the share of the
    /// bit's work that drills rather than heats the bit: the "cutting" share of Detournay &
    /// Defourny's split of bit work (Int. J. Rock Mech. Min. Sci. 29, 1992). It grows with the
    /// depth of cut V0/Ω, i.e. it varies with the operating point where `efficiency` does not.
    /// 0 when the bit does no work.
    pub axial_power_share: f64,
    /// Energy-balance self-check over the whole run (from sample 0, not the window):
    /// |W_in − (ΔE_kinetic + ΔE_potential + Δdissipated)| / max(|Δwork_top|, |Δwork_bit|,
    /// [`ENERGY_FLOOR_J`]) with W_in = Δwork_top + Δwork_bit, dimensionless (0 for a perfectly
    /// consistent run). The denominator is the gross energy flow (the work put in by the top
    /// drive while drilling), not the net W_in, which is a small difference of two large flows.
    pub energy_balance_residual: f64,
    /// Largest von Mises stress at the outer fibre over the string and the analysis window, Pa
    /// (the [`crate::sim::StressEnvelope`]; definition in [`crate::fem::SectionStress`]). NaN
    /// when the run kept no envelope.
    pub max_von_mises_pa: f64,
    /// Where along the string (element midpoint x from the top drive) it occurs, m.
    pub max_von_mises_at_m: f64,
    /// Yield strength over `max_von_mises_pa` (> 1: no fibre yields); NaN when the problem gives
    /// no `model.pipe.yield_strength`. Larger is safer, so risk terms and chance constraints use
    /// its inverse, `von_mises_utilization`.
    pub von_mises_safety_factor: f64,
    /// `max_von_mises_pa` over the yield strength (the unity check: ≥ 1 yields), dimensionless;
    /// NaN without a yield strength.
    pub von_mises_utilization: f64,
    /// Largest compressive axial force anywhere along the string over the window, N (≥ 0).
    pub max_compression_n: f64,
    /// Largest torque magnitude anywhere along the string over the window, N·m.
    pub max_torque_nm: f64,
    /// Miner damage per hour of drilling of the worst section (its worst material fibre),
    /// extrapolated from the analysis window: D_window · 3600 s / T_w, 1/h. Rainflow cycles of
    /// the axial stress of material fibres of the spinning sections against the pipe's S-N
    /// curve ([`crate::sim::SectionFatigue`], [`crate::fatigue`]); NaN without an envelope.
    pub fatigue_damage_per_h: f64,
    /// Fatigue life 1 / `fatigue_damage_per_h`, h of drilling at this operating point; +∞ (null
    /// in JSON) when no section accumulates damage. Larger is safer, so risk terms and chance
    /// constraints use `fatigue_damage_per_h`.
    pub fatigue_life_h: f64,
    /// Where the worst section is (element midpoint x from the top drive), m; NaN when no section
    /// accumulates damage.
    pub fatigue_worst_at_m: f64,
    /// Largest compression anywhere along the string over the window, divided by the sinusoidal
    /// buckling load of the pipe in its hole (Dawson & Paslay 1984, [`crate::model::BucklingLoads`]):
    /// ≥ 1 the pipe buckles sinusoidally, dimensionless; NaN without an envelope.
    pub buckling_utilization: f64,
    /// The same compression over the helical buckling load (Chen, Lin & Cheatham 1990): ≥ 1 the
    /// pipe buckles into a helix, dimensionless.
    pub helical_buckling_utilization: f64,
    /// 1 − `buckling_utilization`: 1 without compression, 0 at the onset of sinusoidal buckling,
    /// negative beyond, dimensionless. Larger is safer, so risk terms and chance constraints use
    /// `buckling_utilization`.
    pub buckling_margin: f64,
    /// Where the compression is closest to buckling (element midpoint x), m.
    pub buckling_at_m: f64,
    /// Relative distance of Ω from the nearest critical speed, min |Ω − Ω_c| / Ω_c over the
    /// speeds Ω_c where a mode of the string linearised about its resting state meets 1× or k×
    /// the rotation frequency (k = `campbell.excitation_multiple`, default 3), dimensionless in
    /// [0, 0.5]: 0 on a critical speed, capped at 0.5 (no critical speed in [Ω/1.5, 2Ω]); see
    /// [`crate::campbell::margin`]. It depends on the model and Ω only, not on the run. Larger is
    /// safer, so risk terms and chance constraints use its inverse,
    /// `critical_speed_proximity`. NaN when not computed (a bare time series, or a resting state
    /// that does not converge).
    pub critical_speed_margin: f64,
    /// 1 / `critical_speed_margin`, dimensionless in [2, +∞] (+∞ on a critical speed; written
    /// `null` in JSON): larger is closer to resonance, e.g. a chance constraint with threshold
    /// 10 keeps Ω at least 10 % from every critical speed.
    pub critical_speed_proximity: f64,
    /// The bit's negative damping over the pipe's torsional impedance, dimensionless (see
    /// [`crate::model::bit_damping_ratio`]): ∂T_BR/∂θ̇ at u̇ = V0, θ̇ = Ω divided by
    /// √(κ_t G J · ρ J). Positive when the bit torque weakens with speed. Above 1 the bit feeds a
    /// torsional disturbance faster than the pipe can carry it away, and with the paper's
    /// mass-proportional damping alone the response is set by the shortest torsional waves the
    /// model holds and no basis converges; a stiffness-proportional damping
    /// (`[model.pipe] stiffness_damping`) bounds them (docs/model.md, "Converged model"). It depends on
    /// the model and the operating point, and under a free top on the mean ROP drilled (taken as
    /// the bit's feed: [`Self::with_drilled_bit_damping_ratio`]). NaN when not computed.
    pub bit_damping_ratio: f64,
    /// The growth rate of a disturbance of steady drilling at the operating point, 1/s: the real
    /// part of the dominant eigenvalue of the run's equations linearised about the pre-loaded
    /// steady state ([`crate::sim::steady_stability`]); > 0 the steady state is unstable (a
    /// window that ends before the growth reads it as the long run), < 0 its slowest decay. A
    /// property of the model and the operating point. NaN when not computed (a depth-of-cut
    /// bit's delay equation; the studies compute it only when the problem uses it).
    pub steady_growth_rate_per_s: f64,
    /// Time-weighted mean torque the top drive applies to turn the string at Ω (the surface
    /// torque), N·m: the torque on bit plus the wall friction and damping along the string
    /// (soft-string torque and drag, [`crate::model::SoftString`]).
    pub mean_top_torque_nm: f64,
    /// Time-weighted mean axial force the top drive applies to feed the string at V0, N
    /// (positive pushing): the weight on bit plus the axial drag along the string.
    pub mean_top_force_n: f64,
    /// Mean ROP over the feed set-point V0, dimensionless (MODEL.md §11.8): 1 under the imposed
    /// feed (to the settling of the window's ends); below 1 under an autodriller whenever a limit
    /// or the dynamics cost footage. 0 at V0 = 0 by definition (off-bottom rotation and a hook
    /// load have no feed set-point; series metrics are never NaN).
    pub rop_set_point_ratio: f64,
    /// The share of the feed set-point the bit did not drill, 1 − mean ROP / V0, dimensionless:
    /// what a set-point above what the rock and the rig allow asks for in vain (a risk term that
    /// grows with the set-point's excess, where ROP itself is flat); about 0 under the imposed
    /// feed, 0 at V0 = 0 (no set-point).
    pub set_point_shortfall: f64,
    /// Share of the window during which the autodriller's WOB limit commanded the block (its
    /// law [`crate::model::autodriller_acceleration`] took the WOB branch), dimensionless in
    /// [0, 1]; 0 under any other top.
    pub wob_limit_fraction: f64,
    /// The same for the autodriller's torque limit.
    pub torque_limit_fraction: f64,
}

impl Metrics {
    /// Every metric NaN (the fields a computation fills are then set).
    fn unset() -> Self {
        let n = f64::NAN;
        Metrics {
            mean_rop_m_s: n,
            mean_rop_m_per_h: n,
            stick_slip_severity: n,
            stick_slip_severity_raw: n,
            stick_fraction: n,
            max_bit_speed_ratio: n,
            bit_bounce_fraction: n,
            axial_velocity_fluctuation: n,
            impacts_per_s: n,
            peak_wall_force_n: n,
            contact_impulse_ns: n,
            max_radial_over_gap: n,
            mean_wob_n: n,
            mean_tob_nm: n,
            mse_pa: n,
            efficiency: n,
            axial_power_share: n,
            energy_balance_residual: n,
            max_von_mises_pa: n,
            max_von_mises_at_m: n,
            von_mises_safety_factor: n,
            von_mises_utilization: n,
            max_compression_n: n,
            max_torque_nm: n,
            fatigue_damage_per_h: n,
            fatigue_life_h: n,
            fatigue_worst_at_m: n,
            buckling_utilization: n,
            helical_buckling_utilization: n,
            buckling_margin: n,
            buckling_at_m: n,
            critical_speed_margin: n,
            critical_speed_proximity: n,
            bit_damping_ratio: n,
            steady_growth_rate_per_s: n,
            mean_top_torque_nm: n,
            mean_top_force_n: n,
            rop_set_point_ratio: n,
            set_point_shortfall: n,
            wob_limit_fraction: n,
            torque_limit_fraction: n,
        }
    }

    /// These metrics with the stress metrics of `envelope` (see the fields), against the pipe's
    /// yield strength if known.
    pub fn with_stresses(
        mut self,
        envelope: &crate::sim::StressEnvelope,
        yield_strength: Option<f64>,
    ) -> Self {
        let (peak, at) = envelope.peak().unwrap_or((f64::NAN, f64::NAN));
        let max = |v: &[f64]| v.iter().copied().fold(f64::NAN, f64::max);
        self.max_von_mises_pa = peak;
        self.max_von_mises_at_m = at;
        let (utilization, safety) = envelope.yield_utilization(yield_strength);
        self.von_mises_safety_factor = safety;
        self.von_mises_utilization = utilization;
        self.max_compression_n = max(&envelope.max_compression_n);
        self.max_torque_nm = max(&envelope.max_torque_nm);
        let (rate, worst) = envelope.fatigue_peak().unwrap_or((f64::NAN, f64::NAN));
        self.fatigue_damage_per_h = rate;
        self.fatigue_life_h = 1.0 / rate; // +∞ for no damage, NaN for none tracked
        self.fatigue_worst_at_m = if rate > 0.0 { worst } else { f64::NAN };
        let (usage, at) = envelope.buckling_peak().unwrap_or((f64::NAN, f64::NAN));
        self.buckling_utilization = usage;
        self.helical_buckling_utilization = envelope.helical_peak().unwrap_or(f64::NAN);
        self.buckling_margin = 1.0 - usage;
        self.buckling_at_m = at;
        self
    }

    /// These metrics with `critical_speed_margin` = `margin` (see the field; NaN: unknown) and
    /// its inverse.
    pub fn with_critical_speed_margin(mut self, margin: f64) -> Self {
        self.critical_speed_margin = margin;
        self.critical_speed_proximity = 1.0 / margin;
        self
    }

    /// These metrics with `bit_damping_ratio` = `ratio` (see the field).
    pub fn with_bit_damping_ratio(mut self, ratio: f64) -> Self {
        self.bit_damping_ratio = ratio;
        self
    }

    /// These metrics with `steady_growth_rate_per_s` of `stability` (NaN for none).
    pub fn with_steady_state(mut self, stability: Option<crate::sim::SteadyStability>) -> Self {
        self.steady_growth_rate_per_s = stability.map_or(f64::NAN, |s| s.growth_rate_per_s);
        self
    }

    /// These metrics with `bit_damping_ratio` = [`crate::model::bit_damping_ratio`] of `string`
    /// at the feed its bit drills: V0 under the imposed feed; under a free top (hook load,
    /// autodriller) the run's mean ROP, not the set-point V0, which a limit may keep the bit
    /// from drilling (the ratio of a rate law grows with the feed: on the slim pipe of
    /// `slim_pipe_autodriller.toml` at 30 rpm and a 20 m/h set-point the bit drills 2.68 m/h,
    /// and the ratio taken at V0 read 21 on a steady run).
    pub fn with_drilled_bit_damping_ratio(
        self,
        string: &crate::model::Drillstring,
        op: crate::model::OperatingPoint,
    ) -> Self {
        let v0 = if string.top.is_feed() {
            op.v0
        } else {
            crate::units::from_m_per_h(self.mean_rop_m_per_h).max(0.0)
        };
        let ratio =
            crate::model::bit_damping_ratio(string, crate::model::OperatingPoint { v0, ..op });
        self.with_bit_damping_ratio(ratio)
    }

    /// Every metric with its `summary.json` key, in the catalogue's order ([`METRICS`]), values
    /// as they are (±∞ and NaN included: a JSON round trip would turn them into null).
    pub fn named_values(&self) -> Vec<(&'static str, f64)> {
        METRICS.iter().map(|s| (s.key, (s.get)(self))).collect()
    }
}

/// What the model, not the time march, adds to a run's metrics: computed apart from the run
/// (a Campbell search, the steady state's linear stability), each caller as it best can (a
/// study keeps a table of critical speeds per sample; `simulate` reports a failed search).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ModelTerms {
    /// `critical_speed_margin` (NaN: unknown, e.g. a string without a resting state).
    pub critical_speed_margin: f64,
    /// The steady state's linear stability, when computed (`steady_growth_rate_per_s`: NaN
    /// otherwise).
    pub steady_state: Option<crate::sim::SteadyStability>,
}

impl Metrics {
    /// The statistics of a run's time series (`self`) completed into its metrics: the stress
    /// metrics of its `envelope` against the yield strength of `string`'s pipe, and with
    /// `model` the model's terms and the bit's damping ratio at the feed it drilled (without:
    /// they stay NaN). The one completion of [`of_run`] and of a streamed run's
    /// `OnlineMetrics::metrics`.
    pub fn completed(
        self,
        envelope: &crate::sim::StressEnvelope,
        string: &crate::model::Drillstring,
        op: crate::model::OperatingPoint,
        model: Option<ModelTerms>,
    ) -> Self {
        let m = self.with_stresses(envelope, string.pipe.yield_strength);
        match model {
            Some(t) => m
                .with_critical_speed_margin(t.critical_speed_margin)
                .with_drilled_bit_damping_ratio(string, op)
                .with_steady_state(t.steady_state),
            None => m,
        }
    }
}

/// The metrics of a finished run of `string` at `op` whose window starts after `settling` s:
/// its time series' statistics ([`compute`] with [`MetricsConfig::for_run`]) completed with
/// its stress envelope and, given, the model's terms ([`Metrics::completed`]). Errors: those of
/// [`compute`].
pub fn of_run(
    run: &crate::sim::RunOutput,
    string: &crate::model::Drillstring,
    op: crate::model::OperatingPoint,
    settling: f64,
    model: Option<ModelTerms>,
) -> Result<Metrics, MetricsError> {
    let config = MetricsConfig::for_run(string, op, settling);
    Ok(compute(&run.series, &config)?.completed(&run.envelope, string, op, model))
}

/// Compute the metrics of `series` (see [`Metrics`] for the definitions). The stress metrics
/// need the run's envelope: they are NaN here (see [`of_run`]). Refuses an invalid
/// configuration, an empty or inconsistent series (unequal channel lengths, non-finite samples,
/// times not strictly increasing) and an analysis window with fewer than two samples. The
/// samples go through [`OnlineMetrics`], the accumulators a streamed run uses.
pub fn compute(series: &TimeSeries, config: &MetricsConfig) -> Result<Metrics, MetricsError> {
    config.validate()?;
    check::check_series(series)?;
    let mut online = OnlineMetrics::new(config.clone(), f64::NAN)?;
    feed(series, &mut online);
    online.metrics()
}

/// Every sample of `series`, in order, into `sink`.
fn feed(series: &TimeSeries, sink: &mut impl crate::sim::Sink) {
    let mut probes = vec![0.0; series.probe_radial.len()];
    for i in 0..series.len() {
        sink.record(&series.row(i, &mut probes));
    }
}

/// A fluctuation `std` (m/s) relative to the feed `v0`: std / V0; at V0 = 0 (off bottom), 0 for
/// a bit at rest axially and +∞ for any axial motion, as x/0 in the extended reals.
pub(crate) fn relative_to_feed(std: f64, v0: f64) -> f64 {
    match (v0 > 0.0, std > 0.0) {
        (true, _) => std / v0,
        (false, false) => 0.0,
        (false, true) => f64::INFINITY,
    }
}
