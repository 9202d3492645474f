//! A string of sections (`[[model.section]]`, MODEL.md §11.5): drill pipe over collars.
//!
//! References:
//! - the natural frequencies of two coupled rods, fixed at the top drive and free at the bit:
//!   with θ₁ = A sin(k₁x) in the upper section and θ₂ = B cos(k₂(L − x)) in the lower, the
//!   continuity of the twist and of the torque at the boundary gives
//!   tan(ωL₁/c₁) tan(ωL₂/c₂) = Z₁/Z₂, c the wave speed and Z = √(stiffness · inertia) the
//!   characteristic impedance of each (torsion: c = √(G/ρ), Z = J√(Gρ); axial: c = √(E/ρ),
//!   Z = A√(Eρ)); e.g. Graff, *Wave Motion in Elastic Solids*, 1975, §1.7 for the rod and its
//!   impedance. Computed here from the pipes' sizes, not from the crate's sections;
//! - the soft-string torque of a string of sections on the low side of the hole (Johancsik,
//!   Friesen & Dawson 1984), summed section by section from each section's buoyed weight;
//! - a file with one section equal to `[model.pipe]` is the file without it.

use crate::common;

use drillopt::problem::Problem;
use serde_json::Value;
use std::f64::consts::PI;
use std::path::Path;

const STEEL: (f64, f64, f64) = (7900.0, 203e9, 0.3);
const MUD: f64 = 1200.0;
const G: f64 = 9.81;

/// (length m, outer diameter m, inner diameter m) of the drill pipe and of the collars.
const PIPE: (f64, f64, f64) = (30.0, 0.1397, 0.121_361_2);
const COLLARS: (f64, f64, f64) = (10.0, 0.171_45, 0.071_437_5);

/// A horizontal string of `scale` × 30 m of 5½ in drill pipe over `scale` × 10 m of 6¾ in
/// collars, in an 8½ in hole full of 1.2 sg mud, on `elements` elements, wall friction
/// `friction`.
fn sections_of(scale: f64, elements: usize, friction: f64) -> String {
    let (pipe, collars) = (30.0 * scale, 10.0 * scale);
    let length = pipe + collars;
    format!(
        r#"name = "two_sections"
[model]
length = "{length} m"
gravity = "9.81 m/s^2"
[model.pipe]
density = "7900 kg/m^3"
youngs_modulus = "203 GPa"
poisson_ratio = 0.3
damping = "0.03 1/s"
torsion_factor = 1
[model.fluid]
density = "1200 kg/m^3"
annulus_density = "1200 kg/m^3"
[model.borehole]
radius = "108 mm"
[model.wall]
law = "hunt_crossley"
stiffness = "3e9 N/m"
restitution = 0.5
impact_speed = "0.1 m/s"
friction = {friction}
[model.bit]
limit_force = "250 kN"
rate = "180 s/m"
friction = "0.04 m"
[mesh]
elements = {elements}
[operating_point]
omega = "60 rpm"
v0 = "10 m/h"
[simulation]
duration = "1 s"
time_step = "10 ms"
settling_time = "0.5 s"

[[model.section]]
name = "drill pipe"
length = "{pipe} m"
outer_diameter = "5.5 in"
inner_diameter = "4.778 in"

[[model.section]]
name = "collars"
length = "{collars} m"
outer_diameter = "6.75 in"
inner_diameter = "2.8125 in"
"#
    )
}

/// The 40 m string of [`sections_of`].
fn two_sections(elements: usize, friction: f64) -> String {
    sections_of(1.0, elements, friction)
}

fn write(dir: &Path, name: &str, text: &str) -> String {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path.to_str().unwrap().to_string()
}

