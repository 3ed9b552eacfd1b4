//! One cloth's simulation step, as phases the ECS systems call one by one, and
//! [`ClothSim`], which owns a cloth and runs all phases for tests, tools and headless use.
//!
//! A fixed step of `dt` seconds runs, in order:
//! 1. [`heat_phase`]: the paper's heat push, self-heating and proximity heating;
//! 2. [`combust_phase`]: ignition and burning by temperature, rest lengths shrink;
//! 3. pins follow their anchors, then `substeps` × [`dynamics_substep`] (forces and
//!    integration, then Provot's correction) and [`collide_phase`];
//! 4. the blow-up guard puts back particles that went non-finite or ran away;
//! 5. [`cull_phase`]: the index list keeps the triangles with three unburnt particles.

use super::collision::{WorldCollider, resolve_collisions};
use super::combustion::{CombustionReport, shrink_rest_lengths, update_burn_states};
use super::conduction::{ConductionParams, conduction_step};
use super::error::ClothError;
use super::forces::ForceParams;
use super::grid::{ClothBuilder, ClothParts};
use super::guard::{BlowUpGuard, GuardSettings};
use super::heat::{HeatParams, HeatWorkspace, paper_heat_step, proximity_heat_step};
use super::integrate::{Integrator, IntegratorWorkspace, drive_pins, integrate, stable_time_step};
use super::material::{BurnMaterial, valid_temperature};
use super::particles::{BurnState, Particles};
use super::provot::{ProvotReport, ProvotSettings, ProvotWorkspace, provot_correct};
use super::springs::{SpringCoefficients, Springs};
use super::topology::{Topology, cull_triangles};
use glam::{Affine3A, Vec3};

/// Most automatic substeps for an unconditionally stable integrator (XPBD's "small steps").
pub const UNCONDITIONAL_AUTO_SUBSTEPS: u32 = 10;

/// How the cloth is stepped: integrator, substeps, constraints, proximity heating.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SolverSettings {
    /// The time integrator.
    pub integrator: Integrator,
    /// Substeps per fixed step. `None` picks enough for stability from the cloth's stiffest
    /// spring and lightest particle (see [`stable_time_step`]), up to [`Self::max_substeps`].
    pub substeps: Option<u32>,
    /// Upper bound on automatic substeps.
    pub max_substeps: u32,
    /// Fraction of the stability limit an automatic substep may use, in (0, 1].
    pub stability_safety: f32,
    /// Provot's stretch limit, or `None` to turn it off.
    pub provot: Option<ProvotSettings>,
    /// Proximity heating radius as a multiple of the grid spacing; 0 turns it off.
    pub proximity_radius_factor: f32,
    /// Distance particles keep from colliders, as a multiple of the grid spacing.
    pub collision_margin_factor: f32,
    /// The blow-up guard's limits.
    pub guard: GuardSettings,
    /// Which heat model spreads the fire.
    pub heat_model: HeatModel,
}

/// How heat moves through a cloth.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum HeatModel {
    /// The paper's model: burning particles push heat to their neighbours, weighted
    /// upward; heat only grows (see [`super::heat`]).
    #[default]
    Paper,
    /// Conduction, upward convection, cooling to the air and heat from burning; heat is
    /// conserved by the exchanges (see [`super::conduction`]). The air is at the material's
    /// `initial_temperature`.
    Physical {
        /// Thermal diffusivity along the cloth, m²/s.
        diffusivity: f32,
        /// Rate at which heat climbs to a cooler particle above, 1/s.
        convection: f32,
        /// Cooling towards the air, 1/s.
        cooling: f32,
        /// Heat released by a burning particle, °C/s: it must outpace what the particle
        /// passes on, or the fire goes out.
        burn_heating: f32,
    },
}

impl HeatModel {
    /// The physical model with values tuned for game cloth with particles about 3 cm apart:
    /// a 16 × 16 cotton cloth lit at the bottom burns away in about 8 s, the fire climbing
    /// faster than it spreads sideways. Diffusivity scales with spacing²: for cloth twice as
    /// fine, a quarter of it gives the same look.
    pub const PHYSICAL: Self = Self::Physical {
        diffusivity: 6e-4,
        convection: 2.0,
        cooling: 0.05,
        burn_heating: 1000.0,
    };

