//! One task through the command line and through the library gives the same bytes: the
//! options and their defaults are the library's, the CLI only overrides fields. (The Python
//! side of the same comparison is `crates/greybox-py/tests/test_surfaces_agree.py`.)

mod common;

use common::{err, greybox, ok};
use greybox_core::choice::Choice;
use greybox_friction::export::engine::{ExportFormat, ObjectPair};
use greybox_pipeline::export::{export, AxisValues, ExportOptions, ExportOverrides};
use std::path::Path;

/// A law that depends on pressure (Usui–Childs: the friction stress saturates at m·k).
fn setup() -> tempfile::TempDir {
    greybox_testkit::law::law_dir(greybox_testkit::law::USUI_CHILDS)
}

fn read(p: &Path) -> Vec<u8> {
    std::fs::read(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

#[test]
fn every_format_with_default_options_is_the_same_file_from_the_cli_and_the_library() {
    let d = setup();
    let p = d.path();
    for &format in ExportFormat::ALL {
        let name = format.name();
        let cli = format!("cli.{name}");
        ok(&greybox(
            &[
                "export", "--law", "law.json", "--format", name, "--out", &cli,
            ],
            p,
        ));
        let lib = p.join(format!("lib.{name}"));
        export(&ExportOptions::new(p.join("law.json"), format, lib.clone())).unwrap();
        let (a, b) = (read(&p.join(&cli)), read(&lib));
        assert!(!a.is_empty());
        assert!(
            a == b,
            "{name}: the CLI and the library wrote different tables"
        );
    }
}

/// The CLI with `flags` and the library with `overrides` write the same `format` file.
fn same_file(format: ExportFormat, flags: &[&str], overrides: ExportOverrides) -> String {
    let d = setup();
    let p = d.path();
    let mut args = vec![
        "export",
        "--law",
        "law.json",
        "--format",
        format.name(),
        "--out",
        "cli.out",
    ];
    args.extend_from_slice(flags);
    ok(&greybox(&args, p));
    let o = ExportOptions::new(p.join("law.json"), format, p.join("lib.out"))
        .overridden(&overrides)
        .unwrap();
    export(&o).unwrap();
    let cli = read(&p.join("cli.out"));
    assert!(
        cli == read(&p.join("lib.out")),
        "{}: {flags:?}",
        format.name()
    );
    String::from_utf8(cli).unwrap()
}

#[test]
fn overrides_in_the_clis_units_give_the_librarys_si_options() {
    let grid = ExportOverrides {
        pressure_Pa: Some(AxisValues(vec![100e6, 300e6, 500e6, 700e6, 900e6])),
        velocity_m_per_s: Some(AxisValues(vec![0.5, 1.0, 2.0])),
        ..Default::default()
    };
    let grid_flags = [
        "--pressure-MPa",
        "100:900:5",
        "--velocity-m-per-min",
        "30,60,120",
    ];
    let mut flags = grid_flags.to_vec();
    flags.extend(["--units", "Pa-m-s", "--lsdyna-table-id", "7"]);
    let text = same_file(
        ExportFormat::Lsdyna,
        &flags,
        ExportOverrides {
            units: Some("Pa-m-s".parse().unwrap()),
            lsdyna_table_id: Some(7),
            ..grid.clone()
        },
    );
    assert!(text.contains("Pa") && text.contains("m/s"), "{text}");
    let mut flags = grid_flags.to_vec();
    flags.extend([
        "--temperature-K",
        "300,600",
        "--taumax-MPa",
        "350",
        "--temperature-unit",
        "K",
    ]);
    let text = same_file(
        ExportFormat::Abaqus,
        &flags,
        ExportOverrides {
            temperature_K: Some(AxisValues(vec![300.0, 600.0])),
            taumax_Pa: Some(350e6),
            temperature_unit: Some("K".parse().unwrap()),
            ..grid.clone()
        },
    );
    assert!(text.contains("TAUMAX=350"), "{text}");
    same_file(
        ExportFormat::Deform,
        &[
            "--deform-reference-velocity-m-per-min",
            "90",
            "--deform-objects",
            "3,4",
        ],
        ExportOverrides {
            deform_reference_velocity_m_per_s: Some(1.5),
            deform_objects: Some(ObjectPair([3, 4])),
            ..Default::default()
        },
    );
}

#[test]
fn the_json_report_is_the_librarys_report() {
    let d = setup();
    let out = ok(&greybox(
        &[
            "export", "--law", "law.json", "--format", "csv", "--out", "t.csv", "--json",
        ],
        d.path(),
    ));
    let v: serde_json::Value = serde_json::from_str(&out).expect("JSON on stdout");
    assert_eq!(v["shape"], serde_json::json!([30, 21, 1]));
    assert!(v["max_deviation"].as_f64().is_some());
    assert_eq!(
        v["bytes"].as_u64().unwrap(),
        read(&d.path().join("t.csv")).len() as u64
    );
}

#[test]
fn an_option_of_another_engine_is_refused_naming_it() {
    let d = setup();
    let e = err(&greybox(
        &[
            "export",
            "--law",
            "law.json",
            "--format",
            "abaqus",
            "--out",
            "a.inp",
            "--lsdyna-table-id",
            "3",
        ],
        d.path(),
    ));
    assert!(
        // the library's `export.lsdyna_table_id`, shown as the flag
        e.contains("--lsdyna-table-id: not an option of the abaqus export"),
        "{e}"
    );
    assert!(!d.path().join("a.inp").exists());
}

#[test]
fn a_table_over_the_size_budget_is_refused_with_its_size_for_every_format() {
    let d = setup();
    for &format in ExportFormat::ALL {
        let out = format!("big.{}", format.name());
        let e = err(&greybox(
            &[
                "export",
                "--law",
                "law.json",
                "--format",
                format.name(),
                "--out",
                &out,
                "--max-table-size",
                "100",
            ],
            d.path(),
        ));
        assert!(
            e.contains("--max-table-size") && (e.contains("values") || e.contains("nodes")),
            "{}: {e}",
            format.name()
        );
        assert!(!d.path().join(&out).exists());
    }
}

#[test]
fn unknown_values_list_the_choices() {
    let d = setup();
    let e = err(&greybox(
        &[
            "export", "--law", "law.json", "--format", "abaqus", "--out", "a.inp", "--units",
            "MPa-m-s",
        ],
        d.path(),
    ));
    assert!(e.contains("MPa-mm-s") && e.contains("Pa-m-s"), "{e}");
}
