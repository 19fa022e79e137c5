//! Linear reciprocating tests (ASTM G133) on the virtual reciprocating rig: strokes from the
//! position, from the friction force's sign and from half-stroke blocks; μ per direction
//! against the truth, cycles counted exactly.

use greybox_tribo::config::{IdentifyConfig, SteadyRule};

use greybox_tribo::reciprocating::{analyse, detect, parts, Signals, StrokeSource};
use greybox_tribo::synth_recip::{reciprocating_recording, RecipSpec};

fn check(spec: &RecipSpec, position: bool, blocks: bool, want: StrokeSource) {
    let (mut rec, block) = reciprocating_recording(spec);
    if !position {
        rec.position_m = None;
    }
    if blocks {
        rec.step = Some(block);
    }
    let cfg = IdentifyConfig::default();
    let s = Signals::of(&rec);
    assert!(
        detect(&s, None, None, &cfg).is_some(),
        "not detected as reciprocating"
    );
    let p = parts(&s, &cfg);
    assert_eq!(p.len(), 1, "{p:?}");
    let r = analyse(&s, p[0].0, p[0].1, &cfg).unwrap();
    eprintln!(
        "{want:?}: strokes {} cycles {} steady {:?} run-in {:?} μ fwd {:.5} bwd {:.5} mean {:.5} v {:?} L {:?} f {:.3}",
        r.strokes,
        r.cycles.len(),
        r.steady_cycles,
        r.run_in_cycles,
        r.mu_forward,
        r.mu_backward,
        r.mu_mean,
        r.velocity_m_s,
        r.stroke_length_m,
        r.frequency_hz
    );
    assert_eq!(r.source, want);
    assert_eq!(r.cycles.len(), spec.cycles, "cycles");
    assert_eq!(r.strokes, 2 * spec.cycles, "strokes");
    assert!(
        (r.mu_forward - spec.mu_forward).abs() < 0.003,
        "forward {}",
        r.mu_forward
    );
    assert!(
        (r.mu_backward - spec.mu_backward).abs() < 0.003,
        "backward {}",
        r.mu_backward
    );
    let mean = 0.5 * (spec.mu_forward + spec.mu_backward);
    assert!((r.mu_mean - mean).abs() < 0.003, "mean {}", r.mu_mean);
    assert!(r.run_in_cycles.unwrap() > 0, "run-in not seen");
    assert!(
        r.cycles[0].mu_mean > mean + 0.04,
        "first cycle shows the run-in"
    );
}

#[test]
fn strokes_from_the_position() {
    check(&RecipSpec::default(), true, false, StrokeSource::Position);
}

#[test]
fn strokes_from_the_force_sign_without_a_position() {
    check(&RecipSpec::default(), false, false, StrokeSource::ForceSign);
}

#[test]
fn strokes_from_half_stroke_blocks() {
    check(&RecipSpec::default(), false, true, StrokeSource::Blocks);
}

#[test]
fn a_flipped_force_axis_still_gives_positive_mu_per_direction() {
    let (mut rec, _) = reciprocating_recording(&RecipSpec::default());
    rec.tangential_n.iter_mut().for_each(|v| *v = -*v);
    let cfg = IdentifyConfig::default();
    let s = Signals::of(&rec);
    let p = parts(&s, &cfg);
    let r = analyse(&s, p[0].0, p[0].1, &cfg).unwrap();
    assert!(
        (r.mu_forward - 0.30).abs() < 0.003 && (r.mu_backward - 0.26).abs() < 0.003,
        "{r:?}"
    );
}

#[test]
fn last_half_rule_takes_the_last_half_of_the_cycles() {
    let (rec, _) = reciprocating_recording(&RecipSpec::default());
    let cfg = IdentifyConfig {
        steady: SteadyRule::Last(0.5),
        ..Default::default()
    };
    let s = Signals::of(&rec);
    let p = parts(&s, &cfg);
    let r = analyse(&s, p[0].0, p[0].1, &cfg).unwrap();
    assert_eq!(r.steady_cycles, (50, 100));
}

#[test]
fn a_one_way_test_is_not_reciprocating() {
    let (mut rec, _) = reciprocating_recording(&RecipSpec::default());
    rec.position_m = None;
    rec.tangential_n.iter_mut().for_each(|v| *v = v.abs());
    let cfg = IdentifyConfig::default();
    assert!(detect(&Signals::of(&rec), None, None, &cfg).is_none());
}

/// Through the campaign identification: one row per test, flagged `reciprocating`, the
/// sliding velocity from the position, the per-cycle evolution kept in the segment.
#[test]
fn campaign_identification_gives_one_row_per_test() {
    use greybox_contact::hertz::PinContact;
    use greybox_tribo::campaign::{identify_recordings, Campaign};
    let (rec, _) = reciprocating_recording(&RecipSpec::default());
    let cfg = IdentifyConfig::default();
    let contact = PinContact::default();
    let c = Campaign {
        expected: None,
        plan: None,
        contact: &contact,
        cfg: &cfg,
        track_radius_mm: &[],
    };
    let id = identify_recordings(&[rec], &c).unwrap();
    assert_eq!(id.dataset.records.len(), 1);
    let row = &id.dataset.records[0];
    assert!((row.cof_apparent - 0.28).abs() < 0.003, "{row:?}");
    assert!(
        row.flags.iter().any(|f| f == "reciprocating"),
        "{:?}",
        row.flags
    );
    assert!(
        (row.sliding_velocity_m_s - 0.015).abs() < 0.001,
        "{}",
        row.sliding_velocity_m_s
    );
    let f = &id.files[0];
    assert_eq!(f.segmentation, "reciprocating");
    assert!(!f.tangential_sign_flipped);
    let r = f.segments[0].reciprocating.as_ref().unwrap();
    assert_eq!(r.cycles.len(), 100);
    assert!((r.mu_forward - 0.30).abs() < 0.003 && (r.mu_backward - 0.26).abs() < 0.003);
}

