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
    /// Confined added mass per length of the annulus fluid on the lateral motion (v, w),
    /// ρ_a π R_ext² (R_bh² + R_ext²)/(R_bh² − R_ext²), kg/m ([`Self::confined_added_mass`]; 0 without
    /// annulus fluid). Lateral inertia only: not axial or torsional, not weight, not damped.
    pub added_mass: f64,
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
            added_mass: Self::confined_added_mass(
                string.annulus_density,
                ro,
                string.borehole_radius,
            ),
            rotary_inertia: p.density * second_moment,
            polar_inertia: p.density * polar_moment,
        }
    }

    /// Lateral mass per length ρA + ρ_f A_f + m_a, kg/m: the pipe, the fluid inside it and the
    /// annulus fluid's confined added mass ([`Self::added_mass`], 0 without annulus fluid, so
    /// that the paper's ρA + ρ_f A_f is kept to the last bit).
    pub fn lateral_mass(&self) -> f64 {
        self.pipe_mass + self.fluid_mass + self.added_mass
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
    /// effective force, which is what the model's axial force is. The annulus fluid's added mass
    /// ([`Self::added_mass`]) is inertia, not weight, and is not in it. Equal to
    /// [`Self::lateral_mass`] to the last bit without annulus fluid.
    pub fn weight_mass(&self) -> f64 {
        self.pipe_mass + self.fluid_mass - self.displaced_mass
    }

    /// The confined added mass per length of the fluid in a concentric annulus on the lateral
    /// motion of the pipe, kg/m (MODEL.md §11.4):
    ///
    ///   m_a = ρ_a π R_ext² (R_bh² + R_ext²) / (R_bh² − R_ext²),
    ///
    /// the inviscid (potential-flow) limit of a rigid cylinder of radius R_ext translating inside a
    /// fixed concentric cylinder of radius R_bh (S. S. Chen, M. W. Wambsganss, J. A. Jendrzejczyk,
    /// *Added mass and damping of a vibrating rod in confined viscous fluids*, J. Appl. Mech. 43
    /// (1976) 325–329; the same coefficient as R. J. Fritz, J. Eng. Ind. 94 (1972) 167–173). It
    /// tends to the displaced mass ρ_a π R_ext² in an unbounded fluid (R_bh → ∞) and grows without
    /// bound as the gap closes. Small motions about the concentric position (the coefficient grows
    /// with eccentricity), no viscous (squeeze-film) damping, no coupling with the spin. 0 (exactly)
    /// for `density` 0, whatever the radii.
    pub fn confined_added_mass(density: f64, outer_radius: f64, borehole_radius: f64) -> f64 {
        if density == 0.0 {
            return 0.0;
        }
        let (a2, b2) = (
            outer_radius * outer_radius,
            borehole_radius * borehole_radius,
        );
        density * PI * a2 * (b2 + a2) / (b2 - a2)
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

    #[test]
    fn confined_added_mass_limits_and_the_seed_value() {
        // 89 kg/m on the seed's pipe (R_ext 60 mm) in its 70 mm hole with 1200 kg/m³ of mud.
        let seed = Section::confined_added_mass(1200.0, 0.06, 0.07);
        assert_relative_eq!(
            seed,
            1200.0 * PI * 0.0036 * 0.0085 / 0.0013,
            max_relative = 1e-14
        );
        assert!((seed - 88.7).abs() < 0.1, "{seed}");
        // An unbounded fluid: the displaced mass (potential flow about a cylinder).
        let far = Section::confined_added_mass(1000.0, 0.05, 5e3);
        assert_relative_eq!(far, 1000.0 * PI * 0.0025, max_relative = 1e-9);
        // No fluid: exactly 0, also for a hole no wider than the pipe.
        assert_eq!(Section::confined_added_mass(0.0, 0.06, 0.06), 0.0);
        assert_eq!(Section::confined_added_mass(0.0, 0.06, 0.07).to_bits(), 0);
    }
}
