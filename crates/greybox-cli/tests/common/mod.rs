//! Helpers shared by the CLI integration tests.
#![allow(dead_code)]

use std::path::Path;
use std::process::{Command, Output};

/// Run the greybox binary in `cwd`.
pub fn greybox(args: &[&str], cwd: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_greybox"))
        .args(args)
        .current_dir(cwd)
        .output()
        .expect("run greybox")
}

/// Assert success; return stdout.
pub fn ok(out: &Output) -> String {
    assert!(
        out.status.success(),
        "stderr: {}\nstdout: {}",
        String::from_utf8_lossy(&out.stderr),
        String::from_utf8_lossy(&out.stdout)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// Assert failure; return stderr.
pub fn err(out: &Output) -> String {
    assert!(
        !out.status.success(),
        "expected failure, stdout: {}",
        String::from_utf8_lossy(&out.stdout)
    );
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// Text of the last `particles_*.vtk` written under `dir/vtk` (the final state of a run).
pub fn last_particle_vtk(dir: &Path) -> String {
    let mut v: Vec<_> = std::fs::read_dir(dir.join("vtk"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| {
            p.file_name()
                .unwrap()
                .to_string_lossy()
                .starts_with("particles_")
        })
        .collect();
    v.sort();
    std::fs::read_to_string(v.last().unwrap()).unwrap()
}
