//! The settings of `sweep run` and `sweep calibrate` as a user states them: the executor and
//! the calibration's search, with the defaults once.
//!
//! ```
//! use greybox_sweep::settings::{ExecutorName, ExecutorSettings};
//! use greybox_sweep::Executor;
//! let s = ExecutorSettings { executor: ExecutorName::Slurm, ..Default::default() };
//! assert!(matches!(s.executor(true), Ok(Executor::Slurm { dry_run: true, .. })));
//! let none: Result<ExecutorSettings, _> = serde_json::from_str(r#"{"jobs": 0}"#);
//! assert!(none.unwrap_err().to_string().starts_with("0 is below the least allowed 1"));
//! assert_eq!("lsf".parse::<ExecutorName>().unwrap_err().to_string(),
//!     "sweep.executor: 'lsf' is not one of local, slurm");
//! ```

use super::calibrate::{CalibrateOptions, HoldOut, C_FIELD};
use super::launch::CaseCommand;
use super::search::FitField;
use super::validate::batch::CutRunner;
use super::validate::{ToolModel, ValidateOptions};
use super::Executor;
use anyhow::{bail, Result};
use serde::{Deserialize, Serialize};
use std::path::PathBuf;

/// Cases run at once by the local executor (each a process, often multi-threaded).
pub type Jobs = greybox_core::count::Count<1, 1_024>;
/// Iterations of a calibration: each runs every calibration case once.
pub type Iterations = greybox_core::count::Count<1, 1_000>;
/// Passes of a calibration's coordinate search over every searched parameter.
pub type Passes = greybox_core::count::Count<1, 10>;
/// Every n-th condition held out of a calibration (2: every other one).
pub type HoldOutEvery = greybox_core::count::Count<2, 1_000>;

/// Where the cases run.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ExecutorName {
    /// A process pool on this machine.
    #[default]
    Local,
    /// One Slurm array job.
    Slurm,
}

greybox_core::choice!(ExecutorName, "sweep.executor", [Local => "local", Slurm => "slurm"]);

/// Seconds between Slurm queue polls.
pub const DEFAULT_POLL_S: f64 = 10.0;

/// The executor of a sweep.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "cli", derive(clap::Args))]
#[serde(deny_unknown_fields, default)]
pub struct ExecutorSettings {
    /// `local` (a process pool here) or `slurm` (one sbatch array job).
    #[cfg_attr(feature = "cli", arg(long, default_value_t = ExecutorName::Local,
        value_parser = greybox_core::choice::clap_parsers::choice::<ExecutorName>()))]
    pub executor: ExecutorName,
    /// Local: cases at once.
    #[cfg_attr(feature = "cli", arg(long, default_value_t = Jobs::of(1)))]
    pub jobs: Jobs,
    /// Slurm: seconds between squeue polls.
    #[cfg_attr(feature = "cli", arg(long, default_value_t = DEFAULT_POLL_S))]
    pub poll_s: f64,
}

impl Default for ExecutorSettings {
    fn default() -> Self {
        ExecutorSettings {
            executor: ExecutorName::Local,
            jobs: Jobs::of(1),
            poll_s: DEFAULT_POLL_S,
        }
    }
}

impl ExecutorSettings {
    /// The executor; `dry_run` (Slurm) prints the array script and submits nothing.
    pub fn executor(&self, dry_run: bool) -> Result<Executor> {
        if !(self.poll_s.is_finite() && self.poll_s > 0.0) {
            bail!(
                "sweep.poll_s: expected a positive number of seconds, got {}",
                self.poll_s
            );
        }
        Ok(match self.executor {
            ExecutorName::Local => Executor::Local {
                jobs: self.jobs.get(),
            },
            ExecutorName::Slurm => Executor::Slurm {
                dry_run,
                poll_s: self.poll_s,
            },
        })
    }
}

