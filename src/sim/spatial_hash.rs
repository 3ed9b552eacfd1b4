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
    /// Bucket of each inserted point (scratch for the counting sort).
    point_bucket: Vec<u32>,
}

impl SpatialHash {
    /// Rebuilds the hash over the points `i` with `include(i)`, in cells of `cell_size` metres.
    ///
    /// Queries find every included point within `cell_size` of the query point. A non-finite
    /// position is left out, as is every point when `cell_size` is not positive and finite.
    pub fn build(&mut self, positions: &[Vec3], cell_size: f32, include: impl Fn(usize) -> bool) {
        self.cell_size = cell_size;
        let table = (2 * positions.len()).max(1);
        self.bucket_start.clear();
        self.bucket_start.resize(table + 1, 0);
        self.point_bucket.clear();
        self.entries.clear();
        if !(cell_size.is_finite() && cell_size > 0.0) {
            return;
        }
        for (i, &p) in positions.iter().enumerate() {
            let bucket = if include(i) && p.is_finite() {
                let bucket = self.bucket_of(self.cell_of(p));
                self.bucket_start[bucket as usize] += 1;
                bucket
            } else {
                u32::MAX
            };
            self.point_bucket.push(bucket);
        }
        // An inclusive prefix sum turns counts into end offsets; filling backwards then
        // decrements each to its start.
        let mut running = 0;
        for start in &mut self.bucket_start {
            running += *start;
            *start = running;
        }
        self.entries.resize(running as usize, 0);
        for (i, &bucket) in self.point_bucket.iter().enumerate().rev() {
            if bucket != u32::MAX {
                let slot = &mut self.bucket_start[bucket as usize];
                *slot -= 1;
                self.entries[*slot as usize] = i as u32;
            }
        }
    }

    /// Calls `visit(j)` once for every included point `j` within `radius` of `point`
    /// (`radius` at most the cell size; larger radii are clamped to it).
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
        let centre = self.cell_of(point);
        // Distinct cells can share a bucket; visit each bucket once per query.
        let mut seen = [u32::MAX; 27];
        let mut seen_count = 0;
        for dz in -1..=1 {
            for dy in -1..=1 {
                for dx in -1..=1 {
                    let bucket = self.bucket_of(centre + IVec3::new(dx, dy, dz));
                    if seen[..seen_count].contains(&bucket) {
                        continue;
                    }
                    seen[seen_count] = bucket;
                    seen_count += 1;
                    let range = self.bucket_start[bucket as usize] as usize
                        ..self.bucket_start[bucket as usize + 1] as usize;
                    for &j in &self.entries[range] {
                        let j = j as usize;
                        if positions[j].distance_squared(point) <= radius_squared {
                            visit(j);
                        }
                    }
                }
            }
        }
    }

    /// Heap memory held, bytes (capacity, not length).
    pub fn heap_bytes(&self) -> usize {
        (self.bucket_start.capacity() + self.entries.capacity() + self.point_bucket.capacity())
            * size_of::<u32>()
    }

    fn cell_of(&self, p: Vec3) -> IVec3 {
        // Saturating float-to-int casts keep far-away points finite cells.
        (p / self.cell_size).floor().as_ivec3()
    }

    fn bucket_of(&self, cell: IVec3) -> u32 {
        let h = (cell.x.wrapping_mul(92_837_111))
            ^ (cell.y.wrapping_mul(689_287_499))
            ^ (cell.z.wrapping_mul(283_923_481));
        (h.unsigned_abs() as usize % (self.bucket_start.len() - 1)) as u32
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
        let mut hash = SpatialHash::default();
        let radius = 0.1;
        hash.build(&positions, radius, |i| i % 7 != 0);
        for (i, &p) in positions.iter().enumerate() {
            let mut found = Vec::new();
            hash.for_each_within(&positions, p, radius, |j| found.push(j));
            found.sort_unstable();
            let expected: Vec<usize> = (0..positions.len())
                .filter(|&j| j % 7 != 0 && positions[j].distance(p) <= radius)
                .collect();
            assert_eq!(found, expected, "point {i}");
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