    fn validate(&self) -> Result<(), ClothError> {
        if let Self::Physical {
            diffusivity,
            convection,
            cooling,
            burn_heating,
        } = *self
        {
            for (name, value) in [
                ("heat_model.diffusivity", diffusivity),
                ("heat_model.convection", convection),
                ("heat_model.cooling", cooling),
                ("heat_model.burn_heating", burn_heating),
            ] {
                if !(value.is_finite() && (0.0..=1e5).contains(&value)) {
                    return Err(ClothError::InvalidSetting { name, value });
                }
            }
        }
        Ok(())
    }
}

impl Default for SolverSettings {
    fn default() -> Self {
        Self {
            integrator: Integrator::default(),
            substeps: None,
            max_substeps: 64,
            stability_safety: 0.8,
            provot: Some(ProvotSettings::default()),
            proximity_radius_factor: 0.6,
            collision_margin_factor: 0.3,
            guard: GuardSettings::default(),
            heat_model: HeatModel::Paper,
        }
    }
}

impl SolverSettings {
    /// Checks every setting for a usable value.
    pub fn validate(&self) -> Result<(), ClothError> {
        let invalid = |name, value| Err(ClothError::InvalidSetting { name, value });
        if self.substeps == Some(0) {
            return invalid("substeps", 0.0);
        }
        if self.max_substeps == 0 {
            return invalid("max_substeps", 0.0);
        }
        if !(self.stability_safety > 0.0 && self.stability_safety <= 1.0) {
            return invalid("stability_safety", self.stability_safety);
        }
        if !(self.proximity_radius_factor.is_finite() && self.proximity_radius_factor >= 0.0) {
            return invalid("proximity_radius_factor", self.proximity_radius_factor);
        }
        if !(self.collision_margin_factor.is_finite() && self.collision_margin_factor >= 0.0) {
            return invalid("collision_margin_factor", self.collision_margin_factor);
        }
        if !(self.guard.max_speed.is_finite() && self.guard.max_speed > 0.0) {
            return invalid("guard.max_speed", self.guard.max_speed);
        }
        if let Some(provot) = self.provot
            && !(provot.max_stretch.is_finite() && provot.max_stretch >= 0.0)
        {
            return invalid("provot.max_stretch", provot.max_stretch);
        }
        self.heat_model.validate()
    }

    /// Substeps for a fixed step of `dt` seconds given the cloth's stable step `stable`:
    /// the fixed count if one is set, else the fewest keeping each substep within
    /// `stability_safety × stable`, capped at `max_substeps` (for an unconditionally stable
    /// integrator, capped at [`UNCONDITIONAL_AUTO_SUBSTEPS`] instead: more only adds accuracy).
    pub fn substeps_for(&self, dt: f32, stable: f32) -> u32 {
        if let Some(n) = self.substeps {
            return n.max(1);
        }
        if self.integrator.is_unconditionally_stable() {
            let needed = Self {
                integrator: Integrator::SymplecticEuler,
                ..*self
            }
            .substeps_for(dt, stable);
            return needed.min(UNCONDITIONAL_AUTO_SUBSTEPS);
        }
        let allowed = self.stability_safety * stable;
        if !(allowed.is_finite() && allowed > 0.0) {
            return 1;
        }
        let needed = (dt / allowed).ceil();
        if needed.is_finite() {
            (needed as u32).clamp(1, self.max_substeps.max(1))
        } else {
            self.max_substeps.max(1)
        }
    }
}

/// The world around the cloths.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Environment {
    /// Gravitational acceleration, m/s².
    pub gravity: Vec3,
    /// Wind velocity, m/s.
    pub wind: Vec3,
    /// World up, a unit vector: heat rises along it.
    pub up: Vec3,
}

impl Default for Environment {
    fn default() -> Self {
        Self {
            gravity: Vec3::new(0.0, -9.81, 0.0),
            wind: Vec3::ZERO,
            up: Vec3::Y,
        }
    }
}

impl Environment {
    /// Checks that every vector is finite and `up` is not zero.
    pub fn validate(&self) -> Result<(), ClothError> {
        if !(self.gravity.is_finite() && self.wind.is_finite() && self.up.is_finite())
            || self.up.length_squared() < 1e-12
        {
            return Err(ClothError::NonFinitePoint);
        }
        Ok(())
    }
}

