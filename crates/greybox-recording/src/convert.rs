//! A table converted into a [`Recording`]: channels in SI, time made continuous, forces by the
//! rig's convention, steps and speed, and the reader's warnings.

use super::assign::{assign_roles, drop_unitless_optional};
use super::channel_map::ChannelMap;
use super::diagnosis::{unresolved, unresolved_error};
use super::roles::{check_unit, example_unit, same_unit, unit_factor, Role};
use super::types::{FoundBy, MappedColumn, ReadReport, Recording, SpeedTrace};
use super::unitless::{assume_friction_unit, cof_disagreement, settle_assumed, unused_columns};
use crate::table::{Column, Table};
use greybox_core::physics::Quantity;
use greybox_core::stats::median;
use greybox_core::units::SpeedUnit;
use greybox_core::{Error, Result, SourcePos};
use rayon::prelude::*;

/// Convert a table into a recording through a channel map.
pub fn recording_from_table(mut table: Table, map: &ChannelMap) -> Result<Recording> {
    let mut notes = std::mem::take(&mut table.notes);
    let mut roles = assign_roles(&table, map)?;
    drop_unitless_optional(&table, map, &mut roles, &mut notes);
    let (map, assumed) = assume_friction_unit(&table, map, &roles);
    let map = &map;
    let mut unused = unused_columns(&table, &roles);
    let problems = unresolved(&table, map, &roles);
    if !problems.is_empty() {
        return Err(unresolved_error(&table, map, &problems));
    }
    let source = table.source.clone();
    let mut report = ReadReport {
        layout: table.layout.clone(),
        footer: std::mem::take(&mut table.footer),
        preamble: std::mem::take(&mut table.preamble),
        notes,
        ..Default::default()
    };
    if let Some(w) = footer_warning(&report.footer) {
        report.warnings.push(w);
    }
    let mut channels = convert_channels(&mut table, map, &roles, &mut report)?;
    let n = channels.first().map_or(table.rows, |c| c.1.len());
    let mut take = |role: Role| {
        channels
            .iter()
            .position(|(r, _, _)| *r == role)
            .map(|i| channels.swap_remove(i))
    };
    let normal = match (take(Role::Normal), map.constant_normal_n) {
        (Some(c), _) => c.1,
        (None, Some(f)) => {
            report.notes.push(format!(
                "no normal-force column: the stated constant load {f} N at every sample"
            ));
            vec![f; n]
        }
        (None, None) => unreachable!("checked by `unresolved`"),
    };
    let cof = take(Role::Cof).map(|c| c.1);
    let tangential = match (take(Role::Tangential).map(|c| c.1), &assumed) {
        (Some(ft), Some(a)) => {
            let kept = settle_assumed(&normal, ft, cof.as_deref(), a, &mut report);
            if kept.is_none() {
                unused.insert(0, format!("'{}' (its unit unknown)", a.column));
            }
            kept
        }
        (ft, _) => ft,
    };
    let (normal, tangential) =
        forces_by_convention(normal, tangential, cof.as_deref(), &unused, &mut report);
    let step = take(Role::Step)
        .map(|c| c.1)
        .or_else(|| block_steps(&table, n, &mut report));
    let time_s = match take(Role::Time) {
        Some((_, t, header)) => {
            let t = continuous_time(
                t,
                step.as_deref(),
                &source,
                &header,
                table.header_line,
                &mut report,
            )?;
            say_rate_beside_time(&t, &header, map.sample_rate_hz, &mut report);
            t
        }
        None => time_from_rate(&table, map, n, &mut report)?,
    };
    let recorded_speed = take(Role::Speed).map(|c| c.1);
    let speed_was_recorded = recorded_speed.is_some();
    let speed = speed_trace(recorded_speed, map, n, &mut report);
    if let (Some(SpeedTrace::SlidingMPerS(v)), true) = (&speed, speed_was_recorded) {
        check_sliding_speed(v, &source, &mut report)?;
    }
    let rec = Recording {
        source: source.clone(),
        time_s,
        normal_n: normal,
        tangential_n: tangential,
        radial_n: take(Role::Radial).map(|c| c.1),
        trigger_v: take(Role::Trigger).map(|c| c.1),
        step,
        speed,
        track_radius_m: take(Role::Radius).map(|c| c.1),
        cof,
        position_m: take(Role::Position).map(|c| c.1),
        provenance: Some(report),
    };
    rec.validate()?;
    Ok(rec)
}

