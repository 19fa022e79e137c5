//! The registry of engine export formats: each format once, with its own options and their
//! documented defaults ([`Engine::defaults`]), and the table settings every format shares
//! ([`TableSpec`]). [`super::write::table_text`] dispatches a spec to its writer.
//!
//! Adding a format touches three files: its writer (a `*_checked` function beside the others
//! in [`super`]), this module (a variant of [`ExportFormat`] and of [`Engine`] with its
//! options and defaults) and the dispatch in [`super::write`]. The command line's help, the
//! Python docstring and the export settings list formats from [`ExportFormat`]'s `Choice`.
//!
//! ```
//! use greybox_core::choice::Choice;
//! use greybox_friction::export::engine::{Engine, ExportFormat, TableSpec};
//! assert_eq!(ExportFormat::names(), ["abaqus", "deform", "lsdyna", "csv", "table"]);
//! let spec = TableSpec::new(ExportFormat::Lsdyna);
//! assert_eq!(spec.engine.lsdyna_table_id(), Some(1000));
//! assert_eq!(spec.engine.format(), ExportFormat::Lsdyna);
//! assert!(matches!(Engine::defaults(ExportFormat::Csv), Engine::Csv));
//! ```

use super::{Grid, StepLines, Units};
use crate::grid::UnitSystem;
use crate::table_file::TableKind;
use greybox_core::count::Count;
use greybox_core::physics::Quantity;
use greybox_core::setting::{SettingError, SettingPath};
use greybox_core::units::TemperatureUnit;
use greybox_core::units::{m_per_min_to_m_per_s, mpa_to_pa};
use greybox_core::{Error, Result};
use serde::{Deserialize, Serialize};
use std::path::PathBuf;

/// The exported form.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ExportFormat {
    /// Abaqus *FRICTION data lines.
    Abaqus,
    /// DEFORM FRCFAC / FRCWIN keyword blocks.
    Deform,
    /// LS-DYNA *DEFINE_TABLE + *DEFINE_CURVE.
    Lsdyna,
    /// The grid as CSV.
    Csv,
    /// A greybox surrogate table (JSON): exact for tree ensembles, adaptive otherwise.
    Table,
}

greybox_core::choice!(ExportFormat, "export.format", [
    Abaqus => "abaqus",
    Deform => "deform",
    Lsdyna => "lsdyna",
    Csv => "csv",
    Table => "table",
]);

/// `n` equidistant values from `min` to `max` (both included): `min + (max − min)·i/(n − 1)`;
/// `[min]` for n = 1, nothing for n = 0.
///
/// ```
/// use greybox_friction::export::engine::equidistant;
/// assert_eq!(equidistant(20.0, 250.0, 3), [20.0, 135.0, 250.0]);
/// assert_eq!(equidistant(20.0, 250.0, 1), [20.0]);
/// assert!(equidistant(20.0, 250.0, 0).is_empty());
/// ```
pub fn equidistant(min: f64, max: f64, n: usize) -> Vec<f64> {
    if n < 2 {
        return vec![min; n];
    }
    (0..n)
        .map(|i| min + (max - min) * i as f64 / (n - 1) as f64)
        .collect()
}

/// The default pressures of an engine table: 500 to 2500 MPa in 21 steps (the article's
/// rake-face range, 100 MPa apart), Pa.
pub fn default_pressures_pa() -> Vec<f64> {
    equidistant(500.0, 2500.0, 21)
        .into_iter()
        .map(mpa_to_pa)
        .collect()
}

/// The default sliding velocities: 10 to 300 m/min in 30 steps (10 m/min apart), m/s.
pub fn default_velocities_m_s() -> Vec<f64> {
    equidistant(10.0, 300.0, 30)
        .into_iter()
        .map(m_per_min_to_m_per_s)
        .collect()
}

