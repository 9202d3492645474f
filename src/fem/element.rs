//! One beam element: consistent mass (Eq. (7)), stiffness (Eq. (9)), damping mass (Eq. (8)) and
//! gravity load (Eq. (15)), each as ∫ Bᵀ D B dx (or ∫ Nᵀ q dx) by 4-point Gauss quadrature, which is
//! exact here: the integrands are polynomials of degree ≤ 6.

use super::shape::{BendingShape, Interpolation, gauss_legendre_4, interpolate};
use crate::model::Section;
use nalgebra::{SMatrix, SVector};

/// DOFs of one element: two nodes × six.
pub const ELEMENT_DOF: usize = 12;
/// A 12 × 12 element matrix (stack-allocated).
pub type ElementMatrix = SMatrix<f64, ELEMENT_DOF, ELEMENT_DOF>;
/// A 12-vector of element DOFs or forces.
pub type ElementVector = SVector<f64, ELEMENT_DOF>;

/// A lateral axis of the section: y (horizontal) or z (vertical, gravity along −z).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Lateral {
    Y,
    Z,
}

/// A straight element of a uniform section.
#[derive(Debug, Clone, Copy)]
pub struct BeamElement {
    /// Element length h, m.
    pub length: f64,
    pub section: Section,
    bending: BendingShape,
}

impl BeamElement {
    pub fn new(length: f64, section: Section) -> Self {
        let bending = BendingShape::new(length, section.ei, section.shear_rigidity);
        BeamElement {
            length,
            section,
            bending,
        }
    }

    /// Field values and derivatives at local x ∈ [0, h].
    pub fn interpolation(&self, x: f64) -> Interpolation {
        interpolate(self.length, &self.bending, x)
    }

    /// ∫ Nᵀ diag(inertia) N dx, inertia per length for (u, v, w, θx, θy, θz).
    fn mass_with(&self, inertia: [f64; 6]) -> ElementMatrix {
        let d = SMatrix::<f64, 6, 6>::from_diagonal(&inertia.into());
        self.integrate(|n| n.value.transpose() * d * n.value)
    }

    /// Consistent mass: pipe ρA on u, v, w; fluid ρ_f A_f and the annulus fluid's confined added
    /// mass m_a on v, w ([`Section::lateral_mass`]); ρJ = 2ρI on θx; ρI on θy, θz.
    pub fn mass(&self) -> ElementMatrix {
        let s = &self.section;
        let lat = s.lateral_mass();
        self.mass_with([
            s.pipe_mass,
            lat,
            lat,
            s.polar_inertia,
            s.rotary_inertia,
            s.rotary_inertia,
        ])
    }

    /// Pipe-only mass M_pipe (no fluid inside or outside), so that the damping is C = c · M_pipe
    /// (Eq. (8)).
    pub fn pipe_mass(&self) -> ElementMatrix {
        let s = &self.section;
        let m = s.pipe_mass;
        self.mass_with([m, m, m, s.polar_inertia, s.rotary_inertia, s.rotary_inertia])
    }

    /// Strains (u′, θx′, θy′, θz′, γ_xy = v′ − θz, γ_xz = w′ + θy) as rows over the element DOFs.
    pub fn strain_operator(n: &Interpolation) -> SMatrix<f64, 6, 12> {
        let mut b = SMatrix::<f64, 6, 12>::zeros();
        b.set_row(0, &n.derivative.row(0));
        b.set_row(1, &n.derivative.row(3));
        b.set_row(2, &n.derivative.row(4));
        b.set_row(3, &n.derivative.row(5));
        b.set_row(4, &(n.derivative.row(1) - n.value.row(5)));
        b.set_row(5, &(n.derivative.row(2) + n.value.row(4)));
        b
    }

    /// Linear stiffness, Eq. (9): EA u′², κ_t G J θx′², EI(θy′² + θz′²), κ_s G A(γ_xy² + γ_xz²).
    pub fn stiffness(&self) -> ElementMatrix {
        let s = &self.section;
        let d = SMatrix::<f64, 6, 6>::from_diagonal(
            &[
                s.ea,
                s.torsional_rigidity,
                s.ei,
                s.ei,
                s.shear_rigidity,
                s.shear_rigidity,
            ]
            .into(),
        );
        self.integrate(|n| {
            let b = Self::strain_operator(n);
            b.transpose() * d * b
        })
    }

    /// Consistent gravity load, Eq. (15) with buoyancy: −(ρA + ρ_f A_f − ρ_a π R_ext²) g on w
    /// ([`Section::weight_mass`]; the paper's −(ρA + ρ_f A_f) g without annulus fluid), N and N·m.
    pub fn gravity_load(&self, gravity: f64) -> ElementVector {
        self.weight_load(gravity, Lateral::Z)
    }

    /// The consistent load of the string's buoyed weight per length acting along −`axis`
    /// ([`Self::gravity_load`] is the one along −z, the real one): along −y it is the twin load
    /// of the other bending plane, on v with its θz moments. N and N·m.
    pub fn weight_load(&self, gravity: f64, axis: Lateral) -> ElementVector {
        let q = -self.section.weight_mass() * gravity;
        let row = match axis {
            Lateral::Y => 1,
            Lateral::Z => 2,
        };
        let (xs, ws) = gauss_legendre_4(self.length);
        xs.iter()
            .zip(ws)
            .fold(ElementVector::zeros(), |acc, (&x, w)| {
                acc + self.interpolation(x).value.row(row).transpose() * (q * w)
            })
    }

