//! Problem files: the loader's refusals (one per fault, in the user's units), the admissible
//! ranges, the study sections and the fuzzing of the shipped files.
//!
//! One test binary of several (`cargo test --release --test problem`; a file's tests alone:
//! `cargo test --release --test problem -- <file>::`): each module is one former tests/<file>.rs.

mod admissible_ranges;
mod constraint_refusals;
mod explore_validation;
mod issue13_refusals;
mod problem_fuzz;
mod problem_one_pass;
mod problem_validation;
mod study_validation;
