//! A study file and overrides of its `[plan]` section, as the stages that build a plan
//! (plan, synth, identify, characterize) take them. The names (serde) are the `[plan]` keys.
//!
//! ```
//! use greybox_pipeline::settings::plan::PlanSettings;
//! use greybox_tribo::plan::PinCount;
//! let s = PlanSettings { normal_force_count: Some(PinCount::of(2)), velocity_max_m_per_min: Some(200.0),
//!     ..Default::default() };
//! let study = s.study()?;
//! assert_eq!((study.plan.normal_force_count.get(), study.plan.velocity_max_m_per_min), (2, 200.0));
//! assert!(s.gives_plan()?);
//! assert!(!PlanSettings::default().gives_plan()?);
//! # Ok::<(), anyhow::Error>(())
//! ```

use crate::study::Study;
use anyhow::Result;
use greybox_tribo::plan::{PinCount, VelocityCount};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// A study file and overrides of its `[plan]`; `None` keeps the study's value.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "cli", derive(clap::Args))]
#[serde(deny_unknown_fields, default)]
#[allow(non_snake_case)]
pub struct PlanSettings {
    /// Study TOML ([plan], [contact], …); the settings below override it.
    #[cfg_attr(feature = "cli", arg(long))]
    pub study: Option<PathBuf>,
    /// Track radius on the disk, mm (required unless the study gives it).
    #[cfg_attr(feature = "cli", arg(long = "track-radius-mm"))]
    pub track_radius_mm: Option<f64>,
    /// Smallest normal force, N.
    #[cfg_attr(feature = "cli", arg(long = "normal-force-min-N"))]
    pub normal_force_min_N: Option<f64>,
    /// Largest normal force, N.
    #[cfg_attr(feature = "cli", arg(long = "normal-force-max-N"))]
    pub normal_force_max_N: Option<f64>,
    /// Number of normal forces (one pin each).
    #[cfg_attr(feature = "cli", arg(long = "normal-force-count"))]
    pub normal_force_count: Option<PinCount>,
    /// Lowest sliding velocity, m/min.
    #[cfg_attr(feature = "cli", arg(long = "velocity-min-m-per-min"))]
    pub velocity_min_m_per_min: Option<f64>,
    /// Highest sliding velocity, m/min.
    #[cfg_attr(feature = "cli", arg(long = "velocity-max-m-per-min"))]
    pub velocity_max_m_per_min: Option<f64>,
    /// Number of sliding velocities.
    #[cfg_attr(feature = "cli", arg(long = "velocity-count"))]
    pub velocity_count: Option<VelocityCount>,
    /// Dwell per velocity once the spindle reached it, s.
    #[cfg_attr(feature = "cli", arg(long = "dwell-s"))]
    pub dwell_s: Option<f64>,
    /// Nominal spindle acceleration, rpm/s.
    #[cfg_attr(feature = "cli", arg(long = "spindle-accel-rpm-per-s"))]
    pub spindle_accel_rpm_per_s: Option<f64>,
    /// Spindle speed limit, rpm.
    #[cfg_attr(feature = "cli", arg(long = "max-spindle-rpm"))]
    pub max_spindle_rpm: Option<f64>,
    /// M-code switching the recording trigger on.
    #[cfg_attr(feature = "cli", arg(long = "trigger-on-mcode"))]
    pub trigger_on_mcode: Option<u32>,
    /// M-code switching the recording trigger off.
    #[cfg_attr(feature = "cli", arg(long = "trigger-off-mcode"))]
    pub trigger_off_mcode: Option<u32>,
}

impl PlanSettings {
    /// The study (or the default one) with these overrides; a new load or velocity range
    /// replaces the study's explicit lists.
    pub fn study(&self) -> Result<Study> {
        self.study_over(Study::default())
    }

    /// The study file, else `base`, with these overrides.
    pub fn study_over(&self, base: Study) -> Result<Study> {
        let mut s = match &self.study {
            Some(path) => Study::load(path)?,
            None => base,
        };
        let p = &mut s.plan;
        fn set<T: Copy>(dst: &mut T, src: Option<T>) {
            if let Some(v) = src {
                *dst = v;
            }
        }
        if self.track_radius_mm.is_some() {
            p.track_radius_mm = self.track_radius_mm;
        }
        set(&mut p.normal_force_min_n, self.normal_force_min_N);
        set(&mut p.normal_force_max_n, self.normal_force_max_N);
        set(&mut p.normal_force_count, self.normal_force_count);
        set(&mut p.velocity_min_m_per_min, self.velocity_min_m_per_min);
        set(&mut p.velocity_max_m_per_min, self.velocity_max_m_per_min);
        set(&mut p.velocity_count, self.velocity_count);
        set(&mut p.dwell_s, self.dwell_s);
        set(&mut p.spindle_accel_rpm_per_s, self.spindle_accel_rpm_per_s);
        set(&mut p.max_spindle_rpm, self.max_spindle_rpm);
        set(&mut p.trigger_on_mcode, self.trigger_on_mcode);
        set(&mut p.trigger_off_mcode, self.trigger_off_mcode);
        if self.sets_loads() {
            p.normal_forces_n = None;
        }
        if self.sets_velocities() {
            p.velocities_m_per_min = None;
        }
        Ok(s)
    }

    fn sets_loads(&self) -> bool {
        self.normal_force_min_N.is_some()
            || self.normal_force_max_N.is_some()
            || self.normal_force_count.is_some()
    }

    fn sets_velocities(&self) -> bool {
        self.velocity_min_m_per_min.is_some()
            || self.velocity_max_m_per_min.is_some()
            || self.velocity_count.is_some()
    }

    /// Whether a plan is given: a `[plan]` section in the study, or a load or velocity range.
    pub fn gives_plan(&self) -> Result<bool> {
        let in_study = match &self.study {
            Some(path) => Study::declares_plan(path)?,
            None => false,
        };
        Ok(self.sets_loads() || self.sets_velocities() || in_study)
    }

    /// The study file as a stage input, for the provenance (when given).
    pub fn inputs(&self) -> Vec<(&'static str, &Path)> {
        self.study
            .as_deref()
            .map(|p| ("study", p))
            .into_iter()
            .collect()
    }
}
