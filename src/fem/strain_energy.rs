//! Geometrically nonlinear strain energy of the rotation-consistent kinematics (MODEL.md §2, §3).
//!
//! Kinematics: u_x = u − Y θz + Z θy, u_y = v + Y − y, u_z = w + Z − z with the spun section
//! coordinates Y = y cos θx − z sin θx, Z = y sin θx + z cos θx. Working out the Green–Lagrange
//! strains and changing the section variables from (y, z) to (Y, Z) (a rotation: the annulus and dA
//! are unchanged) gives, with a = u′ + Y(θx′θy − θz′) + Z(θy′ + θx′θz):
//!
//!   E_xx = a + ½ (a² + (v′ − Z θx′)² + (w′ + Y θx′)²),
//!   (γ_xy, γ_xz) = R(−θx) Γ,   Γ = (v′ − θz − Z θx′ − a θz,  w′ + θy + Y θx′ + a θy),
//!
//! so |γ| = |Γ| and the energy per unit length depends on the generalised strains
//! g = (u′, v′, w′, θx′, θy′, θz′, θy, θz) only: θx itself drops out (objectivity). E_xx is a
//! polynomial of degree 2 and Γ of degree 1 in (Y, Z), so the section integrals are exact from the
//! annulus moments ∫dA = A, ∫Y² = ∫Z² = I, ∫Y⁴ = ∫Z⁴ = 3K₄, ∫Y²Z² = K₄, K₄ = π(R_ext⁶ − R_int⁶)/24,
//! odd moments zero. The energy per length is
//!
//!   W(g) = ½ [ E ∫E_xx² dA + G (κ_s A |Γ̄|² + κ_t ∫|Γ − Γ̄|² dA) ],  Γ̄ the section average,
//!
//! whose quadratic part is exactly the stiffness operator (9).
//!
//! The element kernels run for every element at every residual evaluation of the time-step loop,
//! so [`ElementStrains`] keeps G = ∂g/∂d by its 28 non-zeros (of 96) and evaluates the four Gauss
//! points together, one per lane ([`Lanes`]), with no generic matrix products.

use super::lanes::{Lanes, Real};
use super::{BeamElement, ELEMENT_DOF, ElementMatrix, ElementVector};
use crate::model::{Drillstring, Section};
use nalgebra::{SMatrix, SVector};
use num_dual::{DualNum, gradient, hessian};
use std::f64::consts::PI;

/// Number of generalised strains g = (u′, v′, w′, θx′, θy′, θz′, θy, θz).
pub const STRAIN_VARS: usize = 8;
/// The generalised strains at a point.
pub type Strains<T> = SVector<T, STRAIN_VARS>;

/// The constitutive and section data of the strain energy per unit length.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StrainEnergy {
    /// Young's modulus E, Pa.
    pub youngs_modulus: f64,
    /// Shear modulus G, Pa.
    pub shear_modulus: f64,
    /// Transverse shear correction κ_s.
    pub shear_factor: f64,
    /// Torsional correction κ_t.
    pub torsion_factor: f64,
    /// ∫dA = A, m².
    pub area: f64,
    /// ∫Y² dA = I, m⁴.
    pub second_moment: f64,
    /// ∫Y²Z² dA = K₄ (and ∫Y⁴ dA = 3K₄), m⁶.
    pub fourth_moment: f64,
}

impl StrainEnergy {
    pub fn of(string: &Drillstring) -> Self {
        let p = &string.pipe;
        let section = Section::of(string);
        StrainEnergy {
            youngs_modulus: p.youngs_modulus,
            shear_modulus: section.shear_modulus,
            shear_factor: p.shear_factor,
            torsion_factor: p.torsion_factor,
            area: section.area,
            second_moment: section.second_moment,
            fourth_moment: PI / 24.0 * (p.outer_radius.powi(6) - p.inner_radius.powi(6)),
        }
    }

