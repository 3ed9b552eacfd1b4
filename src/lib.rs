//! # bevy_burning_cloth
//!
//! Cloth that burns, for the Bevy game engine: a mass-spring cloth (structural, shear and
//! bending springs, Provot's stretch limit) whose particles heat up, ignite, shrink their
//! springs, and burn away, after Loshak & Killian, *Simulating Burning Cloth*.
//!
//! ```no_run
//! use bevy::prelude::*;
//! use bevy_burning_cloth::prelude::*;
//!
//! fn spawn(mut commands: Commands) {
//!     let cloth = commands
//!         .spawn((
//!             ClothBuilder::grid(32, 32, 0.03).pin_top_corners(),
//!             BurnMaterial::SILK,
//!             Transform::from_xyz(0.0, 2.0, 0.0),
//!         ))
//!         .id();
//!     // Later, from gameplay: set it alight near its bottom corner.
//!     commands.trigger(Ignite::at_world_point(cloth, Vec3::new(0.4, 1.1, 0.0)));
//! }
//!
//! App::new()
//!     .add_plugins((MinimalPlugins, BurningClothPlugins::default()))
//!     .add_systems(Startup, spawn)
//!     .run();
//! ```
//!
//! ## Layers
//! Each layer only uses the ones above it in this list:
//! - [`sim`]: the physics, plain Rust over slices, testable without an `App`. One cloth's step
//!   is defined once, in [`sim::step`].
//! - [`plugin`]: components, events, system sets; thin systems that gather the world, call
//!   the step for each cloth, and report.
//! - `render` (feature `render`): the dynamic mesh, the burning material, click-to-ignite,
//!   `render::Flammable` meshes.
//! - `material_file` (feature `material_assets`): materials as `.burnmat.ron` asset files.
//! - `smoke` (feature `smoke`): flames, smoke and embers from the burning front.
//! - `ui` (feature `egui`): the control panel.
//!
//! [`BurningClothPlugins`] (here, in the crate root) puts the plugins of every layer together.
//!
//! ## Units
//! Metres, kilograms, seconds, degrees Celsius. The paper's Fahrenheit thresholds are
//! converted once, in [`sim::material`].
//!
//! ## Cargo features
//! - `render` (default): draw cloths with Bevy's renderer. Without it nothing of Bevy's
//!   renderer is compiled and the simulation runs headless.
//! - `smoke` (default): flames, smoke and embers. Without it none of that code is compiled.
//! - `egui` (default, implies `render`): the control panel, `ui::BurningClothUiPlugin`.
//! - `gltf` (default, implies `render`): Bevy's glTF loader, for the glTF example and test.
//! - `material_assets` (default): materials as `.burnmat.ron` asset files
//!   (`material_file`); `hot_reload` (off) adds Bevy's file watcher so edits apply live.
//! - `report` (off): the accuracy report and stability matrix (`report`), for the report
//!   examples and their tests.

#![warn(missing_docs)]

pub mod plugin;

/// The README's Rust blocks, compiled by `cargo test --doc` (and run, where they open no
/// window) when the features they use are on, so the README cannot drift from the crate.
#[cfg(all(doctest, feature = "render", feature = "gltf"))]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;

#[cfg(feature = "fluid")]
pub mod fluid;
#[cfg(feature = "material_assets")]
pub mod material_file;
#[cfg(feature = "render")]
pub mod render;
#[cfg(feature = "report")]
pub mod report;
pub mod sim;
#[cfg(feature = "smoke")]
pub mod smoke;
#[cfg(feature = "egui")]
pub mod ui;

use bevy::app::{FixedUpdate, PluginGroup, PluginGroupBuilder};
use bevy::ecs::intern::Interned;
use bevy::ecs::schedule::ScheduleLabel;

