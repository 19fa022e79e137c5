//! The roles a column can play, their usual names, and a role's column with its unit and scale
//! ([`ChannelSpec`]).

use greybox_core::units::{ForceUnit, LengthUnit, SpeedUnit, TimeUnit};
use greybox_core::{Error, Result};
use serde::{Deserialize, Serialize};

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

pub(super) fn one() -> f64 {
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

greybox_core::choice!(Role, "role", [
    Time => "time",
    Normal => "normal",
    Tangential => "tangential",
    Radial => "radial",
    Trigger => "trigger",
    Step => "step",
    Speed => "speed",
    Radius => "radius",
    Cof => "cof",
    Position => "position",
]);

impl Role {
    /// Every role, in the order of the list above.
    pub const ALL: &'static [Role] = <Role as greybox_core::choice::Choice>::ALL;
    pub fn name(self) -> &'static str {
        greybox_core::choice::Choice::name(self)
    }
    pub fn parse(s: &str) -> Option<Role> {
        Role::ALL.iter().copied().find(|r| r.name() == s.trim())
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

/// Check that a unit fits a role; the message lists the accepted spellings.
pub(super) fn check_unit(role: Role, unit: &str) -> std::result::Result<(), String> {
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

pub(super) fn example_unit(role: Role) -> &'static str {
    match role {
        Role::Time => "s",
        Role::Speed => "rpm",
        Role::Radius | Role::Position => "mm",
        Role::Trigger => "V",
        _ => "N",
    }
}

/// Factor from a unit to SI (forces N, time s, radius m) or the speed base (rpm or m/s).
pub(super) fn unit_factor(role: Role, unit: &str) -> f64 {
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
pub(super) fn cof_factor(unit: &str) -> Option<f64> {
    match unit.trim() {
        "" | "-" | "1" | "()" | "[]" | "[-]" | "(-)" | "N/N" => Some(1.0),
        "%" => Some(0.01),
        _ => None,
    }
}

pub(super) fn same_unit(role: Role, a: &str, b: &str) -> bool {
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