    /// Strain energy per unit length W(g), J/m, for any dual-number type (for derivatives).
    pub fn density<T: DualNum<Primitive = f64> + Copy>(&self, g: &Strains<T>) -> T {
        let [du, dv, dw, dtx, dty, dtz, ty, tz] = [g[0], g[1], g[2], g[3], g[4], g[5], g[6], g[7]];
        let (a_, i_, k4) = (self.area, self.second_moment, self.fourth_moment);
        let half = 0.5;
        // a = e0 + k1 Y + k2 Z.
        let e0 = du;
        let k1 = dtx * ty - dtz;
        let k2 = dty + dtx * tz;
        // E_xx = c0 + c1 Y + c2 Z + c3 Y² + c4 YZ + c5 Z².
        let c0 = e0 + (e0 * e0 + dv * dv + dw * dw) * half;
        let c1 = k1 * (e0 + 1.0) + dw * dtx;
        let c2 = k2 * (e0 + 1.0) - dv * dtx;
        let c3 = (k1 * k1 + dtx * dtx) * half;
        let c4 = k1 * k2;
        let c5 = (k2 * k2 + dtx * dtx) * half;
        let exx2 = c0 * c0 * a_
            + c0 * (c3 + c5) * (2.0 * i_)
            + (c1 * c1 + c2 * c2) * i_
            + (c3 * c3 + c5 * c5) * (3.0 * k4)
            + c3 * c5 * (2.0 * k4)
            + c4 * c4 * k4;
        // Γ = Γ̄ + (linear in Y, Z).
        let g1_mean = dv - tz - e0 * tz;
        let g2_mean = dw + ty + e0 * ty;
        let (g1_y, g1_z) = (-(k1 * tz), -(dtx + k2 * tz));
        let (g2_y, g2_z) = (dtx + k1 * ty, k2 * ty);
        let mean_sq = g1_mean * g1_mean + g2_mean * g2_mean;
        let fluct_sq = (g1_y * g1_y + g1_z * g1_z + g2_y * g2_y + g2_z * g2_z) * i_;
        let shear = mean_sq * (self.shear_factor * a_) + fluct_sq * self.torsion_factor;
        (exx2 * self.youngs_modulus + shear * self.shear_modulus) * half
    }

    /// W and ∂W/∂g by automatic differentiation (the reference for [`Self::gradient`]).
    pub fn gradient_ad(&self, g: &Strains<f64>) -> (f64, Strains<f64>) {
        gradient(|x| self.density(&x), g)
    }

    /// W and ∂W/∂g, differentiated by hand in reverse mode through the same intermediate
    /// quantities as [`Self::density`] (the time-step loop's hot path; checked against AD).
    pub fn gradient(&self, g: &Strains<f64>) -> (f64, Strains<f64>) {
        let (w, gr) = self.gradient_of(&g.data.0[0]);
        (w, Strains::from(gr))
    }

    /// [`Self::gradient`] for `f64` or for the four Gauss points at once ([`Lanes`]). Constants
    /// stand on the right of the strains (see [`Real`]); each lane rounds exactly as the `f64`.
    #[inline]
    fn gradient_of<T: Real>(&self, g: &[T; STRAIN_VARS]) -> (T, [T; STRAIN_VARS]) {
        let [du, dv, dw, dtx, dty, dtz, ty, tz] = *g;
        let (a_, i_, k4) = (self.area, self.second_moment, self.fourth_moment);
        let e0 = du;
        let k1 = dtx * ty - dtz;
        let k2 = dty + dtx * tz;
        let c0 = e0 + (e0 * e0 + dv * dv + dw * dw) * 0.5;
        let c1 = k1 * (e0 + 1.0) + dw * dtx;
        let c2 = k2 * (e0 + 1.0) - dv * dtx;
        let c3 = (k1 * k1 + dtx * dtx) * 0.5;
        let c4 = k1 * k2;
        let c5 = (k2 * k2 + dtx * dtx) * 0.5;
        let exx2 = c0 * a_ * c0
            + c0 * (2.0 * i_) * (c3 + c5)
            + (c1 * c1 + c2 * c2) * i_
            + (c3 * c3 + c5 * c5) * (3.0 * k4)
            + c3 * (2.0 * k4) * c5
            + c4 * k4 * c4;
        let g1m = dv - tz - e0 * tz;
        let g2m = dw + ty + e0 * ty;
        let (g1y, g1z) = (-k1 * tz, -(dtx + k2 * tz));
        let (g2y, g2z) = (dtx + k1 * ty, k2 * ty);
        let wm = 0.5 * self.shear_modulus * self.shear_factor * a_;
        let wf = 0.5 * self.shear_modulus * self.torsion_factor * i_;
        let w = exx2 * (0.5 * self.youngs_modulus)
            + (g1m * g1m + g2m * g2m) * wm
            + (g1y * g1y + g1z * g1z + g2y * g2y + g2z * g2z) * wf;
        // Adjoints of c0..c5.
        let he = 0.5 * self.youngs_modulus;
        let s0 = (c0 * (2.0 * a_) + (c3 + c5) * (2.0 * i_)) * he;
        let s1 = c1 * (he * 2.0 * i_);
        let s2 = c2 * (he * 2.0 * i_);
        let s3 = (c0 * (2.0 * i_) + c3 * (6.0 * k4) + c5 * (2.0 * k4)) * he;
        let s4 = c4 * (he * 2.0 * k4);
        let s5 = (c0 * (2.0 * i_) + c5 * (6.0 * k4) + c3 * (2.0 * k4)) * he;
        let zero = T::from(0.0);
        let mut gr = [zero; STRAIN_VARS];
        let (mut e0b, mut k1b, mut k2b) = (zero, zero, zero);
        e0b += s0 * (e0 + 1.0);
        gr[1] += s0 * dv;
        gr[2] += s0 * dw;
        k1b += s1 * (e0 + 1.0);
        e0b += s1 * k1;
        gr[2] += s1 * dtx;
        gr[3] += s1 * dw;
        k2b += s2 * (e0 + 1.0);
        e0b += s2 * k2;
        gr[1] -= s2 * dtx;
        gr[3] -= s2 * dv;
        k1b += s3 * k1;
        gr[3] += s3 * dtx;
        k1b += s4 * k2;
        k2b += s4 * k1;
        k2b += s5 * k2;
        gr[3] += s5 * dtx;
        // Mean shear.
        let (a1, a2) = (g1m * (2.0 * wm), g2m * (2.0 * wm));
        gr[1] += a1;
        gr[7] -= a1 * (e0 + 1.0);
        e0b -= a1 * tz;
        gr[2] += a2;
        gr[6] += a2 * (e0 + 1.0);
        e0b += a2 * ty;
        // Torsional (fluctuating) shear.
        let (b1, b2, b3, b4) = (
            g1y * (2.0 * wf),
            g1z * (2.0 * wf),
            g2y * (2.0 * wf),
            g2z * (2.0 * wf),
        );
        k1b -= b1 * tz;
        gr[7] -= b1 * k1;
        gr[3] -= b2;
        k2b -= b2 * tz;
        gr[7] -= b2 * k2;
        gr[3] += b3;
        k1b += b3 * ty;
        gr[6] += b3 * k1;
        k2b += b4 * ty;
        gr[6] += b4 * k2;
        // Back through e0, k1, k2.
        gr[0] += e0b;
        gr[3] += k1b * ty + k2b * tz;
        gr[6] += k1b * dtx;
        gr[5] -= k1b;
        gr[4] += k2b;
        gr[7] += k2b * dtx;
        (w, gr)
    }

