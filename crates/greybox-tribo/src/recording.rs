//! Raw tribometer recordings and how a file's columns map onto roles.
//!
//! A reader gives a [`Table`] (named columns with their units); a [`ChannelMap`] says which
//! column plays which role — time, normal and tangential force, and where the rig records
//! them, radial force, trigger, step number, spindle or sliding speed, track radius — and
//! [`recording_from_table`] converts them to SI. Roles not mapped explicitly are found by
//! their usual names ([`ROLE_ALIASES`]), ignoring case, spaces and units in the header.

use crate::signal::median;
use crate::table::{column_matches, Column, ColumnData, Table};
use greybox_core::units::{ForceUnit, LengthUnit, SpeedUnit, TimeUnit};
use greybox_core::{Error, Result, SourcePos};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// One pin's raw recording, SI units (s, N, V).
#[derive(Debug, Clone, PartialEq)]
pub struct Recording {
    /// File (or other source) it was read from.
    pub source: String,
    /// Sample times, s (strictly increasing).
    pub time_s: Vec<f64>,
    /// Normal force F_N, N.
    pub normal_n: Vec<f64>,
    /// Tangential (friction) force F_t, N.
    pub tangential_n: Vec<f64>,
    /// Radial force, N (not used for μ; kept for checks).
    pub radial_n: Option<Vec<f64>>,
    /// Recording-trigger channel, V.
    pub trigger_v: Option<Vec<f64>>,
    /// Step (segment) number the rig software wrote per sample.
    pub step: Option<Vec<f64>>,
    /// Recorded spindle speed (rpm) or sliding velocity (m/s).
    pub speed: Option<SpeedTrace>,
    /// Recorded track radius per sample, m.
    pub track_radius_m: Option<Vec<f64>>,
    /// The friction coefficient the rig computed itself (`cof` role), dimensionless. Kept
    /// beside the forces: where the file has no friction force, `tangential_n` is μ·F_N.
    pub cof: Option<Vec<f64>>,
    /// Position along the stroke of a linear reciprocating rig (ASTM G133), m.
    pub position_m: Option<Vec<f64>>,
    /// How the file was read: its layout and which column became which role.
    pub provenance: Option<ReadReport>,
}

/// A recorded speed channel in SI-like base units.
#[derive(Debug, Clone, PartialEq)]
pub enum SpeedTrace {
    /// Spindle speed, rpm (needs the track radius to give a sliding velocity).
    SpindleRpm(Vec<f64>),
    /// Sliding velocity, m/s.
    SlidingMPerS(Vec<f64>),
}

impl SpeedTrace {
    pub fn values(&self) -> &[f64] {
        match self {
            SpeedTrace::SpindleRpm(v) | SpeedTrace::SlidingMPerS(v) => v,
        }
    }
}

/// What a reader found in a file, for `identify --inspect`.
#[derive(Debug, Clone, PartialEq, Default, Serialize)]
pub struct ReadReport {
    /// Dialect and layout, e.g. `semicolon-delimited, decimal comma, header on line 1`.
    pub layout: String,
    /// Role → column, unit and how it was found.
    pub columns: Vec<MappedColumn>,
    /// Footer lines after the data (reported, not an error): (line, text).
    pub footer: Vec<(u64, String)>,
    /// Preamble lines above the header.
    pub preamble: Vec<String>,
    /// Anything the reader repaired, e.g. a time that restarts per step.
    pub notes: Vec<String>,
    /// What was read but not used, or contradicts what was used (a long footer, a rig's own μ
    /// far from F_t/F_N): lines of the identification's summary, not only of `--inspect`
    /// (carried into [`crate::campaign::FileReport::warnings`]).
    pub warnings: Vec<String>,
    /// How the rig profile says the rig runs its tests (`None`: no profile).
    pub test_mode: Option<crate::identify_config::TestMode>,
}

/// One role's column.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MappedColumn {
    pub role: String,
    pub column: String,
    pub unit: String,
    pub scale: f64,
    /// `mapped` (named by the user) or `auto` (found by its usual name).
    pub how: String,
}

impl Recording {
    /// A recording of time and the two forces only.
    pub fn new(source: &str, time_s: Vec<f64>, normal_n: Vec<f64>, tangential_n: Vec<f64>) -> Self {
        Recording {
            source: source.to_string(),
            time_s,
            normal_n,
            tangential_n,
            radial_n: None,
            trigger_v: None,
            step: None,
            speed: None,
            track_radius_m: None,
            cof: None,
            position_m: None,
            provenance: None,
        }
    }
    pub fn len(&self) -> usize {
        self.time_s.len()
    }
    pub fn is_empty(&self) -> bool {
        self.time_s.is_empty()
    }
    /// Duration from first to last sample, s.
    pub fn duration_s(&self) -> f64 {
        match (self.time_s.first(), self.time_s.last()) {
            (Some(a), Some(b)) => b - a,
            _ => 0.0,
        }
    }
    /// Sample rate from the median sample interval, Hz.
    pub fn sample_rate_hz(&self) -> f64 {
        let mut dt: Vec<f64> = self.time_s.windows(2).map(|w| w[1] - w[0]).collect();
        if dt.is_empty() {
            return f64::NAN;
        }
        let mid = dt.len() / 2;
        let (_, m, _) = dt.select_nth_unstable_by(mid, f64::total_cmp);
        1.0 / *m
    }