/// The lowest roots ω of sin a sin b − r cos a cos b = 0 (tan a tan b = r), a = ωL₁/c₁,
/// b = ωL₂/c₂: a scan in steps of 1e-3 of the first root's scale, then bisection.
fn coupled_rod_roots(count: usize, [l1, l2]: [f64; 2], [c1, c2]: [f64; 2], r: f64) -> Vec<f64> {
    let f = |w: f64| {
        let (a, b) = (w * l1 / c1, w * l2 / c2);
        a.sin() * b.sin() - r * a.cos() * b.cos()
    };
    let step = 1e-3 * (c1 / l1).min(c2 / l2);
    let mut roots = Vec::new();
    let mut w = step;
    while roots.len() < count {
        if f(w) * f(w + step) < 0.0 {
            let (mut lo, mut hi) = (w, w + step);
            for _ in 0..100 {
                let mid = 0.5 * (lo + hi);
                if f(lo) * f(mid) <= 0.0 {
                    hi = mid
                } else {
                    lo = mid
                }
            }
            roots.push(0.5 * (lo + hi));
        }
        w += step;
    }
    roots
}

fn family(json: &Value, name: &str) -> Vec<f64> {
    (json["modes"].as_array().unwrap().iter())
        .filter(|m| m["family"] == name)
        .map(|m| m["freq_hz"].as_f64().unwrap())
        .collect()
}

