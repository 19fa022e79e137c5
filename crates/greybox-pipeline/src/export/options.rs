//! The options of [`export`](super::export): the law and the file, and the table as the
//! friction crate's registry states it ([`TableSpec`], [`Engine`] with its defaults and
//! validation, whose errors name the option, `export.deform_reference_velocity_m_per_s`,
//! never a command-line flag); and the overrides a surface sets by name.
//!
//! Every surface starts from [`ExportOptions::new`] and only overrides fields: the command
//! line and Python through [`ExportOverrides`] (the same names, with units in them), the
//! demo and library users through the builder methods.
//!
//! ```
//! use greybox_friction::export::engine::{ExportFormat, ObjectPair};
//! use greybox_pipeline::export::{ExportOptions, ExportOverrides};
//! let o = ExportOptions::new("law.json".into(), ExportFormat::Lsdyna, "law.k".into());
//! assert_eq!(o.table.engine.lsdyna_table_id(), Some(1000));
//! let o = o.overridden(&ExportOverrides { lsdyna_table_id: Some(7), ..Default::default() })?;
//! assert_eq!(o.table.engine.lsdyna_table_id(), Some(7));
//! // an option of another engine is refused, naming it
//! let e = o.overridden(&ExportOverrides { deform_objects: Some(ObjectPair([1, 2])), ..Default::default() });
//! assert!(e.unwrap_err().to_string().contains("export.deform_objects"));
//! # Ok::<(), anyhow::Error>(())
//! ```

use anyhow::Result;
use greybox_core::choice::Choice;
use greybox_core::units::TemperatureUnit;
use greybox_friction::export::engine::{
    CheckPoints, Engine, ExportFormat, ObjectPair, TableSize, TableSpec, ValidTableSpec,
};
use greybox_friction::export::{Grid, StepLines};
use greybox_friction::grid::UnitSystem;
use greybox_friction::table_file::TableKind;
use serde::{Deserialize, Serialize};
use std::path::PathBuf;

/// Options of [`export`](super::export()): the law, the file, and the table
/// ([`TableSpec`]: engine, grid, check; its defaults are the friction crate's registry's),
/// checked once where it is stated: by [`ExportOptions::new`] (the defaults), the builder
/// methods and [`ExportOptions::overridden`].
#[derive(Debug, Clone, PartialEq)]
pub struct ExportOptions {
    /// Law file, model file or table.
    pub law: PathBuf,
    /// Output file.
    pub out: PathBuf,
    /// The engine with its options, the grid and the check.
    pub table: ValidTableSpec,
}

impl ExportOptions {
    /// Export `law` as `format` to `out` with every other option at its default.
    pub fn new(law: PathBuf, format: ExportFormat, out: PathBuf) -> Self {
        ExportOptions {
            law,
            out,
            table: ValidTableSpec::defaults(format),
        }
    }

    pub fn format(&self) -> ExportFormat {
        self.table.format()
    }

    /// With this grid (SI), checked.
    pub fn with_grid(self, grid: Grid) -> Result<Self> {
        self.changed(|t| {
            t.grid = grid;
            Ok(())
        })
    }

    /// With this engine (and its options), checked.
    pub fn with_engine(self, engine: Engine) -> Result<Self> {
        self.changed(|t| {
            t.engine = engine;
            Ok(())
        })
    }

    /// These options with the fields `o` sets replaced, checked. An option of another
    /// engine than this export's is an error naming it.
    pub fn overridden(self, o: &ExportOverrides) -> Result<Self> {
        self.changed(|t| {
            o.apply_common(t);
            o.apply_engine(&mut t.engine)
        })
    }

    /// The table changed by `change`, then checked (errors name the option,
    /// `export.tolerance`).
    pub fn changed(mut self, change: impl FnOnce(&mut TableSpec) -> Result<()>) -> Result<Self> {
        let mut table = self.table.into_inner();
        change(&mut table)?;
        self.table = table.validated()?;
        Ok(self)
    }
}