    /// Check lengths, finiteness and strictly increasing time.
    pub fn validate(&self) -> Result<()> {
        let n = self.time_s.len();
        let pos = || SourcePos::file(&self.source);
        if n < 2 {
            return Err(Error::input(
                pos(),
                format!("a recording needs at least 2 samples, found {n}"),
            ));
        }
        let speed = self.speed.as_ref().map(SpeedTrace::values);
        let channels: [(&str, Option<&[f64]>); 8] = [
            ("normal", Some(&self.normal_n)),
            ("tangential", Some(&self.tangential_n)),
            ("radial", self.radial_n.as_deref()),
            ("trigger", self.trigger_v.as_deref()),
            ("step", self.step.as_deref()),
            ("speed", speed),
            ("radius", self.track_radius_m.as_deref()),
            ("position", self.position_m.as_deref()),
        ];
        for (name, ch) in channels {
            if let Some(ch) = ch {
                if ch.len() != n {
                    return Err(Error::input(
                        pos().field(name),
                        format!("channel has {} samples, time has {n}", ch.len()),
                    ));
                }
                if let Some(i) = first_non_finite(ch) {
                    return Err(Error::input(
                        pos().field(name),
                        format!("sample {i} is not finite ({})", ch[i]),
                    ));
                }
            }
        }
        if let Some(i) = first_non_increasing(&self.time_s) {
            return Err(Error::input(
                pos().field("time"),
                format!(
                    "time must increase strictly: sample {} ({} s) follows {} s",
                    i + 1,
                    self.time_s[i + 1],
                    self.time_s[i]
                ),
            ));
        }
        Ok(())
    }
}

/// Index of the first NaN or infinity. Blocks are screened in parallel with a branch-free OR
/// that vectorises; only a failing block is searched.
fn first_non_finite(values: &[f64]) -> Option<usize> {
    const BLOCK: usize = 1 << 14;
    values
        .par_chunks(BLOCK)
        .position_first(|b| b.iter().fold(false, |bad, v| bad | !v.is_finite()))
        .and_then(|k| {
            let start = k * BLOCK;
            values[start..]
                .iter()
                .position(|v| !v.is_finite())
                .map(|i| start + i)
        })
}

/// Index `i` of the first pair with `t[i+1] ≤ t[i]` (or a NaN), screened in parallel blocks
/// like [`first_non_finite`].
fn first_non_increasing(t: &[f64]) -> Option<usize> {
    const BLOCK: usize = 1 << 14;
    let bad = |s: &[f64]| s.windows(2).fold(false, |bad, w| bad | !(w[1] > w[0]));
    let blocks = t.len().div_ceil(BLOCK);
    (0..blocks)
        .into_par_iter()
        .position_first(|k| bad(&t[k * BLOCK..((k + 1) * BLOCK + 1).min(t.len())]))
        .and_then(|k| {
            t[k * BLOCK..]
                .windows(2)
                .position(|w| !(w[1] > w[0]))
                .map(|i| k * BLOCK + i)
        })
}

/// Where a channel comes from: column (or TDMS channel) name, unit and an extra scale (e.g.
/// −1 to flip a dynamometer axis).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ChannelSpec {
    /// Column or TDMS channel name; matched ignoring case, surrounding spaces and the unit
    /// in the header (`fz` finds ` DAQ.Fz (N)`). `#K` is column K of the file counted from 1
    /// (a log without a header line names its columns so).
    pub name: String,
    /// Unit (`kN`, `rpm`, `mm/s`, `ms`, …); if absent it is taken from the header (`Fz (N)`,
    /// `Fz [kN]`, `Fz_kN`, `Fz/N`) or the TDMS `unit_string`; an error if neither names one.
    #[serde(default)]
    pub unit: Option<String>,
    /// Multiplier applied after unit conversion.
    #[serde(default = "one")]
    pub scale: f64,
}

fn one() -> f64 {
    1.0
}

impl ChannelSpec {
    pub fn named(name: &str) -> Self {
        ChannelSpec {
            name: name.to_string(),
            unit: None,
            scale: 1.0,
        }
    }
    pub fn with_unit(name: &str, unit: &str) -> Self {
        ChannelSpec {
            name: name.to_string(),
            unit: Some(unit.to_string()),
            scale: 1.0,
        }
    }
    /// Parse `NAME[:UNIT[:SCALE]]`, e.g. `Fz:kN:-1` or `#3:N` (column 3).
    pub fn parse(text: &str) -> Result<Self> {
        let mut parts = text.split(':');
        let name = parts.next().unwrap_or("").trim();
        if name.is_empty() {
            return Err(Error::invalid(
                "channel mapping",
                format!("'{text}' has no column name (expected NAME[:UNIT[:SCALE]])"),
            ));
        }
        let unit = parts
            .next()
            .map(|u| u.trim().to_string())
            .filter(|u| !u.is_empty());
        let scale = match parts.next() {
            Some(s) => s
                .trim()
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite() && *v != 0.0)
                .ok_or_else(|| {
                    Error::invalid(
                        "channel mapping",
                        format!("scale '{s}' in '{text}' must be a non-zero number"),
                    )
                })?,
            None => 1.0,
        };
        if parts.next().is_some() {
            return Err(Error::invalid(
                "channel mapping",
                format!("'{text}': too many ':' parts (expected NAME[:UNIT[:SCALE]])"),
            ));
        }
        Ok(ChannelSpec {
            name: name.to_string(),
            unit,
            scale,
        })
    }
}

/// Unit suffix of a column name: `normal_force_kN` → kN.
pub fn force_unit_from_name(name: &str) -> Option<ForceUnit> {
    crate::table::split_unit(name)
        .1
        .and_then(|u| ForceUnit::parse_lenient(&u))
}

/// Unit suffix of a time column: `time_ms` → ms.
pub fn time_unit_from_name(name: &str) -> Option<TimeUnit> {
    crate::table::split_unit(name)
        .1
        .and_then(|u| TimeUnit::parse(&u))
}

/// The roles a column can play.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Role {
    Time,
    Normal,
    Tangential,
    Radial,
    Trigger,
    Step,
    Speed,
    Radius,
    /// A friction coefficient the rig software computed (dimensionless).
    Cof,
    /// Position along a reciprocating stroke (length).
    Position,
}