/// The calibration's search: the bracket of C, its length, the held-out conditions.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "cli", derive(clap::Args))]
#[serde(deny_unknown_fields, default)]
pub struct CalibrateSettings {
    /// CSV: configuration fields per condition, cutting_force_N_per_mm[, feed_force_N_per_mm]
    /// [, chip_ratio] (h_c/h: counted in the error where given).
    #[cfg_attr(feature = "cli", arg(long))]
    pub measured: PathBuf,
    /// Output directory.
    #[cfg_attr(feature = "cli", arg(long, default_value = "calibrate-out"))]
    pub out: PathBuf,
    #[cfg_attr(feature = "cli", command(flatten))]
    #[serde(flatten)]
    pub executor: ExecutorSettings,
    /// Lower end of the bracket of C.
    #[cfg_attr(feature = "cli", arg(long = "c-min", default_value_t = 0.001))]
    pub c_min: f64,
    /// Upper end of the bracket of C.
    #[cfg_attr(feature = "cli", arg(long = "c-max", default_value_t = 0.1))]
    pub c_max: f64,
    /// Evaluations per golden-section search.
    #[cfg_attr(feature = "cli", arg(long, default_value_t = Iterations::of(10)))]
    pub iterations: Iterations,
    /// Passes of the search over every searched parameter (default: two where more than one
    /// is searched, as coupled parameters move the forces together; one otherwise).
    #[cfg_attr(feature = "cli", arg(long))]
    pub passes: Option<Passes>,
    /// Hold out every k-th condition (default 3) …
    #[cfg_attr(feature = "cli", arg(long = "hold-out-every", default_value_t = HoldOutEvery::of(3)))]
    pub hold_out_every: HoldOutEvery,
    /// … or these conditions (1-based, comma-separated).
    #[cfg_attr(feature = "cli", arg(long = "hold-out", value_delimiter = ','))]
    pub hold_out: Vec<usize>,
    /// Also scale the base's Coulomb mu.
    #[cfg_attr(feature = "cli", arg(long))]
    pub friction_scale: bool,
    /// Fit these set-up fields instead of C: `FIELD=LOW:HIGH` (linear) or
    /// `FIELD=LOW:HIGH:log`, e.g. `friction.law.b=-0.8:0.2` for a parameter of an inline
    /// friction law; repeat for several.
    #[cfg_attr(feature = "cli", arg(long = "fit"))]
    pub fit: Vec<String>,
}

impl Default for CalibrateSettings {
    fn default() -> Self {
        CalibrateSettings {
            measured: PathBuf::new(),
            out: "calibrate-out".into(),
            executor: ExecutorSettings::default(),
            c_min: 0.001,
            c_max: 0.1,
            iterations: Iterations::of(10),
            passes: None,
            hold_out_every: HoldOutEvery::of(3),
            hold_out: Vec::new(),
            friction_scale: false,
            fit: Vec::new(),
        }
    }
}

impl CalibrateSettings {
    /// The fitted fields: those of `fit`, or C over [c_min, c_max] on a log scale.
    pub fn fields(&self) -> Result<Vec<FitField>> {
        if self.fit.is_empty() {
            let c = FitField::new(C_FIELD, [self.c_min, self.c_max], true);
            c.check()?;
            return Ok(vec![c]);
        }
        self.fit.iter().map(|s| parse_fit(s)).collect()
    }

    /// The calibration of `sweep_file`'s base, each case's process started by `command`.
    pub fn options(&self, sweep_file: PathBuf, command: CaseCommand) -> Result<CalibrateOptions> {
        Ok(CalibrateOptions {
            sweep_file,
            measured: self.measured.clone(),
            out: self.out.clone(),
            executor: self.executor.executor(false)?,
            command,
            fields: self.fields()?,
            iterations: self.iterations.get(),
            passes: self.passes.map(Passes::get),
            hold_out: if self.hold_out.is_empty() {
                HoldOut::Every(self.hold_out_every.get())
            } else {
                HoldOut::List(self.hold_out.clone())
            },
            friction_scale: self.friction_scale,
        })
    }
}

/// `FIELD=LOW:HIGH[:log]` as a fitted field.
fn parse_fit(s: &str) -> Result<FitField> {
    let bad = || {
        anyhow::anyhow!(
            "fit '{s}': expected FIELD=LOW:HIGH or FIELD=LOW:HIGH:log, e.g. friction.law.b=-0.8:0.2"
        )
    };
    let (field, range) = s.split_once('=').ok_or_else(bad)?;
    let parts: Vec<&str> = range.split(':').collect();
    let log = match parts.get(2) {
        None => false,
        Some(&"log") if parts.len() == 3 => true,
        _ => return Err(bad()),
    };
    let num = |t: &str| t.trim().parse::<f64>().map_err(|_| bad());
    let f = FitField::new(
        field.trim(),
        [num(parts[0])?, num(parts.get(1).ok_or_else(bad)?)?],
        log,
    );
    if f.field.is_empty() {
        return Err(bad());
    }
    f.check()?;
    Ok(f)
}

#[cfg(test)]
mod fit_tests {
    use super::*;

    #[test]
    fn fit_fields_read_with_their_scale_and_refuse_bad_brackets() {
        let f = parse_fit("friction.law.b=-0.8:0.2").unwrap();
        assert_eq!(f, FitField::new("friction.law.b", [-0.8, 0.2], false));
        assert!(
            parse_fit("material.plasticity.c=0.001:0.1:log")
                .unwrap()
                .log
        );
        for bad in ["b", "b=1", "b=1:0", "b=0:1:ln", "=0:1", "c=0:1:log"] {
            assert!(parse_fit(bad).is_err(), "{bad}");
        }
        let s = CalibrateSettings::default();
        assert_eq!(s.fields().unwrap()[0].field, C_FIELD);
    }
}

/// The suite `greybox bench validate` runs without `--suite`.
pub const DEFAULT_SUITE: &str = "validation/suite.toml";

