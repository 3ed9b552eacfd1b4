//! Which parts of a cloth still hang together: connected components of the unburnt particles
//! over live structural springs, and which of them has lost every pin.
//!
//! A piece that burning has cut loose needs no special physics: its particles are no longer
//! held, so it falls, keeps burning and lands on colliders like the rest. This module tells
//! gameplay when that happens ([`PieceTracker::update`] reports newly detached pieces).

use super::particles::{BurnState, Particles};
use super::springs::{SpringKind, Springs};
use glam::Vec3;

/// Connected components of a cloth's unburnt particles.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Pieces {
    /// Component of each particle (`u32::MAX` for burnt particles), numbered from 0.
    pub label: Vec<u32>,
    /// Per component: whether it holds an unburnt pin.
    pub pinned: Vec<bool>,
    /// Per component: its particle count.
    pub size: Vec<u32>,
    parent: Vec<u32>,
}

impl Pieces {
    /// Number of pieces.
    pub fn count(&self) -> usize {
        self.size.len()
    }

    /// Number of pieces with no pin left.
    pub fn loose_count(&self) -> usize {
        self.pinned.iter().filter(|p| !**p).count()
    }

    /// Recomputes the pieces: union-find over live structural springs (path halving, union by
    /// index), O(particles + springs). Memory is reused.
    pub fn find(&mut self, particles: &Particles, springs: &Springs) {
        let n = particles.len();
        self.parent.clear();
        self.parent.extend(0..n as u32);
        for s in 0..springs.len() {
            if springs.kind[s] != SpringKind::Structural || !springs.is_live(s, &particles.state) {
                continue;
            }
            let (a, b) = (
                find_root(&mut self.parent, springs.a[s]),
                find_root(&mut self.parent, springs.b[s]),
            );
            if a != b {
                // Attach the larger root to the smaller: deterministic.
                let (low, high) = (a.min(b), a.max(b));
                self.parent[high as usize] = low;
            }
        }
        self.label.clear();
        self.label.resize(n, u32::MAX);
        self.pinned.clear();
        self.size.clear();
        // There are never more pieces than particles: reserve once, never grow mid-burn.
        self.pinned.reserve(n);
        self.size.reserve(n);
        for i in 0..n {
            if particles.state[i] == BurnState::Burnt {
                continue;
            }
            let root = find_root(&mut self.parent, i as u32) as usize;
            if self.label[root] == u32::MAX {
                self.label[root] = self.size.len() as u32;
                self.size.push(0);
                self.pinned.push(false);
            }
            let c = self.label[root];
            self.label[i] = c;
            self.size[c as usize] += 1;
            if particles.is_pinned(i) {
                self.pinned[c as usize] = true;
            }
        }
    }
}

fn find_root(parent: &mut [u32], mut i: u32) -> u32 {
    while parent[i as usize] != i {
        let grandparent = parent[parent[i as usize] as usize];
        parent[i as usize] = grandparent;
        i = grandparent;
    }
    i
}

/// A piece that has just lost its last pin.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DetachedPiece {
    /// Its particle count.
    pub particles: u32,
    /// Its centroid, world space, m.
    pub centroid: Vec3,
}

/// Remembers which particles were already loose, to report each piece once when it comes
/// off.
#[derive(Clone, Debug, Default)]
pub struct PieceTracker {
    /// The current pieces.
    pub pieces: Pieces,
    loose: Vec<bool>,
    sums: Vec<(Vec3, u32, bool)>,
}

impl PieceTracker {
    /// Heap memory held, bytes (capacity, not length).
    pub fn heap_bytes(&self) -> usize {
        let p = &self.pieces;
        (p.label.capacity() + p.size.capacity() + p.parent.capacity()) * size_of::<u32>()
            + p.pinned.capacity()
            + self.loose.capacity()
            + self.sums.capacity() * size_of::<(Vec3, u32, bool)>()
    }

    /// Whether the tracker has seen a cloth of `particles` particles (false before the first
    /// [`PieceTracker::update`], or after a rebuild changed the count).
    pub fn tracks(&self, particles: usize) -> bool {
        self.loose.len() == particles
    }

