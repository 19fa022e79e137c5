//! The suite's outputs: `results.csv` (one row per cut), `summary.json`, `validation.md`
//! (the tables: per material, tool and friction model, then per condition) and
//! `forces.svg`.

use super::{distinct, Outcome, Role, ToolModel, Validation};
use anyhow::Result;
use std::path::{Path, PathBuf};

/// The columns of `results.csv`, units in the names.
const COLUMNS: [&str; 36] = [
    "id",
    "material",
    "tool",
    "friction",
    "role",
    "mu",
    "cutting_speed_m_per_min",
    "uncut_chip_thickness_mm",
    "measured_cutting_force_N_per_mm",
    "simulated_cutting_force_N_per_mm",
    "simulated_cutting_force_ci95_N_per_mm",
    "cutting_force_error",
    "measured_feed_force_N_per_mm",
    "simulated_feed_force_N_per_mm",
    "simulated_feed_force_ci95_N_per_mm",
    "feed_force_error",
    "measured_chip_ratio",
    "simulated_chip_ratio",
    "simulated_chip_ratio_ci95",
    "chip_ratio_error",
    "simulated_contact_length_mm",
    "mean_mu_applied",
    "pressure_min_MPa",
    "pressure_max_MPa",
    "sliding_velocity_min_m_per_min",
    "sliding_velocity_max_m_per_min",
    "peak_temperature_C",
    "steady",
    "steady_from_mm",
    "steady_length_mm",
    "sure",
    "short_stretch",
    "simulated_cut_length_mm",
    "wall_s",
    "measured_contact_length_mm",
    "simulated_extent_ratio",
];

fn opt(v: Option<f64>, d: usize) -> String {
    v.map_or(String::new(), |x| format!("{x:.d$}"))
}

/// One `results.csv` record of an outcome, in the order of [`COLUMNS`].
fn record(o: &Outcome) -> Vec<String> {
    let l = &o.local;
    let end = |r: Option<[f64; 2]>, k: usize| opt(r.map(|r| r[k]), 1);
    vec![
        o.id.clone(),
        o.material.clone(),
        o.tool.name().to_string(),
        o.friction.clone(),
        o.role.to_string(),
        opt(o.mu, 4),
        format!("{}", o.cutting_speed_m_per_min),
        format!("{:.3}", o.uncut_chip_thickness_mm),
        format!("{:.2}", o.measured_cutting_force_n_per_mm),
        format!("{:.2}", o.simulated_cutting_force_n_per_mm),
        opt(o.simulated_ci95[0], 2),
        format!("{:.4}", o.cutting_force_error),
        format!("{:.2}", o.measured_feed_force_n_per_mm),
        format!("{:.2}", o.simulated_feed_force_n_per_mm),
        opt(o.simulated_ci95[1], 2),
        format!("{:.4}", o.feed_force_error),
        opt(o.measured_chip_ratio, 3),
        opt(o.simulated_chip_ratio, 3),
        opt(o.simulated_ci95[2], 3),
        opt(o.chip_ratio_error, 4),
        opt(o.simulated_contact_length_mm, 3),
        opt(l.mean_mu, 4),
        end(l.pressure_mpa, 0),
        end(l.pressure_mpa, 1),
        end(l.sliding_velocity_m_per_min, 0),
        end(l.sliding_velocity_m_per_min, 1),
        format!("{:.1}", o.max_temperature_c),
        o.steady.to_string(),
        opt(o.steady_from_mm, 3),
        opt(o.steady_length_mm, 3),
        o.sure.to_string(),
        o.short_stretch.to_string(),
        format!("{:.3}", o.simulated_cut_length_mm),
        format!("{:.1}", o.wall_s),
        opt(o.measured_contact_length_mm, 3),
        opt(o.simulated_extent_ratio, 3),
    ]
}

/// Writes `results.csv`, `summary.json`, `validation.md` (tables) and the plot
/// `forces.svg` (simulated against measured forces) into the existing directory `out`.
pub fn write_outputs(v: &Validation, out: &Path) -> Result<Vec<PathBuf>> {
    use greybox_core::atomic::{write_atomic, write_string_atomic};
    let results = out.join("results.csv");
    // names given in a suite file (materials, friction models) are quoted where they hold a
    // separator, a quote or a line break
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record(greybox_core::escape::csv_cells(COLUMNS))?;
    for o in &v.outcomes {
        w.write_record(greybox_core::escape::csv_cells(record(o)))?;
    }
    let bytes = w
        .into_inner()
        .map_err(|e| anyhow::anyhow!("results.csv: {e}"))?;
    write_atomic(&results, |f| f.write_all(&bytes))?;
    let summary = out.join("summary.json");
    write_string_atomic(&summary, &serde_json::to_string_pretty(v)?)?;
    let md = out.join("validation.md");
    write_string_atomic(&md, &markdown(v))?;
    let plot = out.join("forces.svg");
    write_string_atomic(&plot, &force_plot(v))?;
    Ok(vec![results, summary, md, plot])
}

