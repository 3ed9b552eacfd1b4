//! Provot's stretch limit on the springs heat has shrunk, as the XPBD solver runs it: the
//! frame's limited springs sorted into the grid's bands, so the bands of one parity are
//! corrected at the same time, on any thread, with the same result.
//!
//! A limited spring is in-plane (structural or shear), so its ends are at most one row
//! apart: a spring whose upper end is in band `b` lies within `b`'s reach (its rows and the
//! two below), and bands two apart share no particle. A spring that does not fit (a cut
//! spring whose end has moved further) goes into a last bucket, corrected on its own after
//! the bands. A mesh's springs are all in that last bucket.
//!
//! Within a grid's bucket the springs go by colour: a family (east, south, the two
//! diagonals) and the parity of its first end's column (east) or row (the others), so the
//! springs of one colour share no particle. A pass then rarely reads what the spring before
//! it has just moved, and the processor corrects several springs at once instead of waiting
//! for each in turn (in the grid's spring order, each particle's east, south and diagonal
//! springs one after another, every correction waited for the one before).

use super::lanes::{GridLanes, GridSlots};
use crate::sim::particles::Particles;
use crate::sim::provot::STRETCH_TOLERANCE;
use crate::sim::springs::Springs;
use core::sync::atomic::{AtomicU32, Ordering};

/// Bits of a packed end that hold the index within its quarter grid; the quarter is above.
const INDEX_BITS: u32 = 30;

/// Colours of a grid's bucket: east, south, south-east and south-west springs, each by the
/// parity of its first end's column (east) or row (the rest), and one for any other spring.
const COLOURS: usize = 9;

/// A spring under the stretch limit for one frame: its ends (as slots, and packed: quarter
/// grid and index from the first row of its bucket's reach) and their inverse masses, and its
/// longest allowed length; gathered once a frame so a substep's pass reads one array in order.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct LimitedSpring {
    slots: [u32; 2],
    packed: [u32; 2],
    wa: f32,
    wb: f32,
    /// The allowed length, m (`scale ×` the rest length).
    limit: f32,
    /// The squared length past which the spring is corrected, m² (the limit and its tolerance).
    past: f32,
}

/// A band's reach as its stretch-limit pass reads and moves it: the rows of the reach in
/// every quarter grid, ends packed (quarter grid, index from the reach's first row).
///
/// One check per end (its index within the reach) stands for the six reads and writes of its
/// three axes, which go through a base pointer per axis and an offset per quarter grid. The
/// same passes through 24 slices (a quarter grid's part of the reach per axis and array, as
/// the spring projection takes them), each read and write loading its slice and checking its
/// bounds, took 24 ns a spring at 128 x 128 and 32 to 34 at
/// 256 x 256 (the burning stress cloth, timed with temporary clocks), against 16 to 21 this
/// way: the stretch limit was then the largest item of a big cloth's frame.
pub(super) struct Reach<'a> {
    /// Each axis' slot array of positions, from its first slot.
    x: [*const f32; 3],
    /// Each axis' slot array of displacements, from its first slot.
    u: [*mut f32; 3],
    /// The slot of the reach's first row in each quarter grid.
    first: [usize; 4],
    /// Slots of the reach in each quarter grid.
    len: usize,
    /// The reach's slots of every array, held as by `&'a mut`.
    arrays: core::marker::PhantomData<&'a mut [f32]>,
}

impl<'a> Reach<'a> {
    /// The reach whose rows start at slot `first[q]` of quarter grid `q` and run `len` slots,
    /// in the slot arrays that `x` and `u` point to (per axis).
    ///
    /// # Safety
    /// Slots `first[q]..first[q] + len` of every array are in bounds and, for as long as the
    /// reach lives, no position among them is written and no other thread reads or writes
    /// their displacements.
    #[allow(unsafe_code)]
    pub unsafe fn new(x: [*const f32; 3], u: [*mut f32; 3], first: [usize; 4], len: usize) -> Self {
        Self {
            x,
            u,
            first,
            len,
            arrays: core::marker::PhantomData,
        }
    }

    /// The slot of a packed end. Panics if the end is outside the reach (a spring sorted
    /// into the wrong bucket), which keeps the reads and writes in bounds.
    #[inline(always)]
    fn slot(&self, end: u32) -> usize {
        let (q, index) = unpack(end);
        assert!(
            index < self.len,
            "a stretch-limited spring outside its reach"
        );
        self.first[q & 3] + index
    }
}

