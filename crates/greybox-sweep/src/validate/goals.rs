//! A suite's goals on the held-out mean |error|s, and whether a friction model meets them,
//! does not, or cannot be told from them.
//!
//! A mean |error| over n held-out conditions is uncertain twice over: each simulated value
//! scatters (the cut's standard error from its steady state's batch means, `error_se`), and
//! each measured value is the mean of a few repeated cuts with its own scatter (the data's
//! dispersion, when the data say what it is: [`super::conditions::DispersionMeaning`]). With
//! e_i = s_i/m_i − 1, a measured mean m_i with standard error σ_m,i moves e_i by
//! −(1 + e_i) δm_i/m_i, so its standard error in e_i is (1 + e_i) σ_m,i/m_i; and
//! d|e| = sign(e) de where the error is clear of zero. The mean |error|'s 95 % interval is
//!
//!   mean |e| ± 1.96 √(Σ_i (se_cut,i² + se_meas,i²)) / n,
//!
//! a cut that could not say given the median of the others' ([`super::imputed_errors`]), a
//! measured value without a stated dispersion counted as exact (and the check says how many).
//! A goal g is **met** when the whole interval lies at or below g, **not met** when it lies
//! above, and otherwise the evidence **cannot tell**: the suite says so instead of choosing.

use super::{imputed_errors, mean_ci95, Outcome};
use serde::{Deserialize, Serialize};

/// The suite file's `[goals]`: the held-out mean |error| each measure should stay within, %
/// (default: F'c 15 %, F'f 30 %, the chip ratio unchecked).
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Goals {
    #[serde(default = "default_cutting_force")]
    pub cutting_force_percent: Option<f64>,
    #[serde(default = "default_feed_force")]
    pub feed_force_percent: Option<f64>,
    #[serde(default)]
    pub chip_ratio_percent: Option<f64>,
}

fn default_cutting_force() -> Option<f64> {
    Some(15.0)
}

fn default_feed_force() -> Option<f64> {
    Some(30.0)
}

impl Default for Goals {
    fn default() -> Self {
        Goals {
            cutting_force_percent: default_cutting_force(),
            feed_force_percent: default_feed_force(),
            chip_ratio_percent: None,
        }
    }
}

/// The three measures a suite compares, in the order of `Outcome::error_se`.
pub const MEASURES: [&str; 3] = ["F'c", "F'f", "chip ratio"];

impl Goals {
    /// The goals as fractions, per measure (`None`: not checked).
    pub fn fractions(&self) -> [Option<f64>; 3] {
        self.fields().map(|(_, g)| g.map(|p| p / 100.0))
    }

    /// Each goal's field name in the suite file and its value, %, in the order of
    /// [`MEASURES`].
    fn fields(&self) -> [(&'static str, Option<f64>); 3] {
        [
            ("cutting_force_percent", self.cutting_force_percent),
            ("feed_force_percent", self.feed_force_percent),
            ("chip_ratio_percent", self.chip_ratio_percent),
        ]
    }

    /// Every goal is a percentage in (0, 100]: the file and field named otherwise.
    pub fn check(&self, source: &str) -> anyhow::Result<()> {
        for (name, g) in self.fields() {
            if let Some(g) = g.filter(|g| !(*g > 0.0 && *g <= 100.0)) {
                anyhow::bail!(
                    "{source}: [goals] {name}: expected a percentage in (0, 100], got {g}"
                );
            }
        }
        Ok(())
    }

    /// "F'c ≤ 15 %, F'f ≤ 30 %": the goals checked, for a table header.
    pub fn describe(&self) -> String {
        let set: Vec<String> = MEASURES
            .iter()
            .zip(self.fractions())
            .filter_map(|(m, g)| g.map(|g| format!("{m} ≤ {} %", percent(g))))
            .collect();
        if set.is_empty() {
            "none set".to_string()
        } else {
            set.join(", ")
        }
    }
}

/// A goal fraction as the percentage it was given as (to 0.01 %: 0.073 is "7.3", not
/// "7.300000000000001").
fn percent(fraction: f64) -> f64 {
    (fraction * 1e4).round() / 100.0
}

/// What the evidence says of a goal.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Verdict {
    Met,
    NotMet,
    CannotTell,
}

greybox_core::choice!(Verdict, "goal verdict", [Met => "met", NotMet => "not met", CannotTell => "cannot tell"]);

impl Verdict {
    /// All of `verdicts` together: not met if one is not, met if all are, otherwise cannot
    /// tell (`None` without a goal).
    pub fn all(verdicts: impl IntoIterator<Item = Verdict>) -> Option<Verdict> {
        let v: Vec<Verdict> = verdicts.into_iter().collect();
        if v.is_empty() {
            None
        } else if v.contains(&Verdict::NotMet) {
            Some(Verdict::NotMet)
        } else if v.iter().all(|x| *x == Verdict::Met) {
            Some(Verdict::Met)
        } else {
            Some(Verdict::CannotTell)
        }
    }
}

