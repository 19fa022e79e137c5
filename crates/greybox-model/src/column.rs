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

/// The contact quantity a feature measures, and how its unit relates to SI: what a friction
/// law maps from the contact state (pressure in Pa, sliding speed in m/s, temperature in K,
/// and the tribometer's normal force in N).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum FeatureQuantity {
    /// Contact pressure: SI value = feature value × `pa_per_unit`.
    Pressure { pa_per_unit: f64 },
    /// Sliding velocity: SI value = feature value × `m_s_per_unit`.
    Velocity { m_s_per_unit: f64 },
    /// Temperature: SI value (K) = feature value + `offset_k`.
    Temperature { offset_k: f64 },
    /// The tribometer's normal force: N = feature value × `n_per_unit` (mapped to pressure
    /// through the pin contact's Hertz relation).
    NormalForce { n_per_unit: f64 },
}

/// The unit suffixes a feature of a friction model may carry, with their units, as a
/// message lists them.
pub const FEATURE_SUFFIXES: &str = "pressure _Pa, _MPa, _GPa; sliding velocity _m_per_s, _m_per_min; temperature _K, _degC; normal force _N, _kN (e.g. normal_force_N, sliding_velocity_m_per_min, hertz_pressure_MPa, temperature_degC)";

impl FeatureQuantity {
    /// The quantity of a feature of unit `unit` (as [`unit_of`] names it), or `None` when no
    /// contact quantity has that unit (lengths, times, dimensionless or unknown suffixes).
    pub fn of_unit(unit: &str) -> Option<Self> {
        use greybox_core::units::{PA_PER_GPA, PA_PER_MPA, S_PER_MIN};
        Some(match unit {
            "Pa" => FeatureQuantity::Pressure { pa_per_unit: 1.0 },
            "MPa" => FeatureQuantity::Pressure {
                pa_per_unit: PA_PER_MPA,
            },
            "GPa" => FeatureQuantity::Pressure {
                pa_per_unit: PA_PER_GPA,
            },
            "m/s" => FeatureQuantity::Velocity { m_s_per_unit: 1.0 },
            "m/min" => FeatureQuantity::Velocity {
                m_s_per_unit: 1.0 / S_PER_MIN,
            },
            "K" => FeatureQuantity::Temperature { offset_k: 0.0 },
            "°C" => FeatureQuantity::Temperature { offset_k: 273.15 },
            "N" => FeatureQuantity::NormalForce { n_per_unit: 1.0 },
            "kN" => FeatureQuantity::NormalForce { n_per_unit: 1e3 },
            _ => return None,
        })
    }

    /// A feature value in SI (Pa, m/s, K, N).
    pub fn to_si(self, value: f64) -> f64 {
        match self {
            FeatureQuantity::Pressure { pa_per_unit } => value * pa_per_unit,
            FeatureQuantity::Velocity { m_s_per_unit } => value * m_s_per_unit,
            FeatureQuantity::Temperature { offset_k } => value + offset_k,
            FeatureQuantity::NormalForce { n_per_unit } => value * n_per_unit,
        }
    }

    /// The physics table's quantity ([`greybox_core::physics`]) a feature's SI values are
    /// checked against.
    pub fn physics(self) -> greybox_core::physics::Quantity {
        use greybox_core::physics::Quantity;
        match self {
            FeatureQuantity::Pressure { .. } => Quantity::ContactPressure,
            FeatureQuantity::Velocity { .. } => Quantity::SlidingVelocity,
            FeatureQuantity::Temperature { .. } => Quantity::Temperature,
            FeatureQuantity::NormalForce { .. } => Quantity::NormalForce,
        }
    }

    /// The quantity of a feature column, or an error naming the feature, its unit and the
    /// suffixes greybox maps to pressure, velocity, temperature and force.
    pub fn of_column(c: &Column) -> std::result::Result<Self, String> {
        Self::of_unit(&c.unit).ok_or_else(|| {
            let unit = if c.unit == "1" {
                "no unit suffix greybox knows".to_string()
            } else {
                format!("unit '{}', not a contact quantity", c.unit)
            };
            format!(
                "feature '{}' has {unit}: a friction model's features are mapped from the contact state by their unit suffix — {FEATURE_SUFFIXES}",
                c.name
            )
        })
    }
}

/// Check that `features` can be the inputs of a friction law μ(p, v[, T]): each maps to a
/// contact quantity, exactly one is a pressure or a normal force, exactly one a sliding
/// velocity, at most one a temperature. The error names the feature set and what is missing
/// or given twice, so that a model is refused where it is made (fit, import), not where it
/// is first used as a law.
///
/// ```
/// use greybox_model::column::{check_law_features, Column};
/// let cols = |n: &[&str]| n.iter().map(|n| Column::new(n)).collect::<Vec<_>>();
/// assert!(check_law_features(&cols(&["normal_force_N", "sliding_velocity_m_per_min"])).is_ok());
/// let e = check_law_features(&cols(&["normal_force_N", "hertz_pressure_MPa"])).unwrap_err();
/// assert!(e.contains("no sliding velocity") && e.contains("two of pressure"), "{e}");
/// ```
pub fn check_law_features(features: &[Column]) -> std::result::Result<(), String> {
    let quantities = features
        .iter()
        .map(FeatureQuantity::of_column)
        .collect::<std::result::Result<Vec<_>, _>>()?;
    let count = |pick: fn(&FeatureQuantity) -> bool| quantities.iter().filter(|q| pick(q)).count();
    let pressure = count(|q| {
        matches!(
            q,
            FeatureQuantity::Pressure { .. } | FeatureQuantity::NormalForce { .. }
        )
    });
    let velocity = count(|q| matches!(q, FeatureQuantity::Velocity { .. }));
    let temperature = count(|q| matches!(q, FeatureQuantity::Temperature { .. }));
    let mut wrong = Vec::new();
    match pressure {
        0 => wrong.push("no pressure or normal force (e.g. normal_force_N, hertz_pressure_MPa)".to_string()),
        1 => {}
        n => wrong.push(format!("{n} features that are each a pressure or a normal force (two of pressure/force describe one contact variable)")),
    }
    match velocity {
        0 => wrong.push("no sliding velocity (e.g. sliding_velocity_m_per_min)".to_string()),
        1 => {}
        n => wrong.push(format!("{n} sliding velocities")),
    }
    if temperature > 1 {
        wrong.push(format!("{temperature} temperatures"));
    }
    if wrong.is_empty() {
        return Ok(());
    }
    let names: Vec<&str> = features.iter().map(|f| f.name.as_str()).collect();
    Err(format!(
        "features [{}] cannot be a friction law μ(p, v[, T]): {}",
        names.join(", "),
        wrong.join("; ")
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn feature_units_map_or_are_named() {
        assert_eq!(
            FeatureQuantity::of_column(&Column::new("normal_force_kN")),
            Ok(FeatureQuantity::NormalForce { n_per_unit: 1e3 })
        );
        assert_eq!(
            FeatureQuantity::of_column(&Column::new("temperature_degC")),
            Ok(FeatureQuantity::Temperature { offset_k: 273.15 })
        );
        for bad in ["pressure", "contact_pressure_psi", "wear_um", "time_s"] {
            let e = FeatureQuantity::of_column(&Column::new(bad)).unwrap_err();
            assert!(e.contains(&format!("'{bad}'")) && e.contains("_MPa"), "{e}");
        }
    }
}