/// A sample rate given beside a time column: the column is the time, and the report says so —
/// a note where the two agree within 1 %, a warning naming both where they do not.
fn say_rate_beside_time(t: &[f64], header: &str, rate_hz: Option<f64>, report: &mut ReadReport) {
    let Some(given) = rate_hz else { return };
    let steps: Vec<f64> = t.windows(2).map(|w| w[1] - w[0]).collect();
    let column_hz = 1.0 / median(&steps);
    let line = format!(
        "a sample rate of {given} Hz was given, but the file has a time column '{header}' (median rate {column_hz:.6} Hz): the time column is used"
    );
    if (column_hz / given - 1.0).abs() <= 0.01 {
        report.notes.push(line);
    } else {
        report.warnings.push(format!(
            "{line}; the two disagree: check the time column's unit (state it with `map` time={header}:UNIT) or drop `sample_rate_hz`"
        ));
    }
}

/// Time without a time column: from the map's sample rate, else the table's own sampling
/// interval (a TDMS waveform's), from the table's start time; an error naming the file
/// without either.
fn time_from_rate(
    table: &Table,
    map: &ChannelMap,
    n: usize,
    report: &mut ReadReport,
) -> Result<Vec<f64>> {
    let dt = map
        .sample_rate_hz
        .map(|f| 1.0 / f)
        .or(table.sample_interval_s)
        .filter(|d| d.is_finite() && *d > 0.0)
        .ok_or_else(|| {
            Error::input(
                SourcePos::file(&table.source),
                "no time column (none mapped, none with a usual name) and no sample rate: give `sample_rate_hz` or map the time column with `map` time=NAME:UNIT",
            )
        })?;
    let t0 = table.start_time_s.unwrap_or(0.0);
    report.notes.push(format!(
        "no time column: time from the sample rate {:.6} Hz",
        1.0 / dt
    ));
    Ok((0..n).into_par_iter().map(|i| t0 + i as f64 * dt).collect())
}

/// The speed channel as recorded (rpm where its unit turns, else m/s), else the stated
/// constant sliding velocity; without either, a note on how to give one (unless the user
/// said the file has no speed).
pub(super) fn speed_trace(
    recorded: Option<Vec<f64>>,
    map: &ChannelMap,
    n: usize,
    report: &mut ReadReport,
) -> Option<SpeedTrace> {
    if let Some(v) = recorded {
        let unit = report
            .columns
            .iter()
            .find(|c| c.role == Role::Speed)
            .and_then(|c| SpeedUnit::parse(&c.unit));
        return Some(match unit {
            Some(u) if u.is_rotational() => SpeedTrace::SpindleRpm(v),
            _ => SpeedTrace::SlidingMPerS(v),
        });
    }
    let Some(v) = map.constant_sliding_m_s else {
        if !map.ignore.iter().any(|r| r == "speed") {
            report.notes.push("no speed channel (none mapped, none with a usual name): the sliding velocity must come from a plan (`study`, `plan_steps`), a speed channel (`map` speed=NAME:UNIT) or, for a rig that runs at one speed, `constant_sliding_velocity_m_per_s`".into());
        }
        return None;
    };
    report.notes.push(format!(
        "no speed column: the stated constant sliding velocity {v} m/s at every sample"
    ));
    Some(SpeedTrace::SlidingMPerS(vec![v; n]))
}

/// A sliding-speed channel against the physics table where it is read, with or without a
/// plan (a plan's speeds label the rows, the channel still aligns and checks them): a largest
/// sample beyond any rig (200 m/s) is refused, one beyond the usual range (20 m/s) is a
/// warning of the read report with the likely unit slip (mm/s or rpm labelled m/s), naming
/// the sample. Samples are finite here (the table's reader refused the others).
fn check_sliding_speed(v: &[f64], source: &str, report: &mut ReadReport) -> Result<()> {
    let largest = super::types::largest_magnitude(v);
    if largest <= *Quantity::SlidingVelocity.usual().end() {
        return Ok(());
    }
    let i = v.iter().position(|x| x.abs() == largest).unwrap_or(0);
    let what = format!("the speed channel's sample {i}");
    match greybox_core::physics::check(Quantity::SlidingVelocity, largest, &what) {
        Ok(flag) => {
            if let Some(flag) = flag {
                report.warnings.push(flag.text);
            }
            Ok(())
        }
        Err(text) => Err(Error::input(SourcePos::file(source).field("speed"), text)),
    }
}