/// The default unit system of Abaqus and LS-DYNA tables (tonne–mm–s–N–MPa, the usual one
/// of metal-cutting models).
pub const DEFAULT_UNITS: UnitSystem = UnitSystem::MpaMmS;
/// The default temperature unit of the tables.
pub const DEFAULT_TEMPERATURE_UNIT: TemperatureUnit = TemperatureUnit::C;
/// The default sliding velocity of DEFORM's FRCFAC p–T table, m/s (150 m/min, mid-range of
/// the article's cutting speeds).
pub const DEFAULT_DEFORM_REFERENCE_VELOCITY_M_S: f64 = 2.5;
/// The default DEFORM object numbers (tool, workpiece): DEFORM's machining templates number
/// the workpiece 1 and the tool 2.
pub const DEFAULT_DEFORM_OBJECTS: (u32, u32) = (2, 1);
/// The default LS-DYNA table id (curves take the ids after it).
pub const DEFAULT_LSDYNA_TABLE_ID: u32 = 1000;

/// DEFORM object numbers (tool, workpiece); `TOOL,WORKPIECE` as text (the command line),
/// a list of two numbers in JSON.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(transparent)]
pub struct ObjectPair(pub [u32; 2]);

impl ObjectPair {
    /// DEFORM's usual numbering: [`DEFAULT_DEFORM_OBJECTS`].
    pub const DEFORM_DEFAULT: ObjectPair =
        ObjectPair([DEFAULT_DEFORM_OBJECTS.0, DEFAULT_DEFORM_OBJECTS.1]);
}

impl std::fmt::Display for ObjectPair {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{},{}", self.0[0], self.0[1])
    }
}

impl std::str::FromStr for ObjectPair {
    type Err = String;
    /// Two object numbers, `TOOL,WORKPIECE`.
    fn from_str(s: &str) -> std::result::Result<Self, String> {
        let n: Vec<u32> = s
            .split(',')
            .map(|x| {
                x.trim()
                    .parse()
                    .map_err(|_| format!("'{x}' is not an object number"))
            })
            .collect::<std::result::Result<_, _>>()?;
        <[u32; 2]>::try_from(n)
            .map(ObjectPair)
            .map_err(|_| "expected two object numbers, TOOL,WORKPIECE".into())
    }
}

/// Random points of the deviation check: each is a law evaluation held in memory (24 B).
pub type CheckPoints = Count<0, 10_000_000>;
/// The largest table one export may be allowed to write, in values (a few GB as text).
pub type TableSize = Count<1, { 1 << 28 }>;
/// Values of one grid axis given as `MIN:MAX:N`.
pub type AxisPoints = Count<2, 1_000_000>;
/// The default number of random points of the deviation check.
pub const DEFAULT_CHECK_POINTS: CheckPoints =
    CheckPoints::of(crate::surrogate::DEFAULT_CHECK_POINTS as u64);
/// The default tolerance of adaptive tables and grids (max |Δμ| on the check set; see
/// [`crate::surrogate::DEFAULT_TOLERANCE`] for why 10⁻³).
pub const DEFAULT_TOLERANCE: f64 = crate::surrogate::DEFAULT_TOLERANCE;
/// The default largest table, in values (engine-table points, surrogate cells or nodes).
pub const DEFAULT_MAX_TABLE_SIZE: TableSize =
    TableSize::of(crate::surrogate::DEFAULT_MAX_SIZE as u64);

/// Each engine with its own options.
#[derive(Debug, Clone, PartialEq)]
pub enum Engine {
    Abaqus {
        units: UnitSystem,
        temperature_unit: TemperatureUnit,
        /// TAUMAX, the limiting shear stress, Pa.
        taumax_pa: Option<f64>,
    },
    Deform {
        /// Sliding velocity at which the FRCFAC p–T table is evaluated, m/s.
        reference_velocity_m_s: f64,
        /// Object numbers (tool, workpiece).
        objects: (u32, u32),
        /// JSON list of windows {points_mm, pressure_mpa, velocity_m_per_min, temperature_k}.
        windows: Option<PathBuf>,
    },
    Lsdyna {
        units: UnitSystem,
        temperature_unit: TemperatureUnit,
        /// Table id (curves take the following ids).
        table_id: u32,
    },
    Csv,
    Table {
        /// `None`: exact for tree ensembles, adaptive otherwise.
        kind: Option<TableKind>,
    },
}

