//! The C ABI from C (gcc) and Fortran (gfortran): same μ as Rust to the last bit, eight
//! threads at once, error codes instead of crashes. The library is built by a nested
//! `cargo build` into the same target directory.

mod common;
use greybox_core::ContactState;
use std::path::{Path, PathBuf};
use std::process::Command;

fn target_dir_and_profile() -> (PathBuf, String) {
    // …/target/<profile>/deps/ffi-<hash>
    let exe = std::env::current_exe().unwrap();
    let profile_dir = exe.parent().unwrap().parent().unwrap().to_path_buf();
    let profile = profile_dir
        .file_name()
        .unwrap()
        .to_string_lossy()
        .into_owned();
    (profile_dir.parent().unwrap().to_path_buf(), profile)
}

fn build_library() -> PathBuf {
    let (target, profile) = target_dir_and_profile();
    let mut cmd = Command::new(env!("CARGO"));
    cmd.args(["build", "-p", "greybox-ffi", "--lib", "--target-dir"])
        .arg(&target)
        .current_dir(env!("CARGO_MANIFEST_DIR"));
    if profile == "release" {
        cmd.arg("--release");
    }
    let out = cmd.output().expect("run cargo");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let lib = target.join(&profile).join("libgreybox_ffi.a");
    assert!(lib.exists(), "{}", lib.display());
    lib
}

fn manifest() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// Parse a C99 `%a` hex float.
fn parse_hex_float(s: &str) -> f64 {
    let (neg, s) = s.strip_prefix('-').map(|r| (true, r)).unwrap_or((false, s));
    let s = s.strip_prefix("0x").expect("0x prefix");
    let (mant, exp) = s.split_once('p').expect("p exponent");
    let (int, frac) = mant.split_once('.').unwrap_or((mant, ""));
    let mut m = u64::from_str_radix(int, 16).unwrap() as f64;
    let mut scale = 1.0 / 16.0;
    for c in frac.chars() {
        m += c.to_digit(16).unwrap() as f64 * scale;
        scale /= 16.0;
    }
    let v = m * 2f64.powi(exp.parse::<i32>().unwrap());
    if neg {
        -v
    } else {
        v
    }
}

/// A law file: a small learned model inside a grey-box law, plus a classical law.
fn law_files(dir: &Path) -> Vec<PathBuf> {
    let model = common::small_model(
        greybox_model::Family::Mlp,
        greybox_model::mlp::Activation::Tanh,
    );
    model.save(&dir.join("mlp.json")).unwrap();
    std::fs::write(
        dir.join("greybox-law.json"),
        r#"{"law": "grey-box", "inner": {"law": "learned", "model": "mlp.json"}, "outside": {"law": "power-fit"}, "shear_cap_k_MPa": 700}"#,
    )
    .unwrap();
    std::fs::write(
        dir.join("usui.json"),
        r#"{"law": "usui-childs", "mu": 0.45, "m": 0.9, "n": 1.5, "k_MPa": 500}"#,
    )
    .unwrap();
    vec![dir.join("greybox-law.json"), dir.join("usui.json")]
}

fn gcc(lib: &Path, src: &str, out: &Path) {
    let st = Command::new("gcc")
        .args(["-O2", "-std=c99", "-Wall", "-Werror"])
        .arg("-I")
        .arg(manifest().join("include"))
        .arg(manifest().join(src))
        .arg(lib)
        .args(["-lpthread", "-ldl", "-lm", "-o"])
        .arg(out)
        .status()
        .expect("gcc");
    assert!(st.success(), "gcc {src}");
}

const POINTS: [(f64, f64, f64); 5] = [
    (1.0e9, 0.5, 293.15),
    (1.5e9, 1.5, 400.0),
    (2.0e9, 3.5, 293.15),
    (4.0e9, 2.0, 293.15),
    (0.2e9, 0.1, 900.0),
];

