//! Critical speeds: the spin rates Ω_c where a mode's frequency meets an excitation at k times
//! the rotation frequency, f(Ω_c) = k Ω_c / 2π, and the margin of an operating Ω from the nearest
//! of them.
//!
//! Which excitations drive which modes ([`multiples_for`], issue 33 item 3): a bending (lateral)
//! mode is driven at 1× (mass imbalance, a bent or sagging pipe turning, the whirl of the spinning
//! string; Jansen 1991, Spanos et al. 2003) and at the bit's multiple k (a tri-cone bit's three
//! cones, a PDC bit's blades: the cutting structure modulates the side force k times a
//! revolution). An axial or torsional mode is driven by the bit's WOB and torque, which the
//! cutting structure modulates k times a revolution (bit-bounce of a tri-cone bit at 3×; blade
//! passing); nothing in a drillstring drives them at 1× (stick-slip is self-excited, not a
//! resonance), so they are met against k× only. Counting them on 1× made the margin 0 at every Ω
//! of a 2 km string, where torsional and axial modes lie densely along the 1× line.
//!
//! On the Campbell grid, g(Ω) = f(Ω) − k Ω/2π changes sign between two spin rates where a curve
//! crosses the line; the crossing is then refined on the eigenvalue itself: g is evaluated by a
//! new eigensolution at the trial Ω (the mode most alike the curve's at the bracket's lower end),
//! and the root found by the Illinois variant of regula falsi (Dowell & Jarratt, BIT 11, 1971),
//! which keeps the bracket and is exact in one step on a straight line; the bracket is closed to
//! [`REFINE_TOLERANCE`] relative.

use super::diagram::CampbellDiagram;
use super::spectrum::mac;
use super::{CampbellError, LinearSystem, ModeFamily, Whirl, spectrum};
use serde::Serialize;
use std::f64::consts::TAU;

/// Relative width of the bracket at which a crossing is taken as found.
pub const REFINE_TOLERANCE: f64 = 1e-9;

/// The margin is reported up to this value: a margin of 50 % or more means no critical speed in
/// [Ω/1.5, 2Ω], and is reported as 0.5 (see [`margin`]).
pub const MARGIN_CAP: f64 = 0.5;

/// Largest ratio of neighbouring spin rates of the grid the margin's search uses.
pub const SEARCH_RATIO: f64 = 1.02;

/// Where a mode meets an excitation line.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CriticalSpeed {
    /// Ω_c, rad/s.
    pub omega_rad_s: f64,
    /// Ω_c, rpm.
    pub omega_rpm: f64,
    /// The mode's frequency there, k Ω_c / 2π, Hz.
    pub freq_hz: f64,
    /// k: 1 or the bit's multiple.
    pub multiple: f64,
    /// The curve's index in the diagram (1-based).
    pub mode: usize,
    pub family: ModeFamily,
    pub whirl: Whirl,
}

/// Indices i where `g` changes sign from `g[i]` to `g[i + 1]` (a zero counts at its own index:
/// i with g[i] = 0 is reported as the bracket (i, i) — see [`crossings`]). Non-finite values
/// break brackets.
pub fn sign_changes(g: &[f64]) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    for i in 0..g.len() {
        if g[i] == 0.0 {
            out.push((i, i));
        } else if i + 1 < g.len()
            && g[i].is_finite()
            && g[i + 1].is_finite()
            && g[i + 1] != 0.0
            && (g[i] > 0.0) != (g[i + 1] > 0.0)
        {
            out.push((i, i + 1));
        }
    }
    out
}

/// A root of the continuous `g` in [lo, hi], where g(lo) = `glo` and g(hi) = `ghi` have opposite
/// signs: Illinois regula falsi until the bracket is narrower than `rel_tol` × |hi| (or g = 0 or
/// 100 steps). `g` returning None (no value there) halves the bracket towards `lo` instead.
pub fn refine_root(
    mut lo: f64,
    mut hi: f64,
    mut glo: f64,
    mut ghi: f64,
    rel_tol: f64,
    mut g: impl FnMut(f64) -> Option<f64>,
) -> f64 {
    let mut side = 0i8;
    for _ in 0..100 {
        if (hi - lo).abs() <= rel_tol * hi.abs().max(lo.abs()) {
            break;
        }
        let mut x = (lo * ghi - hi * glo) / (ghi - glo);
        if !(x > lo.min(hi) && x < lo.max(hi)) {
            x = 0.5 * (lo + hi);
        }
        let Some(gx) = g(x) else {
            hi = x;
            continue;
        };
        if gx == 0.0 {
            return x;
        }
        if (gx > 0.0) == (ghi > 0.0) {
            hi = x;
            ghi = gx;
            if side == 1 {
                glo *= 0.5;
            }
            side = 1;
        } else {
            lo = x;
            glo = gx;
            if side == -1 {
                ghi *= 0.5;
            }
            side = -1;
        }
    }
    (lo * ghi - hi * glo) / (ghi - glo)
}

