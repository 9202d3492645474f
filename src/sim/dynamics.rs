//! The reduced drillstring equations as an [`ImplicitSystem`] (MODEL.md §3–§7):
//!
//!   r(q, q̇, q̈) = q̈ + D q̇ + Φᵀ C Q̇_rigid − Φᵀ F_g
//!               + Φᵀ [ f_int(Φq) + f_gyro(Q, Q̇, Q̈) − F_wall(Q, Q̇) − F_bit(Q̇) ] = 0,
//!
//! with Q = Q_rigid(t) + Φq, Q̇_rigid = V0 on every u and Ω on every θx. The internal force is
//! evaluated on the elastic part Φq only: the rigid motion adds no strain, and keeping the large
//! spin angle out of the strain evaluation avoids cancellation. Nonlinear forces are computed on
//! the full mesh and projected (Φᵀ).

use super::contact::wall_contact_force;
use super::contact::{FRICTION_DOFS, NodeMotion, WallGeometry};
use super::contact_tangent::ContactTangent;
use super::{BitLoad, Cut, NodeContact, RockSurface, wall_contact};
use crate::fem::{Dof, ElementVector};
use crate::integrate::{ImplicitSystem, JacobianCoefficients, copy_vector};
use crate::model::OperatingPoint;
use crate::rom::{BlockWork, Operator, ReducedModel};
use nalgebra::{DMatrix, DVector};

/// Newton matrices a gathered wall tangent serves before it is gathered again (see
/// [`Dynamics::jacobian`]'s wall part). A tangent kept while the same nodes touch, however old,
/// let Newton's iterates lift whole groups of nodes off the wall once the seed's stick-slip had
/// developed (its friction's tangent changes with the slip): from 25 s on, two to three times
/// as many Newton matrices as with a fresh tangent. Measured on the seed over 35 s (`drillopt
/// simulate problems/seed_mc2014.toml --duration 35`): 4 uses, 78 991 Newton matrices and 15 808
/// gatherings; 8 uses, 79 496 and 8 850; a fresh tangent for every matrix, about 79 000
/// (the same count as before the wall tangent was kept).
const WALL_TANGENT_USES: usize = 8;

/// Which physical effects are on (all on for a real run; tests switch some off).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Effects {
    pub damping: bool,
    pub gravity: bool,
    pub wall: bool,
    pub bit: bool,
}

impl Effects {
    pub const ALL: Effects = Effects {
        damping: true,
        gravity: true,
        wall: true,
        bit: true,
    };
    pub const NONE: Effects = Effects {
        damping: false,
        gravity: false,
        wall: false,
        bit: false,
    };
}

/// Quantities observed at a state, for the time history and the energy balance.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Observation {
    pub bit: BitLoad,
    /// Bit axial velocity u̇(L) and spin rate θ̇x(L).
    pub bit_velocity: f64,
    pub bit_spin: f64,
    /// Elastic bit displacement and rotation (add the rigid V0 t, Ω t for absolute values).
    pub bit_u_elastic: f64,
    pub bit_theta_elastic: f64,
    pub top_force: f64,
    pub top_torque: f64,
    pub nodes_in_contact: u32,
    pub wall_force_total: f64,
    pub wall_force_max: f64,
    pub max_radial_over_gap: f64,
    pub kinetic_energy: f64,
    pub potential_energy: f64,
    /// Power dissipated (damping, wall damping and friction), W.
    pub dissipation: f64,
    /// Power of the top drive F_top V0 + T_top Ω, W.
    pub power_top: f64,
    /// Power of the rock on the string F_BR u̇ + T_BR θ̇, W.
    pub power_bit: f64,
    /// The block's position s (the top's axial position, u(0, t)), m: V0 t for the imposed feed;
    /// set by the run (the system knows no time).
    pub block_position: f64,
    /// The block's speed ṡ, m/s.
    pub block_speed: f64,
    /// The depth of cut per revolution a depth-of-cut bit law read off the rock surface, m
    /// (≤ 0: the bit above the rock); NaN for a rate law.
    pub depth_of_cut: f64,
}

