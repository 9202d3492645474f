//! Validation of the study sections ([`super::study`]): every error names the file and the dotted
//! key and says what is allowed.

use super::ProblemError;
use super::check::Checker;
use super::file::ProblemFile;
use super::schema::RawQuantity;
use super::study::*;
use super::validate_range::{range, set_point_range};
use super::validate_threshold::threshold;
use crate::model::{Drillstring, SetPoint};
use crate::stats::Distribution;
use crate::stats::Statistic;
use std::f64::consts::PI;

const GAINS: &str = "one of \"mean\", \"lower_cvar\", \"quantile\", \"min\"";
const RISKS: &str =
    "one of \"mean\", \"std_dev\", \"cvar\", \"prob_exceed\", \"quantile\", \"max\"";

pub(super) fn study(
    c: &Checker,
    raw: &ProblemFile,
    model: &Drillstring,
) -> Result<Study, ProblemError> {
    let (uncertain, samples, seed) = match &raw.uncertain {
        None => (Vec::new(), 1, 0),
        Some(u) => uncertain(c, u, model)?,
    };
    let sequential = raw
        .uncertain
        .as_ref()
        .and_then(|u| u.sequential.as_ref())
        .and_then(|s| sequential(c, s, samples));
    let (quantity, statistic, risk) = match &raw.objective {
        None => (Quantity::Rop, Statistic::Mean, Vec::new()),
        Some(o) => objective(c, o)?,
    };
    // The second design variable: V0, or the WOB under a hook load.
    let kind = model.top.set_point();
    let constraints = raw
        .constraints
        .as_ref()
        .map(|k| constraints(c, k, kind))
        .transpose()?;
    let optimizer = optimizer(c, raw.optimizer.as_ref(), constraints.as_ref(), kind)?;
    let expect = raw
        .expect
        .as_ref()
        .map(|e| super::validate_expect::expect(c, e, constraints.as_ref(), kind))
        .transpose()?;
    // Risk terms and chance constraints penalise large values: the safety factor and the
    // critical speed margin (larger is safer) are refused there, in favour of their inverses;
    // the utilization needs a yield strength.
    let at = |uses: &dyn Fn(&str) -> bool| {
        risk.iter()
            .position(|r| uses(&r.metric))
            .map(|i| format!("objective.risk[{i}].metric"))
            .or_else(|| {
                let chance = &constraints.as_ref()?.chance;
                let i = chance.iter().position(|k| uses(&k.metric))?;
                Some(format!("constraints.chance[{i}].metric"))
            })
    };
    for spec in crate::metrics::METRICS {
        if let crate::metrics::Direction::Safer { inverse, hint } = spec.direction
            && let Some(key) = at(&|m| m == spec.key)
        {
            return Err(c.fail(
                &key,
                format!(
                    "{} is larger when safer, and risk terms and chance constraints penalise large values: use {inverse} {hint}",
                    spec.key
                ),
            ));
        }
    }
    if model.pipe.yield_strength.is_none()
        && let Some(key) = at(&|m| m == "von_mises_utilization")
    {
        return Err(c.fail(
            &key,
            "von_mises_utilization needs model.pipe.yield_strength (a pressure or an API grade such as \"S-135\")".into(),
        ));
    }
    if expect.is_some() && constraints.is_none() {
        return Err(c.fail(
            "expect",
            "needs a [constraints] section (the bounds of Ω and V0) to be solvable".into(),
        ));
    }
    Ok(Study {
        uncertain,
        samples,
        sequential,
        seed,
        quantity,
        statistic,
        risk,
        constraints,
        optimizer,
        // Read by `validate_explore` once the mesh and the window it overrides are known.
        explore: None,
        expect,
        overrides: Overrides::default(),
    })
}

fn seed(c: &Checker, key: &str, s: Option<i64>, default: u64) -> Result<u64, ProblemError> {
    match s {
        None => Ok(default),
        Some(v) if v >= 0 => Ok(v as u64),
        Some(v) => Err(c.fail(key, format!("must be an integer >= 0, got {v}"))),
    }
}

