//! Round trips, resumption after a kill, corruption and concurrent inserts.

use super::*;
use rayon::prelude::*;
use std::collections::BTreeMap;

fn key(i: usize) -> CacheKey {
    CacheKey::new(
        10.0 + 0.1 * i as f64,
        0.005,
        i,
        0x9E37_79B9_7F4A_7C15 ^ i as u64,
        7,
    )
}

fn ok(pairs: &[(&str, f64)]) -> Outcome {
    Outcome::Ok {
        metrics: pairs.iter().map(|&(k, v)| (k.to_string(), v)).collect(),
    }
}

/// Bit-level equality, so that NaN compares equal to NaN.
fn same(a: &Outcome, b: &Outcome) -> bool {
    match (a, b) {
        (Outcome::Ok { metrics: x }, Outcome::Ok { metrics: y }) => {
            x.len() == y.len()
                && x.iter()
                    .zip(y)
                    .all(|((k1, v1), (k2, v2))| k1 == k2 && v1.to_bits() == v2.to_bits())
        }
        _ => a == b,
    }
}

/// Values that a naive float parser gets wrong, and every non-finite value.
fn awkward() -> Vec<(&'static str, f64)> {
    vec![
        ("tenth", 0.1),
        ("third", 1.0 / 3.0),
        ("ulp_trap", 1.691_843_555_264_218e-91), // misread by serde_json without float_roundtrip
        ("big", 4.472_871_350_414_216e283),
        ("subnormal", 5e-324),
        ("min_positive", f64::MIN_POSITIVE),
        ("max", f64::MAX),
        ("neg_zero", -0.0),
        ("nan", f64::NAN),
        ("inf", f64::INFINITY),
        ("neg_inf", f64::NEG_INFINITY),
    ]
}

#[test]
fn fnv1a_64_reference_vectors() {
    // From the FNV reference test suite (Fowler/Noll/Vo, fnv/test_fnv.c, FNV-1a 64).
    assert_eq!(stable_hash(b""), 0xcbf2_9ce4_8422_2325);
    assert_eq!(stable_hash(b"a"), 0xaf63_dc4c_8601_ec8c);
    assert_eq!(stable_hash(b"foobar"), 0x8594_4171_f739_67e8);
}

#[test]
fn key_keeps_the_exact_floats() {
    let k = CacheKey::new(0.1 + 0.2, 1e-3, 4, 99, 1);
    assert_eq!(k.omega(), 0.1 + 0.2);
    assert_ne!(
        k,
        CacheKey::new(0.3, 1e-3, 4, 99, 1),
        "0.1 + 0.2 ≠ 0.3 in binary"
    );
    assert_eq!(
        (k.v0(), k.sample, k.sample_seed, k.model_hash),
        (1e-3, 4, 99, 1)
    );
}

#[test]
fn round_trip_and_reopen_see_every_record_bit_for_bit() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("nested/dirs/cache.jsonl");
    let outcomes = [
        ok(&awkward()),
        ok(&[("rop", 0.0049871), ("mse", 3.2e8)]),
        Outcome::Failed {
            message: "Newmark step below 1e-12 s at t = 3.4 s \"quoted\"\nsecond line".into(),
        },
        ok(&[]),
    ];
    {
        let cache = EvalCache::open(&path).unwrap();
        assert!(cache.is_empty());
        assert_eq!((cache.loaded(), cache.torn()), (0, 0));
        for (i, o) in outcomes.iter().enumerate() {
            assert!(cache.get(&key(i)).is_none());
            cache.insert(key(i), o.clone()).unwrap();
            assert!(same(&cache.get(&key(i)).unwrap(), o));
        }
        let info = EvalInfo {
            wall_time_s: Some(41.25),
            version: Some("0.1.0".into()),
        };
        cache
            .insert_with_info(key(9), ok(&[("x", 1.0)]), Some(info.clone()))
            .unwrap();
        assert_eq!(cache.info(&key(9)), Some(info));
        assert_eq!((cache.len(), cache.hits(), cache.misses()), (5, 4, 4));
    }
    let cache = EvalCache::open(&path).unwrap();
    assert_eq!((cache.len(), cache.loaded(), cache.torn()), (5, 5, 0));
    assert_eq!((cache.hits(), cache.misses()), (0, 0));
    for (i, o) in outcomes.iter().enumerate() {
        let got = cache.get(&key(i)).unwrap();
        assert!(same(&got, o), "record {i}: {got:?} vs {o:?}");
    }
    assert_eq!(cache.info(&key(9)).unwrap().wall_time_s, Some(41.25));
    assert!(cache.get(&key(100)).is_none());
    assert_eq!((cache.hits(), cache.misses()), (4, 1));

    // The file is one JSON object per line, readable without drillopt.
    let text = fs::read_to_string(&path).unwrap();
    assert_eq!(text.lines().count(), 5);
    assert!(text.ends_with('\n'));
    let first: serde_json::Value = serde_json::from_str(text.lines().next().unwrap()).unwrap();
    assert_eq!(first["outcome"]["status"], "ok");
    assert_eq!(first["outcome"]["metrics"]["nan"], "NaN");
    assert_eq!(first["omega"], 10.0);
}

