//! The demo never changes the process's working directory, and what its outputs record
//! holds after its directory is moved: no provenance record names the staging directory,
//! and the report over the moved directory finds the same sections.

use greybox_core::provenance::Provenance;
use greybox_report::report::{report, ReportOptions};
use greybox_testkit::files::files_under;
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};

#[test]
fn demo_keeps_the_cwd_and_its_directory_is_relocatable() {
    let d = tempfile::tempdir().unwrap();
    let out = d.path().join("demo");
    let cwd = std::env::current_dir().unwrap();
    // the demo runs in a thread while this one watches the (process-wide) working directory
    let done = AtomicBool::new(false);
    let demo = std::thread::scope(|s| {
        let run = s.spawn(|| {
            let r = greybox_report::demo::run(&out, false);
            done.store(true, Ordering::SeqCst);
            r
        });
        while !done.load(Ordering::SeqCst) {
            assert_eq!(
                std::env::current_dir().unwrap(),
                cwd,
                "the demo changed the cwd"
            );
            std::thread::sleep(std::time::Duration::from_millis(5));
        }
        run.join().unwrap()
    })
    .unwrap();
    assert_eq!(std::env::current_dir().unwrap(), cwd);
    // the summary's paths are relative to the demo's directory
    assert_eq!(demo.summary.identify.dataset, "dataset.csv");
    assert_eq!(demo.summary.law, "law.json");
    assert!(demo.paths.law.is_relative() && demo.paths.cutting.is_relative());
    for f in demo
        .summary
        .fit_outputs
        .models
        .iter()
        .chain(&demo.summary.cutting.files)
        .chain(&demo.summary.dynamics.files)
        .chain(&demo.summary.synth.files)
    {
        assert!(Path::new(f).is_relative(), "{f}");
        assert!(out.join(f).is_file(), "{f}");
    }
    assert!(
        !demo.export_line.contains("greybox-staging"),
        "{}",
        demo.export_line
    );

    // nothing the demo wrote names its staging directory or any absolute path in it
    let parent = d.path().display().to_string();
    let mut records = 0;
    for f in files_under(&out) {
        let name = f.file_name().unwrap().to_string_lossy().into_owned();
        if name == "provenance.json" || name.ends_with(".provenance.json") {
            records += 1;
            for input in Provenance::read(&f).unwrap().inputs {
                let p = Path::new(&input.path);
                assert!(p.is_relative(), "{}: {}", f.display(), input.path);
                assert!(out.join(p).is_file(), "{}: {}", f.display(), input.path);
            }
        }
        if let Ok(text) = std::fs::read_to_string(&f) {
            // the report page names the directory it was made for (`out`), by design
            let absolute = if name == "report.html" {
                None
            } else {
                text.find(&parent)
            };
            if let Some(at) = text.find("greybox-staging").or(absolute) {
                let around: String = text[at.saturating_sub(80)..].chars().take(200).collect();
                panic!("{} names the staging directory: …{around}…", f.display());
            }
        }
    }
    assert!(records >= 8, "{records} provenance records");

    // moved elsewhere, the directory still makes the same report
    let moved = d.path().join("elsewhere").join("moved-demo");
    std::fs::create_dir_all(moved.parent().unwrap()).unwrap();
    std::fs::rename(&out, &moved).unwrap();
    let again = report(&ReportOptions::new(&moved)).unwrap();
    assert_eq!(again.sections, demo.summary.report.sections);
    assert_eq!(again.figures, demo.summary.report.figures);
    assert_eq!(again.warnings, demo.summary.report.warnings);
    assert!(again.sections.len() >= 5, "{:?}", again.sections);
}
