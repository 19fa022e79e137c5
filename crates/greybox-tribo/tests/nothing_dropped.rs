//! Nothing read is dropped, split or contradicted without a line in the summary, and every
//! recording reader opens its file the same guarded way (issue 46 items 2, 5 and 6).

use greybox_contact::hertz::PinContact;
use greybox_recording::readers::read_recording;
use greybox_recording::{ChannelMap, Recording, SpeedTrace};
use greybox_tribo::campaign::{identify_recordings, Campaign, Identification};
use greybox_tribo::config::IdentifyConfig;
use std::fmt::Write as _;
use std::path::Path;

fn read(path: &Path) -> greybox_core::Result<Recording> {
    read_recording(path, &ChannelMap::default())
}

fn identify(recs: &[Recording], cfg: &IdentifyConfig) -> Identification {
    let contact = PinContact::default();
    identify_recordings(
        recs,
        &Campaign {
            expected: None,
            plan: None,
            contact: &contact,
            cfg,
            track_radius_mm: &[],
        },
    )
    .unwrap()
}

/// A text recording at 10 Hz: `rows` rows of time, F_N = 100 N and F_t = 30 N (μ 0.3), and
/// `cof` as the rig's own μ column when given.
fn table(rows: usize, cof: Option<f64>) -> String {
    let mut s = String::from("Time [s],Fn [N],Ft [N]");
    s.push_str(if cof.is_some() { ",COF\n" } else { "\n" });
    for k in 0..rows {
        let _ = write!(s, "{:.1},100,30", k as f64 * 0.1);
        match cof {
            Some(c) => {
                let _ = writeln!(s, ",{c}");
            }
            None => s.push('\n'),
        }
    }
    s
}

/// Every reader (text, spreadsheet, TDMS, by the name's format) refuses a link to a device and
/// a FIFO by name and kind, without opening the FIFO (which would wait for a writer).
#[cfg(target_os = "linux")]
#[test]
fn every_reader_refuses_what_is_not_a_regular_file() {
    let d = tempfile::tempdir().unwrap();
    for ext in ["csv", "xlsx", "tdms"] {
        let link = d.path().join(format!("zero.{ext}"));
        std::os::unix::fs::symlink("/dev/zero", &link).unwrap();
        let e = read(&link).unwrap_err().to_string();
        assert!(
            e.contains(&format!("zero.{ext}")) && e.contains("character device"),
            "{ext}: {e}"
        );
        let fifo = d.path().join(format!("fifo.{ext}"));
        let status = std::process::Command::new("mkfifo")
            .arg(&fifo)
            .status()
            .unwrap();
        assert!(status.success());
        let e = read(&fifo).unwrap_err().to_string();
        assert!(
            e.contains("FIFO") && e.contains("not a regular file"),
            "{ext}: {e}"
        );
    }
}

/// A units row that contradicts the header's unit is an error naming the file, the line and
/// both units, not a column silently read in one of them.
#[test]
fn a_units_row_that_contradicts_the_header_is_refused() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path().join("units.csv");
    std::fs::write(
        &p,
        "Time,Fn (kN),Ft (N)\ns,N,N\n0,1,0.3\n0.1,1,0.3\n0.2,1,0.3\n0.3,1,0.3\n",
    )
    .unwrap();
    let e = read(&p).unwrap_err().to_string();
    assert!(
        e.contains("units.csv") && e.contains("line 2") && e.contains("kN") && e.contains("says N"),
        "{e}"
    );
}

/// A rig's own μ 50 % off F_t/F_N is a warning with the numbers (not only an `--inspect`
/// note), carried into the identification's file report.
#[test]
fn a_cof_column_far_from_the_forces_is_a_summary_line() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path().join("cof.csv");
    std::fs::write(&p, table(200, Some(0.6))).unwrap();
    let rec = read(&p).unwrap();
    let w = rec.provenance.as_ref().unwrap().warnings.join("\n");
    assert!(
        w.contains("differs") && w.contains("50 %") && w.contains("0.6000"),
        "{w}"
    );
    // agreeing within the tolerance: no warning
    std::fs::write(&p, table(200, Some(0.31))).unwrap();
    let rec = read(&p).unwrap();
    assert!(rec.provenance.as_ref().unwrap().warnings.is_empty());
}