/// Scratch memory of one cloth, reused every step so stepping does not allocate.
#[derive(Clone, Debug, Default)]
pub struct ClothWorkspace {
    /// Integrator buffers.
    pub integrator: IntegratorWorkspace,
    /// Provot buffers.
    pub provot: ProvotWorkspace,
    /// Heat buffers and the spatial hash.
    pub heat: HeatWorkspace,
    /// Particles burnt in the latest combustion update.
    pub newly_burnt: Vec<u32>,
    /// Positions at the start of the step, for the blow-up guard.
    pub guard: BlowUpGuard,
    /// Stable step of the cloth, s, cached by [`ClothWorkspace::stable_step`].
    stable_step: Option<f32>,
}

impl ClothWorkspace {
    /// The cloth's stable symplectic step (s), computed once and cached.
    pub fn stable_step(
        &mut self,
        particles: &Particles,
        springs: &Springs,
        coefficients: &SpringCoefficients,
    ) -> f32 {
        *self
            .stable_step
            .get_or_insert_with(|| stable_time_step(particles, springs, coefficients))
    }

    /// Heap memory held by every buffer, bytes (capacity, not length).
    pub fn heap_bytes(&self) -> usize {
        self.integrator.heap_bytes()
            + self.provot.heap_bytes()
            + self.heat.heap_bytes()
            + self.guard.heap_bytes()
            + self.newly_burnt.capacity() * size_of::<u32>()
    }

    /// Forgets the cached stable step (call after changing masses or stiffness).
    pub fn invalidate_stable_step(&mut self) {
        self.stable_step = None;
    }
}

/// Force parameters of a cloth for the current material and environment.
pub fn force_params(
    material: &BurnMaterial,
    topology: &Topology,
    environment: &Environment,
) -> ForceParams {
    ForceParams {
        gravity: environment.gravity,
        wind: environment.wind,
        drag_per_mass: material.air_drag / material.areal_density,
        coefficients: SpringCoefficients::from_material(material, topology.particle_mass),
    }
}

/// Total mechanical energy of a cloth's unburnt particles, J: kinetic, spring potential
/// (`½ k (l − l₀)²` over live springs) and gravitational potential relative to the origin.
pub fn cloth_energy(
    particles: &Particles,
    springs: &Springs,
    material: &BurnMaterial,
    topology: &Topology,
    environment: &Environment,
) -> f32 {
    let params = force_params(material, topology, environment);
    let gravity: f32 = (0..particles.len())
        .filter(|&i| particles.state[i] != BurnState::Burnt)
        .map(|i| -particles.mass[i] * environment.gravity.dot(particles.position[i]))
        .sum();
    particles.kinetic_energy()
        + springs.potential_energy(&particles.position, &particles.state, &params.coefficients)
        + gravity
}

/// Heat parameters of a cloth for the current material, solver and environment.
pub fn heat_params(
    material: &BurnMaterial,
    topology: &Topology,
    solver: &SolverSettings,
    environment: &Environment,
) -> HeatParams {
    let mut params =
        HeatParams::from_material(material, solver.proximity_radius_factor * topology.spacing);
    params.up = environment.up.normalize_or(Vec3::Y);
    if let HeatModel::Physical {
        diffusivity,
        convection,
        cooling,
        burn_heating,
    } = solver.heat_model
    {
        params.physical = Some(ConductionParams {
            diffusivity,
            convection,
            cooling,
            combustion_heating: burn_heating,
            air_temperature: material.initial_temperature,
            up: params.up,
        });
    }
    params
}

/// Heat phase: one step of `h` seconds of the cloth's heat model.
pub fn heat_phase(
    particles: &mut Particles,
    springs: &Springs,
    params: &HeatParams,
    workspace: &mut ClothWorkspace,
    h: f32,
) {
    match &params.physical {
        None => paper_heat_step(
            springs,
            &particles.position,
            &mut particles.temperature,
            &particles.state,
            params,
            &mut workspace.heat,
            h,
        ),
        Some(physical) => {
            conduction_step(
                springs,
                &particles.position,
                &particles.mass,
                &mut particles.temperature,
                &particles.state,
                physical,
                &mut workspace.heat.delta,
                h,
            );
            proximity_heat_step(
                &particles.position,
                &mut particles.temperature,
                &particles.state,
                params,
                &mut workspace.heat,
                h,
            );
        }
    }
}