impl Engine {
    /// The engine of `format` with its documented defaults.
    pub fn defaults(format: ExportFormat) -> Self {
        match format {
            ExportFormat::Abaqus => Engine::Abaqus {
                units: DEFAULT_UNITS,
                temperature_unit: DEFAULT_TEMPERATURE_UNIT,
                taumax_pa: None,
            },
            ExportFormat::Deform => Engine::Deform {
                reference_velocity_m_s: DEFAULT_DEFORM_REFERENCE_VELOCITY_M_S,
                objects: DEFAULT_DEFORM_OBJECTS,
                windows: None,
            },
            ExportFormat::Lsdyna => Engine::Lsdyna {
                units: DEFAULT_UNITS,
                temperature_unit: DEFAULT_TEMPERATURE_UNIT,
                table_id: DEFAULT_LSDYNA_TABLE_ID,
            },
            ExportFormat::Csv => Engine::Csv,
            ExportFormat::Table => Engine::Table { kind: None },
        }
    }

    pub fn format(&self) -> ExportFormat {
        match self {
            Engine::Abaqus { .. } => ExportFormat::Abaqus,
            Engine::Deform { .. } => ExportFormat::Deform,
            Engine::Lsdyna { .. } => ExportFormat::Lsdyna,
            Engine::Csv => ExportFormat::Csv,
            Engine::Table { .. } => ExportFormat::Table,
        }
    }

    /// The table units of an Abaqus or LS-DYNA export.
    pub fn units(&self) -> Option<Units> {
        match self {
            Engine::Abaqus {
                units,
                temperature_unit,
                ..
            }
            | Engine::Lsdyna {
                units,
                temperature_unit,
                ..
            } => Some(Units::of(*units, *temperature_unit)),
            _ => None,
        }
    }

    /// The LS-DYNA table id, for an LS-DYNA export.
    pub fn lsdyna_table_id(&self) -> Option<u32> {
        match self {
            Engine::Lsdyna { table_id, .. } => Some(*table_id),
            _ => None,
        }
    }

    /// The DEFORM windows file, which the export reads.
    pub fn deform_windows(&self) -> Option<&PathBuf> {
        match self {
            Engine::Deform { windows, .. } => windows.as_ref(),
            _ => None,
        }
    }

    /// Check the engine's own options; errors name the option (`export.taumax_Pa`).
    pub fn validate(&self) -> Result<()> {
        match self {
            Engine::Abaqus {
                taumax_pa: Some(t), ..
            } if !(*t > 0.0 && t.is_finite()) => Err(invalid(
                "taumax_Pa",
                format!("{t} is not a positive stress"),
            )),
            Engine::Deform {
                reference_velocity_m_s: v,
                ..
            } if !(*v > 0.0 && v.is_finite()) => Err(invalid(
                "deform_reference_velocity_m_per_s",
                format!("{v} is not a positive speed"),
            )),
            // the physical quantities against the physics table (TAUMAX 0.6 MPa: GPa typed)
            Engine::Abaqus {
                taumax_pa: Some(t), ..
            } => physical("taumax_Pa", Quantity::ShearFlowStress, *t),
            Engine::Deform {
                reference_velocity_m_s: v,
                ..
            } => physical(
                "deform_reference_velocity_m_per_s",
                Quantity::SlidingVelocity,
                *v,
            ),
            _ => Ok(()),
        }
    }
}

/// `value` of the option `what` against the physics table ([`greybox_core::physics::admit`]):
/// refused outside the possible range, said outside the usual one.
fn physical(field: &str, q: Quantity, value: f64) -> Result<()> {
    Ok(greybox_core::physics::admit_setting(
        q,
        value,
        &option(field),
    )?)
}

/// The export option `field` as a setting.
fn option(field: &str) -> SettingPath {
    SettingPath::new("export", field)
}

/// A refused export option (`field` of the export's settings), named.
pub(crate) fn invalid(field: &str, message: String) -> Error {
    Error::setting(option(field), message)
}

/// A [`TableSpec`] whose every option was checked ([`TableSpec::validated`]): what a table
/// is written from, so that a run checks its options once, where they are stated. Its
/// options are read through `Deref`; a changed spec is checked again
/// (`into_inner`, change, `validated`).
#[derive(Debug, Clone, PartialEq)]
pub struct ValidTableSpec(TableSpec);

impl std::ops::Deref for ValidTableSpec {
    type Target = TableSpec;
    fn deref(&self) -> &TableSpec {
        &self.0
    }
}

