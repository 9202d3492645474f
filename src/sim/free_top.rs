//! The string under a top that is not an imposed feed (MODEL.md §11.8, [`crate::model::top`]):
//! the block's position s joins the reduced coordinates.
//!
//! Q = e_u s + e_θ Ω t + Φ q, so the unknowns are (q, s) (n + 1). The rows of q are those of
//! [`Dynamics`] with the rigid axial velocity ṡ in place of V0 and the inertia Φᵀ M e_u s̈ of the
//! block's acceleration added. The row of s is the top law:
//!
//! - hook load: F_top(q, q̇, q̈, ṡ, s̈) − W = 0, the axial balance of the whole string
//!   ([`Dynamics::top_loads`]: e_uᵀ(M Q̈ + C Q̇ + f − F), the force the top must push with) held at
//!   the set-point;
//! - autodriller: M_s (s̈ − a_cmd(ṡ, F_top, T_top)) = 0 with the commanded acceleration of
//!   [`autodriller_acceleration`], scaled by the string's axial mass M_s = e_uᵀ M e_u so that the
//!   row weighs like a force.
//!
//! The Jacobian is exact except for the nonlinear (gyroscopic) inertia's share of T_top, which the
//! autodriller's torque limit sees (it is of second order in the lateral rotations): Newton then
//! converges linearly on that term, to the same solution.

use super::contact::FRICTION_DOFS;
use super::{Dynamics, Effects, SimulationError};
use crate::fem::Dof;
use crate::integrate::{ImplicitSystem, JacobianCoefficients};
use crate::model::{Autodriller, OperatingPoint, TopDrive, autodriller_acceleration};
use crate::rom::ReducedModel;
use nalgebra::{DMatrix, DVector};

/// [`Dynamics`] with the block's position as unknown n + 1.
pub struct FreeTop<'m> {
    pub dynamics: Dynamics<'m>,
    law: TopDrive,
    /// The feed set-point V0, m/s (the autodriller's).
    v0: f64,
    /// The hook load's WOB set-point W, N.
    wob: f64,
    /// (q, q̇, q̈) of the string: the first n unknowns.
    part: [DVector<f64>; 3],
    residual: DVector<f64>,
    jacobian: DMatrix<f64>,
    /// ∂F_top, ∂T_top over the string's unknowns and ∂r_q/∂s (the Jacobian's last row and column
    /// before the top law combines them).
    force_row: DVector<f64>,
    torque_row: DVector<f64>,
    column: DVector<f64>,
    /// The autodriller's derivatives (∂/∂ṡ, ∂/∂W, ∂/∂T) at the last residual.
    command_slope: [f64; 3],
    /// Which of the autodriller's laws acted at the last residual and at the last Jacobian.
    branch: (u8, u8),
}

impl<'m> FreeTop<'m> {
    /// The string of `dynamics` under `law` (not [`TopDrive::Feed`]) with the set-points of
    /// `dynamics`' operating point (the autodriller's V0, the hook load's W).
    pub fn new(dynamics: Dynamics<'m>, law: TopDrive) -> Self {
        debug_assert!(law.is_free());
        // A power limit is the torque limit it sets at the run's Ω.
        let op = dynamics.op();
        let law = law.at_speed(op.omega);
        let n = dynamics.model.size();
        FreeTop {
            dynamics,
            law,
            v0: op.v0,
            wob: op.wob,
            part: std::array::from_fn(|_| DVector::zeros(n)),
            residual: DVector::zeros(n),
            jacobian: DMatrix::zeros(n, n),
            force_row: DVector::zeros(n),
            torque_row: DVector::zeros(n),
            column: DVector::zeros(n),
            command_slope: [0.0; 3],
            branch: (0, u8::MAX),
        }
    }

    /// The string's axial mass M_s = e_uᵀ M e_u, kg (the scale of the autodriller's row).
    fn axial_mass(&self) -> f64 {
        self.dynamics.model.rigid_self_mass[0]
    }

