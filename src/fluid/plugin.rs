//! The ECS face of the plume: [`FluidPlugin`], the [`FirePlume`] resource and its systems.

use super::coupling::{blow_and_heat_on, feed_plume};
use super::plume::{Plume, PlumeReport};
use super::settings::{PlumeSettings, PlumeSettingsError};
use crate::plugin::{
    BurningClothSystems, ClothColliders, ClothEnvironment, ClothInUse, ClothParticles, ClothStatus,
    ClothTopology, FireSpread,
};
use crate::sim::WorldCollider;
use crate::smoke::BurningCloth;
use bevy::diagnostic::{Diagnostic, DiagnosticPath, Diagnostics, RegisterDiagnostic};
use bevy::ecs::intern::Interned;
use bevy::ecs::schedule::ScheduleLabel;
use bevy::prelude::*;
use glam::Vec3;
use std::time::{Duration, Instant};

/// The scene's one plume: a box of air that follows the fire. Built the first time something
/// burns, with [`FirePlume::settings`]; cost is bounded by its grid whatever the number of
/// cloths, and nothing while no fire burns and the air has settled.
#[derive(Resource, Debug, Default)]
pub struct FirePlume {
    settings: PlumeSettings,
    plume: Option<Plume>,
    colliders: Vec<WorldCollider>,
    /// Time the latest plume step took (feeding included).
    pub last_step: Duration,
}

impl FirePlume {
    /// A plume with these settings (checked when it is built; invalid ones are logged and the
    /// defaults used).
    pub fn new(settings: PlumeSettings) -> Self {
        Self {
            settings,
            ..Default::default()
        }
    }

    /// The settings the plume is (or will be) built with.
    pub fn settings(&self) -> &PlumeSettings {
        &self.settings
    }

    /// Replaces the settings if they are valid. New rates and strengths take effect at once
    /// on the moving air ([`Plume::retune`]); a new grid (resolution, cell size, walls)
    /// restarts the air still, in a new box, the next time it is needed.
    pub fn set_settings(&mut self, settings: PlumeSettings) -> Result<(), PlumeSettingsError> {
        settings.validate()?;
        if let Some(plume) = &mut self.plume
            && plume.retune(settings).is_err()
        {
            self.plume = None;
        }
        self.settings = settings;
        Ok(())
    }

    /// The air, once something has burnt.
    pub fn plume(&self) -> Option<&Plume> {
        self.plume.as_ref()
    }

    /// The air if it is moving or hot (`None` while it sleeps).
    pub fn active(&self) -> Option<&Plume> {
        self.plume.as_ref().filter(|p| !p.is_quiet())
    }

    /// What the latest step did.
    pub fn report(&self) -> PlumeReport {
        self.plume.as_ref().map(|p| *p.report()).unwrap_or_default()
    }
}

/// Plume diagnostics, read by `LogDiagnosticsPlugin` and the panel.
pub struct PlumeDiagnostics;

impl PlumeDiagnostics {
    /// Time of one plume step (feeding, advection, forces, projection), ms.
    pub const STEP: DiagnosticPath = DiagnosticPath::const_new("burning_cloth/plume_step");
    /// Conjugate-gradient iterations of the latest pressure solve.
    pub const ITERATIONS: DiagnosticPath =
        DiagnosticPath::const_new("burning_cloth/plume_iterations");
}

/// The plume's systems: after [`BurningClothSystems::Report`] the burning cloths feed it and
/// it steps; before [`BurningClothSystems::Simulate`] it blows on and heats the cloths.
#[derive(SystemSet, Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum PlumeSystems {
    /// The plume pushes and warms the cloths for the coming step.
    OnCloth,
    /// The burning cloths feed the plume, which then steps.
    Step,
}

/// The fire's air (feature `fluid`). Part of `BurningClothPlugins`; needs `SmokePlugin`'s
/// particles to carry smoke (they ride the plume when both are in). Insert a [`FirePlume`]
/// with your [`PlumeSettings`] before adding it to change the box; remove the plugin from
/// the group (`.disable::<FluidPlugin>()`) for a scene that needs no plume.
pub struct FluidPlugin {
    /// The schedule the simulation steps in.
    pub schedule: Interned<dyn ScheduleLabel>,
}

impl Default for FluidPlugin {
    fn default() -> Self {
        Self {
            schedule: FixedUpdate.intern(),
        }
    }
}

impl Plugin for FluidPlugin {
    fn build(&self, app: &mut App) {
        app.init_resource::<FirePlume>()
            .register_type::<PlumeSettings>()
            .register_diagnostic(Diagnostic::new(PlumeDiagnostics::STEP).with_suffix("ms"))
            .register_diagnostic(Diagnostic::new(PlumeDiagnostics::ITERATIONS))
            .configure_sets(
                self.schedule,
                (
                    PlumeSystems::OnCloth
                        .after(BurningClothSystems::Prepare)
                        .before(BurningClothSystems::Simulate),
                    PlumeSystems::Step
                        .after(BurningClothSystems::Report)
                        .before(crate::plugin::consume_pending_step),
                ),
            )
            .configure_sets(
                self.schedule,
                (PlumeSystems::OnCloth, PlumeSystems::Step)
                    .run_if(crate::plugin::simulation_is_running),
            )
            .configure_sets(
                self.schedule,
                PlumeSystems::Step.before(crate::smoke::SmokeSystems),
            )
            .add_systems(self.schedule, plume_on_cloth.in_set(PlumeSystems::OnCloth))
            .add_systems(self.schedule, step_plume.in_set(PlumeSystems::Step));
    }
}

