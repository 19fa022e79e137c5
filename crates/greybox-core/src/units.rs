//! Unit conversions used only at the edges (CLI flags, file columns).
//! Inside greybox everything is SI: N, Pa, m, m/s, s, K.

/// Pa per MPa.
pub const PA_PER_MPA: f64 = 1.0e6;
/// Pa per GPa.
pub const PA_PER_GPA: f64 = 1.0e9;
/// m per mm.
pub const M_PER_MM: f64 = 1.0e-3;
/// mm per m.
pub const MM_PER_M: f64 = 1.0e3;
/// MPa per Pa.
pub const MPA_PER_PA: f64 = 1.0e-6;
/// m per µm.
pub const M_PER_UM: f64 = 1.0e-6;
/// Seconds per minute.
pub const S_PER_MIN: f64 = 60.0;

/// mm → m.
pub fn mm_to_m(x: f64) -> f64 {
    x * M_PER_MM
}
/// µm → m.
pub fn um_to_m(x: f64) -> f64 {
    x * M_PER_UM
}
/// A quantity per mm → per m (N/mm → N/m: ×1000).
pub fn per_mm_to_per_m(x: f64) -> f64 {
    x / M_PER_MM
}
/// Bytes → kB (10³ bytes), for reports of sizes.
pub fn bytes_to_kb(bytes: u64) -> f64 {
    bytes as f64 / 1e3
}
/// MPa → Pa.
pub fn mpa_to_pa(p: f64) -> f64 {
    p * PA_PER_MPA
}
/// Pa → MPa.
pub fn pa_to_mpa(p: f64) -> f64 {
    p / PA_PER_MPA
}
/// The Kelvin temperature of 0 °C.
pub const KELVIN_AT_0_C: f64 = 273.15;
/// °C → K.
pub fn celsius_to_kelvin(t: f64) -> f64 {
    t + KELVIN_AT_0_C
}
/// m/min → m/s.
pub fn m_per_min_to_m_per_s(v: f64) -> f64 {
    v / S_PER_MIN
}
/// m/s → m/min.
pub fn m_per_s_to_m_per_min(v: f64) -> f64 {
    v * S_PER_MIN
}
/// Spindle speed n in rpm for a sliding velocity v (m/s) on a track of radius R (m):
/// n = v / (2 π R) · 60.
pub fn rpm_for_velocity(v_m_s: f64, radius_m: f64) -> f64 {
    v_m_s / (2.0 * std::f64::consts::PI * radius_m) * S_PER_MIN
}
/// Sliding velocity (m/s) at spindle speed n (rpm) on track radius R (m): v = 2 π R n / 60.
pub fn velocity_for_rpm(rpm: f64, radius_m: f64) -> f64 {
    2.0 * std::f64::consts::PI * radius_m * rpm / S_PER_MIN
}

/// A force unit as it may appear in a recording column; converts to newtons.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum ForceUnit {
    #[serde(rename = "N")]
    Newton,
    #[serde(rename = "kN")]
    Kilonewton,
    #[serde(rename = "daN")]
    Decanewton,
    #[serde(rename = "mN")]
    Millinewton,
    #[serde(rename = "lbf")]
    PoundForce,
    /// Gram-force (UMT and load-cell rigs log forces in g): g_n × 1e-3 N.
    #[serde(rename = "gf")]
    GramForce,
    /// Kilogram-force (kgf, kp): g_n N.
    #[serde(rename = "kgf")]
    KilogramForce,
}

/// Standard gravity g_n, m/s² (CGPM 1901; ISO 80000-3), defining the gram- and kilogram-force.
pub const STANDARD_GRAVITY_M_PER_S2: f64 = 9.806_65;

