//! Tribometer campaign plans: the article's full-factorial design (digest §1) and its timing.
//!
//! One pin per normal load; on each pin the spindle steps through the sliding velocities.
//! Timeline of one pin, seconds after the recording trigger switches on (t = 0):
//!
//! ```text
//! [0, zero)            pin unloaded: force offsets for drift compensation
//! [zero, zero+load)    normal load applied
//! step k:  S command at t_k; spindle ramps |n_k − n_{k−1}| / accel; plateau dwell; t_{k+1}
//! stop:    spindle stop, ramp-down n_last / accel, unload (load time), unloaded (zero time)
//! end:     trigger off
//! ```
//! Spindle speed for velocity v on track radius R: n = v / (2 π R).

use greybox_core::count::Count;
use greybox_core::{units, Error, Result};
use serde::{Deserialize, Serialize};

/// Normal forces (pins) of a plan.
pub type PinCount = Count<1, 1_000_000>;
/// Sliding velocities (steps per pin) of a plan.
pub type VelocityCount = Count<1, 100_000>;
/// Steps of a whole plan (pins × velocities): each is a run-sheet row and NC blocks.
pub type StepCount = Count<1, 10_000_000>;

/// A campaign as the user states it. Field names carry their units (study TOML `[plan]`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct PlanSpec {
    /// Smallest normal force, N (equidistant series).
    #[serde(rename = "normal_force_min_N")]
    pub normal_force_min_n: f64,
    /// Largest normal force, N.
    #[serde(rename = "normal_force_max_N")]
    pub normal_force_max_n: f64,
    /// Number of normal forces (= number of pins).
    pub normal_force_count: PinCount,
    /// Explicit list of normal forces, N; replaces the equidistant series when given.
    #[serde(rename = "normal_forces_N", skip_serializing_if = "Option::is_none")]
    pub normal_forces_n: Option<Vec<f64>>,
    pub velocity_min_m_per_min: f64,
    pub velocity_max_m_per_min: f64,
    pub velocity_count: VelocityCount,
    /// Explicit list of sliding velocities, m/min; replaces the equidistant series when given.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub velocities_m_per_min: Option<Vec<f64>>,
    /// Dwell at each velocity after the spindle reached it, s.
    pub dwell_s: f64,
    /// Radius of the pin's track on the disk, mm (no default: it depends on the rig).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub track_radius_mm: Option<f64>,
    /// Spindle acceleration used for nominal ramp times, rpm/s.
    pub spindle_accel_rpm_per_s: f64,
    /// Highest spindle speed the machine allows, rpm.
    pub max_spindle_rpm: f64,
    /// Unloaded time at the start and end of each pin (offset/drift reference), s.
    pub zero_time_s: f64,
    /// Time to apply or release the normal load, s.
    pub load_time_s: f64,
    /// M-code that switches the recording trigger on.
    pub trigger_on_mcode: u32,
    /// M-code that switches the recording trigger off.
    pub trigger_off_mcode: u32,
    /// Decimal places of the S word (spindle rpm) in the NC program.
    pub rpm_decimals: u32,
}

impl Default for PlanSpec {
    /// The article's design: 10 loads 150–2000 N, 21 velocities 20–250 m/min, 0.5 s dwell.
    fn default() -> Self {
        PlanSpec {
            normal_force_min_n: 150.0,
            normal_force_max_n: 2000.0,
            normal_force_count: PinCount::of(10),
            normal_forces_n: None,
            velocity_min_m_per_min: 20.0,
            velocity_max_m_per_min: 250.0,
            velocity_count: VelocityCount::of(21),
            velocities_m_per_min: None,
            dwell_s: 0.5,
            track_radius_mm: None,
            spindle_accel_rpm_per_s: 100.0,
            max_spindle_rpm: 3000.0,
            zero_time_s: 1.0,
            load_time_s: 1.0,
            trigger_on_mcode: 62,
            trigger_off_mcode: 63,
            rpm_decimals: 2,
        }
    }
}

/// One velocity step of one pin; times in seconds after the trigger.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PlanStep {
    /// Pin number, 1-based (one pin per normal force).
    pub pin: u32,
    /// Step number within the pin, 1-based.
    pub step: u32,
    pub normal_force_n: f64,
    /// Planned sliding velocity, m/s.
    pub sliding_velocity_m_s: f64,
    /// Commanded spindle speed (rounded as written to the NC program), rpm.
    pub spindle_rpm: f64,
    /// Time of the S command, s.
    pub step_start_s: f64,
    /// Nominal end of the spindle ramp = start of the plateau, s.
    pub plateau_start_s: f64,
    /// End of the plateau (next S command), s.
    pub plateau_end_s: f64,
}