/// One measure's held-out mean |error| against its goal.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct GoalCheck {
    /// "F'c", "F'f" or "chip ratio".
    pub measure: String,
    /// The goal and the mean |error|, fractions.
    pub goal: f64,
    pub mean_abs: f64,
    /// Half-widths of the mean |error|'s 95 % interval: from the cuts' scatter, from the
    /// measured values' own, and both together (`None`: no cut could say how sure it is).
    pub cuts_ci95: Option<f64>,
    pub measured_ci95: f64,
    pub ci95: Option<f64>,
    pub conditions: usize,
    /// Conditions whose measured value's uncertainty the data state (the others counted as
    /// exact, which narrows the interval).
    pub measured_uncertainty_known: usize,
    pub verdict: Verdict,
}

/// The goals `goals` checked on the held-out outcomes `rows` of one friction model.
pub fn check(rows: &[&Outcome], goals: &Goals) -> Vec<GoalCheck> {
    MEASURES
        .iter()
        .zip(goals.fractions())
        .enumerate()
        .filter_map(|(k, (measure, goal))| {
            let goal = goal?;
            let used: Vec<&Outcome> = rows
                .iter()
                .copied()
                .filter(|o| o.error(k).is_some())
                .collect();
            if used.is_empty() {
                return None;
            }
            let n = used.len();
            let mean_abs = used
                .iter()
                .filter_map(|o| o.error(k))
                .map(f64::abs)
                .sum::<f64>()
                / n as f64;
            let cut_se: Vec<Option<f64>> = used.iter().map(|o| o.error_se[k]).collect();
            let cuts = imputed_errors(&cut_se).map(|(v, _)| v);
            let measured: Vec<f64> = used.iter().filter_map(|o| o.measured_error_se[k]).collect();
            let ci95 = cuts
                .as_ref()
                .map(|c| mean_ci95(c.iter().chain(&measured), n));
            Some(GoalCheck {
                measure: measure.to_string(),
                goal,
                mean_abs,
                cuts_ci95: cuts.as_ref().map(|c| mean_ci95(c, n)),
                measured_ci95: mean_ci95(&measured, n),
                ci95,
                conditions: used.len(),
                measured_uncertainty_known: used
                    .iter()
                    .filter(|o| o.measured_error_se[k].is_some())
                    .count(),
                verdict: verdict(mean_abs, ci95, goal),
            })
        })
        .collect()
}

/// Met when the interval lies at or below the goal, not met when above it, otherwise
/// cannot tell (and cannot tell without an interval).
fn verdict(mean_abs: f64, ci95: Option<f64>, goal: f64) -> Verdict {
    match ci95 {
        Some(h) if mean_abs + h <= goal => Verdict::Met,
        Some(h) if mean_abs - h > goal => Verdict::NotMet,
        _ => Verdict::CannotTell,
    }
}

