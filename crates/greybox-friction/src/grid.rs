//! The grid a friction law is tabulated on for an FE engine (SI), and the engine's units.

use greybox_core::{Error, Result};

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

use greybox_core::units::{PressureUnit, TemperatureUnit, VelocityUnit};

/// The units of an engine table's columns.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Units {
    pub pressure: PressureUnit,
    pub speed: VelocityUnit,
    pub temperature: TemperatureUnit,
}

impl Units {
    /// The pressure and speed units of a consistent unit system, with a temperature unit.
    pub fn of(system: UnitSystem, temperature: TemperatureUnit) -> Self {
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
    pub fn pressure_and_speed(self) -> (PressureUnit, VelocityUnit) {
        match self {
            UnitSystem::MpaMmS => (PressureUnit::MPa, VelocityUnit::MmPerS),
            UnitSystem::PaMS => (PressureUnit::Pa, VelocityUnit::MPerS),
            UnitSystem::MpaMmMs => (PressureUnit::MPa, VelocityUnit::MmPerMs),
        }
    }
    /// Pa per stress unit of a deck in this system (MPa: 10⁶).
    pub fn pa_per_stress_unit(self) -> f64 {
        self.pressure_and_speed().0.to_pa(1.0)
    }
    /// m per length unit of a deck in this system (mm: 10⁻³).
    pub fn m_per_length_unit(self) -> f64 {
        match self {
            UnitSystem::MpaMmS | UnitSystem::MpaMmMs => greybox_core::units::M_PER_MM,
            UnitSystem::PaMS => 1.0,
        }
    }
}
