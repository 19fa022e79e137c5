//! The steps a plan expects (pin, step, load, velocity and, where stated, duration), from a
//! greybox plan or a CSV of steps: what identification aligns its segments with.

use crate::plan::Plan;
use greybox_core::csvutil::{csv_error, parse_f64, parse_u64, record_line, Header};
use greybox_core::units;
use greybox_core::{Error, Result, SourcePos};
use serde::Serialize;

/// One step a plan expects: pin, step, load, velocity and, where the plan states it, the
/// step's duration (ramp and dwell).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ExpectedStep {
    pub pin: u32,
    pub step: u32,
    pub normal_force_n: f64,
    pub sliding_velocity_m_s: f64,
    /// Planned duration of the step from the start of its ramp to the end of its dwell, s.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub duration_s: Option<f64>,
}

/// The steps of a greybox plan, in run order.
pub fn expected_from_plan(plan: &Plan) -> Vec<ExpectedStep> {
    plan.steps
        .iter()
        .map(|s| ExpectedStep {
            pin: s.pin,
            step: s.step,
            normal_force_n: s.normal_force_n,
            sliding_velocity_m_s: s.sliding_velocity_m_s,
            duration_s: Some(s.plateau_end_s - s.step_start_s),
        })
        .collect()
}

/// Read expected steps from a CSV in run order: `pin, normal_force_N,
/// sliding_velocity_m_per_min`, optionally `step` (default: numbered per pin) and
/// `duration_s` (the step's planned duration, ramp and dwell: the alignment then uses it,
/// and a sliding run without a speed channel is cut at the plan's timing).
pub fn read_expected_steps(path: &std::path::Path) -> Result<Vec<ExpectedStep>> {
    let source = path.display().to_string();
    let mut rdr = greybox_core::input::data_csv(
        path,
        "expected-steps table",
        csv::ReaderBuilder::new().trim(csv::Trim::All),
    )?;
    let header = Header::new(&source, rdr.headers().map_err(|e| csv_error(&source, e))?);
    let (ip, inf, iv) = (
        header.require("pin")?,
        header.require("normal_force_N")?,
        header.require("sliding_velocity_m_per_min")?,
    );
    let is = header.find("step");
    let id = header.find("duration_s");
    let mut out: Vec<ExpectedStep> = Vec::new();
    for (k, row) in rdr.records().enumerate() {
        let row = row.map_err(|e| csv_error(&source, e))?;
        let line = record_line(row.position(), k as u64 + 2);
        let pin = parse_u64(&row[ip], &source, line, "pin")? as u32;
        let f = parse_f64(&row[inf], &source, line, "normal_force_N")?;
        let v = parse_f64(&row[iv], &source, line, "sliding_velocity_m_per_min")?;
        if !(f > 0.0) || !(v > 0.0) || pin == 0 {
            return Err(Error::input(
                SourcePos::file(&source).line(line),
                "pin must be ≥ 1, load and velocity positive",
            ));
        }
        let step = match is {
            Some(i) => parse_u64(&row[i], &source, line, "step")? as u32,
            None => out.iter().filter(|s| s.pin == pin).count() as u32 + 1,
        };
        let duration_s = match id {
            Some(i) => {
                let d = parse_f64(&row[i], &source, line, "duration_s")?;
                if !(d > 0.0) {
                    return Err(Error::input(
                        SourcePos::file(&source).line(line).field("duration_s"),
                        format!("a step's duration must be positive, got {d}"),
                    ));
                }
                Some(d)
            }
            None => None,
        };
        out.push(ExpectedStep {
            pin,
            step,
            normal_force_n: f,
            sliding_velocity_m_s: units::m_per_min_to_m_per_s(v),
            duration_s,
        });
    }
    if out.is_empty() {
        return Err(Error::input(
            SourcePos::file(&source),
            "no steps in the file",
        ));
    }
    Ok(out)
}