    /// ∂²W/∂g² by forward differences of the analytic gradient, symmetrised: a cheap tangent for
    /// Newton (9 gradient evaluations; relative accuracy ~1e-7, [`Self::hessian`] is exact).
    pub fn hessian_fd(&self, g: &Strains<f64>) -> SMatrix<f64, STRAIN_VARS, STRAIN_VARS> {
        SMatrix::from(self.hessian_fd_of(&g.data.0[0]))
    }

    /// [`Self::hessian_fd`] for `f64` or for the four Gauss points at once, by columns.
    fn hessian_fd_of<T: Real>(&self, g: &[T; STRAIN_VARS]) -> [[T; STRAIN_VARS]; STRAIN_VARS] {
        let base = self.gradient_of(g).1;
        let mut h = [[T::from(0.0); STRAIN_VARS]; STRAIN_VARS];
        for (j, col) in h.iter_mut().enumerate() {
            let step = (g[j].abs() + 1e-3) * 1e-7;
            let mut p = *g;
            p[j] += step;
            let grad = self.gradient_of(&p).1;
            for i in 0..STRAIN_VARS {
                col[i] = (grad[i] - base[i]) / step;
            }
        }
        let mut sym = h;
        for (j, col) in sym.iter_mut().enumerate() {
            for (i, x) in col.iter_mut().enumerate() {
                *x = (h[j][i] + h[i][j]) * 0.5;
            }
        }
        sym
    }

    /// W, ∂W/∂g and ∂²W/∂g².
    pub fn hessian(
        &self,
        g: &Strains<f64>,
    ) -> (f64, Strains<f64>, SMatrix<f64, STRAIN_VARS, STRAIN_VARS>) {
        hessian(|x| self.density(&x), g)
    }
}

/// Element DOFs of u (u1, u2) and of θx (θx1, θx2).
const AXIAL_DOFS: [usize; 2] = [0, 6];
const TWIST_DOFS: [usize; 2] = [3, 9];
/// Element DOFs of the bending planes x–y (v1, θz1, v2, θz2) and x–z (w1, θy1, w2, θy2).
const PLANE_DOFS: [[usize; 4]; 2] = [[1, 5, 7, 11], [2, 4, 8, 10]];
/// The strains each plane drives: (v′, θz′, θz) and (w′, θy′, θy).
const PLANE_STRAINS: [[usize; 3]; 2] = [[1, 5, 7], [2, 4, 6]];

/// The strain operator G by its non-zeros (28 of 96): u′ takes the axial DOFs only, θx′ the twist
/// DOFs, and each bending plane's DOFs drive that plane's slope, curvature and rotation.
/// [`ElementStrains::new`] checks that G vanishes elsewhere. Each entry holds its values at the
/// four Gauss points (one lane each).
#[derive(Debug, Clone, Copy)]
struct SparseOperator {
    /// u′ over [`AXIAL_DOFS`].
    axial: [Lanes; 2],
    /// θx′ over [`TWIST_DOFS`].
    twist: [Lanes; 2],
    /// Per plane, the rows [`PLANE_STRAINS`] over the columns [`PLANE_DOFS`].
    planes: [[[Lanes; 4]; 3]; 2],
}

