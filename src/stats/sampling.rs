//! Seeded Monte Carlo samples of the uncertain parameters.
//!
//! # Reproducibility contract
//! Sample `i` of a draw with master seed `m` is a pure function of (`m`, `i`, the laws in
//! declaration order):
//!
//! 1. its seed is `s = sample_seed(m, i)`, the (i+1)-th output of SplitMix64 (Steele, Lea &
//!    Flood 2014; Vigna's `splitmix64.c`) started from state `m`:
//!    `s = mix(m + (i+1)·0x9E3779B97F4A7C15)` (wrapping arithmetic), see [`splitmix64_mix`].
//!    This is written out here, not taken from a crate, so it cannot change with a dependency;
//!    it is tested against the reference outputs of `splitmix64.c`;
//! 2. its generator is ChaCha20 ([`SampleRng`], `rand_chacha` 0.10) keyed with the 32 bytes of
//!    the next four SplitMix64 outputs from state `s`, little-endian (again written out, rather
//!    than `seed_from_u64`, whose expansion rand does not promise to keep);
//! 3. its values are drawn from that generator, one law after the other in declaration order.
//!
//! So sample `i` does not depend on `n`, on the number of threads or on the order in which
//! samples are evaluated. The values depend on the sampling algorithms of `rand_distr` 0.6 (the
//! seeds do not): a major upgrade of `rand_distr` may change the values, never the seeds.
//!
//! Two master seeds that differ by a multiple k of the SplitMix64 increment give shifted
//! sequences (sample i of one is sample i + k of the other); ordinary seeds (0, 1, 42, …) are
//! nowhere near that.
//!
//! # No uncertainty
//! `n = 0` (or no uncertain parameter) means the nominal model: use [`SampleSet::nominal`] (or
//! [`SampleSet::draw_or_nominal`]), one sample of index 0 with no values, whose seed does not
//! depend on the master seed, so nominal cache entries are shared between runs.

use rand::SeedableRng;
use rand_chacha::ChaCha20Rng;
use serde::Serialize;

use super::Distribution;

/// The generator of one sample: ChaCha20 from `rand_chacha` 0.10 (rand 0.10 traits).
pub type SampleRng = ChaCha20Rng;

/// SplitMix64 increment, the odd integer closest to 2⁶⁴/φ.
const GOLDEN_GAMMA: u64 = 0x9E37_79B9_7F4A_7C15;

/// The SplitMix64 output function (Stafford's "Mix13" variant): a bijection of u64.
pub fn splitmix64_mix(state: u64) -> u64 {
    let mut z = state;
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// Seed of sample `index` under `master_seed`: the (index+1)-th output of SplitMix64 started at
/// `master_seed`. Stable across versions and platforms (see the module doc).
pub fn sample_seed(master_seed: u64, index: usize) -> u64 {
    let step = (index as u64).wrapping_add(1).wrapping_mul(GOLDEN_GAMMA);
    splitmix64_mix(master_seed.wrapping_add(step))
}

/// The generator of the sample whose seed is `seed`: ChaCha20 keyed with the first four
/// SplitMix64 outputs from state `seed`, little-endian.
pub fn sample_rng(seed: u64) -> SampleRng {
    let mut key = [0u8; 32];
    for (i, chunk) in key.chunks_exact_mut(8).enumerate() {
        chunk.copy_from_slice(&sample_seed(seed, i).to_le_bytes());
    }
    SampleRng::from_seed(key)
}

/// One Monte Carlo sample: the values of the uncertain parameters, in declaration order.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Sample {
    /// Position of the sample in its set, from 0.
    pub index: usize,
    /// Seed of the sample, [`sample_seed`]`(master_seed, index)`; also the seed to give any
    /// randomness inside the evaluation of this sample.
    pub seed: u64,
    /// One value per uncertain parameter, in declaration order; empty for the nominal sample.
    pub values: Vec<f64>,
}

impl Sample {
    /// Sample `index` under `master_seed` for the laws `dists` (see the module doc).
    ///
    /// # Panics
    /// If a law fails [`Distribution::validate`].
    pub fn draw(dists: &[Distribution], index: usize, master_seed: u64) -> Self {
        let seed = sample_seed(master_seed, index);
        let mut rng = sample_rng(seed);
        let values = dists.iter().map(|d| d.sample(&mut rng)).collect();
        Self {
            index,
            seed,
            values,
        }
    }
}

/// The samples of one robust evaluation, with the master seed they came from.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SampleSet {
    /// Seed from which every sample seed is derived.
    pub master_seed: u64,
    /// Samples 0..n in index order.
    pub samples: Vec<Sample>,
}

impl SampleSet {
    /// Samples 0..`n` of the laws `dists` under `master_seed`. `n = 0` gives an empty set; see
    /// [`SampleSet::nominal`] for the no-uncertainty case.
    ///
    /// # Panics
    /// If a law fails [`Distribution::validate`].
    pub fn draw(dists: &[Distribution], n: usize, master_seed: u64) -> Self {
        Self {
            master_seed,
            samples: (0..n)
                .map(|i| Sample::draw(dists, i, master_seed))
                .collect(),
        }
    }

    /// The nominal (deterministic) case: one sample, index 0, no values, master seed 0. Equal to
    /// `SampleSet::draw(&[], 1, 0)`.
    pub fn nominal() -> Self {
        Self::draw(&[], 1, 0)
    }

    /// [`draw`](Self::draw) when there is something to sample (`n > 0` and at least one law),
    /// else [`nominal`](Self::nominal).
    pub fn draw_or_nominal(dists: &[Distribution], n: usize, master_seed: u64) -> Self {
        if n == 0 || dists.is_empty() {
            Self::nominal()
        } else {
            Self::draw(dists, n, master_seed)
        }
    }

    /// Number of samples.
    pub fn len(&self) -> usize {
        self.samples.len()
    }

    /// Whether the set holds no sample.
    pub fn is_empty(&self) -> bool {
        self.samples.is_empty()
    }

    /// The values of parameter `param` (declaration order) across the samples.
    pub fn column(&self, param: usize) -> Vec<f64> {
        self.samples.iter().map(|s| s.values[param]).collect()
    }
}
