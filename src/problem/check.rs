//! The checker every validation module reads the raw file through ([`Checker`]), and the
//! checks several sections share (the mesh's element count, a basis family's size, the yield
//! strength, a value's bare-number form). A leaf of the validation: the sections' modules
//! ([`super::validate`] and the `validate_*` modules) use it, it uses none of them.

use super::error::KeyError;
use super::schema::*;
use super::{Dimension, ProblemError};
use crate::model::{FamilySize, ParameterSpec};
use crate::units::show;
use std::cell::RefCell;
use std::path::Path;

/// Reads values from the raw file and checks them, naming the file and key on failure.
///
/// All refusals of a file are reported in one pass: a value that cannot be read (unknown unit,
/// not finite) or lies outside its range is recorded and reads as NaN, and validation goes on; a
/// check that meets a NaN skips it (it was reported where it was read). A refusal that leaves
/// nothing sensible to check (an unknown law, method or basis) still ends its section, returned
/// as `Err`; [`Checker::section`] records it and the other sections are checked. [`Checker::finish`]
/// returns everything recorded as one [`ProblemError::Invalid`].
pub(super) struct Checker<'a> {
    pub(super) file: &'a Path,
    errors: RefCell<Vec<KeyError>>,
    /// How many of `errors` are the parse's shape errors.
    shape: usize,
    /// Keys of the wrong type (reported among the shape errors), taken out or stood in for: a
    /// refusal of one of them, or of a key under it, is about its stand-in and not reported.
    masked: Vec<String>,
}

impl<'a> Checker<'a> {
    /// A checker for `file` that already holds the parse's shape errors; `masked`: the keys of
    /// the wrong type among them (see [`super::validate::parse`]).
    pub(super) fn new(file: &'a Path, errors: Vec<KeyError>, masked: Vec<String>) -> Self {
        Checker {
            file,
            shape: errors.len(),
            errors: RefCell::new(errors),
            masked,
        }
    }

    pub(super) fn fail(&self, key: &str, message: String) -> ProblemError {
        ProblemError::invalid(self.file, key, message)
    }

    /// Record a refusal and carry on: the value reads as NaN.
    pub(super) fn record(&self, key: &str, message: String) -> f64 {
        self.errors.borrow_mut().push(KeyError {
            key: key.to_string(),
            message,
        });
        f64::NAN
    }

    /// How many refusals have been recorded so far.
    pub(super) fn errors_recorded(&self) -> usize {
        self.errors.borrow().len()
    }

    /// A section's value, or `None` with its refusal recorded.
    pub(super) fn section<T>(&self, result: Result<T, ProblemError>) -> Option<T> {
        match result {
            Ok(v) => Some(v),
            Err(e) => {
                let mut errors = self.errors.borrow_mut();
                match e {
                    ProblemError::Invalid { errors: more, .. } => errors.extend(more),
                    other => errors.push(KeyError {
                        key: "(file)".into(),
                        message: other.to_string(),
                    }),
                }
                None
            }
        }
    }

    /// Every refusal recorded, as one error; `Ok` when there is none.
    pub(super) fn finish(self) -> Result<(), ProblemError> {
        let mut errors = self.errors.into_inner();
        let masked = &self.masked;
        let under = |key: &str| {
            masked.iter().any(|m| {
                key == m
                    || key
                        .strip_prefix(m.as_str())
                        .is_some_and(|rest| rest.starts_with(['.', '[']))
            })
        };
        // A refusal that names a masked key in its message rests on its stand-in too (a count
        // of modes against `mesh.elements`).
        let cites = |message: &str| masked.iter().any(|m| message.contains(m.as_str()));
        let later = errors.split_off(self.shape.min(errors.len()));
        errors.extend(
            later
                .into_iter()
                .filter(|e| !under(&e.key) && !cites(&e.message)),
        );
        if errors.is_empty() {
            Ok(())
        } else {
            Err(ProblemError::Invalid {
                file: self.file.to_path_buf(),
                errors,
            })
        }
    }

    /// The value of a key of the key table ([`super::keys::KEYS`]) given as `raw` (SI, within
    /// the key's range, in its dimension), or when it is not given the table's default; a
    /// required key left out is refused (recorded: it reads as NaN).
    pub(super) fn key_value(
        &self,
        key: &str,
        raw: Option<&RawQuantity>,
    ) -> Result<f64, ProblemError> {
        let Some(row) = super::keys::find(key) else {
            // A programming error that the key table's tests catch: said, not a panic.
            return Err(self.fail(
                key,
                "is not in the key table (a bug: please report it)".into(),
            ));
        };
        match (raw, row.spec.default) {
            (Some(raw), _) => self.value(key, raw, row.spec.dimension),
            (None, Some(default)) => Ok(default),
            (None, None) => {
                let (unit, factor) = shown_in(key, row.spec.dimension);
                Ok(self.record(
                    key,
                    format!(
                        "is required: a value {}",
                        row.spec.range.describe_in(unit, factor)
                    ),
                ))
            }
        }
    }

