//! Identification settings (study TOML `[identify]`): how recordings are aligned, segmented
//! and matched. Its own module so that the stages using it (`identify`, `steady`, `campaign`)
//! import it without importing each other.

use greybox_core::choice::Choice;
use greybox_recording::TestMode;
use serde::{Deserialize, Serialize};

/// Which evidence cuts a recording into steps.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Segmentation {
    /// The best available: step column, then speed channel, then the plan's timing (a
    /// greybox NC-program recording with a trigger and a plan), then the signals.
    #[default]
    Auto,
    /// The plan's nominal timing from the trigger edge (greybox's own NC programs).
    PlanTiming,
    /// Runs of one value of the step/segment column.
    StepColumn,
    /// Runs of constant speed in the speed channel.
    Speed,
    /// Change points of F_N and F_t/F_N.
    Signals,
}

greybox_core::choice!(
    Segmentation,
    "segment",
    [
        Auto => "auto",
        PlanTiming => "plan-timing",
        StepColumn => "step-column",
        Speed => "speed",
        Signals => "signals",
    ],
    text
);

impl Segmentation {
    /// The segmentation's name (`auto`, `plan-timing`, …), as its [`Choice`] spells it.
    pub fn name(self) -> &'static str {
        Choice::name(self)
    }
}

/// Which part of a segment gives its steady-state friction coefficient.
///
/// ASTM G99-17 (pin-on-disk) and G133-05 (reciprocating ball-on-flat) report the friction
/// force "at steady state", i.e. after the run-in (running-in) period in which μ settles; the
/// standards leave the window to the operator. `auto` implements that practice: the final
/// stationary stretch of the step, after the run-in, with a slow drift reported as a trend
/// (μ per hour and per km) rather than shortening the window.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum SteadyRule {
    /// The final stationary stretch after run-in (see [`crate::steady_window::final_stationary`]).
    #[default]
    Auto,
    /// The last share (0 < p ≤ 1) of the segment's sliding time (`last:50%`).
    Last(f64),
    /// From this many seconds after the segment's start, s (`from:300s`).
    From(f64),
}

impl SteadyRule {
    /// The accepted spellings, for help texts and error messages.
    pub const VALUES: &'static [&'static str] = &["auto", "last:P%", "from:Ts"];
}

impl std::fmt::Display for SteadyRule {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            SteadyRule::Auto => write!(f, "auto"),
            SteadyRule::Last(p) => write!(f, "last:{}%", p * 100.0),
            SteadyRule::From(t) => write!(f, "from:{t}s"),
        }
    }
}

impl std::str::FromStr for SteadyRule {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        let s = s.trim();
        let bad = || {
            format!(
                "steady-state rule '{s}': expected one of {} (e.g. last:50%, from:300s)",
                SteadyRule::VALUES.join(", ")
            )
        };
        if s.eq_ignore_ascii_case("auto") {
            return Ok(SteadyRule::Auto);
        }
        if let Some(p) = s.strip_prefix("last:") {
            let v: f64 = p
                .trim()
                .trim_end_matches('%')
                .trim()
                .parse()
                .map_err(|_| bad())?;
            if !(v > 0.0 && v <= 100.0) {
                return Err(format!("{}: the share must lie in (0, 100] %", bad()));
            }
            return Ok(SteadyRule::Last(v / 100.0));
        }
        if let Some(t) = s.strip_prefix("from:") {
            let v: f64 = t
                .trim()
                .trim_end_matches('s')
                .trim()
                .parse()
                .map_err(|_| bad())?;
            if !(v.is_finite() && v >= 0.0) {
                return Err(format!("{}: the start must be a time ≥ 0 s", bad()));
            }
            return Ok(SteadyRule::From(v));
        }
        Err(bad())
    }
}

impl Serialize for SteadyRule {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(&self.to_string())
    }
}

impl<'de> Deserialize<'de> for SteadyRule {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let s = String::deserialize(d)?;
        s.parse().map_err(serde::de::Error::custom)
    }
}

/// How the plan's time zero is found in a recording.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum TimeZero {
    /// Rising edge of the trigger channel.
    #[default]
    Trigger,
    /// The onset of sliding is the first S command (no trigger channel needed).
    FirstPlateau,
}

greybox_core::choice!(
    TimeZero,
    "align",
    [Trigger => "trigger", FirstPlateau => "first-plateau"],
    text
);