/// The drillstring system at one operating point, with its work buffers.
pub struct Dynamics<'m> {
    pub model: &'m ReducedModel,
    op: OperatingPoint,
    effects: Effects,
    /// The rigid axial motion's velocity ṡ and acceleration s̈ (V0 and 0 for the imposed feed;
    /// set by [`super::FreeTop`] for the other tops).
    rigid_axial: [f64; 2],
    /// The rigid axial velocity in the attempt base `attempt_full` (see `begin_attempt`).
    attempt_rigid_velocity: f64,
    /// The rigid axial velocity of the `evaluated` state.
    evaluated_rigid_velocity: f64,
    /// The time of the state being evaluated (set by each residual), s.
    time: f64,
    /// The block's position s when it is an unknown (set by [`super::FreeTop`]); `None`: the
    /// imposed feed, s = V0 t.
    block: Option<f64>,
    /// The rigid motion [s, Ω t] of the `evaluated` state.
    evaluated_rigid_position: [f64; 2],
    /// The rock surface of a depth-of-cut bit law (installed after the start: the start is
    /// solved on the law's quasi-static form), and the cut read at the last residual.
    surface: Option<RockSurface>,
    cut: Cut,
    /// The wall's geometry at each node ([`WallGeometry::per_node`]).
    walls: Vec<WallGeometry>,
    q_full: DVector<f64>,
    v_full: DVector<f64>,
    a_full: DVector<f64>,
    f_full: DVector<f64>,
    /// Φq for the tangent refresh (kept apart so that the vectors above always belong together).
    q_tangent: DVector<f64>,
    /// The step attempt announced by the integrator: q = q_p + c_q q̈, q̇ = v_p + c_v q̈ (modal),
    /// with Φq_p and Φq_p + Q̇_rigid on the full mesh, so that a residual expands q̈ only.
    attempt: Option<(f64, f64)>,
    attempt_modal: [DVector<f64>; 2],
    attempt_full: [DVector<f64>; 2],
    /// The wall-contact part of the Jacobian (gathered rows of the touching nodes).
    contact_tangent: ContactTangent,
    /// The wall's tangent on the modal coordinates, −Φᵀ ∂F_wall/∂Q Φ and −Φᵀ ∂F_wall/∂Q̇ Φ
    /// (n × n, N/m and N·s/m in modal units), gathered at the residual of `wall_tangent_at`; kept
    /// while the same nodes touch (see [`Self::jacobian`]).
    wall_tangent: [DMatrix<f64>; 2],
    /// The touching nodes with their contact tangents, while a Newton matrix is built (sized
    /// once, for every node: the time-step loop allocates nothing).
    touching: Vec<(usize, NodeContact)>,
    /// The residual signature at which `wall_tangent` was gathered (`None`: to be gathered).
    wall_tangent_at: Option<(u64, u64, bool)>,
    /// The residual signature of the last Newton matrix whose wall part was added directly
    /// (see [`Self::jacobian`]).
    wall_added_at: Option<(u64, u64, bool)>,
    /// Newton matrices built on `wall_tangent` since it was gathered.
    wall_tangent_uses: usize,
    blocks: BlockWork,
    /// The modal state (q, q̇, q̈) of the full-mesh vectors and forces above, and the element
    /// energies there: strain energy U and nonlinear kinetic energy T_nl, J.
    evaluated: [DVector<f64>; 3],
    element_energies: (f64, f64),
    /// Cached Φᵀ K_t Φ (refreshed on request).
    strain_tangent: DMatrix<f64>,
    /// ∂r/∂q̇ of the linear terms: D + Ω G (D only with damping on).
    damping_gyroscopic: DMatrix<f64>,
    scratch: DMatrix<f64>,
    /// Contact state per node (index = node), from the last residual evaluation.
    pub contacts: Vec<NodeContact>,
    pub bit: BitLoad,
    /// Touching nodes and bit on/off when the Jacobian was last built, and at the last residual.
    jacobian_signature: (u64, u64, bool),
    residual_signature: (u64, u64, bool),
    /// Residual evaluations, strain-tangent refreshes and wall-tangent gatherings so far (cost
    /// accounting).
    pub residual_evaluations: usize,
    pub tangent_refreshes: usize,
    pub wall_tangent_refreshes: usize,
}

impl<'m> Dynamics<'m> {
    pub fn new(model: &'m ReducedModel, op: OperatingPoint, effects: Effects) -> Self {
        let (ndof, n) = (model.phi.nrows(), model.size());
        Dynamics {
            model,
            op,
            effects,
            rigid_axial: [op.v0, 0.0],
            attempt_rigid_velocity: op.v0,
            evaluated_rigid_velocity: op.v0,
            time: 0.0,
            block: None,
            evaluated_rigid_position: [f64::NAN; 2],
            surface: None,
            cut: Cut::default(),
            walls: WallGeometry::per_node(&model.string, &model.global.layout),
            q_full: DVector::zeros(ndof),
            v_full: DVector::zeros(ndof),
            a_full: DVector::zeros(ndof),
            f_full: DVector::zeros(ndof),
            q_tangent: DVector::zeros(ndof),
            attempt: None,
            attempt_modal: [DVector::zeros(n), DVector::zeros(n)],
            attempt_full: [DVector::zeros(ndof), DVector::zeros(ndof)],
            contact_tangent: ContactTangent::new(&model.sparse, model.nodes(), n),
            // The unreduced model (a sparse Newton matrix) adds the wall directly: no dense n × n
            // copies of its thousands of coordinates.
            wall_tangent: match model.jacobian_pattern {
                None => [DMatrix::zeros(n, n), DMatrix::zeros(n, n)],
                Some(_) => [DMatrix::zeros(0, 0), DMatrix::zeros(0, 0)],
            },
            touching: Vec::with_capacity(model.nodes()),
            wall_tangent_at: None,
            wall_added_at: None,
            wall_tangent_uses: 0,
            blocks: model.blocks.workspace(),
            evaluated: [
                DVector::from_element(n, f64::NAN),
                DVector::zeros(n),
                DVector::zeros(n),
            ],
            element_energies: (0.0, 0.0),
            strain_tangent: model.stiffness.to_dense(n),
            damping_gyroscopic: match (&model.damping, effects.damping) {
                (Operator::Dense(d), true) => d + &model.gyroscopic * op.omega,
                (d, true) => d.to_dense(n) + &model.gyroscopic * op.omega,
                (_, false) => &model.gyroscopic * op.omega,
            },
            scratch: DMatrix::zeros(ndof, n),
            contacts: vec![NodeContact::default(); model.nodes()],
            bit: BitLoad::default(),
            jacobian_signature: (u64::MAX, 0, false),
            residual_signature: (0, 0, false),
            residual_evaluations: 0,
            tangent_refreshes: 0,
            wall_tangent_refreshes: 0,
        }
    }

