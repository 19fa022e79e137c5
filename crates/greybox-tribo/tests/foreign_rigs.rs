//! Recordings from rigs that did not run greybox's NC program: a second virtual rig written
//! independently of `synth` (tests/support/rig2.rs) and four export layouts of other
//! tribometers (tests/support/exports.rs), identified against their ground truth.

mod glue;
mod support;

use greybox_core::units;
use greybox_recording::readers::read_recording;
use greybox_recording::{ChannelMap, Recording};
use greybox_tribo::campaign::{ExpectedStep, Identification};
use greybox_tribo::config::IdentifyConfig;
use std::path::PathBuf;
use support::TruthStep;

fn read_all(files: &[PathBuf], map: &ChannelMap) -> Vec<Recording> {
    files
        .iter()
        .map(|f| read_recording(f, map).unwrap())
        .collect()
}

fn files_of(truth: &[TruthStep]) -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = Vec::new();
    for t in truth {
        if !v.contains(&t.file) {
            v.push(t.file.clone());
        }
    }
    v
}

fn identify(
    recs: &[Recording],
    expected: Option<&[ExpectedStep]>,
    radii: &[f64],
) -> Identification {
    glue::identify_on(recs, expected, &IdentifyConfig::default(), radii)
}

/// With a plan, rows carry the plan's pin and step: compare one to one.
fn check_against_plan(id: &Identification, truth: &[TruthStep], tol: f64) {
    assert_eq!(id.dataset.records.len(), truth.len(), "{:#?}", id.matching);
    for t in truth {
        let r = id
            .dataset
            .records
            .iter()
            .find(|r| r.pin == t.pin && r.step == t.step)
            .unwrap_or_else(|| panic!("no row for pin {} step {}", t.pin, t.step));
        assert!(
            (r.cof_apparent - t.mu_true).abs() <= tol,
            "pin {} step {} ({} N, {} m/min): {:.5} vs truth {:.5}",
            t.pin,
            t.step,
            t.normal_force_n,
            t.velocity_m_per_min,
            r.cof_apparent,
            t.mu_true
        );
    }
    assert!(
        id.matching.missing.is_empty() && id.matching.extra.is_empty(),
        "{:#?}",
        id.matching
    );
    report_error(id, truth);
}

/// Largest |μ − μ_true| (printed with `--nocapture`, for the docs).
fn report_error(id: &Identification, truth: &[TruthStep]) {
    let worst = truth
        .iter()
        .zip(&id.dataset.records)
        .map(|(t, r)| (r.cof_apparent - t.mu_true).abs())
        .fold(0.0, f64::max);
    eprintln!("max |mu - mu_true| = {worst:.5} over {} steps", truth.len());
}

/// Without a plan, rows are numbered in the order found and carry measured values.
fn check_without_plan(id: &Identification, truth: &[TruthStep], tol: f64) {
    assert_eq!(id.dataset.records.len(), truth.len());
    for (r, t) in id.dataset.records.iter().zip(truth) {
        assert!(
            (r.cof_apparent - t.mu_true).abs() <= tol,
            "pin {} step {}: {:.5} vs truth {:.5}",
            t.pin,
            t.step,
            r.cof_apparent,
            t.mu_true
        );
        let v = units::m_per_s_to_m_per_min(r.sliding_velocity_m_s);
        assert!(
            (v / t.velocity_m_per_min - 1.0).abs() < 0.01,
            "pin {} step {}: measured {v:.2} m/min vs {}",
            t.pin,
            t.step,
            t.velocity_m_per_min
        );
        assert!(
            (r.normal_force_n / t.normal_force_n - 1.0).abs() < 0.02,
            "pin {} step {}: measured {:.1} N vs {}",
            t.pin,
            t.step,
            r.normal_force_n,
            t.normal_force_n
        );
    }
    report_error(id, truth);
}

fn lathe_rig() -> (tempfile::TempDir, Vec<TruthStep>) {
    let dir = tempfile::tempdir().unwrap();
    let truth =
        support::rig2::LatheRig::new(7).write_campaign(dir.path(), &support::rig2::default_pins());
    (dir, truth)
}

