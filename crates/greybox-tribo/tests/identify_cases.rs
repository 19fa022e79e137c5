//! Identification beyond the default path: no trigger, stick-slip, and bad recordings.

use greybox_contact::hertz::PinContact;
use greybox_tribo::plan::{Plan, PlanSpec};
use greybox_tribo::plan_timing::{identify_pin, IdentifyConfig, TimeZero};
use greybox_tribo::synth::{StickSlip, SynthConfig};

fn small_plan() -> Plan {
    PlanSpec {
        track_radius_mm: Some(100.0),
        normal_force_count: greybox_tribo::plan::PinCount::of(2),
        normal_force_max_n: 1000.0,
        velocity_count: greybox_tribo::plan::VelocityCount::of(5),
        velocity_max_m_per_min: 120.0,
        ..Default::default()
    }
    .build()
    .unwrap()
}

fn truth_error(cfg: &SynthConfig, id: &IdentifyConfig, strip_trigger: bool) -> f64 {
    let plan = small_plan();
    let c = PinContact::default();
    let truth = cfg.ground_truth(&plan, &c).unwrap();
    let mut worst = 0.0f64;
    for pin in 1..=2 {
        let mut rec = cfg.simulate_pin(&plan, &c, pin).unwrap();
        if strip_trigger {
            rec.trigger_v = None;
        }
        let (rows, _) = identify_pin(&rec, &plan, pin, &c, id).unwrap();
        for r in rows {
            let t = truth
                .iter()
                .find(|t| t.pin == r.pin && t.step == r.step)
                .unwrap();
            worst = worst.max((r.cof_apparent - t.cof_true).abs());
        }
    }
    worst
}

#[test]
fn first_plateau_alignment_without_trigger() {
    let id = IdentifyConfig {
        align: TimeZero::FirstPlateau,
        ..Default::default()
    };
    let worst = truth_error(&SynthConfig::default(), &id, true);
    assert!(worst <= 0.003, "{worst}");
    // and with the trigger alignment the missing channel is a clear error
    let plan = small_plan();
    let c = PinContact::default();
    let mut rec = SynthConfig::default().simulate_pin(&plan, &c, 1).unwrap();
    rec.trigger_v = None;
    let e = identify_pin(&rec, &plan, 1, &c, &IdentifyConfig::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("no trigger channel"), "{e}");
}

#[test]
fn stick_slip_is_flagged_only_where_injected() {
    let plan = small_plan();
    let c = PinContact::default();
    let cfg = SynthConfig {
        stick_slip: Some(StickSlip {
            below_m_per_min: 50.0,
            amplitude_rel: 0.15,
            frequency_hz: 12.0,
        }),
        ..Default::default()
    };
    let rec = cfg.simulate_pin(&plan, &c, 1).unwrap();
    let (rows, _) = identify_pin(&rec, &plan, 1, &c, &IdentifyConfig::default()).unwrap();
    for r in rows {
        let slow = r.sliding_velocity_m_s * 60.0 < 50.0;
        assert_eq!(
            r.flags.iter().any(|f| f == "stick-slip"),
            slow,
            "step {} flags {:?}",
            r.step,
            r.flags
        );
        assert_eq!(r.stationary, !slow);
    }
}

#[test]
fn recording_shorter_than_the_plan() {
    let plan = small_plan();
    let c = PinContact::default();
    let mut rec = SynthConfig::default().simulate_pin(&plan, &c, 1).unwrap();
    let keep = rec.len() / 2;
    rec.time_s.truncate(keep);
    rec.normal_n.truncate(keep);
    rec.tangential_n.truncate(keep);
    rec.radial_n = None;
    rec.trigger_v.as_mut().unwrap().truncate(keep);
    let e = identify_pin(&rec, &plan, 1, &c, &IdentifyConfig::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("shorter than the plan"), "{e}");
}

#[test]
fn zero_or_negative_normal_force() {
    let plan = small_plan();
    let c = PinContact::default();
    let mut rec = SynthConfig::default().simulate_pin(&plan, &c, 1).unwrap();
    // the pin lifts off for 0.2 s in the middle of step 3
    let s = &plan.pin_steps(1)[2];
    let t_trig = 0.3;
    for (t, f) in rec.time_s.iter().zip(rec.normal_n.iter_mut()) {
        if *t > t_trig + s.plateau_start_s + 0.1 && *t < t_trig + s.plateau_start_s + 0.3 {
            *f = -3.0;
        }
    }
    let e = identify_pin(&rec, &plan, 1, &c, &IdentifyConfig::default())
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("zero or negative") && e.contains("step 3"),
        "{e}"
    );
}

#[test]
fn wrong_units_are_caught_by_the_load_check() {
    let plan = small_plan();
    let c = PinContact::default();
    let mut rec = SynthConfig::default().simulate_pin(&plan, &c, 2).unwrap();
    for f in rec.normal_n.iter_mut() {
        *f /= 1000.0; // a kN column read as N
    }
    let e = identify_pin(&rec, &plan, 2, &c, &IdentifyConfig::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("check the channel mapping and units"), "{e}");
}