    /// Copies the string's part of (q, q̇, q̈) and sets the block's velocity and acceleration.
    fn split(&mut self, q: &DVector<f64>, v: &DVector<f64>, a: &DVector<f64>) {
        let n = self.part[0].len();
        for (p, x) in self.part.iter_mut().zip([q, v, a]) {
            p.as_mut_slice().copy_from_slice(&x.as_slice()[..n]);
        }
        self.dynamics.set_rigid_axial(v[n], a[n]);
        self.dynamics.set_block_position(q[n]);
    }

    /// The top law's residual from the top loads, and the autodriller's slopes.
    fn top_residual(&mut self, speed: f64, accel: f64, loads: [f64; 2]) -> f64 {
        match self.law {
            TopDrive::Feed => unreachable!("FreeTop is built for the other tops"),
            TopDrive::HookLoad => loads[0] - self.wob,
            TopDrive::Autodriller(ad) => {
                let (command, slope) = self.command(&ad, speed, loads);
                self.command_slope = slope;
                self.axial_mass() * (accel - command)
            }
        }
    }

    fn command(&mut self, ad: &Autodriller, speed: f64, loads: [f64; 2]) -> (f64, [f64; 3]) {
        let (command, slope) = autodriller_acceleration(ad, self.v0, speed, loads[0], loads[1]);
        self.branch.0 = slope.iter().position(|&d| d != 0.0).unwrap_or(0) as u8;
        (command, slope)
    }

    /// [`Dynamics::observe_step`] of the accepted state (q, q̇, q̈) (n + 1 each), with the block's
    /// position and speed.
    pub fn observe_step(
        &mut self,
        q: &DVector<f64>,
        v: &DVector<f64>,
        a: &DVector<f64>,
    ) -> super::Observation {
        self.split(q, v, a);
        let [pq, pv, pa] = &self.part;
        let mut obs = self.dynamics.observe_step(pq, pv, pa);
        obs.block_position = q[pq.len()];
        obs
    }

    /// The top loads [F_top, T_top] at the last residual's state.
    pub fn top_loads(&self) -> [f64; 2] {
        self.dynamics.top_loads(&self.part[1], &self.part[2])
    }

