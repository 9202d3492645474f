//! Section loads and the von Mises stress at the outer fibre of a beam element, from its 12 DOFs,
//! at the element's midpoint (issue 14). The strains are those of the model's own kinematics
//! ([`super::strain_energy`], MODEL.md §2): with the generalised strains
//! g = (u′, v′, w′, θx′, θy′, θz′, θy, θz) at the midpoint and a fibre (Y, Z) = R(cos φ, sin φ) of
//! the outer surface R = R_ext,
//!
//!   a = u′ + Y(θx′θy − θz′) + Z(θy′ + θx′θz),   E_xx = a + ½(a² + (v′ − Zθx′)² + (w′ + Yθx′)²),
//!   σ = E E_xx,   τ = κ_t G |Γ − Γ̄|,   Γ − Γ̄ = (−Zθx′ − (a − u′)θz, Yθx′ + (a − u′)θy),
//!   σ_vM = √(σ² + 3τ²)   (von Mises for the uniaxial-plus-shear state of a beam fibre).
//!
//! τ is the fibre's torsional shear (for small rotations κ_t G R θx′ = T R / J); the transverse
//! shear, which vanishes at the extreme fibres of bending of a circular section, is reported as the
//! shear force but left out of σ_vM. The maximum over the circumference is taken at the two
//! fibres where the bending stress is extreme (φ* and φ* + π, φ* = atan2(θy′, −θz′)) and at
//! 8 equally spaced fibres. The axial force is the section integral N = E ∫E_xx dA
//! = EA(u′ + ½(u′² + v′² + w′²)) + ½EI(p² + q² + 2θx′²) with p, q the bending parts of a, tension
//! positive: the linear EA u′ would read the shortening of a sagging string as compression. The other
//! resultants are the linear ones of the stiffness operator (Eq. (9)): T = κ_t G J θx′,
//! M = EI √(θy′² + θz′²), Q = κ_s G A √((v′ − θz)² + (w′ + θy)²).
//!
//! The membrane strain is the element's average, not its midpoint value. The element
//! interpolates u linearly and v, w cubically, so its membrane strain u′ + ½(v′² + w′²) varies
//! along it where the string bends (by ½(κx)² about the midpoint, κ the curvature), while the
//! axial force that keeps the nodes in equilibrium is its average (the internal force's axial
//! entries are ±(1/L)∫N(1 + u′) dx): the midpoint reads EA(κL)²/24 less tension, a few kN of
//! spurious compression on a 12 m drill-pipe element at a bend or a section boundary (the
//! oscillation of the membrane strain behind membrane locking: Stolarski & Belytschko, J. Appl.
//! Mech. 49 (1982) 172-176). So every fibre's strain takes the element
//! average of the section's membrane strain (by the element's own 4-point Gauss rule) in place of
//! its midpoint value ([`SectionStrains::membrane_correction`]): N is the force the element's
//! nodes carry, and the fibre stresses integrate to it.
//!
//! Stresses are recovered from the reduced basis by mode displacement, which converges more
//! slowly in the basis than the displacements do: `verify` checks `max_von_mises_pa`.

use super::{BeamElement, ELEMENT_DOF, ElementStrains, STRAIN_VARS, StrainEnergy};
use crate::model::{Drillstring, Section};
use nalgebra::SMatrix;
use std::f64::consts::PI;

/// Loads and the largest von Mises stress of one section.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct SectionLoads {
    /// Axial force N, N (tension > 0).
    pub axial_force: f64,
    /// Torque T, N·m.
    pub torque: f64,
    /// Bending moment magnitude M, N·m.
    pub bending_moment: f64,
    /// Transverse shear force magnitude Q, N.
    pub shear_force: f64,
    /// Largest von Mises stress over the outer fibre, Pa.
    pub von_mises: f64,
}

