//! The paper's heat model: ignited particles push heat to their neighbours, more upward.
//!
//! Every step, each ignited particle `i` adds to each grid neighbour `j` (its structural and
//! shear springs: the 8 surrounding particles of a grid)
//!
//! `ΔT_j = w(ĵ·up) × rate × (L_ref / l) × h × (T_i − T_initial)`
//!
//! where `l` is the cloth's particle spacing and `L_ref` the [`REFERENCE_SPACING`] the
//! material's rate is given for: the front crosses one neighbour in a time proportional to
//! `l`, so it moves the same metres per second at any resolution (the paper's push, per
//! neighbour, made a cloth twice as fine burn half as fast).
//!
//! where `ĵ` is the world direction from `i` to `j`. The paper gives the weights for the
//! particle directly above (4) and the upward diagonals (2); its Figure 3 with the others did
//! not survive, so this crate sets sideways 1, downward diagonals 0.5 and directly below 0.25,
//! and interpolates linearly in the direction's cosine with world up for cloth that is not
//! upright. Fire therefore follows world up, wherever the cloth's rows point.
//!
//! As in the paper the pushing particle loses no heat: heat only grows. Two additions keep
//! the model from stalling: an ignited particle heats itself at the material's
//! `self_heating_rate`, scaled by `L_ref / l` like the push (a lone burning particle would
//! otherwise never reach the burnt temperature; scaled, a pusher is as hot when the front
//! reaches its neighbour at any spacing, and the front's speed does not change with it),
//! and particles that come within `proximity_radius` of a burning one (a fold,
//! another layer) are heated through a [`SpatialHash`], not only grid neighbours.
//!
//! Increments are gathered in a buffer and applied together, so the result does not depend
//! on the order particles are visited. The work follows the fire: only the particles on fire
//! (the [`Front`]'s list) push, and only the particles they reach are touched.

use super::front::Front;
#[cfg(doc)]
use super::material::REFERENCE_SPACING;
use super::material::{BurnMaterial, MAX_TEMPERATURE};
use super::particles::{BurnState, Particles};
use super::spatial_hash::SpatialHash;
use super::springs::Springs;
use glam::Vec3;

/// The heat push's weight by the cosine of its direction with world up, piecewise linear
/// between the paper's weights: 0.25 straight down (cosine −1), 0.5 on the downward diagonals
/// (−1/√2), 1 sideways (0), 2 on the upward diagonals (1/√2), 4 straight up (1). By piece,
/// from the lowest: the cosine at its upper end, the weight there, and the weight's slope.
const DIRECTION_PIECES: [(f32, f32, f32); 4] = {
    const DIAGONAL: f32 = core::f32::consts::FRAC_1_SQRT_2;
    [
        (-DIAGONAL, 0.5, (0.5 - 0.25) / (1.0 - DIAGONAL)),
        (0.0, 1.0, (1.0 - 0.5) / DIAGONAL),
        (DIAGONAL, 2.0, (2.0 - 1.0) / DIAGONAL),
        (1.0, 4.0, (4.0 - 2.0) / (1.0 - DIAGONAL)),
    ]
};

/// Weight of a heat push toward a neighbour whose direction has cosine `cos_up` with world
/// up: 4 straight up, 2 on the upward diagonals, 1 sideways, 0.5 on the downward
/// diagonals, 0.25 straight down, linear in between (a non-finite cosine counts as sideways).
/// Without a branch or a division: it runs for every neighbour of every burning particle.
pub fn direction_weight(cos_up: f32) -> f32 {
    let c = if cos_up.is_finite() {
        cos_up.clamp(-1.0, 1.0)
    } else {
        0.0
    };
    // The piece holding `c`: the count of pieces whose upper end is below it.
    let piece = DIRECTION_PIECES[..3]
        .iter()
        .map(|&(end, _, _)| usize::from(c > end))
        .sum::<usize>();
    let (end, weight, slope) = DIRECTION_PIECES[piece];
    weight - slope * (end - c)
}

