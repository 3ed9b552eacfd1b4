//! A cloth's description saved as a Bevy world (scene) in RON and loaded into a fresh app
//! builds and burns the same cloth. Needs Bevy's world serialization, which the `gltf`
//! feature brings in.
#![cfg(feature = "gltf")]

use bevy::asset::{AssetPath, LoadFromPath, UntypedHandle};
use bevy::ecs::entity::EntityHashMap;
use bevy::prelude::*;
use bevy::time::TimeUpdateStrategy;
use bevy::world_serialization::DynamicWorldBuilder;
use bevy::world_serialization::serde::WorldDeserializer;
use bevy_burning_cloth::prelude::*;
use serde::de::DeserializeSeed;
use std::any::TypeId;
use std::time::Duration;

mod common;

fn app() -> App {
    let mut app = App::new();
    app.add_plugins((MinimalPlugins, BurningClothPlugins::default()))
        .insert_resource(TimeUpdateStrategy::ManualDuration(Duration::from_micros(
            15_625,
        )))
        .register_type::<Transform>();
    app
}

/// The description holds no asset handles; any asked for is a test failure.
struct NoAssets;

impl LoadFromPath for NoAssets {
    fn load_from_path_erased(&mut self, _: TypeId, path: AssetPath<'static>) -> UntypedHandle {
        panic!("the cloth description asked for an asset: {path}")
    }
}

#[test]
fn a_cloth_saved_as_ron_loads_into_a_fresh_app_and_burns() {
    let mut source = app();
    let [cloth, torch] = common::spawn_description(source.world_mut());
    let registry = source.world().resource::<AppTypeRegistry>().clone();
    let ron = {
        let registry = registry.read();
        DynamicWorldBuilder::from_world(source.world(), &registry)
            .extract_entities([cloth, torch].into_iter())
            .build()
            .serialize(&registry)
            .expect("serialises")
    };
    assert!(
        ron.contains("ClothBuilder") && ron.contains("HeatSource"),
        "{ron}"
    );

    let mut target = app();
    let registry = target.world().resource::<AppTypeRegistry>().clone();
    let world = {
        let registry = registry.read();
        let mut deserializer = ron::de::Deserializer::from_str(&ron).expect("RON");
        WorldDeserializer {
            type_registry: &registry,
            load_from_path: &mut NoAssets,
        }
        .deserialize(&mut deserializer)
        .expect("deserialises")
    };
    world
        .write_to_world(target.world_mut(), &mut EntityHashMap::default())
        .expect("spawns");
    common::assert_built_and_burning(&mut target);
}
