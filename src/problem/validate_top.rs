//! `[operating_point] top` and its keys: the driller's top (MODEL.md §11.8, [`crate::model::top`]).

use super::ProblemError;
use super::check::Checker;
use super::schema::{OperatingPointSection, RawQuantity};
use crate::model::{
    AUTODRILLER_TIME_CONSTANT, Autodriller, POWER_LIMIT, TORQUE_LIMIT, TopDrive, WOB_LIMIT,
};

/// The tops a problem file can choose.
const FILE_TOPS: [&str; 3] = crate::model::TOP_DRIVES;

/// The top law of `[operating_point]`: `"feed"` when `top` is absent. Keys of another law than
/// the one chosen are refused (a `wob_limit` without the autodriller would be silently unused).
pub(super) fn top(c: &Checker, o: &OperatingPointSection) -> Result<TopDrive, ProblemError> {
    let key = "operating_point.top";
    let name = match &o.top {
        None => "feed".to_string(),
        Some(RawQuantity::Text(t)) => t.trim().to_string(),
        Some(RawQuantity::Number(x)) => {
            // Recorded, not returned: the other refusals of the file are reported with it.
            c.record(
                key,
                format!(
                    "must be a string, one of {}, got the number {}",
                    quoted(&FILE_TOPS),
                    crate::units::show(*x)
                ),
            );
            return Ok(TopDrive::Feed);
        }
    };
    if !FILE_TOPS.contains(&name.as_str()) {
        c.record(
            key,
            format!("must be one of {}, got \"{name}\"", quoted(&FILE_TOPS)),
        );
        return Ok(TopDrive::Feed);
    }
    if o.wob.is_some() && name != "hook_load" {
        c.record(
            "operating_point.wob",
            format!(
                "is the WOB set-point of top = \"hook_load\", not of top = \"{name}\": remove it \
                 (the autodriller's limit is wob_limit)"
            ),
        );
    }
    let keys: [(&str, &Option<RawQuantity>, &[&str]); 4] = [
        ("wob_limit", &o.wob_limit, &["autodriller"]),
        ("torque_limit", &o.torque_limit, &["autodriller"]),
        ("power_limit", &o.power_limit, &["autodriller"]),
        (
            "autodriller_time_constant",
            &o.autodriller_time_constant,
            &["autodriller"],
        ),
    ];
    for (k, value, laws) in keys {
        if value.is_some() && !laws.contains(&name.as_str()) {
            c.record(
                &format!("operating_point.{k}"),
                format!(
                    "belongs to top = {}, not to top = \"{name}\": remove it or choose that top",
                    quoted(laws)
                ),
            );
        }
    }
    match name.as_str() {
        "feed" => Ok(TopDrive::Feed),
        // The set-point `wob` is the operating point's (read with it).
        "hook_load" => Ok(TopDrive::HookLoad),
        "autodriller" => {
            let wob_limit = match &o.wob_limit {
                Some(raw) => c.spec_value(&WOB_LIMIT, raw)?,
                None => c.record(
                    WOB_LIMIT.key,
                    "is required with top = \"autodriller\": the surface WOB (e.g. \"80 kN\") \
                     above which the block slows"
                        .into(),
                ),
            };
            let torque_limit = match &o.torque_limit {
                Some(raw) => Some(c.spec_value(&TORQUE_LIMIT, raw)?),
                None => None,
            };
            let power_limit = match &o.power_limit {
                Some(raw) => Some(c.spec_value(&POWER_LIMIT, raw)?),
                None => None,
            };
            let time_constant = c.key_value(
                AUTODRILLER_TIME_CONSTANT.key,
                o.autodriller_time_constant.as_ref(),
            )?;
            Ok(TopDrive::Autodriller(Autodriller {
                wob_limit,
                torque_limit,
                power_limit,
                time_constant,
            }))
        }
        _ => unreachable!("checked against FILE_TOPS above"),
    }
}

fn quoted(names: &[&str]) -> String {
    names
        .iter()
        .map(|n| format!("\"{n}\""))
        .collect::<Vec<_>>()
        .join(", ")
}
