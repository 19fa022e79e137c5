//! `greybox characterize`: FRF of the rig from impact-hammer recordings, and the article's
//! dynamics check against the campaign's spindle excitation.

use crate::cmd_plan::{study_input, PlanFlags};
use crate::output::{print_json, stage_out_dir, Table};
use anyhow::{bail, Context, Result};
use greybox_core::atomic::write_string_atomic;
use greybox_core::plot::{lines, Line};
use greybox_tribo::frf::{
    estimate, excitation_check, ExcitationCheck, Frf, ImpactConfig, ImpactRecording, Resonance,
};
use greybox_tribo::readers::RecordingFormat;
use greybox_tribo::tdms::{PropValue, TdmsFile};
use serde::Serialize;
use std::path::{Path, PathBuf};

#[derive(clap::Args, Debug)]
pub struct Args {
    /// Hammer recording PATH[@LOAD_N] (CSV or TDMS; repeatable). Recordings with the same load
    /// are averaged together; different loads are compared.
    #[arg(long = "recording", required = true)]
    pub recordings: Vec<String>,
    /// Hammer force channel (N).
    #[arg(long, default_value = "hammer_N")]
    pub hammer: String,
    /// Response channel (accelerometer or dynamometer output).
    #[arg(long, default_value = "response")]
    pub response: String,
    /// CSV time column (seconds); without it, --sample-rate-hz.
    #[arg(long, default_value = "time_s")]
    pub time: String,
    /// Sample rate when the CSV has no time column, Hz.
    #[arg(long = "sample-rate-hz")]
    pub sample_rate_hz: Option<f64>,
    /// TDMS group of the channels.
    #[arg(long, default_value = "Hammer")]
    pub tdms_group: String,
    /// Record length per impact, s.
    #[arg(long = "block-s")]
    pub block_s: Option<f64>,
    /// Exponential window value at the record end (1 = none).
    #[arg(long)]
    pub exponential_end: Option<f64>,
    /// Harmonics of the spindle rotation frequency in the excitation check.
    #[arg(long, default_value_t = 3)]
    pub harmonics: usize,
    /// The campaign plan for the excitation check (study TOML and/or plan flags).
    #[command(flatten)]
    pub plan: PlanFlags,
    /// Output directory: frf_<load>.csv, plots, report.json.
    #[arg(long, default_value = "characterize-out")]
    pub out: PathBuf,
    /// Replace an existing, non-empty output directory (swapped out whole once this run is
    /// complete; without it such a directory is refused).
    #[arg(long)]
    pub force: bool,
    #[arg(long)]
    pub json: bool,
}

#[derive(Serialize)]
pub struct LoadResult {
    pub load_n: Option<f64>,
    pub impacts_used: usize,
    pub rejected: Vec<greybox_tribo::frf::Rejected>,
    pub usable_max_hz: f64,
    pub resonances: Vec<Resonance>,
}

#[derive(Serialize)]
pub struct CharacterizeReport {
    pub loads: Vec<LoadResult>,
    pub excitation_check: Option<ExcitationCheck>,
    pub files: Vec<String>,
}

fn read_channels(path: &Path, a: &Args) -> Result<ImpactRecording> {
    let src = path.display().to_string();
    match RecordingFormat::of_path(path) {
        Some(RecordingFormat::Tdms) => {
            let f = TdmsFile::read(path)?;
            let ch = |name: &str| {
                f.channel(&a.tdms_group, name).with_context(|| {
                    format!("{src}: no channel '{name}' in group '{}'", a.tdms_group)
                })
            };
            let h = ch(&a.hammer)?;
            let r = ch(&a.response)?;
            let dt = h
                .property("wf_increment")
                .and_then(PropValue::as_f64)
                .or(a.sample_rate_hz.map(|f| 1.0 / f));
            let fs = 1.0
                / dt.with_context(|| {
                    format!("{src}: no wf_increment property; give --sample-rate-hz")
                })?;
            Ok(ImpactRecording {
                source: src,
                sample_rate_hz: fs,
                hammer: h.data.clone(),
                response: r.data.clone(),
            })
        }
        Some(RecordingFormat::Spreadsheet) => {
            anyhow::bail!("{src}: impact recordings are read from CSV or TDMS files")
        }
        Some(RecordingFormat::Csv) => {
            let mut rdr =
                csv::Reader::from_path(path).with_context(|| format!("cannot read {src}"))?;
            let header = rdr.headers()?.clone();
            let col = |name: &str| header.iter().position(|h| h.trim() == name);
            let hi = col(&a.hammer).with_context(|| format!("{src}: no column '{}'", a.hammer))?;
            let ri =
                col(&a.response).with_context(|| format!("{src}: no column '{}'", a.response))?;
            let ti = col(&a.time);
            let (mut t, mut h, mut r) = (Vec::new(), Vec::new(), Vec::new());
            for (k, rec) in rdr.records().enumerate() {
                let rec =
                    rec.with_context(|| format!("{src}: malformed CSV near line {}", k + 2))?;
                let line = k as u64 + 2;
                let num = |i: usize, name: &str| {
                    greybox_core::csvutil::parse_f64(&rec[i], &src, line, name)
                };
                h.push(num(hi, &a.hammer)?);
                r.push(num(ri, &a.response)?);
                if let Some(i) = ti {
                    t.push(num(i, &a.time)?);
                }
            }
            let fs = if t.len() > 1 {
                let dt = (t[t.len() - 1] - t[0]) / (t.len() - 1) as f64;
                if let Some(k) = t
                    .windows(2)
                    .position(|w| ((w[1] - w[0]) - dt).abs() > 1e-3 * dt)
                {
                    bail!(
                        "{src}, line {}: the time column is not uniformly sampled",
                        k + 3
                    );
                }
                1.0 / dt
            } else {
                a.sample_rate_hz.with_context(|| {
                    format!("{src}: no '{}' column; give --sample-rate-hz", a.time)
                })?
            };
            Ok(ImpactRecording {
                source: src,
                sample_rate_hz: fs,
                hammer: h,
                response: r,
            })
        }
        None => bail!("{src}: expected a .csv or .tdms recording"),
    }
}