fn uncertain(
    c: &Checker,
    u: &UncertainSection,
    model: &Drillstring,
) -> Result<(Vec<UncertainParameter>, usize, u64), ProblemError> {
    if !(1..=10_000).contains(&u.samples) {
        return Err(c.fail(
            "uncertain.samples",
            format!("must be an integer in [1, 10000], got {}", u.samples),
        ));
    }
    let seed = seed(c, "uncertain.seed", u.seed, 0)?;
    let mut params: Vec<UncertainParameter> = Vec::new();
    for (i, p) in u.parameter.iter().enumerate() {
        let before = c.errors_recorded();
        let at = |k: &str| format!("uncertain.parameter[{i}].{k}");
        let key = ParameterKey::resolve(&p.key, model).ok_or_else(|| {
            let names = ParameterKey::available(model);
            c.fail(
                &at("key"),
                format!("must be one of {}, got {:?}", names.join(", "), p.key),
            )
        })?;
        if params.iter().any(|q| q.key == key) {
            return Err(c.fail(&at("key"), format!("{:?} is declared twice", p.key)));
        }
        if key.spec().range.integer {
            return Err(c.fail(
                &at("key"),
                format!(
                    "{:?} is a count (whole numbers only): it cannot be drawn from a continuous law",
                    p.key
                ),
            ));
        }
        let dim = key.spec().dimension;
        let value = |name: &str, v: &Option<RawQuantity>| -> Result<f64, ProblemError> {
            match v {
                Some(v) => c.value(&at(name), v, dim),
                None => Err(c.fail(&at(name), format!("is required for law = {:?}", p.law))),
            }
        };
        let cov = |v: Option<f64>| {
            v.ok_or_else(|| c.fail(&at("cov"), format!("is required for law = {:?}", p.law)))
        };
        let unused = |names: &[(&str, bool)]| -> Result<(), ProblemError> {
            match names.iter().find(|(_, set)| *set) {
                Some((n, _)) => {
                    Err(c.fail(&at(n), format!("is not a parameter of law = {:?}", p.law)))
                }
                None => Ok(()),
            }
        };
        let law = match p.law.as_str() {
            "gamma" | "lognormal" => {
                unused(&[
                    ("std", p.std.is_some()),
                    ("low", p.low.is_some()),
                    ("high", p.high.is_some()),
                ])?;
                let (mean, cov) = (value("mean", &p.mean)?, cov(p.cov)?);
                if p.law == "gamma" {
                    Distribution::Gamma { mean, cov }
                } else {
                    Distribution::LogNormal { mean, cov }
                }
            }
            "normal" => {
                unused(&[
                    ("cov", p.cov.is_some()),
                    ("low", p.low.is_some()),
                    ("high", p.high.is_some()),
                ])?;
                Distribution::Normal {
                    mean: value("mean", &p.mean)?,
                    std: value("std", &p.std)?,
                }
            }
            "uniform" => {
                unused(&[
                    ("mean", p.mean.is_some()),
                    ("cov", p.cov.is_some()),
                    ("std", p.std.is_some()),
                ])?;
                Distribution::Uniform {
                    low: value("low", &p.low)?,
                    high: value("high", &p.high)?,
                }
            }
            other => {
                return Err(c.fail(
                    &at("law"),
                    format!(
                        "must be one of \"gamma\", \"lognormal\", \"normal\", \"uniform\", got {other:?}"
                    ),
                ));
            }
        };
        if c.errors_recorded() > before {
            continue; // a value of the law was refused where it was read
        }
        // The spread's range and the laws' own rules, under the key of the parameter at fault.
        law.validate()
            .map_err(|e| c.fail(&at(e.parameter), e.message))?;
        // A law whose bulk leaves the admissible range would make samples fail, not the
        // optimisation: refuse it here (normal laws are not truncated).
        // At either end: the support's end or mean ∓ 4σ, whichever is nearer.
        let (mean, reach) = (law.mean(), 4.0 * law.std_dev());
        let ends = [
            (
                law.lower_support().max(mean - reach),
                "mean − 4σ or the lower end",
                "use gamma or lognormal for a positive parameter",
            ),
            (
                law.upper_support().min(mean + reach),
                "mean + 4σ or the upper end",
                "lower the mean, the spread or `high`",
            ),
        ];
        for (end, which, advice) in ends {
            if let Err(why) = key.admissible(model, end) {
                return Err(c.fail(
                    &at("law"),
                    format!(
                        "puts probability on inadmissible values of {} ({which} = {end}; it {why}); {advice}",
                        key.name()
                    ),
                ));
            }
        }
        params.push(UncertainParameter { key, law });
    }
    // Every value the samples draw, checked here rather than when the study runs (a draw
    // outside its range was refused at run time, without the file's name).
    if c.errors_recorded() == 0
        && let Some(bad) = inadmissible_draw(&params, u.samples as usize, seed, model)
    {
        return Err(c.fail(
            &format!("uncertain.parameter[{}].law", bad.parameter),
            format!("{bad}; narrow the law (or use another seed or fewer samples)"),
        ));
    }
    // Entries refused above (a bad value, a misspelt key, `[[uncertain.parameters]]`) are
    // reported once, where they were met: the section is not also called empty.
    if params.is_empty() && u.samples > 1 && !c.refused_under("uncertain") {
        return Err(c.fail(
            "uncertain.parameter",
            format!(
                "is empty, so the {} samples would all be the same; declare at least one [[uncertain.parameter]] or set samples = 1",
                u.samples
            ),
        ));
    }
    Ok((params, u.samples as usize, seed))
}

