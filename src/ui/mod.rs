//! A control panel for burning cloth (feature `egui`): add [`BurningClothUiPlugin`] after
//! `BurningClothPlugins` and a side panel edits the selected cloth's material and solver, the
//! wind and gravity; pauses, steps, resets, ignites and extinguishes; shows live statistics
//! and a plot of the burnt fraction; and switches the heat map and the spring and pin gizmos.
//!
//! ```no_run
//! use bevy::prelude::*;
//! use bevy_burning_cloth::prelude::*;
//! App::new()
//!     .add_plugins((DefaultPlugins, BurningClothPlugins::default(), BurningClothUiPlugin))
//!     .run();
//! ```
//!
//! Every edit takes one path ([`PanelValues::apply`]): clamped to the sliders' ranges, then
//! validated like the builder; an edit that fails is not applied and the panel says why.
//! Clicks on the panel do not reach the cloth behind it (bevy_egui's picking capture).

#[cfg(feature = "material_assets")]
pub mod material_save;
mod panel;
pub mod params;
#[cfg(feature = "fluid")]
pub mod plume_params;

pub use params::{FieldRange, MATERIAL_FIELDS, PanelValues};

use crate::plugin::{ClothParticles, ClothStatus};
use bevy::prelude::*;
use bevy::time::Real;
use bevy_egui::{EguiPlugin, EguiPrimaryContextPass};

/// The control panel: a side panel for the selected cloth. See the [module docs](self).
pub struct BurningClothUiPlugin;

impl Plugin for BurningClothUiPlugin {
    fn build(&self, app: &mut App) {
        if !app.is_plugin_added::<EguiPlugin>() {
            app.add_plugins(EguiPlugin::default());
        }
        let mut panel = ClothPanel::default();
        #[cfg(feature = "material_assets")]
        if let Some(assets) = app.get_added_plugins::<bevy::asset::AssetPlugin>().first() {
            panel.asset_folder = Some(
                bevy::asset::io::file::FileAssetReader::get_base_path().join(&assets.file_path),
            );
        }
        app.insert_resource(panel)
            .add_observer(select_clicked_cloth)
            .add_systems(EguiPrimaryContextPass, panel::draw_panel)
            .add_systems(
                Update,
                (
                    keep_selection_valid,
                    record_burnt_fraction,
                    panel::apply_heat_map,
                    panel::draw_gizmos
                        .run_if(|panel: Res<ClothPanel>| panel.show_springs || panel.show_pins),
                ),
            );
    }
}

/// Samples of the burnt-fraction plot: one every this many seconds of real time.
pub const HISTORY_INTERVAL: f32 = 0.1;
/// Samples kept for the burnt-fraction plot.
pub const HISTORY_LENGTH: usize = 300;

/// State of the control panel.
#[derive(Resource, Clone, Debug)]
pub struct ClothPanel {
    /// Whether the panel is shown.
    pub open: bool,
    /// The cloth the panel edits; the first cloth when `None` or despawned.
    pub selected: Option<Entity>,
    /// Draw the temperature heat map instead of the burn look on every cloth.
    pub heat_map: bool,
    /// Draw the selected cloth's springs as gizmos.
    pub show_springs: bool,
    /// Draw the selected cloth's pins as gizmos.
    pub show_pins: bool,
    /// Burnt fraction of the selected cloth, oldest first, one sample per
    /// [`HISTORY_INTERVAL`].
    pub burnt_history: Vec<f32>,
    /// Why the last edit was refused, if it was.
    pub last_error: Option<String>,
    /// Where the panel was drawn last frame, in logical window pixels (`None` when closed).
    pub screen_rect: Option<Rect>,
    /// The material file "save" writes, inside the asset folder (filled in for the selected
    /// cloth when empty: the file its material came from, else `materials/my_<name>.burnmat.ron`).
    pub material_file: String,
    /// What the last "save" did.
    pub save_message: Option<String>,
    /// The asset folder on disk (Bevy's `AssetPlugin::file_path` under its base path), where
    /// material files are saved; `None` hides "save" (no `AssetPlugin`, or no
    /// `material_assets` feature).
    pub asset_folder: Option<std::path::PathBuf>,
    /// The cloth `material_file` was filled in for.
    material_file_cloth: Option<Entity>,
    since_sample: f32,
    random_state: u64,
}

impl Default for ClothPanel {
    fn default() -> Self {
        Self {
            open: true,
            selected: None,
            heat_map: false,
            show_springs: false,
            show_pins: false,
            burnt_history: Vec::with_capacity(HISTORY_LENGTH),
            last_error: None,
            screen_rect: None,
            material_file: String::new(),
            save_message: None,
            asset_folder: None,
            material_file_cloth: None,
            since_sample: 0.0,
            random_state: 0x9E37_79B9_7F4A_7C15,
        }
    }
}

impl ClothPanel {
    /// A pseudo-random index below `n` (splitmix64), for "ignite at a random point".
    fn random_below(&mut self, n: usize) -> usize {
        self.random_state = self.random_state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.random_state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        (z % n.max(1) as u64) as usize
    }

    fn push_sample(&mut self, value: f32) {
        if self.burnt_history.len() == HISTORY_LENGTH {
            self.burnt_history.remove(0);
        }
        self.burnt_history.push(value);
    }
}

/// Selects a cloth when it is clicked.
fn select_clicked_cloth(
    click: On<Pointer<Click>>,
    cloths: Query<(), With<ClothParticles>>,
    mut panel: ResMut<ClothPanel>,
) {
    if cloths.contains(click.entity) && panel.selected != Some(click.entity) {
        panel.selected = Some(click.entity);
        panel.burnt_history.clear();
    }
}

/// Falls back to the first cloth when the selection is gone.
fn keep_selection_valid(
    mut panel: ResMut<ClothPanel>,
    cloths: Query<Entity, With<ClothParticles>>,
) {
    if panel.selected.is_some_and(|e| cloths.contains(e)) {
        return;
    }
    let first = cloths.iter().min();
    if panel.selected != first {
        panel.selected = first;
        panel.burnt_history.clear();
    }
}

/// Samples the selected cloth's burnt fraction for the plot.
fn record_burnt_fraction(
    time: Res<Time<Real>>,
    mut panel: ResMut<ClothPanel>,
    statuses: Query<&ClothStatus>,
) {
    panel.since_sample += time.delta_secs();
    if panel.since_sample < HISTORY_INTERVAL {
        return;
    }
    panel.since_sample = 0.0;
    if let Some(status) = panel.selected.and_then(|e| statuses.get(e).ok()) {
        let fraction = status.burnt_fraction();
        panel.push_sample(fraction);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn random_points_cover_the_range_and_stay_in_it() {
        let mut panel = ClothPanel::default();
        let mut seen = [false; 10];
        for _ in 0..200 {
            let i = panel.random_below(10);
            assert!(i < 10);
            seen[i] = true;
        }
        assert!(seen.iter().all(|&s| s));
        assert_eq!(panel.random_below(0), 0);
    }

    #[test]
    fn the_history_keeps_the_latest_samples() {
        let mut panel = ClothPanel::default();
        for i in 0..HISTORY_LENGTH + 5 {
            panel.push_sample(i as f32);
        }
        assert_eq!(panel.burnt_history.len(), HISTORY_LENGTH);
        assert_eq!(panel.burnt_history[0], 5.0);
        assert_eq!(panel.burnt_history.capacity(), HISTORY_LENGTH);
    }
}
