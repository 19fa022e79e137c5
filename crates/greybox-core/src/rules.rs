//! Field-by-field checks of configuration values, for errors that name the field and the
//! rule it breaks ("cutting_speed_m_s must be > 0, got -5"). A [`Rules`] collects every
//! violation of one configuration and reports them together.

use crate::{Error, Result};

pub use crate::units::Compact;

/// The violations found in one configuration (`what`, e.g. "cutting set-up").
#[derive(Debug)]
pub struct Rules {
    what: String,
    prefix: String,
    broken: Vec<String>,
}

impl Rules {
    pub fn new(what: impl Into<String>) -> Self {
        Rules {
            what: what.into(),
            prefix: String::new(),
            broken: Vec::new(),
        }
    }

    /// Check the fields of a sub-section (`insert.` …) with `f`.
    pub fn section(&mut self, name: &str, f: impl FnOnce(&mut Rules)) -> &mut Self {
        let inner = format!("{}{name}.", self.prefix);
        let saved = std::mem::replace(&mut self.prefix, inner);
        f(self);
        self.prefix = saved;
        self
    }

    fn check(
        &mut self,
        field: &str,
        ok: bool,
        rule: &str,
        got: impl std::fmt::Display,
    ) -> &mut Self {
        if !ok {
            self.broken
                .push(format!("{}{field} must be {rule}, got {got}", self.prefix));
        }
        self
    }

    /// A finite number.
    pub fn finite(&mut self, field: &str, v: f64) -> &mut Self {
        self.check(field, v.is_finite(), "a finite number", Compact(v))
    }
    /// > 0 and finite.
    pub fn positive(&mut self, field: &str, v: f64) -> &mut Self {
        self.check(field, v.is_finite() && v > 0.0, "> 0", Compact(v))
    }
    /// ≥ 0 and finite.
    pub fn non_negative(&mut self, field: &str, v: f64) -> &mut Self {
        self.check(field, v.is_finite() && v >= 0.0, "≥ 0", Compact(v))
    }
    /// In [lo, hi].
    pub fn within(&mut self, field: &str, v: f64, lo: f64, hi: f64) -> &mut Self {
        self.check(
            field,
            v >= lo && v <= hi,
            &format!("in [{lo}, {hi}]"),
            Compact(v),
        )
    }
    /// In (lo, hi].
    pub fn above_up_to(&mut self, field: &str, v: f64, lo: f64, hi: f64) -> &mut Self {
        self.check(
            field,
            v > lo && v <= hi,
            &format!("in ({lo}, {hi}]"),
            Compact(v),
        )
    }
    /// In (lo, hi).
    pub fn between(&mut self, field: &str, v: f64, lo: f64, hi: f64) -> &mut Self {
        self.check(
            field,
            v > lo && v < hi,
            &format!("in ({lo}, {hi})"),
            Compact(v),
        )
    }
    /// An integer of at least `min`.
    pub fn at_least(&mut self, field: &str, v: u64, min: u64) -> &mut Self {
        self.check(field, v >= min, &format!("≥ {min}"), v)
    }
    /// In the possible range of a physical quantity ([`crate::physics`], SI): the refusal
    /// names the field, the number, the ranges and the likely unit mistake. Outside the
    /// usual range it is not broken but said ([`crate::notes::note`]: "warning: …" on the
    /// command line, a `UnusualValueWarning` in Python) with the same details.
    pub fn physics(&mut self, field: &str, q: crate::physics::Quantity, v: f64) -> &mut Self {
        if let Err(e) = crate::physics::admit(q, v, &format!("{}{field}", self.prefix)) {
            self.broken.push(e);
        }
        self
    }
    /// A rule relating several fields, stated in words.
    pub fn relation(&mut self, ok: bool, rule: impl Into<String>) -> &mut Self {
        if !ok {
            let rule = rule.into();
            self.broken.push(format!("{}{rule}", self.prefix));
        }
        self
    }

    /// Every violation, or Ok.
    pub fn finish(&mut self) -> Result<()> {
        if self.broken.is_empty() {
            return Ok(());
        }
        Err(Error::invalid(
            std::mem::take(&mut self.what),
            self.broken.join("; "),
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_in_messages_stay_short() {
        let shown = |v: f64| Compact(v).to_string();
        assert_eq!(shown(0.02), "0.02");
        assert_eq!(shown(-5.0), "-5");
        assert_eq!(shown(1e308), "1e308");
        assert_eq!(shown(-2.5e-9), "-2.5e-9");
        assert_eq!(shown(f64::NAN), "NaN");
        assert_eq!(shown(0.0), "0");
    }

    #[test]
    fn names_every_broken_field_and_rule() {
        let e = Rules::new("cutting set-up")
            .positive("cutting_speed_m_s", -5.0)
            .positive("spacing_m", f64::NAN)
            .within("tolerance", 0.5, 0.0, 1.0)
            .section("insert", |r| {
                r.non_negative("edge_radius_m", -1e-6);
            })
            .finish()
            .unwrap_err()
            .to_string();
        assert!(e.contains("cutting_speed_m_s must be > 0, got -5"), "{e}");
        assert!(e.contains("spacing_m must be > 0, got NaN"), "{e}");
        assert!(
            e.contains("insert.edge_radius_m must be ≥ 0, got -1e-6"),
            "{e}"
        );
        assert!(!e.contains("tolerance"), "{e}");
        Rules::new("ok").positive("x", 1.0).finish().unwrap();
    }
}
