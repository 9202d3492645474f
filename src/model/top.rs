//! The driller's top: how the top drive moves the string along its axis (MODEL.md §4, §11.8).
//!
//! The rotation is always imposed (θx(0, t) = Ω t). Along the axis the top is at the block's
//! position s(t): u(0, t) = s(t), and the whole string moves with the rigid translation s on
//! top of its elastic motion (Q = e_u s + e_θ Ω t + Φ q, MODEL.md §4's lifting with s in place of
//! V0 t). Three laws give s:
//!
//! - [`TopDrive::Feed`], the paper's imposed feed s = V0 t: the mean rate of penetration is V0
//!   whatever the rock does.
//! - [`TopDrive::HookLoad`], a constant top force: the hook holds the string with a constant load,
//!   so the force the top drive pushes on the string, F_top, is the set-point W
//!   ([`crate::model::OperatingPoint::wob`], `[operating_point] wob`) (Ritto, Soize
//!   & Sampaio, Int. J. Non-Linear Mech. 44, 2009 and 2010, optimise Ω and this force). s is a
//!   degree of freedom of its own; the rock and the string decide how fast it advances.
//! - [`TopDrive::Autodriller`], a driller's autodriller in rate-of-penetration mode with a WOB and
//!   a torque limit: the block accelerates towards the set-point V0 with the time constant τ, and
//!   decelerates while the surface WOB or the surface torque is above its limit, at a rate
//!   proportional to the relative excess (integral action on the excess, so that a limit that
//!   binds is held exactly in a steady state):
//!
//!   s̈ = min( (V0 − ṡ)/τ,  −V0 (W_s − W_lim)/(W_lim τ),  −V0 (T_s − T_lim)/(T_lim τ) ),
//!
//!   the torque term only when a torque limit is given. A top drive's power rating P caps the
//!   torque it can give at Ω: T_lim = min(torque limit, P/Ω) ([`Autodriller::at_speed`]), so at
//!   high rotation speed the rig, not the bit, limits the depth of cut. The surface WOB W_s is the off-bottom hook
//!   load minus the hook load, the top force F_top less the top force off bottom: a horizontal
//!   string rotating off bottom with the block at rest has no axial load at the top (no axial
//!   gravity; its wall friction acts on the spin only), so W_s = F_top. T_s is the top-drive
//!   torque. This is a control law of our own, stated so that it can be checked: real
//!   autodrillers run PI loops on the same errors (Cayeux et al., SPE 178841, 2016, review them);
//!   what matters to the optimum is that the limit holds on average and that the block answers in
//!   about τ.
//!
//! Sign conventions: F_top > 0 pushes the string towards the bit (compression at the top, the
//! surface WOB), T_top > 0 turns it in the sense of Ω. Units SI.

use super::ParameterSpec;
use crate::units::{Dimension, Range};

/// How the top drive moves the string along its axis (`[operating_point] top`).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[serde(tag = "top", rename_all = "snake_case")]
pub enum TopDrive {
    /// u(0, t) = V0 t (the paper's).
    Feed,
    /// F_top = W, constant: the set-point [`crate::model::OperatingPoint::wob`], N.
    HookLoad,
    /// The block at V0 unless the surface WOB or torque exceeds its limit (module doc).
    Autodriller(Autodriller),
}

/// The autodriller's limits and time constant (module doc).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Autodriller {
    /// W_lim, N.
    pub wob_limit: f64,
    /// T_lim, N·m; `None` for no torque limit.
    pub torque_limit: Option<f64>,
    /// The top drive's power rating P, W: a torque limit P/Ω at rotation speed Ω; `None` for none.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub power_limit: Option<f64>,
    /// τ, s.
    pub time_constant: f64,
}

impl Autodriller {
    /// The torque limit at rotation speed `omega` (rad/s), N·m: the smaller of the torque limit
    /// and the power limit over Ω; `None` when neither is set.
    pub fn torque_limit_at(&self, omega: f64) -> Option<f64> {
        let by_power = self
            .power_limit
            .map(|p| p / omega.abs().max(f64::MIN_POSITIVE));
        match (self.torque_limit, by_power) {
            (Some(t), Some(p)) => Some(t.min(p)),
            (t, p) => t.or(p),
        }
    }

    /// This autodriller at rotation speed `omega` (rad/s): the power limit turned into the torque
    /// limit it sets there ([`Self::torque_limit_at`]), which is what
    /// [`autodriller_acceleration`] reads.
    pub fn at_speed(&self, omega: f64) -> Autodriller {
        Autodriller {
            torque_limit: self.torque_limit_at(omega),
            power_limit: None,
            ..*self
        }
    }
}