impl Role {
    pub const ALL: [Role; 10] = [
        Role::Time,
        Role::Normal,
        Role::Tangential,
        Role::Radial,
        Role::Trigger,
        Role::Step,
        Role::Speed,
        Role::Radius,
        Role::Cof,
        Role::Position,
    ];
    pub fn name(self) -> &'static str {
        match self {
            Role::Time => "time",
            Role::Normal => "normal",
            Role::Tangential => "tangential",
            Role::Radial => "radial",
            Role::Trigger => "trigger",
            Role::Step => "step",
            Role::Speed => "speed",
            Role::Radius => "radius",
            Role::Cof => "cof",
            Role::Position => "position",
        }
    }
    pub fn parse(s: &str) -> Option<Role> {
        Role::ALL.into_iter().find(|r| r.name() == s.trim())
    }
}

/// The usual names of each role, tried in order when a role is not mapped explicitly
/// (compared like [`column_matches`]: case, `_`/`-`/spaces and units ignored).
pub const ROLE_ALIASES: [(Role, &[&str]); 10] = [
    (
        Role::Time,
        &[
            "time",
            "t",
            "zeit",
            "timestamp",
            "elapsed time",
            "relative time",
            "time elapsed",
            "sec",
        ],
    ),
    (
        Role::Normal,
        &[
            "normal force",
            "normal_force",
            "fn",
            "fz",
            "normal load",
            "load",
            "normalkraft",
            "force normal",
            "normal",
            "f n",
            "f_n",
        ],
    ),
    (
        Role::Tangential,
        &[
            "tangential force",
            "friction force",
            "ft",
            "fx",
            "friction",
            "reibkraft",
            "tangential",
            "force friction",
            "f t",
            "f_t",
            "ff",
        ],
    ),
    (
        Role::Radial,
        &["radial force", "radial_force", "fy", "fr", "radial"],
    ),
    (Role::Trigger, &["trigger", "trig"]),
    (
        Role::Step,
        &[
            "step",
            "segment",
            "step no",
            "step number",
            "stage",
            "schritt",
            "sequence",
        ],
    ),
    (
        Role::Speed,
        &[
            "sliding velocity",
            "sliding speed",
            "sliding_velocity",
            "velocity",
            "speed",
            "spindle speed",
            "spindle",
            "rotational speed",
            "rotation speed",
            "rpm",
            "drehzahl",
            "geschwindigkeit",
            "v",
            "n",
        ],
    ),
    (
        Role::Radius,
        &["track radius", "wear track radius", "radius", "r track"],
    ),
    (
        Role::Cof,
        &[
            "cof",
            "friction coefficient",
            "coefficient of friction",
            "friction coeff",
            "traction coeff",
            "traction coefficient",
            "mu",
            "µ",
            "μ",
            "reibwert",
            "reibungskoeffizient",
            "reibungszahl",
            "daq.cof",
        ],
    ),
    (
        Role::Position,
        &[
            "position",
            "x position",
            "stroke position",
            "x",
            "displacement",
            "weg",
        ],
    ),
];

/// How to find the channels of a recording (study TOML `[recording]`, `identify --map`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ChannelMap {
    /// Time column/channel; its unit from the header (`time_s`, `Time (ms)`) or `time_unit`.
    /// If there is none, time comes from `sample_rate_hz` or the TDMS `wf_increment` property.
    pub time: Option<String>,
    pub time_unit: Option<TimeUnit>,
    /// Sample rate when there is no time column, Hz.
    pub sample_rate_hz: Option<f64>,
    pub normal: Option<ChannelSpec>,
    pub tangential: Option<ChannelSpec>,
    pub radial: Option<ChannelSpec>,
    /// Trigger channel (volts).
    pub trigger: Option<String>,
    /// Step/segment number column written by the rig software.
    pub step: Option<String>,
    /// Spindle speed (rpm, rps) or sliding velocity (m/s, mm/s, m/min) channel.
    pub speed: Option<ChannelSpec>,
    /// Track-radius column (mm, m).
    pub radius: Option<ChannelSpec>,
    /// Friction coefficient computed by the rig (dimensionless, or `%`).
    pub cof: Option<ChannelSpec>,
    /// Stroke position of a reciprocating rig (mm, m, um).
    pub position: Option<ChannelSpec>,
    /// Normal load, N, for rigs that do not record it (dead-weight pin-on-disc rigs): the
    /// same value at every sample.
    pub constant_normal_n: Option<f64>,
    /// Sliding velocity, m/s, for rigs that do not record their speed: the same value at
    /// every sample.
    pub constant_sliding_m_s: Option<f64>,
    /// Rig profile by name (see [`crate::profiles`]); `None` detects one from the file's
    /// signature when exactly one matches.
    pub rig: Option<String>,
    /// Track radius, mm: one value for the whole recording, or one per segment in the
    /// order found (used with a speed channel in rpm when the file has no radius column).
    pub track_radius_mm: Vec<f64>,
    /// Find unmapped roles by their usual names (default true).
    pub auto: bool,
    /// Roles never to fill automatically (`--map speed=` adds `speed`).
    pub ignore: Vec<String>,
    /// TDMS group holding the channels (default: `Tribometer`, or the file's only group).
    pub tdms_group: Option<String>,
    /// Text files: 1-based header line (default: found automatically).
    pub header_line: Option<u64>,
    /// Text files: delimiter (default: sniffed).
    pub delimiter: Option<crate::text_table::Delimiter>,
    /// Text files: decimal comma (default: sniffed).
    pub decimal_comma: Option<bool>,
    /// Spreadsheets: sheet name (default: the first sheet holding a table).
    pub sheet: Option<String>,
    /// Names for the file's columns in order (`--columns t_s,Fn_N,Ft_N`), units in the names
    /// as in any header; for a headerless log, whose columns are otherwise `#1`, `#2`, …, and
    /// for renaming the columns of a file with a header alike. Empty: the file's own names.
    pub columns: Vec<String>,
}

