//! Unit conversions used only at the edges (CLI flags, file columns).
//! Inside greybox everything is SI: N, Pa, m, m/s, s, K.

/// Pa per MPa.
pub const PA_PER_MPA: f64 = 1.0e6;
/// Pa per GPa.
pub const PA_PER_GPA: f64 = 1.0e9;
/// m per mm.
pub const M_PER_MM: f64 = 1.0e-3;
/// m per µm.
pub const M_PER_UM: f64 = 1.0e-6;
/// Seconds per minute.
pub const S_PER_MIN: f64 = 60.0;

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
}

impl ForceUnit {
    /// Newtons per one of this unit.
    pub fn to_newton(self) -> f64 {
        match self {
            ForceUnit::Newton => 1.0,
            ForceUnit::Kilonewton => 1.0e3,
            ForceUnit::Decanewton => 10.0,
            ForceUnit::Millinewton => 1.0e-3,
            ForceUnit::PoundForce => 4.448_221_615_260_5,
        }
    }
    pub const ALL: [ForceUnit; 5] = [
        ForceUnit::Newton,
        ForceUnit::Kilonewton,
        ForceUnit::Decanewton,
        ForceUnit::Millinewton,
        ForceUnit::PoundForce,
    ];
    pub fn symbol(self) -> &'static str {
        match self {
            ForceUnit::Newton => "N",
            ForceUnit::Kilonewton => "kN",
            ForceUnit::Decanewton => "daN",
            ForceUnit::Millinewton => "mN",
            ForceUnit::PoundForce => "lbf",
        }
    }
    /// Parse a unit symbol (case-sensitive, as in SI: `N`, `kN`, `daN`, `mN`, `lbf`).
    pub fn parse(s: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|u| u.symbol() == s.trim())
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
}

impl TimeUnit {
    pub fn to_second(self) -> f64 {
        match self {
            TimeUnit::Second => 1.0,
            TimeUnit::Millisecond => 1.0e-3,
            TimeUnit::Microsecond => 1.0e-6,
        }
    }
    pub fn symbol(self) -> &'static str {
        match self {
            TimeUnit::Second => "s",
            TimeUnit::Millisecond => "ms",
            TimeUnit::Microsecond => "us",
        }
    }
    pub fn parse(s: &str) -> Option<Self> {
        match s.trim() {
            "s" => Some(TimeUnit::Second),
            "ms" => Some(TimeUnit::Millisecond),
            "us" | "µs" => Some(TimeUnit::Microsecond),
            _ => None,
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
        assert_eq!(ForceUnit::parse("kgf"), None);
        assert_eq!(TimeUnit::parse("ms"), Some(TimeUnit::Millisecond));
    }
}
