//! `greybox identify`.

use crate::cmd_plan::PlanFlags;
use crate::output::{print_json, Table};
use crate::study::Study;
use anyhow::{bail, Context, Result};
use greybox_core::dataset::{FrictionDataset, PressureConvention};
use greybox_core::units;
use greybox_tribo::campaign::{
    expected_from_plan, match_segments, read_expected_steps, segment_recordings, Campaign,
    ExpectedStep, FileReport, Identification, MatchReport, Segmentation,
};
use greybox_tribo::identify::Alignment;
use greybox_tribo::plan::Plan;
use greybox_tribo::readers::{read_recording, RecordingFormat};
use greybox_tribo::recording::Recording;
use serde::Serialize;
use std::path::{Path, PathBuf};

#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum InFormat {
    /// Delimited text (.csv, .txt, .tsv, .dat, .asc, .prn).
    Csv,
    Tdms,
    /// Spreadsheets (.xlsx, .xlsm, .xls, .xlsb, .ods).
    Xlsx,
}

impl From<InFormat> for RecordingFormat {
    fn from(f: InFormat) -> Self {
        match f {
            InFormat::Csv => RecordingFormat::Csv,
            InFormat::Tdms => RecordingFormat::Tdms,
            InFormat::Xlsx => RecordingFormat::Spreadsheet,
        }
    }
}

#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum SegmentArg {
    /// Step column, else speed channel, else the plan's timing (greybox NC programs with a
    /// trigger), else the signals.
    Auto,
    /// The plan's nominal timing from the trigger edge (greybox's own NC programs).
    PlanTiming,
    /// Runs of one value of the step/segment column (--map step=NAME).
    StepColumn,
    /// Runs of constant speed in the speed channel (--map speed=NAME:UNIT).
    Speed,
    /// Change points of F_N and F_t/F_N (with a plan: as many steps per pin as it has).
    Signals,
}

impl From<SegmentArg> for Segmentation {
    fn from(s: SegmentArg) -> Self {
        match s {
            SegmentArg::Auto => Segmentation::Auto,
            SegmentArg::PlanTiming => Segmentation::PlanTiming,
            SegmentArg::StepColumn => Segmentation::StepColumn,
            SegmentArg::Speed => Segmentation::Speed,
            SegmentArg::Signals => Segmentation::Signals,
        }
    }
}

#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum AlignArg {
    Trigger,
    FirstPlateau,
}

#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum ConventionArg {
    TextbookMax,
    TextbookMean,
    ArticleEq7,
}

impl From<ConventionArg> for PressureConvention {
    fn from(c: ConventionArg) -> Self {
        match c {
            ConventionArg::TextbookMax => PressureConvention::TextbookMax,
            ConventionArg::TextbookMean => PressureConvention::TextbookMean,
            ConventionArg::ArticleEq7 => PressureConvention::ArticleEq7,
        }
    }
}

