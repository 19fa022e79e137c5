//! `greybox import`: a model trained elsewhere as a greybox model file.

use crate::output::print_json;
use anyhow::Result;
use greybox_core::choice::clap_parsers::choice;
use greybox_core::dataset::PressureConvention;
use greybox_model::column::FeatureQuantity;
use greybox_pipeline::import::{import, ContactSpec};
use greybox_pipeline::settings::import::{ImportRows, ImportSettings};
use std::path::PathBuf;

#[derive(clap::Args, Debug)]
pub struct Args {
    /// The model: an XGBoost booster saved as JSON (.json) or UBJSON (.ubj), an ONNX model
    /// (.onnx), or a scikit-learn model exported by greybox's Python package
    /// (greybox.export_sklearn).
    pub model: PathBuf,
    #[command(flatten)]
    pub settings: ImportSettings,
    #[command(flatten)]
    pub contact: ContactArgs,
    /// The greybox model file to write.
    #[arg(long)]
    pub out: PathBuf,
    /// Print JSON.
    #[arg(long)]
    pub json: bool,
}

/// The tribometer's pin contact, for a model trained on a normal force (`normal_force_N`):
/// recorded in the model file so that it maps contact pressure to that force as a friction
/// law, a table or in a simulation. The flags are the keys of a study's `[contact]` table;
/// they override `--contact`'s. The pressure convention must be stated; other keys default
/// as in the `[contact]` table (the article's 17 mm carbide pin on AISI 1045).
#[derive(clap::Args, Debug, Default)]
pub struct ContactArgs {
    /// A study TOML whose [contact] table states the tribometer's pin contact (needed for a
    /// model on normal_force_N to be a friction law); the flags below override its keys.
    #[arg(long, value_name = "STUDY.toml")]
    pub contact: Option<PathBuf>,
    /// Pressure convention the training data's pressures were computed with.
    #[arg(long, value_parser = choice::<PressureConvention>())]
    pub convention: Option<PressureConvention>,
    /// Pin tip radius, mm.
    #[arg(long = "pin-tip-radius-mm")]
    pub pin_tip_radius_mm: Option<f64>,
    /// Pin Young's modulus, GPa.
    #[arg(long = "pin-youngs-modulus-gpa")]
    pub pin_youngs_modulus_gpa: Option<f64>,
    /// Pin Poisson ratio.
    #[arg(long = "pin-poisson-ratio")]
    pub pin_poisson_ratio: Option<f64>,
    /// Disk (workpiece) Young's modulus, GPa.
    #[arg(long = "disk-youngs-modulus-gpa")]
    pub disk_youngs_modulus_gpa: Option<f64>,
    /// Disk Poisson ratio.
    #[arg(long = "disk-poisson-ratio")]
    pub disk_poisson_ratio: Option<f64>,
}

impl ContactArgs {
    /// The flags as the library's [`ContactSpec`].
    fn spec(&self) -> ContactSpec {
        let mut fields = serde_json::Map::new();
        let numbers = [
            ("pin_tip_radius_mm", self.pin_tip_radius_mm),
            ("pin_youngs_modulus_gpa", self.pin_youngs_modulus_gpa),
            ("pin_poisson_ratio", self.pin_poisson_ratio),
            ("disk_youngs_modulus_gpa", self.disk_youngs_modulus_gpa),
            ("disk_poisson_ratio", self.disk_poisson_ratio),
        ];
        for (key, v) in numbers {
            if let Some(v) = v {
                fields.insert(key.into(), serde_json::json!(v));
            }
        }
        if let Some(c) = self.convention {
            fields.insert("convention".into(), c.name().into());
        }
        ContactSpec {
            study: self.contact.clone(),
            fields,
        }
    }
}

pub fn run(a: Args) -> Result<()> {
    let settings = ImportSettings {
        contact: a.contact.spec(),
        ..a.settings
    };
    let opts = settings.options(ImportRows::default())?;
    let m = import(&a.model, &opts, a.contact.contact.as_deref(), &a.out)?;
    if a.json {
        return print_json(&m.hyperparameters);
    }
    println!(
        "{}: {} ({} → {}), interval {}, written to {}",
        a.model.display(),
        m.hyperparameters.label(),
        m.features
            .iter()
            .map(|f| format!("{} [{}]", f.name, f.unit))
            .collect::<Vec<_>>()
            .join(", "),
        m.target.name,
        match m.prediction_interval.method {
            greybox_model::interval::IntervalMethod::None => "none (no calibration data)".into(),
            _ => format!(
                "±{:.4} at {:.0} %",
                m.prediction_interval.half_width,
                m.prediction_interval.coverage * 100.0
            ),
        },
        a.out.display()
    );
    match &m.force_to_pressure {
        Some(fp) => println!(
            "contact: {:.6e} Pa at 1 N ({} convention)",
            fp.pressure_pa_at_1_n,
            fp.pressure_convention.name()
        ),
        None => {
            if let Some(f) = m.features.iter().find(|f| {
                matches!(
                    FeatureQuantity::of_column(f),
                    Ok(FeatureQuantity::NormalForce { .. })
                )
            }) {
                eprintln!("note: feature '{}' is a normal force and no contact was stated: the model predicts on forces, but is no friction law (greybox export, simulate) until it is re-imported with --contact STUDY.toml or --convention, --pin-tip-radius-mm, …", f.name);
            }
        }
    }
    Ok(())
}