impl Default for ChannelMap {
    /// Every role found by its usual name; the layout `greybox synth` writes is one of them.
    fn default() -> Self {
        ChannelMap {
            time: None,
            time_unit: None,
            sample_rate_hz: None,
            normal: None,
            tangential: None,
            radial: None,
            trigger: None,
            step: None,
            speed: None,
            radius: None,
            cof: None,
            position: None,
            constant_normal_n: None,
            constant_sliding_m_s: None,
            rig: None,
            track_radius_mm: Vec::new(),
            auto: true,
            ignore: Vec::new(),
            tdms_group: None,
            header_line: None,
            delimiter: None,
            decimal_comma: None,
            sheet: None,
            columns: Vec::new(),
        }
    }
}

/// TDMS group used when none is named and the file has it.
pub const DEFAULT_TDMS_GROUP: &str = "Tribometer";

impl ChannelMap {
    /// The explicit mapping of a role, if any.
    fn spec(&self, role: Role) -> Option<ChannelSpec> {
        match role {
            Role::Time => self.time.as_ref().map(|t| ChannelSpec {
                name: t.clone(),
                unit: self.time_unit.map(|u| u.symbol().to_string()),
                scale: 1.0,
            }),
            Role::Normal => self.normal.clone(),
            Role::Tangential => self.tangential.clone(),
            Role::Radial => self.radial.clone(),
            Role::Trigger => self.trigger.as_deref().map(ChannelSpec::named),
            Role::Step => self.step.as_deref().map(ChannelSpec::named),
            Role::Speed => self.speed.clone(),
            Role::Radius => self.radius.clone(),
            Role::Cof => self.cof.clone(),
            Role::Position => self.position.clone(),
        }
    }

    /// Apply a `ROLE=NAME[:UNIT[:SCALE]]` override (roles: time, normal, tangential, radial,
    /// trigger, step, speed, radius). An empty name (`speed=`) means the file has no such
    /// channel: the role is not searched for.
    pub fn apply_override(&mut self, text: &str) -> Result<()> {
        let (role, spec) = text.split_once('=').ok_or_else(|| {
            Error::invalid(
                "channel mapping",
                format!("'{text}' is not ROLE=NAME[:UNIT[:SCALE]]"),
            )
        })?;
        let role = Role::parse(role).ok_or_else(|| {
            Error::invalid(
                "channel mapping",
                format!(
                    "unknown role '{}'; expected time, normal, tangential, radial, trigger, step, speed, radius, cof or position",
                    role.trim()
                ),
            )
        })?;
        if spec.trim().is_empty() {
            self.set(role, None);
            if !self.ignore.iter().any(|r| r == role.name()) {
                self.ignore.push(role.name().to_string());
            }
            return Ok(());
        }
        let parsed = ChannelSpec::parse(spec)?;
        if let Some(u) = &parsed.unit {
            check_unit(role, u)
                .map_err(|m| Error::invalid("channel mapping", format!("'{text}': {m}")))?;
        }
        self.ignore.retain(|r| r != role.name());
        self.set(role, Some(parsed));
        Ok(())
    }

    /// Whether the user mapped `role` explicitly.
    pub fn is_mapped(&self, role: Role) -> bool {
        self.spec(role).is_some()
    }

    /// Map `role` to a column (or unmap it with `None`).
    pub fn set_spec(&mut self, role: Role, spec: Option<ChannelSpec>) {
        self.set(role, spec)
    }

    fn set(&mut self, role: Role, spec: Option<ChannelSpec>) {
        match role {
            Role::Time => {
                self.time_unit = spec
                    .as_ref()
                    .and_then(|s| s.unit.as_deref())
                    .and_then(TimeUnit::parse);
                self.time = spec.map(|s| s.name);
            }
            Role::Normal => self.normal = spec,
            Role::Tangential => self.tangential = spec,
            Role::Radial => self.radial = spec,
            Role::Trigger => self.trigger = spec.map(|s| s.name),
            Role::Step => self.step = spec.map(|s| s.name),
            Role::Speed => self.speed = spec,
            Role::Radius => self.radius = spec,
            Role::Cof => self.cof = spec,
            Role::Position => self.position = spec,
        }
    }

    /// Options for the text-table reader.
    pub fn text_options(&self) -> crate::text_table::TextOptions {
        crate::text_table::TextOptions {
            header_line: self.header_line,
            delimiter: self.delimiter,
            decimal_comma: self.decimal_comma,
        }
    }
}

/// Check that a unit fits a role; the message lists the accepted spellings.
fn check_unit(role: Role, unit: &str) -> std::result::Result<(), String> {
    let ok = match role {
        Role::Normal | Role::Tangential | Role::Radial => ForceUnit::parse_lenient(unit).is_some(),
        Role::Time => TimeUnit::parse(unit).is_some(),
        Role::Speed => SpeedUnit::parse(unit).is_some(),
        Role::Radius | Role::Position => LengthUnit::parse(unit).is_some(),
        Role::Cof => cof_factor(unit).is_some(),
        Role::Trigger | Role::Step => true,
    };
    if ok {
        return Ok(());
    }
    Err(match role {
        Role::Normal | Role::Tangential | Role::Radial => {
            format!("unknown force unit '{unit}'; expected N, kN, daN, mN, lbf, gf (g) or kgf")
        }
        Role::Time => format!("unknown time unit '{unit}'; expected s, ms, us, min or h"),
        Role::Speed => format!(
            "unknown speed unit '{unit}'; expected rpm (1/min), rps, m/s, mm/s, cm/s or m/min"
        ),
        Role::Radius | Role::Position => {
            format!("unknown length unit '{unit}'; expected m, cm, mm or um (µm, micron)")
        }
        Role::Cof => {
            format!("unknown friction-coefficient unit '{unit}'; expected none, '-', '1' or '%'")
        }
        Role::Trigger | Role::Step => unreachable!("no unit check"),
    })
}

