//! Cross-section constants of the hollow circular pipe and the stiffness/inertia products the beam
//! element needs (MODEL.md §1, §3).

use super::Drillstring;
use std::f64::consts::PI;

/// Cowper's shear correction for a hollow circular section,
/// κ_s = 6(1+ν)(1+m²)² / ((7+6ν)(1+m²)² + (20+12ν)m²), m = R_int/R_ext.
pub fn cowper_shear_factor(poisson_ratio: f64, inner_radius: f64, outer_radius: f64) -> f64 {
    let nu = poisson_ratio;
    let m2 = (inner_radius / outer_radius).powi(2);
    let a = (1.0 + m2).powi(2);
    6.0 * (1.0 + nu) * a / ((7.0 + 6.0 * nu) * a + (20.0 + 12.0 * nu) * m2)
}

/// Section constants and the rigidities and inertias per unit length used by the element.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Section {
    /// Pipe area A = π(R_ext² − R_int²), m².
    pub area: f64,
    /// Second moment of area I = π/4 (R_ext⁴ − R_int⁴), m⁴ (the paper's I_4).
    pub second_moment: f64,
    /// Polar moment J = 2I, m⁴.
    pub polar_moment: f64,
    /// Fluid area A_f = π R_int², m².
    pub fluid_area: f64,
    /// Shear modulus G = E / (2(1+ν)), Pa.
    pub shear_modulus: f64,
    /// Axial rigidity E A, N.
    pub ea: f64,
    /// Bending rigidity E I, N·m².
    pub ei: f64,
    /// Shear rigidity κ_s G A, N.
    pub shear_rigidity: f64,
    /// Torsional rigidity κ_t G J, N·m².
    pub torsional_rigidity: f64,
    /// Pipe mass per length ρA, kg/m.
    pub pipe_mass: f64,
    /// Fluid lateral mass per length ρ_f A_f, kg/m.
    pub fluid_mass: f64,
    /// Mass per length of the annulus fluid the pipe displaces, ρ_a π R_ext², kg/m (0 without
    /// annulus fluid).
    pub displaced_mass: f64,
    /// Rotatory inertia per length about a diameter ρI, kg·m.
    pub rotary_inertia: f64,
    /// Polar inertia per length ρJ = 2ρI, kg·m.
    pub polar_inertia: f64,
}

impl Section {
    /// Section of the drillstring's pipe, with its fluid.
    pub fn of(string: &Drillstring) -> Self {
        let p = &string.pipe;
        let (ro, ri) = (p.outer_radius, p.inner_radius);
        let area = PI * (ro * ro - ri * ri);
        let second_moment = PI / 4.0 * (ro.powi(4) - ri.powi(4));
        let polar_moment = 2.0 * second_moment;
        let fluid_area = PI * ri * ri;
        let shear_modulus = p.youngs_modulus / (2.0 * (1.0 + p.poisson_ratio));
        Section {
            area,
            second_moment,
            polar_moment,
            fluid_area,
            shear_modulus,
            ea: p.youngs_modulus * area,
            ei: p.youngs_modulus * second_moment,
            shear_rigidity: p.shear_factor * shear_modulus * area,
            torsional_rigidity: p.torsion_factor * shear_modulus * polar_moment,
            pipe_mass: p.density * area,
            fluid_mass: string.fluid_density * fluid_area,
            displaced_mass: string.annulus_density * PI * ro * ro,
            rotary_inertia: p.density * second_moment,
            polar_inertia: p.density * polar_moment,
        }
    }

    /// Lateral mass per length ρA + ρ_f A_f, kg/m.
    pub fn lateral_mass(&self) -> f64 {
        self.pipe_mass + self.fluid_mass
    }

    /// The mass per length whose weight loads the string, kg/m: the buoyed weight over g,
    ///
    ///   w/g = ρA + ρ_f A_f − ρ_a π R_ext²,
    ///
    /// the pipe and the fluid inside it (as the paper's Eq. (15) has them) less the annulus
    /// fluid the pipe displaces (Archimedes on the outer volume; the buoyed weight per length of
    /// Mitchell & Miska, *Fundamentals of Drilling Engineering*, SPE Textbook Series 12, 2011,
    /// and of Aadnøy, *Mechanics of Drilling*, 2006: w_b = w_s + ρ_i A_i g − ρ_o A_o g). With
    /// ρ_a = ρ_f it is the steel's weight times the buoyancy factor 1 − ρ_f/ρ. The hydrostatic
    /// pressure itself is not modelled: in a horizontal hole it is uniform along the string, and
    /// the lateral load it leaves is this one when the axial force is read as Lubinski's
    /// effective force, which is what the model's axial force is. The annulus fluid adds no
    /// lateral (added) mass here. Equal to [`Self::lateral_mass`] to the last bit without it.
    pub fn weight_mass(&self) -> f64 {
        self.lateral_mass() - self.displaced_mass
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn cowper_reduces_to_the_solid_circle_and_thin_ring_limits() {
        // Solid circle: 6(1+ν)/(7+6ν); thin ring (m → 1): 2(1+ν)/(4+3ν).
        let nu: f64 = 0.3;
        assert_relative_eq!(
            cowper_shear_factor(nu, 0.0, 1.0),
            6.0 * (1.0 + nu) / (7.0 + 6.0 * nu)
        );
        assert_relative_eq!(
            cowper_shear_factor(nu, 1.0 - 1e-9, 1.0),
            2.0 * (1.0 + nu) / (4.0 + 3.0 * nu),
            max_relative = 1e-8
        );
    }
}
