//! Interpolation inside one element: the fields (u, v, w, θx, θy, θz) and their x-derivatives as
//! linear maps of the 12 element DOFs.
//!
//! Bending uses the interdependent interpolation: the exact solution of the homogeneous static
//! Timoshenko equations EI ψ″ = κGA (w′ + ψ), (w′ + ψ)′ = 0 on an element, written in one plane as
//! w = a0 + a1 x + a2 x² + a3 x³, ψ = −a1 − 6g a3 − 2a2 x − 3a3 x², g = EI/(κGA). The four a's are
//! fixed by the nodal (w, ψ); the shear strain w′ + ψ = −6g a3 is constant on the element. The x–z
//! plane uses ψ = θy; the x–y plane uses (v, ψ = −θz), from γ_xy = v′ − θz.

use nalgebra::{Matrix4, RowVector4, SMatrix};

/// Field values and x-derivatives at a point of an element.
#[derive(Debug, Clone, Copy)]
pub struct Interpolation {
    /// Rows (u, v, w, θx, θy, θz) as functions of the 12 element DOFs.
    pub value: SMatrix<f64, 6, 12>,
    /// Rows (u′, v′, w′, θx′, θy′, θz′), 1/m.
    pub derivative: SMatrix<f64, 6, 12>,
}

/// Element-local indices of one bending plane's DOFs (displacement 1, rotation 1, displacement 2,
/// rotation 2) and the sign that turns the rotation into ψ.
struct Plane {
    disp: usize,
    rot: usize,
    rot_sign: f64,
}

const PLANE_XZ: Plane = Plane {
    disp: 2,
    rot: 4,
    rot_sign: 1.0,
};
const PLANE_XY: Plane = Plane {
    disp: 1,
    rot: 5,
    rot_sign: -1.0,
};

/// Polynomial coefficients of the interdependent bending interpolation for one element.
#[derive(Debug, Clone, Copy)]
pub(crate) struct BendingShape {
    /// a = C · (w1, ψ1, w2, ψ2).
    coeffs: Matrix4<f64>,
    /// g = EI / (κ_s G A), m².
    g: f64,
}

impl BendingShape {
    pub(crate) fn new(length: f64, ei: f64, shear_rigidity: f64) -> Self {
        let h = length;
        let g = ei / shear_rigidity;
        #[rustfmt::skip]
        let nodal = Matrix4::new(
            1.0, 0.0, 0.0, 0.0,
            0.0, -1.0, 0.0, -6.0 * g,
            1.0, h, h * h, h * h * h,
            0.0, -1.0, -2.0 * h, -(3.0 * h * h + 6.0 * g),
        );
        let coeffs = nodal
            .try_inverse()
            .expect("the interdependent interpolation matrix is regular for h > 0");
        BendingShape { coeffs, g }
    }

    /// (w, w′, ψ, ψ′) at x as rows over (w1, ψ1, w2, ψ2).
    fn at(&self, x: f64) -> [RowVector4<f64>; 4] {
        let g = self.g;
        let w = RowVector4::new(1.0, x, x * x, x * x * x);
        let dw = RowVector4::new(0.0, 1.0, 2.0 * x, 3.0 * x * x);
        let psi = RowVector4::new(0.0, -1.0, -2.0 * x, -(3.0 * x * x + 6.0 * g));
        let dpsi = RowVector4::new(0.0, 0.0, -2.0, -6.0 * x);
        [
            w * self.coeffs,
            dw * self.coeffs,
            psi * self.coeffs,
            dpsi * self.coeffs,
        ]
    }
}