impl ForceUnit {
    /// Newtons per one of this unit.
    pub fn to_newton(self) -> f64 {
        match self {
            ForceUnit::Newton => 1.0,
            ForceUnit::Kilonewton => 1.0e3,
            ForceUnit::Decanewton => 10.0,
            ForceUnit::Millinewton => 1.0e-3,
            ForceUnit::PoundForce => 4.448_221_615_260_5,
            ForceUnit::GramForce => STANDARD_GRAVITY_M_PER_S2 * 1e-3,
            ForceUnit::KilogramForce => STANDARD_GRAVITY_M_PER_S2,
        }
    }
    pub const ALL: [ForceUnit; 7] = [
        ForceUnit::Newton,
        ForceUnit::Kilonewton,
        ForceUnit::Decanewton,
        ForceUnit::Millinewton,
        ForceUnit::PoundForce,
        ForceUnit::GramForce,
        ForceUnit::KilogramForce,
    ];
    pub fn symbol(self) -> &'static str {
        match self {
            ForceUnit::Newton => "N",
            ForceUnit::Kilonewton => "kN",
            ForceUnit::Decanewton => "daN",
            ForceUnit::Millinewton => "mN",
            ForceUnit::PoundForce => "lbf",
            ForceUnit::GramForce => "gf",
            ForceUnit::KilogramForce => "kgf",
        }
    }
    /// Parse a unit symbol (case-sensitive, as in SI: `N`, `kN`, `daN`, `mN`, `lbf`).
    pub fn parse(s: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|u| u.symbol() == s.trim())
    }
    /// Parse a unit as rig software spells it in column names: the SI symbols, and also
    /// `KN`, `kn`, `n`, `DAN`, `LBF`, `lb`. `MN` stays unknown (meganewton or millinewton?).
    pub fn parse_lenient(s: &str) -> Option<Self> {
        let t = s.trim();
        Self::parse(t).or(match t {
            "n" => Some(ForceUnit::Newton),
            "KN" | "kn" | "Kn" => Some(ForceUnit::Kilonewton),
            "DAN" | "dan" | "DaN" => Some(ForceUnit::Decanewton),
            "LBF" | "lb" | "lbs" | "Lbf" => Some(ForceUnit::PoundForce),
            // a force column "in g" (UMT, load cells) is gram-force: g is never a force unit
            "g" | "grams" | "gram" | "GF" | "grf" | "gr" => Some(ForceUnit::GramForce),
            "kg" | "KGF" | "Kgf" | "kp" | "kilogram" => Some(ForceUnit::KilogramForce),
            _ => None,
        })
    }
}

/// A speed unit of a recorded speed channel: a spindle speed (needs the track radius to
/// become a sliding velocity) or a sliding velocity.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum SpeedUnit {
    /// Revolutions per minute.
    #[serde(rename = "rpm")]
    Rpm,
    /// Revolutions per second.
    #[serde(rename = "rps")]
    RevPerSecond,
    #[serde(rename = "m/s")]
    MetrePerSecond,
    #[serde(rename = "mm/s")]
    MillimetrePerSecond,
    #[serde(rename = "cm/s")]
    CentimetrePerSecond,
    #[serde(rename = "m/min")]
    MetrePerMinute,
}

impl SpeedUnit {
    pub const ALL: [SpeedUnit; 6] = [
        SpeedUnit::Rpm,
        SpeedUnit::RevPerSecond,
        SpeedUnit::MetrePerSecond,
        SpeedUnit::MillimetrePerSecond,
        SpeedUnit::CentimetrePerSecond,
        SpeedUnit::MetrePerMinute,
    ];
    pub fn symbol(self) -> &'static str {
        match self {
            SpeedUnit::Rpm => "rpm",
            SpeedUnit::RevPerSecond => "rps",
            SpeedUnit::MetrePerSecond => "m/s",
            SpeedUnit::MillimetrePerSecond => "mm/s",
            SpeedUnit::CentimetrePerSecond => "cm/s",
            SpeedUnit::MetrePerMinute => "m/min",
        }
    }
    /// True for spindle speeds (revolutions per time), false for sliding velocities.
    pub fn is_rotational(self) -> bool {
        matches!(self, SpeedUnit::Rpm | SpeedUnit::RevPerSecond)
    }
    /// Factor to rpm (rotational units) or to m/s (sliding units).
    pub fn to_base(self) -> f64 {
        match self {
            SpeedUnit::Rpm => 1.0,
            SpeedUnit::RevPerSecond => 60.0,
            SpeedUnit::MetrePerSecond => 1.0,
            SpeedUnit::MillimetrePerSecond => 1.0e-3,
            SpeedUnit::CentimetrePerSecond => 1.0e-2,
            SpeedUnit::MetrePerMinute => 1.0 / S_PER_MIN,
        }
    }
    /// Parse the usual spellings: `rpm`, `1/min`, `min^-1`, `min-1`, `U/min`, `r/min`,
    /// `rev/min`, `rps`, `1/s` is *not* accepted (ambiguous), `Hz`/`rev/s` for rps, `m/s`,
    /// `mm/s`, `cm/s`, `m/min`, `mps`, the `_per_` forms (`m_per_s`, `m_per_min`, `mm_per_s`).
    pub fn parse(s: &str) -> Option<Self> {
        let t = s.trim().to_ascii_lowercase().replace(' ', "");
        Some(match t.as_str() {
            "rpm" | "1/min" | "min^-1" | "min-1" | "min⁻¹" | "u/min" | "r/min" | "rev/min"
            | "rev_per_min" => SpeedUnit::Rpm,
            "rps" | "rev/s" | "hz" | "rev_per_s" => SpeedUnit::RevPerSecond,
            "m/s" | "mps" | "m_per_s" | "m/sec" => SpeedUnit::MetrePerSecond,
            "mm/s" | "mm_per_s" | "mm/sec" => SpeedUnit::MillimetrePerSecond,
            "cm/s" | "cm_per_s" => SpeedUnit::CentimetrePerSecond,
            "m/min" | "m_per_min" | "mpm" => SpeedUnit::MetrePerMinute,
            _ => return None,
        })
    }
}