/// Where a grid's rows are: its slots, and the band each row's springs are in.
#[derive(Clone, Debug, Default)]
struct GridPlaces {
    slots: Option<GridSlots>,
    band_of_row: Vec<u32>,
    /// By particle: its row, and its slot packed (quarter grid, and index from the quarter
    /// grid's first row), so placing a spring takes no division.
    row_of: Vec<u32>,
    home: Vec<u32>,
    /// Each band's first row and the end of its reach.
    reach: Vec<(u32, u32)>,
    /// Particles per grid row.
    columns: u32,
}

/// The frame's limited springs, by bucket (a grid's bands, then one for the rest), and the
/// lists of a bucket's passes.
#[derive(Clone, Debug, Default)]
pub(super) struct LimitedSprings {
    places: GridPlaces,
    springs: Vec<LimitedSpring>,
    /// Where each colour of each bucket starts in `springs` (bucket `b`'s colour `c` at
    /// `b × COLOURS + c`); one entry more than there are colours in all.
    start: Vec<u32>,
    /// Scratch for sorting: each spring with its bucket and colour, and where each one's next
    /// goes.
    gathered: Vec<(u32, LimitedSpring)>,
    next: Vec<u32>,
}

impl LimitedSprings {
    /// Lays out the buckets for a grid (`lanes`, `slots` and its `columns`) or, with `None`,
    /// a mesh, and reserves room for `springs` springs and `particles` particles.
    pub fn prepare(&mut self, grid: Option<(&GridLanes, GridSlots, u32)>, springs: usize) {
        self.places = match grid {
            Some((lanes, slots, columns)) => {
                let mut band_of_row = Vec::new();
                for (b, band) in lanes.bands.iter().enumerate() {
                    band_of_row.extend(band.rows.clone().map(|_| b as u32));
                }
                let particles = 0..columns * slots.rows();
                let quarter = slots.quarter_len();
                GridPlaces {
                    slots: Some(slots),
                    band_of_row,
                    row_of: particles.clone().map(|i| i / columns).collect(),
                    home: particles
                        .map(|i| {
                            let s = slots.slot(i % columns, i / columns);
                            (s / quarter) << INDEX_BITS | (s % quarter)
                        })
                        .collect(),
                    reach: lanes
                        .bands
                        .iter()
                        .map(|band| (band.reach.start, band.reach.end))
                        .collect(),
                    columns,
                }
            }
            None => GridPlaces::default(),
        };
        let keys = self.buckets() * COLOURS;
        for list in [&mut self.start, &mut self.next] {
            list.clear();
            list.reserve(keys + 1);
        }
        self.springs.clear();
        self.springs.reserve(springs);
        self.gathered.clear();
        self.gathered.reserve(springs);
    }

    /// Buckets: one per band and one for the rest.
    fn buckets(&self) -> usize {
        self.places.reach.len() + 1
    }

    /// No spring limited this frame.
    pub fn clear(&mut self) {
        self.springs.clear();
        self.start.clear();
    }

    /// Whether no spring is limited this frame.
    pub fn is_empty(&self) -> bool {
        self.springs.is_empty()
    }

    /// Whether the last bucket (springs outside any band, or a mesh's) has springs.
    pub fn has_rest(&self) -> bool {
        let n = self.start.len();
        n > COLOURS && self.start[n - 1] > self.start[n - 1 - COLOURS]
    }

    /// Heap memory held, bytes.
    pub fn heap_bytes(&self) -> usize {
        self.springs.capacity() * size_of::<LimitedSpring>()
            + self.gathered.capacity() * size_of::<(u32, LimitedSpring)>()
            + (self.start.capacity()
                + self.next.capacity()
                + self.places.band_of_row.capacity()
                + self.places.row_of.capacity()
                + self.places.home.capacity())
                * size_of::<u32>()
            + self.places.reach.capacity() * size_of::<(u32, u32)>()
    }

