//! Wall contact and friction at a node (MODEL.md §5, Eqs. (2), (3), (13)): the geometry, the
//! same for every wall law.
//!
//! With r = √(v² + w²), outward normal n = (v, w)/r, indentation δ = r − gap and its rate
//! δ̇ = n · (v̇, ẇ), for δ > 0 the wall pushes the node back with the law's normal force
//! F(δ, δ̇) ([`WallContactLaw::normal`]; the seed's F_FS = −k₁δ − k₂δ³ − c_FS|δ|³δ̇), clamped to
//! F ≤ 0 (the wall never pulls) and applied along n; the law's friction torque
//! ([`WallContactLaw::friction_torque`]; the seed's T_FS = −μ_FS |F| R_bh tanh(θ̇x/ε)) acts on θx.

use crate::model::WallContactLaw;

/// Contact state and forces at one node, with derivatives for the Newton tangent.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct NodeContact {
    /// Whether the node touches the wall (δ > 0).
    pub active: bool,
    /// Indentation δ, m (≤ 0 when free).
    pub indentation: f64,
    /// Normal approach speed δ̇ = n · (v̇, ẇ), m/s, positive towards the wall (0 when free).
    pub approach_speed: f64,
    /// Normal force F_FS ≤ 0, N.
    pub normal: f64,
    /// Force on (v, w), N.
    pub force: [f64; 2],
    /// Friction torque on θx, N·m.
    pub torque: f64,
    /// ∂force/∂(v, w), N/m (row i = force component i).
    pub stiffness: [[f64; 2]; 2],
    /// ∂force/∂(v̇, ẇ), N·s/m.
    pub damping: [[f64; 2]; 2],
    /// Power dissipated by contact damping and friction, W (≥ 0).
    pub dissipation: f64,
    /// Elastic energy stored in the wall (the law's; the seed's ½k₁δ² + ¼k₂δ⁴), J.
    pub elastic_energy: f64,
}