impl TopDrive {
    /// This top at rotation speed `omega` (rad/s): an autodriller's power limit becomes its
    /// torque limit there ([`Autodriller::at_speed`]); the other tops are unchanged.
    pub fn at_speed(&self, omega: f64) -> TopDrive {
        match self {
            TopDrive::Autodriller(a) => TopDrive::Autodriller(a.at_speed(omega)),
            top => *top,
        }
    }

    /// Whether the block's position is a degree of freedom (every top but the imposed feed).
    pub fn is_free(&self) -> bool {
        !matches!(self, TopDrive::Feed)
    }

    /// Whether the top is the paper's imposed feed (`serde(skip_serializing_if)`).
    pub fn is_feed(&self) -> bool {
        matches!(self, TopDrive::Feed)
    }

    /// The driller's second design variable under this top: the hook load's WOB, else the feed
    /// V0 (the imposed feed's, or the autodriller's set-point).
    pub fn set_point(&self) -> crate::model::SetPoint {
        match self {
            TopDrive::HookLoad => crate::model::SetPoint::Wob,
            _ => crate::model::SetPoint::Feed,
        }
    }

    /// The problem file's name of the law.
    pub fn name(&self) -> &'static str {
        match self {
            TopDrive::Feed => "feed",
            TopDrive::HookLoad => "hook_load",
            TopDrive::Autodriller(_) => "autodriller",
        }
    }
}

/// The names `[operating_point] top` takes.
pub const TOP_DRIVES: [&str; 3] = ["feed", "hook_load", "autodriller"];

/// Admissible range of the surface WOB of a hook-load top and of the autodriller's WOB limit, N:
/// from 100 N (a laboratory string) to 2 MN, above any bit's rating (a 17½ in bit takes about
/// 400 kN).
pub const WOB_RANGE: Range = Range::closed(100.0, 2e6, "100 N to 2 MN, above any bit's rating");

/// Admissible range of the autodriller's torque limit, N·m: 10 N·m to 500 kN·m, above any top
/// drive's rating (about 150 kN·m).
pub const TORQUE_RANGE: Range = Range::closed(
    10.0,
    5e5,
    "10 N·m to 500 kN·m, above any top drive's rating",
);

/// Admissible range of the autodriller's time constant, s: 10 ms (faster than any block can
/// follow) to 10 min.
pub const TIME_CONSTANT_RANGE: Range =
    Range::closed(0.01, 600.0, "10 ms to 10 min: how fast the block answers");

/// Admissible range of the top drive's power rating, W: 100 W (a laboratory string) to 10 MW,
/// above any top drive's (about 1.5 MW, 2000 hp).
pub const POWER_RANGE: Range =
    Range::closed(100.0, 1e7, "100 W to 10 MW, above any top drive's rating");

/// The autodriller's time constant when a file names none, s: a block that answers in a second,
/// as the drawworks of a modern rig do.
pub const DEFAULT_TIME_CONSTANT: f64 = 1.0;

/// The keys of the driller's tops, as the problem's key table ([`crate::problem::keys`]) and
/// their validation read them.
pub const WOB_SET_POINT: ParameterSpec = ParameterSpec::new(
    "operating_point.wob",
    Dimension::Force,
    WOB_RANGE,
    None,
    50e3,
    "the hook load's WOB set-point, its surface push (top = \"hook_load\"; required with it)",
);
pub const WOB_LIMIT: ParameterSpec = ParameterSpec::new(
    "operating_point.wob_limit",
    Dimension::Force,
    WOB_RANGE,
    None,
    80e3,
    "the autodriller's surface WOB limit (top = \"autodriller\"; required with it)",
);
pub const TORQUE_LIMIT: ParameterSpec = ParameterSpec::new(
    "operating_point.torque_limit",
    Dimension::Torque,
    TORQUE_RANGE,
    None,
    20e3,
    "the autodriller's surface torque limit (optional: none)",
);
pub const POWER_LIMIT: ParameterSpec = ParameterSpec::new(
    "operating_point.power_limit",
    Dimension::Power,
    POWER_RANGE,
    None,
    600e3,
    "the top drive's power rating: a torque limit P/Ω (optional: none)",
);
pub const AUTODRILLER_TIME_CONSTANT: ParameterSpec = ParameterSpec::new(
    "operating_point.autodriller_time_constant",
    Dimension::Time,
    TIME_CONSTANT_RANGE,
    Some(DEFAULT_TIME_CONSTANT),
    1.0,
    "the autodriller's time constant τ",
);

