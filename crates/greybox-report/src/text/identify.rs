//! Plain-text tables of the identify stage: the per-pin summary, every plateau, how each file
//! was segmented and matched to the plan, and the per-file report of `--inspect`.

use super::table::Table;
use greybox_core::dataset::FrictionDataset;
use greybox_core::units;
use greybox_pipeline::identify::IdentifySummary;
use greybox_tribo::campaign::{FileReport, Identification, MatchReport};
use std::fmt::Write as _;

/// Per-pin summary table.
pub fn summary_table(ds: &FrictionDataset) -> String {
    let mut t = Table::new(&[
        "pin",
        "F_N plan [N]",
        "F_N meas. [N]",
        "p_H [MPa]",
        "COF first",
        "COF last",
        "std max",
        "steps",
        "flagged",
    ]);
    let mut pins: Vec<u32> = ds.records.iter().map(|r| r.pin).collect();
    pins.dedup();
    for pin in pins {
        let rows: Vec<_> = ds.records.iter().filter(|r| r.pin == pin).collect();
        let (first, last) = (rows[0], rows[rows.len() - 1]);
        t.row(vec![
            pin.to_string(),
            first
                .normal_force_planned_n
                .map_or("-".into(), |f| format!("{f:.1}")),
            format!("{:.1}", first.normal_force_n),
            format!("{:.1}", first.hertz_pressure_pa / units::PA_PER_MPA),
            format!("{:.4}", first.cof_apparent),
            format!("{:.4}", last.cof_apparent),
            format!(
                "{:.4}",
                rows.iter().map(|r| r.cof_apparent_std).fold(0.0, f64::max)
            ),
            rows.len().to_string(),
            rows.iter().filter(|r| !r.stationary).count().to_string(),
        ]);
    }
    t.render()
}

/// One line per file: how it was segmented.
pub fn files_table(id: &Identification) -> String {
    let mut t = Table::new(&[
        "file",
        "segmentation",
        "baseline",
        "segments",
        "rows",
        "notes",
    ]);
    for f in &id.files {
        t.row(vec![
            f.source.clone(),
            f.segmentation.clone(),
            f.baseline.clone(),
            f.segments.len().to_string(),
            f.segments
                .iter()
                .filter(|s| s.matched.is_some())
                .count()
                .to_string(),
            f.notes.len().to_string(),
        ]);
    }
    let mut s = t.render();
    for f in &id.files {
        s.push_str(&coverage_lines(f));
    }
    s
}

/// A file's coverage line, its dropped parts with their reasons, and its warnings (what was
/// split, left unread or contradicts what was used): the one place the summary and
/// `--inspect` say what did not make it into the dataset.
pub fn coverage_lines(f: &FileReport) -> String {
    let mut s = format!("coverage of {}: {}\n", f.source, f.coverage.line());
    for d in f.coverage.dropped_notes() {
        s.push_str(&format!("   {d}\n"));
    }
    for w in &f.warnings {
        s.push_str(&format!("   warning: {w}\n"));
    }
    s
}

/// Every plateau, one row each.
pub fn all_rows_table(ds: &FrictionDataset) -> String {
    let mut t = Table::new(&[
        "pin",
        "step",
        "F_N [N]",
        "v [m/min]",
        "p_H [MPa]",
        "COF",
        "±95%",
        "std",
        "n",
        "label",
        "flags",
    ]);
    for r in &ds.records {
        t.row(vec![
            r.pin.to_string(),
            r.step.to_string(),
            format!("{:.1}", r.normal_force_n),
            format!("{:.1}", units::m_per_s_to_m_per_min(r.sliding_velocity_m_s)),
            format!("{:.1}", r.hertz_pressure_pa / units::PA_PER_MPA),
            format!("{:.4}", r.cof_apparent),
            r.cof_apparent_ci95
                .map_or("-".into(), |c| format!("{c:.4}")),
            format!("{:.4}", r.cof_apparent_std),
            r.n_samples.to_string(),
            r.label_evidence.clone().unwrap_or_else(|| "-".into()),
            r.flags.join(";"),
        ]);
    }
    t.render()
}

