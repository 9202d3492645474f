//! Wall contact and friction at a node (MODEL.md §5, Eqs. (2), (3), (13)): the geometry, the
//! same for every wall law.
//!
//! With r = √(v² + w²), outward normal n = (v, w)/r, indentation δ = r − gap and its rate
//! δ̇ = n · (v̇, ẇ), for δ > 0 the wall pushes the node back with the law's normal force
//! F(δ, δ̇) ([`WallContactLaw::normal`]; the seed's F_FS = −k₁δ − k₂δ³ − c_FS|δ|³δ̇), clamped to
//! F ≤ 0 (the wall never pulls) and applied along n; the law's friction torque
//! ([`WallContactLaw::friction_torque`]; the seed's T_FS = −μ_FS |F| R_bh tanh(θ̇x/ε)) acts on θx.

use crate::model::{WallContactLaw, WallFriction};

/// Where the wall is for a node: the radial gap R_bh − R_ext, the borehole radius R_bh (the
/// paper's friction lever) and the pipe's outer radius R_ext (the contact point's radius), m;
/// and the share of the law's friction coefficient that acts (1 in a run; the pre-loaded start
/// ramps it from 0 to 1, see [`super::preloaded_equilibrium`]); and the factor on the law's
/// force at the node, [`crate::model::WallStiffnessPer::factor`] (1 per node; the node's
/// tributary length in m when the law is per metre of string).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WallGeometry {
    pub gap: f64,
    pub borehole_radius: f64,
    pub outer_radius: f64,
    pub friction_scale: f64,
    pub law_factor: f64,
}

impl WallGeometry {
    /// The geometry of a drillstring's (one) section, with a law factor of 1 (set it per node
    /// with [`Self::at_node`]).
    pub fn of(string: &crate::model::Drillstring) -> Self {
        WallGeometry {
            gap: string.gap(),
            borehole_radius: string.borehole_radius,
            outer_radius: string.pipe.outer_radius,
            friction_scale: 1.0,
            law_factor: 1.0,
        }
    }

    /// The geometry of every node of `layout` (a mesh of `string`): the node's outer radius
    /// ([`crate::fem::ElementLayout::node_outer_radius`]: the larger pipe at a section boundary),
    /// its gap to the wall and the wall law's factor of its tributary length
    /// ([`crate::fem::ElementLayout::wall_factors`]). For a string of one section every node has
    /// [`Self::of`]'s gap and radii.
    pub fn per_node(
        string: &crate::model::Drillstring,
        layout: &crate::fem::ElementLayout,
    ) -> Vec<Self> {
        let factors = layout.wall_factors(string.wall_stiffness_per);
        let gaps = layout.node_gaps(string.borehole_radius);
        (factors.iter().zip(gaps).enumerate())
            .map(|(node, (&law_factor, gap))| WallGeometry {
                gap,
                outer_radius: layout.node_outer_radius(node),
                law_factor,
                ..WallGeometry::of(string)
            })
            .collect()
    }

    /// This geometry with the law factor `law_factor` of a node.
    #[inline]
    pub fn at_node(self, law_factor: f64) -> Self {
        WallGeometry { law_factor, ..self }
    }
}

/// The motion of a node: lateral displacement (v, w) (m) and velocity (v̇, ẇ) (m/s), absolute
/// axial velocity u̇ (m/s) and spin rate θ̇x (rad/s), rigid motion included.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct NodeMotion {
    pub position: [f64; 2],
    pub velocity: [f64; 2],
    pub axial_velocity: f64,
    pub spin: f64,
}

