//! A TDMS file as a [`Table`](crate::table::Table) of one group's channels, and as a recording.

use super::format::{channel_path, group_path, PropValue, TdmsFile, T_STRING};
use crate::recording::{ChannelMap, Recording, DEFAULT_TDMS_GROUP};
use crate::table::{split_unit, Column, ColumnData, Table};
use greybox_core::{Error, Result, SourcePos};
use std::path::Path;

/// Read a recording from a TDMS file through a channel map.
pub fn read_tdms_recording(path: &Path, map: &ChannelMap) -> Result<Recording> {
    let file = TdmsFile::read(path)?;
    recording_from_tdms(file, map)
}

/// Build a recording from a parsed TDMS file.
pub fn recording_from_tdms(file: TdmsFile, map: &ChannelMap) -> Result<Recording> {
    crate::recording::recording_from_table(
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
            interval = obj.property("wf_increment").and_then(PropValue::as_f64);
            start = obj.property("wf_start_offset").and_then(PropValue::as_f64);
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
        footer: Vec::new(),
        sample_interval_s: interval,
        start_time_s: start,
        ..Default::default()
    })
}
