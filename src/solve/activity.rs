//! What holds an optimum (issue 33, item 2): each bound, linear limit and chance constraint of the
//! study with its margin at a point, and whether it is at its limit there.
//!
//! The rules, stated so that they can be checked against a problem's `[expect] active`:
//! - a bound is at its limit when the point lies within [`BOX_TOLERANCE`] of the box's width
//!   from it;
//! - a linear constraint, when the point's distance to its line in the unit box (rows scaled to
//!   unit norm, [`Scaling::feasible_set`]) is within [`BOX_TOLERANCE`];
//! - a chance constraint P(m > T) ≤ p, when the samples' (1 − p) quantile q of m (the value that
//!   decides the constraint: P(m > T) ≤ p ⇔ q ≤ T, up to the samples' resolution) lies within
//!   [`CHANCE_TOLERANCE`] of T, relative to max(|T|, the metric's floor), or when the study
//!   evaluated a point within [`NEIGHBOURHOOD`] of the unit box that scores higher and fails this
//!   constraint (the constraint is what keeps the score from rising there: a metric that is zero
//!   at its edge, such as the growth rate of a stability edge, moves by more than its floor across
//!   the optimizer's last step). Its margin (T − q) / max(|T|, floor) is positive on the safe
//!   side.
//!
//! The tolerances are those of the optimizers' resolution, not of the physics: a trust region stops
//! within its minimum radius (0.25-2 % of the box) of the edge it meets, and across that distance
//! a fatigue damage rate (∝ Ω) or a buckling utilization moves by a few per cent (the regression
//! problems' optima sit at 0.1-6 % of their chance thresholds; the next-nearest constraint that
//! does not hold one, 22 %).

use super::Scaling;
use crate::problem::study::Constraints;
use crate::study::{PointEvaluation, SampleOutcome};
use serde::Serialize;

/// Distance to a bound or a linear constraint, as a fraction of the unit box, within which it is
/// at its limit.
pub const BOX_TOLERANCE: f64 = 0.005;
/// Relative distance of a chance constraint's deciding quantile to its threshold within which it
/// is at its limit.
pub const CHANCE_TOLERANCE: f64 = 0.1;
/// Unit-box distance within which a better point that fails a chance constraint shows the
/// constraint holding the optimum: 5 % of the box (a trust region's last steps are 0.2-2 %).
pub const NEIGHBOURHOOD: f64 = 0.05;

/// One constraint at a point.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Activity {
    /// Its name in `[expect] active`: `"omega.min"`, `"v0.max"` (`"wob.max"`), a linear label
    /// (`"max_depth_of_cut"`, `"linear"`), `"chance.<metric>"`.
    pub name: String,
    /// Bounds: the point's Ω (rpm) or set-point (m/h or kN); linear: a_Ω Ω + a_s s (SI); chance:
    /// the samples' (1 − p) quantile of the metric (SI).
    pub value: f64,
    /// The bound, the right-hand side or the threshold, in the unit of `value`.
    pub limit: f64,
    /// Bounds and linear constraints: the distance to the limit in unit-box widths; chance
    /// constraints: (limit − value) / max(|limit|, floor). ≥ 0 on the feasible side.
    pub margin: f64,
    /// Within [`BOX_TOLERANCE`] or [`CHANCE_TOLERANCE`] of its limit.
    pub at_limit: bool,
}

