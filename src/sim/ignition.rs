//! Setting a cloth alight: raising a particle to an ignition temperature, and finding the
//! particle nearest to a point.

use super::error::ClothError;
use super::material::valid_temperature;
use super::particles::{BurnState, Particles};
use glam::Vec3;

/// Raises particle `index` to `temperature` (°C) if it is colder, as an ignition point.
pub fn heat_particle(
    particles: &mut Particles,
    index: usize,
    temperature: f32,
) -> Result<(), ClothError> {
    if index >= particles.len() {
        return Err(ClothError::ParticleOutOfRange {
            index,
            len: particles.len(),
        });
    }
    if !valid_temperature(temperature) {
        return Err(ClothError::InvalidTemperature(temperature));
    }
    let t = &mut particles.temperature[index];
    *t = t.max(temperature);
    Ok(())
}

/// The unburnt particle nearest to `point`.
pub fn nearest_unburnt_particle(particles: &Particles, point: Vec3) -> Result<usize, ClothError> {
    if !point.is_finite() {
        return Err(ClothError::NonFinitePoint);
    }
    (0..particles.len())
        .filter(|&i| particles.state[i] != BurnState::Burnt)
        .min_by(|&a, &b| {
            let da = particles.position[a].distance_squared(point);
            let db = particles.position[b].distance_squared(point);
            da.total_cmp(&db)
        })
        .ok_or(ClothError::NothingLeftToIgnite)
}