/// Per-pin schedule of the phases around the velocity steps.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PinSchedule {
    pub pin: u32,
    pub normal_force_n: f64,
    /// Load application starts, s.
    pub load_start_s: f64,
    /// Spindle stop command, s.
    pub spindle_stop_s: f64,
    /// Unloading starts (spindle at rest), s.
    pub unload_start_s: f64,
    /// Trigger off, end of the recording, s.
    pub end_s: f64,
}

/// A validated plan with every step's nominal timing.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Plan {
    pub spec: PlanSpec,
    pub pins: Vec<PinSchedule>,
    pub steps: Vec<PlanStep>,
}

fn equidistant(min: f64, max: f64, count: usize) -> Vec<f64> {
    if count == 1 {
        return vec![min];
    }
    (0..count)
        .map(|i| min + (max - min) * i as f64 / (count - 1) as f64)
        .collect()
}

fn check_series(
    what: &str,
    unit: &str,
    min: f64,
    max: f64,
    count: usize, // ≥ 1: a PinCount or VelocityCount
    list: &Option<Vec<f64>>,
) -> Result<Vec<f64>> {
    let values = match list {
        Some(l) => {
            if l.is_empty() {
                return Err(Error::invalid(
                    "plan",
                    format!("the list of {what} is empty"),
                ));
            }
            l.clone()
        }
        None => {
            if !(min.is_finite() && max.is_finite()) || max < min {
                return Err(Error::invalid(
                    "plan",
                    format!("{what}: empty range {min}..{max} {unit} (max must be ≥ min)"),
                ));
            }
            if count == 1 && max != min {
                return Err(Error::invalid(
                    "plan",
                    format!("{what}: a count of 1 needs min = max, got {min}..{max} {unit}"),
                ));
            }
            equidistant(min, max, count)
        }
    };
    for v in &values {
        if !(v.is_finite() && *v > 0.0) {
            return Err(Error::invalid(
                "plan",
                format!("{what} must be positive, got {v} {unit}"),
            ));
        }
    }
    Ok(values)
}

fn round_to(x: f64, decimals: u32) -> f64 {
    let s = 10f64.powi(decimals as i32);
    (x * s).round() / s
}

impl PlanSpec {
    /// The normal forces of the plan, N.
    pub fn normal_forces(&self) -> Result<Vec<f64>> {
        check_series(
            "normal forces",
            "N",
            self.normal_force_min_n,
            self.normal_force_max_n,
            self.normal_force_count.get(),
            &self.normal_forces_n,
        )
    }
    /// The sliding velocities of the plan, m/min.
    pub fn velocities_m_per_min(&self) -> Result<Vec<f64>> {
        check_series(
            "sliding velocities",
            "m/min",
            self.velocity_min_m_per_min,
            self.velocity_max_m_per_min,
            self.velocity_count.get(),
            &self.velocities_m_per_min,
        )
    }
    pub fn track_radius_m(&self) -> Result<f64> {
        match self.track_radius_mm {
            Some(r) if r.is_finite() && r > 0.0 => {
                let m = r * units::M_PER_MM;
                greybox_core::physics::check(
                    greybox_core::physics::Quantity::TrackRadius,
                    m,
                    "track_radius_mm",
                )
                .map_err(|e| Error::invalid("plan", e))?;
                Ok(m)
            }
            Some(r) => Err(Error::invalid(
                "plan",
                format!("track radius must be positive, got {r} mm"),
            )),
            None => Err(Error::invalid(
                "plan",
                "the track radius is required (`track_radius_mm`)",
            )),
        }
    }
    /// Nominal spindle ramp time between two speeds, s.
    pub fn ramp_time_s(&self, from_rpm: f64, to_rpm: f64) -> f64 {
        (to_rpm - from_rpm).abs() / self.spindle_accel_rpm_per_s
    }
    /// Commanded spindle speed for a velocity (m/min), rounded to `rpm_decimals`.
    pub fn commanded_rpm(&self, velocity_m_per_min: f64, radius_m: f64) -> f64 {
        round_to(
            units::rpm_for_velocity(units::m_per_min_to_m_per_s(velocity_m_per_min), radius_m),
            self.rpm_decimals,
        )
    }

