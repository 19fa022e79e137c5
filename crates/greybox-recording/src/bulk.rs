//! Large sample vectors, allocated the way bulk readers need them.

/// A zeroed vector for `n` values, or the message that the memory for them is not available
/// (an error for the reader to return, never an abort: a large valid recording under a memory
/// limit is refused, not killed). Large ones are backed by transparent huge pages where the
/// system offers them (as numpy does): filling 80 MB then costs 40 page faults rather than
/// 20,000.
pub(crate) fn zeroed_values(n: usize) -> Result<Vec<f64>, String> {
    let unavailable = || {
        format!(
            "{n} values need {} of memory, which is not available",
            greybox_core::budget::bytes_text(n as f64 * 8.0)
        )
    };
    if n == 0 {
        return Ok(Vec::new());
    }
    let layout = std::alloc::Layout::array::<f64>(n).map_err(|_| unavailable())?;
    // SAFETY: the layout has a non-zero size (n > 0); a null pointer is checked below.
    let ptr = unsafe { std::alloc::alloc_zeroed(layout) }.cast::<f64>();
    if ptr.is_null() {
        return Err(unavailable());
    }
    // SAFETY: `ptr` was allocated by the global allocator with the layout of `n` f64 (what a
    // `Vec<f64>` of capacity `n` uses), and all `n` values are initialised (zero bits are 0.0).
    let v = unsafe { Vec::from_raw_parts(ptr, n, n) };
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
    Ok(v)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Memory that cannot be had is an error with the size, never an abort.
    #[test]
    fn values_that_do_not_fit_are_an_error_not_an_abort() {
        assert_eq!(zeroed_values(3).unwrap(), [0.0; 3]);
        assert!(zeroed_values(0).unwrap().is_empty());
        for n in [1usize << 58, usize::MAX / 4] {
            let e = zeroed_values(n).unwrap_err();
            assert!(
                e.contains("not available") && e.contains(&n.to_string()),
                "{e}"
            );
        }
    }
}
