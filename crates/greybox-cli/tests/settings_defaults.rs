//! The library's settings types carry their defaults once: what clap fills in for an absent
//! flag equals what serde fills in for an absent key (Python's keyword arguments, JSON), so
//! the command line and Python cannot drift apart again.

use clap::Parser;
use greybox_pipeline::export::ExportOverrides;
use greybox_pipeline::settings::{
    adhesive::AdhesiveSettings, couple::CoupleSettings, cut::CutSettings, fit::FitSettings,
    hertz::HertzSettings, identify::IdentifySettings, law::GreyBoxSettings,
    material::FlowCurveSettings, material::RateSensitivitySettings, pin::PinSettings,
    plan::PlanSettings, synth::SynthSettings, windows::WindowsSettings,
};
use greybox_pipeline::settings::{
    characterize::CharacterizeSettings, import::ImportSettings, predict::DomainCheck,
    wear::WearSettings,
};
use greybox_pipeline::simulate::RunOutput;
use greybox_sweep::settings::{CalibrateSettings, ExecutorSettings, ValidateSettings};
use serde::de::DeserializeOwned;
use std::fmt::Debug;

/// `T` parsed from `args` by clap.
fn flags<T: clap::Args + clap::FromArgMatches>(args: &[&str]) -> T {
    #[derive(Parser)]
    struct Wrap<U: clap::Args> {
        #[command(flatten)]
        inner: U,
    }
    let mut all = vec!["greybox"];
    all.extend_from_slice(args);
    Wrap::<T>::try_parse_from(all).unwrap().inner
}

/// `T` from JSON holding only `json`'s keys.
fn keys<T: DeserializeOwned + serde::Serialize>(json: &str) -> T {
    greybox_pipeline::settings::from_json("test", json).unwrap()
}

fn same<T: PartialEq + Debug>(clap: T, serde: T) {
    assert_eq!(clap, serde);
}

#[test]
fn clap_and_serde_fill_in_the_same_defaults() {
    same(
        flags::<AdhesiveSettings>(&["--data", "d.csv"]),
        keys(r#"{"data": "d.csv"}"#),
    );
    same(flags::<PinSettings>(&[]), keys("{}"));
    same(
        flags::<CutSettings>(&["--config", "c.toml"]),
        keys(r#"{"config": "c.toml"}"#),
    );
    same(flags::<CoupleSettings>(&[]), keys("{}"));
    same(flags::<PlanSettings>(&[]), keys("{}"));
    same(flags::<ExecutorSettings>(&[]), keys("{}"));
    same(flags::<ValidateSettings>(&[]), keys("{}"));
    same(
        flags::<CalibrateSettings>(&["--measured", "m.csv"]),
        keys(r#"{"measured": "m.csv"}"#),
    );
    same(
        flags::<FitSettings>(&["--data", "d.csv"]),
        keys(r#"{"data": "d.csv"}"#),
    );
    same(flags::<RunOutput>(&[]), keys("{}"));
    same(
        flags::<IdentifySettings>(&["--recordings", "r.csv"]),
        keys(r#"{"recordings": ["r.csv"]}"#),
    );
    same(flags::<SynthSettings>(&[]), keys("{}"));
    same(
        flags::<HertzSettings>(&["--force-N", "60"]),
        keys(r#"{"force_N": [60]}"#),
    );
    same(
        flags::<GreyBoxSettings>(&["--model", "m.json"]),
        keys(r#"{"model": "m.json"}"#),
    );
    same(flags::<ExportOverrides>(&[]), keys("{}"));
    same(flags::<DomainCheck>(&[]), keys("{}"));
    same(flags::<ImportSettings>(&[]), keys("{}"));
    same(flags::<WearSettings>(&[]), keys("{}"));
    same(
        flags::<CharacterizeSettings>(&["--recording", "h.csv@500"]),
        keys(r#"{"recordings": ["h.csv@500"]}"#),
    );
    same(
        flags::<WindowsSettings>(&["--mesh", "t.msh"]),
        keys(r#"{"mesh": "t.msh"}"#),
    );
    same(
        flags::<FlowCurveSettings>(&["--curves", "c.csv"]),
        keys(r#"{"curves": "c.csv"}"#),
    );
    same(
        flags::<RateSensitivitySettings>(&[
            "--config",
            "c.toml",
            "--measured-force-n-per-mm",
            "250",
        ]),
        keys(r#"{"config": "c.toml", "measured_force_N_per_mm": 250}"#),
    );
}

#[test]
fn a_flag_in_its_edge_unit_sets_the_si_field() {
    same(
        flags::<IdentifySettings>(&[
            "--recordings",
            "r.csv",
            "--constant-sliding-velocity-m-per-min",
            "30",
            "--settle-s",
            "0.5",
            "--test-mode",
            "reciprocating",
            "--normal-force-count",
            "3",
        ]),
        keys(
            r#"{"recordings": ["r.csv"], "constant_sliding_velocity_m_per_s": 0.5,
            "settle_time_s": 0.5, "test_mode": "reciprocating", "normal_force_count": 3}"#,
        ),
    );
    same(
        flags::<ExportOverrides>(&[
            "--pressure-MPa",
            "100,200",
            "--taumax-MPa",
            "350",
            "--deform-reference-velocity-m-per-min",
            "60",
            "--adaptive-grid",
        ]),
        keys(
            r#"{"pressure_Pa": [1e8, 2e8], "taumax_Pa": 3.5e8,
            "deform_reference_velocity_m_per_s": 1.0, "adaptive_grid": true}"#,
        ),
    );
}

#[test]
fn a_flag_and_a_key_of_the_same_name_set_the_same_field() {
    same(
        flags::<PinSettings>(&[
            "--depth-um",
            "5",
            "--speed-m-per-min",
            "60",
            "--mach",
            "0.02",
        ]),
        keys(r#"{"depth_um": 5, "speed_m_per_min": 60, "mach": 0.02}"#),
    );
    same(
        flags::<AdhesiveSettings>(&["--data", "d", "--method", "simulation", "--sim-loads", "2"]),
        keys(r#"{"data": "d", "method": "simulation", "sim_loads": 2}"#),
    );
    same(
        flags::<CoupleSettings>(&["--engine", "command", "--units", "Pa-m-s", "--tol", "0.01"]),
        keys(r#"{"engine": "command", "units": "Pa-m-s", "tol": 0.01}"#),
    );
}