#[test]
fn last_record_for_a_key_wins() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("c.jsonl");
    {
        let cache = EvalCache::open(&path).unwrap();
        cache
            .insert(
                key(1),
                Outcome::Failed {
                    message: "first".into(),
                },
            )
            .unwrap();
        cache.insert(key(1), ok(&[("rop", 2.0)])).unwrap();
        assert_eq!(cache.len(), 1);
        assert_eq!(cache.get(&key(1)), Some(ok(&[("rop", 2.0)])));
    }
    let cache = EvalCache::open(&path).unwrap();
    assert_eq!((cache.len(), cache.loaded()), (1, 2));
    assert_eq!(cache.get(&key(1)), Some(ok(&[("rop", 2.0)])));
}

/// Writes two records, then appends `tail` raw, as a kill mid-write would leave it.
fn file_with_tail(tail: &[u8]) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("c.jsonl");
    {
        let cache = EvalCache::open(&path).unwrap();
        cache.insert(key(0), ok(&[("a", 1.0)])).unwrap();
        cache.insert(key(1), ok(&[("a", 2.0)])).unwrap();
    }
    let mut f = OpenOptions::new().append(true).open(&path).unwrap();
    f.write_all(tail).unwrap();
    (dir, path)
}

#[test]
fn torn_last_line_is_skipped_and_the_next_append_starts_a_fresh_line() {
    // A prefix of a real record, a zero-filled block (delayed allocation after a power cut),
    // and a garbage line that did get its newline.
    let mut record = serde_json::to_string(&RecordOut {
        key: &key(2),
        omega: 0.0,
        v0: 0.0,
        outcome: &ok(&[("a", 3.0)]),
        info: None,
    })
    .unwrap();
    record.truncate(record.len() / 2);
    for tail in [
        record.as_bytes(),
        &[0u8; 64][..],
        b"{\"key\": tru\n",
        b"{\n\n  \n",
    ] {
        let (_dir, path) = file_with_tail(tail);
        {
            let cache = EvalCache::open(&path).unwrap();
            assert_eq!((cache.len(), cache.loaded(), cache.torn()), (2, 2, 1));
            assert!(cache.get(&key(2)).is_none());
            cache.insert(key(3), ok(&[("a", 4.0)])).unwrap();
        }
        let cache = EvalCache::open(&path).unwrap();
        assert_eq!((cache.len(), cache.loaded(), cache.torn()), (3, 3, 0));
        assert_eq!(cache.get(&key(3)), Some(ok(&[("a", 4.0)])));
        assert_eq!(fs::read_to_string(&path).unwrap().lines().count(), 3);
    }
}

#[test]
fn whole_last_record_without_newline_is_kept() {
    let line = serde_json::to_string(&RecordOut {
        key: &key(2),
        omega: 0.0,
        v0: 0.0,
        outcome: &ok(&[("a", 3.0)]),
        info: None,
    })
    .unwrap();
    let (_dir, path) = file_with_tail(line.as_bytes());
    {
        let cache = EvalCache::open(&path).unwrap();
        assert_eq!((cache.len(), cache.torn()), (3, 0));
        cache.insert(key(3), ok(&[("a", 4.0)])).unwrap();
    }
    let cache = EvalCache::open(&path).unwrap();
    assert_eq!((cache.len(), cache.loaded(), cache.torn()), (4, 4, 0));
}