    /// This frame's springs: those of `list` that are in-plane, live and have a movable end
    /// (inverse masses `w` by particle, slots `slot`), allowed `scale ×` their rest length,
    /// by colour within each bucket, in `list`'s order within each colour.
    pub fn gather(
        &mut self,
        list: &[u32],
        particles: &Particles,
        springs: &Springs,
        (w, slot): (&[f32], &[u32]),
        scale: f32,
    ) {
        let keys = self.buckets() * COLOURS;
        self.springs.clear();
        self.gathered.clear();
        self.start.clear();
        self.start.resize(keys + 1, 0);
        for &s in list {
            let s = s as usize;
            if s >= springs.len()
                || !springs.kind[s].is_in_plane()
                || !springs.is_live(s, &particles.state)
            {
                continue;
            }
            let (i, j) = (springs.a[s] as usize, springs.b[s] as usize);
            let (wa, wb) = (w[i], w[j]);
            if wa + wb <= 0.0 {
                continue;
            }
            let limit = scale * springs.rest_length[s];
            let past = limit * (1.0 + STRETCH_TOLERANCE);
            let (bucket, packed) = self.places.place(i as u32, j as u32, slot);
            let key = bucket * COLOURS as u32 + self.places.colour(i as u32, j as u32);
            self.start[key as usize + 1] += 1;
            self.gathered.push((
                key,
                LimitedSpring {
                    slots: [slot[i], slot[j]],
                    packed,
                    wa,
                    wb,
                    limit,
                    past: past * past,
                },
            ));
        }
        for k in 1..=keys {
            self.start[k] += self.start[k - 1];
        }
        self.next.clear();
        self.next.extend_from_slice(&self.start[..keys]);
        self.springs
            .resize(self.gathered.len(), LimitedSpring::default());
        for &(key, spring) in &self.gathered {
            let at = &mut self.next[key as usize];
            self.springs[*at as usize] = spring;
            *at += 1;
        }
    }

    /// The buckets, to hand to the threads of a frame's passes.
    pub fn share(&self) -> SharedBuckets<'_> {
        SharedBuckets {
            springs: &self.springs,
            start: &self.start,
        }
    }
}

impl GridPlaces {
    /// The bucket of the spring joining particles `i` and `j`, and its two ends packed.
    fn place(&self, i: u32, j: u32, slot: &[u32]) -> (u32, [u32; 2]) {
        let (i, j) = (i as usize, j as usize);
        let Some(slots) = self.slots else {
            return (0, [slot[i], slot[j]]);
        };
        let (ri, rj) = (self.row_of[i], self.row_of[j]);
        let band = self.band_of_row[ri.min(rj) as usize];
        let (first, end) = self.reach[band as usize];
        let (bucket, first) = if ri.max(rj) < end {
            (band, first)
        } else {
            (self.reach.len() as u32, 0)
        };
        // Both ends are in the reach's rows, so the index stays at or above its first row.
        let offset = first * slots.width();
        (bucket, [self.home[i] - offset, self.home[j] - offset])
    }

    /// The colour of the spring joining particles `i` and `j` within its bucket: springs of
    /// one colour but the last share no particle (a mesh's springs are all of the last).
    fn colour(&self, i: u32, j: u32) -> u32 {
        if self.slots.is_none() || self.columns == 0 {
            return COLOURS as u32 - 1;
        }
        let cell = |p: u32| {
            let row = self.row_of[p as usize];
            (row, p - row * self.columns)
        };
        // The spring from its upper end, or from its left end on one row.
        let ((r0, c0), (r1, c1)) = {
            let (a, b) = (cell(i), cell(j));
            if a <= b { (a, b) } else { (b, a) }
        };
        match (r1 - r0, i64::from(c1) - i64::from(c0)) {
            (0, 1) => c0 % 2,
            (1, 0) => 2 + r0 % 2,
            (1, 1) => 4 + r0 % 2,
            (1, -1) => 6 + r0 % 2,
            _ => COLOURS as u32 - 1,
        }
    }
}

/// The buckets as the threads of a frame's passes read them.
pub(super) struct SharedBuckets<'a> {
    springs: &'a [LimitedSpring],
    start: &'a [u32],
}

impl<'a> SharedBuckets<'a> {
    /// Bucket `bucket`'s springs.
    #[cfg(test)]
    pub fn bucket(&self, bucket: usize) -> &'a [LimitedSpring] {
        let (first, end) = (bucket * COLOURS, (bucket + 1) * COLOURS);
        &self.springs[self.start[first] as usize..self.start[end] as usize]
    }

    /// Colour `colour` of bucket `bucket`.
    fn colour(&self, bucket: usize, colour: usize) -> &'a [LimitedSpring] {
        let key = bucket * COLOURS + colour;
        &self.springs[self.start[key] as usize..self.start[key + 1] as usize]
    }

    /// The last bucket: springs outside any band, or a mesh's.
    pub fn rest(&self) -> usize {
        (self.start.len() / COLOURS).saturating_sub(1)
    }
}

