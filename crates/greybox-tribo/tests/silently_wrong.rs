//! Recordings that used to give a silently wrong dataset (issue "never give a silently wrong
//! μ"): swapped pin files, a tangential channel in kN read as N, and the planned load standing
//! in for the measured one.

use greybox_contact::hertz::PinContact;
use greybox_recording::Recording;
use greybox_tribo::campaign::{expected_from_plan, identify_recordings, Campaign};
use greybox_tribo::config::IdentifyConfig;
use greybox_tribo::plan::{Plan, PlanSpec};
use greybox_tribo::synth::SynthConfig;

fn plan() -> Plan {
    PlanSpec {
        track_radius_mm: Some(100.0),
        normal_force_count: greybox_tribo::plan::PinCount::of(3),
        normal_force_max_n: 1000.0,
        velocity_count: greybox_tribo::plan::VelocityCount::of(3),
        velocity_max_m_per_min: 120.0,
        ..Default::default()
    }
    .build()
    .unwrap()
}

fn recordings(plan: &Plan, synth: &SynthConfig) -> Vec<Recording> {
    let c = PinContact::default();
    (1..=plan.pins.len() as u32)
        .map(|p| synth.simulate_pin(plan, &c, p).unwrap())
        .collect()
}

fn identify(
    plan: &Plan,
    recs: &[Recording],
) -> greybox_core::Result<greybox_tribo::campaign::Identification> {
    let c = PinContact::default();
    let cfg = IdentifyConfig::default();
    let steps = expected_from_plan(plan);
    identify_recordings(
        recs,
        &Campaign {
            expected: Some(&steps),
            plan: Some(plan),
            contact: &c,
            cfg: &cfg,
            track_radius_mm: &[],
        },
    )
}

#[test]
fn swapped_pin_files_are_refused_with_the_evidence() {
    let plan = plan();
    let mut recs = recordings(&plan, &SynthConfig::default());
    recs.swap(1, 2);
    let e = identify(&plan, &recs).unwrap_err().to_string();
    assert!(e.contains("swapped or mislabelled"), "{e}");
    assert!(e.contains("pin 3") && e.contains("(2)"), "{e}");
}

#[test]
fn a_channel_in_the_wrong_unit_is_refused_against_the_other_pins() {
    let plan = plan();
    let mut recs = recordings(&plan, &SynthConfig::default());
    // pin 2's tangential force logged in kN and read as N
    recs[1].tangential_n.iter_mut().for_each(|v| *v *= 1e-3);
    let e = identify(&plan, &recs).unwrap_err().to_string();
    assert!(
        e.contains("pin 2's median μ") && e.contains("below") && e.contains("kN"),
        "{e}"
    );
    // the same with the normal channel in kN: caught by the plan's load already
    let mut recs = recordings(&plan, &SynthConfig::default());
    recs[0].normal_n.iter_mut().for_each(|v| *v *= 1e-3);
    let e = identify(&plan, &recs).unwrap_err().to_string();
    assert!(e.contains("normal"), "{e}");
}

/// The tangential channel in kN in every pin: no pin stands out against the others, but the
/// campaign's μ (0.0002-0.0007 for steel on steel) is outside any sliding pair's.
#[test]
fn a_channel_in_the_wrong_unit_in_every_pin_is_refused_for_the_campaign() {
    let plan = plan();
    let mut recs = recordings(&plan, &SynthConfig::default());
    for r in &mut recs {
        r.tangential_n.iter_mut().for_each(|v| *v *= 1e-3);
    }
    let e = identify(&plan, &recs).unwrap_err().to_string();
    assert!(
        e.contains("the campaign's median μ") && e.contains("0.005..3") && e.contains("kN"),
        "{e}"
    );
    // and in N it passes
    assert!(identify(&plan, &recordings(&plan, &SynthConfig::default())).is_ok());
}

#[test]
fn the_dataset_load_is_the_measured_one_with_the_plan_beside_it() {
    let plan = plan();
    let recs = recordings(&plan, &SynthConfig::default());
    let id = identify(&plan, &recs).unwrap();
    for r in &id.dataset.records {
        let planned = plan.pins[r.pin as usize - 1].normal_force_n;
        assert_eq!(r.normal_force_planned_n, Some(planned));
        // measured: close to the plan but not the plan's number itself
        assert!(
            (r.normal_force_n / planned - 1.0).abs() < 0.05,
            "{} vs {planned}",
            r.normal_force_n
        );
        assert_ne!(r.normal_force_n, planned);
        let p = PinContact::default().pressure_pa(r.normal_force_n).unwrap();
        assert!(
            (r.hertz_pressure_pa / p - 1.0).abs() < 1e-12,
            "pressure of the measured load"
        );
    }
}

/// `--map tangential=normal_force_N` used to give μ ≡ 1.
#[test]
fn one_column_for_two_roles_is_refused() {
    use greybox_recording::readers::read_recording;
    use greybox_recording::{ChannelMap, ChannelSpec};
    let d = tempfile::tempdir().unwrap();
    let p = d.path().join("pin01.csv");
    std::fs::write(
        &p,
        "time_s,normal_force_N,tangential_force_N\n0,100,40\n0.001,100,41\n0.002,101,40\n",
    )
    .unwrap();
    let map = ChannelMap {
        tangential: Some(ChannelSpec::named("normal_force_N")),
        ..ChannelMap::default()
    };
    let e = read_recording(&p, &map).unwrap_err().to_string();
    assert!(e.contains("pin01.csv") && e.contains("two roles"), "{e}");
}

