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
//! - [`sim`]: the physics, plain Rust over slices, testable without an `App`.
//! - [`plugin`]: components, events, system sets; thin systems over [`sim`].
//! - `render` (feature `render`): the dynamic mesh and click-to-ignite.
//! - `smoke` (feature `smoke`): flames, smoke and embers from the burning front.
//!
//! ## Units
//! Metres, kilograms, seconds, degrees Celsius. The paper's Fahrenheit thresholds are
//! converted once, in [`sim::material`].
//!
//! ## Cargo features
//! - `render` (default): draw cloths with Bevy's renderer. Without it nothing of Bevy's
//!   renderer is compiled and the simulation runs headless.
//! - `smoke` (default): flames, smoke and embers. Without it none of that code is compiled.
//! - `egui` (default, implies `render`): the control panel, [`ui::BurningClothUiPlugin`].

#![warn(missing_docs)]
#![forbid(unsafe_code)]

pub mod plugin;
#[cfg(feature = "render")]
pub mod render;
pub mod report;
pub mod sim;
#[cfg(feature = "smoke")]
pub mod smoke;
#[cfg(feature = "egui")]
pub mod ui;

/// The types most users need.
pub mod prelude {
    pub use crate::plugin::{
        BurningClothPlugins, BurningClothSystems, ClothBuildSystems, ClothBurntOut, ClothCollider,
        ClothEnvironment, ClothIgnited, ClothInstability, ClothParticles, ClothParticlesBurnt,
        ClothPieceDetached, ClothSimulationControl, ClothSimulationPlugin, ClothSolver,
        ClothSprings, ClothStatus, ClothStepTiming, ClothSubstepSystems, ClothTopology,
        DespawnWhenBurntAway, Extinguish, FireSpread, HeatSource, Ignite, IgniteAt,
    };
    #[cfg(feature = "render")]
    pub use crate::render::{ClothRenderPlugin, Flammable};
    pub use crate::sim::{
        BurnMaterial, BurnState, ClothBuilder, ClothError, ColliderShape, Cutout, GridPlane,
        Integrator, MeshClothBuilder, MeshPins, ProvotSettings, SolverSettings,
    };
    #[cfg(feature = "smoke")]
    pub use crate::smoke::{KindSettings, SmokeEmitter, SmokeKind, SmokePlugin, SmokeSettings};
    #[cfg(feature = "egui")]
    pub use crate::ui::{BurningClothUiPlugin, ClothPanel};
}