/// Interpolation at local coordinate x ∈ [0, h] of an element of length h.
pub(crate) fn interpolate(length: f64, bending: &BendingShape, x: f64) -> Interpolation {
    let mut value = SMatrix::<f64, 6, 12>::zeros();
    let mut derivative = SMatrix::<f64, 6, 12>::zeros();
    let s = x / length;
    // Linear fields: u (row 0, DOFs 0 and 6) and θx (row 3, DOFs 3 and 9).
    for (row, dof) in [(0, 0), (3, 3)] {
        value[(row, dof)] = 1.0 - s;
        value[(row, dof + 6)] = s;
        derivative[(row, dof)] = -1.0 / length;
        derivative[(row, dof + 6)] = 1.0 / length;
    }
    let [w, dw, psi, dpsi] = bending.at(x);
    for (plane, disp_row, rot_row) in [(PLANE_XZ, 2, 4), (PLANE_XY, 1, 5)] {
        let cols = [plane.disp, plane.rot, plane.disp + 6, plane.rot + 6];
        let col_sign = [1.0, plane.rot_sign, 1.0, plane.rot_sign];
        for k in 0..4 {
            let (col, cs) = (cols[k], col_sign[k]);
            value[(disp_row, col)] = cs * w[k];
            derivative[(disp_row, col)] = cs * dw[k];
            // The rotation DOF is rot_sign · ψ.
            value[(rot_row, col)] = plane.rot_sign * cs * psi[k];
            derivative[(rot_row, col)] = plane.rot_sign * cs * dpsi[k];
        }
    }
    Interpolation { value, derivative }
}

/// 4-point Gauss–Legendre rule on [0, h]: (points, weights), exact for polynomials of degree ≤ 7.
pub fn gauss_legendre_4(length: f64) -> ([f64; 4], [f64; 4]) {
    let a = (3.0 / 7.0 - 2.0 / 7.0 * (6.0f64 / 5.0).sqrt()).sqrt();
    let b = (3.0 / 7.0 + 2.0 / 7.0 * (6.0f64 / 5.0).sqrt()).sqrt();
    let wa = (18.0 + 30.0f64.sqrt()) / 36.0;
    let wb = (18.0 - 30.0f64.sqrt()) / 36.0;
    let xi = [-b, -a, a, b];
    let wi = [wb, wa, wa, wb];
    let half = 0.5 * length;
    (xi.map(|x| half * (x + 1.0)), wi.map(|w| half * w))
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;
    type ElementDofs = nalgebra::SVector<f64, 12>;

    #[test]
    fn shape_functions_interpolate_the_nodal_values() {
        let b = BendingShape::new(0.7, 2.0e6, 3.0e8);
        for (x, node) in [(0.0, 0usize), (0.7, 1)] {
            let n = interpolate(0.7, &b, x);
            for field in 0..6 {
                for dof in 0..12 {
                    let expected = if dof == 6 * node + field { 1.0 } else { 0.0 };
                    assert_relative_eq!(n.value[(field, dof)], expected, epsilon = 1e-12);
                }
            }
        }
    }

    #[test]
    fn shear_strain_is_constant_and_vanishes_for_a_rigid_rotation() {
        let h = 0.5;
        let b = BendingShape::new(h, 1.0e4, 2.0e6);
        // Rigid rotation about z by α: v = α x, θz = α (γ_xy = v' − θz = 0).
        let alpha = 1e-3;
        let mut d = ElementDofs::zeros();
        d[1] = 0.0;
        d[5] = alpha;
        d[7] = alpha * h;
        d[11] = alpha;
        for x in [0.0, 0.13, 0.37, h] {
            let n = interpolate(h, &b, x);
            let f = n.value * d;
            let df = n.derivative * d;
            assert_relative_eq!(f[1], alpha * x, epsilon = 1e-15);
            assert_relative_eq!(f[5], alpha, epsilon = 1e-15);
            assert_relative_eq!(df[1] - f[5], 0.0, epsilon = 1e-15);
        }
        // An arbitrary state: w' + θy is the same at every point.
        let d = ElementDofs::from_fn(|i, _| (i as f64 * 0.37).sin());
        let shear = |x: f64| {
            let n = interpolate(h, &b, x);
            (n.derivative * d)[2] + (n.value * d)[4]
        };
        assert_relative_eq!(shear(0.0), shear(0.21), epsilon = 1e-12);
        assert_relative_eq!(shear(0.0), shear(h), epsilon = 1e-12);
    }

    #[test]
    fn gauss_rule_integrates_degree_seven_exactly() {
        let (x, w) = gauss_legendre_4(2.0);
        let integral: f64 = x.iter().zip(&w).map(|(x, w)| w * x.powi(7)).sum();
        assert_relative_eq!(integral, 2.0f64.powi(8) / 8.0, max_relative = 1e-14);
    }
}
