//! A run that cannot go on stops with an error that says when and why, and keeps what it had
//! recorded up to then.

use crate::common;

use drillopt::rom::ReducedModel;
use drillopt::sim::{Effects, InitialState, RunOutput, RunSettings, SimulationError, simulate};

fn model() -> (drillopt::problem::Problem, ReducedModel) {
    let p = common::seed();
    let m = ReducedModel::new(&p.model, 30, &common::small_basis()).unwrap();
    (p, m)
}

/// The seed operating point with all effects, from `start`.
fn run(
    p: &drillopt::problem::Problem,
    m: &ReducedModel,
    settings: &RunSettings,
    start: InitialState,
) -> RunOutput {
    simulate(m, p.operating_point, Effects::ALL, settings, start, |_| {})
}

#[test]
fn divergence_stops_the_run_and_keeps_the_history() {
    let (p, m) = model();
    // Declare divergence as soon as any node exceeds 0.5 gap: the string rests on the wall
    // (r = gap) from the first step, so the run must stop at once, after the first step.
    let mut settings = RunSettings::new(1.0, p.simulation.time_step);
    settings.divergence_gaps = 0.5;
    let out = run(&p, &m, &settings, InitialState::StaticEquilibrium);
    match out.error {
        Some(SimulationError::Diverged {
            time,
            radial_over_gap,
        }) => {
            assert!(time > 0.0 && time < 0.01, "stopped at {time} s");
            assert_eq!(
                *out.series.t.last().unwrap(),
                time,
                "history kept up to the failure"
            );
            assert!(radial_over_gap > 0.9, "{radial_over_gap}");
            let message = out.error.as_ref().unwrap().to_string();
            assert!(
                message.contains("diverged") && message.contains("t ="),
                "{message}"
            );
        }
        other => panic!("expected divergence, got {other:?}"),
    }
    assert_eq!(
        out.series.len(),
        2,
        "the initial state and the step that diverged are kept"
    );
}

#[test]
fn a_step_below_the_minimum_stops_the_run_with_its_time() {
    let (p, m) = model();
    // A minimum step above what the stick-slip and contact dynamics need: from the steady
    // drilling state the march is smooth at first, then stick-slip grows and the controller has
    // to refine below the minimum within the first second and must give up there, saying when.
    let mut settings = RunSettings::new(1.0, p.simulation.time_step);
    settings.min_step = 2e-4;
    let out = run(&p, &m, &settings, InitialState::Preloaded);
    match &out.error {
        Some(SimulationError::StepTooSmall { time, min_step, .. }) => {
            assert_eq!(*min_step, 2e-4);
            assert!(
                *time > 1e-3 && *time < 1.0,
                "it must first march, then fail: t = {time}"
            );
            assert!(
                out.stats.steps > 3,
                "{} steps before failing",
                out.stats.steps
            );
            assert!(
                (out.series.t.last().unwrap() - time).abs() < 1e-12,
                "history kept up to the failure"
            );
        }
        other => panic!("expected a step-size failure, got {other:?}"),
    }
}

/// A run whose step keeps collapsing above `min_step` still ends: after `max_attempts` step
/// attempts it stops with the time and the count, keeping what it had recorded.
#[test]
fn a_run_stops_after_its_step_attempt_limit() {
    let (p, m) = model();
    let mut settings = RunSettings::new(1.0, p.simulation.time_step);
    settings.max_attempts = 500;
    let out = run(&p, &m, &settings, InitialState::Preloaded);
    match &out.error {
        Some(SimulationError::TooManySteps { time, attempts, .. }) => {
            assert_eq!(*attempts, 500);
            assert!(*time > 0.0 && *time < 1.0, "t = {time}");
            assert_eq!(
                (out.stats.steps + out.stats.rejected_steps) as u64,
                500,
                "stopped at the limit"
            );
            assert!((out.series.t.last().unwrap() - time).abs() < 1e-12);
            let message = out.error.as_ref().unwrap().to_string();
            assert!(message.contains("500 step attempts"), "{message}");
        }
        other => panic!("expected the attempt limit, got {other:?}"),
    }
}
