//! What each particle hangs from: the nearest unburnt pin through the cloth, and how far
//! along the cloth it is.
//!
//! The distances are shortest paths over the live in-plane springs (structural and shear; a
//! mesh's edges), each weighted by its rest length as built, from every unburnt pin at once
//! (Dijkstra). They bound how far a particle can be from its pin in an inextensible cloth,
//! which the XPBD solver uses as tethers (long-range attachments); a particle with no path to
//! any pin has burnt loose.
//!
//! The paths form a forest rooted at the pins. When particles burn, only the particles whose
//! path ran through them (their subtrees) lose their distance; those are found through the
//! forest's child lists and given new paths by a Dijkstra seeded from their still-anchored
//! neighbours. The work is proportional to the subtrees cut, not to the cloth: a fire at the
//! bottom of a curtain costs little, one that burns through a pin re-anchors what hung from
//! it. Particles left with no path form the pieces that came loose in that step.

use super::particles::Particles;
use super::springs::{SpringKind, Springs};
use glam::Vec3;
use std::cmp::Reverse;
use std::collections::BinaryHeap;

const NONE: u32 = u32::MAX;

/// A piece of cloth that has just lost its last pin: it falls (and keeps burning) from now on.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DetachedPiece {
    /// Its particle count.
    pub particles: u32,
    /// Its centroid, world space, m.
    pub centroid: Vec3,
}

/// The anchor forest of one cloth.
#[derive(Clone, Debug, Default)]
pub struct Anchors {
    /// Neighbours over in-plane springs, compressed rows: `start[i]..start[i + 1]`.
    start: Vec<u32>,
    neighbour: Vec<u32>,
    /// The spring of each neighbour entry, to check it is still live.
    spring: Vec<u32>,
    /// Rest length of each neighbour entry as built, m.
    length: Vec<f32>,
    /// Distance along the cloth to the anchor, m; infinite when there is none.
    distance: Vec<f32>,
    /// The pin each particle hangs from, or `NONE`.
    anchor: Vec<u32>,
    parent: Vec<u32>,
    first_child: Vec<u32>,
    next_sibling: Vec<u32>,
    previous_sibling: Vec<u32>,
    /// Scratch: particles whose path was cut, a mark per particle, the Dijkstra queue.
    cut: Vec<u32>,
    marked: Vec<bool>,
    queue: BinaryHeap<Reverse<(u32, u32)>>,
    /// Particles whose anchor or distance changed in the latest update.
    changed: Vec<u32>,
    /// Whether the whole forest must be (re)built.
    stale: bool,
    built_for: usize,
}

impl Anchors {
    /// Heap memory held, bytes (capacity, not length).
    pub fn heap_bytes(&self) -> usize {
        let words = [
            &self.start,
            &self.neighbour,
            &self.spring,
            &self.anchor,
            &self.parent,
            &self.first_child,
            &self.next_sibling,
            &self.previous_sibling,
            &self.cut,
            &self.changed,
        ]
        .iter()
        .map(|v| v.capacity())
        .sum::<usize>();
        (words + self.length.capacity() + self.distance.capacity()) * size_of::<u32>()
            + self.marked.capacity()
            + self.queue.capacity() * size_of::<Reverse<(u32, u32)>>()
    }

    /// Asks for a full rebuild at the next update (pins were added or removed).
    pub fn invalidate(&mut self) {
        self.stale = true;
    }

    /// Distance along the cloth from particle `i` to its pin, m (infinite when loose).
    pub fn distance(&self, i: usize) -> f32 {
        self.distance[i]
    }

    /// The pin particle `i` hangs from, if any (a pin hangs from itself).
    pub fn anchor(&self, i: usize) -> Option<u32> {
        (self.anchor[i] != NONE).then_some(self.anchor[i])
    }

    /// Particles whose anchor or distance changed in the latest update (every particle after
    /// a full build).
    pub fn changed(&self) -> &[u32] {
        &self.changed
    }

    /// Whether particle `i` hangs from a pin.
    pub fn is_anchored(&self, i: usize) -> bool {
        self.anchor[i] != NONE
    }

