//! Nonlinear (gyroscopic) inertia, Eq. (11), from the kinetic energy of MODEL.md §3.
//!
//! T = ½∫[… + 2ρI(θ̇x + θy θ̇z)²] dx; the part not in the mass operator (7) is
//! T_nl = ∫ ρI (2 θy θ̇x θ̇z + θy² θ̇z²) dx. Its Lagrange terms d/dt(∂T_nl/∂θ̇) − ∂T_nl/∂θ give the
//! inertial force per length that stands on the left-hand side with M Q̈ (this is −F_KE):
//!
//!   f_x = 2ρI (θ̇y θ̇z + θy θ̈z)
//!   f_y = −2ρI (θ̇x θ̇z + θy θ̇z²)
//!   f_z = 2ρI (θ̇x θ̇y + θy θ̈x + 2 θy θ̇y θ̇z + θy² θ̈z)
//!
//! (the paper's fifth line of (11) repeats the fourth and is dropped). Here θ̇x is the absolute
//! spin rate, rigid Ω included: 2ρIΩ θ̇ is the gyroscopic coupling of the two bending planes.

use super::{BeamElement, ElementMatrix, ElementVector, gauss_legendre_4};
use nalgebra::{Matrix3, SMatrix, Vector3};

/// Rows (θx, θy, θz) of the interpolation at the element's Gauss points, with weights.
#[derive(Debug, Clone)]
pub struct ElementInertia {
    rotations: [SMatrix<f64, 3, 12>; 4],
    weights: [f64; 4],
    /// Rotatory inertia per length ρI, kg·m.
    rho_i: f64,
}

/// Derivatives of the inertial force per length w.r.t. (θx, θy, θz) and their rates.
struct PointTangent {
    position: Matrix3<f64>,
    velocity: Matrix3<f64>,
    acceleration: Matrix3<f64>,
}

impl ElementInertia {
    pub fn new(element: &BeamElement) -> Self {
        let (xs, weights) = gauss_legendre_4(element.length);
        let rotations = xs.map(|x| {
            element
                .interpolation(x)
                .value
                .fixed_rows::<3>(3)
                .into_owned()
        });
        ElementInertia {
            rotations,
            weights,
            rho_i: element.section.rotary_inertia,
        }
    }

    fn point_force(
        &self,
        th: &Vector3<f64>,
        rate: &Vector3<f64>,
        acc: &Vector3<f64>,
    ) -> Vector3<f64> {
        let k = 2.0 * self.rho_i;
        let (ty, wx, wy, wz) = (th[1], rate[0], rate[1], rate[2]);
        Vector3::new(
            k * (wy * wz + ty * acc[2]),
            -k * (wx * wz + ty * wz * wz),
            k * (wx * wy + ty * acc[0] + 2.0 * ty * wy * wz + ty * ty * acc[2]),
        )
    }

    fn point_tangent(
        &self,
        th: &Vector3<f64>,
        rate: &Vector3<f64>,
        acc: &Vector3<f64>,
    ) -> PointTangent {
        let k = 2.0 * self.rho_i;
        let (ty, wx, wy, wz) = (th[1], rate[0], rate[1], rate[2]);
        #[rustfmt::skip]
        let position = Matrix3::new(
            0.0, k * acc[2], 0.0,
            0.0, -k * wz * wz, 0.0,
            0.0, k * (acc[0] + 2.0 * wy * wz + 2.0 * ty * acc[2]), 0.0,
        );
        #[rustfmt::skip]
        let velocity = Matrix3::new(
            0.0, k * wz, k * wy,
            -k * wz, 0.0, -k * (wx + 2.0 * ty * wz),
            k * wy, k * (wx + 2.0 * ty * wz), k * 2.0 * ty * wy,
        );
        #[rustfmt::skip]
        let acceleration = Matrix3::new(
            0.0, 0.0, k * ty,
            0.0, 0.0, 0.0,
            k * ty, 0.0, k * ty * ty,
        );
        PointTangent {
            position,
            velocity,
            acceleration,
        }
    }

    /// The nonlinear inertial force on the element's DOFs (left-hand side), N and N·m, from the
    /// absolute element displacement, velocity and acceleration vectors.
    pub fn force(&self, d: &ElementVector, v: &ElementVector, a: &ElementVector) -> ElementVector {
        let mut f = ElementVector::zeros();
        for (n, w) in self.rotations.iter().zip(self.weights) {
            let p = self.point_force(&(n * d), &(n * v), &(n * a));
            f.gemv_tr(w, n, &p, 1.0);
        }
        f
    }

    /// ∂force/∂d, ∂force/∂v, ∂force/∂a.
    pub fn tangents(
        &self,
        d: &ElementVector,
        v: &ElementVector,
        a: &ElementVector,
    ) -> [ElementMatrix; 3] {
        let mut out = [ElementMatrix::zeros(); 3];
        for (n, w) in self.rotations.iter().zip(self.weights) {
            let t = self.point_tangent(&(n * d), &(n * v), &(n * a));
            for (o, m) in out.iter_mut().zip([t.position, t.velocity, t.acceleration]) {
                *o += n.transpose() * (m * w) * n;
            }
        }
        out
    }

