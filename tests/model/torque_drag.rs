//! Torque and drag of long horizontal strings at field wall friction (MODEL.md §11.2, §11.6)
//! against the soft-string closed form (Johancsik, Friesen & Dawson, JPT 1984), computed here
//! from the raw numbers of `problems/long_collars.toml` (not through the crate's `SoftString`):
//!
//!   top torque = TOB + μ N L R_ext c_t + c ρJ Ω L,   top force = WOB + μ N L c_a + c ρA V0 L,
//!   (c_a, c_t) = (V0, Ω R_ext)/√(V0² + (Ω R_ext)²),
//!
//! with N the wall's normal force per length: the buoyed weight w_b in Johancsik's soft string,
//! w_b cos φ once the turning pipe has climbed the wall to tan φ = μ c_t (the simulated string
//! does). Both are checked: the steady pre-loaded state of the simulator within 5 % of
//! Johancsik's form for μ ≤ 0.3 and within 2.5 % of the climbing form for μ up to 0.5 (the rest
//! is the supported ends, which hang off the wall); the climbing angle of the mid-string nodes
//! within 2 % of atan(μ c_t); and strings of 100 m, 1 km and 3 km at μ = 0.3 start at once.

use drillopt::fem::Dof;
use drillopt::model::OperatingPoint;
use drillopt::problem::Problem;
use drillopt::rom::ReducedModel;
use drillopt::sim::{Dynamics, Effects, preloaded_equilibrium};
use nalgebra::DVector;
use std::f64::consts::PI;

const COLLARS: &str = include_str!("../../problems/long_collars.toml");

/// long_collars.toml with the wall friction `mu`, length `length` (m) and `elements`.
fn collars(mu: f64, length: f64, elements: usize) -> Problem {
    let text = COLLARS
        .replace(
            "friction = 0.3                  # Coulomb",
            &format!("friction = {mu} #"),
        )
        .replace("length = \"466 m\"", &format!("length = \"{length} m\""))
        .replace("elements = 150 ", &format!("elements = {elements} "))
        .replace("probes = [\"233 m\"]", "probes = [\"10 m\"]");
    assert!(
        text.contains(&format!("friction = {mu} #")),
        "the edit took"
    );
    Problem::from_toml(&text, std::path::Path::new("long_collars_edited.toml")).unwrap()
}

/// The raw numbers of long_collars.toml, SI.
struct Raw;
impl Raw {
    const RHO: f64 = 7900.0;
    const RHO_F: f64 = 1200.0;
    /// The annulus mud: it buoys the string.
    const RHO_A: f64 = 1200.0;
    const R_EXT: f64 = 0.085725;
    const R_INT: f64 = 0.0357;
    const G: f64 = 9.81;
    const C: f64 = 0.03;
    fn omega() -> f64 {
        40.0 * 2.0 * PI / 60.0
    }
    fn v0() -> f64 {
        32.0 / 3600.0
    }
    /// Buoyed weight per length (pipe and inner mud less the annulus mud displaced), N/m.
    fn weight() -> f64 {
        (Self::RHO * PI * (Self::R_EXT.powi(2) - Self::R_INT.powi(2))
            + Self::RHO_F * PI * Self::R_INT.powi(2)
            - Self::RHO_A * PI * Self::R_EXT.powi(2))
            * Self::G
    }
    /// (c_a, c_t).
    fn split() -> (f64, f64) {
        let (v, s) = (Self::v0(), Self::omega() * Self::R_EXT);
        (v / v.hypot(s), s / v.hypot(s))
    }
}

/// The steady pre-loaded state: (top force, top torque, WOB, TOB, mid-string climbing angle).
fn steady_state(p: &Problem) -> (f64, f64, f64, f64, f64) {
    let model = ReducedModel::new(&p.model, p.mesh.elements, &p.mesh.basis).unwrap();
    let op = OperatingPoint {
        omega: Raw::omega(),
        v0: Raw::v0(),
        wob: 0.0,
    };
    let (q, _) = preloaded_equilibrium(&model, op, Effects::ALL).expect("the start converges");
    let mut sys = Dynamics::new(&model, op, Effects::ALL);
    let zero = DVector::zeros(model.size());
    let obs = sys.observe(&q, &zero, &zero);
    // The climbing angle at the middle node: the position angle from the bottom of the hole,
    // positive towards −y (against the spin Ω > 0).
    let full = sys.displacement_full();
    let mid = model.nodes() / 2;
    let (v, w) = (full[Dof::V.at(mid)], full[Dof::W.at(mid)]);
    let climb = (-v).atan2(-w);
    (
        obs.top_force,
        obs.top_torque,
        -obs.bit.force,
        -obs.bit.torque,
        climb,
    )
}

