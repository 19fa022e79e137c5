//! The numeric fields of a law spec by dotted path (`mu`, `b`, `factor`,
//! `inner.b`), as a law file names them: what a calibration sets when it fits
//! a law's parameters to measurements.

use crate::spec::LawSpec;
use greybox_core::{Error, Result};
use serde_json::Value;

/// A law spec whose numeric fields are read and replaced by their dotted paths.
#[derive(Debug, Clone)]
pub struct LawFields {
    value: Value,
}

impl LawFields {
    pub fn new(spec: &LawSpec) -> Result<Self> {
        let value = serde_json::to_value(spec)
            .map_err(|e| Error::invalid("law", format!("cannot represent the law: {e}")))?;
        Ok(LawFields { value })
    }

    /// The value of the numeric field at `path`.
    pub fn get(&self, path: &str) -> Result<f64> {
        let v = walk(&self.value, path)?;
        v.as_f64().ok_or_else(|| not_numeric(path, v))
    }

    /// The spec with each `(path, value)` set; every path must name a numeric field the law
    /// has (optional fields included once given), and the result must still be a valid law
    /// spec.
    pub fn with(&self, values: &[(String, f64)]) -> Result<LawSpec> {
        let mut v = self.value.clone();
        for (path, x) in values {
            let slot = walk_mut(&mut v, path)?;
            if !slot.is_number() {
                return Err(not_numeric(path, slot));
            }
            *slot = serde_json::Number::from_f64(*x)
                .map(Value::Number)
                .ok_or_else(|| {
                    Error::invalid(
                        "law",
                        format!("field '{path}': expected a finite number, got {x}"),
                    )
                })?;
        }
        serde_json::from_value(v).map_err(|e| Error::invalid("law", e.to_string()))
    }

    /// Every numeric field's dotted path, in the spec's order.
    pub fn numeric_paths(&self) -> Vec<String> {
        fn collect(v: &Value, prefix: &str, out: &mut Vec<String>) {
            if let Value::Object(m) = v {
                for (k, x) in m {
                    let p = if prefix.is_empty() {
                        k.clone()
                    } else {
                        format!("{prefix}.{k}")
                    };
                    match x {
                        Value::Number(_) => out.push(p),
                        Value::Object(_) => collect(x, &p, out),
                        _ => {}
                    }
                }
            }
        }
        let mut out = Vec::new();
        collect(&self.value, "", &mut out);
        out
    }

    fn unknown(&self, path: &str) -> Error {
        Error::invalid(
            "law",
            format!(
                "field '{path}': the law has no such numeric field (its numeric fields: {})",
                self.numeric_paths().join(", ")
            ),
        )
    }
}

fn not_numeric(path: &str, v: &Value) -> Error {
    Error::invalid(
        "law",
        format!("field '{path}': expected a numeric field, it holds {v}"),
    )
}

fn walk<'a>(root: &'a Value, path: &str) -> Result<&'a Value> {
    let mut v = root;
    for k in path.split('.') {
        v = v.get(k).ok_or_else(|| {
            LawFields {
                value: root.clone(),
            }
            .unknown(path)
        })?;
    }
    Ok(v)
}

fn walk_mut<'a>(root: &'a mut Value, path: &str) -> Result<&'a mut Value> {
    let known = LawFields {
        value: root.clone(),
    };
    let mut v = root;
    for k in path.split('.') {
        v = v.get_mut(k).ok_or_else(|| known.unknown(path))?;
    }
    Ok(v)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spec(json: &str) -> LawSpec {
        serde_json::from_str(json).unwrap()
    }

    #[test]
    fn sets_nested_numeric_fields_and_names_the_known_ones() {
        let s = spec(
            r#"{"law": "scaled", "factor": 1.0, "inner": {"law": "power", "mu_ref": 0.5,
                "p_ref_MPa": 1000, "v_ref_m_per_min": 60, "b": -0.2}}"#,
        );
        let f = LawFields::new(&s).unwrap();
        assert_eq!(f.get("inner.b").unwrap(), -0.2);
        let t = f
            .with(&[("factor".into(), 1.3), ("inner.mu_ref".into(), 0.4)])
            .unwrap();
        let g = LawFields::new(&t).unwrap();
        assert_eq!(g.get("factor").unwrap(), 1.3);
        assert_eq!(g.get("inner.mu_ref").unwrap(), 0.4);
        let e = f.with(&[("inner.c".into(), 1.0)]).unwrap_err().to_string();
        assert!(e.contains("inner.c") && e.contains("inner.mu_ref"), "{e}");
        let e = f
            .with(&[("inner.law".into(), 1.0)])
            .unwrap_err()
            .to_string();
        assert!(e.contains("expected a numeric field"), "{e}");
        assert!(f.with(&[("factor".into(), f64::NAN)]).is_err());
    }
}
