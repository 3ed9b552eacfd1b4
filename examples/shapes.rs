//! Several cloth shapes, each lit at several points at once (the paper's Figure 8): a square
//! of silk, a long cotton banner, paper with a round hole and a triangle cut out, and denim
//! draped over an invisible rod.
//!
//! Controls: left click ignites, `R` resets, right drag orbits, scroll zooms.
//!
//! ```sh
//! cargo run --release --example shapes
//! ```

#[path = "common/mod.rs"]
mod common;

use bevy::prelude::*;
use bevy_burning_cloth::prelude::*;

const SPACING: f32 = 0.03;

fn main() -> AppExit {
    App::new()
        .add_plugins((
            DefaultPlugins.set(common::window("bevy_burning_cloth: shapes")),
            BurningClothPlugins::default(),
            common::ExamplePlugin {
                // With the control panel on the right, the scene sits in the window's left
                // part (as in `materials`): the denim on the right is not hidden behind it.
                camera_target: Vec3::new(if cfg!(feature = "egui") { 0.6 } else { 0.0 }, 1.05, 0.0),
                camera_distance: if cfg!(feature = "egui") { 4.0 } else { 3.6 },
            },
        ))
        .add_systems(Startup, (spawn_rod, spawn_shapes))
        .add_systems(Update, keyboard)
        .add_systems(FixedUpdate, ignite_new.before(BurningClothSystems::Prepare))
        .run()
}

/// A cloth of this scene and where (in its own frame) it is lit.
#[derive(Component)]
struct Shape {
    ignition_points: Vec<Vec3>,
}

fn spawn_rod(mut commands: Commands) {
    // Invisible: only the denim shows it is there.
    commands.spawn((
        ClothCollider::capsule(1.0, 0.025).with_friction(0.999),
        Transform::from_xyz(1.25, 1.05, 0.0)
            .with_rotation(Quat::from_rotation_x(std::f32::consts::FRAC_PI_2)),
    ));
}

fn spawn_shapes(mut commands: Commands) {
    let s = SPACING;
    // A square of silk pinned at its corners, lit at two bottom points.
    commands.spawn((
        Shape {
            ignition_points: vec![Vec3::new(-0.2, -0.6, 0.0), Vec3::new(0.25, -0.55, 0.0)],
        },
        ClothBuilder::grid(22, 22, s).pin_top_corners(),
        BurnMaterial::SILK,
        Transform::from_xyz(-1.35, 1.8, 0.0),
    ));
    // A long, narrow cotton banner, lit at its foot and halfway up.
    commands.spawn((
        Shape {
            ignition_points: vec![Vec3::new(0.0, -1.45, 0.0), Vec3::new(0.1, -0.7, 0.0)],
        },
        ClothBuilder::grid(9, 52, s).pin_top_edge(),
        BurnMaterial::COTTON,
        Transform::from_xyz(-0.6, 1.85, 0.0),
    ));
    // Paper with a round hole and a triangle cut out, lit on three sides.
    commands.spawn((
        Shape {
            ignition_points: vec![
                Vec3::new(-0.3, -0.75, 0.0),
                Vec3::new(0.3, -0.7, 0.0),
                Vec3::new(0.0, -0.05 - 0.35, 0.0),
            ],
        },
        ClothBuilder::grid(22, 28, s)
            .pin_top_every(3)
            .cut_out(Cutout::Disc {
                centre: Vec2::new(0.32, 0.3),
                radius: 0.12,
            })
            .cut_out(Cutout::Triangle([
                Vec2::new(0.1, 0.8),
                Vec2::new(0.5, 0.8),
                Vec2::new(0.3, 0.55),
            ])),
        BurnMaterial::PAPER,
        Transform::from_xyz(0.3, 1.8, 0.0),
    ));
    // Denim dropped flat onto the rod, where it drapes; lit at two hanging corners.
    commands.spawn((
        Shape {
            ignition_points: vec![Vec3::new(-0.3, -0.6, 0.3), Vec3::new(0.3, -0.6, -0.3)],
        },
        ClothBuilder::grid(22, 22, s).in_plane(GridPlane::Horizontal),
        BurnMaterial::DENIM,
        Transform::from_xyz(1.25, 1.15, 0.0),
    ));
}

/// Lights each shape at its points two seconds after it is built (the denim has draped by
/// then): nearest particles to the points, in the shape's frame.
fn ignite_new(
    time: Res<Time>,
    mut commands: Commands,
    mut pending: Local<Vec<(Entity, f32)>>,
    built: Query<Entity, (With<Shape>, Added<ClothParticles>)>,
    shapes: Query<(&Shape, &GlobalTransform)>,
) {
    let now = time.elapsed_secs();
    pending.extend(built.iter().map(|e| (e, now + 2.0)));
    pending.retain(|&(entity, when)| {
        if now < when {
            return true;
        }
        if let Ok((shape, transform)) = shapes.get(entity) {
            for &point in &shape.ignition_points {
                let world = transform.translation() + point;
                commands.trigger(Ignite::at_world_point(entity, world));
            }
        }
        false
    });
}

fn keyboard(
    keys: Res<ButtonInput<KeyCode>>,
    mut commands: Commands,
    shapes: Query<Entity, With<Shape>>,
) {
    if keys.just_pressed(KeyCode::KeyR) {
        for entity in &shapes {
            commands.entity(entity).despawn();
        }
        spawn_shapes(commands.reborrow());
    }
}
