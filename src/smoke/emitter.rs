//! Emission from a burning cloth and the motion of the particles: plain functions over the
//! pool, no ECS.

use super::pool::{NewParticle, SmokeKind, SmokePool};
use super::settings::{KindSettings, SmokeSettings, SmokeSettingsError};
use super::turbulence::{LANES, Turbulence, random_unit};
use crate::sim::{BurnMaterial, BurnState, ClothSim, Particles, Topology};
use glam::Vec3;
use rand::rngs::SmallRng;
use rand::{RngExt, SeedableRng};

/// What an emitter reads from its cloth each step.
#[derive(Clone, Copy, Debug)]
pub struct BurningCloth<'a> {
    /// Particle positions, m.
    pub position: &'a [Vec3],
    /// Particle temperatures, °C.
    pub temperature: &'a [f32],
    /// Particle burn states.
    pub state: &'a [BurnState],
    /// Particles that burnt away in this step (they throw embers).
    pub newly_burnt: &'a [u32],
    /// The material's ignition temperature, °C.
    pub ignition_temperature: f32,
    /// The material's burnt temperature, °C.
    pub burnt_temperature: f32,
    /// Cloth area each particle stands for, m².
    pub area_per_particle: f32,
}

impl<'a> BurningCloth<'a> {
    /// The burning state of a cloth's parts; `newly_burnt` lists the particles that burnt
    /// away in the latest step (`StepOutcome::newly_burnt`).
    pub fn new(
        particles: &'a Particles,
        material: &BurnMaterial,
        topology: &Topology,
        newly_burnt: &'a [u32],
    ) -> Self {
        Self {
            position: &particles.position,
            temperature: &particles.temperature,
            state: &particles.state,
            newly_burnt,
            ignition_temperature: material.ignition_temperature,
            burnt_temperature: material.burnt_temperature,
            area_per_particle: topology.spacing * topology.spacing,
        }
    }

    /// The burning state of a [`ClothSim`] after its latest step.
    pub fn of(sim: &'a ClothSim) -> Self {
        Self::new(
            &sim.particles,
            sim.material(),
            &sim.topology,
            sim.newly_burnt(),
        )
    }

    /// How hard particle `i` burns, in [0.1, 1]: where its temperature sits between
    /// ignition and burning away. Zero for particles not on fire.
    pub fn intensity(&self, i: usize) -> f32 {
        if !self.state[i].is_ignited() {
            return 0.0;
        }
        let span = (self.burnt_temperature - self.ignition_temperature).max(1e-3);
        ((self.temperature[i] - self.ignition_temperature) / span).clamp(0.1, 1.0)
    }
}

/// Slots of the pool [`SmokeSim::advance_in`] passes over at once when none is alive.
const DEAD_RUN: usize = 32;

/// Share of the curl-noise turbulence kept inside a simulated plume, whose grid resolves the
/// large eddies itself: the rest is detail smaller than a cell.
const SUBGRID_EDDIES: f32 = 0.35;

/// The air particles move in.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Air {
    /// Wind velocity, m/s (the cloth's wind).
    pub wind: Vec3,
    /// Gravitational acceleration, m/s².
    pub gravity: Vec3,
    /// World up, unit vector.
    pub up: Vec3,
}

impl Default for Air {
    fn default() -> Self {
        Self {
            wind: Vec3::ZERO,
            gravity: Vec3::new(0.0, -9.81, 0.0),
            up: Vec3::Y,
        }
    }
}

/// Births and deaths in one call of [`SmokeSim::emit`] or [`SmokeSim::advance`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SmokeCounts {
    /// Particles born, by kind.
    pub born: [u32; 3],
    /// Particles that died of age or went non-finite.
    pub died: u32,
}

/// One emitter: its settings, particle pool, random numbers, turbulence and clock.
#[derive(Clone, Debug)]
pub struct SmokeSim {
    settings: SmokeSettings,
    /// The particles.
    pub pool: SmokePool,
    rng: SmallRng,
    turbulence: Turbulence,
    /// Seconds simulated.
    pub time: f32,
}

impl SmokeSim {
    /// An emitter with validated settings; the pool is allocated here, once.
    pub fn new(settings: SmokeSettings) -> Result<Self, SmokeSettingsError> {
        settings.validate()?;
        let mut rng = SmallRng::seed_from_u64(settings.seed);
        let turbulence = Turbulence::new(&mut rng, settings.eddy_size, settings.eddy_rate);
        Ok(Self {
            pool: SmokePool::with_capacity(settings.capacity),
            settings,
            rng,
            turbulence,
            time: 0.0,
        })
    }

