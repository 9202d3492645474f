//! The model and its physics against closed forms and independent references: the finite
//! elements, the reduced bases, the wall, the bit, the fluid, the driller's top, the simulator,
//! stresses, fatigue and buckling, the Campbell diagram and the stability of steady drilling.
//!
//! One test binary of several (`cargo test --release --test model`; a file's tests alone:
//! `cargo test --release --test model -- <file>::`): each module is one former tests/<file>.rs.

#[path = "../common/mod.rs"]
mod common;

mod added_mass;
mod basis_per_family;
mod bit_inertia;
mod bit_rgd;
mod bit_rock_laws;
mod buoyancy;
mod campbell;
mod driller_top;
mod fatigue_buckling;
mod fem_identities;
mod field_wells;
mod modes_closed_form;
mod modes_sparse;
mod resting_shape;
mod sections;
mod simulator_energy;
mod simulator_failures;
mod simulator_physics;
mod spinning_shaft;
mod steady_shapes;
mod steady_stability;
mod stiffness_damping;
mod stresses;
mod torque_drag;
mod unreduced;
mod wall_laws;
mod wall_per_length;
