//! `greybox sweep` on the local executor: expansion and hashing, a run collected into one
//! table, resume after a killed run, failure reporting, and calibration of C against
//! forces simulated at a known C.
mod common;
use common::{coarse_config, err, greybox, ok};
use std::path::Path;
use std::process::Command;

/// A sweep of the coarse cut: speed × rake, 4 cases.
fn sweep_file(dir: &Path, extra: &str) {
    coarse_config(dir, None);
    let text = format!(
        r#"[sweep]
kind = "cutting"
base = "cut.toml"
fraction = 0.4
[[axis]]
field = "cutting_speed_m_s"
values = [2.5, 3.5]
[[axis]]
field = "insert.rake_deg"
values = [0.0, 6.0]
{extra}"#
    );
    std::fs::write(dir.join("sweep.toml"), text).unwrap();
}

fn plan(dir: &Path, out: &str) -> serde_json::Value {
    serde_json::from_str(&ok(&greybox(
        &["sweep", "plan", "sweep.toml", "--out", out, "--json"],
        dir,
    )))
    .unwrap()
}

fn ids(p: &serde_json::Value) -> Vec<String> {
    p["cases"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c["id"].as_str().unwrap().to_string())
        .collect()
}

fn done_count(out: &Path) -> usize {
    std::fs::read_dir(out.join("cases"))
        .map(|r| {
            r.filter(|e| e.as_ref().unwrap().path().join("done.json").is_file())
                .count()
        })
        .unwrap_or(0)
}

#[test]
fn plan_expands_axes_and_keys_cases_by_their_resolved_config() {
    let d = tempfile::tempdir().unwrap();
    sweep_file(d.path(), "");
    let p = plan(d.path(), "o");
    let cases = p["cases"].as_array().unwrap();
    assert_eq!(cases.len(), 4);
    // first axis slowest
    let v = |i: usize, k: usize| cases[i]["values"][k][1].as_str().unwrap().to_string();
    assert_eq!(
        (v(0, 0), v(0, 1), v(1, 1), v(2, 0)),
        ("2.5".into(), "0.0".into(), "6.0".into(), "3.5".into())
    );
    // the cost estimate: particles × steps, faster cuts take fewer steps
    let ps = |i: usize| cases[i]["cost"]["particle_steps"].as_f64().unwrap();
    assert!(ps(0) > 1e5 && ps(2) < ps(0));
    // every case directory holds its resolved config; the rake is applied
    let first = ids(&p);
    let cfg = std::fs::read_to_string(d.path().join("o/cases").join(&first[1]).join("config.toml"))
        .unwrap();
    assert!(cfg.contains("rake_deg = 6.0"), "{cfg}");
    // same file, same ids; a changed base gives new ids (never mixed with the old outputs)
    assert_eq!(ids(&plan(d.path(), "o")), first);
    let base = std::fs::read_to_string(d.path().join("cut.toml")).unwrap();
    std::fs::write(
        d.path().join("cut.toml"),
        base.replace("mu = 0.35", "mu = 0.3"),
    )
    .unwrap();
    let changed = ids(&plan(d.path(), "o"));
    assert!(changed.iter().all(|i| !first.contains(i)));
    // a bad field names the case and the field
    std::fs::write(
        d.path().join("sweep.toml"),
        "[sweep]\nkind = \"cutting\"\nbase = \"cut.toml\"\n[[axis]]\nfield = \"insert.rake_deg\"\nvalues = [60.0]\n",
    )
    .unwrap();
    let e = err(&greybox(&["sweep", "plan", "sweep.toml"], d.path()));
    assert!(
        e.contains("case 1 (insert.rake_deg = 60.0)") && e.contains("rake_deg"),
        "{e}"
    );
}

