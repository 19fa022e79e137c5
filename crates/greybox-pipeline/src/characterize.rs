//! Rig dynamics: the FRF from impact-hammer recordings, and the article's check that the
//! rig's first resonance lies an order of magnitude above the campaign's spindle excitation.

use crate::output::{provenance, stage_out_dir};
use anyhow::{bail, Context, Result};
use greybox_core::atomic::write_string_atomic;
use greybox_core::plot::{lines, Line};
use greybox_recording::readers::RecordingFormat;
use greybox_recording::tdms::{PropValue, TdmsFile};
use greybox_tribo::frf::{
    estimate, excitation_check, ExcitationCheck, Frf, ImpactConfig, ImpactRecording, Resonance,
};
use greybox_tribo::plan::Plan;
use serde::Serialize;
use std::path::{Path, PathBuf};

/// The plan the excitation check runs against, and whether its velocities were stated or
/// are the article's (a track radius alone was given).
#[derive(Debug, Clone)]
pub struct ExcitationPlan {
    pub plan: Plan,
    pub velocities_stated: bool,
}

/// The article's excitation check and what it rests on: the plan's fastest step (its spindle
/// speed is the check's `max_spindle_rpm`).
#[derive(Debug, Clone, Serialize)]
pub struct PlannedExcitationCheck {
    #[serde(flatten)]
    pub check: ExcitationCheck,
    /// The plan's highest sliding velocity, m/min.
    pub velocity_max_m_per_min: f64,
    /// The track radius it is turned on, mm.
    pub track_radius_mm: f64,
    /// Where the velocities come from: "stated", or "the article's plan (no velocity
    /// stated)" when only a track radius was given.
    pub velocities: String,
}

impl PlannedExcitationCheck {
    /// The check of `resonances` against `p`'s fastest step.
    fn of(resonances: &[Resonance], p: &ExcitationPlan, harmonics: usize) -> Result<Self> {
        let check = excitation_check(resonances, &p.plan, harmonics)?;
        let steps = p.plan.steps.iter();
        let fastest_m_s = steps.map(|s| s.sliding_velocity_m_s).fold(0.0, f64::max);
        let velocities = match p.velocities_stated {
            true => "stated",
            false => "the article's plan (no velocity stated)",
        };
        Ok(PlannedExcitationCheck {
            check,
            velocity_max_m_per_min: fastest_m_s * 60.0,
            track_radius_mm: p.plan.spec.track_radius_m()? * 1e3,
            velocities: velocities.into(),
        })
    }
}

/// Where the hammer and response signals are in a recording.
#[derive(Debug, Clone)]
pub struct ImpactChannels {
    /// Hammer force channel (N).
    pub hammer: String,
    /// Response channel (accelerometer or dynamometer output).
    pub response: String,
    /// CSV time column (seconds); without it, `sample_rate_hz`.
    pub time: String,
    /// Sample rate when the CSV has no time column (or TDMS has no wf_increment), Hz.
    pub sample_rate_hz: Option<f64>,
    /// TDMS group of the channels.
    pub tdms_group: String,
}

/// The hammer force channel's name when none is given.
pub const DEFAULT_HAMMER_CHANNEL: &str = "hammer_N";
/// The response channel's name when none is given.
pub const DEFAULT_RESPONSE_CHANNEL: &str = "response";
/// The CSV time column's name when none is given.
pub const DEFAULT_TIME_COLUMN: &str = "time_s";
/// The TDMS group of the channels when none is given.
pub const DEFAULT_TDMS_GROUP: &str = "Hammer";
/// The output directory when none is given.
pub const DEFAULT_CHARACTERIZE_DIR: &str = "characterize-out";
/// Harmonics of the spindle frequency checked when none are given.
pub const DEFAULT_HARMONICS: u64 = 3;

impl Default for ImpactChannels {
    fn default() -> Self {
        ImpactChannels {
            hammer: DEFAULT_HAMMER_CHANNEL.into(),
            response: DEFAULT_RESPONSE_CHANNEL.into(),
            time: DEFAULT_TIME_COLUMN.into(),
            sample_rate_hz: None,
            tdms_group: DEFAULT_TDMS_GROUP.into(),
        }
    }
}

/// Harmonics of the spindle frequency checked against the rig's resonances.
pub type Harmonics = greybox_core::count::Count<1, 100>;

