//! The ECS face of smoke: [`SmokePlugin`], the [`SmokeEmitter`] component and its systems.

use super::emitter::{Air, BurningCloth, SmokeSim};
use super::pool::SmokePool;
use super::settings::{SmokeSettings, SmokeSettingsError};
use crate::plugin::{
    BurningClothSystems, ClothEnvironment, ClothInUse, ClothParticles, ClothTopology, HoldDespawn,
};
use bevy::diagnostic::{Diagnostic, DiagnosticPath, Diagnostics, RegisterDiagnostic};
use bevy::ecs::intern::Interned;
use bevy::ecs::schedule::ScheduleLabel;
use bevy::prelude::*;
use std::time::{Duration, Instant};

/// Smoke diagnostics, read by `LogDiagnosticsPlugin` and the panel (one measurement per
/// simulation step while any emitter exists).
pub struct SmokeDiagnostics;

impl SmokeDiagnostics {
    /// Time to emit from every cloth and move every particle, ms.
    pub const STEP: DiagnosticPath = DiagnosticPath::const_new("burning_cloth/smoke_step");
    /// Flame, smoke and ember particles alive, over every emitter.
    pub const PARTICLES: DiagnosticPath =
        DiagnosticPath::const_new("burning_cloth/smoke_particles");
}

/// Time spent emitting this step, carried to the system that moves the particles.
#[derive(Resource, Default)]
struct SmokeEmitTime(Duration);

/// A cloth's flames, smoke and embers: settings and a fixed-capacity particle pool.
///
/// With [`SmokePlugin`] in the app every cloth gets one with default settings when it is
/// built; insert your own at spawn to change them, or change them later with
/// [`SmokeEmitter::set_settings`]. Particles live in world space and keep flying after the
/// cloth has burnt out.
#[derive(Component, Clone, Debug)]
pub struct SmokeEmitter {
    sim: SmokeSim,
}

impl Default for SmokeEmitter {
    fn default() -> Self {
        Self::new(SmokeSettings::default())
    }
}

impl SmokeEmitter {
    /// An emitter with these settings; invalid settings are logged and the defaults used.
    pub fn new(settings: SmokeSettings) -> Self {
        Self::try_new(settings).unwrap_or_else(|error| {
            warn!("SmokeEmitter: {error}; default settings used");
            Self::try_new(SmokeSettings::default()).expect("default smoke settings are valid")
        })
    }

    /// An emitter with these settings, or why they are unusable.
    pub fn try_new(settings: SmokeSettings) -> Result<Self, SmokeSettingsError> {
        Ok(Self {
            sim: SmokeSim::new(settings)?,
        })
    }

    /// The settings in use.
    pub fn settings(&self) -> &SmokeSettings {
        self.sim.settings()
    }

    /// Replaces the settings if they are valid; otherwise keeps the old ones and says why.
    pub fn set_settings(&mut self, settings: SmokeSettings) -> Result<(), SmokeSettingsError> {
        self.sim.set_settings(settings)
    }

    /// The particles.
    pub fn pool(&self) -> &SmokePool {
        &self.sim.pool
    }

    /// The simulation behind the component.
    pub fn sim(&self) -> &SmokeSim {
        &self.sim
    }

    /// Removes every live particle.
    pub fn clear(&mut self) {
        self.sim.pool.clear();
    }
}

/// The smoke systems, after [`BurningClothSystems::Report`] in the simulation's schedule.
#[derive(SystemSet, Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct SmokeSystems;

/// Flames, smoke and embers from every burning cloth (feature `smoke`). Part of
/// `BurningClothPlugins`. Gives every cloth a [`SmokeEmitter`], emits and moves particles in
/// the simulation's schedule. Its systems run only while some entity has an emitter. While a
/// cloth's smoke is still in the air, the cloth holds [`HoldDespawn`], so
/// `DespawnWhenBurntAway` waits for its last particle. `SmokeRenderPlugin` (feature `render`,
/// also in the group) draws them.
pub struct SmokePlugin {
    /// The schedule the simulation steps in.
    pub schedule: Interned<dyn ScheduleLabel>,
}