/// The midpoint strain operator of an element and the section data the stresses need.
#[derive(Debug, Clone)]
pub struct SectionStress {
    /// g = G d at the element's midpoint, G by rows (28 non-zeros of 96, but the dense product
    /// vectorises and is faster than the sparse one, which is called at every step).
    operator: [[f64; ELEMENT_DOF]; STRAIN_VARS],
    law: StrainEnergy,
    /// The strains at the element's Gauss points, for the element average of the membrane
    /// strain ([`SectionStrains::membrane_correction`]).
    points: ElementStrains,
    /// 1 / element length, 1/m.
    inverse_length: f64,
    outer_radius: f64,
    polar_moment: f64,
    /// (cos φ, sin φ) of the equally spaced fibres.
    fibres: [(f64, f64); FIBRES],
}

const FIBRES: usize = 8;

impl SectionStress {
    /// For elements of length `length` of `string`'s pipe.
    pub fn new(string: &Drillstring, length: f64) -> Self {
        let section = Section::of(string);
        let element = BeamElement::new(length, section);
        let n = element.interpolation(0.5 * length);
        let mut operator = SMatrix::<f64, STRAIN_VARS, ELEMENT_DOF>::zeros();
        for k in 0..6 {
            operator.set_row(k, &n.derivative.row(k));
        }
        operator.set_row(6, &n.value.row(4));
        operator.set_row(7, &n.value.row(5));
        SectionStress {
            operator: std::array::from_fn(|i| std::array::from_fn(|j| operator[(i, j)])),
            law: StrainEnergy::of(string),
            points: ElementStrains::new(&element),
            inverse_length: 1.0 / length,
            outer_radius: string.pipe.outer_radius,
            polar_moment: section.polar_moment,
            fibres: std::array::from_fn(|k| {
                let phi = 2.0 * PI * k as f64 / FIBRES as f64;
                (phi.cos(), phi.sin())
            }),
        }
    }

    /// The generalised strains at the midpoint of an element whose DOFs (node 1 then node 2,
    /// each (u, v, w, θx, θy, θz), elastic part) are `d` (12 values), with the element average
    /// of the section's membrane strain less its midpoint value.
    #[inline]
    pub fn strains(&self, d: &[f64]) -> SectionStrains {
        let d: &[f64; ELEMENT_DOF] = d.try_into().expect("an element has 12 DOFs");
        let midpoint = std::array::from_fn(|i| {
            let row = &self.operator[i];
            (0..ELEMENT_DOF).map(|j| row[j] * d[j]).sum()
        });
        let points = self.points.strains_at_points(d);
        let weights = self.points.weights();
        let average = (0..4)
            .map(|p| weights.0[p] * self.membrane_strain(&points.map(|g| g.0[p])))
            .sum::<f64>()
            * self.inverse_length;
        SectionStrains {
            membrane_correction: average - self.membrane_strain(&midpoint),
            midpoint,
        }
    }

    /// Moves `strains` so that the section carries the axial force and the torque of its strains
    /// less `axial_defect` (N) and `torque_defect` (N·m): the twist rate θx′ by
    /// −torque_defect / (κ_t G J), then the membrane strain (through its correction) by
    /// −axial_defect / (EA). The force-summation recovery of a reduced model
    /// ([`crate::rom::ForceSummation`]); the bending strains are left as they are.
    pub fn balance(&self, strains: &mut SectionStrains, axial_defect: f64, torque_defect: f64) {
        let l = &self.law;
        let membrane = self.membrane_strain(&strains.midpoint) + strains.membrane_correction;
        strains.midpoint[3] -=
            torque_defect / (l.torsion_factor * l.shear_modulus * self.polar_moment);
        strains.membrane_correction = membrane
            - axial_defect / (l.youngs_modulus * l.area)
            - self.membrane_strain(&strains.midpoint);
    }

