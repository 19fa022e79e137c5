//! A model imported from another library (here an XGBoost booster in its JSON schema) goes
//! through the C ABI like one from `greybox fit`: the same μ, bit for bit, as XGBoost's own
//! float32 arithmetic on the features the law maps from SI.

use greybox_import::{from_json, model_file, Domain, ImportOptions};
use greybox_model::modelfile::FeatureRange;
use std::ffi::CString;

/// One stump on the pressure feature (MPa) at 1200.5f32, base 0.3f32.
fn booster() -> serde_json::Value {
    serde_json::json!({
        "version": [3, 2, 0],
        "learner": {
            "objective": {"name": "reg:squarederror"},
            "learner_model_param": {"base_score": "[3E-1]", "num_feature": "2", "num_class": "0", "num_target": "1"},
            "gradient_booster": {"name": "gbtree", "model": {"trees": [{
                "left_children": [1, -1, -1], "right_children": [2, -1, -1], "split_indices": [0, 0, 0],
                "split_conditions": [1200.5, 0.125, -0.0625], "split_type": [0, 0, 0], "default_left": [0, 0, 0],
                "tree_param": {"num_nodes": "3", "size_leaf_vector": "1"}}]}}
        }
    })
}

#[test]
fn an_imported_booster_through_the_c_abi() {
    let opts = ImportOptions::new(Domain::Stated(vec![
        FeatureRange {
            min: 100.0,
            max: 3000.0,
        },
        FeatureRange { min: 0.1, max: 5.0 },
    ]))
    .with_features(&["contact_pressure_MPa", "sliding_velocity_m_per_s"]);
    let model = model_file(from_json(booster(), "booster.json").unwrap(), &opts).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("imported.json");
    model.save(&path).unwrap();
    let c = CString::new(path.to_str().unwrap()).unwrap();
    let mut law = std::ptr::null_mut();
    assert_eq!(
        unsafe { greybox_ffi::greybox_law_load(c.as_ptr(), &mut law) },
        0
    );
    // pressures around the split in MPa, as the solver passes them in Pa
    let mpa = [1000.0, 1200.5, 1200.5f64.next_up(), 1200.53125, 1500.0];
    let p: Vec<f64> = mpa.iter().map(|m| m * 1e6).collect();
    let v = vec![1.0; p.len()];
    let mut mu = vec![0.0; p.len()];
    let code = unsafe {
        greybox_ffi::greybox_law_mu(
            law,
            p.len(),
            p.as_ptr(),
            v.as_ptr(),
            std::ptr::null(),
            mu.as_mut_ptr(),
        )
    };
    assert_eq!(code, 0);
    for (k, pa) in p.iter().enumerate() {
        let x = (pa / 1e6) as f32;
        let want = (0.3f32 + if x < 1200.5f32 { 0.125f32 } else { -0.0625f32 }) as f64;
        assert_eq!(mu[k].to_bits(), want.to_bits(), "at {} MPa", pa / 1e6);
    }
    unsafe { greybox_ffi::greybox_law_free(law) };
}
