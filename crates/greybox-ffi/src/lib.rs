//! The greybox C ABI: load a friction law (law file, model file or table) once, evaluate μ —
//! and ∂μ/∂p, ∂μ/∂v, ∂μ/∂T for implicit solvers — for batches of contact states, free it.
//!
//! Contract (see `include/greybox.h` and `fortran/greybox.f90`):
//! * every function returns a status code (`GREYBOX_OK` = 0) and never unwinds a panic into
//!   the caller; the message of the last failure on the calling thread is available from
//!   `greybox_last_error`;
//! * a loaded law is immutable: any number of threads may evaluate it at once;
//! * evaluation does not allocate; inputs are validated first (NaN, negative pressure) and
//!   the outputs are written only on success;
//! * every array comes with its length ([`greybox_law_eval`]): an array shorter than the
//!   batch is refused (`GREYBOX_ERR_LENGTH`, naming the array) before any value is read or
//!   written — a wrong count never reads or writes past the caller's arrays (the Fortran
//!   module passes `size()` of each array itself); `greybox_law_mu` / `greybox_law_mu_grad`,
//!   which take one count for all arrays, remain for existing callers;
//! * every μ the law gives is checked against the physics table's possible range (0..3) and
//!   every derivative to be finite: a law that gives μ = −inf or 1000 between the checks made
//!   when it was loaded returns `GREYBOX_ERR_MU` naming the state, and its outputs are all
//!   set to NaN (a caller that ignores the code sees NaN, never a plausible-looking number);
//! * SI units: pressure in Pa, sliding velocity in m/s, temperature in K.

use greybox_core::{ContactState, FrictionLaw};
use greybox_friction::gradient::mu_and_gradient;
use std::cell::RefCell;
use std::ffi::{c_char, CStr};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::Path;

pub const GREYBOX_OK: i32 = 0;
pub const GREYBOX_ERR_NULL: i32 = 1;
pub const GREYBOX_ERR_LOAD: i32 = 2;
pub const GREYBOX_ERR_INPUT: i32 = 3;
pub const GREYBOX_ERR_PANIC: i32 = 4;
/// An array shorter than the batch (`n`).
pub const GREYBOX_ERR_LENGTH: i32 = 5;
/// The law gave a μ outside the physics table's possible range, or a non-finite derivative.
pub const GREYBOX_ERR_MU: i32 = 6;

/// An opaque loaded law.
pub struct GreyboxLaw {
    law: Box<dyn FrictionLaw>,
}

thread_local! {
    static LAST_ERROR: RefCell<String> = const { RefCell::new(String::new()) };
}

fn fail(code: i32, msg: impl Into<String>) -> i32 {
    let msg = msg.into();
    LAST_ERROR.with(|e| *e.borrow_mut() = msg);
    code
}

fn guarded(f: impl FnOnce() -> i32) -> i32 {
    match catch_unwind(AssertUnwindSafe(f)) {
        Ok(code) => code,
        Err(_) => fail(
            GREYBOX_ERR_PANIC,
            "internal error (panic caught at the C boundary)",
        ),
    }
}

/// Load a law from `path` (NUL-terminated UTF-8). On success `*out` holds a handle to free
/// with `greybox_law_free`.
///
/// # Safety
/// `path` must be a valid NUL-terminated string and `out` a valid pointer, or null (an
/// error is returned).
#[no_mangle]
pub unsafe extern "C" fn greybox_law_load(path: *const c_char, out: *mut *mut GreyboxLaw) -> i32 {
    guarded(|| {
        if path.is_null() || out.is_null() {
            return fail(
                GREYBOX_ERR_NULL,
                "greybox_law_load: null path or output pointer",
            );
        }
        // SAFETY: checked non-null; the caller promises NUL termination.
        let p = match unsafe { CStr::from_ptr(path) }.to_str() {
            Ok(s) => s,
            Err(_) => return fail(GREYBOX_ERR_LOAD, "greybox_law_load: path is not UTF-8"),
        };
        match greybox_friction::spec::load_law(Path::new(p)) {
            Ok(law) => {
                // SAFETY: checked non-null.
                unsafe { *out = Box::into_raw(Box::new(GreyboxLaw { law })) };
                GREYBOX_OK
            }
            Err(e) => fail(GREYBOX_ERR_LOAD, e.to_string()),
        }
    })
}

/// Free a law (null is ignored).
///
/// # Safety
/// `law` must come from `greybox_law_load` and not be used afterwards.
#[no_mangle]
pub unsafe extern "C" fn greybox_law_free(law: *mut GreyboxLaw) {
    if !law.is_null() {
        let _ = catch_unwind(AssertUnwindSafe(|| {
            // SAFETY: the caller passes a pointer from greybox_law_load exactly once.
            drop(unsafe { Box::from_raw(law) });
        }));
    }
}

