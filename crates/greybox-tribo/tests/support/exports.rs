//! Export layouts of four other tribometers. Each writer takes `(dir, seed)`, creates `dir` if
//! needed, writes its file(s) and returns the ground truth (one [`TruthStep`] per (pin, step),
//! in the order run). Offsets are zero; noise is small (a good identification gets within
//! 0.002 of `mu_true`); μ follows [`mu_law`](super::mu_law) at the instantaneous speed, so it
//! moves through the short ramps and the friction force is ~0 at rest. Ramps are cosine S-curves.
//!
//! ## a. [`write_rotary_export`] → `dir/rotary.csv` (ball-on-disk vendor CSV, ONE pin)
//!
//! LF line ends, comma-separated. Exact layout:
//! ```text
//! Instrument: RT-1000,Serial 1234
//! Test: 2026-05-03 10:12,Operator: X
//! Step, Time (s), DAQ.Fz (N), DAQ.Fx (N), Velocity (rpm), COF,
//! 1,0.0,10.0123,0.0021,0.00,0.00021,
//! …                                  (500 rows per step, 5 steps)
//! End of data
//! Total time: 250 s
//! ```
//! * two metadata lines (they contain commas), then the header: column names after the first
//!   have ONE leading space (`" Time (s)"`, `" DAQ.Fz (N)"`, …) and the header ends with a
//!   trailing comma; every data line also ends with a trailing comma (so a plain CSV split
//!   yields a 7th, empty field). Data fields have no spaces.
//! * `Step`: integer 1…5. `Time (s)`: restarts at 0.0 at every step, 1 decimal, 10 Hz,
//!   0.0 … 49.9 (500 rows per step). `DAQ.Fz (N)`: normal force (10 N nominal, 4 decimals).
//!   `DAQ.Fx (N)`: friction force, positive (4 decimals). `Velocity (rpm)`: measured disk
//!   speed, rpm (2 decimals). `COF`: Fx/Fz as computed by the instrument (5 decimals).
//! * then two footer lines `End of data` and `Total time: 250 s`.
//! * each step starts from rest: 2.0 s S-ramp 0 → rpm, and a settling transient (μ 15 % high,
//!   decaying with τ = 0.5 s), so the first ~3 s of every step are not steady.
//! * steps: rpm [`ROTARY_RPM`] = 300, 400, 500, 600, 700 on track radii [`ROTARY_RADII_MM`]
//!   = 5, 6, 7, 8, 9 mm. `velocity_m_per_min` = 2π·R[m]·n[rpm] (≈ 9.42, 15.08, 21.99,
//!   30.16, 39.58 m/min); load 10 N; pin 1, steps 1…5.
//!
//! ## b. [`write_semicolon_campaign`] → `dir/campaign.csv` (ONE file, whole campaign)
//!
//! UTF-8 BOM (EF BB BF) at the start, CRLF line ends, `;` delimiter, decimal COMMA in every
//! number (`0,200123`, `-0,412`), one header line, no preamble:
//! `Zeit [s];Fn [kN];Ft/N;v [m/min]`
//! * `Zeit [s]`: time from 0, 500 Hz, 3 decimals. `Fn [kN]`: normal force in **kN**,
//!   6 decimals. `Ft/N`: friction force in N, positive, 3 decimals. `v [m/min]`: measured
//!   sliding velocity in m/min (0.2 % noise), 3 decimals.
//! * 2 pins: pin 1 at 200 N with 30, 60, 90, 120 m/min; pin 2 at 600 N with 50, 100, 150,
//!   200 m/min ([`SEMICOLON_PINS`]).
//! * timeline: 1 s lifted (Fn ≈ 0 noise only, v = 0), then per pin: load rise 0.3 s (S),
//!   0.2 s loaded at rest, for each velocity a 0.25 s ramp from the previous speed + 3.0 s
//!   dwell, ramp down 0.25 s to 0, 0.2 s at rest, unload 0.3 s, then 1 s lifted (between the
//!   pins and after the last one).
//!
//! ## c. [`write_tab_per_step`] → `dir/step_01.txt` … `dir/step_04.txt` (one file per step)
//!
//! Tab-separated, LF line ends, one header line, NO time column (sample rate
//! [`TAB_SAMPLE_RATE_HZ`] = 1000 Hz): `Fz_kN\tFx_N\tSpeed_mm/s`
//! * `Fz_kN`: normal force in **kN** (6 decimals), `Fx_N`: friction force in N, positive
//!   (3 decimals), `Speed_mm/s`: measured sliding speed in **mm/s** (2 decimals).
//! * one pin at 400 N (loaded throughout), speeds 500, 1000, 1500, 2000 mm/s
//!   ([`TAB_SPEEDS_MM_PER_S`]; = 30, 60, 90, 120 m/min).
//! * each file: first row at speed 0, 0.4 s S-ramp up, 3.0 s dwell, 0.2 s S-ramp down; the
//!   last row is at speed 0 again (3601 data rows + header; row i is at t = i / 1000 s).
//!
//! ## d. [`write_xlsx_workbook`] → `dir/tribo.xlsx`
//!
//! One worksheet named `Data`:
//! * row 1: `A1` = string `Pin-on-disk test`; row 2: empty;
//! * row 3: header strings `Time (s)` | `Normal Force (N)` | `Friction Force (N)` |
//!   `Sliding Speed (m/s)` in A3:D3;
//! * rows 4…: numeric cells (time from 0 at 200 Hz; forces in N, positive; speed in **m/s**).
//! * one pin at 50 N, 0.2, 0.4, 0.6, 0.8 m/s ([`XLSX_SPEEDS_M_PER_S`]; = 12, 24, 36, 48
//!   m/min): 0.5 s loaded at rest, per step 0.5 s ramp + 5.0 s dwell, 0.5 s ramp down, 0.5 s
//!   at rest. Document creation time is fixed, so the bytes are deterministic.

