//! `greybox characterize` and `greybox wear` end to end.

use greybox_tribo::frf_synth::Chain;
use std::path::Path;
mod common;
use common::greybox;

fn write_csv(path: &Path, fs: f64, f_hz: f64, zeta: f64) {
    let rec = Chain::sdof(2.0, f_hz, zeta).record(fs, 1.2, &[150.0; 4], 0.5e-3, 0.0, 1);
    greybox_testkit::hammer::write_hammer_csv(path, &rec);
}

#[test]
fn characterize_two_loads_and_check_the_plan() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    write_csv(&p.join("a.csv"), 20_000.0, 300.0, 0.02);
    write_csv(&p.join("b.csv"), 20_000.0, 360.0, 0.03);
    let out = greybox(
        &[
            "characterize",
            "--recording",
            "a.csv@500",
            "--recording",
            "b.csv@2000",
            "--response",
            "response_m",
            "--track-radius-mm",
            "100",
            "--json",
        ],
        p,
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let f0 = v["loads"][0]["resonances"][0]["frequency_hz"]
        .as_f64()
        .unwrap();
    let z1 = v["loads"][1]["resonances"][0]["damping"].as_f64().unwrap();
    assert!((f0 - 300.0).abs() <= 1.0, "{f0}");
    assert!((z1 - 0.03).abs() <= 0.05 * 0.03, "{z1}");
    // the article's plan on R = 100 mm: 397.89 rpm → 6.63 Hz × 3 harmonics = 19.9 Hz; 300/19.9 ≈ 15
    let c = &v["excitation_check"];
    assert!((c["max_excitation_hz"].as_f64().unwrap() - 397.89 / 60.0 * 3.0).abs() < 1e-9);
    assert_eq!(c["pass"], true);
    // what the check rests on: only a radius was stated, so the velocities are the article's
    assert!((c["max_spindle_rpm"].as_f64().unwrap() - 397.89).abs() < 0.01);
    assert!((c["velocity_max_m_per_min"].as_f64().unwrap() - 250.0).abs() < 1e-9);
    assert_eq!(c["track_radius_mm"], 100.0);
    assert_eq!(c["velocities"], "the article's plan (no velocity stated)");
    for f in [
        "frf_500N.csv",
        "frf_2000N.csv",
        "frf_magnitude.svg",
        "coherence.svg",
        "report.json",
    ] {
        assert!(p.join("characterize-out").join(f).exists(), "{f}");
    }
    // bad input: mismatched sample rates within one load, a missing channel, no impact
    write_csv(&p.join("c.csv"), 10_000.0, 300.0, 0.02);
    let o = greybox(
        &[
            "characterize",
            "--force",
            "--recording",
            "a.csv",
            "--recording",
            "c.csv",
            "--response",
            "response_m",
        ],
        p,
    );
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(
        !o.status.success() && e.contains("c.csv") && e.contains("differs"),
        "{e}"
    );
    let o = greybox(
        &[
            "characterize",
            "--force",
            "--recording",
            "a.csv",
            "--response",
            "accel",
        ],
        p,
    );
    assert!(
        !o.status.success() && String::from_utf8_lossy(&o.stderr).contains("no column 'accel'")
    );
    std::fs::write(
        p.join("z.csv"),
        "time_s,hammer_N,response_m\n0,0,0\n0.001,0,0\n0.002,0,0\n",
    )
    .unwrap();
    let o = greybox(
        &[
            "characterize",
            "--force",
            "--recording",
            "z.csv",
            "--response",
            "response_m",
        ],
        p,
    );
    assert!(!o.status.success() && String::from_utf8_lossy(&o.stderr).contains("no impact found"));
}

#[test]
fn characterize_reads_tdms() {
    let d = tempfile::tempdir().unwrap();
    let fs = 20_000.0;
    let rec = Chain::sdof(2.0, 250.0, 0.02).record(fs, 1.2, &[150.0; 3], 0.5e-3, 0.0, 2);
    let chans = [
        greybox_recording::tdms::WriteChannel {
            name: "hammer_N",
            unit: "N",
            data: &rec.hammer,
        },
        greybox_recording::tdms::WriteChannel {
            name: "accel",
            unit: "m",
            data: &rec.response,
        },
    ];
    let mut buf = Vec::new();
    greybox_recording::tdms::write_tdms(&mut buf, "Hammer", &chans, 1.0 / fs, 0.0, 10_000).unwrap();
    std::fs::write(d.path().join("h.tdms"), buf).unwrap();
    let out = greybox(
        &[
            "characterize",
            "--recording",
            "h.tdms",
            "--response",
            "accel",
            "--json",
        ],
        d.path(),
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["loads"][0]["impacts_used"], 3);
    let f = v["loads"][0]["resonances"][0]["frequency_hz"]
        .as_f64()
        .unwrap();
    assert!((f - 250.0).abs() <= 1.0, "{f}");
    assert!(v["excitation_check"].is_null(), "no plan given");
}

/// The article's five wear tests: V = K F s computed here, then `greybox wear` run the other
/// way gives K back.
#[test]
fn article_wear_tests_the_other_way() {
    let d = tempfile::tempdir().unwrap();
    let tests = [
        (1075.0, 125.0, 45.0, 0.50),
        (150.0, 250.0, 30.0, 3.07),
        (150.0, 20.0, 2460.0, 0.93),
        (2000.0, 20.0, 397.0, 0.52),
        (2000.0, 250.0, 7.0, 2.51),
    ];
    for (f, v, t, k) in tests {
        let s = v / 60.0 * t;
        let vol = k * 1e-7 * f * s;
        let out = greybox(
            &[
                "wear",
                "--force-N",
                &f.to_string(),
                "--velocity-m-per-min",
                &v.to_string(),
                "--duration-s",
                &t.to_string(),
                "--volume-mm3",
                &format!("{vol:e}"),
                "--json",
            ],
            d.path(),
        );
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let j: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        let k_back = j["k_mm3_per_nm"].as_f64().unwrap() * 1e7;
        assert!((k_back - k).abs() < 1e-12, "{k_back} vs {k}");
    }
    let bundled = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/wear-tests.csv");
    let out = greybox(
        &["wear", "--tests", bundled.to_str().unwrap(), "--json"],
        d.path(),
    );
    let rows: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    for r in rows.as_array().unwrap() {
        assert!(
            (r["k_back_1e_7"].as_f64().unwrap() - r["k_article_1e_7"].as_f64().unwrap()).abs()
                < 1e-12
        );
    }
    let out = greybox(
        &[
            "wear",
            "--force-N",
            "100",
            "--velocity-m-per-min",
            "50",
            "--duration-s",
            "10",
        ],
        d.path(),
    );
    let e = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success()
            && e.contains("--volume-mm3")
            && e.contains("--scar-diameter-mm")
            && e.contains("exactly one way to the wear volume"),
        "{e}"
    );
    // every number is checked where it is read, named as its flag
    let out = greybox(
        &[
            "wear",
            "--force-N=-100",
            "--velocity-m-per-min",
            "50",
            "--duration-s",
            "10",
            "--volume-mm3",
            "0.1",
        ],
        d.path(),
    );
    let e = String::from_utf8_lossy(&out.stderr);
    assert!(
        e.contains("--force-N") && e.contains("expected a positive number"),
        "{e}"
    );
}
