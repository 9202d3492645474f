//! Statistics of a metric over Monte Carlo samples. Being built.