/// The critical speeds of the diagram's curves against the excitation lines k Ω/2π that drive
/// each curve's family ([`multiples_for`] of the bit's `multiple`), refined on `sys` (see the
/// module documentation), by increasing Ω.
pub fn crossings(
    sys: &LinearSystem,
    diagram: &CampbellDiagram,
    multiple: f64,
) -> Result<Vec<CriticalSpeed>, CampbellError> {
    let mut out = Vec::new();
    let om = &diagram.omegas;
    for (c, curve) in diagram.curves.iter().enumerate() {
        for k in multiples_for(curve.family, multiple) {
            let g: Vec<f64> = (0..om.len())
                .map(|i| diagram.freq_hz(c, i) - k * om[i] / TAU)
                .collect();
            for (a, b) in sign_changes(&g) {
                let omega =
                    if a == b {
                        om[a]
                    } else {
                        let reference = diagram.mode(c, a).expect("finite g").vector.clone();
                        let mut failure = None;
                        let root = refine_root(om[a], om[b], g[a], g[b], REFINE_TOLERANCE, |x| {
                            match spectrum(sys, x) {
                                Ok(s) => s
                                    .modes
                                    .iter()
                                    .max_by(|p, q| {
                                        mac(sys, &reference, &p.vector)
                                            .total_cmp(&mac(sys, &reference, &q.vector))
                                    })
                                    .map(|m| m.freq_hz - k * x / TAU),
                                Err(e) => {
                                    failure = Some(e);
                                    None
                                }
                            }
                        });
                        if let Some(e) = failure {
                            return Err(e);
                        }
                        root
                    };
                out.push(CriticalSpeed {
                    omega_rad_s: omega,
                    omega_rpm: crate::units::to_rpm(omega),
                    freq_hz: k * omega / TAU,
                    multiple: k,
                    mode: curve.index,
                    family: curve.family,
                    whirl: curve.whirl,
                });
            }
        }
    }
    out.sort_by(|a, b| a.omega_rad_s.total_cmp(&b.omega_rad_s));
    Ok(out)
}

/// The relative distance of `omega` from the nearest critical speed,
/// min over Ω_c of |Ω − Ω_c| / Ω_c, capped at [`MARGIN_CAP`]. The cap makes the value depend only
/// on the critical speeds in [`margin_window`]`(omega)`: a critical speed outside it is at least
/// 50 % away.
pub fn margin(omega: f64, speeds: &[CriticalSpeed]) -> f64 {
    speeds
        .iter()
        .map(|c| (omega - c.omega_rad_s).abs() / c.omega_rad_s)
        .fold(MARGIN_CAP, f64::min)
}

/// [Ω/(1 + cap), Ω/(1 − cap)] = [Ω/1.5, 2Ω]: the critical speeds whose margin from Ω is at most
/// the cap.
pub fn margin_window(omega: f64) -> [f64; 2] {
    [omega / (1.0 + MARGIN_CAP), omega / (1.0 - MARGIN_CAP)]
}

/// A geometric grid from `lo` to `hi` (0 < lo < hi) with neighbouring ratios at most `ratio`,
/// at least 8 points.
pub fn geometric_grid(lo: f64, hi: f64, ratio: f64) -> Vec<f64> {
    let steps = ((hi / lo).ln() / ratio.ln()).ceil().max(7.0) as usize;
    (0..=steps)
        .map(|i| lo * (hi / lo).powf(i as f64 / steps as f64))
        .collect()
}

/// The critical speeds that decide the margin of any Ω in an operating range.
#[derive(Debug, Clone, PartialEq)]
pub struct MarginTable {
    /// The operating range [Ω_lo, Ω_hi] it answers for, rad/s.
    pub range: [f64; 2],
    /// The critical speeds in [Ω_lo/1.5, 2 Ω_hi].
    pub speeds: Vec<CriticalSpeed>,
}

impl MarginTable {
    /// Search the critical speeds of `sys` against 1× and `multiple` over the windows of every
    /// Ω in `range` (rad/s, 0 < lo ≤ hi), on a geometric grid of ratio [`SEARCH_RATIO`].
    pub fn search(
        sys: &LinearSystem,
        multiple: f64,
        range: [f64; 2],
    ) -> Result<Self, CampbellError> {
        let (lo, hi) = (margin_window(range[0])[0], margin_window(range[1])[1]);
        let grid = geometric_grid(lo, hi, SEARCH_RATIO);
        let diagram = CampbellDiagram::sweep(sys, &grid, |_| {})?;
        let speeds = crossings(sys, &diagram, multiple)?;
        Ok(MarginTable { range, speeds })
    }