impl SparseOperator {
    /// The non-zeros of the dense G at the four Gauss points; panics if G does not vanish
    /// outside the pattern.
    fn compress(g: &[SMatrix<f64, STRAIN_VARS, ELEMENT_DOF>; 4]) -> Self {
        let mut rest = *g;
        let mut take = |r: usize, j: usize| {
            Lanes(std::array::from_fn(|p| {
                std::mem::take(&mut rest[p][(r, j)])
            }))
        };
        let axial = AXIAL_DOFS.map(|j| take(0, j));
        let twist = TWIST_DOFS.map(|j| take(3, j));
        let planes = [0, 1].map(|p| PLANE_STRAINS[p].map(|r| PLANE_DOFS[p].map(|j| take(r, j))));
        assert!(
            rest.iter().flatten().all(|&x| x == 0.0),
            "strain operator has non-zeros outside the axial/twist/bending pattern: {rest:?}"
        );
        SparseOperator {
            axial,
            twist,
            planes,
        }
    }

    /// g = G d.
    #[inline(always)]
    fn strains(&self, d: &[f64; ELEMENT_DOF]) -> [Lanes; STRAIN_VARS] {
        let mut g = [Lanes::from(0.0); STRAIN_VARS];
        g[0] = self.axial[0] * d[AXIAL_DOFS[0]] + self.axial[1] * d[AXIAL_DOFS[1]];
        g[3] = self.twist[0] * d[TWIST_DOFS[0]] + self.twist[1] * d[TWIST_DOFS[1]];
        for p in 0..2 {
            let [j0, j1, j2, j3] = PLANE_DOFS[p];
            let x = [d[j0], d[j1], d[j2], d[j3]];
            for (&r, c) in PLANE_STRAINS[p].iter().zip(&self.planes[p]) {
                g[r] = c[0] * x[0] + c[1] * x[1] + c[2] * x[2] + c[3] * x[3];
            }
        }
        g
    }

    /// Gᵀ s.
    #[inline(always)]
    fn transpose_product(&self, s: &[Lanes; STRAIN_VARS]) -> [Lanes; ELEMENT_DOF] {
        let mut f = [Lanes::from(0.0); ELEMENT_DOF];
        for k in 0..2 {
            f[AXIAL_DOFS[k]] = self.axial[k] * s[0];
            f[TWIST_DOFS[k]] = self.twist[k] * s[3];
        }
        for p in 0..2 {
            let [r0, r1, r2] = PLANE_STRAINS[p];
            let c = &self.planes[p];
            for (k, &j) in PLANE_DOFS[p].iter().enumerate() {
                f[j] = c[0][k] * s[r0] + c[1][k] * s[r1] + c[2][k] * s[r2];
            }
        }
        f
    }

    /// Gᵀ H G by columns, for H by columns (at each Gauss point): T = H G column by column (each
    /// column of G has one or three non-zeros), then Gᵀ times each column of T.
    fn congruence(
        &self,
        h: &[[Lanes; STRAIN_VARS]; STRAIN_VARS],
    ) -> [[Lanes; ELEMENT_DOF]; ELEMENT_DOF] {
        let mut t = [[Lanes::from(0.0); STRAIN_VARS]; ELEMENT_DOF];
        for k in 0..2 {
            for r in 0..STRAIN_VARS {
                t[AXIAL_DOFS[k]][r] = h[0][r] * self.axial[k];
                t[TWIST_DOFS[k]][r] = h[3][r] * self.twist[k];
            }
        }
        for p in 0..2 {
            let [s0, s1, s2] = PLANE_STRAINS[p];
            let c = &self.planes[p];
            for (k, &j) in PLANE_DOFS[p].iter().enumerate() {
                for r in 0..STRAIN_VARS {
                    t[j][r] = h[s0][r] * c[0][k] + h[s1][r] * c[1][k] + h[s2][r] * c[2][k];
                }
            }
        }
        let mut k = [[Lanes::from(0.0); ELEMENT_DOF]; ELEMENT_DOF];
        for (k_col, t_col) in k.iter_mut().zip(&t) {
            *k_col = self.transpose_product(t_col);
        }
        k
    }
}

/// The element DOFs as an array.
fn dofs(d: &ElementVector) -> &[f64; ELEMENT_DOF] {
    &d.data.0[0]
}