/// The options a surface overrides, by their names with units, SI. `None` keeps the
/// format's default ([`ExportOverrides::defaults_of`]; the command line states them in its
/// help). Python passes these as keyword arguments, JSON and sweep files as a table with
/// these keys; the command line's flags are the same fields, their edge units (MPa, m/min)
/// converted by the flag's parser.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "cli", derive(clap::Args))]
#[serde(deny_unknown_fields)]
#[allow(non_snake_case)]
pub struct ExportOverrides {
    /// Pressures, MPa: MIN:MAX:N (equidistant) or a comma list.
    #[cfg_attr(feature = "cli", arg(long = "pressure-MPa", value_name = "MPA_GRID", value_parser = edge::pressures_mpa))]
    pub pressure_Pa: Option<AxisValues>,
    /// Sliding velocities, m/min: MIN:MAX:N or a comma list.
    #[cfg_attr(feature = "cli", arg(long = "velocity-m-per-min", value_name = "M_PER_MIN_GRID", value_parser = edge::velocities_m_per_min))]
    pub velocity_m_per_s: Option<AxisValues>,
    /// Temperatures, K: MIN:MAX:N or a comma list (none: μ(p, v) only).
    #[cfg_attr(feature = "cli", arg(long = "temperature-K", value_name = "K_GRID", value_parser = edge::temperatures_k))]
    pub temperature_K: Option<AxisValues>,
    /// Abaqus/LS-DYNA: the model's consistent unit system (pressure and slip-rate units
    /// follow from it).
    #[cfg_attr(feature = "cli", arg(long,
        value_parser = greybox_core::choice::clap_parsers::choice::<UnitSystem>()))]
    pub units: Option<UnitSystem>,
    /// Abaqus/LS-DYNA temperature unit.
    #[cfg_attr(feature = "cli", arg(long,
        value_parser = greybox_core::choice::clap_parsers::choice::<TemperatureUnit>()))]
    pub temperature_unit: Option<TemperatureUnit>,
    /// Abaqus TAUMAX (limiting shear stress), MPa.
    #[cfg_attr(feature = "cli", arg(long = "taumax-MPa", value_name = "MPA",
        value_parser = greybox_core::units::clap_parsers::mpa_as_pa))]
    pub taumax_Pa: Option<f64>,
    /// DEFORM: sliding velocity at which the FRCFAC p-T table is evaluated, m/min.
    #[cfg_attr(feature = "cli", arg(long = "deform-reference-velocity-m-per-min", value_name = "M_PER_MIN",
        value_parser = greybox_core::units::clap_parsers::m_per_min_as_m_per_s))]
    pub deform_reference_velocity_m_per_s: Option<f64>,
    /// DEFORM: object numbers TOOL,WORKPIECE.
    #[cfg_attr(feature = "cli", arg(long))]
    pub deform_objects: Option<ObjectPair>,
    /// DEFORM: JSON list of windows {points_mm, pressure_mpa, velocity_m_per_min, temperature_k}.
    #[cfg_attr(feature = "cli", arg(long))]
    pub deform_windows: Option<PathBuf>,
    /// LS-DYNA table id (curves take the following ids).
    #[cfg_attr(feature = "cli", arg(long))]
    pub lsdyna_table_id: Option<u32>,
    /// Surrogate table (format table): exact, adaptive (over the box of the grid) or
    /// uniform (the grid itself, equidistant); default: exact for tree ensembles, adaptive
    /// otherwise.
    #[cfg_attr(feature = "cli", arg(long,
        value_parser = greybox_core::choice::clap_parsers::choice::<TableKind>()))]
    pub table_kind: Option<TableKind>,
    /// Random points of the deviation check of every format (cell centres and the
    /// neighbours of every grid line come on top); 0: no check.
    #[cfg_attr(feature = "cli", arg(long))]
    pub check_points: Option<CheckPoints>,
    /// Engine tables: grid lines at the split thresholds of tree ensembles, two points one
    /// float apart per threshold (exact for engines that interpolate linearly); auto: for
    /// tree-ensemble laws.
    #[cfg_attr(feature = "cli", arg(long,
        value_parser = greybox_core::choice::clap_parsers::choice::<StepLines>()))]
    pub steps: Option<StepLines>,
    /// Engine tables: grid lines of an adaptive table over the box of the grid, refined to
    /// the tolerance, instead of the given values.
    #[cfg_attr(feature = "cli", arg(long, num_args = 0..=1, default_missing_value = "true"))]
    pub adaptive_grid: Option<bool>,
    /// Adaptive table or grid: max deviation of μ from the law on its check set.
    #[cfg_attr(feature = "cli", arg(long))]
    pub tolerance: Option<f64>,
    /// Largest table in values (engine-table points, surrogate cells or nodes); a bigger
    /// one is refused with its size.
    #[cfg_attr(feature = "cli", arg(long = "max-table-size"))]
    pub max_table_size: Option<TableSize>,
}

/// The values of one grid axis, SI (JSON: a list of numbers).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(transparent)]
pub struct AxisValues(pub Vec<f64>);

/// The command line's edge units of the export options, parsed into SI (clap value
/// parsers, so that the flag and the field are one).
#[cfg(feature = "cli")]
pub mod edge {
    use super::AxisValues;
    use greybox_core::units::{m_per_min_to_m_per_s, mpa_to_pa};

