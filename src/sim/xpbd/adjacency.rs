//! Which elements (springs) each particle is in, as compressed rows: built once per cloth, so
//! work after a particle burns or is pinned touches only its springs.

/// The elements of each particle, as compressed rows.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Adjacency {
    /// `start[i]..start[i + 1]` indexes `elements` for particle `i`.
    start: Vec<u32>,
    elements: Vec<u32>,
}

impl Adjacency {
    /// Rebuilds the rows of `particles` particles over `count` elements, element `e` being in
    /// the rows of the particles `members(e)` (entries past the particle count, such as
    /// `u32::MAX`, are skipped).
    pub fn build(&mut self, particles: usize, count: usize, members: impl Fn(u32) -> [u32; 4]) {
        self.start.clear();
        self.start.resize(particles + 1, 0);
        for e in 0..count as u32 {
            for i in members(e) {
                if (i as usize) < particles {
                    self.start[i as usize + 1] += 1;
                }
            }
        }
        for i in 0..particles {
            self.start[i + 1] += self.start[i];
        }
        self.elements.clear();
        self.elements.resize(self.start[particles] as usize, 0);
        let mut cursor: Vec<u32> = self.start[..particles].to_vec();
        for e in 0..count as u32 {
            for i in members(e) {
                if (i as usize) < particles {
                    let slot = &mut cursor[i as usize];
                    self.elements[*slot as usize] = e;
                    *slot += 1;
                }
            }
        }
    }

    /// The elements particle `i` is in, in increasing order.
    pub fn of(&self, i: usize) -> &[u32] {
        &self.elements[self.start[i] as usize..self.start[i + 1] as usize]
    }

    /// Heap memory held, bytes (capacity, not length).
    pub fn heap_bytes(&self) -> usize {
        (self.start.capacity() + self.elements.capacity()) * size_of::<u32>()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_element_is_listed_under_each_of_its_members() {
        let members = [
            [0, 1, u32::MAX, u32::MAX],
            [1, 2, u32::MAX, u32::MAX],
            [0, 2, 1, 7],
        ];
        let mut adjacency = Adjacency::default();
        adjacency.build(3, 3, |e| members[e as usize]);
        assert_eq!(adjacency.of(0), &[0, 2]);
        assert_eq!(adjacency.of(1), &[0, 1, 2]);
        assert_eq!(adjacency.of(2), &[1, 2]);
    }
}