    fn integrate(&self, f: impl Fn(&Interpolation) -> ElementMatrix) -> ElementMatrix {
        let (xs, ws) = gauss_legendre_4(self.length);
        xs.iter()
            .zip(ws)
            .fold(ElementMatrix::zeros(), |acc, (&x, w)| {
                acc + f(&self.interpolation(x)) * w
            })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::Section;
    use approx::assert_relative_eq;

    fn section() -> Section {
        Section {
            area: 6.283e-3,
            second_moment: 8.168e-6,
            polar_moment: 1.634e-5,
            fluid_area: 5.027e-3,
            shear_modulus: 78e9,
            ea: 1.275e9,
            ei: 1.658e6,
            shear_rigidity: 2.76e8,
            torsional_rigidity: 7.2e5,
            pipe_mass: 49.64,
            fluid_mass: 6.03,
            displaced_mass: 0.0,
            added_mass: 0.0,
            rotary_inertia: 0.0645,
            polar_inertia: 0.129,
        }
    }

    #[test]
    fn matrices_are_symmetric_and_mass_is_positive_definite() {
        let e = BeamElement::new(0.33, section());
        for m in [e.mass(), e.pipe_mass(), e.stiffness()] {
            assert_relative_eq!(m, m.transpose(), max_relative = 1e-13, epsilon = 1e-9);
        }
        assert!(e.mass().cholesky().is_some());
    }

    #[test]
    fn euler_bernoulli_limit_gives_the_classical_hermite_stiffness() {
        // Very stiff in shear: the x–z bending block tends to EI/h³ [12, −6h; …] (with θy = −w′).
        let mut s = section();
        s.shear_rigidity = 1e20;
        let h = 0.5;
        let k = BeamElement::new(h, s).stiffness();
        let ei = s.ei;
        assert_relative_eq!(k[(2, 2)], 12.0 * ei / h.powi(3), max_relative = 1e-8);
        assert_relative_eq!(k[(2, 4)], -6.0 * ei / h.powi(2), max_relative = 1e-8);
        assert_relative_eq!(k[(4, 4)], 4.0 * ei / h, max_relative = 1e-8);
        assert_relative_eq!(k[(4, 10)], 2.0 * ei / h, max_relative = 1e-8);
        // x–y plane (θz = +v′): the coupling changes sign.
        assert_relative_eq!(k[(1, 5)], 6.0 * ei / h.powi(2), max_relative = 1e-8);
        assert_relative_eq!(k[(0, 0)], s.ea / h, max_relative = 1e-14);
        assert_relative_eq!(k[(3, 9)], -s.torsional_rigidity / h, max_relative = 1e-14);
    }

    #[test]
    fn gravity_load_sums_to_the_element_weight_with_the_classical_end_moments() {
        let h = 0.4;
        let e = BeamElement::new(h, section());
        let f = e.gravity_load(9.81);
        let weight = -section().lateral_mass() * 9.81 * h;
        assert_relative_eq!(f[2] + f[8], weight, max_relative = 1e-14);
        assert_relative_eq!(f[2], weight / 2.0, max_relative = 1e-12);
        // End moments q h²/12 about y, equal and opposite (independent of shear for a uniform load).
        assert_relative_eq!(f[4], -f[10], max_relative = 1e-12);
        assert_relative_eq!(f[4].abs(), weight.abs() * h / 12.0, max_relative = 1e-10);
        for i in [0, 1, 3, 5, 6, 7, 9, 11] {
            assert_eq!(f[i], 0.0);
        }
    }

    #[test]
    fn an_annulus_fluid_lifts_the_element_by_the_weight_of_the_fluid_it_displaces() {
        let (h, rho_a, r_ext) = (0.4, 1200.0, 0.06);
        let displaced = rho_a * std::f64::consts::PI * r_ext * r_ext;
        let buoyed = Section {
            displaced_mass: displaced,
            ..section()
        };
        let f = BeamElement::new(h, buoyed).gravity_load(9.81);
        let weight = -(49.64 + 6.03 - displaced) * 9.81 * h;
        assert_relative_eq!(f[2] + f[8], weight, max_relative = 1e-14);
        // Without annulus fluid the load is the paper's, to the last bit.
        let paper = BeamElement::new(h, section()).gravity_load(9.81);
        let q = -section().lateral_mass() * 9.81;
        assert_relative_eq!(paper[2] + paper[8], q * h, max_relative = 1e-14);
        assert_eq!(section().weight_mass(), section().lateral_mass());
    }

    #[test]
    fn the_annulus_added_mass_is_lateral_inertia_only() {
        let (h, m_a) = (0.4, 88.7);
        let dry = BeamElement::new(h, section());
        let mud = BeamElement::new(
            h,
            Section {
                added_mass: m_a,
                ..section()
            },
        );
        let (m0, m1) = (dry.mass(), mud.mass());
        // Total lateral mass on v and on w: (ρA + ρ_f A_f + m_a) h (rigid translation).
        for t in [1, 2] {
            let rigid = |m: &ElementMatrix| m[(t, t)] + 2.0 * m[(t, t + 6)] + m[(t + 6, t + 6)];
            assert_relative_eq!(rigid(&m1), (49.64 + 6.03 + m_a) * h, max_relative = 1e-12);
            assert_relative_eq!(rigid(&m1) - rigid(&m0), m_a * h, max_relative = 1e-12);
        }
        // Axial and torsional rows unchanged to the bit; damping mass and weight unchanged.
        for i in [0, 3, 6, 9] {
            assert_eq!(m1.row(i), m0.row(i), "row {i}");
        }
        assert_eq!(mud.pipe_mass(), dry.pipe_mass());
        assert_eq!(mud.gravity_load(9.81), dry.gravity_load(9.81));
        assert_eq!(mud.stiffness(), dry.stiffness());
    }
}