/// The goal column of a summary row: the verdict of all goals, then each goal's check.
fn goal_cell(e: &super::ErrorSummary) -> String {
    match (e.role, e.goal) {
        (Role::HeldOut, Some(v)) => format!(
            "{v}: {}",
            e.goals
                .iter()
                .map(super::goals::describe)
                .collect::<Vec<_>>()
                .join("; ")
        ),
        (Role::HeldOut, None) => "none set".to_string(),
        _ => "(calibration)".to_string(),
    }
}

/// A table cell of text from a suite file: markup, `|` and line breaks escaped
/// ([`greybox_core::escape::markdown_text`]).
fn cell(s: &str) -> String {
    greybox_core::escape::markdown_text(s)
}

fn pct(e: f64) -> String {
    format!("{:+.1} %", 100.0 * e)
}

/// Tables of the errors (summary per material, tool and friction model, then per
/// condition).
pub fn markdown(v: &Validation) -> String {
    let mut s = format!("Intervals are 95 %: of a mean |error|, from the cuts' own scatter; of a fitted factor (μ\\* for Coulomb), from the calibration cuts' scatter; of a goal's check, from the cuts' and the measurements' scatter together (met: the whole interval within the goal; not met: all of it beyond; otherwise the evidence cannot tell).\n\n| material | tool | friction | parameters | conditions | F'c mean abs error (mean) | F'f mean abs error (mean) | chip ratio mean abs error (mean) | μ applied (mean) | goal ({}) | cost: cuts, cut time |\n|---|---|---|---|---|---|---|---|---|---|---|\n", v.goals.describe());
    for e in &v.summaries {
        let range = e
            .factor_ci95
            .map_or(String::new(), |[a, b]| format!(" [{a:.3}, {b:.3}]"));
        let params = match e.mu {
            Some(mu) => format!("μ* = {mu:.3}{range}"),
            None if e.parameters.is_empty() => "as given".to_string(),
            None => e
                .parameters
                .iter()
                .map(|(f, x)| match f.as_str() {
                    "factor" => format!("factor = {x:.4}{range}"),
                    _ => format!("{} = {x:.4}", cell(f)),
                })
                .collect::<Vec<_>>()
                .join(", "),
        };
        let pm = |ci: Option<f64>| ci.map_or(String::new(), |h| format!(" ± {:.1}", 100.0 * h));
        s += &format!(
            "| {} | {} | {} | {} | {} {}{} | {:.1}{} % ({}) | {:.1}{} % ({}) | {} | {} | {} | {} cuts, {:.0} s |\n",
            cell(&e.material),
            e.tool.name(),
            cell(&e.friction),
            params,
            e.conditions,
            e.role,
            imputed_note(e.imputed_errors),
            100.0 * e.cutting_force_mean_abs,
            pm(e.cutting_force_mean_abs_ci95),
            pct(e.cutting_force_mean),
            100.0 * e.feed_force_mean_abs,
            pm(e.feed_force_mean_abs_ci95),
            pct(e.feed_force_mean),
            e.chip_ratio_mean_abs
                .zip(e.chip_ratio_mean)
                .map_or("—".into(), |(a, m)| format!("{:.1}{} % ({})", 100.0 * a, pm(e.chip_ratio_mean_abs_ci95), pct(m))),
            opt(e.mean_mu_applied, 3),
            goal_cell(e),
            e.cuts,
            e.cut_seconds
        );
    }
    let steady = v.outcomes.iter().filter(|o| o.steady).count();
    let sure = v.outcomes.iter().filter(|o| o.sure).count();
    let length: f64 = v.outcomes.iter().map(|o| o.simulated_cut_length_mm).sum();
    s += &format!(
        "\n{steady} of {} cuts found a steady stretch and {sure} met their interval targets; {:.3} mm of cut simulated on average.",
        v.outcomes.len(),
        length / v.outcomes.len().max(1) as f64
    );
    if let Some(l) = super::compare::feed_resolution_length_mm(&v.outcomes) {
        s += &format!(
            " Two cuts of one condition would tell F'f values {:.0} % apart at about {l:.1} mm of cut each (the median cut's F'f scatter).",
            100.0 * super::compare::RESOLVE
        );
    }
    s += "\n";
    s += &comparisons(v);
    s += &speed_trends(v);
    s += &where_models_differ(v);
    s += "\n| id | material | tool | friction | role | v_c m/min | h mm | F'c meas / sim N/mm | F'f meas / sim N/mm | h_c/h meas / sim | μ applied | p MPa (rake) | v_slide m/min (rake) | l_c mm | T_peak °C |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    let range = |r: Option<[f64; 2]>| r.map_or("—".into(), |[a, b]| format!("{a:.0}–{b:.0}"));
    for o in &v.outcomes {
        s += &format!(
            "| {} | {} | {} | {} | {} | {} | {:.3} | {:.1} / {:.1}{} ({}) | {:.1} / {:.1}{} ({}) | {} | {} | {} | {} | {} | {:.0} |\n",
            cell(&o.id),
            cell(&o.material),
            o.tool.name(),
            cell(&o.friction),
            o.role,
            o.cutting_speed_m_per_min,
            o.uncut_chip_thickness_mm,
            o.measured_cutting_force_n_per_mm,
            o.simulated_cutting_force_n_per_mm,
            plus_minus(o.simulated_ci95[0], 1),
            pct(o.cutting_force_error),
            o.measured_feed_force_n_per_mm,
            o.simulated_feed_force_n_per_mm,
            plus_minus(o.simulated_ci95[1], 1),
            pct(o.feed_force_error),
            o.measured_chip_ratio
                .zip(o.simulated_chip_ratio)
                .map_or("—".into(), |(m, s)| format!("{m:.2} / {s:.2}{}", plus_minus(o.simulated_ci95[2], 2))),
            opt(o.local.mean_mu, 3),
            range(o.local.pressure_mpa),
            range(o.local.sliding_velocity_m_per_min),
            opt(o.simulated_contact_length_mm, 3),
            o.max_temperature_c
        );
    }
    s
}

