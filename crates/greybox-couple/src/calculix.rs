//! CalculiX (ccx ≥ 2.20) as the coupling engine, following the experiment verified in
//! shared/docs/research/fe-engine-interfaces.md §4.2:
//!
//! * one `*SURFACE INTERACTION` + `*CONTACT PAIR, TYPE=SURFACE TO SURFACE` per window (penalty
//!   face-to-face; mortar contact with a shared slave surface fails in ccx 2.20);
//! * per-window forces from `*CONTACT PRINT, SLAVE=…, MASTER=…` with `CF` (area, normal force,
//!   shear force of the pair) in the `.dat` file; the window's pressure is |N|/A;
//! * the sliding velocity from the change of the mean tangential relative displacement (`CDIS`)
//!   of the slave surface over the segment, divided by the segment's physical duration;
//! * the next segment: `*RESTART,READ` (the previous `.rout` copied to `.rin`), the segment
//!   template with `{{FRICTION}}` replaced by `*CHANGE FRICTION` blocks for every window.
//!
//! Each cycle runs in `work/cycle_NNN/` and keeps its files.

use crate::engine::{Engine, WindowState};
use greybox_core::{Error, Result, SourcePos};
use std::path::{Path, PathBuf};
use std::process::Command;

/// Where the deck's numbers live in SI.
#[derive(Debug, Clone, PartialEq)]
pub struct CalculixConfig {
    pub ccx: PathBuf,
    pub deck: PathBuf,
    pub segment_template: PathBuf,
    pub work: PathBuf,
    /// Pa per deck stress unit (1e6 for N–mm–MPa decks).
    pub pressure_pa_per_unit: f64,
    /// m per deck length unit (1e-3 for mm).
    pub length_m_per_unit: f64,
    /// Physical duration of one segment, s (converts slip per segment to velocity).
    pub segment_s: f64,
}

/// A CalculiX deck prepared for coupling.
pub struct CalculixEngine {
    cfg: CalculixConfig,
    deck: String,
    template: String,
    windows: Vec<String>,
    interactions: Vec<String>,
    slave: String,
    stick_slopes: Vec<f64>,
    prev_slip: f64,
}

fn keyword_param(line: &str, key: &str) -> Option<String> {
    line.split(',').skip(1).find_map(|p| {
        let (k, v) = p.split_once('=')?;
        k.trim()
            .eq_ignore_ascii_case(key)
            .then(|| v.trim().to_string())
    })
}

/// Data lines after each occurrence of a keyword: (keyword line, data lines).
fn keyword_blocks<'a>(text: &'a str, keyword: &str) -> Vec<(&'a str, Vec<&'a str>)> {
    let lines: Vec<&str> = text.lines().collect();
    let mut out = Vec::new();
    for (i, l) in lines.iter().enumerate() {
        let t = l.trim();
        let head = t.split(',').next().unwrap_or("").trim();
        if head.eq_ignore_ascii_case(keyword) {
            let data = lines[i + 1..]
                .iter()
                .map(|s| s.trim())
                .take_while(|s| !s.starts_with('*') || s.starts_with("**"))
                .filter(|s| !s.starts_with("**") && !s.is_empty())
                .collect();
            out.push((t, data));
        }
    }
    out
}

/// An error in the file `src`.
fn missing(src: &str, what: String) -> Error {
    Error::input(SourcePos::file(src), what)
}

/// The deck's friction windows: one `*CONTACT PAIR` each (its master surface and surface
/// interaction), all sharing one slave surface.
struct ContactPairs {
    windows: Vec<String>,
    interactions: Vec<String>,
    slave: String,
}