#[test]
fn corrupt_line_before_the_last_is_rejected_with_its_line_number() {
    let good = serde_json::to_string(&RecordOut {
        key: &key(5),
        omega: 0.0,
        v0: 0.0,
        outcome: &ok(&[("a", 3.0)]),
        info: None,
    })
    .unwrap();
    // Records on lines 1–2, a blank line 3, garbage on line 4, a good record on line 5.
    let tail = format!("\n{{\"key\": 12, \"outcome\": 3}}\n{good}\n");
    let (_dir, path) = file_with_tail(tail.as_bytes());
    let before = fs::read(&path).unwrap();
    let err = EvalCache::open(&path).unwrap_err();
    match &err {
        CacheError::Corrupt { line, path: p, .. } => {
            assert_eq!(*line, 4);
            assert_eq!(p, &path);
        }
        other => panic!("expected Corrupt, got {other:?}"),
    }
    let msg = err.to_string();
    assert!(msg.contains("line 4") && msg.contains("c.jsonl"), "{msg}");
    assert_eq!(
        fs::read(&path).unwrap(),
        before,
        "a refused file is left untouched"
    );

    // A bad metric string is corruption too.
    let bad = good.replace("\"3.0\"", "\"three\"");
    let (_dir, path) = file_with_tail(format!("{bad}\n{good}\n").as_bytes());
    let msg = EvalCache::open(&path).unwrap_err().to_string();
    assert!(msg.contains("line 3") && msg.contains("three"), "{msg}");
}

#[test]
fn a_second_open_of_the_same_file_is_refused_while_the_first_lives() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("c.jsonl");
    let first = EvalCache::open(&path).unwrap();
    match EvalCache::open(&path) {
        Err(CacheError::Locked { .. }) => {}
        other => panic!("expected Locked, got {other:?}"),
    }
    drop(first);
    EvalCache::open(&path).unwrap();
}

#[test]
fn concurrent_inserts_from_rayon_threads_are_all_kept() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("c.jsonl");
    let n = 400;
    let value = |i: usize| (i as f64).sqrt() * std::f64::consts::PI;
    {
        let cache = EvalCache::open(&path).unwrap();
        (0..n).into_par_iter().for_each(|i| {
            let mut m = BTreeMap::new();
            m.insert("v".to_string(), value(i));
            m.insert("i".to_string(), i as f64);
            assert!(cache.get(&key(i)).is_none());
            cache.insert(key(i), Outcome::Ok { metrics: m }).unwrap();
        });
        assert_eq!((cache.len(), cache.misses()), (n, n as u64));
    }
    let cache = EvalCache::open(&path).unwrap();
    assert_eq!((cache.len(), cache.loaded(), cache.torn()), (n, n, 0));
    for i in 0..n {
        match cache.get(&key(i)) {
            Some(Outcome::Ok { metrics }) => {
                assert_eq!(metrics["v"].to_bits(), value(i).to_bits());
                assert_eq!(metrics["i"], i as f64);
            }
            other => panic!("sample {i}: {other:?}"),
        }
    }
}

#[test]
fn plain_json_numbers_are_accepted_when_reading() {
    let text = r#"{"key":{"omega_bits":1,"v0_bits":2,"sample":0,"sample_seed":3,"model_hash":4},"outcome":{"status":"ok","metrics":{"rop":0.25,"n":3}}}"#;
    let r: RecordIn = serde_json::from_str(text).unwrap();
    assert_eq!(r.outcome, ok(&[("n", 3.0), ("rop", 0.25)]));
    assert!(r.info.is_none());
    // Unknown fields in the key or outcome are refused; at the top level they are ignored.
    assert!(
        serde_json::from_str::<RecordIn>(&text.replace("\"sample\":0", "\"sample\":0,\"x\":1"))
            .is_err()
    );
    assert!(
        serde_json::from_str::<RecordIn>(
            &text.replace("\"status\":\"ok\"", "\"status\":\"ok\",\"x\":1")
        )
        .is_err()
    );
    assert!(
        serde_json::from_str::<RecordIn>(&text.replace("{\"key\"", "{\"later\":[1],\"key\""))
            .is_ok()
    );
}
