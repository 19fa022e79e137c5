//! Self-checks of the test-support generators in `tests/support/` (no greybox identification
//! code is called here): files exist, same seed → same bytes, ground-truth counts, and a light
//! sanity check of the written values with plain std parsing.

mod support;

use std::path::Path;
use support::exports::{
    write_rotary_export, write_semicolon_campaign, write_tab_per_step, write_xlsx_workbook,
    ROTARY_RADII_MM, ROTARY_RPM, TAB_SAMPLE_RATE_HZ,
};
use support::rig2::{default_pins, LatheRig};
use support::{mu_law, TruthStep};

fn read_dir_bytes(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut v: Vec<(String, Vec<u8>)> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| {
            let e = e.unwrap();
            (
                e.file_name().to_string_lossy().into_owned(),
                std::fs::read(e.path()).unwrap(),
            )
        })
        .collect();
    v.sort();
    v
}

fn assert_deterministic(write: impl Fn(&Path, u64) -> Vec<TruthStep>) {
    let a = tempfile::tempdir().unwrap();
    let b = tempfile::tempdir().unwrap();
    let c = tempfile::tempdir().unwrap();
    let ta = write(a.path(), 7);
    let tb = write(b.path(), 7);
    write(c.path(), 8);
    let (ba, bb, bc) = (
        read_dir_bytes(a.path()),
        read_dir_bytes(b.path()),
        read_dir_bytes(c.path()),
    );
    assert!(!ba.is_empty());
    assert_eq!(ba, bb, "same seed must give the same bytes");
    assert_ne!(ba, bc, "another seed must give other bytes");
    assert_eq!(ta.len(), tb.len());
    for (x, y) in ta.iter().zip(&tb) {
        assert_eq!(x.mu_true, y.mu_true);
        assert_eq!(x.file.file_name(), y.file.file_name());
    }
}

fn check_truth(truth: &[TruthStep]) {
    for t in truth {
        assert!(t.file.exists(), "{}", t.file.display());
        assert!((0.25..=0.6).contains(&t.mu_true), "{t:?}");
        assert!((t.mu_true - mu_law(t.normal_force_n, t.velocity_m_per_min)).abs() < 1e-15);
    }
}

#[test]
fn ground_truth_law_is_plausible() {
    assert!(mu_law(300.0, 40.0) > mu_law(300.0, 240.0));
    assert!(mu_law(300.0, 120.0) > mu_law(1800.0, 120.0));
    assert_eq!(mu_law(500.0, 0.0), 0.0);
    assert!(mu_law(10.0, 9.0) < 0.6 && mu_law(1800.0, 240.0) > 0.25);
}

// ------------------------------------------------------------------ rig 2

struct Row {
    t: f64,
    fz_kn: f64,
    fx: f64,
    fy: f64,
    rpm: f64,
}

fn read_rig2(path: &Path) -> Vec<Row> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    assert_eq!(
        lines.next().unwrap(),
        "Time [s],Fz [kN],Fx [N],Fy [N],Spindle [rpm]"
    );
    lines
        .map(|l| {
            let f: Vec<f64> = l.split(',').map(|x| x.parse().unwrap()).collect();
            assert_eq!(f.len(), 5, "{l}");
            Row {
                t: f[0],
                fz_kn: f[1],
                fx: f[2],
                fy: f[3],
                rpm: f[4],
            }
        })
        .collect()
}

#[test]
fn rig2_is_deterministic() {
    assert_deterministic(|d, s| LatheRig::new(s).write_campaign(d, &default_pins()[..1]));
}

