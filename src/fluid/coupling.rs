//! The two ways between cloth and air: burning cloth feeds the plume heat and smoke; the
//! plume blows on the cloth (the cloth's own air drag, against the plume's velocity) and
//! heats the cloth it bathes.

use super::plume::Plume;
use crate::sim::parallel::{for_each_part, parts_for};
use crate::sim::{BurnMaterial, Particles};
use crate::smoke::BurningCloth;
use bevy::tasks::TaskPool;
use core::sync::atomic::{AtomicU32, Ordering};

/// Feeds `plume` from one cloth over `dt` seconds. A burning particle burns its mass `m`
/// away over `τ = (T_burnt − T_ignition) / self_heating_rate` seconds (the time its
/// self-heating alone takes to burn it; several times the [`BurnMaterial::burn_time`] a
/// particle is drawn burning for, so a particle feeds the plume a fraction of its mass's heat
/// before it burns away), so it gives the air `χ ΔH_c m dt / τ` joules (heat of combustion `ΔH_c`,
/// convective fraction `χ`) and `yield × m dt / τ` of smoke at its position: the heat a
/// cloth gives off is the heat in the mass it burns, at any resolution. Returns the heat
/// given, J.
pub fn feed_plume(
    plume: &mut Plume,
    cloth: &BurningCloth,
    material: &BurnMaterial,
    mass: &[f32],
    dt: f32,
) -> f32 {
    if !(dt.is_finite() && dt > 0.0) {
        return 0.0;
    }
    let burn_time = ((material.burnt_temperature - material.ignition_temperature)
        / material.self_heating_rate)
        .max(MIN_BURN_TIME);
    if !burn_time.is_finite() {
        return 0.0;
    }
    let settings = *plume.settings();
    let heat_per_kg = settings.convective_fraction * settings.heat_of_combustion * dt / burn_time;
    let smoke_per_kg = settings.smoke_yield * dt / burn_time;
    let mut given = 0.0;
    for ((position, state), mass) in cloth.position.iter().zip(cloth.state).zip(mass) {
        if !(state.is_ignited() && mass.is_finite() && *mass > 0.0) {
            continue;
        }
        plume.add_heat(*position, heat_per_kg * mass);
        plume.add_smoke(*position, smoke_per_kg * mass);
        given += heat_per_kg * mass;
    }
    given
}

/// Shortest burn time a particle is given, s (a material that burns faster still releases
/// its heat over this time, so one frame's feed stays bounded).
const MIN_BURN_TIME: f32 = 0.1;

/// What the plume did to one cloth in one call of [`blow_and_heat`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PlumeOnCloth {
    /// Particles inside the plume's box.
    pub inside: u32,
    /// Particles the hot air warmed.
    pub heated: u32,
}

/// The plume acting on one cloth for the coming step of `dt` seconds: each free, unburnt
/// particle inside the box feels the cloth's air drag against the plume's velocity (added
/// to `external_force`, which the step clears), and air hotter than it warms it by
/// convection, `dT/dt = h (T_air − T) / (ρ_A c)`, integrated exactly over `dt` (it never
/// overshoots the air's temperature). `ambient` is the air's temperature outside the plume,
/// °C. With `heating` false the plume only blows (the plugin turns heating off with
/// `FireSpread::enabled`, since the plume is how fire jumps through the air).
pub fn blow_and_heat(
    plume: &Plume,
    particles: &mut Particles,
    material: &BurnMaterial,
    ambient: f32,
    heating: bool,
    dt: f32,
) -> PlumeOnCloth {
    blow_and_heat_on(plume, particles, material, [ambient, dt], heating, None)
}

/// Particles per part when [`blow_and_heat_on`] splits a cloth over the pool: about 0.4 ms
/// of work on the 2-core machine, against the 16 µs an empty scope costs there.
const PARTICLES_PER_PART: usize = 8192;

/// [`blow_and_heat`] (`[ambient, dt]` in °C and s) with a cloth of more than
/// 8 192 particles split over `pool`'s threads: each particle's update
/// reads only the plume and writes only that particle, so the result is the same on any
/// number of threads.
pub fn blow_and_heat_on(
    plume: &Plume,
    particles: &mut Particles,
    material: &BurnMaterial,
    [ambient, dt]: [f32; 2],
    heating: bool,
    pool: Option<&TaskPool>,
) -> PlumeOnCloth {
    if plume.is_quiet() || !(dt.is_finite() && dt > 0.0) || !ambient.is_finite() {
        return PlumeOnCloth::default();
    }
    let settings = plume.settings();
    let drag_per_mass = material.drag_per_mass();
    let rate =
        settings.cloth_heat_transfer / (material.areal_density * settings.cloth_specific_heat);
    let warmed = 1.0 - (-rate * dt).exp();
    let Particles {
        position,
        state,
        mass,
        inv_mass,
        temperature,
        external_force,
        ..
    } = particles;
    let n = position.len();
    let size = n.div_ceil(parts_for(pool, n, PARTICLES_PER_PART)).max(1);
    let (inside, heated) = (AtomicU32::new(0), AtomicU32::new(0));
    let parts = external_force
        .chunks_mut(size)
        .zip(temperature.chunks_mut(size))
        .enumerate();
    for_each_part(pool, parts, |(part, (force, temperature))| {
        let first = part * size;
        let mut counts = PlumeOnCloth::default();
        for (k, (force, t)) in force.iter_mut().zip(temperature).enumerate() {
            let i = first + k;
            if state[i].is_burnt() {
                continue;
            }
            let Some((wind, excess)) = plume.air_at(position[i]) else {
                continue;
            };
            counts.inside += 1;
            if inv_mass[i] != 0.0 {
                *force += drag_per_mass * mass[i] * wind;
            }
            let air = ambient + excess;
            if heating && air > *t {
                *t += (air - *t) * warmed;
                counts.heated += 1;
            }
        }
        inside.fetch_add(counts.inside, Ordering::Relaxed);
        heated.fetch_add(counts.heated, Ordering::Relaxed);
    });
    PlumeOnCloth {
        inside: inside.into_inner(),
        heated: heated.into_inner(),
    }
}
