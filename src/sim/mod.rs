//! One simulation of the nonlinear reduced-order drillstring model: force laws (wall contact,
//! bit–rock), the recorded time history, and the run itself.

mod series;

pub use series::TimeSeries;
