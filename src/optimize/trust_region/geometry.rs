//! Where the trust-region method may sample: the feasible version of a point, the failure cuts
//! about the centre, the initial `2n+1` design, the sample sets about the centre and the
//! geometry point that most improves their poisedness (steps 1 and 5 of the module doc of
//! [`super`]).

use super::{CUT_FRACTION, TrustRegion, dist_inf, norm_inf};
use crate::optimize::feasible::FEASIBILITY_TOL;
use crate::optimize::model::poisedness;

impl TrustRegion {
    /// `y` clipped to the box, projected onto the set if still outside (`None` if that fails).
    pub(super) fn feasible(&self, y: &[f64]) -> Option<Vec<f64>> {
        let y = self.set.clip_to_box(y);
        if self.set.contains(&y, FEASIBILITY_TOL) {
            return Some(y);
        }
        self.set.project(&y).ok()
    }

    /// Voronoi-type cuts from the failed points within `4Δ` of `xc` (∞-norm): unit normals `u`
    /// and offsets `h` of `uᵀd ≤ h`, `u = (f − x_c)/‖f − x_c‖`, `h = CUT_FRACTION·‖f − x_c‖`.
    pub(super) fn failure_cuts(&self, xc: &[f64]) -> Vec<(Vec<f64>, f64)> {
        self.history
            .iter()
            .filter(|(x, e)| e.failed && dist_inf(x, xc) <= 4.0 * self.radius)
            .filter_map(|(x, _)| {
                let v: Vec<f64> = x.iter().zip(xc).map(|(a, b)| a - b).collect();
                let norm = v.iter().map(|a| a * a).sum::<f64>().sqrt();
                (norm > 0.0).then(|| (v.iter().map(|a| a / norm).collect(), CUT_FRACTION * norm))
            })
            .collect()
    }

    /// `y` violates a failure cut about the centre `xc` (beyond a 1e-9 + 1e-6·Δ tolerance).
    pub(super) fn beyond_cut(&self, y: &[f64], xc: &[f64]) -> bool {
        let tol = 1e-9 + 1e-6 * self.radius;
        self.failure_cuts(xc).iter().any(|(u, h)| {
            u.iter()
                .zip(y.iter().zip(xc))
                .map(|(ui, (a, b))| ui * (a - b))
                .sum::<f64>()
                > h + tol
        })
    }

    pub(super) fn duplicate(&self, y: &[f64]) -> Option<usize> {
        let tol = 1e-12 * (1.0 + norm_inf(y));
        self.history.iter().position(|(x, _)| dist_inf(x, y) <= tol)
    }

    pub(super) fn design(&self, x0: &[f64], radius: f64) -> Vec<Vec<f64>> {
        let mut pts = vec![x0.to_vec()];
        for i in 0..self.n() {
            for sign in [1.0, -1.0] {
                let mut y = x0.to_vec();
                y[i] += sign * radius;
                if let Some(y) = self.feasible(&y)
                    && pts.iter().all(|p| dist_inf(p, &y) > 0.1 * radius)
                {
                    pts.push(y);
                }
            }
        }
        pts
    }

    /// Successful points within `factor·Δ` (∞-norm) of the centre, the centre first, nearest
    /// first, at most `(n+1)(n+2)`.
    pub(super) fn sample_set(&self, c: usize, factor: f64) -> Vec<usize> {
        let xc = &self.history[c].0;
        let lim = factor * self.radius * (1.0 + 1e-9);
        let mut near: Vec<(f64, usize)> = self
            .history
            .iter()
            .enumerate()
            .filter(|&(i, (_, e))| i != c && !e.failed)
            .map(|(i, (x, _))| (dist_inf(x, xc), i))
            .filter(|&(d, _)| d <= lim && d > 1e-10 * self.radius)
            .collect();
        near.sort_by(|a, b| a.0.total_cmp(&b.0));
        let n = self.n();
        let cap = (n + 1) * (n + 2);
        let mut out = vec![c];
        out.extend(near.into_iter().map(|(_, i)| i).take(cap - 1));
        out
    }

    pub(super) fn displacements(&self, c: usize, set: &[usize]) -> Vec<Vec<f64>> {
        let xc = &self.history[c].0;
        set.iter()
            .filter(|&&i| i != c)
            .map(|&i| {
                self.history[i]
                    .0
                    .iter()
                    .zip(xc)
                    .map(|(y, x)| (y - x) / self.radius)
                    .collect()
            })
            .collect()
    }

    /// Picks the candidate point that most improves poisedness; `None` if none improves it.
    /// With `k < n` displacements a candidate is scored by the `(k+1)`-th singular value (how
    /// well it adds a new direction), otherwise by `σ_min`.
    pub(super) fn geometry_point(&self, c: usize, sample: &[usize]) -> Option<Vec<f64>> {
        let n = self.n();
        let xc = self.history[c].0.clone();
        let disp = self.displacements(c, sample);
        let current = poisedness(&disp, n);
        let k = (disp.len() + 1).min(n);
        let floor = if disp.len() < n {
            1e-3
        } else {
            current.sigma_min() + 1e-6
        };
        let mut dirs: Vec<Vec<f64>> = Vec::new();
        for v in current.directions.iter().cloned().chain((0..n).map(|i| {
            let mut e = vec![0.0; n];
            e[i] = 1.0;
            e
        })) {
            dirs.push(v.iter().map(|x| -x).collect());
            dirs.push(v);
        }
        let mut best: Option<(f64, Vec<f64>)> = None;
        for u in dirs {
            let scale = norm_inf(&u);
            if scale < 1e-12 {
                continue;
            }
            let y: Vec<f64> = xc
                .iter()
                .zip(&u)
                .map(|(x, ui)| x + self.radius * ui / scale)
                .collect();
            let Some(y) = self.feasible(&y) else { continue };
            if dist_inf(&y, &xc) < 0.1 * self.radius
                || self.beyond_cut(&y, &xc)
                || self
                    .history
                    .iter()
                    .any(|(x, _)| dist_inf(x, &y) < 0.05 * self.radius)
            {
                continue;
            }
            let mut with = disp.clone();
            with.push(
                y.iter()
                    .zip(&xc)
                    .map(|(a, b)| (a - b) / self.radius)
                    .collect(),
            );
            let s = poisedness(&with, n).kth(k);
            if best.as_ref().is_none_or(|(bs, _)| s > *bs) {
                best = Some((s, y));
            }
        }
        best.filter(|(s, _)| *s > floor).map(|(_, y)| y)
    }
}
