//! Stage 5: the grey-box friction law around a fitted model — the learned model inside its
//! training domain, a fitted power law outside, a smooth blend between them, Zorev's shear
//! cap and a clamp (digest §6).

use anyhow::Result;
use greybox_contact::PinContact;
use greybox_core::atomic::write_string_atomic;
use greybox_friction::spec::LawSpec;
use greybox_learn::protocol::{FamilyReport, FitReport};
use std::path::{Path, PathBuf};

/// The family with the best held-out R² (nested cross-validation); families without
/// held-out metrics rank last.
pub fn best_family(report: &FitReport) -> Option<&FamilyReport> {
    report.families.iter().max_by(|a, b| {
        let r2 = |f: &FamilyReport| {
            f.held_out
                .as_ref()
                .map(|h| h.metrics.r2.value)
                .unwrap_or(f64::NEG_INFINITY)
        };
        r2(a).total_cmp(&r2(b))
    })
}

/// The grey-box law's settings around the learned model.
#[derive(Debug, Clone, PartialEq)]
pub struct GreyBoxOptions {
    /// Width of the blend between model and power law, as a fraction of each feature's
    /// training range.
    pub blend_fraction: f64,
    /// Zorev's cap τ ≤ k on the friction shear stress, MPa.
    pub shear_cap_k_mpa: Option<f64>,
    /// μ is kept within (min, max).
    pub clamp: Option<(f64, f64)>,
}

impl Default for GreyBoxOptions {
    /// A 10 % blend, no shear cap, μ within 0.05–1.0.
    fn default() -> Self {
        GreyBoxOptions {
            blend_fraction: greybox_friction::greybox::DEFAULT_BLEND_FRACTION,
            shear_cap_k_mpa: None,
            clamp: Some((0.05, 1.0)),
        }
    }
}

/// The grey-box law around the model file `model` (a path as the law file will hold it:
/// relative paths are resolved against the law file's folder), trained on data measured
/// with `contact` (how its force feature maps to contact pressure); a power law fitted to
/// the model's training data outside its domain.
///
/// ```
/// use greybox_pipeline::law::{grey_box_law, GreyBoxOptions};
/// let law = grey_box_law("fit/models/svr.json".into(), None, &GreyBoxOptions::default());
/// let json = serde_json::to_value(&law).unwrap();
/// assert_eq!(json["law"], "grey-box");
/// assert_eq!(json["inner"]["model"], "fit/models/svr.json");
/// assert_eq!(json["outside"]["law"], "power-fit");
/// ```
pub fn grey_box_law(model: PathBuf, contact: Option<PinContact>, o: &GreyBoxOptions) -> LawSpec {
    LawSpec::GreyBox {
        inner: Box::new(LawSpec::Learned { model, contact }),
        outside: Box::new(LawSpec::PowerFit),
        blend_fraction: o.blend_fraction,
        shear_cap_k_mpa: o.shear_cap_k_mpa,
        clamp: o.clamp,
    }
}

/// Write a law file (JSON), atomically.
pub fn write_law(path: &Path, law: &LawSpec) -> Result<()> {
    write_string_atomic(path, &serde_json::to_string_pretty(law)?)?;
    Ok(())
}