unsafe fn slice<'a>(p: *const f64, n: usize) -> Option<&'a [f64]> {
    // SAFETY: the caller promises `n` readable values when non-null.
    (!p.is_null()).then(|| unsafe { std::slice::from_raw_parts(p, n) })
}

unsafe fn slice_mut<'a>(p: *mut f64, n: usize) -> Option<&'a mut [f64]> {
    // SAFETY: the caller promises `n` writable values when non-null.
    (!p.is_null()).then(|| unsafe { std::slice::from_raw_parts_mut(p, n) })
}

#[inline]
fn state(p: &[f64], v: &[f64], t: Option<&[f64]>, i: usize) -> ContactState {
    ContactState {
        pressure_pa: p[i],
        sliding_velocity_m_s: v[i],
        temperature_k: t.map(|t| t[i]).unwrap_or(ContactState::ROOM_TEMPERATURE_K),
    }
}

/// μ for `n` contact states. `temperature_k` may be null (room temperature). Every array
/// must hold `n` values; prefer [`greybox_law_eval`], which checks each array's length.
///
/// # Safety
/// Non-null arrays must hold `n` values; `law` must be a live handle.
#[no_mangle]
pub unsafe extern "C" fn greybox_law_mu(
    law: *const GreyboxLaw,
    n: usize,
    pressure_pa: *const f64,
    velocity_m_s: *const f64,
    temperature_k: *const f64,
    mu: *mut f64,
) -> i32 {
    // SAFETY: forwarded caller contract (every array holds `n` values).
    unsafe {
        greybox_law_mu_grad(
            law,
            n,
            pressure_pa,
            velocity_m_s,
            temperature_k,
            mu,
            std::ptr::null_mut(),
            std::ptr::null_mut(),
            std::ptr::null_mut(),
        )
    }
}

/// μ and, where the output pointers are non-null, ∂μ/∂p (1/Pa), ∂μ/∂v (s/m), ∂μ/∂T (1/K).
/// Every array must hold `n` values; prefer [`greybox_law_eval`].
///
/// # Safety
/// Non-null arrays must hold `n` values; `law` must be a live handle.
#[no_mangle]
pub unsafe extern "C" fn greybox_law_mu_grad(
    law: *const GreyboxLaw,
    n: usize,
    pressure_pa: *const f64,
    velocity_m_s: *const f64,
    temperature_k: *const f64,
    mu: *mut f64,
    dmu_dp: *mut f64,
    dmu_dv: *mut f64,
    dmu_dt: *mut f64,
) -> i32 {
    // SAFETY: forwarded caller contract (every array holds `n` values).
    unsafe {
        greybox_law_eval(
            law,
            n,
            pressure_pa,
            n,
            velocity_m_s,
            n,
            temperature_k,
            n,
            mu,
            n,
            dmu_dp,
            n,
            dmu_dv,
            n,
            dmu_dt,
            n,
        )
    }
}

/// An array argument shorter than the batch: the error naming it, or `None`. A null array
/// has no length to check (its pointer is checked where it is required).
fn short_array(name: &str, ptr_null: bool, len: usize, n: usize) -> Option<String> {
    (!ptr_null && len < n).then(|| {
        format!("{name} holds {len} values, but the batch has n = {n} states: pass each array's own length (nothing was read or written)")
    })
}

/// The lengths of the arrays of one call, checked against `n` before any is touched.
fn check_lengths(n: usize, arrays: &[(&str, bool, usize)]) -> Result<(), String> {
    for (name, null, len) in arrays {
        if let Some(e) = short_array(name, *null, *len, n) {
            return Err(e);
        }
    }
    Ok(())
}

/// The check of one computed μ and its derivatives (no allocation unless refused): μ inside
/// the physics table's possible range, every derivative finite.
fn check_mu(i: usize, s: &ContactState, mu: f64, grad: Option<[f64; 3]>) -> Result<(), String> {
    use greybox_core::physics::{self, Quantity};
    let bad_grad = grad.is_some_and(|g| g.iter().any(|x| !x.is_finite()));
    if Quantity::Mu.hard().contains(&mu) && !bad_grad {
        return Ok(());
    }
    let at = format!(
        "state {i} (p = {} Pa, v = {} m/s, T = {} K)",
        s.pressure_pa, s.sliding_velocity_m_s, s.temperature_k
    );
    let why = match physics::check(Quantity::Mu, mu, "the law's μ") {
        Err(e) => e,
        Ok(_) => format!("a derivative is not finite: {:?}", grad.unwrap_or_default()),
    };
    Err(format!(
        "{at}: {why}: the law is broken between the points checked when it was loaded (outputs set to NaN)"
    ))
}

