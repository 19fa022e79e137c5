#![allow(clippy::neg_cmp_op_on_partial_ord)] // `!(x > 0.0)` deliberately rejects NaN too
//! greybox's workflows as library calls: each stage of the seed article's pipeline takes
//! plain option types (no command-line types), writes its outputs safely (staged, swapped
//! in whole, with provenance) and returns what it found. The `greybox` command line only
//! parses arguments into these options, calls them and prints (with `greybox-report`).
//!
//! The data path, left to right:
//!
//! | stage | module | in → out |
//! |---|---|---|
//! | plan a campaign | [`plan`] | study → run sheet, NC programs |
//! | virtual rig | [`synth`] | plan → recordings, ground truth |
//! | identify | [`identify`] | recordings (any rig) → dataset of μ per load × speed |
//! | ploughing correction | [`adhesive`] | dataset → adhesive μ (analytic or inverse simulation) |
//! | learn | [`fit`] | dataset → model files, reports, plots |
//! | bring your own model | [`import`](mod@import) | XGBoost / scikit-learn model → model file |
//! | grey-box law | [`law`] | model → law file |
//! | tables for FE engines | [`export`] | law → Abaqus / DEFORM / LS-DYNA / surrogate table |
//! | cut, pin | [`simulate`] | set-up + law → forces, contact profile, chip |
//! | chip pictures | [`chip_picture`] | particle states → SVG pictures and frames |
//! | rig dynamics | [`characterize`] | hammer recordings → FRF, excitation check |
//! | FE restart loop | [`couple`] | deck + law → μ per window |
//! | material | [`material`] | flow curves → Johnson–Cook |
//! | Hertz contact | [`hertz`] | load, geometry → contact size, pressures |
//! | model evaluation | [`predict`] | model file + points → μ with intervals |
//! | wear | [`wear`] | volumes, height maps, scars → Archard k |
//! | tool windows | [`windows`] | coated tool mesh → friction windows |
//! | speed | [`bench`](mod@bench) | ingestion, prediction latency, surrogate tables, SPH |
//!
//! How results are shown — the plain-text tables each stage prints, the `report.html` of a
//! study directory, the progress display and the demo that runs every stage — is the crate
//! `greybox-report`, which depends on this one (never the other way round).
//!
//! Errors are [`anyhow::Error`]s whose messages name the file, line or field at fault.

pub mod adhesive;
pub mod adhesive_3d;
pub mod adhesive_loads;
pub mod bench;
pub mod characterize;
pub mod chip_picture;
pub mod config_toml;
pub mod couple;
pub mod export;
pub mod fit;
pub mod hertz;
pub mod identify;
pub mod identify_cycles;
pub mod import;
pub mod law;
pub mod material;
pub mod output;
pub mod plan;
pub mod predict;
pub mod settings;
pub mod simulate;
pub mod study;
pub mod synth;
pub mod wear;
pub mod windows;

pub use study::Study;
