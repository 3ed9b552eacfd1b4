//! Each particle's in-plane links: the structural and shear springs (a mesh's edges) it ends,
//! with the particle at the other end, row by row.
//!
//! The heat push and the flame visit a burning particle's in-plane neighbours every step.
//! Found through the springs, each visit read the kind and both ends of every spring the
//! particle touches (bending springs and the springs it only spans included), scattered over
//! arrays of several hundred thousand springs on a big cloth. A row here holds just the links,
//! in spring order, next to one another. A spring [`Front::sever`](super::Front::sever) cuts
//! leaves both ends' rows.

use super::{NONE, Rows};
use crate::sim::springs::{SpringKind, Springs};

/// Each particle's row of links: the springs (in spring order, from [`Rows`]) and, beside
/// each, the particle at its other end, `NONE` where the link was cut.
#[derive(Clone, Debug, Default)]
pub(super) struct InPlaneLinks {
    springs: Rows,
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
        self.springs.build(n, count, |s| {
            let (pa, pb) = (a[s], b[s]);
            let links = kind[s] != SpringKind::Bend && pa != pb && (pa as usize) < n;
            if links && (pb as usize) < n {
                [pa, pb, NONE, NONE]
            } else {
                [NONE; 4]
            }
        });
        self.other.clear();
        self.other.resize(self.springs.items.len(), NONE);
        for i in 0..n {
            let row = self.row(i);
            for (other, &s) in self.other[row.clone()]
                .iter_mut()
                .zip(&self.springs.items[row])
            {
                let (pa, pb) = (a[s as usize], b[s as usize]);
                *other = if pa as usize == i { pb } else { pa };
            }
        }
    }

    /// Particle `i`'s links not cut: (spring, particle at its other end).
    #[inline]
    pub(super) fn of(&self, i: usize) -> impl Iterator<Item = (usize, usize)> + '_ {
        let row = self.row(i);
        self.springs.items[row.clone()]
            .iter()
            .zip(&self.other[row])
            .filter(|&(_, &other)| other != NONE)
            .map(|(&s, &other)| (s as usize, other as usize))
    }

    /// Removes spring `s`'s link from the rows of `ends` (its two ends before it was cut).
    pub(super) fn cut(&mut self, s: usize, ends: [usize; 2]) {
        for end in ends {
            if end + 1 >= self.springs.start.len() {
                continue;
            }
            for at in self.row(end) {
                if self.springs.items[at] as usize == s {
                    self.other[at] = NONE;
                }
            }
        }
    }

    /// Where particle `i`'s row lies in `springs.items` and `other`.
    fn row(&self, i: usize) -> core::ops::Range<usize> {
        self.springs.start[i] as usize..self.springs.start[i + 1] as usize
    }

    /// Heap memory held, bytes (capacity, not length).
    pub(super) fn heap_bytes(&self) -> usize {
        self.springs.heap_bytes() + self.other.capacity() * size_of::<u32>()
    }
}