#[test]
fn rig2_campaign_layout_and_values() {
    let dir = tempfile::tempdir().unwrap();
    let rig = LatheRig::new(42);
    let pins = default_pins();
    let truth = rig.write_campaign(dir.path(), &pins);
    assert_eq!(truth.len(), 18);
    check_truth(&truth);
    assert_eq!(pins[1].1[0], 240.0);
    for (p, (load, vels)) in pins.iter().enumerate() {
        let path = dir.path().join(format!("rig2_pin{:02}.csv", p + 1));
        assert!(std::fs::metadata(&path).unwrap().len() < 1_500_000);
        let rows = read_rig2(&path);
        let fs = rig.sample_rate_hz;
        let cycle = rig.ramp_s + rig.dwell_s;
        let t_stop = rig.pre_roll_s + vels.len() as f64 * cycle;
        let n_total = ((t_stop + rig.tail_s) * fs).round() as usize;
        assert_eq!(rows.len(), n_total - 80, "exactly one 40 ms gap");
        // exactly one gap of 81 nominal steps, timestamps 0.05 % fast
        let dt_rec = rig.clock_factor / fs;
        let big: Vec<f64> = rows
            .windows(2)
            .map(|w| w[1].t - w[0].t)
            .filter(|d| *d > 1.5 * dt_rec)
            .collect();
        assert_eq!(big.len(), 1);
        assert!((big[0] - 81.0 * dt_rec).abs() < 2e-6, "{big:?}");
        assert!((rows[1].t - rows[0].t - dt_rec).abs() < 1.5e-6);
        // loaded everywhere (no unloaded window), spindle at rest at both ends
        assert!(
            rows.iter().all(|r| r.fz_kn * 1000.0 > 0.8 * load),
            "unloaded sample"
        );
        assert_eq!(rows[0].rpm, 0.0);
        assert_eq!(rows.last().unwrap().rpm, 0.0);
        assert!(rows[0].fx.abs() < 5.0 && rows.last().unwrap().fx.abs() < 5.0);
        assert!((rows.last().unwrap().fz_kn * 1000.0 - load).abs() < 0.05 * load);
        // dwell averages give mu_true (window from 1.0 s after the ramp, true time)
        for (k, &v) in vels.iter().enumerate() {
            let t0 = rig.pre_roll_s + k as f64 * cycle + rig.ramp_s + 1.0;
            let t1 = rig.pre_roll_s + (k + 1) as f64 * cycle - 0.05;
            let (mut st, mut sn, mut sr, mut sy, mut m) = (0.0, 0.0, 0.0, 0.0, 0usize);
            for r in rows.iter().filter(|r| {
                let t = r.t / rig.clock_factor;
                t >= t0 && t < t1
            }) {
                st += -r.fx;
                sn += r.fz_kn * 1000.0;
                sr += r.rpm;
                sy += r.fy;
                m += 1;
            }
            assert!(m > 1500);
            let mu = st / sn;
            let mu_true = mu_law(*load, v);
            assert!(
                (mu - mu_true).abs() < 0.003,
                "pin {} step {}: {mu} vs {mu_true}",
                p + 1,
                k + 1
            );
            let rpm = sr / m as f64;
            assert!((rpm / rig.rpm_for(v) - 1.0).abs() < 0.01, "{rpm}");
            assert!((sy / sn - 0.05).abs() < 0.01);
        }
    }
}

// ------------------------------------------------------------------ exports

#[test]
fn rotary_is_deterministic() {
    assert_deterministic(write_rotary_export);
}

#[test]
fn rotary_layout_and_values() {
    let dir = tempfile::tempdir().unwrap();
    let truth = write_rotary_export(dir.path(), 3);
    assert_eq!(truth.len(), 5);
    check_truth(&truth);
    for (k, t) in truth.iter().enumerate() {
        let v = 2.0 * std::f64::consts::PI * ROTARY_RADII_MM[k] / 1000.0 * ROTARY_RPM[k];
        assert!((t.velocity_m_per_min - v).abs() < 1e-12);
        assert_eq!(t.normal_force_n, 10.0);
    }
    let text = std::fs::read_to_string(dir.path().join("rotary.csv")).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), 2 + 1 + 2500 + 2);
    assert!(lines[0].starts_with("Instrument:"));
    assert_eq!(
        lines[2],
        "Step, Time (s), DAQ.Fz (N), DAQ.Fx (N), Velocity (rpm), COF,"
    );
    assert_eq!(lines[lines.len() - 2], "End of data");
    assert_eq!(lines[lines.len() - 1], "Total time: 250 s");
    let data = &lines[3..lines.len() - 2];
    let mut sums = [(0.0f64, 0.0f64, 0usize); 5];
    for (i, l) in data.iter().enumerate() {
        assert!(l.ends_with(','));
        let f: Vec<&str> = l.split(',').collect();
        assert_eq!(f.len(), 7);
        assert_eq!(f[6], "");
        let step: usize = f[0].parse().unwrap();
        assert_eq!(step, i / 500 + 1);
        let t: f64 = f[1].parse().unwrap();
        assert!((t - (i % 500) as f64 * 0.1).abs() < 1e-9);
        let fz: f64 = f[2].parse().unwrap();
        let fx: f64 = f[3].parse().unwrap();
        let cof: f64 = f[5].parse().unwrap();
        assert!((cof - fx / fz).abs() < 1e-5);
        if t >= 5.0 {
            sums[step - 1].0 += fx;
            sums[step - 1].1 += fz;
            sums[step - 1].2 += 1;
        }
        if t == 0.0 {
            assert!(fx.abs() < 0.1);
        }
    }
    for (k, s) in sums.iter().enumerate() {
        assert!((s.0 / s.1 - truth[k].mu_true).abs() < 0.001, "{k}");
    }
}