/// Every constraint of `c` at the evaluated point `p` (bounds, then linear, then chance, in the
/// file's order), with the study's other `evaluated` points as evidence for the chance
/// constraints (module doc). A chance constraint whose metric no sample has is left out.
pub fn activity(
    c: &Constraints,
    p: &PointEvaluation,
    evaluated: &[PointEvaluation],
) -> Vec<Activity> {
    let scaling = Scaling::of(c);
    let op = p.op();
    let x = scaling.to_unit(op);
    let mut out = Vec::new();
    let key = c.kind.key();
    let shown = |s: f64| c.kind.to_unit(s);
    let rpm = crate::units::to_rpm;
    let bounds = [
        (
            "omega.min".to_string(),
            rpm(op.omega),
            rpm(c.omega[0]),
            x[0],
        ),
        (
            "omega.max".into(),
            rpm(op.omega),
            rpm(c.omega[1]),
            1.0 - x[0],
        ),
        (
            format!("{key}.min"),
            op.shown_set_point(),
            shown(c.set_point[0]),
            x[1],
        ),
        (
            format!("{key}.max"),
            op.shown_set_point(),
            shown(c.set_point[1]),
            1.0 - x[1],
        ),
    ];
    for (name, value, limit, margin) in bounds {
        out.push(Activity {
            name,
            value,
            limit,
            margin,
            at_limit: margin <= BOX_TOLERANCE,
        });
    }
    // The rows of the feasible set are the linear constraints in order, scaled to unit norm.
    if let Ok(set) = scaling.feasible_set(c) {
        let s = op.set_point(c.kind);
        for (k, l) in c.linear.iter().enumerate() {
            let (row, rhs) = (&set.a()[k], set.b()[k]);
            let margin = rhs - row[0] * x[0] - row[1] * x[1];
            out.push(Activity {
                name: l.label.to_string(),
                value: l.omega * op.omega + l.set_point * s,
                limit: l.upper,
                margin,
                at_limit: margin <= BOX_TOLERANCE,
            });
        }
    }
    for ch in &c.chance {
        let mut values: Vec<f64> = p
            .samples
            .iter()
            .filter_map(|s| match &s.outcome {
                SampleOutcome::Metrics(m) => m.get(&ch.metric).copied(),
                SampleOutcome::Failed(_) => None,
            })
            .collect();
        if values.is_empty() {
            continue;
        }
        values.sort_by(f64::total_cmp);
        let q = deciding_quantile(&values, ch.max_probability);
        let floor = crate::metrics::catalogue::find(&ch.metric)
            .and_then(|spec| spec.compared())
            .map_or(0.0, |(_, floor)| floor);
        let scale = ch.threshold.abs().max(floor).max(f64::MIN_POSITIVE);
        let margin = (ch.threshold - q) / scale;
        let score = p.objective.unwrap_or(f64::NEG_INFINITY);
        let blocked = evaluated.iter().any(|e| {
            let y = scaling.to_unit(e.op());
            e.objective.is_some_and(|s| s > score)
                && (y[0] - x[0]).hypot(y[1] - x[1]) <= NEIGHBOURHOOD
                && e.chance
                    .iter()
                    .any(|v| v.metric == ch.metric && !v.satisfied)
        });
        out.push(Activity {
            name: format!("chance.{}", ch.metric),
            value: q,
            limit: ch.threshold,
            margin,
            at_limit: margin.abs() <= CHANCE_TOLERANCE || blocked,
        });
    }
    out
}

/// Share of the window the bit may stick at an optimum without a warning: 5 % (a driller's
/// severe stick-slip sticks for a large part of each cycle; the study benchmark's "no damage"
/// optimum stuck 55 % of the time, unsaid: issue 33).
pub const STICK_WARNING: f64 = 0.05;
/// Peak bit speed over Ω above which an optimum is warned of: 2 (the slip phase of developed
/// stick-slip spins the bit to two or three times Ω).
pub const PEAK_SPEED_WARNING: f64 = 2.0;
/// Relative distance of Ω to a critical speed below which an optimum is warned of: 5 %.
pub const CRITICAL_SPEED_WARNING: f64 = 0.05;