    /// The settings in use.
    pub fn settings(&self) -> &SmokeSettings {
        &self.settings
    }

    /// Replaces the settings after validating them. Live particles keep flying; the pool is
    /// reallocated (and cleared) only when the capacity changes, the turbulence redrawn only
    /// when the seed or eddies change.
    pub fn set_settings(&mut self, settings: SmokeSettings) -> Result<(), SmokeSettingsError> {
        settings.validate()?;
        if settings.capacity != self.settings.capacity {
            self.pool = SmokePool::with_capacity(settings.capacity);
        }
        if (settings.seed, settings.eddy_size, settings.eddy_rate)
            != (
                self.settings.seed,
                self.settings.eddy_size,
                self.settings.eddy_rate,
            )
        {
            self.rng = SmallRng::seed_from_u64(settings.seed);
            self.turbulence =
                Turbulence::new(&mut self.rng, settings.eddy_size, settings.eddy_rate);
        }
        self.settings = settings;
        Ok(())
    }

    /// Births over `dt` seconds: flames and smoke from every ignited, unburnt particle at a
    /// rate proportional to how hard it burns and the area it stands for; embers from the
    /// particles that burnt away this step, by the area each stood for. A cloth with nothing
    /// on fire emits nothing.
    pub fn emit(&mut self, cloth: &BurningCloth, air: &Air, dt: f32) -> SmokeCounts {
        let mut counts = SmokeCounts::default();
        if !(dt.is_finite() && dt > 0.0) {
            return counts;
        }
        let up = air.up.normalize_or(Vec3::Y);
        let area = if cloth.area_per_particle.is_finite() {
            cloth.area_per_particle.max(0.0)
        } else {
            0.0
        };
        let len = cloth
            .position
            .len()
            .min(cloth.temperature.len())
            .min(cloth.state.len());
        for i in 0..len {
            let intensity = cloth.intensity(i);
            if intensity == 0.0 {
                continue;
            }
            let source = cloth.position[i];
            if !source.is_finite() {
                continue;
            }
            let temperature = cloth.temperature[i];
            for kind in [SmokeKind::Flame, SmokeKind::Smoke] {
                let mean = self.settings.of(kind).rate * area * intensity * dt;
                let count = self.draw_count(mean);
                for _ in 0..count {
                    self.spawn(kind, source, temperature, up);
                }
                counts.born[kind as usize] += count;
            }
        }
        // Embers per square metre burnt away: the same sparks per hole at any spacing.
        let embers_per_particle = self.settings.of(SmokeKind::Ember).rate * area;
        for &i in cloth.newly_burnt {
            let Some(&source) = cloth.position.get(i as usize) else {
                continue;
            };
            if !source.is_finite() {
                continue;
            }
            let count = self.draw_count(embers_per_particle);
            for _ in 0..count {
                self.spawn(
                    SmokeKind::Ember,
                    source,
                    cloth.burnt_temperature.min(1500.0),
                    up,
                );
            }
            counts.born[SmokeKind::Ember as usize] += count;
        }
        counts
    }

    /// A whole number of births with mean `mean`: its integer part, plus one with the
    /// probability of its fraction.
    fn draw_count(&mut self, mean: f32) -> u32 {
        if !(mean.is_finite() && mean > 0.0) {
            return 0;
        }
        let mean = mean.min(1e4);
        let whole = mean.floor();
        let extra = u32::from(self.rng.random::<f32>() < mean - whole);
        whole as u32 + extra
    }

    fn spawn(&mut self, kind: SmokeKind, source: Vec3, temperature: f32, up: Vec3) {
        let settings = *self.settings.of(kind);
        let radius = self.settings.birth_radius * self.rng.random::<f32>().cbrt();
        let position = source + random_unit(&mut self.rng) * radius;
        let velocity = up * settings.rise_speed
            + random_unit(&mut self.rng) * settings.spread_speed * self.rng.random::<f32>();
        let [shortest, longest] = settings.lifetime;
        let lifetime = if longest > shortest {
            self.rng.random_range(shortest..longest)
        } else {
            shortest
        };
        let scale = self.rng.random_range(0.7..1.3);
        self.pool.spawn(NewParticle {
            kind,
            position,
            velocity,
            temperature: if temperature.is_finite() {
                temperature
            } else {
                self.settings.ambient_temperature
            },
            lifetime,
            scale,
        });
    }

    /// Moves every live particle `dt` seconds: it ages (and dies at the end of its life),
    /// cools towards ambient, is lifted by buoyancy, pulled by its share of gravity, and
    /// dragged towards the air's velocity (wind plus curl-noise turbulence). The velocity
    /// update is implicit in the drag, so any `dt` is stable.
    pub fn advance(&mut self, air: &Air, dt: f32) -> SmokeCounts {
        self.advance_in(air, |_| None, dt)
    }

