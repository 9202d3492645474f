//! The rock surface a bit's blades leave: the state of a depth-of-cut law (MODEL.md §11.7,
//! [`crate::model::bit::Rgd`]).
//!
//! Richard, Germay & Detournay (2007) write the depth of cut with a state-dependent delay,
//! d(t) = n (u(t) − u(t − t_n)), t_n the time the bit took to turn the last 2π/n. drillopt keeps
//! the same information as a function of angle instead of time: the axial position L(ψ) of the
//! rock at each angle ψ ∈ [0, 2π/n) of one blade sector (the blades are identical, so the
//! bottom hole repeats every 2π/n). A blade at absolute angle θ cuts
//!
//! d = n (u − L(θ mod 2π/n)),
//!
//! and as it passes an angle it leaves the rock at max(L, u) there: the rock only gets deeper.
//! For a bit that turns forward and stays on bottom this is the delay law exactly (L(ψ) is where
//! the previous blade was when it passed ψ); it also says what the delay law leaves open: after a
//! bounce the bit lands on the rock the last blade that touched it left (d ≤ 0 while it is above
//! it: no load), it does not cut while it stands still or turns back, and the history needs no
//! memory that grows with a stick phase's length.
//!
//! Discretisation: [`NODES_PER_REVOLUTION`] nodes over the revolution (so 2π/n is split in equal
//! cells), L linear between nodes. At the end of each accepted step the nodes the blade swept
//! are set from u linear in θ between the step's ends (the integrator's own second order). A
//! depth is read on the rock ahead of the blade: in the cell the blade is crossing, the node it
//! has just cut belongs to the next blade's rock, so the cell is read from the two nodes ahead.
//! Memory: two vectors of one revolution's nodes, allocated once.

use std::f64::consts::PI;

/// Nodes of the rock surface per revolution of the bit (4096: 0.088° apart; the depth a blade
/// reads is exact on a steady helix and second-order in the node spacing otherwise).
pub const NODES_PER_REVOLUTION: usize = 4096;

/// The bottom hole under a bit of n blades: rock position L at each node of one blade sector.
#[derive(Debug, Clone, PartialEq)]
pub struct RockSurface {
    blades: f64,
    /// 2π/n, rad.
    sector: f64,
    /// Node spacing Δψ, rad.
    spacing: f64,
    /// L at each node (the absolute axial position of the rock, positive into the rock), m.
    height: Vec<f64>,
    /// The bit's absolute angle when a blade last cut each node, rad.
    cut_at: Vec<f64>,
    /// The bit's absolute angle and axial position at the last accepted state.
    last: (f64, f64),
}

/// A depth of cut read off the surface: d per revolution and its derivatives.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Cut {
    /// d = n (u − L), m per revolution (≤ 0: the bit is above the rock).
    pub depth: f64,
    /// ∂d/∂u = n.
    pub d_position: f64,
    /// ∂d/∂θ = −n ∂L/∂ψ, m/rad.
    pub d_angle: f64,
}

impl RockSurface {
    /// The helical bottom hole of steady drilling: the bit at absolute angle `angle` (rad) and
    /// axial position `position` (m) has cut `pitch` metres per revolution (≥ 0) for ever, so
    /// the rock at an angle δ behind the blade is at `position − pitch δ/2π`. A pitch of 0 is a
    /// flat bottom touching the bit.
    pub fn helix(blades: u32, angle: f64, position: f64, pitch: f64) -> Self {
        let n = blades.max(1) as usize;
        let nodes = NODES_PER_REVOLUTION.div_ceil(n);
        let sector = 2.0 * PI / n as f64;
        let spacing = sector / nodes as f64;
        let front = angle.rem_euclid(sector);
        let mut height = Vec::with_capacity(nodes);
        let mut cut_at = Vec::with_capacity(nodes);
        for j in 0..nodes {
            let lag = (front - j as f64 * spacing).rem_euclid(sector);
            height.push(position - pitch * lag / (2.0 * PI));
            cut_at.push(angle - lag);
        }
        RockSurface {
            blades: n as f64,
            sector,
            spacing,
            height,
            cut_at,
            last: (angle, position),
        }
    }

    /// The number of blades n.
    pub fn blades(&self) -> u32 {
        self.blades as u32
    }

    /// Whether node `j` was cut by the blade now at `angle` (within half a sector behind or
    /// anywhere ahead of it: it turned back), not by the blade before.
    fn fresh(&self, j: usize, angle: f64) -> bool {
        angle - self.cut_at[j] < 0.5 * self.sector
    }

