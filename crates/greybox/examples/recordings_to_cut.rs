//! Recordings → dataset → model → grey-box law → cut: the seed article's pipeline on a
//! small virtual campaign (4 loads × 6 velocities instead of 10 × 21), in a temporary
//! directory (or the directory given as the first argument).
//!
//! `cargo run --release -p greybox --example recordings_to_cut [OUT_DIR]`
//!
//! To run it on your own rig, skip step 1 and point `IdentifyOptions::new` at your
//! recordings (CSV/TXT, XLSX, TDMS; `study.recording` maps their columns).

use anyhow::Result;
use greybox::model::Family;
use greybox::pipeline::{adhesive, fit, identify, law, simulate, study::DEMO_STUDY, synth, Study};
use greybox::recording::readers::RecordingFormat;
use std::path::{Path, PathBuf};

fn main() -> Result<()> {
    let tmp = tempfile::tempdir()?;
    let dir: PathBuf = std::env::args_os()
        .nth(1)
        .map(PathBuf::from)
        .unwrap_or_else(|| tmp.path().to_path_buf());
    let mut study = Study::parse(DEMO_STUDY, "bundled examples/demo-study.toml")?;
    study.plan.normal_force_count = greybox::tribo::plan::PinCount::of(4);
    study.plan.velocity_count = greybox::tribo::plan::VelocityCount::of(6);

    // 1. recordings from a virtual rig (the article's NC programs, noise, drift, spikes)
    let recordings = dir.join("recordings");
    synth::synth(&study, &[RecordingFormat::Csv], &recordings, true, &[])?;

    // 2. apparent μ per (load, velocity) with Hertzian pressures, matched to the plan
    let dataset = dir.join("dataset.csv");
    let options =
        identify::IdentifyOptions::new(vec![recordings], &dataset).with_plan(study.plan.build()?);
    let id = identify::identify_campaign(&study, &options, None)?;
    print!("{}", greybox::report::text::summary_table(&id.dataset));

    // 3. adhesive μ: Bowden–Tabor ploughing with the article's track widths (Table 3)
    let adhesive_csv = dir.join("dataset_adhesive.csv");
    let (_, correction) = adhesive::adhesive(&adhesive::AdhesiveOptions::analytic(
        dataset,
        adhesive_csv.clone(),
    ))?;
    println!(
        "ploughing lowers μ by {:.2} % on average",
        correction.mean_reduction_percent
    );

    // 4. SVR with the article's grid, nested cross-validation
    let mut fit_options = fit::FitOptions::article(adhesive_csv, "cof_adhesive", dir.join("fit"));
    fit_options.config.families = vec![Family::Svr];
    fit_options.force = true;
    let fitted = fit::fit(&fit_options)?;
    let svr = &fitted.report.families[0];
    println!(
        "SVR {}: held-out R² {:.3}",
        svr.selected_label,
        svr.held_out
            .as_ref()
            .map_or(f64::NAN, |h| h.metrics.r2.value)
    );

    // 5. the grey-box law: SVR inside its domain, a power law outside, Zorev cap 600 MPa
    let spec = law::grey_box_law(
        "fit/models/svr.json".into(),
        Some(study.contact),
        &law::GreyBoxOptions {
            shear_cap_k_mpa: Some(600.0),
            ..Default::default()
        },
    );
    law::write_law(&dir.join("law.json"), &spec)?;

    // 6. the article's cut (AISI 1045, 150 m/min, h = 0.1 mm), coarse and short, with the
    //    law in friction windows along the tool
    let examples = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples");
    let mut setup = simulate::read_cutting_setup(&examples.join("aisi1045-cut.toml"))?.setup;
    setup.spacing_m = 12.5e-6;
    setup.friction.window_length_m = 12.5e-6;
    setup.cut_length_m = 0.25e-3;
    setup.friction.law_file = Some("law.json".into());
    let case = simulate::cut_case(setup, &dir)?;
    let mut output = simulate::RunOutput::to(dir.join("cut"));
    output.force = true;
    let cut = simulate::run_cut(&case, 1.0, &output)?;
    print!("{}", greybox::report::text::cut(&cut));
    Ok(())
}
