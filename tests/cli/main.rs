//! The drillopt binary end to end: exit status, refusals of the command line, output folders,
//! quiet and broken-pipe output, time series, interrupted and killed runs, compare and campbell.
//!
//! One test binary of several (`cargo test --release --test cli`; a file's tests alone:
//! `cargo test --release --test cli -- <file>::`): each module is one former tests/<file>.rs.

#[path = "../common/mod.rs"]
mod common;

mod broken_pipe;
mod campbell_cli;
mod cli_exit_status;
mod cli_overrides;
mod compare_feasibility;
mod converged_model;
mod keys_reference;
mod off_bottom;
mod output_dirs;
mod quiet_output;
mod timeseries_output;
