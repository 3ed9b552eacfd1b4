//! The blow-up guard: one bad step never spreads NaN over a cloth or a game.
//!
//! Before the dynamics of a step, [`BlowUpGuard::remember`] keeps each particle's position.
//! After it, [`BlowUpGuard::check`] finds particles whose position or velocity is not finite
//! or whose speed exceeds the limit (a runaway: explicit integration past its stability limit
//! gains energy every step), puts them back where they were with zero velocity, and resets
//! non-finite temperatures to the initial temperature. The caller reports the count (the
//! plugin logs a warning and triggers `ClothInstability`).

use super::particles::Particles;
use bevy::reflect::Reflect;
use glam::Vec3;

/// Settings of the guard.
#[derive(Clone, Copy, Debug, PartialEq, Reflect)]
#[reflect(Clone, Debug, PartialEq)]
pub struct GuardSettings {
    /// Whether the guard runs (off only to study raw solver failures).
    pub enabled: bool,
    /// Particles faster than this are treated as blown up, m/s. Far above anything cloth
    /// does (a cloth falling 100 m reaches 44 m/s).
    pub max_speed: f32,
}

impl Default for GuardSettings {
    fn default() -> Self {
        Self {
            enabled: true,
            max_speed: 200.0,
        }
    }
}

/// Positions at the start of the step, for restoring.
#[derive(Clone, Debug, Default)]
pub struct BlowUpGuard {
    last_good: Vec<Vec3>,
}

impl BlowUpGuard {
    /// Heap memory held, bytes (capacity, not length).
    pub fn heap_bytes(&self) -> usize {
        self.last_good.capacity() * size_of::<Vec3>()
    }

    /// True when particle `i` has blown up under `settings`: a non-finite position or
    /// velocity, or a speed above the limit.
    pub fn is_blown_up(particles: &Particles, i: usize, settings: &GuardSettings) -> bool {
        let (p, v) = (particles.position[i], particles.velocity[i]);
        !(p.is_finite() && v.is_finite() && v.length() <= settings.max_speed)
    }

    /// Remembers every particle's position (call before the dynamics of a step). Reuses its
    /// memory. A non-finite position is not remembered: the last finite one is kept.
    pub fn remember(&mut self, particles: &Particles) {
        if self.last_good.len() != particles.len() {
            self.last_good.clear();
            self.last_good.extend(
                particles
                    .position
                    .iter()
                    .map(|p| if p.is_finite() { *p } else { Vec3::ZERO }),
            );
            return;
        }
        for (good, p) in self.last_good.iter_mut().zip(&particles.position) {
            if p.is_finite() {
                *good = *p;
            }
        }
    }

    /// Resets non-finite temperatures to `initial_temperature` (when the guard is enabled) and
    /// returns how many there were. [`Self::check`] does this too; solvers that check their
    /// particles themselves call this for the temperatures.
    pub fn repair_temperatures(
        particles: &mut Particles,
        settings: &GuardSettings,
        initial_temperature: f32,
    ) -> u32 {
        if !settings.enabled || particles.temperature.iter().all(|t| t.is_finite()) {
            return 0;
        }
        let mut repaired = 0;
        for t in &mut particles.temperature {
            if !t.is_finite() {
                *t = initial_temperature;
                repaired += 1;
            }
        }
        repaired
    }

    /// Repairs blown-up particles and returns how many were repaired.
    pub fn check(
        &self,
        particles: &mut Particles,
        settings: &GuardSettings,
        initial_temperature: f32,
    ) -> u32 {
        if !settings.enabled {
            return 0;
        }
        let mut repaired = 0;
        for i in 0..particles.len() {
            let runaway = Self::is_blown_up(particles, i, settings);
            if runaway {
                particles.position[i] = self.last_good.get(i).copied().unwrap_or(Vec3::ZERO);
                particles.velocity[i] = Vec3::ZERO;
                repaired += 1;
            }
            if !particles.temperature[i].is_finite() {
                particles.temperature[i] = initial_temperature;
                repaired += u32::from(!runaway);
            }
        }
        repaired
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::BurnState;

    #[test]
    fn nan_and_runaway_particles_are_put_back() {
        let mut particles = Particles {
            position: vec![Vec3::ZERO, Vec3::X, Vec3::Y],
            velocity: vec![Vec3::ZERO; 3],
            mass: vec![1.0; 3],
            inv_mass: vec![1.0; 3],
            temperature: vec![20.0; 3],
            state: vec![BurnState::Intact; 3],
            burning_for: vec![0.0; 3],
            anchor: vec![Vec3::ZERO; 3],
            external_force: vec![Vec3::ZERO; 3],
        };
        let mut guard = BlowUpGuard::default();
        guard.remember(&particles);
        particles.position[0] = Vec3::NAN;
        particles.velocity[1] = Vec3::new(1.0e4, 0.0, 0.0);
        particles.position[1] = Vec3::new(50.0, 0.0, 0.0);
        particles.temperature[2] = f32::INFINITY;
        let repaired = guard.check(&mut particles, &GuardSettings::default(), 15.0);
        assert_eq!(repaired, 3);
        assert_eq!(particles.position, vec![Vec3::ZERO, Vec3::X, Vec3::Y]);
        assert_eq!(particles.velocity[1], Vec3::ZERO);
        assert_eq!(particles.temperature[2], 15.0);
        assert!(particles.is_finite());
        // A healthy cloth is left alone.
        assert_eq!(
            guard.check(&mut particles, &GuardSettings::default(), 15.0),
            0
        );
    }
}
