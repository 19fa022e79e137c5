//! Mutants of valid inputs that a mutation-fuzz campaign (2026-11-26: byte flips,
//! truncations, repeated blocks, numbers swapped for huge values, NaN, ∞ and zero) found to
//! panic, to allocate without bound, to run for months or to write ∞/NaN into an output.
//! Each is reduced to its cause here and must now be refused with the file, line or field
//! named, under an address-space and a wall-clock limit.
mod common;
use common::{coarse_config, greybox_limited, refused_with};
use greybox_testkit::mesh::{
    gmsh, unit_square_abaqus, GMSH_ELEMENTS as ELEMENTS, GMSH_NODES as NODES,
};
use std::path::Path;

const MEMORY_MIB: u64 = 2048;
const SECONDS: u64 = 60;

fn run(args: &[&str], cwd: &Path) -> std::process::Output {
    greybox_limited(args, cwd, MEMORY_MIB, SECONDS)
}

#[test]
fn gmsh_mutants_are_refused_with_their_line() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    let windows = |name: &str, text: &str| {
        std::fs::write(p.join(name), text).unwrap();
        run(&["windows", "--mesh", name, "--out", "w"], p)
    };
    // the intact file builds windows, so each refusal below is the mutation's
    std::fs::write(p.join("ok.msh"), gmsh(NODES, ELEMENTS)).unwrap();
    common::ok(&run(&["windows", "--mesh", "ok.msh", "--out", "w0"], p));
    for (mutant, needles) in [
        // a node block header cut short (was: index out of bounds)
        (
            gmsh("1 4 1 4\n2 1 0\n", ELEMENTS),
            &["line 14", "a node block header", "needs 4 numbers"][..],
        ),
        // an element with two of its four corners (was: slice index out of range)
        (
            gmsh(NODES, "1 1 1 1\n2 1 3 1\n1 1 2\n"),
            &["line 27", "needs 5 numbers"][..],
        ),
        // a count of 10¹⁸ nodes (was: an allocation of exabytes)
        (
            gmsh("1 4 1 4\n2 1 0 1e18\n", ELEMENTS),
            &[
                "line 14",
                "the number of nodes in the block is 1000000000000000000",
            ][..],
        ),
        // a coordinate that is NaN (was: NaN windows written)
        (
            gmsh(&NODES.replace("1 1 0\n", "nan 1 0\n"), ELEMENTS),
            &["line 21", "expected a finite number, found 'nan'"][..],
        ),
        // the surface entity claims more physical tags than it lists (was: slice panic)
        (
            gmsh(NODES, ELEMENTS).replace("1 0 0 0 1 1 0 1 1 0", "1 0 0 0 1 1 0 3 1"),
            &["line 10", "names 3 physical tags"][..],
        ),
        // two corners at the same point: a coating edge of zero length (was: NaN windows)
        (
            gmsh(&NODES.replace("1 0 0\n", "0 0 0\n"), ELEMENTS),
            &["edge of zero length", "nodes 1 and 2"][..],
        ),
    ] {
        let r = windows("m.msh", &mutant);
        refused_with(&r, &[&["m.msh"][..], needles].concat());
        assert!(!p.join("w").exists(), "a refused mesh wrote windows");
    }
}

#[test]
fn abaqus_mutants_are_refused_with_their_line() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    let deck = unit_square_abaqus;
    for (text, needles) in [
        // a GENERATE range of 10¹⁸ elements (was: a vector of exabytes)
        (
            deck("*ELSET, ELSET=E, GENERATE\n1, 1000000000000000000\n"),
            &["line 9", "names 1000000000000000000 elements"][..],
        ),
        // a line of commas where an element was (was: an index underflow)
        (
            "*NODE\n1, 0, 0\n*ELEMENT, TYPE=CPE4\n,,,,\n".to_string(),
            &["line 4", "unsupported element with 0 nodes"][..],
        ),
        // a node number that is not a whole number
        (
            deck("").replace("3, 1, 1", "-3, 1, 1"),
            &["line 4", "whole number ≥ 0), found '-3'"][..],
        ),
    ] {
        std::fs::write(p.join("m.inp"), text).unwrap();
        let r = run(&["windows", "--mesh", "m.inp", "--out", "w"], p);
        refused_with(&r, &[&["m.inp"][..], needles].concat());
    }
}