/// Combustion phase: burn states from temperatures, then rest lengths shrink by `h`
/// seconds of heat. Particles burnt in this phase are listed in `workspace.newly_burnt`.
pub fn combust_phase(
    particles: &mut Particles,
    springs: &mut Springs,
    material: &BurnMaterial,
    topology: &Topology,
    workspace: &mut ClothWorkspace,
    h: f32,
) -> CombustionReport {
    workspace.newly_burnt.clear();
    // Room for every particle once, so a big burn never reallocates mid-game.
    workspace.newly_burnt.reserve(particles.len());
    let report = update_burn_states(
        &particles.temperature,
        &mut particles.state,
        material,
        &mut workspace.newly_burnt,
    );
    if !workspace.newly_burnt.is_empty() {
        springs.sever_spanning(&particles.state);
    }
    let coefficients = SpringCoefficients::from_material(material, topology.particle_mass);
    shrink_rest_lengths(
        springs,
        &particles.temperature,
        &particles.state,
        material,
        &coefficients,
        h,
    );
    report
}

/// Integration phase of a substep: advance free particles by `h` seconds.
pub fn integrate_phase(
    particles: &mut Particles,
    springs: &Springs,
    params: &ForceParams,
    integrator: Integrator,
    workspace: &mut ClothWorkspace,
    h: f32,
) {
    integrate(
        integrator,
        particles,
        springs,
        params,
        &mut workspace.integrator,
        h,
    );
}

/// Constraint phase of a substep of `h` seconds: Provot's correction, if enabled.
pub fn constrain_phase(
    particles: &mut Particles,
    springs: &Springs,
    provot: Option<ProvotSettings>,
    workspace: &mut ClothWorkspace,
    h: f32,
) -> Option<ProvotReport> {
    provot.map(|provot| provot_correct(particles, springs, &provot, &mut workspace.provot, h))
}

/// One dynamics substep of `h` seconds: integrate, then Provot's correction if enabled.
pub fn dynamics_substep(
    particles: &mut Particles,
    springs: &Springs,
    params: &ForceParams,
    solver: &SolverSettings,
    workspace: &mut ClothWorkspace,
    h: f32,
) -> Option<ProvotReport> {
    integrate_phase(particles, springs, params, solver.integrator, workspace, h);
    constrain_phase(particles, springs, solver.provot, workspace, h)
}

/// Collision phase of a substep: push particles out of colliders.
pub fn collide_phase(
    particles: &mut Particles,
    colliders: &[WorldCollider],
    solver: &SolverSettings,
    topology: &Topology,
) {
    resolve_collisions(
        particles,
        colliders,
        solver.collision_margin_factor * topology.spacing,
    );
}

/// Cull phase: rebuild the live index list from burn states.
pub fn cull_phase(particles: &Particles, topology: &mut Topology) {
    cull_triangles(
        &topology.triangles,
        &particles.state,
        &mut topology.live_indices,
    );
}

/// Raises particle `index` to `temperature` (°C) if it is colder, as an ignition point.
pub fn heat_particle(
    particles: &mut Particles,
    index: usize,
    temperature: f32,
) -> Result<(), ClothError> {
    if index >= particles.len() {
        return Err(ClothError::ParticleOutOfRange {
            index,
            len: particles.len(),
        });
    }
    if !valid_temperature(temperature) {
        return Err(ClothError::InvalidTemperature(temperature));
    }
    let t = &mut particles.temperature[index];
    *t = t.max(temperature);
    Ok(())
}

/// The unburnt particle nearest to `point`.
pub fn nearest_unburnt_particle(particles: &Particles, point: Vec3) -> Result<usize, ClothError> {
    if !point.is_finite() {
        return Err(ClothError::NonFinitePoint);
    }
    (0..particles.len())
        .filter(|&i| particles.state[i] != BurnState::Burnt)
        .min_by(|&a, &b| {
            let da = particles.position[a].distance_squared(point);
            let db = particles.position[b].distance_squared(point);
            da.total_cmp(&db)
        })
        .ok_or(ClothError::NothingLeftToIgnite)
}

