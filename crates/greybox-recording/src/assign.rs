//! Roles assigned to a table's columns: the explicit mapping first, then the usual names, with the
//! optional roles a unitless column cannot fill dropped.

use super::channel_map::map_flag;
use super::channel_map::ChannelMap;
use super::roles::{example_unit, Role, ROLE_ALIASES};
use crate::table::{column_matches, Column, Table};
use greybox_core::{Error, Result};

/// Which column each role takes, and how it was found.
pub(super) fn assign_roles(table: &Table, map: &ChannelMap) -> Result<Vec<(Role, usize, bool)>> {
    let pos = || table.header_pos();
    let mut taken: Vec<(Role, usize, bool)> = Vec::new();
    // explicit mappings first, so that automatic ones never steal their columns
    for &role in Role::ALL {
        if let Some(spec) = map.spec(role) {
            let idx = first_match(table, &spec.name).ok_or_else(|| {
                let has = match column_number(&spec.name) {
                    Some(_) => format!("the file's columns are {}", positions_list(table)),
                    None => format!("the header has: {}", table.header_list()),
                };
                Error::input(
                    pos().field(&spec.name),
                    format!(
                        "missing column '{}' (mapped as {}); {has}",
                        spec.name,
                        role.name(),
                    ),
                )
            })?;
            if let Some((other, _, _)) = taken.iter().find(|(_, i, _)| *i == idx) {
                return Err(Error::input(
                    pos().field(&table.columns[idx].header),
                    format!(
                        "column '{}' is mapped to two roles, {} and {}: each role needs its own column",
                        table.columns[idx].header,
                        other.name(),
                        role.name()
                    ),
                ));
            }
            taken.push((role, idx, true));
        }
    }
    if map.auto {
        for (role, aliases) in ROLE_ALIASES {
            if taken.iter().any(|(r, _, _)| *r == role)
                || map.ignore.iter().any(|r| r == role.name())
            {
                continue;
            }
            // a friction coefficient is never a force, whatever its name (`Friction (µ)`)
            let fits = |c: &Column| !(is_force(role) && looks_like_cof(c));
            let found = aliases.iter().find_map(|a| {
                (0..table.columns.len())
                    .find(|&i| column_matches(&table.columns[i], a) && fits(&table.columns[i]))
            });
            if let Some(idx) = found {
                match taken.iter().find(|(_, i, _)| *i == idx) {
                    // the role's usual column went to another role by an explicit mapping
                    Some((other, _, true)) if matches!(role, Role::Normal | Role::Tangential) => {
                        return Err(Error::input(
                            pos().field(&table.columns[idx].header),
                            format!(
                                "column '{}' is mapped as {} but is the file's {} column: one column cannot be two roles; map {} to its own column",
                                table.columns[idx].header,
                                other.name(),
                                role.name(),
                                role.name()
                            ),
                        ));
                    }
                    Some(_) => {}
                    None => taken.push((role, idx, false)),
                }
            }
        }
    }
    Ok(taken)
}

/// The first column matching `wanted` (the reader names a repeated header's later columns
/// `NAME #2`, … and notes it, so the first is the one that answers to the name); `#K` is the
/// column at 1-based position K in the file.
pub(super) fn first_match(table: &Table, wanted: &str) -> Option<usize> {
    match column_number(wanted) {
        Some(k) => table.at_position(k),
        None => (0..table.columns.len()).find(|&i| column_matches(&table.columns[i], wanted)),
    }
}

/// `#K` in a mapping (`--map normal=#3:N`): column K of the file, counted from 1.
pub fn column_number(wanted: &str) -> Option<usize> {
    let k = wanted
        .trim()
        .strip_prefix('#')?
        .trim()
        .parse::<usize>()
        .ok()?;
    (k > 0).then_some(k)
}

/// Whether a column's name or unit says it holds a friction coefficient (`COF`, `µ`, `mu`,
/// `Friction coefficient`, `Reibwert`, a unit `-` or `µ`): such a column is never taken or
/// suggested as a force.
pub fn looks_like_cof(col: &Column) -> bool {
    let name = crate::table::normalise_name(&col.header);
    let says = name.split(|c: char| !c.is_alphanumeric()).any(|w| {
        matches!(
            w,
            "cof"
                | "mu"
                | "µ"
                | "μ"
                | "coefficient"
                | "coeff"
                | "coef"
                | "reibwert"
                | "reibungszahl"
                | "reibungskoeffizient"
        )
    });
    let unit = col
        .unit
        .as_deref()
        .is_some_and(|u| matches!(u.trim(), "-" | "µ" | "μ" | "mu" | "()" | "[-]" | "(-)"));
    says || unit
}

pub(super) fn is_force(role: Role) -> bool {
    matches!(role, Role::Normal | Role::Tangential | Role::Radial)
}

/// Optional roles found by their usual name (not mapped) in a column that states no unit are
/// left out with a note, not an error: the identification does not need them.
pub(super) fn drop_unitless_optional(
    table: &Table,
    map: &ChannelMap,
    roles: &mut Vec<(Role, usize, bool)>,
    notes: &mut Vec<String>,
) {
    roles.retain(|(role, idx, mapped)| {
        let optional = matches!(
            role,
            Role::Radial | Role::Speed | Role::Radius | Role::Position
        );
        let col = &table.columns[*idx];
        let unitless = map.spec(*role).and_then(|s| s.unit).is_none() && col.unit.is_none();
        if optional && !mapped && unitless {
            notes.push(format!(
                "column '{}' looks like the {} but states no unit: not used ({} uses it)",
                col.header,
                role.name(),
                map_flag(*role, &col.name, example_unit(*role))
            ));
            return false;
        }
        true
    });
}

/// The file's column positions for messages: `#1 to #3`, or `#1, #2, #5` where columns
/// without values were left out.
pub(super) fn positions_list(table: &Table) -> String {
    let p: Vec<usize> = (0..table.columns.len())
        .map(|k| table.position(k))
        .collect();
    match (p.first(), p.last()) {
        (Some(a), Some(b)) if b - a + 1 == p.len() && p.len() > 2 => format!("#{a} to #{b}"),
        _ => p
            .iter()
            .map(|k| format!("#{k}"))
            .collect::<Vec<_>>()
            .join(", "),
    }
}