    /// The depth of cut per revolution of a bit at absolute angle `angle` (rad) and axial
    /// position `position` (m) on this surface, with its derivatives.
    pub fn cut(&self, angle: f64, position: f64) -> Cut {
        let m = self.height.len();
        let x = angle / self.spacing;
        let k = x.floor();
        let f = x - k;
        let node = |i: f64| (i.rem_euclid(m as f64) as usize).min(m - 1);
        let (j0, j1, j2) = (node(k), node(k + 1.0), node(k + 2.0));
        let h = &self.height;
        let (level, slope) = if self.fresh(j0, angle) && !self.fresh(j1, angle) {
            if self.fresh(j2, angle) {
                (h[j1], 0.0)
            } else {
                let s = (h[j2] - h[j1]) / self.spacing;
                (h[j1] + (f - 1.0) * (h[j2] - h[j1]), s)
            }
        } else {
            (h[j0] + f * (h[j1] - h[j0]), (h[j1] - h[j0]) / self.spacing)
        };
        Cut {
            depth: self.blades * (position - level),
            d_position: self.blades,
            d_angle: -self.blades * slope,
        }
    }

    /// The blades sweep from the last accepted state to the bit at absolute `angle` (rad) and
    /// `position` (m), the new accepted state: every node passed going forward is cut to the
    /// deeper of its rock and the bit (u linear in θ along the step). Turning back cuts nothing.
    pub fn advance(&mut self, angle: f64, position: f64) {
        let (a0, u0) = self.last;
        self.last = (angle, position);
        if angle <= a0 {
            return;
        }
        let m = self.height.len() as f64;
        let first = (a0 / self.spacing).floor() + 1.0;
        let last = (angle / self.spacing).floor();
        let mut k = first;
        while k <= last {
            let at = k * self.spacing;
            let u = u0 + (position - u0) * (at - a0) / (angle - a0);
            let j = (k.rem_euclid(m) as usize).min(self.height.len() - 1);
            if u > self.height[j] {
                self.height[j] = u;
                self.cut_at[j] = at;
            }
            k += 1.0;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Drives a bit along (θ(t), u(t)) in steps of `dt`, returns the depths read at each step's
    /// end before the step is accepted (as the integrator's residual does).
    fn drive(
        s: &mut RockSurface,
        path: impl Fn(f64) -> (f64, f64),
        dt: f64,
        steps: usize,
    ) -> Vec<(f64, Cut)> {
        (1..=steps)
            .map(|i| {
                let t = i as f64 * dt;
                let (a, u) = path(t);
                let c = s.cut(a, u);
                s.advance(a, u);
                (t, c)
            })
            .collect()
    }

    #[test]
    fn steady_drilling_cuts_the_pitch_of_its_helix() {
        // 120 rpm, 10 m/h, 4 blades: 2πV/Ω = 1.389 mm per revolution, from the start and after
        // 20 revolutions, whatever the step.
        let (omega, v) = (4.0 * PI, 10.0 / 3600.0);
        let pitch = 2.0 * PI * v / omega;
        for dt in [1e-4, 7.3e-4, 3e-3] {
            let mut s = RockSurface::helix(4, 0.3, 0.01, pitch);
            let path = |t: f64| (0.3 + omega * t, 0.01 + v * t);
            for (t, c) in drive(&mut s, path, dt, (10.0 / dt) as usize) {
                assert!(
                    (c.depth / pitch - 1.0).abs() < 1e-9,
                    "dt {dt}, t {t}: {} vs {pitch}",
                    c.depth
                );
                assert_eq!(c.d_position, 4.0);
                assert!((c.d_angle / (-pitch / (2.0 * PI)) * 1.0 / 4.0 - 1.0).abs() < 1e-6);
            }
        }
    }

    #[test]
    fn an_oscillating_bit_cuts_what_the_delay_law_says() {
        // u(t) = V t + A sin(ϖ t) at constant Ω, A ϖ < V (the bit never rises, so it never
        // leaves the rock): the delay law gives d(t) = n (u(t) − u(t − 2π/(nΩ))) in closed
        // form, once the helix of the start has been cut away (after one sector).
        let (n, omega, v, amp, w) = (5u32, 10.0, 2e-3, 4e-5, 37.0);
        let u = |t: f64| v * t + amp * (w * t).sin();
        let tau = 2.0 * PI / (n as f64 * omega);
        let mut s = RockSurface::helix(n, 0.0, 0.0, 2.0 * PI * v / omega);
        let mut worst: f64 = 0.0;
        let dt = 2e-4;
        for (t, c) in drive(&mut s, |t| (omega * t, u(t)), dt, 20_000) {
            if t > 1.5 * tau {
                let exact = n as f64 * (u(t) - u(t - tau));
                worst = worst.max((c.depth - exact).abs() / (n as f64 * amp));
            }
        }
        // u linear in θ within a step (Δt = 2e-4 s) and between nodes (1.5e-4 s apart at this
        // speed): each errs by at most A ϖ² Δt²/8, 7e-6 and 4e-6 of A.
        assert!(worst < 1.5e-5, "worst relative error {worst}");
    }

    #[test]
    fn a_bit_that_lifts_off_lands_on_the_rock_it_left() {
        // Drill one revolution steadily (3 blades, 5 mm per revolution), lift 3 mm (more than a
        // blade's 1.67 mm) and turn half a revolution in the air: above the rock all along, and
        // nothing is cut. Back at the depth it had, the blade reads the rock the last cutting
        // pass left: at θ = 3π (ψ = π/3 in the 2π/3 sector) the pass at θ = 5π/3, t = 5/6 s.
        let (n, omega, v) = (3u32, 2.0 * PI, 5e-3);
        let pitch = 2.0 * PI * v / omega;
        let mut s = RockSurface::helix(n, 0.0, 0.0, pitch);
        drive(&mut s, |t| (omega * t, v * t), 1e-3, 1000);
        // Lifted straight up (no turn, no cut), then turning in the air.
        s.advance(2.0 * PI, v - 3e-3);
        let before = s.height.clone();
        let lifted = drive(&mut s, |t| (omega * (1.0 + t), v - 3e-3), 1e-3, 500);
        assert!(lifted.iter().all(|(_, c)| c.depth < 0.0));
        assert!(s.height == before, "an airborne bit cuts nothing");
        let c = s.cut(3.0 * PI, v);
        let exact = n as f64 * (v - v * 5.0 / 6.0);
        assert!((c.depth - exact).abs() < 1e-9 * exact, "{c:?} vs {exact}");
    }

    #[test]
    fn standing_still_or_turning_back_cuts_nothing() {
        let (omega, v) = (6.0, 3e-3);
        let pitch = 2.0 * PI * v / omega;
        let mut s = RockSurface::helix(4, 1.0, 0.0, pitch);
        let before = s.clone();
        // Stuck, pushed 0.2 mm into the rock: the depth grows as n Δu, the rock does not move.
        s.advance(1.0, 2e-4);
        assert_eq!(s.height, before.height);
        let c = s.cut(1.0, 2e-4);
        assert!((c.depth - (pitch + 4.0 * 2e-4)).abs() < 1e-12, "{c:?}");
        // Turning back along its own path over the rock it has just cut: nothing left to cut,
        // and the rock is not cut again.
        let mut s = before.clone();
        s.advance(1.2, 0.2 * v / omega);
        let cut = s.height.clone();
        s.advance(1.1, 0.1 * v / omega);
        assert_eq!(s.height, cut);
        let c = s.cut(1.1, 0.1 * v / omega);
        assert!(c.depth.abs() < 1e-12, "{c:?}");
    }

    #[test]
    fn the_read_is_second_order_in_the_node_spacing_on_a_curved_surface() {
        // A bit that turned at constant speed while its axial position followed a parabola
        // leaves a parabolic rock: linear interpolation errs by L'' Δψ²/8 at most.
        let (n, omega) = (2u32, 8.0);
        let u = |t: f64| 1e-3 * t * t;
        let mut s = RockSurface::helix(n, 0.0, 0.0, 0.0);
        drive(&mut s, |t| (omega * t, u(t)), 1e-4, 4000);
        let t = 0.3 + 0.123e-3;
        let c = s.cut(omega * t + 2.0 * PI / n as f64, 0.0);
        let exact = n as f64 * (0.0 - u(t));
        let spacing = 2.0 * PI / NODES_PER_REVOLUTION as f64;
        let curvature = 2e-3 / (omega * omega);
        assert!(
            // Node spacing, and u linear in θ within the 0.1 ms steps.
            (c.depth - exact).abs()
                <= n as f64 * (curvature * spacing * spacing + 2e-3 * 1e-8) / 8.0 * (1.0 + 1e-6),
            "{} vs {exact}",
            c.depth
        );
    }
}