    fn axis(text: &str, field: &str, to_si: fn(f64) -> f64) -> Result<AxisValues, String> {
        crate::export::parse_values(text, field)
            .map(|v| AxisValues(v.into_iter().map(to_si).collect()))
            .map_err(|e| format!("{e:#}"))
    }
    pub fn pressures_mpa(text: &str) -> Result<AxisValues, String> {
        axis(text, "export.pressure_MPa", mpa_to_pa)
    }
    pub fn velocities_m_per_min(text: &str) -> Result<AxisValues, String> {
        axis(text, "export.velocity_m_per_min", m_per_min_to_m_per_s)
    }
    pub fn temperatures_k(text: &str) -> Result<AxisValues, String> {
        axis(text, "export.temperature_K", |t| t)
    }
    /// A default in the flag's unit: grids as `MIN:MAX:N` when equidistant.
    fn shown(field: &str, value: &serde_json::Value) -> Option<String> {
        use greybox_core::units::{m_per_s_to_m_per_min, pa_to_mpa};
        let edge: fn(f64) -> f64 = match field {
            "pressure_Pa" | "taumax_Pa" => pa_to_mpa,
            "velocity_m_per_s" | "deform_reference_velocity_m_per_s" => m_per_s_to_m_per_min,
            _ => |x| x,
        };
        let number = |x: f64| greybox_core::units::Compact(edge(x)).to_string();
        Some(match value {
            serde_json::Value::Null => return None,
            serde_json::Value::Number(n) => number(n.as_f64()?),
            serde_json::Value::Array(items) if items.len() > 2 => {
                let v: Vec<f64> = items.iter().filter_map(|x| x.as_f64()).collect();
                let (a, b, n) = (v[0], v[v.len() - 1], v.len());
                let even = greybox_friction::export::engine::equidistant(a, b, n)
                    .iter()
                    .zip(&v)
                    .all(|(x, y)| (x - y).abs() <= 1e-9 * y.abs().max(1e-300));
                if even {
                    format!("{}:{}:{n}", number(a), number(b))
                } else {
                    v.iter().map(|x| number(*x)).collect::<Vec<_>>().join(",")
                }
            }
            serde_json::Value::Array(items) => items
                .iter()
                .map(|x| x.to_string())
                .collect::<Vec<_>>()
                .join(","),
            serde_json::Value::String(t) => t.clone(),
            other => other.to_string(),
        })
    }

    /// One option's default texts, each with the formats that have it.
    type DefaultsByText = Vec<(String, Vec<&'static str>)>;

    /// Per option, its defaults as `--help` states them, in the flag's units, by format
    /// where they differ (`MPa-mm-s for abaqus, lsdyna`): from
    /// [`super::ExportOverrides::defaults_of`], so that no default is typed twice.
    pub fn default_help() -> Vec<(String, String)> {
        use greybox_core::choice::Choice;
        let mut fields: Vec<(String, DefaultsByText)> = Vec::new();
        for format in super::ExportFormat::ALL {
            let d = serde_json::to_value(super::ExportOverrides::defaults_of(*format))
                .expect("overrides serialize");
            for (field, value) in d.as_object().into_iter().flatten() {
                let Some(text) = shown(field, value) else {
                    continue;
                };
                let texts = match fields.iter().position(|(f, _)| f == field) {
                    Some(i) => &mut fields[i].1,
                    None => {
                        fields.push((field.clone(), Vec::new()));
                        &mut fields.last_mut().expect("just pushed").1
                    }
                };
                match texts.iter_mut().find(|(t, _)| *t == text) {
                    Some((_, formats)) => formats.push(format.name()),
                    None => texts.push((text, vec![format.name()])),
                }
            }
        }
        let all = super::ExportFormat::ALL.len();
        let describe = |(text, formats): &(String, Vec<&str>)| match formats.len() == all {
            true => text.clone(),
            false => format!("{text} for {}", formats.join(", ")),
        };
        fields
            .into_iter()
            .map(|(field, texts)| {
                let parts: Vec<String> = texts.iter().map(describe).collect();
                (field, parts.join("; "))
            })
            .collect()
    }
}

impl ExportOverrides {
    /// Every option of `format` at its default, the others `None`: what a user may set.
    pub fn defaults_of(format: ExportFormat) -> Self {
        let o = TableSpec::new(format);
        let engine_tables = format != ExportFormat::Table;
        let mut d = ExportOverrides {
            pressure_Pa: Some(AxisValues(o.grid.pressure_pa)),
            velocity_m_per_s: Some(AxisValues(o.grid.velocity_m_s)),
            check_points: Some(o.check_points),
            tolerance: Some(o.tolerance),
            max_table_size: Some(o.max_table_size),
            steps: engine_tables.then_some(o.steps),
            adaptive_grid: engine_tables.then_some(o.adaptive_grid),
            ..Default::default()
        };
        match o.engine {
            Engine::Abaqus {
                units,
                temperature_unit,
                taumax_pa,
            } => {
                d.units = Some(units);
                d.temperature_unit = Some(temperature_unit);
                d.taumax_Pa = taumax_pa;
            }
            Engine::Deform {
                reference_velocity_m_s,
                objects,
                windows,
            } => {
                d.deform_reference_velocity_m_per_s = Some(reference_velocity_m_s);
                d.deform_objects = Some(ObjectPair([objects.0, objects.1]));
                d.deform_windows = windows;
            }
            Engine::Lsdyna {
                units,
                temperature_unit,
                table_id,
            } => {
                d.units = Some(units);
                d.temperature_unit = Some(temperature_unit);
                d.lsdyna_table_id = Some(table_id);
            }
            Engine::Csv | Engine::Table { .. } => {}
        }
        d
    }

