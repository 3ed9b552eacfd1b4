//! Determinism: the same scene, ignition and step count give bit-identical state.

use bevy::math::{Affine3A, Vec3};
use bevy::prelude::*;
use bevy::time::TimeUpdateStrategy;
use bevy_burning_cloth::prelude::*;
use bevy_burning_cloth::sim::{
    ClothSim, ColliderShape, Particles, Springs, WorldCollider, WorldHeatSource,
};
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

/// Hashes every spring's rest length and ends, bit for bit.
fn springs_hash(springs: &Springs) -> u64 {
    let mut hasher = std::collections::hash_map::DefaultHasher::new();
    for s in 0..springs.len() {
        (springs.a[s], springs.b[s], springs.rest_length[s].to_bits()).hash(&mut hasher);
    }
    hasher.finish()
}

/// The scene of the `ClothSim`-against-`App` test: a paper cloth over a floor, lit at one
/// point, with a torch held under another corner.
const SCENE_STEPS: u64 = 500;
const FLOOR_Y: f32 = 0.9;
const TORCH: Vec3 = Vec3::new(0.25, 1.3, 0.02);
fn scene_cloth() -> ClothBuilder {
    ClothBuilder::grid(20, 20, 0.03).pin_top_every(5)
}
fn scene_transform() -> Transform {
    Transform::from_xyz(0.0, 1.5, 0.0)
}
const IGNITE_AT: usize = 385;

fn scene_in_clothsim() -> (u64, u64) {
    let mut sim = ClothSim::new(
        &scene_cloth(),
        BurnMaterial::PAPER,
        scene_transform().compute_affine(),
    )
    .unwrap();
    sim.colliders.push(WorldCollider {
        shape: ColliderShape::Plane,
        transform: Affine3A::from_translation(Vec3::new(0.0, FLOOR_Y, 0.0)),
        friction: ClothCollider::plane().friction,
    });
    let torch = HeatSource::default();
    sim.heat_sources.push(WorldHeatSource {
        centre: TORCH,
        radius: torch.radius,
        temperature: torch.temperature,
        rate: torch.rate,
        falloff: torch.falloff,
        owner: WorldHeatSource::NO_OWNER,
    });
    sim.ignite(IGNITE_AT).unwrap();
    for _ in 0..SCENE_STEPS {
        sim.step(1.0 / 64.0);
    }
    assert!(sim.particles.count(BurnState::Burnt) > 0, "the scene burns");
    (state_hash(&sim.particles), springs_hash(&sim.springs))
}

fn scene_in_app() -> (u64, u64) {
    let mut app = App::new();
    // The plume is an input a lone `ClothSim` does not have: compare without it.
    let plugins = BurningClothPlugins::default().build();
    #[cfg(feature = "fluid")]
    let plugins = plugins.disable::<bevy_burning_cloth::fluid::FluidPlugin>();
    app.add_plugins((MinimalPlugins, plugins))
        .insert_resource(TimeUpdateStrategy::ManualDuration(Duration::from_micros(
            15_625,
        )));
    app.world_mut().spawn((
        ClothCollider::plane(),
        Transform::from_xyz(0.0, FLOOR_Y, 0.0),
    ));
    app.world_mut()
        .spawn((HeatSource::default(), Transform::from_translation(TORCH)));
    let cloth = app
        .world_mut()
        .spawn((scene_cloth(), BurnMaterial::PAPER, scene_transform()))
        .id();
    app.world_mut().trigger(Ignite::particle(cloth, IGNITE_AT));
    while app.world().resource::<ClothStepTiming>().steps < SCENE_STEPS {
        app.update();
    }
    let world = app.world();
    (
        state_hash(world.get::<ClothParticles>(cloth).unwrap()),
        springs_hash(world.get::<ClothSprings>(cloth).unwrap()),
    )
}

/// The step is defined once: a cloth stepped by `ClothSim` and the same cloth stepped by the
/// plugin in an `App` (with a collider entity and a heat source entity) end bit-identical.
#[test]
fn clothsim_and_the_plugin_step_a_cloth_identically() {
    assert_eq!(scene_in_clothsim(), scene_in_app());
}

/// A cloth big enough to be split across threads (96 x 96), burning, with tethers and a
/// collider, stepped with the default XPBD solver on no pool, a 1-thread pool and a 4-thread
/// pool: the state is bit-identical. (Without the `parallel` feature every pool runs on the
/// calling thread and this holds trivially.)
#[test]
fn the_result_does_not_depend_on_the_number_of_threads() {
    use bevy::tasks::TaskPoolBuilder;
    use bevy_burning_cloth::sim::Integrator;
    let run = |threads: Option<usize>| {
        let pool = threads.map(|n| TaskPoolBuilder::new().num_threads(n).build());
        let mut sim = ClothSim::new(
            &ClothBuilder::grid(96, 96, 0.015).pin_top_every(6),
            BurnMaterial::PAPER,
            Affine3A::from_translation(Vec3::new(0.0, 1.6, 0.0)),
        )
        .unwrap();
        sim.update_settings(|s| s.solver.integrator = Integrator::Xpbd)
            .unwrap();
        sim.colliders.push(WorldCollider {
            shape: ColliderShape::Plane,
            transform: Affine3A::from_translation(Vec3::new(0.0, 0.3, 0.0)),
            friction: 0.5,
        });
        sim.ignite_nearest(Vec3::new(0.2, 0.4, 0.0)).unwrap();
        for _ in 0..150 {
            sim.step_on(1.0 / 60.0, pool.as_ref());
        }
        assert!(sim.particles.count(BurnState::Burnt) > 0, "the scene burns");
        (state_hash(&sim.particles), springs_hash(&sim.springs))
    };
    let alone = run(None);
    assert_eq!(run(Some(1)), alone, "one pool thread");
    assert_eq!(run(Some(4)), alone, "four pool threads");
}