/// A goal check in words: "F'c 6.2 ± 1.1 % ≤ 15 %: met".
pub fn describe(c: &GoalCheck) -> String {
    let pm = c.ci95.map_or(" (no interval)".to_string(), |h| {
        format!(" ± {:.1}", 100.0 * h)
    });
    let unknown = c.conditions - c.measured_uncertainty_known;
    let note = if unknown > 0 {
        format!(
            " ({unknown} of {} measured values without a stated uncertainty)",
            c.conditions
        )
    } else {
        String::new()
    };
    format!(
        "{} {:.1}{pm} % against ≤ {} %: {}{note}",
        c.measure,
        100.0 * c.mean_abs,
        percent(c.goal),
        c.verdict
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::validate::test_support::outcome;
    use rand::SeedableRng;
    use rand_distr::{Distribution, Normal};

    /// The interval of a suite's held-out chip-ratio mean |error| covers the model's true
    /// mean |error| about 95 % of the time when both the simulated and the measured values
    /// scatter as stated, and far less often when the measurements' scatter is left out (the
    /// cuts' scatter alone, as the suite's summary intervals are).
    #[test]
    fn the_goal_interval_covers_the_true_mean_error_when_measurements_scatter() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(61);
        let unit = Normal::new(0.0, 1.0).unwrap();
        // twelve conditions: true ratios, true model errors of either sign and size, the
        // measured means' standard errors (dispersion 2σ over 3 repeats, 1–8 % of the value)
        // and the cuts' standard errors (0.5–1.5 %)
        let truth: Vec<(f64, f64, f64, f64)> = (0..12)
            .map(|i| {
                let i = i as f64;
                let m = 1.2 + 0.07 * i;
                let e = [0.11, -0.09, 0.06, 0.14, -0.12, 0.08][i as usize % 6] * (1.0 + 0.05 * i);
                let sigma_m = m * (0.01 + 0.006 * i);
                let sigma_s = m * (1.0 + e) * (0.005 + 0.001 * (11.0 - i));
                (m, e, sigma_m, sigma_s)
            })
            .collect();
        let true_mean = truth.iter().map(|t| t.1.abs()).sum::<f64>() / 12.0;
        let goal = Goals {
            chip_ratio_percent: Some(8.0),
            ..Default::default()
        };
        let (mut covered, mut covered_cuts_only, trials) = (0, 0, 2000);
        for _ in 0..trials {
            let rows: Vec<Outcome> = truth
                .iter()
                .map(|&(m, e, sm, ss)| {
                    let measured = m + sm * unit.sample(&mut rng);
                    let simulated = m * (1.0 + e) + ss * unit.sample(&mut rng);
                    let err = simulated / measured - 1.0;
                    outcome(
                        err,
                        Some(ss / measured),
                        Some(simulated / measured * sm / measured),
                    )
                })
                .collect();
            let refs: Vec<&Outcome> = rows.iter().collect();
            let c = check(&refs, &goal).pop().unwrap();
            assert_eq!(c.measure, "chip ratio");
            let h = c.ci95.unwrap();
            covered += ((c.mean_abs - true_mean).abs() <= h) as usize;
            covered_cuts_only += ((c.mean_abs - true_mean).abs() <= c.cuts_ci95.unwrap()) as usize;
        }
        let rate = covered as f64 / trials as f64;
        let cuts_only = covered_cuts_only as f64 / trials as f64;
        assert!((0.93..=0.975).contains(&rate), "coverage {rate}");
        assert!(cuts_only < 0.8, "cuts' scatter alone covers {cuts_only}");
    }

    /// Rows without a measured uncertainty are counted as exact and counted as such; a cut
    /// that cannot say takes the others' median; without a goal nothing is checked.
    #[test]
    fn unknown_uncertainties_are_counted_and_said() {
        let rows = [
            outcome(0.10, Some(0.01), Some(0.02)),
            outcome(-0.05, Some(0.03), None),
            outcome(0.12, None, Some(0.04)),
        ];
        let refs: Vec<&Outcome> = rows.iter().collect();
        let goal = Goals {
            chip_ratio_percent: Some(8.0),
            ..Default::default()
        };
        let c = check(&refs, &goal);
        assert_eq!(c.len(), 3);
        let chip = &c[2];
        assert!((chip.mean_abs - 0.09).abs() < 1e-12);
        let cuts = 1.96 * (0.01f64.powi(2) + 0.03f64.powi(2) + 0.02f64.powi(2)).sqrt() / 3.0;
        let measured = 1.96 * (0.02f64.powi(2) + 0.04f64.powi(2)).sqrt() / 3.0;
        assert!((chip.cuts_ci95.unwrap() - cuts).abs() < 1e-12);
        assert!((chip.measured_ci95 - measured).abs() < 1e-12);
        assert!((chip.ci95.unwrap() - (cuts * cuts + measured * measured).sqrt()).abs() < 1e-12);
        assert_eq!(chip.measured_uncertainty_known, 2);
        assert_eq!(chip.verdict, Verdict::CannotTell);
        assert!(describe(chip).contains("1 of 3 measured values without a stated uncertainty"));
        assert!(check(
            &refs,
            &Goals {
                cutting_force_percent: None,
                feed_force_percent: None,
                chip_ratio_percent: None
            }
        )
        .is_empty());
    }

    #[test]
    fn a_goal_inside_the_interval_cannot_be_told() {
        assert_eq!(verdict(0.05, Some(0.01), 0.08), Verdict::Met);
        assert_eq!(verdict(0.07, Some(0.01), 0.08), Verdict::Met);
        assert_eq!(verdict(0.082, Some(0.016), 0.08), Verdict::CannotTell);
        assert_eq!(verdict(0.075, Some(0.016), 0.08), Verdict::CannotTell);
        assert_eq!(verdict(0.106, Some(0.016), 0.08), Verdict::NotMet);
        assert_eq!(verdict(0.01, None, 0.08), Verdict::CannotTell);
        assert_eq!(
            Verdict::all([Verdict::Met, Verdict::CannotTell]),
            Some(Verdict::CannotTell)
        );
        assert_eq!(
            Verdict::all([Verdict::CannotTell, Verdict::NotMet]),
            Some(Verdict::NotMet)
        );
        assert_eq!(
            Verdict::all([Verdict::Met, Verdict::Met]),
            Some(Verdict::Met)
        );
        assert_eq!(Verdict::all([]), None);
    }

    #[test]
    fn goals_are_percentages() {
        let g: Goals = toml::from_str("chip_ratio_percent = 8.0").unwrap();
        assert_eq!(g.fractions(), [Some(0.15), Some(0.30), Some(0.08)]);
        assert_eq!(g.describe(), "F'c ≤ 15 %, F'f ≤ 30 %, chip ratio ≤ 8 %");
        let odd: Goals =
            toml::from_str("chip_ratio_percent = 7.3\nfeed_force_percent = 29.9").unwrap();
        assert_eq!(
            odd.describe(),
            "F'c ≤ 15 %, F'f ≤ 29.9 %, chip ratio ≤ 7.3 %"
        );
        let bad: Goals = toml::from_str("feed_force_percent = 0.0").unwrap();
        let e = bad.check("s.toml").unwrap_err().to_string();
        assert!(
            e.contains("s.toml") && e.contains("feed_force_percent"),
            "{e}"
        );
        assert!(toml::from_str::<Goals>("chip = 8.0").is_err());
    }
}
