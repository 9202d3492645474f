//! Fatigue of the spinning string, seen by its material (issue 14, item 2; MODEL.md §10).
//!
//! A material fibre of the outer surface at angle φ₀ of the unspun section is, at time t, at the
//! angle ψ = φ₀ + θx(t) of the fixed frame, θx the section's **absolute** rotation: the rigid spin
//! Ω t plus the elastic twist (MODEL.md §2, §4). Its axial stress is σ(t) = E E_xx(ψ) (the
//! model's Green–Lagrange strain, [`crate::fem::SectionStress::axial_stress`]: the axial force,
//! both bending planes and the twist's helix), so on a bent string that turns it swings through
//! one cycle of amplitude M R / I per revolution (rotating bending), while a stuck bit (θ̇x = 0)
//! holds it. At the midpoint of every element, [`FATIGUE_FIBRES`] equally spaced fibres are
//! followed at every accepted step of the analysis window, their cycles counted by a streaming
//! rainflow counter ([`crate::fatigue::Rainflow`], ASTM E1049-85) and turned into Miner damage
//! against the pipe's S-N curve ([`crate::fatigue::SnCurve`]) as they close. A section's damage
//! is that of its worst fibre. Memory: one counter of fixed size per fibre, nothing per step.

use crate::fatigue::{Rainflow, SnCurve};
use crate::fem::{SectionStrains, SectionStress};

/// Material fibres followed per section (even: opposite fibres are evaluated as a pair), equally
/// spaced round the outer surface. In rotating
/// bending every fibre sees the full range; 8 keep the worst fibre of a section that bends while
/// it does not turn (stick) within cos(22.5°) = 0.92 of the extreme fibre's range.
pub const FATIGUE_FIBRES: usize = 8;

/// Rainflow counters and Miner sums of every fibre of every section.
#[derive(Debug, Clone, PartialEq)]
pub struct SectionFatigue {
    curve: SnCurve,
    /// Element-major: fibre k of element e at `e * FATIGUE_FIBRES + k`.
    counters: Vec<Rainflow>,
    damage: Vec<f64>,
    /// (cos φ₀, sin φ₀) of the fibres.
    fibres: [(f64, f64); FATIGUE_FIBRES],
}

impl SectionFatigue {
    /// Counters for `elements` sections, damage read on `curve`.
    pub fn new(elements: usize, curve: SnCurve) -> Self {
        SectionFatigue {
            curve,
            counters: vec![Rainflow::new(); elements * FATIGUE_FIBRES],
            damage: vec![0.0; elements * FATIGUE_FIBRES],
            fibres: std::array::from_fn(|k| {
                let phi = std::f64::consts::TAU * k as f64 / FATIGUE_FIBRES as f64;
                (phi.cos(), phi.sin())
            }),
        }
    }

    /// The stresses of element `e`'s fibres for midpoint strains `strains` and absolute section
    /// rotation `theta` (rad), into their counters.
    #[inline]
    pub fn record(
        &mut self,
        e: usize,
        strains: &SectionStrains,
        theta: f64,
        stress: &SectionStress,
    ) {
        const HALF: usize = FATIGUE_FIBRES / 2;
        let field = stress.axial_field(strains);
        let (s, c) = theta.sin_cos();
        let base = e * FATIGUE_FIBRES;
        let counters = &mut self.counters[base..base + FATIGUE_FIBRES];
        let damage = &mut self.damage[base..base + FATIGUE_FIBRES];
        let curve = &self.curve;
        // Fibre k and fibre k + HALF are opposite: one evaluation of the field gives both.
        let (near, far) = counters.split_at_mut(HALF);
        let (d_near, d_far) = damage.split_at_mut(HALF);
        for k in 0..HALF {
            // ψ = φ₀ + θ by the angle-sum formulas.
            let (c0, s0) = self.fibres[k];
            let (plus, minus) = field.pair((c0 * c - s0 * s, s0 * c + c0 * s));
            let d = &mut d_near[k];
            near[k].push(plus, &mut |range, count| *d += curve.damage(range, count));
            let d = &mut d_far[k];
            far[k].push(minus, &mut |range, count| *d += curve.damage(range, count));
        }
    }

    /// End of the window: every residue counted as half cycles.
    pub fn finish(&mut self) {
        let curve = &self.curve;
        for (counter, d) in self.counters.iter_mut().zip(&mut self.damage) {
            counter.finish(&mut |range, count| *d += curve.damage(range, count));
        }
    }

    /// Miner damage of element `e`'s worst fibre so far.
    pub fn damage(&self, e: usize) -> f64 {
        self.damage[e * FATIGUE_FIBRES..(e + 1) * FATIGUE_FIBRES]
            .iter()
            .copied()
            .fold(0.0, f64::max)
    }

