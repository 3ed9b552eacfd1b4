//! Heat from gameplay: [`HeatSource`] on any entity, and fire spreading from one cloth to
//! the cloths near it ([`FireSpread`]).

use super::ClothEnvironment;
use super::components::ClothParticles;
use crate::sim::heat_sources::{HashedHeatSources, WorldHeatSource};
use bevy::prelude::*;

/// A heat source on any entity with a `Transform`: a torch, a fireball, a lava tile, a
/// candle. Every unburnt cloth particle within `radius` of the entity's position is heated
/// towards `temperature` at `rate` (1/s) at the centre, falling off as
/// `(1 − distance / radius)^falloff`; hot enough, it ignites. Moving sources work: the
/// position is read every step. Invalid values are logged once and the source skipped.
#[derive(Component, Clone, Copy, Debug, PartialEq, Reflect)]
#[reflect(Component, Clone, Debug, PartialEq)]
#[require(Transform)]
pub struct HeatSource {
    /// Reach, m.
    pub radius: f32,
    /// Temperature it heats towards, °C.
    pub temperature: f32,
    /// Heating rate at the centre, 1/s: a particle there closes `1 − e^(−rate·t)` of its gap
    /// to `temperature` in `t` seconds.
    pub rate: f32,
    /// Falloff exponent: 0 heats evenly over the sphere, 1 linearly less towards its edge.
    pub falloff: f32,
}

impl Default for HeatSource {
    /// A torch flame: 12 cm reach, 900 °C, rate 3/s, linear falloff.
    fn default() -> Self {
        Self {
            radius: 0.12,
            temperature: 900.0,
            rate: 3.0,
            falloff: 1.0,
        }
    }
}

impl HeatSource {
    /// A source of `radius` (m) at `temperature` (°C), default rate and falloff.
    pub fn new(radius: f32, temperature: f32) -> Self {
        Self {
            radius,
            temperature,
            ..Self::default()
        }
    }

    /// With heating rate `rate` (1/s).
    pub fn with_rate(mut self, rate: f32) -> Self {
        self.rate = rate;
        self
    }

    /// With falloff exponent `falloff`.
    pub fn with_falloff(mut self, falloff: f32) -> Self {
        self.falloff = falloff;
        self
    }
}

/// How fire jumps between separate cloths: every burning particle heats the particles of
/// *other* cloths within `radius` of a point `radius / 2` above it (fire reaches up more than
/// sideways), towards its own temperature at `rate` (1/s). A cloth's own particles heat each
/// other through its heat model, not through this.
#[derive(Resource, Clone, Copy, Debug, PartialEq, Reflect)]
#[reflect(Resource, Clone, Debug, PartialEq)]
pub struct FireSpread {
    /// Whether fire jumps between cloths at all.
    pub enabled: bool,
    /// Reach of a burning particle, m.
    pub radius: f32,
    /// Heating rate at the centre, 1/s.
    pub rate: f32,
}

impl Default for FireSpread {
    fn default() -> Self {
        Self {
            enabled: true,
            radius: 0.08,
            rate: 2.0,
        }
    }
}

/// Heat sources in world space, gathered once per step.
#[derive(Resource, Clone, Debug, Default)]
pub struct ClothHeatSources {
    /// Every valid [`HeatSource`].
    pub explicit: Vec<WorldHeatSource>,
    /// Every burning particle of every cloth, hashed.
    pub burning: HashedHeatSources,
}

/// Collects every [`HeatSource`] in world space (Prepare).
pub(crate) fn gather_heat_sources(
    mut cache: ResMut<ClothHeatSources>,
    sources: Query<(Entity, &HeatSource, &GlobalTransform)>,
) {
    cache.explicit.clear();
    for (entity, source, transform) in &sources {
        let world = WorldHeatSource {
            centre: transform.translation(),
            radius: source.radius,
            temperature: source.temperature,
            rate: source.rate,
            falloff: source.falloff,
            owner: WorldHeatSource::NO_OWNER,
        };
        if world.is_valid() {
            cache.explicit.push(world);
        } else {
            warn_once!(
                "HeatSource on {entity} skipped: invalid radius, temperature, rate, falloff or position"
            );
        }
    }
}

/// Hashes the burning particles of every cloth as small heat sources for the other cloths
/// (Prepare): from the state the previous step left, so every cloth steps against the same
/// fires whatever order the cloths step in.
pub(crate) fn gather_burning_particles(
    spread: Res<FireSpread>,
    environment: Res<ClothEnvironment>,
    mut cache: ResMut<ClothHeatSources>,
    cloths: Query<(Entity, &ClothParticles)>,
) {
    let cache = &mut *cache;
    cache.burning.clear();
    let spreading = spread.enabled
        && spread.radius.is_finite()
        && spread.radius > 0.0
        && spread.rate.is_finite()
        && spread.rate > 0.0
        && cloths.iter().nth(1).is_some();
    if !spreading {
        return;
    }
    let up = environment.unit_up() * (0.5 * spread.radius);
    for (entity, particles) in &cloths {
        let owner = entity.to_bits();
        for ((p, t), s) in particles
            .position
            .iter()
            .zip(&particles.temperature)
            .zip(&particles.state)
        {
            if s.is_ignited() {
                cache.burning.push(WorldHeatSource {
                    centre: *p + up,
                    radius: spread.radius,
                    temperature: *t,
                    rate: spread.rate,
                    falloff: 1.0,
                    owner,
                });
            }
        }
    }
    cache.burning.rebuild();
}