use super::{fixed, mu_law, stream_rng, Schedule, TruthStep};
use rand::Rng;
use rand_distr::{Distribution, StandardNormal};
use std::f64::consts::PI;
use std::fmt::Write as _;
use std::path::Path;

/// Wear-track radius of each step of the rotary export, mm.
pub const ROTARY_RADII_MM: [f64; 5] = [5.0, 6.0, 7.0, 8.0, 9.0];
/// Disk speed of each step of the rotary export, rpm.
pub const ROTARY_RPM: [f64; 5] = [300.0, 400.0, 500.0, 600.0, 700.0];
/// Load of the rotary export, N.
pub const ROTARY_LOAD_N: f64 = 10.0;
/// Logging rate of the rotary export, Hz.
pub const ROTARY_SAMPLE_RATE_HZ: f64 = 10.0;
/// Duration of each rotary step, s.
pub const ROTARY_STEP_S: f64 = 50.0;

/// Pins of the semicolon campaign: (load N, velocities m/min in order run).
pub const SEMICOLON_PINS: [(f64, [f64; 4]); 2] = [
    (200.0, [30.0, 60.0, 90.0, 120.0]),
    (600.0, [50.0, 100.0, 150.0, 200.0]),
];
/// Sample rate of the semicolon campaign, Hz.
pub const SEMICOLON_SAMPLE_RATE_HZ: f64 = 500.0;

/// Sample rate of the tab-separated per-step files (they have no time column), Hz.
pub const TAB_SAMPLE_RATE_HZ: f64 = 1000.0;
/// Load of the tab-separated per-step files, N.
pub const TAB_LOAD_N: f64 = 400.0;
/// Sliding speed of each tab-separated step file, mm/s.
pub const TAB_SPEEDS_MM_PER_S: [f64; 4] = [500.0, 1000.0, 1500.0, 2000.0];

/// Load of the xlsx workbook, N.
pub const XLSX_LOAD_N: f64 = 50.0;
/// Sliding speeds of the xlsx workbook, m/s.
pub const XLSX_SPEEDS_M_PER_S: [f64; 4] = [0.2, 0.4, 0.6, 0.8];
/// Sample rate of the xlsx workbook, Hz.
pub const XLSX_SAMPLE_RATE_HZ: f64 = 200.0;

fn gauss(rng: &mut impl Rng) -> f64 {
    StandardNormal.sample(rng)
}

fn write_file(path: &Path, bytes: &[u8]) {
    std::fs::write(path, bytes).unwrap_or_else(|e| panic!("write {}: {e}", path.display()));
}

