//! The robust evaluation of operating points: every point is simulated for every Monte Carlo
//! sample (the same samples at every point: common random numbers) and scored by [`super::score`].
//!
//! The (point, sample) simulations of a batch are handed to a [`SampleExecutor`] (threads by
//! default); each result is looked up in, and stored to, the evaluation cache first, so no
//! simulation runs twice and an interrupted run resumes without losing finished work. A
//! simulation that fails (diverges, leaves the finite range, cannot step) makes its point
//! infeasible; it is recorded, never a crash.

use super::Fidelity;
use super::executor::{SampleExecutor, SampleJob, Simulated, Threads};
use super::score::{PointEvaluation, SampleOutcome, SampleResult, metric_map, score};
use super::sequential::evaluate_in_rounds;
use crate::cache::{CacheKey, EvalCache, EvalInfo, Outcome, stable_hash};
use crate::campbell::{self, LinearSystem, Linearisation, MarginTable};
use crate::metrics;
use crate::model::{Drillstring, Enters, OperatingPoint};
use crate::problem::Problem;
use crate::rom::{BasisError, ReducedModel};
use crate::sim::{Effects, InitialState, RunSettings, simulate};
use crate::stats::{Distribution, SampleSet};
use rayon::prelude::*;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, OnceLock};
use std::time::Instant;

/// Counters of work done (for notes and the resume test).
#[derive(Debug, Default)]
pub struct WorkCounters {
    /// Simulations actually run.
    pub simulated: AtomicUsize,
    /// Simulations answered by the cache.
    pub cached: AtomicUsize,
    /// Simulations that failed.
    pub failed: AtomicUsize,
}

/// Evaluates operating points of one problem robustly.
pub struct RobustEvaluator<'a> {
    pub problem: &'a Problem,
    pub samples: SampleSet,
    /// One reduced model per sample (shared when no uncertain parameter changes the operators).
    models: Vec<Arc<ReducedModel>>,
    /// The critical speeds of each sample's model, searched once, on first use, over the
    /// windows of [`RobustEvaluator::margin_range`]; samples that differ in bit parameters
    /// only share one (`margin_owner`).
    margins: Vec<OnceLock<Option<MarginTable>>>,
    margin_owner: Vec<usize>,
    /// The rotation speeds the tables answer for, rad/s: the `[constraints]` bounds of Ω, else
    /// the admissible 1–1000 rpm.
    margin_range: [f64; 2],
    settings: RunSettings,
    cache: Option<&'a EvalCache>,
    pub model_hash: u64,
    pub counters: WorkCounters,
    progress: Option<Box<dyn Fn() + Sync + 'a>>,
    executor: Box<dyn SampleExecutor + 'a>,
    /// The fidelity its evaluations are tagged with ([`Fidelity::Full`] unless set).
    fidelity: Fidelity,
    /// What became of the steady-state shapes of the models' basis (the nominal string's).
    pub steady_shapes: crate::rom::SteadyStatus,
}

/// Why the evaluator could not be set up.
#[derive(Debug, thiserror::Error)]
pub enum SetupError {
    #[error("modal analysis of sample {sample}: {source}")]
    Modes { sample: usize, source: BasisError },
    #[error(
        "sample {sample} draws {key} = {value}, which is not admissible (it {why}); narrow its law in [[uncertain.parameter]]"
    )]
    Inadmissible {
        sample: usize,
        key: &'static str,
        value: f64,
        why: String,
    },
}

