//! The Campbell diagram: the spectrum of the linearised string over a grid of spin rates, each
//! mode followed from one rate to the next.
//!
//! A mode is followed by its shape, not by its rank: the mode at Ω_{i+1} that continues a mode at
//! Ω_i is the one whose eigenvector is most alike (largest modal assurance criterion
//! |xᴴ M y|², the vectors M-normalised; Allemang, *The modal assurance criterion — twenty years
//! of use and abuse*, Sound Vib. 37, 2003), matched greedily from the most alike pair down, among
//! modes within a factor 2 in frequency. So two curves may cross (a forward and a backward mode,
//! or a bending and a torsional one) without swapping. A mode left unmatched starts a new curve.
//! At Ω = 0 without contact the bending modes come in degenerate pairs whose eigenvectors are any
//! mixture of the two planes; either matching gives the same frequencies there.

use super::spectrum::mac;
use super::{CampbellError, EigenMode, LinearSystem, ModeFamily, Spectrum, Whirl, spectrum};

/// One mode followed over the grid.
#[derive(Debug, Clone, PartialEq)]
pub struct Curve {
    /// 1-based, by frequency where the curve starts.
    pub index: usize,
    /// The family of most of its points.
    pub family: ModeFamily,
    /// The whirl of most of its points with one (forward, backward or planar), else none.
    pub whirl: Whirl,
    /// At each grid point, the index of the mode in that point's spectrum (None: not there).
    pub members: Vec<Option<usize>>,
}

/// Spectra over a grid of spin rates and the modes followed through them.
#[derive(Debug, Clone)]
pub struct CampbellDiagram {
    /// The spin rates Ω, rad/s, increasing.
    pub omegas: Vec<f64>,
    pub spectra: Vec<Spectrum>,
    pub curves: Vec<Curve>,
}

impl CampbellDiagram {
    /// The spectra of `sys` at `omegas` (rad/s, ≥ 0, increasing), modes followed by shape;
    /// `progress(i)` after the i-th spin rate.
    pub fn sweep(
        sys: &LinearSystem,
        omegas: &[f64],
        mut progress: impl FnMut(usize),
    ) -> Result<Self, CampbellError> {
        let mut spectra = Vec::with_capacity(omegas.len());
        for (i, &omega) in omegas.iter().enumerate() {
            spectra.push(spectrum(sys, omega)?);
            progress(i);
        }
        let mut members: Vec<Vec<Option<usize>>> = Vec::new();
        if let Some(first) = spectra.first() {
            members = (0..first.modes.len())
                .map(|j| {
                    let mut m = vec![None; omegas.len()];
                    m[0] = Some(j);
                    m
                })
                .collect();
        }
        for i in 1..spectra.len() {
            let next = follow(sys, &spectra[i - 1].modes, &spectra[i].modes);
            let mut taken = vec![false; spectra[i].modes.len()];
            for m in members.iter_mut() {
                if let Some(b) = m[i - 1].and_then(|a| next[a]) {
                    m[i] = Some(b);
                    taken[b] = true;
                }
            }
            for (b, _) in taken.iter().enumerate().filter(|(_, t)| !**t) {
                let mut m = vec![None; omegas.len()];
                m[i] = Some(b);
                members.push(m);
            }
        }
        let start = |m: &Vec<Option<usize>>| {
            let i = m.iter().position(Option::is_some).unwrap_or(0);
            (spectra[i].modes[m[i].unwrap_or(0)].freq_hz, i)
        };
        members.sort_by(|a, b| {
            let (fa, ia) = start(a);
            let (fb, ib) = start(b);
            fa.total_cmp(&fb).then(ia.cmp(&ib))
        });
        let curves = members
            .into_iter()
            .enumerate()
            .map(|(k, members)| {
                let modes: Vec<&EigenMode> = members
                    .iter()
                    .enumerate()
                    .filter_map(|(i, m)| m.map(|j| &spectra[i].modes[j]))
                    .collect();
                Curve {
                    index: k + 1,
                    family: majority(&modes),
                    whirl: whirl(&modes),
                    members,
                }
            })
            .collect();
        Ok(CampbellDiagram {
            omegas: omegas.to_vec(),
            spectra,
            curves,
        })
    }

    /// The mode of curve `c` (0-based position in `curves`) at grid point `i`.
    pub fn mode(&self, c: usize, i: usize) -> Option<&EigenMode> {
        self.curves[c].members[i].map(|j| &self.spectra[i].modes[j])
    }

    /// Its frequency, Hz (NaN where the curve is not).
    pub fn freq_hz(&self, c: usize, i: usize) -> f64 {
        self.mode(c, i).map_or(f64::NAN, |m| m.freq_hz)
    }
}

/// For each mode of `prev`, the mode of `next` that continues it (see the module documentation).
pub(super) fn follow(
    sys: &LinearSystem,
    prev: &[EigenMode],
    next: &[EigenMode],
) -> Vec<Option<usize>> {
    let mut pairs: Vec<(f64, f64, usize, usize)> = Vec::new();
    for (a, ma) in prev.iter().enumerate() {
        for (b, mb) in next.iter().enumerate() {
            let (lo, hi) = (ma.freq_hz.min(mb.freq_hz), ma.freq_hz.max(mb.freq_hz));
            if hi > 2.0 * lo {
                continue;
            }
            let alike = mac(sys, &ma.vector, &mb.vector);
            pairs.push((alike, (hi - lo) / hi.max(f64::MIN_POSITIVE), a, b));
        }
    }
    // Most alike first; among equals, the closest in frequency.
    pairs.sort_by(|x, y| y.0.total_cmp(&x.0).then(x.1.total_cmp(&y.1)));
    let mut out = vec![None; prev.len()];
    let mut used = vec![false; next.len()];
    for (_, _, a, b) in pairs {
        if out[a].is_none() && !used[b] {
            out[a] = Some(b);
            used[b] = true;
        }
    }
    out
}

fn majority(modes: &[&EigenMode]) -> ModeFamily {
    let families = [
        ModeFamily::Axial,
        ModeFamily::Torsional,
        ModeFamily::Bending,
    ];
    let count = |f: ModeFamily| modes.iter().filter(|m| m.family == f).count();
    families
        .into_iter()
        .max_by_key(|&f| count(f))
        .unwrap_or(ModeFamily::Bending)
}

/// The whirl most of a curve's points have among forward, backward and planar; none on a tie
/// or when no point has one.
fn whirl(modes: &[&EigenMode]) -> Whirl {
    let count = |w: Whirl| modes.iter().filter(|m| m.whirl == w).count();
    let counts = [Whirl::Forward, Whirl::Backward, Whirl::Planar].map(|w| (count(w), w));
    let top = counts.iter().map(|c| c.0).max().unwrap_or(0);
    let mut leaders = counts.iter().filter(|c| c.0 == top && top > 0);
    match (leaders.next(), leaders.next()) {
        (Some(&(_, w)), None) => w,
        _ => Whirl::None,
    }
}
