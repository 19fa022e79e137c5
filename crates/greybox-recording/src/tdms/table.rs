//! A TDMS file as a [`Table`](crate::table::Table) of one group's channels, and as a recording.

use super::format::{channel_path, group_path, PropValue, TdmsFile, T_STRING};
use crate::table::{split_unit, Column, ColumnData, Table};
use crate::{ChannelMap, Recording, DEFAULT_TDMS_GROUP};
use greybox_core::{Error, Result, SourcePos};
use std::path::Path;

/// Read a recording from a TDMS file through a channel map.
pub fn read_tdms_recording(path: &Path, map: &ChannelMap) -> Result<Recording> {
    let file = TdmsFile::read(path)?;
    recording_from_tdms(file, map)
}

/// Build a recording from a parsed TDMS file.
pub fn recording_from_tdms(file: TdmsFile, map: &ChannelMap) -> Result<Recording> {
    crate::recording_from_table(
        table_from_tdms(file, map.reader.tdms_group.as_deref())?,
        map,
    )
}

/// The channels of one group as a table (columns named by channel, units from
/// `unit_string`, waveform timing from the first channel's `wf_increment` and
/// `wf_start_offset`). Without a group name: `Tribometer` if present, else the file's only
/// group holding channels.
pub fn table_from_tdms(mut file: TdmsFile, group: Option<&str>) -> Result<Table> {
    let groups: Vec<String> = file
        .objects
        .iter()
        .filter_map(|o| {
            let rest = o.path.strip_prefix("/'")?;
            let end = rest.find("'/'")?;
            Some(rest[..end].replace("''", "'"))
        })
        .fold(Vec::new(), |mut v, g| {
            if !v.contains(&g) {
                v.push(g);
            }
            v
        });
    let group = match group {
        Some(g) => g.to_string(),
        None if groups.iter().any(|g| g == DEFAULT_TDMS_GROUP) => DEFAULT_TDMS_GROUP.to_string(),
        None if groups.len() == 1 => groups[0].clone(),
        None => {
            return Err(Error::input(
                SourcePos::file(&file.source),
                format!(
                    "{} groups hold channels ({}): name one with `tdms_group`",
                    groups.len(),
                    groups.join(", ")
                ),
            ))
        }
    };
    let names = file.channel_names(&group);
    if names.is_empty() {
        return Err(Error::input(
            SourcePos::file(&file.source).field(&group),
            if file.object(&group_path(&group)).is_none() {
                format!(
                    "no group '{group}' in the file; it has: {}",
                    groups.join(", ")
                )
            } else {
                format!("group '{group}' has no channels")
            },
        ));
    }
    let mut columns = Vec::with_capacity(names.len());
    let mut interval = None;
    let mut start = None;
    for name in &names {
        let path = channel_path(&group, name);
        let Some(obj) = file.objects.iter_mut().find(|o| o.path == path) else {
            continue;
        };
        if obj.data_type == Some(T_STRING) || obj.data_type.is_none() {
            continue;
        }
        if interval.is_none() {
            // 0: a channel that is no waveform (some writers set it so)
            interval = obj
                .property("wf_increment")
                .and_then(PropValue::as_f64)
                .filter(|dt| *dt != 0.0);
            start = obj.property("wf_start_offset").and_then(PropValue::as_f64);
            check_waveform_timing(&file.source, &path, interval, start)?;
        }
        let unit = obj
            .property("unit_string")
            .and_then(PropValue::as_str)
            .map(str::trim)
            .filter(|u| !u.is_empty())
            .map(str::to_string);
        let (base, header_unit) = split_unit(name);
        columns.push(Column {
            header: name.clone(),
            name: base,
            unit: unit.or(header_unit),
            data: ColumnData::Numbers(std::mem::take(&mut obj.data)),
        });
    }
    let rows = columns.iter().map(|c| match &c.data {
        ColumnData::Numbers(v) => v.len(),
        ColumnData::NotNumeric { .. } => 0,
    });
    let rows = rows.max().unwrap_or(0);
    Ok(Table {
        source: file.source.clone(),
        columns,
        rows,
        layout: format!("TDMS, group '{group}'"),
        header_line: 0,
        headerless: false,
        preamble: Vec::new(),
        header_alternatives: Vec::new(),
        footer: Vec::new(),
        sample_interval_s: interval,
        start_time_s: start,
        ..Default::default()
    })
}

/// The shortest and longest sample interval a recording can have, s: a 1 GHz digitiser and
/// one sample an hour.
const WF_INCREMENT_S: std::ops::RangeInclusive<f64> = 1e-9..=3600.0;
/// The latest a waveform may start, s after its time origin (about 30 years).
const WF_START_MAX_S: f64 = 1e9;

/// A waveform's timing properties, where present: `wf_increment` a sample interval of
/// [`WF_INCREMENT_S`], `wf_start_offset` finite within ±[`WF_START_MAX_S`] — an interval of
/// 1e300 s would put the steps at 10³⁰⁵ s, one of 1e-300 s make every rate look infinite;
/// both are refused naming the property and the channel.
fn check_waveform_timing(
    source: &str,
    channel: &str,
    interval: Option<f64>,
    start: Option<f64>,
) -> Result<()> {
    let bad = |property: &str, text: String| {
        Err(Error::input(
            SourcePos::file(source).field(format!("{channel} {property}")),
            text,
        ))
    };
    if let Some(dt) = interval.filter(|dt| !WF_INCREMENT_S.contains(dt)) {
        return bad(
            "wf_increment",
            format!(
                "the waveform's sample interval is {dt:e} s, outside {:e}..{:e} s (a 1 GHz digitiser to one sample an hour): give the time another way (`sample_rate_hz`, or a time channel)",
                WF_INCREMENT_S.start(),
                WF_INCREMENT_S.end()
            ),
        );
    }
    if let Some(t0) = start.filter(|t0| !(t0.abs() <= WF_START_MAX_S)) {
        return bad(
            "wf_start_offset",
            format!(
                "the waveform starts at {t0:e} s, beyond ±{WF_START_MAX_S:e} s of its time origin"
            ),
        );
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::super::write::{write_tdms, WriteChannel};
    use super::*;

    fn table(dt: f64, t0: f64) -> Result<Table> {
        let data: Vec<f64> = (0..50).map(|k| 10.0 + k as f64 * 0.01).collect();
        let chans = [WriteChannel {
            name: "Fn",
            unit: "N",
            data: &data,
        }];
        let mut bytes = Vec::new();
        write_tdms(&mut bytes, "Tribometer", &chans, dt, t0, 20).unwrap();
        table_from_tdms(TdmsFile::parse(&bytes, "w.tdms").unwrap(), None)
    }

    #[test]
    fn waveform_timing_out_of_any_rigs_range_is_refused_naming_the_property() {
        assert_eq!(table(1e-3, 0.0).unwrap().sample_interval_s, Some(1e-3));
        assert_eq!(
            table(0.0, 0.0).unwrap().sample_interval_s,
            None,
            "0: no waveform"
        );
        for dt in [1e300, 1e-300, -1e-3] {
            let e = table(dt, 0.0).unwrap_err().to_string();
            assert!(
                e.contains("w.tdms") && e.contains("wf_increment") && e.contains("sample interval"),
                "{dt}: {e}"
            );
        }
        let e = table(1e-3, 1e300).unwrap_err().to_string();
        assert!(e.contains("wf_start_offset"), "{e}");
    }
}
