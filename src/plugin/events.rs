//! Events in and out of the simulation: [`Ignite`] asks a cloth to catch fire;
//! [`ClothIgnited`] and [`ClothBurntOut`] tell gameplay what happened.

use super::components::{ClothParticles, PendingIgnitions};
use crate::sim::{self, BurnMaterial, ClothBuilder, ClothError};
use bevy::prelude::*;

/// Where on a cloth an [`Ignite`] lands.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum IgniteAt {
    /// A particle by index.
    Particle(usize),
    /// The unburnt particle nearest to a world point (m).
    WorldPoint(Vec3),
}

/// Sets a cloth alight: the target particle is raised to `temperature` (default: the
/// material's seed temperature, the paper's 1000 °F) if it is colder.
///
/// Trigger it with `commands.trigger(Ignite::at_world_point(cloth, point))`. A request on an
/// entity that is not a cloth (or no longer exists), at an index out of range, at a
/// non-finite point or with an invalid temperature is logged as a warning and ignored. A
/// request on a cloth whose [`ClothBuilder`] has not been built yet is kept until it is.
#[derive(EntityEvent, Clone, Copy, Debug, PartialEq)]
pub struct Ignite {
    /// The cloth entity.
    pub entity: Entity,
    /// Where on the cloth.
    pub at: IgniteAt,
    /// Temperature to raise the particle to, °C; `None` uses the material's seed temperature.
    pub temperature: Option<f32>,
}

impl Ignite {
    /// Ignites particle `index` of `cloth`.
    pub fn particle(cloth: Entity, index: usize) -> Self {
        Self {
            entity: cloth,
            at: IgniteAt::Particle(index),
            temperature: None,
        }
    }

    /// Ignites the particle of `cloth` nearest to `point` (world space, m).
    pub fn at_world_point(cloth: Entity, point: Vec3) -> Self {
        Self {
            entity: cloth,
            at: IgniteAt::WorldPoint(point),
            temperature: None,
        }
    }

    /// Uses `celsius` instead of the material's seed temperature.
    pub fn with_temperature(mut self, celsius: f32) -> Self {
        self.temperature = Some(celsius);
        self
    }
}

/// Triggered on a cloth when it catches fire (no particle was burning, now one is).
#[derive(EntityEvent, Clone, Copy, Debug, PartialEq, Eq)]
pub struct ClothIgnited {
    /// The cloth entity.
    pub entity: Entity,
}

/// Triggered on a cloth when its fire goes out: nothing is burning any more.
/// `burnt_fraction` is 1 when the cloth has burnt away completely.
#[derive(EntityEvent, Clone, Copy, Debug, PartialEq)]
pub struct ClothBurntOut {
    /// The cloth entity.
    pub entity: Entity,
    /// Fraction of particles burnt away, in [0, 1].
    pub burnt_fraction: f32,
}

/// Triggered on a cloth when the blow-up guard had to put particles back this step: the
/// solver went past its stability limit (stiffness too high for the substeps, a violent
/// impulse) or something wrote NaN into the cloth. The cloth stays finite; raise substeps,
/// lower stiffness, or look for the NaN.
#[derive(EntityEvent, Clone, Copy, Debug, PartialEq, Eq)]
pub struct ClothInstability {
    /// The cloth entity.
    pub entity: Entity,
    /// Particles put back this step.
    pub repaired: u32,
}

/// Applies one ignition to a cloth's particles.
pub(crate) fn apply_ignition(
    particles: &mut sim::Particles,
    material: &BurnMaterial,
    at: IgniteAt,
    temperature: Option<f32>,
) -> Result<usize, ClothError> {
    let index = match at {
        IgniteAt::Particle(index) => index,
        IgniteAt::WorldPoint(point) => sim::cloth::nearest_unburnt_particle(particles, point)?,
    };
    let temperature = temperature.unwrap_or(material.seed_temperature);
    sim::cloth::heat_particle(particles, index, temperature)?;
    Ok(index)
}

/// Observer of [`Ignite`].
pub(crate) fn on_ignite(
    ignite: On<Ignite>,
    mut cloths: Query<(&mut ClothParticles, Option<&BurnMaterial>)>,
    mut pending: Query<Option<&mut PendingIgnitions>, With<ClothBuilder>>,
    mut commands: Commands,
) {
    let event = *ignite.event();
    if let Ok((mut particles, material)) = cloths.get_mut(event.entity) {
        let material = material.copied().unwrap_or_default();
        if let Err(error) = apply_ignition(&mut particles, &material, event.at, event.temperature) {
            warn!("Ignite on cloth {} ignored: {error}", event.entity);
        }
    } else if let Ok(queue) = pending.get_mut(event.entity) {
        match queue {
            Some(mut queue) => queue.0.push(event),
            None => {
                commands
                    .entity(event.entity)
                    .insert(PendingIgnitions(vec![event]));
            }
        }
    } else {
        warn!(
            "Ignite ignored: entity {} is not a cloth (despawned, or never had a ClothBuilder)",
            event.entity
        );
    }
}