/// The particles a stretch-limit pass moves: where a spring's ends are, and moving them.
pub(super) trait Ends {
    /// End `k` of `spring` as this view names it.
    fn end(spring: &LimitedSpring, k: usize) -> u32;
    /// The position of `end` in this substep (`x + u`), m.
    fn at(&self, end: u32) -> [f32; 3];
    /// Moves `end` by `by` (added to `u`), m.
    fn add(&mut self, end: u32, by: [f32; 3]);
}

/// Every slot's positions and displacements, ends by slot: the whole cloth on one thread.
pub(super) struct Flat<'a> {
    pub x: [&'a [f32]; 3],
    pub u: [&'a mut [f32]; 3],
}

impl Ends for Flat<'_> {
    #[inline(always)]
    fn end(spring: &LimitedSpring, k: usize) -> u32 {
        spring.slots[k]
    }

    #[inline(always)]
    fn at(&self, end: u32) -> [f32; 3] {
        let s = end as usize;
        [
            self.x[0][s] + self.u[0][s],
            self.x[1][s] + self.u[1][s],
            self.x[2][s] + self.u[2][s],
        ]
    }

    #[inline(always)]
    fn add(&mut self, end: u32, by: [f32; 3]) {
        let s = end as usize;
        self.u[0][s] += by[0];
        self.u[1][s] += by[1];
        self.u[2][s] += by[2];
    }
}

impl Ends for Reach<'_> {
    #[inline(always)]
    fn end(spring: &LimitedSpring, k: usize) -> u32 {
        spring.packed[k]
    }

    #[inline(always)]
    #[allow(unsafe_code)]
    fn at(&self, end: u32) -> [f32; 3] {
        let s = self.slot(end);
        // SAFETY: `s` is in the reach (`slot`), which `new`'s caller promised is in bounds and
        // written by nobody else.
        unsafe {
            [
                *self.x[0].add(s) + *self.u[0].add(s),
                *self.x[1].add(s) + *self.u[1].add(s),
                *self.x[2].add(s) + *self.u[2].add(s),
            ]
        }
    }

    #[inline(always)]
    #[allow(unsafe_code)]
    fn add(&mut self, end: u32, by: [f32; 3]) {
        let s = self.slot(end);
        // SAFETY: as in `at`; the displacements of the reach are this reach's alone.
        unsafe {
            *self.u[0].add(s) += by[0];
            *self.u[1].add(s) += by[1];
            *self.u[2].add(s) += by[2];
        }
    }
}

/// Up to `rounds` rounds of Provot's correction, each one pass over every bucket in turn (the
/// even bands, the odd bands, the rest), stopping after a round that corrects nothing (a
/// further round would change nothing). One thread does here what the bands' passes do on
/// several, in the same order: bands of one parity share no particle.
///
/// The rounds go round the buckets, not each bucket's passes round itself: a bucket corrected
/// to convergence on its own stretches the springs of the bucket before it that share its
/// rows, and that bucket was not visited again (a burning curtain's springs stayed up to 1.5
/// times their limit with 2 passes per bucket, 2.2 times with 400).
pub(super) fn limit_all(flat: &mut Flat, buckets: &SharedBuckets, rounds: u32) {
    // Every array cut to one length here, where the loops are, so the six tests of an end's
    // reads are one.
    let n = flat.x[0].len();
    let [x0, x1, x2] = flat.x;
    let [u0, u1, u2] = &mut flat.u;
    let flat = &mut Flat {
        x: [&x0[..n], &x1[..n], &x2[..n]],
        u: [&mut u0[..n], &mut u1[..n], &mut u2[..n]],
    };
    let bands = buckets.rest();
    for _ in 0..rounds {
        let mut corrected = 0;
        for bucket in (0..bands)
            .step_by(2)
            .chain((1..bands).step_by(2))
            .chain([bands])
        {
            corrected += limit_bucket(flat, buckets, bucket);
        }
        if corrected == 0 {
            break;
        }
    }
}

/// How many springs each round of the stretch limit corrected in a frame, counted by every
/// thread that runs a part of the round; a round after one that corrected nothing is skipped.
/// Kept between frames so a frame allocates nothing; a clone starts empty.
#[derive(Debug, Default)]
pub(super) struct RoundTallies(Vec<AtomicU32>);

impl Clone for RoundTallies {
    fn clone(&self) -> Self {
        Self::default()
    }
}

impl RoundTallies {
    /// Tallies for `rounds` rounds, all at zero.
    pub fn reset(&mut self, rounds: usize) {
        if self.0.len() < rounds {
            self.0.resize_with(rounds, AtomicU32::default);
        }
        for tally in &self.0[..rounds] {
            tally.store(0, Ordering::Relaxed);
        }
    }