    /// Recomputes the pieces and appends to `detached` every loose piece holding a particle
    /// that was not loose before (a cloth with no pins at all is loose from the start and
    /// reports nothing). Call it after particles burn; between burns nothing changes.
    pub fn update(
        &mut self,
        particles: &Particles,
        springs: &Springs,
        detached: &mut Vec<DetachedPiece>,
    ) {
        let n = particles.len();
        if self.loose.len() != n {
            // First call (or a rebuilt cloth): whatever is loose now was always loose.
            self.pieces.find(particles, springs);
            self.loose.clear();
            self.loose.extend((0..n).map(|i| {
                let c = self.pieces.label[i];
                c == u32::MAX || !self.pieces.pinned[c as usize]
            }));
            return;
        }
        self.pieces.find(particles, springs);
        self.sums.clear();
        self.sums.reserve(n);
        detached.reserve(n);
        self.sums
            .resize(self.pieces.count(), (Vec3::ZERO, 0, false));
        for i in 0..n {
            let c = self.pieces.label[i];
            if c == u32::MAX || self.pieces.pinned[c as usize] {
                continue;
            }
            let entry = &mut self.sums[c as usize];
            entry.0 += particles.position[i];
            entry.1 += 1;
            entry.2 |= !self.loose[i];
            self.loose[i] = true;
        }
        for &(sum, count, new) in &self.sums {
            if new && count > 0 {
                detached.push(DetachedPiece {
                    particles: count,
                    centroid: sum / count as f32,
                });
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::{BurnMaterial, ClothBuilder};
    use glam::Affine3A;

    #[test]
    fn burning_a_row_across_cuts_the_cloth_in_two_and_the_lower_piece_is_loose() {
        let parts = ClothBuilder::grid(6, 6, 0.1)
            .pin_top_edge()
            .build(&BurnMaterial::COTTON, Affine3A::IDENTITY)
            .unwrap();
        let mut particles = parts.particles;
        let springs = parts.springs;
        let mut tracker = PieceTracker::default();
        let mut detached = Vec::new();
        tracker.update(&particles, &springs, &mut detached);
        assert_eq!(tracker.pieces.count(), 1);
        assert!(detached.is_empty());
        // Burn row 3 across (all 6 columns): rows 4 and 5 (12 particles) come loose.
        for column in 0..6 {
            particles.state[3 * 6 + column] = BurnState::Burnt;
        }
        tracker.update(&particles, &springs, &mut detached);
        assert_eq!(tracker.pieces.count(), 2);
        assert_eq!(tracker.pieces.loose_count(), 1);
        assert_eq!(detached.len(), 1);
        assert_eq!(detached[0].particles, 12);
        assert!((detached[0].centroid.y - (-0.45)).abs() < 1e-5);
        // Splitting the loose piece further reports nothing new: it was already off.
        for row in 4..6 {
            particles.state[row * 6 + 2] = BurnState::Burnt;
        }
        detached.clear();
        tracker.update(&particles, &springs, &mut detached);
        assert_eq!(tracker.pieces.count(), 3);
        assert!(detached.is_empty());
    }

    #[test]
    fn bending_springs_across_a_burnt_row_are_cut_and_do_not_hold_the_piece() {
        // Bend springs from row 2 to row 4 jump over row 3; when row 3 burns they must go.
        let parts = ClothBuilder::grid(4, 6, 0.1)
            .pin_top_edge()
            .build(&BurnMaterial::COTTON, Affine3A::IDENTITY)
            .unwrap();
        let mut particles = parts.particles;
        let mut springs = parts.springs;
        for column in 0..4 {
            particles.state[3 * 4 + column] = BurnState::Burnt;
        }
        let live_bends_across = |springs: &Springs, particles: &Particles| {
            (0..springs.len())
                .filter(|&s| {
                    springs.kind[s] == SpringKind::Bend
                        && springs.is_live(s, &particles.state)
                        && (springs.a[s] / 4 < 3) != (springs.b[s] / 4 < 3)
                })
                .count()
        };
        assert_eq!(
            live_bends_across(&springs, &particles),
            4,
            "rows 2 to 4, one per column"
        );
        assert_eq!(springs.sever_spanning(&particles.state), 4);
        assert_eq!(live_bends_across(&springs, &particles), 0);
        assert_eq!(springs.sever_spanning(&particles.state), 0, "cut once");
        let mut pieces = Pieces::default();
        pieces.find(&particles, &springs);
        assert_eq!(pieces.count(), 2);
        assert_eq!(pieces.loose_count(), 1);
    }
}