/// Which column each role takes, and how it was found.
fn assign_roles(table: &Table, map: &ChannelMap) -> Result<Vec<(Role, usize, bool)>> {
    let pos = || table.header_pos();
    let mut taken: Vec<(Role, usize, bool)> = Vec::new();
    // explicit mappings first, so that automatic ones never steal their columns
    for role in Role::ALL {
        if let Some(spec) = map.spec(role) {
            let idx = first_match(table, &spec.name).ok_or_else(|| {
                let has = match column_number(&spec.name) {
                    Some(_) => format!("the file's columns are {}", positions_list(table)),
                    None => format!("the header has: {}", table.header_list()),
                };
                Error::input(
                    pos().field(&spec.name),
                    format!(
                        "missing column '{}' (mapped as {}); {has}",
                        spec.name,
                        role.name(),
                    ),
                )
            })?;
            if let Some((other, _, _)) = taken.iter().find(|(_, i, _)| *i == idx) {
                return Err(Error::input(
                    pos().field(&table.columns[idx].header),
                    format!(
                        "column '{}' is mapped to two roles, {} and {}: each role needs its own column",
                        table.columns[idx].header,
                        other.name(),
                        role.name()
                    ),
                ));
            }
            taken.push((role, idx, true));
        }
    }
    if map.auto {
        for (role, aliases) in ROLE_ALIASES {
            if taken.iter().any(|(r, _, _)| *r == role)
                || map.ignore.iter().any(|r| r == role.name())
            {
                continue;
            }
            // a friction coefficient is never a force, whatever its name (`Friction (µ)`)
            let fits = |c: &Column| !(is_force(role) && looks_like_cof(c));
            let found = aliases.iter().find_map(|a| {
                (0..table.columns.len())
                    .find(|&i| column_matches(&table.columns[i], a) && fits(&table.columns[i]))
            });
            if let Some(idx) = found {
                match taken.iter().find(|(_, i, _)| *i == idx) {
                    // the role's usual column went to another role by an explicit mapping
                    Some((other, _, true)) if matches!(role, Role::Normal | Role::Tangential) => {
                        return Err(Error::input(
                            pos().field(&table.columns[idx].header),
                            format!(
                                "column '{}' is mapped as {} but is the file's {} column: one column cannot be two roles; map {} to its own column",
                                table.columns[idx].header,
                                other.name(),
                                role.name(),
                                role.name()
                            ),
                        ));
                    }
                    Some(_) => {}
                    None => taken.push((role, idx, false)),
                }
            }
        }
    }
    Ok(taken)
}

/// The first column matching `wanted` (the reader names a repeated header's later columns
/// `NAME #2`, … and notes it, so the first is the one that answers to the name); `#K` is the
/// column at 1-based position K in the file.
fn first_match(table: &Table, wanted: &str) -> Option<usize> {
    match column_number(wanted) {
        Some(k) => table.at_position(k),
        None => (0..table.columns.len()).find(|&i| column_matches(&table.columns[i], wanted)),
    }
}

/// `#K` in a mapping (`--map normal=#3:N`): column K of the file, counted from 1.
pub fn column_number(wanted: &str) -> Option<usize> {
    let k = wanted
        .trim()
        .strip_prefix('#')?
        .trim()
        .parse::<usize>()
        .ok()?;
    (k > 0).then_some(k)
}

/// Whether a column's name or unit says it holds a friction coefficient (`COF`, `µ`, `mu`,
/// `Friction coefficient`, `Reibwert`, a unit `-` or `µ`): such a column is never taken or
/// suggested as a force.
pub fn looks_like_cof(col: &Column) -> bool {
    let name = crate::table::normalise_name(&col.header);
    let says = name.split(|c: char| !c.is_alphanumeric()).any(|w| {
        matches!(
            w,
            "cof"
                | "mu"
                | "µ"
                | "μ"
                | "coefficient"
                | "coeff"
                | "coef"
                | "reibwert"
                | "reibungszahl"
                | "reibungskoeffizient"
        )
    });
    let unit = col
        .unit
        .as_deref()
        .is_some_and(|u| matches!(u.trim(), "-" | "µ" | "μ" | "mu" | "()" | "[-]" | "(-)"));
    says || unit
}

fn is_force(role: Role) -> bool {
    matches!(role, Role::Normal | Role::Tangential | Role::Radial)
}

/// Optional roles found by their usual name (not mapped) in a column that states no unit are
/// left out with a note, not an error: the identification does not need them.
fn drop_unitless_optional(
    table: &Table,
    map: &ChannelMap,
    roles: &mut Vec<(Role, usize, bool)>,
    notes: &mut Vec<String>,
) {
    roles.retain(|(role, idx, mapped)| {
        let optional = matches!(
            role,
            Role::Radial | Role::Speed | Role::Radius | Role::Position
        );
        let col = &table.columns[*idx];
        let unitless = map.spec(*role).and_then(|s| s.unit).is_none() && col.unit.is_none();
        if optional && !mapped && unitless {
            notes.push(format!(
                "column '{}' looks like the {} but states no unit: not used ({} uses it)",
                col.header,
                role.name(),
                map_flag(*role, &col.name, example_unit(*role))
            ));
            return false;
        }
        true
    });
}

/// One role a file leaves unresolved: why, the `--map` flag that resolves it, and other ways
/// (`or …`) shown beside it.
struct Unresolved {
    role: Role,
    why: String,
    flag: String,
    or: Option<String>,
}