/// The map from element DOFs to generalised strains at the element's Gauss points.
#[derive(Debug, Clone)]
pub struct ElementStrains {
    /// g = G d at the four Gauss points (one lane each), G by its non-zeros.
    operator: SparseOperator,
    /// Quadrature weights (include the element length), m.
    weights: Lanes,
}

impl ElementStrains {
    pub fn new(element: &BeamElement) -> Self {
        let (xs, weights) = super::gauss_legendre_4(element.length);
        let operators = xs.map(|x| {
            let n = element.interpolation(x);
            let mut g = SMatrix::<f64, STRAIN_VARS, ELEMENT_DOF>::zeros();
            for k in 0..6 {
                g.set_row(k, &n.derivative.row(k));
            }
            g.set_row(6, &n.value.row(4));
            g.set_row(7, &n.value.row(5));
            g
        });
        ElementStrains {
            operator: SparseOperator::compress(&operators),
            weights: Lanes(weights),
        }
    }

    /// The generalised strains at the four Gauss points (one lane each) of the element whose
    /// DOFs are `d`.
    pub(super) fn strains_at_points(&self, d: &[f64; ELEMENT_DOF]) -> [Lanes; STRAIN_VARS] {
        self.operator.strains(d)
    }

    /// The quadrature weights of the four Gauss points (they include the element length), m.
    pub(super) fn weights(&self) -> Lanes {
        self.weights
    }

    /// The strains at Gauss point `p` from the strains at all four.
    fn point_strains(g: &[Lanes; STRAIN_VARS], p: usize) -> Strains<f64> {
        Strains::from(g.map(|x| x.0[p]))
    }

    /// Strain energy of the element in state `d`, J.
    pub fn energy(&self, law: &StrainEnergy, d: &ElementVector) -> f64 {
        let g = self.operator.strains(dofs(d));
        let density = Lanes(std::array::from_fn(|p| {
            law.density(&Self::point_strains(&g, p))
        }));
        (density * self.weights).sum()
    }

    /// Internal force ∂U/∂d (linear and nonlinear parts), N and N·m.
    pub fn internal_force(&self, law: &StrainEnergy, d: &ElementVector) -> ElementVector {
        self.internal_force_and_energy(law, d).0
    }

    /// Internal force ∂U/∂d, N and N·m, and strain energy U, J (as [`Self::energy`], to
    /// round-off): the time-step loop's kernel, all four Gauss points at once.
    pub fn internal_force_and_energy(
        &self,
        law: &StrainEnergy,
        d: &ElementVector,
    ) -> (ElementVector, f64) {
        let g = self.operator.strains(dofs(d));
        let (density, mut dw) = law.gradient_of(&g);
        for x in &mut dw {
            *x = *x * self.weights;
        }
        let f = self.operator.transpose_product(&dw);
        (
            ElementVector::from_fn(|i, _| f[i].sum()),
            (density * self.weights).sum(),
        )
    }

    /// Tangent stiffness ∂²U/∂d² with the finite-difference Hessian (fast, for Newton).
    pub fn tangent_fast(&self, law: &StrainEnergy, d: &ElementVector) -> ElementMatrix {
        let mut h = law.hessian_fd_of(&self.operator.strains(dofs(d)));
        for x in h.iter_mut().flatten() {
            *x = *x * self.weights;
        }
        Self::sum_points(&self.operator.congruence(&h))
    }

    /// Internal force and tangent stiffness ∂²U/∂d².
    pub fn internal_force_and_tangent(
        &self,
        law: &StrainEnergy,
        d: &ElementVector,
    ) -> (ElementVector, ElementMatrix) {
        let g = self.operator.strains(dofs(d));
        let mut dw = [Lanes::from(0.0); STRAIN_VARS];
        let mut h = [[Lanes::from(0.0); STRAIN_VARS]; STRAIN_VARS];
        for (p, w) in self.weights.0.into_iter().enumerate() {
            let (_, dw_p, h_p) = law.hessian(&Self::point_strains(&g, p));
            for (i, x) in dw.iter_mut().enumerate() {
                x.0[p] = dw_p[i] * w;
            }
            for (j, col) in h.iter_mut().enumerate() {
                for (i, x) in col.iter_mut().enumerate() {
                    x.0[p] = h_p[(i, j)] * w;
                }
            }
        }
        let f = self.operator.transpose_product(&dw);
        (
            ElementVector::from_fn(|i, _| f[i].sum()),
            Self::sum_points(&self.operator.congruence(&h)),
        )
    }

