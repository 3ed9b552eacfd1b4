//! The five materials side by side, lit at the same moment (the paper's Figure 9):
//! cloth, silk, denim, paper and cotton, each labelled with its parameters and how much
//! of it has burnt.
//!
//! Controls: `Space` lights them all again at the bottom, `R` resets, left click ignites
//! where you click, right drag orbits, scroll zooms.
//!
//! With the `material_assets` feature (on by default) each swatch loads its material from
//! `assets/materials/<name>.burnmat.ron`. Run it with `hot_reload` and edit one of those files
//! while it runs: the swatch takes the new material as soon as the file is saved (the panel's
//! "save" writes such files too).
//!
//! ```sh
//! cargo run --release --example materials
//! cargo run --release --example materials --features hot_reload
//! ```

#[path = "common/mod.rs"]
mod common;

use bevy::prelude::*;
use bevy_burning_cloth::prelude::*;

const COLUMNS: u32 = 20;
const ROWS: u32 = 30;
const SPACING: f32 = 0.03;
const RAIL_HEIGHT: f32 = 1.7;
const GAP: f32 = 0.78;

fn main() -> AppExit {
    App::new()
        .add_plugins((
            DefaultPlugins.set(common::window("bevy_burning_cloth: materials")),
            BurningClothPlugins::default(),
            common::ExamplePlugin {
                // With the control panel on the right, look a little right of centre so all
                // five swatches stay clear of it.
                camera_target: Vec3::new(if cfg!(feature = "egui") { 0.55 } else { 0.0 }, 1.1, 0.0),
                camera_distance: if cfg!(feature = "egui") { 3.9 } else { 3.5 },
            },
        ))
        .add_systems(Startup, spawn_all)
        .add_systems(Update, (keyboard, update_labels))
        .add_systems(FixedUpdate, ignite_new.before(BurningClothSystems::Prepare))
        .run()
}

/// Which preset a swatch shows, and its label.
#[derive(Component)]
struct Swatch {
    label: Entity,
}

fn x_of(index: usize) -> f32 {
    (index as f32 - 2.0) * GAP
}

fn spawn_all(mut commands: Commands, assets: Res<AssetServer>) {
    for (index, material) in BurnMaterial::PRESETS.into_iter().enumerate() {
        spawn_swatch(&mut commands, &assets, index, material);
    }
}

fn spawn_swatch(
    commands: &mut Commands,
    #[cfg_attr(not(feature = "material_assets"), allow(unused_variables))] assets: &AssetServer,
    index: usize,
    material: BurnMaterial,
) {
    let label = commands
        .spawn((
            Text::new(""),
            TextFont {
                font_size: FontSize::Px(13.0),
                ..default()
            },
            Node {
                position_type: PositionType::Absolute,
                ..default()
            },
        ))
        .id();
    let mut swatch = commands.spawn((
        Swatch { label },
        Name::new(material.name),
        ClothBuilder::grid(COLUMNS, ROWS, SPACING).pin_top_every(4),
        Transform::from_xyz(x_of(index), RAIL_HEIGHT, 0.0),
        material,
    ));
    // The preset's file: the cloth is built once it loads, with the file's material. The
    // preset beside it is the fallback: a file that cannot be found (a binary run from
    // outside the crate, without `BEVY_ASSET_ROOT`) is logged, and the swatch keeps its
    // preset instead of every swatch becoming the default cloth.
    #[cfg(feature = "material_assets")]
    swatch.insert(bevy_burning_cloth::material_file::BurnMaterialFile(
        assets.load(format!("materials/{}.burnmat.ron", material.name)),
    ));
}

fn bottom_centre(cloth: &GlobalTransform) -> Vec3 {
    cloth.translation() + Vec3::new(0.0, -((ROWS - 3) as f32) * SPACING, 0.0)
}

/// Lights every swatch as soon as it is built, all in the same step.
fn ignite_new(
    mut commands: Commands,
    swatches: Query<(Entity, &GlobalTransform), (With<Swatch>, Added<ClothParticles>)>,
) {
    for (entity, transform) in &swatches {
        commands.trigger(Ignite::at_world_point(entity, bottom_centre(transform)));
    }
}

fn keyboard(
    keys: Res<ButtonInput<KeyCode>>,
    mut commands: Commands,
    assets: Res<AssetServer>,
    swatches: Query<(Entity, &Swatch, &GlobalTransform)>,
) {
    if keys.just_pressed(KeyCode::KeyR) {
        for (entity, swatch, _) in &swatches {
            commands.entity(swatch.label).despawn();
            commands.entity(entity).despawn();
        }
        spawn_all(commands.reborrow(), assets);
    } else if keys.just_pressed(KeyCode::Space) {
        for (entity, _, transform) in &swatches {
            commands.trigger(Ignite::at_world_point(entity, bottom_centre(transform)));
        }
    }
}

fn update_labels(
    cameras: Query<(&Camera, &GlobalTransform), With<Camera3d>>,
    swatches: Query<(
        &Swatch,
        &BurnMaterial,
        &GlobalTransform,
        Option<&ClothStatus>,
    )>,
    mut labels: Query<(&mut Text, &mut Node)>,
) {
    let Ok((camera, camera_transform)) = cameras.single() else {
        return;
    };
    for (swatch, material, transform, status) in &swatches {
        let Ok((mut text, mut node)) = labels.get_mut(swatch.label) else {
            continue;
        };
        let anchor =
            transform.translation() + Vec3::new(-0.28, -(ROWS as f32) * SPACING - 0.05, 0.0);
        if let Ok(screen) = camera.world_to_viewport(camera_transform, anchor) {
            node.left = Val::Px(screen.x);
            node.top = Val::Px(screen.y);
        }
        let burnt = status.map_or(0.0, |s| 100.0 * s.burnt_fraction());
        let ignition_f = material.ignition_temperature * 9.0 / 5.0 + 32.0;
        // The default font has no degree or superscript signs.
        text.0 = format!(
            "{}\nignites {:.0} F\n{:.2} kg/m2\nk {:.0} N/m\nspread {:.2}/s\nburnt {burnt:.0} %",
            material.name,
            ignition_f,
            material.areal_density,
            material.structural_stiffness,
            material.heat_spread_rate,
        );
    }
}
