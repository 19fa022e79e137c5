//! # greybox
//!
//! Tribometer recordings to data-driven friction models, and those models at work as
//! grey-box friction laws in metal-cutting simulation. This crate is the one to depend on:
//! it re-exports the workflow layer ([`pipeline`]) and every stage crate, the way ripgrep's
//! `grep` crate re-exports its parts.
//!
//! The article's pipeline, from raw recordings to a cut with friction windows:
//!
//! ```no_run
//! use greybox::pipeline::{adhesive, fit, identify, law, simulate, synth, Study};
//! # fn main() -> anyhow::Result<()> {
//! let study = Study::parse(greybox::pipeline::study::DEMO_STUDY, "demo study")?;
//! let rig = greybox::recording::readers::RecordingFormat::Csv;
//! synth::synth(&study, &[rig], "recordings".as_ref(), false, &[])?; // or your rig's files
//! let id = identify::IdentifyOptions::new(vec!["recordings".into()], "dataset.csv")
//!     .with_plan(study.plan.build()?);
//! identify::identify_campaign(&study, &id, None)?;
//! adhesive::adhesive(&adhesive::AdhesiveOptions::analytic("dataset.csv".into(), "adh.csv".into()))?;
//! fit::fit(&fit::FitOptions::article("adh.csv".into(), "cof_adhesive", "fit".into()))?;
//! let spec = law::grey_box_law("fit/models/svr.json".into(), Some(study.contact), &Default::default());
//! law::write_law("law.json".as_ref(), &spec)?;
//! let case = simulate::read_cutting_setup("examples/aisi1045-cut.toml".as_ref())?; // names law.json
//! let cut = simulate::run_cut(&case, 1.0, &simulate::RunOutput::to("cut"))?;
//! println!("cutting force {:.1} N/mm", cut.cutting_force_n_per_mm);
//! # Ok(()) }
//! ```
//!
//! Runnable versions: `cargo run --release -p greybox --example recordings_to_cut`,
//! `--example custom_friction_law` (your own law in the simulator) and `--example c_abi`
//! (a law evaluated through the C ABI that Fortran user routines call).
//!
//! | crate | re-exported as | owns |
//! |---|---|---|
//! | `greybox-pipeline` | [`pipeline`] | the workflows: each stage with plain options |
//! | `greybox-report` | [`report`] | how results are shown: `report.html`, each stage's text tables, the demo |
//! | `greybox-sweep` | [`sweep`] | many cuts: sweeps (local pool, Slurm), calibration, the validation suite |
//! | `greybox-core` | [`core`] | SI units, `ContactState`, the `FrictionLaw` seam, safe outputs, provenance |
//! | `greybox-contact` | [`contact`] | contact mechanics: Hertzian pin-on-disk contact, ploughing, wear |
//! | `greybox-recording` | [`recording`] | recordings from any rig: text, xlsx and TDMS readers, rig profiles, column roles |
//! | `greybox-tribo` | [`tribo`] | plans, identification of μ from recordings, the virtual rig, rig dynamics |
//! | `greybox-model` | [`model`] | inference: model files, predictors, domain checks |
//! | `greybox-learn` | [`learn`] | training: the four families, the article's protocol |
//! | `greybox-import` | [`import`] | models trained elsewhere: XGBoost, scikit-learn, ONNX |
//! | `greybox-friction` | [`friction`] | friction laws (learned, grey-box, tables) and FE exports |
//! | `greybox-couple` | [`couple`] | friction windows on FE meshes, the FE restart loop |
//! | `greybox-material` | [`material`] | Johnson–Cook and flow-curve fits |
//! | `greybox-sim` | [`sim`] | the 2D SPH cutting and pin simulator |

pub use greybox_contact as contact;
pub use greybox_core as core;
pub use greybox_couple as couple;
pub use greybox_friction as friction;
pub use greybox_import as import;
pub use greybox_learn as learn;
pub use greybox_material as material;
pub use greybox_model as model;
pub use greybox_pipeline as pipeline;
pub use greybox_recording as recording;
pub use greybox_report as report;
pub use greybox_sim as sim;
pub use greybox_sweep as sweep;
pub use greybox_tribo as tribo;

pub use greybox_core::{ContactState, FrictionLaw};
pub use greybox_pipeline::Study;
