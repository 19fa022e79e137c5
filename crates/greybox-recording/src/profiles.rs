//! Rig profiles: what a vendor program's export means, over the one tolerant text reader.
//!
//! The reader ([`crate::text_table`]) finds the layout (delimiter, decimal mark, preamble,
//! header, units row, blocks); a profile adds what the file does not say in a form the generic
//! role search can use: which of its columns is the time, the forces, the rig's own friction
//! coefficient, the speed and the step, and the units the vendor leaves unprinted. A profile is
//! chosen with `--rig NAME` (study `[recording] rig = "NAME"`) or detected from the file's
//! signature (preamble lines and header names) when exactly one profile matches.
//!
//! Every profile here was written against a real public export of that rig or program (see
//! [`RigProfile::verified_against`] and `tests/data/real-rigs/SOURCES.md`); a profile only
//! fills roles the user did not map, and only with columns the file has.

use crate::table::{column_matches, ColumnData, Table};
use crate::{ChannelMap, ChannelSpec, Role};
use greybox_core::{Error, Result, SourcePos};

use crate::TestMode;

/// One role's column in a profile: names tried in order (the first numeric column present
/// is taken) and the unit when the file does not print one (`""`: the file's own).
#[derive(Debug, Clone, Copy)]
pub struct ProfileColumn {
    pub role: Role,
    pub names: &'static [&'static str],
    pub unit: &'static str,
}

/// A vendor program's export.
#[derive(Debug, Clone, Copy)]
pub struct RigProfile {
    /// `--rig` name.
    pub name: &'static str,
    /// Rig and program, for messages and `identify --list-rigs`.
    pub vendor: &'static str,
    /// What every export of this program carries (all of them, case-insensitive): text in
    /// its preamble or header, or with a `col:` prefix a whole column name.
    pub signature: &'static [&'static str],
    pub mode: TestMode,
    pub columns: &'static [ProfileColumn],
    /// The real public export this profile was written against.
    pub verified_against: &'static str,
}

const fn col(role: Role, names: &'static [&'static str], unit: &'static str) -> ProfileColumn {
    ProfileColumn { role, names, unit }
}

/// The profiles greybox knows.
pub const PROFILES: &[RigProfile] = &[
    RigProfile {
        name: "phoenix-te",
        vendor: "Phoenix Tribology TE series (COMPEND export, e.g. TE67 pin-on-disc)",
        signature: &["test control file", "calibration file", "friction force"],
        mode: TestMode::Continuous,
        columns: &[
            col(Role::Time, &["Test Time"], "s"),
            col(Role::Normal, &["Load"], "N"),
            col(Role::Tangential, &["Friction Force"], "N"),
            col(Role::Cof, &["Friction Coefficient"], ""),
            col(Role::Speed, &["Sliding Velocity"], "m/s"),
            col(Role::Step, &["This Step"], ""),
            col(Role::Radius, &["Radius"], "mm"),
        ],
        verified_against: "kyembot/pin-on-disk-data-analysis: PPS_60N_1.TSV, PPS_100N_1.TSV (MIT)",
    },
    RigProfile {
        name: "pcs-mtm",
        vendor: "PCS Instruments MTM/EHD (Multitracker export)",
        signature: &["test data file", "traction coeff"],
        mode: TestMode::Stepped,
        columns: &[
            col(Role::Time, &["Step Time"], "s"),
            col(Role::Normal, &["Pin Load", "Ball Load"], "N"),
            col(Role::Tangential, &["Traction Force"], "N"),
            col(Role::Cof, &["Traction Coeff"], ""),
            col(Role::Speed, &["Sliding Speed", "Disc Speed 1"], "mm/s"),
        ],
        verified_against: "moritzploss/tribology: demo_5.txt, demo_7.txt, demo_8.txt, demo-mtm-output.txt (MIT)",
    },
    RigProfile {
        name: "bruker-umt",
        vendor: "Bruker/CETR UMT (CETR Data Viewer CSV export)",
        signature: &["cetr"],
        mode: TestMode::Reciprocating,
        columns: &[
            col(Role::Time, &["T"], "s"),
            col(Role::Normal, &["Fz"], ""),
            col(Role::Tangential, &["Fx"], ""),
            col(Role::Cof, &["COF"], ""),
        ],
        verified_against: "okilitive/CETR-tribometer: data/HT-2n-6-4 2_001.csv (read, not kept: data rights)",
    },
    RigProfile {
        name: "rtec",
        vendor: "Rtec Instruments MFT (rotary and reciprocating CSV export)",
        signature: &["daq.fz", "daq.cof"],
        mode: TestMode::Stepped,
        columns: &[
            col(Role::Time, &["Timestamp"], "s"),
            col(Role::Normal, &["DAQ.Fz"], ""),
            col(Role::Tangential, &["DAQ.Fx"], ""),
            col(Role::Cof, &["DAQ.COF"], ""),
            col(Role::Speed, &["Rotary.Velocity"], ""),
            col(Role::Step, &["Step"], ""),
        ],
        verified_against: "Dichimanaym/Tribometer-Data-Processing: Sample Data/013_…csv (read, not kept: no licence)",
    },
    RigProfile {
        name: "pod-dwf",
        vendor: "pin-on-disc acquisition program writing .dwf files (TIME;FF; no load column)",
        signature: &["col:time", "col:ff"],
        mode: TestMode::Continuous,
        columns: &[
            col(Role::Time, &["TIME"], "s"),
            col(Role::Tangential, &["FF"], "N"),
        ],
        verified_against: "mihail-15/ML-Models-in-Tribology-and-Mechanics-for-hybrid-Al-based-composites: 9-Al10Cu-50N-140m-328.dwf and two more (CC-BY-4.0)",
    },
];