    /// [`SmokeSim::advance`] in a moving air: where `flow(position)` gives a velocity (m/s,
    /// relative to the wind; a simulated plume), particles are carried by it, curl noise
    /// adds only sub-grid detail, and their own buoyancy is off (the plume's air is what
    /// rises); where it gives `None`, they move as in still air.
    pub fn advance_in(
        &mut self,
        air: &Air,
        flow: impl Fn(Vec3) -> Option<Vec3>,
        dt: f32,
    ) -> SmokeCounts {
        let mut counts = SmokeCounts::default();
        if !(dt.is_finite() && dt > 0.0) {
            return counts;
        }
        let up = air.up.normalize_or(Vec3::Y);
        let ambient = self.settings.ambient_temperature;
        let time = self.time;
        let cooled: [f32; 3] =
            core::array::from_fn(|k| (-self.settings.kind[k].cooling * dt).exp());
        let capacity = self.pool.capacity();
        // A pool is mostly empty while a fire is small: runs of dead slots are passed over
        // a run at a time.
        for run in (0..capacity).step_by(DEAD_RUN) {
            let slots = run..(run + DEAD_RUN).min(capacity);
            if !self.pool.alive[slots.clone()]
                .iter()
                .fold(false, |any, &alive| any | alive)
            {
                continue;
            }
            // The run's eddies eight slots at a time where one of the eight is alive (a dead
            // slot's are not used): eight points side by side cost a fraction of eight in turn.
            let mut eddies = [[[0.0f32; LANES]; 3]; DEAD_RUN / LANES];
            for (k, eddies) in eddies.iter_mut().enumerate() {
                let first = (run + k * LANES).min(capacity);
                let lanes = first..(first + LANES).min(capacity);
                if !self.pool.alive[lanes.clone()].contains(&true) {
                    continue;
                }
                let position = &self.pool.position[lanes];
                let axis = |a: usize| -> [f32; LANES] {
                    core::array::from_fn(|l| position.get(l).map_or(0.0, |p| p[a]))
                };
                *eddies = self
                    .turbulence
                    .velocities(&[axis(0), axis(1), axis(2)], time);
            }
            for slot in slots {
                if !self.pool.alive[slot] {
                    continue;
                }
                self.pool.age[slot] += dt;
                if self.pool.age[slot] >= self.pool.lifetime[slot] {
                    self.pool.kill(slot);
                    counts.died += 1;
                    continue;
                }
                let kind = self.pool.kind[slot] as usize;
                let settings: &KindSettings = &self.settings.kind[kind];
                let temperature = ambient + (self.pool.temperature[slot] - ambient) * cooled[kind];
                let position = self.pool.position[slot];
                let (k, l) = ((slot - run) / LANES, (slot - run) % LANES);
                let [ex, ey, ez] = &eddies[k];
                let eddies = Vec3::new(ex[l], ey[l], ez[l]) * settings.turbulence;
                let (air_velocity, buoyancy) = match flow(position) {
                    Some(plume) => (air.wind + plume + eddies * SUBGRID_EDDIES, 0.0),
                    None => (air.wind + eddies, settings.buoyancy),
                };
                let acceleration = up * (buoyancy * (temperature - ambient) * 1e-3)
                    + air.gravity * settings.gravity_scale;
                let velocity = (self.pool.velocity[slot]
                    + dt * (acceleration + settings.drag * air_velocity))
                    / (1.0 + dt * settings.drag);
                let position = position + velocity * dt;
                if !(position.is_finite() && velocity.is_finite()) {
                    self.pool.kill(slot);
                    counts.died += 1;
                    continue;
                }
                self.pool.temperature[slot] = temperature;
                self.pool.velocity[slot] = velocity;
                self.pool.position[slot] = position;
            }
        }
        self.time += dt;
        counts
    }

    /// Size (half-width, m) and linear RGBA colour of a live slot at its current age.
    pub fn appearance(&self, slot: usize) -> (f32, [f32; 4]) {
        let settings = self.settings.of(self.pool.kind[slot]);
        let t = self.pool.life_fraction(slot);
        let size =
            (settings.size[0] + (settings.size[1] - settings.size[0]) * t) * self.pool.scale[slot];
        let [birth, death] = settings.colour;
        let mut colour: [f32; 4] = core::array::from_fn(|c| birth[c] + (death[c] - birth[c]) * t);
        colour[3] *= (t * 10.0).min(1.0);
        (size, colour)
    }
}