/// Rows written with another delimiter after the data are not silently a "footer": the
/// summary says how many lines were left unread and that they hold numbers.
#[test]
fn rows_left_unread_after_the_data_are_a_summary_line() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path().join("footer.csv");
    let mut text = table(100, None);
    for k in 100..1100 {
        let _ = writeln!(text, "{:.1};100;30", k as f64 * 0.1);
    }
    std::fs::write(&p, text).unwrap();
    match read(&p) {
        Ok(rec) => {
            let w = rec.provenance.as_ref().unwrap().warnings.join("\n");
            assert!(
                w.contains("1000 line(s) after the data") && w.contains("mostly numbers"),
                "{w}"
            );
        }
        // refused outright is as good: nothing is lost silently
        Err(e) => assert!(e.to_string().contains("footer.csv"), "{e}"),
    }
    // an `End of data` line stays a quiet footer
    std::fs::write(&p, table(100, None) + "End of data\n").unwrap();
    let rec = read(&p).unwrap();
    assert!(rec.provenance.as_ref().unwrap().warnings.is_empty());
}

/// An 11-day pause inside one loaded sliding stretch splits it: no steady window spans the
/// gap, and the split is named in the file's warnings.
#[test]
fn a_long_gap_in_time_splits_the_segment_and_is_named() {
    let (fs, half) = (10.0, 3000);
    let gap_s = 11.0 * 86_400.0;
    let mut r = Recording::new("gap.csv", Vec::new(), Vec::new(), Vec::new());
    let mut speed = Vec::new();
    let mut push = |t: f64, loaded: bool| {
        r.time_s.push(t);
        r.normal_n.push(if loaded { 100.0 } else { 0.0 });
        r.tangential_n.push(if loaded { 30.0 } else { 0.0 });
        speed.push(if loaded { 0.1 } else { 0.0 });
    };
    // 20 s unloaded, 300 s sliding, the pause, 300 s sliding, 20 s unloaded
    for k in 0..200 {
        push(k as f64 / fs, false);
    }
    for k in 0..half {
        push(20.0 + k as f64 / fs, true);
    }
    let resume = 20.0 + half as f64 / fs + gap_s;
    for k in 0..half {
        push(resume + k as f64 / fs, true);
    }
    let end = resume + half as f64 / fs;
    for k in 0..200 {
        push(end + k as f64 / fs, false);
    }
    r.speed = Some(SpeedTrace::SlidingMPerS(speed));
    let id = identify(&[r], &IdentifyConfig::default());
    let f = &id.files[0];
    let w = f.warnings.join("\n");
    assert!(
        w.contains("11.0 days") && w.contains("splits a segment"),
        "{w}"
    );
    let gap = (20.0 + half as f64 / fs, resume);
    for s in &f.segments {
        if let (Some(a), Some(b)) = (s.steady_start_s, s.steady_end_s) {
            assert!(
                b <= gap.0 || a >= gap.1,
                "steady window {a}..{b} spans the gap"
            );
        }
    }
    assert!(
        f.segments.iter().filter(|s| s.cof.is_some()).count() >= 2,
        "{:#?}",
        f.segments
    );
}

/// A block with a header but no rows keeps its step number (the blocks after it are not
/// renumbered) and is a summary line.
#[test]
fn an_empty_block_keeps_its_step_number_and_is_named() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path().join("blocks.csv");
    let mut text = String::from("Rig 7\n");
    for b in 1..=3 {
        let _ = write!(text, "\nStep {b} started\nTime,Fz,Fx\ns,N,N\n");
        if b != 2 {
            for i in 0..40 {
                let _ = writeln!(text, "{:.1},{},{}", i as f64 * 0.1, 10 * b, 3 * b);
            }
        }
    }
    std::fs::write(&p, text).unwrap();
    let rec = read(&p).unwrap();
    let steps = rec.step.as_ref().expect("blocks give the step");
    assert_eq!(steps.first(), Some(&1.0));
    assert_eq!(steps.last(), Some(&3.0), "block 3 renumbered");
    assert!(!steps.contains(&2.0));
    let w = rec.provenance.as_ref().unwrap().warnings.join("\n");
    assert!(w.contains("block 2 has a header but no data row"), "{w}");
}