    /// Full-mesh state and forces at (q, q̇, q̈), unless they are there already (an accepted step
    /// is observed at the state of its last Newton residual: nothing is recomputed).
    fn evaluate(&mut self, q: &DVector<f64>, v: &DVector<f64>, a: &DVector<f64>) {
        let [eq, ev, ea] = &self.evaluated;
        let same = |x: &DVector<f64>, y: &DVector<f64>| x.as_slice() == y.as_slice();
        let position = self.rigid_position();
        if same(eq, q)
            && same(ev, v)
            && same(ea, a)
            && self.evaluated_rigid_velocity == self.rigid_axial[0]
            && (self.surface.is_none() || self.evaluated_rigid_position == position)
        {
            return;
        }
        if self.on_attempt(q, v, a) {
            // Φq = Φq_p + c_q Φq̈ and Φq̇ = Φv_p + c_v Φq̈: one product with Φ instead of three.
            let (cq, cv) = self.attempt.expect("checked by on_attempt");
            self.model
                .blocks
                .expand(a, &mut self.a_full, &mut self.blocks);
            // On slices: nalgebra's matrix iterators do not vectorise (this loop cost 10 % of a run).
            let [qp, vp] = &self.attempt_full;
            let base = (qp.as_slice().iter())
                .zip(vp.as_slice())
                .zip(self.a_full.as_slice());
            let full = (self.q_full.as_mut_slice().iter_mut()).zip(self.v_full.as_mut_slice());
            for ((q, v), ((&qp, &vp), &a)) in full.zip(base) {
                *q = qp + cq * a;
                *v = vp + cv * a;
            }
            let change = self.rigid_axial[0] - self.attempt_rigid_velocity;
            if change != 0.0 {
                for node in 0..self.model.nodes() {
                    self.v_full[Dof::U.at(node)] += change;
                }
            }
        } else {
            self.expand(q, v, a);
        }
        self.full_forces();
        for (e, x) in self.evaluated.iter_mut().zip([q, v, a]) {
            copy_vector(e, x);
        }
        self.evaluated_rigid_velocity = self.rigid_axial[0];
        self.evaluated_rigid_position = position;
    }

    /// The rigid motion [s (m), Ω t (rad)] at the current time.
    fn rigid_position(&self) -> [f64; 2] {
        [
            self.block.unwrap_or(self.op.v0 * self.time),
            self.op.omega * self.time,
        ]
    }

    /// The bit's elastic axial displacement and rotation (Φq at the bit node), m and rad.
    fn bit_elastic(&self, q: &[f64]) -> [f64; 2] {
        let node = self.model.elements();
        [Dof::U.at(node), Dof::ThetaX.at(node)].map(|dof| {
            let (modes, values) = self.model.sparse.dof(dof);
            modes.iter().zip(values).map(|(&j, &x)| x * q[j]).sum()
        })
    }

    /// The depth of cut read at the last residual (zero for a rate law).
    pub fn cut(&self) -> Cut {
        self.cut
    }

    /// The time of the states that follow, s (a residual sets it; [`Self::observe`] needs it
    /// for a depth-of-cut law, whose rock surface is fixed in space).
    pub fn set_time(&mut self, t: f64) {
        self.time = t;
    }

    /// The block's position s (m) when the top is free ([`super::FreeTop`]).
    pub fn set_block_position(&mut self, s: f64) {
        self.block = Some(s);
    }

    /// For a depth-of-cut bit law: the helical bottom hole of steady drilling under the bit of
    /// the modal state `q` at time `t`, cut at `axial_speed` (m/s) and Ω (the start's steady
    /// state, so that its first depth of cut is that of the law's quasi-static form). Nothing
    /// for a rate law.
    pub fn start_surface(&mut self, q: &[f64], t: f64, axial_speed: f64) {
        let bit = &self.model.string.bit;
        let Some(blades) = bit.blades() else {
            return;
        };
        self.time = t;
        let [s, angle] = self.rigid_position();
        let [u, theta] = self.bit_elastic(q);
        let pitch = bit.law().steady_depth(axial_speed, self.op.omega);
        self.surface = Some(RockSurface::helix(blades, angle + theta, s + u, pitch));
        self.evaluated[0].fill(f64::NAN);
    }

    /// The blades cut the rock up to the accepted state `q` at time `t` (call once per accepted
    /// step, after the block position of a free top is set). Nothing for a rate law.
    pub fn advance_surface(&mut self, q: &[f64], t: f64) {
        if self.surface.is_none() {
            return;
        }
        self.time = t;
        let [s, angle] = self.rigid_position();
        let [u, theta] = self.bit_elastic(q);
        if let Some(surface) = &mut self.surface {
            surface.advance(angle + theta, s + u);
        }
        // The cached forces were read off the rock before this cut.
        self.evaluated[0].fill(f64::NAN);
    }

    /// Whether (q, q̇) = (q_p + c_q q̈, v_p + c_v q̈) of the announced attempt, exactly as the
    /// integrator forms them (bitwise), so that the full-mesh attempt base applies.
    fn on_attempt(&self, q: &DVector<f64>, v: &DVector<f64>, a: &DVector<f64>) -> bool {
        let Some((cq, cv)) = self.attempt else {
            return false;
        };
        let [qp, vp] = &self.attempt_modal;
        (0..a.len()).all(|i| q[i] == qp[i] + cq * a[i] && v[i] == vp[i] + cv * a[i])
    }

    /// Full-mesh elastic displacement, absolute velocity and acceleration from (q, q̇, q̈).
    fn expand(&mut self, q: &DVector<f64>, v: &DVector<f64>, a: &DVector<f64>) {
        // Per-family dense blocks of Φ: vectorised, and they skip the zeros of Φ.
        let (phi, work) = (&self.model.blocks, &mut self.blocks);
        phi.expand(q, &mut self.q_full, work);
        phi.expand(v, &mut self.v_full, work);
        phi.expand(a, &mut self.a_full, work);
        add_rigid_velocity(&mut self.v_full, self.rigid_axial[0], self.op.omega);
    }

    fn element_state(x: &DVector<f64>, e: usize) -> ElementVector {
        ElementVector::from_column_slice(&x.as_slice()[6 * e..6 * e + 12])
    }