#[test]
fn configuration_numbers_must_be_finite_and_sized() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    let study = |name: &str, synth: &str| {
        std::fs::write(
            p.join(name),
            format!("[plan]\ntrack_radius_mm = 80.0\n[synth]\n{synth}\n"),
        )
        .unwrap();
    };
    // TOML's inf: was copied into the plan's study.toml and into every recording
    study("inf.toml", "pre_trigger_s = inf");
    refused_with(
        &run(&["plan", "--study", "inf.toml", "--out", "p"], p),
        &["inf.toml", "synth.pre_trigger_s = inf", "finite"],
    );
    // a negative noise: was NaN in every trigger sample
    study("noise.toml", "trigger_noise_v = -1e308");
    refused_with(
        &run(&["synth", "--study", "noise.toml", "--out", "s"], p),
        &["trigger_noise_v must be ≥ 0, got -1e308"],
    );
    // a terahertz rig: was an allocation of hundreds of terabytes
    study("rate.toml", "sample_rate_hz = 1e12");
    refused_with(
        &run(&["synth", "--study", "rate.toml", "--out", "s"], p),
        &["sample_rate_hz = 1e12", "samples, more than 2e7"],
    );
    assert!(!p.join("s").exists() && !p.join("p").exists());
}

#[test]
fn cutting_set_ups_that_would_not_fit_or_not_end_are_refused() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    coarse_config(p, None);
    let base = std::fs::read_to_string(p.join("cut.toml")).unwrap();
    let with = |name: &str, key: &str, value: &str| {
        let text: String = base
            .lines()
            .map(|l| {
                if l.starts_with(&format!("{key} =")) {
                    format!("{key} = {value}\n")
                } else {
                    format!("{l}\n")
                }
            })
            .collect();
        assert!(
            text.contains(&format!("{key} = {value}")),
            "{key} not in the set-up"
        );
        std::fs::write(p.join(name), text).unwrap();
    };
    // windows of 1e-308 m: was a vector of 10³⁰⁰ windows
    with("w.toml", "window_length_m", "1e-308");
    refused_with(
        &run(
            &["simulate", "cutting", "--config", "w.toml", "--out", "o"],
            p,
        ),
        &[
            "w.toml",
            "window_length_m = 1e-308",
            "more than 1e5 windows",
        ],
    );
    // a 300 km flank: the same, by the tool's length
    with("f.toml", "flank_length_m", "3.0e5");
    refused_with(
        &run(
            &["simulate", "cutting", "--config", "f.toml", "--out", "o"],
            p,
        ),
        &["f.toml", "more than 1e5 windows"],
    );
    // 2.5 µm/s where 2.5 m/s was meant: was a run of months
    with("v.toml", "cutting_speed_m_s", "2.5e-6");
    refused_with(
        &run(
            &["simulate", "cutting", "--config", "v.toml", "--out", "o"],
            p,
        ),
        &["time steps", "numerics.max_steps", "cutting_speed_m_s"],
    );
    // a thermal tool 0.1 m in edge radius: was a grid of gigabytes
    let thermal = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../examples/iwf-ti64-thermal-tool.toml"
    ))
    .unwrap()
    .replace("edge_radius_m = 5.0e-6", "edge_radius_m = 0.1")
    .replace("window_length_m = 1.0e-5", "window_length_m = 1.0e-3");
    assert!(thermal.contains("edge_radius_m = 0.1") && thermal.contains("[tool_thermal]"));
    std::fs::write(p.join("t.toml"), thermal).unwrap();
    refused_with(
        &run(
            &["simulate", "cutting", "--config", "t.toml", "--out", "o"],
            p,
        ),
        &["t.toml", "thermal tool's grid", "numerics.max_particles"],
    );
    assert!(!p.join("o").exists());
}