/// Parameters of the paper's heat model for one step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HeatParams {
    /// Push rate for this cloth's spacing, 1/s (the material's `heat_spread_rate` times
    /// `REFERENCE_SPACING / spacing`).
    pub spread_rate: f32,
    /// Self-heating of an ignited particle, °C/s (the material's `self_heating_rate` times
    /// `REFERENCE_SPACING / spacing`).
    pub self_heating_rate: f32,
    /// Temperature the push is measured from, °C.
    pub initial_temperature: f32,
    /// Temperature above which a particle is on fire, °C: where the push dates a catch.
    pub ignition_temperature: f32,
    /// Temperature above which a particle on fire is spent, °C: the front has crossed its
    /// patch, and it pushes no more heat while it glows on to its burn time (see
    /// [`Front::scan`]).
    pub burnt_temperature: f32,
    /// World up, unit vector: heat rises along it.
    pub up: Vec3,
    /// Particles this close to a burning one are heated even without a spring, m.
    /// Zero turns proximity heating off.
    pub proximity_radius: f32,
    /// Push rate across proximity, 1/s, at zero distance, scaled like `spread_rate`; falls
    /// linearly to 0 at the radius.
    pub proximity_rate: f32,
    /// The physical model's parameters, when the cloth uses it instead of the push model
    /// (proximity heating then still applies).
    pub physical: Option<super::settings::PhysicalHeat>,
}

impl HeatParams {
    /// Parameters from a material for particles `REFERENCE_SPACING` apart, with world up
    /// `+Y`, the given proximity radius and the paper's model.
    pub fn from_material(material: &BurnMaterial, proximity_radius: f32) -> Self {
        Self {
            spread_rate: material.heat_spread_rate,
            self_heating_rate: material.self_heating_rate,
            initial_temperature: material.initial_temperature,
            ignition_temperature: material.ignition_temperature,
            burnt_temperature: material.burnt_temperature,
            up: Vec3::Y,
            proximity_radius,
            proximity_rate: material.heat_spread_rate,
            physical: None,
        }
    }
}

/// Scratch memory for a heat step: increments, the particles they touch, and the spatial
/// hash.
#[derive(Clone, Debug, Default)]
pub struct HeatWorkspace {
    /// Temperature increments of the step being assembled, °C; zero outside `touched`.
    delta: Vec<f32>,
    /// The particles with an increment, and a mark per particle for being among them.
    touched: Vec<u32>,
    marked: Vec<bool>,
    /// Hash of the unburnt particles near the fire, for proximity heating.
    hash: SpatialHash,
    /// Per particle, s: how long before the end of the last step it caught (crossed the
    /// ignition temperature), so its first push makes up for the part of the step it was
    /// already burning; zero but for the particles in `caught`.
    owed: Vec<f32>,
    caught: Vec<u32>,
}

impl HeatWorkspace {
    /// Heap memory held, bytes (capacity, not length).
    pub fn heap_bytes(&self) -> usize {
        (self.delta.capacity()
            + self.touched.capacity()
            + self.owed.capacity()
            + self.caught.capacity())
            * size_of::<f32>()
            + self.marked.capacity()
            + self.hash.heap_bytes()
    }

    /// Sized for `n` particles (all increments zero).
    fn prepare(&mut self, n: usize) {
        if self.delta.len() != n {
            self.delta.clear();
            self.delta.resize(n, 0.0);
            self.marked.clear();
            self.marked.resize(n, false);
            self.touched.clear();
            self.touched.reserve(n);
            self.hash.reserve(n);
            self.owed.clear();
            self.owed.resize(n, 0.0);
            self.caught.clear();
            self.caught.reserve(n);
        }
    }

    /// Adds `amount` (°C) to particle `j`'s increment.
    #[inline]
    fn add(&mut self, j: usize, amount: f32) {
        self.delta[j] += amount;
        if !self.marked[j] {
            self.marked[j] = true;
            self.touched.push(j as u32);
        }
    }

    /// Adds the increments to the temperatures of unburnt particles, keeping each within the
    /// accepted range (non-finite increments are dropped), and clears them.
    ///
    /// With `dating` = (ignition temperature °C, step s), also dates each catch: a particle
    /// that crosses the ignition temperature in this step is owed the part of the step after
    /// the crossing (the increment taken as even over the step), which its first push makes up
    /// for. Without it a catch would start pushing only at the next step, and on a fine grid,
    /// whose front crosses a cell in a few steps, that lag slowed the front: silk's climb on a
    /// 5 mm grid went from 137 to 149 mm/s with the catch dated (178 at 50 mm).
    fn apply(&mut self, temperature: &mut [f32], state: &[BurnState], dating: Option<(f32, f32)>) {
        for &j in &self.caught {
            self.owed[j as usize] = 0.0;
        }
        self.caught.clear();
        for &j in &self.touched {
            let j = j as usize;
            let (before, d) = (temperature[j], self.delta[j]);
            if !state[j].is_burnt() && d.is_finite() {
                let after = before + d;
                if let Some((ignition, h)) = dating
                    && d > 0.0
                    && before <= ignition
                    && after > ignition
                {
                    self.owed[j] = h * ((after - ignition) / d).clamp(0.0, 1.0);
                    self.caught.push(j as u32);
                }
                temperature[j] = after.min(MAX_TEMPERATURE);
            }
            self.delta[j] = 0.0;
            self.marked[j] = false;
        }
        self.touched.clear();
    }
}