/// " (F'f of 2 cuts imputed)": the cuts whose scatter the intervals took as the median of the
/// others' (F'c, F'f, chip ratio), or nothing.
fn imputed_note(n: [usize; 3]) -> String {
    let parts: Vec<String> = ["F'c", "F'f", "chip ratio"]
        .iter()
        .zip(n)
        .filter(|(_, k)| *k > 0)
        .map(|(name, k)| format!("{name} of {k}"))
        .collect();
    if parts.is_empty() {
        String::new()
    } else {
        format!(" (scatter imputed: {})", parts.join(", "))
    }
}

/// " ± h" with `d` decimals, or nothing without an interval.
fn plus_minus(ci: Option<f64>, d: usize) -> String {
    ci.map_or(String::new(), |h| format!(" ± {h:.d$}"))
}

/// The friction models against the baseline, paired on the held-out conditions
/// ([`super::compare`]).
fn comparisons(v: &Validation) -> String {
    if v.comparisons.is_empty() {
        return String::new();
    }
    let mut s = String::from("\nFriction models against the first one, paired on the held-out conditions: the mean of |error| − |baseline's error| (negative: closer to the measurements) with its 95 % interval from the cuts' scatter (the verdict adds the measured values' own), the paired interval across the conditions, the conditions where the model is closer, and the cut length at which the scatter's interval would be ±3 points.\n\n| material | tool | friction | against | measure | difference | across conditions | closer in | verdict | cut length for ±3 points |\n|---|---|---|---|---|---|---|---|---|---|\n");
    for c in &v.comparisons {
        let rows = [
            ("F'c", Some(&c.cutting_force)),
            ("F'f", Some(&c.feed_force)),
            ("chip ratio", c.chip_ratio.as_ref()),
        ];
        for (name, d) in rows {
            let Some(d) = d else { continue };
            s += &format!(
                "| {} | {} | {} | {} | {name} | {:+.1}{} points | {} | {} of {} | {} | {} |\n",
                cell(&c.material),
                c.tool.name(),
                cell(&c.friction),
                cell(&c.baseline),
                100.0 * d.mean,
                d.ci95
                    .map_or(String::new(), |h| format!(" ± {:.1}", 100.0 * h)),
                d.across_conditions_ci95
                    .map_or("—".into(), |h| format!("± {:.1}", 100.0 * h)),
                d.conditions_better,
                d.conditions,
                d.verdict,
                d.length_to_resolve_mm
                    .map_or("—".into(), |l| format!("{l:.1} mm")),
            );
        }
    }
    s
}