/// `[uncertain.sequential]` against `samples` (the most a point may use). Every refused key
/// is recorded (one pass); None when one was.
fn sequential(c: &Checker, s: &RawSequential, samples: usize) -> Option<Sequential> {
    let before = c.errors_recorded();
    let key = |k: &str| format!("uncertain.sequential.{k}");
    let min_samples = match usize::try_from(s.min_samples) {
        Ok(n) if n >= 2 && n < samples => n,
        _ if samples < 3 => {
            c.record(
                &key("min_samples"),
                format!(
                    "must be an integer in [2, uncertain.samples − 1], and uncertain.samples = {samples} (the most samples a point may use) leaves no room: raise it to at least 3, got min_samples = {}",
                    s.min_samples
                ),
            );
            0
        }
        _ => {
            c.record(
                &key("min_samples"),
                format!(
                    "must be an integer in [2, {}] (at least 2 for an interval, fewer than uncertain.samples = {samples}, the most samples a point may use), got {}",
                    samples - 1,
                    s.min_samples
                ),
            );
            0
        }
    };
    let w = s.score_half_width;
    if !(w.is_finite() && w > 0.0 && w <= SCORE_HALF_WIDTH_MAX) {
        c.record(
            &key("score_half_width"),
            format!(
                "must be a number in (0, {SCORE_HALF_WIDTH_MAX:e}], in the score's unit (m/h for quantity = \"rop\", 1 for \"efficiency\"), got {}",
                crate::units::show(w)
            ),
        );
    }
    let confidence = s.confidence.unwrap_or(CONFIDENCE);
    if !CONFIDENCE_RANGE.contains(&confidence) {
        c.record(
            &key("confidence"),
            format!(
                "must be a number in [{}, {}] (the level of the score's confidence interval), got {}",
                CONFIDENCE_RANGE.start(),
                CONFIDENCE_RANGE.end(),
                crate::units::show(confidence)
            ),
        );
    }
    let resamples = match s.resamples {
        None => RESAMPLES,
        Some(n) => match usize::try_from(n) {
            Ok(n) if RESAMPLES_RANGE.contains(&n) => n,
            _ => {
                c.record(
                    &key("resamples"),
                    format!(
                        "must be an integer in [{}, {}] (bootstrap resamples of the score), got {n}",
                        RESAMPLES_RANGE.start(),
                        RESAMPLES_RANGE.end()
                    ),
                );
                0
            }
        },
    };
    (c.errors_recorded() == before).then_some(Sequential {
        min_samples,
        score_half_width: w,
        confidence,
        resamples,
    })
}

