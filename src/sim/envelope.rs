//! The stress envelope of a run along the string (issue 14): at every accepted step from
//! `from` on, the loads and outer-fibre von Mises stress at the midpoint of every element
//! ([`crate::fem::SectionStress`]), reduced on the fly to their extremes and time means, and the
//! fatigue damage of the spinning sections ([`super::fatigue`]); at the end, the compression
//! against the buckling loads of the pipe in its hole ([`crate::model::BucklingLoads`]). Its
//! memory does not grow with the run's length.

use super::fatigue::{FATIGUE_FIBRES, SectionFatigue};
use crate::fatigue::SnCurve;
use crate::fem::{DOF_PER_NODE, ElementLayout, SectionStress};
use crate::model::{BucklingLoads, Drillstring};
use serde::Serialize;

/// Seconds per hour: damage is reported per hour of drilling.
const S_PER_H: f64 = 3600.0;

/// A section of a string of sections along it (`[[model.section]]`): its name and where it
/// starts and ends, m from the top drive.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SectionSpan {
    pub name: String,
    pub from_m: f64,
    pub to_m: f64,
}

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
    /// Miner damage of the section's worst fibre over the window, per hour of drilling
    /// (D · 3600 s / `duration_s`), 1/h; NaN without fatigue tracking or before [`Self::finish`].
    pub fatigue_damage_per_h: Vec<f64>,
    /// Largest compression over the sinusoidal buckling load (≥ 1: buckled sinusoidally, ≥ √2:
    /// helically); NaN without buckling loads or before [`Self::finish`].
    pub buckling_utilization: Vec<f64>,
    /// The buckling loads of the pipe in its hole, if known.
    pub buckling: Option<BucklingLoads>,
    /// The S-N curve of the fatigue damage, if tracked.
    pub sn_curve: Option<SnCurve>,
    /// Material fibres followed per section (0 without fatigue tracking).
    pub fatigue_fibres: usize,
    /// Rainflow residues that filled their counter (see [`crate::fatigue::Rainflow`]).
    pub rainflow_overflows: u64,
    /// The sections of a string of sections, top to bit (empty for a string of one section).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub sections: Vec<SectionSpan>,
    /// Time covered by the means, s (0 before the envelope starts).
    pub duration_s: f64,
    /// When the envelope starts (the analysis window's start), s.
    pub from_s: f64,
    #[serde(skip)]
    last_time: Option<f64>,
    #[serde(skip)]
    fatigue: Option<SectionFatigue>,
    /// Per element, the index of its [`SectionStress`] in the slice [`Self::record`] is given.
    #[serde(skip)]
    kind_of: Vec<usize>,
    /// Per kind of element: the buckling loads of its section (empty without buckling loads).
    #[serde(skip)]
    buckling_by_kind: Vec<BucklingLoads>,
    /// Per kind of element: the yield strength of its section's pipe (empty: not known here).
    #[serde(skip)]
    yield_by_kind: Vec<Option<f64>>,
}

impl StressEnvelope {
    /// An empty envelope of `elements` elements of length `length`, recording from time `from`,
    /// without fatigue tracking and buckling loads (see [`Self::for_string`]).
    pub fn new(elements: usize, length: f64, from: f64) -> Self {
        let midpoints: Vec<f64> = (0..elements).map(|e| (e as f64 + 0.5) * length).collect();
        Self::at(midpoints, vec![0; elements], from)
    }

    /// An empty envelope of the elements whose midpoints are at `midpoints` (m) and whose
    /// [`SectionStress`] is `kinds[e]` of the slice [`Self::record`] is given.
    fn at(midpoints: Vec<f64>, kinds: Vec<usize>, from: f64) -> Self {
        let elements = midpoints.len();
        let zeros = vec![0.0; elements];
        StressEnvelope {
            kind_of: kinds,
            position_m: midpoints,
            max_von_mises_pa: zeros.clone(),
            mean_von_mises_pa: zeros.clone(),
            max_compression_n: zeros.clone(),
            max_tension_n: zeros.clone(),
            max_torque_nm: zeros.clone(),
            max_bending_moment_nm: zeros,
            fatigue_damage_per_h: vec![f64::NAN; elements],
            buckling_utilization: vec![f64::NAN; elements],
            duration_s: 0.0,
            from_s: from,
            ..Default::default()
        }
    }