/// A file of blocks (each with its own settings and header, as UMT and PCS exports write one
/// per step) without a step column: the block number is the step, so that a time restarting
/// in every block is made continuous and each block is a segment.
pub(super) fn block_steps(table: &Table, n: usize, report: &mut ReadReport) -> Option<Vec<f64>> {
    if table.block_starts.len() < 2 {
        return None;
    }
    report.notes.push(format!(
        "{} blocks, each with its own header: the block number (1, 2, …) is the step",
        table.block_starts.len()
    ));
    let mut step = vec![0.0; n];
    for (b, w) in table.block_starts.iter().enumerate() {
        let end = table.block_starts.get(b + 1).copied().unwrap_or(n).min(n);
        if end <= *w {
            report.warnings.push(format!(
                "block {} has a header but no data row: step {} is empty, the blocks after it keep their numbers",
                b + 1,
                b + 1
            ));
        }
        step[(*w).min(n)..end]
            .iter_mut()
            .for_each(|s| *s = (b + 1) as f64);
    }
    Some(step)
}

/// The forces as greybox reads them: a normal force recorded negative (a load cell whose axis
/// points away from the contact, as UMT rigs write `Fz`) is flipped (the friction force's
/// sign is the identification's business: flipped per file there, or taken per stroke in a
/// reciprocating test). Without a friction
/// force, F_t = μ·F_N from the rig's own μ (the note names the `unused` numeric columns a
/// friction force could have been); with both, their disagreement is reported.
pub(super) fn forces_by_convention(
    mut normal: Vec<f64>,
    tangential: Option<Vec<f64>>,
    cof: Option<&[f64]>,
    unused: &[String],
    report: &mut ReadReport,
) -> (Vec<f64>, Vec<f64>) {
    if mostly_negative(&normal) {
        normal.iter_mut().for_each(|v| *v = -*v);
        report
            .notes
            .push("the normal force is recorded negative (load-cell axis away from the contact): its sign was flipped".into());
    }
    let Some(ft) = tangential else {
        let mu = cof.expect("checked by `unresolved`");
        let which = if unused.is_empty() {
            "the file has no other numeric column".to_string()
        } else {
            format!(
                "unused numeric columns: {} (map one with `map` tangential=NAME:UNIT)",
                unused.join(", ")
            )
        };
        report.notes.push(format!(
            "no column is used as the friction force ({which}): F_t = μ·F_N from the rig's own friction coefficient (cof)"
        ));
        return (
            normal.clone(),
            mu.iter().zip(&normal).map(|(m, f)| m * f).collect(),
        );
    };
    if let Some(mu) = cof {
        let (note, far) = cof_disagreement(&normal, &ft, mu);
        if far {
            report.warnings.push(note.clone());
        }
        report.notes.push(note);
    }
    (normal, ft)
}

/// Whether more than half the samples are negative: a normal force recorded on a load-cell
/// axis pointing away from the contact. One counting pass (the median's sign, without
/// copying and partially sorting a channel of millions of samples).
fn mostly_negative(values: &[f64]) -> bool {
    let negative: usize = values.iter().map(|v| usize::from(*v < 0.0)).sum();
    2 * negative > values.len()
}

/// Footer lines beyond this many are a line of the summary: a footer is an `End of data` or
/// a few summary lines, not hundreds of lines left unread.
pub const FOOTER_LINES_NOTED: usize = 5;

/// The summary line for a footer that is more than a few closing lines, or that holds
/// numbers (rows written with another delimiter, which the table's layout does not read).
pub(super) fn footer_warning(footer: &[(u64, String)]) -> Option<String> {
    let (first, text) = footer.first()?;
    let numeric = footer
        .iter()
        .filter(|(_, t)| {
            let digits = t.chars().filter(char::is_ascii_digit).count();
            digits > 0 && 2 * digits >= t.chars().filter(|c| !c.is_whitespace()).count()
        })
        .count();
    if footer.len() <= FOOTER_LINES_NOTED && numeric == 0 {
        return None;
    }
    let last = footer.last().map_or(*first, |l| l.0);
    Some(format!(
        "{} line(s) after the data (lines {first}-{last}, first: '{}') were not read as data{}",
        footer.len(),
        greybox_core::escape::one_line(text.chars().take(60).collect::<String>().as_str()),
        if numeric > 0 {
            format!(
                "; {numeric} of them hold mostly numbers (rows with another delimiter or layout?)"
            )
        } else {
            String::new()
        }
    ))
}

