//! Cases of a sweep: the base configuration with a case's values applied, checked by
//! deserialising into the real set-up type, keyed by a hash of the resolved configuration
//! (law files by their content), with a cost estimate; and what a case directory holds.
//!
//! A case directory `cases/<id>/` holds `config.toml` (the resolved set-up), after a run
//! `result/` (the run's outputs, swapped in whole) and then `done.json` (written last,
//! atomically: the marker that the case is finished), or `failed.json` with the error.

use super::spec::CaseKind;
use anyhow::{bail, Context, Result};
use greybox_core::atomic::write_string_atomic;
use greybox_core::outputs::output_subdir;
use greybox_pipeline::simulate::Frames;
use greybox_sim::cutting::CuttingSetup;
use greybox_sim::pin::PinSetup;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// The value of an axis that removes an optional field.
pub const NONE: &str = "none";

/// Work of one case, for scheduling and Slurm resources.
#[derive(Debug, Clone, Copy, Serialize, Deserialize, PartialEq)]
pub struct Cost {
    pub particles: usize,
    /// Solver steps to the end of the run (without a steady-state stop).
    pub steps: u64,
    /// particles × steps.
    pub particle_steps: f64,
}

/// One case of a sweep.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Case {
    /// Position in the plan (Slurm array index).
    pub index: usize,
    /// First 12 hex digits of the SHA-256 of the resolved configuration.
    pub id: String,
    /// The axes' (field, value) of this case, as written in the sweep file.
    pub values: Vec<(String, String)>,
    /// The resolved configuration (TOML), as written to `config.toml`.
    pub config: String,
    pub cost: Cost,
}

/// Sets `value` at the dotted `path` of `root` (tables created on the way); the string
/// [`NONE`] removes the field.
pub fn apply(root: &mut toml::Value, path: &str, value: &toml::Value) -> Result<()> {
    let keys: Vec<&str> = path.split('.').collect();
    if keys.iter().any(|k| k.is_empty()) {
        bail!("field '{path}': expected a dotted path such as insert.rake_deg");
    }
    let mut t = root
        .as_table_mut()
        .context("the base configuration is not a table")?;
    for k in &keys[..keys.len() - 1] {
        t = t
            .entry(k.to_string())
            .or_insert_with(|| toml::Value::Table(Default::default()))
            .as_table_mut()
            .with_context(|| format!("field '{path}': '{k}' is not a table"))?;
    }
    let last = keys[keys.len() - 1].to_string();
    if value.as_str() == Some(NONE) {
        t.remove(&last);
    } else {
        t.insert(last, value.clone());
    }
    Ok(())
}

/// A `*_file` value made absolute against `base` (paths in a case's config must hold from
/// its own directory).
pub fn absolute_file(path: &str, value: &toml::Value, base: &Path) -> toml::Value {
    match value.as_str() {
        Some(s) if path.ends_with("_file") && s != NONE && !Path::new(s).is_absolute() => {
            toml::Value::String(
                std::path::absolute(base.join(s))
                    .unwrap_or_else(|_| base.join(s))
                    .display()
                    .to_string(),
            )
        }
        _ => value.clone(),
    }
}

/// The base configuration as a TOML value, its relative file paths made absolute; cuts
/// stop once sure where the sweep says so (`[sweep] stop_when_sure`).
pub fn read_base(path: &Path, kind: CaseKind, stop_when_sure: bool) -> Result<toml::Value> {
    let mut v: toml::Value = greybox_pipeline::config_toml::read(path, "base configuration")?;
    let dir = path.parent().unwrap_or(Path::new(""));
    if kind == CaseKind::Cutting {
        let stop = toml::Value::Boolean(stop_when_sure);
        apply(&mut v, "steady.stop_when_sure", &stop)?;
        if let Some(f) = v.get("friction").and_then(|f| f.get("law_file")).cloned() {
            let abs = absolute_file("friction.law_file", &f, dir);
            apply(&mut v, "friction.law_file", &abs)?;
        }
        let table = v.get("material").and_then(|m| m.get("plasticity"));
        if let Some(f) = table.and_then(|p| p.get("file")).cloned() {
            let abs = absolute_file("material.plasticity.file", &f, dir);
            apply(&mut v, "material.plasticity.file", &abs)?;
        }
    }
    Ok(v)
}

/// The canonical JSON of a resolved configuration with every referenced file replaced by
/// its content's SHA-256, and the case id from it.
fn case_id(kind: CaseKind, fraction: f64, frames: Frames, canonical: &serde_json::Value) -> String {
    let key = serde_json::json!({ "kind": kind, "fraction": fraction, "frames": frames, "config": canonical });
    greybox_core::provenance::sha256_bytes(key.to_string().as_bytes())[..12].to_string()
}

