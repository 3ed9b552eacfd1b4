//! System sets and the substep schedule.
//!
//! Each step of the simulation schedule (default `FixedUpdate`) runs the chained sets of
//! [`BurningClothSystems`]. Its `Simulate` set runs [`ClothSubstepSchedule`] once per
//! substep, whose chained [`ClothSubstepSystems`] move the cloth. Order your own systems
//! against these sets; add gameplay forces to `ClothParticles::external_force` in
//! [`ClothSubstepSystems::Forces`].

use bevy::ecs::schedule::ScheduleLabel;
use bevy::prelude::*;

/// The chained sets of one simulation step.
#[derive(SystemSet, Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum BurningClothSystems {
    /// Applies material and solver changes, moves pins with their entity, picks substeps.
    Prepare,
    /// Heat spreads: the paper's upward push and proximity heating.
    Heat,
    /// Particles ignite and burn by temperature; rest lengths shrink; events are sent.
    Combust,
    /// Runs [`ClothSubstepSchedule`] once per substep.
    Simulate,
    /// Rebuilds each cloth's index list from the unburnt particles.
    Cull,
}

/// The schedule run once per substep inside [`BurningClothSystems::Simulate`].
#[derive(ScheduleLabel, Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ClothSubstepSchedule;

/// The chained sets of one substep.
#[derive(SystemSet, Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ClothSubstepSystems {
    /// Force parameters are refreshed; add external forces here.
    Forces,
    /// The integrator advances each cloth.
    Integrate,
    /// Provot's correction limits stretch.
    Constrain,
}

/// Which substep is running. Cloths need different substep counts: a cloth takes part in
/// substeps `0..ClothStatus::substeps` with a step of `dt / substeps` each.
#[derive(Resource, Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SubstepCounter {
    /// Index of the running substep.
    pub index: u32,
    /// Substeps run in this step: the most any cloth needs.
    pub count: u32,
}
