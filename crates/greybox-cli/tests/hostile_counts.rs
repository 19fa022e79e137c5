//! Counts as a type (issue "Hostile and careless input", mechanism 3): every count option of
//! every subcommand, found from `--help` (where each states `[count: MIN..=MAX]`), is given
//! 0, −1, 10⁹ and 10¹⁸ under a memory and a time limit. Each value outside its range must be
//! refused by the parser, before any work, with the range in the message, and leave the
//! working directory as it was. Before, 10 of 20 count options tried aborted on an
//! allocation failure or started runs that did not end.
mod common;
use common::{greybox_limited, listing, refused_with};
use std::path::Path;

/// The subcommand paths below `path` (from the "Commands:" section of its help).
fn subcommands(path: &[String], dir: &Path, out: &mut Vec<Vec<String>>) {
    let mut args: Vec<&str> = path.iter().map(String::as_str).collect();
    args.push("--help");
    let help = String::from_utf8(greybox_limited(&args, dir, 1024, 30).stdout).unwrap();
    out.push(path.to_vec());
    let Some(commands) = help.split("Commands:\n").nth(1) else {
        return;
    };
    for line in commands.lines().take_while(|l| l.starts_with("  ")) {
        let name = line.split_whitespace().next().unwrap_or("");
        if !name.is_empty() && name != "help" {
            let mut p = path.to_vec();
            p.push(name.to_string());
            subcommands(&p, dir, out);
        }
    }
}

/// Every `--option` of a help text whose description states a count range, with the range.
fn count_options(help: &str) -> Vec<(String, i128, i128)> {
    let mut out = Vec::new();
    let mut option = None;
    for line in help.lines() {
        let t = line.trim_start();
        if t.starts_with("--") || (t.starts_with('-') && t.contains(", --")) {
            option = t
                .split_whitespace()
                .find(|w| w.starts_with("--"))
                .map(|w| w.trim_end_matches(',').to_string());
        }
        if let (Some(o), Some(i)) = (&option, line.find("[count: ")) {
            let range = &line[i + 8..line[i..].find(']').unwrap() + i];
            let (lo, hi) = range.split_once("..=").unwrap();
            out.push((o.clone(), lo.parse().unwrap(), hi.parse().unwrap()));
            option = None;
        }
    }
    out
}

#[test]
fn every_count_option_refuses_zero_negative_and_huge_values_before_any_work() {
    let d = tempfile::tempdir().unwrap();
    let dir = d.path();
    std::fs::write(dir.join("keep.txt"), "a file the runs must leave alone").unwrap();
    let before = listing(dir);
    let mut paths = Vec::new();
    subcommands(&[], dir, &mut paths);
    let mut tried = 0;
    let mut options = std::collections::BTreeSet::new();
    for path in &paths {
        let mut args: Vec<&str> = path.iter().map(String::as_str).collect();
        args.push("--help");
        let help = String::from_utf8(greybox_limited(&args, dir, 1024, 30).stdout).unwrap();
        for (option, lo, hi) in count_options(&help) {
            options.insert(option.clone());
            for value in [0i128, -1, 1_000_000_000, 1_000_000_000_000_000_000] {
                if (lo..=hi).contains(&value) {
                    continue; // inside its range: a legitimate request, not a hostile one
                }
                let flag = format!("{option}={value}");
                let mut run: Vec<&str> = path.iter().map(String::as_str).collect();
                run.push(&flag);
                let r = greybox_limited(&run, dir, 1024, 30);
                let range = format!("{lo}..={hi}");
                let e = refused_with(&r, &[option.as_str(), range.as_str()]);
                assert_eq!(
                    r.status.code(),
                    Some(2),
                    "{run:?}: a usage error expected: {e}"
                );
                assert_eq!(listing(dir), before, "{run:?} wrote into the directory");
                tried += 1;
            }
        }
    }
    // the options the probe named are among them
    for named in [
        "--check-points",
        "--rf-n-estimators",
        "--bootstrap",
        "--importance-repeats",
        "--normal-force-count",
        "--sim3d-increments",
        "--sim-max-runs",
        "--max-cycles",
        "--jobs",
    ] {
        assert!(
            options.contains(named),
            "{named} is not a count option: {options:?}"
        );
    }
    assert!(tried >= 80, "only {tried} hostile values tried");
}

/// Counts inside other values and counts computed from them are checked before the
/// allocation they size: the N of a grid axis, the 3D pin mesh from its ratios, a plan's
/// pins × velocities.
#[test]
fn computed_counts_are_refused_with_the_setting_that_makes_them() {
    let d = tempfile::tempdir().unwrap();
    let dir = d.path();
    std::fs::write(dir.join("law.json"), r#"{"law": "coulomb", "mu": 0.3}"#).unwrap();
    let before = listing(dir);
    let r = greybox_limited(
        &[
            "export",
            "--law",
            "law.json",
            "--format",
            "abaqus",
            "--out",
            "t.inp",
            "--pressure-MPa",
            "100:2000:1000000000",
        ],
        dir,
        1024,
        30,
    );
    refused_with(
        &r,
        &[
            "export.pressure_MPa",
            "N of MIN:MAX:N",
            "above the cap of 1000000",
        ],
    );
    let r = greybox_limited(
        &[
            "adhesive",
            "--data",
            "missing.csv",
            "--method",
            "simulation-3d",
            "--sim3d-slide-per-radius",
            "1e9",
        ],
        dir,
        1024,
        30,
    );
    refused_with(
        &r,
        &[
            "--sim3d-slide-per-radius",
            "grid lines along the slide",
            "above the cap",
        ],
    );
    let r = greybox_limited(
        &[
            "plan",
            "--track-radius-mm",
            "50",
            "--normal-force-count",
            "1000000",
            "--velocity-count",
            "100",
            "--out",
            "plan",
        ],
        dir,
        1024,
        30,
    );
    refused_with(
        &r,
        &[
            "plan steps (normal forces × velocities)",
            "above the cap of 10000000",
        ],
    );
    assert_eq!(listing(dir), before);
}