    /// Brings the forest up to date after `newly_burnt` burnt: builds it on first use (or
    /// after [`Self::invalidate`], or when the particle count changed), else re-anchors the
    /// subtrees of the burnt particles. Appends to `detached` each piece that lost its last
    /// pin (a cloth with no pin at all is loose from the start and reports nothing).
    pub fn update(
        &mut self,
        particles: &Particles,
        springs: &Springs,
        newly_burnt: &[u32],
        detached: &mut Vec<DetachedPiece>,
    ) {
        self.changed.clear();
        if self.stale || self.built_for != particles.len() {
            self.build(particles, springs);
            return;
        }
        if newly_burnt.is_empty() {
            return;
        }
        self.cut_subtrees(newly_burnt);
        self.reanchor(particles, springs);
        self.report_loose(particles, springs, detached);
        for &i in &self.cut {
            self.marked[i as usize] = false;
        }
    }

    /// Builds the neighbour rows and the whole forest.
    fn build(&mut self, particles: &Particles, springs: &Springs) {
        let n = particles.len();
        self.built_for = n;
        self.stale = false;
        let in_plane = |s: usize| springs.kind[s] != SpringKind::Bend;
        self.start.clear();
        self.start.resize(n + 1, 0);
        for s in (0..springs.len()).filter(|&s| in_plane(s)) {
            self.start[springs.a[s] as usize + 1] += 1;
            self.start[springs.b[s] as usize + 1] += 1;
        }
        for i in 0..n {
            self.start[i + 1] += self.start[i];
        }
        let entries = self.start[n] as usize;
        self.neighbour.clear();
        self.neighbour.resize(entries, NONE);
        self.spring.clear();
        self.spring.resize(entries, NONE);
        self.length.clear();
        self.length.resize(entries, 0.0);
        let mut cursor = self.start[..n].to_vec();
        for s in (0..springs.len()).filter(|&s| in_plane(s)) {
            let (a, b) = (springs.a[s] as usize, springs.b[s] as usize);
            for (from, to) in [(a, b), (b, a)] {
                let slot = cursor[from] as usize;
                self.neighbour[slot] = to as u32;
                self.spring[slot] = s as u32;
                self.length[slot] = springs.initial_rest_length[s].max(0.0);
                cursor[from] += 1;
            }
        }
        for array in [
            &mut self.anchor,
            &mut self.parent,
            &mut self.first_child,
            &mut self.next_sibling,
            &mut self.previous_sibling,
        ] {
            array.clear();
            array.resize(n, NONE);
        }
        self.distance.clear();
        self.distance.resize(n, f32::INFINITY);
        self.marked.clear();
        self.marked.resize(n, false);
        self.cut.clear();
        self.cut.reserve(n);
        self.changed.reserve(n);
        self.queue.clear();
        // A particle enters the queue at most once per neighbour that improves it.
        self.queue.reserve(entries + n);
        for i in 0..n {
            if particles.is_pinned(i) && !particles.state[i].is_burnt() {
                self.distance[i] = 0.0;
                self.anchor[i] = i as u32;
                self.queue.push(Reverse((0, i as u32)));
            }
        }
        // Every particle takes part, as in a re-anchoring of the whole cloth.
        self.marked.fill(true);
        self.dijkstra(particles, springs);
        self.marked.fill(false);
        for i in 0..n {
            self.link(i);
        }
        self.changed.extend(0..n as u32);
    }

    /// Marks the subtrees of the burnt particles as cut and detaches them from their parents.
    fn cut_subtrees(&mut self, newly_burnt: &[u32]) {
        self.cut.clear();
        for &root in newly_burnt {
            let root = root as usize;
            if self.marked[root] {
                continue;
            }
            self.unlink(root);
            self.marked[root] = true;
            let first = self.cut.len();
            self.cut.push(root as u32);
            let mut next = first;
            while next < self.cut.len() {
                let i = self.cut[next] as usize;
                next += 1;
                let mut child = self.first_child[i];
                while child != NONE {
                    let c = child as usize;
                    child = self.next_sibling[c];
                    if !self.marked[c] {
                        self.marked[c] = true;
                        self.cut.push(c as u32);
                    }
                }
            }
        }
        for &i in &self.cut {
            let i = i as usize;
            self.distance[i] = f32::INFINITY;
            self.anchor[i] = NONE;
            self.parent[i] = NONE;
            self.first_child[i] = NONE;
            self.next_sibling[i] = NONE;
            self.previous_sibling[i] = NONE;
        }
    }

