//! Time integrals and time averages over non-uniformly spaced samples, by the trapezoid rule.
//!
//! Every function takes the sample times `t` (strictly increasing, at least two) and the values
//! `y` at those times (same length). Each interval [tᵢ, tᵢ₊₁] contributes (tᵢ₊₁ − tᵢ)(yᵢ + yᵢ₊₁)/2,
//! so a sample's weight is half the sum of its two adjacent steps, never 1/n.

/// ∫ y dt over [t₀, t_end] (trapezoid rule), in the units of y times seconds.
pub(crate) fn integral(t: &[f64], y: &[f64]) -> f64 {
    debug_assert_eq!(t.len(), y.len());
    t.windows(2)
        .zip(y.windows(2))
        .map(|(tw, yw)| 0.5 * (tw[1] - tw[0]) * (yw[0] + yw[1]))
        .sum()
}

/// Length t_end − t₀ of the sampled interval, s.
pub(crate) fn duration(t: &[f64]) -> f64 {
    t[t.len() - 1] - t[0]
}

/// Time-weighted mean (1/T) ∫ y dt.
pub(crate) fn mean(t: &[f64], y: &[f64]) -> f64 {
    integral(t, y) / duration(t)
}

/// Time-weighted standard deviation √((1/T) ∫ (y − ȳ)² dt), ȳ the time-weighted mean; the
/// integral is the trapezoid rule on the sampled squared deviations.
pub(crate) fn std_dev(t: &[f64], y: &[f64]) -> f64 {
    let m = mean(t, y);
    let sq: Vec<f64> = y.iter().map(|&v| (v - m) * (v - m)).collect();
    mean(t, &sq).max(0.0).sqrt()
}

/// Share of time in [0, 1] during which `condition` holds: the trapezoid rule applied to the
/// indicator of the condition, so an interval whose two ends disagree counts for half its length
/// (the error is at most half a step per change of state).
#[cfg(test)] // the streamed accumulators (`online`) fold the same way
pub(crate) fn share(t: &[f64], y: &[f64], condition: impl Fn(f64) -> bool) -> f64 {
    let indicator: Vec<f64> = y
        .iter()
        .map(|&v| if condition(v) { 1.0 } else { 0.0 })
        .collect();
    mean(t, &indicator)
}

/// Largest sample value (no interpolation between samples).
#[cfg(test)] // the streamed accumulators (`online`) fold the same way
pub(crate) fn max(y: &[f64]) -> f64 {
    y.iter().copied().fold(f64::NEG_INFINITY, f64::max)
}

/// Smallest sample value (no interpolation between samples).
#[cfg(test)] // the streamed accumulators (`online`) fold the same way
pub(crate) fn min(y: &[f64]) -> f64 {
    y.iter().copied().fold(f64::INFINITY, f64::min)
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    // Steps 1, 3, 0.5: a sample mean or a left-endpoint rule gives different numbers.
    const T: [f64; 4] = [0.0, 1.0, 4.0, 4.5];

    #[test]
    fn integral_is_exact_for_piecewise_linear_data_on_uneven_steps() {
        let y = [2.0, 4.0, 10.0, 0.0];
        // 1·(2+4)/2 + 3·(4+10)/2 + 0.5·(10+0)/2 = 3 + 21 + 2.5
        assert_relative_eq!(integral(&T, &y), 26.5, max_relative = 1e-15);
        assert_relative_eq!(mean(&T, &y), 26.5 / 4.5, max_relative = 1e-15);
        // A linear function is integrated exactly whatever the steps: ∫₀^4.5 (3t − 1) dt.
        let lin: Vec<f64> = T.iter().map(|&t| 3.0 * t - 1.0).collect();
        assert_relative_eq!(
            integral(&T, &lin),
            1.5 * 4.5 * 4.5 - 4.5,
            max_relative = 1e-15
        );
    }

    #[test]
    fn std_dev_weights_by_step_length() {
        let y = [0.0, 4.0, 1.0];
        let t = [0.0, 1.0, 4.0];
        // mean = (1·2 + 3·2.5)/4 = 2.375; deviations² = 5.640625, 2.640625, 1.890625;
        // ∫ = 1·4.140625 + 3·2.265625 = 10.9375.
        assert_relative_eq!(
            std_dev(&t, &y),
            (10.9375f64 / 4.0).sqrt(),
            max_relative = 1e-14
        );
        assert_eq!(std_dev(&t, &[3.0, 3.0, 3.0]), 0.0);
    }

    #[test]
    fn share_counts_state_changes_half_and_weights_by_step() {
        let y = [1.0, 0.0, 0.0, 1.0];
        // Intervals: [0,1] half, [1,4] full, [4,4.5] half → (0.5 + 3 + 0.25) / 4.5.
        assert_relative_eq!(
            share(&T, &y, |v| v == 0.0),
            3.75 / 4.5,
            max_relative = 1e-15
        );
        assert_eq!(share(&T, &y, |v| v > 5.0), 0.0);
        assert_eq!(share(&T, &y, |v| v < 5.0), 1.0);
    }

    #[test]
    fn extremes_of_samples() {
        let y = [1.0, -3.0, 7.5, 2.0];
        assert_eq!(max(&y), 7.5);
        assert_eq!(min(&y), -3.0);
    }
}