    /// A finite value in SI units, within its admissible range (see [`super::keys`]).
    pub(super) fn value(
        &self,
        key: &str,
        raw: &RawQuantity,
        dim: Dimension,
    ) -> Result<f64, ProblemError> {
        let v = self.finite(key, raw, dim);
        Ok(self.admissible(key, v, dim, raw))
    }

    /// A finite value in SI units under `key`, within the admissible range of `range_key`: a
    /// bound of `[constraints]` or `optimizer.start` takes the range of the operating point's
    /// key, so that a file key, its override and `--point` obey one range.
    pub(super) fn value_as(
        &self,
        key: &str,
        range_key: &str,
        raw: &RawQuantity,
        dim: Dimension,
    ) -> f64 {
        let v = self.finite(key, raw, dim);
        self.admissible_as(key, range_key, v, dim, raw)
    }

    /// A finite value of a declared parameter, in SI units, within the parameter's range.
    pub(super) fn spec_value(
        &self,
        spec: &ParameterSpec,
        raw: &RawQuantity,
    ) -> Result<f64, ProblemError> {
        let v = self.finite(spec.key, raw, spec.dimension);
        if v.is_nan() || spec.range.contains(v) {
            Ok(v)
        } else {
            Ok(self.record(
                spec.key,
                format!(
                    "must be {}, got {}",
                    spec.range.describe(spec.dimension),
                    got(v, spec.dimension.si_unit(), 1.0, raw)
                ),
            ))
        }
    }

    /// A finite value in SI units (no range check); NaN, recorded, when it is not one.
    fn finite(&self, key: &str, raw: &RawQuantity, dim: Dimension) -> f64 {
        let v = match raw {
            RawQuantity::Number(v)
                if dim != Dimension::Dimensionless && v.is_finite() && *v != 0.0 =>
            {
                return self.record(key, bare_number(*v, dim));
            }
            RawQuantity::Number(v) => *v,
            // A quoted number with no unit ("60") is the same ambiguity as a bare one.
            RawQuantity::Text(t) if dim != Dimension::Dimensionless && unitless(t) => {
                let v = dim.parse(t).unwrap_or(f64::NAN);
                if v != 0.0 {
                    return self.record(key, bare_number(v, dim));
                }
                v
            }
            RawQuantity::Text(t) => match dim.parse(t) {
                Ok(v) => v,
                Err(e) => return self.record(key, e.to_string()),
            },
        };
        if v.is_finite() {
            v
        } else {
            // 1e300 GPa overflows to inf: say the range the key takes, when it has one.
            let (unit, factor) = shown_in(key, dim);
            let allowed = super::keys::range_of(key).map_or(String::new(), |r| {
                format!(" {}", r.describe_in(unit, factor))
            });
            let typed = match raw {
                RawQuantity::Text(t) => format!(" ({t:?} is beyond the largest double)"),
                RawQuantity::Number(_) => String::new(),
            };
            self.record(
                key,
                format!("must be a finite number{allowed}, got {v}{typed}"),
            )
        }
    }

    /// `v` (read from `raw`) if it lies in the admissible range of `key` (if the key has one).
    fn admissible(&self, key: &str, v: f64, dim: Dimension, raw: &RawQuantity) -> f64 {
        self.admissible_as(key, key, v, dim, raw)
    }

    /// `v` (read from `raw`) if it lies in the admissible range of `range_key` (if it has one);
    /// refused under `key`.
    fn admissible_as(
        &self,
        key: &str,
        range_key: &str,
        v: f64,
        dim: Dimension,
        raw: &RawQuantity,
    ) -> f64 {
        match super::keys::range_of(range_key) {
            Some(r) if !v.is_nan() && !r.contains(v) => {
                let (unit, factor) = shown_in(range_key, dim);
                let of = if key == range_key {
                    String::new()
                } else {
                    format!(", the range of {range_key}")
                };
                self.record(
                    key,
                    format!(
                        "must be {}{of}, got {}",
                        r.describe_in(unit, factor),
                        got(v, unit, factor, raw)
                    ),
                )
            }
            _ => v,
        }
    }