/// What one [`ClothSim::step`] did.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StepReport {
    /// Substeps run.
    pub substeps: u32,
    /// Combustion changes.
    pub combustion: CombustionReport,
    /// Provot's report from the last substep, if enabled.
    pub provot: Option<ProvotReport>,
    /// Particles the blow-up guard had to put back.
    pub repaired: u32,
}

/// A cloth with everything needed to step it, outside any ECS.
#[derive(Clone, Debug)]
pub struct ClothSim {
    /// Particles.
    pub particles: Particles,
    /// Springs.
    pub springs: Springs,
    /// Triangles and scale.
    pub topology: Topology,
    /// The material.
    pub material: BurnMaterial,
    /// Solver settings.
    pub solver: SolverSettings,
    /// Gravity, wind and up.
    pub environment: Environment,
    /// Where the cloth's anchors are placed in the world.
    pub transform: Affine3A,
    /// Colliders in the world.
    pub colliders: Vec<WorldCollider>,
    /// Scratch memory.
    pub workspace: ClothWorkspace,
    /// Simulated time, s.
    pub time: f64,
}

impl ClothSim {
    /// Builds a cloth from `builder` with `material`, placed by `transform`.
    pub fn new(
        builder: &ClothBuilder,
        material: BurnMaterial,
        transform: Affine3A,
    ) -> Result<Self, ClothError> {
        let parts = builder.build(&material, transform)?;
        Ok(Self::from_parts(parts, material, transform))
    }

    /// Wraps already built parts.
    pub fn from_parts(parts: ClothParts, material: BurnMaterial, transform: Affine3A) -> Self {
        Self {
            particles: parts.particles,
            springs: parts.springs,
            topology: parts.topology,
            material,
            solver: SolverSettings::default(),
            environment: Environment::default(),
            transform,
            colliders: Vec::new(),
            workspace: ClothWorkspace::default(),
            time: 0.0,
        }
    }

    /// Puts out the fire within `region` (world centre and radius, m; `None` for the whole
    /// cloth): unburnt particles there are cooled to `to` (default
    /// [`extinguished_temperature`](super::combustion::extinguished_temperature), never above
    /// ignition) and stop burning. Returns how many were cooled.
    pub fn extinguish(&mut self, region: Option<(Vec3, f32)>, to: Option<f32>) -> u32 {
        let to = to.unwrap_or_else(|| super::combustion::extinguished_temperature(&self.material));
        super::combustion::extinguish(
            &self.particles.position,
            &mut self.particles.temperature,
            &mut self.particles.state,
            &self.material,
            region,
            to,
        )
    }

    /// Sets particle `index` to the material's seed temperature (if colder).
    pub fn ignite(&mut self, index: usize) -> Result<(), ClothError> {
        heat_particle(&mut self.particles, index, self.material.seed_temperature)
    }

    /// Ignites the unburnt particle nearest to `point` and returns its index.
    pub fn ignite_nearest(&mut self, point: Vec3) -> Result<usize, ClothError> {
        let index = nearest_unburnt_particle(&self.particles, point)?;
        self.ignite(index)?;
        Ok(index)
    }

    /// Heap memory held by the cloth's data and buffers, bytes (capacity, not length).
    pub fn heap_bytes(&self) -> usize {
        let p = &self.particles;
        let vec3 = size_of::<Vec3>();
        let particles = (p.position.capacity()
            + p.velocity.capacity()
            + p.anchor.capacity()
            + p.external_force.capacity())
            * vec3
            + (p.mass.capacity() + p.inv_mass.capacity() + p.temperature.capacity())
                * size_of::<f32>()
            + p.state.capacity();
        let s = &self.springs;
        let springs = (s.a.capacity() + s.b.capacity()) * size_of::<u32>()
            + (s.rest_length.capacity() + s.initial_rest_length.capacity()) * size_of::<f32>()
            + s.kind.capacity()
            + s.spans.capacity() * size_of::<[u32; 2]>();
        let t = &self.topology;
        let topology = t.triangles.capacity() * size_of::<[u32; 3]>()
            + t.uv.capacity() * size_of::<glam::Vec2>()
            + t.live_indices.capacity() * size_of::<u32>();
        particles + springs + topology + self.workspace.heap_bytes()
    }