/// Segment and identify tribometer recordings from any rig.
///
/// Three ways to find the steps, tried in this order with `--segment auto`: a step/segment
/// column (`--map step=Step`), a speed channel (`--map speed="Velocity:rpm"`, with
/// `--track-radius-mm` or `--track-radii-mm` for rpm), or the signals themselves (change
/// points of F_N and F_t/F_N). greybox's own NC-program recordings (a trigger channel and a
/// `--study` plan) keep the plan-timed path. With a plan (`--study` with a [plan], or
/// `--plan-steps` listing pin, normal_force_N, sliding_velocity_m_per_min in run order),
/// segments are matched to its steps; without one, loads and velocities are the measured
/// ones. `--inspect` prints what was found per file and writes an SVG per recording.
#[derive(clap::Args, Debug)]
pub struct Args {
    #[command(flatten)]
    pub plan: PlanFlags,
    /// Recording files (CSV/TXT, XLSX/XLS/ODS, TDMS) or directories: a file per step, per
    /// pin or for the whole campaign. A directory gives its pinNN files when the plan's pins
    /// are all there, else every recording file in natural order.
    #[arg(long, num_args = 1.., required = true)]
    pub recordings: Vec<PathBuf>,
    /// Which files to pick from a directory (default: every supported format).
    #[arg(long, value_enum)]
    pub format: Option<InFormat>,
    /// How to find the steps.
    #[arg(long, value_enum)]
    pub segment: Option<SegmentArg>,
    /// Expected steps without timing: CSV with pin, normal_force_N,
    /// sliding_velocity_m_per_min [, step], in the order they were run.
    #[arg(long = "plan-steps")]
    pub plan_steps: Option<PathBuf>,
    /// Ignore the study's plan: loads and velocities from the recordings.
    #[arg(long = "no-plan")]
    pub no_plan: bool,
    /// How to align the plan with each recording (plan-timing path).
    #[arg(long, value_enum)]
    pub align: Option<AlignArg>,
    /// Time dropped after the spindle ramp, s.
    #[arg(long = "settle-s")]
    pub settle_s: Option<f64>,
    /// Channel mapping ROLE=NAME[:UNIT[:SCALE]], repeatable. Roles: time, normal, tangential,
    /// radial, trigger, step, speed, radius; an empty name (speed=) ignores a role. Unmapped
    /// roles are found by their usual names (Fz, Fx, Time, Step, Velocity, ...).
    #[arg(long = "map")]
    pub map: Vec<String>,
    /// 1-based header line of text files (default: found below any preamble).
    #[arg(long = "header-line")]
    pub header_line: Option<u64>,
    /// Sample rate of files without a time column, Hz.
    #[arg(long = "sample-rate-hz")]
    pub sample_rate_hz: Option<f64>,
    /// Track radius per segment for rpm speed channels, mm (comma-separated: one per segment
    /// of each file, or of the whole campaign).
    #[arg(long = "track-radii-mm", value_delimiter = ',')]
    pub track_radii_mm: Vec<f64>,
    /// Spreadsheet sheet to read (default: the first holding a table).
    #[arg(long)]
    pub sheet: Option<String>,
    /// TDMS group holding the channels.
    #[arg(long = "tdms-group")]
    pub tdms_group: Option<String>,
    /// Pressure convention written to the dataset (overrides [contact] convention).
    #[arg(long, value_enum)]
    pub convention: Option<ConventionArg>,
    /// Output dataset CSV.
    #[arg(long, default_value = "dataset.csv")]
    pub out: PathBuf,
    /// Ground truth CSV from `greybox synth`: report the identification error against it.
    #[arg(long)]
    pub truth: Option<PathBuf>,
    /// Print every plateau, not only the per-pin summary.
    #[arg(long)]
    pub all: bool,
    /// Print per file the mapped columns, sampling rate and every segment (start, end, load,
    /// speed, steady window, μ, flags), and write an SVG per recording with the steady
    /// windows shaded into --inspect-dir.
    #[arg(long)]
    pub inspect: bool,
    /// Where --inspect writes its SVGs (default: DATASET_inspect/ beside the dataset).
    #[arg(long = "inspect-dir")]
    pub inspect_dir: Option<PathBuf>,
    /// Print the result as JSON.
    #[arg(long)]
    pub json: bool,
}

/// Natural order: digit runs compare as numbers (`pin2` before `pin10`).
fn natural_key(name: &str) -> Vec<(u8, u64, String)> {
    let mut out = Vec::new();
    let mut chars = name.chars().peekable();
    while let Some(&c) = chars.peek() {
        if c.is_ascii_digit() {
            let mut n = String::new();
            while let Some(&d) = chars.peek().filter(|d| d.is_ascii_digit()) {
                n.push(d);
                chars.next();
            }
            out.push((0, n.parse().unwrap_or(u64::MAX), n));
        } else {
            let mut t = String::new();
            while let Some(&d) = chars.peek().filter(|d| !d.is_ascii_digit()) {
                t.push(d.to_ascii_lowercase());
                chars.next();
            }
            out.push((1, 0, t));
        }
    }
    out
}

