//! Measured speed of what must be fast: recording ingestion, prediction latency, law and
//! surrogate-table evaluation, the SPH solver.

use crate::simulate::{read_cutting_setup, run_cut, CutCase, CutSummary, RunOutput};
use crate::study::{Study, DEMO_STUDY};
use anyhow::{bail, Result};
use greybox_recording::csv_recording::{read_csv_recording, write_csv_recording};
use greybox_recording::tdms::{read_tdms_recording, write_tdms_recording};
use greybox_recording::{ChannelMap, Recording};
use serde::Serialize;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Run the cut of the set-up `config` (a `fraction` of its length) in a temporary
/// directory; the summary holds the solver's speed.
pub fn sph(config: &Path, fraction: f64) -> Result<(CutCase, CutSummary)> {
    let case = read_cutting_setup(config)?;
    let dir = tempfile::tempdir()?;
    let s = run_cut(&case, fraction, &RunOutput::to(dir.path().join("sph")))?;
    Ok((case, s))
}

/// Single-point prediction latency of a model file.
#[derive(Debug, Clone, Serialize)]
pub struct PredictLatency {
    pub model: String,
    pub family: String,
    pub calls: usize,
    pub ns_per_call: f64,
}

/// Time `predict_one` on points spread over the model's training domain.
pub fn predict_latency(path: &Path, calls: usize) -> Result<PredictLatency> {
    use greybox_model::Predictor;
    let m = greybox_model::modelfile::ModelFile::load(path)?;
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

/// Write a recording of at least `size_mb` MB as CSV, TDMS and a rig-export CSV dialect
/// into `dir` (a temporary directory when `None`) and time `repeats` reads of each.
pub fn ingest(size_mb: f64, repeats: usize, dir: Option<PathBuf>) -> Result<Vec<IngestResult>> {
    if size_mb.is_nan() || size_mb <= 0.0 {
        bail!("bench size_mb: must be positive");
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
                    _ => greybox_recording::readers::read_recording(path, &map)?,
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
    Ok(results)
}

/// Read speed of one recording format.
#[derive(Debug, Clone, Serialize)]
pub struct IngestResult {
    pub format: String,
    /// The file that was read (kept when `--dir` is given).
    pub path: String,
    pub file_mb: f64,
    pub samples: usize,
    pub best_s: f64,
    pub median_s: f64,
    pub best_mb_per_s: f64,
    pub best_msamples_per_s: f64,
    /// For a text dialect: the delimiter, decimal mark and lines above the header, so a peer
    /// reader can be told what greybox sniffs.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sep: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub decimal: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub skiprows: Option<usize>,
}

/// A rig-export dialect of the benchmark recording: two metadata lines above the header,
/// semicolons, decimal commas, units in parentheses, a trailing delimiter and CRLF.
fn write_export_dialect(path: &Path, rec: &Recording) -> Result<()> {
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

/// Time `law.mu` over a cycle of states: ns per call, the best of 10 rounds of `calls / 10`
/// (on a shared machine the best round is the one least disturbed by other processes).
fn time_law(
    law: &dyn greybox_core::FrictionLaw,
    states: &[greybox_core::ContactState],
    calls: usize,
) -> f64 {
    const ROUNDS: usize = 10;
    let per_round = (calls / ROUNDS).max(1);
    let mut sink = 0.0;
    let mut best = f64::INFINITY;
    for _ in 0..ROUNDS {
        let t = Instant::now();
        for k in 0..per_round {
            sink += law.mu(std::hint::black_box(&states[k % states.len()]));
        }
        best = best.min(t.elapsed().as_secs_f64() * 1e9 / per_round as f64);
    }
    std::hint::black_box(sink);
    best
}

/// Evaluation speed of a law and of its surrogate table, the table's size and deviation.
#[derive(Debug, Clone, Serialize)]
pub struct SurrogateSpeed {
    pub law: String,
    pub law_ns_per_call: f64,
    /// "exact", "adaptive" or "uniform".
    pub table_kind: String,
    pub table_ns_per_call: f64,
    /// Nodes (uniform, adaptive) or cells (exact) per axis: pressure, velocity, temperature.
    pub shape: [usize; 3],
    /// μ values stored (8 bytes each).
    pub values: usize,
    /// Seconds to build (and check) the table.
    pub build_s: f64,
    /// Largest |μ_table − μ_law| on fresh random states in the law's domain (exact tables:
    /// also on every line and its neighbouring floats).
    pub max_deviation: f64,
    pub check_points: usize,
    /// The adaptive table's tolerance.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tolerance: Option<f64>,
}

/// What [`surrogate`] builds and times.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurrogateBench {
    /// `None`: exact for tree ensembles, adaptive otherwise.
    pub kind: Option<greybox_friction::table_file::TableKind>,
    /// Uniform tables: points per axis.
    pub points: usize,
    /// Adaptive tables: max deviation on the refinement's check set.
    pub tolerance: f64,
    /// Most cells or nodes.
    pub max_size: usize,
    /// Timed table evaluations (the raw law gets a hundredth, at least 10 000).
    pub calls: usize,
}

/// Build the surrogate table of the law at `path` over its domain, check it on 100 000
/// fresh random states (seed 7; the build uses seed 1), and time the law and the table on
/// one core, through `&dyn FrictionLaw`, on 4096 states cycling over the domain (best of 10
/// rounds).
pub fn surrogate(path: &Path, o: &SurrogateBench) -> Result<SurrogateSpeed> {
    use greybox_friction::surrogate::{build, fresh_deviation, SurrogateOptions};
    let law = greybox_friction::spec::load_law(path)?;
    let d = law
        .domain()
        .ok_or_else(|| anyhow::anyhow!("the law has no domain to tabulate over"))?;
    let mut so = SurrogateOptions::over_domain(&d);
    so.kind = o.kind;
    so.uniform_points = [o.points, o.points, 21];
    so.tolerance = o.tolerance;
    so.max_size = o.max_size;
    let t0 = Instant::now();
    let table = build(law.as_ref(), &so)?;
    let build_s = t0.elapsed().as_secs_f64();
    let (dev, checked) = fresh_deviation(&table, law.as_ref(), &d, 100_000, 7);
    let t = d
        .temperature_k
        .map_or(greybox_core::ContactState::ROOM_TEMPERATURE_K, |r| {
            0.5 * (r.min + r.max)
        });
    let states: Vec<greybox_core::ContactState> = (0..4096)
        .map(|k| {
            let u = ((k as f64 + 1.0) * 0.618_033_988_75).fract();
            let w = ((k as f64 + 1.0) * 0.754_877_666_2).fract();
            greybox_core::ContactState {
                pressure_pa: d.pressure_pa.min + u * (d.pressure_pa.max - d.pressure_pa.min),
                sliding_velocity_m_s: d.sliding_velocity_m_s.min
                    + w * (d.sliding_velocity_m_s.max - d.sliding_velocity_m_s.min),
                temperature_k: t,
            }
        })
        .collect();
    let raw_calls = (o.calls / 100).max(10_000);
    let raw = time_law(law.as_ref(), &states, raw_calls);
    let tab = time_law(table.law(), &states, o.calls);
    Ok(SurrogateSpeed {
        law: law.name(),
        law_ns_per_call: raw,
        table_kind: table.kind().name().into(),
        table_ns_per_call: tab,
        shape: table.shape(),
        values: table.len(),
        build_s,
        max_deviation: dev,
        check_points: checked,
        tolerance: match &table {
            greybox_friction::table_file::AnyTable::Adaptive(a) => Some(a.tolerance),
            _ => None,
        },
    })
}
