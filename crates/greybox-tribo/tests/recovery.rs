//! `identify` recovers `synth`'s ground truth over the article's full plan (210 plateaus).

use greybox_contact::hertz::PinContact;
use greybox_tribo::plan::PlanSpec;
use greybox_tribo::plan_timing::{identify_pins, IdentifyConfig};
use greybox_tribo::synth::SynthConfig;

fn max_error(cfg: &SynthConfig) -> (f64, usize) {
    let plan = PlanSpec {
        track_radius_mm: Some(100.0),
        ..Default::default()
    }
    .build()
    .unwrap();
    let contact = PinContact::default();
    let recs: Vec<_> = (1..=plan.pins.len() as u32)
        .map(|p| cfg.simulate_pin(&plan, &contact, p).unwrap())
        .collect();
    let truth = cfg.ground_truth(&plan, &contact).unwrap();
    let (ds, _) = identify_pins(&plan, &recs, &contact, &IdentifyConfig::default()).unwrap();
    assert_eq!(ds.records.len(), 210);
    let mut worst = 0.0f64;
    for (r, t) in ds.records.iter().zip(&truth) {
        assert_eq!((r.pin, r.step), (t.pin, t.step));
        worst = worst.max((r.cof_apparent - t.cof_true).abs());
    }
    let flagged = ds.records.iter().filter(|r| !r.stationary).count();
    (worst, flagged)
}

#[test]
fn recovers_ground_truth_at_default_noise() {
    let (worst, flagged) = max_error(&SynthConfig::default());
    eprintln!("default disturbances: max |mu_id - mu_true| = {worst:.5}, non-stationary plateaus = {flagged}");
    assert!(worst <= 0.003, "{worst}");
    assert_eq!(flagged, 0);
}

#[test]
fn recovers_ground_truth_with_doubled_noise_drift_and_spikes() {
    let cfg = SynthConfig {
        disturbance_scale: 2.0,
        seed: 7,
        ..Default::default()
    };
    let (worst, _) = max_error(&cfg);
    eprintln!("doubled disturbances: max |mu_id - mu_true| = {worst:.5}");
    assert!(worst <= 0.006, "{worst}");
}