    /// The margin of `omega` (rad/s), or None outside the range the table answers for.
    pub fn margin(&self, omega: f64) -> Option<f64> {
        let tolerance = 1e-12 * self.range[1];
        (omega >= self.range[0] - tolerance && omega <= self.range[1] + tolerance)
            .then(|| margin(omega, &self.speeds))
    }
}

/// The rule of [`multiples_for`], in the evaluation cache's key: 2 since axial and torsional
/// modes are met against the bit's multiple only (1: every family against 1× and k×).
pub const CRITICAL_SPEED_RULE: u32 = 2;

/// The excitation lines that drive a mode of `family` (module doc): bending 1× and `multiple`×,
/// axial and torsional `multiple`× only.
pub fn multiples_for(family: ModeFamily, multiple: f64) -> Vec<f64> {
    match family {
        ModeFamily::Bending => multiples(multiple),
        ModeFamily::Axial | ModeFamily::Torsional => vec![multiple],
    }
}

/// The excitation lines of the diagram: 1× and `multiple`× (once when the multiple is 1).
pub fn multiples(multiple: f64) -> Vec<f64> {
    if multiple == 1.0 {
        vec![1.0]
    } else {
        vec![1.0, multiple]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn illinois_finds_a_line_crossing_at_once_and_a_curve_to_tolerance() {
        // f(Ω) = a + bΩ Hz meets kΩ/2π at Ω* = a / (k/2π − b).
        let (a, b, k) = (5.0, 0.002, 3.0);
        let g = |x: f64| a + b * x - k * x / TAU;
        let exact = a / (k / TAU - b);
        let mut calls = 0;
        let root = refine_root(1.0, 40.0, g(1.0), g(40.0), 1e-12, |x| {
            calls += 1;
            Some(g(x))
        });
        assert!((root - exact).abs() < 1e-10 * exact, "{root} vs {exact}");
        assert!(calls <= 3, "{calls} evaluations for a straight line");
        let root = refine_root(0.0, 3.0, -2.0, 7.0, 1e-12, |x| Some(x * x * x - 2.0));
        assert!((root - 2f64.cbrt()).abs() < 1e-11);
    }

    #[test]
    fn sign_changes_and_margins() {
        assert_eq!(
            sign_changes(&[1.0, 0.5, -0.1, -0.2, 0.0, 3.0, f64::NAN, -1.0]),
            vec![(1, 2), (4, 4)]
        );
        let at = |rpm: f64| CriticalSpeed {
            omega_rad_s: crate::units::from_rpm(rpm),
            omega_rpm: rpm,
            freq_hz: 0.0,
            multiple: 1.0,
            mode: 1,
            family: ModeFamily::Bending,
            whirl: Whirl::Forward,
        };
        let omega = crate::units::from_rpm(60.0);
        assert!((margin(omega, &[at(50.0), at(100.0)]) - 0.2).abs() < 1e-12);
        assert!((margin(omega, &[at(70.0)]) - 10.0 / 70.0).abs() < 1e-12);
        assert_eq!(margin(omega, &[at(10.0), at(500.0)]), MARGIN_CAP);
        assert_eq!(margin(omega, &[]), MARGIN_CAP);
        let [lo, hi] = margin_window(omega);
        assert!(
            (margin(
                omega,
                &[CriticalSpeed {
                    omega_rad_s: lo,
                    ..at(0.0)
                }]
            ) - 0.5)
                .abs()
                < 1e-12
        );
        assert!(
            (margin(
                omega,
                &[CriticalSpeed {
                    omega_rad_s: hi,
                    ..at(0.0)
                }]
            ) - 0.5)
                .abs()
                < 1e-12
        );
        let grid = geometric_grid(1.0, 10.0, 1.02);
        assert!(grid.windows(2).all(|w| w[1] / w[0] <= 1.02 + 1e-12));
        assert!((grid[0] - 1.0).abs() < 1e-15 && (grid.last().unwrap() - 10.0).abs() < 1e-12);
        assert_eq!(multiples(1.0), vec![1.0]);
        assert_eq!(multiples(3.0), vec![1.0, 3.0]);
        assert_eq!(multiples_for(ModeFamily::Bending, 3.0), vec![1.0, 3.0]);
        assert_eq!(multiples_for(ModeFamily::Torsional, 3.0), vec![3.0]);
        assert_eq!(multiples_for(ModeFamily::Axial, 4.0), vec![4.0]);
        assert_eq!(multiples_for(ModeFamily::Axial, 1.0), vec![1.0]);
    }
}
