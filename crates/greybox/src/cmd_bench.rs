//! `greybox bench`: measured speed of the things that must be fast.

use crate::output::print_json;
use crate::study::{Study, DEMO_STUDY};
use anyhow::{bail, Result};
use greybox_tribo::csv_recording::{read_csv_recording, write_csv_recording};
use greybox_tribo::recording::{ChannelMap, Recording};
use greybox_tribo::tdms::{read_tdms_recording, write_tdms_recording};
use serde::Serialize;
use std::path::PathBuf;
use std::time::Instant;

#[derive(clap::Subcommand, Debug)]
pub enum Bench {
    /// Ingestion speed of CSV and TDMS recordings (MB/s) on a large synthetic recording.
    Ingest {
        /// Minimum CSV file size, MB.
        #[arg(long = "size-mb", default_value_t = 100.0)]
        size_mb: f64,
        /// Timed repetitions per format (the best and the median are reported).
        #[arg(long, default_value_t = 3)]
        repeats: usize,
        /// Directory for the files (default: a temporary directory, removed afterwards).
        #[arg(long)]
        dir: Option<PathBuf>,
        /// Print JSON.
        #[arg(long)]
        json: bool,
    },
    /// Evaluations per second of a law (raw) and of its surrogate table, one core.
    Surrogate {
        /// Law, model or table file.
        #[arg(long)]
        law: PathBuf,
        /// Surrogate grid points per axis (pressure, velocity).
        #[arg(long, default_value_t = 201)]
        points: usize,
        /// Timed evaluations per law.
        #[arg(long, default_value_t = 20_000_000)]
        calls: usize,
    },
    /// SPH solver speed on a cutting set-up (default: the bundled ETH IWF Ti6Al4V case):
    /// particle-steps per second per core and the wall time of the cut.
    Sph {
        #[arg(long, default_value = "examples/iwf-ti64-cut.toml")]
        config: PathBuf,
        /// Fraction of the configured cut to run (the full-cut time is extrapolated if < 1).
        #[arg(long, default_value_t = 1.0)]
        fraction: f64,
        #[arg(long)]
        json: bool,
    },
    /// Single-point prediction latency of model files (the simulator's hot path).
    Predict {
        /// Model files from `greybox fit`.
        #[arg(long, num_args = 1.., required = true)]
        models: Vec<PathBuf>,
        /// Timed calls per model.
        #[arg(long, default_value_t = 200_000)]
        calls: usize,
        /// Print JSON.
        #[arg(long)]
        json: bool,
    },
}

#[derive(Serialize)]
struct PredictLatency {
    model: String,
    family: String,
    calls: usize,
    ns_per_call: f64,
}

/// Time `predict_one` on points spread over the model's training domain.
fn predict_latency(path: &std::path::Path, calls: usize) -> Result<PredictLatency> {
    use greybox_learn::Predictor;
    let m = greybox_learn::modelfile::ModelFile::load(path)?;
    let n_points = 1024;
    let points: Vec<Vec<f64>> = (0..n_points)
        .map(|k| {
            m.training_domain
                .iter()
                .enumerate()
                .map(|(j, r)| {
                    // deterministic low-discrepancy spread (golden-ratio sequence per feature)
                    let u = ((k as f64 + 1.0) * (0.618_033_988_75 + 0.1 * j as f64)).fract();
                    r.min + u * (r.max - r.min)
                })
                .collect()
        })
        .collect();
    let mut sink = 0.0;
    for p in &points {
        sink += m.model.predict_one(p);
    }
    let t = Instant::now();
    for k in 0..calls {
        sink += m
            .model
            .predict_one(std::hint::black_box(&points[k % n_points]));
    }
    let ns = t.elapsed().as_secs_f64() * 1e9 / calls as f64;
    std::hint::black_box(sink);
    Ok(PredictLatency {
        model: path.display().to_string(),
        family: m.family.name().into(),
        calls,
        ns_per_call: ns,
    })
}

#[derive(clap::Args, Debug)]
pub struct Args {
    #[command(subcommand)]
    pub bench: Bench,
}

#[derive(Serialize)]
struct IngestResult {
    format: String,
    /// The file that was read (kept when `--dir` is given).
    path: String,
    file_mb: f64,
    samples: usize,
    best_s: f64,
    median_s: f64,
    best_mb_per_s: f64,
    best_msamples_per_s: f64,
    /// For a text dialect: the delimiter, decimal mark and lines above the header, so a peer
    /// reader can be told what greybox sniffs.
    #[serde(skip_serializing_if = "Option::is_none")]
    sep: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    decimal: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    skiprows: Option<usize>,
}

