//! The grid a friction law is tabulated on for an FE engine (SI), and the engine's units.

use greybox_core::{Error, Result};
use serde::{Deserialize, Serialize};

/// The grid a law is evaluated on (SI).
#[derive(Debug, Clone, PartialEq)]
pub struct Grid {
    pub pressure_pa: Vec<f64>,
    pub velocity_m_s: Vec<f64>,
    /// Temperatures, K (absent: room temperature, no temperature column).
    pub temperature_k: Option<Vec<f64>>,
}

impl Grid {
    pub fn validate(&self) -> Result<()> {
        let asc = |v: &[f64], what: &str| -> Result<()> {
            if v.is_empty()
                || v.iter().any(|x| !x.is_finite())
                || v.windows(2).any(|w| !(w[1] > w[0]))
            {
                return Err(Error::invalid(
                    "export grid",
                    format!("{what} must be finite, strictly ascending and non-empty"),
                ));
            }
            Ok(())
        };
        asc(&self.pressure_pa, "pressures")?;
        asc(&self.velocity_m_s, "velocities")?;
        if let Some(t) = &self.temperature_k {
            asc(t, "temperatures")?;
        }
        if self.pressure_pa[0] < 0.0 || self.velocity_m_s[0] < 0.0 {
            return Err(Error::invalid(
                "export grid",
                "pressures and velocities must be ≥ 0",
            ));
        }
        Ok(())
    }
}

/// Units of an Abaqus table.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum PressureUnit {
    Pa,
    #[serde(rename = "MPa")]
    MPa,
}
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum SpeedUnit {
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
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum TempUnit {
    K,
    C,
}

impl PressureUnit {
    pub fn per_pa(self) -> f64 {
        match self {
            PressureUnit::Pa => 1.0,
            PressureUnit::MPa => 1e-6,
        }
    }
    /// Pa of a number in this unit (exact factors: Pa·1, MPa·10⁶).
    pub fn to_pa(self, x: f64) -> f64 {
        match self {
            PressureUnit::Pa => x,
            PressureUnit::MPa => x * 1e6,
        }
    }
    pub fn name(self) -> &'static str {
        match self {
            PressureUnit::Pa => "Pa",
            PressureUnit::MPa => "MPa",
        }
    }
}
impl SpeedUnit {
    pub fn per_m_s(self) -> f64 {
        match self {
            SpeedUnit::MPerS => 1.0,
            SpeedUnit::MmPerS => 1e3,
            SpeedUnit::MPerMin => 60.0,
            SpeedUnit::MmPerMs => 1.0,
        }
    }
    /// m/s of a number in this unit (divided by an exact 1, 10³ or 60).
    pub fn to_m_s(self, x: f64) -> f64 {
        match self {
            SpeedUnit::MPerS => x,
            SpeedUnit::MmPerS => x / 1e3,
            SpeedUnit::MPerMin => x / 60.0,
            SpeedUnit::MmPerMs => x,
        }
    }
    pub fn name(self) -> &'static str {
        match self {
            SpeedUnit::MPerS => "m/s",
            SpeedUnit::MmPerS => "mm/s",
            SpeedUnit::MPerMin => "m/min",
            SpeedUnit::MmPerMs => "mm/ms",
        }
    }
}
impl TempUnit {
    pub fn from_k(self, t: f64) -> f64 {
        match self {
            TempUnit::K => t,
            TempUnit::C => t - 273.15,
        }
    }
    /// K of a number in this unit.
    pub fn to_k(self, x: f64) -> f64 {
        match self {
            TempUnit::K => x,
            TempUnit::C => x + 273.15,
        }
    }
    /// The unit's name (its [`Choice`](greybox_core::choice::Choice) name).
    pub fn name(self) -> &'static str {
        greybox_core::choice::Choice::name(self)
    }
}

/// The units of an engine table's columns.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Units {
    pub pressure: PressureUnit,
    pub speed: SpeedUnit,
    pub temperature: TempUnit,
}

impl Units {
    /// The pressure and speed units of a consistent unit system, with a temperature unit.
    pub fn of(system: UnitSystem, temperature: TempUnit) -> Self {
        let (pressure, speed) = system.pressure_and_speed();
        Units {
            pressure,
            speed,
            temperature,
        }
    }
}

/// A consistent mechanical unit system of an FE model (Abaqus and LS-DYNA have no units of
/// their own: the table must be written in the model's). Pressure and sliding speed follow
/// from the system's length, time and force units, so they can never be mixed (MPa with m/s
/// is consistent only when time is in ms).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum UnitSystem {
    /// tonne, mm, s, N, MPa: slip rates in mm/s.
    MpaMmS,
    /// kg, m, s, N, Pa (SI): slip rates in m/s.
    PaMS,
    /// g, mm, ms, N, MPa (an LS-DYNA set): slip rates in mm/ms (= m/s).
    MpaMmMs,
}

greybox_core::choice!(
    UnitSystem,
    "units",
    [MpaMmS => "MPa-mm-s", PaMS => "Pa-m-s", MpaMmMs => "MPa-mm-ms"]
);

impl UnitSystem {
    /// The table's pressure and slip-rate units in this system.
    pub fn pressure_and_speed(self) -> (PressureUnit, SpeedUnit) {
        match self {
            UnitSystem::MpaMmS => (PressureUnit::MPa, SpeedUnit::MmPerS),
            UnitSystem::PaMS => (PressureUnit::Pa, SpeedUnit::MPerS),
            UnitSystem::MpaMmMs => (PressureUnit::MPa, SpeedUnit::MmPerMs),
        }
    }
    /// Pa per stress unit of a deck in this system (MPa: 10⁶).
    pub fn pa_per_stress_unit(self) -> f64 {
        self.pressure_and_speed().0.to_pa(1.0)
    }
    /// m per length unit of a deck in this system (mm: 10⁻³).
    pub fn m_per_length_unit(self) -> f64 {
        match self {
            UnitSystem::MpaMmS | UnitSystem::MpaMmMs => 1e-3,
            UnitSystem::PaMS => 1.0,
        }
    }
}

greybox_core::choice!(TempUnit, "temperature_unit", [C => "C", K => "K"], text);
