//! Validation of `[optimizer.explore]` ([`super::study::Explore`]) against the full fidelity it
//! overrides: every key is checked, every refusal names the file and the key and says what is
//! allowed, and an override that is not cheaper than the full fidelity is refused (a longer
//! window, as many samples or more, a family with more modes). Every refusal is recorded (one
//! pass); the section reads as `None` when one was.

use super::Dimension::Time;
use super::check::{Checker, family_size};
use super::schema::BasisSection;
use super::study::{
    CONFIRM, CONFIRM_RANGE, Explore, MARGIN_RANGE, MAX_CONFIRM_RANGE, MAX_CONFIRM_ROUNDS,
    REFINE_RANGE, RawExplore, SEPARATION, SEPARATION_RANGE, Study,
};
use crate::model::{BasisSpec, FamilySize, Mesh, Simulation};
use crate::units::short;

const KEY: &str = "optimizer.explore";

fn key(k: &str) -> String {
    format!("{KEY}.{k}")
}

/// The explore fidelity of `raw`, checked against the full fidelity's `mesh`, `simulation` and
/// `study` (None where that section was refused: the comparisons with it are skipped, it was
/// reported where it was read).
pub(super) fn explore(
    c: &Checker,
    raw: &RawExplore,
    mesh: Option<&Mesh>,
    simulation: Option<&Simulation>,
    study: &Study,
) -> Option<Explore> {
    let before = c.errors_recorded();
    if raw.duration.is_none() && raw.samples.is_none() && raw.basis.is_none() {
        c.record(
            KEY,
            "must make the exploration cheaper than the full fidelity: give at least one of \
             duration (a shorter window), samples (fewer Monte Carlo samples per point) or \
             [optimizer.explore.basis] (a smaller basis)"
                .into(),
        );
    }
    let (duration, settling_time) = window(c, raw, simulation);
    let samples = raw.samples.and_then(|n| samples(c, n, study));
    let confirm = match raw.confirm {
        None => CONFIRM,
        Some(n) => match usize::try_from(n) {
            Ok(n) if CONFIRM_RANGE.contains(&n) => n,
            _ => {
                c.record(
                    &key("confirm"),
                    format!(
                        "must be an integer in [{}, {}] (the distinct best explore candidates re-evaluated at full fidelity), got {n}",
                        CONFIRM_RANGE.start(),
                        CONFIRM_RANGE.end()
                    ),
                );
                0
            }
        },
    };
    let max_confirm = max_confirm(c, raw.max_confirm, confirm);
    let separation = match raw.separation {
        None => SEPARATION,
        Some(d) if d.is_finite() && SEPARATION_RANGE.contains(&d) => d,
        Some(d) => {
            c.record(
                &key("separation"),
                format!(
                    "must be a number in [{}, {}] (the least distance between two candidates, as a fraction of the box: Ω and V0 scaled by their bounds; 0 separates exact duplicates only), got {d}",
                    SEPARATION_RANGE.start(),
                    SEPARATION_RANGE.end()
                ),
            );
            0.0
        }
    };
    let margin = match raw.margin {
        None => 0.0,
        Some(m) if m.is_finite() && MARGIN_RANGE.contains(&m) => {
            if m > 0.0
                && study
                    .constraints
                    .as_ref()
                    .is_none_or(|c| c.chance.is_empty())
            {
                c.record(
                    &key("margin"),
                    format!(
                        "tightens the chance constraints' thresholds at the explore fidelity, and the problem has no [[constraints.chance]]; remove the key, got {m}"
                    ),
                );
            }
            m
        }
        Some(m) => {
            c.record(
                &key("margin"),
                format!(
                    "must be a number in [{}, {}] (the fraction by which each chance constraint's threshold is tightened at the explore fidelity; 0: as written), got {m}",
                    MARGIN_RANGE.start(),
                    MARGIN_RANGE.end()
                ),
            );
            0.0
        }
    };
    let refine = match raw.refine {
        None => 0,
        Some(n) => match usize::try_from(n) {
            Ok(n) if REFINE_RANGE.contains(&n) => {
                if n > 0 && study.optimizer.trust_radii().is_none() {
                    c.record(
                        &key("refine"),
                        format!(
                            "is a trust-region refinement: only for method = \"trust_region\" or \"ego+trust_region\" (whose initial_radius and min_radius it uses), not \"{}\"; use 0 or remove the key, got {n}",
                            study.optimizer.method().name()
                        ),
                    );
                }
                n
            }
            _ => {
                c.record(
                    &key("refine"),
                    format!(
                        "must be an integer in [{}, {}] (full-fidelity design points of a trust-region refinement from the best confirmed point; 0: none), got {n}",
                        REFINE_RANGE.start(),
                        REFINE_RANGE.end()
                    ),
                );
                0
            }
        },
    };
    let basis = raw.basis.as_ref().and_then(|b| basis(c, b, mesh));
    (c.errors_recorded() == before).then_some(Explore {
        duration,
        settling_time,
        samples,
        basis,
        confirm,
        max_confirm,
        separation,
        margin,
        refine,
    })
}

