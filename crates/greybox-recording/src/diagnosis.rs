//! Why a role found no column: what was looked for, what the file holds, and the flag that would
//! map it.

use super::assign::{assign_roles, is_force, looks_like_cof};
use super::channel_map::{map_flag, ChannelMap};
use super::roles::{example_unit, Role};
use crate::table::{Column, ColumnData, Table};
use greybox_core::{Error, SourcePos};

/// One role a file leaves unresolved: why, the `--map` flag that resolves it, and other ways
/// (`or …`) shown beside it.
pub(super) struct Unresolved {
    role: Role,
    why: String,
    flag: String,
    or: Option<String>,
}

/// Every role the file and the map leave unresolved, all at once: missing forces (a friction
/// coefficient stands in for the friction force), a missing time without a sample rate, and
/// mapped or found columns whose unit nobody states.
pub(super) fn unresolved(
    table: &Table,
    map: &ChannelMap,
    taken: &[(Role, usize, bool)],
) -> Vec<Unresolved> {
    let has = |r: Role| taken.iter().any(|(t, _, _)| *t == r);
    let free: Vec<&Column> = table
        .columns
        .iter()
        .enumerate()
        .filter(|(i, c)| {
            !taken.iter().any(|(_, t, _)| t == i) && matches!(c.data, ColumnData::Numbers(_))
        })
        .map(|(_, c)| c)
        .collect();
    // a friction coefficient is never offered as a force
    let candidates = |role: Role| {
        let shown: Vec<String> = free
            .iter()
            .filter(|c| !(is_force(role) && looks_like_cof(c)))
            .take(8)
            .map(|c| format!("'{}'", c.header))
            .collect();
        if shown.is_empty() {
            "no unassigned numeric column".to_string()
        } else {
            format!("candidates: {}", shown.join(", "))
        }
    };
    let name = if table.headerless { "#K" } else { "NAME" };
    let mut out = Vec::new();
    let missing = |role: Role, what: &str, unit: &str| Unresolved {
        role,
        why: format!("no {what} column by a usual name ({})", candidates(role)),
        flag: map_flag(role, name, unit),
        or: None,
    };
    if !has(Role::Normal) && map.constant_normal_n.is_none() {
        let mut u = missing(Role::Normal, "normal force", "N");
        u.or = Some("for a dead-weight rig, `constant_normal_force_N` VALUE".into());
        out.push(u);
    }
    if !has(Role::Tangential) && !has(Role::Cof) {
        let mut u = missing(
            Role::Tangential,
            "friction force (tangential) or friction coefficient (cof)",
            "N",
        );
        let cof = free
            .iter()
            .find(|c| looks_like_cof(c))
            .map_or(name, |c| &c.name);
        u.or = Some(map_flag(Role::Cof, cof, ""));
        out.push(u);
    }
    if !has(Role::Time) && map.sample_rate_hz.is_none() && table.sample_interval_s.is_none() {
        let mut u = missing(Role::Time, "time", "s");
        // a headerless log's one increasing column is most likely its time
        let rising: Vec<&&Column> = free.iter().filter(|c| increasing(&c.data)).collect();
        if let ([c], true) = (&rising[..], table.headerless) {
            u.flag = map_flag(Role::Time, &c.name, "s");
        }
        u.or = Some("`sample_rate_hz` HZ".into());
        out.push(u);
    }
    for (role, idx, _) in taken {
        if matches!(role, Role::Trigger | Role::Step | Role::Cof) {
            continue;
        }
        let col = &table.columns[*idx];
        let stated = map
            .spec(*role)
            .and_then(|s| s.unit)
            .or_else(|| col.unit.clone());
        if stated.is_none() {
            // a column that says it is a friction coefficient is offered as one, not in N
            let cof = is_force(*role) && looks_like_cof(col);
            out.push(Unresolved {
                role: *role,
                why: format!("column '{}' states no unit", col.header),
                flag: match cof {
                    true => map_flag(Role::Cof, &col.name, ""),
                    false => map_flag(*role, &col.name, example_unit(*role)),
                },
                or: None,
            });
        }
    }
    out.sort_by_key(|u| Role::ALL.iter().position(|r| *r == u.role));
    out
}