    /// Residue overflows of all counters ([`Rainflow::overflows`]).
    pub fn overflows(&self) -> u64 {
        self.counters.iter().map(Rainflow::overflows).sum()
    }

    /// The S-N curve the damage is read on.
    pub fn curve(&self) -> &SnCurve {
        &self.curve
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::Section;
    use crate::sim::StressEnvelope;

    /// A 0.5 m element of the seed pipe under the constant curvature κ (pure bending in the
    /// plane at angle α; the Euler–Bernoulli fields of `fem::stress`'s test): the bending moment
    /// M = E I κ everywhere, the outer-fibre stress ±M R / I.
    fn bent(alpha: f64, kappa: f64) -> (crate::model::Drillstring, [f64; 12], f64) {
        let seed = concat!(env!("CARGO_MANIFEST_DIR"), "/problems/seed_mc2014.toml");
        let mut string = crate::problem::Problem::load(seed).unwrap().model;
        let h = 0.5;
        string.length = h;
        let (c, s) = (alpha.cos(), alpha.sin());
        let mut d = [0.0; 12];
        d[7] = 0.5 * kappa * c * h * h;
        d[8] = -0.5 * kappa * s * h * h;
        d[10] = kappa * s * h;
        d[11] = kappa * c * h;
        let section = Section::of(&string);
        let sigma = section.ei * kappa * string.pipe.outer_radius / section.second_moment;
        (string, d, sigma)
    }

    /// Miner damage of the worst fibre after spinning the bent section through `revolutions`
    /// turns at `per_rev` steps per turn, on `curve`.
    fn spun_damage(
        string: &mut crate::model::Drillstring,
        d: &[f64; 12],
        curve: SnCurve,
        revolutions: usize,
        per_rev: usize,
        spin_rate: f64,
    ) -> f64 {
        string.pipe.fatigue = curve;
        let stress = SectionStress::new(string, string.length);
        let mut envelope =
            StressEnvelope::for_string(string, &crate::fem::ElementLayout::of(string, 1), 0.0);
        let dt = 1.0 / per_rev as f64;
        for k in 0..=revolutions * per_rev {
            let t = k as f64 * dt;
            envelope.record(
                t,
                d,
                spin_rate * std::f64::consts::TAU * t,
                std::slice::from_ref(&stress),
                &[],
            );
        }
        envelope.finish();
        envelope.fatigue_damage_per_h[0] * envelope.duration_s / 3600.0
    }

    /// The closed form of rotating bending: a fibre of a section bent by M that turns once sees
    /// σ = (M R / I) cos(ψ), one full cycle of range 2 M R / I per revolution. On a one-slope
    /// curve (log ā = 12, m = 3, no cut-off) n turns do between n − 1 and n cycles' damage
    /// (the ends of the window leave half cycles), each (2σ_b)³ / 10¹²; a cut-off just below the
    /// range keeps that damage, one just above it removes all (the amplitude is M R / I to
    /// 1e-4: the strain's quadratic terms, 6e-6, and the 1° sampling of the turn, 4e-5).
    #[test]
    fn a_rotating_bent_pipe_sees_one_cycle_of_m_r_over_i_per_revolution() {
        let (mut string, d, sigma) = bent(0.7, 1e-4);
        let one_slope = |limit: f64| SnCurve {
            name: "custom",
            log_a1: 12.0,
            m1: 3.0,
            second: None,
            endurance_limit: limit,
            stress_concentration: 1.0,
        };
        let per_cycle = (2.0 * sigma / 1e6).powi(3) / 1e12;
        let n = 50;
        let damage = spun_damage(&mut string, &d, one_slope(0.0), n, 360, 1.0);
        assert!(
            damage >= (n - 1) as f64 * per_cycle * (1.0 - 1e-3)
                && damage <= n as f64 * per_cycle * (1.0 + 1e-3),
            "{damage} against {per_cycle} per cycle"
        );
        let below = spun_damage(
            &mut string,
            &d,
            one_slope(2.0 * sigma * 0.9999),
            n,
            360,
            1.0,
        );
        assert!(
            below >= (n - 1) as f64 * per_cycle * (1.0 - 1e-3),
            "{below}"
        );
        let above = spun_damage(
            &mut string,
            &d,
            one_slope(2.0 * sigma * 1.0001),
            n,
            360,
            1.0,
        );
        assert_eq!(above, 0.0);
        // A section that does not turn (a stuck string) under the same moment: no cycle.
        let still = spun_damage(&mut string, &d, one_slope(0.0), n, 360, 0.0);
        assert_eq!(still, 0.0);
    }
}
