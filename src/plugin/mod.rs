//! The ECS face of the simulation: components, events, system sets and plugins.
//!
//! | plugin | feature | what it adds |
//! |---|---|---|
//! | [`ClothSimulationPlugin`] | always | building cloths, heat, combustion, dynamics, culling, [`Ignite`] |
//! | `ClothRenderPlugin` (module `render`) | `render` | a dynamic mesh per cloth, the burning-cloth material, click to ignite |
//! | `SmokePlugin` (module `smoke`) | `smoke` | a flame, smoke and ember emitter per cloth |
//! | `SmokeRenderPlugin` (module `smoke::render`) | `smoke` + `render` | the particles as billboards |
//!
//! [`BurningClothPlugins`] groups them, so `.build().disable::<X>()` removes one.

mod components;
mod control;
mod events;
mod heat_sources;
mod schedule;
mod systems;

pub use components::{
    ClothCollider, ClothParticles, ClothScratch, ClothSolver, ClothSprings, ClothStatus,
    ClothTopology, DespawnWhenBurntAway,
};
#[cfg(feature = "smoke")]
pub(crate) use control::consume_pending_step;
pub use control::{ClothSimulationControl, ClothStepTiming, simulation_is_running};
pub use events::{
    ClothBurntOut, ClothIgnited, ClothInstability, ClothParticlesBurnt, ClothPieceDetached,
    Extinguish, Ignite, IgniteAt,
};
pub use heat_sources::{ClothHeatSources, FireSpread, HeatSource};
pub use schedule::{
    BurningClothSystems, ClothSubstepSchedule, ClothSubstepSystems, SubstepCounter,
};

use crate::sim;
use bevy::app::PluginGroupBuilder;
use bevy::ecs::intern::Interned;
use bevy::ecs::schedule::{ScheduleLabel, SingleThreadedExecutor};
use bevy::prelude::*;
use bevy::transform::TransformSystems;

/// Gravity, wind and world up for every cloth. Invalid values (NaN, infinity, zero up) are
/// logged and the previous values kept.
#[derive(Resource, Clone, Copy, Debug, Default, PartialEq, Deref, DerefMut)]
pub struct ClothEnvironment(pub sim::Environment);

/// The systems that build cloths from [`ClothBuilder`](sim::ClothBuilder)s and
/// [`MeshClothBuilder`](sim::MeshClothBuilder)s (in `PostUpdate`, after transform
/// propagation).
#[derive(SystemSet, Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ClothBuildSystems;

/// Every [`ClothCollider`] in world space, gathered once per step.
#[derive(Resource, Clone, Debug, Default)]
pub struct ClothColliders(pub Vec<sim::WorldCollider>);

/// Every plugin of the crate. Add it once:
///
/// ```no_run
/// use bevy::prelude::*;
/// use bevy_burning_cloth::prelude::*;
/// App::new()
///     .add_plugins((MinimalPlugins, BurningClothPlugins::default()))
///     .run();
/// ```
///
/// The simulation runs in `FixedUpdate`; [`BurningClothPlugins::new`] moves it to another
/// schedule.
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
        let group = PluginGroupBuilder::start::<Self>().add(ClothSimulationPlugin {
            schedule: self.schedule,
        });
        #[cfg(feature = "render")]
        let group = group.add(crate::render::ClothRenderPlugin);
        #[cfg(feature = "smoke")]
        let group = group.add(crate::smoke::SmokePlugin {
            schedule: self.schedule,
        });
        #[cfg(all(feature = "smoke", feature = "render"))]
        let group = group.add(crate::smoke::render::SmokeRenderPlugin);
        group
    }
}

/// Builds cloths from [`ClothBuilder`](crate::sim::ClothBuilder)s and steps them: heat,
/// combustion, dynamics in substeps, culling. Handles [`Ignite`].
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
            .init_resource::<SubstepCounter>()
            .init_resource::<ClothColliders>()
            .init_resource::<ClothSimulationControl>()
            .init_resource::<ClothStepTiming>()
            .init_resource::<ClothHeatSources>()
            .init_resource::<FireSpread>()
            .add_observer(events::on_ignite)
            .add_observer(events::on_extinguish);

        let mut substep = Schedule::new(ClothSubstepSchedule);
        substep.set_executor(SingleThreadedExecutor::new());
        substep.configure_sets(
            (
                ClothSubstepSystems::Forces,
                ClothSubstepSystems::Integrate,
                ClothSubstepSystems::Constrain,
            )
                .chain(),
        );
        substep.add_systems((
            systems::prepare_forces.in_set(ClothSubstepSystems::Forces),
            systems::integrate_cloths.in_set(ClothSubstepSystems::Integrate),
            systems::constrain_cloths.in_set(ClothSubstepSystems::Constrain),
        ));
        app.add_schedule(substep);

        let has_cloth = any_with_component::<ClothParticles>;
        app.configure_sets(
            self.schedule,
            (
                BurningClothSystems::Prepare,
                BurningClothSystems::Heat,
                BurningClothSystems::Combust,
                BurningClothSystems::Simulate,
                BurningClothSystems::Cull,
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
                    systems::prepare_cloths,
                )
                    .chain()
                    .in_set(BurningClothSystems::Prepare),
                (systems::spread_heat, heat_sources::heat_from_sources)
                    .chain()
                    .in_set(BurningClothSystems::Heat),
                systems::combust.in_set(BurningClothSystems::Combust),
                systems::run_substeps.in_set(BurningClothSystems::Simulate),
                (
                    systems::guard_cloths,
                    systems::cull_cloths,
                    control::finish_step_timer,
                )
                    .chain()
                    .in_set(BurningClothSystems::Cull),
            ),
        )
        .add_systems(
            self.schedule,
            control::consume_pending_step.after(BurningClothSystems::Cull),
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