/// A UMT-like export of blocks (one half-stroke each, forces in g, Fz negative, T restarting
/// per block, a constant X column) read through the readers: the profile is detected, the
/// blocks become the strokes, μ per direction within 0.003.
#[test]
fn umt_export_of_half_stroke_blocks() {
    use greybox_contact::hertz::PinContact;
    use greybox_recording::readers::read_recording;
    use greybox_recording::ChannelMap;
    use greybox_recording::TestMode;
    use greybox_tribo::campaign::{identify_recordings, Campaign};
    use greybox_tribo::synth_recip::umt_export_text;
    let spec = RecipSpec {
        sample_rate_hz: 500.0,
        frequency_hz: 2.0,
        cycles: 60,
        run_in_cycles: 4.0,
        ..RecipSpec::default()
    };
    let (rec, block) = reciprocating_recording(&spec);
    let d = tempfile::tempdir().unwrap();
    let path = d.path().join("umt_001.csv");
    std::fs::write(&path, umt_export_text(&rec, &block)).unwrap();
    let map = ChannelMap {
        constant_sliding_m_s: Some(0.004),
        ..ChannelMap::default()
    };
    let read = read_recording(&path, &map).unwrap();
    let report = read.provenance.as_ref().unwrap();
    assert_eq!(report.test_mode, Some(TestMode::Reciprocating));
    assert!(
        report.notes.iter().any(|n| n.contains("bruker-umt")),
        "{:?}",
        report.notes
    );
    assert!(
        (read.normal_n[10] - 10.0).abs() < 0.3,
        "Fz in g, flipped: {}",
        read.normal_n[10]
    );
    let cfg = IdentifyConfig::default();
    let contact = PinContact::default();
    let c = Campaign {
        expected: None,
        plan: None,
        contact: &contact,
        cfg: &cfg,
        track_radius_mm: &[],
    };
    let id = identify_recordings(&[read], &c).unwrap();
    let seg = &id.files[0].segments[0];
    let r = seg.reciprocating.as_ref().unwrap();
    eprintln!(
        "UMT: {} strokes, {} cycles, steady {:?}, μ {:.5} / {:.5}",
        r.strokes,
        r.cycles.len(),
        r.steady_cycles,
        r.mu_forward,
        r.mu_backward
    );
    assert_eq!(r.source, StrokeSource::Blocks);
    assert_eq!(r.strokes, 120);
    assert_eq!(r.cycles.len(), 60);
    assert!((r.mu_forward - 0.30).abs() < 0.003, "{}", r.mu_forward);
    assert!((r.mu_backward - 0.26).abs() < 0.003, "{}", r.mu_backward);
    assert_eq!(id.dataset.records.len(), 1);
}

/// Two load steps of one reciprocating test (a step column whose runs hold many strokes
/// each): one row per step, each with its own cycles.
#[test]
fn load_steps_give_one_row_each() {
    use greybox_contact::hertz::PinContact;
    use greybox_tribo::campaign::{identify_recordings, Campaign};
    let (mut rec, _) = reciprocating_recording(&RecipSpec {
        cycles: 40,
        rest_s: 0.2,
        ..RecipSpec::default()
    });
    let (b, _) = reciprocating_recording(&RecipSpec {
        cycles: 40,
        rest_s: 0.2,
        normal_n: 20.0,
        seed: 8,
        ..RecipSpec::default()
    });
    let n = rec.len();
    let t_end = rec.time_s[n - 1] + 1e-3;
    rec.time_s.extend(b.time_s.iter().map(|t| t + t_end));
    rec.normal_n.extend(&b.normal_n);
    rec.tangential_n.extend(&b.tangential_n);
    rec.position_m
        .as_mut()
        .unwrap()
        .extend(b.position_m.as_ref().unwrap());
    rec.step = Some((0..2 * n).map(|k| if k < n { 1.0 } else { 2.0 }).collect());
    let cfg = IdentifyConfig::default();
    let contact = PinContact::default();
    let c = Campaign {
        expected: None,
        plan: None,
        contact: &contact,
        cfg: &cfg,
        track_radius_mm: &[],
    };
    let id = identify_recordings(&[rec], &c).unwrap();
    assert_eq!(id.dataset.records.len(), 2, "{:?}", id.files[0].notes);
    for (row, f) in id.dataset.records.iter().zip([10.0, 20.0]) {
        assert!(
            (row.normal_force_n - f).abs() < 0.1 && (row.cof_apparent - 0.28).abs() < 0.003,
            "{row:?}"
        );
    }
    for s in &id.files[0].segments {
        assert_eq!(s.reciprocating.as_ref().unwrap().cycles.len(), 40);
    }
}
