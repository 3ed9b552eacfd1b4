//! The mechanical energy of a cloth, for stability studies and the control panel.

use super::derived::force_params;
use super::material::BurnMaterial;
use super::particles::{BurnState, Particles};
use super::settings::Environment;
use super::springs::Springs;
use super::topology::Topology;

/// Total mechanical energy of a cloth's unburnt particles, J: kinetic, spring potential
/// (`½ k (l − l₀)²` over live springs) and gravitational potential relative to the origin.
pub fn cloth_energy(
    particles: &Particles,
    springs: &Springs,
    material: &BurnMaterial,
    topology: &Topology,
    environment: &Environment,
) -> f32 {
    let params = force_params(material, topology, environment);
    let gravity: f32 = (0..particles.len())
        .filter(|&i| particles.state[i] != BurnState::Burnt)
        .map(|i| -particles.mass[i] * environment.gravity.dot(particles.position[i]))
        .sum();
    particles.kinetic_energy()
        + springs.potential_energy(&particles.position, &particles.state, &params.coefficients)
        + gravity
}