/// A length unit (track radius columns and flags); converts to metres.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum LengthUnit {
    #[serde(rename = "m")]
    Metre,
    #[serde(rename = "cm")]
    Centimetre,
    #[serde(rename = "mm")]
    Millimetre,
    #[serde(rename = "um")]
    Micrometre,
}

impl LengthUnit {
    pub fn to_metre(self) -> f64 {
        match self {
            LengthUnit::Metre => 1.0,
            LengthUnit::Centimetre => 1.0e-2,
            LengthUnit::Millimetre => 1.0e-3,
            LengthUnit::Micrometre => 1.0e-6,
        }
    }
    pub fn symbol(self) -> &'static str {
        match self {
            LengthUnit::Metre => "m",
            LengthUnit::Centimetre => "cm",
            LengthUnit::Millimetre => "mm",
            LengthUnit::Micrometre => "um",
        }
    }
    pub fn parse(s: &str) -> Option<Self> {
        match s.trim() {
            "m" => Some(LengthUnit::Metre),
            "cm" => Some(LengthUnit::Centimetre),
            "mm" => Some(LengthUnit::Millimetre),
            "um" | "µm" | "μm" | "micron" | "microns" | "micrometre" | "micrometer" => {
                Some(LengthUnit::Micrometre)
            }
            _ => None,
        }
    }
}

/// A time unit as it may appear in a recording column; converts to seconds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum TimeUnit {
    #[serde(rename = "s")]
    Second,
    #[serde(rename = "ms")]
    Millisecond,
    #[serde(rename = "us")]
    Microsecond,
    #[serde(rename = "min")]
    Minute,
    #[serde(rename = "h")]
    Hour,
}

impl TimeUnit {
    pub fn to_second(self) -> f64 {
        match self {
            TimeUnit::Second => 1.0,
            TimeUnit::Millisecond => 1.0e-3,
            TimeUnit::Microsecond => 1.0e-6,
            TimeUnit::Minute => S_PER_MIN,
            TimeUnit::Hour => 3600.0,
        }
    }
    pub fn symbol(self) -> &'static str {
        match self {
            TimeUnit::Second => "s",
            TimeUnit::Millisecond => "ms",
            TimeUnit::Microsecond => "us",
            TimeUnit::Minute => "min",
            TimeUnit::Hour => "h",
        }
    }
    pub fn parse(s: &str) -> Option<Self> {
        match s.trim() {
            "s" | "sec" | "S" => Some(TimeUnit::Second),
            "ms" | "msec" => Some(TimeUnit::Millisecond),
            "us" | "µs" | "μs" => Some(TimeUnit::Microsecond),
            "min" => Some(TimeUnit::Minute),
            "h" => Some(TimeUnit::Hour),
            _ => None,
        }
    }
}

/// The pressure (stress) unit of a table's column for an FE engine.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum PressureUnit {
    Pa,
    #[serde(rename = "MPa")]
    MPa,
}

impl PressureUnit {
    /// Units of this per Pa (the factor a Pa value is multiplied by: 1 or 10⁻⁶).
    pub fn per_pa(self) -> f64 {
        match self {
            PressureUnit::Pa => 1.0,
            PressureUnit::MPa => MPA_PER_PA,
        }
    }
    /// Pa of a number in this unit (exact factors: Pa·1, MPa·10⁶).
    pub fn to_pa(self, x: f64) -> f64 {
        match self {
            PressureUnit::Pa => x,
            PressureUnit::MPa => mpa_to_pa(x),
        }
    }
    /// The unit's symbol.
    pub fn name(self) -> &'static str {
        match self {
            PressureUnit::Pa => "Pa",
            PressureUnit::MPa => "MPa",
        }
    }
}