/// The profile called `name`, or an error listing them.
pub fn by_name(name: &str) -> Result<&'static RigProfile> {
    PROFILES
        .iter()
        .find(|p| p.name == name.trim())
        .ok_or_else(|| {
            Error::invalid(
                "rig",
                format!(
                    "unknown rig profile '{name}'; known: {}",
                    names().join(", ")
                ),
            )
        })
}

/// What `rig` may be set to: `auto` (detected) or a profile's name.
pub fn choices() -> Vec<&'static str> {
    std::iter::once("auto").chain(names()).collect()
}

/// Names of all profiles.
pub fn names() -> Vec<&'static str> {
    PROFILES.iter().map(|p| p.name).collect()
}

/// The text a signature is looked for in: preamble lines and column headers, lower case.
fn signature_text(table: &Table) -> String {
    let mut text = table.preamble.join("\n");
    for c in &table.columns {
        text.push('\n');
        text.push_str(&c.header);
    }
    text.to_lowercase()
}

/// Whether the table carries every part of the profile's signature (a `col:NAME` part must
/// be a whole column name: `ff` is not in `offset`).
fn matches(p: &RigProfile, table: &Table, text: &str) -> bool {
    p.signature.iter().all(|s| match s.strip_prefix("col:") {
        Some(name) => table.columns.iter().any(|c| column_matches(c, name)),
        None => text.contains(s),
    })
}

/// The profile for a table: the one named, else the only one whose signature matches.
pub fn detect(table: &Table, named: Option<&str>) -> Result<Option<&'static RigProfile>> {
    if let Some(n) = named.filter(|n| !n.is_empty() && *n != "auto") {
        return by_name(n).map(Some);
    }
    let text = signature_text(table);
    let found: Vec<&RigProfile> = PROFILES
        .iter()
        .filter(|p| matches(p, table, &text))
        .collect();
    Ok(match found.as_slice() {
        [one] => Some(one),
        _ => None,
    })
}

/// The first numeric column among a profile column's names.
fn present(table: &Table, pc: &ProfileColumn) -> Option<String> {
    pc.names.iter().find_map(|n| {
        table
            .columns
            .iter()
            .find(|c| column_matches(c, n) && matches!(c.data, ColumnData::Numbers(_)))
            .map(|c| c.name.clone())
    })
}

/// `map` with the profile's columns filled in where the user mapped nothing (and did not
/// ignore the role), and a note saying which profile was used and how it was chosen.
pub fn apply(table: &Table, map: &ChannelMap, notes: &mut Vec<String>) -> Result<ChannelMap> {
    let Some(p) = detect(table, map.rig.as_deref())
        .map_err(|e| Error::input(SourcePos::file(&table.source), e.to_string()))?
    else {
        return Ok(map.clone());
    };
    let mut out = map.clone();
    for pc in p.columns {
        if map.is_mapped(pc.role) || map.ignore.iter().any(|r| r == pc.role.name()) {
            continue;
        }
        let Some(name) = present(table, pc) else {
            continue;
        };
        let header_unit = table
            .columns
            .iter()
            .find(|c| c.name == name)
            .and_then(|c| c.unit.clone());
        let unit = match (header_unit, pc.unit) {
            (Some(u), _) => Some(u),
            (None, "") => None,
            (None, u) => Some(u.to_string()),
        };
        out.set_spec(
            pc.role,
            Some(ChannelSpec {
                name,
                unit,
                scale: 1.0,
            }),
        );
    }
    let how = if map
        .rig
        .as_deref()
        .is_some_and(|n| !n.is_empty() && n != "auto")
    {
        "named with `rig`"
    } else {
        "detected from the file's preamble and header"
    };
    notes.push(format!(
        "rig profile {} ({}), {how}; {} test",
        p.name,
        p.vendor,
        p.mode.name()
    ));
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::table::Column;

    fn table(preamble: &[&str], headers: &[&str]) -> Table {
        Table {
            source: "t".into(),
            preamble: preamble.iter().map(|s| s.to_string()).collect(),
            columns: headers
                .iter()
                .map(|h| Column::numbers(h, vec![1.0, 2.0]))
                .collect(),
            rows: 2,
            ..Default::default()
        }
    }

    #[test]
    fn detection_needs_the_whole_signature_and_one_match() {
        let t = table(&["Created by CETR Data Viewer"], &["Fx", "Fz", "T", "COF"]);
        assert_eq!(detect(&t, None).unwrap().unwrap().name, "bruker-umt");
        let t = table(&[], &["time", "offset", "Fz"]);
        assert!(
            detect(&t, None).unwrap().is_none(),
            "'ff' inside 'offset' is no signature"
        );
        let t = table(&[], &["TIME", "FF"]);
        assert_eq!(detect(&t, None).unwrap().unwrap().name, "pod-dwf");
        assert!(by_name("nope")
            .unwrap_err()
            .to_string()
            .contains("phoenix-te"));
    }

    #[test]
    fn a_profile_fills_only_what_the_user_left_open() {
        let t = table(&["Created by CETR UMT"], &["Fx", "Fz", "T", "COF"]);
        let mut map = ChannelMap::default();
        map.apply_override("normal=Fz:kN").unwrap();
        let mut notes = Vec::new();
        let m = apply(&t, &map, &mut notes).unwrap();
        assert_eq!(m.normal.as_ref().unwrap().unit.as_deref(), Some("kN"));
        assert_eq!(m.time.as_deref(), Some("T"));
        assert!(
            notes[0].contains("bruker-umt") && notes[0].contains("detected"),
            "{notes:?}"
        );
    }
}