fn statistic(
    c: &Checker,
    key: &str,
    name: &str,
    level: Option<f64>,
    threshold: Option<f64>,
    allowed: &[&str],
    allowed_text: &str,
) -> Result<Statistic, ProblemError> {
    if !allowed.contains(&name) {
        return Err(c.fail(
            &format!("{key}.statistic"),
            format!("must be {allowed_text}, got {name:?}"),
        ));
    }
    let need = |v: Option<f64>, what: &str| {
        v.ok_or_else(|| {
            c.fail(
                &format!("{key}.{what}"),
                format!("is required for statistic = {name:?}"),
            )
        })
    };
    let s = match name {
        "mean" => Statistic::Mean,
        "std_dev" => Statistic::StdDev,
        "max" => Statistic::Max,
        "min" => Statistic::Min,
        "cvar" => Statistic::Cvar {
            level: need(level, "level")?,
        },
        "lower_cvar" => Statistic::LowerCvar {
            level: need(level, "level")?,
        },
        "quantile" => Statistic::Quantile {
            level: need(level, "level")?,
        },
        "prob_exceed" => Statistic::ProbExceed {
            threshold: need(threshold, "threshold")?,
        },
        _ => unreachable!("checked against the allowed names"),
    };
    let uses_level = matches!(name, "cvar" | "lower_cvar" | "quantile");
    if level.is_some() && !uses_level {
        return Err(c.fail(
            &format!("{key}.level"),
            format!("is not used by statistic = {name:?}"),
        ));
    }
    if threshold.is_some() && name != "prob_exceed" {
        return Err(c.fail(
            &format!("{key}.threshold"),
            format!("is not used by statistic = {name:?}"),
        ));
    }
    s.validate()
        .map_err(|m| c.fail(&format!("{key}.statistic"), m))?;
    Ok(s)
}

fn metric(c: &Checker, key: &str, name: &str) -> Result<String, ProblemError> {
    use crate::metrics::catalogue;
    if catalogue::find(name).is_some() {
        Ok(name.to_string())
    } else {
        let keys: Vec<&str> = catalogue::keys().collect();
        Err(c.fail(
            key,
            format!("must be one of {}, got {name:?}", keys.join(", ")),
        ))
    }
}

fn objective(
    c: &Checker,
    o: &ObjectiveSection,
) -> Result<(Quantity, Statistic, Vec<RiskTerm>), ProblemError> {
    let quantity = match o.quantity.as_deref().unwrap_or("rop") {
        "rop" => Quantity::Rop,
        "efficiency" => Quantity::Efficiency,
        other => {
            return Err(c.fail(
                "objective.quantity",
                format!("must be \"rop\" or \"efficiency\", got {other:?}"),
            ));
        }
    };
    let stat = statistic(
        c,
        "objective",
        o.statistic.as_deref().unwrap_or("mean"),
        o.level,
        o.threshold,
        &["mean", "lower_cvar", "quantile", "min"],
        GAINS,
    )?;
    let mut risk = Vec::new();
    for (i, r) in o.risk.iter().enumerate() {
        let key = format!("objective.risk[{i}]");
        let m = metric(c, &format!("{key}.metric"), &r.metric)?;
        let threshold = r
            .threshold
            .as_ref()
            .map(|t| threshold(c, &format!("{key}.threshold"), &m, t))
            .transpose()?;
        let s = statistic(
            c,
            &key,
            r.statistic.as_deref().unwrap_or("mean"),
            r.level,
            threshold,
            &["mean", "std_dev", "cvar", "prob_exceed", "quantile", "max"],
            RISKS,
        )?;
        if !(r.weight.is_finite() && r.weight >= 0.0) {
            return Err(c.fail(
                &format!("{key}.weight"),
                format!("must be a finite number >= 0, got {}", r.weight),
            ));
        }
        risk.push(RiskTerm {
            metric: m,
            statistic: s,
            weight: r.weight,
        });
    }
    Ok((quantity, stat, risk))
}

/// Largest magnitude of a `[[constraints.linear]]` coefficient or bound (SI): far beyond any
/// physical limit on (Ω, V0) (V0 ≤ 1 m/h is `v0 = 3600`, `upper = 1`), it keeps the products
/// with the bounds finite.
const LINEAR_MAX: f64 = 1e9;
/// Smallest magnitude of a non-zero coefficient: below it the row's norm is lost to round-off.
const LINEAR_MIN: f64 = 1e-9;

