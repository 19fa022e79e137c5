//! Paths in directories nobody vouches for (issue 46, mechanism 2): a link planted where an
//! output goes, an output directory that holds the working directory, a case id that leads
//! out of its sweep. Each case runs the binary under a memory and a wall-clock limit and
//! checks that it is refused by name and that nothing outside was changed or deleted.
mod common;
use common::{coarse_config, greybox_limited, ok, refused_with, study};
use std::path::Path;
use std::process::Output;

const MIB: u64 = 1024;
const SECONDS: u64 = 60;

fn run(args: &[&str], cwd: &Path) -> Output {
    greybox_limited(args, cwd, MIB, SECONDS)
}

/// A planned (not run) sweep of the coarse cut in `root/o`: two cases.
fn planned_sweep(root: &Path) {
    coarse_config(root, None);
    std::fs::write(
        root.join("sweep.toml"),
        "[sweep]\nkind = \"cutting\"\nbase = \"cut.toml\"\nfraction = 0.4\n[[axis]]\nfield = \"insert.rake_deg\"\nvalues = [0.0, 6.0]\n",
    )
    .unwrap();
    ok(&run(&["sweep", "plan", "sweep.toml", "--out", "o"], root));
}

/// `root/outside.txt` holding `precious`, and a link to it at `link`.
fn plant(root: &Path, link: &Path) -> std::path::PathBuf {
    let outside = root.join("outside.txt");
    std::fs::write(&outside, "precious").unwrap();
    std::os::unix::fs::symlink(&outside, link).unwrap();
    outside
}

fn assert_kept(outside: &Path, link: &Path) {
    assert_eq!(std::fs::read_to_string(outside).unwrap(), "precious");
    assert!(std::fs::symlink_metadata(link)
        .unwrap()
        .file_type()
        .is_symlink());
}

/// `greybox report STUDY` with a link at `STUDY/report.html` to a file outside the study:
/// the page replaced the file the link points to.
#[test]
fn a_link_planted_at_report_html_is_refused() {
    let d = tempfile::tempdir().unwrap();
    let s = study(d.path());
    let link = s.join("report.html");
    let outside = plant(d.path(), &link);
    refused_with(
        &run(&["report", "study", "--json"], d.path()),
        &["report.html", "symbolic link"],
    );
    assert_kept(&outside, &link);
    // the same through --out
    refused_with(
        &run(
            &["report", "study", "--out", "study/report.html", "--json"],
            d.path(),
        ),
        &["symbolic link"],
    );
    assert_kept(&outside, &link);
    // a dangling link creates nothing where it points
    std::fs::remove_file(&link).unwrap();
    std::os::unix::fs::symlink(d.path().join("made-outside.html"), &link).unwrap();
    refused_with(&run(&["report", "study"], d.path()), &["symbolic link"]);
    assert!(!d.path().join("made-outside.html").exists());
}

/// `greybox sweep collect DIR` with a link at `DIR/results.csv` (or `DIR/plan.json` for
/// `sweep plan`) to a file outside the sweep.
#[test]
fn a_link_planted_at_results_csv_or_plan_json_is_refused() {
    let d = tempfile::tempdir().unwrap();
    planned_sweep(d.path());
    let link = d.path().join("o/results.csv");
    let outside = plant(d.path(), &link);
    refused_with(
        &run(&["sweep", "collect", "o"], d.path()),
        &["results.csv", "symbolic link"],
    );
    assert_kept(&outside, &link);
    let plan = d.path().join("o/plan.json");
    std::fs::remove_file(&plan).unwrap();
    std::os::unix::fs::symlink(&outside, &plan).unwrap();
    refused_with(
        &run(&["sweep", "plan", "sweep.toml", "--out", "o"], d.path()),
        &["plan.json", "symbolic link"],
    );
    assert_kept(&outside, &plan);
}