/// The deck's contact pairs (at least one, surface-to-surface, one slave surface).
fn contact_pairs(deck: &str, dsrc: &str) -> Result<ContactPairs> {
    let (mut windows, mut interactions, mut slave) = (Vec::new(), Vec::new(), String::new());
    for (head, data) in keyword_blocks(deck, "*CONTACT PAIR") {
        let inter = keyword_param(head, "INTERACTION")
            .ok_or_else(|| missing(dsrc, format!("'{head}' has no INTERACTION=")))?;
        if keyword_param(head, "TYPE").is_some_and(|t| t.to_ascii_uppercase().contains("MORTAR")) {
            return Err(missing(dsrc, format!("'{head}': use TYPE=SURFACE TO SURFACE (mortar contact with a shared slave surface fails in CalculiX 2.20)")));
        }
        let pair: Vec<&str> = data
            .first()
            .map(|d| d.split(',').map(str::trim).collect())
            .unwrap_or_default();
        if pair.len() < 2 {
            return Err(missing(
                dsrc,
                format!("'{head}' needs a data line SLAVE, MASTER"),
            ));
        }
        if !slave.is_empty() && !slave.eq_ignore_ascii_case(pair[0]) {
            return Err(missing(
                dsrc,
                format!(
                    "all windows must share one slave surface; found {slave} and {}",
                    pair[0]
                ),
            ));
        }
        slave = pair[0].to_string();
        windows.push(pair[1].to_string());
        interactions.push(inter);
    }
    if windows.is_empty() {
        return Err(missing(dsrc, "no *CONTACT PAIR: every friction window needs its own contact pair and surface interaction".into()));
    }
    Ok(ContactPairs {
        windows,
        interactions,
        slave,
    })
}

/// The stick slope λ of every interaction: from the `*FRICTION` that follows its
/// `*SURFACE INTERACTION` (0 where none gives one); an interaction the deck does not define
/// is an error.
fn stick_slopes(deck: &str, interactions: &[String], dsrc: &str) -> Result<Vec<f64>> {
    let inter_blocks = keyword_blocks(deck, "*SURFACE INTERACTION");
    let mut stick_slopes = Vec::new();
    for name in interactions {
        if !inter_blocks
            .iter()
            .any(|(h, _)| keyword_param(h, "NAME").is_some_and(|n| n.eq_ignore_ascii_case(name)))
        {
            return Err(missing(
                dsrc,
                format!("no *SURFACE INTERACTION, NAME={name} for the contact pair that uses it"),
            ));
        }
        // the *FRICTION that follows this interaction's definition: take its stick slope λ
        let pos = deck
            .to_ascii_uppercase()
            .find(&format!("NAME={}", name.to_ascii_uppercase()))
            .unwrap_or(0);
        let after = &deck[pos..];
        let lambda = keyword_blocks(after, "*FRICTION")
            .first()
            .and_then(|(_, d)| d.first())
            .and_then(|l| l.split(',').nth(1))
            .and_then(|v| v.trim().parse::<f64>().ok())
            .unwrap_or(0.0);
        stick_slopes.push(lambda);
    }
    Ok(stick_slopes)
}

/// The outputs greybox reads, in the deck or the segment template `text`: each window's
/// contact forces (CF), the slips (CDIS) and a restart file.
fn check_outputs(text: &str, src: &str, windows: &[String], slave: &str) -> Result<()> {
    let prints: Vec<String> = keyword_blocks(text, "*CONTACT PRINT")
        .iter()
        .filter(|(_, d)| {
            d.iter()
                .any(|l| l.split(',').any(|v| v.trim().eq_ignore_ascii_case("CF")))
        })
        .filter_map(|(h, _)| keyword_param(h, "MASTER"))
        .collect();
    for w in windows {
        if !prints.iter().any(|m| m.eq_ignore_ascii_case(w)) {
            return Err(missing(src, format!("no *CONTACT PRINT, SLAVE={slave}, MASTER={w} with CF: greybox reads each window's forces from it")));
        }
    }
    if !text.to_ascii_uppercase().contains("*RESTART,WRITE")
        && !text.to_ascii_uppercase().contains("*RESTART, WRITE")
    {
        return Err(missing(
            src,
            "no *RESTART,WRITE: the next segment restarts from it".into(),
        ));
    }
    if !keyword_blocks(text, "*CONTACT PRINT")
        .iter()
        .any(|(_, d)| d.iter().any(|l| l.to_ascii_uppercase().contains("CDIS")))
    {
        return Err(missing(
            src,
            "no *CONTACT PRINT with CDIS: the sliding velocity comes from it".into(),
        ));
    }
    Ok(())
}