    /// f_full = f_int + f_gyro − F_wall − F_bit on the full mesh (expand first).
    fn full_forces(&mut self) {
        // On slices: nalgebra's fill goes through its generic iterators.
        self.f_full.as_mut_slice().fill(0.0);
        let m = self.model;
        let (mut strain, mut kinetic) = (0.0, 0.0);
        for e in 0..m.elements() {
            let (d, v, a) = (
                Self::element_state(&self.q_full, e),
                Self::element_state(&self.v_full, e),
                Self::element_state(&self.a_full, e),
            );
            let kernel = m.kernel(e);
            let (f_strain, u) = (kernel.strains).internal_force_and_energy(&kernel.strain_law, &d);
            let (f_inertia, t) = kernel.inertia.force_and_energy(&d, &v, &a);
            strain += u;
            kinetic += t;
            let f = f_strain + f_inertia;
            for (out, x) in self.f_full.as_mut_slice()[6 * e..6 * e + 12]
                .iter_mut()
                .zip(f.as_slice())
            {
                *out += x;
            }
        }
        self.element_energies = (strain, kinetic);
        let (law, friction) = (m.string.wall.law(), m.string.wall_friction);
        for node in 0..m.nodes() {
            let (iu, iv, iw, it) = (
                Dof::U.at(node),
                Dof::V.at(node),
                Dof::W.at(node),
                Dof::ThetaX.at(node),
            );
            let c = if self.effects.wall {
                wall_contact_force(law, friction, self.walls[node], self.motion(node))
            } else {
                NodeContact::default()
            };
            let stored = &mut self.contacts[node];
            if c.active || stored.active {
                self.f_full[iu] -= c.axial_force;
                self.f_full[iv] -= c.force[0];
                self.f_full[iw] -= c.force[1];
                self.f_full[it] -= c.torque;
                *stored = c;
            } else {
                // Free before and now: only the indentation changes (no 130-byte store per node).
                stored.indentation = c.indentation;
            }
        }
        let bit_node = m.elements();
        let (iu, it) = (Dof::U.at(bit_node), Dof::ThetaX.at(bit_node));
        self.bit = match (&self.surface, self.effects.bit) {
            (_, false) => BitLoad::default(),
            (None, true) => m.string.bit.load(self.v_full[iu], self.v_full[it]),
            (Some(surface), true) => {
                let [s, angle] = self.rigid_position();
                self.cut = surface.cut(angle + self.q_full[it], s + self.q_full[iu]);
                (m.string.bit).load_at_depth(self.cut.depth, self.v_full[iu], self.v_full[it])
            }
        };
        self.f_full[iu] -= self.bit.force;
        self.f_full[it] -= self.bit.torque;
        self.residual_signature = self.signature();
    }

    /// The motion of node `node` at the last residual's state (elastic position, absolute
    /// velocities).
    fn motion(&self, node: usize) -> NodeMotion {
        let (iu, iv, iw, it) = (
            Dof::U.at(node),
            Dof::V.at(node),
            Dof::W.at(node),
            Dof::ThetaX.at(node),
        );
        NodeMotion {
            position: [self.q_full[iv], self.q_full[iw]],
            velocity: [self.v_full[iv], self.v_full[iw]],
            axial_velocity: self.v_full[iu],
            spin: self.v_full[it],
        }
    }