/// μ and, where the output pointers are non-null, ∂μ/∂p (1/Pa), ∂μ/∂v (s/m), ∂μ/∂T (1/K) for
/// `n` contact states, every array with its length: an array shorter than `n` is refused
/// (`GREYBOX_ERR_LENGTH`) before anything is read. `temperature_k` may be null (room
/// temperature). A μ outside the physics table's possible range or a non-finite derivative is
/// `GREYBOX_ERR_MU`, with every output set to NaN.
///
/// # Safety
/// Each non-null array must hold at least its stated length of values; `law` must be a live
/// handle.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn greybox_law_eval(
    law: *const GreyboxLaw,
    n: usize,
    pressure_pa: *const f64,
    pressure_len: usize,
    velocity_m_s: *const f64,
    velocity_len: usize,
    temperature_k: *const f64,
    temperature_len: usize,
    mu: *mut f64,
    mu_len: usize,
    dmu_dp: *mut f64,
    dmu_dp_len: usize,
    dmu_dv: *mut f64,
    dmu_dv_len: usize,
    dmu_dt: *mut f64,
    dmu_dt_len: usize,
) -> i32 {
    guarded(|| {
        if law.is_null() {
            return fail(GREYBOX_ERR_NULL, "null law handle");
        }
        if pressure_pa.is_null() || velocity_m_s.is_null() || mu.is_null() {
            return fail(GREYBOX_ERR_NULL, "null pressure, velocity or mu array");
        }
        if let Err(msg) = check_lengths(
            n,
            &[
                ("pressure_pa", false, pressure_len),
                ("velocity_m_s", false, velocity_len),
                ("temperature_k", temperature_k.is_null(), temperature_len),
                ("mu", false, mu_len),
                ("dmu_dp", dmu_dp.is_null(), dmu_dp_len),
                ("dmu_dv", dmu_dv.is_null(), dmu_dv_len),
                ("dmu_dt", dmu_dt.is_null(), dmu_dt_len),
            ],
        ) {
            return fail(GREYBOX_ERR_LENGTH, msg);
        }
        // SAFETY: every non-null array holds at least `n` values (its length, checked above).
        let (l, p, v, t, m) = unsafe {
            (
                &*law,
                slice(pressure_pa, n),
                slice(velocity_m_s, n),
                slice(temperature_k, n),
                slice_mut(mu, n),
            )
        };
        let (Some(p), Some(v), Some(m)) = (p, v, m) else {
            return fail(GREYBOX_ERR_NULL, "null pressure, velocity or mu array");
        };
        if let Err(msg) = greybox_core::contact::check_states(p, v, t) {
            return fail(GREYBOX_ERR_INPUT, msg);
        }
        // SAFETY: as above.
        let grads = unsafe {
            [
                slice_mut(dmu_dp, n),
                slice_mut(dmu_dv, n),
                slice_mut(dmu_dt, n),
            ]
        };
        match evaluate(l.law.as_ref(), p, v, t, m, grads) {
            Ok(()) => GREYBOX_OK,
            Err(msg) => fail(GREYBOX_ERR_MU, msg),
        }
    })
}

/// μ (and the derivatives wanted) at every state, each checked ([`check_mu`]) before it is
/// written; on a refused one every output is set to NaN and the error returned.
fn evaluate(
    law: &dyn FrictionLaw,
    p: &[f64],
    v: &[f64],
    t: Option<&[f64]>,
    m: &mut [f64],
    mut grads: [Option<&mut [f64]>; 3],
) -> Result<(), String> {
    let with_grad = grads.iter().any(Option::is_some);
    for i in 0..m.len() {
        let s = state(p, v, t, i);
        let (mu_i, g) = if with_grad {
            let (mu_i, g) = mu_and_gradient(law, &s);
            (mu_i, Some(g))
        } else {
            (law.mu(&s), None)
        };
        if let Err(msg) = check_mu(i, &s, mu_i, g) {
            m.fill(f64::NAN);
            for out in grads.iter_mut().flatten() {
                out.fill(f64::NAN);
            }
            return Err(msg);
        }
        m[i] = mu_i;
        if let Some(g) = g {
            for (out, x) in grads.iter_mut().zip(g) {
                if let Some(out) = out {
                    out[i] = x;
                }
            }
        }
    }
    Ok(())
}

/// Copy the calling thread's last error message into `buf` (NUL-terminated, truncated to
/// `len`); returns the message length without the NUL.
///
/// # Safety
/// `buf` must hold `len` bytes, or be null.
#[no_mangle]
pub unsafe extern "C" fn greybox_last_error(buf: *mut c_char, len: usize) -> usize {
    LAST_ERROR.with(|e| {
        let e = e.borrow();
        let bytes = e.as_bytes();
        if !buf.is_null() && len > 0 {
            let k = bytes.len().min(len - 1);
            // SAFETY: the caller promises `len` writable bytes.
            unsafe {
                std::ptr::copy_nonoverlapping(bytes.as_ptr(), buf as *mut u8, k);
                *buf.add(k) = 0;
            }
        }
        bytes.len()
    })
}

/// The library version, a static NUL-terminated string.
#[no_mangle]
pub extern "C" fn greybox_version() -> *const c_char {
    concat!(env!("CARGO_PKG_VERSION"), "\0").as_ptr() as *const c_char
}