impl CalculixEngine {
    /// Read and check the deck and the segment template before anything runs.
    pub fn new(cfg: CalculixConfig) -> Result<Self> {
        let deck = greybox_core::input::read_data_text(&cfg.deck, "CalculiX deck")?;
        let template =
            greybox_core::input::read_data_text(&cfg.segment_template, "segment template")?;
        let dsrc = cfg.deck.display().to_string();
        let tsrc = cfg.segment_template.display().to_string();
        let ContactPairs {
            windows,
            interactions,
            slave,
        } = contact_pairs(&deck, &dsrc)?;
        let stick_slopes = stick_slopes(&deck, &interactions, &dsrc)?;
        for (text, src) in [(&deck, &dsrc), (&template, &tsrc)] {
            check_outputs(text, src, &windows, &slave)?;
        }
        if !template.contains("{{FRICTION}}") {
            return Err(missing(
                &tsrc,
                "the segment template has no {{FRICTION}} placeholder".into(),
            ));
        }
        if !(cfg.pressure_pa_per_unit > 0.0 && cfg.length_m_per_unit > 0.0 && cfg.segment_s > 0.0) {
            return Err(Error::invalid(
                "CalculiX coupling",
                "unit factors and the segment duration must be positive",
            ));
        }
        Ok(CalculixEngine {
            cfg,
            deck,
            template,
            windows,
            interactions,
            slave,
            stick_slopes,
            prev_slip: 0.0,
        })
    }

    fn cycle_dir(&self, cycle: usize) -> PathBuf {
        self.cfg.work.join(format!("cycle_{cycle:03}"))
    }

    fn friction_text(&self, mu: &[f64]) -> String {
        let mut s = String::new();
        for ((name, m), lambda) in self.interactions.iter().zip(mu).zip(&self.stick_slopes) {
            s.push_str(&format!(
                "*CHANGE FRICTION,INTERACTION={name}\n*FRICTION\n{m:?}"
            ));
            if *lambda > 0.0 {
                s.push_str(&format!(",{lambda:?}"));
            }
            s.push('\n');
        }
        s
    }
}

/// Per-window contact forces: (area, |normal force|, shear force).
pub type PairForces = Vec<(f64, f64, f64)>;

/// Per-window (area, |normal force|, shear force) at the last printed time, and the mean
/// tangential relative displacement of the slave surface, from a `.dat` file.
pub fn parse_dat(
    text: &str,
    source: &str,
    slave: &str,
    masters: &[String],
) -> Result<(PairForces, f64)> {
    let lines: Vec<&str> = text.lines().collect();
    let mut forces = Vec::new();
    for m in masters {
        let tag = format!(
            "statistics for slave set {}, master set {} and time",
            slave.to_ascii_uppercase(),
            m.to_ascii_uppercase()
        );
        let heads: Vec<(usize, f64)> = lines
            .iter()
            .enumerate()
            .filter(|(_, l)| l.to_ascii_uppercase().contains(&tag.to_ascii_uppercase()))
            .map(|(i, l)| {
                (
                    i,
                    l.split_whitespace()
                        .last()
                        .and_then(|t| t.parse::<f64>().ok())
                        .unwrap_or(f64::NAN),
                )
            })
            .collect();
        let t_last = heads.iter().map(|h| h.1).fold(f64::NEG_INFINITY, f64::max);
        let (mut area, mut normal, mut shear) = (0.0f64, 0.0f64, 0.0f64);
        let mut found = false;
        for &(i, _) in heads.iter().filter(|h| h.1 == t_last) {
            let Some(k) =
                (i..lines.len().min(i + 20)).find(|&k| lines[k].contains("area,  normal force"))
            else {
                continue;
            };
            let vals: Vec<f64> = lines
                .get(k + 2)
                .map(|l| {
                    l.split_whitespace()
                        .filter_map(|v| v.parse().ok())
                        .collect()
                })
                .unwrap_or_default();
            if vals.len() == 3 {
                found = true;
                area = area.max(vals[0]);
                normal = normal.max(vals[1].abs());
                shear = shear.max(vals[2].abs());
            }
        }
        if !found {
            return Err(Error::input(
                SourcePos::file(source),
                format!(
                    "no contact force statistics for master set {m}: is the window in contact?"
                ),
            ));
        }
        forces.push((area, normal, shear));
    }
    let head = lines
        .iter()
        .rposition(|l| l.contains("relative contact displacement"))
        .ok_or_else(|| {
            Error::input(
                SourcePos::file(source),
                "no relative contact displacement (CDIS) output",
            )
        })?;
    let mut slips = Vec::new();
    for l in &lines[head + 1..] {
        let v: Vec<f64> = l
            .split_whitespace()
            .filter_map(|x| x.parse().ok())
            .collect();
        if v.len() == 5 {
            slips.push((v[3] * v[3] + v[4] * v[4]).sqrt());
        } else if !slips.is_empty() && !l.trim().is_empty() {
            break;
        }
    }
    let slip = if slips.is_empty() {
        0.0
    } else {
        slips.iter().sum::<f64>() / slips.len() as f64
    };
    Ok((forces, slip))
}

