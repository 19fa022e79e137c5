//! The restart loop of the article's section 6 (digest §8), with the FE engine behind a small
//! trait: run one segment with given per-window friction, report each window's contact state.
//!
//! Each cycle: the engine runs a segment; greybox reads every window's mean pressure and
//! sliding velocity (and temperature where available), evaluates the friction law per window,
//! and hands the new μ to the next segment. The loop stops at the cycle limit or when every
//! window's μ changes by less than the tolerance between cycles. Every cycle keeps its own
//! input and output files.

use greybox_core::atomic::write_string_atomic;
use greybox_core::units;
use greybox_core::{ContactState, Error, FrictionLaw, Result};
use serde::Serialize;
use std::path::Path;

/// A window's contact state over the last segment (SI).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct WindowState {
    pub pressure_pa: f64,
    pub sliding_velocity_m_s: f64,
    pub temperature_k: Option<f64>,
    /// Shear force / |normal force| as the engine reports it (the μ it applied, when sliding).
    pub shear_ratio: f64,
}

/// An FE engine that runs restartable segments: the seam between the restart loop
/// ([`couple`]) and an external solver (CalculiX, a DEFORM deck, a test double).
///
/// An implementation names its friction windows once and, per segment, runs the engine with
/// the given μ per window (in the order of [`Engine::windows`]) and reads back each window's
/// mean contact state. A toy engine whose contact state does not depend on μ converges after
/// one restart:
///
/// ```
/// use greybox_core::{ContactState, FrictionLaw, Result};
/// use greybox_couple::engine::{couple, Engine, WindowState};
///
/// struct Toy { names: Vec<String> }
/// impl Engine for Toy {
///     fn windows(&self) -> &[String] { &self.names }
///     fn run_segment(&mut self, _cycle: usize, friction: Option<&[f64]>) -> Result<Vec<WindowState>> {
///         let mu = friction.map_or(0.5, |f| f[0]); // the deck's own μ: 0.5
///         Ok(vec![WindowState {
///             pressure_pa: 5e8,
///             sliding_velocity_m_s: 2.0,
///             temperature_k: None,
///             shear_ratio: mu,
///         }])
///     }
/// }
/// struct Constant;
/// impl FrictionLaw for Constant {
///     fn name(&self) -> String { "constant".into() }
///     fn mu(&self, _: &ContactState) -> f64 { 0.3 }
/// }
///
/// let mut engine = Toy { names: vec!["rake".into()] };
/// let r = couple(&mut engine, &Constant, 5, 1e-3, None)?;
/// assert!(r.converged);
/// assert_eq!(r.cycles, 1);
/// assert_eq!(r.final_mu, vec![("rake".to_string(), 0.3)]);
/// assert_eq!(r.history[0].shear_ratio, 0.5); // cycle 0 ran with the deck's μ
/// # Ok::<(), greybox_core::Error>(())
/// ```
pub trait Engine {
    /// The friction windows (names) in a fixed order.
    fn windows(&self) -> &[String];
    /// Run segment `cycle` (0 = the initial run of the deck, whose friction is the deck's own
    /// when `friction` is `None`) and return the state of every window.
    fn run_segment(&mut self, cycle: usize, friction: Option<&[f64]>) -> Result<Vec<WindowState>>;
}

/// One row of the coupling history.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct HistoryRow {
    pub cycle: usize,
    pub window: String,
    pub pressure_mpa: f64,
    pub velocity_m_per_min: f64,
    pub temperature_k: Option<f64>,
    pub shear_ratio: f64,
    /// μ in force during the segment (None for the deck's own in cycle 0).
    pub mu_used: Option<f64>,
    /// μ the law gives for the state read back.
    pub mu_new: f64,
}

/// Outcome of a coupling run.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CouplingResult {
    pub cycles: usize,
    pub converged: bool,
    pub final_mu: Vec<(String, f64)>,
    pub history: Vec<HistoryRow>,
}