    /// The touching nodes of the last residual with their contact forces and tangents (the
    /// residual computes the forces only; [`super::contact::wall_contact`] at the same motion
    /// gives the same forces with the tangent).
    pub(super) fn touching_with_tangents(&self) -> impl Iterator<Item = (usize, NodeContact)> + '_ {
        let m = self.model;
        let (law, friction) = (m.string.wall.law(), m.string.wall_friction);
        (self.contacts.iter().enumerate())
            .filter(|(_, c)| c.active)
            .map(move |(node, _)| {
                let c = wall_contact(law, friction, self.walls[node], self.motion(node));
                (node, c)
            })
    }

    /// (number of touching nodes, a hash of which ones, bit on bottom).
    fn signature(&self) -> (u64, u64, bool) {
        let mut count = 0;
        let mut hash = crate::hash::Fnv1a::new();
        for (node, c) in self.contacts.iter().enumerate() {
            if c.active {
                count += 1;
                hash.word(node as u64);
            }
        }
        (count, hash.finish(), self.bit.force != 0.0)
    }

    /// The share of the wall law's friction coefficient that acts (1 unless changed: the
    /// pre-loaded start ramps it from 0 to 1).
    pub fn set_friction_scale(&mut self, scale: f64) {
        for wall in &mut self.walls {
            wall.friction_scale = scale;
        }
        // The gathered wall tangent belongs to the old friction.
        self.wall_tangent_at = None;
        self.wall_added_at = None;
        // The cached full-mesh forces belong to the old friction.
        self.evaluated[0].fill(f64::NAN);
    }

    /// The rigid axial motion's velocity ṡ (m/s) and acceleration s̈ (m/s²) of the states that
    /// follow (the imposed feed's are V0 and 0).
    pub fn set_rigid_axial(&mut self, velocity: f64, acceleration: f64) {
        self.rigid_axial = [velocity, acceleration];
    }

    /// The radial gap between node `k` and the wall, m (its section's: the hole less its outer
    /// radius).
    pub fn node_gap(&self, k: usize) -> f64 {
        self.walls[k].gap
    }

    /// The operating point (Ω, and the feed V0 or the autodriller's set-point).
    pub fn op(&self) -> OperatingPoint {
        self.op
    }

    /// Whether damping is on (the rigid motion's damping load belongs to the top loads).
    pub fn damping_on(&self) -> bool {
        self.effects.damping
    }

    /// The top-drive loads [F_top (N), T_top (N·m)] at the modal velocity and acceleration
    /// (v, a) of the last evaluated state: the global balance of the string along the rigid
    /// motion, F_top = e_uᵀ(M Q̈ + C Q̇ + f − F), T_top = e_θᵀ(…). In the reduced model only
    /// Φᵀ R = 0 holds, so this (not the local reaction of element 0) is the load whose power
    /// Q̇_rigidᵀ R closes the energy balance; e_uᵀ f_int = e_θᵀ f_int = 0 exactly (the strain
    /// energy is invariant under rigid translation and spin). F_top > 0 pushes towards the bit.
    pub fn top_loads(&self, v: &DVector<f64>, a: &DVector<f64>) -> [f64; 2] {
        let m = self.model;
        let c = if self.effects.damping { 1.0 } else { 0.0 };
        let mut resultant = [0.0; 2];
        for node in 0..m.nodes() {
            resultant[0] += self.f_full[Dof::U.at(node)];
            resultant[1] += self.f_full[Dof::ThetaX.at(node)];
        }
        let rigid = [self.rigid_axial[0], self.op.omega];
        let accel = [self.rigid_axial[1], 0.0];
        std::array::from_fn(|k| {
            resultant[k]
                + m.rigid_mass[k].dot(a)
                + accel[k] * m.rigid_self_mass[k]
                + c * (m.rigid_damping[k].dot(v) + rigid[k] * m.rigid_self_damping[k])
        })
    }

    /// out += the wall's tangent at the contacts in `touching` ([`Self::collect_touching`]) for
    /// the coefficients c_q, c_v: −Σₙ Pₙ (c_q ∂Fₙ/∂(v, w) + c_v ∂Fₙ/∂(v̇, ẇ)) Pₙᵀ over the touching
    /// nodes, Pₙ the rows of Φ for the node's lateral DOFs, gathered and added in one pass over
    /// the matrix (see
    /// [`ContactTangent`]), and the friction's coupling of u and θx with the lateral DOFs (and
    /// of u and θx with each other), one rank-one term per non-zero entry.
    fn add_wall_tangent(&mut self, cq: f64, cv: f64, out: &mut DMatrix<f64>) {
        let (touching, gathered, phi) = (
            &self.touching,
            &mut self.contact_tangent,
            &self.model.sparse,
        );
        gathered.clear();
        for (node, k) in touching {
            let w = std::array::from_fn::<_, 2, _>(|a_| {
                std::array::from_fn::<_, 2, _>(|b| {
                    -(cq * k.stiffness[a_][b] + cv * k.damping[a_][b])
                })
            });
            gathered.push(phi, *node, w);
        }
        gathered.add_to(out);
        for &(node, ref k) in touching {
            if !k.coupled {
                continue;
            }
            for (a, row) in FRICTION_DOFS.iter().enumerate() {
                for (b, col) in FRICTION_DOFS.iter().enumerate() {
                    let stiffness = match b {
                        1 | 2 => k.coupling_stiffness[a][b - 1],
                        _ => 0.0,
                    };
                    let w = -(cq * stiffness + cv * k.coupling_damping[a][b]);
                    if w != 0.0 {
                        phi.add_dof_outer(w, row.at(node), col.at(node), out);
                    }
                }
            }
        }
    }

    /// The touching nodes of the last residual with their tangents, into `touching`.
    fn collect_touching(&mut self) {
        let mut touching = std::mem::take(&mut self.touching);
        touching.clear();
        touching.extend(self.touching_with_tangents());
        self.touching = touching;
    }

    /// Gathers the wall's tangent at the last residual's contacts into `wall_tangent`:
    /// −Σₙ Pₙ ∂Fₙ/∂(v, w) Pₙᵀ and −Σₙ Pₙ ∂Fₙ/∂(v̇, ẇ) Pₙᵀ over the touching nodes n, with Pₙ the
    /// rows of Φ for the node's lateral DOFs (see [`ContactTangent`]), and the friction's coupling
    /// of u and θx with the lateral DOFs, one rank-one term per non-zero entry.
    ///
    /// [`Self::jacobian`] gathers it when the same nodes (and the bit's contact) have touched at
    /// two Newton matrices in a row; while they keep touching, a new step length only
    /// recombines it with the other parts. The Newton matrix then holds the wall tangent of an
    /// earlier state of the same contacts, as it holds the strain tangent of an earlier state:
    /// Newton converges to the same tolerance (a chord iteration), and the matrix is rebuilt for
    /// a new step length in O(n²) instead of O(touching nodes × n²). Measured on the seed (10 s,
    /// `drillopt simulate problems/seed_mc2014.toml --duration 10`): 19 721 factorisations, each
    /// re-gathering the 71 touching nodes, took a quarter of the run; the same nodes touch
    /// throughout, and over the 90 s the wall tangent is now gathered 23 319 times for 209 450
    /// Newton matrices (every [`WALL_TANGENT_USES`] matrices).
    fn gather_wall_tangent(&mut self) {
        self.wall_tangent_refreshes += 1;
        self.wall_tangent_at = Some(self.residual_signature);
        self.wall_tangent_uses = 0;
        self.collect_touching();
        // The stiffness part (c_q = 1, c_v = 0), then the damping part (c_q = 0, c_v = 1).
        for (part, (cq, cv)) in [(1.0, 0.0), (0.0, 1.0)].into_iter().enumerate() {
            let mut tangent = std::mem::replace(&mut self.wall_tangent[part], DMatrix::zeros(0, 0));
            tangent.fill(0.0);
            self.add_wall_tangent(cq, cv, &mut tangent);
            self.wall_tangent[part] = tangent;
        }
    }

    /// The equilibrium defects of the last residual's state for the force-summation recovery of
    /// the axial force and torque ([`crate::rom::ForceSummation::defects`]), one [N, N·m] per
    /// element into `out` (`out.len()` = elements). False, and `out` untouched, for a model
    /// whose strains carry its loads (the unreduced model).
    pub fn force_summation_defects(&self, out: &mut [[f64; 2]]) -> bool {
        let Some(summation) = &self.model.force_summation else {
            return false;
        };
        let state = crate::rom::FullState {
            forces: self.f_full.as_slice(),
            acceleration: self.a_full.as_slice(),
            velocity: self.v_full.as_slice(),
            rigid_acceleration: self.rigid_axial[1],
            damping: self.effects.damping,
            gravity: self.effects.gravity,
        };
        summation.defects(&state, out);
        true
    }

    /// What the time history records at a state.
    pub fn observe(&mut self, q: &DVector<f64>, v: &DVector<f64>, a: &DVector<f64>) -> Observation {
        self.evaluate(q, v, a);
        self.observe_step(q, v, a)
    }

    /// What the time history records at the end of a converged step (q, q̇, q̈), without a new
    /// full-mesh evaluation: the full-mesh quantities (element energies, contact and bit loads,
    /// the load resultant, the radial displacements) are those of the last Newton residual,
    /// whose state differs from the accepted one by the last Newton correction (within the
    /// Newton tolerance, ≤ 1e-3 of the local error tolerance by default); the modal terms
    /// (kinetic energy of Φq̇, damping, gravity, the inertia of the rigid motion) are exact.
    pub fn observe_step(
        &self,
        q: &DVector<f64>,
        v: &DVector<f64>,
        a: &DVector<f64>,
    ) -> Observation {
        let m = self.model;
        let (v0, om) = (self.rigid_axial[0], self.op.omega);
        let rigid = [v0, om];
        let [top_force, top_torque] = self.top_loads(v, a);
        // Energies.
        let mut kinetic = 0.5 * m.mass.quadratic(v);
        let mut dissipation = 0.0;
        for (k, &r) in rigid.iter().enumerate() {
            // (e_θᵀ M e_u = 0: the translation and the spin do not share kinetic energy.)
            kinetic += r * m.rigid_mass[k].dot(v) + 0.5 * r * r * m.rigid_self_mass[k];
            if self.effects.damping {
                dissipation +=
                    2.0 * r * m.rigid_damping[k].dot(v) + r * r * m.rigid_self_damping[k];
            }
        }
        if self.effects.damping {
            match &m.damping {
                // q̇ᵀ D q̇ column by column (no temporary vector).
                Operator::Dense(d) => {
                    for (j, vj) in v.iter().enumerate() {
                        dissipation += vj * d.column(j).dot(v);
                    }
                }
                d => dissipation += d.quadratic(v),
            }
        }
        let (strain, kinetic_nl) = self.element_energies;
        kinetic += kinetic_nl;
        let mut obs = Observation {
            top_force,
            top_torque,
            ..Default::default()
        };
        let mut wall_elastic = 0.0;
        for (node, c) in self.contacts.iter().enumerate() {
            let (v, w) = (self.q_full[Dof::V.at(node)], self.q_full[Dof::W.at(node)]);
            let r = (v * v + w * w).sqrt();
            obs.max_radial_over_gap = obs.max_radial_over_gap.max(r / self.walls[node].gap);
            if c.active {
                obs.nodes_in_contact += 1;
                obs.wall_force_total += c.normal.abs();
                obs.wall_force_max = obs.wall_force_max.max(c.normal.abs());
                wall_elastic += c.elastic_energy;
                dissipation += c.dissipation;
            }
        }
        let gravity = if self.effects.gravity {
            -m.gravity.dot(q)
        } else {
            0.0
        };
        let bit_node = m.elements();
        obs.bit = self.bit;
        obs.bit_velocity = self.v_full[Dof::U.at(bit_node)];
        obs.bit_spin = self.v_full[Dof::ThetaX.at(bit_node)];
        obs.bit_u_elastic = self.q_full[Dof::U.at(bit_node)];
        obs.bit_theta_elastic = self.q_full[Dof::ThetaX.at(bit_node)];
        obs.kinetic_energy = kinetic;
        obs.potential_energy = strain + wall_elastic + gravity;
        obs.dissipation = dissipation;
        obs.power_top = top_force * v0 + top_torque * om;
        obs.block_speed = v0;
        obs.depth_of_cut = if self.surface.is_some() {
            self.cut.depth
        } else {
            f64::NAN
        };
        obs.power_bit = self.bit.force * obs.bit_velocity + self.bit.torque * obs.bit_spin;
        obs
    }

    /// Elastic radial displacement at position x (interpolated linearly between nodes), m, of the
    /// state last passed to [`Self::observe`] (or to a residual evaluation).
    /// Elastic full-mesh displacements Φq of the last residual evaluation (node-major, 6 DOFs
    /// per node), m and rad.
    pub fn displacement_full(&self) -> &[f64] {
        self.q_full.as_slice()
    }

    pub fn radial_at(&self, x: f64) -> f64 {
        let (i, f) = self.model.global.layout.locate(x);
        let r = |n: usize| self.q_full[Dof::V.at(n)].hypot(self.q_full[Dof::W.at(n)]);
        (1.0 - f) * r(i) + f * r(i + 1)
    }
}

