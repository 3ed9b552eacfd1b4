//! A fixed-capacity pool of smoke, flame and ember particles as a structure of arrays.

use glam::Vec3;

/// What a pool particle is; each kind has its own [`KindSettings`](super::KindSettings).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[repr(u8)]
pub enum SmokeKind {
    /// Short-lived, bright, rising fast; drawn additively.
    #[default]
    Flame,
    /// Long-lived, grey, growing and fading; drawn alpha-blended.
    Smoke,
    /// Small glowing sparks that drift up while hot and fall as they cool; drawn additively.
    Ember,
}

impl SmokeKind {
    /// Every kind, in the order of [`SmokeSettings::kind`](super::SmokeSettings::kind).
    pub const ALL: [Self; 3] = [Self::Flame, Self::Smoke, Self::Ember];

    /// True for kinds drawn with additive blending (they emit light).
    pub fn is_additive(self) -> bool {
        self != Self::Smoke
    }
}

/// A fixed-capacity particle pool. Slots are reused; nothing is allocated after
/// [`SmokePool::with_capacity`]. When every slot is alive a new particle replaces the slot
/// at a rotating cursor, which with full slots is the one spawned longest ago among those
/// the cursor has not yet passed: the oldest particles go first, approximately.
#[derive(Clone, Debug, Default)]
pub struct SmokePool {
    /// World positions, m.
    pub position: Vec<Vec3>,
    /// Velocities, m/s.
    pub velocity: Vec<Vec3>,
    /// Temperatures, °C (drive buoyancy).
    pub temperature: Vec<f32>,
    /// Seconds since birth.
    pub age: Vec<f32>,
    /// Seconds the particle lives.
    pub lifetime: Vec<f32>,
    /// Per-particle size factor (variety), around 1.
    pub scale: Vec<f32>,
    /// Kind of each slot.
    pub kind: Vec<SmokeKind>,
    /// Whether each slot holds a live particle.
    pub alive: Vec<bool>,
    free: Vec<u32>,
    live: usize,
    cursor: usize,
    replaced: u64,
}

/// A particle to put in the pool.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NewParticle {
    /// Kind.
    pub kind: SmokeKind,
    /// World position, m.
    pub position: Vec3,
    /// Velocity, m/s.
    pub velocity: Vec3,
    /// Temperature, °C.
    pub temperature: f32,
    /// Lifetime, s (positive).
    pub lifetime: f32,
    /// Size factor.
    pub scale: f32,
}

impl SmokePool {
    /// An empty pool with room for `capacity` particles, allocated once.
    pub fn with_capacity(capacity: usize) -> Self {
        Self {
            position: vec![Vec3::ZERO; capacity],
            velocity: vec![Vec3::ZERO; capacity],
            temperature: vec![0.0; capacity],
            age: vec![0.0; capacity],
            lifetime: vec![0.0; capacity],
            scale: vec![0.0; capacity],
            kind: vec![SmokeKind::Flame; capacity],
            alive: vec![false; capacity],
            // Popped from the end: slot 0 is used first.
            free: (0..capacity as u32).rev().collect(),
            live: 0,
            cursor: 0,
            replaced: 0,
        }
    }

    /// Number of slots.
    pub fn capacity(&self) -> usize {
        self.alive.len()
    }

    /// Number of live particles.
    pub fn live(&self) -> usize {
        self.live
    }

    /// True when no particle is alive.
    pub fn is_empty(&self) -> bool {
        self.live == 0
    }

    /// Live particles replaced because the pool was full, since it was made.
    pub fn replaced(&self) -> u64 {
        self.replaced
    }

    /// Bytes of heap memory the pool holds (constant after construction).
    pub fn heap_bytes(&self) -> usize {
        use core::mem::size_of;
        self.position.capacity() * size_of::<Vec3>() * 2
            + (self.temperature.capacity()
                + self.age.capacity()
                + self.lifetime.capacity()
                + self.scale.capacity())
                * size_of::<f32>()
            + self.kind.capacity() * size_of::<SmokeKind>()
            + self.alive.capacity()
            + self.free.capacity() * size_of::<u32>()
    }

    /// Puts a particle in a free slot, or over the slot at the rotating cursor when the pool
    /// is full. Returns the slot, or `None` for a pool of capacity zero.
    pub fn spawn(&mut self, particle: NewParticle) -> Option<usize> {
        let slot = match self.free.pop() {
            Some(slot) => {
                self.live += 1;
                slot as usize
            }
            None => {
                if self.capacity() == 0 {
                    return None;
                }
                let slot = self.cursor;
                self.cursor = (self.cursor + 1) % self.capacity();
                self.replaced += 1;
                slot
            }
        };
        self.position[slot] = particle.position;
        self.velocity[slot] = particle.velocity;
        self.temperature[slot] = particle.temperature;
        self.age[slot] = 0.0;
        self.lifetime[slot] = particle.lifetime;
        self.scale[slot] = particle.scale;
        self.kind[slot] = particle.kind;
        self.alive[slot] = true;
        Some(slot)
    }

    /// Frees a live slot (does nothing to a free one).
    pub fn kill(&mut self, slot: usize) {
        if self.alive[slot] {
            self.alive[slot] = false;
            self.free.push(slot as u32);
            self.live -= 1;
        }
    }

    /// Frees every slot.
    pub fn clear(&mut self) {
        for slot in 0..self.capacity() {
            self.kill(slot);
        }
    }

    /// Fraction of its life a slot has lived, in [0, 1].
    pub fn life_fraction(&self, slot: usize) -> f32 {
        (self.age[slot] / self.lifetime[slot]).clamp(0.0, 1.0)
    }

    /// Indices of live slots.
    pub fn live_slots(&self) -> impl Iterator<Item = usize> + '_ {
        self.alive
            .iter()
            .enumerate()
            .filter_map(|(slot, &alive)| alive.then_some(slot))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn particle(x: f32) -> NewParticle {
        NewParticle {
            kind: SmokeKind::Smoke,
            position: Vec3::new(x, 0.0, 0.0),
            velocity: Vec3::ZERO,
            temperature: 20.0,
            lifetime: 1.0,
            scale: 1.0,
        }
    }

    #[test]
    fn full_pool_replaces_in_rotation_and_never_grows() {
        let mut pool = SmokePool::with_capacity(4);
        let bytes = pool.heap_bytes();
        for i in 0..4 {
            assert_eq!(pool.spawn(particle(i as f32)), Some(i));
        }
        assert_eq!(pool.live(), 4);
        // Full: the oldest (slot 0, then 1) are replaced.
        assert_eq!(pool.spawn(particle(10.0)), Some(0));
        assert_eq!(pool.spawn(particle(11.0)), Some(1));
        assert_eq!(pool.live(), 4);
        assert_eq!(pool.replaced(), 2);
        pool.kill(2);
        assert_eq!(pool.live(), 3);
        // A freed slot is used before replacing anything.
        assert_eq!(pool.spawn(particle(12.0)), Some(2));
        assert_eq!(pool.replaced(), 2);
        assert_eq!(pool.heap_bytes(), bytes);
    }

    #[test]
    fn killing_twice_counts_once_and_zero_capacity_refuses() {
        let mut pool = SmokePool::with_capacity(2);
        pool.spawn(particle(0.0));
        pool.kill(0);
        pool.kill(0);
        assert_eq!(pool.live(), 0);
        assert_eq!(pool.live_slots().count(), 0);
        let mut empty = SmokePool::with_capacity(0);
        assert_eq!(empty.spawn(particle(0.0)), None);
    }
}