impl Default for SmokePlugin {
    fn default() -> Self {
        Self {
            schedule: FixedUpdate.intern(),
        }
    }
}

impl Plugin for SmokePlugin {
    fn build(&self, app: &mut App) {
        app.register_required_components::<ClothParticles, SmokeEmitter>()
            .init_resource::<SmokeEmitTime>()
            .register_diagnostic(Diagnostic::new(SmokeDiagnostics::STEP).with_suffix("ms"))
            .register_diagnostic(Diagnostic::new(SmokeDiagnostics::PARTICLES))
            .configure_sets(
                self.schedule,
                SmokeSystems
                    .after(BurningClothSystems::Report)
                    .run_if(any_with_component::<SmokeEmitter>)
                    .run_if(crate::plugin::simulation_is_running)
                    .before(crate::plugin::consume_pending_step),
            )
            .add_systems(
                self.schedule,
                (emit_smoke, advance_smoke).chain().in_set(SmokeSystems),
            );
    }
}

/// The air particles move in: the cloths' environment (still air while it is invalid).
pub(crate) fn air(environment: &ClothEnvironment) -> Air {
    if environment.validate().is_ok() {
        Air {
            wind: environment.wind,
            gravity: environment.gravity,
            up: environment.up,
        }
    } else {
        Air::default()
    }
}

/// Emits from each cloth's burning particles and those that burnt away this step.
fn emit_smoke(
    time: Res<Time>,
    environment: Res<ClothEnvironment>,
    mut emit_time: ResMut<SmokeEmitTime>,
    mut emitters: Query<(
        &mut SmokeEmitter,
        &ClothParticles,
        &ClothInUse,
        &ClothTopology,
    )>,
) {
    let started = Instant::now();
    let air = air(&environment);
    for (mut emitter, particles, in_use, topology) in &mut emitters {
        let cloth = BurningCloth::new(particles, in_use.material(), topology, in_use.newly_burnt());
        emitter.sim.emit(&cloth, &air, time.delta_secs());
    }
    emit_time.0 = started.elapsed();
}

/// Moves every emitter's live particles, on cloths or not, and holds the entity of an
/// emitter with particles in the air ([`HoldDespawn`]) until the last one has died; records
/// the [`SmokeDiagnostics`].
fn advance_smoke(
    time: Res<Time>,
    environment: Res<ClothEnvironment>,
    emit_time: Res<SmokeEmitTime>,
    mut diagnostics: Diagnostics,
    #[cfg(feature = "fluid")] fire: Option<Res<crate::fluid::FirePlume>>,
    mut commands: Commands,
    mut emitters: Query<(Entity, &mut SmokeEmitter, Has<HoldDespawn>)>,
) {
    let started = Instant::now();
    let air = air(&environment);
    #[cfg(feature = "fluid")]
    let plume = fire.as_deref().and_then(crate::fluid::FirePlume::active);
    #[cfg(not(feature = "fluid"))]
    let plume: Option<&()> = None;
    for (entity, mut emitter, held) in &mut emitters {
        if !emitter.sim.pool.is_empty() {
            match plume {
                #[cfg(feature = "fluid")]
                Some(plume) => {
                    let flow = |p: Vec3| plume.shape().contains(p).then(|| plume.velocity_at(p));
                    emitter.sim.advance_in(&air, flow, time.delta_secs());
                }
                _ => {
                    emitter.sim.advance(&air, time.delta_secs());
                }
            }
        }
        let in_the_air = !emitter.sim.pool.is_empty();
        if in_the_air && !held {
            commands.entity(entity).try_insert(HoldDespawn);
        } else if !in_the_air && held {
            commands.entity(entity).try_remove::<HoldDespawn>();
        }
    }
    let milliseconds = (emit_time.0 + started.elapsed()).as_secs_f64() * 1e3;
    diagnostics.add_measurement(&SmokeDiagnostics::STEP, || milliseconds);
    diagnostics.add_measurement(&SmokeDiagnostics::PARTICLES, || {
        emitters
            .iter()
            .map(|(_, emitter, _)| emitter.sim.pool.live() as f64)
            .sum()
    });
}
