//! Events in and out of the simulation: [`Ignite`] asks a cloth to catch fire;
//! [`ClothIgnited`] and [`ClothBurntOut`] tell gameplay what happened.

use super::components::{ClothInUse, ClothParticles, PendingIgnitions};
use crate::sim::{self, BurnMaterial, ClothBuilder, ClothError, MeshClothBuilder};
use bevy::prelude::*;

/// Where on a cloth an [`Ignite`] lands.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum IgniteAt {
    /// A particle by index.
    Particle(usize),
    /// The unburnt particle nearest to a world point (m).
    WorldPoint(Vec3),
}

/// Sets a cloth alight: the target particle, and every unburnt particle within
/// [`sim::ignition::IGNITION_RADIUS`] (3 cm) of it, is raised to `temperature` (default: the
/// material's seed temperature, the paper's 1000 °F) where colder.
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

/// Puts a fire out: cools the cloth's unburnt particles within a region (or all of them)
/// below ignition, so they stop burning; burnt holes stay. Water, a spell, a sprinkler.
///
/// The default temperature is
/// [`extinguished_temperature`](sim::combustion::extinguished_temperature): just below ignition, so
/// the doused cloth keeps its scorch and char. Heat from a fire still burning elsewhere can relight
/// it. A request on an entity that is not a built cloth, with a non-finite region or an invalid
/// temperature is logged and ignored.
#[derive(EntityEvent, Clone, Copy, Debug, PartialEq)]
pub struct Extinguish {
    /// The cloth entity.
    pub entity: Entity,
    /// World centre and radius (m) of the region; `None` for the whole cloth.
    pub region: Option<(Vec3, f32)>,
    /// Temperature to cool to, °C; `None` for just below the material's ignition.
    pub temperature: Option<f32>,
}

impl Extinguish {
    /// Puts out the whole cloth.
    pub fn all(cloth: Entity) -> Self {
        Self {
            entity: cloth,
            region: None,
            temperature: None,
        }
    }

    /// Puts out the cloth within `radius` (m) of the world point `centre`.
    pub fn within(cloth: Entity, centre: Vec3, radius: f32) -> Self {
        Self {
            entity: cloth,
            region: Some((centre, radius)),
            temperature: None,
        }
    }

    /// Cools to `celsius` (at most the ignition temperature) instead of just below ignition.
    pub fn to_temperature(mut self, celsius: f32) -> Self {
        self.temperature = Some(celsius);
        self
    }
}

/// Applies [`Extinguish`] to a built cloth.
pub(crate) fn on_extinguish(
    extinguish: On<Extinguish>,
    mut cloths: Query<(&mut ClothParticles, &ClothInUse)>,
) {
    let event = *extinguish.event();
    let Ok((mut particles, in_use)) = cloths.get_mut(event.entity) else {
        warn!(
            "Extinguish ignored: entity {} is not a built cloth",
            event.entity
        );
        return;
    };
    if let Some((centre, radius)) = event.region
        && !(centre.is_finite() && radius.is_finite() && radius >= 0.0)
    {
        warn!(
            "Extinguish on cloth {} ignored: bad region {centre} r {radius}",
            event.entity
        );
        return;
    }
    let material = in_use.material();
    let to = event
        .temperature
        .unwrap_or_else(|| sim::combustion::extinguished_temperature(material));
    if !sim::material::valid_temperature(to) {
        warn!(
            "Extinguish on cloth {} ignored: bad temperature {to}",
            event.entity
        );
        return;
    }
    let particles = &mut particles.0;
    sim::combustion::extinguish(
        &particles.position,
        &mut particles.temperature,
        &mut particles.state,
        material,
        event.region,
        to,
    );
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

/// Triggered on a cloth when burning cuts a piece of it loose from every pin: the piece falls
/// (and keeps burning) from now on. Once per piece; a loose piece splitting again does not
/// trigger it. For a sound, a score, or to hand the piece to gameplay.
#[derive(EntityEvent, Clone, Copy, Debug, PartialEq)]
pub struct ClothPieceDetached {
    /// The cloth entity.
    pub entity: Entity,
    /// Particles in the piece.
    pub particles: u32,
    /// Its centroid when it came loose, world space, m.
    pub centroid: Vec3,
}

/// Triggered on a cloth in every step in which some of its particles burnt away: how many,
/// and where (world centroid of those particles). For sound, score, or spreading fire to
/// props that are not cloth.
#[derive(EntityEvent, Clone, Copy, Debug, PartialEq)]
pub struct ClothParticlesBurnt {
    /// The cloth entity.
    pub entity: Entity,
    /// Particles that burnt away in this step.
    pub count: u32,
    /// Their centroid, world space, m.
    pub centroid: Vec3,
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
        IgniteAt::WorldPoint(point) => sim::ignition::nearest_unburnt_particle(particles, point)?,
    };
    let temperature = temperature.unwrap_or(material.seed_temperature);
    sim::ignition::ignite_patch(particles, index, temperature)?;
    Ok(index)
}

/// Observer of [`Ignite`].
pub(crate) fn on_ignite(
    ignite: On<Ignite>,
    mut cloths: Query<(&mut ClothParticles, &ClothInUse)>,
    mut pending: Query<
        Option<&mut PendingIgnitions>,
        Or<(With<ClothBuilder>, With<MeshClothBuilder>)>,
    >,
    mut commands: Commands,
) {
    let event = *ignite.event();
    if let Ok((mut particles, in_use)) = cloths.get_mut(event.entity) {
        let material = in_use.material();
        if let Err(error) = apply_ignition(&mut particles, material, event.at, event.temperature) {
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