/// `` `map` ROLE=NAME:UNIT ``, the mapping quoted for a shell where the name needs it (the
/// command line shows the setting as its flag).
fn map_flag(role: Role, name: &str, unit: &str) -> String {
    let arg = if unit.is_empty() {
        format!("{}={name}", role.name())
    } else {
        format!("{}={name}:{unit}", role.name())
    };
    let word = greybox_core::shell::word(&arg).unwrap_or_else(|_| arg.escape_debug().to_string());
    format!("`map` {word}")
}

/// The file's column positions for messages: `#1 to #3`, or `#1, #2, #5` where columns
/// without values were left out.
fn positions_list(table: &Table) -> String {
    let p: Vec<usize> = (0..table.columns.len())
        .map(|k| table.position(k))
        .collect();
    match (p.first(), p.last()) {
        (Some(a), Some(b)) if b - a + 1 == p.len() && p.len() > 2 => format!("#{a} to #{b}"),
        _ => p
            .iter()
            .map(|k| format!("#{k}"))
            .collect::<Vec<_>>()
            .join(", "),
    }
}

/// Every role the file and the map leave unresolved, all at once: missing forces (a friction
/// coefficient stands in for the friction force), a missing time without a sample rate, and
/// mapped or found columns whose unit nobody states.
fn unresolved(table: &Table, map: &ChannelMap, taken: &[(Role, usize, bool)]) -> Vec<Unresolved> {
    let has = |r: Role| taken.iter().any(|(t, _, _)| *t == r);
    let free: Vec<&Column> = table
        .columns
        .iter()
        .enumerate()
        .filter(|(i, c)| {
            !taken.iter().any(|(_, t, _)| t == i) && matches!(c.data, ColumnData::Numbers(_))
        })
        .map(|(_, c)| c)
        .collect();
    // a friction coefficient is never offered as a force
    let candidates = |role: Role| {
        let shown: Vec<String> = free
            .iter()
            .filter(|c| !(is_force(role) && looks_like_cof(c)))
            .take(8)
            .map(|c| format!("'{}'", c.header))
            .collect();
        if shown.is_empty() {
            "no unassigned numeric column".to_string()
        } else {
            format!("candidates: {}", shown.join(", "))
        }
    };
    let name = if table.headerless { "#K" } else { "NAME" };
    let mut out = Vec::new();
    let missing = |role: Role, what: &str, unit: &str| Unresolved {
        role,
        why: format!("no {what} column by a usual name ({})", candidates(role)),
        flag: map_flag(role, name, unit),
        or: None,
    };
    if !has(Role::Normal) && map.constant_normal_n.is_none() {
        let mut u = missing(Role::Normal, "normal force", "N");
        u.or = Some("for a dead-weight rig, `constant_normal_force_N` VALUE".into());
        out.push(u);
    }
    if !has(Role::Tangential) && !has(Role::Cof) {
        let mut u = missing(
            Role::Tangential,
            "friction force (tangential) or friction coefficient (cof)",
            "N",
        );
        let cof = free
            .iter()
            .find(|c| looks_like_cof(c))
            .map_or(name, |c| &c.name);
        u.or = Some(map_flag(Role::Cof, cof, ""));
        out.push(u);
    }
    if !has(Role::Time) && map.sample_rate_hz.is_none() && table.sample_interval_s.is_none() {
        let mut u = missing(Role::Time, "time", "s");
        // a headerless log's one increasing column is most likely its time
        let rising: Vec<&&Column> = free.iter().filter(|c| increasing(&c.data)).collect();
        if let ([c], true) = (&rising[..], table.headerless) {
            u.flag = map_flag(Role::Time, &c.name, "s");
        }
        u.or = Some("`sample_rate_hz` HZ".into());
        out.push(u);
    }
    for (role, idx, _) in taken {
        if matches!(role, Role::Trigger | Role::Step | Role::Cof) {
            continue;
        }
        let col = &table.columns[*idx];
        let stated = map
            .spec(*role)
            .and_then(|s| s.unit)
            .or_else(|| col.unit.clone());
        if stated.is_none() {
            // a column that says it is a friction coefficient is offered as one, not in N
            let cof = is_force(*role) && looks_like_cof(col);
            out.push(Unresolved {
                role: *role,
                why: format!("column '{}' states no unit", col.header),
                flag: match cof {
                    true => map_flag(Role::Cof, &col.name, ""),
                    false => map_flag(*role, &col.name, example_unit(*role)),
                },
                or: None,
            });
        }
    }
    out.sort_by_key(|u| Role::ALL.iter().position(|r| *r == u.role));
    out
}

/// One error for everything unresolved, with each role's candidates and the flags to pass.
fn unresolved_error(table: &Table, problems: &[Unresolved]) -> Error {
    let lines: Vec<String> = problems
        .iter()
        .map(|u| {
            let or =
                u.or.as_ref()
                    .map_or(String::new(), |o| format!(" (or {o})"));
            format!("  {}: {} → {}{or}", u.role.name(), u.why, u.flag)
        })
        .collect();
    let all: Vec<&str> = problems.iter().map(|u| u.flag.as_str()).collect();
    if table.headerless {
        return Error::input(
            SourcePos::file(&table.source),
            format!(
                "{} channel(s) unresolved in a file without a header line; its columns, by number:\n{}\n{}\nmap them by number, e.g. {} (columns counted from 1), or name them in order with `columns` NAME,NAME,… (units in the names, e.g. `columns` t_s,Fn_N,Ft_N); without a time column give `sample_rate_hz` HZ",
                problems.len(),
                column_overview(table),
                lines.join("\n"),
                all.join(" ")
            ),
        );
    }
    Error::input(
        SourcePos::file(&table.source).line(table.header_line),
        format!(
            "{} channel(s) unresolved (the header has: {}):\n{}\npass them together: {} (or name the rig with `rig` NAME; `rig` list lists the profiles)",
            problems.len(),
            table.header_list(),
            lines.join("\n"),
            all.join(" ")
        ),
    )
}

