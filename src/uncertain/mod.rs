//! Uncertain parameters: distributions and seeded Monte Carlo samples (issue 4). Being built.