    /// A value that must satisfy `ok`; `allowed` says what is allowed, in words. A NaN `v` was
    /// refused where it was read and is not checked again; a check that compares `v` with
    /// another value must also pass when that value is NaN.
    pub(super) fn check(
        &self,
        key: &str,
        v: f64,
        ok: bool,
        allowed: &str,
        dim: Dimension,
    ) -> Result<f64, ProblemError> {
        if ok || v.is_nan() {
            Ok(v)
        } else {
            let unit = dim.si_unit();
            Ok(self.record(key, format!("must be {allowed}, got {} {unit}", show(v))))
        }
    }

    pub(super) fn positive(
        &self,
        key: &str,
        raw: &RawQuantity,
        dim: Dimension,
    ) -> Result<f64, ProblemError> {
        Ok(self.signed(key, raw, dim, true))
    }

    pub(super) fn non_negative(
        &self,
        key: &str,
        raw: &RawQuantity,
        dim: Dimension,
    ) -> Result<f64, ProblemError> {
        Ok(self.signed(key, raw, dim, false))
    }

    /// A value that must be > 0 (`strict`) or >= 0, and within the key's admissible range if it
    /// has one: one refusal, through the same message as every range ("must be in [0, 1000]
    /// kg m^2 (why)"), the sign said too when the range does not imply it.
    fn signed(&self, key: &str, raw: &RawQuantity, dim: Dimension, strict: bool) -> f64 {
        let v = self.finite(key, raw, dim);
        let sign = if strict { "> 0" } else { ">= 0" };
        let sign_ok = if strict { v > 0.0 } else { v >= 0.0 };
        if v.is_nan() || sign_ok {
            return self.admissible(key, v, dim, raw);
        }
        let (unit, factor) = shown_in(key, dim);
        let allowed = match super::keys::range_of(key) {
            // The range excludes what the sign does: it says it all.
            Some(r) if (r.lo > 0.0 && !(strict && r.zero)) || (r.lo == 0.0 && !strict) => {
                r.describe_in(unit, factor)
            }
            Some(r) => format!("{sign} and {}", r.describe_in(unit, factor)),
            None => sign.to_string(),
        };
        self.record(
            key,
            format!("must be {allowed}, got {}", got(v, unit, factor, raw)),
        )
    }

    /// Whether a refusal was recorded for `prefix` or a key below it (`uncertain` covers
    /// `uncertain.parameter[0].mean`).
    pub(super) fn refused_under(&self, prefix: &str) -> bool {
        self.errors.borrow().iter().any(|e| {
            e.key == prefix
                || e.key
                    .strip_prefix(prefix)
                    .is_some_and(|rest| rest.starts_with(['.', '[']))
        })
    }
}

/// The unit a refusal of `key` is said in, and its size in SI: the operating point in the
/// driller's rpm and m/h (`omega = "1e-300 rpm"` was refused as "must be in
/// [0.10471975511965977, 104.71975511965977] rad/s … got 1.0471975511965978e-301 rad/s"), every
/// other key in SI.
pub(super) fn shown_in(key: &str, dim: Dimension) -> (&'static str, f64) {
    match super::keys::display_unit(key, dim) {
        // A number without unit: said so after it, as before.
        ("", _) => (dim.si_unit(), 1.0),
        shown => shown,
    }
}

/// `v` (SI) in a unit of size `factor`, to 10 significant digits: −1e-3 m/s is −3.6 m/h, not
/// −3.5999999999999996.
fn in_unit(v: f64, factor: f64) -> f64 {
    if !v.is_finite() {
        return v;
    }
    format!("{:.9e}", v / factor).parse().unwrap_or(v / factor)
}

/// "4448221.615 N (written \"1000 klbf\")": a refused value `v` (SI) in the unit of size
/// `factor` a message shows, and as the file wrote it when that was in another unit (the number
/// shown is not the one written).
pub(super) fn got(v: f64, unit: &str, factor: f64, raw: &RawQuantity) -> String {
    let number = show(in_unit(v, factor));
    let shown = if unit.is_empty() {
        number.clone()
    } else {
        format!("{number} {unit}")
    };
    match raw {
        RawQuantity::Text(t) if !t.trim().starts_with(number.as_str()) => {
            format!("{shown} (written {:?})", t.trim())
        }
        _ => shown,
    }
}