#[test]
fn lathe_rig_with_a_plan_and_no_speed_channel() {
    // the signals alone, matched by order to a plan of loads and velocities (no timing)
    let (_dir, truth) = lathe_rig();
    let mut map = ChannelMap::default();
    map.apply_override("speed=").unwrap();
    let recs = read_all(&files_of(&truth), &map);
    assert!(recs.iter().all(|r| r.speed.is_none()));
    let expected = glue::plan_of(&truth, false);
    let id = identify(&recs, Some(&expected), &[]);
    assert!(id.files.iter().all(|f| f.segmentation == "signals"));
    assert!(id
        .files
        .iter()
        .all(|f| f.tangential_sign_flipped && f.baseline == "none"));
    // no unloaded window: a warning of each file (a file-wide fact), not a flag of each row
    assert!(id
        .files
        .iter()
        .all(|f| f.warnings.iter().any(|w| w.contains("no unloaded window"))));
    // nothing but the order places a step among a pin's steps at one load: every row says so
    assert!(id.dataset.records.iter().all(|r| {
        r.label_evidence.as_deref() == Some("order")
            && r.flags.iter().any(|f| f == "label-by-order")
    }));
    assert_eq!(id.matching.labels_by_order, id.dataset.records.len());
    check_against_plan(&id, &truth, 0.003);
}

#[test]
fn lathe_rig_without_a_plan() {
    // velocities from the spindle speed and the track radius, loads measured
    let (_dir, truth) = lathe_rig();
    let recs = read_all(&files_of(&truth), &ChannelMap::default());
    let id = identify(&recs, None, &[100.0]);
    assert!(id.files.iter().all(|f| f.segmentation == "speed"));
    check_without_plan(&id, &truth, 0.003);
    // one pin per file
    let pins: Vec<u32> = id.dataset.records.iter().map(|r| r.pin).collect();
    assert_eq!(pins.iter().max(), Some(&3));
}

#[test]
fn lathe_rig_matched_by_speed_reports_a_reordered_pin() {
    // a factorial plan lists every pin ascending; the rig ran pin 2 descending
    let (_dir, truth) = lathe_rig();
    let recs = read_all(&files_of(&truth), &ChannelMap::default());
    let mut expected = glue::plan_of(&truth, false);
    for pin in 1..=3 {
        let mut v: Vec<&mut ExpectedStep> = expected.iter_mut().filter(|e| e.pin == pin).collect();
        let mut speeds: Vec<f64> = v.iter().map(|e| e.sliding_velocity_m_s).collect();
        speeds.sort_by(f64::total_cmp);
        for (k, e) in v.iter_mut().enumerate() {
            e.sliding_velocity_m_s = speeds[k];
            e.step = k as u32 + 1;
        }
    }
    let id = identify(&recs, Some(&expected), &[100.0]);
    assert_eq!(id.matching.method, "alignment by load and speed");
    assert!(!id.matching.reordered.is_empty());
    assert!(
        id.matching.reordered.iter().all(|r| r.contains("pin 2")),
        "{:#?}",
        id.matching
    );
    for t in &truth {
        let r = id
            .dataset
            .records
            .iter()
            .find(|r| {
                r.pin == t.pin
                    && (units::m_per_s_to_m_per_min(r.sliding_velocity_m_s) - t.velocity_m_per_min)
                        .abs()
                        < 1e-6
            })
            .unwrap();
        assert!((r.cof_apparent - t.mu_true).abs() <= 0.003);
    }
}

#[test]
fn a_missing_step_is_reported_by_name() {
    let (_dir, truth) = lathe_rig();
    let recs = read_all(&files_of(&truth), &ChannelMap::default());
    let mut expected = glue::plan_of(&truth, false);
    expected.push(ExpectedStep {
        pin: 3,
        step: 7,
        normal_force_n: 1800.0,
        sliding_velocity_m_s: units::m_per_min_to_m_per_s(280.0),
        duration_s: None,
    });
    let id = identify(&recs, Some(&expected), &[100.0]);
    assert_eq!(
        id.matching.missing,
        vec!["pin 3 step 7 (1800.0 N, 280.0 m/min)".to_string()]
    );
    assert_eq!(id.dataset.records.len(), truth.len());
}