/// The node DOFs the friction couples, in this order: u, v, w, θx.
pub const FRICTION_DOFS: [crate::fem::Dof; 4] = [
    crate::fem::Dof::U,
    crate::fem::Dof::V,
    crate::fem::Dof::W,
    crate::fem::Dof::ThetaX,
];

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
    /// Force on (v, w): the normal force and the circumferential friction, N.
    pub force: [f64; 2],
    /// Friction force on u (axial drag), N.
    pub axial_force: f64,
    /// Friction torque on θx, N·m.
    pub torque: f64,
    /// ∂force/∂(v, w), N/m (row i = force component i).
    pub stiffness: [[f64; 2]; 2],
    /// ∂force/∂(v̇, ẇ), N·s/m.
    pub damping: [[f64; 2]; 2],
    /// The friction's tangent beyond the lateral blocks above (those hold its (v, w) × (v, w)
    /// part): ∂(f_u, f_v, f_w, f_θ)/∂(v, w) in `coupling_stiffness` (rows v, w zero) and
    /// ∂(…)/∂(u̇, v̇, ẇ, θ̇x) in `coupling_damping` (the (v, w) × (v, w) block zero), DOFs in the
    /// order of [`FRICTION_DOFS`]. All zero for the paper's friction, whose tangent is left out.
    pub coupling_stiffness: [[f64; 2]; 4],
    pub coupling_damping: [[f64; 4]; 4],
    /// Whether the coupling blocks hold anything.
    pub coupled: bool,
    /// Power dissipated by contact damping and friction, W (≥ 0).
    pub dissipation: f64,
    /// Elastic energy stored in the wall (the law's; the seed's ½k₁δ² + ¼k₂δ⁴), J.
    pub elastic_energy: f64,
}

/// Forces at a node with motion `m` under wall law `law`, friction `friction` and geometry `g`,
/// with their tangent (`stiffness`, `damping` and the friction's coupling blocks).
pub fn wall_contact(
    law: &dyn WallContactLaw,
    friction: WallFriction,
    g: WallGeometry,
    m: NodeMotion,
) -> NodeContact {
    contact::<true>(law, friction, g, m)
}

/// The forces of [`wall_contact`] without their tangent (its tangent fields are zero; every
/// other field is the same, bit for bit): a residual needs the forces at every evaluation, the
/// Newton matrix the tangent only when it is built (the friction's tangent was most of the cost
/// of [`wall_contact`], 15 % of a seed run).
pub fn wall_contact_force(
    law: &dyn WallContactLaw,
    friction: WallFriction,
    g: WallGeometry,
    m: NodeMotion,
) -> NodeContact {
    contact::<false>(law, friction, g, m)
}

fn contact<const TANGENT: bool>(
    law: &dyn WallContactLaw,
    friction: WallFriction,
    g: WallGeometry,
    m: NodeMotion,
) -> NodeContact {
    let (pos, vel) = (m.position, m.velocity);
    // √(v² + w²) rather than hypot: displacements of cm size cannot overflow, and hypot's
    // extra care was 2 % of a seed run.
    let r = (pos[0] * pos[0] + pos[1] * pos[1]).sqrt();
    let delta = r - g.gap;
    if delta <= 0.0 || r == 0.0 {
        return NodeContact {
            indentation: delta,
            ..Default::default()
        };
    }
    let n = [pos[0] / r, pos[1] / r];
    let delta_dot = n[0] * vel[0] + n[1] * vel[1];
    let f = law.normal(delta, delta_dot).scaled(g.law_factor);
    let raw = f.elastic + f.dissipative;
    let clamped = raw > 0.0;
    let normal = raw.min(0.0);
    let force = [normal * n[0], normal * n[1]];
    let mut stiffness = [[0.0; 2]; 2];
    let mut damping = [[0.0; 2]; 2];
    // ∂F/∂(v, w) and ∂F/∂(v̇, ẇ) of the (clamped) normal force.
    let (mut df_dp, mut df_dv) = ([0.0; 2], [0.0; 2]);
    if TANGENT && !clamped {
        // ∂F/∂δ, ∂F/∂δ̇ of the normal force; ∂δ/∂x = n; ∂δ̇/∂x = (vel − δ̇ n)/r; ∂n/∂x = (I − n nᵀ)/r.
        let (df_ddelta, df_ddot) = (f.dforce_dindentation, f.dforce_drate);
        for j in 0..2 {
            let ddot_dx = (vel[j] - delta_dot * n[j]) / r;
            df_dp[j] = df_ddelta * n[j] + df_ddot * ddot_dx;
            df_dv[j] = df_ddot * n[j];
        }
        for i in 0..2 {
            for j in 0..2 {
                let proj = (if i == j { 1.0 } else { 0.0 } - n[i] * n[j]) / r;
                stiffness[i][j] = n[i] * df_dp[j] + normal * proj;
                damping[i][j] = n[i] * df_dv[j];
            }
        }
    }
    let damping_power = if clamped {
        0.0
    } else {
        -f.dissipative * delta_dot
    };
    let mut c = NodeContact {
        active: true,
        indentation: delta,
        approach_speed: delta_dot,
        normal,
        force,
        stiffness,
        damping,
        dissipation: damping_power,
        elastic_energy: f.energy,
        ..Default::default()
    };
    match friction {
        WallFriction::Paper => {
            c.torque = g.friction_scale * law.friction_torque(normal, g.borehole_radius, m.spin);
            c.dissipation -= c.torque * m.spin;
        }
        WallFriction::Coulomb { slip_smoothing } => {
            let mu = g.friction_scale * law.friction();
            if mu > 0.0 && normal < 0.0 {
                let k = Kinematics {
                    n,
                    r,
                    velocity: vel,
                    axial_velocity: m.axial_velocity,
                    spin: m.spin,
                    outer_radius: g.outer_radius,
                };
                coulomb_slip::<TANGENT>(&mut c, mu, slip_smoothing, &k, df_dp, df_dv);
            }
        }
    }
    c
}

