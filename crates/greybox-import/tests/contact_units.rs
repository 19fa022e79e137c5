//! What an import must state: the pin contact of a model trained on a normal force is
//! recorded in the model file (so the model becomes a friction law), a model imported
//! without it says so at use, and feature names whose unit greybox cannot map are refused
//! at import, naming the feature.

use greybox_contact::PinContact;
use greybox_core::dataset::PressureConvention;
use greybox_core::FrictionLaw;
use greybox_friction::learned::LearnedLaw;
use greybox_import::{from_json, model_file, Domain, ImportOptions};
use greybox_model::modelfile::{FeatureRange, ModelFile};

/// One stump on feature 0 (normal force) at 1000.5 N.
fn booster() -> serde_json::Value {
    serde_json::json!({
        "version": [3, 2, 0],
        "learner": {
            "objective": {"name": "reg:squarederror"},
            "learner_model_param": {"base_score": "[3.3E-1]", "num_feature": "2", "num_class": "0", "num_target": "1"},
            "gradient_booster": {"name": "gbtree", "model": {"trees": [{
                "left_children": [1, -1, -1], "right_children": [2, -1, -1], "split_indices": [0, 0, 0],
                "split_conditions": [1000.5, 0.0123, -0.0456], "split_type": [0, 0, 0], "default_left": [0, 0, 0],
                "tree_param": {"num_nodes": "3", "size_leaf_vector": "1"}}]}}
        }
    })
}

fn options(features: &[&str]) -> ImportOptions {
    ImportOptions::new(Domain::Stated(vec![
        FeatureRange {
            min: 150.0,
            max: 2000.0,
        },
        FeatureRange {
            min: 20.0,
            max: 250.0,
        },
    ]))
    .with_features(features)
}

fn article_contact() -> PinContact {
    PinContact {
        convention: PressureConvention::ArticleEq7,
        ..PinContact::default()
    }
}

fn import(opts: &ImportOptions) -> greybox_core::Result<ModelFile> {
    model_file(from_json(booster(), "hand.json")?, opts)
}

#[test]
fn stated_contact_is_recorded_and_makes_a_law() {
    let contact = article_contact();
    let opts = options(&["normal_force_N", "sliding_velocity_m_per_min"]).with_contact(contact);
    let m = import(&opts).unwrap();
    let fp = m.force_to_pressure.expect("force_to_pressure recorded");
    assert_eq!(fp.pressure_convention, PressureConvention::ArticleEq7);
    assert_eq!(fp.pressure_pa_at_1_n, contact.pressure_pa(1.0).unwrap());
    // survives the file, and the law maps pressure back to the force of the training contact
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("m.json");
    m.save(&path).unwrap();
    let m = ModelFile::load(&path).unwrap();
    let law = LearnedLaw::new(m, None).unwrap();
    let at = |force_n: f64| greybox_core::ContactState {
        pressure_pa: contact.pressure_pa(force_n).unwrap(),
        sliding_velocity_m_s: 1.0,
        temperature_k: 293.15,
    };
    assert_eq!(law.mu(&at(500.0)), (0.33f32 + 0.0123f32) as f64);
    assert_eq!(law.mu(&at(1500.0)), (0.33f32 - 0.0456f32) as f64);
    let d = law.domain().unwrap();
    let rel = |a: f64, b: f64| (a / b - 1.0).abs();
    assert!(rel(d.pressure_pa.min, contact.pressure_pa(150.0).unwrap()) < 1e-12);
    assert!(rel(d.pressure_pa.max, contact.pressure_pa(2000.0).unwrap()) < 1e-12);
}

#[test]
fn without_a_contact_the_import_predicts_and_the_law_says_what_is_missing() {
    let m = import(&options(&["normal_force_N", "sliding_velocity_m_per_min"])).unwrap();
    assert_eq!(m.force_to_pressure, None);
    assert_eq!(
        m.predict(
            &[500.0, 100.0],
            greybox_model::modelfile::DomainPolicy::Refuse,
            0.0
        )
        .unwrap()
        .value,
        (0.33f32 + 0.0123f32) as f64
    );
    let e = LearnedLaw::new(m, None).unwrap_err().to_string();
    assert!(e.contains("imported without a contact"), "{e}");
    assert!(
        e.contains("`contact` STUDY.toml") && e.contains("contact="),
        "{e}"
    );
    assert!(!e.contains("schema version"), "{e}");
    // a law file's contact still makes it a law
    let m = import(&options(&["normal_force_N", "sliding_velocity_m_per_min"])).unwrap();
    assert!(LearnedLaw::new(m.clone(), Some(&article_contact())).is_ok());
    // only a file of schema version 1 is said to be one
    let old = ModelFile {
        schema_version: 1,
        ..m
    };
    let e = LearnedLaw::new(old, None).unwrap_err().to_string();
    assert!(e.contains("before schema version 2"), "{e}");
}

#[test]
fn a_model_on_pressure_needs_no_contact() {
    let m = import(&options(&[
        "hertz_pressure_MPa",
        "sliding_velocity_m_per_min",
    ]))
    .unwrap();
    assert!(LearnedLaw::new(m, None).is_ok());
}

#[test]
fn invalid_contact_is_refused_naming_the_field() {
    let bad = PinContact {
        pin_tip_radius_mm: -1.0,
        ..article_contact()
    };
    let opts = options(&["normal_force_N", "sliding_velocity_m_per_min"]).with_contact(bad);
    let e = import(&opts).unwrap_err().to_string();
    assert!(e.contains("pin_tip_radius_mm"), "{e}");
}

#[test]
fn features_of_unknown_units_are_refused_at_import() {
    for (bad, features) in [
        ("pressure", ["pressure", "sliding_velocity_m_per_min"]),
        (
            "contact_pressure_psi",
            ["contact_pressure_psi", "sliding_velocity_m_per_min"],
        ),
        ("speed_fpm", ["normal_force_N", "speed_fpm"]),
        ("track_width_um", ["normal_force_N", "track_width_um"]),
    ] {
        let e = import(&options(&features)).unwrap_err().to_string();
        assert!(e.contains(&format!("'{bad}'")), "{e}");
        for suffix in ["_MPa", "_m_per_min", "_degC", "_N"] {
            assert!(e.contains(suffix), "{e}");
        }
    }
}