fn parse_recording(spec: &str) -> Result<(PathBuf, Option<f64>)> {
    match spec.rsplit_once('@') {
        Some((p, load)) => {
            Ok((
                PathBuf::from(p),
                Some(load.parse().with_context(|| {
                    format!("--recording '{spec}': '{load}' is not a load in N")
                })?),
            ))
        }
        None => Ok((PathBuf::from(spec), None)),
    }
}

fn write_frf_csv(path: &Path, frf: &Frf) -> Result<()> {
    let mut s = String::from("frequency_Hz,h1_magnitude,h1_phase_deg,h2_magnitude,coherence\n");
    for k in 0..frf.frequency_hz.len() {
        let h1 = frf.h1[k].0;
        s.push_str(&format!(
            "{},{},{},{},{}\n",
            frf.frequency_hz[k],
            h1.norm(),
            h1.arg().to_degrees(),
            frf.h2[k].0.norm(),
            frf.coherence[k]
        ));
    }
    write_string_atomic(path, &s)?;
    Ok(())
}

/// Run the characterization; returns the report.
pub fn characterize(a: &Args) -> Result<CharacterizeReport> {
    let mut cfg = ImpactConfig::default();
    if let Some(b) = a.block_s {
        cfg.block_s = b;
    }
    if let Some(e) = a.exponential_end {
        cfg.exponential_end = e;
    }
    let mut groups: Vec<(Option<f64>, Vec<ImpactRecording>)> = Vec::new();
    let specs: Vec<PathBuf> = a
        .recordings
        .iter()
        .map(|s| parse_recording(s).map(|r| r.0))
        .collect::<Result<_>>()?;
    let mut inputs: Vec<(&str, &Path)> = specs
        .iter()
        .map(|p| ("--recordings", p.as_path()))
        .collect();
    inputs.extend(study_input(&a.plan));
    for spec in &a.recordings {
        let (path, load) = parse_recording(spec)?;
        let rec = read_channels(&path, a)?;
        match groups.iter_mut().find(|g| g.0 == load) {
            Some(g) => g.1.push(rec),
            None => groups.push((load, vec![rec])),
        }
    }
    let staged = stage_out_dir(&a.out, a.force, &inputs)?;
    let out = staged.path();
    let mut loads = Vec::new();
    let mut files = Vec::new();
    let mut all_res = Vec::new();
    let mut series_f = Vec::new();
    for (load, recs) in &groups {
        let frf = estimate(recs, &cfg)?;
        let res = frf.resonances(&cfg, 5);
        let tag = load
            .map(|l| format!("{l:.0}N"))
            .unwrap_or_else(|| "all".into());
        let p = out.join(format!("frf_{tag}.csv"));
        write_frf_csv(&p, &frf)?;
        files.push(staged.shown(&p).display().to_string());
        all_res.extend(res.iter().copied());
        series_f.push((tag, frf.clone()));
        loads.push(LoadResult {
            load_n: *load,
            impacts_used: frf.impacts_used,
            rejected: frf.rejected.clone(),
            usable_max_hz: frf.usable_max_hz,
            resonances: res,
        });
    }
    let plan = a.plan.study().ok().and_then(|s| s.plan.build().ok());
    let check = match &plan {
        Some(p) => Some(excitation_check(&all_res, p, a.harmonics)?),
        None => None,
    };
    // plots: |H1| (log) with the excitation band, and coherence
    let colours = ["#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e"];
    let fmax = series_f
        .iter()
        .map(|(_, f)| f.usable_max_hz)
        .fold(0.0, f64::max);
    let cut = |f: &Frf| {
        f.frequency_hz
            .iter()
            .position(|x| *x > fmax)
            .unwrap_or(f.frequency_hz.len())
    };
    let mags: Vec<Vec<f64>> = series_f
        .iter()
        .map(|(_, f)| f.h1[..cut(f)].iter().map(|h| h.0.norm()).collect())
        .collect();
    let band = check
        .as_ref()
        .map(|c| vec![(0.0, c.max_excitation_hz, "spindle excitation")])
        .unwrap_or_default();
    let mag_lines: Vec<Line> = series_f
        .iter()
        .zip(&mags)
        .enumerate()
        .map(|(i, ((tag, f), m))| Line {
            label: tag,
            colour: colours[i % 5],
            x: &f.frequency_hz[..cut(f)],
            y: m,
        })
        .collect();
    let svg = lines(
        "FRF |H1| (impact hammer)",
        "frequency [Hz]",
        "|H1|",
        &mag_lines,
        true,
        &band,
    );
    let p = out.join("frf_magnitude.svg");
    write_string_atomic(&p, &svg)?;
    files.push(staged.shown(&p).display().to_string());
    let coh_lines: Vec<Line> = series_f
        .iter()
        .enumerate()
        .map(|(i, (tag, f))| Line {
            label: tag,
            colour: colours[i % 5],
            x: &f.frequency_hz[..cut(f)],
            y: &f.coherence[..cut(f)],
        })
        .collect();
    let svg = lines(
        "coherence",
        "frequency [Hz]",
        "coherence",
        &coh_lines,
        false,
        &band,
    );
    let p = out.join("coherence.svg");
    write_string_atomic(&p, &svg)?;
    files.push(staged.shown(&p).display().to_string());
    let report = CharacterizeReport {
        loads,
        excitation_check: check,
        files,
    };
    let p = out.join("report.json");
    write_string_atomic(&p, &serde_json::to_string_pretty(&report)?)?;
    crate::output::provenance(&inputs)?.write_into(out)?;
    staged.commit()?;
    Ok(report)
}

