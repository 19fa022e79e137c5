//! The progress displays the command line installs (see `greybox_core::progress`):
//! a bar with rate and ETA when stderr is a terminal, one-line status every few seconds
//! when it is not (logs, CI, batch jobs), nothing with `--quiet`. Everything goes to
//! stderr, so `--json` output on stdout is never touched.
//!
//! `GREYBOX_PROGRESS=bar|lines|off` overrides the choice; `GREYBOX_PROGRESS_INTERVAL_S`
//! sets the seconds between status lines (default 10).

use greybox_core::progress::{install, Sink};
use indicatif::{MultiProgress, ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::collections::HashMap;
use std::io::{IsTerminal, Write};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// How progress is shown.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Mode {
    Bar,
    Lines(Duration),
    Off,
}

impl Mode {
    /// The mode for this process: `--quiet` wins, then `GREYBOX_PROGRESS`, then whether
    /// stderr is a terminal.
    pub fn choose(quiet: bool) -> Mode {
        if quiet {
            return Mode::Off;
        }
        let interval = std::env::var("GREYBOX_PROGRESS_INTERVAL_S")
            .ok()
            .and_then(|s| s.trim().parse::<f64>().ok())
            .filter(|s| s.is_finite() && *s >= 0.0)
            .map(Duration::from_secs_f64)
            .unwrap_or(Duration::from_secs(10));
        match std::env::var("GREYBOX_PROGRESS").as_deref() {
            Ok("off") => Mode::Off,
            Ok("lines") => Mode::Lines(interval),
            Ok("bar") => Mode::Bar,
            _ if std::io::stderr().is_terminal() => Mode::Bar,
            _ => Mode::Lines(interval),
        }
    }
    /// Installs the display for this mode.
    pub fn install(self) {
        match self {
            Mode::Bar => install(Arc::new(Bars::default())),
            Mode::Lines(every) => install(Arc::new(Lines::new(every))),
            Mode::Off => {}
        }
    }
}

/// indicatif bars, one per running task.
#[derive(Default)]
struct Bars {
    multi: MultiProgressOnStderr,
    bars: Mutex<HashMap<u64, ProgressBar>>,
}

struct MultiProgressOnStderr(MultiProgress);

impl Default for MultiProgressOnStderr {
    fn default() -> Self {
        MultiProgressOnStderr(MultiProgress::with_draw_target(
            ProgressDrawTarget::stderr_with_hz(10),
        ))
    }
}

impl Sink for Bars {
    fn begin(&self, id: u64, label: &str, total: Option<u64>, unit: &str) {
        let bar = match total {
            Some(n) => ProgressBar::new(n).with_style(
                ProgressStyle::with_template(&format!(
                    "{{prefix}} [{{bar:30}}] {{pos}}/{{len}} {unit} ({{percent}} %) {{per_sec}} ETA {{eta}} {{msg}}"
                ))
                .unwrap_or_else(|_| ProgressStyle::default_bar())
                .progress_chars("=> "),
            ),
            None => ProgressBar::new_spinner().with_style(
                ProgressStyle::with_template(&format!(
                    "{{prefix}} {{spinner}} {{pos}} {unit} {{elapsed}} {{msg}}"
                ))
                .unwrap_or_else(|_| ProgressStyle::default_spinner()),
            ),
        };
        let bar = self.multi.0.add(bar.with_prefix(label.to_string()));
        bar.enable_steady_tick(Duration::from_millis(200));
        self.bars
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .insert(id, bar);
    }
    fn update(&self, id: u64, done: u64, message: Option<&str>) {
        if let Some(b) = self.bars.lock().unwrap_or_else(|e| e.into_inner()).get(&id) {
            b.set_position(done);
            if let Some(m) = message {
                b.set_message(m.to_string());
            }
        }
    }
    fn end(&self, id: u64, outcome: &str) {
        if let Some(b) = self
            .bars
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .remove(&id)
        {
            b.finish_with_message(outcome.to_string());
        }
    }
}