#[test]
fn c_program_gets_the_same_mu_bit_for_bit() {
    let lib = build_library();
    let dir = tempfile::tempdir().unwrap();
    let exe = dir.path().join("test_basic");
    gcc(&lib, "tests/c/test_basic.c", &exe);
    for law_path in law_files(dir.path()) {
        let law = greybox_friction::spec::load_law(&law_path).unwrap();
        let mut cmd = Command::new(&exe);
        cmd.arg(&law_path);
        for (p, v, t) in POINTS {
            cmd.arg(format!("{p:e}"))
                .arg(format!("{v:e}"))
                .arg(format!("{t:e}"));
        }
        let out = cmd.output().unwrap();
        let stdout = String::from_utf8_lossy(&out.stdout);
        assert!(
            out.status.success(),
            "{stdout}\n{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let mus: Vec<f64> = stdout
            .lines()
            .filter_map(|l| l.strip_prefix("mu "))
            .map(parse_hex_float)
            .collect();
        let grads: Vec<Vec<f64>> = stdout
            .lines()
            .filter_map(|l| l.strip_prefix("grad "))
            .map(|l| l.split(' ').map(parse_hex_float).collect())
            .collect();
        assert_eq!(mus.len(), POINTS.len());
        for (k, (p, v, t)) in POINTS.iter().enumerate() {
            let s = ContactState {
                pressure_pa: *p,
                sliding_velocity_m_s: *v,
                temperature_k: *t,
            };
            assert_eq!(
                mus[k].to_bits(),
                law.mu(&s).to_bits(),
                "{}: point {k}",
                law_path.display()
            );
            let (m, g) = greybox_friction::gradient::mu_and_gradient(law.as_ref(), &s);
            assert_eq!(grads[k], vec![m, g[0], g[1], g[2]]);
        }
        assert!(stdout.contains("error-checks-failed 0"), "{stdout}");
    }
}

/// A power law of sliding velocity without a clamp: μ = 0.5 (v / 1 m/s)^-1 is 0.5 at 1 m/s,
/// 500 at 1 mm/s and ∞ at rest — sound where it is loaded, broken between.
fn broken_law(dir: &Path) -> PathBuf {
    let p = dir.join("broken.json");
    std::fs::write(
        &p,
        r#"{"law": "power", "mu_ref": 0.5, "p_ref_MPa": 1000, "v_ref_m_per_min": 60, "a": 0, "b": -1}"#,
    )
    .unwrap();
    p
}

/// Issue 62: each array with its length (a short one refused before anything is read or
/// written) and the law's μ checked against the physics table (GREYBOX_ERR_MU, outputs NaN).
#[test]
fn c_arrays_are_checked_against_their_lengths_and_mu_against_the_physics_table() {
    let lib = build_library();
    let dir = tempfile::tempdir().unwrap();
    let exe = dir.path().join("test_checks");
    gcc(&lib, "tests/c/test_checks.c", &exe);
    let law = &law_files(dir.path())[0];
    let out = Command::new(&exe)
        .arg(law)
        .arg(broken_law(dir.path()))
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success() && stdout.contains("checks-failed 0"),
        "{stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn eight_c_threads_at_once() {
    let lib = build_library();
    let dir = tempfile::tempdir().unwrap();
    let exe = dir.path().join("test_threads");
    gcc(&lib, "tests/c/test_threads.c", &exe);
    let law = &law_files(dir.path())[0];
    let out = Command::new(&exe).arg(law).output().unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success() && stdout.contains("threads 8 bad 0"),
        "{stdout}"
    );
}

