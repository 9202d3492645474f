//! The initial design of EGO: a maximin Latin hypercube inside the [`FeasibleSet`].
//!
//! A Latin hypercube of `k` points (McKay, Beckman & Conover 1979, *Technometrics* 21(2)) puts
//! exactly one point in each of the `k` equal strata of every variable (a random permutation of
//! the strata per variable, a uniform position inside each stratum). Of [`CANDIDATES`] such
//! designs, drawn from ChaCha20 seeded with the run's seed, the one whose smallest pairwise
//! distance is largest is kept (the maximin criterion of Morris & Mitchell 1995, which Jones,
//! Schonlau & Welch 1998 §4 recommend for the initial EGO design). A point outside the linear
//! constraints is replaced by its projection onto the set (Clarabel QP), so that every point of
//! the design is evaluated where the problem allows it; the maximin choice is made on the
//! projected points, so a design that piles points onto one edge loses to one that does not.

use rand::{RngExt as _, SeedableRng as _};
use rand_chacha::ChaCha20Rng;

use crate::optimize::{FeasibleSet, OptimizeError};

/// Latin hypercubes drawn; the maximin one is kept.
pub(crate) const CANDIDATES: usize = 32;

/// One Latin hypercube of `k` points in the box of `set`.
fn latin_hypercube(set: &FeasibleSet, k: usize, rng: &mut ChaCha20Rng) -> Vec<Vec<f64>> {
    let n = set.dim();
    let mut points = vec![vec![0.0; n]; k];
    for j in 0..n {
        // Fisher–Yates permutation of the strata 0..k.
        let mut strata: Vec<usize> = (0..k).collect();
        for i in (1..k).rev() {
            strata.swap(i, rng.random_range(0..=i));
        }
        let (lo, hi) = (set.lower()[j], set.upper()[j]);
        for (p, s) in points.iter_mut().zip(&strata) {
            let u = (*s as f64 + rng.random::<f64>()) / k as f64;
            p[j] = lo + u * (hi - lo);
        }
    }
    points
}

/// Smallest pairwise Euclidean distance of a design (+∞ for fewer than two points).
fn min_distance(points: &[Vec<f64>]) -> f64 {
    let mut d = f64::INFINITY;
    for (i, a) in points.iter().enumerate() {
        for b in &points[i + 1..] {
            let s: f64 = a.iter().zip(b).map(|(x, y)| (x - y) * (x - y)).sum();
            d = d.min(s.sqrt());
        }
    }
    d
}

/// The maximin Latin hypercube of `k` points projected into `set`, from `seed`.
pub(crate) fn initial_design(
    set: &FeasibleSet,
    k: usize,
    seed: u64,
) -> Result<Vec<Vec<f64>>, OptimizeError> {
    let mut rng = ChaCha20Rng::seed_from_u64(seed);
    let mut best: Option<(f64, Vec<Vec<f64>>)> = None;
    for _ in 0..CANDIDATES {
        let design = latin_hypercube(set, k, &mut rng)
            .iter()
            .map(|x| set.project(x))
            .collect::<Result<Vec<_>, _>>()?;
        let d = min_distance(&design);
        if best.as_ref().is_none_or(|(b, _)| d > *b) {
            best = Some((d, design));
        }
    }
    Ok(best.map(|(_, d)| d).unwrap_or_default())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One point per stratum of each variable (before projection), reproducible from the seed,
    /// every point inside the linear constraints after it.
    #[test]
    fn latin_strata_seeded_and_inside() {
        let unit = FeasibleSet::from_box(vec![0.0, 0.0], vec![1.0, 1.0]).unwrap();
        let d = initial_design(&unit, 10, 7).unwrap();
        for j in 0..2 {
            let mut strata: Vec<usize> = d.iter().map(|p| (p[j] * 10.0) as usize).collect();
            strata.sort_unstable();
            assert_eq!(strata, (0..10).collect::<Vec<_>>());
        }
        assert_eq!(d, initial_design(&unit, 10, 7).unwrap());
        assert_ne!(d, initial_design(&unit, 10, 8).unwrap());
        let cut = FeasibleSet::new(
            vec![0.0, 0.0],
            vec![1.0, 1.0],
            vec![vec![1.0, 1.0]],
            vec![1.0],
        )
        .unwrap();
        let d = initial_design(&cut, 12, 7).unwrap();
        assert_eq!(d.len(), 12);
        assert!(d.iter().all(|x| cut.contains(x, 1e-8)), "{d:?}");
    }
}