/// Warnings on the dynamics at an optimum `best`, from the worst of its samples (a mean would hide
/// the sample that sticks): stick fraction above [`STICK_WARNING`], peak bit speed ratio above
/// [`PEAK_SPEED_WARNING`], critical speed margin below [`CRITICAL_SPEED_WARNING`]. Each says the
/// value, its threshold and how many samples pass it; none when the study constrains or penalises
/// the metric itself (it then says what it is worth).
pub fn warnings(best: &PointEvaluation, used: &[&str]) -> Vec<String> {
    let per_sample = |key: &str| -> Vec<f64> {
        best.samples
            .iter()
            .filter_map(|s| match &s.outcome {
                SampleOutcome::Metrics(m) => m.get(key).copied().filter(|v| !v.is_nan()),
                SampleOutcome::Failed(_) => None,
            })
            .collect()
    };
    let n = best.samples.len();
    let mut out = Vec::new();
    // (metric, warned above (else below), threshold, what the worst value says)
    type Check = (&'static str, bool, f64, fn(f64) -> String);
    let checks: [Check; 3] = [
        ("stick_fraction", true, STICK_WARNING, |v| {
            format!("the bit sticks {:.0} % of the window", 100.0 * v)
        }),
        ("max_bit_speed_ratio", true, PEAK_SPEED_WARNING, |v| {
            format!("the bit's peak speed is {v:.2} Ω")
        }),
        (
            "critical_speed_margin",
            false,
            CRITICAL_SPEED_WARNING,
            |v| format!("Ω is {:.1} % from a critical speed", 100.0 * v),
        ),
    ];
    for (key, above, threshold, say) in checks {
        if used.contains(&key) {
            continue;
        }
        let values = per_sample(key);
        let beyond = |v: &f64| {
            if above {
                *v > threshold
            } else {
                *v < threshold
            }
        };
        let count = values.iter().filter(|v| beyond(v)).count();
        if count == 0 {
            continue;
        }
        let worst = if above {
            values.iter().cloned().fold(f64::MIN, f64::max)
        } else {
            values.iter().cloned().fold(f64::MAX, f64::min)
        };
        out.push(format!(
            "{} in {} of {n} sample{} ({key} {} {}; the study neither scores nor constrains it)",
            say(worst),
            count,
            if n == 1 { "" } else { "s" },
            if above { "above" } else { "below" },
            threshold
        ));
    }
    out
}

/// The value of sorted `values` (n samples) that decides P(m > T) ≤ p: the smallest sample with at
/// most ⌊p n⌋ samples above it, the ⌈(1 − p) n⌉-th (1-based); the largest when p n < 1.
pub fn deciding_quantile(sorted: &[f64], p: f64) -> f64 {
    let n = sorted.len();
    let above = (p * n as f64 + 1e-9).floor() as usize;
    sorted[n - 1 - above.min(n - 1)]
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::model::{OperatingPoint, SetPoint, SetPointValue};
    use crate::problem::study::{ChanceConstraint, LinearConstraint};
    use crate::study::SampleResult;
    use std::collections::BTreeMap;

    /// A point at `op` whose samples read `fatigue_damage_per_h` = `damage`.
    pub(crate) fn point(op: OperatingPoint, damage: &[f64]) -> PointEvaluation {
        PointEvaluation {
            omega_rad_s: op.omega,
            omega_rpm: crate::units::to_rpm(op.omega),
            set_point: SetPointValue::of(&op),
            objective: Some(1.0),
            quantity: Some(1.0),
            risk: Vec::new(),
            chance: Vec::new(),
            feasible: true,
            failure: None,
            mean_metrics: BTreeMap::new(),
            samples_used: damage.len(),
            score_half_width: None,
            score_interval: None,
            samples: damage
                .iter()
                .enumerate()
                .map(|(k, &d)| SampleResult {
                    sample: k,
                    seed: k as u64,
                    outcome: SampleOutcome::Metrics(BTreeMap::from([(
                        "fatigue_damage_per_h".to_string(),
                        d,
                    )])),
                    cached: false,
                })
                .collect(),
            fidelity: crate::study::Fidelity::Full,
        }
    }

    #[test]
    fn bounds_lines_and_chance_constraints_at_their_limits() {
        let rpm = crate::units::from_rpm;
        // Ω 30-150 rpm, WOB 40-90 kN, Ω/(rad/s) + WOB/(10 kN) ≤ 20, damage ≤ 0.05/h with p 0.25.
        let c = Constraints {
            omega: [rpm(30.0), rpm(150.0)],
            kind: SetPoint::Wob,
            set_point: [40e3, 90e3],
            linear: vec![LinearConstraint {
                omega: 1.0,
                set_point: 1e-4,
                upper: 20.0,
                label: "linear",
            }],
            chance: vec![ChanceConstraint {
                metric: "fatigue_damage_per_h".into(),
                threshold: 0.05,
                max_probability: 0.25,
            }],
        };
        let held = |p: &PointEvaluation| -> Vec<String> {
            activity(&c, p, &[])
                .into_iter()
                .filter(|a| a.at_limit)
                .map(|a| a.name)
                .collect()
        };
        // Inside everything: the deciding quantile of four samples at p = 0.25 is the third
        // (0.040), 20 % below the threshold.
        let inside = point(
            OperatingPoint::hook_load(rpm(60.0), 60e3),
            &[0.01, 0.03, 0.04, 0.2],
        );
        assert!(held(&inside).is_empty(), "{:?}", activity(&c, &inside, &[]));
        let a = activity(&c, &inside, &[]);
        let chance = a
            .iter()
            .find(|a| a.name == "chance.fatigue_damage_per_h")
            .unwrap();
        assert_eq!(chance.value, 0.04);
        assert!((chance.margin - 0.2).abs() < 1e-12);
        // On the line at Ω = 11.5 rad/s, 85 kN (11.5 + 8.5 = 20), 10 % of the box from the WOB
        // bound; the third sample at 0.048 puts the chance constraint 4 % from its threshold.
        let corner = point(
            OperatingPoint::hook_load(11.5, 85e3),
            &[0.01, 0.03, 0.048, 0.2],
        );
        let corner_held = held(&corner);
        assert_eq!(
            corner_held,
            ["linear", "chance.fatigue_damage_per_h"],
            "{:?}",
            activity(&c, &corner, &[])
        );
        // 20 % from its threshold, but a point 1 % of the box away scores higher and fails it:
        // the constraint is what stops the score; a failing point 10 % away, or one that scores
        // lower, is no such evidence.
        let neighbour = |rpm_: f64, score: f64| {
            let mut e = point(OperatingPoint::hook_load(rpm(rpm_), 60e3), &[0.1]);
            e.objective = Some(score);
            e.chance = vec![crate::study::ChanceValue {
                metric: "fatigue_damage_per_h".into(),
                threshold: 0.05,
                probability: 1.0,
                max_probability: 0.25,
                satisfied: false,
            }];
            e
        };
        let with = |e: PointEvaluation| {
            activity(&c, &inside, &[e])
                .into_iter()
                .find(|a| a.name == "chance.fatigue_damage_per_h")
                .unwrap()
                .at_limit
        };
        assert!(with(neighbour(61.2, 2.0)));
        assert!(!with(neighbour(72.0, 2.0)));
        assert!(!with(neighbour(61.2, 0.5)));
        let top = point(OperatingPoint::hook_load(rpm(60.0), 90e3), &[0.0]);
        assert_eq!(held(&top), ["wob.max"]);
        let slow = point(OperatingPoint::hook_load(rpm(30.0), 60e3), &[0.0]);
        assert_eq!(held(&slow), ["omega.min"]);
    }

    #[test]
    fn an_optimum_that_sticks_or_sits_near_a_critical_speed_is_warned_of() {
        let mut p = point(OperatingPoint::feed(6.0, 1e-3), &[0.0, 0.0]);
        let set = |p: &mut PointEvaluation, k: usize, key: &str, v: f64| {
            if let SampleOutcome::Metrics(m) = &mut p.samples[k].outcome {
                m.insert(key.into(), v);
            }
        };
        for k in 0..2 {
            set(&mut p, k, "stick_fraction", [0.0, 0.55][k]);
            set(&mut p, k, "max_bit_speed_ratio", [1.2, 2.8][k]);
            set(&mut p, k, "critical_speed_margin", 0.3);
        }
        let w = warnings(&p, &["mean_rop_m_per_h"]);
        assert_eq!(w.len(), 2, "{w:?}");
        assert!(
            w[0].starts_with("the bit sticks 55 % of the window in 1 of 2 samples"),
            "{w:?}"
        );
        assert!(
            w[1].starts_with("the bit's peak speed is 2.80 Ω in 1 of 2 samples"),
            "{w:?}"
        );
        // A metric the study scores or constrains is its own warning.
        assert_eq!(
            warnings(&p, &["stick_fraction", "max_bit_speed_ratio"]).len(),
            0
        );
        set(&mut p, 1, "critical_speed_margin", 0.013);
        let w = warnings(&p, &["stick_fraction", "max_bit_speed_ratio"]);
        assert!(
            w.len() == 1 && w[0].starts_with("Ω is 1.3 % from a critical speed"),
            "{w:?}"
        );
    }

    #[test]
    fn the_deciding_quantile_leaves_at_most_p_n_samples_above_it() {
        let v: Vec<f64> = (1..=10).map(f64::from).collect();
        // p = 0.1 of 10: one sample may exceed T, so the 9th decides.
        assert_eq!(deciding_quantile(&v, 0.1), 9.0);
        assert_eq!(deciding_quantile(&v, 0.0), 10.0);
        assert_eq!(deciding_quantile(&v, 0.25), 8.0);
        // One sample: its value, whatever p < 1.
        assert_eq!(deciding_quantile(&[3.0], 0.1), 3.0);
        assert_eq!(deciding_quantile(&[3.0], 0.9), 3.0);
        // P(m > T) ≤ p holds exactly when the quantile is ≤ T.
        for p in [0.0, 0.1, 0.2, 0.35] {
            let q = deciding_quantile(&v, p);
            let exceed = |t: f64| v.iter().filter(|&&x| x > t).count() as f64 / 10.0;
            assert!(exceed(q) <= p + 1e-12, "p {p}");
            assert!(exceed(q - 1e-9) > p, "p {p}");
        }
    }
}
