//! `greybox demo`: the whole pipeline on the bundled example study.

use crate::output::print_json;
use crate::study::{Study, DEMO_STUDY};
use crate::{cmd_fit, cmd_identify, cmd_plan, cmd_synth};
use anyhow::Result;
use greybox_tribo::recording::RecordingFormat;
use serde::Serialize;
use std::path::PathBuf;

#[derive(clap::Args, Debug)]
pub struct Args {
    /// Output directory.
    #[arg(long, default_value = "demo-out")]
    pub out: PathBuf,
    /// Print the result as JSON.
    #[arg(long)]
    pub json: bool,
}

#[derive(Serialize)]
struct DemoSummary {
    plan: cmd_plan::PlanSummary,
    synth: cmd_synth::SynthSummary,
    identify: cmd_identify::IdentifySummary,
    fit: greybox_learn::protocol::FitReport,
    fit_outputs: cmd_fit::FitOutputs,
}

pub fn run(a: Args) -> Result<()> {
    let study = Study::parse(DEMO_STUDY, "bundled examples/demo-study.toml")?;
    let plan = study.plan.build()?;
    let out = &a.out;
    let plan_files = cmd_plan::write_plan(&study, &plan, &out.join("plan"))?;
    let plan_summary = cmd_plan::summarize(&plan, plan_files);
    let rec_dir = out.join("recordings");
    let synth = cmd_synth::synthesize(
        &study,
        &plan,
        &rec_dir,
        &[RecordingFormat::Csv, RecordingFormat::Tdms],
    )?;
    let dataset = out.join("dataset.csv");
    let files = cmd_identify::recording_files(
        std::slice::from_ref(&rec_dir),
        RecordingFormat::Tdms,
        plan.pins.len(),
    )?;
    let (ds, diags) = cmd_identify::identify(&study, &plan, &files, &dataset)?;
    let truth = cmd_identify::compare_with_truth(&ds, &rec_dir.join("ground_truth.csv"))?;
    let identify = cmd_identify::IdentifySummary {
        dataset: dataset.display().to_string(),
        plateaus: ds.records.len(),
        non_stationary: ds.records.iter().filter(|r| !r.stationary).count(),
        pressure_convention: study.contact.convention.name().into(),
        pins: diags.clone(),
        truth: Some(truth),
    };
    let fit_args = cmd_fit::Args::defaults(dataset.clone(), out.join("fit"));
    let (fit, fit_outputs) = cmd_fit::fit(&fit_args)?;
    if a.json {
        return print_json(&DemoSummary {
            plan: plan_summary,
            synth,
            identify,
            fit,
            fit_outputs,
        });
    }
    println!("greybox demo — the seed article's tribometer campaign on a virtual rig\n");
    println!("[1/4] plan -> {}", out.join("plan").display());
    cmd_plan::print_summary(&plan_summary);
    println!("\n[2/4] synth -> {}", rec_dir.display());
    cmd_synth::print_summary(&synth);
    println!(
        "\n[3/3] identify (TDMS recordings) -> {}",
        dataset.display()
    );
    print!("{}", cmd_identify::summary_table(&ds, &diags));
    cmd_identify::print_identify_footer(&identify);
    Ok(())
}