/// A rig-export dialect of the benchmark recording: two metadata lines above the header,
/// semicolons, decimal commas, units in parentheses, a trailing delimiter and CRLF.
fn write_export_dialect(path: &std::path::Path, rec: &Recording) -> Result<()> {
    greybox_core::atomic::write_atomic(path, |w| {
        w.write_all(b"Instrument: virtual rig;Serial 1\r\nExported: 2026-11-22 10:00;\r\n")?;
        w.write_all(b"Time (s);Fz (N);Fx (N);Fy (N);Trigger (V);\r\n")?;
        let mut line = String::with_capacity(96);
        for i in 0..rec.len() {
            line.clear();
            for v in [
                rec.time_s[i],
                rec.normal_n[i],
                rec.tangential_n[i],
                rec.radial_n.as_ref().map_or(0.0, |r| r[i]),
                rec.trigger_v.as_ref().map_or(0.0, |t| t[i]),
            ] {
                use std::fmt::Write as _;
                let _ = write!(line, "{v:.4};");
            }
            line.push_str("\r\n");
            w.write_all(line.replace('.', ",").as_bytes())?;
        }
        Ok(())
    })?;
    Ok(())
}

/// The demo campaign's pins back to back, repeated until the CSV would reach `size_mb`.
fn big_recording(size_mb: f64) -> Result<Recording> {
    let study = Study::parse(DEMO_STUDY, "demo")?;
    let plan = study.plan.build()?;
    let pins: Vec<Recording> = (1..=plan.pins.len() as u32)
        .map(|p| study.synth.simulate_pin(&plan, &study.contact, p))
        .collect::<Result<_, _>>()?;
    const BYTES_PER_ROW: f64 = 42.0; // measured on synth output: "12.3450,150.1234,…"
    let rows_needed = (size_mb * 1e6 / BYTES_PER_ROW).ceil() as usize;
    let mut big = Recording {
        source: "bench".into(),
        time_s: Vec::with_capacity(rows_needed),
        normal_n: Vec::with_capacity(rows_needed),
        tangential_n: Vec::with_capacity(rows_needed),
        radial_n: Some(Vec::with_capacity(rows_needed)),
        trigger_v: Some(Vec::with_capacity(rows_needed)),
        ..Recording::new("", Vec::new(), Vec::new(), Vec::new())
    };
    let dt = 1e-3;
    while big.len() < rows_needed {
        for p in &pins {
            for i in 0..p.len() {
                big.time_s.push(big.time_s.len() as f64 * dt);
                big.normal_n.push(p.normal_n[i]);
                big.tangential_n.push(p.tangential_n[i]);
                big.radial_n
                    .as_mut()
                    .expect("radial")
                    .push(p.radial_n.as_ref().expect("radial")[i]);
                big.trigger_v
                    .as_mut()
                    .expect("trigger")
                    .push(p.trigger_v.as_ref().expect("trigger")[i]);
            }
        }
    }
    Ok(big)
}

fn time_reads(f: impl Fn() -> Result<usize>, repeats: usize) -> Result<(Vec<f64>, usize)> {
    let mut times = Vec::new();
    let mut n = 0;
    for _ in 0..repeats.max(1) {
        let t = Instant::now();
        n = f()?;
        times.push(t.elapsed().as_secs_f64());
    }
    times.sort_by(f64::total_cmp);
    Ok((times, n))
}

/// Time `law.mu` over a cycle of states, ns per call.
fn time_law(
    law: &dyn greybox_core::FrictionLaw,
    states: &[greybox_core::ContactState],
    calls: usize,
) -> f64 {
    let mut sink = 0.0;
    let t = Instant::now();
    for k in 0..calls {
        sink += law.mu(std::hint::black_box(&states[k % states.len()]));
    }
    std::hint::black_box(sink);
    t.elapsed().as_secs_f64() * 1e9 / calls as f64
}

fn bench_surrogate(path: &std::path::Path, points: usize, calls: usize) -> Result<()> {
    use greybox_friction::table::{Axis, TabulatedLaw};
    let law = greybox_friction::spec::load_law(path)?;
    let d = law
        .domain()
        .ok_or_else(|| anyhow::anyhow!("the law has no domain to tabulate over"))?;
    let mut table = TabulatedLaw::bake(
        law.as_ref(),
        Axis::new(d.pressure_pa.min, d.pressure_pa.max, points)?,
        Axis::new(
            d.sliding_velocity_m_s.min,
            d.sliding_velocity_m_s.max,
            points,
        )?,
        None,
    );
    let dev = table.check(law.as_ref(), 100_000, 1);
    let states: Vec<greybox_core::ContactState> = (0..4096)
        .map(|k| {
            let u = ((k as f64 + 1.0) * 0.618_033_988_75).fract();
            let w = ((k as f64 + 1.0) * 0.754_877_666_2).fract();
            greybox_core::ContactState::new(
                d.pressure_pa.min + u * (d.pressure_pa.max - d.pressure_pa.min),
                d.sliding_velocity_m_s.min
                    + w * (d.sliding_velocity_m_s.max - d.sliding_velocity_m_s.min),
            )
        })
        .collect();
    let raw_calls = (calls / 100).max(10_000);
    let raw = time_law(law.as_ref(), &states, raw_calls);
    let tab = time_law(&table, &states, calls);
    println!(
        "law:       {:8.1} ns per call, {:.3e} evaluations/s/core ({})",
        raw,
        1e9 / raw,
        law.name()
    );
    println!("surrogate: {:8.1} ns per call, {:.3e} evaluations/s/core ({points} x {points} grid, max deviation {dev:.2e})", tab, 1e9 / tab);
    Ok(())
}

