//! Sequential sampling (issue 16, item 3; `[uncertain.sequential]`): the samples of each point
//! chosen by a stopping rule on the confidence of its score, instead of a fixed count.
//!
//! Rule ([`next_count`]): every point starts with `min_samples` samples; after each round a
//! point whose score's bootstrap interval ([`super::score::score_interval`]) is wider than
//! ± `score_half_width`, and that has fewer than `samples` (the most a point may use), doubles
//! its samples, capped at `samples`. A point stops at the first count that meets the target,
//! at `samples`, or when it has no score (a sample failed, or the score is not finite).
//!
//! Rounds ([`evaluate_in_rounds`]): round 1 is every point × `min_samples`; round r + 1 holds
//! the next batch of every point not yet stopped. Each round is one batch for the executor,
//! so threads and MPI ranks stay busy across points.
//!
//! Common random numbers: a point with n samples uses samples 0..n, and sample k is the same
//! draw (same seed, same cache key) at every point, so two points compared with different
//! counts share their first samples, and a resumed run answers every finished sample from the
//! cache and takes the same decisions (cached metrics are exact). Chance constraints keep their
//! point estimate over the samples run; the rule targets the score alone.
//!
//! The rule is a heuristic stopping rule on an estimated interval: the interval at the count
//! where it stops is not an exact (1 − α) interval (the count depends on the data, and the
//! bootstrap is itself approximate for small n), so `min_samples` should not be tiny.

use super::score::{PointEvaluation, SampleResult};
use crate::problem::study::Sequential;

/// The count a point needs next after a round, or None when it stops (see the module doc):
/// `eval` holds its samples so far; `max` is the most samples a point may use.
pub fn next_count(rule: &Sequential, max: usize, eval: &PointEvaluation) -> Option<usize> {
    let n = eval.samples_used;
    if n >= max || eval.objective.is_none() {
        return None;
    }
    match eval.score_half_width {
        Some(h) if h <= rule.score_half_width => None,
        _ => Some((2 * n).min(max)),
    }
}

