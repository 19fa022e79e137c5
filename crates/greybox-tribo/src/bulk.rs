//! Large sample vectors, allocated the way bulk readers need them.

/// A zeroed vector for `n` values. Large ones are backed by transparent huge pages where
/// the system offers them (as numpy does): filling 80 MB then costs 40 page faults rather
/// than 20,000.
pub(crate) fn zeroed_values(n: usize) -> Vec<f64> {
    let v = vec![0.0; n];
    #[cfg(target_os = "linux")]
    {
        const HUGE: usize = 2 << 20;
        let bytes = std::mem::size_of_val(v.as_slice());
        let addr = v.as_ptr() as usize;
        let start = addr.next_multiple_of(HUGE);
        let end = (addr + bytes) / HUGE * HUGE;
        if bytes >= 4 * HUGE && end > start {
            // SAFETY: [start, end) lies inside `v`'s allocation; MADV_HUGEPAGE only asks the
            // kernel to back it with huge pages, contents and validity are unchanged, and a
            // refusal (huge pages disabled) is harmless.
            unsafe {
                libc::madvise(start as *mut libc::c_void, end - start, libc::MADV_HUGEPAGE);
            }
        }
    }
    v
}