fn log_tail(path: &Path) -> String {
    let text = greybox_core::input::read_data_text(path, "CalculiX log").unwrap_or_default();
    let lines: Vec<&str> = text.lines().filter(|l| !l.trim().is_empty()).collect();
    lines[lines.len().saturating_sub(15)..].join("\n")
}

impl Engine for CalculixEngine {
    fn windows(&self) -> &[String] {
        &self.windows
    }

    fn run_segment(&mut self, cycle: usize, friction: Option<&[f64]>) -> Result<Vec<WindowState>> {
        let dir = self.cycle_dir(cycle);
        std::fs::create_dir_all(&dir).map_err(|e| Error::io(&dir, e))?;
        let input = if cycle == 0 {
            match friction {
                None => self.deck.clone(),
                Some(_) => {
                    return Err(Error::invalid(
                        "CalculiX coupling",
                        "the first cycle runs the deck with its own friction",
                    ))
                }
            }
        } else {
            let mu = friction.ok_or_else(|| {
                Error::invalid(
                    "CalculiX coupling",
                    "a restart segment needs the window friction",
                )
            })?;
            let prev = self.cycle_dir(cycle - 1).join("job.rout");
            std::fs::copy(&prev, dir.join("job.rin")).map_err(|e| Error::io(&prev, e))?;
            format!(
                "*RESTART,READ\n{}",
                self.template
                    .replace("{{FRICTION}}", &self.friction_text(mu))
                    .replace("{{CYCLE}}", &cycle.to_string())
            )
        };
        greybox_core::atomic::write_string_atomic(&dir.join("job.inp"), &input)?;
        let log = dir.join("ccx.log");
        let out = Command::new(&self.cfg.ccx)
            .arg("job")
            .current_dir(&dir)
            .output()
            .map_err(|e| {
                Error::invalid(
                    "CalculiX",
                    format!(
                        "cannot run '{}': {e} (install calculix-ccx or set `ccx` to its path)",
                        self.cfg.ccx.display()
                    ),
                )
            })?;
        let mut text = out.stdout.clone();
        text.extend_from_slice(&out.stderr);
        greybox_core::atomic::write_atomic(&log, |w| w.write_all(&text))?;
        let text = String::from_utf8_lossy(&text);
        if !out.status.success() || text.contains("*ERROR") || !text.contains("Job finished") {
            return Err(Error::invalid(
                "CalculiX",
                format!(
                    "cycle {cycle} failed (files kept in {}); log tail:\n{}",
                    dir.display(),
                    log_tail(&log)
                ),
            ));
        }
        let dat = dir.join("job.dat");
        let dtext = greybox_core::input::read_data_text(&dat, "CalculiX results")?;
        let (forces, slip) = parse_dat(
            &dtext,
            &dat.display().to_string(),
            &self.slave,
            &self.windows,
        )?;
        let dslip = if slip >= self.prev_slip {
            slip - self.prev_slip
        } else {
            slip
        };
        self.prev_slip = slip;
        let v = dslip * self.cfg.length_m_per_unit / self.cfg.segment_s;
        Ok(forces
            .into_iter()
            .map(|(a, n, s)| WindowState {
                pressure_pa: if a > 0.0 {
                    n / a * self.cfg.pressure_pa_per_unit
                } else {
                    0.0
                },
                sliding_velocity_m_s: v,
                temperature_k: None,
                shear_ratio: if n > 0.0 { s / n } else { 0.0 },
            })
            .collect())
    }
}
