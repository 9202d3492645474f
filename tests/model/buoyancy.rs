//! Buoyancy (issue 14 item 6): `[model.fluid] annulus_density`, the mud outside the pipe, turns
//! the gravity load into the buoyed weight w = (ρA + ρ_f A_f − ρ_a π R_ext²) g. References are
//! closed forms from the raw numbers of the seed's Table 1, not from the crate's `Section`.

use crate::common;

use common::Table1;
use drillopt::model::{BasisSpec, OperatingPoint};
use drillopt::problem::{Problem, ProblemError};
use drillopt::rom::ReducedModel;
use drillopt::sim::{Dynamics, Effects, static_equilibrium};
use drillopt::study::model_hash;
use std::f64::consts::PI;
use std::path::Path;

fn seed_text() -> String {
    std::fs::read_to_string(common::SEED).unwrap()
}

/// The seed with `annulus_density = value` in `[model.fluid]`.
fn with_annulus(value: &str) -> String {
    seed_text().replacen(
        "[model.fluid]\n",
        &format!("[model.fluid]\nannulus_density = {value}\n"),
        1,
    )
}

fn load(text: &str) -> Result<Problem, ProblemError> {
    Problem::from_toml(text, Path::new("cases/mud.toml"))
}

/// Buoyed weight per length of the seed's pipe, N/m: steel, the fluid inside (ρ_f = 1200), less
/// the annulus fluid displaced by the outer section.
fn buoyed_weight(rho_annulus: f64) -> f64 {
    let (ro, ri) = (Table1::R_EXT, Table1::R_INT);
    let steel = Table1::RHO * PI * (ro * ro - ri * ri);
    let inside = Table1::RHO_F * PI * ri * ri;
    (steel + inside - rho_annulus * PI * ro * ro) * 9.81
}

#[test]
fn the_key_is_read_in_any_density_unit_and_refused_outside_its_range_by_name() {
    assert_eq!(load(&seed_text()).unwrap().model.annulus_density, 0.0);
    let p = load(&with_annulus("\"1.2 sg\"")).unwrap();
    assert_eq!(p.model.annulus_density, 1200.0);
    let p = load(&with_annulus("\"10 ppg\"")).unwrap();
    assert!((p.model.annulus_density - 1198.26427).abs() < 1e-6);
    for (value, words) in [
        ("\"5000 kg/m^3\"", "in [0, 3000] kg/m3"),
        ("\"-1 kg/m^3\"", "must be in [0, 3000] kg/m3"),
        ("\"1.2 furlong\"", "unknown unit"),
        // A pressure for a density: said as the wrong dimension.
        ("\"1.2 bar\"", "the wrong dimension: the value is a density"),
    ] {
        let err = load(&with_annulus(value)).unwrap_err();
        let msg = err.to_string();
        assert_eq!(err.key(), Some("model.fluid.annulus_density"), "{msg}");
        assert!(
            msg.contains(words) && msg.contains("cases/mud.toml"),
            "{msg}"
        );
    }
}

#[test]
fn the_cache_key_changes_only_when_the_annulus_holds_fluid() {
    let seed = model_hash(&load(&seed_text()).unwrap());
    assert_eq!(model_hash(&load(&with_annulus("0")).unwrap()), seed);
    assert_ne!(
        model_hash(&load(&with_annulus("\"1200 kg/m^3\"")).unwrap()),
        seed
    );
}

/// Wall reaction per length where the string rests on the wall, N/m: the static equilibrium
/// under gravity of the seed's pipe, 100 m long on 100 one-metre elements, with every mode (the
/// exact finite-element state), summed over the nodes of the middle 41 m. Each end of the pipe,
/// pinned on the hole's axis, lifts off the wall over (72 EI gap / w)^¼ ≈ 7 m; the disturbance
/// of the wall reactions this makes dies out by the factor 2 − √3 ≈ 0.27 per span (a continuous
/// beam on stiff supports), below 1e-12 of the weight 23 spans in.
fn resting_reaction_per_length(annulus: &str) -> f64 {
    let text = with_annulus(annulus).replacen("length = \"35 m\"", "length = \"100 m\"", 1);
    let p = load(&text).unwrap();
    assert_eq!(p.model.length, 100.0);
    let elements = 100;
    let all_modes = BasisSpec::Lowest(6 * elements - 2);
    let model = ReducedModel::new(&p.model, elements, &all_modes).unwrap();
    let (q, _) = static_equilibrium(&model).unwrap();
    let rest = OperatingPoint {
        omega: 0.0,
        v0: 0.0,
        wob: 0.0,
    };
    let statics = Effects {
        damping: false,
        bit: false,
        ..Effects::ALL
    };
    let mut sys = Dynamics::new(&model, rest, statics);
    let zero = nalgebra::DVector::zeros(model.size());
    sys.observe(&q, &zero, &zero);
    let middle = &sys.contacts[30..=70];
    assert!(
        middle.iter().all(|c| c.active),
        "every middle node on the wall"
    );
    let total: f64 = middle.iter().map(|c| c.normal.abs()).sum();
    total / middle.len() as f64 // per node, one metre each
}

#[test]
fn a_resting_string_weighs_on_the_wall_with_its_buoyed_weight() {
    for (annulus, rho) in [("0", 0.0), ("\"1200 kg/m^3\"", 1200.0)] {
        let reaction = resting_reaction_per_length(annulus);
        let w = buoyed_weight(rho);
        println!("ρ_a = {rho}: wall reaction {reaction} N/m, buoyed weight {w} N/m");
        assert!(
            (reaction / w - 1.0).abs() < 1e-9,
            "ρ_a = {rho}: wall reaction {reaction} N/m, buoyed weight {w} N/m"
        );
    }
    // 1200 kg/m³ of mud, as dense as the fluid inside: the steel's weight times 1 − ρ_f/ρ.
    let steel = Table1::RHO * PI * (Table1::R_EXT.powi(2) - Table1::R_INT.powi(2)) * 9.81;
    assert!((buoyed_weight(1200.0) / (steel * (1.0 - 1200.0 / 7900.0)) - 1.0).abs() < 1e-12);
}
