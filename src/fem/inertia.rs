//! Nonlinear (gyroscopic) inertia, Eq. (11) with the sign of MODEL.md §3 [settled, turn 3].
//!
//! T = ½∫[… + 2ρI(θ̇x − θy θ̇z)²] dx: θ̇x − θy θ̇z is the spin rate of the section tilted by
//! (θy, θz) (rotation sequence R_z R_y R_x, up to cubic terms). The paper's Eq. (11) follows from
//! (θ̇x + θy θ̇z)², whose cross term has the wrong sign (with it forward whirl softens with Ω). The
//! part not in the mass operator (7) (which holds ρI θ̇x², the polar inertia 2ρI) is
//!
//!   T_nl = ∫ ρI (−2 θy θ̇x θ̇z + θy² θ̇z²) dx,
//!
//! with ∂T_nl/∂θ̇ = ρI (−2 θy θ̇z, 0, −2 θy θ̇x + 2 θy² θ̇z) and
//! ∂T_nl/∂θ = ρI (0, −2 θ̇x θ̇z + 2 θy θ̇z², 0). Its Lagrange terms d/dt(∂T_nl/∂θ̇) − ∂T_nl/∂θ give
//! the inertial force per length that stands on the left-hand side with M Q̈ (this is −F_KE):
//!
//!   f_x = −2ρI (θ̇y θ̇z + θy θ̈z)
//!   f_y = 2ρI (θ̇x θ̇z − θy θ̇z²)
//!   f_z = 2ρI (−θ̇x θ̇y − θy θ̈x + 2 θy θ̇y θ̇z + θy² θ̈z)
//!
//! (the paper's (11) with θy replaced by −θy, f_y, the force conjugate to θy, changing sign with
//! it; the paper's fifth line repeats the fourth and is dropped). Here θ̇x is the absolute spin rate, rigid Ω included: at rest the
//! gyroscopic coupling of the two bending planes is f_y = 2ρIΩ θ̇z, f_z = −2ρIΩ θ̇y, the rate of
//! change of the spin's angular momentum 2ρIΩ (1, θz, −θy) as the axis tilts (Nelson 1980;
//! Lalanne & Ferraris 1998): forward whirl stiffens with Ω.
//!
//! As for the strains, the rows (θx, θy, θz) of the interpolation are kept by their non-zeros and
//! the four Gauss points are evaluated together, one per lane ([`Lanes`]).

use super::lanes::{Lanes, Real, element_sums};
use super::{BeamElement, ELEMENT_DOF, ElementMatrix, ElementVector, gauss_legendre_4};
use nalgebra::{Matrix3, SMatrix, Vector3};

/// Element DOFs of θx (θx1, θx2), of the x–z plane (w1, θy1, w2, θy2) and of the x–y plane
/// (v1, θz1, v2, θz2): the only DOFs the rows θx, θy, θz of the interpolation take.
const TWIST_DOFS: [usize; 2] = [3, 9];
const PLANE_XZ_DOFS: [usize; 4] = [2, 4, 8, 10];
const PLANE_XY_DOFS: [usize; 4] = [1, 5, 7, 11];

/// The rotation rows (θx, θy, θz) of the interpolation by their non-zeros (10 of 36; each DOF
/// enters one row at most). [`ElementInertia::new`] checks that the rows vanish elsewhere. `T` is
/// `f64` at one Gauss point, or [`Lanes`] for the four.
#[derive(Debug, Clone, Copy)]
struct SparseRotations<T> {
    /// θx over [`TWIST_DOFS`].
    x: [T; 2],
    /// θy over [`PLANE_XZ_DOFS`].
    y: [T; 4],
    /// θz over [`PLANE_XY_DOFS`].
    z: [T; 4],
}

impl SparseRotations<Lanes> {
    /// The non-zeros of the dense rows (θx, θy, θz) at the four Gauss points; panics if the rows
    /// do not vanish outside the pattern.
    fn compress(rows: &[SMatrix<f64, 3, ELEMENT_DOF>; 4]) -> Self {
        let mut rest = *rows;
        let mut take = |r: usize, j: usize| {
            Lanes(std::array::from_fn(|p| {
                std::mem::take(&mut rest[p][(r, j)])
            }))
        };
        let n = SparseRotations {
            x: TWIST_DOFS.map(|j| take(0, j)),
            y: PLANE_XZ_DOFS.map(|j| take(1, j)),
            z: PLANE_XY_DOFS.map(|j| take(2, j)),
        };
        assert!(
            rest.iter().flatten().all(|&x| x == 0.0),
            "rotation interpolation has non-zeros outside the twist/bending pattern: {rest:?}"
        );
        n
    }

