//! The steps a plan expects (pin, step, load, velocity and, where stated, duration), from a
//! greybox plan or a CSV of steps: what identification aligns its segments with.

use crate::plan::Plan;
use greybox_core::csvutil::{csv_error, parse_f64, parse_u32, record_line, Header};
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
    refuse_near_misses(&header, &source)?;
    let is = header.find("step");
    let id = header.find("duration_s");
    let mut out: Vec<ExpectedStep> = Vec::new();
    for (k, row) in rdr.records().enumerate() {
        let row = row.map_err(|e| csv_error(&source, e))?;
        let line = record_line(row.position(), k as u64 + 2);
        let pin = parse_u32(&row[ip], &source, line, "pin")?;
        let f = parse_f64(&row[inf], &source, line, "normal_force_N")?;
        let v = parse_f64(&row[iv], &source, line, "sliding_velocity_m_per_min")?;
        if !(f > 0.0) || !(v > 0.0) || pin == 0 {
            return Err(Error::input(
                SourcePos::file(&source).line(line),
                "pin must be ≥ 1, load and velocity positive",
            ));
        }
        let step = match is {
            Some(i) => parse_u32(&row[i], &source, line, "step")?,
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

/// Refuses a column that names a step duration other than as `duration_s` (`duration_sec`,
/// `Duration (s)`, `duration_min`): read as unknown it would be ignored, and the plan taken
/// without the timing the user meant it to give (the alignment and the cut at the plan's
/// timing use it). Other columns (a greybox plan sheet's `step_start_s`, comments, a rig's
/// own ids) are left alone.
fn refuse_near_misses(header: &Header, source: &str) -> Result<()> {
    for name in header.names() {
        if name != "duration_s" && name.trim().to_ascii_lowercase().starts_with("duration") {
            return Err(Error::input(
                SourcePos::file(source).line(1).field(name.clone()),
                format!(
                    "column '{name}' is not read: a step's planned duration is the column 'duration_s', in seconds"
                ),
            ));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read(text: &str) -> Result<Vec<ExpectedStep>> {
        let d = tempfile::tempdir().unwrap();
        let p = d.path().join("plan.csv");
        std::fs::write(&p, text).unwrap();
        read_expected_steps(&p)
    }

    #[test]
    fn pin_and_step_numbers_never_wrap() {
        let head = "pin,step,normal_force_N,sliding_velocity_m_per_min\n";
        let e = read(&format!("{head}4294967297,1,100,60\n"))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("plan.csv") && e.contains("pin") && e.contains("4294967297"),
            "{e}"
        );
        let e = read(&format!("{head}1,4294967296,100,60\n"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("step") && e.contains("4294967296"), "{e}");
        let ok = read(&format!("{head}4294967295,2,100,60\n")).unwrap();
        assert_eq!((ok[0].pin, ok[0].step), (u32::MAX, 2));
    }

    #[test]
    fn a_misspelled_duration_is_refused_other_columns_are_not() {
        let e = read("pin,normal_force_N,sliding_velocity_m_per_min,duration_sec\n1,100,60,30\n")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("'duration_sec'") && e.contains("'duration_s'"),
            "{e}"
        );
        // a greybox plan sheet's own columns are read as a plan
        let ok = read("pin,step,normal_force_N,sliding_velocity_m_per_min,spindle_rpm,step_start_s\n1,1,100,60,955,0\n")
            .unwrap();
        assert_eq!(ok[0].duration_s, None);
        let ok = read("pin,normal_force_N,sliding_velocity_m_per_min,duration_s\n1,100,60,30\n")
            .unwrap();
        assert_eq!(ok[0].duration_s, Some(30.0));
    }
}