/// Times in s, made continuous where the rig restarts its clock at every step (a time that
/// falls where the step number changes is shifted to follow the previous step by one
/// sample interval). A time that falls anywhere else is an error naming its line.
pub(super) fn continuous_time(
    mut t: Vec<f64>,
    step: Option<&[f64]>,
    source: &str,
    header: &str,
    header_line: u64,
    report: &mut ReadReport,
) -> Result<Vec<f64>> {
    if t.windows(2).all(|w| w[1] > w[0]) {
        return Ok(t);
    }
    let mut dts: Vec<f64> = t
        .windows(2)
        .map(|w| w[1] - w[0])
        .filter(|d| *d > 0.0)
        .collect();
    let dt = if dts.is_empty() {
        0.0
    } else {
        let mid = dts.len() / 2;
        *dts.select_nth_unstable_by(mid, f64::total_cmp).1
    };
    let mut offset = 0.0;
    let mut restarts = 0;
    for i in 1..t.len() {
        let raw = t[i] + offset;
        let prev = t[i - 1];
        if raw > prev {
            t[i] = raw;
            continue;
        }
        let step_changed = step.is_some_and(|s| s[i] != s[i - 1]);
        if step_changed && dt > 0.0 {
            offset += prev + dt - raw;
            t[i] = prev + dt;
            restarts += 1;
            continue;
        }
        return Err(Error::input(
            SourcePos::file(source)
                .line(header_line + 1 + i as u64)
                .field(header),
            format!(
                "time must increase strictly: {} s follows {} s{}",
                t[i] + offset,
                prev,
                if step.is_some() {
                    ""
                } else {
                    " (a time that restarts per step needs the step column mapped: `map` step=NAME)"
                }
            ),
        ));
    }
    if restarts > 0 {
        report.notes.push(format!(
            "time restarts at {restarts} step change(s): made continuous (next step follows after one sample interval, {dt:.6} s)"
        ));
    }
    Ok(t)
}

/// Each role's column converted to SI (or the speed base), with what was mapped recorded.
pub(super) fn convert_channels(
    table: &mut Table,
    map: &ChannelMap,
    roles: &[(Role, usize, bool)],
    report: &mut ReadReport,
) -> Result<Vec<(Role, Vec<f64>, String)>> {
    let source = table.source.clone();
    let at = table.header_pos();
    let mut channels: Vec<(Role, Vec<f64>, String)> = Vec::new();
    for (role, idx, mapped) in roles {
        let spec = map.spec(*role);
        let col: &mut Column = &mut table.columns[*idx];
        let header = col.header.clone();
        let pos = || at.clone().field(&header);
        let unit = match (spec.as_ref().and_then(|s| s.unit.clone()), col.unit.clone()) {
            (Some(m), Some(f)) if *role != Role::Trigger && *role != Role::Step => {
                if !same_unit(*role, &m, &f) {
                    return Err(Error::input(
                        pos(),
                        format!("mapped as {m} but the file says the unit is '{f}'"),
                    ));
                }
                Some(m)
            }
            (Some(m), _) => Some(m),
            (None, f) => f,
        };
        let scale = spec.as_ref().map_or(1.0, |s| s.scale);
        let (factor, unit_name) = match role {
            Role::Trigger => (1.0, unit.clone().unwrap_or_else(|| "V".into())),
            Role::Step => (1.0, "-".into()),
            Role::Cof if unit.is_none() => (1.0, "-".into()),
            _ => {
                let u = unit.clone().ok_or_else(|| {
                    Error::input(
                        pos(),
                        format!(
                            "column '{header}' ({}) states no unit: name it with one (e.g. '{} ({})') or map it as `map` {}={}:{}",
                            role.name(),
                            col.name,
                            example_unit(*role),
                            role.name(),
                            col.name,
                            example_unit(*role)
                        ),
                    )
                })?;
                check_unit(*role, &u).map_err(|m| Error::input(pos(), m))?;
                (unit_factor(*role, &u), u)
            }
        };
        let mut values = col.take_values(&source)?;
        let k = factor * scale;
        if k != 1.0 {
            values.iter_mut().for_each(|v| *v *= k);
        }
        report.columns.push(MappedColumn {
            role: *role,
            column: header.clone(),
            unit: unit_name,
            scale,
            how: if *mapped {
                FoundBy::Mapped
            } else {
                FoundBy::Auto
            },
        });
        channels.push((*role, values, header));
    }
    Ok(channels)
}