fn constraints(
    c: &Checker,
    k: &ConstraintsSection,
    kind: SetPoint,
) -> Result<Constraints, ProblemError> {
    use super::Dimension::*;
    let omega = range(
        c,
        "constraints.omega",
        "operating_point.omega",
        &k.omega,
        AngularVelocity,
    )?;
    let set_point = set_point_range(c, "constraints", kind, &k.v0, &k.wob)?;
    let mut linear = Vec::new();
    if k.max_depth_of_cut.is_some() && kind == SetPoint::Wob {
        c.record(
            "constraints.max_depth_of_cut",
            "is a line in (Omega, V0) (2 pi V0 / Omega <= d); under top = \"hook_load\" the \
             design variables are Omega and the WOB, and the WOB set-point decides the depth of \
             cut: remove it and bound the WOB (constraints.wob) instead"
                .into(),
        );
    } else if let Some(d) = &k.max_depth_of_cut {
        // Depth of cut per revolution 2π V0 / Ω ≤ d  ⇔  2π V0 − d Ω ≤ 0 (Ω > 0).
        let d = c.positive("constraints.max_depth_of_cut", d, Length)?;
        linear.push(LinearConstraint {
            omega: -d,
            set_point: 2.0 * PI,
            upper: 0.0,
            label: "max_depth_of_cut",
        });
    }
    for (i, l) in k.linear.iter().enumerate() {
        let key = format!("constraints.linear[{i}]");
        let mut refused = false;
        let (own, other, unit) = match kind {
            SetPoint::Feed => (l.v0, l.wob, "per m/s"),
            SetPoint::Wob => (l.wob, l.v0, "per N"),
        };
        if other.is_some() {
            refused = true;
            let other_key = if kind == SetPoint::Feed { "wob" } else { "v0" };
            c.record(
                &format!("{key}.{other_key}"),
                format!(
                    "is not a design variable of this problem (its set-point is {}): use {}",
                    kind.symbol(),
                    kind.key()
                ),
            );
        }
        let a_s = own.unwrap_or(0.0);
        for (name, v, unit) in [
            ("omega", l.omega, "per rad/s"),
            (kind.key(), a_s, unit),
            ("upper", l.upper, "SI"),
        ] {
            let coefficient = name != "upper";
            let ok = v.abs() <= LINEAR_MAX && (!coefficient || v == 0.0 || v.abs() >= LINEAR_MIN);
            if !ok {
                refused = true;
                let allowed = if coefficient {
                    format!("0 or a magnitude in [{LINEAR_MIN:e}, {LINEAR_MAX:e}] ({unit})")
                } else {
                    format!("a finite number in [-{LINEAR_MAX:e}, {LINEAR_MAX:e}]")
                };
                let got = crate::units::show(v);
                c.record(
                    &format!("{key}.{name}"),
                    format!("must be {allowed}, got {got}"),
                );
            }
        }
        if refused {
            continue;
        }
        if l.omega == 0.0 && a_s == 0.0 {
            return Err(c.fail(
                &key,
                format!(
                    "needs a non-zero coefficient on omega or {} (SI: per rad/s, {unit})",
                    kind.key()
                ),
            ));
        }
        linear.push(LinearConstraint {
            omega: l.omega,
            set_point: a_s,
            upper: l.upper,
            label: "linear",
        });
    }
    let mut chance = Vec::new();
    for (i, ch) in k.chance.iter().enumerate() {
        let key = format!("constraints.chance[{i}]");
        let m = metric(c, &format!("{key}.metric"), &ch.metric)?;
        let threshold = threshold(c, &format!("{key}.threshold"), &m, &ch.threshold)?;
        if !(0.0..1.0).contains(&ch.max_probability) {
            return Err(c.fail(
                &format!("{key}.max_probability"),
                format!("must be in [0, 1), got {}", ch.max_probability),
            ));
        }
        chance.push(ChanceConstraint {
            metric: m,
            threshold,
            max_probability: ch.max_probability,
        });
    }
    Ok(Constraints {
        omega,
        kind,
        set_point,
        linear,
        chance,
    })
}