/// Forces at a node with lateral displacement (v, w), velocity (v̇, ẇ) and spin rate θ̇x, under
/// wall law `law`, radial gap `gap` and borehole radius `borehole_radius` (m).
pub fn wall_contact(
    law: &dyn WallContactLaw,
    gap: f64,
    borehole_radius: f64,
    pos: [f64; 2],
    vel: [f64; 2],
    spin_rate: f64,
) -> NodeContact {
    // √(v² + w²) rather than hypot: displacements of cm size cannot overflow, and hypot's
    // extra care was 2 % of a seed run.
    let r = (pos[0] * pos[0] + pos[1] * pos[1]).sqrt();
    let delta = r - gap;
    if delta <= 0.0 || r == 0.0 {
        return NodeContact {
            indentation: delta,
            ..Default::default()
        };
    }
    let n = [pos[0] / r, pos[1] / r];
    let delta_dot = n[0] * vel[0] + n[1] * vel[1];
    let f = law.normal(delta, delta_dot);
    let raw = f.elastic + f.dissipative;
    let clamped = raw > 0.0;
    let normal = raw.min(0.0);
    let force = [normal * n[0], normal * n[1]];
    let mut stiffness = [[0.0; 2]; 2];
    let mut damping = [[0.0; 2]; 2];
    if !clamped {
        // ∂F/∂δ, ∂F/∂δ̇ of the normal force; ∂δ/∂x = n; ∂δ̇/∂x = (vel − δ̇ n)/r; ∂n/∂x = (I − n nᵀ)/r.
        let (df_ddelta, df_ddot) = (f.dforce_dindentation, f.dforce_drate);
        for i in 0..2 {
            for j in 0..2 {
                let proj = (if i == j { 1.0 } else { 0.0 } - n[i] * n[j]) / r;
                let ddot_dx = (vel[j] - delta_dot * n[j]) / r;
                stiffness[i][j] = n[i] * (df_ddelta * n[j] + df_ddot * ddot_dx) + normal * proj;
                damping[i][j] = n[i] * df_ddot * n[j];
            }
        }
    }
    let torque = law.friction_torque(normal, borehole_radius, spin_rate);
    let damping_power = if clamped {
        0.0
    } else {
        -f.dissipative * delta_dot
    };
    NodeContact {
        active: true,
        indentation: delta,
        approach_speed: delta_dot,
        normal,
        force,
        torque,
        stiffness,
        damping,
        dissipation: damping_power - torque * spin_rate,
        elastic_energy: f.energy,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::wall::Cubic;

    fn law() -> Cubic {
        Cubic {
            stiffness: 1e10,
            cubic_stiffness: 1e16,
            damping: 1e9,
            friction: 0.3,
            sign_smoothing: 1e-3,
        }
    }

    #[test]
    fn free_node_feels_nothing_and_contact_pushes_back_along_the_radius() {
        let c = wall_contact(&law(), 0.01, 0.07, [0.006, -0.0079], [0.0, 0.0], 6.0);
        assert!(!c.active && c.force == [0.0, 0.0] && c.torque == 0.0);
        let c = wall_contact(&law(), 0.01, 0.07, [0.0, -0.0101], [0.0, 0.0], 6.0);
        let delta: f64 = 1e-4;
        let expected = -(1e10 * delta + 1e16 * delta.powi(3));
        assert!(c.active);
        assert!((c.normal - expected).abs() < 1e-9 * expected.abs());
        assert!(
            c.force[0].abs() < 1e-9 && (c.force[1] + expected).abs() < 1e-6,
            "pushes up: {:?}",
            c.force
        );
        // Friction opposes the spin in both directions, scaled by |F| R_bh μ.
        assert!((c.torque + 0.3 * expected.abs() * 0.07).abs() < 1e-6 * c.torque.abs());
        let back = wall_contact(&law(), 0.01, 0.07, [0.0, -0.0101], [0.0, 0.0], -6.0);
        assert!((back.torque + c.torque).abs() < 1e-9 * c.torque.abs());
    }

    #[test]
    fn the_wall_never_pulls() {
        // Moving away fast: the damping term would make the force attractive; it is clamped at 0.
        let sticky = Cubic {
            damping: 1e15,
            ..law()
        };
        // c|δ|³δ̇ = 1e15 · 1e-12 · 1e4 = 1e7 N > k₁δ + k₂δ³ ≈ 1.01e6 N.
        let c = wall_contact(&sticky, 0.01, 0.07, [0.0101, 0.0], [-1e4, 0.0], 0.0);
        assert!(c.active);
        assert_eq!(c.normal, 0.0);
        assert_eq!(c.stiffness, [[0.0; 2]; 2]);
    }

    #[test]
    fn tangents_match_finite_differences() {
        let (pos, vel) = ([0.0071, -0.0072], [0.3, -0.2]);
        let c = wall_contact(&law(), 0.01, 0.07, pos, vel, 2.0);
        for j in 0..2 {
            let h = 1e-10;
            let (mut p, mut m) = (pos, pos);
            p[j] += h;
            m[j] -= h;
            let (fp, fm) = (
                wall_contact(&law(), 0.01, 0.07, p, vel, 2.0),
                wall_contact(&law(), 0.01, 0.07, m, vel, 2.0),
            );
            let (mut vp, mut vm) = (vel, vel);
            vp[j] += 1e-4;
            vm[j] -= 1e-4;
            let (gp, gm) = (
                wall_contact(&law(), 0.01, 0.07, pos, vp, 2.0),
                wall_contact(&law(), 0.01, 0.07, pos, vm, 2.0),
            );
            for i in 0..2 {
                let fd = (fp.force[i] - fm.force[i]) / (2.0 * h);
                assert!(
                    (fd - c.stiffness[i][j]).abs() < 1e-5 * c.stiffness[i][j].abs().max(1e6),
                    "K[{i}][{j}]: {fd} vs {}",
                    c.stiffness[i][j]
                );
                let fd = (gp.force[i] - gm.force[i]) / 2e-4;
                assert!(
                    (fd - c.damping[i][j]).abs() < 1e-6 * c.damping[i][j].abs().max(1.0),
                    "C[{i}][{j}]: {fd} vs {}",
                    c.damping[i][j]
                );
            }
        }
    }
}