    /// Gives the cut particles new paths: seeded from their anchored neighbours, spread
    /// among the cut particles.
    fn reanchor(&mut self, particles: &Particles, springs: &Springs) {
        self.queue.clear();
        for c in 0..self.cut.len() {
            let i = self.cut[c] as usize;
            if particles.state[i].is_burnt() {
                continue;
            }
            for entry in self.start[i] as usize..self.start[i + 1] as usize {
                let j = self.neighbour[entry] as usize;
                let live = springs.is_live(self.spring[entry] as usize, &particles.state);
                if !live || self.marked[j] || self.anchor[j] == NONE {
                    continue;
                }
                let candidate = self.distance[j] + self.length[entry];
                if candidate < self.distance[i] {
                    self.distance[i] = candidate;
                    self.parent[i] = j as u32;
                    self.anchor[i] = self.anchor[j];
                }
            }
            if self.anchor[i] != NONE {
                self.queue
                    .push(Reverse((self.distance[i].to_bits(), i as u32)));
            }
        }
        self.dijkstra(particles, springs);
        for c in 0..self.cut.len() {
            let i = self.cut[c] as usize;
            self.link(i);
            self.changed.push(i as u32);
        }
    }

    /// Settles the queued particles and spreads to marked, unburnt neighbours. Ties break by
    /// particle index, so the forest does not depend on anything but the cloth.
    fn dijkstra(&mut self, particles: &Particles, springs: &Springs) {
        while let Some(Reverse((bits, i))) = self.queue.pop() {
            let i = i as usize;
            let d = f32::from_bits(bits);
            if d > self.distance[i] {
                continue;
            }
            for entry in self.start[i] as usize..self.start[i + 1] as usize {
                let j = self.neighbour[entry] as usize;
                if !self.marked[j] || particles.state[j].is_burnt() {
                    continue;
                }
                if !springs.is_live(self.spring[entry] as usize, &particles.state) {
                    continue;
                }
                let candidate = d + self.length[entry];
                let better = candidate < self.distance[j]
                    || (candidate == self.distance[j] && (i as u32) < self.parent[j]);
                if better {
                    self.distance[j] = candidate;
                    self.parent[j] = i as u32;
                    self.anchor[j] = self.anchor[i];
                    self.queue.push(Reverse((candidate.to_bits(), j as u32)));
                }
            }
        }
    }

    /// Puts particle `i` in its parent's child list.
    fn link(&mut self, i: usize) {
        let parent = self.parent[i];
        if parent == NONE {
            return;
        }
        let head = self.first_child[parent as usize];
        self.next_sibling[i] = head;
        self.previous_sibling[i] = NONE;
        if head != NONE {
            self.previous_sibling[head as usize] = i as u32;
        }
        self.first_child[parent as usize] = i as u32;
    }

    /// Takes particle `i` out of its parent's child list.
    fn unlink(&mut self, i: usize) {
        let parent = self.parent[i];
        if parent == NONE {
            return;
        }
        let (previous, next) = (self.previous_sibling[i], self.next_sibling[i]);
        if previous == NONE {
            self.first_child[parent as usize] = next;
        } else {
            self.next_sibling[previous as usize] = next;
        }
        if next != NONE {
            self.previous_sibling[next as usize] = previous;
        }
        self.parent[i] = NONE;
    }