/// Everything that determines a simulation's result apart from the operating point and the
/// sample, in canonical form: JSON with fields in declaration order and every float written in
/// its shortest exact form, so equal inputs give equal bytes whatever the Rust version or the
/// layout of the structs' `Debug` output.
#[derive(serde::Serialize)]
struct CanonicalModel<'a> {
    /// Revision of the numerics ([`crate::sim::SIMULATOR_REVISION`]): bumped by any change that
    /// can move a simulated number.
    simulator_revision: u32,
    model: &'a Drillstring,
    mesh: &'a crate::model::Mesh,
    simulation: &'a crate::model::Simulation,
    /// Integrator settings, step limits and probes of every run.
    run: &'a RunSettings,
    /// The uncertain parameters and their laws, in declaration order.
    uncertain: Vec<(&'a str, Distribution)>,
    /// `[campbell]`: the excitation multiple of `critical_speed_margin`.
    campbell: &'a crate::model::CampbellSettings,
    /// Which excitations `critical_speed_margin` meets each family with
    /// ([`crate::campbell::CRITICAL_SPEED_RULE`]).
    critical_speed_rule: u32,
    /// The operating point whose steady state the basis holds (`[mesh.basis] steady_shapes`);
    /// left out without them, so that other problems keep their keys.
    #[serde(skip_serializing_if = "Option::is_none")]
    steady_shapes_at: Option<crate::model::OperatingPoint>,
}

/// [`stable_hash`] of the canonical serialisation of everything that determines a simulation's
/// result apart from the operating point and the sample: the simulator revision, the model (bit
/// law by name and parameters), mesh and basis, simulation window and start, integrator
/// settings, the uncertain laws and the excitation multiple of the critical speeds. The
/// drillopt version is not part of it: a release that does not change the numerics keeps its
/// cache.
pub fn model_hash(problem: &Problem) -> u64 {
    let run = run_settings(problem);
    let canonical = CanonicalModel {
        simulator_revision: crate::sim::SIMULATOR_REVISION,
        model: &problem.model,
        mesh: &problem.mesh,
        simulation: &problem.simulation,
        run: &run,
        uncertain: problem
            .study
            .uncertain
            .iter()
            .map(|u| (u.key.name(), u.law))
            .collect(),
        campbell: &problem.campbell,
        critical_speed_rule: crate::campbell::CRITICAL_SPEED_RULE,
        steady_shapes_at: problem
            .mesh
            .basis
            .steady_shapes()
            .then_some(problem.operating_point),
    };
    let bytes = serde_json::to_vec(&canonical).expect("the model serialises");
    stable_hash(&bytes)
}

/// The settings of every run of a problem's study.
fn run_settings(problem: &Problem) -> RunSettings {
    let sim = &problem.simulation;
    let mut settings = RunSettings::new(sim.duration, sim.time_step);
    settings.probes = sim.probes.clone();
    settings.envelope_from = sim.settling_for(sim.duration);
    settings
}