    /// The gyroscopic matrix per unit spin rate: ∂force/∂v at rest with θ̇x = 1 (skew-symmetric).
    pub fn gyroscopic(&self) -> ElementMatrix {
        let mut v = ElementVector::zeros();
        v[3] = 1.0;
        v[9] = 1.0;
        self.tangents(&ElementVector::zeros(), &v, &ElementVector::zeros())[1]
    }

    /// The nonlinear kinetic energy T_nl of the element, J.
    pub fn energy(&self, d: &ElementVector, v: &ElementVector) -> f64 {
        self.rotations
            .iter()
            .zip(self.weights)
            .map(|(n, w)| {
                let (th, rate) = (n * d, n * v);
                w * self.rho_i
                    * (2.0 * th[1] * rate[0] * rate[2] + th[1] * th[1] * rate[2] * rate[2])
            })
            .sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::Section;

    fn element() -> ElementInertia {
        let string = crate::problem::Problem::load(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/problems/seed_mc2014.toml"
        ))
        .unwrap()
        .model;
        ElementInertia::new(&BeamElement::new(1.0 / 3.0, Section::of(&string)))
    }

    /// A smooth trajectory of the element DOFs: d(t) = Σ c_k t^k with arbitrary coefficients.
    fn trajectory(t: f64) -> [ElementVector; 3] {
        let c =
            |k: usize| ElementVector::from_fn(|i, _| ((i * 7 + k * 3) as f64 * 0.61).sin() * 0.3);
        let mut d = c(0) + c(1) * t + c(2) * t * t + c(3) * t * t * t;
        let mut v = c(1) + c(2) * (2.0 * t) + c(3) * (3.0 * t * t);
        let a = c(2) * 2.0 + c(3) * (6.0 * t);
        // A spin of 2π rad/s on top, as in drilling.
        for i in [3, 9] {
            d[i] += 2.0 * std::f64::consts::PI * t;
            v[i] += 2.0 * std::f64::consts::PI;
        }
        [d, v, a]
    }

    #[test]
    fn force_is_the_euler_lagrange_expression_of_the_kinetic_energy() {
        let e = element();
        let t0 = 0.37;
        let [d, v, a] = trajectory(t0);
        let f = e.force(&d, &v, &a);
        let scale = f.abs().max();
        assert!(scale > 1e-3, "the test state must exercise the terms");
        // ∂T/∂v along the trajectory, differentiated in time; ∂T/∂d at t0; all by central differences.
        let dt_dv = |t: f64, j: usize| {
            let [d, mut v, _] = trajectory(t);
            let h = 1e-6;
            v[j] += h;
            let p = e.energy(&d, &v);
            v[j] -= 2.0 * h;
            (p - e.energy(&d, &v)) / (2.0 * h)
        };
        for j in 0..12 {
            let ht = 1e-4;
            let ddt = (dt_dv(t0 + ht, j) - dt_dv(t0 - ht, j)) / (2.0 * ht);
            let (mut dp, mut dm) = (d, d);
            dp[j] += 1e-6;
            dm[j] -= 1e-6;
            let dt_dd = (e.energy(&dp, &v) - e.energy(&dm, &v)) / 2e-6;
            let lagrange = ddt - dt_dd;
            assert!(
                (lagrange - f[j]).abs() < 1e-5 * scale,
                "DOF {j}: Euler–Lagrange {lagrange} vs force {}",
                f[j]
            );
        }
    }

    #[test]
    fn tangents_match_finite_differences_and_gyroscopic_matrix_is_skew() {
        let e = element();
        let [d, v, a] = trajectory(0.21);
        let t = e.tangents(&d, &v, &a);
        for (which, m) in t.iter().enumerate() {
            for j in 0..12 {
                let h = 1e-6;
                let bump = |x: &ElementVector, s: f64| {
                    let mut y = *x;
                    y[j] += s;
                    y
                };
                let (fp, fm) = match which {
                    0 => (
                        e.force(&bump(&d, h), &v, &a),
                        e.force(&bump(&d, -h), &v, &a),
                    ),
                    1 => (
                        e.force(&d, &bump(&v, h), &a),
                        e.force(&d, &bump(&v, -h), &a),
                    ),
                    _ => (
                        e.force(&d, &v, &bump(&a, h)),
                        e.force(&d, &v, &bump(&a, -h)),
                    ),
                };
                let fd = (fp - fm) / (2.0 * h);
                let err = (fd - m.column(j)).abs().max();
                assert!(
                    err < 1e-7 * (1.0 + m.abs().max()),
                    "tangent {which}, column {j}: error {err:e}"
                );
            }
        }
        let g = e.gyroscopic();
        assert!((g + g.transpose()).abs().max() < 1e-15 * g.abs().max() && g.abs().max() > 0.0);
    }
}