    /// The element matrix from its Gauss-point contributions (by columns).
    fn sum_points(k: &[[Lanes; ELEMENT_DOF]; ELEMENT_DOF]) -> ElementMatrix {
        ElementMatrix::from_fn(|i, j| k[j][i].sum())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fem::test_support::{Rng, relative_error, seed_string};
    use crate::fem::{BeamElement, ElementVector};
    use crate::model::Section;

    /// Fields (u, v, w, θx, θy, θz) at a point and their x-derivatives.
    #[derive(Clone, Copy)]
    struct PointState {
        value: [f64; 6],
        slope: [f64; 6],
    }

    /// Displacement of the material point (x, y, z) by the kinematics of MODEL.md §2, with the
    /// fields linear in x around x = 0.
    fn displacement(s: &PointState, x: f64, y: f64, z: f64) -> [f64; 3] {
        let f: Vec<f64> = (0..6).map(|i| s.value[i] + s.slope[i] * x).collect();
        let (c, sn) = (f[3].cos(), f[3].sin());
        let (yy, zz) = (y * c - z * sn, y * sn + z * c);
        [f[0] - yy * f[5] + zz * f[4], f[1] + yy - y, f[2] + zz - z]
    }

    /// Reference energy per length: Green–Lagrange strains from a finite-difference displacement
    /// gradient, integrated over the annulus by polar quadrature (3 radial Gauss × 12 angles).
    fn reference_density(law: &StrainEnergy, s: &PointState, ri: f64, ro: f64) -> f64 {
        let h = 1e-5;
        let gauss = [
            (-(0.6f64).sqrt(), 5.0 / 9.0),
            (0.0, 8.0 / 9.0),
            ((0.6f64).sqrt(), 5.0 / 9.0),
        ];
        let mut pts = Vec::new();
        for (xi, wr) in gauss {
            let r = 0.5 * (ro + ri) + 0.5 * (ro - ri) * xi;
            for k in 0..12 {
                let phi = 2.0 * PI * k as f64 / 12.0;
                let w = wr * 0.5 * (ro - ri) * r * 2.0 * PI / 12.0;
                pts.push((r * phi.cos(), r * phi.sin(), w));
            }
        }
        let strains: Vec<(f64, f64, f64, f64)> = pts
            .iter()
            .map(|&(y, z, w)| {
                let mut grad = [[0.0; 3]; 3];
                for j in 0..3 {
                    let mut p = [0.0, y, z];
                    let mut m = [0.0, y, z];
                    p[j] += h;
                    m[j] -= h;
                    let (up, um) = (
                        displacement(s, p[0], p[1], p[2]),
                        displacement(s, m[0], m[1], m[2]),
                    );
                    for i in 0..3 {
                        grad[i][j] = (up[i] - um[i]) / (2.0 * h);
                    }
                }
                let e = |i: usize, j: usize| {
                    0.5 * (grad[i][j]
                        + grad[j][i]
                        + (0..3).map(|k| grad[k][i] * grad[k][j]).sum::<f64>())
                };
                (e(0, 0), 2.0 * e(0, 1), 2.0 * e(0, 2), w)
            })
            .collect();
        let area: f64 = strains.iter().map(|s| s.3).sum();
        let gy = strains.iter().map(|s| s.1 * s.3).sum::<f64>() / area;
        let gz = strains.iter().map(|s| s.2 * s.3).sum::<f64>() / area;
        let exx2: f64 = strains.iter().map(|s| s.0 * s.0 * s.3).sum();
        let fluct: f64 = strains
            .iter()
            .map(|s| ((s.1 - gy).powi(2) + (s.2 - gz).powi(2)) * s.3)
            .sum();
        let shear = law.shear_factor * area * (gy * gy + gz * gz) + law.torsion_factor * fluct;
        0.5 * (law.youngs_modulus * exx2 + law.shear_modulus * shear)
    }

    fn random_state(rng: &mut Rng, scale: f64) -> PointState {
        let mut s = PointState {
            value: [0.0; 6],
            slope: [0.0; 6],
        };
        for i in 0..6 {
            s.value[i] = rng.uniform(-scale, scale);
            s.slope[i] = rng.uniform(-scale, scale);
        }
        s.value[3] = rng.uniform(-400.0, 400.0); // the spin: hundreds of radians
        s
    }

    fn strains_of(s: &PointState) -> Strains<f64> {
        Strains::from([
            s.slope[0], s.slope[1], s.slope[2], s.slope[3], s.slope[4], s.slope[5], s.value[4],
            s.value[5],
        ])
    }

    #[test]
    fn closed_form_energy_matches_the_3d_green_lagrange_reference_at_any_spin() {
        let string = seed_string();
        let law = StrainEnergy::of(&string);
        let (ri, ro) = (string.pipe.inner_radius, string.pipe.outer_radius);
        let mut rng = Rng(0x9E3779B97F4A7C15);
        for case in 0..50 {
            let s = random_state(&mut rng, 0.05);
            let w = law.density(&strains_of(&s));
            let w_ref = reference_density(&law, &s, ri, ro);
            let rel = (w - w_ref).abs() / w_ref;
            assert!(
                rel < 1e-6,
                "case {case}: closed form {w} vs 3D reference {w_ref} (rel {rel:e})"
            );
            // Objectivity: the reference with the spin shifted by any angle gives the same energy.
            let mut shifted = s;
            shifted.value[3] += rng.uniform(-10.0, 10.0);
            let w_shift = reference_density(&law, &shifted, ri, ro);
            assert!(
                (w_shift - w_ref).abs() < 1e-6 * w_ref,
                "case {case}: spin shift changed energy"
            );
        }
    }

    fn element() -> (BeamElement, ElementStrains, StrainEnergy) {
        let string = seed_string();
        let e = BeamElement::new(35.0 / 105.0, Section::of(&string));
        let strains = ElementStrains::new(&e);
        (e, strains, StrainEnergy::of(&string))
    }

    fn random_element_state(rng: &mut Rng, scale: f64) -> ElementVector {
        let mut d = ElementVector::from_fn(|_, _| rng.uniform(-scale, scale));
        d[3] = rng.uniform(-400.0, 400.0);
        d[9] = d[3] + rng.uniform(-0.2, 0.2);
        d
    }

    #[test]
    fn rigid_spin_shift_leaves_element_energy_unchanged_and_rigid_motion_is_force_free() {
        let (_, es, law) = element();
        let mut rng = Rng(42);
        for _ in 0..20 {
            let d = random_element_state(&mut rng, 0.01);
            let mut shifted = d;
            let alpha = rng.uniform(-1e3, 1e3);
            shifted[3] += alpha;
            shifted[9] += alpha;
            let (u0, u1) = (es.energy(&law, &d), es.energy(&law, &shifted));
            // Only rounding remains: θx′ = (θx₂ − θx₁)/h loses digits when both angles are ~10³ rad
            // (the simulator therefore evaluates strains on the elastic part of the state only).
            assert!((u0 - u1).abs() <= 1e-10 * u0, "{u0} vs {u1}");
        }
        // The imposed rigid motion: u = V0 t, θx = Ω t at both nodes, with t large.
        let mut rigid = ElementVector::zeros();
        rigid[0] = 0.125;
        rigid[6] = 0.125;
        rigid[3] = 2.0 * PI * 90.0;
        rigid[9] = 2.0 * PI * 90.0;
        assert_eq!(es.internal_force(&law, &rigid).norm(), 0.0);
    }

    #[test]
    fn hand_gradient_equals_automatic_differentiation() {
        let law = StrainEnergy::of(&seed_string());
        let mut rng = Rng(99);
        for _ in 0..200 {
            let g = Strains::from_fn(|_, _| rng.uniform(-0.3, 0.3));
            let (w, dw) = law.gradient(&g);
            let (w_ad, dw_ad) = law.gradient_ad(&g);
            assert!((w - w_ad).abs() <= 1e-12 * w_ad.abs());
            let err = (dw - dw_ad).abs().max();
            assert!(err <= 1e-11 * dw_ad.abs().max(), "gradient error {err:e}");
        }
    }

    #[test]
    fn fast_tangent_agrees_with_the_exact_one() {
        let (_, es, law) = element();
        let mut rng = Rng(5);
        for scale in [0.0, 1e-4, 1e-2] {
            let d = random_element_state(&mut rng, scale);
            let (_, exact) = es.internal_force_and_tangent(&law, &d);
            let fast = es.tangent_fast(&law, &d);
            let err = (fast - exact).abs().max() / exact.abs().max();
            assert!(err < 1e-7, "scale {scale}: relative error {err:e}");
        }
    }

    #[test]
    fn tangent_at_rest_is_the_linear_stiffness() {
        let (e, es, law) = element();
        let (f, k) = es.internal_force_and_tangent(&law, &ElementVector::zeros());
        assert_eq!(f.norm(), 0.0);
        let k_lin = e.stiffness();
        let scale = k_lin.abs().max();
        assert!(
            (k - k_lin).abs().max() < 1e-12 * scale,
            "{}",
            (k - k_lin).abs().max() / scale
        );
    }

    #[test]
    fn internal_force_and_tangent_match_finite_differences() {
        let (_, es, law) = element();
        let mut rng = Rng(7);
        for _ in 0..10 {
            let d = random_element_state(&mut rng, 5e-3);
            let (f, k) = es.internal_force_and_tangent(&law, &d);
            assert!((f - es.internal_force(&law, &d)).norm() <= 1e-12 * f.norm());
            let f_scale = f.abs().max();
            let k_scale = k.abs().max();
            for j in 0..12 {
                let h = 1e-7 * (1.0 + d[j].abs());
                let (mut p, mut m) = (d, d);
                p[j] += h;
                m[j] -= h;
                let fd_force = (es.energy(&law, &p) - es.energy(&law, &m)) / (2.0 * h);
                assert!(
                    (fd_force - f[j]).abs() < 1e-5 * f_scale,
                    "force {j}: {fd_force} vs {}",
                    f[j]
                );
                let fd_col =
                    (es.internal_force(&law, &p) - es.internal_force(&law, &m)) / (2.0 * h);
                let err = (fd_col - k.column(j)).abs().max();
                assert!(
                    err < 1e-6 * k_scale,
                    "tangent column {j}: error {err:e} vs scale {k_scale:e}"
                );
            }
        }
    }

    /// The dense 8 × 12 operators G at the Gauss points, straight from the interpolation (the
    /// reference for the sparse kernels).
    fn dense_operators(e: &BeamElement) -> [(SMatrix<f64, STRAIN_VARS, 12>, f64); 4] {
        let (xs, ws) = super::super::gauss_legendre_4(e.length);
        std::array::from_fn(|p| {
            let n = e.interpolation(xs[p]);
            let mut g = SMatrix::<f64, STRAIN_VARS, 12>::zeros();
            for k in 0..6 {
                g.set_row(k, &n.derivative.row(k));
            }
            g.set_row(6, &n.value.row(4));
            g.set_row(7, &n.value.row(5));
            (g, ws[p])
        })
    }

    #[test]
    fn sparse_kernels_agree_with_the_dense_operators() {
        let (e, es, law) = element();
        let dense = dense_operators(&e);
        let mut rng = Rng(2024);
        for case in 0..50 {
            // Displacements and rotations ~1e-2 (m, rad), spin hundreds of radians.
            let d = random_element_state(&mut rng, 1e-2);
            let mut f_ref = ElementVector::zeros();
            let mut u_ref = 0.0;
            let mut k_ref = ElementMatrix::zeros();
            let mut k_fd_ref = ElementMatrix::zeros();
            for (g, w) in &dense {
                let strains = g * d;
                let (_, dw, h) = law.hessian(&strains);
                f_ref += g.transpose() * dw * *w;
                u_ref += w * law.density(&strains);
                k_ref += g.transpose() * (h * *w) * g;
                k_fd_ref += g.transpose() * (law.hessian_fd(&strains) * *w) * g;
            }
            let (f, u) = es.internal_force_and_energy(&law, &d);
            let err_f = relative_error(&f, &f_ref);
            assert!(err_f < 1e-12, "case {case}: force error {err_f:e}");
            assert!(
                (u - u_ref).abs() < 1e-12 * u_ref,
                "case {case}: energy {u} vs {u_ref}"
            );
            assert!((es.energy(&law, &d) - u_ref).abs() < 1e-12 * u_ref);
            assert_eq!(es.internal_force(&law, &d), f);
            let (f_t, k) = es.internal_force_and_tangent(&law, &d);
            assert!(
                relative_error(&f_t, &f_ref) < 1e-12,
                "case {case}: force with tangent"
            );
            let err_k = relative_error(&k, &k_ref);
            assert!(err_k < 1e-12, "case {case}: tangent error {err_k:e}");
            let err_fd = relative_error(&es.tangent_fast(&law, &d), &k_fd_ref);
            assert!(err_fd < 1e-12, "case {case}: fast tangent error {err_fd:e}");
        }
    }

    #[test]
    fn the_four_gauss_point_lanes_are_bitwise_the_scalar_gradient_and_hessian() {
        let law = StrainEnergy::of(&seed_string());
        let mut rng = Rng(31);
        for _ in 0..100 {
            let gs: [Strains<f64>; 4] =
                std::array::from_fn(|_| Strains::from_fn(|_, _| rng.uniform(-0.3, 0.3)));
            let lanes: [Lanes; STRAIN_VARS] =
                std::array::from_fn(|i| Lanes(std::array::from_fn(|p| gs[p][i])));
            let (w, dw) = law.gradient_of(&lanes);
            let h = law.hessian_fd_of(&lanes);
            for (p, g) in gs.iter().enumerate() {
                let (w_p, dw_p) = law.gradient(g);
                let h_p = law.hessian_fd(g);
                assert_eq!(w.0[p].to_bits(), w_p.to_bits());
                for i in 0..STRAIN_VARS {
                    assert_eq!(dw[i].0[p].to_bits(), dw_p[i].to_bits());
                    for j in 0..STRAIN_VARS {
                        assert_eq!(h[j][i].0[p].to_bits(), h_p[(i, j)].to_bits());
                    }
                }
            }
        }
    }

    #[test]
    #[should_panic(expected = "outside the axial/twist/bending pattern")]
    fn a_strain_operator_outside_the_sparsity_pattern_is_rejected() {
        let (e, _, _) = element();
        let mut g = dense_operators(&e).map(|(g, _)| g);
        g[2][(0, 1)] = 1e-3; // u′ depending on v1
        SparseOperator::compress(&g);
    }
}
