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
    motion_energy(particles, environment)
        + springs.potential_energy(&particles.position, &particles.state, &params.coefficients)
}

/// Kinetic plus gravitational potential energy (relative to the origin) of a cloth's unburnt
/// particles, J: the mechanical energy without the springs' share. While springs only store
/// energy (`½ k (l − l₀)² ≥ 0`) and nothing adds any, it never exceeds the total at the
/// start, whatever the solver; unlike the total it does not charge a constraint solver
/// (XPBD) with `½ k (l − l₀)²` for stretch its unconverged constraints leave, which is not
/// energy its constraint forces hold.
pub fn motion_energy(particles: &Particles, environment: &Environment) -> f32 {
    let gravity: f32 = (0..particles.len())
        .filter(|&i| particles.state[i] != BurnState::Burnt)
        .map(|i| -particles.mass[i] * environment.gravity.dot(particles.position[i]))
        .sum();
    particles.kinetic_energy() + gravity
}