/// a. Rotary ball-on-disk vendor CSV, `dir/rotary.csv` (see the module docs).
pub fn write_rotary_export(dir: &Path, seed: u64) -> Vec<TruthStep> {
    std::fs::create_dir_all(dir).expect("create output directory");
    let path = dir.join("rotary.csv");
    let mut rng = stream_rng(seed, 0xA1);
    let mut s = String::new();
    s.push_str("Instrument: RT-1000,Serial 1234\n");
    s.push_str("Test: 2026-05-03 10:12,Operator: X\n");
    s.push_str("Step, Time (s), DAQ.Fz (N), DAQ.Fx (N), Velocity (rpm), COF,\n");
    let rows = (ROTARY_STEP_S * ROTARY_SAMPLE_RATE_HZ).round() as usize;
    let mut truth = Vec::new();
    for (k, (&rpm, &r_mm)) in ROTARY_RPM.iter().zip(ROTARY_RADII_MM.iter()).enumerate() {
        let radius_m = r_mm / 1000.0;
        let v_nominal = 2.0 * PI * radius_m * rpm;
        let mut speed = Schedule::new(0.0);
        speed.ramp_to(2.0, rpm);
        for i in 0..rows {
            let t = i as f64 / ROTARY_SAMPLE_RATE_HZ;
            let n = speed.value(t);
            let v = 2.0 * PI * radius_m * n;
            let settle = 1.0 + 0.15 * (-t / 0.5).exp();
            let mu = mu_law(ROTARY_LOAD_N, v) * settle;
            let f_n = ROTARY_LOAD_N * (1.0 + 0.002 * (2.0 * PI * n / 60.0 * t).sin());
            let fz = f_n + 0.02 * gauss(&mut rng);
            let fx = mu * f_n + 0.01 * gauss(&mut rng);
            let n_meas = n * (1.0 + 0.002 * gauss(&mut rng));
            let fz_s = fixed(fz, 4);
            let fx_s = fixed(fx, 4);
            let cof = fx_s.parse::<f64>().unwrap() / fz_s.parse::<f64>().unwrap();
            writeln!(
                s,
                "{},{},{},{},{},{},",
                k + 1,
                fixed(t, 1),
                fz_s,
                fx_s,
                fixed(n_meas, 2),
                fixed(cof, 5)
            )
            .unwrap();
        }
        truth.push(TruthStep {
            pin: 1,
            step: k as u32 + 1,
            normal_force_n: ROTARY_LOAD_N,
            velocity_m_per_min: v_nominal,
            mu_true: mu_law(ROTARY_LOAD_N, v_nominal),
            file: path.clone(),
        });
    }
    s.push_str("End of data\n");
    writeln!(
        s,
        "Total time: {} s",
        (ROTARY_STEP_S * ROTARY_RPM.len() as f64).round()
    )
    .unwrap();
    write_file(&path, s.as_bytes());
    truth
}

/// b. Whole campaign in one German-locale CSV, `dir/campaign.csv` (see the module docs).
pub fn write_semicolon_campaign(dir: &Path, seed: u64) -> Vec<TruthStep> {
    std::fs::create_dir_all(dir).expect("create output directory");
    let path = dir.join("campaign.csv");
    let mut rng = stream_rng(seed, 0xB2);

    // Load (N) and speed (m/min) schedules over the whole file.
    let mut load = Schedule::new(0.0);
    let mut speed = Schedule::new(0.0);
    let both_hold = |load: &mut Schedule, speed: &mut Schedule, d: f64| {
        load.hold(d);
        speed.hold(d);
    };
    both_hold(&mut load, &mut speed, 1.0);
    let mut truth = Vec::new();
    for (p, (l, vels)) in SEMICOLON_PINS.iter().enumerate() {
        load.ramp_to(0.3, *l);
        speed.hold(0.3);
        both_hold(&mut load, &mut speed, 0.2);
        for (k, &v) in vels.iter().enumerate() {
            speed.ramp_to(0.25, v).hold(3.0);
            load.hold(3.25);
            truth.push(TruthStep {
                pin: p as u32 + 1,
                step: k as u32 + 1,
                normal_force_n: *l,
                velocity_m_per_min: v,
                mu_true: mu_law(*l, v),
                file: path.clone(),
            });
        }
        speed.ramp_to(0.25, 0.0);
        load.hold(0.25);
        both_hold(&mut load, &mut speed, 0.2);
        load.ramp_to(0.3, 0.0);
        speed.hold(0.3);
        both_hold(&mut load, &mut speed, 1.0);
    }
    let n = (load.duration() * SEMICOLON_SAMPLE_RATE_HZ).round() as usize;
    let comma = |x: String| x.replace('.', ",");
    let mut s = String::from("\u{feff}Zeit [s];Fn [kN];Ft/N;v [m/min]\r\n");
    for i in 0..n {
        let t = i as f64 / SEMICOLON_SAMPLE_RATE_HZ;
        let l = load.value(t);
        let v = speed.value(t);
        let f_n = l;
        let f_t = mu_law(l, v) * f_n;
        let fn_meas = f_n + 1.0 * gauss(&mut rng);
        let ft_meas = f_t + 0.4 * gauss(&mut rng);
        let v_meas = v * (1.0 + 0.002 * gauss(&mut rng));
        write!(
            s,
            "{};{};{};{}\r\n",
            comma(fixed(t, 3)),
            comma(fixed(fn_meas / 1000.0, 6)),
            comma(fixed(ft_meas, 3)),
            comma(fixed(v_meas, 3))
        )
        .unwrap();
    }
    write_file(&path, s.as_bytes());
    truth
}

