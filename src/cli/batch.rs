//! `drillopt batch DIR`: solve every problem of DIR that has an `[expect]` section and check the
//! optimum against its expected ranges; a pass/fail table; exit status 1 on any failure.

use crate::problem::Problem;
use clap::Args;
use std::path::{Path, PathBuf};

#[derive(Debug, Args)]
pub struct BatchArgs {
    /// Directory of problem files (*.toml, searched recursively).
    pub dir: PathBuf,
    #[command(flatten)]
    pub run: super::study::RunArgs,
}

fn toml_files(dir: &Path, out: &mut Vec<PathBuf>) -> anyhow::Result<()> {
    let mut entries: Vec<_> = std::fs::read_dir(dir)
        .map_err(|e| anyhow::anyhow!("{}: {e}", dir.display()))?
        .collect::<Result<_, _>>()?;
    entries.sort_by_key(|e| e.path());
    for e in entries {
        let p = e.path();
        if p.is_dir() {
            toml_files(&p, out)?;
        } else if p.extension().is_some_and(|x| x == "toml") {
            out.push(p);
        }
    }
    Ok(())
}

/// Where batch writes: `--out`, else `results/batch/` (ignored by git: a regression run must not
/// overwrite the committed reports of `results/`, issue 13 item 17); one directory per problem.
pub fn out_root(out: &Option<PathBuf>) -> PathBuf {
    out.clone()
        .unwrap_or_else(|| Path::new("results").join("batch"))
}

/// The verdict on one problem.
#[derive(Debug, Clone, PartialEq)]
pub struct Verdict {
    pub problem: String,
    pub pass: bool,
    pub detail: String,
}

/// Check an optimum against the expected ranges.
pub fn check(
    expect: &crate::problem::study::Expect,
    kind: crate::model::SetPoint,
    op: crate::model::OperatingPoint,
    score: f64,
) -> (bool, String) {
    let (omega, s) = (op.omega, op.set_point(kind));
    let (symbol, unit) = (kind.symbol(), kind.unit());
    let mut fails = Vec::new();
    let rpm = crate::units::to_rpm;
    if !(expect.omega[0]..=expect.omega[1]).contains(&omega) {
        fails.push(format!(
            "Ω = {:.1} rpm outside [{:.1}, {:.1}]",
            rpm(omega),
            rpm(expect.omega[0]),
            rpm(expect.omega[1])
        ));
    }
    if !(expect.set_point[0]..=expect.set_point[1]).contains(&s) {
        fails.push(format!(
            "{symbol} = {:.2} {unit} outside [{:.2}, {:.2}]",
            kind.to_unit(s),
            kind.to_unit(expect.set_point[0]),
            kind.to_unit(expect.set_point[1])
        ));
    }
    if let Some([lo, hi]) = expect.objective
        && !(lo..=hi).contains(&score)
    {
        fails.push(format!("score {score:.3} outside [{lo}, {hi}]"));
    }
    if fails.is_empty() {
        (
            true,
            format!(
                "Ω = {:.1} rpm, {symbol} = {:.2} {unit}, score {score:.3}",
                rpm(omega),
                kind.to_unit(s)
            ),
        )
    } else {
        (false, fails.join("; "))
    }
}

/// Whether the constraints at their limit at the optimum `best` ([`crate::solve::activity`]) are
/// those `[expect] active` declares: the reason a regression problem gives for its optimum is
/// checked, not only its place. `None` when they agree, else what differs.
pub fn held_by_mismatch(
    declared: &[crate::problem::study::ActiveConstraint],
    constraints: &crate::problem::study::Constraints,
    best: &crate::study::PointEvaluation,
    evaluated: &[crate::study::PointEvaluation],
) -> Option<String> {
    use std::collections::BTreeSet;
    let declared: BTreeSet<String> = declared.iter().map(|a| a.name(constraints.kind)).collect();
    let held: BTreeSet<String> = crate::solve::activity(constraints, best, evaluated)
        .into_iter()
        .filter(|a| a.at_limit)
        .map(|a| a.name)
        .collect();
    (declared != held).then(|| {
        let list = |s: &BTreeSet<String>| {
            if s.is_empty() {
                "none".to_string()
            } else {
                s.iter().cloned().collect::<Vec<_>>().join(", ")
            }
        };
        format!(
            "held by {} at the optimum, but [expect] active declares {}",
            list(&held),
            list(&declared)
        )
    })
}

