//! A friction law evaluated through greybox's C ABI, the way an FE engine's Fortran user
//! routine (VFRIC, VFRICTION, …) calls it: load a law file once, then μ and its derivatives
//! for a batch of contact states per call, errors as return codes with a message to fetch.
//! (From C: `include/greybox.h`; from Fortran: `fortran/greybox.f90`; library:
//! `cargo build --release -p greybox-ffi`.)
//!
//! `cargo run --release -p greybox --example c_abi`

use greybox_ffi::{
    greybox_last_error, greybox_law_free, greybox_law_load, greybox_law_mu_grad, GreyboxLaw,
};
use std::ffi::CString;

fn main() -> anyhow::Result<()> {
    // a law file: Zorev, Coulomb μ = 0.4 until μp reaches the shear flow stress k = 600 MPa
    // (any law file, model file or table works the same way)
    let dir = tempfile::tempdir()?;
    let path = dir.path().join("law.json");
    std::fs::write(&path, r#"{"law": "zorev", "mu": 0.4, "k_MPa": 600.0}"#)?;
    let c_path = CString::new(path.to_str().expect("a UTF-8 temporary path"))?;
    let mut law: *mut GreyboxLaw = std::ptr::null_mut();
    // SAFETY: a NUL-terminated path and a valid out pointer.
    let rc = unsafe { greybox_law_load(c_path.as_ptr(), &mut law) };
    check(rc)?;
    let pressure_pa = [0.5e9, 1.0e9, 1.5e9, 2.0e9];
    let velocity_m_s = [1.0, 2.0, 3.0, 4.0];
    let (mut mu, mut dmu_dp, mut dmu_dv) = ([0.0; 4], [0.0; 4], [0.0; 4]);
    // SAFETY: every array holds 4 values; temperature null = room temperature; dμ/dT unused.
    let rc = unsafe {
        greybox_law_mu_grad(
            law,
            4,
            pressure_pa.as_ptr(),
            velocity_m_s.as_ptr(),
            std::ptr::null(),
            mu.as_mut_ptr(),
            dmu_dp.as_mut_ptr(),
            dmu_dv.as_mut_ptr(),
            std::ptr::null_mut(),
        )
    };
    check(rc)?;
    for k in 0..4 {
        println!(
            "p = {:4.0} MPa, v = {:.1} m/s: mu = {:.4}, dmu/dp = {:+.3e} 1/Pa, dmu/dv = {:+.3e} s/m",
            pressure_pa[k] * 1e-6,
            velocity_m_s[k],
            mu[k],
            dmu_dp[k],
            dmu_dv[k]
        );
    }
    // SAFETY: a live handle, freed once.
    unsafe { greybox_law_free(law) };
    // an error comes back as a code and a message, never as a crash in the host solver
    let missing = CString::new("no-such-law.json")?;
    let mut none: *mut GreyboxLaw = std::ptr::null_mut();
    // SAFETY: as above.
    let rc = unsafe { greybox_law_load(missing.as_ptr(), &mut none) };
    println!("loading a missing file: code {rc}, {}", last_error());
    Ok(())
}

/// The message of the last failed call on this thread.
fn last_error() -> String {
    let mut buf = vec![0u8; 512];
    // SAFETY: `buf` holds 512 bytes.
    let n = unsafe { greybox_last_error(buf.as_mut_ptr().cast(), buf.len()) };
    buf.truncate(n.min(buf.len() - 1));
    String::from_utf8_lossy(&buf).into_owned()
}

fn check(rc: i32) -> anyhow::Result<()> {
    if rc == 0 {
        Ok(())
    } else {
        anyhow::bail!("greybox C ABI error {rc}: {}", last_error())
    }
}