fn hash_file(path: &Path) -> Result<String> {
    let bytes = greybox_core::input::read_bytes(
        path,
        "file named by the configuration",
        greybox_core::budget::Cap::DataBytes,
    )?;
    Ok(format!(
        "sha256:{}",
        greybox_core::provenance::sha256_bytes(&bytes)
    ))
}

/// Checks the configuration by deserialising it and returns (canonical JSON, cost).
pub fn check(kind: CaseKind, v: &toml::Value, fraction: f64) -> Result<(serde_json::Value, Cost)> {
    match kind {
        CaseKind::Cutting => {
            let mut s: CuttingSetup = v.clone().try_into().context("not a valid cutting set-up")?;
            // A flow-stress table's curves go into the canonical form: the case id follows
            // their content.
            greybox_pipeline::simulate::load_material_files(&mut s.material, Path::new(""))?;
            s.validate()?;
            let mut canonical = serde_json::to_value(&s)?;
            if let Some(f) = s.friction.law_file.as_deref().map(Path::new) {
                canonical["friction"]["law_file"] = hash_file(f)?.into();
                greybox_friction::spec::load_law(f)
                    .with_context(|| format!("friction.law_file {}", f.display()))?;
            }
            let (model, duration) = s.model()?;
            let sim = greybox_sim::Solver::new(model)?;
            Ok((
                canonical,
                cost(sim.particle_count(), duration * fraction / sim.dt),
            ))
        }
        CaseKind::Pin => {
            let s: PinSetup = v.clone().try_into().context("not a valid pin set-up")?;
            s.validate()?;
            let (model, press, slide) = s.model()?;
            let sim = greybox_sim::Solver::new(model)?;
            Ok((
                serde_json::to_value(&s)?,
                cost(sim.particle_count(), (press + slide) / sim.dt),
            ))
        }
    }
}

fn cost(particles: usize, steps: f64) -> Cost {
    let steps = steps.ceil().max(0.0) as u64;
    Cost {
        particles,
        steps,
        particle_steps: particles as f64 * steps as f64,
    }
}

/// Builds case `index` from the base and its (field, value) pairs; `sweep_dir` resolves
/// relative file values.
pub fn build(
    kind: CaseKind,
    base: &toml::Value,
    values: &[(String, toml::Value)],
    sweep_dir: &Path,
    fraction: f64,
    frames: Frames,
    index: usize,
) -> Result<Case> {
    let mut v = base.clone();
    for (field, value) in values {
        apply(&mut v, field, &absolute_file(field, value, sweep_dir))?;
    }
    let shown: Vec<(String, String)> = values
        .iter()
        .map(|(f, x)| (f.clone(), value_text(x)))
        .collect();
    let what = shown
        .iter()
        .map(|(f, x)| format!("{f} = {x}"))
        .collect::<Vec<_>>()
        .join(", ");
    let (canonical, cost) =
        check(kind, &v, fraction).with_context(|| format!("case {} ({what})", index + 1))?;
    Ok(Case {
        index,
        id: case_id(kind, fraction, frames, &canonical),
        values: shown,
        config: toml::to_string_pretty(&v)?,
        cost,
    })
}

/// A TOML value as a table cell: strings bare, numbers as written.
pub fn value_text(v: &toml::Value) -> String {
    match v {
        toml::Value::String(s) => s.clone(),
        other => other.to_string(),
    }
}

/// Where a case stands.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Status {
    Done,
    Failed,
    Pending,
}

/// A case's directory and its files.
pub struct CaseDir(pub PathBuf);

