//! An argmin observer that records the optimiser's path and drives an optional user callback
//! (e.g. a progress bar).
//!
//! The solvers of this module put two keys in their per-iteration argmin `KV`: `"evals"`
//! (black-box evaluations so far, an unsigned integer), for the trust-region method `"radius"`
//! (trust-region radius, variable units) and `"step"` (what the iteration did); Nelder–Mead
//! reports its `"action"`. The observer turns each argmin iteration
//! (and the state after `init`) into one [`Iterate`].

use std::sync::{Arc, Mutex};

use argmin::core::{Error, KV, State, observers::Observe};

/// One point of an optimiser's path.
#[derive(Clone, Debug, PartialEq)]
pub struct Iterate {
    /// Sequence number over the whole run, from 0 (the state after the initial design); restarts
    /// of Nelder–Mead continue the count.
    pub iteration: usize,
    /// Current iterate (trust-region centre, best simplex vertex, swarm best).
    pub x: Vec<f64>,
    /// The solver's cost at `x`: the merit `f + μ Σ max(0, c_j)` (plus the projection penalty for
    /// Nelder–Mead and the swarm).
    pub merit: f64,
    /// Trust-region radius (variable units), for the trust-region method only.
    pub radius: Option<f64>,
    /// Black-box evaluations so far.
    pub evaluations: usize,
    /// What the iteration did, when the solver says (trust region: `"trust region"`,
    /// `"geometry"`, `"shrink (…)"`, …; Nelder–Mead: the simplex action).
    pub step: Option<String>,
}

/// A user callback called with every new [`Iterate`].
pub type IterateCallback = Box<dyn FnMut(&Iterate) + Send>;

/// Shared log of the path.
pub type PathLog = Arc<Mutex<Vec<Iterate>>>;

/// Observer appending every iterate to a shared [`PathLog`].
pub struct PathObserver {
    log: PathLog,
    callback: Option<IterateCallback>,
}

impl PathObserver {
    /// A new observer writing into `log` and calling `callback` after each record.
    pub fn new(log: PathLog, callback: Option<IterateCallback>) -> Self {
        PathObserver { log, callback }
    }

    /// Gives the callback back (so that restarts can move it to a new observer).
    pub fn into_callback(self) -> Option<IterateCallback> {
        self.callback
    }

    fn record<I: State<Param = Vec<f64>, Float = f64>>(&mut self, state: &I, kv: &KV) {
        let Some(x) = state.get_param() else {
            return;
        };
        let evaluations = kv
            .get("evals")
            .and_then(|v| v.get_uint().or(v.get_int().map(|i| i.max(0) as u64)))
            .unwrap_or(0) as usize;
        let radius = kv.get("radius").and_then(|v| v.get_float());
        let step = kv
            .get("step")
            .or_else(|| kv.get("action"))
            .and_then(|v| v.get_string());
        let mut log = self.log.lock().unwrap_or_else(|p| p.into_inner());
        let it = Iterate {
            iteration: log.len(),
            x: x.clone(),
            merit: state.get_cost(),
            radius,
            evaluations,
            step,
        };
        log.push(it.clone());
        drop(log);
        if let Some(cb) = self.callback.as_mut() {
            cb(&it);
        }
    }
}

impl<I: State<Param = Vec<f64>, Float = f64>> Observe<I> for PathObserver {
    fn observe_init(&mut self, _name: &str, state: &I, kv: &KV) -> Result<(), Error> {
        self.record(state, kv);
        Ok(())
    }

    fn observe_iter(&mut self, state: &I, kv: &KV) -> Result<(), Error> {
        self.record(state, kv);
        Ok(())
    }
}

/// Adapter so that one callback can be shared by several observers (restarts).
pub(crate) struct SharedCallback(pub(crate) Arc<Mutex<Option<IterateCallback>>>);

impl SharedCallback {
    pub(crate) fn boxed(&self) -> Option<IterateCallback> {
        let inner = Arc::clone(&self.0);
        let has = inner.lock().map(|c| c.is_some()).unwrap_or(false);
        if !has {
            return None;
        }
        Some(Box::new(move |it: &Iterate| {
            if let Ok(mut guard) = inner.lock()
                && let Some(cb) = guard.as_mut()
            {
                cb(it);
            }
        }))
    }
}

/// The recorded path (a copy).
pub(crate) fn take_path(log: &PathLog) -> Vec<Iterate> {
    log.lock().map(|l| l.clone()).unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;
    use argmin::core::{IterState, KvValue};

    #[test]
    fn records_iterates_and_calls_back() {
        let log: PathLog = Arc::new(Mutex::new(Vec::new()));
        let seen = Arc::new(Mutex::new(0usize));
        let seen2 = Arc::clone(&seen);
        let mut obs = PathObserver::new(
            Arc::clone(&log),
            Some(Box::new(move |_it: &Iterate| *seen2.lock().unwrap() += 1)),
        );
        let state: IterState<Vec<f64>, (), (), (), (), f64> =
            IterState::new().param(vec![1.0, 2.0]).cost(3.0);
        let mut kv = KV::new();
        kv.insert("evals", KvValue::Uint(5));
        obs.observe_init("t", &state, &kv).unwrap();
        kv.insert("evals", KvValue::Uint(6));
        kv.insert("radius", KvValue::Float(0.5));
        obs.observe_iter(&state, &kv).unwrap();
        let path = take_path(&log);
        assert_eq!(path.len(), 2);
        assert_eq!(path[1].iteration, 1);
        assert_eq!(path[1].evaluations, 6);
        assert_eq!(path[1].radius, Some(0.5));
        assert_eq!(path[0].merit, 3.0);
        assert_eq!(*seen.lock().unwrap(), 2);
    }
}
