//! Determinism: the same scene, ignition and step count give bit-identical state.

use bevy::math::{Affine3A, Vec3};
use bevy::prelude::*;
use bevy::time::TimeUpdateStrategy;
use bevy_burning_cloth::prelude::*;
use bevy_burning_cloth::sim::{ClothSim, Particles};
use std::hash::{Hash, Hasher};
use std::time::Duration;

/// Hashes every particle's position, velocity, temperature and burn state, bit for bit.
fn state_hash(particles: &Particles) -> u64 {
    let mut hasher = std::collections::hash_map::DefaultHasher::new();
    for i in 0..particles.len() {
        for v in [particles.position[i], particles.velocity[i]] {
            v.to_array().map(f32::to_bits).hash(&mut hasher);
        }
        particles.temperature[i].to_bits().hash(&mut hasher);
        particles.state[i].hash(&mut hasher);
    }
    hasher.finish()
}

fn simulate() -> u64 {
    let mut sim = ClothSim::new(
        &ClothBuilder::grid(20, 20, 0.03).pin_top_corners(),
        BurnMaterial::PAPER,
        Affine3A::from_translation(Vec3::new(0.0, 1.5, 0.0)),
    )
    .unwrap();
    sim.ignite(385).unwrap();
    sim.ignite_nearest(Vec3::new(-0.2, 1.2, 0.0)).unwrap();
    for _ in 0..500 {
        sim.step(1.0 / 64.0);
    }
    assert!(sim.particles.count(BurnState::Burnt) > 0, "the scene burns");
    state_hash(&sim.particles)
}

#[test]
fn the_simulation_is_bit_for_bit_repeatable() {
    assert_eq!(simulate(), simulate());
}

fn simulate_in_app() -> u64 {
    let mut app = App::new();
    app.add_plugins((MinimalPlugins, BurningClothPlugins::default()))
        .insert_resource(TimeUpdateStrategy::ManualDuration(Duration::from_micros(
            15_625,
        )));
    let cloths: Vec<Entity> = (0..3)
        .map(|n| {
            app.world_mut()
                .spawn((
                    ClothBuilder::grid(16, 16, 0.03).pin_top_corners(),
                    BurnMaterial::PRESETS[n],
                    Transform::from_xyz(n as f32 * 0.2, 1.5, 0.0),
                ))
                .id()
        })
        .collect();
    for &cloth in &cloths {
        app.world_mut().trigger(Ignite::particle(cloth, 200));
    }
    for _ in 0..500 {
        app.update();
    }
    let mut hasher = std::collections::hash_map::DefaultHasher::new();
    for &cloth in &cloths {
        state_hash(app.world().get::<ClothParticles>(cloth).unwrap()).hash(&mut hasher);
    }
    hasher.finish()
}

#[test]
fn the_plugin_is_bit_for_bit_repeatable_with_several_cloths() {
    assert_eq!(simulate_in_app(), simulate_in_app());
}
