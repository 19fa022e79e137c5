//! Parallel writes into disjoint ranges of one slice.
//!
//! The half-list passes give each particle chunk the contiguous range of pair slots of its
//! particles (CSR rows), so the chunks write disjoint ranges of the pair buffers; rayon has
//! no variable-size chunking, hence this small wrapper. Its only unsafe promise is that no
//! two live ranges overlap.

use std::marker::PhantomData;
use std::ops::Range;

/// A mutable slice shared between threads that each take a disjoint range of it.
pub(crate) struct DisjointMut<'a, T> {
    ptr: *mut T,
    len: usize,
    _slice: PhantomData<&'a mut [T]>,
}

// SAFETY: the wrapper hands out `&mut [T]` to disjoint ranges only (the caller's promise in
// `range`), which is what `&mut [T]: Send` already allows across threads.
unsafe impl<T: Send> Send for DisjointMut<'_, T> {}
unsafe impl<T: Send> Sync for DisjointMut<'_, T> {}

impl<'a, T> DisjointMut<'a, T> {
    pub(crate) fn new(slice: &'a mut [T]) -> Self {
        DisjointMut {
            ptr: slice.as_mut_ptr(),
            len: slice.len(),
            _slice: PhantomData,
        }
    }

    /// The sub-slice `r`.
    ///
    /// # Safety
    /// No other range obtained from this wrapper and still in use may overlap `r`.
    #[inline]
    #[allow(clippy::mut_from_ref)] // disjointness is the caller's promise, see above
    pub(crate) unsafe fn range(&self, r: Range<usize>) -> &'a mut [T] {
        assert!(
            r.start <= r.end && r.end <= self.len,
            "range {r:?} outside 0..{}",
            self.len
        );
        // SAFETY: in bounds (checked above); exclusive by the caller's promise.
        unsafe { std::slice::from_raw_parts_mut(self.ptr.add(r.start), r.end - r.start) }
    }
}
