//! Readers never panic: thousands of seeded mutations (byte flips, truncations, insertions)
//! of valid files go through every reader of external data; each must return Ok or Err.

use greybox_contact::wear::read_height_map_from;
use greybox_recording::csv_recording::read_csv_recording_from;
use greybox_recording::tdms::{recording_from_tdms, TdmsFile};
use greybox_recording::ChannelMap;
use greybox_tribo::gcode::parse_program;
use greybox_tribo::plan::PlanSpec;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn mutate(base: &[u8], rng: &mut ChaCha8Rng) -> Vec<u8> {
    let mut b = base.to_vec();
    for _ in 0..rng.gen_range(1..6) {
        if b.is_empty() {
            break;
        }
        match rng.gen_range(0..5) {
            0 => {
                let i = rng.gen_range(0..b.len());
                b[i] = rng.gen();
            }
            1 => b.truncate(rng.gen_range(0..b.len())),
            2 => {
                let i = rng.gen_range(0..b.len());
                let chunk: Vec<u8> = (0..rng.gen_range(1..16)).map(|_| rng.gen()).collect();
                b.splice(i..i, chunk);
            }
            3 => {
                let i = rng.gen_range(0..b.len());
                let j = (i + rng.gen_range(1..64)).min(b.len());
                b.drain(i..j);
            }
            _ => {
                // overwrite 4 or 8 bytes with extreme integers (TDMS lengths, counts)
                let i = rng.gen_range(0..b.len());
                let v: u64 = [u64::MAX, 0, 1 << 31, 1 << 40, rng.gen()][rng.gen_range(0..5)];
                for (k, byte) in v
                    .to_le_bytes()
                    .iter()
                    .enumerate()
                    .take(if rng.gen_bool(0.5) { 4 } else { 8 })
                {
                    if i + k < b.len() {
                        b[i + k] = *byte;
                    }
                }
            }
        }
    }
    b
}

fn small_recording() -> greybox_recording::Recording {
    // one pin, two velocity steps
    let plan = PlanSpec {
        track_radius_mm: Some(100.0),
        normal_force_count: greybox_tribo::plan::PinCount::of(1),
        normal_force_max_n: 150.0,
        velocity_count: greybox_tribo::plan::VelocityCount::of(2),
        velocity_max_m_per_min: 31.5,
        ..Default::default()
    }
    .build()
    .unwrap();
    greybox_tribo::synth::SynthConfig::default()
        .simulate_pin(&plan, &greybox_contact::hertz::PinContact::default(), 1)
        .unwrap()
}

#[test]
fn tdms_reader_survives_mutations() {
    // a small multi-segment file, so that mutations hit lead-ins and metadata often
    let data: Vec<f64> = (0..50).map(|i| i as f64).collect();
    let chans = [
        greybox_recording::tdms::WriteChannel {
            name: "normal_force_N",
            unit: "N",
            data: &data,
        },
        greybox_recording::tdms::WriteChannel {
            name: "tangential_force_N",
            unit: "N",
            data: &data,
        },
    ];
    let mut base = Vec::new();
    greybox_recording::tdms::write_tdms(&mut base, "Tribometer", &chans, 1e-3, 0.0, 20).unwrap();
    let map = ChannelMap {
        radial: None,
        trigger: None,
        ..Default::default()
    };
    assert!(recording_from_tdms(TdmsFile::parse(&base, "ok.tdms").unwrap(), &map).is_ok());
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    for _ in 0..20_000 {
        let m = mutate(&base, &mut rng);
        if let Ok(f) = TdmsFile::parse(&m, "m.tdms") {
            let _ = recording_from_tdms(f, &map);
        }
    }
}