/// An xlsx time column formatted as clock times is read as seconds, not dropped.
#[test]
fn an_xlsx_time_column_of_dates_is_read_as_seconds() {
    use rust_xlsxwriter::{Format, Workbook};
    let d = tempfile::tempdir().unwrap();
    let p = d.path().join("dates.xlsx");
    let mut wb = Workbook::new();
    let sheet = wb.add_worksheet();
    for (c, h) in ["Time", "Fn (N)", "Ft (N)"].iter().enumerate() {
        sheet.write_string(0, c as u16, *h).unwrap();
    }
    let clock = Format::new().set_num_format("hh:mm:ss");
    // 2026-05-03 12:00:00 onwards, one row a second
    let start = 46_145.5;
    for k in 0..60u32 {
        let row = k + 1;
        sheet
            .write_number_with_format(row, 0, start + f64::from(k) / 86_400.0, &clock)
            .unwrap();
        sheet.write_number(row, 1, 100.0).unwrap();
        sheet.write_number(row, 2, 30.0).unwrap();
    }
    wb.save(&p).unwrap();
    let rec = read(&p).unwrap();
    assert_eq!(rec.len(), 60);
    let dt = rec.time_s[1] - rec.time_s[0];
    assert!((dt - 1.0).abs() < 1e-3, "one row a second, got {dt} s");
    let notes = rec.provenance.as_ref().unwrap().notes.join("\n");
    assert!(notes.contains("dates or times"), "{notes}");
}

/// `--test-mode continuous` forced on a reciprocating recording: the file's warnings say that
/// the named mode is contradicted (runs, strokes), instead of a bare "no plateau".
#[test]
fn a_forced_test_mode_the_signals_contradict_is_named() {
    use greybox_recording::TestMode;
    use greybox_tribo::campaign::segment_recordings;
    use greybox_tribo::synth_recip::{reciprocating_recording, RecipSpec};
    let (rec, _) = reciprocating_recording(&RecipSpec::default());
    let contact = PinContact::default();
    let cfg = IdentifyConfig {
        mode: Some(TestMode::Continuous),
        ..Default::default()
    };
    let files = segment_recordings(
        &[rec],
        &Campaign {
            expected: None,
            plan: None,
            contact: &contact,
            cfg: &cfg,
            track_radius_mm: &[],
        },
    )
    .unwrap();
    let f = &files[0];
    assert!(
        f.segments.iter().all(|s| s.cof.is_none()),
        "a continuous row from a reciprocating test: {:#?}",
        f.segments
    );
    let w = f.warnings.join("\n");
    assert!(
        w.contains("`test_mode` continuous was named")
            && w.contains("sliding run(s)")
            && w.contains("reciprocating"),
        "{w}"
    );
}

/// `µm` written by Windows rig software as the single Latin-1 byte 0xB5, in the header or in
/// a units row, is micrometres, not an unknown unit.
#[test]
fn latin1_micro_is_micrometres() {
    let d = tempfile::tempdir().unwrap();
    for (name, head) in [
        (
            "header.csv",
            &b"Time [s];Fn [N];Ft [N];Position [\xB5m]\n"[..],
        ),
        ("units.csv", &b"Time;Fn;Ft;Position\ns;N;N;\xB5m\n"[..]),
    ] {
        let p = d.path().join(name);
        let mut bytes = head.to_vec();
        for k in 0..50 {
            bytes.extend_from_slice(format!("{:.1};10;3;{}\n", k as f64 * 0.1, k * 100).as_bytes());
        }
        std::fs::write(&p, bytes).unwrap();
        let rec = read(&p).unwrap_or_else(|e| panic!("{name}: {e}"));
        let x = rec.position_m.as_ref().expect("the position column");
        assert!((x[10] - 1000e-6).abs() < 1e-12, "{name}: {}", x[10]);
    }
}