    /// Overrides from JSON (Python's keyword arguments); unknown keys are errors.
    pub fn from_json(text: &str) -> Result<Self> {
        crate::settings::from_json("export", text)
    }

    fn apply_common(&self, o: &mut TableSpec) {
        let set = |v: &Option<AxisValues>, into: &mut Vec<f64>| {
            if let Some(v) = v {
                *into = v.0.clone();
            }
        };
        set(&self.pressure_Pa, &mut o.grid.pressure_pa);
        set(&self.velocity_m_per_s, &mut o.grid.velocity_m_s);
        if let Some(t) = &self.temperature_K {
            o.grid.temperature_k = Some(t.0.clone());
        }
        o.check_points = self.check_points.unwrap_or(o.check_points);
        o.steps = self.steps.unwrap_or(o.steps);
        o.adaptive_grid = self.adaptive_grid.unwrap_or(o.adaptive_grid);
        o.tolerance = self.tolerance.unwrap_or(o.tolerance);
        o.max_table_size = self.max_table_size.unwrap_or(o.max_table_size);
    }

    fn apply_engine(&self, engine: &mut Engine) -> Result<()> {
        let temperature_unit = self.temperature_unit;
        let format = engine.format();
        match engine {
            Engine::Abaqus {
                units,
                temperature_unit: t,
                taumax_pa,
            } => {
                *units = self.units.unwrap_or(*units);
                *t = temperature_unit.unwrap_or(*t);
                *taumax_pa = self.taumax_Pa.or(*taumax_pa);
            }
            Engine::Deform {
                reference_velocity_m_s,
                objects,
                windows,
            } => {
                *reference_velocity_m_s = self
                    .deform_reference_velocity_m_per_s
                    .unwrap_or(*reference_velocity_m_s);
                *objects = self
                    .deform_objects
                    .map_or(*objects, |ObjectPair([t, w])| (t, w));
                if self.deform_windows.is_some() {
                    windows.clone_from(&self.deform_windows);
                }
            }
            Engine::Lsdyna {
                units,
                temperature_unit: t,
                table_id,
            } => {
                *units = self.units.unwrap_or(*units);
                *t = temperature_unit.unwrap_or(*t);
                *table_id = self.lsdyna_table_id.unwrap_or(*table_id);
            }
            Engine::Table { kind } => *kind = self.table_kind.or(*kind),
            Engine::Csv => {}
        }
        match self.foreign_option(format) {
            Some(name) => {
                let why = format!("not an option of the {} export", format.name());
                Err(greybox_core::setting::refused("export", name, why).into())
            }
            None => Ok(()),
        }
    }

    /// The first option set here that `format` does not have.
    fn foreign_option(&self, format: ExportFormat) -> Option<&'static str> {
        use ExportFormat::*;
        let set = [
            ("units", self.units.is_some(), &[Abaqus, Lsdyna][..]),
            (
                "temperature_unit",
                self.temperature_unit.is_some(),
                &[Abaqus, Lsdyna],
            ),
            ("taumax_Pa", self.taumax_Pa.is_some(), &[Abaqus]),
            (
                "deform_reference_velocity_m_per_s",
                self.deform_reference_velocity_m_per_s.is_some(),
                &[Deform],
            ),
            ("deform_objects", self.deform_objects.is_some(), &[Deform]),
            ("deform_windows", self.deform_windows.is_some(), &[Deform]),
            ("lsdyna_table_id", self.lsdyna_table_id.is_some(), &[Lsdyna]),
            ("table_kind", self.table_kind.is_some(), &[Table]),
            (
                "steps",
                self.steps.is_some(),
                &[Abaqus, Deform, Lsdyna, Csv],
            ),
            (
                "adaptive_grid",
                self.adaptive_grid.is_some(),
                &[Abaqus, Deform, Lsdyna, Csv],
            ),
        ];
        set.iter()
            .find(|(_, given, formats)| *given && !formats.contains(&format))
            .map(|(name, ..)| *name)
    }
}