/// Resolve the recording files: explicit files as given; a directory gives `pinNN.<ext>`
/// for every pin of the plan when they all exist, else every recording file in it (of
/// `format`, if given) in natural order.
pub fn recording_files(
    paths: &[PathBuf],
    format: Option<RecordingFormat>,
    pins: Option<usize>,
) -> Result<Vec<PathBuf>> {
    let mut files = Vec::new();
    for p in paths {
        if !p.is_dir() {
            files.push(p.clone());
            continue;
        }
        if let Some(pins) = pins {
            let ext = format.unwrap_or(RecordingFormat::Csv).extension();
            let named: Vec<PathBuf> = (1..=pins)
                .map(|k| p.join(format!("pin{k:02}.{ext}")))
                .collect();
            if named.iter().all(|f| f.is_file()) {
                files.extend(named);
                continue;
            }
        }
        let mut found: Vec<PathBuf> = std::fs::read_dir(p)
            .with_context(|| format!("cannot read directory {}", p.display()))?
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|f| f.is_file())
            .filter(|f| match (RecordingFormat::of_path(f), format) {
                (Some(have), Some(want)) => have == want,
                (Some(_), None) => true,
                (None, _) => false,
            })
            .filter(|f| {
                // greybox's own side files are not recordings
                let n = f.file_name().and_then(|n| n.to_str()).unwrap_or("");
                n != "ground_truth.csv" && n != "run_sheet.csv"
            })
            .collect();
        found.sort_by_key(|f| {
            natural_key(
                &f.file_name()
                    .map(|n| n.to_string_lossy().to_string())
                    .unwrap_or_default(),
            )
        });
        if found.is_empty() {
            bail!(
                "{}: no recording files (.csv, .txt, .tsv, .dat, .xlsx, .xls, .ods, .tdms)",
                p.display()
            );
        }
        files.extend(found);
    }
    Ok(files)
}

#[derive(Serialize)]
pub struct TruthComparison {
    pub max_abs_error: f64,
    pub mean_abs_error: f64,
    pub plateaus: usize,
}

/// Compare identified COFs to a ground truth CSV written by `greybox synth`.
pub fn compare_with_truth(ds: &FrictionDataset, truth_csv: &Path) -> Result<TruthComparison> {
    let mut rdr = csv::Reader::from_path(truth_csv)
        .with_context(|| format!("cannot read {}", truth_csv.display()))?;
    let header = rdr.headers()?.clone();
    let col = |name: &str| {
        header
            .iter()
            .position(|h| h == name)
            .with_context(|| format!("{}: missing column '{name}'", truth_csv.display()))
    };
    let (ip, is, ic) = (col("pin")?, col("step")?, col("cof_true")?);
    let mut truth = std::collections::HashMap::new();
    for (k, r) in rdr.records().enumerate() {
        let r = r.with_context(|| format!("{}: line {}", truth_csv.display(), k + 2))?;
        let parse = |i: usize| -> Result<f64> {
            r[i].parse::<f64>().with_context(|| {
                format!(
                    "{}: line {}: bad number '{}'",
                    truth_csv.display(),
                    k + 2,
                    &r[i]
                )
            })
        };
        truth.insert((parse(ip)? as u32, parse(is)? as u32), parse(ic)?);
    }
    let mut errs = Vec::new();
    for rec in &ds.records {
        let t = truth
            .get(&(rec.pin, rec.step))
            .with_context(|| format!("no ground truth for pin {} step {}", rec.pin, rec.step))?;
        errs.push((rec.cof_apparent - t).abs());
    }
    Ok(TruthComparison {
        max_abs_error: errs.iter().cloned().fold(0.0, f64::max),
        mean_abs_error: errs.iter().sum::<f64>() / errs.len() as f64,
        plateaus: errs.len(),
    })
}

#[derive(Serialize)]
pub struct IdentifySummary {
    pub dataset: String,
    pub plateaus: usize,
    pub non_stationary: usize,
    pub pressure_convention: String,
    #[serde(flatten)]
    pub identification: Identification,
    pub truth: Option<TruthComparison>,
}

/// What identification is matched against.
pub enum Expectation {
    /// A greybox plan with timing (also gives its steps and track radius).
    Plan(Plan),
    /// Steps without timing.
    Steps(Vec<ExpectedStep>),
    None,
}

