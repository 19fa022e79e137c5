//! Raw tribometer recordings and how their channels map onto roles.

use greybox_core::units::{ForceUnit, TimeUnit};
use greybox_core::{Error, Result, SourcePos};
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
}

impl Recording {
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
        let channels: [(&str, Option<&Vec<f64>>); 4] = [
            ("normal", Some(&self.normal_n)),
            ("tangential", Some(&self.tangential_n)),
            ("radial", self.radial_n.as_ref()),
            ("trigger", self.trigger_v.as_ref()),
        ];
        for (name, ch) in channels {
            if let Some(ch) = ch {
                if ch.len() != n {
                    return Err(Error::input(
                        pos().field(name),
                        format!("channel has {} samples, time has {n}", ch.len()),
                    ));
                }
                if let Some(i) = ch.iter().position(|v| !v.is_finite()) {
                    return Err(Error::input(
                        pos().field(name),
                        format!("sample {i} is not finite ({})", ch[i]),
                    ));
                }
            }
        }
        if let Some(i) = self.time_s.windows(2).position(|w| !(w[1] > w[0])) {
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

/// Where a force channel comes from: column/channel name, unit and an extra scale (e.g. −1 to
/// flip a dynamometer axis).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ChannelSpec {
    /// CSV column or TDMS channel name.
    pub name: String,
    /// Unit; if absent it is taken from the column-name suffix (`Fz_kN`) or the TDMS
    /// `unit_string` property, and it is an error if neither names one.
    #[serde(default)]
    pub unit: Option<ForceUnit>,
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
    /// Parse `NAME[:UNIT[:SCALE]]`, e.g. `Fz:kN:-1`.
    pub fn parse(text: &str) -> Result<Self> {
        let mut parts = text.split(':');
        let name = parts.next().unwrap_or("").trim();
        if name.is_empty() {
            return Err(Error::invalid(
                "channel mapping",
                format!("'{text}' has no column name (expected NAME[:UNIT[:SCALE]])"),
            ));
        }
        let unit = match parts.next() {
            Some(u) => Some(ForceUnit::parse(u).ok_or_else(|| {
                Error::invalid(
                    "channel mapping",
                    format!("unknown force unit '{u}' in '{text}'; expected N, kN, daN, mN or lbf"),
                )
            })?),
            None => None,
        };
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
    name.rsplit_once('_')
        .and_then(|(_, suffix)| ForceUnit::parse(suffix))
}

/// Unit suffix of a time column: `time_ms` → ms.
pub fn time_unit_from_name(name: &str) -> Option<TimeUnit> {
    name.rsplit_once('_')
        .and_then(|(_, suffix)| TimeUnit::parse(suffix))
}

/// How to find the channels of a recording (study TOML `[recording]`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ChannelMap {
    /// Time column/channel; its unit from the suffix (`time_s`, `time_ms`) or `time_unit`.
    /// If absent, time comes from `sample_rate_hz` (CSV) or the TDMS `wf_increment` property.
    pub time: Option<String>,
    pub time_unit: Option<TimeUnit>,
    /// Sample rate when there is no time column, Hz.
    pub sample_rate_hz: Option<f64>,
    pub normal: ChannelSpec,
    pub tangential: ChannelSpec,
    pub radial: Option<ChannelSpec>,
    /// Trigger channel (volts).
    pub trigger: Option<String>,
    /// TDMS group holding the channels.
    pub tdms_group: String,
}

impl Default for ChannelMap {
    /// The layout `greybox synth` writes.
    fn default() -> Self {
        ChannelMap {
            time: Some("time_s".into()),
            time_unit: None,
            sample_rate_hz: None,
            normal: ChannelSpec::named("normal_force_N"),
            tangential: ChannelSpec::named("tangential_force_N"),
            radial: Some(ChannelSpec::named("radial_force_N")),
            trigger: Some("trigger_V".into()),
            tdms_group: "Tribometer".into(),
        }
    }
}

impl ChannelMap {
    /// Apply a `ROLE=NAME[:UNIT[:SCALE]]` override (roles: time, normal, tangential, radial,
    /// trigger; `radial=` or `trigger=` with an empty name removes the channel).
    pub fn apply_override(&mut self, text: &str) -> Result<()> {
        let (role, spec) = text.split_once('=').ok_or_else(|| {
            Error::invalid(
                "channel mapping",
                format!("'{text}' is not ROLE=NAME[:UNIT[:SCALE]]"),
            )
        })?;
        match role.trim() {
            "normal" => self.normal = ChannelSpec::parse(spec)?,
            "tangential" => self.tangential = ChannelSpec::parse(spec)?,
            "radial" if spec.trim().is_empty() => self.radial = None,
            "radial" => self.radial = Some(ChannelSpec::parse(spec)?),
            "trigger" if spec.trim().is_empty() => self.trigger = None,
            "trigger" => self.trigger = Some(spec.trim().to_string()),
            "time" => {
                let (name, unit) = match spec.split_once(':') {
                    Some((n, u)) => (
                        n,
                        Some(TimeUnit::parse(u).ok_or_else(|| {
                            Error::invalid(
                                "channel mapping",
                                format!("unknown time unit '{u}'; expected s, ms or us"),
                            )
                        })?),
                    ),
                    None => (spec, None),
                };
                self.time = if name.trim().is_empty() {
                    None
                } else {
                    Some(name.trim().to_string())
                };
                self.time_unit = unit;
            }
            other => {
                return Err(Error::invalid(
                    "channel mapping",
                    format!(
                    "unknown role '{other}'; expected time, normal, tangential, radial or trigger"
                ),
                ))
            }
        }
        Ok(())
    }
}

/// File formats of raw recordings.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum RecordingFormat {
    Csv,
    Tdms,
}

impl RecordingFormat {
    pub fn extension(self) -> &'static str {
        match self {
            RecordingFormat::Csv => "csv",
            RecordingFormat::Tdms => "tdms",
        }
    }
    /// The format a file name's extension says.
    pub fn of_path(path: &std::path::Path) -> Option<Self> {
        match path.extension()?.to_str()?.to_ascii_lowercase().as_str() {
            "csv" => Some(RecordingFormat::Csv),
            "tdms" => Some(RecordingFormat::Tdms),
            _ => None,
        }
    }
}

/// Read a recording, choosing the reader from the file extension (`.csv` or `.tdms`).
pub fn read_recording(path: &std::path::Path, map: &ChannelMap) -> Result<Recording> {
    match RecordingFormat::of_path(path) {
        Some(RecordingFormat::Csv) => crate::csv_recording::read_csv_recording(path, map),
        Some(RecordingFormat::Tdms) => crate::tdms::read_tdms_recording(path, map),
        None => Err(Error::input(
            SourcePos::path(path),
            "unknown recording format: expected a .csv or .tdms file",
        )),
    }
}