/// A column of at least two numbers, each above the one before (a time, most likely).
fn increasing(data: &ColumnData) -> bool {
    matches!(data, ColumnData::Numbers(v) if v.len() > 1 && v.windows(2).all(|w| w[1] > w[0]))
}

/// Each column of a table by number with its first values and what they look like, e.g.
/// `  #1: 0, 0.01, 0.02, … (increasing: time?)`.
fn column_overview(table: &Table) -> String {
    let lines: Vec<String> = table
        .columns
        .iter()
        .enumerate()
        .map(|(k, c)| {
            let label = match c.name == format!("#{}", table.position(k)) {
                true => c.name.clone(),
                false => format!("#{} '{}'", table.position(k), c.header),
            };
            let v = match &c.data {
                ColumnData::Numbers(v) => v,
                ColumnData::NotNumeric { line, text } => {
                    return format!("  {label}: not numbers ('{}' on line {line})", text.trim())
                }
            };
            let shown: Vec<String> = v.iter().take(4).map(|x| format!("{x}")).collect();
            let more = if v.len() > 4 { ", …" } else { "" };
            let looks = if increasing(&c.data) {
                " (increasing: time?)"
            } else if v.iter().all(|x| x.abs() <= 1.0) {
                " (all within ±1: friction coefficient?)"
            } else {
                ""
            };
            format!("  {label}: {}{more}{looks}", shown.join(", "))
        })
        .collect();
    lines.join("\n")
}

