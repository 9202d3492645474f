//! The row type of the metric catalogue ([`super::METRICS`]): what drillopt knows about a metric
//! besides its computation — its key, unit, how the terminal shows it, which way is safe, how
//! `verify` and `solve`'s numerical check compare it, and what it is computed from.

use super::Metrics;
use crate::units::Dimension;
use serde::Serialize;

/// The kind of a metric under refinement (`verify`), which sets its tolerance.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum MetricClass {
    /// A time mean: tolerance 2 %.
    Mean,
    /// A stick-slip statistic (extremes and shares of time): tolerance 10 %.
    StickSlip,
    /// An extreme of the section loads along the string (largest stress) or of the wall contact:
    /// tolerance 10 %.
    Peak,
    /// A fatigue damage rate: tolerance 46 %, the 10 % of a peak stress carried to the damage
    /// through the S-N curve's slope, (1.1)^m − 1 at m = 4 (DNV-B1's first branch): Miner damage
    /// goes as the m-th power of the stress range.
    Fatigue,
    /// A property of the model at the operating point, not of the run (the critical speeds of
    /// the string linearised at rest, the bit damping ratio): tolerance 10 %, as a peak. A
    /// refinement of the basis or the mesh moves the critical speeds (a few tenths of a percent
    /// on the seed), and near a critical speed the relative distance from it moves much more.
    Model,
}

impl MetricClass {
    /// Largest relative change accepted.
    pub fn tolerance(self) -> f64 {
        match self {
            MetricClass::Mean => 0.02,
            MetricClass::StickSlip | MetricClass::Peak | MetricClass::Model => 0.10,
            MetricClass::Fatigue => 0.46,
        }
    }
}

/// Which way of a metric is safe or good. Risk terms and chance constraints penalise large
/// values.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Direction {
    /// Larger is worse (stick-slip, stresses, impacts): what risk terms and chance constraints
    /// are for.
    Worse,
    /// Larger is better (ROP, efficiency): the objective's quantities; still accepted in risk
    /// terms and chance constraints.
    Better,
    /// Neither (loads, locations).
    Neutral,
    /// Larger is safer (a safety factor, a margin): refused in risk terms and chance constraints
    /// in favour of `inverse`, the metric that grows with danger; `hint` says how to translate
    /// a limit (it follows "use `inverse`" in the error).
    Safer {
        inverse: &'static str,
        hint: &'static str,
    },
}

/// How `verify` and `solve`'s numerical check compare a metric under refinement.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Verification {
    /// Compared in every verification, with its class and the floor of the denominator of its
    /// relative change (in the metric's unit): the metrics the optimizer ranks points by.
    Always(MetricClass, f64),
    /// Compared when the problem's objective, risk terms or chance constraints use it (or a
    /// metric computed from it), with its class and floor.
    WhenUsed(MetricClass, f64),
    /// Not compared itself: checked through the compared metrics it is computed from
    /// ([`MetricSpec::derives_from`]; the same number in another unit, a location, a ratio to a
    /// constant of the model).
    Through,
}

/// What a metric's value is computed from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Source {
    /// The run's time series ([`super::compute`]).
    Series,
    /// The run's stress envelope ([`Metrics::with_stresses`]): NaN for a bare time series.
    Envelope,
    /// The model and the operating point alone, not the run
    /// ([`Metrics::with_critical_speed_margin`], [`Metrics::with_bit_damping_ratio`]): NaN until
    /// set.
    Model,
}

/// One row of the metric catalogue.
#[derive(Debug, Clone, Copy)]
pub struct MetricSpec {
    /// Its key in `summary.json`, the problem file (risk terms, chance constraints), the cache
    /// and the CSV columns: the name of its [`Metrics`] field.
    pub key: &'static str,
    /// Dimension of the value (thresholds may be written in any unit of it).
    pub dimension: Dimension,
    /// Factor from SI to the unit the key names: value = `per_si` × SI value (1 but for
    /// `mean_rop_m_per_h`, `fatigue_damage_per_h`, `fatigue_life_h`).
    pub per_si: f64,
    /// The unit the key names when it is not the dimension's SI unit (`"m/h"`, `"1/h"`, `"h"`).
    pub own_unit: Option<&'static str>,
    /// Human name on the terminal and in plots, e.g. "mean WOB".
    pub name: &'static str,
    /// Terminal unit, e.g. "kN"; empty for a plain number.
    pub display_unit: &'static str,
    /// Terminal value = `display_scale` × value (e.g. 1e-3 for N → kN).
    pub display_scale: f64,
    pub direction: Direction,
    pub verification: Verification,
    /// Compared metrics it is computed from: using it brings them into the check (MSE the mean
    /// WOB, TOB and ROP of Teale's formula; the von Mises utilization the peak stress).
    pub derives_from: &'static [&'static str],
    pub source: Source,
    /// A time mean or a share of time: `summary.json`'s `confidence_95` gives its batch-means
    /// interval ([`super::batch_means`]).
    pub batch_interval: bool,
    /// Its value in `m` (NaN: not computed, or undefined by the inputs).
    pub get: fn(&Metrics) -> f64,
}

impl MetricSpec {
    /// A row with the key's SI unit of `dimension`, shown as the plain value under its key,
    /// neutral, from the time series, without batch interval (set the rest with the methods
    /// below).
    pub const fn new(
        key: &'static str,
        dimension: Dimension,
        verification: Verification,
        get: fn(&Metrics) -> f64,
    ) -> Self {
        MetricSpec {
            key,
            dimension,
            per_si: 1.0,
            own_unit: None,
            name: key,
            display_unit: "",
            display_scale: 1.0,
            direction: Direction::Neutral,
            verification,
            derives_from: &[],
            source: Source::Series,
            batch_interval: false,
            get,
        }
    }

    /// Held in `unit` = `per_si` × SI, not in SI.
    pub const fn in_unit(mut self, unit: &'static str, per_si: f64) -> Self {
        self.own_unit = Some(unit);
        self.per_si = per_si;
        self
    }

    /// Shown as `name` in `unit` = `scale` × value.
    pub const fn shown(mut self, name: &'static str, unit: &'static str, scale: f64) -> Self {
        self.name = name;
        self.display_unit = unit;
        self.display_scale = scale;
        self
    }

    pub const fn direction(mut self, direction: Direction) -> Self {
        self.direction = direction;
        self
    }

    pub const fn derives_from(mut self, keys: &'static [&'static str]) -> Self {
        self.derives_from = keys;
        self
    }

    pub const fn source(mut self, source: Source) -> Self {
        self.source = source;
        self
    }

    pub const fn batch_interval(mut self) -> Self {
        self.batch_interval = true;
        self
    }

    /// The unit the key names (the unit of a bare threshold): its own, or the SI unit.
    pub fn unit(&self) -> &'static str {
        self.own_unit.unwrap_or_else(|| self.dimension.si_unit())
    }

    /// Its class and floor when `verify` compares it itself.
    pub fn compared(&self) -> Option<(MetricClass, f64)> {
        match self.verification {
            Verification::Always(class, floor) | Verification::WhenUsed(class, floor) => {
                Some((class, floor))
            }
            Verification::Through => None,
        }
    }

    /// Risk terms and chance constraints accept it (it is not larger when safer).
    pub fn penalisable(&self) -> bool {
        !matches!(self.direction, Direction::Safer { .. })
    }
}