fn bench_sph(config: &std::path::Path, fraction: f64, json: bool) -> Result<()> {
    let case = crate::cmd_simulate::read_cutting_setup(config)?;
    let dir = tempfile::tempdir()?;
    let out = crate::cmd_simulate::Output {
        out: dir.path().join("sph"),
        vtk_every: 0,
        checkpoint_every: 0,
        resume: None,
        force: false,
        json: false,
    };
    let s = crate::cmd_simulate::run_cut(&case, fraction, &out)?;
    if json {
        return print_json(&s);
    }
    // A run that stopped at a steady force is complete; otherwise extrapolate the fraction.
    let (full, how) = match s.steady_from_mm {
        Some(mm) if case.setup.steady.stop_when_steady => (
            s.wall_s,
            format!(", stopped at a steady force that set in at {mm:.3} mm"),
        ),
        _ if fraction < 1.0 => (s.wall_s / fraction, ", extrapolated".to_string()),
        _ => (s.wall_s, String::new()),
    };
    println!(
        "SPH cutting benchmark ({}): {} particles, {} steps, dt {:.3e} s, mass scaling {}",
        config.display(),
        s.particles,
        s.steps,
        s.dt_s,
        s.mass_scaling
    );
    println!(
        "  {:.3e} particle-steps/s on {} threads = {:.3e} per core; {:.3} mm of cut in {:.1} s (full run: {:.1} s{how})",
        s.particle_steps_per_s,
        s.threads,
        s.particle_steps_per_s_per_core,
        s.simulated_cut_length_mm,
        s.wall_s,
        full
    );
    if config.ends_with("iwf-ti64-cut.toml") {
        println!(
            "  reference: ETH IWF mfree_iwf-ul-cut-refine ~1.7e5 particle-steps/s/core, 59 min for the cut on one core"
        );
    }
    println!(
        "  cutting force {:.1} N/mm, feed force {:.1} N/mm",
        s.cutting_force_n_per_mm, s.feed_force_n_per_mm
    );
    Ok(())
}

pub fn run(a: Args) -> Result<()> {
    match a.bench {
        Bench::Sph {
            config,
            fraction,
            json,
        } => bench_sph(&config, fraction, json),
        Bench::Surrogate { law, points, calls } => {
            bench_surrogate(&law, points.max(2), calls.max(1))
        }
        Bench::Predict {
            models,
            calls,
            json,
        } => {
            let rows = models
                .iter()
                .map(|m| predict_latency(m, calls.max(1)))
                .collect::<Result<Vec<_>>>()?;
            if json {
                return print_json(&rows);
            }
            for r in &rows {
                println!(
                    "predict {:>18}: {:8.1} ns per point ({} calls, {})",
                    r.family, r.ns_per_call, r.calls, r.model
                );
            }
            Ok(())
        }
        Bench::Ingest {
            size_mb,
            repeats,
            dir,
            json,
        } => {
            if size_mb.is_nan() || size_mb <= 0.0 {
                bail!("--size-mb must be positive");
            }
            let tmp = tempfile::tempdir()?;
            let dir = dir.unwrap_or_else(|| tmp.path().to_path_buf());
            let rec = big_recording(size_mb)?;
            let csv = dir.join("bench.csv");
            let tdms = dir.join("bench.tdms");
            let export = dir.join("bench-export.csv");
            write_csv_recording(&csv, &rec)?;
            write_tdms_recording(&tdms, &rec, "Tribometer")?;
            write_export_dialect(&export, &rec)?;
            let map = ChannelMap::default();
            let mut results = Vec::new();
            for (name, path) in [("csv", &csv), ("tdms", &tdms), ("csv-export", &export)] {
                let bytes = std::fs::metadata(path)?.len() as f64;
                let (times, n) = time_reads(
                    || {
                        let r = match name {
                            "csv" => read_csv_recording(path, &map)?,
                            "tdms" => read_tdms_recording(path, &map)?,
                            _ => greybox_tribo::readers::read_recording(path, &map)?,
                        };
                        Ok(r.len())
                    },
                    repeats,
                )?;
                let export_dialect = name == "csv-export";
                results.push(IngestResult {
                    format: name.into(),
                    path: path.display().to_string(),
                    file_mb: bytes / 1e6,
                    samples: n,
                    best_s: times[0],
                    median_s: times[times.len() / 2],
                    best_mb_per_s: bytes / 1e6 / times[0],
                    best_msamples_per_s: n as f64 / 1e6 / times[0],
                    sep: export_dialect.then(|| ";".into()),
                    decimal: export_dialect.then(|| ",".into()),
                    skiprows: export_dialect.then_some(2),
                });
            }
            if json {
                return print_json(&results);
            }
            for r in &results {
                println!(
                    "ingest {:>4}: {:8.1} MB, {} samples x 5 channels: best {:.3} s (median {:.3} s) -> {:7.1} MB/s, {:.2} Msamples/s",
                    r.format, r.file_mb, r.samples, r.best_s, r.median_s, r.best_mb_per_s, r.best_msamples_per_s
                );
            }
            Ok(())
        }
    }
}
