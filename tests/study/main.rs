//! Studies: the optimizers on analytic problems, solve and map end to end (multi-fidelity,
//! sequential sampling, resume, status), the evaluation cache and the regression set.
//!
//! One test binary of several (`cargo test --release --test study`; a file's tests alone:
//! `cargo test --release --test study -- <file>::`): each module is one former tests/<file>.rs.

#[path = "../common/mod.rs"]
mod common;

mod bench_problem;
mod cache_key;
mod hook_load_study;
mod multi_fidelity;
mod optimizer_analytic;
mod optimizer_ego;
mod regression_set;
mod sequential_sampling;
mod solve_status;
mod study_solve;
