//! One simulation of the nonlinear reduced-order drillstring model: force laws (wall contact,
//! bit–rock), the recorded time history, and the run itself.

mod bit_rock;
mod contact;
mod dynamics;
mod run;
mod series;

pub use bit_rock::{BitLoad, bit_rock, xi};
pub use contact::{NodeContact, wall_contact};
pub use dynamics::{Dynamics, Effects, Observation};
pub use run::{
    IMPACT_SEPARATION, InitialState, RunOutput, RunSettings, SimulationError, SolverStats,
    run_problem, simulate, static_equilibrium,
};
pub use series::TimeSeries;
