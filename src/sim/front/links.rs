//! Each particle's in-plane links: the structural and shear springs (a mesh's edges) it ends,
//! with the particle at the other end, row by row.
//!
//! The heat push and the flame visit a burning particle's in-plane neighbours every step.
//! Found through the springs, each visit read the kind and both ends of every spring the
//! particle touches (bending springs and the springs it only spans included), scattered over
//! arrays of several hundred thousand springs on a big cloth. A row here holds just the links,
//! in spring order, next to one another. A spring [`Front::sever`](super::Front::sever) cuts
//! leaves both ends' rows.

use super::NONE;
use crate::sim::springs::{SpringKind, Springs};

/// Compressed rows: `start[i]..start[i + 1]` indexes `spring` and `other` for particle `i`;
/// `other` is `NONE` where the link was cut.
#[derive(Clone, Debug, Default)]
pub(super) struct InPlaneLinks {
    start: Vec<u32>,
    spring: Vec<u32>,
    other: Vec<u32>,
}

impl InPlaneLinks {
    /// The links of `n` particles through `springs` as they are now: for each spring that is
    /// not a bending one and joins two particles (both ends below `n`), one link in each end's
    /// row, rows in spring order.
    pub(super) fn build(&mut self, n: usize, springs: &Springs) {
        let count = springs.len();
        let (a, b, kind) = (
            &springs.a[..count],
            &springs.b[..count],
            &springs.kind[..count],
        );
        let links = |s: usize| {
            let (pa, pb) = (a[s] as usize, b[s] as usize);
            (kind[s] != SpringKind::Bend && pa != pb && pa < n && pb < n).then_some((pa, pb))
        };
        self.start.clear();
        self.start.resize(n + 1, 0);
        for s in 0..count {
            if let Some((pa, pb)) = links(s) {
                self.start[pa + 1] += 1;
                self.start[pb + 1] += 1;
            }
        }
        for i in 0..n {
            self.start[i + 1] += self.start[i];
        }
        let total = self.start[n] as usize;
        self.spring.clear();
        self.spring.resize(total, 0);
        self.other.clear();
        self.other.resize(total, NONE);
        // Each row filled from its end backwards, springs taken from the last: rows in spring
        // order, and `start` back at each row's start when done.
        for s in (0..count).rev() {
            if let Some((pa, pb)) = links(s) {
                for (end, other) in [(pb, pa), (pa, pb)] {
                    self.start[end + 1] -= 1;
                    let at = self.start[end + 1] as usize;
                    self.spring[at] = s as u32;
                    self.other[at] = other as u32;
                }
            }
        }
        // `start[i + 1]` now holds row `i`'s start: shift back by one.
        self.start.copy_within(1..=n, 0);
        self.start[n] = total as u32;
    }

    /// Particle `i`'s links not cut: (spring, particle at its other end).
    #[inline]
    pub(super) fn of(&self, i: usize) -> impl Iterator<Item = (usize, usize)> + '_ {
        let row = self.start[i] as usize..self.start[i + 1] as usize;
        self.spring[row.clone()]
            .iter()
            .zip(&self.other[row])
            .filter(|&(_, &other)| other != NONE)
            .map(|(&s, &other)| (s as usize, other as usize))
    }

    /// Removes spring `s`'s link from the rows of `ends` (its two ends before it was cut).
    pub(super) fn cut(&mut self, s: usize, ends: [usize; 2]) {
        for end in ends {
            if end + 1 >= self.start.len() {
                continue;
            }
            let row = self.start[end] as usize..self.start[end + 1] as usize;
            for at in row {
                if self.spring[at] as usize == s {
                    self.other[at] = NONE;
                }
            }
        }
    }

    /// Heap memory held, bytes (capacity, not length).
    pub(super) fn heap_bytes(&self) -> usize {
        (self.start.capacity() + self.spring.capacity() + self.other.capacity()) * size_of::<u32>()
    }
}
