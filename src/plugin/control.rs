//! Pausing, single-stepping and timing the simulation of every cloth.

use bevy::platform::time::Instant;
use bevy::prelude::*;
use std::time::Duration;

/// Pauses or single-steps every cloth (and its smoke). While `paused`, a step runs only for
/// each of `pending_steps`, which [`ClothSimulationControl::step_once`] adds to. Rendering,
/// picking and [`Ignite`](super::Ignite) keep working while paused.
#[derive(Resource, Clone, Copy, Debug, Default, PartialEq, Eq, Reflect)]
#[reflect(Resource, Default, Clone, Debug, PartialEq)]
pub struct ClothSimulationControl {
    /// Whether the simulation is stopped.
    pub paused: bool,
    /// Steps still to run while paused.
    pub pending_steps: u32,
}

impl ClothSimulationControl {
    /// Asks for one more step while paused.
    pub fn step_once(&mut self) {
        self.pending_steps = self.pending_steps.saturating_add(1);
    }
}

/// Run condition: true unless the simulation is paused with no single step pending.
pub fn simulation_is_running(control: Option<Res<ClothSimulationControl>>) -> bool {
    control.is_none_or(|control| !control.paused || control.pending_steps > 0)
}

/// Wall-clock cost of the last simulation step of all cloths (gathering, every cloth's step,
/// status and events; not smoke or drawing).
#[derive(Resource, Clone, Copy, Debug, Default, PartialEq)]
pub struct ClothStepTiming {
    /// Wall time of the last step.
    pub last_step: Duration,
    /// The most substeps any cloth took in it.
    pub substeps: u32,
    /// Steps timed since the app started.
    pub steps: u64,
    started: Option<Instant>,
}

impl ClothStepTiming {
    /// Wall time per substep of the last step.
    pub fn per_substep(&self) -> Duration {
        self.last_step / self.substeps.max(1)
    }
}

/// First system of a step: starts the clock.
pub(crate) fn start_step_timer(mut timing: ResMut<ClothStepTiming>) {
    timing.started = Some(Instant::now());
}

/// Last system of a cloth step: stops the clock.
pub(crate) fn finish_step_timer(mut timing: ResMut<ClothStepTiming>) {
    if let Some(started) = timing.started.take() {
        timing.last_step = started.elapsed();
        timing.steps += 1;
    }
}

/// After everything that steps with the cloths (smoke too): uses up a pending single step.
pub(crate) fn consume_pending_step(mut control: ResMut<ClothSimulationControl>) {
    if control.paused && control.pending_steps > 0 {
        control.pending_steps -= 1;
    }
}