/// The box's minimum corner for a fire centred at `centre`: centred across, the fire a
/// quarter of the way up so the plume has room to rise.
fn origin_for(settings: &PlumeSettings, centre: Vec3) -> Vec3 {
    let size = Vec3::new(
        settings.resolution[0] as f32,
        settings.resolution[1] as f32,
        settings.resolution[2] as f32,
    ) * settings.cell_size;
    centre - size * Vec3::new(0.5, 0.25, 0.5)
}

/// Builds the plume when a fire first burns, moves it after the fire, feeds it from every
/// burning cloth and steps it.
fn step_plume(
    time: Res<Time>,
    environment: Res<ClothEnvironment>,
    colliders: Res<ClothColliders>,
    mut fire: ResMut<FirePlume>,
    mut diagnostics: Diagnostics,
    cloths: Query<(&ClothParticles, &ClothInUse, &ClothTopology, &ClothStatus)>,
) {
    let started = Instant::now();
    let dt = time.delta_secs();
    // Only cloths with something on fire feed the plume or place it: no particle loop while
    // nothing burns.
    let burning_cloths = || {
        cloths
            .iter()
            .filter(|(.., status)| status.ignited > 0)
            .map(|(particles, in_use, topology, _)| (particles, in_use, topology))
    };
    // The burning region: the mean of the burning particles, weighted by intensity.
    let (mut sum, mut weight) = (Vec3::ZERO, 0.0f32);
    for (particles, in_use, topology) in burning_cloths() {
        let cloth = BurningCloth::new(particles, in_use.material(), topology, &[]);
        for i in 0..particles.len() {
            let w = cloth.intensity(i);
            if w > 0.0 && particles.position[i].is_finite() {
                sum += particles.position[i] * w;
                weight += w;
            }
        }
    }
    let burning = weight > 0.0;
    if !burning && fire.active().is_none() {
        fire.last_step = Duration::ZERO;
        return;
    }
    let fire = &mut *fire;
    if fire.plume.is_none() {
        let settings = match fire.settings.validate() {
            Ok(()) => fire.settings,
            Err(error) => {
                warn!("FirePlume: {error}; default settings used");
                fire.settings = PlumeSettings::default();
                fire.settings
            }
        };
        let centre = if burning { sum / weight } else { Vec3::ZERO };
        fire.plume = Plume::new(settings, origin_for(&settings, centre)).ok();
        fire.colliders.clear();
    }
    let Some(plume) = fire.plume.as_mut() else {
        return;
    };
    // Follow the fire, two cells of slack so the box does not jitter.
    let mut moved = false;
    if burning {
        let target = origin_for(plume.settings(), sum / weight);
        if (target - plume.shape().origin).abs().max_element() > 2.0 * plume.shape().cell {
            moved = plume.move_towards(target);
        }
    }
    if moved || fire.colliders != colliders.0 {
        fire.colliders.clone_from(&colliders.0);
        let solids = &fire.colliders;
        plume.set_solids(|p| solids.iter().any(|c| c.distance(p).0 < 0.0));
    }
    for (particles, in_use, topology) in burning_cloths() {
        let cloth = BurningCloth::new(particles, in_use.material(), topology, &[]);
        feed_plume(plume, &cloth, in_use.material(), &particles.mass, dt);
    }
    let air = crate::smoke::air(&environment);
    let pool = bevy::tasks::ComputeTaskPool::try_get().map(|p| &**p);
    let report = plume.step_on(dt, air.wind, air.up, pool);
    fire.last_step = started.elapsed();
    let milliseconds = fire.last_step.as_secs_f64() * 1e3;
    diagnostics.add_measurement(&PlumeDiagnostics::STEP, || milliseconds);
    diagnostics.add_measurement(&PlumeDiagnostics::ITERATIONS, || {
        f64::from(report.solve.iterations)
    });
}

/// The plume blows on every cloth in it (as wind, through the cloth's drag) and heats it
/// (unless `FireSpread` is off: the plume is how fire jumps through the air).
fn plume_on_cloth(
    time: Res<Time>,
    fire: Res<FirePlume>,
    spread: Option<Res<FireSpread>>,
    mut cloths: Query<(&mut ClothParticles, &ClothInUse)>,
) {
    let Some(plume) = fire.active() else {
        return;
    };
    let heating = spread.is_none_or(|s| s.enabled);
    let dt = time.delta_secs();
    let pool = bevy::tasks::ComputeTaskPool::try_get().map(|p| &**p);
    for (mut particles, in_use) in &mut cloths {
        let material = in_use.material();
        blow_and_heat_on(
            plume,
            &mut particles,
            material,
            [material.initial_temperature, dt],
            heating,
            pool,
        );
    }
}
