//! A booster written by hand in XGBoost's JSON schema, evaluated by hand in float32: the
//! import must take float32 splits (`x < s` on the float32 input) and float32 sums exactly,
//! from JSON and from the same document in UBJSON.

use greybox_import::{from_json, model_file, Domain, ImportOptions};
use greybox_model::modelfile::FeatureRange;
use greybox_model::Predictor;

/// Two stumps: tree 0 splits feature 0 at 0.1f32, tree 1 feature 1 at 1/3 (f32).
fn booster() -> serde_json::Value {
    let s0 = 0.1f32 as f64;
    let s1 = (1.0f32 / 3.0) as f64;
    let tree = |f: i64, s: f64, l: f64, r: f64| {
        serde_json::json!({
            "left_children": [1, -1, -1], "right_children": [2, -1, -1],
            "split_indices": [f, 0, 0], "split_conditions": [s, l, r],
            "split_type": [0, 0, 0], "default_left": [0, 0, 0],
            "tree_param": {"num_nodes": "3", "size_leaf_vector": "1"}
        })
    };
    serde_json::json!({
        "version": [3, 2, 0],
        "learner": {
            "objective": {"name": "reg:squarederror"},
            "learner_model_param": {"base_score": "[3.3E-1]", "num_feature": "2", "num_class": "0", "num_target": "1"},
            "gradient_booster": {"name": "gbtree", "model": {"trees": [
                tree(0, s0, 0.0123_f32 as f64, -0.0456_f32 as f64),
                tree(1, s1, 0.1_f32 as f64, 0.2_f32 as f64)
            ]}}
        }
    })
}

/// XGBoost's arithmetic, by hand: float32 inputs, `<` splits, a float32 running sum.
fn by_hand(x: [f64; 2]) -> f64 {
    let (x0, x1) = (x[0] as f32, x[1] as f32);
    let mut m = 0.33f32;
    m += if x0 < 0.1f32 { 0.0123f32 } else { -0.0456f32 };
    m += if x1 < 1.0f32 / 3.0 { 0.1f32 } else { 0.2f32 };
    m as f64
}

/// The document in UBJSON (objects and arrays unoptimised, numbers as float64/int64).
fn ubjson(v: &serde_json::Value, out: &mut Vec<u8>) {
    let key = |k: &str, out: &mut Vec<u8>| {
        out.push(b'L');
        out.extend((k.len() as i64).to_be_bytes());
        out.extend(k.as_bytes());
    };
    match v {
        serde_json::Value::Object(m) => {
            out.push(b'{');
            for (k, v) in m {
                key(k, out);
                ubjson(v, out);
            }
            out.push(b'}');
        }
        serde_json::Value::Array(a) => {
            out.push(b'[');
            a.iter().for_each(|v| ubjson(v, out));
            out.push(b']');
        }
        serde_json::Value::String(s) => {
            out.push(b'S');
            key(s, out);
        }
        serde_json::Value::Number(n) if n.is_i64() => {
            out.push(b'L');
            out.extend(n.as_i64().unwrap().to_be_bytes());
        }
        serde_json::Value::Number(n) => {
            out.push(b'D');
            out.extend(n.as_f64().unwrap().to_be_bytes());
        }
        other => panic!("not used here: {other}"),
    }
}

fn points() -> Vec<[f64; 2]> {
    let s0 = 0.1f32 as f64;
    let s1 = (1.0f32 / 3.0) as f64;
    let f32_below = |s: f64| f32::from_bits((s as f32).to_bits() - 1) as f64;
    let mut xs = vec![0.0, 1.0, 0.1, 1.0 / 3.0, s0, s1];
    for s in [s0, s1] {
        let b = f32_below(s);
        // the float32 tie between s and the float32 below it, and the f64 values around it
        let mid = (s + b) / 2.0;
        xs.extend([
            s.next_down(),
            s.next_up(),
            b,
            mid,
            mid.next_down(),
            mid.next_up(),
        ]);
    }
    xs.iter()
        .flat_map(|&a| xs.iter().map(move |&b| [a, b]))
        .collect()
}

#[test]
fn float32_splits_and_sums_as_xgboost_computes_them() {
    let opts = ImportOptions::new(Domain::Stated(vec![
        FeatureRange { min: 0.0, max: 1.0 },
        FeatureRange { min: 0.0, max: 1.0 },
    ]))
    .with_features(&["pressure_MPa", "sliding_velocity_m_per_s"]);
    let json = model_file(from_json(booster(), "hand.json").unwrap(), &opts).unwrap();
    let mut bytes = Vec::new();
    ubjson(&booster(), &mut bytes);
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("hand.ubj");
    std::fs::write(&path, &bytes).unwrap();
    let ubj = greybox_import::import_file(&path, &opts).unwrap();
    let pts = points();
    let mut flips = 0;
    for x in &pts {
        let want = by_hand(*x);
        assert_eq!(
            json.model.predict_one(x).to_bits(),
            want.to_bits(),
            "json at {x:?}"
        );
        assert_eq!(
            ubj.model.predict_one(x).to_bits(),
            want.to_bits(),
            "ubj at {x:?}"
        );
        // where the float32 cast decides differently from an f64 comparison
        flips += usize::from((x[0] < 0.1f32 as f64) != ((x[0] as f32) < 0.1f32));
    }
    assert!(flips > 0, "the points must exercise the float32 cast");
}

#[test]
fn unsupported_boosters_are_named() {
    let mut b = booster();
    b["learner"]["objective"]["name"] = "binary:logistic".into();
    let e = from_json(b, "b.json").unwrap_err().to_string();
    assert!(e.contains("b.json") && e.contains("binary:logistic"), "{e}");
    let mut b = booster();
    b["learner"]["gradient_booster"]["name"] = "dart".into();
    assert!(from_json(b, "b.json")
        .unwrap_err()
        .to_string()
        .contains("'dart'"));
    let mut b = booster();
    b["learner"]["gradient_booster"]["model"]["trees"][0]["left_children"][0] = 7.into();
    let e = from_json(b, "b.json").unwrap_err().to_string();
    assert!(e.contains("tree 0") && e.contains("child 7"), "{e}");
    let mut b = booster();
    b["learner"]["gradient_booster"]["model"]["trees"][1]["left_children"] =
        serde_json::json!([0, -1, -1]);
    let e = from_json(b, "b.json").unwrap_err().to_string();
    assert!(e.contains("tree 1") && e.contains("reached twice"), "{e}");
}
