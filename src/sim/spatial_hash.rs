//! A uniform spatial hash for neighbour queries in O(n): particles that come close when the
//! cloth folds find each other without an O(n²) search.
//!
//! Dense hashing after Müller: each point falls in a cubic cell, the cell's integer
//! coordinates hash into a table of about twice as many buckets as points, and a counting
//! sort lays the points out bucket by bucket. Building reuses its buffers, so after the first
//! build it does not allocate unless the point count grows.

use glam::{IVec3, Vec3};

/// A spatial hash over a set of points.
#[derive(Clone, Debug, Default)]
pub struct SpatialHash {
    cell_size: f32,
    /// `bucket_start[b]..bucket_start[b + 1]` indexes `entries` for bucket `b`.
    bucket_start: Vec<u32>,
    /// Point indices sorted by bucket.
    entries: Vec<u32>,
    /// The cell of each entry: a query visits an entry only from its own cell, so a bucket
    /// that two of the 27 cells share is not counted twice.
    entry_cells: Vec<IVec3>,
    /// The points inserted (included, with a finite position), and the bucket and cell of
    /// each (scratch for the counting sort).
    inserted: Vec<u32>,
    point_bucket: Vec<u32>,
    point_cell: Vec<IVec3>,
}

impl SpatialHash {
    /// Rebuilds the hash over the points `i` with `include(i)`, in cells of `cell_size` metres.
    ///
    /// Queries find every included point within `cell_size` of the query point. A non-finite
    /// position is left out, as is every point when `cell_size` is not positive and finite.
    pub fn build(&mut self, positions: &[Vec3], cell_size: f32, include: impl Fn(usize) -> bool) {
        self.cell_size = cell_size;
        self.bucket_start.clear();
        self.point_bucket.clear();
        self.point_cell.clear();
        self.inserted.clear();
        self.entries.clear();
        self.entry_cells.clear();
        let valid = cell_size.is_finite() && cell_size > 0.0;
        // The included points with a finite position, and their cells; the table is sized by
        // every included point.
        let mut included = 0usize;
        for (i, &p) in positions.iter().enumerate() {
            if include(i) {
                included += 1;
                if valid && p.is_finite() {
                    self.inserted.push(i as u32);
                    self.point_cell.push(self.cell_of(p));
                }
            }
        }
        // About two buckets per included point: the table grows with what is hashed, not with
        // the cloth. A power of two, so a bucket is a shift, not a division.
        let table = (2 * included).max(2).next_power_of_two();
        self.bucket_start.resize(table + 1, 0);
        for k in 0..self.point_cell.len() {
            let bucket = self.bucket_of(self.point_cell[k]);
            self.bucket_start[bucket as usize] += 1;
            self.point_bucket.push(bucket);
        }
        // An inclusive prefix sum turns counts into end offsets; filling backwards then
        // decrements each to its start, leaving each bucket's points in index order.
        let mut running = 0;
        for start in &mut self.bucket_start {
            running += *start;
            *start = running;
        }
        self.entries.resize(running as usize, 0);
        self.entry_cells.resize(running as usize, IVec3::ZERO);
        for k in (0..self.inserted.len()).rev() {
            let slot = &mut self.bucket_start[self.point_bucket[k] as usize];
            *slot -= 1;
            self.entries[*slot as usize] = self.inserted[k];
            self.entry_cells[*slot as usize] = self.point_cell[k];
        }
    }

    /// Calls `visit(j)` once for every included point `j` within `radius` of `point`
    /// (`radius` at most the cell size; larger radii are clamped to it). Only the cells the
    /// query's bounding box overlaps are visited: at most 8 when `radius` is at most half the
    /// cell size (build with cells twice the radius for that), at most 27 otherwise.
    pub fn for_each_within(
        &self,
        positions: &[Vec3],
        point: Vec3,
        radius: f32,
        mut visit: impl FnMut(usize),
    ) {
        if self.entries.is_empty() || !point.is_finite() {
            return;
        }
        let radius = radius.min(self.cell_size);
        let radius_squared = radius * radius;
        let (low, high) = (
            self.cell_of(point - Vec3::splat(radius)),
            self.cell_of(point + Vec3::splat(radius)),
        );
        for z in low.z..=high.z {
            for y in low.y..=high.y {
                for x in low.x..=high.x {
                    let cell = IVec3::new(x, y, z);
                    let bucket = self.bucket_of(cell) as usize;
                    let range =
                        self.bucket_start[bucket] as usize..self.bucket_start[bucket + 1] as usize;
                    for (&j, &at) in self.entries[range.clone()]
                        .iter()
                        .zip(&self.entry_cells[range])
                    {
                        let j = j as usize;
                        if at == cell && positions[j].distance_squared(point) <= radius_squared {
                            visit(j);
                        }
                    }
                }
            }
        }
    }

    /// Makes room for hashing up to `points` points, so building never allocates after.
    pub fn reserve(&mut self, points: usize) {
        let reserve = |v: &mut Vec<u32>, wanted: usize| v.reserve(wanted.saturating_sub(v.len()));
        reserve(
            &mut self.bucket_start,
            (2 * points).max(2).next_power_of_two() + 1,
        );
        reserve(&mut self.entries, points);
        reserve(&mut self.inserted, points);
        reserve(&mut self.point_bucket, points);
        let reserve = |v: &mut Vec<IVec3>, wanted: usize| v.reserve(wanted.saturating_sub(v.len()));
        reserve(&mut self.entry_cells, points);
        reserve(&mut self.point_cell, points);
    }