/// Files given out of the plan's pin order, without a speed channel: the alignment places
/// each file where its loads fit, identifies every step as if they were in order, and says
/// that the files were reordered.
#[test]
fn swapped_files_are_placed_by_their_loads() {
    let (_dir, truth) = lathe_rig();
    let mut files = files_of(&truth);
    files.swap(0, 2);
    let mut map = ChannelMap::default();
    map.apply_override("speed=").unwrap();
    let recs = read_all(&files, &map);
    let expected = glue::plan_of(&truth, false);
    let id = identify(&recs, Some(&expected), &[]);
    check_against_plan(&id, &truth, 0.003);
    assert!(
        id.matching
            .reordered
            .iter()
            .any(|r| r.contains("order") && r.find("rig2_pin01.csv") < r.find("rig2_pin03.csv")),
        "{:#?}",
        id.matching
    );
}

/// Every export layout identifies within 0.002 of its ground truth, without a plan.
fn check_export(truth: &[TruthStep], map: &ChannelMap, radii: &[f64]) -> Identification {
    let recs = read_all(&files_of(truth), map);
    let id = identify(&recs, None, radii);
    check_without_plan(&id, truth, 0.002);
    id
}

#[test]
fn rotary_tribometer_export() {
    // preamble, Step column, time restarting per step, trailing delimiter, footer, 10 Hz,
    // rpm with a track radius that changes from step to step
    let dir = tempfile::tempdir().unwrap();
    let truth = support::exports::write_rotary_export(dir.path(), 3);
    let id = check_export(
        &truth,
        &ChannelMap::default(),
        &support::exports::ROTARY_RADII_MM,
    );
    let f = &id.files[0];
    assert_eq!(f.segmentation, "step-column");
    let read = f.read.as_ref().unwrap();
    assert!(
        read.layout.contains("trailing delimiter") && read.layout.contains("header on line 3"),
        "{}",
        read.layout
    );
    assert_eq!(read.footer.len(), 2);
    assert!(
        read.notes
            .iter()
            .any(|n| n.contains("restarts at 4 step change")),
        "{:?}",
        read.notes
    );
    let roles: Vec<(&str, &str)> = read
        .columns
        .iter()
        .map(|c| (c.role.name(), c.column.as_str()))
        .collect();
    assert!(
        roles.contains(&("normal", "DAQ.Fz (N)")) && roles.contains(&("speed", "Velocity (rpm)")),
        "{roles:?}"
    );
}

#[test]
fn semicolon_decimal_comma_campaign_in_one_file() {
    let dir = tempfile::tempdir().unwrap();
    let truth = support::exports::write_semicolon_campaign(dir.path(), 4);
    let id = check_export(&truth, &ChannelMap::default(), &[]);
    assert_eq!(id.files[0].baseline, "start and end");
    let pins: Vec<u32> = id.dataset.records.iter().map(|r| r.pin).collect();
    assert_eq!(pins, vec![1, 1, 1, 1, 2, 2, 2, 2]);
}

#[test]
fn tab_separated_files_per_step_without_time() {
    let dir = tempfile::tempdir().unwrap();
    let truth = support::exports::write_tab_per_step(dir.path(), 5);
    let mut map = ChannelMap::default();
    // without a time column the sample rate is required, and the error says so
    let e = read_recording(&truth[0].file, &map)
        .unwrap_err()
        .to_string();
    assert!(e.contains("`sample_rate_hz`"), "{e}");
    map.sample_rate_hz = Some(support::exports::TAB_SAMPLE_RATE_HZ);
    let id = check_export(&truth, &map, &[]);
    // one pin made of four files
    assert!(id.dataset.records.iter().all(|r| r.pin == 1));
}

#[test]
fn xlsx_workbook() {
    let dir = tempfile::tempdir().unwrap();
    let truth = support::exports::write_xlsx_workbook(dir.path(), 6);
    let id = check_export(&truth, &ChannelMap::default(), &[]);
    assert!(id.files[0]
        .read
        .as_ref()
        .unwrap()
        .layout
        .contains("sheet 'Data'"));
}
