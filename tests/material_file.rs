//! Materials as files: a cloth waits for its `.burnmat.ron` file and is built from it, a bad
//! or missing file is reported and the cloth built without it, and an edited file reaches the
//! cloth mid-burn (through Bevy's file watcher with the `hot_reload` feature, else through
//! `AssetServer::reload`, the call the watcher makes).
#![cfg(feature = "material_assets")]

use bevy::asset::AssetPlugin;
use bevy::prelude::*;
use bevy::time::TimeUpdateStrategy;
use bevy_burning_cloth::material_file::{BurnMaterialAsset, BurnMaterialFile, material_to_ron};
use bevy_burning_cloth::prelude::*;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// A fresh asset folder for one test.
fn asset_folder(test: &str) -> PathBuf {
    let folder =
        std::env::temp_dir().join(format!("bevy_burning_cloth_{test}_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&folder);
    std::fs::create_dir_all(&folder).unwrap();
    folder
}

fn app(folder: &Path) -> App {
    let mut app = App::new();
    app.add_plugins((
        MinimalPlugins,
        AssetPlugin {
            file_path: folder.to_string_lossy().into_owned(),
            watch_for_changes_override: Some(cfg!(feature = "hot_reload")),
            ..default()
        },
        BurningClothPlugins::default(),
    ))
    .insert_resource(TimeUpdateStrategy::ManualDuration(Duration::from_micros(
        15_625,
    )));
    app
}

/// Spawns a 9 x 9 cloth at 10 cm (0.64 m²) using the material file `file`.
fn spawn_cloth(app: &mut App, file: &str) -> Entity {
    let handle = app.world().resource::<AssetServer>().load(file.to_owned());
    app.world_mut()
        .spawn((
            ClothBuilder::grid(9, 9, 0.1).pin_top_corners(),
            BurnMaterialFile(handle),
            Transform::from_xyz(0.0, 2.0, 0.0),
        ))
        .id()
}

/// Updates `app` (sleeping a little between frames, so file loads and watchers get time) until
/// `done` holds; panics after `seconds`.
fn update_until(app: &mut App, seconds: f32, what: &str, done: impl Fn(&mut World) -> bool) {
    let start = Instant::now();
    while !done(app.world_mut()) {
        assert!(
            start.elapsed().as_secs_f32() < seconds,
            "{what}: not after {seconds} s"
        );
        app.update();
        std::thread::sleep(Duration::from_millis(5));
    }
}

fn material_in_use(world: &mut World, cloth: Entity) -> Option<BurnMaterial> {
    world
        .get::<ClothInUse>(cloth)
        .map(|in_use| *in_use.material())
}

/// A heavy, stiff variant of cotton the presets do not have.
fn heavy() -> BurnMaterial {
    BurnMaterial {
        areal_density: 0.35,
        structural_stiffness: 55.0,
        ..BurnMaterial::COTTON
    }
}

/// Checks the cloth's masses are [`heavy`]'s areal density times its area (0.8 m x 0.8 m):
/// built from the file, not built from the default and changed after.
fn assert_built_from_heavy(app: &App, cloth: Entity) {
    let particles = app.world().get::<ClothParticles>(cloth).expect("built");
    let total: f32 = particles.mass.iter().sum();
    assert!((total - 0.35 * 0.64).abs() < 1e-4, "total mass {total} kg");
}

#[test]
fn a_cloth_waits_for_its_material_file_and_is_built_from_it() {
    let folder = asset_folder("waits");
    std::fs::write(
        folder.join("heavy.burnmat.ron"),
        material_to_ron(&heavy()).unwrap(),
    )
    .unwrap();
    let mut app = app(&folder);
    let cloth = spawn_cloth(&mut app, "heavy.burnmat.ron");
    update_until(&mut app, 10.0, "cloth built", |world| {
        world.get::<ClothParticles>(cloth).is_some()
    });
    let material = material_in_use(app.world_mut(), cloth).unwrap();
    assert_eq!(material.name, "heavy");
    assert_eq!(
        BurnMaterial {
            name: "cotton",
            ..material
        },
        heavy()
    );
    assert_built_from_heavy(&app, cloth);
}

#[test]
fn a_cloth_is_not_built_before_its_material_arrives() {
    let folder = asset_folder("held");
    let mut app = app(&folder);
    // A handle whose asset does not exist yet: the cloth must wait however long it takes.
    let handle = app
        .world()
        .resource::<Assets<BurnMaterialAsset>>()
        .reserve_handle();
    let cloth = app
        .world_mut()
        .spawn((
            ClothBuilder::grid(9, 9, 0.1).pin_top_corners(),
            BurnMaterialFile(handle.clone()),
            Transform::from_xyz(0.0, 2.0, 0.0),
        ))
        .id();
    for _ in 0..20 {
        app.update();
    }
    assert!(app.world().get::<ClothParticles>(cloth).is_none());
    app.world_mut()
        .resource_mut::<Assets<BurnMaterialAsset>>()
        .insert(&handle, BurnMaterialAsset { material: heavy() })
        .unwrap();
    app.update();
    assert_built_from_heavy(&app, cloth);
}

#[test]
fn a_missing_or_bad_file_is_reported_and_the_cloth_built_without_it() {
    let folder = asset_folder("bad");
    let mut nan = material_to_ron(&BurnMaterial::SILK).unwrap();
    nan = nan.replace("areal_density: 0.06", "areal_density: NaN");
    std::fs::write(folder.join("nan.burnmat.ron"), nan).unwrap();
    std::fs::write(folder.join("garbled.burnmat.ron"), "BurnMaterial(areal").unwrap();
    let mut app = app(&folder);
    let cloths = [
        spawn_cloth(&mut app, "missing.burnmat.ron"),
        spawn_cloth(&mut app, "nan.burnmat.ron"),
        spawn_cloth(&mut app, "garbled.burnmat.ron"),
    ];
    update_until(&mut app, 10.0, "every cloth built", |world| {
        cloths
            .iter()
            .all(|&c| world.get::<ClothParticles>(c).is_some())
    });
    for cloth in cloths {
        assert_eq!(
            material_in_use(app.world_mut(), cloth),
            Some(BurnMaterial::default())
        );
    }
}

#[test]
fn an_edited_file_reaches_the_burning_cloth_and_a_broken_edit_is_ignored() {
    let folder = asset_folder("reload");
    let file = folder.join("tuned.burnmat.ron");
    std::fs::write(&file, material_to_ron(&BurnMaterial::COTTON).unwrap()).unwrap();
    let mut app = app(&folder);
    let cloth = spawn_cloth(&mut app, "tuned.burnmat.ron");
    update_until(&mut app, 10.0, "cloth built", |world| {
        world.get::<ClothParticles>(cloth).is_some()
    });
    app.world_mut().trigger(Ignite::particle(cloth, 4));
    app.update();

    let reload = |app: &mut App| {
        if !cfg!(feature = "hot_reload") {
            app.world()
                .resource::<AssetServer>()
                .reload("tuned.burnmat.ron");
        }
    };
    // Let the watcher settle on the first write before editing.
    std::thread::sleep(Duration::from_millis(400));
    let tuned = BurnMaterial {
        self_heating_rate: 900.0,
        ..BurnMaterial::COTTON
    };
    std::fs::write(&file, material_to_ron(&tuned).unwrap()).unwrap();
    reload(&mut app);
    update_until(&mut app, 15.0, "edited material in use", |world| {
        material_in_use(world, cloth).map(|m| m.self_heating_rate) == Some(900.0)
    });
    assert!(
        app.world().get::<ClothStatus>(cloth).unwrap().burning,
        "still burning"
    );

    // A broken edit fails to load; the cloth keeps the material it has.
    std::fs::write(&file, "BurnMaterial(self_heating_rate: -1.0").unwrap();
    reload(&mut app);
    let start = Instant::now();
    while start.elapsed() < Duration::from_millis(1500) {
        app.update();
        std::thread::sleep(Duration::from_millis(5));
    }
    assert_eq!(
        material_in_use(app.world_mut(), cloth).map(|m| m.self_heating_rate),
        Some(900.0)
    );
}
