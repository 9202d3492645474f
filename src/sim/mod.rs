//! One simulation of the nonlinear reduced-order drillstring model: the geometry of the wall
//! contact, the dynamics (the wall contact and bit–rock laws are the model's,
//! [`crate::model::wall`], [`crate::model::bit`]), the recorded time history, and the run itself.

mod contact;
mod contact_tangent;
mod dynamics;
mod envelope;
mod fatigue;
mod free_top;
mod plot_history;
mod rock_surface;
mod run;
mod sampler;
mod series;
mod stability;
mod steady_basis;

pub use crate::model::BitLoad;
pub use contact::{NodeContact, NodeMotion, WallGeometry, wall_contact};
pub use dynamics::{Dynamics, Effects, Observation};
pub use envelope::StressEnvelope;
pub use fatigue::{FATIGUE_FIBRES, SectionFatigue};
pub use free_top::{FreeTop, START_TOLERANCE, free_top_start};
pub use plot_history::{PLOTTED, PlotHistory};
pub use rock_surface::{Cut, NODES_PER_REVOLUTION, RockSurface};
pub use run::{
    IMPACT_SEPARATION, IMPACT_SPEED, InitialState, ModelKind, RunOutput, RunSettings,
    STEPS_PER_PERIOD, SimulationError, SolverStats, StopFlag, check_against_soft_string,
    preloaded_equilibrium, resolving_step, run_model_until, simulate, simulate_into,
    static_equilibrium,
};
pub use sampler::{SampleInterval, Sampler};
pub use series::{CHANNELS, Channel, Frame, Row, Sink, TimeSeries, at};
pub use stability::{MAX_UNKNOWNS, NEUTRAL, SteadyStability, steady_stability};
pub use steady_basis::{
    FiniteElementSteadyState, STEADY_SHAPES_MAX_UNKNOWNS, finite_element_steady_state,
    reduced_model, reduced_model_with, with_status,
};

/// Revision of the simulator's numerics, part of every cache key: bump it with any change that
/// can move a simulated number (model, basis, start, integrator, metrics), so that results of
/// older numerics are never reused. 2: basis per family with static corrections, pre-loaded start,
/// step resolving the lowest torsional and axial modes, averaged bit speed, impacts by speed.
/// 3: strain tangent refreshed after failed attempts only; metric stick_slip_severity_raw.
/// 4: stress envelope and its metrics (max_von_mises_pa, …); the simulated motion is unchanged.
/// 5: fatigue (rainflow, Miner), buckling, critical_speed_margin and critical_speed_proximity
/// (Campbell diagram at rest) in every record; the simulated motion is unchanged.
/// 6: the resting shape of each bending plane in the basis (part of the static corrections): the
/// reduced string lies on the wall where the finite-element model does.
/// 7: metric bit_damping_ratio in every record; the simulated motion is unchanged.
/// 8: Newton starts each step from the acceleration extrapolated through the last three accepted
/// steps (was: the current one); results move within the Newton tolerance (seed_study, 10 s:
/// stick-slip statistics by ≤ 0.9 %, means by ≤ 1e-4).
/// 9: wall friction on the slip of the contact point (`friction_law = "coulomb"`, the default:
/// axial drag, circumferential force, torque with lever R_ext; exact tangent in the Newton
/// matrix); the pre-loaded start by continuation in the friction with the climbing predictor,
/// checked against the soft-string torque and drag; runs above 10× yield refused; metrics
/// mean_top_torque_nm and mean_top_force_n. Gyroscopic sign: the nonlinear inertia follows
/// from 2ρI(θ̇x − θy θ̇z)², the spin of the tilted section (MODEL.md §3), not the paper's
/// (θ̇x + θy θ̇z)²: forward whirl stiffens with Ω (seed metrics move < 0.2 % over 90 s).
/// The tiny string's golden run (tests/study/cache_key.rs) moved by 2.3 % in SSI: μ = 1e-5 friction
/// on the slip instead of the torque, and the start by continuation (chaotic stick-slip).
/// The annulus mud's confined added mass ρ_a π R_ext² (R_bh² + R_ext²)/(R_bh² − R_ext²) on the
/// lateral inertia whenever `annulus_density` is set (89 kg/m on the seed with 1.2 sg mud).
/// 10: a string of sections caps the start's Newton updates per node at half of each node's own
/// gap (a near-gauge stabiliser held the whole string to its 1.6 mm and the start failed); the
/// resting shape of 5-6 km strings (left out before, silently) from the string lying on the
/// wall; many modes of long strings by a wider Krylov space or the dense solver. A string of one
/// section shorter than about 4 km is unchanged bit for bit.
/// 11: the Newton matrix keeps the wall's contact tangent apart while the same nodes touch (two
/// matrices gathered once and recombined for each new step length, gathered again after 8
/// matrices) instead of gathering it for every matrix: Newton's matrix changes, so results move
/// within the Newton tolerance (the seed over 90 s: stick-slip statistics by ≤ 0.6 %, means by
/// ≤ 1e-4); the residual's wall contact computes forces without their tangent (bit for bit).
/// 12: the stresses take the element average of the membrane strain instead of its midpoint
/// value (`fem::stress`): the axial force is the one the element's nodes carry (the midpoint
/// read up to EA(κL)²/24 less tension where the string bends: 83.3-88.5 kN of compression along
/// the 1 km well whose equilibrium bounds it to 86.3-86.9 kN, by the finite-element model), and
/// a reduced model's axial force and torque are summed from the loads below each section
/// (`rom::ForceSummation`; its strains read 65.2-91.6 kN there): max_compression_n, the
/// buckling utilizations, von Mises and fatigue move; the dynamics do not.
/// (`[mesh.basis] steady_shapes = true`, the steady drilling state's shapes in the basis, is new
/// input, off by default: a file without it gives the numbers of revision 12 bit for bit.)
/// 13: the dense generalized eigen-solve of the basis (family blocks up to 800 DOFs, the
/// Rayleigh–Ritz steps) is done in inverse form, K = L Lᵀ and L⁻¹ M L⁻ᵀ (the standard form when
/// K does not factor), instead of the standard form L_M⁻¹ K L_M⁻ᵀ, whose round-off is relative to the mesh's highest eigenvalue: on
/// fine BHA meshes it put the mHz bending modes of a long span 0.2 % off or at 0 Hz, the axial
/// modes 1 % off, and with them the static corrections (a 488-element lateral: their Rayleigh
/// frequencies 425 and 520 Hz against 191 and 204 Hz) and the steady state's growth rate (1.28
/// against 0.27 1/s). Every basis moves at round-off (the seed's frequencies by ≤ 1e-8).
pub const SIMULATOR_REVISION: u32 = 13;