/// `units`: of each solve's terminal output and reports; the pass/fail table compares with the
/// `[expect]` ranges in the units they are written in (rpm, m/h, kN).
pub fn run(args: &BatchArgs, units: crate::units::UnitSystem) -> anyhow::Result<()> {
    let mut files = Vec::new();
    toml_files(&args.dir, &mut files)?;
    super::study::start_threads(args.run.threads)?;
    let _root_lock = super::create_out_dir(&out_root(&args.run.out))?;
    let mut verdicts = Vec::new();
    let mut written: std::collections::BTreeMap<String, PathBuf> = Default::default();
    for file in &files {
        let loaded = Problem::load(file)
            .map_err(anyhow::Error::from)
            .and_then(|mut p| {
                super::study::apply_overrides(&mut p, file, &args.run, None)?;
                Ok(p)
            });
        let problem = match loaded {
            Ok(p) => p,
            Err(e) => {
                verdicts.push(Verdict {
                    problem: file.display().to_string(),
                    pass: false,
                    detail: format!("invalid: {e}"),
                });
                continue;
            }
        };
        let Some(expect) = problem.study.expect.clone() else {
            if !args.run.quiet {
                println!("skip {} (no [expect] section)", file.display());
            }
            continue;
        };
        let out = out_root(&args.run.out).join(&problem.name);
        // Each problem writes to <out>/<name>: a second file of the same name would overwrite
        // the first one's report (and set its cache aside).
        if let Some(first) = written.get(&problem.name) {
            verdicts.push(Verdict {
                problem: problem.name.clone(),
                pass: false,
                detail: format!(
                    "{}: not solved: `name = \"{}\"` is also the name of {}, whose report in {} it would overwrite; give one of them another name",
                    file.display(),
                    problem.name,
                    first.display(),
                    out.display()
                ),
            });
            continue;
        }
        written.insert(problem.name.clone(), file.clone());
        let verdict = match super::create_out_dir(&out).and_then(|_out_lock| {
            super::solve::solve_and_report(
                &problem,
                file,
                &out,
                args.run.resume,
                args.run.quiet,
                !args.run.quiet,
                units,
            )
        }) {
            Err(e) => Verdict {
                problem: problem.name.clone(),
                pass: false,
                detail: format!("error: {}", super::error_text(&e)),
            },
            Ok((outcome, numbers)) => match outcome.best {
                None => Verdict {
                    problem: problem.name.clone(),
                    pass: false,
                    detail: "no feasible point".into(),
                },
                Some(b) => {
                    let (mut pass, mut detail) = check(
                        &expect,
                        problem.model.top.set_point(),
                        b.op(),
                        b.objective.unwrap_or(f64::NAN),
                    );
                    if let (Some(declared), Some(k)) = (&expect.active, &problem.study.constraints)
                    {
                        match held_by_mismatch(declared, k, &b, &outcome.evaluations) {
                            Some(why) => {
                                pass = false;
                                detail = format!("{detail}; {why}");
                            }
                            None if declared.is_empty() => detail.push_str(", held by none"),
                            None => {
                                let names: Vec<String> =
                                    declared.iter().map(|a| a.name(k.kind)).collect();
                                detail = format!("{detail}, held by {}", names.join(", "));
                            }
                        }
                    }
                    // Not judged (a regression set may be kept cheap), but said.
                    if let Some(c) = &numbers {
                        detail.push_str(if c.converged {
                            "; numerical check converged"
                        } else {
                            "; numerical check NOT converged"
                        });
                    }
                    Verdict {
                        problem: problem.name.clone(),
                        pass,
                        detail,
                    }
                }
            },
        };
        verdicts.push(verdict);
    }
    println!("{:30} {:6} detail", "problem", "result");
    for v in &verdicts {
        println!(
            "{:30} {:6} {}",
            v.problem,
            if v.pass { "PASS" } else { "FAIL" },
            v.detail
        );
    }
    let failed = verdicts.iter().filter(|v| !v.pass).count();
    anyhow::ensure!(
        !verdicts.is_empty(),
        "no problem with an [expect] section in {}",
        args.dir.display()
    );
    anyhow::ensure!(
        failed == 0,
        "{failed} of {} regression problems failed",
        verdicts.len()
    );
    println!("all {} regression problems pass", verdicts.len());
    Ok(())
}

#[cfg(test)]
mod tests {
    use crate::model::{OperatingPoint, SetPoint};
    use crate::problem::study::Expect;

    #[test]
    fn the_declared_active_constraints_must_be_those_at_their_limit() {
        use crate::problem::study::{ActiveConstraint, ChanceConstraint, Constraints};
        let rpm = crate::units::from_rpm;
        let c = Constraints {
            omega: [rpm(30.0), rpm(150.0)],
            kind: SetPoint::Feed,
            set_point: [2.0 / 3600.0, 20.0 / 3600.0],
            linear: Vec::new(),
            chance: vec![ChanceConstraint {
                metric: "fatigue_damage_per_h".into(),
                threshold: 0.05,
                max_probability: 0.1,
            }],
        };
        let p = crate::solve::activity_tests::point(
            OperatingPoint::feed(rpm(30.0), 5.0 / 3600.0),
            &[0.0499],
        );
        let chance = ActiveConstraint::Chance("fatigue_damage_per_h".into());
        let both = [ActiveConstraint::OmegaMin, chance.clone()];
        assert_eq!(super::held_by_mismatch(&both, &c, &p, &[]), None);
        let why = super::held_by_mismatch(&[chance], &c, &p, &[]).unwrap();
        assert!(
            why.contains("held by chance.fatigue_damage_per_h, omega.min")
                && why.contains("declares chance.fatigue_damage_per_h"),
            "{why}"
        );
        let why = super::held_by_mismatch(&[], &c, &p, &[]).unwrap();
        assert!(why.ends_with("declares none"), "{why}");
    }

    #[test]
    fn check_reports_each_range_it_misses() {
        let e = Expect {
            omega: [5.0, 8.0],
            set_point: [1e-3, 2e-3],
            objective: Some([1.0, 2.0]),
            reason: "test".into(),
            active: None,
        };
        let feed = SetPoint::Feed;
        assert!(super::check(&e, feed, OperatingPoint::feed(6.0, 1.5e-3), 1.5).0);
        let (pass, why) = super::check(&e, feed, OperatingPoint::feed(9.0, 3e-3), 2.5);
        assert!(!pass);
        assert!(
            why.contains("Ω") && why.contains("V0") && why.contains("score"),
            "{why}"
        );
        // A hook load's range is the WOB's, in kN.
        let e = Expect {
            set_point: [40e3, 60e3],
            ..e
        };
        let wob = SetPoint::Wob;
        assert!(super::check(&e, wob, OperatingPoint::hook_load(6.0, 50e3), 1.5).0);
        let (pass, why) = super::check(&e, wob, OperatingPoint::hook_load(6.0, 70e3), 1.5);
        assert!(
            !pass && why.contains("WOB = 70.00 kN outside [40.00, 60.00]"),
            "{why}"
        );
    }
}