impl<'a> RobustEvaluator<'a> {
    /// Draw the samples and build the reduced models.
    pub fn new(problem: &'a Problem, cache: Option<&'a EvalCache>) -> Result<Self, SetupError> {
        let study = &problem.study;
        let laws: Vec<Distribution> = study.uncertain.iter().map(|u| u.law).collect();
        let samples = SampleSet::draw_or_nominal(&laws, study.samples, study.seed);
        let strings = samples
            .samples
            .iter()
            .map(|s| {
                let mut string = problem.model.clone();
                for (u, &value) in study.uncertain.iter().zip(&s.values) {
                    if let Err(why) = u.key.admissible(&string, value) {
                        return Err(SetupError::Inadmissible {
                            sample: s.index,
                            key: u.key.name(),
                            value,
                            why,
                        });
                    }
                    u.key.apply(&mut string, value);
                }
                Ok(string)
            })
            .collect::<Result<Vec<Drillstring>, _>>()?;
        let rebuild = study
            .uncertain
            .iter()
            .any(|u| u.key.enters(&problem.model) == Enters::LinearOperators);
        // The steady-state shapes (when the basis asks for them) are the nominal string's at the
        // problem's operating point, for every sample: a sample's basis does not depend on which
        // other keys are uncertain.
        let modes = |i: usize| move |source| SetupError::Modes { sample: i, source };
        let nominal_steady = if problem.mesh.basis.steady_shapes() {
            let plain =
                ReducedModel::new(&problem.model, problem.mesh.elements, &problem.mesh.basis)
                    .map_err(modes(0))?;
            Some(crate::sim::finite_element_steady_state(
                &plain,
                problem.operating_point,
            ))
        } else {
            None
        };
        let steady_shapes = match &nominal_steady {
            None => crate::rom::SteadyStatus::NotAsked,
            Some(Ok(found)) => found.status(),
            Some(Err(status)) => *status,
        };
        let build = |i: usize, s: &Drillstring| match &nominal_steady {
            Some(Ok(found)) => {
                crate::sim::reduced_model_with(s, &problem.mesh, found).map_err(modes(i))
            }
            Some(Err(status)) => ReducedModel::new(s, problem.mesh.elements, &problem.mesh.basis)
                .map(|m| crate::sim::with_status(m, *status))
                .map_err(modes(i)),
            None => {
                ReducedModel::new(s, problem.mesh.elements, &problem.mesh.basis).map_err(modes(i))
            }
        };
        let models = if rebuild {
            strings
                .par_iter()
                .enumerate()
                .map(|(i, s)| build(i, s).map(Arc::new))
                .collect::<Result<Vec<_>, _>>()?
        } else {
            let nominal = build(0, &problem.model)?;
            strings
                .iter()
                .map(|s| {
                    // Bit, wall and (without annulus fluid) borehole parameters act in the
                    // nonlinear forces only.
                    let mut m = nominal.clone();
                    m.string = s.clone();
                    Arc::new(m)
                })
                .collect()
        };
        let settings = run_settings(problem);
        // Bit parameters do not enter the string linearised at rest: samples that agree on every
        // other parameter share their critical speeds.
        let linear_values = |i: usize| -> Vec<u64> {
            study
                .uncertain
                .iter()
                .zip(&samples.samples[i].values)
                .filter(|(u, _)| !u.key.name().starts_with("model.bit."))
                .map(|(_, v)| v.to_bits())
                .collect()
        };
        let margin_owner: Vec<usize> = (0..models.len())
            .map(|i| {
                (0..=i)
                    .find(|&j| linear_values(j) == linear_values(i))
                    .unwrap_or(i)
            })
            .collect();
        let margin_range = study.constraints.as_ref().map_or(
            [crate::units::from_rpm(1.0), crate::units::from_rpm(1000.0)],
            |c| c.omega,
        );
        Ok(RobustEvaluator {
            problem,
            samples,
            margins: (0..models.len()).map(|_| OnceLock::new()).collect(),
            margin_owner,
            margin_range,
            models,
            settings,
            cache,
            model_hash: model_hash(problem),
            counters: WorkCounters::default(),
            progress: None,
            executor: Box::new(Threads),
            fidelity: Fidelity::Full,
            steady_shapes,
        })
    }

    /// Call `f` after every finished simulation (cached or run), e.g. to tick a progress bar.
    pub fn with_progress(mut self, f: impl Fn() + Sync + 'a) -> Self {
        self.progress = Some(Box::new(f));
        self
    }

    /// Run the simulations with `executor` instead of the default [`Threads`].
    pub fn with_executor(mut self, executor: impl SampleExecutor + 'a) -> Self {
        self.executor = Box::new(executor);
        self
    }

    /// Tag every evaluation with `fidelity` (a multi-fidelity solve's explore evaluator).
    pub fn with_fidelity(mut self, fidelity: Fidelity) -> Self {
        self.fidelity = fidelity;
        self
    }

    /// The fidelity its evaluations are tagged with.
    pub fn fidelity(&self) -> Fidelity {
        self.fidelity
    }

    /// Generalised coordinates of the (nominal) reduced model: the size of the basis.
    pub fn basis_size(&self) -> usize {
        self.models.first().map_or(0, |m| m.size())
    }

    /// What runs the simulations ("2 threads").
    pub fn executor(&self) -> &dyn SampleExecutor {
        self.executor.as_ref()
    }

    /// Simulations per point; with sequential sampling, the most a point may use.
    pub fn samples_per_point(&self) -> usize {
        self.samples.len()
    }

