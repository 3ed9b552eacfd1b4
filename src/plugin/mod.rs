//! The ECS face of the simulation: components, events, system sets and
//! [`ClothSimulationPlugin`].
//!
//! A cloth is one entity. [`ClothBuilder`](crate::sim::ClothBuilder) or
//! [`MeshClothBuilder`](crate::sim::MeshClothBuilder) on it (with a
//! [`BurnMaterial`](crate::sim::BurnMaterial) and a `Transform`) is turned into the
//! simulated components in `PostUpdate` ([`ClothBuildSystems`]). Each step of the simulation
//! schedule then runs the chained [`BurningClothSystems`]:
//!
//! | set | systems |
//! |---|---|
//! | `Prepare` | colliders, [`HeatSource`]s and the burning particles of every cloth gathered in world space; valid settings taken into use ([`ClothInUse`]) |
//! | `Simulate` | every cloth runs [`ClothMut::step`](crate::sim::ClothMut::step): pins, heat, combustion, dynamics, culling |
//! | `Report` | [`ClothStatus`] written; [`ClothDiagnostics`] measured; [`ClothIgnited`], [`ClothBurntOut`], [`ClothParticlesBurnt`], [`ClothPieceDetached`], [`ClothInstability`] triggered |
//!
//! The physics lives in [`crate::sim`]; these systems only gather, call and report. This
//! module knows nothing of drawing, smoke or the panel: those plugins read its components.
//!
//! Where its accuracy ends: that of [`crate::sim`] (see its page). Cloths do not collide with
//! each other; a loose piece stays part of its cloth entity.

mod components;
mod control;
mod diagnostics;
mod events;
mod heat_sources;
mod schedule;
mod systems;

pub use components::{
    ClothCollider, ClothInUse, ClothParticles, ClothSolver, ClothSprings, ClothStatus,
    ClothTopology, DespawnWhenBurntAway, HoldBuild, HoldDespawn,
};
#[cfg(feature = "smoke")]
pub(crate) use control::consume_pending_step;
pub use control::{ClothSimulationControl, ClothStepTiming, simulation_is_running};
pub use diagnostics::ClothDiagnostics;
pub use events::{
    ClothBurntOut, ClothIgnited, ClothInstability, ClothParticlesBurnt, ClothPieceDetached,
    Extinguish, Ignite, IgniteAt,
};
pub use heat_sources::{ClothHeatSources, FireSpread, HeatSource};
pub use schedule::BurningClothSystems;

use crate::sim;
use bevy::ecs::intern::Interned;
use bevy::ecs::schedule::ScheduleLabel;
use bevy::prelude::*;
use bevy::transform::TransformSystems;

/// Gravity, wind and world up for every cloth. Invalid values (NaN, infinity, zero up) are
/// logged and the previous values kept.
#[derive(Resource, Clone, Copy, Debug, Default, PartialEq, Deref, DerefMut, Reflect)]
#[reflect(Resource, Default, Clone, Debug, PartialEq)]
pub struct ClothEnvironment(pub sim::Environment);

/// The systems that build cloths from [`ClothBuilder`](sim::ClothBuilder)s and
/// [`MeshClothBuilder`](sim::MeshClothBuilder)s (in `PostUpdate`, after transform
/// propagation).
#[derive(SystemSet, Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ClothBuildSystems;

/// Every [`ClothCollider`] in world space, gathered once per step.
#[derive(Resource, Clone, Debug, Default)]
pub struct ClothColliders(pub Vec<sim::WorldCollider>);

/// Builds cloths from [`ClothBuilder`](crate::sim::ClothBuilder)s and
/// [`MeshClothBuilder`](crate::sim::MeshClothBuilder)s and steps them; handles [`Ignite`] and
/// [`Extinguish`]. Part of [`BurningClothPlugins`](crate::BurningClothPlugins).
pub struct ClothSimulationPlugin {
    /// The schedule the simulation steps in.
    pub schedule: Interned<dyn ScheduleLabel>,
}

impl Default for ClothSimulationPlugin {
    fn default() -> Self {
        Self {
            schedule: FixedUpdate.intern(),
        }
    }
}

impl Plugin for ClothSimulationPlugin {
    fn build(&self, app: &mut App) {
        if !app.is_plugin_added::<TransformPlugin>() {
            app.add_plugins(TransformPlugin);
        }
        app.init_resource::<ClothEnvironment>()
            .init_resource::<ClothColliders>()
            .init_resource::<ClothSimulationControl>()
            .init_resource::<ClothStepTiming>()
            .init_resource::<ClothHeatSources>()
            .init_resource::<FireSpread>()
            .add_observer(events::on_ignite)
            .add_observer(events::on_extinguish);
        diagnostics::register(app);
        register_types(app);

        let has_cloth = any_with_component::<ClothParticles>;
        app.configure_sets(
            self.schedule,
            (
                BurningClothSystems::Prepare,
                BurningClothSystems::Simulate,
                BurningClothSystems::Report,
            )
                .chain()
                .run_if(has_cloth)
                .run_if(simulation_is_running),
        )
        .add_systems(
            self.schedule,
            (
                (
                    control::start_step_timer,
                    systems::gather_colliders,
                    heat_sources::gather_heat_sources,
                    heat_sources::gather_burning_particles,
                    systems::take_settings_into_use,
                )
                    .chain()
                    .in_set(BurningClothSystems::Prepare),
                systems::simulate_cloths.in_set(BurningClothSystems::Simulate),
                (
                    systems::report_cloths,
                    control::finish_step_timer,
                    diagnostics::measure,
                )
                    .chain()
                    .in_set(BurningClothSystems::Report),
            ),
        )
        .add_systems(
            self.schedule,
            control::consume_pending_step.after(BurningClothSystems::Report),
        )
        .add_systems(
            PostUpdate,
            (
                systems::build_cloths::<sim::ClothBuilder>
                    .run_if(any_with_component::<sim::ClothBuilder>),
                systems::build_cloths::<sim::MeshClothBuilder>
                    .run_if(any_with_component::<sim::MeshClothBuilder>),
            )
                .in_set(ClothBuildSystems)
                .after(TransformSystems::Propagate),
        )
        .add_systems(
            PostUpdate,
            systems::despawn_burnt_away.run_if(any_with_component::<DespawnWhenBurntAway>),
        );
    }
}

/// Registers the reflected types of a cloth's description and the simulation's resources, so
/// inspectors, scenes and the Bevy Remote Protocol see them. Runtime state (particles,
/// springs, topology, workspace) is not reflected: it is rebuilt from the description.
fn register_types(app: &mut App) {
    app.register_type::<sim::ClothBuilder>()
        .register_type_data::<sim::ClothBuilder, ReflectComponent>()
        .register_type::<sim::BurnMaterial>()
        .register_type_data::<sim::BurnMaterial, ReflectComponent>()
        .register_type::<ClothSolver>()
        .register_type::<ClothStatus>()
        .register_type::<ClothCollider>()
        .register_type::<DespawnWhenBurntAway>()
        .register_type::<HoldDespawn>()
        .register_type::<HeatSource>()
        .register_type::<FireSpread>()
        .register_type::<ClothEnvironment>()
        .register_type::<ClothSimulationControl>();
}