    /// The section's membrane strain ∫E_xx dA / A at a point whose generalised strains are `g`:
    /// u′ + ½(u′² + v′² + w′²) + ½(I/A)(p² + q² + 2θx′²), p = θx′θy − θz′, q = θy′ + θx′θz (the
    /// fibre strain's odd moments vanish over the section and ∫Y² dA = ∫Z² dA = I).
    #[inline]
    fn membrane_strain(&self, g: &[f64; STRAIN_VARS]) -> f64 {
        let [du, dv, dw, dtx, dty, dtz, ty, tz] = *g;
        let (p, q) = (dtx * ty - dtz, dty + dtx * tz);
        du + 0.5 * (du * du + dv * dv + dw * dw)
            + 0.5 * self.law.second_moment / self.law.area * (p * p + q * q + 2.0 * dtx * dtx)
    }

    /// The loads at the midpoint of an element whose DOFs (node 1 then node 2, each
    /// (u, v, w, θx, θy, θz), elastic part) are `d`.
    pub fn loads(&self, d: &[f64]) -> SectionLoads {
        self.loads_of(&self.strains(d))
    }

    /// Axial stress σ = E E_xx, Pa (tension > 0), at the outer fibre that is at angle ψ in the
    /// section's fixed frame, (Y, Z) = R(cos ψ, sin ψ), given as `(cos ψ, sin ψ)`. A material
    /// fibre at angle φ₀ of the unspun section is at ψ = φ₀ + θx, θx the section's absolute
    /// rotation (MODEL.md §2: Y = y cos θx − z sin θx, Z = y sin θx + z cos θx).
    #[inline]
    pub fn axial_stress(&self, strains: &SectionStrains, (c, s): (f64, f64)) -> f64 {
        let [du, dv, dw, dtx, dty, dtz, ty, tz] = strains.midpoint;
        let (y, z) = (self.outer_radius * c, self.outer_radius * s);
        let a = du + y * (dtx * ty - dtz) + z * (dty + dtx * tz);
        let exx = a + 0.5 * (a * a + (dv - z * dtx).powi(2) + (dw + y * dtx).powi(2));
        self.law.youngs_modulus * (exx + strains.membrane_correction)
    }

    /// The axial stress round the outer surface as a function of the fibre's angle
    /// ([`AxialStressField`]), for many fibres of one section at a few flops each.
    #[inline]
    pub fn axial_field(&self, strains: &SectionStrains) -> AxialStressField {
        let [du, dv, dw, dtx, dty, dtz, ty, tz] = strains.midpoint;
        let r = self.outer_radius;
        let e = self.law.youngs_modulus;
        let (alpha, beta) = (r * (dtx * ty - dtz), r * (dty + dtx * tz));
        let rt = r * dtx;
        AxialStressField {
            even: e
                * (du
                    + 0.5 * (du * du + dv * dv + dw * dw + rt * rt)
                    + strains.membrane_correction),
            half_e: 0.5 * e,
            alpha,
            beta,
            gamma: e * (alpha * (1.0 + du) + rt * dw),
            delta: e * (beta * (1.0 + du) - rt * dv),
        }
    }

    /// The loads of a section whose midpoint strains are `strains` ([`Self::strains`]).
    pub fn loads_of(&self, strains: &SectionStrains) -> SectionLoads {
        let [du, dv, dw, dtx, dty, dtz, ty, tz] = strains.midpoint;
        let l = &self.law;
        // A fibre by (cos φ, sin φ): no trigonometry in the time-step loop.
        let stress_at = |(c, s): (f64, f64)| {
            let (y, z) = (self.outer_radius * c, self.outer_radius * s);
            let bend = y * (dtx * ty - dtz) + z * (dty + dtx * tz);
            let a = du + bend;
            let exx = a + 0.5 * (a * a + (dv - z * dtx).powi(2) + (dw + y * dtx).powi(2));
            let sigma = l.youngs_modulus * (exx + strains.membrane_correction);
            let (gy, gz) = (-z * dtx - bend * tz, y * dtx + bend * ty);
            let tau = l.torsion_factor * l.shear_modulus * (gy * gy + gz * gz).sqrt();
            (sigma * sigma + 3.0 * tau * tau).sqrt()
        };
        // φ* = atan2(θy′, −θz′) and φ* + π, by the unit vector of the curvature.
        let k = (dty * dty + dtz * dtz).sqrt();
        let extreme = if k > 0.0 {
            (-dtz / k, dty / k)
        } else {
            (1.0, 0.0)
        };
        let mut von_mises = stress_at(extreme).max(stress_at((-extreme.0, -extreme.1)));
        for &fibre in &self.fibres {
            von_mises = von_mises.max(stress_at(fibre));
        }
        let (e, gm) = (l.youngs_modulus, l.shear_modulus);
        // N = E ∫E_xx dA: the section integral of the fibre strain above, so the sag's
        // ½(v′² + w′²) is not read as compression, averaged over the element.
        let mean_strain = self.membrane_strain(&strains.midpoint) + strains.membrane_correction;
        SectionLoads {
            axial_force: e * l.area * mean_strain,
            torque: l.torsion_factor * gm * self.polar_moment * dtx,
            bending_moment: e * l.second_moment * dty.hypot(dtz),
            shear_force: l.shear_factor * gm * l.area * (dv - tz).hypot(dw + ty),
            von_mises,
        }
    }
}