impl ValidTableSpec {
    /// A table of `format` with every option at its default (valid for every format: the
    /// test `every_format_defaults_are_valid` checks it).
    pub fn defaults(format: ExportFormat) -> Self {
        ValidTableSpec(TableSpec::new(format))
    }

    /// The spec, to change and check again.
    pub fn into_inner(self) -> TableSpec {
        self.0
    }
}

/// What a table is, apart from the law it tabulates and the file it goes to: the engine
/// with its options, the grid and the check.
#[derive(Debug, Clone, PartialEq)]
pub struct TableSpec {
    /// The engine and its own options.
    pub engine: Engine,
    /// Pressures, sliding velocities (and temperatures) of the table, SI. A surrogate table
    /// or an adaptive grid covers their box (min and max per axis).
    pub grid: Grid,
    /// Random points of the deviation check (every format; 0: no check).
    pub check_points: CheckPoints,
    /// Engine tables: grid lines at a tree ensemble's split thresholds (two points one
    /// float apart, so that linear interpolation is exact); `Auto`: for piecewise-constant
    /// laws.
    pub steps: StepLines,
    /// Engine tables: the grid lines of an adaptive table refined to `tolerance` over the
    /// box of `grid`, so that a smooth law's table is within the tolerance under the
    /// engine's linear interpolation too.
    pub adaptive_grid: bool,
    /// Adaptive table or grid: max deviation on its check set.
    pub tolerance: f64,
    /// Largest table in values: engine-table points (pressures × velocities ×
    /// temperatures), surrogate cells (exact) or nodes (adaptive). A bigger table is
    /// refused with the size it would have.
    pub max_table_size: TableSize,
}

impl TableSpec {
    /// A table of `format` with every option at its default.
    pub fn new(format: ExportFormat) -> Self {
        TableSpec {
            engine: Engine::defaults(format),
            grid: Grid {
                pressure_pa: default_pressures_pa(),
                velocity_m_s: default_velocities_m_s(),
                temperature_k: None,
            },
            check_points: DEFAULT_CHECK_POINTS,
            steps: StepLines::Auto,
            adaptive_grid: false,
            tolerance: DEFAULT_TOLERANCE,
            max_table_size: DEFAULT_MAX_TABLE_SIZE,
        }
    }

    pub fn format(&self) -> ExportFormat {
        self.engine.format()
    }

    /// The spec, every option checked once; errors name the option (`export.tolerance`).
    pub fn validated(self) -> Result<ValidTableSpec> {
        self.validate()?;
        Ok(ValidTableSpec(self))
    }

    /// Check every option; errors name the option (`export.tolerance`).
    fn validate(&self) -> Result<()> {
        self.grid.validate().map_err(|e| {
            let axes = ["pressure_Pa", "velocity_m_per_s", "temperature_K"];
            SettingError::between(axes.map(option).to_vec(), e.to_string())
        })?;
        if !(self.tolerance > 0.0 && self.tolerance.is_finite()) {
            return Err(invalid(
                "tolerance",
                format!("{} is not a positive number", self.tolerance),
            ));
        }
        // the grid's extremes physical states: 500-2500 GPa or 333-500 m/s are unit slips
        let g = &self.grid;
        let none = Vec::new();
        let axes = [
            ("pressure_Pa", Quantity::ContactPressure, &g.pressure_pa),
            (
                "velocity_m_per_s",
                Quantity::SlidingVelocity,
                &g.velocity_m_s,
            ),
            (
                "temperature_K",
                Quantity::Temperature,
                g.temperature_k.as_ref().unwrap_or(&none),
            ),
        ];
        for (what, q, values) in axes {
            let lo = values.iter().copied().fold(f64::INFINITY, f64::min);
            let hi = values.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            for v in [lo, hi].into_iter().filter(|_| !values.is_empty()) {
                physical(what, q, v)?;
            }
        }
        self.engine.validate()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use greybox_core::choice::Choice;

    /// [`ValidTableSpec::defaults`] holds what it says: every format's defaults pass the check.
    #[test]
    fn every_format_defaults_are_valid() {
        for &format in ExportFormat::ALL {
            let checked = TableSpec::new(format).validated().unwrap();
            assert_eq!(
                checked,
                ValidTableSpec::defaults(format),
                "{}",
                format.name()
            );
        }
    }
}