/// A run of the validation suite: the command line's flags and Python's keywords, with
/// their defaults in one place.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "cli", derive(clap::Args))]
#[serde(deny_unknown_fields, default)]
pub struct ValidateSettings {
    /// Suite file (its materials, their friction models and calibration conditions).
    #[cfg_attr(feature = "cli", arg(long, default_value = DEFAULT_SUITE))]
    pub suite: PathBuf,
    /// Output directory (results.csv, summary.json, validation.md, forces.svg).
    #[cfg_attr(feature = "cli", arg(long, default_value = "validation-out"))]
    pub out: PathBuf,
    /// Only these held-out conditions (comma-separated ids); the calibration ones always
    /// run.
    #[cfg_attr(feature = "cli", arg(long, value_delimiter = ','))]
    pub only: Vec<String>,
    /// Tool models: adiabatic, thermal (default: both).
    #[cfg_attr(feature = "cli", arg(long, value_delimiter = ',',
        value_parser = greybox_core::choice::clap_parsers::choice::<ToolModel>(),
        default_values_t = <ToolModel as greybox_core::choice::Choice>::ALL.to_vec()))]
    pub tool: Vec<ToolModel>,
    /// Fraction of each template's cut length (shorter: faster, less steady).
    #[cfg_attr(feature = "cli", arg(long, default_value_t = 1.0))]
    pub fraction: f64,
    /// Replace an existing, non-empty output directory (swapped out whole once every cut
    /// has run).
    #[cfg_attr(feature = "cli", arg(long))]
    pub force: bool,
    /// Where the cuts run: unset, in this process (every cut of a step in parallel);
    /// `local`, a process pool (`jobs`); `slurm`, one array job per step (the suite's
    /// `[slurm]` resources). Cases go under the output directory's `cuts/`.
    #[cfg_attr(feature = "cli", arg(long,
        value_parser = greybox_core::choice::clap_parsers::choice::<ExecutorName>()))]
    pub executor: Option<ExecutorName>,
    /// Local executor: cuts at once.
    #[cfg_attr(feature = "cli", arg(long, default_value_t = Jobs::of(1)))]
    pub jobs: Jobs,
    /// Slurm executor: seconds between squeue polls.
    #[cfg_attr(feature = "cli", arg(long, default_value_t = DEFAULT_POLL_S))]
    pub poll_s: f64,
}

impl Default for ValidateSettings {
    fn default() -> Self {
        ValidateSettings {
            suite: DEFAULT_SUITE.into(),
            out: "validation-out".into(),
            only: Vec::new(),
            tool: <ToolModel as greybox_core::choice::Choice>::ALL.to_vec(),
            fraction: 1.0,
            force: false,
            executor: None,
            jobs: Jobs::of(1),
            poll_s: DEFAULT_POLL_S,
        }
    }
}

impl ValidateSettings {
    /// The suite run's options; `program` gives the `greybox` program that runs a case
    /// (asked only when an executor is set).
    pub fn options(&self, program: &dyn Fn() -> Result<PathBuf>) -> Result<ValidateOptions> {
        let runner = match self.executor {
            None if self.jobs != Jobs::of(1) || self.poll_s != DEFAULT_POLL_S => bail!(
                "jobs and poll_s set the local and Slurm executors: set executor to local or slurm (the cuts otherwise run in this process)"
            ),
            None => CutRunner::InProcess,
            Some(executor) => CutRunner::Cases {
                executor: ExecutorSettings {
                    executor,
                    jobs: self.jobs,
                    poll_s: self.poll_s,
                }
                .executor(false)?,
                command: CaseCommand::greybox(program()?),
            },
        };
        Ok(ValidateOptions {
            only: self.only.clone(),
            tools: self.tool.clone(),
            fraction: self.fraction,
            runner,
        })
    }

    /// Runs the suite into `out` ([`super::validate::validate_into`]).
    pub fn run(
        &self,
        program: &dyn Fn() -> Result<PathBuf>,
    ) -> Result<(super::validate::Validation, Vec<PathBuf>)> {
        super::validate::validate_into(&self.suite, &self.options(program)?, &self.out, self.force)
    }
}

#[cfg(test)]
mod validate_tests {
    use super::*;

    #[test]
    fn executor_settings_without_an_executor_are_refused_not_ignored() {
        let program = || -> Result<PathBuf> { Ok("/opt/greybox".into()) };
        let here = ValidateSettings::default().options(&program).unwrap();
        assert!(matches!(here.runner, CutRunner::InProcess));
        let jobs = ValidateSettings {
            jobs: Jobs::of(4),
            ..Default::default()
        };
        let e = jobs.options(&program).err().unwrap().to_string();
        assert!(e.contains("set executor to local or slurm"), "{e}");
        let pool = ValidateSettings {
            executor: Some(ExecutorName::Local),
            ..jobs
        };
        let o = pool.options(&program).unwrap();
        assert!(matches!(
            o.runner,
            CutRunner::Cases {
                executor: Executor::Local { jobs: 4 },
                ..
            }
        ));
    }
}