#[test]
fn top_torque_and_force_of_a_long_string_match_the_soft_string_closed_form() {
    let length = 466.0;
    for mu in [0.1, 0.2, 0.3, 0.4, 0.5] {
        let p = collars(mu, length, 150);
        let (force, torque, wob, tob, climb) = steady_state(&p);
        let (c_a, c_t) = Raw::split();
        let area = PI * (Raw::R_EXT.powi(2) - Raw::R_INT.powi(2));
        let polar = PI / 2.0 * (Raw::R_EXT.powi(4) - Raw::R_INT.powi(4));
        let damping_force = Raw::C * Raw::RHO * area * Raw::v0() * length;
        let damping_torque = Raw::C * Raw::RHO * polar * Raw::omega() * length;
        let closed = |normal: f64| {
            (
                wob + mu * normal * length * c_a + damping_force,
                tob + mu * normal * length * Raw::R_EXT * c_t + damping_torque,
            )
        };
        let phi = (mu * c_t).atan();
        let (f_j, t_j) = closed(Raw::weight());
        let (f_c, t_c) = closed(Raw::weight() * phi.cos());
        let err = |a: f64, b: f64| (a - b).abs() / b;
        eprintln!(
            "mu {mu}: top torque {torque:.0} N m (Johancsik {t_j:.0}, {:+.2} %; climbing {t_c:.0}, {:+.2} %), top force {force:.0} N ({f_j:.0}, {:+.2} %; {f_c:.0}, {:+.2} %), climb {:.2} deg (atan(mu c_t) {:.2})",
            100.0 * (torque / t_j - 1.0),
            100.0 * (torque / t_c - 1.0),
            100.0 * (force / f_j - 1.0),
            100.0 * (force / f_c - 1.0),
            climb.to_degrees(),
            phi.to_degrees()
        );
        assert!(
            err(torque, t_c) < 0.025 && err(force, f_c) < 0.025,
            "mu {mu}"
        );
        if mu <= 0.3 {
            assert!(err(torque, t_j) < 0.05 && err(force, f_j) < 0.05, "mu {mu}");
        }
        assert!(
            (climb - phi).abs() < 0.02 * phi,
            "mu {mu}: climb {climb} vs {phi}"
        );
        // The friction is a real share of the torque (the test would pass on TOB alone otherwise).
        assert!(t_c - tob > 0.25 * tob, "mu {mu}");
    }
}

#[test]
fn strings_of_100_m_to_3_km_start_at_field_friction_and_carry_the_closed_form_torque() {
    for (length, elements) in [(100.0, 40), (1000.0, 300), (3000.0, 600)] {
        let p = collars(0.3, length, elements);
        let clock = std::time::Instant::now();
        let (_, torque, _, tob, _) = steady_state(&p);
        let seconds = clock.elapsed().as_secs_f64();
        let (_, c_t) = Raw::split();
        let normal = Raw::weight() * (0.3 * c_t).atan().cos();
        let polar = PI / 2.0 * (Raw::R_EXT.powi(4) - Raw::R_INT.powi(4));
        let expected = tob
            + 0.3 * normal * length * Raw::R_EXT * c_t
            + Raw::C * Raw::RHO * polar * Raw::omega() * length;
        eprintln!(
            "{length} m: top torque {torque:.0} vs {expected:.0} N m ({:+.2} %), start and model in {seconds:.2} s",
            100.0 * (torque / expected - 1.0)
        );
        // The supported ends hang off the wall: their share of the weight falls with the length
        // (9 % of 100 m, 0.3 % of 3 km).
        let tolerance = if length < 200.0 { 0.05 } else { 0.015 };
        assert!(
            (torque - expected).abs() < tolerance * expected,
            "{length} m"
        );
    }
}

/// Every shipped problem starts at every field friction (0 to 0.5, MODEL.md §11.6), at its own
/// operating point, and its start passes the soft-string check (`sim::check_against_soft_string`,
/// which `simulate` applies: a state that fails it is an error).
#[test]
fn every_shipped_problem_starts_at_every_field_friction() {
    let mut files = Vec::new();
    for dir in ["problems", "problems/regression", "problems/bench"] {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(dir);
        for entry in std::fs::read_dir(dir).unwrap() {
            let path = entry.unwrap().path();
            if path.extension().is_some_and(|e| e == "toml") {
                files.push(path);
            }
        }
    }
    assert!(files.len() >= 10, "{files:?}");
    for file in files {
        let mut p = Problem::load(&file).unwrap();
        let model_at =
            |p: &Problem| ReducedModel::new(&p.model, p.mesh.elements, &p.mesh.basis).unwrap();
        let index = p
            .model
            .wall
            .index_of("friction")
            .expect("every wall law has a friction");
        for mu in [0.0, 0.1, 0.3, 0.5] {
            p.model.wall.set(index, mu);
            let model = model_at(&p);
            // A hook load's start is its steady drilling state at the feed its WOB drills (off
            // bottom this slim string hangs free of the wall, which the soft string does not).
            let op = match p.model.top {
                drillopt::model::TopDrive::HookLoad => {
                    let (_, v, _) =
                        drillopt::sim::free_top_start(&model, p.operating_point, Effects::ALL)
                            .unwrap_or_else(|e| panic!("{}: mu {mu}: {e}", file.display()));
                    drillopt::model::OperatingPoint {
                        v0: v,
                        ..p.operating_point
                    }
                }
                _ => p.operating_point,
            };
            let (q, iterations) = preloaded_equilibrium(&model, op, Effects::ALL)
                .unwrap_or_else(|e| panic!("{}: mu {mu}: {e}", file.display()));
            let mut sys = Dynamics::new(&model, op, Effects::ALL);
            let zero = DVector::zeros(model.size());
            let obs = sys.observe(&q, &zero, &zero);
            drillopt::sim::check_against_soft_string(&model, op, &obs)
                .unwrap_or_else(|e| panic!("{}: mu {mu}: {e}", file.display()));
            assert!(
                iterations < 1000,
                "{}: mu {mu}: {iterations}",
                file.display()
            );
        }
    }
}