/// The axial stress of the outer fibres of one section (MODEL.md §2, §10), split into its parts
/// even and odd in the fibre's position: with (Y, Z) = R(cos ψ, sin ψ), L = α cos ψ + β sin ψ
/// (α = R(θx′θy − θz′), β = R(θy′ + θx′θz)) the bending part of a = u′ + L, and
/// (v′ − Zθx′)² + (w′ + Yθx′)² = v′² + w′² + (Rθx′)² + 2Rθx′(w′ cos ψ − v′ sin ψ),
///
///   σ(ψ) = E [u′ + ½(u′² + v′² + w′² + (Rθx′)²) + ½L²] + E [(1 + u′)L + Rθx′(w′ cos ψ − v′ sin ψ)],
///
/// the second bracket odd (it changes sign at ψ + π), so a pair of opposite fibres costs one
/// evaluation. Equal to [`SectionStress::axial_stress`] to round-off.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AxialStressField {
    /// E (u′ + ½(u′² + v′² + w′² + (Rθx′)²)), Pa.
    even: f64,
    half_e: f64,
    alpha: f64,
    beta: f64,
    /// E (α(1 + u′) + Rθx′ w′) and E (β(1 + u′) − Rθx′ v′): the odd part γ cos ψ + δ sin ψ, Pa.
    gamma: f64,
    delta: f64,
}

impl AxialStressField {
    /// σ at the fibres at ψ and ψ + π, given (cos ψ, sin ψ), Pa.
    #[inline]
    pub fn pair(&self, (c, s): (f64, f64)) -> (f64, f64) {
        let l = self.alpha * c + self.beta * s;
        let even = self.even + self.half_e * l * l;
        let odd = self.gamma * c + self.delta * s;
        (even + odd, even - odd)
    }
}