#[test]
fn semicolon_is_deterministic() {
    assert_deterministic(write_semicolon_campaign);
}

#[test]
fn semicolon_layout_and_values() {
    let dir = tempfile::tempdir().unwrap();
    let truth = write_semicolon_campaign(dir.path(), 5);
    assert_eq!(truth.len(), 8);
    check_truth(&truth);
    let bytes = std::fs::read(dir.path().join("campaign.csv")).unwrap();
    assert_eq!(&bytes[..3], &[0xEF, 0xBB, 0xBF]);
    let text = std::str::from_utf8(&bytes[3..]).unwrap();
    assert!(text.ends_with("\r\n"));
    assert_eq!(text.matches('\n').count(), text.matches("\r\n").count());
    let mut lines = text.split("\r\n").filter(|l| !l.is_empty());
    assert_eq!(lines.next().unwrap(), "Zeit [s];Fn [kN];Ft/N;v [m/min]");
    let rows: Vec<[f64; 4]> = lines
        .map(|l| {
            assert!(!l.contains('.'), "{l}");
            let f: Vec<f64> = l
                .split(';')
                .map(|x| x.replace(',', ".").parse().unwrap())
                .collect();
            [f[0], f[1], f[2], f[3]]
        })
        .collect();
    assert!(rows.len() > 15_000);
    // lifted at the start and at the end
    for r in rows.iter().take(400).chain(rows.iter().rev().take(400)) {
        assert!(
            r[1].abs() < 0.006 && r[3] == 0.0 && r[2].abs() < 2.5,
            "{r:?}"
        );
    }
    // dwells: pin 1 starts at 1.0 + 0.3 + 0.2 = 1.5 s, steps 3.25 s each, pin length 15.25 s incl. the 1 s lifted after it
    for t in &truth {
        let pin_start = 1.0 + (t.pin - 1) as f64 * 15.25;
        let t0 = pin_start + 0.5 + (t.step - 1) as f64 * 3.25 + 0.25 + 0.5;
        let t1 = t0 + 2.4;
        let (mut st, mut sn) = (0.0, 0.0);
        for r in rows.iter().filter(|r| r[0] >= t0 && r[0] < t1) {
            st += r[2];
            sn += r[1] * 1000.0;
            assert!((r[3] / t.velocity_m_per_min - 1.0).abs() < 0.02);
        }
        assert!((st / sn - t.mu_true).abs() < 0.001, "{t:?}: {}", st / sn);
    }
}

#[test]
fn tab_is_deterministic() {
    assert_deterministic(write_tab_per_step);
}