/// The sliding-velocity unit of a table's column for an FE engine.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum VelocityUnit {
    #[serde(rename = "m/s")]
    MPerS,
    #[serde(rename = "mm/s")]
    MmPerS,
    #[serde(rename = "m/min")]
    MPerMin,
    /// mm/ms: numerically m/s, the speed unit of the g–mm–ms and kg–mm–ms sets.
    #[serde(rename = "mm/ms")]
    MmPerMs,
}

impl VelocityUnit {
    /// Units of this per m/s (the factor an m/s value is multiplied by: 1, 10³ or 60).
    pub fn per_m_s(self) -> f64 {
        match self {
            VelocityUnit::MPerS => 1.0,
            VelocityUnit::MmPerS => MM_PER_M,
            VelocityUnit::MPerMin => S_PER_MIN,
            VelocityUnit::MmPerMs => 1.0,
        }
    }
    /// m/s of a number in this unit (divided by an exact 1, 10³ or 60).
    pub fn to_m_s(self, x: f64) -> f64 {
        match self {
            VelocityUnit::MPerS => x,
            VelocityUnit::MmPerS => x / MM_PER_M,
            VelocityUnit::MPerMin => m_per_min_to_m_per_s(x),
            VelocityUnit::MmPerMs => x,
        }
    }
    /// The unit's symbol.
    pub fn name(self) -> &'static str {
        match self {
            VelocityUnit::MPerS => "m/s",
            VelocityUnit::MmPerS => "mm/s",
            VelocityUnit::MPerMin => "m/min",
            VelocityUnit::MmPerMs => "mm/ms",
        }
    }
}

/// The temperature unit of a table's column: kelvin or degrees Celsius.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum TemperatureUnit {
    K,
    C,
}

crate::choice!(TemperatureUnit, "temperature_unit", [C => "C", K => "K"], text);

impl TemperatureUnit {
    /// A temperature t in K, in this unit.
    pub fn from_k(self, t: f64) -> f64 {
        match self {
            TemperatureUnit::K => t,
            TemperatureUnit::C => t - KELVIN_AT_0_C,
        }
    }
    /// K of a number in this unit.
    pub fn to_k(self, x: f64) -> f64 {
        match self {
            TemperatureUnit::K => x,
            TemperatureUnit::C => celsius_to_kelvin(x),
        }
    }
    /// The unit's name (its [`Choice`](crate::choice::Choice) name).
    pub fn name(self) -> &'static str {
        crate::choice::Choice::name(self)
    }
}

/// A number as a person reads it in a message: plain where that is short, in scientific
/// notation for the very large and very small (a `1e308` typed by mistake is not printed
/// as 309 digits).
#[derive(Debug, Clone, Copy)]
pub struct Compact(pub f64);

impl std::fmt::Display for Compact {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let a = self.0.abs();
        if a == 0.0 || !a.is_finite() || (1e-4..1e7).contains(&a) {
            write!(f, "{}", self.0)
        } else {
            write!(f, "{:e}", self.0)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    #[test]
    fn rpm_velocity_round_trip() {
        let r = 0.1;
        let n = rpm_for_velocity(m_per_min_to_m_per_s(20.0), r);
        assert!((n - 31.830_988_618).abs() < 1e-6);
        assert!((m_per_s_to_m_per_min(velocity_for_rpm(n, r)) - 20.0).abs() < 1e-12);
    }
    #[test]
    fn units_parse() {
        assert_eq!(ForceUnit::parse("kN"), Some(ForceUnit::Kilonewton));
        assert_eq!(ForceUnit::parse("tonf"), None);
        assert_eq!(TimeUnit::parse("ms"), Some(TimeUnit::Millisecond));
    }
}

/// clap parsers that read a flag in its edge unit and give the SI value the settings field
/// holds (feature `clap`): the conversion is an attribute of the field, not a second struct
/// (`#[arg(long = "speed-m-per-min", value_parser = m_per_min_as_m_per_s)] speed_m_per_s`).
#[cfg(feature = "clap")]
pub mod clap_parsers {
    fn number(s: &str) -> Result<f64, String> {
        s.trim()
            .parse::<f64>()
            .map_err(|_| format!("'{s}' is not a number"))
    }
    /// A velocity given in m/min, as m/s.
    pub fn m_per_min_as_m_per_s(s: &str) -> Result<f64, String> {
        number(s).map(super::m_per_min_to_m_per_s)
    }
    /// A pressure or stress given in MPa, as Pa.
    pub fn mpa_as_pa(s: &str) -> Result<f64, String> {
        number(s).map(super::mpa_to_pa)
    }
}