    /// Validate and derive every step's timing.
    pub fn build(&self) -> Result<Plan> {
        let forces = self.normal_forces()?;
        let velocities = self.velocities_m_per_min()?;
        StepCount::of_usize(
            forces.len().saturating_mul(velocities.len()),
            "plan steps (normal forces × velocities)",
        )
        .map_err(|e| Error::invalid("plan", e))?;
        let radius = self.track_radius_m()?;
        self.check_machine()?;
        let rpms = self.commanded_rpms(&velocities, radius)?;
        let mut steps = Vec::with_capacity(forces.len() * velocities.len());
        let mut pins = Vec::with_capacity(forces.len());
        for (ip, &force) in forces.iter().enumerate() {
            let pin = ip as u32 + 1;
            let load_start = self.zero_time_s;
            let mut t = self.zero_time_s + self.load_time_s;
            let mut prev_rpm = 0.0;
            for (iv, (&v, &n)) in velocities.iter().zip(&rpms).enumerate() {
                let plateau_start = t + self.ramp_time_s(prev_rpm, n);
                let plateau_end = plateau_start + self.dwell_s;
                steps.push(PlanStep {
                    pin,
                    step: iv as u32 + 1,
                    normal_force_n: force,
                    sliding_velocity_m_s: units::m_per_min_to_m_per_s(v),
                    spindle_rpm: n,
                    step_start_s: t,
                    plateau_start_s: plateau_start,
                    plateau_end_s: plateau_end,
                });
                t = plateau_end;
                prev_rpm = n;
            }
            let unload = t + self.ramp_time_s(prev_rpm, 0.0);
            pins.push(PinSchedule {
                pin,
                normal_force_n: force,
                load_start_s: load_start,
                spindle_stop_s: t,
                unload_start_s: unload,
                end_s: unload + self.load_time_s + self.zero_time_s,
            });
        }
        Ok(Plan {
            spec: self.clone(),
            pins,
            steps,
        })
    }

    /// Check the machine settings: dwell, acceleration, spindle limit and load times
    /// positive, `rpm_decimals` 0..4, and trigger M-codes that differ and are not standard.
    fn check_machine(&self) -> Result<()> {
        let positive = |name: &str, v: f64, unit: &str| -> Result<()> {
            if v.is_finite() && v > 0.0 {
                Ok(())
            } else {
                Err(Error::invalid(
                    "plan",
                    format!("{name} must be positive, got {v} {unit}"),
                ))
            }
        };
        positive("dwell_s", self.dwell_s, "s")?;
        positive(
            "spindle_accel_rpm_per_s",
            self.spindle_accel_rpm_per_s,
            "rpm/s",
        )?;
        positive("max_spindle_rpm", self.max_spindle_rpm, "rpm")?;
        positive("zero_time_s", self.zero_time_s, "s")?;
        positive("load_time_s", self.load_time_s, "s")?;
        if self.rpm_decimals > 4 {
            return Err(Error::invalid(
                "plan",
                format!("rpm_decimals must be 0..4, got {}", self.rpm_decimals),
            ));
        }
        if self.trigger_on_mcode == self.trigger_off_mcode {
            return Err(Error::invalid(
                "plan",
                "trigger on and off M-codes must differ",
            ));
        }
        for m in [self.trigger_on_mcode, self.trigger_off_mcode] {
            if matches!(m, 0..=6 | 30) {
                return Err(Error::invalid("plan", format!("M{m} is a standard M-code (stop/spindle/end); choose another for the trigger")));
            }
        }
        Ok(())
    }

    /// The commanded spindle speed of each velocity on a track of `radius` m, refused above
    /// the spindle limit or when it rounds to 0 rpm.
    fn commanded_rpms(&self, velocities: &[f64], radius: f64) -> Result<Vec<f64>> {
        let rpms: Vec<f64> = velocities
            .iter()
            .map(|&v| self.commanded_rpm(v, radius))
            .collect();
        for (v, n) in velocities.iter().zip(&rpms) {
            if *n > self.max_spindle_rpm {
                return Err(Error::invalid(
                    "plan",
                    format!(
                        "{v} m/min on a {} mm track needs {n} rpm, above the spindle limit of {} rpm",
                        radius / units::M_PER_MM,
                        self.max_spindle_rpm
                    ),
                ));
            }
            if *n <= 0.0 {
                return Err(Error::invalid(
                    "plan",
                    format!("{v} m/min rounds to 0 rpm; raise rpm_decimals"),
                ));
            }
        }
        Ok(rpms)
    }
}

impl Plan {
    /// Steps of one pin (1-based), in order.
    pub fn pin_steps(&self, pin: u32) -> &[PlanStep] {
        let n = self.velocity_count();
        let start = (pin as usize - 1) * n;
        &self.steps[start..start + n]
    }
    pub fn velocity_count(&self) -> usize {
        self.steps.len() / self.pins.len()
    }
    pub fn track_radius_m(&self) -> f64 {
        self.spec.track_radius_m().expect("validated plan")
    }

