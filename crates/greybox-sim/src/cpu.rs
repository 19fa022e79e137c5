//! Runtime CPU-feature dispatch for the hot loops.
//!
//! The release build targets the x86-64 baseline (SSE2) so that the binary runs anywhere.
//! The pair passes ([`crate::pair_lanes`]) are compiled three times — baseline, AVX2 and
//! AVX-512 (F + VL) — and the widest the running CPU has is picked at run time
//! (`is_x86_feature_detected!`). Rust never fuses a·b + c into one rounding, and the lane
//! sums run in a fixed order, so every path gives the same bits: the path taken never changes a result.
//!
//! A cap on the path (for comparisons and diagnosis) is handed in by the host: the command
//! line and the Python package read `GREYBOX_SIMD=baseline|avx2|avx512` ([`SIMD_ENV`]) at
//! start and pass its value to [`apply_cap`]; the library itself reads no environment. A
//! path the CPU lacks falls back to the widest one below it. Any other value sets no cap and
//! the host names it in one warning on stderr.

use std::sync::atomic::{AtomicU8, Ordering};

/// The instruction sets the pair passes are compiled for, narrowest first.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum SimdPath {
    Baseline = 1,
    Avx2 = 2,
    Avx512 = 3,
}

impl SimdPath {
    pub const ALL: [SimdPath; 3] = [SimdPath::Baseline, SimdPath::Avx2, SimdPath::Avx512];

    pub fn name(self) -> &'static str {
        match self {
            SimdPath::Baseline => "baseline",
            SimdPath::Avx2 => "avx2",
            SimdPath::Avx512 => "avx512",
        }
    }

    fn from_u8(v: u8) -> Option<SimdPath> {
        SimdPath::ALL.into_iter().find(|p| *p as u8 == v)
    }

    /// Whether the running CPU has this path's instructions.
    pub fn available(self) -> bool {
        match self {
            SimdPath::Baseline => true,
            #[cfg(target_arch = "x86_64")]
            SimdPath::Avx2 => std::arch::is_x86_feature_detected!("avx2"),
            #[cfg(target_arch = "x86_64")]
            SimdPath::Avx512 => {
                std::arch::is_x86_feature_detected!("avx512f")
                    && std::arch::is_x86_feature_detected!("avx512vl")
            }
            #[cfg(not(target_arch = "x86_64"))]
            _ => false,
        }
    }
}

/// The path in use (0: not chosen yet).
static ACTIVE: AtomicU8 = AtomicU8::new(0);

/// The widest available path at or below `cap`.
fn widest_up_to(cap: SimdPath) -> SimdPath {
    SimdPath::ALL
        .into_iter()
        .rev()
        .find(|p| *p <= cap && p.available())
        .unwrap_or(SimdPath::Baseline)
}

/// The environment variable the hosts (command line, Python package) read the cap from and
/// hand to [`apply_cap`].
pub const SIMD_ENV: &str = "GREYBOX_SIMD";

/// The path the pair passes run on: the widest the CPU has, capped by [`apply_cap`] or
/// [`set_path`] if the host called them.
pub fn active() -> SimdPath {
    if let Some(p) = SimdPath::from_u8(ACTIVE.load(Ordering::Relaxed)) {
        return p;
    }
    set_path(SimdPath::Avx512)
}

/// Caps the path at the one `value` names (`baseline`, `avx2`, `avx512`, any case; `None`
/// or empty: no cap) from now on, process-wide, and returns the path taken. Any other value
/// sets no cap and is returned in the warning the host prints.
pub fn apply_cap(value: Option<&str>) -> Result<SimdPath, String> {
    match cap_from(value) {
        Ok(cap) => Ok(set_path(cap)),
        Err(unknown) => {
            set_path(SimdPath::Avx512);
            Err(format!(
                "greybox: {SIMD_ENV}={unknown:?} is not one of baseline, avx2, avx512; \
                 no cap is set (the widest path the CPU has runs)"
            ))
        }
    }
}

/// The cap a `GREYBOX_SIMD` value sets: a path's name, or no cap when unset or empty; any
/// other value is returned as the error.
fn cap_from(value: Option<&str>) -> Result<SimdPath, String> {
    match value.map(str::trim) {
        None | Some("") => Ok(SimdPath::Avx512),
        Some(v) => SimdPath::ALL
            .into_iter()
            .find(|p| p.name().eq_ignore_ascii_case(v))
            .ok_or_else(|| v.to_string()),
    }
}

/// Runs the pair passes on `cap` (or the widest available path below it) from now on,
/// process-wide; returns the path taken. For tests and benchmarks that compare the paths.
pub fn set_path(cap: SimdPath) -> SimdPath {
    let p = widest_up_to(cap);
    ACTIVE.store(p as u8, Ordering::Relaxed);
    p
}

/// Defines a function whose body is compiled once per [`SimdPath`] (the body is inlined into
/// a baseline, an AVX2 and an AVX-512 copy) and that runs the copy of the active path.
macro_rules! multiversion {
    ($(#[$attr:meta])* $vis:vis fn $name:ident($($arg:ident: $ty:ty),* $(,)?) $body:block) => {
        $(#[$attr])*
        #[allow(clippy::too_many_arguments)]
        $vis fn $name($($arg: $ty),*) {
            #[inline(always)]
            #[allow(clippy::too_many_arguments)]
            fn body($($arg: $ty),*) $body
            #[cfg(target_arch = "x86_64")]
            {
                #[target_feature(enable = "avx2")]
                #[allow(clippy::too_many_arguments)]
                fn avx2($($arg: $ty),*) {
                    body($($arg),*)
                }
                #[target_feature(enable = "avx512f,avx512vl")]
                #[allow(clippy::too_many_arguments)]
                fn avx512($($arg: $ty),*) {
                    body($($arg),*)
                }
                match $crate::cpu::active() {
                    // SAFETY: `active` only returns paths the running CPU was checked for.
                    $crate::cpu::SimdPath::Avx512 => return unsafe { avx512($($arg),*) },
                    $crate::cpu::SimdPath::Avx2 => return unsafe { avx2($($arg),*) },
                    $crate::cpu::SimdPath::Baseline => {}
                }
            }
            body($($arg),*)
        }
    };
}
pub(crate) use multiversion;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn simd_cap_names_a_path_or_is_refused() {
        assert_eq!(cap_from(None), Ok(SimdPath::Avx512));
        assert_eq!(cap_from(Some("")), Ok(SimdPath::Avx512));
        assert_eq!(cap_from(Some("baseline")), Ok(SimdPath::Baseline));
        assert_eq!(cap_from(Some(" AVX2 ")), Ok(SimdPath::Avx2));
        assert_eq!(cap_from(Some("avx512")), Ok(SimdPath::Avx512));
        assert_eq!(cap_from(Some("avx3")), Err("avx3".to_string()));
        assert_eq!(cap_from(Some("sse")), Err("sse".to_string()));
    }
}
