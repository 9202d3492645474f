//! How much a binding bound costs: the local slope of the robust score at an optimum, from the
//! points the study already evaluated around it (no extra simulation).
//!
//! The score is fitted by a plane, score ≈ a + g·(x − x*), over the feasible points of the
//! optimum's fidelity within [`FIT_RADIUS`] of it in the unit box (the optimum included), by least
//! squares; the gradient g, converted to score units per rpm and per unit of the set-point (m/h,
//! or kN under a hook load), says what moving a binding bound would give: at a V0 bound that holds
//! the optimum, raising the bound 1 m/h would gain about `per_set_point` of score. It is a local
//! estimate over the optimizer's last steps, not a derivative: a chance constraint that binds
//! nearby makes it one-sided, and the fit is refused ([`score_slope`] returns `None`) when the
//! points do not spread over at least [`MIN_SPREAD`] of the box in both directions.

use super::Scaling;
use crate::problem::study::Constraints;
use crate::study::PointEvaluation;
use serde::Serialize;

/// Unit-box distance of the points the fit uses: 15 % (a trust region's last iterates and the
/// design points around them).
pub const FIT_RADIUS: f64 = 0.15;
/// Smallest standard deviation of the fitted points along each axis of the unit box: 1 %.
pub const MIN_SPREAD: f64 = 0.01;

/// The local slope of the score at an optimum.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ScoreSlope {
    /// ∂score/∂Ω, score units (m/h for a score of ROP) per rpm.
    pub per_rpm: f64,
    /// ∂score/∂s, score units per m/h of V0, or per kN of WOB under a hook load.
    pub per_set_point: f64,
    /// The evaluated points of the fit (the optimum included).
    pub points: usize,
    /// The fit's radius, a fraction of the unit box ([`FIT_RADIUS`]).
    pub radius: f64,
}

/// The plane fitted through the feasible `evaluated` points of `best`'s fidelity within
/// [`FIT_RADIUS`] of `best` (module doc); `None` with fewer than 3 points or a spread below
/// [`MIN_SPREAD`] along an axis.
pub fn score_slope(
    c: &Constraints,
    best: &PointEvaluation,
    evaluated: &[PointEvaluation],
) -> Option<ScoreSlope> {
    let scaling = Scaling::of(c);
    let x0 = scaling.to_unit(best.op());
    let mut rows: Vec<[f64; 3]> = Vec::new();
    for p in evaluated.iter().chain(std::iter::once(best)) {
        let Some(score) = p.objective.filter(|s| s.is_finite()) else {
            continue;
        };
        if !p.feasible || p.fidelity != best.fidelity {
            continue;
        }
        let x = scaling.to_unit(p.op());
        let (dx, dy) = (x[0] - x0[0], x[1] - x0[1]);
        if dx.hypot(dy) > FIT_RADIUS {
            continue;
        }
        // The optimum itself is also among the evaluated points: once.
        if rows.iter().any(|r| r[0] == dx && r[1] == dy) {
            continue;
        }
        rows.push([dx, dy, score]);
    }
    let n = rows.len();
    if n < 3 {
        return None;
    }
    let mean = |k: usize| rows.iter().map(|r| r[k]).sum::<f64>() / n as f64;
    let (mx, my, ms) = (mean(0), mean(1), mean(2));
    let cov = |a: usize, b: usize, ma: f64, mb: f64| {
        rows.iter().map(|r| (r[a] - ma) * (r[b] - mb)).sum::<f64>() / n as f64
    };
    let (sxx, syy, sxy) = (cov(0, 0, mx, mx), cov(1, 1, my, my), cov(0, 1, mx, my));
    let (sxs, sys) = (cov(0, 2, mx, ms), cov(1, 2, my, ms));
    // The smaller eigenvalue of the points' covariance: their spread across the thinner axis.
    let half_trace = 0.5 * (sxx + syy);
    let root = (0.25 * (sxx - syy).powi(2) + sxy * sxy).sqrt();
    if half_trace - root < MIN_SPREAD * MIN_SPREAD {
        return None;
    }
    let det = sxx * syy - sxy * sxy;
    let gx = (syy * sxs - sxy * sys) / det;
    let gy = (sxx * sys - sxy * sxs) / det;
    // Unit box → rpm and the set-point's shown unit.
    let rpm_width = crate::units::to_rpm(c.omega[1] - c.omega[0]);
    let set_width = c.kind.to_unit(c.set_point[1] - c.set_point[0]);
    Some(ScoreSlope {
        per_rpm: gx / rpm_width,
        per_set_point: gy / set_width,
        points: n,
        radius: FIT_RADIUS,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{OperatingPoint, SetPoint};

    fn constraints() -> Constraints {
        Constraints {
            omega: [crate::units::from_rpm(30.0), crate::units::from_rpm(150.0)],
            kind: SetPoint::Feed,
            set_point: [2.0 / 3600.0, 20.0 / 3600.0],
            linear: Vec::new(),
            chance: Vec::new(),
        }
    }

    /// A feasible point at (rpm, m/h) scoring `score`.
    fn at(rpm: f64, v: f64, score: f64) -> PointEvaluation {
        let op = OperatingPoint::feed(crate::units::from_rpm(rpm), v / 3600.0);
        let mut p = crate::solve::activity_tests::point(op, &[0.0]);
        p.objective = Some(score);
        p
    }

    #[test]
    fn a_plane_of_scores_gives_its_own_slopes() {
        // score = 3 + 0.02/rpm · Ω + 0.5/(m/h) · V0, optimum at the V0 bound (120 rpm, 20 m/h);
        // points within 15 % of the box (18 rpm, 2.7 m/h), one outside, one infeasible.
        let c = constraints();
        let plane = |r: f64, v: f64| 3.0 + 0.02 * r + 0.5 * v;
        let best = at(120.0, 20.0, plane(120.0, 20.0));
        let mut evaluated: Vec<PointEvaluation> = [(110.0, 19.0), (125.0, 18.5), (118.0, 17.8)]
            .iter()
            .map(|&(r, v)| at(r, v, plane(r, v)))
            .collect();
        evaluated.push(at(60.0, 5.0, 100.0)); // far: not in the fit
        let mut infeasible = at(121.0, 19.5, 100.0);
        infeasible.feasible = false;
        evaluated.push(infeasible);
        evaluated.push(best.clone()); // the optimum is among the evaluated points too
        let s = score_slope(&c, &best, &evaluated).unwrap();
        assert_eq!(s.points, 4);
        assert!((s.per_rpm - 0.02).abs() < 1e-12, "{s:?}");
        assert!((s.per_set_point - 0.5).abs() < 1e-12, "{s:?}");
    }

    #[test]
    fn too_few_or_collinear_points_give_no_slope() {
        let c = constraints();
        let best = at(120.0, 20.0, 10.0);
        assert_eq!(score_slope(&c, &best, &[at(119.0, 20.0, 9.9)]), None);
        // Along V0 = 20 m/h only: no spread across V0.
        let line: Vec<PointEvaluation> = [110.0, 115.0, 125.0]
            .iter()
            .map(|&r| at(r, 20.0, r / 10.0))
            .collect();
        assert_eq!(score_slope(&c, &best, &line), None);
    }
}
