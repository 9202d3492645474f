//! The metric catalogue against the [`Metrics`] it describes, and its own consistency.

use super::catalogue::{checked_through, compared_for, find, keys};
use super::*;

/// The catalogue lists the fields of `Metrics` under their serde names, in the order of
/// `summary.json`, and each row's getter reads the field of its key.
#[test]
fn the_catalogue_is_the_serialised_metrics_in_order() {
    let values: serde_json::Map<String, serde_json::Value> = keys()
        .enumerate()
        .map(|(i, k)| (k.to_string(), serde_json::json!(i as f64 + 0.5)))
        .collect();
    let m: Metrics = serde_json::from_value(serde_json::Value::Object(values)).unwrap();
    let json = serde_json::to_value(&m).unwrap();
    let serialised: Vec<&str> = json
        .as_object()
        .unwrap()
        .keys()
        .map(|k| k.as_str())
        .collect();
    // serde_json keeps the struct's field order only with `preserve_order`; compare the sets
    // here and the order through `named_values` and the serialised text below.
    let mut sorted: Vec<&str> = keys().collect();
    sorted.sort_unstable();
    let mut got = serialised.clone();
    got.sort_unstable();
    assert_eq!(got, sorted);
    for (i, spec) in METRICS.iter().enumerate() {
        assert_eq!((spec.get)(&m), i as f64 + 0.5, "{}", spec.key);
    }
    let text = serde_json::to_string(&m).unwrap();
    let positions: Vec<usize> = keys()
        .map(|k| text.find(&format!("\"{k}\":")).unwrap())
        .collect();
    assert!(positions.windows(2).all(|w| w[0] < w[1]), "{text}");
}

#[test]
fn the_catalogue_is_consistent() {
    for (i, spec) in METRICS.iter().enumerate() {
        let key = spec.key;
        assert!(!keys().skip(i + 1).any(|k| k == key), "{key} twice");
        // A human name for the terminal and the plots, never the code key.
        assert_ne!(spec.name, key);
        assert!(!spec.name.contains('_'), "{key}");
        // A key that names a unit other than SI says which.
        assert_eq!(spec.own_unit.is_some(), spec.per_si != 1.0, "{key}");
        // Every metric is checked, by itself or through compared metrics it is computed from.
        assert!(!checked_through(key).is_empty(), "{key}");
        if spec.compared().is_none() {
            assert!(!spec.derives_from.is_empty(), "{key}");
        }
        for from in spec.derives_from {
            let s = find(from).unwrap_or_else(|| panic!("{key}: {from} is no metric"));
            assert!(s.compared().is_some(), "{key}: {from} is not compared");
        }
        if let Direction::Safer { inverse, .. } = spec.direction {
            assert!(find(inverse).is_some_and(|s| s.penalisable()), "{key}");
        }
        // Batch intervals are of time means over the run's window.
        assert!(
            !spec.batch_interval || spec.source == Source::Series,
            "{key}"
        );
    }
}

/// The metrics every verification compares, and those with a batch-means interval, are the
/// ones shipped before the catalogue.
#[test]
fn the_always_compared_and_the_interval_metrics_are_unchanged() {
    let mut always: Vec<&str> = compared_for([]).iter().map(|s| s.key).collect();
    always.sort_unstable();
    assert_eq!(
        always,
        [
            "max_bit_speed_ratio",
            "mean_rop_m_per_h",
            "mean_tob_nm",
            "mean_wob_n",
            "mse_pa",
            "stick_fraction",
            "stick_slip_severity"
        ]
    );
    let intervals: Vec<&str> = METRICS
        .iter()
        .filter(|s| s.batch_interval)
        .map(|s| s.key)
        .collect();
    assert_eq!(
        intervals,
        [
            "mean_rop_m_per_h",
            "stick_fraction",
            "bit_bounce_fraction",
            "impacts_per_s",
            "mean_wob_n",
            "mean_tob_nm",
            "axial_power_share",
            // Added at revision 9 (surface torque and push, MODEL.md §11.2).
            "mean_top_torque_nm",
            "mean_top_force_n"
        ]
    );
    // A use brings what the metric is computed from.
    assert_eq!(
        checked_through("von_mises_utilization"),
        ["max_von_mises_pa"]
    );
    assert_eq!(
        checked_through("mse_pa"),
        ["mse_pa", "mean_rop_m_per_h", "mean_wob_n", "mean_tob_nm"]
    );
    assert!(checked_through("no_such_metric").is_empty());
}
