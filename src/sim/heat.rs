//! The paper's heat model: ignited particles push heat to their neighbours, more upward.
//!
//! Every step, each ignited particle `i` adds to each grid neighbour `j` (its structural and
//! shear springs: the 8 surrounding particles of a grid)
//!
//! `ΔT_j = w(ĵ·up) × rate × h × (T_i − T_initial)`
//!
//! where `ĵ` is the world direction from `i` to `j`. The paper gives the weights for the
//! particle directly above (4) and the upward diagonals (2); its Figure 3 with the others did
//! not survive, so this crate sets sideways 1, downward diagonals 0.5 and directly below 0.25,
//! and interpolates linearly in the direction's cosine with world up for cloth that is not
//! upright. Fire therefore follows world up, wherever the cloth's rows point.
//!
//! As in the paper the pushing particle loses no heat: heat only grows. Two additions keep
//! the model from stalling: an ignited particle heats itself at the material's
//! `self_heating_rate` (a lone burning particle would otherwise never reach the burnt
//! temperature), and particles that come within `proximity_radius` of a burning one (a fold,
//! another layer) are heated through a [`SpatialHash`], not only grid neighbours.
//!
//! Increments are gathered in a buffer and applied together, so the result does not depend
//! on the order particles are visited.

use super::material::{BurnMaterial, MAX_TEMPERATURE};
use super::particles::BurnState;
use super::spatial_hash::SpatialHash;
use super::springs::Springs;
use glam::Vec3;

/// Heat push weights by the cosine of the direction with world up: (cosine, weight).
const DIRECTION_WEIGHTS: [(f32, f32); 5] = [
    (-1.0, 0.25),
    (-core::f32::consts::FRAC_1_SQRT_2, 0.5),
    (0.0, 1.0),
    (core::f32::consts::FRAC_1_SQRT_2, 2.0),
    (1.0, 4.0),
];

/// Weight of a heat push toward a neighbour whose direction has cosine `cos_up` with world
/// up: 4 straight up, 2 on the upward diagonals, 1 sideways, 0.5 on the downward
/// diagonals, 0.25 straight down, linear in between.
pub fn direction_weight(cos_up: f32) -> f32 {
    let c = if cos_up.is_finite() {
        cos_up.clamp(-1.0, 1.0)
    } else {
        0.0
    };
    for pair in DIRECTION_WEIGHTS.windows(2) {
        let ((c0, w0), (c1, w1)) = (pair[0], pair[1]);
        if c <= c1 {
            return w0 + (w1 - w0) * (c - c0) / (c1 - c0);
        }
    }
    DIRECTION_WEIGHTS[DIRECTION_WEIGHTS.len() - 1].1
}

/// Parameters of the paper's heat model for one step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HeatParams {
    /// Push rate, 1/s (the material's `heat_spread_rate`).
    pub spread_rate: f32,
    /// Self-heating of an ignited particle, °C/s.
    pub self_heating_rate: f32,
    /// Temperature the push is measured from, °C.
    pub initial_temperature: f32,
    /// World up, unit vector: heat rises along it.
    pub up: Vec3,
    /// Particles this close to a burning one are heated even without a spring, m.
    /// Zero turns proximity heating off.
    pub proximity_radius: f32,
    /// Push rate across proximity, 1/s, at zero distance; falls linearly to 0 at the radius.
    pub proximity_rate: f32,
    /// The physical model's parameters, when the cloth uses it instead of the push model
    /// (proximity heating then still applies).
    pub physical: Option<super::settings::PhysicalHeat>,
}

impl HeatParams {
    /// Parameters from a material, with world up `+Y`, the given proximity radius and the
    /// paper's model.
    pub fn from_material(material: &BurnMaterial, proximity_radius: f32) -> Self {
        Self {
            spread_rate: material.heat_spread_rate,
            self_heating_rate: material.self_heating_rate,
            initial_temperature: material.initial_temperature,
            up: Vec3::Y,
            proximity_radius,
            proximity_rate: material.heat_spread_rate,
            physical: None,
        }
    }
}

/// Scratch memory for a heat step: the increment buffer and the spatial hash.
#[derive(Clone, Debug, Default)]
pub struct HeatWorkspace {
    /// Temperature increments of the step being assembled, °C.
    pub delta: Vec<f32>,
    /// Hash of unburnt particles for proximity heating.
    pub hash: SpatialHash,
}