impl CaseDir {
    pub fn of(sweep_out: &Path, id: &str) -> Self {
        CaseDir(sweep_out.join("cases").join(id))
    }
    pub fn config(&self) -> PathBuf {
        self.0.join("config.toml")
    }
    pub fn result(&self) -> PathBuf {
        self.0.join("result")
    }
    pub fn done(&self) -> PathBuf {
        self.0.join("done.json")
    }
    pub fn failed(&self) -> PathBuf {
        self.0.join("failed.json")
    }
    pub fn log(&self) -> PathBuf {
        self.0.join("log.txt")
    }
    /// The error `failed.json` records, if the case failed.
    pub fn failure(&self) -> Option<String> {
        let text = read_state(&self.failed(), "case failure marker").ok()?;
        let v: serde_json::Value = serde_json::from_str(&text).ok()?;
        v["error"].as_str().map(str::to_string)
    }
    /// Where `case` stands: done only when its `done.json` is this case's, made from the
    /// configuration the plan holds ([`CaseDir::read_done`]); a marker that is not (copied
    /// from another case, left from an edited `config.toml`) leaves the case to be run again.
    pub fn status(&self, case: &Case) -> Status {
        if matches!(self.read_done(case), Ok(Some(_))) {
            Status::Done
        } else if self.failed().is_file() {
            Status::Failed
        } else {
            Status::Pending
        }
    }
    /// The case's `done.json`, checked to be `case`'s own: `None` when there is none; an error
    /// naming the file when it is not a done marker, belongs to another case (its `id`), or
    /// was made from another configuration than the plan's (its `config_sha256`, the SHA-256
    /// of the `config.toml` the run read).
    pub fn read_done(&self, case: &Case) -> Result<Option<Done>> {
        let p = self.done();
        if !p.exists() && std::fs::symlink_metadata(&p).is_err() {
            return Ok(None);
        }
        let text = read_state(&p, "case done marker")?;
        let done: Done = serde_json::from_str(&text)
            .with_context(|| format!("{}: not a done marker", p.display()))?;
        if done.id != case.id {
            bail!(
                "{}: the marker of case {}, not of case {} (copied from another case?): delete it to run this case",
                p.display(),
                greybox_core::escape::excerpt(&done.id),
                case.id
            );
        }
        let planned = config_sha256(&case.config);
        if done.config_sha256.as_deref() != Some(planned.as_str()) {
            bail!(
                "{}: made from another configuration than the plan's for case {} (config.toml edited after the run, or a marker from before markers were bound to their configuration): run the sweep again to re-run this case",
                p.display(),
                case.id
            );
        }
        Ok(Some(done))
    }
    /// Creates the directory (and `cases/`) if missing, refusing a link planted at either:
    /// it could lead the case's files outside the sweep.
    pub fn ensure(&self) -> Result<()> {
        let (Some(cases), Some(id)) = (self.0.parent(), self.0.file_name()) else {
            bail!("{}: not a case directory", self.0.display());
        };
        let sweep = cases.parent().unwrap_or(Path::new("."));
        output_subdir(&output_subdir(sweep, "cases")?, &id.to_string_lossy())?;
        Ok(())
    }
    /// Creates the directory and writes `config.toml` (if it is not there already, or holds
    /// anything but the case's configuration: the case id stands for the planned
    /// configuration, and a `done.json` made from an edited one no longer counts).
    pub fn prepare(&self, case: &Case) -> Result<()> {
        self.ensure()?;
        let current = read_state(&self.config(), "case configuration").ok();
        if current.as_deref() != Some(case.config.as_str()) {
            write_string_atomic(&self.config(), &case.config)?;
        }
        Ok(())
    }
    /// The case's `config.toml`, refused unless it is the plan's configuration for `case`
    /// (what a run reads: a result is the one its case id claims).
    pub fn checked_config(&self, case: &Case) -> Result<()> {
        let text = read_state(&self.config(), "case configuration")?;
        if text != case.config {
            bail!(
                "{}: differs from the plan's configuration for case {} (edited after the sweep was planned?): the case id stands for the planned configuration; change the sweep file and plan again",
                self.config().display(),
                case.id
            );
        }
        Ok(())
    }
}

/// A sweep's state file (plan, case markers, a case's configuration) read through the one
/// safe open: a regular file under `max_data_bytes`, as UTF-8 text.
pub fn read_state(path: &Path, what: &str) -> Result<String> {
    Ok(greybox_core::input::read_data_text(path, what)?)
}

/// The SHA-256 of a case's configuration text, as `done.json` records it.
pub fn config_sha256(config: &str) -> String {
    format!(
        "sha256:{}",
        greybox_core::provenance::sha256_bytes(config.as_bytes())
    )
}

/// What `done.json` holds.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Done {
    pub id: String,
    /// The SHA-256 of the `config.toml` the run read ([`config_sha256`]): binds the marker to
    /// its configuration. Markers without it (from before) count as not done.
    #[serde(default)]
    pub config_sha256: Option<String>,
    pub wall_s: f64,
    /// Peak resident memory of the process that ran the case, MB.
    #[serde(default)]
    pub peak_memory_mb: Option<f64>,
    /// The run's summary (cut or pin), as its `summary.json`.
    pub summary: serde_json::Value,
}

