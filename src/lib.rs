//! drillopt: robust operating-point optimisation of horizontal drillstrings.
//!
//! The data flow mirrors the modules: [`problem`] (TOML schema, validation) → [`model`] (physical
//! parameters) → [`fem`] (beam element, assembly, boundary conditions) → [`rom`] (modes) → …
//! The physics is that of `MODEL.md` (Cunha Jr, Soize & Sampaio 2014, with its settled choices).

pub mod cache;
pub mod campbell;
pub mod cli;
pub mod fatigue;
pub mod fem;
pub mod hash;
pub mod integrate;
pub mod metrics;
pub mod model;
pub mod optimize;
pub mod problem;
pub mod report;
pub mod rom;
pub mod sim;
pub mod solve;
pub mod stats;
pub mod study;
pub mod units;
pub mod verify;

/// Version of drillopt, recorded in every result file.
pub const VERSION: &str = env!("CARGO_PKG_VERSION");

#[cfg(test)]
mod file_cycles;
