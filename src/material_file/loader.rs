//! [`BurnMaterialAsset`] and its [`AssetLoader`]: `.burnmat.ron` files.

use super::format::{MaterialFileError, material_from_ron};
use crate::sim::BurnMaterial;
use bevy::asset::io::Reader;
use bevy::asset::{Asset, AssetLoader, LoadContext};
use bevy::prelude::*;
use std::sync::Mutex;

/// A [`BurnMaterial`] loaded from a `.burnmat.ron` file (see [`super::material_to_ron`] for
/// the format). Its name is the file's, without `.burnmat.ron`.
#[derive(Asset, TypePath, Clone, Copy, Debug, PartialEq, Deref)]
pub struct BurnMaterialAsset {
    /// The material, checked by [`BurnMaterial::validate`] when it was loaded.
    pub material: BurnMaterial,
}

/// Loads `.burnmat.ron` files as [`BurnMaterialAsset`]s. A file that is not a material, or
/// whose material does not validate, fails to load with the reason (Bevy logs it; on a hot
/// reload the previous material stays).
#[derive(Clone, Copy, Debug, Default, TypePath)]
pub struct BurnMaterialLoader;

/// The extension of a material file, without its leading dot.
pub const MATERIAL_FILE_EXTENSION: &str = "burnmat.ron";

impl AssetLoader for BurnMaterialLoader {
    type Asset = BurnMaterialAsset;
    type Settings = ();
    type Error = MaterialFileError;

    async fn load(
        &self,
        reader: &mut dyn Reader,
        _settings: &(),
        load_context: &mut LoadContext<'_>,
    ) -> Result<Self::Asset, Self::Error> {
        let mut bytes = Vec::new();
        reader
            .read_to_end(&mut bytes)
            .await
            .map_err(|error| MaterialFileError::Io(error.to_string()))?;
        let text = core::str::from_utf8(&bytes)
            .map_err(|error| MaterialFileError::Syntax(error.to_string()))?;
        let mut material = material_from_ron(text)?;
        let file = load_context
            .path()
            .path()
            .file_name()
            .and_then(|name| name.to_str())
            .unwrap_or_default();
        let stem = file
            .strip_suffix(MATERIAL_FILE_EXTENSION)
            .and_then(|s| s.strip_suffix('.'))
            .unwrap_or(file);
        material.name = material_name(stem);
        Ok(BurnMaterialAsset { material })
    }

    fn extensions(&self) -> &[&str] {
        &[MATERIAL_FILE_EXTENSION]
    }
}

/// A `'static` name for a material loaded from a file called `stem`: a preset's own name if it
/// is one, else the name kept once for the program's life (one small string per distinct
/// file name, however often it reloads).
fn material_name(stem: &str) -> &'static str {
    static NAMES: Mutex<Vec<&'static str>> = Mutex::new(Vec::new());
    if stem.is_empty() {
        return "custom";
    }
    if let Some(preset) = BurnMaterial::PRESETS.iter().find(|p| p.name == stem) {
        return preset.name;
    }
    let mut names = NAMES
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner());
    if let Some(name) = names.iter().find(|name| **name == stem) {
        return name;
    }
    let name: &'static str = Box::leak(stem.to_owned().into_boxed_str());
    names.push(name);
    name
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_the_preset_names_or_kept_once_per_file_name() {
        assert!(core::ptr::eq(
            material_name("silk"),
            BurnMaterial::SILK.name
        ));
        let wool = material_name("wool");
        assert_eq!(wool, "wool");
        assert!(core::ptr::eq(material_name("wool"), wool));
        assert_eq!(material_name(""), "custom");
    }
}