/// Evaluate `n_points` points in rounds under `rule`, at most `max` samples each: `run` is
/// given each round's jobs, (point index, sample index) in point order and, per point, in
/// sample order, and returns one result per job in the same order; `score` scores a point
/// from all its samples so far (samples 0..n in order). Returns each point's last evaluation.
pub fn evaluate_in_rounds(
    rule: &Sequential,
    max: usize,
    n_points: usize,
    mut run: impl FnMut(&[(usize, usize)]) -> Vec<SampleResult>,
    score: impl Fn(usize, Vec<SampleResult>) -> PointEvaluation,
) -> Vec<PointEvaluation> {
    let mut results: Vec<Vec<SampleResult>> = vec![Vec::new(); n_points];
    let mut evals: Vec<Option<PointEvaluation>> = vec![None; n_points];
    let first = rule.min_samples.min(max);
    let mut wanted: Vec<(usize, usize)> = (0..n_points).map(|p| (p, first)).collect();
    while !wanted.is_empty() {
        let jobs: Vec<(usize, usize)> = wanted
            .iter()
            .flat_map(|&(p, n)| (results[p].len()..n).map(move |k| (p, k)))
            .collect();
        let done = run(&jobs);
        assert_eq!(done.len(), jobs.len(), "one result per job");
        for (&(p, _), r) in jobs.iter().zip(done) {
            results[p].push(r);
        }
        wanted = wanted
            .iter()
            .filter_map(|&(p, _)| {
                let eval = score(p, results[p].clone());
                let next = next_count(rule, max, &eval);
                evals[p] = Some(eval);
                next.map(|n| (p, n))
            })
            .collect();
    }
    evals
        .into_iter()
        .map(|e| e.expect("every point is scored in round 1"))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::OperatingPoint;
    use crate::problem::Problem;
    use crate::problem::study::Study;
    use crate::stats::{Distribution, SampleSet};
    use crate::study::score::{SampleOutcome, score};
    use std::cell::RefCell;
    use std::collections::BTreeMap;

    /// The tiny regression string's study with a mean-ROP score (no risk term) and the rule
    /// 8 → 64 samples, ± 0.5 m/h at 95 %.
    fn study() -> Study {
        let text = include_str!("../../problems/regression/tiny_string.toml").to_string()
            + "\n[uncertain]\nsamples = 64\nseed = 11\n[uncertain.sequential]\nmin_samples = 8\nscore_half_width = 0.5\n\
               [[uncertain.parameter]]\nkey = \"model.bit.friction\"\nlaw = \"gamma\"\nmean = \"0.04 m\"\ncov = 0.1\n";
        let mut study = Problem::from_toml(&text, std::path::Path::new("seq.toml"))
            .unwrap()
            .study;
        study.risk.clear();
        study
    }

    const OP: OperatingPoint = OperatingPoint {
        omega: 2.0 * std::f64::consts::PI,
        v0: 5.0 / 3600.0,
        wob: 0.0,
    };

    /// Synthetic stream: sample k of a point of spread `sigma` has ROP 10 + sigma·z_k (m/h),
    /// z_k the k-th unit normal of one seeded set (the same z_k at every point: common random
    /// numbers).
    fn stream(sigma: f64, n: usize) -> Vec<SampleResult> {
        let z = SampleSet::draw(
            &[Distribution::Normal {
                mean: 0.0,
                std: 1.0,
            }],
            n,
            3,
        )
        .column(0);
        z.iter()
            .enumerate()
            .map(|(k, z)| SampleResult {
                sample: k,
                seed: k as u64,
                outcome: SampleOutcome::Metrics(BTreeMap::from([(
                    "mean_rop_m_per_h".to_string(),
                    10.0 + sigma * z,
                )])),
                cached: false,
            })
            .collect()
    }

    #[test]
    fn a_constant_point_stops_at_min_and_a_noisy_one_grows_to_max_in_batches() {
        let study = study();
        let rule = study.sequential.unwrap();
        assert_eq!((rule.min_samples, study.samples), (8, 64));
        // Point 0 has no spread, point 1 a large one (± 1.96·5/√64 = 1.2 m/h at 64 samples),
        // point 2 a moderate one (± t·1.2/√n = 1.0, 0.64, 0.43 m/h at n = 8, 16, 32).
        let sigmas = [0.0, 5.0, 1.2];
        let streams: Vec<Vec<SampleResult>> = sigmas.iter().map(|&s| stream(s, 64)).collect();
        let rounds = RefCell::new(Vec::new());
        let evals = evaluate_in_rounds(
            &rule,
            study.samples,
            3,
            |jobs| {
                rounds.borrow_mut().push(jobs.to_vec());
                jobs.iter().map(|&(p, k)| streams[p][k].clone()).collect()
            },
            |_, samples| score(&study, OP, samples),
        );
        let used: Vec<usize> = evals.iter().map(|e| e.samples_used).collect();
        assert_eq!(used[0], 8, "{used:?}");
        assert_eq!(evals[0].score_half_width, Some(0.0));
        assert_eq!(used[1], 64, "{used:?}");
        assert!(evals[1].score_half_width.unwrap() > 0.5);
        assert!(used[2] > 8 && used[2] < 64, "{used:?}");
        // Point 2 stopped at the first count whose interval meets the target.
        let at = |n: usize| {
            score(&study, OP, streams[2][..n].to_vec())
                .score_half_width
                .unwrap()
        };
        assert!(
            at(used[2]) <= 0.5 && at(used[2] / 2) > 0.5,
            "{}",
            at(used[2])
        );
        assert_eq!(evals[2].score_half_width, Some(at(used[2])));
        // One batch per round: every point's first 8 samples, then the points still running,
        // each with its next samples, doubling.
        let rounds = rounds.into_inner();
        assert_eq!(rounds.len(), 4, "8 → 16 → 32 → 64");
        assert_eq!(rounds[0].len(), 24);
        assert!(rounds[0][..8].iter().enumerate().all(|(k, &j)| j == (0, k)));
        assert_eq!(rounds[1].iter().filter(|j| j.0 == 0).count(), 0);
        assert_eq!(rounds[1].iter().filter(|j| j.0 == 1).count(), 8);
        assert_eq!(rounds[1][0], (1, 8), "samples 8..16 follow 0..8");
        assert_eq!(rounds[3], (32..64).map(|k| (1, k)).collect::<Vec<_>>());
        let total: usize = rounds.iter().map(Vec::len).sum();
        assert_eq!(total, used.iter().sum::<usize>(), "no sample run twice");
        // The samples of a point are 0..n in order.
        for e in &evals {
            assert!(e.samples.iter().enumerate().all(|(k, s)| s.sample == k));
        }
    }

    /// Student's t quantile t_{n−1, 0.975}.
    fn t975(n: usize) -> f64 {
        use statrs::distribution::{ContinuousCDF, StudentsT};
        StudentsT::new(0.0, 1.0, (n - 1) as f64)
            .unwrap()
            .inverse_cdf(0.975)
    }

    /// The reported half-width falls as 1/√n: at n = 16, 64, 256 it is t·s/√n (s the standard
    /// deviation of those n samples, t Student's 97.5 % quantile) within the bootstrap's error,
    /// so it quarters from 16 to 256 samples as the spread of the stream settles.
    #[test]
    fn the_half_width_shrinks_as_one_over_root_n() {
        let study = study();
        let s = stream(2.0, 256);
        let rops = |n: usize| -> Vec<f64> {
            s[..n]
                .iter()
                .map(|r| match &r.outcome {
                    SampleOutcome::Metrics(m) => m["mean_rop_m_per_h"],
                    SampleOutcome::Failed(_) => unreachable!(),
                })
                .collect()
        };
        let hw = |n: usize| score(&study, OP, s[..n].to_vec()).score_half_width.unwrap();
        for n in [16, 64, 256] {
            let clt = t975(n) * crate::stats::std_dev(&rops(n)) / (n as f64).sqrt();
            println!("n = {n}: ± {:.4} m/h, CLT ± {clt:.4}", hw(n));
            assert!(
                (hw(n) / clt - 1.0).abs() < 0.08,
                "n = {n}: {} vs {clt}",
                hw(n)
            );
        }
        let quarter = hw(16) / hw(256);
        let spread = crate::stats::std_dev(&rops(16)) / crate::stats::std_dev(&rops(256));
        let t = t975(16) / t975(256);
        assert!(
            (quarter / (4.0 * spread * t) - 1.0).abs() < 0.12,
            "{quarter} for 4 × {spread} × {t}"
        );
        assert!(hw(256) < 0.3 && hw(16) > 0.6, "{} {}", hw(16), hw(256));
    }

    /// A mean-only score: its bootstrap half-width is the CLT's t s/√n (t = 1.984 at n = 100).
    #[test]
    fn a_mean_score_has_the_clt_half_width() {
        let mut study = study();
        study.sequential.as_mut().unwrap().resamples = 4000;
        let s = stream(3.0, 100);
        let e = score(&study, OP, s.clone());
        let rops: Vec<f64> = s
            .iter()
            .map(|r| match &r.outcome {
                SampleOutcome::Metrics(m) => m["mean_rop_m_per_h"],
                SampleOutcome::Failed(_) => unreachable!(),
            })
            .collect();
        let clt = t975(100) * crate::stats::std_dev(&rops) / 10.0;
        let hw = e.score_half_width.unwrap();
        assert!((hw / clt - 1.0).abs() < 0.06, "{hw} vs {clt}");
        let [lo, hi] = e.score_interval.unwrap();
        assert!(lo < e.objective.unwrap() && e.objective.unwrap() < hi);
    }

    /// A failed sample stops the point: more samples cannot give it a score.
    #[test]
    fn a_failed_point_stops() {
        let study = study();
        let rule = study.sequential.unwrap();
        let mut s = stream(5.0, 8);
        s[3].outcome = SampleOutcome::Failed("diverged".into());
        let e = score(&study, OP, s);
        assert_eq!(next_count(&rule, 64, &e), None);
        let e = score(&study, OP, stream(5.0, 8));
        assert_eq!(next_count(&rule, 64, &e), Some(16));
        assert_eq!(next_count(&rule, 12, &e), Some(12), "capped at the maximum");
        let e = score(&study, OP, stream(5.0, 12));
        assert_eq!(next_count(&rule, 12, &e), None, "at the maximum");
    }
}