/// `max_confirm`: the most candidates confirmed in all, at least `confirm` (0 when `confirm`
/// was refused: then only the range is checked).
fn max_confirm(c: &Checker, raw: Option<i64>, confirm: usize) -> usize {
    let (least, most) = (
        confirm.max(*MAX_CONFIRM_RANGE.start()),
        *MAX_CONFIRM_RANGE.end(),
    );
    match raw {
        None => (confirm * MAX_CONFIRM_ROUNDS).clamp(confirm, most),
        Some(n) => match usize::try_from(n) {
            Ok(n) if (least..=most).contains(&n) => n,
            _ => {
                c.record(
                    &key("max_confirm"),
                    format!(
                        "must be an integer in [{least}, {most}], at least confirm = {confirm} (the most candidates confirmed at full fidelity in all: the next ones of the explore ranking are confirmed while none is feasible), got {n}"
                    ),
                );
                0
            }
        },
    }
}

/// `duration` and `settling_time`: the explore window, shorter than the full one, with its
/// settling inside it (a settling time not given is the full fidelity's).
fn window(
    c: &Checker,
    raw: &RawExplore,
    simulation: Option<&Simulation>,
) -> (Option<f64>, Option<f64>) {
    let full = simulation.map_or(f64::NAN, |s| s.duration);
    let full_settling = simulation.map_or(f64::NAN, |s| s.settling_time);
    let step = simulation.map_or(f64::NAN, |s| s.time_step);
    let duration = raw.duration.as_ref().map(|d| {
        let k = key("duration");
        let d = c.value_as(&k, "simulation.duration", d, Time);
        if d.is_nan() || full.is_nan() {
            return d;
        }
        if d >= full {
            return c.record(
                &k,
                format!(
                    "must be shorter than simulation.duration ({} s): the explore window is the cheap one, got {} s",
                    short(full),
                    short(d)
                ),
            );
        }
        if d < step {
            return c.record(
                &k,
                format!(
                    "must be at least simulation.time_step ({} s) and shorter than simulation.duration ({} s), got {} s",
                    short(step),
                    short(full),
                    short(d)
                ),
            );
        }
        d
    });
    let settling = raw.settling_time.as_ref().map(|t| {
        c.non_negative(&key("settling_time"), t, Time)
            .unwrap_or(f64::NAN)
    });
    let window_end = duration.unwrap_or(full);
    match settling {
        Some(t) if !t.is_nan() && !window_end.is_nan() && t > 0.5 * window_end => {
            c.record(
                &key("settling_time"),
                format!(
                    "must be in [0, {} s], at most half the explore duration (the metrics are read over the window after it, which must be no shorter), got {} s",
                    short(0.5 * window_end),
                    short(t)
                ),
            );
        }
        None if duration.is_some_and(|d| !d.is_nan())
            && !full_settling.is_nan()
            && full_settling > 0.5 * window_end =>
        {
            c.record(
                &key("duration"),
                format!(
                    "must be at least twice simulation.settling_time ({} s), which the explore window keeps unless optimizer.explore.settling_time is given, got {} s",
                    short(full_settling),
                    short(window_end)
                ),
            );
        }
        _ => {}
    }
    (duration, settling)
}