#[test]
fn a_killed_run_resumes_without_redoing_finished_cases_and_collects_every_result() {
    let d = tempfile::tempdir().unwrap();
    sweep_file(d.path(), "");
    let out = d.path().join("o");
    // one case at a time; killed (with its workers) once the first case is done
    let mut child = {
        use std::os::unix::process::CommandExt;
        Command::new(env!("CARGO_BIN_EXE_greybox"))
            .args([
                "-q",
                "sweep",
                "run",
                "sweep.toml",
                "--out",
                "o",
                "--jobs",
                "1",
            ])
            .current_dir(d.path())
            .process_group(0)
            .spawn()
            .unwrap()
    };
    let t0 = std::time::Instant::now();
    while done_count(&out) < 1 {
        assert!(t0.elapsed().as_secs() < 120, "no case finished");
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    let pgid = nix::unistd::Pid::from_raw(child.id() as i32);
    nix::sys::signal::killpg(pgid, nix::sys::signal::Signal::SIGKILL).unwrap();
    child.wait().unwrap();
    let finished = done_count(&out);
    assert!((1..4).contains(&finished), "{finished}");
    // nothing looks finished that is not: every done marker has the run's summary
    let p = plan(d.path(), "o");
    let mut stamps = Vec::new();
    for id in ids(&p) {
        let c = out.join("cases").join(&id);
        if c.join("done.json").is_file() {
            assert!(c.join("result/summary.json").is_file());
            stamps.push((
                id,
                std::fs::metadata(c.join("done.json"))
                    .unwrap()
                    .modified()
                    .unwrap(),
            ));
        }
    }
    let r: serde_json::Value = serde_json::from_str(&ok(&greybox(
        &[
            "-q",
            "sweep",
            "run",
            "sweep.toml",
            "--out",
            "o",
            "--jobs",
            "2",
            "--json",
        ],
        d.path(),
    )))
    .unwrap();
    assert_eq!(
        (r["done"].as_u64(), r["skipped"].as_u64()),
        (Some(4), Some(finished as u64))
    );
    for (id, t) in stamps {
        let now = std::fs::metadata(out.join("cases").join(id).join("done.json"))
            .unwrap()
            .modified()
            .unwrap();
        assert_eq!(now, t, "a finished case ran again");
    }
    let c: serde_json::Value = serde_json::from_str(&ok(&greybox(
        &["sweep", "collect", "o", "--json"],
        d.path(),
    )))
    .unwrap();
    assert_eq!(c["done"], 4);
    let csv = std::fs::read_to_string(out.join("results.csv")).unwrap();
    let mut rdr = csv::Reader::from_reader(csv.as_bytes());
    let h = rdr.headers().unwrap().clone();
    let col = |n: &str| h.iter().position(|x| x == n).unwrap();
    let rows: Vec<csv::StringRecord> = rdr.records().map(|r| r.unwrap()).collect();
    assert_eq!(rows.len(), 4);
    for r in &rows {
        let fc: f64 = r[col("cutting_force_N_per_mm")].parse().unwrap();
        assert!(fc > 50.0 && fc < 1000.0, "{fc}");
        assert_eq!(&r[col("status")], "done");
    }
    // a positive rake lowers the cutting force at either speed (the textbook trend)
    let fc = |i: usize| {
        rows[i][col("cutting_force_N_per_mm")]
            .parse::<f64>()
            .unwrap()
    };
    assert!(fc(1) < fc(0) && fc(3) < fc(2), "{}", csv);
    assert!(out
        .join("plots/cutting_force_N_per_mm_vs_cutting_speed_m_s.svg")
        .is_file()); // the report shows the sweep as one table with its plots, not its cases one by one
    let rep: serde_json::Value = serde_json::from_str(&ok(&greybox(
        &["report", ".", "--out", "report.html", "--json"],
        d.path(),
    )))
    .unwrap();
    assert_eq!(rep["sections"], serde_json::json!(["Sweeps"]), "{rep}");
    let html = std::fs::read_to_string(d.path().join("report.html")).unwrap();
    let plots = std::fs::read_dir(out.join("plots")).unwrap().count();
    assert!(plots >= 2);
    assert!(html.contains("4 cases of sweep.toml"));
    assert_eq!(html.matches("<figure").count(), plots);
}

#[test]
fn a_failing_case_is_reported_with_its_log_and_retried_on_the_next_run() {
    let d = tempfile::tempdir().unwrap();
    sweep_file(d.path(), "");
    let p = plan(d.path(), "o");
    let first = ids(&p)[0].clone();
    // a case whose result directory cannot be written (a file stands where it goes): its run
    // fails (an edited config.toml no longer can: the run puts the planned one back)
    let blocker = d.path().join("o/cases").join(&first).join("result");
    std::fs::write(&blocker, "in the way").unwrap();
    let out = greybox(
        &[
            "-q",
            "sweep",
            "run",
            "sweep.toml",
            "--out",
            "o",
            "--jobs",
            "2",
        ],
        d.path(),
    );
    let e = err(&out);
    assert!(e.contains("1 case(s) failed"), "{e}");
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains(&format!("case 0 ({first}) failed")) && text.contains("result"),
        "{text}"
    );
    assert!(d
        .path()
        .join("o/cases")
        .join(&first)
        .join("failed.json")
        .is_file());
    let c: serde_json::Value = serde_json::from_str(&ok(&greybox(
        &["sweep", "collect", "o", "--json"],
        d.path(),
    )))
    .unwrap();
    assert_eq!(c["done"], 3);
    assert_eq!(c["missing"][0][0], 0);
    // repaired, the next run reruns only the failed case
    std::fs::remove_file(&blocker).unwrap();
    let r: serde_json::Value = serde_json::from_str(&ok(&greybox(
        &["-q", "sweep", "run", "sweep.toml", "--out", "o", "--json"],
        d.path(),
    )))
    .unwrap();
    assert_eq!(
        (r["done"].as_u64(), r["skipped"].as_u64()),
        (Some(4), Some(3))
    );
    assert!(!d
        .path()
        .join("o/cases")
        .join(&first)
        .join("failed.json")
        .exists());
}