    /// Write the run sheet CSV (one row per step) atomically.
    pub fn write_run_sheet(&self, path: &std::path::Path) -> Result<()> {
        greybox_core::atomic::write_atomic(path, |w| {
            writeln!(
                w,
                "pin,step,normal_force_N,sliding_velocity_m_per_min,spindle_rpm,step_start_s,plateau_start_s,plateau_end_s,pin_end_s"
            )?;
            for s in &self.steps {
                let pin = &self.pins[s.pin as usize - 1];
                writeln!(
                    w,
                    "{},{},{},{},{},{:.4},{:.4},{:.4},{:.4}",
                    s.pin,
                    s.step,
                    s.normal_force_n,
                    units::m_per_s_to_m_per_min(s.sliding_velocity_m_s),
                    s.spindle_rpm,
                    s.step_start_s,
                    s.plateau_start_s,
                    s.plateau_end_s,
                    pin.end_s
                )?;
            }
            Ok(())
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    pub(crate) fn article_spec() -> PlanSpec {
        PlanSpec {
            track_radius_mm: Some(100.0),
            ..Default::default()
        }
    }

    #[test]
    fn article_design() {
        let plan = article_spec().build().unwrap();
        assert_eq!(plan.pins.len(), 10);
        assert_eq!(plan.steps.len(), 210);
        let forces: Vec<f64> = plan.pins.iter().map(|p| p.normal_force_n).collect();
        let expected = [
            150.0, 355.6, 561.1, 766.7, 972.2, 1177.8, 1383.3, 1588.9, 1794.4, 2000.0,
        ];
        for (f, e) in forces.iter().zip(expected) {
            assert!((f - e).abs() < 0.05, "{f} vs {e}");
        }
        let v: Vec<f64> = plan
            .pin_steps(1)
            .iter()
            .map(|s| units::m_per_s_to_m_per_min(s.sliding_velocity_m_s))
            .collect();
        assert!((v[1] - v[0] - 11.5).abs() < 1e-9);
        assert!((v[20] - 250.0).abs() < 1e-9);
        // n = v / (2πR): 20 m/min on R = 100 mm → 31.83 rpm; 250 m/min → 397.89 rpm
        assert_eq!(plan.steps[0].spindle_rpm, 31.83);
        assert_eq!(plan.steps[20].spindle_rpm, 397.89);
        // dwell and ramp: first ramp 0 → 31.83 rpm at 100 rpm/s
        let s = &plan.steps[0];
        assert!((s.plateau_start_s - s.step_start_s - 31.83 / 100.0).abs() < 1e-9);
        assert!((s.plateau_end_s - s.plateau_start_s - 0.5).abs() < 1e-12);
    }

    #[test]
    fn rejects_impossible_plans() {
        let e = PlanSpec {
            track_radius_mm: Some(1.0),
            ..Default::default()
        }
        .build()
        .unwrap_err()
        .to_string();
        assert!(e.contains("above the spindle limit"), "{e}");
        let e = PlanSpec::default().build().unwrap_err().to_string();
        assert!(e.contains("track radius is required"), "{e}");
        let e = PlanSpec {
            normal_force_min_n: -5.0,
            ..article_spec()
        }
        .build()
        .unwrap_err()
        .to_string();
        assert!(e.contains("must be positive"), "{e}");
        let e = serde_json::from_str::<PlanSpec>(r#"{"velocity_count": 0}"#)
            .unwrap_err()
            .to_string();
        assert!(e.contains("0 is below the least allowed 1"), "{e}");
        let e = serde_json::from_str::<PlanSpec>(r#"{"normal_force_count": 1000000000}"#)
            .unwrap_err()
            .to_string();
        assert!(e.contains("above the cap of 1000000"), "{e}");
        let e = PlanSpec {
            normal_force_count: PinCount::of(1_000_000),
            velocity_count: VelocityCount::of(100),
            ..article_spec()
        }
        .build()
        .unwrap_err()
        .to_string();
        assert!(
            e.contains(
                "plan steps (normal forces × velocities): 100000000 is above the cap of 10000000"
            ),
            "{e}"
        );
        let e = PlanSpec {
            velocity_min_m_per_min: 300.0,
            ..article_spec()
        }
        .build()
        .unwrap_err()
        .to_string();
        assert!(e.contains("empty range"), "{e}");
        let e = PlanSpec {
            dwell_s: 0.0,
            ..article_spec()
        }
        .build()
        .unwrap_err()
        .to_string();
        assert!(e.contains("dwell_s"), "{e}");
        let e = PlanSpec {
            normal_forces_n: Some(vec![]),
            ..article_spec()
        }
        .build()
        .unwrap_err()
        .to_string();
        assert!(e.contains("empty"), "{e}");
        let e = PlanSpec {
            trigger_on_mcode: 3,
            ..article_spec()
        }
        .build()
        .unwrap_err()
        .to_string();
        assert!(e.contains("standard M-code"), "{e}");
    }
}