/// Adds the rigid velocity field (`axial` on every u, `spin` on every θx) to a full-mesh elastic
/// velocity.
fn add_rigid_velocity(v_full: &mut DVector<f64>, axial: f64, spin: f64) {
    for node in 0..v_full.len() / 6 {
        v_full[Dof::U.at(node)] += axial;
        v_full[Dof::ThetaX.at(node)] += spin;
    }
}

impl ImplicitSystem for Dynamics<'_> {
    fn size(&self) -> usize {
        self.model.size()
    }

    fn begin_attempt(&mut self, qp: &DVector<f64>, vp: &DVector<f64>, cq: f64, cv: f64) {
        let (phi, work) = (&self.model.blocks, &mut self.blocks);
        let [q_full, v_full] = &mut self.attempt_full;
        phi.expand(qp, q_full, work);
        phi.expand(vp, v_full, work);
        add_rigid_velocity(v_full, self.rigid_axial[0], self.op.omega);
        self.attempt_rigid_velocity = self.rigid_axial[0];
        copy_vector(&mut self.attempt_modal[0], qp);
        copy_vector(&mut self.attempt_modal[1], vp);
        self.attempt = Some((cq, cv));
    }

    fn jacobian_reusable(&self) -> bool {
        self.jacobian_signature == self.residual_signature
    }

    fn residual(
        &mut self,
        t: f64,
        q: &DVector<f64>,
        v: &DVector<f64>,
        a: &DVector<f64>,
        out: &mut DVector<f64>,
    ) {
        self.residual_evaluations += 1;
        self.time = t;
        self.evaluate(q, v, a);
        let m = self.model;
        m.blocks.project(&self.f_full, out, &mut self.blocks);
        m.mass.mul_add(1.0, a, out);
        if self.effects.damping {
            m.damping.mul_add(1.0, v, out);
            out.axpy(self.rigid_axial[0], &m.rigid_damping[0], 1.0);
            out.axpy(self.op.omega, &m.rigid_damping[1], 1.0);
        }
        if self.rigid_axial[1] != 0.0 {
            // The inertia of the rigid axial acceleration, Φᵀ M e_u s̈.
            out.axpy(self.rigid_axial[1], &m.rigid_mass[0], 1.0);
        }
        if self.effects.gravity {
            *out -= &m.gravity;
        }
    }

    fn jacobian(
        &mut self,
        _t: f64,
        q: &DVector<f64>,
        _v: &DVector<f64>,
        _a: &DVector<f64>,
        c: JacobianCoefficients,
        refresh: bool,
        out: &mut DMatrix<f64>,
    ) {
        let m = self.model;
        self.jacobian_signature = self.residual_signature;
        if refresh {
            self.tangent_refreshes += 1;
            m.blocks.expand(q, &mut self.q_tangent, &mut self.blocks);
            self.strain_tangent.fill(0.0);
            m.add_strain_tangent(
                &self.q_tangent,
                &mut self.strain_tangent,
                &mut self.scratch,
                &mut self.blocks,
                false,
            );
        }
        // The wall's part: kept apart (two matrices gathered once, then recombined for each new
        // step length) once the same nodes have touched at two Newton matrices in a row, else
        // added for this matrix only, as the other parts are combined (a string whose contacts
        // change at every matrix pays no more than one gathering per matrix). The unreduced
        // model's sparse matrix always adds it directly.
        let signature = Some(self.residual_signature);
        if refresh
            || self.wall_tangent_at != signature
            || self.wall_tangent_uses >= WALL_TANGENT_USES
        {
            self.wall_tangent_at = None;
        }
        let kept = if m.jacobian_pattern.is_some() {
            false
        } else if self.wall_tangent_at == signature {
            self.wall_tangent_uses += 1;
            true
        } else if !refresh && self.wall_added_at == signature {
            self.gather_wall_tangent();
            true
        } else {
            self.wall_added_at = signature;
            false
        };
        // cq K_t + cv (D + Ω G) + ca M (+ cq K_wall + cv C_wall when kept), in one pass over the
        // (column-major) storage, or over the pattern of a sparse Newton matrix (zero elsewhere,
        // in `out` too).
        let [wall_k, wall_c] = &self.wall_tangent;
        match (&m.jacobian_pattern, kept) {
            (None, false) => {
                let terms =
                    (self.strain_tangent.as_slice().iter()).zip(self.damping_gyroscopic.as_slice());
                for (x, (&k, &d)) in out.as_mut_slice().iter_mut().zip(terms) {
                    *x = c.cq * k + c.cv * d;
                }
            }
            (None, true) => {
                let terms = (self.strain_tangent.as_slice().iter())
                    .zip(self.damping_gyroscopic.as_slice())
                    .zip(wall_k.as_slice().iter().zip(wall_c.as_slice()));
                for (x, ((&k, &d), (&kw, &cw))) in out.as_mut_slice().iter_mut().zip(terms) {
                    *x = c.cq * (k + kw) + c.cv * (d + cw);
                }
            }
            (Some(pattern), _) => {
                for (j, rows) in pattern.columns().enumerate() {
                    for &i in rows {
                        out[(i, j)] = c.cq * self.strain_tangent[(i, j)]
                            + c.cv * self.damping_gyroscopic[(i, j)];
                    }
                }
            }
        }
        m.mass.add_to(c.ca, out);
        let phi = &m.sparse;
        if !kept {
            self.collect_touching();
            self.add_wall_tangent(c.cq, c.cv, out);
        }
        // Bit: −∂(F, T)/∂(u̇, θ̇) at the bit node.
        let bit_node = m.elements();
        let (iu, it) = (Dof::U.at(bit_node), Dof::ThetaX.at(bit_node));
        let b = self.bit;
        if b.dforce_dvel != 0.0 {
            phi.add_dof_outer(-c.cv * b.dforce_dvel, iu, iu, out);
            phi.add_dof_outer(-c.cv * b.dtorque_dvel, it, iu, out);
            phi.add_dof_outer(-c.cv * b.dtorque_dspin, it, it, out);
            if b.dforce_dspin != 0.0 {
                phi.add_dof_outer(-c.cv * b.dforce_dspin, iu, it, out);
            }
        } else if b.dtorque_dspin != 0.0 {
            // A depth-of-cut law while the bit rises: the torque still follows the spin.
            phi.add_dof_outer(-c.cv * b.dtorque_dspin, it, it, out);
        }
        // A depth-of-cut law: the depth d = n (u − L(θ)) moves with the bit's position and angle,
        // ∂(F, T)/∂(u, θ) = ∂(F, T)/∂d · (∂d/∂u, ∂d/∂θ).
        if b.dforce_ddepth != 0.0 || b.dtorque_ddepth != 0.0 {
            let Cut {
                d_position,
                d_angle,
                ..
            } = self.cut;
            for (row, slope) in [(iu, b.dforce_ddepth), (it, b.dtorque_ddepth)] {
                phi.add_dof_outer(-c.cq * slope * d_position, row, iu, out);
                if d_angle != 0.0 {
                    phi.add_dof_outer(-c.cq * slope * d_angle, row, it, out);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{BasisSpec, FamilySize};
    use crate::problem::Problem;

    /// The seed string (coulomb wall friction, 30 elements) at rest on the wall, drilling, with a
    /// small lateral and axial velocity: its dynamics after one residual.
    fn seed_on_the_wall(model: &ReducedModel, op: OperatingPoint) -> Dynamics<'_> {
        let n = model.size();
        let (q, _) = crate::sim::static_equilibrium(model).expect("static equilibrium");
        let mut v = DVector::from_fn(n, |i, _| 1e-3 * ((i as f64) * 0.7).sin());
        v[0] += 1e-3;
        let mut sys = Dynamics::new(model, op, Effects::ALL);
        let mut r = DVector::zeros(n);
        sys.residual(0.0, &q, &v, &DVector::zeros(n), &mut r);
        assert!(sys.contacts.iter().filter(|c| c.active).count() > 3);
        sys
    }

    fn seed_model() -> (ReducedModel, OperatingPoint) {
        let file = concat!(env!("CARGO_MANIFEST_DIR"), "/problems/seed_mc2014.toml");
        let p = Problem::load(file).expect("the seed problem loads");
        let basis = BasisSpec::PerFamily {
            bending: FamilySize::Count(10),
            torsional: FamilySize::Count(2),
            axial: FamilySize::Count(2),
            static_corrections: true,
            steady_shapes: false,
        };
        let model = ReducedModel::new(&p.model, 30, &basis).expect("the basis");
        (model, p.operating_point)
    }

    fn coefficients(h: f64) -> JacobianCoefficients {
        JacobianCoefficients {
            ca: 1.0,
            cv: 0.5 * h,
            cq: 0.25 * h * h,
        }
    }

    /// The Newton matrix with the wall tangent kept apart (gathered into two matrices and
    /// recombined for a new step length) equals the one that adds the wall tangent for its own
    /// coefficients, to round-off; and the wall part is not negligible in it.
    #[test]
    fn kept_wall_tangent_gives_the_direct_newton_matrix() {
        let (model, op) = seed_model();
        let n = model.size();
        let (q, a) = (DVector::zeros(n), DVector::zeros(n));
        let mut sys = seed_on_the_wall(&model, op);
        let mut kept = DMatrix::zeros(n, n);
        sys.jacobian(0.0, &q, &q, &a, coefficients(1e-4), false, &mut kept);
        assert_eq!(
            sys.wall_tangent_refreshes, 0,
            "the first matrix adds the wall directly"
        );
        sys.jacobian(0.0, &q, &q, &a, coefficients(3e-4), false, &mut kept);
        assert_eq!(
            sys.wall_tangent_refreshes, 1,
            "the same nodes touch: kept apart"
        );
        let mut fresh = seed_on_the_wall(&model, op);
        let mut direct = DMatrix::zeros(n, n);
        fresh.jacobian(0.0, &q, &q, &a, coefficients(3e-4), false, &mut direct);
        assert_eq!(fresh.wall_tangent_refreshes, 0);
        let error = (&kept - &direct).norm() / direct.norm();
        assert!(error < 1e-12, "kept and direct differ by {error:e}");
        // Without the wall the matrix is far from it: the test compares the wall part.
        let mut free = Dynamics::new(
            &model,
            op,
            Effects {
                wall: false,
                ..Effects::ALL
            },
        );
        let mut r = DVector::zeros(n);
        let (q0, _) = crate::sim::static_equilibrium(&model).unwrap();
        free.residual(0.0, &q0, &q, &a, &mut r);
        let mut without = DMatrix::zeros(n, n);
        free.jacobian(0.0, &q, &q, &a, coefficients(3e-4), false, &mut without);
        assert!((&direct - &without).norm() > 1e-3 * direct.norm());
    }

    /// A kept wall tangent serves [`WALL_TANGENT_USES`] more Newton matrices, then is gathered
    /// again; a fresh tangent asked for (`refresh`) is added directly.
    #[test]
    fn kept_wall_tangent_is_gathered_again_after_its_uses() {
        let (model, op) = seed_model();
        let n = model.size();
        let (q, a) = (DVector::zeros(n), DVector::zeros(n));
        let mut sys = seed_on_the_wall(&model, op);
        let mut out = DMatrix::zeros(n, n);
        let mut matrix = |sys: &mut Dynamics, k: usize, refresh: bool| {
            let h = 1e-4 * (1.0 + 0.1 * k as f64);
            sys.jacobian(0.0, &q, &q, &a, coefficients(h), refresh, &mut out);
            sys.wall_tangent_refreshes
        };
        assert_eq!(matrix(&mut sys, 0, false), 0);
        assert_eq!(matrix(&mut sys, 1, false), 1);
        for k in 0..WALL_TANGENT_USES {
            assert_eq!(matrix(&mut sys, 2 + k, false), 1, "use {k}");
        }
        assert_eq!(matrix(&mut sys, 99, false), 2, "gathered again");
        assert_eq!(
            matrix(&mut sys, 100, true),
            2,
            "a refresh adds the wall directly"
        );
        assert_eq!(matrix(&mut sys, 101, false), 3, "and gathers at the next");
    }
}