#[test]
fn torsional_and_axial_frequencies_of_pipe_over_collars_are_those_of_two_coupled_rods() {
    let dir = tempfile::tempdir().unwrap();
    let file = write(dir.path(), "two.toml", &two_sections(80, 0.3));
    let out = common::drillopt(&["modes", &file, "--json", "--count", "120"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let json: Value = serde_json::from_slice(&out.stdout).unwrap();
    let (rho, e, nu) = STEEL;
    let shear = e / (2.0 * (1.0 + nu));
    let area = |(_, od, id): (f64, f64, f64)| PI / 4.0 * (od * od - id * id);
    let polar = |(_, od, id): (f64, f64, f64)| PI / 32.0 * (od.powi(4) - id.powi(4));
    let lengths = [PIPE.0, COLLARS.0];
    for (name, speed, impedance) in [
        (
            "torsional",
            (shear / rho).sqrt(),
            [polar(PIPE), polar(COLLARS)].map(|j| j * (shear * rho).sqrt()),
        ),
        (
            "axial",
            (e / rho).sqrt(),
            [area(PIPE), area(COLLARS)].map(|a| a * (e * rho).sqrt()),
        ),
    ] {
        let fe = family(&json, name);
        let exact = coupled_rod_roots(4, lengths, [speed; 2], impedance[0] / impedance[1]);
        assert!(
            fe.len() >= 4,
            "{name}: {} modes in the lowest 120",
            fe.len()
        );
        for (n, (f, w)) in fe.iter().zip(&exact).enumerate() {
            let reference = w / (2.0 * PI);
            let err = (f - reference).abs() / reference;
            eprintln!(
                "{name} {}: FE {f:.4} Hz, two rods {reference:.4} Hz, {err:.2e}",
                n + 1
            );
            assert!(
                err < 5e-3,
                "{name} {}: {f} Hz against {reference} Hz",
                n + 1
            );
        }
        // The coupling matters: a uniform rod of the pipe alone is far off (more than 5 %).
        let uniform = (2.0 * 1.0 - 1.0) * speed / (4.0 * (lengths[0] + lengths[1]));
        assert!(
            (fe[0] - uniform).abs() / uniform > 0.05,
            "{name}: {} vs {uniform}",
            fe[0]
        );
    }
}

#[test]
fn the_start_carries_the_soft_string_torque_and_drag_of_each_section() {
    let dir = tempfile::tempdir().unwrap();
    let mu = 0.3;
    // 300 m of drill pipe over 100 m of collars: long against the metres that hang off the wall
    // at the supported ends (about 12 m of pipe under the top drive, 10 m of collars above the
    // bit, from (72 EI gap / w)^¼).
    let scale = 10.0;
    let file = write(dir.path(), "two.toml", &sections_of(scale, 160, mu));
    let out_dir = dir.path().join("out");
    let out = common::drillopt(&[
        "simulate",
        &file,
        "--quiet",
        "--out",
        out_dir.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    // The terminal says what string was built, section by section (sizes in mm, as input).
    let stdout = String::from_utf8_lossy(&out.stdout);
    for line in [
        "section 0 \"drill pipe\": 300.00 m, OD 139.70 mm, ID 121.36 mm",
        "section 1 \"collars\": 100.00 m, OD 171.45 mm, ID 71.44 mm",
    ] {
        assert!(stdout.contains(line), "{line} not in {stdout}");
    }
    // In oilfield units, inches to the thousandth as the pipe tables give them.
    let field = common::drillopt(&[
        "simulate",
        &file,
        "--quiet",
        "--units",
        "field",
        "--duration",
        "0.01s",
        "--out",
        dir.path().join("field").to_str().unwrap(),
    ]);
    let field = String::from_utf8_lossy(&field.stdout);
    for line in [
        "section 0 \"drill pipe\": 984.25 ft, OD 5.500 in, ID 4.778 in",
        "section 1 \"collars\": 328.08 ft, OD 6.750 in, ID 2.812 in",
    ] {
        assert!(field.contains(line), "{line} not in {field}");
    }
    let summary: Value =
        serde_json::from_str(&std::fs::read_to_string(out_dir.join("summary.json")).unwrap())
            .unwrap();
    let m = &summary["metrics"];
    let (top_torque, tob) = (
        m["mean_top_torque_nm"].as_f64().unwrap(),
        m["mean_tob_nm"].as_f64().unwrap(),
    );
    // Johancsik's torque of each section on the low side, with the climb of the turning pipe
    // (N = w cos φ, tan φ = μ: the slip is all rotation to 1e-3 at 60 rpm and 10 m/h).
    let (rho, ..) = STEEL;
    let weight = |(_, od, id): (f64, f64, f64)| {
        let (outer, inner) = (PI / 4.0 * od * od, PI / 4.0 * id * id);
        (rho * (outer - inner) + MUD * inner - MUD * outer) * G
    };
    let climb = mu.atan().cos();
    let friction: f64 = [PIPE, COLLARS]
        .iter()
        .map(|&s| mu * weight(s) * climb * 0.5 * s.1 * scale * s.0)
        .sum();
    let estimate = tob + friction;
    eprintln!("top torque {top_torque:.1} N m, TOB {tob:.1}, friction estimate {friction:.1}");
    // The supported ends hang off the wall (the damping of the rigid spin adds a little):
    // within 5 % of the whole, and the friction part within 10 %.
    assert!((top_torque - estimate).abs() < 0.05 * estimate);
    assert!((top_torque - tob - friction).abs() < 0.10 * friction);
    // The collars' share is the larger: with drill pipe all the way the friction would be
    // 41 % of this (a check that each section's weight enters).
    let pipe_only = mu * weight(PIPE) * climb * 0.5 * PIPE.1 * 40.0 * scale;
    assert!(top_torque - tob > 2.0 * pipe_only);
}

#[test]
fn one_section_equal_to_the_pipe_is_the_string_without_sections() {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/problems/regression/tiny_string.toml"
    ))
    .unwrap();
    // The sizes move from [model.pipe] (where they are refused beside sections) to the section.
    let sizes = "inner_radius = \"40 mm\"\nouter_radius = \"60 mm\"\n";
    assert!(text.contains(sizes));
    let one = format!(
        "{}\n[[model.section]]\nname = \"pipe\"\nlength = \"8 m\"\nouter_radius = \"60 mm\"\ninner_radius = \"40 mm\"\n",
        text.replace(sizes, "")
    );
    let plain = Problem::from_toml(&text, Path::new("plain.toml")).unwrap();
    let sectioned = Problem::from_toml(&one, Path::new("one.toml")).unwrap();
    assert_eq!(sectioned.model.sections.len(), 1);
    assert_eq!(sectioned.model.sections[0].pipe, plain.model.pipe);
    let (a, b) = (
        common::tiny_run_metrics(&plain),
        common::tiny_run_metrics(&sectioned),
    );
    for ((name, x), (_, y)) in a.iter().zip(&b) {
        assert!(
            x == y || (x.is_nan() && y.is_nan()) || (x - y).abs() <= 1e-9 * x.abs().max(1e-12),
            "{name}: {x} vs {y}"
        );
    }
}

/// A string length written in feet to two decimals (a driller's rounding, 1.2 mm here) is the
/// sum of the sections; 2 cm off is refused.
#[test]
fn a_length_rounded_in_feet_is_the_sum_of_the_sections() {
    let text = two_sections(80, 0.3);
    let exact = Problem::from_toml(&text, Path::new("a.toml")).unwrap();
    let total = exact.model.length;
    let feet = total / 0.3048;
    let rounded = (feet * 100.0).round() / 100.0;
    assert!(
        (rounded * 0.3048 - total).abs() > 1e-4,
        "the rounding must matter"
    );
    let written = text.replacen(
        &format!("length = \"{} m\"", drillopt::units::short(total)),
        &format!("length = \"{rounded:.2} ft\""),
        1,
    );
    assert_ne!(written, text, "the edit applies");
    let p = Problem::from_toml(&written, Path::new("a.toml")).unwrap();
    assert_eq!(p.model.length, total, "the sections' sum");
    let off = text.replacen(
        &format!("length = \"{} m\"", drillopt::units::short(total)),
        &format!("length = \"{} m\"", total + 0.02),
        1,
    );
    let err = Problem::from_toml(&off, Path::new("a.toml")).unwrap_err();
    assert_eq!(err.key(), Some("model.length"), "{err}");
    assert!(err.to_string().contains("within 0.01 m"), "{err}");
}

/// A drill-pipe table's nominal weight (tool joints included) typed as the tube's plain-end
/// `linear_weight` is refused with the plain-end weight and the ID to give instead (helper-28
/// typed 19.5 lb/ft for 5 in pipe: 8.8 % more steel than the pipe has).
#[test]
fn a_nominal_drill_pipe_weight_is_refused_with_the_plain_end_weight() {
    let text = two_sections(80, 0.3);
    let nominal = text.replace(
        "inner_diameter = \"4.778 in\"",
        "linear_weight = \"21.9 lb/ft\"",
    );
    assert_ne!(nominal, text, "the edit applies");
    let err = Problem::from_toml(&nominal, Path::new("n.toml")).unwrap_err();
    assert_eq!(err.key(), Some("model.section[0].linear_weight"), "{err}");
    let msg = err.to_string();
    for w in [
        "nominal weight of API 5.5 in drill pipe",
        "plain-end weight, 19.96 lb/ft",
        "steel of 7900",
        "4.778 in",
    ] {
        assert!(msg.contains(w), "{w}: {msg}");
    }
    // The plain-end weight itself is taken.
    let plain = text.replace(
        "inner_diameter = \"4.778 in\"",
        "linear_weight = \"19.81 lb/ft\"",
    );
    Problem::from_toml(&plain, Path::new("p.toml")).unwrap();
}

#[test]
fn bad_sections_are_refused_by_section_and_key_in_one_pass() {
    let text = two_sections(80, 0.3)
        // Collars wider than the 8½ in hole, drill pipe with its bore wider than its OD, a
        // duplicate name, lengths that do not add up, and a section without a name.
        .replace("outer_diameter = \"6.75 in\"", "outer_diameter = \"9 in\"")
        .replace("inner_diameter = \"4.778 in\"", "inner_diameter = \"6 in\"")
        .replace("name = \"collars\"", "name = \"drill pipe\"")
        .replace("length = \"10 m\"", "length = \"12 m\"")
        + "\n[[model.section]]\nlength = \"1 m\"\nouter_radius = \"50 mm\"\ninner_radius = \"20 mm\"\n";
    let err = Problem::from_toml(&text, Path::new("cases/bad_sections.toml")).unwrap_err();
    let keys: Vec<&str> = err.key_errors().iter().map(|e| e.key.as_str()).collect();
    for k in [
        "model.section[0].outer_diameter",
        "model.section[1].outer_diameter",
        "model.section[1].name",
        "model.section[2].name",
        "model.length",
    ] {
        assert!(keys.contains(&k), "{k} missing in {keys:?}: {err}");
    }
    let msg = err.to_string();
    for w in [
        "cases/bad_sections.toml",
        "section \"drill pipe\"",
        "must fit in the hole",
        "is also the name of model.section[0]",
    ] {
        assert!(msg.contains(w), "{w}: {msg}");
    }
    // A radius and a diameter at once; more sections than elements; a pipe density declared
    // uncertain (the sections carry their own).
    let both = two_sections(80, 0.3).replace(
        "outer_diameter = \"5.5 in\"",
        "outer_diameter = \"5.5 in\"\nouter_radius = \"2.75 in\"",
    );
    let err = Problem::from_toml(&both, Path::new("b.toml")).unwrap_err();
    assert_eq!(err.key(), Some("model.section[0].outer_diameter"), "{err}");
    let negative = two_sections(80, 0.3).replace("length = \"10 m\"", "length = \"-10 m\"");
    let err = Problem::from_toml(&negative, Path::new("b.toml")).unwrap_err();
    let keys: Vec<&str> = err.key_errors().iter().map(|e| e.key.as_str()).collect();
    assert!(keys.contains(&"model.section[1].length"), "{err}");
    let sized = two_sections(80, 0.3).replace(
        "poisson_ratio = 0.3\n",
        "poisson_ratio = 0.3\nouter_radius = \"69.85 mm\"\n",
    );
    let err = Problem::from_toml(&sized, Path::new("b.toml")).unwrap_err();
    assert_eq!(err.key(), Some("model.pipe.outer_radius"), "{err}");
    assert!(err.to_string().contains("not used beside"), "{err}");
    let err = Problem::from_toml(&two_sections(1, 0.3), Path::new("b.toml")).unwrap_err();
    assert_eq!(err.key(), Some("mesh.elements"), "{err}");
    let uncertain = two_sections(80, 0.3)
        + "\n[uncertain]\nsamples = 2\n[[uncertain.parameter]]\nkey = \"model.pipe.density\"\nlaw = \"uniform\"\nlow = \"7800 kg/m^3\"\nhigh = \"8000 kg/m^3\"\n";
    let err = Problem::from_toml(&uncertain, Path::new("b.toml")).unwrap_err();
    assert_eq!(err.key(), Some("uncertain.parameter[0].key"), "{err}");
}

#[test]
fn a_graded_mesh_gives_each_section_its_elements_and_verify_doubles_each() {
    let graded = two_sections(60, 0.3)
        .replace(
            "inner_diameter = \"4.778 in\"",
            "inner_diameter = \"4.778 in\"\nelements = 20",
        )
        .replace(
            "inner_diameter = \"2.8125 in\"",
            "inner_diameter = \"2.8125 in\"\nelements = 40",
        );
    let p = Problem::from_toml(&graded, Path::new("graded.toml")).unwrap();
    let layout = drillopt::fem::ElementLayout::of(&p.model, p.mesh.elements);
    assert_eq!(layout.kinds().len(), 2);
    assert_eq!(layout.element(0).length, 1.5, "30 m in 20 elements");
    assert_eq!(layout.element(59).length, 0.25, "10 m in 40 elements");
    approx::assert_relative_eq!(layout.node_x(20), 30.0, max_relative = 1e-12);
    approx::assert_relative_eq!(layout.node_x(60), 40.0, max_relative = 1e-12);
    // The refined mesh of `verify` (twice the elements) halves every section's elements.
    let refined = drillopt::fem::ElementLayout::of(&p.model, 120);
    assert_eq!(refined.element(0).length, 0.75);
    assert_eq!(refined.element(119).length, 0.125);
    // The sum must be [mesh] elements, and either every section gives its count or none.
    let err = Problem::from_toml(
        &graded.replace("elements = 60", "elements = 61"),
        Path::new("g.toml"),
    )
    .unwrap_err();
    assert_eq!(err.key(), Some("mesh.elements"), "{err}");
    let partial = graded.replace("elements = 20\n", "");
    let err = Problem::from_toml(&partial, Path::new("g.toml")).unwrap_err();
    assert_eq!(err.key(), Some("model.section[0].elements"), "{err}");
}

/// A drill-pipe table gives the OD and the weight: API 5DP 5½ in 21.90 lb/ft pipe has a
/// 4.778 in bore and a plain-end (body) weight of 19.81 lb/ft; from the OD and that weight, with
/// the steel density API uses (489.5 lb/ft³, 7841 kg/m³), the bore is 4.778 in again.
#[test]
fn an_outer_diameter_and_a_linear_weight_give_the_bore() {
    let text = two_sections(80, 0.3).replace(
        "inner_diameter = \"4.778 in\"",
        "linear_weight = \"19.81 lb/ft\"\ndensity = \"7841 kg/m^3\"",
    );
    let p = Problem::from_toml(&text, Path::new("w.toml")).unwrap();
    let pipe = &p.model.sections[0].pipe;
    let bore_in = 2.0 * pipe.inner_radius / 0.0254;
    assert!((bore_in - 4.778).abs() < 2e-3, "bore {bore_in} in");
    // The steel area is the weight over the density, exactly.
    let area = PI * (pipe.outer_radius.powi(2) - pipe.inner_radius.powi(2));
    approx::assert_relative_eq!(
        area * 7841.0,
        19.81 * 0.453_592_37 / 0.3048,
        max_relative = 1e-12
    );
    // A weight heavier than a solid bar of that OD, a weight beside a bore, and none at all.
    let heavy = text.replace("19.81 lb/ft", "200 lb/ft");
    let err = Problem::from_toml(&heavy, Path::new("w.toml")).unwrap_err();
    assert_eq!(err.key(), Some("model.section[0].linear_weight"), "{err}");
    assert!(err.to_string().contains("solid bar"), "{err}");
    let both = text.replace(
        "linear_weight = \"19.81 lb/ft\"",
        "linear_weight = \"19.81 lb/ft\"\ninner_diameter = \"4.778 in\"",
    );
    let err = Problem::from_toml(&both, Path::new("w.toml")).unwrap_err();
    assert_eq!(err.key(), Some("model.section[0].linear_weight"), "{err}");
    let none = text.replace("linear_weight = \"19.81 lb/ft\"\n", "");
    let err = Problem::from_toml(&none, Path::new("w.toml")).unwrap_err();
    assert_eq!(err.key(), Some("model.section[0].inner_radius"), "{err}");
    assert!(err.to_string().contains("linear_weight"), "{err}");
}

/// The radial probe's plot draws the wall at the probe's own gap: on the drill pipe of
/// `problems/bha_example.toml` (5.5 in in an 8.5 in hole: 38.1 mm), not the near-gauge
/// stabiliser's 1.5875 mm, the smallest gap of the string.
#[test]
fn a_probe_on_the_drill_pipe_draws_the_wall_at_the_pipes_gap() {
    let dir = tempfile::tempdir().unwrap();
    let file = concat!(env!("CARGO_MANIFEST_DIR"), "/problems/bha_example.toml");
    let out = dir.path().join("run");
    let o = common::drillopt(&[
        "simulate",
        file,
        "--duration",
        "0.05",
        "--quiet",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let svg = std::fs::read_to_string(out.join("radial_x200m.svg")).unwrap();
    let pipe_gap_mm = (0.108 - 0.5 * 5.5 * 0.0254) * 1e3;
    assert!(
        svg.contains(&format!("wall, r = gap = {pipe_gap_mm:.4} mm")),
        "{}",
        svg.lines()
            .filter(|l| l.contains("gap"))
            .collect::<Vec<_>>()
            .join("\n")
    );
    assert!(svg.contains("Radial displacement at x = 200 m,"));
}
