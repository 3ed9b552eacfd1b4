//! Arrays of `f32` that start at chosen offsets within a 4 KiB page.
//!
//! The per-slot pass reads and writes up to eighteen arrays of one length slot by slot.
//! Allocated one after another they start at nearly the same offset within a page (a 64 x 64 cloth's
//! are 16 KiB each), so a load from one array and a store just made to another at the same
//! slot share their low twelve address bits, and the processor holds the load back as if it
//! read the store's bytes (4K aliasing). Each array here starts at its own offset, spread over
//! the page: a burning 64 x 64 cloth's dynamics took 0.331–0.338 ms a frame with the arrays
//! where the allocator put them and 0.304–0.317 spread (three alternated runs of `stress
//! --default-only`), 32 x 32 0.087–0.088 and 0.080–0.084. (Those runs spread eighteen
//! arrays over seventeen offsets, so two shared one; with one each, three more alternated
//! runs: 64 x 64 0.307–0.311 → 0.302–0.306, 32 x 32 0.081–0.083 → 0.080–0.081.)

use core::ops::{Deref, DerefMut};

/// Bytes in the page the offsets are taken within.
const PAGE: usize = 4096;

/// The offset, bytes within a page, of array `k` of `count` spread evenly over the page, each
/// at the start of a cache line of its own (for `count` up to 64).
pub(super) fn spread(k: usize, count: usize) -> usize {
    (k * PAGE / count.max(1)) / 64 * 64 % PAGE
}

/// An array of `f32` whose first element lies `offset` bytes past the start of a page (as
/// [`Staggered::reset`] placed it: a clone holds the same values wherever its allocator puts
/// them). Reads and writes as a slice.
#[derive(Clone, Debug, Default)]
pub(super) struct Staggered {
    buffer: Vec<f32>,
    start: usize,
    len: usize,
}

impl Staggered {
    /// `len` copies of `value`, the first `offset` bytes past the start of a page (`offset`
    /// taken modulo the page and rounded down to a whole `f32`). Allocates only when the
    /// array grows.
    pub fn reset(&mut self, len: usize, value: f32, offset: usize) {
        let slack = PAGE / size_of::<f32>();
        if self.buffer.len() < len + slack {
            self.buffer = vec![0.0; len + slack];
        }
        let base = self.buffer.as_ptr() as usize % PAGE;
        let wanted = offset % PAGE;
        self.start = (wanted + PAGE - base) % PAGE / size_of::<f32>();
        self.len = len;
        self.fill(value);
    }

    /// Heap memory held, in `f32`s.
    pub fn capacity(&self) -> usize {
        self.buffer.capacity()
    }
}

impl Deref for Staggered {
    type Target = [f32];

    fn deref(&self) -> &[f32] {
        &self.buffer[self.start..self.start + self.len]
    }
}

impl DerefMut for Staggered {
    fn deref_mut(&mut self) -> &mut [f32] {
        &mut self.buffer[self.start..self.start + self.len]
    }
}

impl<'a> IntoIterator for &'a Staggered {
    type Item = &'a f32;
    type IntoIter = core::slice::Iter<'a, f32>;

    fn into_iter(self) -> Self::IntoIter {
        self.iter()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each array starts at the offset asked for within a page, holds `len` copies of the
    /// value, and keeps its place when reset to a length it has room for.
    #[test]
    fn an_array_starts_where_it_is_asked_to_within_a_page() {
        let mut arrays: Vec<Staggered> = (0..5).map(|_| Staggered::default()).collect();
        for (k, array) in arrays.iter_mut().enumerate() {
            let offset = 832 * k + 4;
            array.reset(1000, 1.5, offset);
            assert_eq!(array.as_ptr() as usize % PAGE, offset % PAGE);
            assert_eq!(array.len(), 1000);
            assert!(array.iter().all(|&v| v == 1.5));
            let before = array.capacity();
            array[999] = 2.0;
            array.reset(700, -1.0, offset + PAGE);
            assert_eq!(array.as_ptr() as usize % PAGE, offset % PAGE);
            assert_eq!(array.capacity(), before, "no new allocation");
            assert_eq!(array.len(), 700);
            assert!(array.iter().all(|&v| v == -1.0));
        }
        let copy = arrays[3].clone();
        assert_eq!(&copy[..], &arrays[3][..]);
    }

    /// Eighteen arrays spread over a page start on eighteen different cache lines.
    #[test]
    fn spread_offsets_are_distinct_cache_lines() {
        let mut lines: Vec<usize> = (0..18).map(|k| spread(k, 18)).collect();
        assert!(
            lines
                .iter()
                .all(|&offset| offset % 64 == 0 && offset < PAGE)
        );
        lines.dedup();
        assert_eq!(lines.len(), 18);
    }
}