    /// ∂F_top, ∂T_top (rows) and ∂r_q/∂(s-unknown) (column), each as ca ∂/∂ẍ + cv ∂/∂ẋ + cq ∂/∂x,
    /// and the derivatives of (F_top, T_top) with respect to the block's unknown.
    fn top_tangent(&mut self, c: JacobianCoefficients) -> [f64; 2] {
        let sys = &self.dynamics;
        let m = sys.model;
        let damp = if sys.damping_on() { 1.0 } else { 0.0 };
        let (force_row, torque_row, column) =
            (&mut self.force_row, &mut self.torque_row, &mut self.column);
        // Mass and damping: e_uᵀ M Φ = (Φᵀ M e_u)ᵀ, and C symmetric.
        for (row, k) in [(&mut *force_row, 0), (&mut *torque_row, 1)] {
            row.as_mut_slice().fill(0.0);
            row.axpy(c.ca, &m.rigid_mass[k], 0.0);
            row.axpy(c.cv * damp, &m.rigid_damping[k], 1.0);
        }
        column.copy_from(force_row);
        // e_θᵀ M e_u = e_θᵀ C e_u = 0: the spin does not see the translation's inertia.
        let mut d_top = [
            c.ca * m.rigid_self_mass[0] + c.cv * damp * m.rigid_self_damping[0],
            0.0,
        ];
        let phi = &m.sparse;
        let add = |out: &mut DVector<f64>, w: f64, dof: usize| {
            if w != 0.0 {
                let (cols, vals) = phi.dof(dof);
                for (&j, &x) in cols.iter().zip(vals) {
                    out[j] += w * x;
                }
            }
        };
        // Wall friction (force F on the string; the residual holds −F): FRICTION_DOFS = (u, v,
        // w, θx), coupling_stiffness over (v, w), coupling_damping over all four.
        for (node, k) in sys.touching_with_tangents() {
            if !k.coupled {
                continue;
            }
            for (a, dof_a) in FRICTION_DOFS.iter().enumerate() {
                // ∂r_q/∂ṡ: every node's axial velocity moves with ṡ.
                add(column, -c.cv * k.coupling_damping[a][0], dof_a.at(node));
            }
            for (row, a, d) in [(&mut *force_row, 0, 0), (&mut *torque_row, 3, 1)] {
                for (b, dof_b) in FRICTION_DOFS.iter().enumerate() {
                    let stiffness = match b {
                        1 | 2 => k.coupling_stiffness[a][b - 1],
                        _ => 0.0,
                    };
                    add(
                        row,
                        -(c.cq * stiffness + c.cv * k.coupling_damping[a][b]),
                        dof_b.at(node),
                    );
                }
                d_top[d] -= c.cv * k.coupling_damping[a][0];
            }
        }
        // The bit.
        let bit = sys.bit;
        let node = m.elements();
        let (iu, it) = (Dof::U.at(node), Dof::ThetaX.at(node));
        add(column, -c.cv * bit.dforce_dvel, iu);
        add(column, -c.cv * bit.dtorque_dvel, it);
        add(force_row, -c.cv * bit.dforce_dvel, iu);
        add(force_row, -c.cv * bit.dforce_dspin, it);
        add(torque_row, -c.cv * bit.dtorque_dvel, iu);
        add(torque_row, -c.cv * bit.dtorque_dspin, it);
        d_top[0] -= c.cv * bit.dforce_dvel;
        d_top[1] -= c.cv * bit.dtorque_dvel;
        // A depth-of-cut law: the depth moves with the bit's position (s + Φq at the bit) and
        // angle, ∂(F, T)/∂(u, θ) = ∂(F, T)/∂d · (∂d/∂u, ∂d/∂θ).
        let cut = sys.cut();
        if bit.dforce_ddepth != 0.0 || bit.dtorque_ddepth != 0.0 {
            let (wf, wt) = (
                -c.cq * bit.dforce_ddepth * cut.d_position,
                -c.cq * bit.dtorque_ddepth * cut.d_position,
            );
            add(column, wf, iu);
            add(column, wt, it);
            add(force_row, wf, iu);
            add(torque_row, wt, iu);
            add(force_row, -c.cq * bit.dforce_ddepth * cut.d_angle, it);
            add(torque_row, -c.cq * bit.dtorque_ddepth * cut.d_angle, it);
            d_top[0] += wf;
            d_top[1] += wt;
        }
        d_top
    }
}

