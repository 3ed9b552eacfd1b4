//! The simulation's system sets.
//!
//! Each step of the simulation schedule (default `FixedUpdate`) runs the chained sets of
//! [`BurningClothSystems`]: the world is gathered, every cloth steps (the phases of
//! [`ClothMut::step`](crate::sim::ClothMut::step), in the order defined there), then status
//! and events are written. Order your own systems against these sets: add gameplay forces to
//! `ClothParticles::external_force` before [`BurningClothSystems::Simulate`] (they act for the
//! whole step), read results after [`BurningClothSystems::Report`].

use bevy::prelude::*;

/// The chained sets of one simulation step.
#[derive(SystemSet, Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum BurningClothSystems {
    /// Colliders, heat sources and burning particles are gathered in world space; valid
    /// material, solver and environment changes are taken into use.
    Prepare,
    /// Every cloth steps: pins, heat, combustion, dynamics, culling.
    Simulate,
    /// [`ClothStatus`](super::ClothStatus) is updated and events are triggered.
    Report,
}