/// Whether a particle on fire at `temperature` is spent: past the burnt temperature, so the
/// front has crossed its patch; it glows on until its burn time is up but heats nothing.
#[inline]
fn is_spent(temperature: f32, params: &HeatParams) -> bool {
    temperature > params.burnt_temperature
}

/// Adds one step of the paper's push from every particle on fire to its neighbours, and its
/// self-heating, to the workspace's increments.
pub fn paper_heat_push(
    front: &Front,
    springs: &Springs,
    particles: &Particles,
    params: &HeatParams,
    h: f32,
    workspace: &mut HeatWorkspace,
) {
    let (position, temperature, state) = (
        &particles.position,
        &particles.temperature,
        &particles.state,
    );
    for &i in front.ignited() {
        let i = i as usize;
        // Put out from outside since the list was made (extinguished): no longer burning.
        // Spent (past the burnt temperature, glowing on to its burn time): the front has
        // crossed it, and it pushes no more, as it did not when it burnt away there.
        if !state[i].is_ignited() || is_spent(temperature[i], params) {
            continue;
        }
        // A particle that caught during the last step also pushes for the part of it after
        // the catch.
        let burning = h + core::mem::take(&mut workspace.owed[i]);
        let excess = (temperature[i] - params.initial_temperature).max(0.0);
        for (_, j) in front.in_plane_neighbours(i, springs) {
            if state[j].is_burnt() {
                continue;
            }
            let direction = (position[j] - position[i]).normalize_or_zero();
            let weight = direction_weight(direction.dot(params.up));
            workspace.add(j, weight * params.spread_rate * burning * excess);
        }
        workspace.add(i, params.self_heating_rate * burning);
    }
}

/// Calls `visit(i, j, weight)` for every burning particle `i` and unburnt particle `j ≠ i`
/// within `params.proximity_radius` of it, with `weight` the direction weight of the grid push
/// times a linear fall to zero at the radius. Only the particles inside the fire's bounding
/// box (grown by the radius) are hashed.
fn for_each_near_fire(
    front: &Front,
    particles: &Particles,
    params: &HeatParams,
    workspace: &mut HeatWorkspace,
    mut visit: impl FnMut(&mut HeatWorkspace, usize, usize, f32),
) {
    let (position, state) = (&particles.position, &particles.state);
    let radius = params.proximity_radius;
    if !(radius > 0.0 && radius.is_finite()) || front.ignited().is_empty() {
        return;
    }
    let (mut low, mut high) = (Vec3::INFINITY, Vec3::NEG_INFINITY);
    for &i in front.ignited() {
        let p = position[i as usize];
        if p.is_finite() {
            (low, high) = (low.min(p), high.max(p));
        }
    }
    let (low, high) = (low - Vec3::splat(radius), high + Vec3::splat(radius));
    let inside = |p: Vec3| p.cmpge(low).all() && p.cmple(high).all();
    // Cells three times the radius: a query's box (twice the radius across) overlaps at most
    // 8 of them, and on average 4.6 (at twice the radius, always 8, most of them empty, as a
    // cloth is a sheet; at four times, 3.4, but with more particles each where the cloth lies
    // in folds). A burning 64 x 64 cloth's heat phase: 0.057 -> 0.055 ms a frame.
    workspace.hash.build(position, 3.0 * radius, |j| {
        !state[j].is_burnt() && inside(position[j])
    });
    let hash = core::mem::take(&mut workspace.hash);
    for &i in front.ignited() {
        let i = i as usize;
        if !state[i].is_ignited() || is_spent(particles.temperature[i], params) {
            continue;
        }
        hash.for_each_within(position, position[i], radius, |j| {
            if j == i {
                return;
            }
            let offset = position[j] - position[i];
            // One square root for both: what `normalize_or_zero` and `length` would give.
            let length = offset.length();
            let inverse = length.recip();
            let direction = if inverse.is_finite() && inverse > 0.0 {
                offset * inverse
            } else {
                Vec3::ZERO
            };
            let cos_up = direction.dot(params.up);
            let falloff = 1.0 - length / radius;
            visit(workspace, i, j, direction_weight(cos_up) * falloff);
        });
    }
    workspace.hash = hash;
}