/// Speed steps at 10 Hz without a plan: 10 s unloaded, then per step (speed m/s, length s,
/// F_t N) at F_N = 100 N with 5 s at rest after each, then 10 s unloaded.
fn speed_steps(source: &str, steps: &[(f64, usize, f64)]) -> Recording {
    let fs = 10.0;
    let mut r = Recording::new(source, Vec::new(), Vec::new(), Vec::new());
    let mut speed = Vec::new();
    let mut t = 0.0;
    let mut push = |r: &mut Recording, n: usize, f_n: f64, f_t: f64, v: f64| {
        for k in 0..n {
            r.time_s.push(t);
            t += 1.0 / fs;
            // a little noise, deterministic
            let wobble = 0.01 * ((k as f64) * 0.7).sin();
            r.normal_n.push(f_n + wobble);
            r.tangential_n.push(f_t + wobble);
            speed.push(v);
        }
    };
    push(&mut r, 100, 0.0, 0.0, 0.0);
    for &(v, secs, f_t) in steps {
        push(&mut r, secs * 10, 100.0, f_t, v);
        push(&mut r, 50, 100.0, 0.0, 0.0);
    }
    push(&mut r, 100, 0.0, 0.0, 0.0);
    r.speed = Some(SpeedTrace::SlidingMPerS(speed));
    r
}

/// Without a plan, a step that gives no row keeps its number: the next step's row is not
/// written under it, and the summary says which step is empty and why.
#[test]
fn a_dropped_step_keeps_its_number() {
    let r = speed_steps(
        "short.csv",
        &[(0.1, 100, 30.0), (0.2, 20, 30.0), (0.3, 100, 30.0)],
    );
    let cfg = IdentifyConfig {
        steady: "from:50s".parse().unwrap(),
        ..Default::default()
    };
    let id = identify(&[r], &cfg);
    let rows: Vec<(u32, f64)> = id
        .dataset
        .records
        .iter()
        .map(|x| (x.step, x.sliding_velocity_m_s))
        .collect();
    assert_eq!(rows.len(), 2, "{rows:?}");
    assert_eq!(rows[1].0, 3, "step 3 renumbered: {rows:?}");
    let w = id.files[0].warnings.join("\n");
    assert!(
        w.contains("pin 1 step 2 but gave no row") && w.contains("from:50s"),
        "{w}"
    );
}

/// Three speed steps without a plan, the second with its friction force's sign reversed:
/// whatever becomes of step 2, step 3's row keeps number 3 (never written under 2), and a
/// step without a row is named.
#[test]
fn a_reversed_step_never_takes_the_next_steps_number() {
    let r = speed_steps(
        "reversed.csv",
        &[(0.1, 100, 30.0), (0.2, 100, -30.0), (0.3, 100, 30.0)],
    );
    let id = identify(&[r], &IdentifyConfig::default());
    let rows: Vec<(u32, f64)> = id
        .dataset
        .records
        .iter()
        .map(|x| (x.step, x.sliding_velocity_m_s))
        .collect();
    let third = rows
        .iter()
        .find(|(_, v)| (v - 0.3).abs() < 0.01)
        .expect("step 3 gave a row");
    assert_eq!(third.0, 3, "step 3 renumbered: {rows:?}");
    if !rows.iter().any(|(_, v)| (v - 0.2).abs() < 0.01) {
        let said = id.files[0]
            .warnings
            .iter()
            .chain(&id.files[0].coverage.dropped_notes())
            .any(|w| w.contains("step 2") || w.contains("segment 2"));
        assert!(said, "step 2 dropped silently: {:#?}", id.files[0]);
    }
}