#[test]
fn calibration_recovers_the_johnson_cook_c_the_measured_forces_were_made_with() {
    let d = tempfile::tempdir().unwrap();
    coarse_config(d.path(), None);
    // "measured": the cut at C = 0.03 at two speeds and a held-out third
    measured_at(
        d.path(),
        0.4,
        ("material.plasticity.c", 0.03),
        &["cutting_force_N_per_mm"],
    );
    std::fs::write(
        d.path().join("cal.toml"),
        "[sweep]\nkind = \"cutting\"\nbase = \"cut.toml\"\nfraction = 0.4\n",
    )
    .unwrap();
    let r: serde_json::Value = serde_json::from_str(&ok(&greybox(
        &[
            "-q",
            "sweep",
            "calibrate",
            "cal.toml",
            "--measured",
            "measured.csv",
            "--out",
            "c",
            "--c-min",
            "0.005",
            "--c-max",
            "0.2",
            "--iterations",
            "9",
            "--jobs",
            "2",
            "--hold-out",
            "3",
            "--json",
        ],
        d.path(),
    )))
    .unwrap();
    let c = r["c"].as_f64().unwrap();
    assert!((c / 0.03 - 1.0).abs() < 0.15, "C = {c}: {r}");
    assert!(r["training_error"].as_f64().unwrap() < 0.02, "{r}");
    assert!(r["held_out_error"].as_f64().unwrap() < 0.03, "{r}");
    let held: Vec<bool> = r["residuals"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x["held_out"].as_bool().unwrap())
        .collect();
    assert_eq!(held, [false, false, true]);
    assert!(d.path().join("c/calibration.json").is_file());
}

/// A flow-stress constant fitted on the cutting force and the chip ratio together: the
/// measured `chip_ratio` column counts in the error (training error = the mean of the F'c
/// and h_c/h terms), and every residual carries the chip.
#[test]
fn calibration_fits_a_flow_stress_constant_on_forces_and_chip() {
    let d = tempfile::tempdir().unwrap();
    coarse_config(d.path(), None);
    measured_at(
        d.path(),
        1.0,
        ("material.plasticity.n", 0.45),
        &["cutting_force_N_per_mm", "compression_ratio"],
    );
    std::fs::write(
        d.path().join("cal.toml"),
        "[sweep]\nkind = \"cutting\"\nbase = \"cut.toml\"\n",
    )
    .unwrap();
    let r: serde_json::Value = serde_json::from_str(&ok(&greybox(
        &[
            "-q",
            "sweep",
            "calibrate",
            "cal.toml",
            "--measured",
            "measured.csv",
            "--out",
            "c",
            "--fit",
            "material.plasticity.n=0.1:0.8",
            "--iterations",
            "8",
            "--jobs",
            "2",
            "--hold-out",
            "3",
            "--json",
        ],
        d.path(),
    )))
    .unwrap();
    let n = r["parameters"][0][1].as_f64().unwrap();
    assert!((n / 0.45 - 1.0).abs() < 0.15, "n = {n}: {r}");
    let res = r["residuals"].as_array().unwrap();
    let terms: Vec<f64> = res
        .iter()
        .filter(|x| !x["held_out"].as_bool().unwrap())
        .flat_map(|x| {
            let chip = x["chip_ratio_error"].as_f64().expect("a chip error");
            [x["cutting_force_error"].as_f64().unwrap().abs(), chip.abs()]
        })
        .collect();
    let mean = terms.iter().sum::<f64>() / terms.len() as f64;
    let training = r["training_error"].as_f64().unwrap();
    assert!(
        (training - mean).abs() < 1e-12,
        "{training} against {mean}: {r}"
    );
    for x in res {
        assert!(x["measured_chip_ratio"].as_f64().unwrap() > 1.0, "{x}");
        assert!(x["simulated_chip_ratio"].as_f64().unwrap() > 1.0, "{x}");
    }
    // how sure: each evaluation keeps its conditions' shares of the error, whose mean is
    // its error; the fitted value lies inside its range, within what was tried
    let evals = r["evaluations"].as_array().unwrap();
    assert_eq!(evals.len(), 8, "{r}");
    for e in evals {
        let shares: Vec<f64> = e["condition_errors"]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_f64().unwrap())
            .collect();
        assert_eq!(shares.len(), 2, "{e}");
        let mean = shares.iter().sum::<f64>() / 2.0;
        assert!((mean - e["error"].as_f64().unwrap()).abs() < 1e-12, "{e}");
    }
    let c = &r["certainty"];
    assert_eq!(c["conditions"], 2, "{r}");
    let f = &c["fields"][0];
    let g = |k: &str| f[k].as_f64().unwrap();
    assert_eq!(f["field"], "material.plasticity.n");
    assert!(g("low") <= n && n <= g("high"), "{f}");
    assert!(
        f["tried"][0].as_f64().unwrap() <= g("low") && g("high") <= f["tried"][1].as_f64().unwrap()
    );
    assert!(r["training_error_ci95"].as_f64().unwrap() >= 0.0, "{r}");
}