// ---- physics as data (issue 46 item 4): each unit mistake refused or flagged with the
// number and the likely mistake.

/// The lines of every file's `unusual` values, or the refusal.
fn unusual(plan: &Plan, recs: &[Recording]) -> Result<String, String> {
    identify(plan, recs)
        .map(|id| {
            id.files
                .iter()
                .flat_map(|f| f.unusual.iter().map(move |u| format!("{}: {u}", f.source)))
                .collect::<Vec<_>>()
                .join("\n")
        })
        .map_err(|e| e.to_string())
}

/// A load in kgf labelled N: μ 9.81× too high (2.94 for 0.3); against the plan, the load is
/// 0.102× the planned one.
#[test]
fn a_load_in_kgf_is_refused_with_the_hint() {
    let plan = plan();
    let mut recs = recordings(&plan, &SynthConfig::default());
    recs.iter_mut()
        .for_each(|r| r.normal_n.iter_mut().for_each(|v| *v /= 9.80665));
    let e = unusual(&plan, &recs).unwrap_err();
    assert!(
        e.contains("-90 % off the planned 150 N") && e.contains("a load in kgf read as N"),
        "{e}"
    );
}

/// Normal and friction channels swapped: the "load" is μ × the planned one.
#[test]
fn swapped_normal_and_friction_channels_are_refused_with_the_hint() {
    let plan = plan();
    let mut recs = recordings(&plan, &SynthConfig::default());
    recs.iter_mut()
        .for_each(|r| std::mem::swap(&mut r.normal_n, &mut r.tangential_n));
    let e = unusual(&plan, &recs).unwrap_err();
    assert!(
        e.contains("off the planned 150 N") && e.contains("normal and friction channels swapped"),
        "{e}"
    );
}

/// μ above the usual 1 (a lubricated COF of 2.31 % read as 2.31, or a kgf load) is flagged in
/// the file's result with the number and the hints; above 3 it is refused.
#[test]
fn a_mu_above_the_usual_range_is_flagged_and_above_three_refused() {
    let plan = plan();
    let base = recordings(&plan, &SynthConfig::default());
    let mut high = base.clone();
    high.iter_mut()
        .for_each(|r| r.tangential_n.iter_mut().for_each(|v| *v *= 2.0));
    let u = unusual(&plan, &high).unwrap();
    assert!(
        u.contains("μ ") && u.contains("is outside the usual range 0.005..1 (possible 0..3)"),
        "{u}"
    );
    assert!(
        u.contains("in % read as a fraction (÷100 → ")
            && u.contains("a load in kgf read as N")
            && u.contains("normal and friction channels swapped (1/μ → ")
            && u.contains("(and 1 more step)"),
        "{u}"
    );
    let mut refused = base.clone();
    refused
        .iter_mut()
        .for_each(|r| r.tangential_n.iter_mut().for_each(|v| *v *= 10.0));
    let e = unusual(&plan, &refused).unwrap_err();
    assert!(
        e.contains("the campaign's median μ 4.516 is outside the possible range 0.005..3")
            && e.contains("in % read as a fraction"),
        "{e}"
    );
    // the same recordings in their units: nothing unusual
    assert_eq!(unusual(&plan, &base).unwrap(), "");
}

/// A speed channel in rpm or mm/s labelled m/s (11 460 or 6 000 m/min): flagged per step
/// with the number and the unit.
#[test]
fn speeds_beyond_the_usual_range_are_flagged_with_the_unit() {
    use greybox_tribo::campaign::check_physics;
    let plan = plan();
    let recs = recordings(&plan, &SynthConfig::default());
    for (v_m_s, hint) in [
        (100.0, "a speed in mm/s read as m/s (÷1000 → 0.1)"),
        (191.0, "a spindle speed in rpm read as m/s"),
    ] {
        let mut id = identify(&plan, &recs).unwrap();
        id.dataset
            .records
            .iter_mut()
            .for_each(|r| r.sliding_velocity_m_s = v_m_s);
        check_physics(&id.dataset, &mut id.files).unwrap();
        let u = id.files[0].unusual.join("\n");
        assert!(
            u.contains("pin 1 step 1: sliding velocity")
                && u.contains("m/s is outside the usual range")
                && u.contains(hint),
            "{u}"
        );
        // beyond 200 m/s: refused
        id.dataset.records[0].sliding_velocity_m_s = 1000.0;
        let e = check_physics(&id.dataset, &mut id.files)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("sliding velocity 1000 m/s is outside the possible range 0..200 m/s"),
            "{e}"
        );
    }
}

/// A track radius of 15 µm or 15 m: refused with the unit.
#[test]
fn a_track_radius_of_microns_or_metres_is_refused() {
    use greybox_tribo::plan::PlanSpec;
    for (mm, hint) in [
        (0.015, "a length in m read as mm"),
        (15000.0, "a length in mm read as m"),
    ] {
        let e = PlanSpec {
            track_radius_mm: Some(mm),
            ..Default::default()
        }
        .track_radius_m()
        .unwrap_err()
        .to_string();
        assert!(
            e.contains("track_radius_mm: track radius")
                && e.contains("outside the possible range 0.0001..5 m")
                && e.contains(hint),
            "{e}"
        );
    }
}
