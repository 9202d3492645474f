//! Derivative-free optimisation inside linear constraints (issue 4). Being built.
