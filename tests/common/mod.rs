//! A cloth's description shared by the reflection test (`ecs.rs`) and the scene test
//! (`scene.rs`): what is spawned, and what must come back.

use bevy::prelude::*;
use bevy_burning_cloth::prelude::*;
use bevy_burning_cloth::sim::SolverSettings;

/// The solver the description carries: not the default, so a copy that lost it shows.
pub fn solver() -> ClothSolver {
    ClothSolver(SolverSettings {
        substep_rate: 480.0,
        ..Default::default()
    })
}

/// Spawns a silk cloth (16 x 16 at 3 cm, pinned at its top corners, [`solver`]) and a torch
/// at its lower middle, as a scene would hold them; returns the two entities.
pub fn spawn_description(world: &mut World) -> [Entity; 2] {
    let cloth = world
        .spawn((
            ClothBuilder::grid(16, 16, 0.03).pin_top_corners(),
            BurnMaterial::SILK,
            solver(),
            Transform::from_xyz(0.0, 2.0, 0.0),
        ))
        .id();
    let torch = world
        .spawn((HeatSource::default(), Transform::from_xyz(0.0, 1.7, 0.0)))
        .id();
    [cloth, torch]
}

/// Steps `app` 2 s and checks that it holds one cloth built from the description, with its
/// solver and material (all but the name, which reflection does not keep), lit by the torch.
pub fn assert_built_and_burning(app: &mut App) {
    for _ in 0..128 {
        app.update();
    }
    let mut cloths = app
        .world_mut()
        .query::<(&ClothStatus, &ClothSolver, &ClothInUse)>();
    let (status, solver_back, in_use) = cloths.single(app.world()).expect("one cloth built");
    assert_eq!(*solver_back, solver());
    let material = *in_use.material();
    assert_eq!(material.name, "custom");
    assert_eq!(
        BurnMaterial {
            name: BurnMaterial::SILK.name,
            ..material
        },
        BurnMaterial::SILK
    );
    assert_eq!(status.particles, 256);
    assert!(
        status.ignited + status.burnt > 0,
        "the torch lit the cloth: {status:?}"
    );
}
