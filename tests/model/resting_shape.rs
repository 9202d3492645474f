//! The resting shape in the basis (issue 11): a reduced string lies on the wall where the
//! finite-element model does, and stays there.
//!
//! Reference: the unreduced finite-element model ([`ReducedModel::unreduced`]), whose static
//! equilibrium on the wall does not depend on any basis.

use drillopt::metrics::{self, MetricsConfig};
use drillopt::model::{BasisSpec, FamilySize, OperatingPoint};
use drillopt::problem::Problem;
use drillopt::rom::{ModeKind, ReducedModel};
use drillopt::sim::{
    Effects, InitialState, RunSettings, preloaded_equilibrium, simulate, static_equilibrium,
};

use crate::common;

/// The shipped seed, with its bit inertia.
fn seed() -> Problem {
    Problem::load(common::SEED).unwrap()
}

/// Radial displacement of every node at the static equilibrium under gravity with the wall, m.
fn resting_radii(model: &ReducedModel) -> Vec<f64> {
    let (q, _) = static_equilibrium(model).unwrap();
    radii(model, &q)
}

/// Radial displacement of every node in the pre-loaded (steady drilling) state of the seed's
/// operating point, 60 rpm and 5 m/h: WOB 55 kN of compression, the bit torque, the wall.
fn preloaded_radii(model: &ReducedModel) -> Vec<f64> {
    let (q, _) = preloaded_equilibrium(model, seed_point(), Effects::ALL).unwrap();
    radii(model, &q)
}

fn radii(model: &ReducedModel, q: &nalgebra::DVector<f64>) -> Vec<f64> {
    let x = &model.phi * q;
    (0..model.nodes())
        .map(|k| x[6 * k + 1].hypot(x[6 * k + 2]))
        .collect()
}

fn seed_point() -> OperatingPoint {
    OperatingPoint {
        omega: 2.0 * std::f64::consts::PI,
        v0: 5.0 / 3600.0,
        wob: 0.0,
    }
}

#[test]
fn the_default_basis_rests_on_the_wall_where_the_finite_element_model_does() {
    let p = seed();
    let gap = p.model.gap();
    let unreduced = resting_radii(&ReducedModel::unreduced(&p.model, p.mesh.elements).unwrap());
    let default = ReducedModel::new(&p.model, p.mesh.elements, &BasisSpec::DEFAULT).unwrap();
    let resting = default
        .basis
        .modes
        .iter()
        .filter(|m| m.kind == ModeKind::RestingShape)
        .count();
    assert_eq!(
        resting, 4,
        "the resting shape and its compression sensitivity per bending plane"
    );
    let touching = |r: &[f64]| r.iter().filter(|&&r| r > gap).count();
    // 71 of the 106 nodes rest on the wall (the string leaves it near its supported ends), at
    // rest and in the pre-loaded state; the wall's indentation under a node's weight is ~0.05 µm,
    // so the contact set is a sharp test of the shape.
    let unreduced_preloaded =
        preloaded_radii(&ReducedModel::unreduced(&p.model, p.mesh.elements).unwrap());
    for (state, reduced, unreduced) in [
        ("at rest", resting_radii(&default), unreduced.clone()),
        ("pre-loaded", preloaded_radii(&default), unreduced_preloaded),
    ] {
        assert!(
            touching(&unreduced) > 60,
            "{state}: {}",
            touching(&unreduced)
        );
        assert_eq!(touching(&reduced), touching(&unreduced), "{state}");
        for (k, (r, u)) in reduced.iter().zip(&unreduced).enumerate() {
            assert!(
                (r - u).abs() < 1e-3 * gap,
                "{state}, node {k}: reduced {r:e} m, unreduced {u:e} m"
            );
        }
    }
    // Without the resting shapes (and the bit corrections) the same modes touch at a few nodes
    // (14 of 71).
    let modes_only = BasisSpec::PerFamily {
        bending: FamilySize::Count(16),
        torsional: FamilySize::Count(8),
        axial: FamilySize::Count(4),
        static_corrections: false,
        steady_shapes: false,
    };
    let bare = ReducedModel::new(&p.model, p.mesh.elements, &modes_only).unwrap();
    assert!(
        touching(&resting_radii(&bare)) < touching(&unreduced) / 2,
        "16 modes per plane cannot lie along the wall"
    );
}

#[test]
fn the_default_seed_string_lies_still_through_stick_slip() {
    // Without the resting shapes the reduced seed string, supported at 14 nodes, lifted off
    // about 5.5 s into the run and bounced at ~1400 impacts/s; the unreduced one never leaves
    // the wall. 8 s from the pre-loaded state: stick-slip from the first second, and at most the
    // odd touch-down of the lifted span (none at revision 12, 0.43 per second at revision 13, whose basis differs
    // at round-off: a count the model does not determine, docs/model.md "The seed run"; the
    // 90 s run has 15.6 per second once the stick-slip has grown).
    let p = seed();
    let model = ReducedModel::new(&p.model, p.mesh.elements, &p.mesh.basis).unwrap();
    let op = seed_point();
    let out = simulate(
        &model,
        op,
        Effects::ALL,
        &RunSettings::new(8.0, p.simulation.time_step),
        InitialState::Preloaded,
        |_| {},
    );
    assert!(out.error.is_none(), "{:?}", out.error);
    let s = &out.series;
    let config = MetricsConfig::new(op.omega, op.v0, p.model.borehole_radius, 1.0);
    let m = metrics::compute(s, &config).unwrap();
    assert!(
        m.stick_fraction > 0.1 && m.stick_slip_severity > 0.5,
        "stick-slip develops: stick fraction {}, SSI {}",
        m.stick_fraction,
        m.stick_slip_severity
    );
    assert!(
        m.impacts_per_s < 2.0,
        "the string lies still: {} impacts/s",
        m.impacts_per_s
    );
    let onsets = s.contact_onsets.last().copied().unwrap_or(0);
    assert!(onsets <= 10, "the string lies still: {onsets} touch-downs");
    let radius = s.max_radial_over_gap.iter().fold(0.0f64, |a, &b| a.max(b));
    assert!(
        radius < 1.001,
        "no deeper indentation than at rest: {radius}"
    );
}

#[test]
fn verify_checks_the_wall_contact_when_the_problem_decides_on_it() {
    let keys = common::decision_keys;
    let text = std::fs::read_to_string(common::SEED).unwrap();
    assert!(!keys(&seed()).contains(&"impacts_per_s"));
    let with = |metric: &str| {
        let t = format!(
            "{text}\n[objective]\n[[objective.risk]]\nmetric = \"{metric}\"\nweight = 1.0\n"
        );
        Problem::from_toml(&t, std::path::Path::new("contact.toml")).unwrap()
    };
    let impacts = keys(&with("impacts_per_s"));
    assert!(impacts.contains(&"impacts_per_s") && !impacts.contains(&"peak_wall_force_n"));
    assert!(keys(&with("peak_wall_force_n")).contains(&"peak_wall_force_n"));
}
