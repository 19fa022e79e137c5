//! `greybox identify`.

use crate::cmd_plan::PlanFlags;
use crate::output::{print_json, Table};
use crate::study::Study;
use anyhow::{bail, Context, Result};
use greybox_core::dataset::{FrictionDataset, PressureConvention};
use greybox_core::units;
use greybox_tribo::identify::{identify_campaign, Alignment, PinDiagnostics};
use greybox_tribo::plan::Plan;
use greybox_tribo::recording::{read_recording, RecordingFormat};
use serde::Serialize;
use std::path::{Path, PathBuf};

#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum InFormat {
    Csv,
    Tdms,
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

#[derive(clap::Args, Debug)]
pub struct Args {
    #[command(flatten)]
    pub plan: PlanFlags,
    /// Recording files in pin order, or one directory holding pinNN.csv / pinNN.tdms.
    #[arg(long, num_args = 1.., required = true)]
    pub recordings: Vec<PathBuf>,
    /// Which files to pick from a directory.
    #[arg(long, value_enum, default_value_t = InFormat::Csv)]
    pub format: InFormat,
    /// How to align the plan with each recording.
    #[arg(long, value_enum)]
    pub align: Option<AlignArg>,
    /// Time dropped after the spindle ramp, s.
    #[arg(long = "settle-s")]
    pub settle_s: Option<f64>,
    /// Channel mapping ROLE=NAME[:UNIT[:SCALE]] (roles: time, normal, tangential, radial, trigger), repeatable.
    #[arg(long = "map")]
    pub map: Vec<String>,
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
    /// Print the result as JSON.
    #[arg(long)]
    pub json: bool,
}

/// Resolve the recording files for `pins` pins.
pub fn recording_files(
    paths: &[PathBuf],
    format: RecordingFormat,
    pins: usize,
) -> Result<Vec<PathBuf>> {
    if paths.len() == 1 && paths[0].is_dir() {
        let dir = &paths[0];
        let files: Vec<PathBuf> = (1..=pins)
            .map(|p| dir.join(format!("pin{p:02}.{}", format.extension())))
            .collect();
        if let Some(missing) = files.iter().find(|f| !f.exists()) {
            bail!(
                "{}: no recording {} for the plan's {pins} pins",
                dir.display(),
                missing.display()
            );
        }
        return Ok(files);
    }
    if paths.len() != pins {
        bail!(
            "the plan has {pins} pins but {} recording files were given",
            paths.len()
        );
    }
    Ok(paths.to_vec())
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
    pub pins: Vec<PinDiagnostics>,
    pub truth: Option<TruthComparison>,
}

/// Read all recordings and identify the campaign.
pub fn identify(
    study: &Study,
    plan: &Plan,
    files: &[PathBuf],
    out: &Path,
) -> Result<(FrictionDataset, Vec<PinDiagnostics>)> {
    let recs = files
        .iter()
        .map(|f| read_recording(f, &study.recording))
        .collect::<Result<Vec<_>, _>>()?;
    let (ds, diags) = identify_campaign(plan, &recs, &study.contact, &study.identify)?;
    ds.write_csv(out)?;
    Ok((ds, diags))
}

/// Per-pin summary table.
pub fn summary_table(ds: &FrictionDataset, diags: &[PinDiagnostics]) -> String {
    let mut t = Table::new(&[
        "pin",
        "F_N [N]",
        "p_H [MPa]",
        "COF @v_min",
        "COF @v_max",
        "std max",
        "flagged",
        "latency [s]",
        "drift F_t [N]",
    ]);
    for d in diags {
        let rows: Vec<_> = ds.records.iter().filter(|r| r.pin == d.pin).collect();
        let (first, last) = (rows[0], rows[rows.len() - 1]);
        t.row(vec![
            d.pin.to_string(),
            format!("{:.1}", first.normal_force_n),
            format!("{:.1}", first.hertz_pressure_pa / units::PA_PER_MPA),
            format!("{:.4}", first.cof_apparent),
            format!("{:.4}", last.cof_apparent),
            format!(
                "{:.4}",
                rows.iter().map(|r| r.cof_apparent_std).fold(0.0, f64::max)
            ),
            rows.iter().filter(|r| !r.stationary).count().to_string(),
            format!("{:.3}", d.latency_s),
            format!("{:.2}", d.drift_tangential_n),
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

pub fn run(args: Args) -> Result<()> {
    let mut study = args.plan.study()?;
    for m in &args.map {
        study.recording.apply_override(m)?;
    }
    if let Some(g) = &args.tdms_group {
        study.recording.tdms_group = g.clone();
    }
    if let Some(a) = args.align {
        study.identify.align = match a {
            AlignArg::Trigger => Alignment::Trigger,
            AlignArg::FirstPlateau => Alignment::FirstPlateau,
        };
    }
    if let Some(s) = args.settle_s {
        study.identify.settle_time_s = s;
    }
    if let Some(c) = args.convention {
        study.contact.convention = c.into();
    }
    let plan = study.plan.build().context("cannot build the plan")?;
    let format = match args.format {
        InFormat::Csv => RecordingFormat::Csv,
        InFormat::Tdms => RecordingFormat::Tdms,
    };
    let files = recording_files(&args.recordings, format, plan.pins.len())?;
    let (ds, diags) = identify(&study, &plan, &files, &args.out)?;
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
        pins: diags.clone(),
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
            summary_table(&ds, &diags)
        }
    );
    print_identify_footer(&summary);
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
