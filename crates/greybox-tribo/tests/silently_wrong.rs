//! Recordings that used to give a silently wrong dataset (issue "never give a silently wrong
//! μ"): swapped pin files, a tangential channel in kN read as N, and the planned load standing
//! in for the measured one.

use greybox_tribo::campaign::{expected_from_plan, identify_recordings, Campaign};
use greybox_tribo::hertz::PinContact;
use greybox_tribo::identify::IdentifyConfig;
use greybox_tribo::plan::{Plan, PlanSpec};
use greybox_tribo::recording::Recording;
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
    use greybox_tribo::readers::read_recording;
    use greybox_tribo::recording::{ChannelMap, ChannelSpec};
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
