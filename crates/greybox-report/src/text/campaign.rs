//! Plain text of planning a campaign and of the virtual rig's recordings.

use greybox_pipeline::plan::PlanSummary;
use greybox_pipeline::synth::SynthSummary;
use std::fmt::Write as _;

/// A plan: pins, velocities, forces, spindle speeds, durations.
pub fn plan(s: &PlanSummary) -> String {
    let mut text = String::new();
    let _ = writeln!(
        text,
        "plan: {} pins x {} velocities = {} plateaus",
        s.pins,
        s.steps / s.pins.max(1),
        s.steps
    );
    let _ = writeln!(
        text,
        "  normal forces {} N",
        s.normal_forces_n
            .iter()
            .map(|f| format!("{f:.1}"))
            .collect::<Vec<_>>()
            .join(", ")
    );
    let _ = writeln!(
        text,
        "  velocities {:.1}..{:.1} m/min -> spindle {:.2}..{:.2} rpm",
        s.velocity_min_m_per_min, s.velocity_max_m_per_min, s.spindle_rpm_min, s.spindle_rpm_max
    );
    let _ = writeln!(
        text,
        "  recording per pin {:.2} s, campaign {:.1} s",
        s.pin_duration_s, s.campaign_recording_s
    );
    text
}

/// What the virtual rig recorded.
pub fn synth(s: &SynthSummary) -> String {
    let mut text = String::new();
    let _ = writeln!(
        text,
        "synth: {} pins, {} samples (seed {}), true COF {:.3}..{:.3}",
        s.pins, s.samples, s.seed, s.cof_true_min, s.cof_true_max
    );
    text
}
