//! The map between operating points and the optimizer's unit box: x = (Ω − Ω_min)/(Ω_max − Ω_min),
//! y = (s − s_min)/(s_max − s_min) for the set-point s (V0, or the WOB under a hook load). Ω
//! (rad/s) and V0 (m/s) differ by three orders of magnitude, Ω and the WOB (N) by four; in the
//! unit box a trust-region radius means the same thing along both axes.

use crate::model::{OperatingPoint, SetPoint};
use crate::optimize::{FeasibleSet, OptimizeError};
use crate::problem::study::Constraints;

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Scaling {
    pub omega: [f64; 2],
    /// What the second axis is.
    pub kind: SetPoint,
    /// The set-point's bounds, SI.
    pub set_point: [f64; 2],
}

impl Scaling {
    pub fn of(c: &Constraints) -> Self {
        Scaling {
            omega: c.omega,
            kind: c.kind,
            set_point: c.set_point,
        }
    }

    pub fn to_unit(&self, op: OperatingPoint) -> Vec<f64> {
        let s = self.set_point;
        vec![
            (op.omega - self.omega[0]) / (self.omega[1] - self.omega[0]),
            (op.set_point(self.kind) - s[0]) / (s[1] - s[0]),
        ]
    }

    pub fn from_unit(&self, x: &[f64]) -> OperatingPoint {
        let s = self.set_point;
        OperatingPoint::of(
            self.kind,
            self.omega[0] + x[0] * (self.omega[1] - self.omega[0]),
            s[0] + x[1] * (s[1] - s[0]),
        )
    }

    /// The bounds and linear constraints in unit-box coordinates, each row scaled to unit norm.
    pub fn feasible_set(&self, c: &Constraints) -> Result<FeasibleSet, OptimizeError> {
        let s = self.set_point;
        let (dw, dv) = (self.omega[1] - self.omega[0], s[1] - s[0]);
        let mut a = Vec::new();
        let mut b = Vec::new();
        for l in &c.linear {
            let row = [l.omega * dw, l.set_point * dv];
            let rhs = l.upper - l.omega * self.omega[0] - l.set_point * s[0];
            let norm = row[0].hypot(row[1]);
            a.push(vec![row[0] / norm, row[1] / norm]);
            b.push(rhs / norm);
        }
        FeasibleSet::new(vec![0.0, 0.0], vec![1.0, 1.0], a, b)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::problem::study::LinearConstraint;

    #[test]
    fn round_trip_and_depth_of_cut_in_unit_coordinates() {
        let c = Constraints {
            omega: [2.0, 12.0],
            kind: SetPoint::Feed,
            set_point: [1e-3, 5e-3],
            linear: vec![LinearConstraint {
                omega: -2e-3,
                set_point: 2.0 * std::f64::consts::PI,
                upper: 0.0,
                label: "max_depth_of_cut",
            }],
            chance: vec![],
        };
        let s = Scaling::of(&c);
        let op = OperatingPoint {
            omega: 7.0,
            v0: 2e-3,
            wob: 0.0,
        };
        let x = s.to_unit(op);
        assert!((x[0] - 0.5).abs() < 1e-15 && (x[1] - 0.25).abs() < 1e-15);
        let back = s.from_unit(&x);
        assert!((back.omega - 7.0).abs() < 1e-12 && (back.v0 - 2e-3).abs() < 1e-15);
        // Depth of cut 2π V0/Ω ≤ 2 mm: at Ω = 7 rad/s the limit is V0 = 2.228e-3 m/s.
        let set = s.feasible_set(&c).unwrap();
        let limit = 2e-3 * 7.0 / (2.0 * std::f64::consts::PI);
        let below = s.to_unit(OperatingPoint {
            omega: 7.0,
            v0: 0.99 * limit,
            wob: 0.0,
        });
        let above = s.to_unit(OperatingPoint {
            omega: 7.0,
            v0: 1.01 * limit,
            wob: 0.0,
        });
        assert!(set.contains(&below, 1e-12));
        assert!(!set.contains(&above, 1e-12));
    }

    #[test]
    fn a_hook_load_maps_its_wob_and_keeps_v0_at_zero() {
        let c = Constraints {
            omega: [2.0, 12.0],
            kind: SetPoint::Wob,
            set_point: [20e3, 120e3],
            // Ω/(rad/s) + WOB/(10 kN) ≤ 15.
            linear: vec![LinearConstraint {
                omega: 1.0,
                set_point: 1e-4,
                upper: 15.0,
                label: "linear",
            }],
            chance: vec![],
        };
        let s = Scaling::of(&c);
        let x = s.to_unit(OperatingPoint::hook_load(7.0, 45e3));
        assert!((x[0] - 0.5).abs() < 1e-15 && (x[1] - 0.25).abs() < 1e-15);
        let back = s.from_unit(&x);
        assert_eq!(back.v0, 0.0);
        assert!((back.omega - 7.0).abs() < 1e-12 && (back.wob - 45e3).abs() < 1e-9);
        // At Ω = 7 rad/s the line allows 80 kN.
        let set = s.feasible_set(&c).unwrap();
        let at = |w: f64| s.to_unit(OperatingPoint::hook_load(7.0, w));
        assert!(set.contains(&at(79.9e3), 1e-12));
        assert!(!set.contains(&at(80.1e3), 1e-12));
    }
}