/// A key the method does not read is refused, naming the key and the method. The section is
/// destructured exhaustively so that a new key cannot be forgotten here.
fn refuse_unused_keys(
    c: &Checker,
    o: &OptimizerSection,
    method: Method,
) -> Result<(), ProblemError> {
    let OptimizerSection {
        method: _,
        max_evaluations,
        grid,
        start,
        initial_radius,
        min_radius,
        seed,
        initial_design,
        ego_share,
        explore: _,
    } = o;
    let given = [
        ("max_evaluations", max_evaluations.is_some()),
        ("grid", grid.is_some()),
        ("start", start.is_some()),
        ("initial_radius", initial_radius.is_some()),
        ("min_radius", min_radius.is_some()),
        ("seed", seed.is_some()),
        ("initial_design", initial_design.is_some()),
        ("ego_share", ego_share.is_some()),
    ];
    match given
        .iter()
        .find(|(key, set)| *set && !method.keys().contains(key))
    {
        None => Ok(()),
        Some((key, _)) => Err(c.fail(
            &format!("optimizer.{key}"),
            format!(
                "is not used by method \"{}\" (its keys: {})",
                method.name(),
                method.keys().join(", ")
            ),
        )),
    }
}

fn optimizer(
    c: &Checker,
    o: Option<&OptimizerSection>,
    constraints: Option<&Constraints>,
    kind: SetPoint,
) -> Result<OptimizerSettings, ProblemError> {
    use super::Dimension::*;
    let Some(o) = o else {
        return Ok(OptimizerSettings::default());
    };
    let method = match o.method.as_deref().unwrap_or("trust_region") {
        "trust_region" => Method::TrustRegion,
        "nelder_mead" => Method::NelderMead,
        "particle_swarm" => Method::ParticleSwarm,
        "grid" => Method::Grid,
        "ego" => Method::Ego,
        "ego+trust_region" => Method::EgoTrustRegion,
        other => {
            return Err(c.fail(
                "optimizer.method",
                format!(
                    "must be one of \"trust_region\", \"nelder_mead\", \"particle_swarm\", \"grid\", \"ego\", \"ego+trust_region\", got {other:?}"
                ),
            ));
        }
    };
    refuse_unused_keys(c, o, method)?;
    let max_evaluations = match o.max_evaluations {
        None => None,
        Some(n) if usize::try_from(n).is_ok_and(|n| MAX_EVALUATIONS.contains(&n)) => {
            Some(n as usize)
        }
        Some(n) => {
            return Err(c.fail(
                "optimizer.max_evaluations",
                format!("must be an integer in [3, 100000], got {n}"),
            ));
        }
    };
    let in_grid = |n: &i64| usize::try_from(*n).is_ok_and(|n| GRID_POINTS.contains(&n));
    let grid = match &o.grid {
        None => None,
        Some(g) if g.len() == 2 && g.iter().all(in_grid) => Some([g[0] as usize, g[1] as usize]),
        Some(g) => {
            return Err(c.fail(
                "optimizer.grid",
                format!(
                    "must be [n_omega, n_{}] with each in [2, 200], got {g:?}",
                    kind.key()
                ),
            ));
        }
    };
    let start = match &o.start {
        None => None,
        Some(s) if s.len() == 2 => {
            let w = c.value_as(
                "optimizer.start[0]",
                "operating_point.omega",
                &s[0],
                AngularVelocity,
            );
            let v = c.value_as(
                "optimizer.start[1]",
                &format!("operating_point.{}", kind.key()),
                &s[1],
                kind.dimension(),
            );
            let known = |x: &[f64]| x.iter().all(|x| !x.is_nan());
            if !known(&[w, v]) {
                // Refused where read; the builders need not see it again.
                None
            } else if let Some(k) = constraints
                && known(&[k.omega[0], k.omega[1], k.set_point[0], k.set_point[1]])
                && (!(k.omega[0]..=k.omega[1]).contains(&w)
                    || !(k.set_point[0]..=k.set_point[1]).contains(&v))
            {
                use crate::units::{short, to_rpm};
                let (key, unit) = (kind.key(), kind.unit());
                return Err(c.fail(
                    "optimizer.start",
                    format!(
                        "must lie inside the bounds constraints.omega = [{}, {}] rpm and constraints.{key} = [{}, {}] {unit}, got ({} rpm, {} {unit})",
                        short(to_rpm(k.omega[0])),
                        short(to_rpm(k.omega[1])),
                        short(kind.to_unit(k.set_point[0])),
                        short(kind.to_unit(k.set_point[1])),
                        short(to_rpm(w)),
                        short(kind.to_unit(v))
                    ),
                ));
            } else {
                Some([w, v])
            }
        }
        Some(s) => {
            return Err(c.fail(
                "optimizer.start",
                format!(
                    "must be a pair [omega, {}], got {} values",
                    kind.key(),
                    s.len()
                ),
            ));
        }
    };
    let fraction = |key: &str, v: Option<f64>| -> Result<Option<f64>, ProblemError> {
        match v {
            None => Ok(None),
            Some(x) if x > 0.0 && x <= 1.0 => Ok(Some(x)),
            Some(x) => Err(c.fail(
                key,
                format!("must be a fraction of the bounds box in (0, 1], got {x}"),
            )),
        }
    };
    let initial_radius = fraction("optimizer.initial_radius", o.initial_radius)?;
    let min_radius = fraction("optimizer.min_radius", o.min_radius)?;
    let seed = seed(c, "optimizer.seed", o.seed, 0)?;
    let initial_design = match o.initial_design {
        None => None,
        Some(n) if usize::try_from(n).is_ok_and(|n| INITIAL_DESIGN.contains(&n)) => {
            Some(n as usize)
        }
        Some(n) => {
            return Err(c.fail(
                "optimizer.initial_design",
                format!("must be an integer in [3, 1000], got {n}"),
            ));
        }
    };
    // Defaults, min_radius < initial_radius and the ranges again: the method's builder.
    let settings = match method {
        Method::TrustRegion | Method::NelderMead => {
            let d = LocalSearchSettings::default();
            LocalSearchSettings::builder()
                .max_evaluations(max_evaluations.unwrap_or(d.max_evaluations))
                .start(start)
                .initial_radius(initial_radius.unwrap_or(d.initial_radius))
                .min_radius(min_radius.unwrap_or(d.min_radius))
                .grid(grid.unwrap_or(d.grid))
                .build()
                .map(if method == Method::TrustRegion {
                    OptimizerSettings::TrustRegion
                } else {
                    OptimizerSettings::NelderMead
                })
        }
        Method::ParticleSwarm => {
            let d = ParticleSwarmSettings::default();
            ParticleSwarmSettings::builder()
                .max_evaluations(max_evaluations.unwrap_or(d.max_evaluations))
                .min_radius(min_radius.unwrap_or(d.min_radius))
                .seed(seed)
                .grid(grid.unwrap_or(d.grid))
                .build()
                .map(OptimizerSettings::ParticleSwarm)
        }
        Method::Grid => GridSettings::builder()
            .grid(grid.unwrap_or(GridSettings::default().grid))
            .build()
            .map(OptimizerSettings::Grid),
        Method::Ego => {
            let d = EgoSettings::default();
            EgoSettings::builder()
                .max_evaluations(max_evaluations.unwrap_or(d.max_evaluations))
                .initial_design(initial_design.unwrap_or(d.initial_design))
                .seed(seed)
                .grid(grid.unwrap_or(d.grid))
                .build()
                .map(OptimizerSettings::Ego)
        }
        Method::EgoTrustRegion => {
            let d = EgoTrustRegionSettings::default();
            EgoTrustRegionSettings::builder()
                .max_evaluations(max_evaluations.unwrap_or(d.max_evaluations))
                .initial_design(initial_design.unwrap_or(d.initial_design))
                .seed(seed)
                .ego_share(o.ego_share.unwrap_or(d.ego_share))
                .initial_radius(initial_radius.unwrap_or(d.initial_radius))
                .min_radius(min_radius.unwrap_or(d.min_radius))
                .grid(grid.unwrap_or(d.grid))
                .build()
                .map(OptimizerSettings::EgoTrustRegion)
        }
    };
    settings.map_err(|e| c.fail(&format!("optimizer.{}", e.key), e.message))
}