#[test]
fn tab_layout_and_values() {
    let dir = tempfile::tempdir().unwrap();
    let truth = write_tab_per_step(dir.path(), 9);
    assert_eq!(truth.len(), 4);
    check_truth(&truth);
    assert_eq!(TAB_SAMPLE_RATE_HZ, 1000.0);
    for (k, t) in truth.iter().enumerate() {
        assert_eq!(t.file, dir.path().join(format!("step_{:02}.txt", k + 1)));
        let text = std::fs::read_to_string(&t.file).unwrap();
        let mut lines = text.lines();
        assert_eq!(lines.next().unwrap(), "Fz_kN\tFx_N\tSpeed_mm/s");
        let rows: Vec<Vec<f64>> = lines
            .map(|l| l.split('\t').map(|x| x.parse().unwrap()).collect())
            .collect();
        assert_eq!(rows.len(), 3601);
        assert_eq!(rows[0][2], 0.0);
        assert_eq!(rows.last().unwrap()[2], 0.0);
        let dwell = &rows[1000..3300];
        let mu = dwell.iter().map(|r| r[1]).sum::<f64>()
            / dwell.iter().map(|r| r[0] * 1000.0).sum::<f64>();
        assert!((mu - t.mu_true).abs() < 0.001);
        let speed = dwell.iter().map(|r| r[2]).sum::<f64>() / dwell.len() as f64;
        assert!((speed * 0.06 / t.velocity_m_per_min - 1.0).abs() < 0.005);
    }
}

#[test]
fn xlsx_is_deterministic() {
    assert_deterministic(write_xlsx_workbook);
}

#[test]
fn xlsx_layout_and_values() {
    use calamine::{open_workbook, Data, Reader, Xlsx};
    let dir = tempfile::tempdir().unwrap();
    let truth = write_xlsx_workbook(dir.path(), 11);
    assert_eq!(truth.len(), 4);
    check_truth(&truth);
    let mut wb: Xlsx<_> = open_workbook(dir.path().join("tribo.xlsx")).unwrap();
    assert_eq!(wb.sheet_names(), vec!["Data".to_string()]);
    let range = wb.worksheet_range("Data").unwrap();
    assert_eq!(range.start(), Some((0, 0)));
    assert_eq!(
        range.get_value((0, 0)),
        Some(&Data::String("Pin-on-disk test".into()))
    );
    assert!(matches!(range.get_value((1, 0)), None | Some(Data::Empty)));
    let header: Vec<String> = (0..4)
        .map(|c| range.get_value((2, c)).unwrap().to_string())
        .collect();
    assert_eq!(
        header,
        [
            "Time (s)",
            "Normal Force (N)",
            "Friction Force (N)",
            "Sliding Speed (m/s)"
        ]
    );
    let num = |r: u32, c: u32| match range.get_value((r, c)) {
        Some(Data::Float(x)) => *x,
        Some(Data::Int(x)) => *x as f64,
        other => panic!("({r},{c}): {other:?}"),
    };
    let rows = range.height() as u32 - 3;
    assert_eq!(rows, (23.5 * 200.0) as u32);
    assert!((num(4, 0) - 0.005).abs() < 1e-12);
    for t in &truth {
        let t0 = 0.5 + (t.step - 1) as f64 * 5.5 + 0.5 + 0.5;
        let (mut st, mut sn) = (0.0, 0.0);
        for r in 0..rows {
            let time = num(3 + r, 0);
            if time >= t0 && time < t0 + 4.4 {
                sn += num(3 + r, 1);
                st += num(3 + r, 2);
                assert!((num(3 + r, 3) * 60.0 / t.velocity_m_per_min - 1.0).abs() < 0.02);
            }
        }
        assert!((st / sn - t.mu_true).abs() < 0.001, "{t:?}");
    }
}

/// Writes every generator's output with seed 1 to `$SUPPORT_DUMP_DIR` for manual inspection:
/// `SUPPORT_DUMP_DIR=/tmp/x cargo test -p greybox-tribo --test support_selfcheck -- --ignored`.
#[test]
#[ignore]
fn dump_samples() {
    let Some(dir) = std::env::var_os("SUPPORT_DUMP_DIR") else {
        return;
    };
    let dir = Path::new(&dir);
    let mut truth = LatheRig::new(1).write_campaign(&dir.join("rig2"), &default_pins());
    truth.extend(write_rotary_export(&dir.join("rotary"), 1));
    truth.extend(write_semicolon_campaign(&dir.join("semicolon"), 1));
    truth.extend(write_tab_per_step(&dir.join("tab"), 1));
    truth.extend(write_xlsx_workbook(&dir.join("xlsx"), 1));
    for t in &truth {
        println!(
            "{} pin {} step {} F {} N v {:.4} m/min mu {:.5}",
            t.file.display(),
            t.pin,
            t.step,
            t.normal_force_n,
            t.velocity_m_per_min,
            t.mu_true
        );
    }
}