/// Where identification writes: the dataset, optional inspect plots, and the inputs besides
/// the recordings (study, step list) that its provenance records.
pub struct IdentifyOutput<'a> {
    pub dataset: &'a Path,
    pub inspect_dir: Option<&'a Path>,
    /// Print nothing (the inspect text is the caller's).
    pub quiet: bool,
    pub side_inputs: &'a [(&'a str, &'a Path)],
}

/// Read all recordings and identify them; writes the dataset.
pub fn identify(
    study: &Study,
    expect: &Expectation,
    files: &[PathBuf],
    track_radii_mm: &[f64],
    o: &IdentifyOutput,
) -> Result<(FrictionDataset, Identification)> {
    let (out, inspect_dir, quiet, side_inputs) = (o.dataset, o.inspect_dir, o.quiet, o.side_inputs);
    let inputs: Vec<(&str, &Path)> = files
        .iter()
        .map(|f| ("--recordings", f.as_path()))
        .collect();
    greybox_core::outputs::check_file_output(out, "--out", &inputs)?;
    let recs: Vec<Recording> = files
        .iter()
        .map(|f| read_recording(f, &study.recording))
        .collect::<Result<Vec<_>, _>>()?;
    let steps;
    let (expected, plan) = match expect {
        Expectation::Plan(p) => {
            steps = expected_from_plan(p);
            (Some(steps.as_slice()), Some(p))
        }
        Expectation::Steps(s) => (Some(s.as_slice()), None),
        Expectation::None => (None, None),
    };
    let radii: Vec<f64> = if track_radii_mm.is_empty() {
        study.recording.track_radius_mm.clone()
    } else {
        track_radii_mm.to_vec()
    };
    let campaign = Campaign {
        expected,
        plan,
        contact: &study.contact,
        cfg: &study.identify,
        track_radius_mm: &radii,
    };
    let mut files_found = segment_recordings(&recs, &campaign)?;
    if let Some(dir) = inspect_dir {
        write_inspect_plots(&recs, &files_found, dir)?;
        if !quiet {
            print!("{}", inspect_text(&files_found));
            println!("inspect plots -> {}", dir.display());
        }
    }
    let (dataset, matching) = match_segments(&mut files_found, &campaign)?;
    let id = Identification {
        dataset,
        files: files_found,
        matching,
    };
    if id.dataset.records.is_empty() {
        let notes: Vec<String> = id
            .files
            .iter()
            .flat_map(|f| f.notes.iter().map(move |n| format!("{}: {n}", f.source)))
            .collect();
        bail!(
            "no plateau was identified in any recording\n  {}",
            notes.join("\n  ")
        );
    }
    id.dataset.write_csv(out)?;
    let mut all_inputs = inputs.clone();
    all_inputs.extend_from_slice(side_inputs);
    crate::output::provenance(&all_inputs)?.write_beside(out)?;
    Ok((id.dataset.clone(), id))
}

/// Per-pin summary table.
pub fn summary_table(ds: &FrictionDataset) -> String {
    let mut t = Table::new(&[
        "pin",
        "F_N plan [N]",
        "F_N meas. [N]",
        "p_H [MPa]",
        "COF first",
        "COF last",
        "std max",
        "steps",
        "flagged",
    ]);
    let mut pins: Vec<u32> = ds.records.iter().map(|r| r.pin).collect();
    pins.dedup();
    for pin in pins {
        let rows: Vec<_> = ds.records.iter().filter(|r| r.pin == pin).collect();
        let (first, last) = (rows[0], rows[rows.len() - 1]);
        t.row(vec![
            pin.to_string(),
            first
                .normal_force_planned_n
                .map_or("-".into(), |f| format!("{f:.1}")),
            format!("{:.1}", first.normal_force_n),
            format!("{:.1}", first.hertz_pressure_pa / units::PA_PER_MPA),
            format!("{:.4}", first.cof_apparent),
            format!("{:.4}", last.cof_apparent),
            format!(
                "{:.4}",
                rows.iter().map(|r| r.cof_apparent_std).fold(0.0, f64::max)
            ),
            rows.len().to_string(),
            rows.iter().filter(|r| !r.stationary).count().to_string(),
        ]);
    }
    t.render()
}

