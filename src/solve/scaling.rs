//! The map between operating points and the optimizer's unit box: x = (Ω − Ω_min)/(Ω_max − Ω_min),
//! y = (V0 − V_min)/(V_max − V_min). Ω (rad/s) and V0 (m/s) differ by three orders of magnitude;
//! in the unit box a trust-region radius means the same thing along both axes.

use crate::model::OperatingPoint;
use crate::optimize::{FeasibleSet, OptimizeError};
use crate::problem::study::Constraints;

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Scaling {
    pub omega: [f64; 2],
    pub v0: [f64; 2],
}

impl Scaling {
    pub fn of(c: &Constraints) -> Self {
        Scaling {
            omega: c.omega,
            v0: c.v0,
        }
    }

    pub fn to_unit(&self, op: OperatingPoint) -> Vec<f64> {
        vec![
            (op.omega - self.omega[0]) / (self.omega[1] - self.omega[0]),
            (op.v0 - self.v0[0]) / (self.v0[1] - self.v0[0]),
        ]
    }

    pub fn from_unit(&self, x: &[f64]) -> OperatingPoint {
        OperatingPoint {
            omega: self.omega[0] + x[0] * (self.omega[1] - self.omega[0]),
            v0: self.v0[0] + x[1] * (self.v0[1] - self.v0[0]),
        }
    }

    /// The bounds and linear constraints in unit-box coordinates, each row scaled to unit norm.
    pub fn feasible_set(&self, c: &Constraints) -> Result<FeasibleSet, OptimizeError> {
        let (dw, dv) = (self.omega[1] - self.omega[0], self.v0[1] - self.v0[0]);
        let mut a = Vec::new();
        let mut b = Vec::new();
        for l in &c.linear {
            let row = [l.omega * dw, l.v0 * dv];
            let rhs = l.upper - l.omega * self.omega[0] - l.v0 * self.v0[0];
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
            v0: [1e-3, 5e-3],
            linear: vec![LinearConstraint {
                omega: -2e-3,
                v0: 2.0 * std::f64::consts::PI,
                upper: 0.0,
                label: "max_depth_of_cut",
            }],
            chance: vec![],
        };
        let s = Scaling::of(&c);
        let op = OperatingPoint {
            omega: 7.0,
            v0: 2e-3,
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
        });
        let above = s.to_unit(OperatingPoint {
            omega: 7.0,
            v0: 1.01 * limit,
        });
        assert!(set.contains(&below, 1e-12));
        assert!(!set.contains(&above, 1e-12));
    }
}