#[test]
fn calibration_fits_a_parameter_of_an_inline_friction_law() {
    // the base cut with an inline law whose μ_ref is fitted (`--fit friction.law.mu_ref`)
    let d = tempfile::tempdir().unwrap();
    coarse_config(d.path(), None);
    let mut cut = std::fs::read_to_string(d.path().join("cut.toml")).unwrap();
    cut += "\n[friction.law]\nlaw = \"power\"\nmu_ref = 0.3\np_ref_MPa = 1000.0\nv_ref_m_per_min = 150.0\nb = -0.2\nclamp = [0.05, 1.0]\n";
    std::fs::write(d.path().join("cut.toml"), cut).unwrap();
    // "measured": the cut with μ_ref = 0.5 at three speeds (the third held out)
    measured_at(
        d.path(),
        0.4,
        ("friction.law.mu_ref", 0.5),
        &["cutting_force_N_per_mm", "feed_force_N_per_mm"],
    );
    std::fs::write(
        d.path().join("cal.toml"),
        "[sweep]\nkind = \"cutting\"\nbase = \"cut.toml\"\nfraction = 0.4\n",
    )
    .unwrap();
    let r: serde_json::Value = serde_json::from_str(&ok(&greybox(
        &[
            "-q",
            "sweep",
            "calibrate",
            "cal.toml",
            "--measured",
            "measured.csv",
            "--out",
            "c",
            "--fit",
            "friction.law.mu_ref=0.2:0.8",
            "--iterations",
            "8",
            "--jobs",
            "2",
            "--hold-out",
            "3",
            "--json",
        ],
        d.path(),
    )))
    .unwrap();
    let p = &r["parameters"][0];
    assert_eq!(p[0], "friction.law.mu_ref", "{r}");
    let mu = p[1].as_f64().unwrap();
    assert!((mu / 0.5 - 1.0).abs() < 0.1, "μ_ref = {mu}: {r}");
    assert!(r["c"].is_null(), "C was not fitted: {r}");
    // a field the law does not have is refused by name
    let e = err(&greybox(
        &[
            "sweep",
            "calibrate",
            "cal.toml",
            "--measured",
            "measured.csv",
            "--out",
            "c2",
            "--fit",
            "friction.law.q=0:1",
        ],
        d.path(),
    ));
    assert!(e.contains("friction.law") || e.contains("'q'"), "{e}");
}

/// "Measured" conditions made by the base cut (`fraction` of its length) with `truth`'s field
/// at its value, at cutting speeds 2, 3 and 4 m/s: `measured.csv` with the speed and
/// `columns` of the sweep's `results.csv` (its `compression_ratio` as the measured
/// `chip_ratio`).
fn measured_at(dir: &std::path::Path, fraction: f64, truth: (&str, f64), columns: &[&str]) {
    let (field, value) = truth;
    std::fs::write(
        dir.join("truth.toml"),
        format!("[sweep]\nkind = \"cutting\"\nbase = \"cut.toml\"\nfraction = {fraction:?}\n[[axis]]\nfield = \"cutting_speed_m_s\"\nvalues = [2.0, 3.0, 4.0]\n[[axis]]\nfield = \"{field}\"\nvalues = [{value:?}]\n"),
    )
    .unwrap();
    ok(&greybox(
        &[
            "-q",
            "sweep",
            "run",
            "truth.toml",
            "--out",
            "t",
            "--jobs",
            "2",
        ],
        dir,
    ));
    ok(&greybox(&["sweep", "collect", "t"], dir));
    let columns: Vec<&str> = std::iter::once("cutting_speed_m_s")
        .chain(columns.iter().copied())
        .collect();
    let csv = std::fs::read_to_string(dir.join("t/results.csv")).unwrap();
    let mut rdr = csv::Reader::from_reader(csv.as_bytes());
    let h = rdr.headers().unwrap().clone();
    let at: Vec<usize> = columns
        .iter()
        .map(|n| h.iter().position(|x| x == *n).unwrap())
        .collect();
    let mut measured = columns.join(",").replace("compression_ratio", "chip_ratio") + "\n";
    for r in rdr.records() {
        let r = r.unwrap();
        measured += &at.iter().map(|&k| &r[k]).collect::<Vec<_>>().join(",");
        measured += "\n";
    }
    std::fs::write(dir.join("measured.csv"), measured).unwrap();
}
