//! Critical axial compressions of the pipe lying in its horizontal hole (issue 14, item 3).
//!
//! - Sinusoidal (lateral) buckling, Dawson & Paslay (1984), "Drillpipe buckling in inclined
//!   holes", J. Pet. Tech. 36 (October 1984), 1734–1738: F_sin = 2 √(E I w sin α / r), here α = 90° (the
//!   hole is horizontal: MODEL.md §1, gravity across the string).
//! - Helical buckling, Chen, Lin & Cheatham (1990), "Tubing and casing buckling in horizontal
//!   wells", J. Pet. Tech. 42 (February 1990), 140–141 and 191 (the load at which a sinusoidally buckled pipe,
//!   compressed further, turns into a helix, from the energy method):
//!   F_hel = 2√2 √(E I w / r) = √2 F_sin.
//!
//! E I is the bending rigidity, r the radial clearance R_bh − R_ext, and w the weight per length
//! that holds the pipe on the low side: the weight the model applies, the pipe's and the mud's
//! inside it less the annulus fluid it displaces (`[model.fluid] annulus_density`, none by
//! default: then the weight in air), w = (ρ A + ρ_f A_f − ρ_a π R_ext²) g
//! ([`Section::weight_mass`]). A buoyed string buckles at lower loads (√ of the weight ratio).

use super::{Drillstring, Section};

/// The critical compressions of a pipe in its hole, N, and the quantities they come from.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct BucklingLoads {
    /// Weight per length w = (ρA + ρ_f A_f − ρ_a π R_ext²) g (buoyed; in air without an annulus
    /// fluid), N/m.
    pub weight_per_length: f64,
    /// Radial clearance r = R_bh − R_ext, m.
    pub clearance: f64,
    /// Sinusoidal buckling load F_sin = 2 √(E I w / r) (Dawson & Paslay 1984, α = 90°), N.
    pub sinusoidal: f64,
    /// Helical buckling load F_hel = 2√2 √(E I w / r) (Chen, Lin & Cheatham 1990), N.
    pub helical: f64,
}

impl BucklingLoads {
    /// The loads of `string`'s pipe in its hole.
    pub fn of(string: &Drillstring) -> Self {
        let section = Section::of(string);
        let w = section.weight_mass() * string.gravity;
        let r = string.gap();
        let root = (section.ei * w / r).sqrt();
        BucklingLoads {
            weight_per_length: w,
            clearance: r,
            sinusoidal: 2.0 * root,
            helical: 2.0 * std::f64::consts::SQRT_2 * root,
        }
    }

    /// A compression `c` (N, ≥ 0 compressive) over the sinusoidal load: ≥ 1 buckles the pipe
    /// sinusoidally, ≥ √2 helically. 0 without compression; +∞ for a compression of a weightless
    /// pipe (F_sin = 0).
    pub fn utilization(&self, compression: f64) -> f64 {
        let c = compression.max(0.0);
        if c == 0.0 { 0.0 } else { c / self.sinusoidal }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn seed_string() -> Drillstring {
        let seed = concat!(env!("CARGO_MANIFEST_DIR"), "/problems/seed_mc2014.toml");
        crate::problem::Problem::load(seed).unwrap().model
    }

    /// The seed pipe (MODEL.md §1: E = 203 GPa, R = 60/40 mm, ρ = 7900, ρ_f = 1200, g = 9.81,
    /// R_bh = 70 mm), by hand: I = π/4 (0.06⁴ − 0.04⁴) = 8.168141e-6 m⁴, E I = 1.658133e6 N·m²,
    /// w = (7900 · 6.283185e-3 + 1200 · 5.026548e-3) · 9.81 = 546.1131 N/m, r = 0.01 m,
    /// E I w / r = 9.05528e10 N², F_sin = 2 · 300 919.9 = 601 839.8 N, F_hel = 851 130.0 N.
    #[test]
    fn the_seed_pipe_buckles_at_the_hand_values() {
        let b = BucklingLoads::of(&seed_string());
        assert!((b.weight_per_length / 546.1131 - 1.0).abs() < 1e-6);
        assert!((b.clearance - 0.01).abs() < 1e-15);
        assert!(
            (b.sinusoidal / 601_839.8 - 1.0).abs() < 1e-6,
            "{}",
            b.sinusoidal
        );
        assert!((b.helical / 851_130.0 - 1.0).abs() < 1e-6, "{}", b.helical);
        assert_eq!(b.utilization(-5.0), 0.0);
        assert!((b.utilization(300_919.9) - 0.5).abs() < 1e-6);
    }
}
