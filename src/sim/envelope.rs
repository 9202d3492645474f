//! The stress envelope of a run along the string (issue 14): at every accepted step from
//! `from` on, the loads and outer-fibre von Mises stress at the midpoint of every element
//! ([`crate::fem::SectionStress`]), reduced on the fly to their extremes and time means, so its
//! memory does not grow with the run's length.

use crate::fem::{DOF_PER_NODE, SectionStress};
use serde::Serialize;

/// Extremes and time means of the section loads, one entry per element (midpoints, top to bit).
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct StressEnvelope {
    /// Element midpoints x, m.
    pub position_m: Vec<f64>,
    /// Largest von Mises stress at the outer fibre, Pa.
    pub max_von_mises_pa: Vec<f64>,
    /// Time mean of the largest von Mises stress over the section's circumference, Pa.
    pub mean_von_mises_pa: Vec<f64>,
    /// Largest compressive axial force (≥ 0, N) and largest tension (≥ 0, N).
    pub max_compression_n: Vec<f64>,
    pub max_tension_n: Vec<f64>,
    /// Largest torque magnitude, N·m.
    pub max_torque_nm: Vec<f64>,
    /// Largest bending moment, N·m.
    pub max_bending_moment_nm: Vec<f64>,
    /// Time covered by the means, s (0 before the envelope starts).
    pub duration_s: f64,
    /// When the envelope starts (the analysis window's start), s.
    pub from_s: f64,
    #[serde(skip)]
    last_time: Option<f64>,
}

impl StressEnvelope {
    /// An empty envelope of `elements` elements of length `length`, recording from time `from`.
    pub fn new(elements: usize, length: f64, from: f64) -> Self {
        let zeros = vec![0.0; elements];
        StressEnvelope {
            position_m: (0..elements).map(|e| (e as f64 + 0.5) * length).collect(),
            max_von_mises_pa: zeros.clone(),
            mean_von_mises_pa: zeros.clone(),
            max_compression_n: zeros.clone(),
            max_tension_n: zeros.clone(),
            max_torque_nm: zeros.clone(),
            max_bending_moment_nm: zeros,
            duration_s: 0.0,
            from_s: from,
            last_time: None,
        }
    }

    /// Add the state at time `t` whose elastic full-mesh displacements are `q_full`. The mean is
    /// weighted by the step that ends at `t` (right Riemann sum on the accepted steps).
    pub fn record(&mut self, t: f64, q_full: &[f64], stress: &SectionStress) {
        if t < self.from_s {
            return;
        }
        let h = self.last_time.map_or(0.0, |t0| t - t0);
        self.last_time = Some(t);
        self.duration_s += h;
        for e in 0..self.position_m.len() {
            let d = &q_full[DOF_PER_NODE * e..DOF_PER_NODE * (e + 2)];
            let l = stress.loads(d);
            self.max_von_mises_pa[e] = self.max_von_mises_pa[e].max(l.von_mises);
            self.mean_von_mises_pa[e] += h * l.von_mises;
            self.max_compression_n[e] = self.max_compression_n[e].max(-l.axial_force);
            self.max_tension_n[e] = self.max_tension_n[e].max(l.axial_force);
            self.max_torque_nm[e] = self.max_torque_nm[e].max(l.torque.abs());
            self.max_bending_moment_nm[e] = self.max_bending_moment_nm[e].max(l.bending_moment);
        }
    }

    /// Turn the accumulated sums into means (call once, at the end of the run).
    pub fn finish(&mut self) {
        if self.duration_s > 0.0 {
            for m in &mut self.mean_von_mises_pa {
                *m /= self.duration_s;
            }
        }
    }

    /// The largest von Mises stress along the string and where, (Pa, m); None when empty.
    pub fn peak(&self) -> Option<(f64, f64)> {
        self.max_von_mises_pa
            .iter()
            .zip(&self.position_m)
            .filter(|(s, _)| s.is_finite())
            .max_by(|a, b| a.0.total_cmp(b.0))
            .map(|(&s, &x)| (s, x))
    }
}