/// Run the loop: at most `max_cycles` segments after the initial one; converged when every
/// window's μ changes by less than `tol`.
pub fn couple(
    engine: &mut dyn Engine,
    law: &dyn FrictionLaw,
    max_cycles: usize,
    tol: f64,
    history_csv: Option<&Path>,
) -> Result<CouplingResult> {
    let names = engine.windows().to_vec();
    let mut history = Vec::new();
    let mut used: Option<Vec<f64>> = None;
    let mut converged = false;
    let mut cycle = 0;
    let progress = greybox_core::progress::task("couple", Some(max_cycles as u64 + 1), "segments");
    loop {
        let states = engine.run_segment(cycle, used.as_deref())?;
        progress.set(cycle as u64 + 1);
        if states.len() != names.len() {
            return Err(Error::invalid(
                "coupling",
                format!(
                    "the engine reported {} windows, expected {}",
                    states.len(),
                    names.len()
                ),
            ));
        }
        let new: Vec<f64> = states
            .iter()
            .map(|s| {
                let st = ContactState {
                    pressure_pa: s.pressure_pa,
                    sliding_velocity_m_s: s.sliding_velocity_m_s,
                    temperature_k: s.temperature_k.unwrap_or(ContactState::ROOM_TEMPERATURE_K),
                };
                let mu = law.mu(&st);
                if mu.is_finite() && mu >= 0.0 {
                    Ok(mu)
                } else {
                    Err(Error::invalid(
                        "coupling",
                        format!(
                            "the law gives μ = {mu} at p = {} Pa, v = {} m/s",
                            st.pressure_pa, st.sliding_velocity_m_s
                        ),
                    ))
                }
            })
            .collect::<Result<_>>()?;
        for (i, s) in states.iter().enumerate() {
            history.push(HistoryRow {
                cycle,
                window: names[i].clone(),
                pressure_mpa: s.pressure_pa * units::MPA_PER_PA,
                velocity_m_per_min: units::m_per_s_to_m_per_min(s.sliding_velocity_m_s),
                temperature_k: s.temperature_k,
                shear_ratio: s.shear_ratio,
                mu_used: used.as_ref().map(|u| u[i]),
                mu_new: new[i],
            });
        }
        if let Some(path) = history_csv {
            write_history(path, &history)?;
        }
        if let Some(u) = &used {
            if u.iter().zip(&new).all(|(a, b)| (a - b).abs() < tol) {
                converged = true;
            }
        }
        used = Some(new);
        if converged || cycle >= max_cycles {
            break;
        }
        cycle += 1;
    }
    progress.finish(if converged {
        "converged"
    } else {
        "not converged"
    });
    let final_mu = names.into_iter().zip(used.unwrap_or_default()).collect();
    Ok(CouplingResult {
        cycles: cycle,
        converged,
        final_mu,
        history,
    })
}

/// The history as CSV.
pub fn write_history(path: &Path, rows: &[HistoryRow]) -> Result<()> {
    let mut s = String::from("cycle,window,pressure_MPa,sliding_velocity_m_per_min,temperature_K,shear_ratio,mu_used,mu_new\n");
    for r in rows {
        s.push_str(&format!(
            "{},{},{},{},{},{},{},{}\n",
            r.cycle,
            r.window,
            r.pressure_mpa,
            r.velocity_m_per_min,
            r.temperature_k.map(|t| t.to_string()).unwrap_or_default(),
            r.shear_ratio,
            r.mu_used.map(|m| m.to_string()).unwrap_or_default(),
            r.mu_new
        ));
    }
    write_string_atomic(path, &s)
}

/// A user-scripted engine (how a DEFORM user hooks in: DEF_PRE text mode with DBREAD/KFWRIT,
/// edit the keyword file's FRCWIN blocks, KFREAD/GENDB, run the solver, export the window
/// states). Per cycle greybox writes `friction.csv` (`window,mu`; empty μ in cycle 0 = keep the
/// model's own) into `work/cycle_NNN/`, runs the command template through `sh -c` with
/// `{cycle}`, `{dir}` and `{prev_dir}` substituted as shell-quoted words ([`command_line`]:
/// write `solver {dir}`, not `solver "{dir}"`), and reads `states.csv` that the command
/// must write there: `window,pressure_MPa,sliding_velocity_m_per_min,temperature_K,shear_ratio`
/// (temperature may be empty).
pub struct CommandEngine {
    pub windows: Vec<String>,
    pub command: String,
    pub work: std::path::PathBuf,
}

impl Engine for CommandEngine {
    fn windows(&self) -> &[String] {
        &self.windows
    }