/// Adds one step of the paper's proximity heating to the workspace's increments: every
/// unburnt particle within `params.proximity_radius` of a particle on fire gains
/// `rate × h × weight × (T_fire − T_initial)`, as the grid push does (the source loses
/// nothing: the paper's model adds heat).
pub fn proximity_heat_push(
    front: &Front,
    particles: &Particles,
    params: &HeatParams,
    h: f32,
    workspace: &mut HeatWorkspace,
) {
    let scale = params.proximity_rate * h;
    let temperature = &particles.temperature;
    for_each_near_fire(
        front,
        particles,
        params,
        workspace,
        |workspace, i, j, weight| {
            let excess = (temperature[i] - params.initial_temperature).max(0.0);
            workspace.add(j, weight * scale * excess);
        },
    );
}

/// Adds one step of proximity heating as an exchange, for the physical model: a particle on fire
/// gives a cooler one within the radius `rate × h × weight × (T_fire − T) × m̄` joules per unit
/// heat capacity (`m̄` the pair's mean mass) and loses the same, so folds and layers conserve heat
/// as the springs' conduction does.
pub fn proximity_heat_exchange(
    front: &Front,
    particles: &Particles,
    params: &HeatParams,
    h: f32,
    workspace: &mut HeatWorkspace,
) {
    let scale = params.proximity_rate * h;
    let (temperature, mass) = (&particles.temperature, &particles.mass);
    for_each_near_fire(
        front,
        particles,
        params,
        workspace,
        |workspace, i, j, weight| {
            let difference = (temperature[i] - temperature[j]).max(0.0);
            let heat = weight * scale * difference * 0.5 * (mass[i] + mass[j]);
            if heat > 0.0 && mass[i] > 0.0 && mass[j] > 0.0 {
                workspace.add(j, heat / mass[j]);
                workspace.add(i, -heat / mass[i]);
            }
        },
    );
}

/// One full step of the paper's heat model: the push from the fire, self-heating and
/// proximity heating, applied together (so the result does not depend on the order of the
/// particles).
pub fn paper_heat_step(
    front: &Front,
    springs: &Springs,
    particles: &mut Particles,
    params: &HeatParams,
    workspace: &mut HeatWorkspace,
    h: f32,
) {
    workspace.prepare(particles.len());
    paper_heat_push(front, springs, particles, params, h, workspace);
    proximity_heat_push(front, particles, params, h, workspace);
    let dating = Some((params.ignition_temperature, h));
    workspace.apply(&mut particles.temperature, &particles.state, dating);
}