/// Convert a table into a recording through a channel map.
pub fn recording_from_table(mut table: Table, map: &ChannelMap) -> Result<Recording> {
    let mut notes = std::mem::take(&mut table.notes);
    let mut roles = assign_roles(&table, map)?;
    drop_unitless_optional(&table, map, &mut roles, &mut notes);
    let problems = unresolved(&table, map, &roles);
    if !problems.is_empty() {
        return Err(unresolved_error(&table, &problems));
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
    let tangential = take(Role::Tangential).map(|c| c.1);
    let (normal, tangential) =
        forces_by_convention(normal, tangential, cof.as_deref(), &mut report);
    let step = take(Role::Step)
        .map(|c| c.1)
        .or_else(|| block_steps(&table, n, &mut report));
    let time_s = match take(Role::Time) {
        Some((_, t, header)) => continuous_time(
            t,
            step.as_deref(),
            &source,
            &header,
            table.header_line,
            &mut report,
        )?,
        None => {
            let dt = map
                .sample_rate_hz
                .map(|f| 1.0 / f)
                .or(table.sample_interval_s)
                .filter(|d| d.is_finite() && *d > 0.0)
                .ok_or_else(|| {
                    Error::input(
                        SourcePos::file(&source),
                        "no time column (none mapped, none with a usual name) and no sample rate: give `sample_rate_hz` or map the time column with `map` time=NAME:UNIT",
                    )
                })?;
            let t0 = table.start_time_s.unwrap_or(0.0);
            report.notes.push(format!(
                "no time column: time from the sample rate {:.6} Hz",
                1.0 / dt
            ));
            (0..n).into_par_iter().map(|i| t0 + i as f64 * dt).collect()
        }
    };
    let speed = speed_trace(take(Role::Speed).map(|c| c.1), map, n, &mut report);
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

/// The speed channel as recorded (rpm where its unit turns, else m/s), else the stated
/// constant sliding velocity; without either, a note on how to give one (unless the user
/// said the file has no speed).
fn speed_trace(
    recorded: Option<Vec<f64>>,
    map: &ChannelMap,
    n: usize,
    report: &mut ReadReport,
) -> Option<SpeedTrace> {
    if let Some(v) = recorded {
        let unit = report
            .columns
            .iter()
            .find(|c| c.role == "speed")
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

/// A file of blocks (each with its own settings and header, as UMT and PCS exports write one
/// per step) without a step column: the block number is the step, so that a time restarting
/// in every block is made continuous and each block is a segment.
fn block_steps(table: &Table, n: usize, report: &mut ReadReport) -> Option<Vec<f64>> {
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
/// force, F_t = μ·F_N from the rig's own μ; with both, their disagreement is reported.
fn forces_by_convention(
    mut normal: Vec<f64>,
    tangential: Option<Vec<f64>>,
    cof: Option<&[f64]>,
    report: &mut ReadReport,
) -> (Vec<f64>, Vec<f64>) {
    if median(&normal) < 0.0 {
        normal.iter_mut().for_each(|v| *v = -*v);
        report
            .notes
            .push("the normal force is recorded negative (load-cell axis away from the contact): its sign was flipped".into());
    }
    let Some(ft) = tangential else {
        let mu = cof.expect("checked by `unresolved`");
        report.notes.push(
            "no friction-force column: F_t = μ·F_N from the rig's own friction coefficient (cof)"
                .into(),
        );
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

/// A rig's own μ further than this fraction of itself from F_t/F_N (median over the loaded
/// samples) is a line of the summary: the forces' units, a channel or the rig's own
/// computation are wrong, and only one of them was used.
pub const COF_DISAGREEMENT_FRACTION: f64 = 0.1;

/// Footer lines beyond this many are a line of the summary: a footer is an `End of data` or
/// a few summary lines, not hundreds of lines left unread.
pub const FOOTER_LINES_NOTED: usize = 5;

/// The summary line for a footer that is more than a few closing lines, or that holds
/// numbers (rows written with another delimiter, which the table's layout does not read).
fn footer_warning(footer: &[(u64, String)]) -> Option<String> {
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

/// How far the rig's own μ lies from F_t/F_N (both taken as magnitudes, loaded samples only),
/// and whether that is more than [`COF_DISAGREEMENT_FRACTION`] of the rig's μ.
fn cof_disagreement(normal: &[f64], ft: &[f64], mu: &[f64]) -> (String, bool) {
    let f_ref = median(normal).abs();
    let diffs: Vec<f64> = normal
        .iter()
        .zip(ft)
        .zip(mu)
        .filter(|((f, _), m)| f.abs() > 0.2 * f_ref && m.is_finite())
        .map(|((f, t), m)| (t / f).abs() - m.abs())
        .collect();
    if diffs.is_empty() {
        return (
            "the rig's own μ (cof) could not be compared with F_t/F_N: no loaded samples".into(),
            false,
        );
    }
    let med = median(&diffs);
    let worst = diffs.iter().fold(0.0f64, |w, d| w.max(d.abs()));
    let own: Vec<f64> = mu
        .iter()
        .filter(|m| m.is_finite())
        .map(|m| m.abs())
        .collect();
    let own = median(&own);
    let far = med.abs() > COF_DISAGREEMENT_FRACTION * own;
    let share = if own > 0.0 {
        format!(
            " ({:.0} % of the rig's μ {own:.4})",
            100.0 * med.abs() / own
        )
    } else {
        String::new()
    };
    (
        format!(
            "μ from the forces; the rig's own μ (cof) differs from F_t/F_N by {med:+.4} (median){share} and at most {worst:.4} over {} loaded samples",
            diffs.len()
        ),
        far,
    )
}

fn example_unit(role: Role) -> &'static str {
    match role {
        Role::Time => "s",
        Role::Speed => "rpm",
        Role::Radius | Role::Position => "mm",
        Role::Trigger => "V",
        _ => "N",
    }
}

/// Factor from a unit to SI (forces N, time s, radius m) or the speed base (rpm or m/s).
fn unit_factor(role: Role, unit: &str) -> f64 {
    match role {
        Role::Normal | Role::Tangential | Role::Radial => {
            ForceUnit::parse_lenient(unit).map_or(1.0, ForceUnit::to_newton)
        }
        Role::Time => TimeUnit::parse(unit).map_or(1.0, TimeUnit::to_second),
        Role::Speed => SpeedUnit::parse(unit).map_or(1.0, SpeedUnit::to_base),
        Role::Radius | Role::Position => LengthUnit::parse(unit).map_or(1.0, LengthUnit::to_metre),
        Role::Cof => cof_factor(unit).unwrap_or(1.0),
        Role::Trigger | Role::Step => 1.0,
    }
}

/// Factor from a friction-coefficient column's unit to a plain ratio: none, `-`, `1`, `()`
/// (as Rtec writes `DAQ.COF ()`) or `%`.
fn cof_factor(unit: &str) -> Option<f64> {
    match unit.trim() {
        "" | "-" | "1" | "()" | "[]" | "[-]" | "(-)" | "N/N" => Some(1.0),
        "%" => Some(0.01),
        _ => None,
    }
}

fn same_unit(role: Role, a: &str, b: &str) -> bool {
    if a.trim() == b.trim() {
        return true;
    }
    match role {
        Role::Speed => match (SpeedUnit::parse(a), SpeedUnit::parse(b)) {
            (Some(x), Some(y)) => x == y,
            _ => false,
        },
        _ => {
            check_unit(role, a).is_ok()
                && check_unit(role, b).is_ok()
                && unit_factor(role, a) == unit_factor(role, b)
        }
    }
}

/// Times in s, made continuous where the rig restarts its clock at every step (a time that
/// falls where the step number changes is shifted to follow the previous step by one
/// sample interval). A time that falls anywhere else is an error naming its line.
fn continuous_time(
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
fn convert_channels(
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
            role: role.name().to_string(),
            column: header.clone(),
            unit: unit_name,
            scale,
            how: if *mapped { "mapped" } else { "auto" }.to_string(),
        });
        channels.push((*role, values, header));
    }
    Ok(channels)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn column_numbers_and_cof_names() {
        assert_eq!(column_number("#3"), Some(3));
        assert_eq!(column_number(" # 12 "), Some(12));
        for not in ["#0", "#", "3", "F #2", "#x"] {
            assert_eq!(column_number(not), None, "{not}");
        }
        let cof = |h: &str| looks_like_cof(&Column::numbers(h, Vec::new()));
        for h in [
            "COF",
            "DAQ.COF ()",
            "µ",
            "Mu kinetic",
            "Friction coefficient",
            "Friction coeff.",
            "Reibwert",
            "Friction (-)",
            "Friction (µ)",
            "COF_avg",
        ] {
            assert!(cof(h), "{h}");
        }
        for h in [
            "Friction force (N)",
            "Fx",
            "Load",
            "Friction",
            "Muffle temp (K)",
        ] {
            assert!(!cof(h), "{h}");
        }
        let spec = ChannelSpec::parse("#3:N").unwrap();
        assert_eq!(
            (spec.name.as_str(), spec.unit.as_deref()),
            ("#3", Some("N"))
        );
    }

    /// The parallel block screens find the same index as a plain scan, at block edges too.
    #[test]
    fn screens_find_the_first_bad_sample() {
        let n = 3 * (1 << 14) + 17;
        let good: Vec<f64> = (0..n).map(|i| i as f64 * 1e-3).collect();
        assert_eq!(first_non_finite(&good), None);
        assert_eq!(first_non_increasing(&good), None);
        for at in [
            0,
            1,
            (1 << 14) - 1,
            1 << 14,
            (1 << 14) + 1,
            2 * (1 << 14),
            n - 1,
        ] {
            for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
                let mut v = good.clone();
                v[at] = bad;
                v[n - 1] = f64::NAN;
                assert_eq!(first_non_finite(&v), Some(at), "{bad} at {at}");
            }
            let mut t = good.clone();
            t[at] = if at == 0 { 1e9 } else { t[at - 1] };
            let want = t.windows(2).position(|w| !(w[1] > w[0]));
            assert_eq!(first_non_increasing(&t), want, "repeat at {at}");
        }
    }
}
