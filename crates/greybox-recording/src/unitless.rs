//! A friction-force column that states no unit: used when the file makes its unit
//! unambiguous, or named as unused with the reason — never a note that the file has no
//! friction-force column when it has one.
//!
//! A column found by a usual friction-force name (`Friction Force`, `Fx`) without a unit in
//! its header, the map or a rig profile is read in the unit of the normal-force column (the
//! two channels of one load cell or one program's export share it). Where the file also
//! holds the rig's own μ, that reading must agree with it: F_t/F_N within
//! [`super::COF_DISAGREEMENT_FRACTION`] of the rig's μ (median over the loaded samples)
//! confirms the unit; a disagreement leaves the column unused (named, with both values) and
//! F_t = μ·F_N from the rig's μ. Without the rig's μ the assumed unit is a warning of the
//! summary, with the mapping that states another; the campaign's μ range check
//! (`greybox_tribo::campaign::check_levels`) then catches a unit off by a factor of 1000.

use super::assign::looks_like_cof;
use super::channel_map::ChannelMap;
use super::roles::{check_unit, ChannelSpec, Role};
use super::types::ReadReport;
use crate::table::{ColumnData, Table};
use greybox_core::stats::median;

/// A friction-force column whose unit was taken from the normal force's.
#[derive(Debug, Clone)]
pub(super) struct Assumed {
    /// The column's header.
    pub(super) column: String,
    pub(super) unit: String,
    /// The normal-force column's header.
    pub(super) from: String,
}

/// `map` with the friction-force column's unit set to the normal force's, where the column
/// (found by its name, not mapped with a unit) states none and the normal force's unit is a
/// force unit; with what was assumed.
pub(super) fn assume_friction_unit(
    table: &Table,
    map: &ChannelMap,
    roles: &[(Role, usize, bool)],
) -> (ChannelMap, Option<Assumed>) {
    let find = |role: Role| roles.iter().find(|(r, _, _)| *r == role).map(|r| r.1);
    let (Some(t), Some(n)) = (find(Role::Tangential), find(Role::Normal)) else {
        return (map.clone(), None);
    };
    let (tc, nc) = (&table.columns[t], &table.columns[n]);
    let t_spec = map.spec(Role::Tangential);
    if tc.unit.is_some() || t_spec.as_ref().and_then(|s| s.unit.clone()).is_some() {
        return (map.clone(), None);
    }
    let Some(unit) = map
        .spec(Role::Normal)
        .and_then(|s| s.unit)
        .or_else(|| nc.unit.clone())
        .filter(|u| check_unit(Role::Tangential, u).is_ok())
    else {
        return (map.clone(), None);
    };
    let mut out = map.clone();
    out.set_spec(
        Role::Tangential,
        Some(ChannelSpec {
            name: tc.name.clone(),
            unit: Some(unit.clone()),
            scale: t_spec.map_or(1.0, |s| s.scale),
        }),
    );
    let assumed = Assumed {
        column: tc.header.clone(),
        unit,
        from: nc.header.clone(),
    };
    (out, Some(assumed))
}

/// The friction force to use, given an assumed unit (see the module documentation): the
/// column as read, or, where the rig's μ contradicts it, none (then F_t = μ·F_N); the notes
/// and warnings say which and why.
pub(super) fn settle_assumed(
    normal: &[f64],
    ft: Vec<f64>,
    cof: Option<&[f64]>,
    assumed: &Assumed,
    report: &mut ReadReport,
) -> Option<Vec<f64>> {
    let Assumed { column, unit, from } = assumed;
    let Some(mu) = cof else {
        report.warnings.push(format!(
            "column '{column}' (the friction force) states no unit: read in {unit}, the unit of the normal force '{from}'; if it differs, state it with `map` 'tangential={column}:UNIT'"
        ));
        return Some(ft);
    };
    let (line, far) = cof_disagreement(normal, &ft, mu);
    if far {
        report.warnings.push(format!(
            "column '{column}' (the friction force) states no unit, and read in {unit} (the normal force's) its F_t/F_N disagrees with the rig's own μ: not used, F_t = μ·F_N from the rig's μ ({line}); state its unit with `map` 'tangential={column}:UNIT' to use it"
        ));
        return None;
    }
    report.notes.push(format!(
        "column '{column}' (the friction force) states no unit: read in {unit}, the normal force's, which the rig's own μ confirms ({line})"
    ));
    Some(ft)
}

/// The file's numeric columns no role took that are no friction coefficient (what a
/// friction force could have been), for the note that F_t comes from the rig's μ.
pub(super) fn unused_columns(table: &Table, roles: &[(Role, usize, bool)]) -> Vec<String> {
    table
        .columns
        .iter()
        .enumerate()
        .filter(|(i, c)| {
            !roles.iter().any(|r| r.1 == *i)
                && matches!(c.data, ColumnData::Numbers(_))
                && !looks_like_cof(c)
        })
        .map(|(_, c)| format!("'{}'", c.header))
        .collect()
}

/// A rig's own μ further than this fraction of itself from F_t/F_N (median over the loaded
/// samples) is a line of the summary: the forces' units, a channel or the rig's own
/// computation are wrong, and only one of them was used.
pub const COF_DISAGREEMENT_FRACTION: f64 = 0.1;

/// How far the rig's own μ lies from F_t/F_N (both taken as magnitudes, loaded samples only),
/// and whether that is more than [`COF_DISAGREEMENT_FRACTION`] of the rig's μ.
pub(super) fn cof_disagreement(normal: &[f64], ft: &[f64], mu: &[f64]) -> (String, bool) {
    let f_ref = median(normal).abs();
    let diffs: Vec<f64> = normal
        .iter()
        .zip(ft)
        .zip(mu)
        .filter(|((f, _), m)| f.abs() > 0.2 * f_ref && m.is_finite())
        .map(|((f, t), m)| (t / f).abs() - m.abs())
        .collect();
    if diffs.is_empty() {
        return (
            "the rig's own μ (cof) could not be compared with F_t/F_N: no loaded samples".into(),
            false,
        );
    }
    let med = median(&diffs);
    let worst = diffs.iter().fold(0.0f64, |w, d| w.max(d.abs()));
    let own: Vec<f64> = mu
        .iter()
        .filter(|m| m.is_finite())
        .map(|m| m.abs())
        .collect();
    let own = median(&own);
    let far = med.abs() > COF_DISAGREEMENT_FRACTION * own;
    let share = if own > 0.0 {
        format!(
            " ({:.0} % of the rig's μ {own:.4})",
            100.0 * med.abs() / own
        )
    } else {
        String::new()
    };
    (
        format!(
            "μ from the forces; the rig's own μ (cof) differs from F_t/F_N by {med:+.4} (median){share} and at most {worst:.4} over {} loaded samples",
            diffs.len()
        ),
        far,
    )
}