    /// Distance particles keep from colliders, m.
    pub fn collision_margin(&self) -> f32 {
        self.solver.collision_margin_factor * self.topology.spacing
    }

    /// Substeps a fixed step of `dt` seconds would use.
    pub fn substeps_for(&mut self, dt: f32) -> u32 {
        let params = force_params(&self.material, &self.topology, &self.environment);
        let stable =
            self.workspace
                .stable_step(&self.particles, &self.springs, &params.coefficients);
        self.solver.substeps_for(dt, stable)
    }

    /// Advances the cloth by one fixed step of `dt` seconds through every phase.
    pub fn step(&mut self, dt: f32) -> StepReport {
        if !(dt.is_finite() && dt > 0.0) {
            return StepReport::default();
        }
        let heat = heat_params(
            &self.material,
            &self.topology,
            &self.solver,
            &self.environment,
        );
        heat_phase(
            &mut self.particles,
            &self.springs,
            &heat,
            &mut self.workspace,
            dt,
        );
        let combustion = combust_phase(
            &mut self.particles,
            &mut self.springs,
            &self.material,
            &self.topology,
            &mut self.workspace,
            dt,
        );
        let substeps = self.substeps_for(dt);
        let h = dt / substeps as f32;
        drive_pins(&mut self.particles, self.transform, dt);
        self.workspace.guard.remember(&self.particles);
        let params = force_params(&self.material, &self.topology, &self.environment);
        let mut provot = None;
        for _ in 0..substeps {
            provot = dynamics_substep(
                &mut self.particles,
                &self.springs,
                &params,
                &self.solver,
                &mut self.workspace,
                h,
            );
            collide_phase(
                &mut self.particles,
                &self.colliders,
                &self.solver,
                &self.topology,
            );
        }
        let repaired = self.workspace.guard.check(
            &mut self.particles,
            &self.solver.guard,
            self.material.initial_temperature,
        );
        cull_phase(&self.particles, &mut self.topology);
        self.time += f64::from(dt);
        StepReport {
            substeps,
            combustion,
            provot,
            repaired,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn automatic_substeps_respect_the_stability_limit() {
        let solver = SolverSettings::default();
        assert_eq!(solver.substeps_for(1.0 / 60.0, 1.0), 1);
        let n = solver.substeps_for(1.0 / 60.0, 1.0e-3);
        assert!((1.0 / 60.0) / n as f32 <= 0.8e-3, "{n}");
        assert_eq!(solver.substeps_for(1.0, 1.0e-9), solver.max_substeps);
        assert_eq!(solver.substeps_for(1.0, f32::NAN), 1);
        let fixed = SolverSettings {
            substeps: Some(7),
            ..solver
        };
        assert_eq!(fixed.substeps_for(1.0, 1e-9), 7);
    }

    #[test]
    fn ignition_requests_are_validated() {
        let mut sim = ClothSim::new(
            &ClothBuilder::grid(4, 4, 0.1),
            BurnMaterial::SILK,
            Affine3A::IDENTITY,
        )
        .unwrap();
        assert!(matches!(
            sim.ignite(16),
            Err(ClothError::ParticleOutOfRange { .. })
        ));
        assert_eq!(
            sim.ignite_nearest(Vec3::NAN),
            Err(ClothError::NonFinitePoint)
        );
        assert_eq!(
            heat_particle(&mut sim.particles, 0, f32::INFINITY),
            Err(ClothError::InvalidTemperature(f32::INFINITY))
        );
        assert_eq!(
            heat_particle(&mut sim.particles, 0, -300.0),
            Err(ClothError::InvalidTemperature(-300.0))
        );
        assert_eq!(sim.ignite_nearest(Vec3::new(10.0, -10.0, 0.0)), Ok(15));
        assert_eq!(sim.particles.temperature[15], sim.material.seed_temperature);
        sim.particles.state.fill(BurnState::Burnt);
        assert_eq!(
            sim.ignite_nearest(Vec3::ZERO),
            Err(ClothError::NothingLeftToIgnite)
        );
    }
}