pub fn print_report(r: &CharacterizeReport) {
    let mut t = Table::new(&[
        "load [N]",
        "impacts",
        "rejected",
        "f1 [Hz]",
        "zeta1",
        "|H1| at f1",
        "f2 [Hz]",
    ]);
    for l in &r.loads {
        let first = l
            .resonances
            .iter()
            .min_by(|a, b| a.frequency_hz.total_cmp(&b.frequency_hz));
        let second = l
            .resonances
            .iter()
            .map(|x| x.frequency_hz)
            .filter(|f| Some(*f) != first.map(|x| x.frequency_hz))
            .fold(f64::INFINITY, f64::min);
        t.row(vec![
            l.load_n
                .map(|x| format!("{x:.0}"))
                .unwrap_or_else(|| "-".into()),
            l.impacts_used.to_string(),
            l.rejected.len().to_string(),
            first
                .map(|x| format!("{:.1}", x.frequency_hz))
                .unwrap_or_else(|| "-".into()),
            first
                .map(|x| format!("{:.4}", x.damping))
                .unwrap_or_else(|| "-".into()),
            first
                .map(|x| format!("{:.3e}", x.magnitude))
                .unwrap_or_else(|| "-".into()),
            if second.is_finite() {
                format!("{second:.1}")
            } else {
                "-".into()
            },
        ]);
    }
    print!("{}", t.render());
    match &r.excitation_check {
        Some(c) => println!(
            "dynamics check: first resonance {:.1} Hz vs highest spindle excitation {:.2} Hz ({} harmonics): ratio {:.1} -> {}",
            c.first_resonance_hz,
            c.max_excitation_hz,
            c.harmonics,
            c.ratio,
            if c.pass { "PASS (at least an order of magnitude)" } else { "FAIL (less than an order of magnitude)" }
        ),
        None => println!("dynamics check: no plan given (--study or --track-radius-mm)"),
    }
}

pub fn run(a: Args) -> Result<()> {
    let r = characterize(&a)?;
    if a.json {
        return print_json(&r);
    }
    print_report(&r);
    println!("wrote {}", r.files.join(", "));
    Ok(())
}