    /// Adds `corrected` to round `round`'s tally.
    pub fn add(&self, round: usize, corrected: usize) {
        if corrected > 0 {
            self.0[round].fetch_add(corrected as u32, Ordering::Relaxed);
        }
    }

    /// Whether round `round` corrected nothing. Read only by a later phase of
    /// [`run_phases`](crate::sim::parallel::run_phases), which starts after every item of the
    /// round has finished (and published its counts with it).
    pub fn corrected_nothing(&self, round: usize) -> bool {
        self.0[round].load(Ordering::Relaxed) == 0
    }
}

/// Springs a colour's pass checks before correcting those past their limit (indices fit a
/// byte).
const CHECKED_AT_ONCE: usize = 256;

/// One pass of Provot's correction over a bucket's springs, colour by colour. Returns how
/// many it corrected.
#[inline(always)]
pub(super) fn limit_bucket<E: Ends>(ends: &mut E, buckets: &SharedBuckets, bucket: usize) -> usize {
    let mut count = 0;
    for colour in 0..COLOURS - 1 {
        count += limit_disjoint(ends, buckets.colour(bucket, colour));
    }
    count + limit_pass(ends, buckets.colour(bucket, COLOURS - 1))
}

/// The end-to-end vector of `spring` on the substep's positions, and its squared length.
#[inline(always)]
fn span<E: Ends>(ends: &E, spring: &LimitedSpring) -> ([f32; 3], f32) {
    let (pa, pb) = (ends.at(E::end(spring, 0)), ends.at(E::end(spring, 1)));
    let e = [pa[0] - pb[0], pa[1] - pb[1], pa[2] - pb[2]];
    (e, e[0] * e[0] + e[1] * e[1] + e[2] * e[2])
}

/// Whether `spring`, its squared length `squared`, is past its limit (a NaN length is, as it
/// always was: the guard repairs what it reaches).
#[inline(always)]
fn is_past(spring: &LimitedSpring, squared: f32) -> bool {
    use core::cmp::Ordering::{Equal, Less};
    !matches!(squared.partial_cmp(&spring.past), Some(Less | Equal))
}

/// Pulls `spring` (end-to-end vector `e`, squared length `squared`) back to its allowed
/// length, the move shared by inverse mass, on the substep's positions `x + u` (the move
/// goes into `u`, so the velocity follows).
#[inline(always)]
fn correct<E: Ends>(ends: &mut E, spring: &LimitedSpring, e: [f32; 3], squared: f32) {
    let length = squared.sqrt();
    let share = (length - spring.limit) / (length * (spring.wa + spring.wb));
    let (wa, wb) = (spring.wa, spring.wb);
    ends.add(
        E::end(spring, 0),
        [
            -(e[0] * share * wa),
            -(e[1] * share * wa),
            -(e[2] * share * wa),
        ],
    );
    ends.add(
        E::end(spring, 1),
        [e[0] * share * wb, e[1] * share * wb, e[2] * share * wb],
    );
}

/// One pass of Provot's correction over `springs`, in order: each one longer than its allowed
/// length is pulled back to it ([`correct`]). Returns how many it corrected.
#[inline(always)]
pub(super) fn limit_pass<E: Ends>(ends: &mut E, springs: &[LimitedSpring]) -> usize {
    let mut count = 0;
    for spring in springs {
        let (e, squared) = span(ends, spring);
        if is_past(spring, squared) {
            correct(ends, spring, e, squared);
            count += 1;
        }
    }
    count
}

/// [`limit_pass`] over springs that share no particle (one colour of a grid's bucket), the
/// same bits: no correction moves an end another spring of the list reads, so every spring
/// is checked first, with no branch, and the listed ones corrected after (about a third
/// are, in no order a processor can predict one by one).
#[inline(always)]
fn limit_disjoint<E: Ends>(ends: &mut E, springs: &[LimitedSpring]) -> usize {
    let mut count = 0;
    let mut listed = [0u8; CHECKED_AT_ONCE];
    for block in springs.chunks(CHECKED_AT_ONCE) {
        let mut n = 0;
        for (k, spring) in block.iter().enumerate() {
            let (_, squared) = span(ends, spring);
            listed[n] = k as u8;
            n += usize::from(is_past(spring, squared));
        }
        for &k in &listed[..n] {
            let spring = &block[usize::from(k)];
            let (e, squared) = span(ends, spring);
            correct(ends, spring, e, squared);
        }
        count += n;
    }
    count
}