    /// Evaluate several points: the (point, sample) simulations the cache cannot answer form one
    /// batch for the executor; results are stored to the cache as they arrive. Each point is
    /// first snapped to its canonical bits ([`crate::units::canonical_point`]): the same point
    /// reached by the optimizer's scaling or by the parse of `--point` is the same cache entry,
    /// and the returned evaluations are at the canonical points. With `[uncertain.sequential]`
    /// the points are evaluated in rounds, one batch per round ([`super::sequential`]).
    pub fn evaluate(&self, points: &[OperatingPoint]) -> Vec<PointEvaluation> {
        let points: Vec<OperatingPoint> = points.iter().map(OperatingPoint::canonical).collect();
        let n = self.samples.len();
        if let Some(rule) = &self.problem.study.sequential {
            return evaluate_in_rounds(
                rule,
                n,
                points.len(),
                |jobs| {
                    let jobs: Vec<SampleJob> = jobs
                        .iter()
                        .map(|&(p, sample)| SampleJob {
                            op: points[p],
                            sample,
                        })
                        .collect();
                    self.run_jobs(&jobs)
                },
                |p, samples| self.score(points[p], samples),
            );
        }
        let jobs: Vec<SampleJob> = points
            .iter()
            .flat_map(|&op| (0..n).map(move |sample| SampleJob { op, sample }))
            .collect();
        let results = self.run_jobs(&jobs);
        points
            .iter()
            .zip(results.chunks(n))
            .map(|(op, s)| self.score(*op, s.to_vec()))
            .collect()
    }

    /// The results of `jobs`, in order: from the cache where it has them, the rest simulated
    /// as one batch of the executor (and stored to the cache as they arrive).
    fn run_jobs(&self, jobs: &[SampleJob]) -> Vec<SampleResult> {
        let mut results: Vec<Option<SampleResult>> = vec![None; jobs.len()];
        let mut missing: Vec<usize> = Vec::new();
        for (k, job) in jobs.iter().enumerate() {
            match self.cached(*job) {
                Some(hit) => results[k] = Some(hit),
                None => missing.push(k),
            }
        }
        let batch: Vec<SampleJob> = missing.iter().map(|&k| jobs[k]).collect();
        let simulated = self
            .executor
            .execute(&batch, &|job| self.simulate_job(job), &|i, run| {
                self.store(batch[i], run)
            });
        for (&k, run) in missing.iter().zip(simulated) {
            results[k] = Some(self.result(jobs[k], run.outcome, false));
        }
        results.into_iter().map(|r| r.expect("every job")).collect()
    }

    fn key(&self, job: SampleJob) -> CacheKey {
        let seed = self.samples.samples[job.sample].seed;
        // The second coordinate is the point's set-point (V0, or a hook load's WOB): the model
        // hash holds the top, so the two never share a key.
        let op = job.op;
        let set_point = op.set_point(op.kind());
        CacheKey::new(op.omega, set_point, job.sample, seed, self.model_hash)
    }

    fn result(&self, job: SampleJob, outcome: SampleOutcome, cached: bool) -> SampleResult {
        SampleResult {
            sample: job.sample,
            seed: self.samples.samples[job.sample].seed,
            outcome,
            cached,
        }
    }

    fn tick(&self) {
        if let Some(p) = &self.progress {
            p();
        }
    }

    /// The cache's answer for `job`, if it has one.
    fn cached(&self, job: SampleJob) -> Option<SampleResult> {
        let hit = self.cache.and_then(|c| c.get(&self.key(job)))?;
        self.counters.cached.fetch_add(1, Ordering::Relaxed);
        self.tick();
        Some(self.result(job, from_cache(hit), true))
    }

    /// Simulate one job (no cache): what an executor runs, on this process or another.
    pub fn simulate_job(&self, job: SampleJob) -> Simulated {
        let clock = Instant::now();
        let outcome = self.simulate(job.op, job.sample);
        Simulated {
            outcome,
            wall_time_s: clock.elapsed().as_secs_f64(),
        }
    }