/// Identification settings (study TOML `[identify]`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct IdentifyConfig {
    pub align: TimeZero,
    /// Trigger threshold, V (default: midway between the channel's extremes).
    pub trigger_threshold_v: Option<f64>,
    /// Time dropped after the end of the spindle ramp, s (0.05).
    pub settle_time_s: f64,
    /// Time dropped before the next S command, s (0.01).
    pub end_margin_s: f64,
    /// Smoothing window for ramp detection and stick-slip, s (0.025).
    pub smoothing_s: f64,
    /// Hampel spike threshold in robust standard deviations (6).
    pub spike_threshold_sigma: f64,
    /// Hampel half window, s (0.01).
    pub spike_half_window_s: f64,
    /// A μ change over the plateau above this (and significant) is a trend (0.01).
    pub trend_tolerance: f64,
    /// Smallest median drop of μ at the slips of a saw-tooth flagged stick-slip (0.01; see
    /// [`crate::steady_window::stick_slip`]).
    pub stick_slip_threshold: f64,
    /// Largest NC-to-spindle latency accepted, s (0.5).
    pub max_latency_s: f64,
    /// Fewest samples for a plateau (50).
    pub min_plateau_samples: usize,
    /// Which evidence cuts recordings into steps (`auto`).
    pub segmentation: Segmentation,
    /// A sample is loaded above the unloaded level plus this share of the loaded range (0.04).
    pub loaded_fraction: f64,
    /// Without a measured speed channel, a loaded block slides when its friction force |F_t|,
    /// smoothed (running median) over the rig's period and `sliding_smoothing_s`, exceeds this
    /// many local standard deviations of the smoothed force's noise (5; see
    /// [`crate::sliding`]) ...
    pub sliding_rest_sigmas: f64,
    /// ... and this μ times F_N in any case (0.001: below the 0.002–0.005 of an elastohydrodynamic
    /// contact at the fast end of a Stribeck sweep, above the μ of a noiseless contact at rest).
    pub sliding_min_mu: f64,
    /// Shortest averaging of μ before the sliding test, s (0.1; the rig's period if longer).
    pub sliding_smoothing_s: f64,
    /// With a measured speed channel, a loaded block slides above this share of the
    /// channel's largest block speed (0.001: a Stribeck sweep spans decades), or five times
    /// the channel's noise if more (see [`crate::sliding::speed_rest_level`]).
    pub speed_rest_fraction: f64,
    /// Longest revolution or stroke period looked for in μ, s (10).
    pub max_period_s: f64,
    /// Autocorrelation a period must reach to count (0.3).
    pub period_min_correlation: f64,
    /// Relative speed change that ends a constant-speed segment (0.01).
    pub speed_tolerance: f64,
    /// Shortest segment, s (0.3).
    pub min_segment_s: f64,
    /// Signal segmentation with a known step count: shortest step as a share of the mean
    /// step length (0.5; keeps run-in from taking a boundary).
    pub min_segment_fraction: f64,
    /// Plan matching: largest relative load deviation (0.3).
    pub match_load_tolerance: f64,
    /// Plan matching: largest relative speed deviation (0.1).
    pub match_speed_tolerance: f64,
    /// Plan matching, where the plan gives step durations: largest relative deviation of a
    /// segment's duration, as a factor − 1 (1.0: within a factor 2; a segment is the step's
    /// sliding time without its ramps).
    pub match_duration_tolerance: f64,
    /// Plan alignment: cost of a segment left unmatched (an extra segment), in units of a
    /// pairing at the edge of every tolerance (1.0; see [`crate::align`]).
    pub unmatched_segment_cost: f64,
    /// Plan alignment: cost of a planned step left without a segment (1.0).
    pub unmatched_step_cost: f64,
    /// A file whose rows rest on less than this share of its sliding time (steady windows
    /// over sliding time) flags its rows `low-coverage` (0.25).
    pub min_steady_share: f64,
    /// Which part of a segment gives its steady value (`auto`: after run-in, see
    /// [`SteadyRule`]).
    pub steady: SteadyRule,
    /// How far μ may move when a weakly determined boundary's uncertainty is cut from the
    /// steady window before the row is flagged `uncertain-boundary`: half of this (0.003).
    pub mean_uncertainty_tolerance: f64,
    /// Plan alignment: another alignment within this cost of the best one (in units of a
    /// pairing at the edge of every tolerance) that places a segment elsewhere makes its row
    /// `ambiguous-alignment` (0.2; see [`crate::align`]).
    pub ambiguity_margin: f64,
    /// How the rig ran its tests (`None`: from the rig profile and the signal; see
    /// [`crate::reciprocating`]). `reciprocating` identifies strokes instead of plateaus.
    pub mode: Option<TestMode>,
}

impl Default for IdentifyConfig {
    fn default() -> Self {
        IdentifyConfig {
            align: TimeZero::Trigger,
            trigger_threshold_v: None,
            settle_time_s: 0.05,
            end_margin_s: 0.01,
            smoothing_s: 0.025,
            spike_threshold_sigma: 6.0,
            spike_half_window_s: 0.01,
            trend_tolerance: 0.01,
            stick_slip_threshold: 0.01,
            max_latency_s: 0.5,
            min_plateau_samples: 50,
            segmentation: Segmentation::Auto,
            loaded_fraction: 0.04,
            sliding_rest_sigmas: 5.0,
            sliding_min_mu: 0.001,
            sliding_smoothing_s: 0.1,
            speed_rest_fraction: 0.001,
            max_period_s: 10.0,
            period_min_correlation: 0.3,
            speed_tolerance: 0.01,
            min_segment_s: 0.3,
            min_segment_fraction: 0.5,
            match_load_tolerance: 0.3,
            match_speed_tolerance: 0.1,
            match_duration_tolerance: 1.0,
            unmatched_segment_cost: 1.0,
            unmatched_step_cost: 1.0,
            min_steady_share: 0.25,
            steady: SteadyRule::Auto,
            mean_uncertainty_tolerance: 0.003,
            ambiguity_margin: 0.2,
            mode: None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::SteadyRule;

    #[test]
    fn steady_rule_parses_and_prints() {
        assert_eq!("auto".parse::<SteadyRule>(), Ok(SteadyRule::Auto));
        assert_eq!("last:50%".parse::<SteadyRule>(), Ok(SteadyRule::Last(0.5)));
        assert_eq!(
            "from:300s".parse::<SteadyRule>(),
            Ok(SteadyRule::From(300.0))
        );
        assert_eq!(SteadyRule::Last(0.5).to_string(), "last:50%");
        assert_eq!(SteadyRule::From(300.0).to_string(), "from:300s");
        for bad in ["last:0%", "last:150%", "from:-1s", "first", "last:x%"] {
            assert!(bad.parse::<SteadyRule>().is_err(), "{bad}");
        }
    }
}
