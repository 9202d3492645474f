//! Validation of `[expect]`, the optimum a regression problem is known to have: the ranges of Ω,
//! V0 and the score, the reason, and the constraints declared to hold the optimum (`active`),
//! checked against the problem's own constraints and the expected ranges.

use super::ProblemError;
use super::study::{ActiveConstraint, Constraints, Expect, ExpectSection};
use super::validate::Checker;
use super::validate_study::range;

/// The names `[expect] active` accepts besides `chance.<metric>` and the linear labels.
const BOUNDS: [(&str, ActiveConstraint); 4] = [
    ("omega.min", ActiveConstraint::OmegaMin),
    ("omega.max", ActiveConstraint::OmegaMax),
    ("v0.min", ActiveConstraint::V0Min),
    ("v0.max", ActiveConstraint::V0Max),
];

pub(super) fn expect(
    c: &Checker,
    e: &ExpectSection,
    constraints: Option<&Constraints>,
) -> Result<Expect, ProblemError> {
    use super::Dimension::*;
    let omega = range(
        c,
        "expect.omega",
        "operating_point.omega",
        &e.omega,
        AngularVelocity,
    )?;
    let v0 = range(c, "expect.v0", "operating_point.v0", &e.v0, Velocity)?;
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
        (Some(names), Some(k)) => Some(active(c, names, k, omega, v0)?),
    };
    Ok(Expect {
        omega,
        v0,
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
    v0: [f64; 2],
) -> Result<Vec<ActiveConstraint>, ProblemError> {
    let allowed = || {
        let mut all: Vec<String> = BOUNDS.iter().map(|(n, _)| format!("\"{n}\"")).collect();
        all.extend(k.linear.iter().map(|l| format!("\"{}\"", l.label)));
        all.extend(k.chance.iter().map(|x| format!("\"chance.{}\"", x.metric)));
        all.dedup();
        all.join(", ")
    };
    let mut out = Vec::new();
    for (i, name) in names.iter().enumerate() {
        let key = format!("expect.active[{i}]");
        let found = if let Some((_, b)) = BOUNDS.iter().find(|(n, _)| n == name) {
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
    if [omega, v0, k.omega, k.v0]
        .iter()
        .flatten()
        .any(|x| x.is_nan())
    {
        return Ok(out); // a range or bound was refused where read: not checked again
    }
    let reaches = |x: f64, bound: f64| (x - bound).abs() <= 1e-9 * bound.abs();
    let checks = [
        (
            "omega.min",
            "expect.omega",
            omega[0] <= k.omega[0] || reaches(omega[0], k.omega[0]),
        ),
        (
            "omega.max",
            "expect.omega",
            omega[1] >= k.omega[1] || reaches(omega[1], k.omega[1]),
        ),
        (
            "v0.min",
            "expect.v0",
            v0[0] <= k.v0[0] || reaches(v0[0], k.v0[0]),
        ),
        (
            "v0.max",
            "expect.v0",
            v0[1] >= k.v0[1] || reaches(v0[1], k.v0[1]),
        ),
    ];
    for ((name, range_key, reached), (_, bound)) in checks.into_iter().zip(BOUNDS.iter()) {
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