/// What the Coulomb friction of a node depends on besides the normal force.
struct Kinematics {
    /// Outward normal (v, w)/r and radius r.
    n: [f64; 2],
    r: f64,
    velocity: [f64; 2],
    axial_velocity: f64,
    spin: f64,
    outer_radius: f64,
}

/// Adds the Coulomb friction on the slip of the contact point (MODEL.md §11.2; the module doc
/// of [`crate::model::wall`]'s friction) to `c`, whose normal force is already set:
///
///   s = (s_a, s_t) = (u̇, t·(v̇, ẇ) + R_ext θ̇x),  t = (−n_w, n_v),  S = √(s_a² + s_t² + ε²),
///   (f_u, f_v, f_w, f_θ) = −μN Dᵀ s/S,  D = [[1, 0, 0, 0], [0, t_v, t_w, R_ext]] = ∂s/∂(u̇, v̇, ẇ, θ̇x),
///
/// with N = −F ≥ 0, and its exact tangent: ∂f/∂ẋ = −μN Dᵀ G D − (Dᵀ g) ⊗ ∂(μN)/∂ẋ and
/// ∂f/∂(v, w) through N, t and s_t, where g = s/S and G = ∂g/∂s = (I S² − s sᵀ)/S³.
fn coulomb_slip<const TANGENT: bool>(
    c: &mut NodeContact,
    mu: f64,
    eps: f64,
    k: &Kinematics,
    df_dp: [f64; 2],
    df_dv: [f64; 2],
) {
    let Kinematics { n, r, .. } = *k;
    let rext = k.outer_radius;
    let t = [-n[1], n[0]];
    // ∂t_i/∂p_j = J (I − n nᵀ)/r, J the rotation by +90°.
    let dn = |i: usize, j: usize| (if i == j { 1.0 } else { 0.0 } - n[i] * n[j]) / r;
    let dt = [[-dn(1, 0), -dn(1, 1)], [dn(0, 0), dn(0, 1)]];
    let s = [
        k.axial_velocity,
        t[0] * k.velocity[0] + t[1] * k.velocity[1] + rext * k.spin,
    ];
    let s2 = s[0] * s[0] + s[1] * s[1];
    let big_s = (s2 + eps * eps).sqrt();
    let g = [s[0] / big_s, s[1] / big_s];
    let a = -mu * c.normal;
    // D (2 × 4) in the DOF order u, v, w, θx.
    let d = [[1.0, 0.0, 0.0, 0.0], [0.0, t[0], t[1], rext]];
    let dtg: [f64; 4] = std::array::from_fn(|i| d[0][i] * g[0] + d[1][i] * g[1]);
    let f: [f64; 4] = dtg.map(|x| -a * x);
    c.axial_force = f[0];
    c.force[0] += f[1];
    c.force[1] += f[2];
    c.torque = f[3];
    c.coupled = true;
    c.dissipation += a * s2 / big_s;
    if !TANGENT {
        return;
    }
    let s3 = big_s * big_s * big_s;
    let gm = [
        [(big_s * big_s - s[0] * s[0]) / s3, -s[0] * s[1] / s3],
        [-s[0] * s[1] / s3, (big_s * big_s - s[1] * s[1]) / s3],
    ];
    // ∂(μN)/∂ẋ and ∂(μN)/∂(v, w): N = −F.
    let da_dv = [0.0, -mu * df_dv[0], -mu * df_dv[1], 0.0];
    let da_dp = [-mu * df_dp[0], -mu * df_dp[1]];
    // Dᵀ G (4 × 2).
    let dtgm: [[f64; 2]; 4] =
        std::array::from_fn(|i| std::array::from_fn(|b| d[0][i] * gm[0][b] + d[1][i] * gm[1][b]));
    let mut cd = [[0.0; 4]; 4];
    for (i, row) in cd.iter_mut().enumerate() {
        for (j, x) in row.iter_mut().enumerate() {
            *x = -a * (dtgm[i][0] * d[0][j] + dtgm[i][1] * d[1][j]) - dtg[i] * da_dv[j];
        }
    }
    // ∂s_t/∂p_j = Σ_k v̇_k ∂t_k/∂p_j; ∂D_t/∂p_j = (0, ∂t_v/∂p_j, ∂t_w/∂p_j, 0).
    let dst: [f64; 2] =
        std::array::from_fn(|j| k.velocity[0] * dt[0][j] + k.velocity[1] * dt[1][j]);
    let mut cs = [[0.0; 2]; 4];
    for (i, row) in cs.iter_mut().enumerate() {
        for (j, x) in row.iter_mut().enumerate() {
            let dd = match i {
                1 => dt[0][j],
                2 => dt[1][j],
                _ => 0.0,
            };
            *x = -dtg[i] * da_dp[j] - a * dtgm[i][1] * dst[j] - a * g[1] * dd;
        }
    }
    // The (v, w) × (v, w) blocks join the normal force's; the rest stays in the coupling.
    for i in 0..2 {
        for j in 0..2 {
            c.stiffness[i][j] += cs[i + 1][j];
            c.damping[i][j] += cd[i + 1][j + 1];
            cs[i + 1][j] = 0.0;
            cd[i + 1][j + 1] = 0.0;
        }
    }
    c.coupling_stiffness = cs;
    c.coupling_damping = cd;
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::wall::Cubic;

    const SEED_WALL: WallGeometry = WallGeometry {
        gap: 0.01,
        borehole_radius: 0.07,
        outer_radius: 0.06,
        friction_scale: 1.0,
        law_factor: 1.0,
    };

    /// The paper's friction (torque only, lever R_bh) at a node.
    fn paper(law: &Cubic, pos: [f64; 2], vel: [f64; 2], spin: f64) -> NodeContact {
        let m = NodeMotion {
            position: pos,
            velocity: vel,
            axial_velocity: 0.0,
            spin,
        };
        wall_contact(law, WallFriction::Paper, SEED_WALL, m)
    }

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
        let c = paper(&law(), [0.006, -0.0079], [0.0, 0.0], 6.0);
        assert!(!c.active && c.force == [0.0, 0.0] && c.torque == 0.0);
        let c = paper(&law(), [0.0, -0.0101], [0.0, 0.0], 6.0);
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
        let back = paper(&law(), [0.0, -0.0101], [0.0, 0.0], -6.0);
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
        let c = paper(&sticky, [0.0101, 0.0], [-1e4, 0.0], 0.0);
        assert!(c.active);
        assert_eq!(c.normal, 0.0);
        assert_eq!(c.stiffness, [[0.0; 2]; 2]);
    }

    #[test]
    fn tangents_match_finite_differences() {
        let (pos, vel) = ([0.0071, -0.0072], [0.3, -0.2]);
        let c = paper(&law(), pos, vel, 2.0);
        for j in 0..2 {
            let h = 1e-10;
            let (mut p, mut m) = (pos, pos);
            p[j] += h;
            m[j] -= h;
            let (fp, fm) = (paper(&law(), p, vel, 2.0), paper(&law(), m, vel, 2.0));
            let (mut vp, mut vm) = (vel, vel);
            vp[j] += 1e-4;
            vm[j] -= 1e-4;
            let (gp, gm) = (paper(&law(), pos, vp, 2.0), paper(&law(), pos, vm, 2.0));
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

    fn coulomb(eps: f64) -> WallFriction {
        WallFriction::Coulomb {
            slip_smoothing: eps,
        }
    }

    /// (f_u, f_v, f_w, f_θ) of a node in contact.
    fn forces(c: &NodeContact) -> [f64; 4] {
        [c.axial_force, c.force[0], c.force[1], c.torque]
    }

    /// A pipe pressed on the low side that turns and slides: the friction is μN along the slip
    /// (V, Ω R_ext), split between drag and torque in that ratio (Johancsik et al. 1984), the
    /// torque has the lever R_ext, the lateral force points against the contact point's spin
    /// velocity (towards the side the pipe climbs), and the power is μN|s| (|s| ≫ ε).
    #[test]
    fn coulomb_friction_acts_along_the_slip_of_the_contact_point() {
        let (v, om) = (1.0 / 720.0, 2.0 * std::f64::consts::PI);
        let m = NodeMotion {
            position: [0.0, -0.0101],
            velocity: [0.0, 0.0],
            axial_velocity: v,
            spin: om,
        };
        let c = wall_contact(&law(), coulomb(1e-4), SEED_WALL, m);
        let nf = c.normal.abs();
        let slip = v.hypot(om * 0.06);
        let mu_n = 0.3 * nf;
        // Magnitudes within the regularisation's ε²/(2|s|²) (here 4e-8 of the axial part).
        let close = |a: f64, b: f64| (a - b).abs() < 1e-6 * b.abs();
        assert!(close(c.axial_force, -mu_n * v / slip), "{c:?}");
        assert!(close(c.torque, -mu_n * 0.06 * om * 0.06 / slip), "{c:?}");
        // On the low side n = (0, −1), t = (1, 0): the spin moves the contact point along +v, so
        // the friction on the pipe is along −v; the normal force pushes up (+w).
        assert!(close(c.force[0], -mu_n * om * 0.06 / slip), "{c:?}");
        assert!(close(c.force[1], nf), "{c:?}");
        // Dissipation: the wall's damping at rest is zero; friction μN|s|.
        assert!(close(c.dissipation, mu_n * slip), "{c:?}");
        // A pipe rolling without slip on the wall (backward whirl: t·ṗ = −R_ext θ̇x) only drags.
        let rolling = NodeMotion {
            velocity: [-0.06 * om, 0.0],
            ..m
        };
        let c = wall_contact(&law(), coulomb(1e-4), SEED_WALL, rolling);
        assert!(c.torque.abs() < 1e-9 * mu_n && close(c.axial_force, -mu_n * v / v.hypot(1e-4)));
        // No friction without it or at rest; the paper's friction is a torque with lever R_bh.
        let dry = Cubic {
            friction: 0.0,
            ..law()
        };
        assert_eq!(wall_contact(&dry, coulomb(1e-4), SEED_WALL, m).torque, 0.0);
        let p = wall_contact(&law(), WallFriction::Paper, SEED_WALL, m);
        assert!(
            close(p.torque, -mu_n * 0.07) && p.axial_force == 0.0,
            "{p:?}"
        );
    }

    /// The residual's forces-only contact is the full one without its tangent, bit for bit, for
    /// both friction laws, free, clamped and touching nodes.
    #[test]
    fn forces_without_tangent_are_the_full_forces_bit_for_bit() {
        let sticky = Cubic {
            damping: 1e15,
            ..law()
        };
        let states = [
            ([0.0071, -0.0072], [0.3, -0.2], 0.02, 2.0),
            ([-0.004, -0.0095], [0.01, 0.002], 1e-3, -0.5),
            ([0.0101, 0.0001], [-1e4, 0.05], -2e-4, 1e-3),
            ([0.003, 0.002], [0.1, 0.1], 0.0, 1.0),
        ];
        for (pos, vel, axial, spin) in states {
            let m = NodeMotion {
                position: pos,
                velocity: vel,
                axial_velocity: axial,
                spin,
            };
            for friction in [WallFriction::Paper, coulomb(1e-4)] {
                for wall in [&law() as &dyn WallContactLaw, &sticky] {
                    let full = wall_contact(wall, friction, SEED_WALL, m);
                    let force = wall_contact_force(wall, friction, SEED_WALL, m);
                    let without_tangent = NodeContact {
                        stiffness: [[0.0; 2]; 2],
                        damping: [[0.0; 2]; 2],
                        coupling_stiffness: [[0.0; 2]; 4],
                        coupling_damping: [[0.0; 4]; 4],
                        ..full
                    };
                    assert_eq!(force, without_tangent, "{m:?} {friction:?}");
                }
            }
        }
    }

    /// The tangent of every friction and normal force against central differences, in every
    /// position and velocity it depends on, with the wall's damping on and slip speeds from
    /// near-stick (|s| ~ ε) to sliding.
    #[test]
    fn coulomb_tangents_match_finite_differences() {
        let states = [
            ([0.0071, -0.0072], [0.3, -0.2], 0.02, 2.0),
            ([-0.004, -0.0095], [0.01, 0.002], 1e-3, -0.5),
            ([0.0101, 0.0001], [-0.001, 0.05], -2e-4, 1e-3),
        ];
        for (pos, vel, axial, spin) in states {
            let motion = NodeMotion {
                position: pos,
                velocity: vel,
                axial_velocity: axial,
                spin,
            };
            let eps = 1e-3;
            let at = |m: NodeMotion| wall_contact(&law(), coulomb(eps), SEED_WALL, m);
            let c = at(motion);
            assert!(c.active && c.coupled);
            // Full 4 × 4 velocity and 4 × 2 position tangents from the stored blocks.
            let kfull = |i: usize, j: usize| match i {
                1 | 2 => c.stiffness[i - 1][j],
                _ => c.coupling_stiffness[i][j],
            };
            let cfull = |i: usize, j: usize| match (i, j) {
                (1 | 2, 1 | 2) => c.damping[i - 1][j - 1],
                _ => c.coupling_damping[i][j],
            };
            for j in 0..4 {
                let h = 1e-7;
                let shift = |sign: f64| {
                    let mut m = motion;
                    match j {
                        0 => m.axial_velocity += sign * h,
                        1 | 2 => m.velocity[j - 1] += sign * h,
                        _ => m.spin += sign * h / 0.06,
                    }
                    forces(&at(m))
                };
                let (fp, fm) = (shift(1.0), shift(-1.0));
                let scale = if j == 3 { 0.06 } else { 1.0 };
                for i in 0..4 {
                    let fd = (fp[i] - fm[i]) / (2.0 * h) * scale;
                    let exact = cfull(i, j);
                    assert!(
                        (fd - exact).abs() < 1e-5 * exact.abs().max(1e3),
                        "∂f{i}/∂ẋ{j} at {motion:?}: {fd} vs {exact}"
                    );
                }
            }
            for j in 0..2 {
                let h = 1e-11;
                let shift = |sign: f64| {
                    let mut m = motion;
                    m.position[j] += sign * h;
                    forces(&at(m))
                };
                let (fp, fm) = (shift(1.0), shift(-1.0));
                for i in 0..4 {
                    let fd = (fp[i] - fm[i]) / (2.0 * h);
                    let exact = kfull(i, j);
                    assert!(
                        (fd - exact).abs() < 1e-5 * exact.abs().max(1e5),
                        "∂f{i}/∂p{j} at {motion:?}: {fd} vs {exact}"
                    );
                }
            }
            assert!(c.dissipation >= 0.0);
        }
    }
}