impl HeatWorkspace {
    /// Heap memory held, bytes (capacity, not length).
    pub fn heap_bytes(&self) -> usize {
        self.delta.capacity() * size_of::<f32>() + self.hash.heap_bytes()
    }
}

/// Adds one step of the paper's neighbour push and self-heating to `delta` (°C).
pub fn paper_heat_push(
    springs: &Springs,
    position: &[Vec3],
    temperature: &[f32],
    state: &[BurnState],
    params: &HeatParams,
    h: f32,
    delta: &mut [f32],
) {
    let scale = params.spread_rate * h;
    for s in 0..springs.len() {
        if !springs.kind[s].is_in_plane() {
            continue;
        }
        let (a, b) = (springs.a[s] as usize, springs.b[s] as usize);
        let (state_a, state_b) = (state[a], state[b]);
        if state_a.is_burnt() || state_b.is_burnt() {
            continue;
        }
        let direction = (position[b] - position[a]).normalize_or_zero();
        let cos_up = direction.dot(params.up);
        if state_a.is_ignited() {
            let excess = (temperature[a] - params.initial_temperature).max(0.0);
            delta[b] += direction_weight(cos_up) * scale * excess;
        }
        if state_b.is_ignited() {
            let excess = (temperature[b] - params.initial_temperature).max(0.0);
            delta[a] += direction_weight(-cos_up) * scale * excess;
        }
    }
    for (i, s) in state.iter().enumerate() {
        if s.is_ignited() {
            delta[i] += params.self_heating_rate * h;
        }
    }
}

/// Adds one step of proximity heating to `delta` (°C): every unburnt particle within
/// `params.proximity_radius` of an ignited one gains heat, weighted by direction like the
/// grid push and falling linearly to zero at the radius. `hash` must have been built over
/// the unburnt particles with a cell size of at least the radius.
pub fn proximity_heat_push(
    hash: &SpatialHash,
    position: &[Vec3],
    temperature: &[f32],
    state: &[BurnState],
    params: &HeatParams,
    h: f32,
    delta: &mut [f32],
) {
    let radius = params.proximity_radius;
    if !(radius > 0.0 && radius.is_finite()) {
        return;
    }
    let scale = params.proximity_rate * h;
    for i in 0..position.len() {
        if !state[i].is_ignited() {
            continue;
        }
        let excess = (temperature[i] - params.initial_temperature).max(0.0);
        hash.for_each_within(position, position[i], radius, |j| {
            if j == i || state[j].is_burnt() {
                return;
            }
            let offset = position[j] - position[i];
            let distance = offset.length();
            let cos_up = offset.normalize_or_zero().dot(params.up);
            let falloff = 1.0 - distance / radius;
            delta[j] += direction_weight(cos_up) * scale * excess * falloff;
        });
    }
}

/// Adds `delta` to the temperatures of unburnt particles, keeping each within the accepted
/// range, and clears `delta`. Non-finite increments are dropped.
pub fn apply_heat(temperature: &mut [f32], state: &[BurnState], delta: &mut [f32]) {
    for ((t, d), s) in temperature.iter_mut().zip(delta.iter_mut()).zip(state) {
        if !s.is_burnt() && d.is_finite() {
            *t = (*t + *d).min(MAX_TEMPERATURE);
        }
        *d = 0.0;
    }
}

/// One full step of the paper's heat model: neighbour push, self-heating and proximity
/// heating, applied together.
pub fn paper_heat_step(
    springs: &Springs,
    position: &[Vec3],
    temperature: &mut [f32],
    state: &[BurnState],
    params: &HeatParams,
    workspace: &mut HeatWorkspace,
    h: f32,
) {
    workspace.delta.clear();
    workspace.delta.resize(temperature.len(), 0.0);
    paper_heat_push(
        springs,
        position,
        temperature,
        state,
        params,
        h,
        &mut workspace.delta,
    );
    if proximity_heat_applies(params, state) {
        add_proximity_heat(position, temperature, state, params, workspace, h);
    }
    apply_heat(temperature, state, &mut workspace.delta);
}