/// The block's acceleration s̈ the autodriller commands (module doc) at block speed `speed`,
/// surface WOB `wob` and surface torque `torque`, with its derivatives
/// (∂/∂speed, ∂/∂wob, ∂/∂torque), for set-point `v0` (m/s).
pub fn autodriller_acceleration(
    a: &Autodriller,
    v0: f64,
    speed: f64,
    wob: f64,
    torque: f64,
) -> (f64, [f64; 3]) {
    let tau = a.time_constant;
    let mut best = ((v0 - speed) / tau, [-1.0 / tau, 0.0, 0.0]);
    let gain_w = v0 / (a.wob_limit * tau);
    let by_wob = -gain_w * (wob - a.wob_limit);
    if by_wob < best.0 {
        best = (by_wob, [0.0, -gain_w, 0.0]);
    }
    if let Some(limit) = a.torque_limit {
        let gain_t = v0 / (limit * tau);
        let by_torque = -gain_t * (torque - limit);
        if by_torque < best.0 {
            best = (by_torque, [0.0, 0.0, -gain_t]);
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_autodriller_follows_the_most_restrictive_of_its_three_laws() {
        let a = Autodriller {
            wob_limit: 50e3,
            torque_limit: Some(10e3),
            power_limit: None,
            time_constant: 2.0,
        };
        let v0 = 0.01;
        // Below both limits: towards V0 at 1/τ.
        let (acc, d) = autodriller_acceleration(&a, v0, 0.009, 20e3, 5e3);
        assert!((acc - 0.0005).abs() < 1e-15 && d == [-0.5, 0.0, 0.0]);
        // Far below V0 but near the WOB limit: the margin to the limit caps the acceleration
        // (the integral law: V0 (W_lim − W)/(W_lim τ)), so the block does not overshoot it.
        let (acc, d) = autodriller_acceleration(&a, v0, 0.0, 45e3, 5e3);
        assert!((acc - 0.1 * v0 / 2.0).abs() < 1e-15 && d[1] < 0.0, "{acc}");
        // WOB 10 % over its limit: decelerates at 0.1 V0/τ, whatever the speed.
        let (acc, d) = autodriller_acceleration(&a, v0, 0.004, 55e3, 5e3);
        assert!((acc + 0.1 * v0 / 2.0).abs() < 1e-15, "{acc}");
        assert!((d[1] + v0 / (50e3 * 2.0)).abs() < 1e-18);
        // Torque 20 % over: the torque law is the more restrictive one.
        let (acc, d) = autodriller_acceleration(&a, v0, 0.004, 55e3, 12e3);
        assert!((acc + 0.2 * v0 / 2.0).abs() < 1e-15 && d[2] < 0.0);
        // A binding limit holds in the steady state: zero acceleration exactly at the limit.
        let (acc, _) = autodriller_acceleration(&a, v0, 0.004, 50e3, 5e3);
        assert_eq!(acc, 0.0);
        // No torque limit: a huge torque does nothing.
        let free = Autodriller {
            torque_limit: None,
            ..a
        };
        assert!(autodriller_acceleration(&free, v0, 0.004, 20e3, 1e9).0 > 0.0);
    }

    #[test]
    fn a_power_rating_caps_the_torque_at_high_speed() {
        // 25 kW: 3.98 kN·m at 60 rpm (2π rad/s), 1.99 kN·m at 120 rpm; the smaller limit rules.
        let a = Autodriller {
            wob_limit: 50e3,
            torque_limit: Some(3e3),
            power_limit: Some(25e3),
            time_constant: 1.0,
        };
        let pi = std::f64::consts::PI;
        assert_eq!(a.torque_limit_at(2.0 * pi), Some(3e3));
        assert!((a.torque_limit_at(4.0 * pi).unwrap() - 25e3 / (4.0 * pi)).abs() < 1e-9);
        let only_power = Autodriller {
            torque_limit: None,
            ..a
        };
        assert!((only_power.torque_limit_at(2.0 * pi).unwrap() - 3978.87).abs() < 0.01);
        let at = only_power.at_speed(4.0 * pi);
        assert_eq!(at.power_limit, None);
        assert_eq!(at.torque_limit, only_power.torque_limit_at(4.0 * pi));
        let neither = Autodriller {
            torque_limit: None,
            power_limit: None,
            ..a
        };
        assert_eq!(neither.torque_limit_at(1.0), None);
    }
}