/// Options of [`characterize`].
#[derive(Debug, Clone)]
pub struct CharacterizeOptions {
    /// Hammer recordings (CSV or TDMS) with their normal load, N. Recordings with the same
    /// load are averaged together; different loads are compared.
    pub recordings: Vec<(PathBuf, Option<f64>)>,
    pub channels: ImpactChannels,
    /// Record length, window and resonance picking.
    pub impact: ImpactConfig,
    /// Harmonics of the spindle rotation frequency in the excitation check.
    pub harmonics: Harmonics,
    /// The campaign plan for the excitation check (none: no check).
    pub plan: Option<ExcitationPlan>,
    /// The study file the plan came from, recorded in the provenance.
    pub study: Option<PathBuf>,
    /// Output directory: `frf_<load>.csv`, plots, report.json.
    pub out: PathBuf,
    /// Replace an existing, non-empty `out`.
    pub force: bool,
}

/// The FRF of one load.
#[derive(Debug, Clone, Serialize)]
pub struct LoadResult {
    pub load_n: Option<f64>,
    pub impacts_used: usize,
    pub rejected: Vec<greybox_tribo::frf::Rejected>,
    pub usable_max_hz: f64,
    pub resonances: Vec<Resonance>,
}

/// The characterisation: per load, and the check against the campaign's excitation.
#[derive(Debug, Clone, Serialize)]
pub struct CharacterizeReport {
    pub loads: Vec<LoadResult>,
    pub excitation_check: Option<PlannedExcitationCheck>,
    pub files: Vec<String>,
}

/// Read the hammer and response channels of one impact recording (CSV or TDMS).
pub fn read_channels(path: &Path, a: &ImpactChannels) -> Result<ImpactRecording> {
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
                    format!(
                        "{src}: no wf_increment property; give the sample rate (sample_rate_hz)"
                    )
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
            let mut rdr = greybox_core::input::csv_reader(
                path,
                "impact recording",
                greybox_core::budget::Cap::RecordingBytes,
                &csv::ReaderBuilder::new(),
            )?;
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
                if !(dt > 0.0) {
                    bail!(
                        "{src}: the time column '{}' must increase (it goes from {} to {} s)",
                        a.time,
                        t[0],
                        t[t.len() - 1]
                    );
                }
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
                    format!(
                        "{src}: no '{}' column; give the sample rate (sample_rate_hz)",
                        a.time
                    )
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
pub fn characterize(a: &CharacterizeOptions) -> Result<CharacterizeReport> {
    let cfg = &a.impact;
    let mut groups: Vec<(Option<f64>, Vec<ImpactRecording>)> = Vec::new();
    let mut inputs: Vec<(&str, &Path)> = a
        .recordings
        .iter()
        .map(|(p, _)| ("recordings", p.as_path()))
        .collect();
    if let Some(s) = &a.study {
        inputs.push(("study", s.as_path()));
    }
    for (path, load) in &a.recordings {
        let rec = read_channels(path, &a.channels)?;
        match groups.iter_mut().find(|g| g.0 == *load) {
            Some(g) => g.1.push(rec),
            None => groups.push((*load, vec![rec])),
        }
    }
    let staged = stage_out_dir(&a.out, a.force, &inputs)?;
    let out = staged.path();
    let mut loads = Vec::new();
    let mut files = Vec::new();
    let mut all_res = Vec::new();
    let mut series_f = Vec::new();
    for (load, recs) in &groups {
        let frf = estimate(recs, cfg)?;
        let res = frf.resonances(cfg, 5);
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
    let check = match &a.plan {
        Some(p) => Some(PlannedExcitationCheck::of(&all_res, p, a.harmonics.get())?),
        None => None,
    };
    for p in plot_frfs(&series_f, check.as_ref().map(|c| &c.check), out)? {
        files.push(staged.shown(&p).display().to_string());
    }
    let report = CharacterizeReport {
        loads,
        excitation_check: check,
        files,
    };
    let p = out.join("report.json");
    write_string_atomic(&p, &serde_json::to_string_pretty(&report)?)?;
    provenance(&inputs)?.write_into(out)?;
    staged.commit()?;
    Ok(report)
}

/// The plots of the FRFs up to the highest usable frequency: |H1| (log) with the spindle's
/// excitation band, and the coherence; returns the files written into `out`.
fn plot_frfs(
    series_f: &[(String, Frf)],
    check: Option<&ExcitationCheck>,
    out: &Path,
) -> Result<Vec<std::path::PathBuf>> {
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
    let magnitude = lines(
        "FRF |H1| (impact hammer)",
        "frequency (Hz)",
        "|H1| (response unit per N)",
        &mag_lines,
        true,
        &band,
    );
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
    let coherence = lines(
        "coherence",
        "frequency (Hz)",
        "coherence (-)",
        &coh_lines,
        false,
        &band,
    );
    let mut files = Vec::new();
    for (name, svg) in [
        ("frf_magnitude.svg", magnitude),
        ("coherence.svg", coherence),
    ] {
        let p = out.join(name);
        write_string_atomic(&p, &svg)?;
        files.push(p);
    }
    Ok(files)
}