/// How each model's signed errors move with the cutting speed, per role ([`super::trend`]).
fn speed_trends(v: &Validation) -> String {
    let rows: Vec<String> = v
        .summaries
        .iter()
        .filter(|e| !e.speed_trends.is_empty())
        .map(|e| {
            let cells: Vec<String> = super::goals::MEASURES
                .iter()
                .map(|m| {
                    e.speed_trends
                        .iter()
                        .find(|t| t.measure == *m)
                        .map_or("—".to_string(), super::trend::describe)
                })
                .collect();
            format!(
                "| {} | {} | {} | {} {} | {} |\n",
                cell(&e.material),
                e.tool.name(),
                cell(&e.friction),
                e.conditions,
                e.role,
                cells.join(" | ")
            )
        })
        .collect();
    if rows.is_empty() {
        return String::new();
    }
    format!("\nHow the signed errors move with the cutting speed: the least-squares line of each error against ln v_c, as the change per doubling of v_c in points with its 95 % interval from the scatter about the line (rises or falls: the whole interval on one side of zero; otherwise no trend resolved), and the line's error at the slowest and the fastest speed. Zero: the simulated value follows the measured one's speed dependence.\n\n| material | tool | friction | conditions | F'c per doubling of v_c | F'f per doubling | chip ratio per doubling |\n|---|---|---|---|---|---|---|\n{}", rows.concat())
}

/// The held-out errors grouped by cutting speed and by uncut chip thickness, per material
/// and tool model, one column per friction model (mean signed F'c / F'f error of the
/// group): where the models differ.
fn where_models_differ(v: &Validation) -> String {
    let mut s = String::new();
    for (material, tool, rows, models) in super::held_out_groups(&v.outcomes) {
        type Key = fn(&Outcome) -> f64;
        let keys: [(&str, Key); 2] = [
            ("v_c m/min", |o| o.cutting_speed_m_per_min),
            ("h mm", |o| o.uncut_chip_thickness_mm),
        ];
        for (name, key) in keys {
            s += &format!(
                "\n| {}, {} tool: held out by {name} | {} |\n|---|{}\n",
                cell(material),
                tool.name(),
                models
                    .iter()
                    .map(|m| format!("{} F'c / F'f mean error", cell(m)))
                    .collect::<Vec<_>>()
                    .join(" | "),
                "---|".repeat(models.len())
            );
            let mut values: Vec<f64> = rows.iter().map(|o| key(o)).collect();
            values.sort_by(f64::total_cmp);
            values.dedup();
            for x in values {
                let cells: Vec<String> = models
                    .iter()
                    .map(|m| {
                        let of: Vec<&&Outcome> = rows
                            .iter()
                            .filter(|o| o.friction == *m && key(o) == x)
                            .collect();
                        let n = of.len().max(1) as f64;
                        let mean =
                            |f: fn(&Outcome) -> f64| of.iter().map(|o| f(o)).sum::<f64>() / n;
                        format!(
                            "{} / {} ({})",
                            pct(mean(|o| o.cutting_force_error)),
                            pct(mean(|o| o.feed_force_error)),
                            of.len()
                        )
                    })
                    .collect();
                // a value computed in m and turned into mm (0.060000000000000005) as written
                let shown = (x * 1e9).round() / 1e9;
                s += &format!("| {shown} | {} |\n", cells.join(" | "));
            }
        }
    }
    s
}

/// Simulated against measured F'c and F'f, held-out conditions, one colour per material
/// entry, tool model and force.
fn force_plot(v: &Validation) -> String {
    let labels = distinct(
        v.outcomes
            .iter()
            .map(|o| (o.material.as_str(), o.friction.as_str())),
    );
    type Pair = fn(&Outcome) -> (f64, f64);
    let forces: [(&str, Pair); 2] = [
        ("F'c", |o| {
            (
                o.measured_cutting_force_n_per_mm,
                o.simulated_cutting_force_n_per_mm,
            )
        }),
        ("F'f", |o| {
            (
                o.measured_feed_force_n_per_mm,
                o.simulated_feed_force_n_per_mm,
            )
        }),
    ];
    let mut data = Vec::new();
    for &(material, friction) in &labels {
        for tool in [ToolModel::Adiabatic, ToolModel::Thermal] {
            for (force, f) in forces {
                let (m, s): (Vec<f64>, Vec<f64>) = v
                    .outcomes
                    .iter()
                    .filter(|o| {
                        o.tool == tool
                            && o.role == Role::HeldOut
                            && o.material == material
                            && o.friction == friction
                    })
                    .map(f)
                    .unzip();
                if !m.is_empty() {
                    data.push((
                        format!("{force}, {material}, {} tool, {friction}", tool.name()),
                        m,
                        s,
                    ));
                }
            }
        }
    }
    const COLOURS: [&str; 8] = [
        "#1f77b4", "#aec7e8", "#d62728", "#ff9896", "#2ca02c", "#98df8a", "#9467bd", "#c5b0d5",
    ];
    let series: Vec<(&str, &str, &[f64], &[f64])> = data
        .iter()
        .zip(COLOURS.iter().cycle())
        .map(|((l, m, s), c)| (l.as_str(), *c, m.as_slice(), s.as_slice()))
        .collect();
    greybox_core::plot::predicted_vs_measured(
        "held-out conditions: simulated against measured force per width",
        "(N/mm)",
        &series,
    )
}