    /// Heap memory held, bytes (capacity, not length).
    pub fn heap_bytes(&self) -> usize {
        (self.bucket_start.capacity()
            + self.entries.capacity()
            + self.inserted.capacity()
            + self.point_bucket.capacity())
            * size_of::<u32>()
            + (self.entry_cells.capacity() + self.point_cell.capacity()) * size_of::<IVec3>()
    }

    fn cell_of(&self, p: Vec3) -> IVec3 {
        let q = p / self.cell_size;
        IVec3::new(floor_to_int(q.x), floor_to_int(q.y), floor_to_int(q.z))
    }

    fn bucket_of(&self, cell: IVec3) -> u32 {
        let h = (cell.x.wrapping_mul(92_837_111))
            ^ (cell.y.wrapping_mul(689_287_499))
            ^ (cell.z.wrapping_mul(283_923_481));
        // Fibonacci hashing: the top bits of a multiply mix every bit of `h`. The table
        // (`bucket_start.len() - 1`) is a power of two of at least 2.
        let bits = (self.bucket_start.len() - 1).trailing_zeros();
        (h as u32).wrapping_mul(0x9E37_79B9) >> (32 - bits)
    }
}

/// `q.floor() as i32` without a call to the C library's `floorf` (x86-64's baseline has no
/// rounding instruction): the saturating cast truncates toward zero, one less for a negative
/// fraction. Saturates at the ends of `i32` as the cast does, so far-away points get finite
/// cells; NaN gives 0.
#[inline]
fn floor_to_int(q: f32) -> i32 {
    let t = q as i32;
    t.saturating_sub(i32::from(t as f32 > q))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn floor_to_int_is_the_floor_cast() {
        let mut values = vec![
            0.0,
            -0.0,
            0.5,
            -0.5,
            1.0,
            -1.0,
            -1.0e-30,
            2.999_999_8,
            -2.999_999_8,
            16_777_217.0,
            -16_777_217.0,
            2.0e9,
            -2.0e9,
            3.0e9,
            -3.0e9,
            1.0e30,
            -1.0e30,
            f32::MAX,
            f32::MIN,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::NAN,
        ];
        values.extend((-2000..2000).map(|i| i as f32 * 0.37));
        for q in values {
            assert_eq!(floor_to_int(q), q.floor() as i32, "{q}");
        }
    }

    #[test]
    fn finds_exactly_the_points_a_brute_force_search_finds() {
        // A deterministic scatter of points, some far away.
        let mut positions = Vec::new();
        let mut seed = 12345u32;
        let mut next = || {
            seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (seed >> 8) as f32 / (1u32 << 24) as f32
        };
        for _ in 0..500 {
            positions.push(Vec3::new(
                next() * 2.0 - 1.0,
                next() * 2.0 - 1.0,
                next() * 0.2,
            ));
        }
        positions.push(Vec3::splat(1.0e6));
        // Left out of the hash, and found by no query.
        positions.push(Vec3::NAN);
        let mut hash = SpatialHash::default();
        let radius = 0.1;
        // Cells as large as the radius (up to 27 visited) and twice as large (up to 8), queried
        // at the points and between them.
        for cell_size in [radius, 2.0 * radius, 0.37] {
            hash.build(&positions, cell_size, |i| i % 7 != 0);
            let between = positions.windows(2).map(|w| 0.5 * (w[0] + w[1]));
            for (i, p) in positions.iter().copied().chain(between).enumerate() {
                let mut found = Vec::new();
                hash.for_each_within(&positions, p, radius, |j| found.push(j));
                found.sort_unstable();
                let expected: Vec<usize> = (0..positions.len())
                    .filter(|&j| j % 7 != 0 && positions[j].distance(p) <= radius)
                    .collect();
                assert_eq!(found, expected, "point {i}, cells {cell_size} m");
            }
        }
    }

    #[test]
    fn cells_that_share_a_bucket_are_each_visited_once() {
        // Three points in a table of six buckets: most of the 27 cells around a query share
        // buckets; every point is still found once.
        let positions = [
            Vec3::ZERO,
            Vec3::new(0.05, 0.0, 0.0),
            Vec3::new(0.0, 0.05, 0.05),
        ];
        let mut hash = SpatialHash::default();
        hash.build(&positions, 0.1, |_| true);
        for p in positions {
            let mut found = Vec::new();
            hash.for_each_within(&positions, p, 0.1, |j| found.push(j));
            found.sort_unstable();
            assert_eq!(found, vec![0, 1, 2]);
        }
    }

    #[test]
    fn non_finite_points_and_sizes_are_ignored() {
        let positions = [Vec3::ZERO, Vec3::NAN, Vec3::new(0.01, 0.0, 0.0)];
        let mut hash = SpatialHash::default();
        hash.build(&positions, 0.1, |_| true);
        let mut found = Vec::new();
        hash.for_each_within(&positions, Vec3::ZERO, 0.1, |j| found.push(j));
        found.sort_unstable();
        assert_eq!(found, vec![0, 2]);
        hash.build(&positions, f32::NAN, |_| true);
        hash.for_each_within(&positions, Vec3::ZERO, 0.1, |_| {
            panic!("nothing is included")
        });
    }
}
