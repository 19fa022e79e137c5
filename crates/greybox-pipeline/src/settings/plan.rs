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
//! assert!(s.stated_in(&study).campaign());
//! let none = PlanSettings::default();
//! assert!(!none.stated_in(&none.study()?).campaign());
//! # Ok::<(), anyhow::Error>(())
//! ```

use crate::study::Study;
use anyhow::Result;
use greybox_tribo::plan::{PinCount, VelocityCount};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// The `[plan]` keys that state the normal loads.
const LOAD_KEYS: [&str; 4] = [
    "normal_force_min_N",
    "normal_force_max_N",
    "normal_force_count",
    "normal_forces_N",
];
/// The `[plan]` keys that state the sliding velocities.
const VELOCITY_KEYS: [&str; 4] = [
    "velocity_min_m_per_min",
    "velocity_max_m_per_min",
    "velocity_count",
    "velocities_m_per_min",
];

/// What of a plan the user stated (flags or the study's `[plan]`); the rest is the article's.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct StatedPlan {
    /// The normal loads (a range, a count or a list).
    pub loads: bool,
    /// The sliding velocities (a range, a count or a list).
    pub velocities: bool,
    /// The track radius on the disk.
    pub track_radius: bool,
}

impl StatedPlan {
    /// A campaign to align recordings against: its loads or its velocities are stated.
    pub fn campaign(&self) -> bool {
        self.loads || self.velocities
    }
    /// Anything stated at all.
    pub fn any(&self) -> bool {
        self.campaign() || self.track_radius
    }
}

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

    /// What of the plan is stated, here or in the study's `[plan]`, rather than filled in
    /// by the article's defaults. The one answer to "is a plan given": identification
    /// aligns against a plan only when its loads or velocities are stated
    /// ([`StatedPlan::campaign`]); the excitation check needs the velocities and the track
    /// radius and says when the velocities are the article's.
    ///
    /// `study` is the one these settings read ([`Self::study`]): its file's `[plan]` keys
    /// come with it, so the file is read once.
    pub fn stated_in(&self, study: &Study) -> StatedPlan {
        let in_study = &study.declared_plan_keys;
        let study_names = |keys: &[&str]| in_study.iter().any(|k| keys.contains(&k.as_str()));
        StatedPlan {
            loads: self.sets_loads() || study_names(&LOAD_KEYS),
            velocities: self.sets_velocities() || study_names(&VELOCITY_KEYS),
            track_radius: self.track_radius_mm.is_some() || study_names(&["track_radius_mm"]),
        }
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

#[cfg(test)]
mod tests {
    use super::*;

    fn study(text: &str) -> (tempfile::TempDir, PathBuf) {
        let d = tempfile::tempdir().unwrap();
        let p = d.path().join("study.toml");
        std::fs::write(&p, text).unwrap();
        (d, p)
    }

    #[test]
    fn a_plan_is_given_by_its_loads_or_velocities_not_by_a_radius() {
        let radius_only = PlanSettings {
            track_radius_mm: Some(80.0),
            ..Default::default()
        };
        let stated = |p: &PlanSettings| p.stated_in(&p.study().unwrap());
        let s = stated(&radius_only);
        assert!(s.any() && s.track_radius && !s.campaign());
        let (_d, p) = study("[plan]\ntrack_radius_mm = 80.0\ndwell_s = 1.0\n");
        let in_study = PlanSettings {
            study: Some(p),
            ..Default::default()
        };
        let s = stated(&in_study);
        assert_eq!((s.track_radius, s.campaign()), (true, false));
        let (_d, p) = study("[plan]\nvelocities_m_per_min = [20.0, 40.0]\n");
        let speeds = PlanSettings {
            study: Some(p),
            ..Default::default()
        };
        let s = stated(&speeds);
        assert_eq!(
            (s.velocities, s.loads, s.track_radius),
            (true, false, false)
        );
        assert!(s.campaign());
        let loads = PlanSettings {
            normal_force_count: Some(PinCount::of(3)),
            ..Default::default()
        };
        assert!(stated(&loads).loads);
        assert!(!stated(&PlanSettings::default()).any());
        // The keys come from the file the study was read from, not from a second reading.
        let (d, p) = study("[plan]\nnormal_forces_N = [10.0, 20.0]\n");
        let from_file = PlanSettings {
            study: Some(p.clone()),
            ..Default::default()
        };
        let read = from_file.study().unwrap();
        std::fs::write(&p, "[plan]\ndwell_s = 1.0\n").unwrap();
        assert!(from_file.stated_in(&read).loads);
        drop(d);
    }
}
