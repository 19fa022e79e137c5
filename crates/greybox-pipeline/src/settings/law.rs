//! The settings of a grey-box law around a fitted model (`greybox law`, Python's
//! `grey_box_law`): one type, one default per field. The file written states every choice:
//! the blend, the μ clamp, the shear cap (`shear_cap_k_MPa`, `null`: none) and the contact
//! (`null`: the force-to-pressure map the model recorded from its training data).
//!
//! ```
//! use greybox_pipeline::settings::{from_json, law::GreyBoxSettings};
//! let s: GreyBoxSettings = from_json("law", r#"{"model": "fit/models/svr.json"}"#)?;
//! let law = serde_json::to_value(s.law()?)?;
//! assert_eq!((law["blend_fraction"].as_f64(), law["shear_cap_k_MPa"].as_f64()), (Some(0.1), None));
//! assert_eq!(law["clamp"], serde_json::json!([0.05, 1.0]));
//! let capped: GreyBoxSettings = from_json("law",
//!     r#"{"model": "m.json", "shear_cap_k_MPa": 600, "no_clamp": true}"#)?;
//! let law = serde_json::to_value(capped.law()?)?;
//! assert_eq!((law["shear_cap_k_MPa"].as_f64(), law["clamp"].is_null()), (Some(600.0), true));
//! # Ok::<(), anyhow::Error>(())
//! ```

use crate::law::{grey_box_law, write_law, GreyBoxOptions};
use crate::study::Study;
use anyhow::Result;
use greybox_core::outputs::check_file_output;
use greybox_core::physics::{self, Quantity};
use greybox_core::setting::{refused, refused_together, SettingPath};
use greybox_core::units::mpa_to_pa;
use greybox_friction::greybox::{DEFAULT_BLEND_FRACTION, MAX_BLEND_FRACTION};
use greybox_friction::spec::LawSpec;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// The law file written when no `out` is given.
pub const DEFAULT_LAW_FILE: &str = "law.json";
/// The lower end of the μ clamp.
pub const DEFAULT_MU_MIN: f64 = 0.05;
/// The upper end of the μ clamp.
pub const DEFAULT_MU_MAX: f64 = 1.0;

/// One grey-box law as a user states it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "cli", derive(clap::Args))]
#[serde(deny_unknown_fields, default)]
#[allow(non_snake_case)]
pub struct GreyBoxSettings {
    /// The fitted model file (e.g. fit-out/models/svr.json); the law records it relative to
    /// the law file's folder when given relative to it.
    #[cfg_attr(feature = "cli", arg(long))]
    pub model: PathBuf,
    /// The law file (JSON).
    #[cfg_attr(feature = "cli", arg(long, default_value = DEFAULT_LAW_FILE))]
    pub out: PathBuf,
    /// Width of the blend between the model and the power law outside its domain, as a
    /// fraction of each feature's training range, in (0, 0.5].
    #[cfg_attr(feature = "cli", arg(long, default_value_t = DEFAULT_BLEND_FRACTION))]
    pub blend_fraction: f64,
    /// Lower end of the μ clamp.
    #[cfg_attr(feature = "cli", arg(long, default_value_t = DEFAULT_MU_MIN))]
    pub mu_min: f64,
    /// Upper end of the μ clamp.
    #[cfg_attr(feature = "cli", arg(long, default_value_t = DEFAULT_MU_MAX))]
    pub mu_max: f64,
    /// No μ clamp at all.
    #[cfg_attr(feature = "cli", arg(long, conflicts_with_all = ["mu_min", "mu_max"]))]
    pub no_clamp: bool,
    /// Zorev's cap on the friction shear stress, τ ≤ k, MPa: the workpiece's shear flow
    /// stress (the demo's study: 600). Default: no cap, stated as `null` in the file.
    #[cfg_attr(feature = "cli", arg(long = "shear-cap-k-MPa"))]
    pub shear_cap_k_MPa: Option<f64>,
    /// Study TOML whose [contact] maps contact pressure to the model's normal-force feature
    /// (written into the law; it must agree with the model's own). Default: the map the model
    /// recorded from its training data.
    #[cfg_attr(feature = "cli", arg(long))]
    pub study: Option<PathBuf>,
}

impl Default for GreyBoxSettings {
    fn default() -> Self {
        GreyBoxSettings {
            model: PathBuf::new(),
            out: PathBuf::from(DEFAULT_LAW_FILE),
            blend_fraction: DEFAULT_BLEND_FRACTION,
            mu_min: DEFAULT_MU_MIN,
            mu_max: DEFAULT_MU_MAX,
            no_clamp: false,
            shear_cap_k_MPa: None,
            study: None,
        }
    }
}

impl GreyBoxSettings {
    /// The law these settings describe (not yet checked against its model).
    pub fn law(&self) -> Result<LawSpec> {
        if self.model.as_os_str().is_empty() {
            return Err(refused("law", "model", "give the fitted model file").into());
        }
        if !(self.blend_fraction > 0.0 && self.blend_fraction <= MAX_BLEND_FRACTION) {
            let why = format!(
                "expected a fraction in (0, {MAX_BLEND_FRACTION}], got {}",
                self.blend_fraction
            );
            return Err(refused("law", "blend_fraction", why).into());
        }
        let clamp = (!self.no_clamp).then_some((self.mu_min, self.mu_max));
        if let Some((lo, hi)) = clamp {
            if !(lo.is_finite() && hi.is_finite() && 0.0 <= lo && lo < hi) {
                let why = format!("expected 0 ≤ mu_min < mu_max, got {lo} and {hi}");
                return Err(refused_together("law", &["mu_min", "mu_max"], why).into());
            }
        }
        if let Some(k) = self.shear_cap_k_MPa {
            physics::admit_setting(
                Quantity::ShearFlowStress,
                mpa_to_pa(k),
                &SettingPath::new("law", "shear_cap_k_MPa"),
            )?;
        }
        let contact = match &self.study {
            Some(p) => Some(Study::load(p)?.contact),
            None => None,
        };
        let o = GreyBoxOptions {
            blend_fraction: self.blend_fraction,
            shear_cap_k_mpa: self.shear_cap_k_MPa,
            clamp,
        };
        Ok(grey_box_law(self.model.clone(), contact, &o))
    }

    /// Write the law file, after building the law (the model read, the power law fitted) so
    /// that a law that cannot run is refused here, not in a simulation; returns the law.
    pub fn write(&self) -> Result<LawSpec> {
        let law = self.law()?;
        let base = self.out.parent().unwrap_or(Path::new("."));
        // the law file must not replace the model it refers to (resolved as the law will)
        let model = base.join(&self.model);
        let mut inputs: Vec<(&str, &Path)> = vec![("model", &model)];
        if let Some(s) = &self.study {
            inputs.push(("study", s));
        }
        check_file_output(&self.out, "out", &inputs)?;
        law.build(base)?;
        write_law(&self.out, &law)?;
        Ok(law)
    }
}