/// A line above the data that names channels the header taken leaves unresolved (a garbled
/// preamble or separator line sat between the header and the data): the sentence that
/// points to the one that leaves the fewest roles unresolved with `header_line` N; empty when
/// none does better than the header taken, or the user chose the header.
fn naming_line(table: &Table, map: &ChannelMap, unresolved_now: usize) -> String {
    if map.reader.header_line.is_some() {
        return String::new();
    }
    // the roles are found from names, units and the first values: a head of the table
    // suffices, whatever its size
    let head = table.head(1000);
    let left_unresolved = |names: &[String]| {
        let mut t = head.clone();
        t.name_columns(names).ok()?;
        let roles = assign_roles(&t, map).ok()?;
        Some(unresolved(&t, map, &roles).len())
    };
    table
        .header_alternatives
        .iter()
        .filter_map(|(line, names)| Some((left_unresolved(names)?, line, names)))
        .filter(|(left, _, _)| *left < unresolved_now)
        .min_by_key(|(left, _, _)| *left)
        .map_or(String::new(), |(_, line, names)| {
            format!(
                "line {line} names the columns ({}), not line {} that was taken as the header: if line {line} is the header, give `header_line` {line}. As read, ",
                names.join(", "),
                table.header_line
            )
        })
}

/// One error for everything unresolved, with each role's candidates and the flags to pass,
/// and the line that names the columns when it is not the one taken as the header.
pub(super) fn unresolved_error(table: &Table, map: &ChannelMap, problems: &[Unresolved]) -> Error {
    let lines: Vec<String> = problems
        .iter()
        .map(|u| {
            let or =
                u.or.as_ref()
                    .map_or(String::new(), |o| format!(" (or {o})"));
            format!("  {}: {} → {}{or}", u.role.name(), u.why, u.flag)
        })
        .collect();
    let all: Vec<&str> = problems.iter().map(|u| u.flag.as_str()).collect();
    if table.headerless {
        return Error::input(
            SourcePos::file(&table.source),
            format!(
                "{} channel(s) unresolved in a file without a header line; its columns, by number:\n{}\n{}\nmap them by number, e.g. {} (columns counted from 1), or name them in order with `columns` NAME,NAME,… (units in the names, e.g. `columns` t_s,Fn_N,Ft_N); without a time column give `sample_rate_hz` HZ",
                problems.len(),
                column_overview(table),
                lines.join("\n"),
                all.join(" ")
            ),
        );
    }
    Error::input(
        SourcePos::file(&table.source).line(table.header_line),
        format!(
            "{}{} channel(s) unresolved (the header has: {}):\n{}\npass them together: {} (or name the rig with `rig` NAME; `rig` list lists the profiles)",
            naming_line(table, map, problems.len()),
            problems.len(),
            table.header_list(),
            lines.join("\n"),
            all.join(" ")
        ),
    )
}

/// A column of at least two numbers, each above the one before (a time, most likely).
pub(super) fn increasing(data: &ColumnData) -> bool {
    matches!(data, ColumnData::Numbers(v) if v.len() > 1 && v.windows(2).all(|w| w[1] > w[0]))
}

/// Each column of a table by number with its first values and what they look like, e.g.
/// `  #1: 0, 0.01, 0.02, … (increasing: time?)`.
pub(super) fn column_overview(table: &Table) -> String {
    let lines: Vec<String> = table
        .columns
        .iter()
        .enumerate()
        .map(|(k, c)| {
            let label = match c.name == format!("#{}", table.position(k)) {
                true => c.name.clone(),
                false => format!("#{} '{}'", table.position(k), c.header),
            };
            let v = match &c.data {
                ColumnData::Numbers(v) => v,
                ColumnData::NotNumeric { line, text } => {
                    return format!("  {label}: not numbers ('{}' on line {line})", text.trim())
                }
            };
            let shown: Vec<String> = v.iter().take(4).map(|x| format!("{x}")).collect();
            let more = if v.len() > 4 { ", …" } else { "" };
            let looks = if increasing(&c.data) {
                " (increasing: time?)"
            } else if v.iter().all(|x| x.abs() <= 1.0) {
                " (all within ±1: friction coefficient?)"
            } else {
                ""
            };
            format!("  {label}: {}{more}{looks}", shown.join(", "))
        })
        .collect();
    lines.join("\n")
}