    /// The rows at Gauss point `p`.
    fn point(&self, p: usize) -> SparseRotations<f64> {
        let lane = |c: Lanes| c.0[p];
        SparseRotations {
            x: self.x.map(lane),
            y: self.y.map(lane),
            z: self.z.map(lane),
        }
    }
}

impl<T: Real> SparseRotations<T> {
    /// (θx, θy, θz) = N x.
    #[inline(always)]
    fn apply(&self, x: &[f64; ELEMENT_DOF]) -> [T; 3] {
        let ([x0, x1], [y0, y1, y2, y3], [z0, z1, z2, z3]) = (self.x, self.y, self.z);
        let (jx, jy, jz) = (TWIST_DOFS, PLANE_XZ_DOFS, PLANE_XY_DOFS);
        [
            x0 * x[jx[0]] + x1 * x[jx[1]],
            y0 * x[jy[0]] + y1 * x[jy[1]] + y2 * x[jy[2]] + y3 * x[jy[3]],
            z0 * x[jz[0]] + z1 * x[jz[1]] + z2 * x[jz[2]] + z3 * x[jz[3]],
        ]
    }

    /// Nᵀ p.
    #[inline(always)]
    fn transpose_product(&self, p: &[T; 3]) -> [T; ELEMENT_DOF] {
        let mut f = [T::from(0.0); ELEMENT_DOF];
        for (&j, &c) in TWIST_DOFS.iter().zip(&self.x) {
            f[j] = c * p[0];
        }
        for k in 0..4 {
            f[PLANE_XZ_DOFS[k]] = self.y[k] * p[1];
            f[PLANE_XY_DOFS[k]] = self.z[k] * p[2];
        }
        f
    }
}

impl SparseRotations<f64> {
    /// k += Nᵀ m N, column by column: Nᵀ (m (N e_j)).
    fn add_congruence(&self, m: &Matrix3<f64>, k: &mut ElementMatrix) {
        for j in 0..ELEMENT_DOF {
            let mut unit = [0.0; ELEMENT_DOF];
            unit[j] = 1.0;
            let mn = m * Vector3::from(self.apply(&unit));
            let col = self.transpose_product(&mn.data.0[0]);
            for (kij, c) in k.column_mut(j).iter_mut().zip(col) {
                *kij += c;
            }
        }
    }
}

/// The element DOFs as an array.
fn dofs(x: &ElementVector) -> &[f64; ELEMENT_DOF] {
    &x.data.0[0]
}