#[test]
fn csv_readers_survive_mutations() {
    let rec = small_recording();
    let mut buf = Vec::new();
    greybox_recording::csv_recording::write_csv_recording_to(&mut buf, &rec).unwrap();
    let base = &buf[..buf.len().min(3000)];
    let mut rng = ChaCha8Rng::seed_from_u64(2);
    for _ in 0..3000 {
        let m = mutate(base, &mut rng);
        let _ = read_csv_recording_from(m.as_slice(), "m.csv", &ChannelMap::default());
    }
    let mut map = String::from("x_mm,y_mm,z_um\n");
    for j in 0..5 {
        for i in 0..5 {
            map.push_str(&format!(
                "{},{},{}\n",
                i as f64 * 0.01,
                j as f64 * 0.01,
                (i * j) as f64 * 0.1
            ));
        }
    }
    for _ in 0..2000 {
        let m = mutate(map.as_bytes(), &mut rng);
        if let Ok(h) = read_height_map_from(m.as_slice(), "m.csv") {
            let _ = greybox_contact::wear::analyze_height_map(
                &h,
                greybox_contact::wear::Reference::Plane,
            );
        }
    }
    let ds = "pin,step,normal_force_N,normal_force_measured_N,sliding_velocity_m_per_min,hertz_pressure_MPa,pressure_convention,cof_apparent,cof_apparent_std,n_samples,plateau_start_s,plateau_end_s,cof_trend_per_s,stationary,flags\n1,1,150,150,20,914,article-eq7,0.4,0.01,400,2.1,2.5,0.0,true,\n";
    for _ in 0..2000 {
        let m = mutate(ds.as_bytes(), &mut rng);
        let _ = greybox_core::dataset::FrictionDataset::read_csv_from(m.as_slice(), "m.csv");
    }
}

#[test]
fn gcode_parser_survives_mutations() {
    let plan = PlanSpec {
        track_radius_mm: Some(100.0),
        ..Default::default()
    }
    .build()
    .unwrap();
    let prog = greybox_tribo::gcode::write_program(&plan, 1);
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    for _ in 0..3000 {
        let m = mutate(prog.as_bytes(), &mut rng);
        let text = String::from_utf8_lossy(&m);
        if let Ok(p) = parse_program(&text, "m.nc") {
            let _ = greybox_tribo::gcode::plan_spec_from_programs(&[p]).map(|s| s.build());
        }
    }
}

mod support;

/// Every reader of foreign layouts (sniffed text, spreadsheets) and the plan-free
/// identification behind them return Ok or an error that names the file.
#[test]
fn foreign_layout_readers_survive_mutations() {
    use greybox_recording::recording_from_table;
    use greybox_recording::text_table::parse_text_table;
    use greybox_recording::xlsx_table::parse_spreadsheet;
    use greybox_tribo::campaign::{identify_recordings, Campaign};
    let dir = tempfile::tempdir().unwrap();
    let rotary = support::exports::write_rotary_export(&dir.path().join("a"), 1);
    let campaign = support::exports::write_semicolon_campaign(&dir.path().join("b"), 1);
    let tab = support::exports::write_tab_per_step(&dir.path().join("c"), 1);
    let xlsx = support::exports::write_xlsx_workbook(&dir.path().join("d"), 1);
    let head_tail = |path: &std::path::Path| {
        let b = std::fs::read(path).unwrap();
        let mut v = b[..b.len().min(2500)].to_vec();
        v.extend_from_slice(&b[b.len().saturating_sub(600)..]);
        v
    };
    let bases = [
        head_tail(&rotary[0].file),
        head_tail(&campaign[0].file),
        head_tail(&tab[0].file),
    ];
    let contact = greybox_contact::hertz::PinContact::default();
    let cfg = greybox_tribo::config::IdentifyConfig::default();
    let campaign_inputs = Campaign {
        expected: None,
        plan: None,
        contact: &contact,
        cfg: &cfg,
        track_radius_mm: &[5.0],
    };
    let map = ChannelMap {
        sample_rate_hz: Some(1000.0),
        ..Default::default()
    };
    let mut rng = ChaCha8Rng::seed_from_u64(4);
    for base in &bases {
        for _ in 0..1500 {
            let m = mutate(base, &mut rng);
            let r = parse_text_table(&m, "m.csv", &map.reader.text_options())
                .and_then(|t| recording_from_table(t, &map));
            match r {
                Ok(rec) => {
                    let _ = identify_recordings(std::slice::from_ref(&rec), &campaign_inputs);
                }
                Err(e) => assert!(e.to_string().starts_with("m.csv"), "{e}"),
            }
        }
    }
    let book = std::fs::read(&xlsx[0].file).unwrap();
    for _ in 0..300 {
        let m = mutate(&book, &mut rng);
        match parse_spreadsheet(&m, "m.xlsx", None) {
            Ok(t) => {
                let _ = recording_from_table(t, &ChannelMap::default());
            }
            Err(e) => assert!(e.to_string().starts_with("m.xlsx"), "{e}"),
        }
    }
}