/// One line per file: how it was segmented.
pub fn files_table(id: &Identification) -> String {
    let mut t = Table::new(&[
        "file",
        "segmentation",
        "baseline",
        "segments",
        "rows",
        "notes",
    ]);
    for f in &id.files {
        t.row(vec![
            f.source.clone(),
            f.segmentation.clone(),
            f.baseline.clone(),
            f.segments.len().to_string(),
            f.segments
                .iter()
                .filter(|s| s.matched.is_some())
                .count()
                .to_string(),
            f.notes.len().to_string(),
        ]);
    }
    t.render()
}

fn all_rows_table(ds: &FrictionDataset) -> String {
    let mut t = Table::new(&[
        "pin",
        "step",
        "F_N [N]",
        "v [m/min]",
        "p_H [MPa]",
        "COF",
        "std",
        "n",
        "flags",
    ]);
    for r in &ds.records {
        t.row(vec![
            r.pin.to_string(),
            r.step.to_string(),
            format!("{:.1}", r.normal_force_n),
            format!("{:.1}", units::m_per_s_to_m_per_min(r.sliding_velocity_m_s)),
            format!("{:.1}", r.hertz_pressure_pa / units::PA_PER_MPA),
            format!("{:.4}", r.cof_apparent),
            format!("{:.4}", r.cof_apparent_std),
            r.n_samples.to_string(),
            r.flags.join(";"),
        ]);
    }
    t.render()
}

/// Whether the user gave a plan: a `[plan]` section in the study, or a plan-shape flag.
fn plan_given(args: &Args) -> Result<bool> {
    let f = &args.plan;
    let flags = f.normal_force_min_n.is_some()
        || f.normal_force_max_n.is_some()
        || f.normal_force_count.is_some()
        || f.velocity_min.is_some()
        || f.velocity_max.is_some()
        || f.velocity_count.is_some();
    let in_study = match &f.study {
        Some(path) => {
            let text = std::fs::read_to_string(path)
                .with_context(|| format!("cannot read study file {}", path.display()))?;
            let value: toml::Value = toml::from_str(&text)
                .with_context(|| format!("{}: invalid study file", path.display()))?;
            value.get("plan").is_some()
        }
        None => false,
    };
    Ok(flags || in_study)
}

