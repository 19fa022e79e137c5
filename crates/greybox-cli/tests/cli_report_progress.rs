//! `greybox report` on a cut (only the sections with data, valid HTML5, pictures that
//! decode, the frame slider) and progress reporting (a bar that advances on a terminal,
//! `--json` output untouched, `--quiet` silent).
mod common;
use common::{coarse_config, greybox, ok};
use std::path::Path;
use std::process::{Command, Stdio};

/// Every `data:image/png;base64,…` in `html`, decoded.
fn embedded_pngs(html: &str) -> Vec<Vec<u8>> {
    use base64::Engine as _;
    let marker = "data:image/png;base64,";
    html.match_indices(marker)
        .map(|(i, _)| {
            let rest = &html[i + marker.len()..];
            let end = rest.find('"').expect("closing quote");
            base64::engine::general_purpose::STANDARD
                .decode(&rest[..end])
                .expect("valid base64")
        })
        .collect()
}

#[test]
fn the_report_of_a_cut_shows_its_sections_parses_as_html5_and_every_picture_decodes() {
    let d = tempfile::tempdir().unwrap();
    coarse_config(d.path(), None);
    ok(&greybox(
        &[
            "-q",
            "simulate",
            "cutting",
            "--config",
            "cut.toml",
            "--fraction",
            "0.5",
            "--frames",
            "3",
            "--out",
            "study/cut",
        ],
        d.path(),
    ));
    let out = ok(&greybox(&["report", "study", "--json"], d.path()));
    let summary: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(
        summary["sections"],
        serde_json::json!(["Cutting", "Provenance"])
    );
    assert_eq!(summary["warnings"], serde_json::json!([]));
    let html = std::fs::read_to_string(d.path().join("study/report.html")).unwrap();
    assert_eq!(summary["bytes"].as_u64().unwrap() as usize, html.len());

    // valid HTML5: the WHATWG parsing algorithm (html5ever) reports no parse error
    let doc = scraper::Html::parse_document(&html);
    assert!(doc.errors.is_empty(), "HTML parse errors: {:?}", doc.errors);
    let sel = |s: &str| scraper::Selector::parse(s).unwrap();
    let h2: Vec<String> = doc
        .select(&sel("section > h2"))
        .map(|e| e.text().collect())
        .collect();
    assert_eq!(h2, ["Cutting", "Provenance"]);
    // the cut's figures, the two chip pictures and a slider over its three frames
    assert_eq!(doc.select(&sel(".frames .frame")).count(), 3);
    assert_eq!(
        doc.select(&sel("input[type=range]"))
            .next()
            .unwrap()
            .value()
            .attr("max"),
        Some("3")
    );
    // forces, 4 profiles, μ history, 2 chip pictures, the frames
    assert_eq!(doc.select(&sel("figure")).count(), 9, "{h2:?}");
    // every embedded raster is a PNG that decodes to a non-empty image (2 pictures + 3 frames)
    let pngs = embedded_pngs(&html);
    assert_eq!(pngs.len(), 5);
    for bytes in pngs {
        let dec = png::Decoder::new(std::io::Cursor::new(bytes));
        let mut r = dec.read_info().expect("PNG header");
        let mut buf = vec![0; r.output_buffer_size().unwrap()];
        let info = r.next_frame(&mut buf).expect("PNG data");
        assert!(info.width > 100 && info.height > 20);
        assert!(buf.chunks(4).any(|p| p[3] == 255), "no particle drawn");
    }
    // units on the axes of the chip pictures
    assert!(html.contains("x (mm)") && html.contains("temperature (°C)"));
}

#[test]
fn report_refuses_a_directory_without_greybox_outputs() {
    let d = tempfile::tempdir().unwrap();
    std::fs::create_dir(d.path().join("empty")).unwrap();
    let e = common::err(&greybox(&["report", "empty"], d.path()));
    assert!(e.contains("no greybox outputs found"), "{e}");
}