#[test]
fn a_hammer_recording_whose_clock_stands_still_is_refused() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    let mut csv = String::from("time_s,hammer_N,response_m\n");
    for k in 0..2000 {
        csv.push_str(&format!(
            "0,{},{}\n",
            if k == 100 { 50.0 } else { 0.0 },
            1e-9
        ));
    }
    std::fs::write(p.join("h.csv"), csv).unwrap();
    // was: a capacity overflow panic (an infinite sample rate sized the FFT block)
    refused_with(
        &run(
            &[
                "characterize",
                "--recording",
                "h.csv",
                "--response",
                "response_m",
                "--out",
                "c",
            ],
            p,
        ),
        &["h.csv", "the time column 'time_s' must increase"],
    );
}

/// A two-load, three-speed campaign of half-second dwells (seconds to synthesise).
const SMALL_STUDY: &str = "[plan]\nnormal_force_min_N = 150.0\nnormal_force_max_N = 2000.0\n\
normal_force_count = 2\nvelocity_min_m_per_min = 20.0\nvelocity_max_m_per_min = 250.0\n\
velocity_count = 3\ndwell_s = 0.5\ntrack_radius_mm = 100.0\n";

#[test]
fn settings_that_combine_into_infinity_or_nothing_are_refused() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    // a ground truth whose velocity exponent is 10¹¹: was ∞ in every recording, exit 0
    std::fs::write(
        p.join("exp.toml"),
        format!("{SMALL_STUDY}[synth.ground_truth]\nvelocity_exponent = 1.9e11\n"),
    )
    .unwrap();
    refused_with(
        &run(&["synth", "--study", "exp.toml", "--out", "s"], p),
        &["tangential force is inf", "[synth.ground_truth]"],
    );
    assert!(!p.join("s").exists());
    // an end margin longer than the dwell: was an index past the step's window (a panic)
    std::fs::write(p.join("ok.toml"), SMALL_STUDY).unwrap();
    common::ok(&run(&["synth", "--study", "ok.toml", "--out", "rec"], p));
    std::fs::write(
        p.join("margin.toml"),
        format!("{SMALL_STUDY}[identify]\nend_margin_s = 2.0\n"),
    )
    .unwrap();
    refused_with(
        &run(
            &[
                "identify",
                "--study",
                "margin.toml",
                "--recordings",
                "rec/pin01.csv",
                "rec/pin02.csv",
                "--out",
                "d.csv",
            ],
            p,
        ),
        &["pin01.csv", "end_margin_s (2 s) leave nothing"],
    );
    assert!(!p.join("d.csv").exists());
}

#[test]
fn a_rig_export_with_an_overflowing_speed_writes_no_dataset() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    // the fuzz campaign's reduced mutant of examples/foreign-rig/rotary-export.csv: 91 of
    // its rows, the steady speeds of step 1 set to 10³⁰⁸ rpm (finite, but not in m/min)
    let mutant = include_str!("fixtures/rotary-rpm-1e308.csv");
    assert!(mutant.contains(",1e308,"));
    std::fs::write(p.join("r.csv"), mutant).unwrap();
    // was: sliding_velocity_m_per_min = inf in the dataset, exit 0; the step at 10³⁰⁸ rpm is
    // now the only one sliding (every other is at rest beside it) and is refused as beyond
    // physics, naming the file, the channel and the likely unit mistake
    refused_with(
        &run(
            &[
                "identify",
                "--no-plan",
                "--recordings",
                "r.csv",
                "--track-radii-mm",
                "10",
                "--out",
                "d.csv",
            ],
            p,
        ),
        &["r.csv", "speed", "beyond any tribometer", "unit"],
    );
    assert!(!p.join("d.csv").exists());
}