/// The last `n` lines of a text file (empty if unreadable).
pub fn tail(path: &Path, n: usize) -> String {
    let text = read_state(path, "case log").unwrap_or_default();
    let lines: Vec<&str> = text.lines().collect();
    lines[lines.len().saturating_sub(n)..].join("\n")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn case(id: &str, config: &str) -> Case {
        Case {
            index: 0,
            id: id.into(),
            values: vec![],
            config: config.into(),
            cost: Cost {
                particles: 1,
                steps: 1,
                particle_steps: 1.0,
            },
        }
    }

    fn done_of(case: &Case, config: &str) -> String {
        serde_json::to_string(&Done {
            id: case.id.clone(),
            config_sha256: Some(config_sha256(config)),
            wall_s: 1.0,
            peak_memory_mb: None,
            summary: serde_json::json!({"cutting_force_n_per_mm": 200.0}),
        })
        .unwrap()
    }

    /// Issue 62: a done marker counts only for the case and the configuration that made it.
    #[test]
    fn a_done_marker_is_bound_to_its_case_and_its_configuration() {
        let d = tempfile::tempdir().unwrap();
        let a = case("aaaaaaaaaaaa", "mu = 0.3\n");
        let dir = CaseDir::of(d.path(), &a.id);
        dir.prepare(&a).unwrap();
        assert!(dir.read_done(&a).unwrap().is_none());
        assert_eq!(dir.status(&a), Status::Pending);
        std::fs::write(dir.done(), done_of(&a, &a.config)).unwrap();
        assert!(dir.read_done(&a).unwrap().is_some());
        assert_eq!(dir.status(&a), Status::Done);
        // another case's marker copied here: refused by id, the case runs again
        let b = case("bbbbbbbbbbbb", "mu = 0.3\n");
        std::fs::write(dir.done(), done_of(&b, &a.config)).unwrap();
        let e = format!("{:#}", dir.read_done(&a).unwrap_err());
        assert!(
            e.contains("the marker of case bbbbbbbbbbbb") && e.contains("done.json"),
            "{e}"
        );
        assert_eq!(dir.status(&a), Status::Pending);
        // made from another configuration (config.toml edited before the run)
        std::fs::write(dir.done(), done_of(&a, "mu = 0.5\n")).unwrap();
        let e = format!("{:#}", dir.read_done(&a).unwrap_err());
        assert!(e.contains("another configuration"), "{e}");
        assert_eq!(dir.status(&a), Status::Pending);
        // an edited config.toml is put back by the plan and refused by a run meanwhile
        std::fs::write(dir.config(), "mu = 0.5\n").unwrap();
        let e = format!("{:#}", dir.checked_config(&a).unwrap_err());
        assert!(e.contains("differs from the plan's configuration"), "{e}");
        dir.prepare(&a).unwrap();
        dir.checked_config(&a).unwrap();
        // a marker that is a FIFO is never opened
        std::fs::remove_file(dir.done()).unwrap();
        let st = std::process::Command::new("mkfifo")
            .arg(dir.done())
            .status()
            .unwrap();
        assert!(st.success());
        let e = format!("{:#}", dir.read_done(&a).unwrap_err());
        assert!(e.contains("FIFO"), "{e}");
    }
    #[test]
    fn cuts_of_a_sweep_stop_when_sure_unless_the_sweep_says_not() {
        let d = tempfile::tempdir().unwrap();
        let base = d.path().join("base.toml");
        std::fs::write(&base, "mu = 0.3\n[steady]\nstop_when_sure = false\n").unwrap();
        let stop = |flag| {
            read_base(&base, CaseKind::Cutting, flag).unwrap()["steady"]["stop_when_sure"].as_bool()
        };
        assert_eq!((stop(true), stop(false)), (Some(true), Some(false)));
        // a pin's set-up has no [steady] criterion to set
        assert!(
            read_base(&base, CaseKind::Pin, true).unwrap()["steady"]["stop_when_sure"]
                .as_bool()
                .is_some_and(|b| !b)
        );
    }
    #[test]
    fn fields_are_set_created_and_removed_by_dotted_path() {
        let mut v: toml::Value =
            toml::from_str("mu = 0.3\n[friction]\nlaw_file = \"a.json\"\n").unwrap();
        apply(&mut v, "insert.rake_deg", &toml::Value::Float(6.0)).unwrap();
        apply(
            &mut v,
            "friction.law_file",
            &toml::Value::String(NONE.into()),
        )
        .unwrap();
        assert_eq!(v["insert"]["rake_deg"].as_float(), Some(6.0));
        assert!(v["friction"].get("law_file").is_none());
        let e = apply(&mut v, "mu.x", &toml::Value::Float(1.0)).unwrap_err();
        assert!(e.to_string().contains("'mu' is not a table"), "{e}");
        let rel = absolute_file(
            "friction.law_file",
            &toml::Value::String("l.json".into()),
            Path::new("/s"),
        );
        assert_eq!(rel.as_str(), Some("/s/l.json"));
    }
}