/// Whether proximity heating has anything to do: a reach, and something burning.
fn proximity_heat_applies(params: &HeatParams, state: &[BurnState]) -> bool {
    params.proximity_radius > 0.0 && state.iter().any(|s| s.is_ignited())
}

/// Adds proximity heating to `workspace.delta` (already sized): hashes the unburnt particles
/// and lets every ignited one heat those within the proximity radius. Callers check
/// [`proximity_heat_applies`] first, so no hash is built when there is nothing to do.
fn add_proximity_heat(
    position: &[Vec3],
    temperature: &[f32],
    state: &[BurnState],
    params: &HeatParams,
    workspace: &mut HeatWorkspace,
    h: f32,
) {
    workspace
        .hash
        .build(position, params.proximity_radius, |j| !state[j].is_burnt());
    proximity_heat_push(
        &workspace.hash,
        position,
        temperature,
        state,
        params,
        h,
        &mut workspace.delta,
    );
}

/// Proximity heating alone, applied at once: what the physical model adds for folds and
/// layers that touch without a spring between them.
pub fn proximity_heat_step(
    position: &[Vec3],
    temperature: &mut [f32],
    state: &[BurnState],
    params: &HeatParams,
    workspace: &mut HeatWorkspace,
    h: f32,
) {
    if !proximity_heat_applies(params, state) {
        return;
    }
    workspace.delta.clear();
    workspace.delta.resize(temperature.len(), 0.0);
    add_proximity_heat(position, temperature, state, params, workspace, h);
    apply_heat(temperature, state, &mut workspace.delta);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::SpringKind;

    #[test]
    fn weights_match_the_paper_where_it_gives_them() {
        assert_eq!(direction_weight(1.0), 4.0);
        assert!((direction_weight(core::f32::consts::FRAC_1_SQRT_2) - 2.0).abs() < 1e-6);
        assert_eq!(direction_weight(0.0), 1.0);
        assert!(direction_weight(-1.0) < direction_weight(0.0));
        assert_eq!(direction_weight(f32::NAN), 1.0);
        // Monotone in the cosine.
        let mut last = 0.0;
        for k in 0..=100 {
            let w = direction_weight(-1.0 + 0.02 * k as f32);
            assert!(w >= last);
            last = w;
        }
    }

    #[test]
    fn push_goes_four_times_harder_up_than_sideways() {
        // Particle 0 ignited at the centre; 1 above, 2 to the side, 3 below.
        let position = [Vec3::ZERO, Vec3::Y, Vec3::X, -Vec3::Y];
        let mut springs = Springs::default();
        for j in 1..4 {
            springs.push(0, j, 1.0, SpringKind::Structural);
        }
        let temperature = [115.6, 15.6, 15.6, 15.6];
        let state = [
            BurnState::Ignited,
            BurnState::Intact,
            BurnState::Intact,
            BurnState::Intact,
        ];
        let params = HeatParams {
            spread_rate: 0.5,
            self_heating_rate: 0.0,
            initial_temperature: 15.6,
            up: Vec3::Y,
            proximity_radius: 0.0,
            proximity_rate: 0.0,
            physical: None,
        };
        let mut delta = [0.0; 4];
        paper_heat_push(
            &springs,
            &position,
            &temperature,
            &state,
            &params,
            0.1,
            &mut delta,
        );
        // Excess 100 °C × 0.5/s × 0.1 s = 5 °C sideways.
        assert!((delta[2] - 5.0).abs() < 1e-4);
        assert!((delta[1] - 20.0).abs() < 1e-4);
        assert!((delta[3] - 1.25).abs() < 1e-4);
        assert_eq!(
            delta[0], 0.0,
            "the source loses no heat and gains none from cold ones"
        );
    }

    #[test]
    fn apply_heat_clamps_and_skips_burnt() {
        let mut temperature = [10.0, 10.0, 10.0];
        let state = [BurnState::Intact, BurnState::Burnt, BurnState::Intact];
        let mut delta = [1.0e9, 5.0, f32::NAN];
        apply_heat(&mut temperature, &state, &mut delta);
        assert_eq!(temperature, [MAX_TEMPERATURE, 10.0, 10.0]);
        assert_eq!(delta, [0.0; 3]);
    }
}