pub fn run(args: Args) -> Result<()> {
    let mut study = args.plan.study()?;
    for m in &args.map {
        study.recording.apply_override(m)?;
    }
    if let Some(g) = &args.tdms_group {
        study.recording.tdms_group = Some(g.clone());
    }
    if let Some(h) = args.header_line {
        study.recording.header_line = Some(h);
    }
    if let Some(f) = args.sample_rate_hz {
        if !(f.is_finite() && f > 0.0) {
            bail!("--sample-rate-hz must be positive, got {f}");
        }
        study.recording.sample_rate_hz = Some(f);
    }
    if let Some(s) = &args.sheet {
        study.recording.sheet = Some(s.clone());
    }
    if let Some(a) = args.align {
        study.identify.align = match a {
            AlignArg::Trigger => Alignment::Trigger,
            AlignArg::FirstPlateau => Alignment::FirstPlateau,
        };
        study.identify.segmentation = Segmentation::PlanTiming;
    }
    if let Some(s) = args.segment {
        study.identify.segmentation = s.into();
    }
    if let Some(s) = args.settle_s {
        study.identify.settle_time_s = s;
    }
    if let Some(c) = args.convention {
        study.contact.convention = c.into();
    }
    if let Some(r) = args
        .track_radii_mm
        .iter()
        .find(|r| !(r.is_finite() && **r > 0.0))
    {
        bail!("--track-radii-mm: every radius must be positive, got {r}");
    }
    let expect = if let Some(path) = &args.plan_steps {
        Expectation::Steps(read_expected_steps(path)?)
    } else if !args.no_plan && plan_given(&args)? {
        Expectation::Plan(study.plan.build().context("cannot build the plan")?)
    } else {
        Expectation::None
    };
    let mut radii = args.track_radii_mm.clone();
    if radii.is_empty() {
        if let (Expectation::None | Expectation::Steps(_), Some(r)) =
            (&expect, args.plan.track_radius_mm)
        {
            radii.push(r);
        }
    }
    let pins = match &expect {
        Expectation::Plan(p) => Some(p.pins.len()),
        _ => None,
    };
    let files = recording_files(&args.recordings, args.format.map(Into::into), pins)?;
    let side_inputs = [
        ("--study", args.plan.study.as_deref()),
        ("--plan-steps", args.plan_steps.as_deref()),
        ("--truth", args.truth.as_deref()),
    ];
    let side_inputs: Vec<(&str, &Path)> = side_inputs
        .iter()
        .filter_map(|(f, p)| p.map(|p| (*f, p)))
        .collect();
    greybox_core::outputs::check_file_output(&args.out, "--out", &side_inputs)?;
    let inspect_dir = args.inspect.then(|| {
        args.inspect_dir.clone().unwrap_or_else(|| {
            let stem = args
                .out
                .file_stem()
                .map(|s| s.to_string_lossy().to_string())
                .unwrap_or_else(|| "dataset".into());
            args.out.with_file_name(format!("{stem}_inspect"))
        })
    });
    let (ds, id) = identify(
        &study,
        &expect,
        &files,
        &radii,
        &IdentifyOutput {
            dataset: &args.out,
            inspect_dir: inspect_dir.as_deref(),
            quiet: args.json,
            side_inputs: &side_inputs,
        },
    )?;
    if args.inspect && !args.json {
        print!("{}", matching_text(&id.matching));
    }
    let truth = args
        .truth
        .as_deref()
        .map(|p| compare_with_truth(&ds, p))
        .transpose()?;
    let summary = IdentifySummary {
        dataset: args.out.display().to_string(),
        plateaus: ds.records.len(),
        non_stationary: ds.records.iter().filter(|r| !r.stationary).count(),
        pressure_convention: study.contact.convention.name().to_string(),
        identification: id,
        truth,
    };
    if args.json {
        return print_json(&summary);
    }
    print!(
        "{}",
        if args.all {
            all_rows_table(&ds)
        } else {
            summary_table(&ds)
        }
    );
    print!("{}", files_table(&summary.identification));
    print_identify_footer(&summary);
    Ok(())
}

/// The per-file report of `--inspect`.
pub fn inspect_text(files: &[FileReport]) -> String {
    use std::fmt::Write as _;
    let mut s = String::new();
    for f in files {
        let _ = writeln!(s, "== {}", f.source);
        if let Some(r) = &f.read {
            let _ = writeln!(s, "   layout: {}", r.layout);
            for c in &r.columns {
                let _ = writeln!(
                    s,
                    "   {:<10} <- '{}' [{}]{} ({})",
                    c.role,
                    c.column,
                    c.unit,
                    if c.scale != 1.0 {
                        format!(" x {}", c.scale)
                    } else {
                        String::new()
                    },
                    c.how
                );
            }
            for (line, text) in &r.footer {
                let _ = writeln!(s, "   footer line {line}: {text}");
            }
            for n in &r.notes {
                let _ = writeln!(s, "   note: {n}");
            }
        }
        let _ = writeln!(
            s,
            "   {} samples at {:.3} Hz over {:.3} s; segmentation: {}; baseline: {}{}",
            f.samples,
            f.sample_rate_hz,
            f.duration_s,
            f.segmentation,
            f.baseline,
            if f.tangential_sign_flipped {
                "; tangential sign flipped"
            } else {
                ""
            }
        );
        for n in &f.notes {
            let _ = writeln!(s, "   note: {n}");
        }
        let mut t = Table::new(&[
            "seg",
            "start [s]",
            "end [s]",
            "F_N [N]",
            "speed",
            "v [m/min]",
            "steady [s]",
            "COF",
            "flags",
            "plan",
        ]);
        for g in &f.segments {
            t.row(vec![
                g.index.to_string(),
                format!("{:.3}", g.start_s),
                format!("{:.3}", g.end_s),
                format!("{:.1}", g.normal_force_n),
                g.spindle_rpm.map_or("-".into(), |r| format!("{r:.1} rpm")),
                g.sliding_velocity_m_per_min
                    .map_or("-".into(), |v| format!("{v:.1}")),
                match (g.steady_start_s, g.steady_end_s) {
                    (Some(a), Some(b)) => format!("{a:.3}-{b:.3}"),
                    _ => "-".into(),
                },
                g.cof.map_or("-".into(), |c| format!("{c:.4}")),
                match &g.problem {
                    Some(p) => p.clone(),
                    None => g.flags.join(";"),
                },
                g.matched
                    .map_or("-".into(), |(p, k)| format!("pin {p} step {k}")),
            ]);
        }
        s.push_str(&t.render());
    }
    s
}