    /// An empty envelope of `string` on the mesh `layout`, recording from time `from`, with
    /// the fatigue damage on the pipe's S-N curve and its buckling loads. [`Self::record`] takes
    /// one [`SectionStress`] per kind of element of `layout`.
    ///
    /// A string of sections has the buckling loads and the yield strength of each section at
    /// its elements; `buckling` (one set of loads for the whole string) is then `None`.
    pub fn for_string(string: &Drillstring, layout: &ElementLayout, from: f64) -> Self {
        let elements = layout.elements();
        let mut envelope = Self::at(
            layout.midpoints().to_vec(),
            layout.kinds_of_elements().to_vec(),
            from,
        );
        let sections = string.section_strings();
        let of_kinds = |k: &crate::fem::ElementKind| &sections[k.section];
        envelope.buckling_by_kind = (layout.kinds().iter())
            .map(|k| BucklingLoads::of(of_kinds(k)))
            .collect();
        envelope.yield_by_kind = (layout.kinds().iter())
            .map(|k| of_kinds(k).pipe.yield_strength)
            .collect();
        envelope.buckling = string
            .sections
            .is_empty()
            .then(|| envelope.buckling_by_kind[0]);
        let mut from = 0.0;
        envelope.sections = (string.sections.iter())
            .map(|s| {
                let span = SectionSpan {
                    name: s.name.clone(),
                    from_m: from,
                    to_m: from + s.length,
                };
                from += s.length;
                span
            })
            .collect();
        envelope.sn_curve = Some(string.pipe.fatigue.clone());
        envelope.fatigue_fibres = FATIGUE_FIBRES;
        envelope.fatigue = Some(SectionFatigue::new(elements, string.pipe.fatigue.clone()));
        envelope
    }

    /// Add the state at time `t` whose elastic full-mesh displacements are `q_full` and whose
    /// rigid spin angle is `spin` (Ω t, rad: the section's absolute rotation is the spin plus
    /// its elastic θx). The mean is weighted by the step that ends at `t` (right Riemann sum on
    /// the accepted steps).
    /// `stresses` holds the [`SectionStress`] of each kind of element (one for an envelope of
    /// [`Self::new`]). `defects` holds each element's force-summation defect [N, N·m]
    /// ([`crate::rom::ForceSummation`]): its axial force and torque are the strain's less the
    /// defect; empty: the strain's (the unreduced model).
    pub fn record(
        &mut self,
        t: f64,
        q_full: &[f64],
        spin: f64,
        stresses: &[SectionStress],
        defects: &[[f64; 2]],
    ) {
        if t < self.from_s {
            return;
        }
        let h = self.last_time.map_or(0.0, |t0| t - t0);
        self.last_time = Some(t);
        self.duration_s += h;
        for e in 0..self.position_m.len() {
            let stress = &stresses[self.kind_of[e]];
            let d = &q_full[DOF_PER_NODE * e..DOF_PER_NODE * (e + 2)];
            let mut strains = stress.strains(d);
            if let Some(&[axial, torque]) = defects.get(e) {
                stress.balance(&mut strains, axial, torque);
            }
            let l = stress.loads_of(&strains);
            self.max_von_mises_pa[e] = self.max_von_mises_pa[e].max(l.von_mises);
            self.mean_von_mises_pa[e] += h * l.von_mises;
            self.max_compression_n[e] = self.max_compression_n[e].max(-l.axial_force);
            self.max_tension_n[e] = self.max_tension_n[e].max(l.axial_force);
            self.max_torque_nm[e] = self.max_torque_nm[e].max(l.torque.abs());
            self.max_bending_moment_nm[e] = self.max_bending_moment_nm[e].max(l.bending_moment);
            if let Some(f) = &mut self.fatigue {
                // θx at the midpoint: the mean of the nodes' (θx is interpolated linearly).
                let theta = spin + 0.5 * (d[3] + d[DOF_PER_NODE + 3]);
                f.record(e, &strains, theta, stress);
            }
        }
    }

