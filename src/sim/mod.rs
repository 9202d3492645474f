//! One simulation of the nonlinear reduced-order drillstring model: force laws (wall contact,
//! bit–rock), the recorded time history, and the run itself.

mod bit_rock;
mod contact;
mod series;

pub use bit_rock::{BitLoad, bit_rock, xi};
pub use contact::{NodeContact, wall_contact};
pub use series::TimeSeries;