    /// Groups the cut particles left with no anchor into pieces (connected over live
    /// in-plane springs) and reports each with its size and centroid.
    fn report_loose(
        &mut self,
        particles: &Particles,
        springs: &Springs,
        detached: &mut Vec<DetachedPiece>,
    ) {
        // Reuse the marks: a loose cut particle stays marked until its piece is counted.
        for c in 0..self.cut.len() {
            let i = self.cut[c] as usize;
            if !self.marked[i] || self.anchor[i] != NONE || particles.state[i].is_burnt() {
                continue;
            }
            let (mut sum, mut count) = (Vec3::ZERO, 0u32);
            // Depth-first over the piece, using `parent` of loose particles as the stack.
            self.marked[i] = false;
            let mut top = i as u32;
            self.parent[i] = NONE;
            while top != NONE {
                let p = top as usize;
                top = self.parent[p];
                self.parent[p] = NONE;
                sum += particles.position[p];
                count += 1;
                for entry in self.start[p] as usize..self.start[p + 1] as usize {
                    let j = self.neighbour[entry] as usize;
                    let live = springs.is_live(self.spring[entry] as usize, &particles.state);
                    if live && self.marked[j] && self.anchor[j] == NONE {
                        self.marked[j] = false;
                        self.parent[j] = top;
                        top = j as u32;
                    }
                }
            }
            detached.push(DetachedPiece {
                particles: count,
                centroid: sum / count as f32,
            });
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::{BurnMaterial, BurnState, ClothBuilder};
    use glam::Affine3A;

    fn cloth(builder: ClothBuilder) -> (Particles, Springs) {
        let parts = builder
            .build(&BurnMaterial::COTTON, Affine3A::IDENTITY)
            .unwrap();
        (parts.particles, parts.springs)
    }

    /// Distances over the grid's structural and shear springs, by brute force (Bellman–Ford).
    fn brute_force(particles: &Particles, springs: &Springs) -> Vec<f32> {
        let n = particles.len();
        let mut distance: Vec<f32> = (0..n)
            .map(|i| {
                if particles.is_pinned(i) && !particles.state[i].is_burnt() {
                    0.0
                } else {
                    f32::INFINITY
                }
            })
            .collect();
        for _ in 0..n {
            for s in 0..springs.len() {
                if springs.kind[s] == SpringKind::Bend || !springs.is_live(s, &particles.state) {
                    continue;
                }
                let (a, b) = (springs.a[s] as usize, springs.b[s] as usize);
                let l = springs.initial_rest_length[s];
                distance[a] = distance[a].min(distance[b] + l);
                distance[b] = distance[b].min(distance[a] + l);
            }
        }
        distance
    }

    #[test]
    fn distances_are_shortest_paths_and_stay_so_as_particles_burn() {
        let (mut particles, springs) = cloth(ClothBuilder::grid(9, 8, 0.1).pin_top_every(4));
        let mut anchors = Anchors::default();
        let mut detached = Vec::new();
        anchors.update(&particles, &springs, &[], &mut detached);
        let check = |anchors: &Anchors, particles: &Particles| {
            let expected = brute_force(particles, &springs);
            for (i, &want) in expected.iter().enumerate() {
                if particles.state[i].is_burnt() {
                    continue;
                }
                let got = anchors.distance(i);
                assert!(
                    (got == want) || (got - want).abs() < 1e-5,
                    "particle {i}: {got} vs {want}"
                );
                assert_eq!(anchors.is_anchored(i), want.is_finite());
            }
        };
        check(&anchors, &particles);
        // Straight below a pin: the distance is the drop.
        assert!((anchors.distance(4 * 9 + 4) - 0.4).abs() < 1e-6);
        // Burn a wall across most of row 3, then the rest, then a pin: every time the
        // distances match the brute force.
        let burn = |particles: &mut Particles, which: &[usize], anchors: &mut Anchors| {
            for &i in which {
                particles.state[i] = BurnState::Burnt;
            }
            let burnt: Vec<u32> = which.iter().map(|&i| i as u32).collect();
            let mut detached = Vec::new();
            anchors.update(particles, &springs, &burnt, &mut detached);
            detached
        };
        let wall: Vec<usize> = (0..7).map(|c| 3 * 9 + c).collect();
        assert!(burn(&mut particles, &wall, &mut anchors).is_empty());
        check(&anchors, &particles);
        assert!(
            anchors.distance(5 * 9 + 2) > 0.5,
            "the path goes round the wall"
        );
        let pieces = burn(&mut particles, &[3 * 9 + 7, 3 * 9 + 8], &mut anchors);
        check(&anchors, &particles);
        assert_eq!(pieces.len(), 1, "rows 4 to 7 came off as one piece");
        assert_eq!(pieces[0].particles, 4 * 9);
        assert!((pieces[0].centroid.y + 0.55).abs() < 1e-5);
        // Burning into the loose piece reports nothing new.
        assert!(burn(&mut particles, &[5 * 9 + 4], &mut anchors).is_empty());
        // The middle pin burns: what hung from it hangs from the others now.
        assert!(burn(&mut particles, &[4], &mut anchors).is_empty());
        check(&anchors, &particles);
        assert_eq!(anchors.anchor(9 + 4).map(|p| p == 0 || p == 8), Some(true));
    }

    #[test]
    fn a_cloth_without_pins_is_loose_from_the_start_and_reports_nothing() {
        let (mut particles, springs) = cloth(ClothBuilder::grid(4, 4, 0.1));
        let mut anchors = Anchors::default();
        let mut detached = Vec::new();
        anchors.update(&particles, &springs, &[], &mut detached);
        assert!((0..16).all(|i| !anchors.is_anchored(i)));
        particles.state[5] = BurnState::Burnt;
        anchors.update(&particles, &springs, &[5], &mut detached);
        assert!(detached.is_empty());
    }
}