impl ImplicitSystem for FreeTop<'_> {
    fn size(&self) -> usize {
        self.part[0].len() + 1
    }

    fn begin_attempt(&mut self, qp: &DVector<f64>, vp: &DVector<f64>, cq: f64, cv: f64) {
        let n = self.part[0].len();
        self.part[0]
            .as_mut_slice()
            .copy_from_slice(&qp.as_slice()[..n]);
        self.part[1]
            .as_mut_slice()
            .copy_from_slice(&vp.as_slice()[..n]);
        self.dynamics.set_rigid_axial(vp[n], 0.0);
        let [q, v, _] = &self.part;
        self.dynamics.begin_attempt(q, v, cq, cv);
    }

    fn jacobian_reusable(&self) -> bool {
        self.dynamics.jacobian_reusable() && self.branch.0 == self.branch.1
    }

    fn residual(
        &mut self,
        t: f64,
        q: &DVector<f64>,
        v: &DVector<f64>,
        a: &DVector<f64>,
        out: &mut DVector<f64>,
    ) {
        let n = self.part[0].len();
        self.split(q, v, a);
        let [pq, pv, pa] = &self.part;
        self.dynamics.residual(t, pq, pv, pa, &mut self.residual);
        out.as_mut_slice()[..n].copy_from_slice(self.residual.as_slice());
        let loads = self.top_loads();
        out[n] = self.top_residual(v[n], a[n], loads);
    }

    fn jacobian(
        &mut self,
        t: f64,
        q: &DVector<f64>,
        v: &DVector<f64>,
        a: &DVector<f64>,
        c: JacobianCoefficients,
        refresh: bool,
        out: &mut DMatrix<f64>,
    ) {
        let n = self.part[0].len();
        self.split(q, v, a);
        let [pq, pv, pa] = &self.part;
        self.dynamics
            .jacobian(t, pq, pv, pa, c, refresh, &mut self.jacobian);
        self.branch.1 = self.branch.0;
        out.view_mut((0, 0), (n, n)).copy_from(&self.jacobian);
        let d_top = self.top_tangent(c);
        for i in 0..n {
            out[(i, n)] = self.column[i];
        }
        match self.law {
            TopDrive::Feed => unreachable!("FreeTop is built for the other tops"),
            TopDrive::HookLoad => {
                for j in 0..n {
                    out[(n, j)] = self.force_row[j];
                }
                out[(n, n)] = d_top[0];
            }
            TopDrive::Autodriller(_) => {
                let ms = self.axial_mass();
                let [d_speed, d_wob, d_torque] = self.command_slope;
                for j in 0..n {
                    out[(n, j)] = -ms * (d_wob * self.force_row[j] + d_torque * self.torque_row[j]);
                }
                out[(n, n)] = ms * (c.ca - c.cv * d_speed - d_wob * d_top[0] - d_torque * d_top[1]);
            }
        }
    }
}

