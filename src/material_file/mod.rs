//! Materials as data (feature `material_assets`): a [`BurnMaterial`] in a `.burnmat.ron`
//! file, loaded as a [`BurnMaterialAsset`] and given to a cloth by [`BurnMaterialFile`].
//!
//! A cloth spawned with a `BurnMaterialFile` is built once its file has loaded (so its masses
//! come from the file's areal density); when the file changes on disk and Bevy watches for
//! changes (Bevy's `file_watcher` feature, or this crate's `hot_reload`), the cloth takes the
//! new material on its next step, mid-burn. A file that fails to load is logged with the
//! reason; a held cloth is then built with its [`BurnMaterial`] component (or the default),
//! a running one keeps the material it has.
//!
//! ```no_run
//! use bevy::prelude::*;
//! use bevy_burning_cloth::material_file::BurnMaterialFile;
//! use bevy_burning_cloth::prelude::*;
//!
//! fn spawn(mut commands: Commands, assets: Res<AssetServer>) {
//!     commands.spawn((
//!         ClothBuilder::grid(24, 32, 0.05).pin_top_every(4),
//!         BurnMaterialFile(assets.load("materials/silk.burnmat.ron")),
//!         Transform::from_xyz(-0.6, 2.0, 0.0),
//!     ));
//! }
//! ```
//!
//! The five presets ship as files in `assets/materials/`; [`material_to_ron`] writes one (the
//! egui panel's "save" does).

mod format;
mod loader;

pub use format::{MaterialFileError, material_from_ron, material_to_ron};
pub use loader::{BurnMaterialAsset, BurnMaterialLoader, MATERIAL_FILE_EXTENSION};

use crate::plugin::{ClothBuildSystems, HoldBuild};
use crate::sim::{BurnMaterial, ClothBuilder, MeshClothBuilder};
use bevy::asset::{AssetPlugin, LoadState};
use bevy::prelude::*;

/// The material of a cloth, from a file: put it on a cloth entity instead of (or beside) a
/// [`BurnMaterial`]. The cloth waits for the file before it is built ([`HoldBuild`]), and
/// takes the file's material again each time it reloads.
#[derive(Component, Clone, Debug, Default, PartialEq, Deref, Reflect)]
#[reflect(Component, Default, Clone, Debug, PartialEq)]
#[require(HoldBuild)]
pub struct BurnMaterialFile(pub Handle<BurnMaterialAsset>);

/// Loads `.burnmat.ron` material files and applies them to cloths with a [`BurnMaterialFile`].
/// Part of [`BurningClothPlugins`](crate::BurningClothPlugins); needs Bevy's `AssetPlugin`
/// added first (without it, as in a `MinimalPlugins` app, it adds nothing).
pub struct MaterialFilePlugin;

impl Plugin for MaterialFilePlugin {
    fn build(&self, app: &mut App) {
        if !app.is_plugin_added::<AssetPlugin>() {
            debug!("MaterialFilePlugin: no AssetPlugin, so no material files");
            return;
        }
        app.init_asset::<BurnMaterialAsset>()
            .register_asset_loader(BurnMaterialLoader)
            .register_type::<BurnMaterialFile>()
            .add_systems(
                PostUpdate,
                apply_material_files
                    .run_if(any_with_component::<BurnMaterialFile>)
                    .before(ClothBuildSystems),
            );
    }
}

/// Gives each cloth its file's material when the file arrives or changes; releases cloths held
/// for their file (and marks their builder changed, so they are built this frame).
fn apply_material_files(
    mut commands: Commands,
    mut events: MessageReader<AssetEvent<BurnMaterialAsset>>,
    mut arrived: Local<Vec<AssetId<BurnMaterialAsset>>>,
    files: Res<Assets<BurnMaterialAsset>>,
    server: Res<AssetServer>,
    mut cloths: Query<(
        Entity,
        Ref<BurnMaterialFile>,
        Option<Mut<BurnMaterial>>,
        Has<HoldBuild>,
        Option<Mut<ClothBuilder>>,
        Option<Mut<MeshClothBuilder>>,
    )>,
) {
    arrived.clear();
    arrived.extend(events.read().filter_map(|event| match event {
        AssetEvent::Added { id }
        | AssetEvent::Modified { id }
        | AssetEvent::LoadedWithDependencies { id } => Some(*id),
        _ => None,
    }));
    for (entity, file, material, held, grid, mesh) in &mut cloths {
        if !(held || file.is_changed() || arrived.contains(&file.id())) {
            continue;
        }
        if let Some(loaded) = files.get(&file.0) {
            match material {
                Some(mut material) => {
                    material.set_if_neq(loaded.material);
                }
                None => {
                    commands.entity(entity).insert(loaded.material);
                }
            }
        } else if let LoadState::Failed(error) = server.load_state(&file.0) {
            if !held {
                continue;
            }
            error!("cloth {entity}: its material file did not load ({error}); built without it");
        } else {
            // Still loading.
            continue;
        }
        if held {
            commands.entity(entity).remove::<HoldBuild>();
            if let Some(mut builder) = grid {
                builder.set_changed();
            }
            if let Some(mut builder) = mesh {
                builder.set_changed();
            }
        }
    }
}
