//! A slice that several threads write at once, each in its own part, for work whose parts
//! change from one phase to the next (see [`run_phases`](super::run_phases)): the bands of a
//! cloth's even springs overlap those of its odd ones, so the parts cannot be split off once
//! as safe `&mut` slices.
#![allow(unsafe_code)]

use core::marker::PhantomData;
use core::ops::Range;

/// A mutable slice handed to several threads, each of which takes parts of it that no other
/// thread touches while it holds them.
pub(crate) struct Disjoint<'a, T> {
    start: *mut T,
    len: usize,
    slice: PhantomData<&'a mut [T]>,
}

// SAFETY: a `Disjoint` is the `&mut [T]` it was made from, handed out in parts; sending or
// sharing it sends `T`s between threads, and the callers of `part`/`read` keep the parts
// apart (see there).
unsafe impl<T: Send> Send for Disjoint<'_, T> {}
// SAFETY: as above; shared `read` parts also need `T: Sync`.
unsafe impl<T: Send + Sync> Sync for Disjoint<'_, T> {}

impl<'a, T> Disjoint<'a, T> {
    /// Holds `slice` for as long as the `Disjoint` lives.
    pub fn new(slice: &'a mut [T]) -> Self {
        Self {
            start: slice.as_mut_ptr(),
            len: slice.len(),
            slice: PhantomData,
        }
    }

    /// Elements in all.
    pub fn len(&self) -> usize {
        self.len
    }

    /// The first element, for a caller that reads and writes its parts through a pointer
    /// (under the promises of [`Self::part`] and [`Self::read`]).
    pub fn as_mut_ptr(&self) -> *mut T {
        self.start
    }

    /// The elements in `range`, to write. Panics if `range` is out of bounds.
    ///
    /// # Safety
    /// While the returned slice is used, no other slice from this `Disjoint` that overlaps
    /// `range` may be used, on any thread.
    pub unsafe fn part(&self, range: Range<usize>) -> &'a mut [T] {
        assert!(
            range.start <= range.end && range.end <= self.len,
            "part out of bounds"
        );
        // SAFETY: in bounds of the slice this was made from, which outlives 'a; exclusive by
        // the caller's promise.
        unsafe { core::slice::from_raw_parts_mut(self.start.add(range.start), range.len()) }
    }

    /// The elements in `range`, to read. Panics if `range` is out of bounds.
    ///
    /// # Safety
    /// While the returned slice is used, no slice from [`Self::part`] that overlaps `range`
    /// may be used, on any thread.
    pub unsafe fn read(&self, range: Range<usize>) -> &'a [T] {
        assert!(
            range.start <= range.end && range.end <= self.len,
            "part out of bounds"
        );
        // SAFETY: in bounds; nobody writes these elements meanwhile, by the caller's promise.
        unsafe { core::slice::from_raw_parts(self.start.add(range.start), range.len()) }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parts_write_through_to_the_slice() {
        let mut data = vec![0u32; 10];
        {
            let shared = Disjoint::new(&mut data);
            // SAFETY: the two parts do not overlap.
            let (a, b) = unsafe { (shared.part(0..4), shared.part(4..10)) };
            a.fill(1);
            b.fill(2);
            // SAFETY: no part is used any more.
            assert_eq!(unsafe { shared.read(3..5) }, &[1, 2]);
        }
        assert_eq!(data, [1, 1, 1, 1, 2, 2, 2, 2, 2, 2]);
    }

    #[test]
    #[should_panic(expected = "out of bounds")]
    fn a_part_past_the_end_panics() {
        let mut data = [0u8; 4];
        let shared = Disjoint::new(&mut data);
        // SAFETY: the only part taken.
        let _ = unsafe { shared.part(2..5) };
    }
}
