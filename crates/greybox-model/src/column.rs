//! Column names with the unit their suffix names (`normal_force_N` → N), as model files
//! record their features and target.

use serde::{Deserialize, Serialize};

/// A column name and the unit its suffix names (`normal_force_N` → N).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct Column {
    pub name: String,
    pub unit: String,
}

impl Column {
    pub fn new(name: &str) -> Self {
        Column {
            name: name.to_string(),
            unit: unit_of(name).to_string(),
        }
    }
}

/// The unit named by a column's suffix; "1" (dimensionless) when none is recognised.
pub fn unit_of(name: &str) -> &'static str {
    const SUFFIXES: [(&str, &str); 12] = [
        ("_m_per_min", "m/min"),
        ("_m_per_s", "m/s"),
        ("_MPa", "MPa"),
        ("_GPa", "GPa"),
        ("_Pa", "Pa"),
        ("_kN", "kN"),
        ("_N", "N"),
        ("_K", "K"),
        ("_degC", "°C"),
        ("_um", "µm"),
        ("_mm", "mm"),
        ("_s", "s"),
    ];
    SUFFIXES
        .iter()
        .find(|(s, _)| name.ends_with(s))
        .map(|(_, u)| *u)
        .unwrap_or("1")
}