/// Proximity heating alone, applied at once, as an exchange that conserves heat
/// ([`proximity_heat_exchange`]): what the physical model adds for folds and layers that touch
/// without a spring between them.
pub fn proximity_heat_step(
    front: &Front,
    particles: &mut Particles,
    params: &HeatParams,
    workspace: &mut HeatWorkspace,
    h: f32,
) {
    workspace.prepare(particles.len());
    proximity_heat_exchange(front, particles, params, h, workspace);
    workspace.apply(&mut particles.temperature, &particles.state, None);
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

    /// The weight is the straight line between the paper's weights at every cosine, as
    /// interpolated in f64, and meets itself at the corners.
    #[test]
    fn weights_are_linear_between_the_papers() {
        let table = [
            (-1.0f64, 0.25f64),
            (-core::f64::consts::FRAC_1_SQRT_2, 0.5),
            (0.0, 1.0),
            (core::f64::consts::FRAC_1_SQRT_2, 2.0),
            (1.0, 4.0),
        ];
        for k in 0..=2000 {
            let c = -1.0 + k as f64 / 1000.0;
            let pair = table.windows(2).find(|pair| c <= pair[1].0).unwrap();
            let ((c0, w0), (c1, w1)) = (pair[0], pair[1]);
            let expected = w0 + (w1 - w0) * (c - c0) / (c1 - c0);
            let got = f64::from(direction_weight(c as f32));
            assert!(
                (got - expected).abs() < 2e-6,
                "cos {c}: {got} against {expected}"
            );
        }
        assert_eq!(direction_weight(-1.0), 0.25);
        assert_eq!(direction_weight(2.0), 4.0);
        assert_eq!(direction_weight(f32::INFINITY), 1.0);
    }

    /// Particle 0 on fire at the centre, `spacing` from particles 1 above, 2 to the side and
    /// 3 below, with `mass`, `fire` °C at the centre and 15.6 °C around; springs from the centre
    /// to each when `springs`. The front has scanned them (particle 0 ignited).
    fn star(
        spacing: f32,
        mass: Vec<f32>,
        fire: f32,
        with_springs: bool,
    ) -> (crate::sim::Particles, Springs, Front) {
        let position = vec![Vec3::ZERO, Vec3::Y, Vec3::X, -Vec3::Y].into_iter();
        let position: Vec<Vec3> = position.map(|p| p * spacing).collect();
        let mut springs = Springs::default();
        if with_springs {
            for j in 1..4 {
                springs.push(0, j, spacing, SpringKind::Structural);
            }
        }
        let mut particles = crate::sim::Particles {
            velocity: vec![Vec3::ZERO; 4],
            inv_mass: mass.iter().map(|m| 1.0 / m).collect(),
            mass,
            temperature: vec![fire, 15.6, 15.6, 15.6],
            state: vec![BurnState::Intact; 4],
            burning_for: vec![0.0; 4],
            anchor: position.clone(),
            external_force: vec![Vec3::ZERO; 4],
            position,
        };
        let material = BurnMaterial {
            ignition_temperature: 100.0,
            initial_temperature: 15.6,
            ..BurnMaterial::CLOTH
        };
        let mut front = Front::default();
        front.prepare(&particles, &mut springs, &mut Default::default());
        front.scan(
            &mut particles,
            &springs,
            &material,
            1.0 / 60.0,
            &mut Vec::new(),
        );
        assert_eq!(front.ignited(), &[0]);
        (particles, springs, front)
    }

    /// The push alone: rate 0.5/s, no self-heating, no proximity, ignition at 100 °C.
    fn push_params() -> HeatParams {
        HeatParams {
            spread_rate: 0.5,
            self_heating_rate: 0.0,
            initial_temperature: 15.6,
            ignition_temperature: 100.0,
            burnt_temperature: 500.0,
            up: Vec3::Y,
            proximity_radius: 0.0,
            proximity_rate: 0.0,
            physical: None,
        }
    }

    #[test]
    fn push_goes_four_times_harder_up_than_sideways() {
        let (particles, springs, front) = star(1.0, vec![1.0; 4], 115.6, true);
        let params = push_params();
        let mut workspace = HeatWorkspace::default();
        workspace.prepare(4);
        paper_heat_push(&front, &springs, &particles, &params, 0.1, &mut workspace);
        let delta = &workspace.delta;
        // Excess 100 °C × 0.5/s × 0.1 s = 5 °C sideways.
        assert!((delta[2] - 5.0).abs() < 1e-4);
        assert!((delta[1] - 20.0).abs() < 1e-4);
        assert!((delta[3] - 1.25).abs() < 1e-4);
        assert_eq!(
            delta[0], 0.0,
            "the source loses no heat and gains none from cold ones"
        );
    }

    /// A particle past the burnt temperature that is still on fire (glowing on to its burn
    /// time) pushes nothing, by springs or across folds, and does not heat itself: the front
    /// has crossed it, and before burn times it had burnt away there.
    #[test]
    fn a_spent_particle_pushes_no_heat() {
        let params = HeatParams {
            self_heating_rate: 100.0,
            proximity_radius: 2.0,
            proximity_rate: 0.5,
            ..push_params()
        };
        for (fire, pushes) in [(499.0, true), (501.0, false)] {
            // Scanned on fire at 115.6 °C, then made hotter.
            let (mut particles, springs, front) = star(1.0, vec![1.0; 4], 115.6, true);
            particles.temperature[0] = fire;
            let mut workspace = HeatWorkspace::default();
            workspace.prepare(4);
            paper_heat_push(&front, &springs, &particles, &params, 0.1, &mut workspace);
            proximity_heat_push(&front, &particles, &params, 0.1, &mut workspace);
            let pushed = workspace.delta.iter().any(|&d| d != 0.0);
            assert_eq!(pushed, pushes, "at {fire} °C (spent above 500)");
        }
    }

    /// A particle that catches a third of the way through a step pushes, in its first step
    /// on fire, for that step and the two thirds it was already burning.
    #[test]
    fn a_catch_is_dated_within_its_step() {
        let (mut particles, springs, front) = star(1.0, vec![1.0; 4], 115.6, true);
        let params = push_params();
        let h = 0.1;
        let mut workspace = HeatWorkspace::default();
        workspace.prepare(4);
        // Particle 1 goes from 95 °C by 15 °C: it crosses 100 °C a third of the way through.
        particles.temperature[1] = 95.0;
        workspace.add(1, 15.0);
        let state = particles.state.clone();
        workspace.apply(&mut particles.temperature, &state, Some((100.0, h)));
        assert!((workspace.owed[1] - 2.0 / 3.0 * h).abs() < 1e-6);
        assert_eq!(workspace.owed[2], 0.0, "no catch, nothing owed");
        // The hub's push is unchanged (it caught long ago) and the owed time is spent once.
        paper_heat_push(&front, &springs, &particles, &params, h, &mut workspace);
        assert!((workspace.delta[2] - 5.0).abs() < 1e-4);
        assert_eq!(workspace.owed[0], 0.0);
        // The next step: particle 1 (now 110 °C) is on fire.
        let material = BurnMaterial {
            ignition_temperature: 100.0,
            initial_temperature: 15.6,
            ..BurnMaterial::CLOTH
        };
        let mut caught = front.clone();
        caught.scan(
            &mut particles,
            &springs,
            &material,
            1.0 / 60.0,
            &mut Vec::new(),
        );
        assert_eq!(caught.ignited(), &[0, 1]);
        let before = workspace.delta[0];
        paper_heat_push(&caught, &springs, &particles, &params, h, &mut workspace);
        // Particle 1 at 110 °C, excess 94.4 °C, pushes down onto the hub (weight below 1)
        // for h + 2h/3.
        let pushed = workspace.delta[0] - before;
        let weight = direction_weight(-1.0);
        let expected = weight * 0.5 * (h + 2.0 / 3.0 * h) * (110.0 - 15.6);
        assert!((pushed - expected).abs() < 1e-3, "{pushed} vs {expected}");
        assert_eq!(workspace.owed[1], 0.0, "spent");
    }

    #[test]
    fn the_physical_models_proximity_heating_moves_heat_without_making_any() {
        // No springs: only proximity heats them. Unequal masses, so the exchange must weigh
        // them.
        let (mut particles, _, front) = star(0.5, vec![2.0, 1.0, 0.5, 1.0], 515.6, false);
        let params = HeatParams {
            spread_rate: 0.0,
            self_heating_rate: 0.0,
            initial_temperature: 15.6,
            ignition_temperature: 100.0,
            burnt_temperature: 1000.0,
            up: Vec3::Y,
            proximity_radius: 1.0,
            proximity_rate: 0.5,
            physical: None,
        };
        let heat = |p: &crate::sim::Particles| -> f32 {
            p.mass.iter().zip(&p.temperature).map(|(m, t)| m * t).sum()
        };
        let before = heat(&particles);
        let old = particles.temperature.clone();
        let mut workspace = HeatWorkspace::default();
        proximity_heat_step(&front, &mut particles, &params, &mut workspace, 0.1);
        let t = &particles.temperature;
        assert!(
            (heat(&particles) - before).abs() < 1e-3 * before,
            "heat {before} -> {}",
            heat(&particles)
        );
        assert!(t[0] < old[0], "the fire gives heat away");
        // Per unit of pair mass the one above gains four times what the one beside does.
        let gain =
            |j: usize| (t[j] - old[j]) * particles.mass[j] / (0.5 * (2.0 + particles.mass[j]));
        assert!(
            (gain(1) / gain(2) - 4.0).abs() < 1e-3,
            "{} vs {}",
            gain(1),
            gain(2)
        );
        assert!(gain(3) < gain(2) && gain(3) > 0.0);
    }

    #[test]
    fn applied_heat_is_clamped_skips_burnt_and_clears() {
        let mut temperature = [10.0, 10.0, 10.0];
        let state = [BurnState::Intact, BurnState::Burnt, BurnState::Intact];
        let mut workspace = HeatWorkspace::default();
        workspace.prepare(3);
        for (j, amount) in [1.0e9, 5.0, f32::NAN].into_iter().enumerate() {
            workspace.add(j, amount);
        }
        workspace.apply(&mut temperature, &state, None);
        assert_eq!(temperature, [MAX_TEMPERATURE, 10.0, 10.0]);
        assert!(workspace.delta.iter().all(|&d| d == 0.0));
        assert!(workspace.touched.is_empty());
    }
}
