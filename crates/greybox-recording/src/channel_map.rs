//! Which column plays which role: the user's mapping ([`ChannelMap`], study TOML `[recording]`,
//! `identify --map`).

use super::map_keys;
use super::reader_options::ReaderOptions;
use super::roles::{check_unit, ChannelSpec, Role};
use greybox_core::units::TimeUnit;
use greybox_core::{Error, Result};
use serde::{Deserialize, Serialize};

/// How to find the channels of a recording (study TOML `[recording]`, `identify --map`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(
    from = "super::map_keys::ChannelMap",
    into = "super::map_keys::ChannelMap"
)]
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
    /// How the file is read (delimiter, decimal comma, header line, sheet, TDMS group,
    /// column names): the same keys as the map's own in a study's `[recording]`
    /// (see `map_keys`).
    pub reader: ReaderOptions,
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
            reader: ReaderOptions::default(),
        }
    }
}

/// TDMS group used when none is named and the file has it.
pub const DEFAULT_TDMS_GROUP: &str = "Tribometer";

impl ChannelMap {
    /// The explicit mapping of a role, if any.
    pub(super) fn spec(&self, role: Role) -> Option<ChannelSpec> {
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
}

/// `` `map` ROLE=NAME:UNIT ``, the mapping quoted for a shell where the name needs it (the
/// command line shows the setting as its flag).
pub(super) fn map_flag(role: Role, name: &str, unit: &str) -> String {
    let arg = if unit.is_empty() {
        format!("{}={name}", role.name())
    } else {
        format!("{}={name}:{unit}", role.name())
    };
    let word = greybox_core::shell::word(&arg).unwrap_or_else(|_| arg.escape_debug().to_string());
    format!("`map` {word}")
}

// The study file's flat keys, both ways.
impl Default for map_keys::ChannelMap {
    fn default() -> Self {
        ChannelMap::default().into()
    }
}

impl From<map_keys::ChannelMap> for ChannelMap {
    fn from(k: map_keys::ChannelMap) -> Self {
        ChannelMap {
            time: k.time,
            time_unit: k.time_unit,
            sample_rate_hz: k.sample_rate_hz,
            normal: k.normal,
            tangential: k.tangential,
            radial: k.radial,
            trigger: k.trigger,
            step: k.step,
            speed: k.speed,
            radius: k.radius,
            cof: k.cof,
            position: k.position,
            constant_normal_n: k.constant_normal_n,
            constant_sliding_m_s: k.constant_sliding_m_s,
            rig: k.rig,
            track_radius_mm: k.track_radius_mm,
            auto: k.auto,
            ignore: k.ignore,
            reader: ReaderOptions {
                tdms_group: k.tdms_group,
                header_line: k.header_line,
                delimiter: k.delimiter,
                decimal_comma: k.decimal_comma,
                sheet: k.sheet,
                columns: k.columns,
            },
        }
    }
}

impl From<ChannelMap> for map_keys::ChannelMap {
    fn from(m: ChannelMap) -> Self {
        map_keys::ChannelMap {
            time: m.time,
            time_unit: m.time_unit,
            sample_rate_hz: m.sample_rate_hz,
            normal: m.normal,
            tangential: m.tangential,
            radial: m.radial,
            trigger: m.trigger,
            step: m.step,
            speed: m.speed,
            radius: m.radius,
            cof: m.cof,
            position: m.position,
            constant_normal_n: m.constant_normal_n,
            constant_sliding_m_s: m.constant_sliding_m_s,
            rig: m.rig,
            track_radius_mm: m.track_radius_mm,
            auto: m.auto,
            ignore: m.ignore,
            tdms_group: m.reader.tdms_group,
            header_line: m.reader.header_line,
            delimiter: m.reader.delimiter,
            decimal_comma: m.reader.decimal_comma,
            sheet: m.reader.sheet,
            columns: m.reader.columns,
        }
    }
}