/// The generalised strains g = (u′, v′, w′, θx′, θy′, θz′, θy, θz) at an element's midpoint
/// (elastic part; the rigid motion carries no strain) and the correction of its membrane strain
/// to the element's average.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SectionStrains {
    /// g at the midpoint (strains dimensionless, θx′, θy′, θz′ in 1/m, θy, θz in rad).
    pub midpoint: [f64; STRAIN_VARS],
    /// ε̄ − ε(½L): the element average of the section's membrane strain ∫E_xx dA / A (by the
    /// element's own 4-point Gauss rule) less its value at the midpoint, dimensionless. Added to
    /// every fibre's strain, so that the recovered axial force is the element's average, the
    /// force its nodes carry (see the module docs).
    pub membrane_correction: f64,
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fem::test_support::seed_string;

    /// Element DOFs of a uniform field: u = ε x, θx = κ x (linear), no bending.
    fn axial_and_twist(length: f64, strain: f64, twist: f64) -> [f64; 12] {
        let mut d = [0.0; 12];
        d[6] = strain * length;
        d[9] = twist * length;
        d
    }

    #[test]
    fn pure_tension_and_pure_torsion_match_the_closed_forms() {
        let s = seed_string();
        let (h, eps, kappa) = (1.0 / 3.0, 1e-4, 2e-3);
        let st = SectionStress::new(&s, h);
        let sec = Section::of(&s);
        let (e, r) = (s.pipe.youngs_modulus, s.pipe.outer_radius);
        // Tension: N = EA(ε + ε²/2), σ = Eε(1 + ε/2) (Green–Lagrange), no shear.
        let t = st.loads(&axial_and_twist(h, eps, 0.0));
        assert!((t.axial_force / (sec.ea * (eps + 0.5 * eps * eps)) - 1.0).abs() < 1e-12);
        assert!((t.von_mises / (e * (eps + 0.5 * eps * eps)) - 1.0).abs() < 1e-12);
        // Torsion: τ = κ_t G R κ = T R / J at the outer fibre; σ_vM = √3 τ (plus the ½(Rκ)²
        // axial strain of the helix fibres, 2e-8 relative here).
        let k = st.loads(&axial_and_twist(h, 0.0, kappa));
        let tau = s.pipe.torsion_factor * sec.shear_modulus * r * kappa;
        assert!((k.torque * r / sec.polar_moment / tau - 1.0).abs() < 1e-12);
        assert!(
            (k.von_mises / (3f64.sqrt() * tau) - 1.0).abs() < 1e-6,
            "{}",
            k.von_mises
        );
    }

    #[test]
    fn the_axial_force_of_a_bent_element_is_the_force_its_nodes_carry() {
        // Constant curvature κ over a 12 m element (v = ½κx², θz = κx) and a uniform stretch ε:
        // the membrane strain ε + ½(κx)² varies along the element; the axial entry of the
        // element's internal force (its own 4-point quadrature of the strain energy, another
        // code path) is the force the node carries, (1/L)∫N(1 + u′)dx. The midpoint value falls
        // short of it by EA(κL)²/24: 12 % of the force in tension here, 7 times it in compression.
        let s = seed_string();
        let (h, kappa) = (12.0, 2e-3);
        let st = SectionStress::new(&s, h);
        let element = BeamElement::new(h, Section::of(&s));
        let law = StrainEnergy::of(&s);
        let ea = Section::of(&s).ea;
        for eps in [1e-4, -1e-4] {
            let mut d = [0.0; 12];
            d[6] = eps * h;
            d[7] = 0.5 * kappa * h * h;
            d[11] = kappa * h;
            let nodal = ElementStrains::new(&element)
                .internal_force(&law, &crate::fem::ElementVector::from_column_slice(&d))[6]
                / (1.0 + eps);
            let strains = st.strains(&d);
            let n = st.loads_of(&strains).axial_force;
            assert!(
                (n / nodal - 1.0).abs() < 1e-3,
                "ε {eps}: N {n}, nodal {nodal}"
            );
            let expected = (kappa * h).powi(2) / 24.0;
            assert!(
                (strains.membrane_correction / expected - 1.0).abs() < 1e-2,
                "ε {eps}: correction {} against (κL)²/24 = {expected}",
                strains.membrane_correction
            );
            let midpoint = n - ea * strains.membrane_correction;
            assert!(
                (midpoint / nodal - 1.0).abs() > 0.1,
                "the midpoint reading should miss it"
            );
            // The fibres integrate to it: the mean of opposite fibres' σ is N/A up to the
            // ½L² bending term's section average ((I/A)κ², 1e-9 of E here).
            let (plus, minus) = st.axial_field(&strains).pair((1.0, 0.0));
            let (up, down) = st.axial_field(&strains).pair((0.0, 1.0));
            let mean = 0.25 * (plus + minus + up + down);
            assert!(
                (mean * Section::of(&s).area / n - 1.0).abs() < 1e-3,
                "ε {eps}: fibre mean {mean} Pa against N/A {}",
                n / Section::of(&s).area
            );
        }
    }

    #[test]
    fn the_stress_field_of_opposite_fibres_equals_the_fibre_stress() {
        let s = seed_string();
        let st = SectionStress::new(&s, 0.4);
        // Every strain at once, of realistic sizes (1e-3) and beyond (0.05).
        for scale in [1e-3, 0.05] {
            let d: [f64; 12] =
                std::array::from_fn(|k| scale * ((k as f64 * 1.7).sin() + 0.3 * k as f64 / 12.0));
            let strains = st.strains(&d);
            let field = st.axial_field(&strains);
            for k in 0..16 {
                let psi = 0.37 + k as f64 * std::f64::consts::TAU / 16.0;
                let (plus, minus) = field.pair((psi.cos(), psi.sin()));
                let direct = st.axial_stress(&strains, (psi.cos(), psi.sin()));
                let opposite = st.axial_stress(&strains, (-psi.cos(), -psi.sin()));
                let tol = 1e-12 * s.pipe.youngs_modulus * scale;
                assert!((plus - direct).abs() < tol, "{plus} {direct}");
                assert!((minus - opposite).abs() < tol, "{minus} {opposite}");
            }
        }
    }

    #[test]
    fn a_rigid_rotation_carries_no_axial_force() {
        // u = (cos β − 1)x, v = x sin β, θz = β: Green–Lagrange gives no strain at all, where the
        // linear EA u′ would read −EA β²/2 of compression (what a sagging string looks like).
        let s = seed_string();
        let (h, beta) = (0.4, 0.02f64);
        let st = SectionStress::new(&s, h);
        let mut d = [0.0; 12];
        d[5] = beta;
        d[6] = (beta.cos() - 1.0) * h;
        d[7] = beta.sin() * h;
        d[11] = beta;
        let l = st.loads(&d);
        let linear = Section::of(&s).ea * (beta.cos() - 1.0);
        // Zero up to the element's interpolation of a rigid rotation (its cubic v through slopes
        // θz = β and chord sin β differ at O(β³)): 5e-5 of the linear reading.
        assert!(
            l.axial_force.abs() < 1e-4 * linear.abs(),
            "N = {}",
            l.axial_force
        );
        assert!(
            l.von_mises < 1e-4 * linear.abs() / Section::of(&s).area,
            "σ_vM = {}",
            l.von_mises
        );
    }

    #[test]
    fn pure_bending_gives_m_r_over_i_at_the_extreme_fibre_whatever_the_plane() {
        let s = seed_string();
        let h = 0.5;
        let st = SectionStress::new(&s, h);
        let sec = Section::of(&s);
        // Constant curvature κ in a plane at angle α: θy′ = κ sin α, θz′ = κ cos α with the
        // Euler–Bernoulli fields v = ½κ cos α x², w = −½κ sin α x² (θz = v′, θy = −w′).
        let kappa = 1e-3;
        for alpha in [0.0f64, 0.3, 1.0, 2.5] {
            let (c, sn) = (alpha.cos(), alpha.sin());
            let mut d = [0.0; 12];
            // node 2 at x = h: v, w, θy, θz
            d[7] = 0.5 * kappa * c * h * h;
            d[8] = -0.5 * kappa * sn * h * h;
            d[10] = kappa * sn * h;
            d[11] = kappa * c * h;
            let l = st.loads(&d);
            let m = sec.ei * kappa;
            assert!(
                (l.bending_moment / m - 1.0).abs() < 1e-9,
                "α {alpha}: M {}",
                l.bending_moment
            );
            let sigma = m * s.pipe.outer_radius / sec.second_moment;
            // σ_vM = |E E_xx| at the extreme fibre: E(Rκ + ½(Rκ)² + ½ v′² terms), within 1e-3.
            assert!(
                (l.von_mises / sigma - 1.0).abs() < 1e-3,
                "α {alpha}: {}",
                l.von_mises / sigma
            );
            assert!(
                l.shear_force < 1e-6 * m,
                "no shear in pure bending: {}",
                l.shear_force
            );
        }
    }
}
