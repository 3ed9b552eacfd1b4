//! Setting a cloth alight: raising a particle (and the patch of cloth a flame would touch
//! around it) to an ignition temperature, and finding the particle nearest to a point.

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

/// Radius of the flame an ignition stands for, m: every unburnt particle closer than it to
/// the lit one (where the cloth is now; 0.1 % short of it, so a grid at exactly this spacing
/// lights one particle) is raised with it. A size in metres, the
/// [`REFERENCE_SPACING`](super::material::REFERENCE_SPACING) the heat rates are stated for,
/// so a click lights a patch of cloth of about the same area at any resolution: one particle
/// alone is a smaller spark the finer the grid, and under the physical heat model its heat
/// flows away to its neighbours before it can ignite them (a 1 m cotton panel at 12.5 mm lit
/// at one particle never caught). On a grid at 3 cm or coarser it is the lit particle alone.
pub const IGNITION_RADIUS: f32 = 0.03;

/// Raises particle `index`, and every unburnt particle within [`IGNITION_RADIUS`] of it, to
/// `temperature` (°C) where they are colder: an ignition point. Looks at every particle
/// once (an event, not a per-step pass).
pub fn ignite_patch(
    particles: &mut Particles,
    index: usize,
    temperature: f32,
) -> Result<(), ClothError> {
    heat_particle(particles, index, temperature)?;
    let centre = particles.position[index];
    if !centre.is_finite() {
        return Ok(());
    }
    let reach = (IGNITION_RADIUS * 0.999).powi(2);
    for (j, position) in particles.position.iter().enumerate() {
        if particles.state[j] != BurnState::Burnt && position.distance_squared(centre) < reach {
            let t = &mut particles.temperature[j];
            *t = t.max(temperature);
        }
    }
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::{BurnMaterial, ClothSim, grid::ClothBuilder};
    use glam::Affine3A;

    fn lit_after_ignite(spacing: f32) -> usize {
        let mut sim = ClothSim::new(
            &ClothBuilder::grid(21, 21, spacing),
            BurnMaterial::COTTON,
            Affine3A::IDENTITY,
        )
        .unwrap();
        sim.ignite(10 * 21 + 10).unwrap();
        let seed = sim.material().seed_temperature;
        sim.particles
            .temperature
            .iter()
            .filter(|&&t| t == seed)
            .count()
    }

    #[test]
    fn an_ignition_lights_a_patch_three_centimetres_across_at_any_spacing() {
        // 1 cm grid: the points with i² + j² < 9 (in spacings), the 5 x 5 block around it.
        assert_eq!(lit_after_ignite(0.01), 25);
        // At 3 cm and coarser, the lit particle alone.
        assert_eq!(lit_after_ignite(0.03), 1);
        assert_eq!(lit_after_ignite(0.05), 1);
    }

    #[test]
    fn an_ignition_leaves_burnt_particles_alone() {
        let mut sim = ClothSim::new(
            &ClothBuilder::grid(5, 5, 0.01),
            BurnMaterial::COTTON,
            Affine3A::IDENTITY,
        )
        .unwrap();
        sim.particles.state[13] = BurnState::Burnt;
        let before = sim.particles.temperature[13];
        sim.ignite(12).unwrap();
        assert_eq!(sim.particles.temperature[13], before);
        assert_eq!(
            sim.particles.temperature[11],
            sim.material().seed_temperature
        );
    }
}