/// The pre-loaded start of a free top (MODEL.md §4's pre-loaded start, §11.8): the steady
/// drilling state under the imposed feed V ([`super::preloaded_equilibrium`]) at the block speed
/// V where the top law holds in a steady state: F_top(V) = W for a hook load; for the
/// autodriller V0 when both limits hold there, else the V where the first limit binds
/// (max(F_top/W_lim, T_top/T_lim) = 1). F_top and T_top grow with V (the bit cuts deeper, the
/// drag grows), so V is bracketed and found by the Illinois variant of regula falsi, started from
/// the soft-string estimate ([`crate::model::SoftString`]). Returns the string's q, V (m/s) and the
/// Newton iterations spent in all.
///
/// Errors: those of [`super::preloaded_equilibrium`], [`SimulationError::NoHookLoad`] for a hook
/// load without a positive set-point, and [`SimulationError::NoSteadyDrilling`]
/// when no feed between 0 and the admissible 1000 m/h satisfies the law (a hook load above what the
/// bit law can take, a torque limit below the off-bottom torque).
pub fn free_top_start(
    model: &ReducedModel,
    op: OperatingPoint,
    effects: Effects,
) -> Result<(DVector<f64>, f64, usize), SimulationError> {
    let string = &model.string;
    let top = string.top.at_speed(op.omega);
    if matches!(top, TopDrive::HookLoad) && !(op.wob > 0.0 && op.wob.is_finite()) {
        return Err(SimulationError::NoHookLoad { wob: op.wob });
    }
    // h(F, T) − 1: negative below the law's load, zero on it.
    let excess = |loads: [f64; 2]| -> f64 {
        match top {
            TopDrive::HookLoad => loads[0] / op.wob - 1.0,
            TopDrive::Autodriller(ad) => {
                let torque = ad.torque_limit.map_or(f64::NEG_INFINITY, |l| loads[1] / l);
                (loads[0] / ad.wob_limit).max(torque) - 1.0
            }
            TopDrive::Feed => unreachable!("a free top"),
        }
    };
    let mut iterations = 0;
    let mut at = |v: f64| -> Result<(DVector<f64>, f64), SimulationError> {
        let op_v = OperatingPoint { v0: v, ..op };
        let (q, its) = super::preloaded_equilibrium(model, op_v, effects)?;
        iterations += its;
        let mut sys = Dynamics::new(model, op_v, effects);
        let rest = DVector::zeros(model.size());
        sys.observe(&q, &rest, &rest);
        Ok((q, excess(sys.top_loads(&rest, &rest))))
    };
    let ceiling = crate::units::from_m_per_h(1000.0);
    let soft = |v: f64| {
        let s = crate::model::SoftString::steady(string, OperatingPoint { v0: v, ..op });
        excess([s.top_force, s.top_torque])
    };
    // The soft string's root, by bisection (cheap), as the first guess.
    let hi_limit = match top {
        TopDrive::Autodriller(_) => op.v0,
        _ => ceiling,
    };
    let guess = {
        let (mut lo, mut hi) = (0.0, hi_limit);
        if soft(hi) <= 0.0 {
            hi
        } else {
            for _ in 0..60 {
                let mid = 0.5 * (lo + hi);
                if soft(mid) > 0.0 { hi = mid } else { lo = mid }
            }
            0.5 * (lo + hi)
        }
    };
    let (q, h) = at(guess)?;
    if matches!(top, TopDrive::Autodriller(_)) && guess == op.v0 && h <= 0.0 {
        return Ok((q, op.v0, iterations));
    }
    // Bracket the root on the full model, stepping out from the guess.
    let mut best = (guess, q, h);
    let (mut lo, mut hi) = if h > 0.0 {
        (None, Some((guess, h)))
    } else {
        (Some((guess, h)), None)
    };
    let mut step = 0.05 * guess.max(crate::units::from_m_per_h(0.1));
    while lo.is_none() || hi.is_none() {
        let v = match (lo, hi) {
            (None, Some((v, _))) => (v - step).max(0.0),
            (Some((v, _)), None) => (v + step).min(hi_limit),
            _ => unreachable!(),
        };
        let (q, h) = at(v)?;
        if h.abs() < best.2.abs() {
            best = (v, q, h);
        }
        if h > 0.0 {
            if v == 0.0 {
                return Err(no_steady(top, "even off bottom (no feed)", h));
            }
            hi = Some((v, h));
        } else {
            if v >= hi_limit {
                if matches!(top, TopDrive::Autodriller(_)) {
                    return Ok((best.1, v, iterations));
                }
                return Err(no_steady(top, "at the admissible 1000 m/h", h));
            }
            lo = Some((v, h));
        }
        step *= 2.0;
    }
    let (Some(mut a), Some(mut b)) = (lo, hi) else {
        unreachable!("bracketed")
    };
    // Illinois: regula falsi that halves the stale end's value.
    let mut side = 0;
    for _ in 0..40 {
        if best.2.abs() < START_TOLERANCE || (b.0 - a.0) < 1e-9 * b.0.max(1e-12) {
            break;
        }
        let v = (a.0 * b.1 - b.0 * a.1) / (b.1 - a.1);
        let (q, h) = at(v)?;
        if h.abs() < best.2.abs() {
            best = (v, q, h);
        }
        if h > 0.0 {
            b = (v, h);
            if side == 1 {
                a.1 *= 0.5;
            }
            side = 1;
        } else {
            a = (v, h);
            if side == -1 {
                b.1 *= 0.5;
            }
            side = -1;
        }
    }
    Ok((best.1, best.0, iterations))
}

/// How close to its set-point or limit the start puts the top load (relative).
pub const START_TOLERANCE: f64 = 1e-6;

fn no_steady(top: TopDrive, at: &'static str, excess: f64) -> SimulationError {
    SimulationError::NoSteadyDrilling {
        top: top.name(),
        at,
        load_ratio: excess + 1.0,
    }
}