/// `greybox plan --out "$PWD" --force` (or `..`, `../proj`, `.`): the working directory was
/// replaced whole, its files deleted.
#[test]
fn force_never_replaces_the_working_directory_or_an_ancestor() {
    let d = tempfile::tempdir().unwrap();
    let proj = d.path().join("proj");
    std::fs::create_dir(&proj).unwrap();
    std::fs::write(proj.join("keep.txt"), "my work").unwrap();
    std::fs::write(d.path().join("beside.txt"), "mine too").unwrap();
    let here = proj.display().to_string();
    let parent = d.path().display().to_string();
    for out in [here.as_str(), ".", "..", "../proj", parent.as_str(), "/"] {
        let e = refused_with(
            &run(
                &["plan", "--track-radius-mm", "120", "--out", out, "--force"],
                &proj,
            ),
            &["out"],
        );
        assert!(
            e.contains("working directory") || e.contains("needs a name"),
            "--out {out}: {e}"
        );
        assert_eq!(
            std::fs::read_to_string(proj.join("keep.txt")).unwrap(),
            "my work"
        );
        assert_eq!(
            std::fs::read_to_string(d.path().join("beside.txt")).unwrap(),
            "mine too"
        );
        assert_eq!(std::fs::read_dir(&proj).unwrap().count(), 1, "--out {out}");
        assert_eq!(
            std::fs::read_dir(d.path()).unwrap().count(),
            2,
            "--out {out}"
        );
    }
    // the user's home (and an ancestor of it), from elsewhere
    let home = d.path().join("home");
    std::fs::create_dir(&home).unwrap();
    std::fs::write(home.join(".profile"), "settings").unwrap();
    let out = std::process::Command::new("timeout")
        .args(["--signal=KILL", "60"])
        .arg(env!("CARGO_BIN_EXE_greybox"))
        .args(["plan", "--track-radius-mm", "120", "--force", "--out"])
        .arg(&home)
        .env("HOME", &home)
        .current_dir(&proj)
        .output()
        .unwrap();
    refused_with(&out, &["home directory"]);
    assert_eq!(
        std::fs::read_to_string(home.join(".profile")).unwrap(),
        "settings"
    );
    // a new directory beside them is written as before
    ok(&run(
        &["plan", "--track-radius-mm", "120", "--out", "../plan"],
        &proj,
    ));
    assert!(d.path().join("plan/run_sheet.csv").is_file());
}

/// A case id `../../victim` in a sweep's `plan.json`: `sweep run-case` read and wrote
/// outside the sweep (`o/cases/../../victim` is the sweep's parent's `victim`).
#[test]
fn a_case_id_that_leaves_the_sweep_is_refused() {
    let d = tempfile::tempdir().unwrap();
    planned_sweep(d.path());
    let plan_path = d.path().join("o/plan.json");
    let mut plan: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&plan_path).unwrap()).unwrap();
    let victim = d.path().join("victim");
    std::fs::create_dir(&victim).unwrap();
    std::fs::write(victim.join("config.toml"), "mu = 0.3\n").unwrap();
    let own_id = plan["cases"][0]["id"].clone();
    for (k, bad) in ["../../victim", "/tmp", "a/b", "..", ""].iter().enumerate() {
        plan["cases"][0]["id"] = serde_json::json!(bad);
        std::fs::write(&plan_path, serde_json::to_string_pretty(&plan).unwrap()).unwrap();
        for args in [
            &["sweep", "run-case", "o", "--index", "0"][..],
            &["sweep", "collect", "o"][..],
        ] {
            refused_with(&run(args, d.path()), &["plan.json", "cases[0].id"]);
        }
        assert_eq!(
            std::fs::read_dir(&victim).unwrap().count(),
            1,
            "written outside the sweep ({k}: {bad:?})"
        );
    }
    // a field that would name a plot file outside plots/
    plan["cases"][0]["id"] = own_id;
    plan["fields"][0] = serde_json::json!("../../x");
    std::fs::write(&plan_path, serde_json::to_string_pretty(&plan).unwrap()).unwrap();
    refused_with(
        &run(&["sweep", "collect", "o"], d.path()),
        &["plan.json", "fields[0]"],
    );
    assert!(!d.path().join("o/results.csv").exists());
}

/// A link planted at a sweep's `cases/` (or at one case's directory) to a directory outside:
/// `sweep run-case` wrote the case's result there.
#[test]
fn a_link_planted_at_a_case_directory_is_refused() {
    let d = tempfile::tempdir().unwrap();
    planned_sweep(d.path());
    let elsewhere = d.path().join("elsewhere");
    std::fs::rename(d.path().join("o/cases"), &elsewhere).unwrap();
    std::os::unix::fs::symlink(&elsewhere, d.path().join("o/cases")).unwrap();
    let before = std::fs::read_dir(&elsewhere).unwrap().count();
    refused_with(
        &run(&["sweep", "run-case", "o", "--index", "0"], d.path()),
        &["cases", "symbolic link"],
    );
    let files = greybox_testkit::files::files_under(&elsewhere);
    assert_eq!(std::fs::read_dir(&elsewhere).unwrap().count(), before);
    assert!(
        files.iter().all(|f| f.ends_with("config.toml")),
        "written outside the sweep: {files:?}"
    );
}