#[test]
fn fortran_program_gets_the_same_mu() {
    let have = Command::new("gfortran")
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success());
    if !have {
        assert!(
            std::env::var("GREYBOX_REQUIRE_FORTRAN").is_err(),
            "gfortran is required (GREYBOX_REQUIRE_FORTRAN is set) but not installed"
        );
        eprintln!("gfortran not installed: skipping the Fortran check (.ci/run installs it)");
        return;
    }
    let lib = build_library();
    let dir = tempfile::tempdir().unwrap();
    let exe = dir.path().join("test_fortran");
    let st = Command::new("gfortran")
        .arg("-O2")
        .arg("-J")
        .arg(dir.path())
        .arg(manifest().join("fortran/greybox.f90"))
        .arg(manifest().join("tests/c/test_fortran.f90"))
        .arg(&lib)
        .args(["-lpthread", "-ldl", "-lm", "-o"])
        .arg(&exe)
        .status()
        .expect("gfortran");
    assert!(st.success());
    let law_path = &law_files(dir.path())[0];
    let law = greybox_friction::spec::load_law(law_path).unwrap();
    let out = Command::new(&exe).arg(law_path).output().unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{stdout}");
    let mus: Vec<f64> = stdout
        .lines()
        .filter_map(|l| l.trim().strip_prefix("mu "))
        .map(|s| s.trim().parse().unwrap())
        .collect();
    for (k, (p, v)) in [(1.0e9, 0.5), (1.5e9, 1.5), (2.0e9, 3.5)]
        .iter()
        .enumerate()
    {
        let expect = law.mu(&ContactState {
            pressure_pa: *p,
            sliding_velocity_m_s: *v,
            temperature_k: 293.15,
        });
        assert_eq!(
            mus[k].to_bits(),
            expect.to_bits(),
            "point {k}: {} vs {expect}",
            mus[k]
        );
    }
    assert!(stdout.contains("error pressure[0]"), "{stdout}");
    assert!(
        stdout.contains("length velocity_m_s holds 2 values"),
        "{stdout}"
    );
    let checked: Vec<f64> = stdout
        .lines()
        .filter_map(|l| l.trim().strip_prefix("checked "))
        .map(|s| s.trim().parse().unwrap())
        .collect();
    assert_eq!(checked, mus, "greybox_mu gives greybox_law_mu's values");
}

/// The example user routines (Abaqus FRIC_COEF and VFRICTION, DEFORM USRBCC) compile with
/// gfortran against stub include files (the solvers themselves are not available here).
#[test]
fn example_user_routines_compile() {
    let have = Command::new("gfortran")
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success());
    if !have {
        assert!(
            std::env::var("GREYBOX_REQUIRE_FORTRAN").is_err(),
            "gfortran is required but not installed"
        );
        eprintln!("gfortran not installed: skipping");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    for f in [
        "abaqus_fric_coef.f",
        "abaqus_vfriction.f",
        "deform_usrbcc.f",
    ] {
        let out = Command::new("gfortran")
            .args(["-c", "-ffixed-line-length-132", "-Wall"])
            .arg("-I")
            .arg(manifest().join("examples/stubs"))
            .arg("-J")
            .arg(dir.path())
            .arg(manifest().join("examples").join(f))
            .arg("-o")
            .arg(dir.path().join(format!("{f}.o")))
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{f}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
}

/// A model file with a valid hash but a cyclic tree: the C ABI refuses it with an error
/// naming the field (it used to panic inside the host solver, or hang on the cycle).
#[test]
fn a_corrupted_model_is_an_error_code_not_a_panic_or_a_hang() {
    use greybox_model::mlp::Activation;
    use greybox_model::{Family, FittedModel};
    let mut m = common::small_model(Family::GradientBoosting, Activation::Relu);
    let FittedModel::TreeEnsemble(t) = &mut m.model else {
        unreachable!()
    };
    let k = t
        .nodes
        .iter()
        .position(|n| n.feature != greybox_model::tree::LEAF)
        .unwrap();
    t.nodes[k].left = k as u32; // points at itself
    let m = m.seal().unwrap();
    let d = tempfile::tempdir().unwrap();
    let p = d.path().join("cyclic.json");
    m.save(&p).unwrap();
    let path = std::ffi::CString::new(p.to_str().unwrap()).unwrap();
    let mut law: *mut greybox_ffi::GreyboxLaw = std::ptr::null_mut();
    let code = unsafe { greybox_ffi::greybox_law_load(path.as_ptr(), &mut law) };
    assert_ne!(code, 0);
    assert!(law.is_null());
    let mut buf = vec![0 as std::ffi::c_char; 512];
    unsafe { greybox_ffi::greybox_last_error(buf.as_mut_ptr(), buf.len()) };
    let msg = unsafe { std::ffi::CStr::from_ptr(buf.as_ptr()) }
        .to_string_lossy()
        .into_owned();
    assert!(
        msg.contains("cyclic.json") && msg.contains("would loop"),
        "{msg}"
    );
}