/// c. Tab-separated files without time column, one per step, `dir/step_NN.txt` (see the
/// module docs).
pub fn write_tab_per_step(dir: &Path, seed: u64) -> Vec<TruthStep> {
    std::fs::create_dir_all(dir).expect("create output directory");
    let mut rng = stream_rng(seed, 0xC3);
    let mut truth = Vec::new();
    for (k, &speed_mm_s) in TAB_SPEEDS_MM_PER_S.iter().enumerate() {
        let path = dir.join(format!("step_{:02}.txt", k + 1));
        let mut speed = Schedule::new(0.0);
        speed.ramp_to(0.4, speed_mm_s).hold(3.0).ramp_to(0.2, 0.0);
        let n = (speed.duration() * TAB_SAMPLE_RATE_HZ).round() as usize + 1;
        let mut s = String::from("Fz_kN\tFx_N\tSpeed_mm/s\n");
        for i in 0..n {
            let t = i as f64 / TAB_SAMPLE_RATE_HZ;
            let u = speed.value(t);
            let v = u * 0.06; // mm/s → m/min
            let f_n = TAB_LOAD_N;
            let f_t = mu_law(TAB_LOAD_N, v) * f_n;
            let fz = f_n + 1.5 * gauss(&mut rng);
            let fx = f_t + 0.6 * gauss(&mut rng);
            let u_meas = u * (1.0 + 0.002 * gauss(&mut rng));
            writeln!(
                s,
                "{}\t{}\t{}",
                fixed(fz / 1000.0, 6),
                fixed(fx, 3),
                fixed(u_meas, 2)
            )
            .unwrap();
        }
        write_file(&path, s.as_bytes());
        let v = speed_mm_s * 0.06;
        truth.push(TruthStep {
            pin: 1,
            step: k as u32 + 1,
            normal_force_n: TAB_LOAD_N,
            velocity_m_per_min: v,
            mu_true: mu_law(TAB_LOAD_N, v),
            file: path,
        });
    }
    truth
}

/// d. Excel workbook `dir/tribo.xlsx`, sheet `Data` (see the module docs).
pub fn write_xlsx_workbook(dir: &Path, seed: u64) -> Vec<TruthStep> {
    use rust_xlsxwriter::{DocProperties, ExcelDateTime, Workbook};
    std::fs::create_dir_all(dir).expect("create output directory");
    let path = dir.join("tribo.xlsx");
    let mut rng = stream_rng(seed, 0xD4);

    let mut speed = Schedule::new(0.0);
    speed.hold(0.5);
    let mut truth = Vec::new();
    for (k, &u) in XLSX_SPEEDS_M_PER_S.iter().enumerate() {
        speed.ramp_to(0.5, u).hold(5.0);
        let v = u * 60.0;
        truth.push(TruthStep {
            pin: 1,
            step: k as u32 + 1,
            normal_force_n: XLSX_LOAD_N,
            velocity_m_per_min: v,
            mu_true: mu_law(XLSX_LOAD_N, v),
            file: path.clone(),
        });
    }
    speed.ramp_to(0.5, 0.0).hold(0.5);
    let n = (speed.duration() * XLSX_SAMPLE_RATE_HZ).round() as usize;

    let mut workbook = Workbook::new();
    let created = ExcelDateTime::from_ymd(2026, 5, 3).expect("date");
    workbook.set_properties(&DocProperties::new().set_creation_datetime(&created));
    let sheet = workbook.add_worksheet();
    sheet.set_name("Data").expect("sheet name");
    sheet.write_string(0, 0, "Pin-on-disk test").unwrap();
    let header = [
        "Time (s)",
        "Normal Force (N)",
        "Friction Force (N)",
        "Sliding Speed (m/s)",
    ];
    for (c, h) in header.iter().enumerate() {
        sheet.write_string(2, c as u16, *h).unwrap();
    }
    let round = |x: f64, d: i32| {
        let f = 10f64.powi(d);
        let r = (x * f).round() / f;
        if r == 0.0 {
            0.0
        } else {
            r
        }
    };
    for i in 0..n {
        let t = i as f64 / XLSX_SAMPLE_RATE_HZ;
        let u = speed.value(t);
        let f_n = XLSX_LOAD_N;
        let f_t = mu_law(XLSX_LOAD_N, u * 60.0) * f_n;
        let fz = f_n + 0.15 * gauss(&mut rng);
        let fx = f_t + 0.08 * gauss(&mut rng);
        let u_meas = u * (1.0 + 0.002 * gauss(&mut rng));
        let row = 3 + i as u32;
        sheet.write_number(row, 0, round(t, 3)).unwrap();
        sheet.write_number(row, 1, round(fz, 4)).unwrap();
        sheet.write_number(row, 2, round(fx, 4)).unwrap();
        sheet.write_number(row, 3, round(u_meas, 5)).unwrap();
    }
    workbook.save(&path).expect("save xlsx");
    truth
}
