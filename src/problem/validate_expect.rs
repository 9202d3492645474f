//! Validation of `[expect]`, the optimum a regression problem is known to have: the ranges of Ω,
//! the set-point (V0, or the WOB under a hook load) and the score, the reason, and the constraints declared to hold the optimum (`active`),
//! checked against the problem's own constraints and the expected ranges.

use super::ProblemError;
use super::check::Checker;
use super::study::{ActiveConstraint, Constraints, Expect, ExpectSection};
use super::validate_range::{range, set_point_range};
use crate::model::SetPoint;

/// The names `[expect] active` accepts besides `chance.<metric>` and the linear labels: the
/// bounds of Ω and of the set-point of `kind` (`v0.*`, or `wob.*` under a hook load).
fn bounds(kind: SetPoint) -> [(String, ActiveConstraint); 4] {
    [
        ("omega.min".into(), ActiveConstraint::OmegaMin),
        ("omega.max".into(), ActiveConstraint::OmegaMax),
        (format!("{}.min", kind.key()), ActiveConstraint::SetPointMin),
        (format!("{}.max", kind.key()), ActiveConstraint::SetPointMax),
    ]
}

pub(super) fn expect(
    c: &Checker,
    e: &ExpectSection,
    constraints: Option<&Constraints>,
    kind: SetPoint,
) -> Result<Expect, ProblemError> {
    use super::Dimension::*;
    let omega = range(
        c,
        "expect.omega",
        "operating_point.omega",
        &e.omega,
        AngularVelocity,
    )?;
    let set_point = set_point_range(c, "expect", kind, &e.v0, &e.wob)?;
    let objective = match &e.objective {
        None => None,
        Some(o) if o.len() == 2 && o[0].is_finite() && o[1].is_finite() && o[0] <= o[1] => {
            Some([o[0], o[1]])
        }
        Some(o) => {
            return Err(c.fail(
                "expect.objective",
                format!("must be a finite pair [min, max] with min <= max, got {o:?}"),
            ));
        }
    };
    if e.reason.trim().is_empty() {
        return Err(c.fail(
            "expect.reason",
            "must say how the expected ranges were established (e.g. a `drillopt map` run)".into(),
        ));
    }
    let active = match (&e.active, constraints) {
        (None, _) => None,
        // Without [constraints] the study refuses `[expect]` itself, naming that section.
        (Some(_), None) => Some(Vec::new()),
        (Some(names), Some(k)) => Some(active(c, names, k, omega, set_point)?),
    };
    Ok(Expect {
        omega,
        set_point,
        objective,
        reason: e.reason.clone(),
        active,
    })
}

/// The declared active constraints, each naming a constraint of the problem, and a bound
/// declared exactly when the expected range reaches it.
fn active(
    c: &Checker,
    names: &[String],
    k: &Constraints,
    omega: [f64; 2],
    set_point: [f64; 2],
) -> Result<Vec<ActiveConstraint>, ProblemError> {
    let bounds = bounds(k.kind);
    let allowed = || {
        let mut all: Vec<String> = bounds.iter().map(|(n, _)| format!("\"{n}\"")).collect();
        all.extend(k.linear.iter().map(|l| format!("\"{}\"", l.label)));
        all.extend(k.chance.iter().map(|x| format!("\"chance.{}\"", x.metric)));
        all.dedup();
        all.join(", ")
    };
    let mut out = Vec::new();
    for (i, name) in names.iter().enumerate() {
        let key = format!("expect.active[{i}]");
        let found = if let Some((_, b)) = bounds.iter().find(|(n, _)| n == name) {
            Some(b.clone())
        } else if let Some(metric) = name.strip_prefix("chance.") {
            k.chance
                .iter()
                .any(|x| x.metric == metric)
                .then(|| ActiveConstraint::Chance(metric.to_string()))
        } else {
            k.linear
                .iter()
                .find(|l| l.label == name)
                .map(|l| ActiveConstraint::Linear(l.label))
        };
        let Some(found) = found else {
            return Err(c.fail(
                &key,
                format!(
                    "`{name}` is not a constraint of this problem; allowed: {}",
                    allowed()
                ),
            ));
        };
        if out.contains(&found) {
            return Err(c.fail(&key, format!("`{name}` is listed twice")));
        }
        out.push(found);
    }
    if [omega, set_point, k.omega, k.set_point]
        .iter()
        .flatten()
        .any(|x| x.is_nan())
    {
        return Ok(out); // a range or bound was refused where read: not checked again
    }
    let reaches = |x: f64, bound: f64| (x - bound).abs() <= 1e-9 * bound.abs();
    let expect_key = format!("expect.{}", k.kind.key());
    let checks = [
        (
            "expect.omega",
            omega[0] <= k.omega[0] || reaches(omega[0], k.omega[0]),
        ),
        (
            "expect.omega",
            omega[1] >= k.omega[1] || reaches(omega[1], k.omega[1]),
        ),
        (
            expect_key.as_str(),
            set_point[0] <= k.set_point[0] || reaches(set_point[0], k.set_point[0]),
        ),
        (
            expect_key.as_str(),
            set_point[1] >= k.set_point[1] || reaches(set_point[1], k.set_point[1]),
        ),
    ];
    for ((range_key, reached), (name, bound)) in checks.into_iter().zip(bounds.iter()) {
        let declared = out.contains(bound);
        if declared && !reached {
            return Err(c.fail(
                "expect.active",
                format!(
                    "declares `{name}` active, but {range_key} does not reach that bound of constraints.{}; widen the range to the bound or drop `{name}`",
                    &name[..name.len() - 4]
                ),
            ));
        }
        if reached && !declared {
            return Err(c.fail(
                "expect.active",
                format!(
                    "{range_key} reaches the bound `{name}` of [constraints], which is not listed; add `{name}` or narrow the range strictly inside the bounds"
                ),
            ));
        }
    }
    Ok(out)
}