/// Runs greybox with stderr on a pseudo-terminal of 120 columns; returns (stdout, what
/// the terminal received).
fn run_on_a_terminal(args: &[&str], cwd: &Path) -> (String, String) {
    use nix::pty::{openpty, Winsize};
    use std::io::Read;
    let ws = Winsize {
        ws_row: 40,
        ws_col: 120,
        ws_xpixel: 0,
        ws_ypixel: 0,
    };
    let pty = openpty(Some(&ws), None).expect("openpty");
    let mut child = Command::new(env!("CARGO_BIN_EXE_greybox"))
        .args(args)
        .current_dir(cwd)
        .env("TERM", "xterm-256color")
        .env_remove("GREYBOX_PROGRESS")
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::from(pty.slave))
        .spawn()
        .expect("run greybox");
    let mut master = std::fs::File::from(pty.master);
    let reader = std::thread::spawn(move || {
        let mut seen = Vec::new();
        let mut buf = [0u8; 4096];
        // EIO once the child closed its end
        while let Ok(n) = master.read(&mut buf) {
            if n == 0 {
                break;
            }
            seen.extend_from_slice(&buf[..n]);
        }
        String::from_utf8_lossy(&seen).into_owned()
    });
    let mut stdout = String::new();
    child
        .stdout
        .take()
        .unwrap()
        .read_to_string(&mut stdout)
        .unwrap();
    assert!(child.wait().unwrap().success(), "stdout: {stdout}");
    (stdout, reader.join().unwrap())
}

#[test]
fn a_cut_on_a_terminal_shows_a_progress_bar_that_advances() {
    let d = tempfile::tempdir().unwrap();
    coarse_config(d.path(), None);
    let (_, tty) = run_on_a_terminal(
        &["simulate", "cutting", "--config", "cut.toml", "--out", "o"],
        d.path(),
    );
    // the bar's "pos/len steps" at successive redraws
    let positions: Vec<(u64, u64)> = tty
        .match_indices(" steps (")
        .filter_map(|(i, _)| {
            let head = &tty[..i];
            let word = head.rsplit(' ').next()?;
            let (a, b) = word.split_once('/')?;
            Some((a.parse().ok()?, b.parse().ok()?))
        })
        .collect();
    let mut distinct: Vec<u64> = positions.iter().map(|p| p.0).collect();
    distinct.dedup();
    assert!(
        distinct.len() >= 3,
        "the bar should redraw at least 3 positions: {positions:?}\n{tty}"
    );
    assert!(distinct.windows(2).all(|w| w[0] <= w[1]), "{distinct:?}");
    let total = positions[0].1;
    assert!(positions.iter().all(|p| p.1 == total && p.0 <= total));
    assert!(tty.contains("cut") && tty.contains("ETA"), "{tty}");
}

#[test]
fn json_output_is_unchanged_by_progress_and_quiet_is_silent() {
    let d = tempfile::tempdir().unwrap();
    coarse_config(d.path(), None);
    let run = |extra: &[&str], envs: &[(&str, &str)], out: &str| {
        let mut c = Command::new(env!("CARGO_BIN_EXE_greybox"));
        c.args(extra)
            .args([
                "simulate",
                "cutting",
                "--config",
                "cut.toml",
                "--fraction",
                "0.5",
                "--json",
                "--out",
                out,
            ])
            .current_dir(d.path());
        for (k, v) in envs {
            c.env(k, v);
        }
        c.output().unwrap()
    };
    // status lines as often as the throttle allows
    let chatty = run(
        &[],
        &[
            ("GREYBOX_PROGRESS", "lines"),
            ("GREYBOX_PROGRESS_INTERVAL_S", "0"),
        ],
        "a",
    );
    let quiet = run(&["--quiet"], &[], "b");
    let stderr = String::from_utf8_lossy(&chatty.stderr);
    assert!(
        stderr.contains("[greybox] cut: started") && stderr.contains("steps/s"),
        "{stderr}"
    );
    assert!(
        quiet.stderr.is_empty(),
        "{}",
        String::from_utf8_lossy(&quiet.stderr)
    );
    // the JSON documents are equal but for timings and the output paths
    let doc = |o: &std::process::Output| {
        let mut v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("stdout is JSON");
        for k in [
            "wall_s",
            "particle_steps_per_s",
            "particle_steps_per_s_per_core",
            "files",
        ] {
            v.as_object_mut().unwrap().remove(k).expect(k);
        }
        v
    };
    assert_eq!(doc(&chatty), doc(&quiet));
}
