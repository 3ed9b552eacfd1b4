//! A curtain hanging from a rail at several rings. Click it to set it alight; it burns,
//! crumples, and falls as its rings burn through.
//!
//! Controls: left click ignites, right drag orbits, scroll zooms, `R` resets, `Space`
//! ignites the bottom corner.
//!
//! ```sh
//! cargo run --release --example curtain
//! ```

#[path = "common/mod.rs"]
mod common;

use bevy::prelude::*;
use bevy_burning_cloth::prelude::*;

const COLUMNS: u32 = 40;
const ROWS: u32 = 48;
const SPACING: f32 = 0.035;
const RAIL_HEIGHT: f32 = 2.2;

fn main() -> AppExit {
    let check = common::CheckRun::from_env();
    App::new()
        .add_plugins((
            DefaultPlugins.set(common::window("bevy_burning_cloth: curtain")),
            BurningClothPlugins::default(),
            common::ExamplePlugin {
                camera_target: Vec3::new(0.0, 1.35, 0.0),
                camera_distance: 3.4,
            },
        ))
        .add_systems(Startup, (spawn_rail, spawn_curtain, spawn_help))
        .add_systems(Update, keyboard)
        .add_systems(
            FixedUpdate,
            ignite_for_check
                .run_if(move || check.is_some())
                .before(BurningClothSystems::Prepare),
        )
        .run()
}

#[derive(Component)]
struct Curtain;

fn curtain() -> impl Bundle {
    (
        Curtain,
        Name::new("curtain"),
        ClothBuilder::grid(COLUMNS, ROWS, SPACING).pin_top_every(5),
        BurnMaterial::COTTON,
        Transform::from_xyz(0.0, RAIL_HEIGHT, 0.0),
    )
}

fn spawn_curtain(mut commands: Commands) {
    commands.spawn(curtain());
}

fn spawn_rail(
    mut commands: Commands,
    mut meshes: ResMut<Assets<Mesh>>,
    mut materials: ResMut<Assets<StandardMaterial>>,
) {
    let width = (COLUMNS - 1) as f32 * SPACING + 0.3;
    commands.spawn((
        Mesh3d(meshes.add(Cylinder::new(0.015, width))),
        MeshMaterial3d(materials.add(StandardMaterial {
            base_color: Color::srgb(0.35, 0.33, 0.3),
            metallic: 0.8,
            ..default()
        })),
        Transform::from_xyz(0.0, RAIL_HEIGHT + 0.01, 0.0)
            .with_rotation(Quat::from_rotation_z(std::f32::consts::FRAC_PI_2)),
    ));
}

fn spawn_help(mut commands: Commands) {
    commands.spawn(common::help_line(
        "left click: ignite   right drag: orbit   scroll: zoom   space: ignite corner   R: reset",
    ));
}

fn bottom_corner() -> Vec3 {
    Vec3::new(
        0.4 * (COLUMNS - 1) as f32 * SPACING,
        RAIL_HEIGHT - (ROWS - 3) as f32 * SPACING,
        0.0,
    )
}

fn keyboard(
    keys: Res<ButtonInput<KeyCode>>,
    mut commands: Commands,
    curtains: Query<Entity, With<Curtain>>,
) {
    if keys.just_pressed(KeyCode::KeyR) {
        for entity in &curtains {
            commands.entity(entity).despawn();
        }
        commands.spawn(curtain());
    }
    if keys.just_pressed(KeyCode::Space) {
        for entity in &curtains {
            commands.trigger(Ignite::at_world_point(entity, bottom_corner()));
        }
    }
}

/// In check mode, light the curtain at two points once it is built, so the screenshot
/// shows it mid-burn.
fn ignite_for_check(
    mut commands: Commands,
    curtains: Query<Entity, (With<Curtain>, Added<ClothParticles>)>,
) {
    for entity in &curtains {
        commands.trigger(Ignite::at_world_point(entity, bottom_corner()));
        commands.trigger(Ignite::at_world_point(
            entity,
            Vec3::new(-0.3, RAIL_HEIGHT - 1.2, 0.0),
        ));
    }
}
