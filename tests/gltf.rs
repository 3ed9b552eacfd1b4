//! A real glTF file through Bevy's glTF loader: `Flammable` on the scene root turns the
//! banner the scene spawns into a cloth that hangs from its top edge and burns.
#![cfg(feature = "gltf")]

use bevy::gltf::GltfPlugin;
use bevy::image::{CompressedImageFormatSupport, CompressedImageFormats};
use bevy::mesh::MeshPlugin;
use bevy::prelude::*;
use bevy::time::TimeUpdateStrategy;
use bevy::world_serialization::WorldSerializationPlugin;
use bevy_burning_cloth::prelude::*;
use std::time::Duration;

/// Vertices of `assets/models/banner.gltf`: 13 columns, 21 rows, no duplicates.
const BANNER_VERTICES: usize = 13 * 21;

fn app() -> App {
    let mut app = App::new();
    app.add_plugins((
        MinimalPlugins,
        AssetPlugin {
            file_path: concat!(env!("CARGO_MANIFEST_DIR"), "/assets").to_owned(),
            ..default()
        },
        TransformPlugin,
        MeshPlugin,
        WorldSerializationPlugin,
    ))
    // No renderer: no compressed texture formats to offer the loader.
    .insert_resource(CompressedImageFormatSupport(CompressedImageFormats::NONE))
    .add_plugins((GltfPlugin::default(), BurningClothPlugins::default()))
    .insert_resource(TimeUpdateStrategy::ManualDuration(Duration::from_micros(
        15_625,
    )));
    // `GltfPlugin` registers its loader in `finish`, which `App::run` would call.
    app.finish();
    app.cleanup();
    app
}

#[test]
fn a_gltf_banner_under_a_flammable_scene_root_becomes_a_cloth_and_burns() {
    let mut app = app();
    let scene = app
        .world()
        .resource::<AssetServer>()
        .load(GltfAssetLabel::Scene(0).from_asset("models/banner.gltf"));
    let root = app
        .world_mut()
        .spawn((
            WorldAssetRoot(scene),
            Flammable::pinned_top(0.01),
            BurnMaterial::COTTON,
            Transform::from_xyz(0.5, 1.6, 0.0),
        ))
        .id();
    // Loading runs on the task pool: wait (in real time) for the scene to spawn and its mesh
    // to become a cloth.
    let mut cloth = None;
    for _ in 0..2_000 {
        app.update();
        let mut cloths = app
            .world_mut()
            .query_filtered::<Entity, With<ClothParticles>>();
        cloth = cloths.iter(app.world()).next();
        if cloth.is_some() {
            break;
        }
        std::thread::sleep(Duration::from_millis(2));
    }
    let cloth = cloth.expect("the glTF banner never became a cloth");
    // It is the mesh entity the scene spawned under the root, with the root's material.
    let mut ancestors = app.world_mut().query::<&ChildOf>();
    let mut parent = cloth;
    while let Ok(child_of) = ancestors.get(app.world(), parent) {
        parent = child_of.parent();
    }
    assert_eq!(parent, root, "the cloth is in the scene under the root");
    assert_eq!(
        *app.world().get::<BurnMaterial>(cloth).unwrap(),
        BurnMaterial::COTTON
    );
    let particles = app.world().get::<ClothParticles>(cloth).unwrap();
    assert_eq!(particles.len(), BANNER_VERTICES);
    let pins: Vec<Vec3> = (0..particles.len())
        .filter(|&i| particles.is_pinned(i))
        .map(|i| particles.position[i])
        .collect();
    // The file's top edge is at local y = 0.4, 13 vertices across 0.5 m.
    assert_eq!(pins.len(), 13, "the banner's top edge is pinned");
    for p in &pins {
        assert!((p.y - 2.0).abs() < 1e-4, "pin at {p}");
        assert!((p.x - 0.5).abs() <= 0.25 + 1e-4, "pin at {p}");
    }
    // The swallowtail's points hang lowest: 0.8 m below the pins.
    let lowest = particles
        .position
        .iter()
        .fold(f32::MAX, |low, p| low.min(p.y));
    assert!((lowest - 1.2).abs() < 1e-3, "lowest point at {lowest}");

    // It burns like any cloth.
    app.world_mut()
        .trigger(Ignite::at_world_point(cloth, Vec3::new(0.5, 1.3, 0.0)));
    for _ in 0..64 * 6 {
        app.update();
    }
    let status = *app.world().get::<ClothStatus>(cloth).unwrap();
    assert!(status.burnt > 20, "only {} particles burnt", status.burnt);
    assert!(
        app.world()
            .get::<ClothParticles>(cloth)
            .unwrap()
            .is_finite()
    );
}