    /// Turn the accumulated sums into means, close the rainflow residues and compare the
    /// compression with the buckling loads (call once, at the end of the run).
    pub fn finish(&mut self) {
        if self.duration_s > 0.0 {
            for m in &mut self.mean_von_mises_pa {
                *m /= self.duration_s;
            }
        }
        if let Some(f) = &mut self.fatigue {
            f.finish();
            self.rainflow_overflows = f.overflows();
            let per_h = if self.duration_s > 0.0 {
                S_PER_H / self.duration_s
            } else {
                f64::NAN
            };
            for (e, rate) in self.fatigue_damage_per_h.iter_mut().enumerate() {
                *rate = f.damage(e) * per_h;
            }
        }
        if let Some(b) = self.buckling
            && self.buckling_by_kind.is_empty()
        {
            // An envelope of `new` given its loads by hand: one set for every element.
            self.buckling_by_kind = vec![b];
            self.kind_of.fill(0);
        }
        if !self.buckling_by_kind.is_empty() {
            for (e, (u, &c)) in (self.buckling_utilization.iter_mut())
                .zip(&self.max_compression_n)
                .enumerate()
            {
                *u = self.buckling_by_kind[self.kind_of[e]].utilization(c);
            }
        }
    }

    /// The sinusoidal buckling load of each element's section, N, top to bit (Dawson & Paslay
    /// 1984, [`BucklingLoads::sinusoidal`]): a step along a string of sections (each section's
    /// own weight and stiffness); empty without buckling loads.
    pub fn sinusoidal_buckling_n(&self) -> Vec<f64> {
        let loads =
            |e: usize| (self.buckling_by_kind.get(self.kind_of[e]).copied()).or(self.buckling);
        if self.kind_of.is_empty() || loads(0).is_none() {
            return Vec::new();
        }
        (0..self.kind_of.len())
            .map(|e| loads(e).map_or(f64::NAN, |b| b.sinusoidal))
            .collect()
    }

    /// The name of the section element `e` belongs to (`None` for a string of one section).
    pub fn section_of(&self, e: usize) -> Option<&str> {
        // A string of sections has one kind of element per section, in order.
        (self.sections.get(self.kind_of[e])).map(|s| s.name.as_str())
    }

    /// The largest compression over the helical buckling load of its section along the string
    /// (0 without compression); None without buckling loads or before [`Self::finish`].
    pub fn helical_peak(&self) -> Option<f64> {
        // Each element's section's loads, or the one set of an envelope given them by hand.
        let loads =
            |e: usize| (self.buckling_by_kind.get(self.kind_of[e]).copied()).or(self.buckling);
        if self.kind_of.is_empty() {
            return None;
        }
        loads(0)?;
        let of = |e: usize, &c: &f64| {
            let c = c.max(0.0);
            match loads(e) {
                Some(b) if c > 0.0 => c / b.helical,
                _ => 0.0,
            }
        };
        Some(
            (self.max_compression_n.iter().enumerate())
                .map(|(e, c)| of(e, c))
                .fold(f64::NAN, f64::max),
        )
    }

    /// The von Mises utilization max σ_vM / σ_y and safety factor min σ_y / σ_vM along the
    /// string, each element against its section's yield strength (`yield_strength` for an
    /// envelope that does not know its sections'); NaN for both without a yield strength.
    pub fn yield_utilization(&self, yield_strength: Option<f64>) -> (f64, f64) {
        let (mut utilization, mut safety) = (f64::NAN, f64::NAN);
        for (e, &peak) in self.max_von_mises_pa.iter().enumerate() {
            let y = match self.yield_by_kind.get(self.kind_of[e]) {
                Some(y) => *y,
                None => yield_strength,
            };
            if let Some(y) = y
                && peak.is_finite()
            {
                utilization = utilization.max(peak / y);
                safety = safety.min(y / peak);
            }
        }
        (utilization, safety)
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

    /// The largest fatigue damage rate along the string and where, (1/h, m), the topmost of
    /// equals; None without fatigue tracking or before [`Self::finish`].
    pub fn fatigue_peak(&self) -> Option<(f64, f64)> {
        largest(&self.fatigue_damage_per_h, &self.position_m)
    }

    /// The largest buckling utilization along the string and where, (–, m), the topmost of
    /// equals; None without buckling loads or before [`Self::finish`].
    pub fn buckling_peak(&self) -> Option<(f64, f64)> {
        largest(&self.buckling_utilization, &self.position_m)
    }
}

/// The largest non-NaN value of `values` and its position (the first of equals).
fn largest(values: &[f64], positions: &[f64]) -> Option<(f64, f64)> {
    values
        .iter()
        .zip(positions)
        .filter(|(v, _)| !v.is_nan())
        .fold(None, |best: Option<(f64, f64)>, (&v, &x)| match best {
            Some((b, _)) if b >= v => best,
            _ => Some((v, x)),
        })
}