/// Periodic one-line status on stderr.
struct Lines {
    every: Duration,
    tasks: Mutex<HashMap<u64, LineTask>>,
}

struct LineTask {
    label: String,
    unit: String,
    total: Option<u64>,
    started: Instant,
    last_line: Instant,
}

impl Lines {
    fn new(every: Duration) -> Self {
        Lines {
            every,
            tasks: Mutex::new(HashMap::new()),
        }
    }
}

/// `h:mm:ss` or `m:ss`.
fn clock(s: f64) -> String {
    let s = s.max(0.0).round() as u64;
    if s >= 3600 {
        format!("{}:{:02}:{:02}", s / 3600, (s / 60) % 60, s % 60)
    } else {
        format!("{}:{:02}", s / 60, s % 60)
    }
}

/// One status line: label, amount done (of total), rate, ETA, message.
fn status_line(t: &LineTask, done: u64, message: Option<&str>) -> String {
    let elapsed = t.started.elapsed().as_secs_f64();
    let rate = if elapsed > 0.0 {
        done as f64 / elapsed
    } else {
        0.0
    };
    let mut line = match t.total {
        Some(n) if n > 0 => format!(
            "{}: {done}/{n} {} ({:.1} %)",
            t.label,
            t.unit,
            100.0 * done as f64 / n as f64
        ),
        _ => format!("{}: {done} {}", t.label, t.unit),
    };
    let rate_text = if rate >= 100.0 {
        format!("{rate:.0}")
    } else {
        format!("{rate:.3}")
    };
    line += &format!(", {rate_text} {}/s, elapsed {}", t.unit, clock(elapsed));
    if let Some(n) = t.total {
        if rate > 0.0 && done < n {
            line += &format!(", ETA {}", clock((n - done) as f64 / rate));
        }
    }
    if let Some(m) = message.filter(|m| !m.is_empty()) {
        line += &format!(" — {m}");
    }
    line
}

fn say(line: &str) {
    let mut err = std::io::stderr().lock();
    let _ = writeln!(err, "[greybox] {line}");
}

impl Sink for Lines {
    fn begin(&self, id: u64, label: &str, total: Option<u64>, unit: &str) {
        let now = Instant::now();
        let t = LineTask {
            label: label.to_string(),
            unit: unit.to_string(),
            total,
            started: now,
            last_line: now,
        };
        say(&match total {
            Some(n) => format!("{label}: started ({n} {unit})"),
            None => format!("{label}: started"),
        });
        self.tasks
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .insert(id, t);
    }
    fn update(&self, id: u64, done: u64, message: Option<&str>) {
        let mut tasks = self.tasks.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(t) = tasks.get_mut(&id) {
            if t.last_line.elapsed() >= self.every {
                t.last_line = Instant::now();
                say(&status_line(t, done, message));
            }
        }
    }
    fn end(&self, id: u64, outcome: &str) {
        if let Some(t) = self
            .tasks
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .remove(&id)
        {
            say(&format!(
                "{}: {outcome} after {}",
                t.label,
                clock(t.started.elapsed().as_secs_f64())
            ));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    #[test]
    fn status_lines_state_amount_rate_and_eta() {
        let t = LineTask {
            label: "simulate cutting".into(),
            unit: "steps".into(),
            total: Some(1000),
            started: Instant::now() - Duration::from_secs(10),
            last_line: Instant::now(),
        };
        let l = status_line(&t, 250, Some("F'c 120 N/mm"));
        assert!(
            l.starts_with("simulate cutting: 250/1000 steps (25.0 %)"),
            "{l}"
        );
        assert!(l.contains("steps/s") && l.contains("ETA 0:3"), "{l}");
        assert!(l.ends_with("— F'c 120 N/mm"), "{l}");
        assert_eq!(clock(3725.0), "1:02:05");
    }
}