/// A minimum yield strength under `key`: an API 5DP grade (`"S-135"`) or a pressure.
pub(super) fn yield_strength(
    c: &Checker,
    key: &str,
    raw: &RawQuantity,
) -> Result<Option<f64>, ProblemError> {
    Ok(match raw {
        RawQuantity::Text(t) if t.chars().next().is_some_and(char::is_alphabetic) => {
            let grade = crate::model::API_GRADES
                .iter()
                // "G-105", "g-105" or "G105": case and the dash do not matter.
                .find(|(name, _)| {
                    name.replace('-', "")
                        .eq_ignore_ascii_case(&t.trim().replace('-', ""))
                });
            Some(grade.map(|g| g.1).ok_or_else(|| {
                let names: Vec<&str> = crate::model::API_GRADES.iter().map(|g| g.0).collect();
                c.fail(
                    key,
                    format!(
                        "`{t}` is not an API drill-pipe grade; expected one of {} or a pressure such as \"931 MPa\"",
                        names.join(", ")
                    ),
                )
            })?)
        }
        raw => Some(c.value_as(key, "model.pipe.yield_strength", raw, Dimension::Pressure)),
    })
}

/// Upper bound on the element count ([`super::keys::MAX_ELEMENTS`]), as the file's integers are read.
pub(super) const MAX_ELEMENTS: i64 = super::keys::MAX_ELEMENTS as i64;

/// The refusal of a bare number for a quantity with a unit (issue 33: `omega = 60` ran at
/// 572.96 rpm, read as rad/s, while the command line refuses `--omega 60`): the same number
/// means different things in the units drilling uses (rpm or rad/s, m/h or m/s, kN or N, in or
/// m), so the file must say which. Zero is zero in every unit and needs none.
pub(super) fn bare_number(v: f64, dim: Dimension) -> String {
    let units: Vec<&str> = dim.units().iter().map(|(u, _)| *u).collect();
    // Two spellings, the SI one and the next: the number alone means either (60 rad/s or 60 rpm).
    let examples: Vec<String> = units
        .iter()
        .take(2)
        .map(|u| format!("\"{} {u}\"", show(v)))
        .collect();
    format!(
        "is {} and needs its unit: the number {} alone could be {}; write the one meant, as a \
         string with one of the units {}",
        dim.name(),
        show(v),
        examples.join(" or "),
        units.join(", ")
    )
}

/// Whether `text` is a number with no unit (`"60"`, `" 1_000 "`).
fn unitless(text: &str) -> bool {
    text.trim().replace('_', "").parse::<f64>().is_ok()
}

/// Highest cutoff frequency accepted for a family, Hz: far above anything the bit or the wall
/// excites, it keeps a typo from asking for every mode of the mesh.
const MAX_CUTOFF_HZ: f64 = 1e5;

/// A family's size: an integer count in [1, elements] or a cutoff frequency in (0, 1e5] Hz.
pub(super) fn family_size(
    c: &Checker,
    key: &str,
    raw: &RawQuantity,
    elements: usize,
) -> Result<FamilySize, ProblemError> {
    match raw {
        RawQuantity::Number(n) => {
            if n.fract() == 0.0 && *n >= 1.0 && *n <= elements as f64 {
                Ok(FamilySize::Count(*n as usize))
            } else {
                Err(c.fail(
                    key,
                    format!(
                        "must be a mode count, an integer in [1, {elements}] (mesh.elements), or a cutoff frequency such as \"60 Hz\", got {n}"
                    ),
                ))
            }
        }
        RawQuantity::Text(text) => {
            // A count is an integer; a string is a cutoff and must say so with its unit.
            if text.trim().parse::<f64>().is_ok() {
                return Err(c.fail(
                    key,
                    format!(
                        "a cutoff frequency needs its unit (\"{} Hz\"); a mode count is written without quotes, got \"{text}\"",
                        text.trim()
                    ),
                ));
            }
            // "60 kN" is neither: say what the key takes, not only that the unit is wrong.
            let hz = Dimension::Frequency.parse(text).map_err(|_| {
                c.fail(
                    key,
                    format!(
                        "must be a mode count (an integer in [1, {elements}], without quotes) or a cutoff frequency with its unit such as \"60 Hz\", got \"{text}\""
                    ),
                )
            })?;
            c.check(
                key,
                hz,
                hz > 0.0 && hz <= MAX_CUTOFF_HZ,
                &format!("a cutoff frequency in (0, {MAX_CUTOFF_HZ}] Hz"),
                Dimension::Frequency,
            )?;
            Ok(FamilySize::Cutoff { hz, min: 1 })
        }
    }
}