/// Every plugin of the crate, for the features compiled in. Add it once, after
/// `DefaultPlugins` (or `MinimalPlugins` headless):
///
/// ```no_run
/// use bevy::prelude::*;
/// use bevy_burning_cloth::prelude::*;
/// App::new()
///     .add_plugins((MinimalPlugins, BurningClothPlugins::default()))
///     .run();
/// ```
///
/// | plugin | feature | what it adds |
/// |---|---|---|
/// | [`ClothSimulationPlugin`](plugin::ClothSimulationPlugin) | always | building cloths, the step of every cloth, [`Ignite`](plugin::Ignite), events |
/// | `MaterialFilePlugin` | `material_assets` | `.burnmat.ron` material files, hot-reloaded onto cloths |
/// | `ClothRenderPlugin` | `render` | a dynamic mesh per cloth, the burning-cloth material, click to ignite, `Flammable` meshes |
/// | `SmokePlugin` | `smoke` | a flame, smoke and ember emitter per cloth |
/// | `FluidPlugin` | `fluid` | the fire's air: a plume grid that carries the smoke, blows on and heats the cloth |
/// | `SmokeRenderPlugin` | `smoke` + `render` | the particles as billboards, flame tongues along the burning front |
///
/// `.build().disable::<X>()` removes one. The simulation runs in `FixedUpdate`;
/// [`BurningClothPlugins::new`] moves it (and the smoke) to another schedule.
pub struct BurningClothPlugins {
    schedule: Interned<dyn ScheduleLabel>,
}

impl BurningClothPlugins {
    /// Runs the simulation in `schedule` instead of `FixedUpdate`.
    pub fn new(schedule: impl ScheduleLabel) -> Self {
        Self {
            schedule: schedule.intern(),
        }
    }
}

impl Default for BurningClothPlugins {
    fn default() -> Self {
        Self::new(FixedUpdate)
    }
}

impl PluginGroup for BurningClothPlugins {
    fn build(self) -> PluginGroupBuilder {
        let group = PluginGroupBuilder::start::<Self>().add(plugin::ClothSimulationPlugin {
            schedule: self.schedule,
        });
        #[cfg(feature = "material_assets")]
        let group = group.add(material_file::MaterialFilePlugin);
        #[cfg(feature = "render")]
        let group = group.add(render::ClothRenderPlugin);
        #[cfg(feature = "smoke")]
        let group = group.add(smoke::SmokePlugin {
            schedule: self.schedule,
        });
        #[cfg(feature = "fluid")]
        let group = group.add(fluid::FluidPlugin {
            schedule: self.schedule,
        });
        #[cfg(all(feature = "smoke", feature = "render"))]
        let group = group.add(smoke::render::SmokeRenderPlugin);
        group
    }
}

/// The types most users need.
pub mod prelude {
    pub use crate::BurningClothPlugins;
    #[cfg(feature = "fluid")]
    pub use crate::fluid::{FirePlume, FluidPlugin, PlumeSettings};
    #[cfg(feature = "material_assets")]
    pub use crate::material_file::{BurnMaterialAsset, BurnMaterialFile};
    pub use crate::plugin::{
        BurningClothSystems, ClothBuildSystems, ClothBurntOut, ClothCollider, ClothDiagnostics,
        ClothEnvironment, ClothIgnited, ClothInUse, ClothInstability, ClothParticles,
        ClothParticlesBurnt, ClothPieceDetached, ClothSimulationControl, ClothSimulationPlugin,
        ClothSolver, ClothSprings, ClothStatus, ClothStepTiming, ClothTopology,
        DespawnWhenBurntAway, Extinguish, FireSpread, HeatSource, HoldDespawn, Ignite, IgniteAt,
    };
    #[cfg(feature = "render")]
    pub use crate::render::{ClothRenderPlugin, Flammable};
    pub use crate::sim::{
        BurnMaterial, BurnState, ClothBuilder, ClothError, ColliderShape, Cutout, GridPlane,
        HeatModel, Integrator, MeshClothBuilder, MeshPins, ProvotSettings, SolverSettings,
    };
    #[cfg(feature = "smoke")]
    pub use crate::smoke::{KindSettings, SmokeEmitter, SmokeKind, SmokePlugin, SmokeSettings};
    #[cfg(feature = "egui")]
    pub use crate::ui::{BurningClothUiPlugin, ClothPanel};
}
