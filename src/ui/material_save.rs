//! The panel's "save material": writes the material being edited to a `.burnmat.ron` file in
//! the asset folder (feature `material_assets`), where a [`BurnMaterialFile`] can load it and,
//! with Bevy watching the folder, every cloth using that file takes it at once.

use super::ClothPanel;
use crate::material_file::{BurnMaterialFile, MATERIAL_FILE_EXTENSION, material_to_ron};
use crate::sim::BurnMaterial;
use bevy::asset::AssetServer;
use bevy::ecs::entity::Entity;
use bevy_egui::egui;
use std::path::{Component, Path, PathBuf};

/// Writes `material` to `relative` (a path inside `folder` ending in `.burnmat.ron`, with no
/// `..`), creating its directories; returns the file written.
pub fn save_material(
    folder: &Path,
    relative: &str,
    material: &BurnMaterial,
) -> Result<PathBuf, String> {
    let relative_path = Path::new(relative.trim());
    if !relative
        .trim()
        .ends_with(&format!(".{MATERIAL_FILE_EXTENSION}"))
    {
        return Err(format!(
            "the file name must end in .{MATERIAL_FILE_EXTENSION}"
        ));
    }
    if relative_path
        .components()
        .any(|c| !matches!(c, Component::Normal(_)))
    {
        return Err("the path must stay inside the asset folder (no /, .. or drive)".to_owned());
    }
    let path = folder.join(relative_path);
    let text = material_to_ron(material).map_err(|e| e.to_string())?;
    if let Some(parent) = path.parent() {
        std::fs::create_dir_all(parent).map_err(|e| format!("{}: {e}", parent.display()))?;
    }
    std::fs::write(&path, text).map_err(|e| format!("{}: {e}", path.display()))?;
    Ok(path)
}

/// The file the panel offers to save the selected cloth's material to: the file it came from,
/// else `materials/my_<name>.burnmat.ron`.
fn default_file(
    material: &BurnMaterial,
    file: Option<&BurnMaterialFile>,
    server: Option<&AssetServer>,
) -> String {
    file.and_then(|file| server?.get_path(file.id()))
        .map(|path| path.path().to_string_lossy().into_owned())
        .unwrap_or_else(|| format!("materials/my_{}.{MATERIAL_FILE_EXTENSION}", material.name))
}

/// The row under the material sliders: the file, a save button, and what the last save did.
pub(super) fn save_row(
    ui: &mut egui::Ui,
    panel: &mut ClothPanel,
    cloth: Entity,
    material: &BurnMaterial,
    file: Option<&BurnMaterialFile>,
    server: Option<&AssetServer>,
) {
    let Some(folder) = panel.asset_folder.clone() else {
        return;
    };
    if panel.material_file_cloth != Some(cloth) {
        panel.material_file_cloth = Some(cloth);
        panel.material_file = default_file(material, file, server);
        panel.save_message = None;
    }
    ui.horizontal(|ui| {
        ui.add(egui::TextEdit::singleline(&mut panel.material_file).desired_width(190.0));
        if ui.button("save").clicked() {
            panel.save_message = Some(
                match save_material(&folder, &panel.material_file, material) {
                    Ok(path) => format!("saved {}", path.display()),
                    Err(error) => format!("not saved: {error}"),
                },
            );
        }
    });
    if let Some(message) = &panel.save_message {
        ui.small(message.as_str());
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material_file::material_from_ron;

    #[test]
    fn a_saved_material_loads_back_and_paths_outside_the_folder_are_refused() {
        let folder =
            std::env::temp_dir().join(format!("burning_cloth_save_{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&folder);
        let tuned = BurnMaterial {
            self_heating_rate: 321.0,
            ..BurnMaterial::DENIM
        };
        let path = save_material(&folder, "materials/tuned.burnmat.ron", &tuned).unwrap();
        let back = material_from_ron(&std::fs::read_to_string(&path).unwrap()).unwrap();
        assert_eq!(
            BurnMaterial {
                name: "denim",
                ..back
            },
            tuned
        );
        for bad in [
            "../escape.burnmat.ron",
            "/abs.burnmat.ron",
            "materials/x.ron",
            "",
        ] {
            assert!(save_material(&folder, bad, &tuned).is_err(), "{bad}");
        }
        std::fs::remove_dir_all(&folder).unwrap();
    }
}