    fn run_segment(&mut self, cycle: usize, friction: Option<&[f64]>) -> Result<Vec<WindowState>> {
        use greybox_core::SourcePos;
        let dir = self.work.join(format!("cycle_{cycle:03}"));
        let prev = if cycle > 0 {
            self.work.join(format!("cycle_{:03}", cycle - 1))
        } else {
            dir.clone()
        };
        std::fs::create_dir_all(&dir).map_err(|e| Error::io(&dir, e))?;
        write_string_atomic(
            &dir.join("friction.csv"),
            &friction_csv(&self.windows, friction),
        )?;
        let cmd = command_line(
            &self.command,
            &[
                ("cycle", cycle.to_string()),
                ("dir", dir.display().to_string()),
                ("prev_dir", prev.display().to_string()),
            ],
        )?;
        let out = std::process::Command::new("sh")
            .arg("-c")
            .arg(&cmd)
            .output()
            .map_err(|e| Error::invalid("command engine", format!("cannot run sh: {e}")))?;
        let log = dir.join("command.log");
        let mut text = out.stdout.clone();
        text.extend_from_slice(&out.stderr);
        greybox_core::atomic::write_atomic(&log, |w| w.write_all(&text))?;
        if !out.status.success() {
            let t = String::from_utf8_lossy(&text);
            let tail: Vec<&str> = t.lines().rev().take(15).collect();
            return Err(Error::invalid(
                "command engine",
                format!(
                    "cycle {cycle}: '{cmd}' failed ({}); output tail:\n{}",
                    out.status,
                    tail.into_iter().rev().collect::<Vec<_>>().join("\n")
                ),
            ));
        }
        let path = dir.join("states.csv");
        let src = path.display().to_string();
        let text = greybox_core::input::read_data_text(&path, "engine's window states")?;
        let mut rows: std::collections::HashMap<String, WindowState> =
            std::collections::HashMap::new();
        for (k, line) in text.lines().enumerate().skip(1) {
            if line.trim().is_empty() {
                continue;
            }
            let f: Vec<&str> = line.split(',').map(str::trim).collect();
            let pos = || SourcePos::file(&src).line(k as u64 + 1);
            if f.len() != 5 {
                return Err(Error::input(pos(), "expected window,pressure_MPa,sliding_velocity_m_per_min,temperature_K,shear_ratio"));
            }
            let num = |s: &str, name: &str| -> Result<f64> {
                let v: f64 = s.parse().map_err(|_| {
                    Error::input(pos().field(name), format!("expected a number, found '{s}'"))
                })?;
                if v.is_finite() {
                    Ok(v)
                } else {
                    Err(Error::input(pos().field(name), "not finite"))
                }
            };
            let t = if f[3].is_empty() {
                None
            } else {
                Some(num(f[3], "temperature_K")?)
            };
            rows.insert(
                f[0].to_string(),
                WindowState {
                    pressure_pa: units::mpa_to_pa(num(f[1], "pressure_MPa")?),
                    sliding_velocity_m_s: units::m_per_min_to_m_per_s(num(
                        f[2],
                        "sliding_velocity_m_per_min",
                    )?),
                    temperature_k: t,
                    shear_ratio: num(f[4], "shear_ratio")?,
                },
            );
        }
        self.windows
            .iter()
            .map(|w| {
                rows.get(w).copied().ok_or_else(|| {
                    Error::input(SourcePos::file(&src), format!("no state for window '{w}'"))
                })
            })
            .collect()
    }
}

/// `friction.csv` of a cycle: `window,mu`, window names as CSV fields, μ empty without
/// `friction` (cycle 0: the model's own).
fn friction_csv(windows: &[String], friction: Option<&[f64]>) -> String {
    let mut f = String::from("window,mu\n");
    for (i, w) in windows.iter().enumerate() {
        f.push_str(&format!(
            "{},{}\n",
            greybox_core::escape::csv_field(w),
            friction.map(|m| format!("{:?}", m[i])).unwrap_or_default()
        ));
    }
    f
}

/// The command template with each `{name}` of `values` replaced by its value as one
/// shell-quoted word ([`greybox_core::escape::shell_quote`], POSIX single quotes), in one
/// pass (a value holding `{dir}` is not substituted again). A work directory named
/// `w;touch PWNED;x` or `my runs` stays one argument. A placeholder the template itself
/// quotes (`"{dir}"`, `'{dir}'`) is refused: the quotes would become part of the argument.
pub fn command_line(template: &str, values: &[(&str, String)]) -> Result<String> {
    for (name, _) in values {
        for q in ['"', '\'', '`'] {
            if template.contains(&format!("{q}{{{name}}}")) {
                return Err(Error::invalid(
                    "command engine",
                    format!("the command template quotes {{{name}}} ({q}{{{name}}}…): greybox substitutes placeholders already shell-quoted, so write {{{name}}} without quotes"),
                ));
            }
        }
    }
    let mut out = String::with_capacity(template.len() + 64);
    let mut rest = template;
    'scan: while let Some(i) = rest.find('{') {
        out.push_str(&rest[..i]);
        for (name, value) in values {
            let key = format!("{{{name}}}");
            if rest[i..].starts_with(&key) {
                out.push_str(&greybox_core::escape::shell_quote(value)?);
                rest = &rest[i + key.len()..];
                continue 'scan;
            }
        }
        out.push('{');
        rest = &rest[i + 1..];
    }
    out.push_str(rest);
    Ok(out)
}