/// The per-file report of `--inspect`.
pub fn inspect_text(files: &[FileReport]) -> String {
    let mut s = String::new();
    for f in files {
        let _ = writeln!(s, "== {}", f.source);
        s.push_str(&read_lines(f));
        s.push_str(&found_line(f));
        let _ = write!(s, "   {}", coverage_lines(f));
        for n in &f.notes {
            let _ = writeln!(s, "   note: {n}");
        }
        for u in &f.unusual {
            let _ = writeln!(s, "   unusual: {u}");
        }
        s.push_str(&reciprocating_lines(f));
        s.push_str(&segments_table(f));
    }
    s
}

/// How a file was read: its layout, the column each channel came from (with its unit, scale
/// and how it was recognised), its footer lines and the reader's notes; nothing when the file
/// was not read here.
fn read_lines(f: &FileReport) -> String {
    let mut s = String::new();
    let Some(r) = &f.read else { return s };
    let _ = writeln!(s, "   layout: {}", r.layout);
    for c in &r.columns {
        let _ = writeln!(
            s,
            "   {:<10} <- '{}' [{}]{} ({})",
            c.role,
            c.column,
            c.unit,
            if c.scale != 1.0 {
                format!(" x {}", c.scale)
            } else {
                String::new()
            },
            c.how
        );
    }
    for (line, text) in &r.footer {
        let _ = writeln!(s, "   footer line {line}: {text}");
    }
    for n in &r.notes {
        let _ = writeln!(s, "   note: {n}");
    }
    s
}

/// One line on what was found in a file: samples, rate, duration, where sliding was read
/// from, its segmentation and baseline, and the signs flipped.
fn found_line(f: &FileReport) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "   {} samples at {:.3} Hz over {:.3} s; sliding from the {}{}; segmentation: {}; baseline: {}{}{}",
        f.samples,
        f.sample_rate_hz,
        f.duration_s,
        f.sliding,
        f.period_s
            .map_or(String::new(), |p| format!(" (period {p:.3} s)")),
        f.segmentation,
        f.baseline,
        if f.tangential_sign_flipped {
            "; tangential sign flipped"
        } else {
            ""
        },
        if f.normal_sign_flipped {
            "; normal sign flipped"
        } else {
            ""
        }
    );
    s
}

/// A file's segments, one row each: times, load, speed, steady window, run-in, drift, μ with
/// its 95 % half-width, flags and the planned step it matched with the label's evidence;
/// below the table, what a segment's own signal says against its cut.
fn segments_table(f: &FileReport) -> String {
    let mut t = Table::new(&[
        "seg",
        "start [s]",
        "end [s]",
        "F_N [N]",
        "speed",
        "v [m/min]",
        "steady [s]",
        "run-in [s]",
        "drift [1/h]",
        "COF ±95%",
        "flags",
        "plan",
    ]);
    for g in &f.segments {
        t.row(vec![
            g.index.to_string(),
            format!("{:.3}", g.start_s),
            format!("{:.3}", g.end_s),
            format!("{:.1}", g.normal_force_n),
            g.spindle_rpm.map_or("-".into(), |r| format!("{r:.1} rpm")),
            g.sliding_velocity_m_per_min
                .map_or("-".into(), |v| format!("{v:.1}")),
            match (g.steady_start_s, g.steady_end_s) {
                (Some(a), Some(b)) => format!("{a:.3}-{b:.3}"),
                _ => "-".into(),
            },
            g.run_in_s.map_or("-".into(), |r| format!("{r:.1}")),
            g.drift_per_hour.map_or("-".into(), |d| format!("{d:+.4}")),
            match (g.cof, g.cof_ci95) {
                (Some(c), Some(h)) => format!("{c:.4} ±{h:.4}"),
                (Some(c), None) => format!("{c:.4}"),
                _ => "-".into(),
            },
            match (&g.problem, g.boundary_uncertainty_s) {
                (Some(p), _) => p.clone(),
                (None, Some(u)) => format!("{} (boundary ±{u:.3} s)", g.flags.join(";")),
                (None, None) => g.flags.join(";"),
            },
            g.matched.map_or("-".into(), |(p, k)| {
                format!(
                    "pin {p} step {k}{}",
                    g.label_evidence
                        .as_deref()
                        .map_or(String::new(), |e| format!(" ({e})"))
                )
            }),
        ]);
    }
    let mut s = t.render();
    for g in &f.segments {
        if let Some(c) = &g.contradiction {
            let _ = writeln!(s, "   segment {}: {c}", g.index);
        }
    }
    s
}

