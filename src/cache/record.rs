//! What one cache line holds: the key of an evaluation, its outcome and optional information.

use serde::{Deserialize, Deserializer, Serialize, Serializer};
use std::collections::BTreeMap;

/// Identifies one simulation: operating point, Monte Carlo sample and model.
///
/// The operating point is stored as the bit patterns of the f64 values, so that two points are
/// the same key exactly when they are the same floats (no rounding, no tolerance).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CacheKey {
    /// `f64::to_bits` of the top rotation speed Ω, rad/s.
    pub omega_bits: u64,
    /// `f64::to_bits` of the set-point: the top axial velocity V0, m/s, or under a hook load (the
    /// model hash holds the top) the WOB set-point, N.
    pub v0_bits: u64,
    /// Index of the Monte Carlo sample (0 for the nominal model).
    pub sample: u32,
    /// Seed of that sample (see `stats::sample_seed`); with `sample` it pins the values.
    pub sample_seed: u64,
    /// [`stable_hash`](super::stable_hash) of everything else the simulation depends on (model,
    /// numerical settings, metric definitions); changing any of them must change this hash.
    pub model_hash: u64,
}

impl CacheKey {
    /// The key of the simulation at (Ω = `omega` rad/s, V0 = `v0` m/s) for sample `sample`.
    ///
    /// # Panics
    /// If `sample` does not fit in a u32.
    pub fn new(omega: f64, v0: f64, sample: usize, sample_seed: u64, model_hash: u64) -> Self {
        Self {
            omega_bits: omega.to_bits(),
            v0_bits: v0.to_bits(),
            sample: u32::try_from(sample).expect("sample index fits in a u32"),
            sample_seed,
            model_hash,
        }
    }

    /// Top rotation speed Ω, rad/s.
    pub fn omega(&self) -> f64 {
        f64::from_bits(self.omega_bits)
    }

    /// Top axial velocity V0, m/s.
    pub fn v0(&self) -> f64 {
        f64::from_bits(self.v0_bits)
    }
}

/// Result of one simulation: its metrics, or why it failed (a failure is data too: it is cached
/// so that a design point that crashes the simulator is not retried on resume).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "status", rename_all = "snake_case", deny_unknown_fields)]
pub enum Outcome {
    /// The simulation finished; metric name → value (any f64, including NaN and ±∞).
    Ok {
        #[serde(with = "exact_f64_map")]
        metrics: BTreeMap<String, f64>,
    },
    /// The simulation failed; the message says why.
    Failed { message: String },
}

/// Optional information stored next to an outcome, for reports; not part of the key.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct EvalInfo {
    /// Wall-clock time of the simulation, s.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wall_time_s: Option<f64>,
    /// drillopt version that ran it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub version: Option<String>,
}

/// A line as written. `omega` and `v0` repeat the key's bits as numbers for people reading
/// the file (e.g. with `jq`); they are ignored when reading.
#[derive(Serialize)]
pub(super) struct RecordOut<'a> {
    pub key: &'a CacheKey,
    pub omega: f64,
    pub v0: f64,
    pub outcome: &'a Outcome,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub info: Option<&'a EvalInfo>,
}

/// A line as read: unknown fields (such as `omega`, `v0`) are ignored so that later versions
/// may add some.
#[derive(Deserialize)]
pub(super) struct RecordIn {
    pub key: CacheKey,
    pub outcome: Outcome,
    #[serde(default)]
    pub info: Option<EvalInfo>,
}

/// Metric values written as JSON strings holding Rust's shortest round-trip decimal form
/// (`"0.1"`, `"1e-7"`, `"NaN"`, `"inf"`, `"-inf"`, `"-0.0"`) and read back with `str::parse`,
/// which rounds correctly: every f64, non-finite ones included, comes back bit for bit (NaN
/// payloads aside).
///
/// Why not JSON numbers: JSON has no NaN/∞, and serde_json parses numbers exactly only with its
/// `float_roundtrip` feature (without it about 30 % of random f64s come back one ulp off);
/// drillopt does not enable that feature itself. Plain JSON numbers are still accepted when
/// reading (best effort), for hand-written files.
mod exact_f64_map {
    use super::*;

    #[derive(Deserialize)]
    #[serde(untagged)]
    enum Repr {
        Text(String),
        Number(f64),
    }

    pub fn serialize<S: Serializer>(map: &BTreeMap<String, f64>, s: S) -> Result<S::Ok, S::Error> {
        s.collect_map(map.iter().map(|(k, v)| (k, format!("{v:?}"))))
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<BTreeMap<String, f64>, D::Error> {
        BTreeMap::<String, Repr>::deserialize(d)?
            .into_iter()
            .map(|(k, r)| match r {
                Repr::Number(v) => Ok((k, v)),
                Repr::Text(t) => t
                    .trim()
                    .parse::<f64>()
                    .map(|v| (k.clone(), v))
                    .map_err(|e| {
                        serde::de::Error::custom(format!(
                            "metric `{k}` = {t:?} is not a number: {e}"
                        ))
                    }),
            })
            .collect()
    }
}
