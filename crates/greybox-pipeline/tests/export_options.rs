//! The export options the library owns: the documented defaults, each engine's own options,
//! validation that names the option, and the table-size budget, tested without the CLI.

use greybox_core::choice::Choice;
use greybox_friction::export::engine::{Engine, ExportFormat};
use greybox_pipeline::export::{export, ExportOptions, ExportOverrides};

use greybox_testkit::law::{law_dir, ZOREV};

#[test]
fn the_documented_defaults_are_the_libraries() {
    let o = |f| ExportOptions::new("l".into(), f, "o".into());
    match o(ExportFormat::Deform).table.into_inner().engine {
        Engine::Deform {
            reference_velocity_m_s,
            objects,
            windows,
        } => {
            assert_eq!(reference_velocity_m_s * 60.0, 150.0); // m/min
            assert_eq!(objects, (2, 1));
            assert!(windows.is_none());
        }
        e => panic!("{e:?}"),
    }
    assert_eq!(
        o(ExportFormat::Lsdyna).table.engine.lsdyna_table_id(),
        Some(1000)
    );
    let u = o(ExportFormat::Abaqus).table.engine.units().unwrap();
    assert_eq!((u.pressure.name(), u.speed.name()), ("MPa", "mm/s"));
    let g = o(ExportFormat::Csv).table.into_inner().grid;
    assert_eq!((g.pressure_pa[0], g.pressure_pa[20]), (500e6, 2500e6));
    assert_eq!(
        (g.velocity_m_s[0] * 60.0, g.velocity_m_s[29] * 60.0),
        (10.0, 300.0)
    );
}

#[test]
fn every_format_name_parses_back_and_unknown_ones_list_the_values() {
    for &f in ExportFormat::ALL {
        assert_eq!(f.name().parse::<ExportFormat>().unwrap(), f);
    }
    let e = "ansys".parse::<ExportFormat>().unwrap_err().to_string();
    assert_eq!(
        e,
        "export.format: 'ansys' is not one of abaqus, deform, lsdyna, csv, table"
    );
}

#[test]
fn validation_names_the_option() {
    let base = ExportOptions::new("l".into(), ExportFormat::Deform, "o".into());
    let bad = |o: ExportOverrides| base.clone().overridden(&o).unwrap_err().to_string();
    let e = bad(ExportOverrides {
        deform_reference_velocity_m_per_s: Some(-1.0),
        ..Default::default()
    });
    assert!(
        e.contains("export.deform_reference_velocity_m_per_s"),
        "{e}"
    );
    let e = bad(ExportOverrides {
        tolerance: Some(0.0),
        ..Default::default()
    });
    assert!(e.contains("export.tolerance"), "{e}");
    let e = bad(ExportOverrides {
        units: Some("Pa-m-s".parse().unwrap()),
        ..Default::default()
    });
    assert!(e.contains("export.units") && e.contains("deform"), "{e}");
    let e = ExportOverrides::from_json(r#"{"speed_unit": "m/s"}"#).unwrap_err();
    assert!(format!("{e:#}").contains("speed_unit"), "{e:#}");
}

#[test]
fn the_size_budget_refuses_before_writing_and_a_fitting_table_is_written() {
    let d = law_dir(ZOREV);
    let law = d.path().join("law.json");
    let out = d.path().join("t.inp");
    let o = ExportOptions::new(law.clone(), ExportFormat::Abaqus, out.clone())
        .overridden(&ExportOverrides {
            max_table_size: Some(greybox_friction::export::engine::TableSize::of(629)),
            ..Default::default()
        })
        .unwrap();
    let e = export(&o).unwrap_err().to_string();
    assert!(
        e.contains("630 values") && e.contains("export.max_table_size"),
        "{e}"
    );
    assert!(!out.exists());
    let o = o
        .changed(|t| {
            t.max_table_size = greybox_friction::export::engine::TableSize::of(630);
            Ok(())
        })
        .unwrap();
    let r = export(&o).unwrap();
    assert_eq!(r.shape.iter().product::<usize>(), 630);
    assert_eq!(r.bytes as u64, std::fs::metadata(&out).unwrap().len());
    assert!(r.warnings.is_empty());
}
