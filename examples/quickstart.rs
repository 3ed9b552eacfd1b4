//! The README's first program, as written there: a camera, a light, a silk cloth hanging
//! from its top corners, lit near its bottom. `tests/readme.rs` checks the two stay the same.
//!
//! ```sh
//! cargo run --example quickstart
//! ```

use bevy::prelude::*;
use bevy_burning_cloth::prelude::*;

fn main() {
    App::new()
        .add_plugins((DefaultPlugins, BurningClothPlugins::default()))
        .add_systems(Startup, spawn)
        .add_observer(|burnt: On<ClothBurntOut>| info!("{} is gone", burnt.entity))
        .run();
}

fn spawn(mut commands: Commands) {
    // A camera facing the cloth, and a light.
    commands.spawn((
        Camera3d::default(),
        Transform::from_xyz(0.0, 1.3, 2.6).looking_at(Vec3::new(0.0, 1.3, 0.0), Vec3::Y),
    ));
    commands.spawn((
        DirectionalLight::default(),
        Transform::from_xyz(1.0, 3.0, 4.0).looking_at(Vec3::new(0.0, 1.3, 0.0), Vec3::Y),
    ));
    // A silk cloth 1.4 m square hanging from its top corners: the middle of its top edge
    // at the Transform, its columns along +X, its rows running down.
    let cloth = commands
        .spawn((
            ClothBuilder::grid(48, 48, 0.03).pin_top_corners(),
            BurnMaterial::SILK,
            Transform::from_xyz(0.0, 2.0, 0.0),
        ))
        .id();
    // From gameplay, any time (also before the cloth is built): light it near the bottom.
    commands.trigger(Ignite::at_world_point(cloth, Vec3::new(0.2, 0.7, 0.0)));
}
