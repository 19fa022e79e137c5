//! `greybox report` on hostile study directories (issue 30): each case runs the binary under
//! a memory and a wall-clock limit. SVGs that would run script are rebuilt without it; link
//! loops, FIFOs, devices and huge (sparse) files are bounded or skipped with a warning that
//! names the cap; an `--out` that is one of the files read, or under /dev, is refused with
//! nothing written.
mod common;
use common::{greybox_limited, refused_with, study, PLOT};
use std::path::Path;
use std::process::Output;

/// Address-space limit for every run (MiB) and wall-clock limit (s).
const MEMORY_MIB: u64 = 1024;
const SECONDS: u64 = 60;
/// Every page here is small: a few figures and tables.
const PAGE_LIMIT: usize = 2 << 20;

/// The run succeeded by itself (not killed by a limit); returns the JSON summary.
fn report_ok(out: &Output) -> serde_json::Value {
    use std::os::unix::process::ExitStatusExt;
    assert!(
        out.status.success() && out.status.signal().is_none(),
        "status {:?}, stderr: {}",
        out.status,
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("JSON summary")
}

fn run(args: &[&str], cwd: &Path) -> Output {
    greybox_limited(args, cwd, MEMORY_MIB, SECONDS)
}

fn warnings(summary: &serde_json::Value) -> String {
    summary["warnings"]
        .as_array()
        .unwrap()
        .iter()
        .map(|w| w.as_str().unwrap().to_string())
        .collect::<Vec<_>>()
        .join("\n")
}

/// The page is bounded, and holds one script (the page's own) and no event-handler
/// attribute on any element.
fn page_is_inert(page: &Path) -> String {
    let html = std::fs::read_to_string(page).unwrap();
    assert!(html.len() < PAGE_LIMIT, "page of {} bytes", html.len());
    assert_eq!(html.matches("<script").count(), 1, "scripts in the page");
    let doc = scraper::Html::parse_document(&html);
    let all = scraper::Selector::parse("*").unwrap();
    for el in doc.select(&all) {
        for (name, value) in el.value().attrs() {
            assert!(
                !name.to_ascii_lowercase().starts_with("on"),
                "{name}={value}"
            );
            assert!(
                !value.to_ascii_lowercase().contains("javascript:"),
                "{name}={value}"
            );
        }
    }
    // inside figures: only drawing elements, and links only within the figure or to
    // embedded images
    let in_svg = scraper::Selector::parse("svg *").unwrap();
    for el in doc.select(&in_svg) {
        let tag = el.value().name().to_ascii_lowercase();
        for bad in [
            "foreignobject",
            "iframe",
            "img",
            "style",
            "script",
            "a",
            "animate",
            "set",
        ] {
            assert!(tag != bad, "<{tag}> in a figure");
        }
        if let Some(h) = el.value().attr("href") {
            assert!(
                h.starts_with('#') || h.starts_with("data:image/png;base64,"),
                "href={h}"
            );
        }
    }
    let script = scraper::Selector::parse("script").unwrap();
    let own = doc.select(&script).next().unwrap().inner_html();
    assert!(
        own.contains("figure.frames"),
        "the page's own script: {own}"
    );
    html
}

#[test]
fn svgs_with_scripts_are_rebuilt_without_them_and_the_removal_is_reported() {
    let d = tempfile::tempdir().unwrap();
    let s = study(d.path());
    let hostile = [
        r#"<svg xmlns="http://www.w3.org/2000/svg" onload="window.pwned=1"><script>window.pwned=1</script><rect width="10" height="10"/></svg>"#,
        r#"<svg xmlns="http://www.w3.org/2000/svg"><foreignObject width="10" height="10"><img xmlns="http://www.w3.org/1999/xhtml" src="x" onerror="window.pwned=1"/></foreignObject></svg>"#,
        r#"<svg xmlns="http://www.w3.org/2000/svg" xmlns:xlink="http://www.w3.org/1999/xlink"><a xlink:href="javascript:window.pwned=1"><text>click</text></a><use href="http://evil.example/x.svg#a"/></svg>"#,
        r#"<svg xmlns="http://www.w3.org/2000/svg"><style>rect { fill: url(javascript:alert(1)) }</style><rect style="fill: url(javascript:x)"/></svg>"#,
        r#"<?xml version="1.0"?><!DOCTYPE svg [<!ENTITY x "&#60;script&#62;window.pwned=1&#60;/script&#62;">]><?xml-stylesheet href="http://evil.example/s.css"?><svg xmlns="http://www.w3.org/2000/svg"><text>&x;</text><script><![CDATA[window.pwned=1]]></script></svg>"#,
    ];
    let names = [
        "forces.svg",
        "profile_stress.svg",
        "profile_velocity.svg",
        "profile_temperature.svg",
        "chip_temperature.svg",
    ];
    for (n, svg) in names.iter().zip(hostile) {
        std::fs::write(s.join("cut").join(n), svg).unwrap();
    }
    std::fs::write(s.join("cut/frames/chip_002.svg"), hostile[0]).unwrap();
    let summary = report_ok(&run(&["report", "study", "--json"], d.path()));
    let w = warnings(&summary);
    for n in names {
        assert!(
            w.contains(&format!("elements/attributes removed from cut/{n}")),
            "{n}: {w}"
        );
    }
    assert!(w.contains("removed from cut/frames/chip_002.svg"), "{w}");
    let html = page_is_inert(&s.join("report.html"));
    assert!(html.contains("Content-Security-Policy"));
    assert!(!html.contains("pwned=1\""), "a handler survived");
    // the safe figures are still there: the force plot's line, the three frames
    assert_eq!(html.matches("<div class=\"frame\"").count(), 3);
    assert!(html.contains("points=\"0,0 100,50 200,20\""));
}

#[test]
fn link_loops_are_searched_once() {
    let d = tempfile::tempdir().unwrap();
    let s = study(d.path());
    for k in 0..12 {
        std::os::unix::fs::symlink(".", s.join(format!("l{k}"))).unwrap();
        std::os::unix::fs::symlink("..", s.join(format!("cut/up{k}"))).unwrap();
    }
    let summary = report_ok(&run(&["report", "study", "--json"], d.path()));
    assert_eq!(
        summary["sections"],
        serde_json::json!(["Cutting", "Rig dynamics and wear"])
    );
    page_is_inert(&s.join("report.html"));
    // the depth and entry caps hold without links too, and name their option
    let deep = s.join("a/b/c/d/e/f/g/h");
    std::fs::create_dir_all(&deep).unwrap();
    let summary = report_ok(&run(
        &[
            "report",
            "study",
            "--json",
            "--max-depth",
            "2",
            "--max-entries",
            "30",
        ],
        d.path(),
    ));
    let w = warnings(&summary);
    assert!(
        w.contains("max_depth (2)") && w.contains("raise max_depth"),
        "{w}"
    );
    assert!(
        w.contains("max_entries") && w.contains("raise it with `max_entries`"),
        "{w}"
    );
}

#[test]
fn fifos_and_devices_are_never_opened() {
    let d = tempfile::tempdir().unwrap();
    let s = study(d.path());
    std::fs::create_dir(s.join("cut2")).unwrap();
    for f in ["x.csv", "cut2/summary.json", "law.json"] {
        let st = std::process::Command::new("mkfifo")
            .arg(s.join(f))
            .status()
            .unwrap();
        assert!(st.success());
    }
    std::os::unix::fs::symlink("/dev/zero", s.join("zero.csv")).unwrap();
    std::os::unix::fs::symlink("/dev/zero", s.join("zero.json")).unwrap();
    std::fs::remove_file(s.join("cut/profile_mu.svg")).ok();
    std::os::unix::fs::symlink("/dev/zero", s.join("cut/profile_mu.svg")).unwrap();
    std::os::unix::fs::symlink("/dev/zero", s.join("cut/frames/chip_004.svg")).unwrap();
    let summary = report_ok(&run(&["report", "study", "--json"], d.path()));
    let w = warnings(&summary);
    for f in ["x.csv", "cut2/summary.json", "law.json"] {
        assert!(
            w.contains(&format!("{f}: a FIFO, not a regular file")),
            "{f}: {w}"
        );
    }
    for f in [
        "zero.csv",
        "zero.json",
        "cut/profile_mu.svg",
        "chip_004.svg",
    ] {
        assert!(
            w.contains(f) && w.contains("a character device"),
            "{f}: {w}"
        );
    }
    page_is_inert(&s.join("report.html"));
}

#[test]
fn huge_files_are_read_within_their_caps() {
    let d = tempfile::tempdir().unwrap();
    let s = study(d.path());
    // a 2 GB sparse CSV (no line end in its first bytes), a dataset whose header is fine
    // but whose body is 2 GB, and a 1 GB SVG
    std::fs::File::create(s.join("big.csv"))
        .unwrap()
        .set_len(2 << 30)
        .unwrap();
    let ds = s.join("dataset.csv");
    std::fs::write(&ds, "pin,cof_apparent\n").unwrap();
    std::fs::OpenOptions::new()
        .write(true)
        .open(&ds)
        .unwrap()
        .set_len(2 << 30)
        .unwrap();
    std::fs::File::create(s.join("cut/profile_mu.svg"))
        .unwrap()
        .set_len(1 << 30)
        .unwrap();
    let summary = report_ok(&run(&["report", "study", "--json"], d.path()));
    let w = warnings(&summary);
    assert!(
        w.contains("big.csv") && w.contains("max_header_bytes") && w.contains("`max_header_bytes`"),
        "{w}"
    );
    assert!(
        w.contains("dataset.csv")
            && w.contains("over max_file_bytes")
            && w.contains("`max_file_bytes`"),
        "{w}"
    );
    assert!(
        w.contains("profile_mu.svg")
            && w.contains("over max_svg_bytes")
            && w.contains("`max_svg_bytes`"),
        "{w}"
    );
    page_is_inert(&s.join("report.html"));

    // the page cap: figures past it are left out with a warning; a page still over it is
    // refused and nothing is written
    std::fs::remove_file(s.join("report.html")).unwrap();
    let points: Vec<String> = (0..10000).map(|k| format!("{k},{}", k % 97)).collect();
    let big_plot = PLOT.replace("0,0 100,50 200,20", &points.join(" "));
    std::fs::write(s.join("cut/forces.svg"), big_plot).unwrap();
    let summary = report_ok(&run(
        &["report", "study", "--json", "--max-page-bytes", "40000"],
        d.path(),
    ));
    let w = warnings(&summary);
    assert!(
        w.contains("cut/forces.svg")
            && w.contains("left out")
            && w.contains("max_page_bytes")
            && w.contains("`max_page_bytes`"),
        "{w}"
    );
    assert!(summary["bytes"].as_u64().unwrap() <= 40000);
    std::fs::remove_file(s.join("report.html")).unwrap();
    let out = run(&["report", "study", "--max-page-bytes", "2000"], d.path());
    refused_with(
        &out,
        &["max_page_bytes", "--max-page-bytes", "nothing written"],
    );
    assert!(!s.join("report.html").exists());
}

#[test]
fn an_out_that_is_a_file_the_report_reads_or_a_device_is_refused() {
    let d = tempfile::tempdir().unwrap();
    let s = study(d.path());
    let before = |p: &str| std::fs::read(s.join(p)).unwrap();
    for (target, kept) in [
        ("study/wear.csv", "wear.csv"),
        ("study/cut/summary.json", "cut/summary.json"),
        ("study/cut/forces.svg", "cut/forces.svg"),
        ("study/./cut/../wear.csv", "wear.csv"),
    ] {
        let was = before(kept);
        let out = run(&["report", "study", "--out", target], d.path());
        refused_with(&out, &["out is the input", "destroy the input"]);
        assert_eq!(before(kept), was, "{kept} changed");
    }
    for dev in [
        "/dev/null",
        "/dev/stdout",
        "/dev/shm/greybox-report-test.html",
    ] {
        let out = run(&["report", "study", "--out", dev], d.path());
        refused_with(&out, &["under /dev"]);
    }
    assert!(!Path::new("/dev/shm/greybox-report-test.html").exists());
    assert!(
        !s.join("report.html").exists(),
        "nothing written on refusals"
    );
    // a hard link to an input is the input
    std::fs::hard_link(s.join("wear.csv"), d.path().join("linked.csv")).unwrap();
    let out = run(&["report", "study", "--out", "linked.csv"], d.path());
    refused_with(&out, &["out is the input"]);
    // an ordinary output still works
    report_ok(&run(
        &["report", "study", "--json", "--out", "page.html"],
        d.path(),
    ));
    assert!(d.path().join("page.html").is_file());
}
