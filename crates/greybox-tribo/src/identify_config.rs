//! Identification settings (study TOML `[identify]`): how recordings are aligned, segmented
//! and matched. Its own module so that the stages using it (`identify`, `steady`, `campaign`)
//! import it without importing each other.

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

impl Segmentation {
    pub fn name(self) -> &'static str {
        match self {
            Segmentation::Auto => "auto",
            Segmentation::PlanTiming => "plan-timing",
            Segmentation::StepColumn => "step-column",
            Segmentation::Speed => "speed",
            Segmentation::Signals => "signals",
        }
    }
}

/// How the plan's time zero is found in a recording.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Alignment {
    /// Rising edge of the trigger channel.
    #[default]
    Trigger,
    /// The onset of sliding is the first S command (no trigger channel needed).
    FirstPlateau,
}

/// Identification settings (study TOML `[identify]`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct IdentifyConfig {
    pub align: Alignment,
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
    /// Peak-to-peak of smoothed, detrended μ above this is stick-slip (0.03).
    pub stick_slip_threshold: f64,
    /// Largest NC-to-spindle latency accepted, s (0.5).
    pub max_latency_s: f64,
    /// Fewest samples for a plateau (50).
    pub min_plateau_samples: usize,
    /// Which evidence cuts recordings into steps (`auto`).
    pub segmentation: Segmentation,
    /// A sample is loaded above the unloaded level plus this share of the loaded range (0.04).
    pub loaded_fraction: f64,
    /// A loaded block slides when its μ exceeds this share of the typical μ (0.25).
    pub sliding_fraction: f64,
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
}

impl Default for IdentifyConfig {
    fn default() -> Self {
        IdentifyConfig {
            align: Alignment::Trigger,
            trigger_threshold_v: None,
            settle_time_s: 0.05,
            end_margin_s: 0.01,
            smoothing_s: 0.025,
            spike_threshold_sigma: 6.0,
            spike_half_window_s: 0.01,
            trend_tolerance: 0.01,
            stick_slip_threshold: 0.03,
            max_latency_s: 0.5,
            min_plateau_samples: 50,
            segmentation: Segmentation::Auto,
            loaded_fraction: 0.04,
            sliding_fraction: 0.25,
            speed_tolerance: 0.01,
            min_segment_s: 0.3,
            min_segment_fraction: 0.5,
            match_load_tolerance: 0.3,
            match_speed_tolerance: 0.1,
        }
    }
}