/// Rows (θx, θy, θz) of the interpolation at the element's Gauss points, with weights.
#[derive(Debug, Clone)]
pub struct ElementInertia {
    /// The rows at the four Gauss points (one lane each), by their non-zeros.
    rotations: SparseRotations<Lanes>,
    weights: Lanes,
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
        let rows = xs.map(|x| {
            element
                .interpolation(x)
                .value
                .fixed_rows::<3>(3)
                .into_owned()
        });
        ElementInertia {
            rotations: SparseRotations::compress(&rows),
            weights: Lanes(weights),
            rho_i: element.section.rotary_inertia,
        }
    }

    /// Inertial force per length from the rotations (θy used), rates and accelerations.
    #[inline(always)]
    fn point_force<T: Real>(&self, th: &[T; 3], rate: &[T; 3], acc: &[T; 3]) -> [T; 3] {
        let k = 2.0 * self.rho_i;
        let (ty, wx, wy, wz) = (th[1], rate[0], rate[1], rate[2]);
        [
            (wy * wz + ty * acc[2]) * -k,
            (wx * wz - ty * wz * wz) * k,
            (ty * 2.0 * wy * wz + ty * ty * acc[2] - wx * wy - ty * acc[0]) * k,
        ]
    }

    /// T_nl per length over ρI: −2 θy θ̇x θ̇z + θy² θ̇z².
    #[inline(always)]
    fn point_energy<T: Real>(th: &[T; 3], rate: &[T; 3]) -> T {
        let (ty, wx, wz) = (th[1], rate[0], rate[2]);
        ty * ty * wz * wz - ty * 2.0 * wx * wz
    }

    fn point_tangent(&self, th: &[f64; 3], rate: &[f64; 3], acc: &[f64; 3]) -> PointTangent {
        let k = 2.0 * self.rho_i;
        let (ty, wx, wy, wz) = (th[1], rate[0], rate[1], rate[2]);
        #[rustfmt::skip]
        let position = Matrix3::new(
            0.0, -k * acc[2], 0.0,
            0.0, -k * wz * wz, 0.0,
            0.0, k * (2.0 * wy * wz + 2.0 * ty * acc[2] - acc[0]), 0.0,
        );
        #[rustfmt::skip]
        let velocity = Matrix3::new(
            0.0, -k * wz, -k * wy,
            k * wz, 0.0, k * (wx - 2.0 * ty * wz),
            -k * wy, -k * (wx - 2.0 * ty * wz), k * 2.0 * ty * wy,
        );
        #[rustfmt::skip]
        let acceleration = Matrix3::new(
            0.0, 0.0, -k * ty,
            0.0, 0.0, 0.0,
            -k * ty, 0.0, k * ty * ty,
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
        self.force_and_energy(d, v, a).0
    }

    /// The nonlinear inertial force, N and N·m (as [`Self::force`]), and the nonlinear kinetic
    /// energy T_nl, J (as [`Self::energy`]), all four Gauss points at once.
    #[inline]
    pub fn force_and_energy(
        &self,
        d: &ElementVector,
        v: &ElementVector,
        a: &ElementVector,
    ) -> (ElementVector, f64) {
        let n = &self.rotations;
        let (th, rate) = (n.apply(dofs(d)), n.apply(dofs(v)));
        let p = self.point_force(&th, &rate, &n.apply(dofs(a)));
        let w = self.weights;
        let f = n.transpose_product(&[p[0] * w, p[1] * w, p[2] * w]);
        let t = Self::point_energy(&th, &rate) * (w * self.rho_i);
        (element_sums(&f), t.sum())
    }

    /// ∂force/∂d, ∂force/∂v, ∂force/∂a.
    pub fn tangents(
        &self,
        d: &ElementVector,
        v: &ElementVector,
        a: &ElementVector,
    ) -> [ElementMatrix; 3] {
        let mut out = [ElementMatrix::zeros(); 3];
        for (p, w) in self.weights.0.into_iter().enumerate() {
            let n = self.rotations.point(p);
            let t = self.point_tangent(&n.apply(dofs(d)), &n.apply(dofs(v)), &n.apply(dofs(a)));
            for (o, m) in out.iter_mut().zip([t.position, t.velocity, t.acceleration]) {
                n.add_congruence(&(m * w), o);
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
        let n = &self.rotations;
        let t = Self::point_energy(&n.apply(dofs(d)), &n.apply(dofs(v)));
        (t * (self.weights * self.rho_i)).sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fem::test_support::{Rng, relative_error, seed_string};
    use crate::model::Section;

    fn beam() -> BeamElement {
        BeamElement::new(1.0 / 3.0, Section::of(&seed_string()))
    }

    fn element() -> ElementInertia {
        ElementInertia::new(&beam())
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

    /// The sign of T_nl from the kinematics of a rotating section, independently of the formulas:
    /// with the orientation R = R_z(θz) R_y(θy) R_x(θx), whose axis R e_x = (cos θz cos θy,
    /// sin θz cos θy, −sin θy) is (1, v′, w′) for θz = v′, θy = −w′ (the model's bending
    /// kinematics, MODEL.md §2–3), the spin about the section's own axis is the x component of
    /// the body angular velocity RᵀṘ, exactly θ̇x − θ̇z sin θy. So ρI((RᵀṘ)_zy² − θ̇x²) must be
    /// T_nl per length up to the terms of sin θy beyond θy (θ̇x θ̇z θy³/3, relative θy²/6 < 1.5e-6
    /// here, against the scale 2|θy θ̇x θ̇z|), where the paper's sign (θ̇x + θy θ̇z) is off by 200 %.
    #[test]
    fn nonlinear_kinetic_energy_is_the_spin_of_the_tilted_section() {
        use nalgebra::{Rotation3, Unit};
        let skew = |a: Vector3<f64>| a.cross_matrix();
        let mut rng = Rng(5);
        for case in 0..20 {
            let th = [
                rng.uniform(-400.0, 400.0),
                rng.uniform(-3e-3, 3e-3),
                rng.uniform(-3e-3, 3e-3),
            ];
            let rate = [
                2.0 * std::f64::consts::PI + rng.uniform(-5.0, 5.0),
                rng.uniform(-1.0, 1.0),
                rng.uniform(-1.0, 1.0),
            ];
            let axes = [Vector3::x(), Vector3::y(), Vector3::z()];
            let rot: [_; 3] = std::array::from_fn(|i| {
                Rotation3::from_axis_angle(&Unit::new_normalize(axes[i]), th[i]).into_inner()
            });
            // Ṙ_i = θ̇_i R_i [e_i]×, and R = R_z R_y R_x by the product rule.
            let dot: [_; 3] = std::array::from_fn(|i| rot[i] * skew(axes[i]) * rate[i]);
            let r = rot[2] * rot[1] * rot[0];
            let r_dot =
                dot[2] * rot[1] * rot[0] + rot[2] * dot[1] * rot[0] + rot[2] * rot[1] * dot[0];
            let body = r.transpose() * r_dot;
            let spin = body[(2, 1)];
            assert!((body[(2, 1)] + body[(1, 2)]).abs() < 1e-12, "RᵀṘ is skew");
            assert!((spin - (rate[0] - rate[2] * th[1].sin())).abs() < 1e-12);
            let kinematic = spin * spin - rate[0] * rate[0];
            let model = ElementInertia::point_energy(&th, &rate);
            let scale = (2.0 * th[1] * rate[0] * rate[2]).abs();
            assert!(
                (model - kinematic).abs() < 2e-6 * scale + 1e-15,
                "case {case}: T_nl/ρI {model} vs kinematic {kinematic}"
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

    #[test]
    fn sparse_kernels_agree_with_the_dense_rotation_rows() {
        let (b, e) = (beam(), element());
        let (xs, ws) = gauss_legendre_4(b.length);
        let rows = xs.map(|x| b.interpolation(x).value.fixed_rows::<3>(3).into_owned());
        let k = 2.0 * b.section.rotary_inertia;
        let mut rng = Rng(77);
        for case in 0..50 {
            // Drilling-like states: lateral 1e-2 m and 1e-2 rad, spin angle hundreds of radians,
            // spin rate 2π ± 5 rad/s, lateral rates ~1, accelerations ~10.
            let mut d = ElementVector::from_fn(|_, _| rng.uniform(-1e-2, 1e-2));
            let mut v = ElementVector::from_fn(|_, _| rng.uniform(-1.0, 1.0));
            let a = ElementVector::from_fn(|_, _| rng.uniform(-20.0, 20.0));
            d[3] = rng.uniform(-400.0, 400.0);
            d[9] = d[3] + rng.uniform(-0.2, 0.2);
            v[3] = 2.0 * std::f64::consts::PI + rng.uniform(-5.0, 5.0);
            v[9] = v[3] + rng.uniform(-0.5, 0.5);
            let mut f_ref = ElementVector::zeros();
            let mut t_ref = 0.0;
            let mut tangents_ref = [ElementMatrix::zeros(); 3];
            for (n, w) in rows.iter().zip(ws) {
                let (th, rate, acc) = (n * d, n * v, n * a);
                let (ty, wx, wy, wz) = (th[1], rate[0], rate[1], rate[2]);
                // The formulas of the module documentation, through the dense rows.
                let p = Vector3::new(
                    -k * (wy * wz + ty * acc[2]),
                    k * (wx * wz - ty * wz * wz),
                    k * (-wx * wy - ty * acc[0] + 2.0 * ty * wy * wz + ty * ty * acc[2]),
                );
                f_ref += n.transpose() * p * w;
                t_ref += w * 0.5 * k * (-2.0 * ty * wx * wz + ty * ty * wz * wz);
                let t = e.point_tangent(&th.into(), &rate.into(), &acc.into());
                for (o, m) in tangents_ref
                    .iter_mut()
                    .zip([t.position, t.velocity, t.acceleration])
                {
                    *o += n.transpose() * (m * w) * n;
                }
            }
            let (f, t) = e.force_and_energy(&d, &v, &a);
            let err = relative_error(&f, &f_ref);
            assert!(err < 1e-12, "case {case}: force error {err:e}");
            assert!(
                (t - t_ref).abs() < 1e-12 * t_ref.abs(),
                "case {case}: {t} vs {t_ref}"
            );
            assert_eq!(e.force(&d, &v, &a), f);
            assert_eq!(e.energy(&d, &v), t);
            for (m, m_ref) in e.tangents(&d, &v, &a).iter().zip(&tangents_ref) {
                let err = relative_error(m, m_ref);
                assert!(err < 1e-12, "case {case}: tangent error {err:e}");
            }
        }
    }

    #[test]
    #[should_panic(expected = "outside the twist/bending pattern")]
    fn rotation_rows_outside_the_sparsity_pattern_are_rejected() {
        let b = beam();
        let mut rows = gauss_legendre_4(b.length)
            .0
            .map(|x| b.interpolation(x).value.fixed_rows::<3>(3).into_owned());
        rows[1][(1, 0)] = 1e-3; // θy depending on u1
        SparseRotations::compress(&rows);
    }
}