/// A packed end's quarter grid and index.
fn unpack(end: u32) -> (usize, usize) {
    (
        (end >> INDEX_BITS) as usize,
        (end & ((1 << INDEX_BITS) - 1)) as usize,
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::grid::ClothBuilder;
    use crate::sim::material::BurnMaterial;
    use glam::Affine3A;

    /// A grid cloth's particles and springs, `columns × rows` particles 2 cm apart.
    fn grid(columns: u32, rows: u32) -> (crate::sim::Particles, crate::sim::Springs) {
        let parts = ClothBuilder::grid(columns, rows, 0.02)
            .build(&BurnMaterial::COTTON, Affine3A::IDENTITY)
            .unwrap();
        (parts.particles, parts.springs)
    }

    /// [`grid`] with every rest length `fraction` of what it was, as heat shrinks springs.
    fn shrunk_grid(
        columns: u32,
        rows: u32,
        fraction: f32,
    ) -> (crate::sim::Particles, crate::sim::Springs) {
        let (particles, mut springs) = grid(columns, rows);
        for rest in &mut springs.rest_length {
            *rest *= fraction;
        }
        (particles, springs)
    }

    /// The particles' positions in `len` slots (particle `i` in slot `slot[i]`), per axis, and
    /// displacements of up to `5 × jitter` m, scattered the same way on every call.
    fn in_slots(
        particles: &crate::sim::Particles,
        slot: &[u32],
        len: usize,
        jitter: f32,
    ) -> ([Vec<f32>; 3], [Vec<f32>; 3]) {
        let mut x: [Vec<f32>; 3] = core::array::from_fn(|_| vec![0.0; len]);
        let mut u = x.clone();
        for (i, p) in particles.position.iter().enumerate() {
            let s = slot[i] as usize;
            for k in 0..3 {
                x[k][s] = p[k];
                u[k][s] = jitter * (((i * 7 + k * 13) % 11) as f32 - 5.0);
            }
        }
        (x, u)
    }

    /// Every eligible spring lands in exactly one bucket: a band whose reach holds both its
    /// ends (the packed ends name its slots), or, if it reaches further, the last bucket.
    #[test]
    fn springs_go_to_the_band_that_holds_both_ends_or_to_the_rest() {
        let (columns, rows) = (21u32, 40u32);
        let (particles, mut springs) = grid(columns, rows);
        let grid = crate::sim::topology::GridShape { columns, rows };
        let slots = GridSlots::new(grid);
        let lanes = GridLanes::new(slots, 8);
        let slot: Vec<u32> = (0..columns * rows)
            .map(|i| slots.slot(i % columns, i / columns))
            .collect();
        // One structural spring rewired to reach 20 rows down (as a cut can rewire one).
        let long = (0..springs.len())
            .find(|&s| springs.kind[s].is_in_plane())
            .unwrap();
        springs.b[long] = springs.a[long] + 20 * columns;
        let list: Vec<u32> = (0..springs.len() as u32).collect();
        let w = vec![1.0f32; particles.len()];
        let mut limited = LimitedSprings::default();
        limited.prepare(Some((&lanes, slots, columns)), springs.len());
        limited.gather(&list, &particles, &springs, (&w, &slot), 1.1);
        let eligible = (0..springs.len())
            .filter(|&s| springs.kind[s].is_in_plane())
            .count();
        assert_eq!(limited.springs.len(), eligible);
        assert!(
            limited.has_rest(),
            "the long spring is left for the last bucket"
        );
        let quarter = slots.quarter_len();
        let buckets = limited.share();
        for bucket in 0..=buckets.rest() {
            let springs = buckets.bucket(bucket);
            let first = lanes.bands.get(bucket).map_or(0, |band| band.reach.start);
            let end = lanes.bands.get(bucket).map_or(rows, |band| band.reach.end);
            for spring in springs {
                for k in 0..2 {
                    let (q, index) = unpack(spring.packed[k]);
                    let s = spring.slots[k];
                    assert_eq!(q as u32, s / quarter);
                    assert_eq!(index as u32 + first * slots.width(), s % quarter);
                    let (_, row) = slots.cell(s).unwrap();
                    assert!((first..end).contains(&row), "bucket {bucket}: row {row}");
                }
            }
            if bucket == buckets.rest() {
                assert_eq!(springs.len(), 1, "only the long spring is left over");
            }
        }
    }

    /// Within a grid's bucket the springs of one colour share no particle, and every spring
    /// keeps its bucket: the colours only order a bucket's springs.
    #[test]
    fn springs_of_one_colour_share_no_particle() {
        let (columns, rows) = (21u32, 40u32);
        let (particles, springs) = grid(columns, rows);
        let slots = GridSlots::new(crate::sim::topology::GridShape { columns, rows });
        let lanes = GridLanes::new(slots, 8);
        let slot: Vec<u32> = (0..columns * rows)
            .map(|i| slots.slot(i % columns, i / columns))
            .collect();
        let list: Vec<u32> = (0..springs.len() as u32).collect();
        let w = vec![1.0f32; particles.len()];
        let mut limited = LimitedSprings::default();
        limited.prepare(Some((&lanes, slots, columns)), springs.len());
        limited.gather(&list, &particles, &springs, (&w, &slot), 1.1);
        let buckets = limited.share();
        let mut coloured = 0;
        for bucket in 0..=buckets.rest() {
            for colour in 0..COLOURS {
                let key = bucket * COLOURS + colour;
                let range = limited.start[key] as usize..limited.start[key + 1] as usize;
                let mut ends: Vec<u32> = limited.springs[range.clone()]
                    .iter()
                    .flat_map(|spring| spring.slots)
                    .collect();
                let count = ends.len();
                ends.sort_unstable();
                ends.dedup();
                if colour < COLOURS - 1 {
                    assert_eq!(ends.len(), count, "bucket {bucket}, colour {colour}");
                    coloured += range.len();
                }
            }
        }
        // Every in-plane spring of an uncut grid has a colour of its own family.
        assert_eq!(coloured, limited.springs.len());
    }

    /// Checking a colour's springs first and correcting the ones past their limit after gives
    /// the bits of correcting each in turn (its springs share no particle); a third or so
    /// of these are past.
    #[test]
    fn a_colour_checked_first_corrects_as_springs_in_turn() {
        let (columns, rows) = (13u32, 11u32);
        let (particles, springs) = shrunk_grid(columns, rows, 0.93);
        let n = particles.len();
        let slots = GridSlots::new(crate::sim::topology::GridShape { columns, rows });
        let lanes = GridLanes::new(slots, rows);
        let w: Vec<f32> = (0..n).map(|i| if i < 3 { 0.0 } else { 1.0 }).collect();
        let slot: Vec<u32> = (0..n as u32).collect();
        let list: Vec<u32> = (0..springs.len() as u32).collect();
        let mut limited = LimitedSprings::default();
        limited.prepare(Some((&lanes, slots, columns)), springs.len());
        limited.gather(&list, &particles, &springs, (&w, &slot), 1.1);
        let x: [Vec<f32>; 3] =
            core::array::from_fn(|k| particles.position.iter().map(|p| p[k]).collect());
        let u0: [Vec<f32>; 3] = core::array::from_fn(|k| {
            (0..n)
                .map(|i| 0.006 * (((i * 7 + k * 13) % 11) as f32 - 5.0))
                .collect()
        });
        let buckets = limited.share();
        let run = |in_turn: bool| {
            let mut u = u0.clone();
            let [u_x, u_y, u_z] = &mut u;
            let mut flat = Flat {
                x: [&x[0], &x[1], &x[2]],
                u: [u_x, u_y, u_z],
            };
            let mut corrected = 0;
            for bucket in 0..=buckets.rest() {
                corrected += if in_turn {
                    limit_pass(&mut flat, buckets.bucket(bucket))
                } else {
                    limit_bucket(&mut flat, &buckets, bucket)
                };
            }
            let bits: Vec<u32> = u.iter().flatten().map(|v| v.to_bits()).collect();
            (corrected, bits)
        };
        let (count, bits) = run(true);
        let total = limited.springs.len();
        assert!(
            count > total / 5 && count < total,
            "{count} of {total} corrected"
        );
        assert_eq!(run(false), (count, bits));
    }

    /// A band's pass through its reach (ends packed from the reach's first row, in every
    /// quarter grid) corrects each bucket to the bits of the same pass through every slot.
    #[test]
    #[allow(unsafe_code)]
    fn a_band_corrects_through_its_reach_as_through_every_slot() {
        let (columns, rows) = (21u32, 40u32);
        let (particles, springs) = shrunk_grid(columns, rows, 0.93);
        let n = particles.len();
        let slots = GridSlots::new(crate::sim::topology::GridShape { columns, rows });
        let lanes = GridLanes::new(slots, 8);
        let slot: Vec<u32> = (0..n as u32)
            .map(|i| slots.slot(i % columns, i / columns))
            .collect();
        let w: Vec<f32> = (0..n).map(|i| if i < 4 { 0.0 } else { 1.0 }).collect();
        let list: Vec<u32> = (0..springs.len() as u32).collect();
        let mut limited = LimitedSprings::default();
        limited.prepare(Some((&lanes, slots, columns)), springs.len());
        limited.gather(&list, &particles, &springs, (&w, &slot), 1.1);
        let (x, u0) = in_slots(&particles, &slot, slots.len(), 0.006);
        let quarter = slots.quarter_len() as usize;
        let buckets = limited.share();
        let mut corrected = 0;
        for (bucket, band) in lanes.bands.iter().enumerate() {
            let mut flat_u = u0.clone();
            let [a, b, c] = &mut flat_u;
            let mut flat = Flat {
                x: [&x[0], &x[1], &x[2]],
                u: [a, b, c],
            };
            let by_flat = limit_bucket(&mut flat, &buckets, bucket);
            let mut reach_u = u0.clone();
            let span = slots.row_span(band.reach.clone());
            // SAFETY: the reach's rows are in every array (each holds the whole grid's
            // slots), and nothing else reads or writes them while the reach lives.
            let mut reach = unsafe {
                Reach::new(
                    core::array::from_fn(|k| x[k].as_ptr()),
                    core::array::from_fn(|k| reach_u[k].as_mut_ptr()),
                    core::array::from_fn(|q| q * quarter + span.start),
                    span.len(),
                )
            };
            let by_reach = limit_bucket(&mut reach, &buckets, bucket);
            assert_eq!(by_reach, by_flat, "bucket {bucket}");
            let bits = |u: &[Vec<f32>; 3]| -> Vec<u32> {
                u.iter().flatten().map(|v| v.to_bits()).collect()
            };
            assert!(bits(&reach_u) == bits(&flat_u), "bucket {bucket}");
            corrected += by_flat;
        }
        assert!(
            corrected > limited.springs.len() / 5,
            "{corrected} of {} corrected",
            limited.springs.len()
        );
    }

    /// Enough rounds over a patch of shrunk springs, stretched at random, leave none longer
    /// than its limit: springs all in one bucket (a mesh), and springs in a grid's bands,
    /// where each round must go round every band. (Passes that revisited only what the pass
    /// before corrected left a patch at 2.2 times its limit after 500; passes that went round
    /// each band on its own before the next left the bands' shared rows stretched.)
    #[test]
    fn rounds_bring_every_spring_within_its_limit() {
        let (columns, rows) = (12u32, 24u32);
        let (particles, springs) = shrunk_grid(columns, rows, 0.7);
        let n = particles.len();
        let slots = GridSlots::new(crate::sim::topology::GridShape { columns, rows });
        let lanes = GridLanes::new(slots, 8);
        let w = vec![1.0f32; n];
        let list: Vec<u32> = (0..springs.len() as u32).collect();
        for banded in [false, true] {
            let slot: Vec<u32> = if banded {
                (0..n as u32)
                    .map(|i| slots.slot(i % columns, i / columns))
                    .collect()
            } else {
                (0..n as u32).collect()
            };
            let mut limited = LimitedSprings::default();
            limited.prepare(banded.then_some((&lanes, slots, columns)), springs.len());
            limited.gather(&list, &particles, &springs, (&w, &slot), 1.1);
            let len = if banded { slots.len() } else { n };
            let (x, mut u) = in_slots(&particles, &slot, len, 0.004);
            {
                let [u0, u1, u2] = &mut u;
                let mut flat = Flat {
                    x: [&x[0], &x[1], &x[2]],
                    u: [u0, u1, u2],
                };
                limit_all(&mut flat, &limited.share(), 2_000);
            }
            let mut worst = 0.0f32;
            for spring in &limited.springs {
                let (a, b) = (spring.slots[0] as usize, spring.slots[1] as usize);
                let e: Vec<f32> = (0..3)
                    .map(|k| (x[k][a] + u[k][a]) - (x[k][b] + u[k][b]))
                    .collect();
                let length = (e[0] * e[0] + e[1] * e[1] + e[2] * e[2]).sqrt();
                worst = worst.max(length / spring.limit);
            }
            assert!(worst < 1.001, "banded {banded}: worst {worst}");
        }
    }
}