    /// Count a finished simulation, store it to the cache and tick the progress.
    fn store(&self, job: SampleJob, run: &Simulated) {
        self.counters.simulated.fetch_add(1, Ordering::Relaxed);
        if matches!(run.outcome, SampleOutcome::Failed(_)) {
            self.counters.failed.fetch_add(1, Ordering::Relaxed);
        }
        if let Some(cache) = self.cache {
            let stored = match &run.outcome {
                SampleOutcome::Metrics(m) => Outcome::Ok { metrics: m.clone() },
                SampleOutcome::Failed(msg) => Outcome::Failed {
                    message: msg.clone(),
                },
            };
            let info = EvalInfo {
                wall_time_s: Some(run.wall_time_s),
                version: Some(crate::VERSION.to_string()),
            };
            // A cache that cannot be written costs a re-simulation later, never this result.
            if let Err(e) = cache.insert_with_info(self.key(job), stored, Some(info)) {
                eprintln!("warning: {e}");
            }
        }
        self.tick();
    }

    fn simulate(&self, op: OperatingPoint, index: usize) -> SampleOutcome {
        let model = &self.models[index];
        let out = simulate(
            model,
            op,
            Effects::ALL,
            &self.settings,
            InitialState::from(self.problem.simulation.start),
            |_| {},
        );
        if let Some(e) = out.error {
            return SampleOutcome::Failed(e.to_string());
        }
        let sim = &self.problem.simulation;
        let terms = metrics::ModelTerms {
            critical_speed_margin: self.critical_speed_margin(index, op.omega),
            steady_state: self.steady_state(model, op),
        };
        let settling = sim.settling_for(sim.duration);
        match metrics::of_run(&out, &model.string, op, settling, Some(terms)) {
            Ok(m) => SampleOutcome::Metrics(metric_map(&m)),
            Err(e) => SampleOutcome::Failed(format!("metrics: {e}")),
        }
    }

    /// `critical_speed_margin` of sample `index`'s model at `omega` (rad/s): from the sample's
    /// table of critical speeds (searched on first use), or searched for this Ω alone when it
    /// lies outside the table's range; NaN when the string has no resting state to linearise
    /// about.
    pub fn critical_speed_margin(&self, index: usize, omega: f64) -> f64 {
        let owner = self.margin_owner[index];
        let model = &self.models[owner];
        let multiple = self.problem.campbell.excitation_multiple;
        let table = self.margins[owner].get_or_init(|| {
            LinearSystem::about_rest(model, Linearisation::default())
                .and_then(|sys| MarginTable::search(&sys, multiple, self.margin_range))
                .ok()
        });
        match table.as_ref().and_then(|t| t.margin(omega)) {
            Some(m) => m,
            None => campbell::critical_speed_margin(model, multiple, omega).unwrap_or(f64::NAN),
        }
    }

    /// [`crate::sim::steady_stability`] of a sample's model at `op`, when the problem uses
    /// `steady_growth_rate_per_s` (another steady state per run: not computed otherwise).
    fn steady_state(
        &self,
        model: &ReducedModel,
        op: OperatingPoint,
    ) -> Option<crate::sim::SteadyStability> {
        let used = self
            .problem
            .study
            .metrics_named()
            .contains(&"steady_growth_rate_per_s");
        if !used {
            return None;
        }
        crate::sim::steady_stability(model, op, Effects::ALL)
            .ok()
            .flatten()
    }

    /// Combine the samples of one point into its score, risk terms and chance constraints.
    pub fn score(&self, op: OperatingPoint, samples: Vec<SampleResult>) -> PointEvaluation {
        let mut p = score(&self.problem.study, op, samples);
        p.fidelity = self.fidelity;
        p
    }
}

fn from_cache(o: Outcome) -> SampleOutcome {
    match o {
        Outcome::Ok { metrics } => SampleOutcome::Metrics(metrics),
        Outcome::Failed { message } => SampleOutcome::Failed(message),
    }
}
