//! TDMS files written by an independent implementation (npTDMS) read back identically to the
//! CSV path, and npTDMS reads the TDMS files greybox writes.
//!
//! The committed fixtures were written by `scripts/nptdms_fixtures.py`. When the environment
//! variable `GREYBOX_PYTHON` names a Python with npTDMS installed (`.ci/run` sets it up), the
//! fixtures are also regenerated fresh and the reverse check runs.

use greybox_recording::csv_recording::{read_csv_recording, write_csv_recording};
use greybox_recording::tdms::{read_tdms_recording, write_tdms_recording, TdmsFile};
use greybox_recording::{ChannelMap, ReaderOptions, Recording};
use std::path::{Path, PathBuf};
use std::process::Command;

fn fixtures() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/nptdms")
}

fn time_channel_map() -> ChannelMap {
    let mut m = ChannelMap {
        reader: ReaderOptions {
            tdms_group: Some("Dyno".into()),
            ..Default::default()
        },
        ..Default::default()
    };
    m.apply_override("time=time:s").unwrap();
    m.apply_override("normal=Fz:kN").unwrap();
    m.apply_override("tangential=Fx:kN:-1").unwrap();
    m
}

fn assert_same(a: &Recording, b: &Recording) {
    assert_eq!(a.len(), b.len());
    // identical doubles: the CSV holds Python's repr, which round-trips exactly
    assert_eq!(a.normal_n, b.normal_n);
    assert_eq!(a.tangential_n, b.tangential_n);
    assert_eq!(a.radial_n, b.radial_n);
    assert_eq!(a.trigger_v, b.trigger_v);
    for (x, y) in a.time_s.iter().zip(&b.time_s) {
        assert!((x - y).abs() <= 1e-12 * x.abs().max(1.0), "{x} vs {y}");
    }
}

fn check_dir(dir: &Path) {
    let map = ChannelMap::default();
    let tdms = read_tdms_recording(&dir.join("waveform.tdms"), &map).unwrap();
    let csv = read_csv_recording(&dir.join("waveform.csv"), &map).unwrap();
    assert_eq!(tdms.len(), 1200, "three segments of 400");
    assert_same(&tdms, &csv);

    let map = time_channel_map();
    let tdms = read_tdms_recording(&dir.join("timechannel.tdms"), &map).unwrap();
    let mut csv_map = map.clone();
    csv_map.apply_override("normal=Fz:kN").unwrap();
    let csv = read_csv_recording(&dir.join("timechannel.csv"), &csv_map).unwrap();
    assert_same(&tdms, &csv);
    assert!(tdms.tangential_n[0] > 300.0, "kN and the −1 scale applied");

    // properties of root and group objects are read too
    let file = TdmsFile::read(&dir.join("waveform.tdms")).unwrap();
    let root = file.object("/").unwrap();
    assert_eq!(
        root.property("title").and_then(|p| p.as_str()),
        Some("greybox parity fixture")
    );
    let counter = file.channel("Dyno", "counter");
    assert!(counter.is_none());
    let file = TdmsFile::read(&dir.join("timechannel.tdms")).unwrap();
    let counter = file.channel("Dyno", "counter").unwrap();
    assert_eq!(counter.data.len(), 600);
    assert_eq!(counter.data[599], 599.0);
}

#[test]
fn committed_nptdms_fixtures_match_csv() {
    check_dir(&fixtures());
}

fn python() -> Option<String> {
    std::env::var("GREYBOX_PYTHON")
        .ok()
        .filter(|p| !p.is_empty())
}

#[test]
fn fresh_nptdms_files_match_csv() {
    let Some(py) = python() else {
        eprintln!("GREYBOX_PYTHON not set: skipping the fresh npTDMS run (committed fixtures are still checked)");
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scripts/nptdms_fixtures.py");
    let st = Command::new(&py)
        .arg(&script)
        .arg(dir.path())
        .status()
        .expect("run python");
    assert!(st.success(), "nptdms_fixtures.py failed");
    check_dir(dir.path());
}

#[test]
fn nptdms_reads_greybox_tdms() {
    let Some(py) = python() else {
        eprintln!("GREYBOX_PYTHON not set: skipping the npTDMS read-back check");
        return;
    };
    let plan = greybox_tribo::plan::PlanSpec {
        track_radius_mm: Some(100.0),
        normal_force_count: greybox_tribo::plan::PinCount::of(1),
        normal_force_max_n: 150.0,
        ..Default::default()
    }
    .build()
    .unwrap();
    let rec = greybox_tribo::synth::SynthConfig::default()
        .simulate_pin(&plan, &greybox_contact::hertz::PinContact::default(), 1)
        .unwrap();
    assert!(
        rec.len() > 2 * greybox_recording::tdms::DEFAULT_SEGMENT_SAMPLES / 2,
        "several segments"
    );
    let dir = tempfile::tempdir().unwrap();
    write_tdms_recording(&dir.path().join("r.tdms"), &rec, "Tribometer").unwrap();
    write_csv_recording(&dir.path().join("r.csv"), &rec).unwrap();
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scripts/nptdms_check.py");
    let out = Command::new(&py)
        .arg(&script)
        .arg(dir.path().join("r.tdms"))
        .arg(dir.path().join("r.csv"))
        .arg("Tribometer")
        .output()
        .expect("run python");
    eprintln!("{}", String::from_utf8_lossy(&out.stdout));
    assert!(
        out.status.success(),
        "npTDMS check failed: {}",
        String::from_utf8_lossy(&out.stdout)
    );
}
