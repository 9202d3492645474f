//! The robust objective (issue 4).

pub mod statistic;