/// How segments were matched to the plan, with what is missing, extra or reordered.
pub fn matching_text(m: &MatchReport) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "matching to the plan: {}", m.method);
    for (what, list) in [
        ("missing", &m.missing),
        ("extra", &m.extra),
        ("merged", &m.merged),
        ("reordered", &m.reordered),
    ] {
        for item in list {
            let _ = writeln!(s, "   {what}: {item}");
        }
    }
    if m.labels_by_order > 0 {
        let _ = writeln!(
            s,
            "   label-by-order: {} row(s) placed on their step by the order of the segments alone (no step column, measured speed, distinct load or plan timing confirms them)",
            m.labels_by_order
        );
    }
    for item in &m.ambiguous {
        let _ = writeln!(s, "   ambiguous: {item}");
    }
    s
}

/// `--inspect` lines of a file's reciprocating segments: strokes, cycles, μ per direction.
pub fn reciprocating_lines(f: &FileReport) -> String {
    let mut s = String::new();
    for g in &f.segments {
        let Some(r) = &g.reciprocating else { continue };
        let (a, b) = r.steady_cycles;
        let _ = writeln!(
            s,
            "   segment {}: reciprocating, {} strokes from the {}, {} cycles{}{}; steady cycles {}-{} ({:.3}-{:.3} s{}): μ forward {:.4}, backward {:.4}, mean {:.4} (std {:.4} over cycles){}",
            g.index,
            r.strokes,
            r.source.describe(),
            r.cycles.len(),
            r.stroke_length_m.map_or(String::new(), |l| format!(", stroke {:.3} mm", l * 1e3)),
            if r.frequency_hz.is_finite() { format!(", {:.2} Hz", r.frequency_hz) } else { String::new() },
            a + 1,
            b,
            r.start_s,
            r.end_s,
            r.run_in_cycles.map_or(String::new(), |k| format!(", run-in {k} cycles")),
            r.mu_forward,
            r.mu_backward,
            r.mu_mean,
            r.mu_std,
            if r.unsigned { "; friction channel unsigned: μ = |F_t|/F_N" } else { "" }
        );
    }
    s
}

/// One line on an identification, and its error against a ground truth.
pub fn identify_footer(s: &IdentifySummary) -> String {
    let mut text = String::new();
    let _ = writeln!(
        text,
        "identify: {} plateaus ({} non-stationary), pressure convention {}, dataset {}",
        s.plateaus, s.non_stationary, s.pressure_convention, s.dataset
    );
    // values outside their usual range (greybox_core::physics), with the likely unit mistake
    for f in &s.identification.files {
        for u in &f.unusual {
            let _ = writeln!(text, "  unusual: {}: {u}", f.source);
        }
    }
    if let Some(c) = &s.cycles {
        let _ = writeln!(
            text,
            "  reciprocating: per-cycle μ (forward, backward, mean) in {c}"
        );
    }
    if let Some(t) = &s.truth {
        let _ = writeln!(text,
            "  against the ground truth: max |COF - COF_true| = {:.5}, mean = {:.5} over {} plateaus",
            t.max_abs_error, t.mean_abs_error, t.plateaus
        );
    }
    text
}