/// `samples`: fewer than the full fidelity's (samples 0..n of the same draws), above the
/// sequential rule's first round when there is one.
fn samples(c: &Checker, n: i64, study: &Study) -> Option<usize> {
    let k = key("samples");
    let full = study.samples;
    if study.uncertain.is_empty() {
        c.record(
            &k,
            format!(
                "the problem is deterministic (no [[uncertain.parameter]], one sample per point): there are no samples to save; remove the key, got {n}"
            ),
        );
        return None;
    }
    let least = study.sequential.map_or(1, |s| s.min_samples + 1);
    match usize::try_from(n) {
        Ok(m) if m >= least && m < full => Some(m),
        _ => {
            let why = match study.sequential {
                Some(s) => format!(
                    "above uncertain.sequential.min_samples = {} (the most samples an explore point may use) and",
                    s.min_samples
                ),
                None => "at least 1 and".into(),
            };
            c.record(
                &k,
                format!(
                    "must be an integer in [{least}, {}], {why} fewer than uncertain.samples = {full} (the explore fidelity is the cheap one), got {n}",
                    full.saturating_sub(1)
                ),
            );
            None
        }
    }
}

/// `[optimizer.explore.basis]`: read as `[mesh.basis]` is, then no family richer than the full
/// basis's where the two can be compared without the modes (counts with counts, cutoffs with
/// cutoffs), no static corrections the full basis lacks, and not the full basis itself. The
/// sizes of the two reduced models are compared when they are built.
fn basis(c: &Checker, b: &BasisSection, mesh: Option<&Mesh>) -> Option<BasisSpec> {
    let mesh = mesh?;
    let family = |name: &str, raw| {
        c.section(family_size(
            c,
            &format!("{KEY}.basis.{name}"),
            raw,
            mesh.elements,
        ))
    };
    let bending = family("bending", &b.bending);
    let torsional = family("torsional", &b.torsional);
    let axial = family("axial", &b.axial);
    let (bending, torsional, axial) = (bending?, torsional?, axial?);
    let static_corrections = b.static_corrections.unwrap_or(true);
    let steady_shapes = b.steady_shapes.unwrap_or(false);
    let spec = BasisSpec::PerFamily {
        bending,
        torsional,
        axial,
        static_corrections,
        steady_shapes,
    };
    if spec == mesh.basis {
        c.record(
            &format!("{KEY}.basis"),
            format!(
                "is the full basis ({}): the explore basis must be smaller",
                mesh.basis
            ),
        );
        return None;
    }
    let BasisSpec::PerFamily {
        bending: full_b,
        torsional: full_t,
        axial: full_a,
        static_corrections: full_sc,
        ..
    } = mesh.basis
    else {
        // The N lowest modes: compared by size when the models are built.
        return Some(spec);
    };
    let mut ok = true;
    for (name, explore, full) in [
        ("bending", bending, full_b),
        ("torsional", torsional, full_t),
        ("axial", axial, full_a),
    ] {
        let richer = match (explore, full) {
            (FamilySize::Count(e), FamilySize::Count(f)) => e > f,
            (FamilySize::Cutoff { hz: e, .. }, FamilySize::Cutoff { hz: f, .. }) => e > f,
            _ => false,
        };
        if richer {
            ok = false;
            c.record(
                &format!("{KEY}.basis.{name}"),
                format!(
                    "must not keep more {name} modes than the full basis (mesh.basis: {full}): the explore basis is the cheap one, got {explore}"
                ),
            );
        }
    }
    if static_corrections && !full_sc {
        ok = false;
        c.record(
            &format!("{KEY}.basis.static_corrections"),
            "must be false when the full basis has none (mesh.basis.static_corrections = false): the explore basis is the cheap one, got true".into(),
        );
    }
    if steady_shapes && !spec.steady_shapes() {
        ok = false;
        c.record(
            &format!("{KEY}.basis.steady_shapes"),
            "needs the static corrections (the steady state's shapes join the resting shapes): set static_corrections = true or leave steady_shapes out, got true".into(),
        );
    } else if steady_shapes && !mesh.basis.steady_shapes() {
        ok = false;
        c.record(
            &format!("{KEY}.basis.steady_shapes"),
            "must be false when the full basis has none (mesh.basis.steady_shapes = false): the explore basis is the cheap one, got true".into(),
        );
    }
    ok.then_some(spec)
}