/// How segments were matched to the plan, with what is missing, extra or reordered.
pub fn matching_text(m: &MatchReport) -> String {
    use std::fmt::Write as _;
    let mut s = String::new();
    let _ = writeln!(s, "matching to the plan: {}", m.method);
    for (what, list) in [
        ("missing", &m.missing),
        ("extra", &m.extra),
        ("reordered", &m.reordered),
    ] {
        for item in list {
            let _ = writeln!(s, "   {what}: {item}");
        }
    }
    s
}

/// One SVG per recording: μ = F_t/F_N and F_N / max F_N over time, steady windows shaded.
fn write_inspect_plots(recs: &[Recording], found: &[FileReport], dir: &Path) -> Result<()> {
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    for (rec, f) in recs.iter().zip(found) {
        let n = rec.len();
        let step = (n / 3000).max(1);
        let fmax = rec
            .normal_n
            .iter()
            .fold(0.0f64, |m, v| m.max(v.abs()))
            .max(1e-12);
        let sign = if f.tangential_sign_flipped { -1.0 } else { 1.0 };
        let (mut t, mut mu, mut fnr) = (Vec::new(), Vec::new(), Vec::new());
        for c in (0..n).step_by(step) {
            let e = (c + step).min(n);
            let fn_m = rec.normal_n[c..e].iter().sum::<f64>() / (e - c) as f64;
            let ft_m = rec.tangential_n[c..e].iter().sum::<f64>() / (e - c) as f64;
            t.push(rec.time_s[c]);
            fnr.push(fn_m / fmax);
            mu.push(if fn_m.abs() > 0.02 * fmax {
                sign * ft_m / fn_m
            } else {
                0.0
            });
        }
        let labels: Vec<String> = f.segments.iter().map(|g| format!("{}", g.index)).collect();
        let bands: Vec<(f64, f64, &str)> = f
            .segments
            .iter()
            .zip(&labels)
            .filter_map(|(g, l)| Some((g.steady_start_s?, g.steady_end_s?, l.as_str())))
            .collect();
        let name = Path::new(&f.source)
            .file_name()
            .map(|s| s.to_string_lossy().to_string())
            .unwrap_or_else(|| "recording".into());
        let svg = greybox_core::plot::lines(
            &format!("{name}: steady windows shaded ({})", f.segmentation),
            "time [s]",
            "F_t/F_N [-] and F_N/max F_N [-]",
            &[
                greybox_core::plot::Line {
                    label: "F_t/F_N",
                    colour: "#1f4e9c",
                    x: &t,
                    y: &mu,
                },
                greybox_core::plot::Line {
                    label: "F_N/max",
                    colour: "#b2182b",
                    x: &t,
                    y: &fnr,
                },
            ],
            false,
            &bands,
        );
        greybox_core::atomic::write_string_atomic(&dir.join(format!("{name}.svg")), &svg)?;
    }
    Ok(())
}
pub fn print_identify_footer(s: &IdentifySummary) {
    println!(
        "identify: {} plateaus ({} non-stationary), pressure convention {}, dataset {}",
        s.plateaus, s.non_stationary, s.pressure_convention, s.dataset
    );
    if let Some(t) = &s.truth {
        println!(
            "  against the ground truth: max |COF - COF_true| = {:.5}, mean = {:.5} over {} plateaus",
            t.max_abs_error, t.mean_abs_error, t.plateaus
        );
    }
}
