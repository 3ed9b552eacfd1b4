//! [`ClothSim`]: one cloth with everything needed to step it, outside any ECS. Tests, tools,
//! reports and headless programs drive it; it runs the same [`ClothMut::step`] as the plugin.

use super::anchors::DetachedPiece;
use super::collision::WorldCollider;
use super::combustion::{extinguish, extinguished_temperature};
use super::error::ClothError;
use super::grid::{ClothBuilder, ClothParts};
use super::heat_sources::WorldHeatSource;
use super::ignition::{ignite_patch, nearest_unburnt_particle};
use super::material::BurnMaterial;
use super::particles::Particles;
use super::settings::{ClothSettings, Environment, SolverSettings, StepPlan};
use super::springs::Springs;
use super::step::{ClothMut, StepInputs, StepOutcome, StepReport};
use super::topology::Topology;
use super::workspace::ClothWorkspace;
use glam::{Affine3A, Vec3};

/// A cloth with everything needed to step it, outside any ECS.
///
/// Particles, springs and topology are public data; the settings are changed through
/// [`ClothSim::set_settings`] and friends, which validate them and re-derive what depends
/// on them.
#[derive(Clone, Debug)]
pub struct ClothSim {
    /// Particles.
    pub particles: Particles,
    /// Springs.
    pub springs: Springs,
    /// Triangles and scale.
    pub topology: Topology,
    /// Where the cloth's anchors are placed in the world.
    pub transform: Affine3A,
    /// Colliders in the world.
    pub colliders: Vec<WorldCollider>,
    /// Heat sources in the world.
    pub heat_sources: Vec<WorldHeatSource>,
    /// Simulated time, s.
    pub time: f64,
    settings: ClothSettings,
    workspace: ClothWorkspace,
    outcome: StepOutcome,
}

impl ClothSim {
    /// Builds a cloth from `builder` with `material`, placed by `transform`, with the default
    /// solver and environment.
    pub fn new(
        builder: &ClothBuilder,
        material: BurnMaterial,
        transform: Affine3A,
    ) -> Result<Self, ClothError> {
        let parts = builder.build(&material, transform)?;
        Ok(Self::from_parts(parts, material, transform))
    }

    /// Wraps already built parts (the material as they were built with: validated).
    pub fn from_parts(parts: ClothParts, material: BurnMaterial, transform: Affine3A) -> Self {
        let settings = ClothSettings {
            material,
            ..ClothSettings::default()
        };
        Self {
            workspace: ClothWorkspace::new(&settings, &parts.topology),
            particles: parts.particles,
            springs: parts.springs,
            topology: parts.topology,
            transform,
            colliders: Vec::new(),
            heat_sources: Vec::new(),
            time: 0.0,
            settings,
            outcome: StepOutcome::default(),
        }
    }

    /// The settings in use.
    pub fn settings(&self) -> &ClothSettings {
        &self.settings
    }

    /// The material in use.
    pub fn material(&self) -> &BurnMaterial {
        &self.settings.material
    }

    /// The solver in use.
    pub fn solver(&self) -> &SolverSettings {
        &self.settings.solver
    }

    /// The environment in use.
    pub fn environment(&self) -> &Environment {
        &self.settings.environment
    }

    /// Replaces the settings if they are valid; otherwise keeps the old ones and says why.
    pub fn set_settings(&mut self, settings: ClothSettings) -> Result<(), ClothError> {
        settings.validate()?;
        let material_changed = settings.material != self.settings.material;
        self.settings = settings;
        self.workspace
            .settings_changed(&self.settings, &self.topology, material_changed);
        Ok(())
    }

    /// Edits a copy of the settings and takes it into use if it is valid:
    /// `sim.update_settings(|s| s.solver.substeps = Some(4))`.
    pub fn update_settings(
        &mut self,
        edit: impl FnOnce(&mut ClothSettings),
    ) -> Result<(), ClothError> {
        let mut settings = self.settings;
        edit(&mut settings);
        self.set_settings(settings)
    }

    /// Replaces the material if it is valid.
    pub fn set_material(&mut self, material: BurnMaterial) -> Result<(), ClothError> {
        self.set_settings(ClothSettings {
            material,
            ..self.settings
        })
    }

    /// Replaces the solver settings if they are valid.
    pub fn set_solver(&mut self, solver: SolverSettings) -> Result<(), ClothError> {
        self.set_settings(ClothSettings {
            solver,
            ..self.settings
        })
    }

    /// Replaces the environment if it is valid.
    pub fn set_environment(&mut self, environment: Environment) -> Result<(), ClothError> {
        self.set_settings(ClothSettings {
            environment,
            ..self.settings
        })
    }

    /// What the latest step did.
    pub fn outcome(&self) -> &StepOutcome {
        &self.outcome
    }

    /// Particles that burnt away in the latest step.
    pub fn newly_burnt(&self) -> &[u32] {
        self.outcome.newly_burnt()
    }

    /// Pieces that came loose in the latest step.
    pub fn detached(&self) -> &[DetachedPiece] {
        self.outcome.detached()
    }

    /// Puts out the fire within `region` (world centre and radius, m; `None` for the whole
    /// cloth): unburnt particles there are cooled to `to` (default
    /// [`extinguished_temperature`], never above ignition) and stop burning. Returns how many
    /// were cooled.
    pub fn extinguish(&mut self, region: Option<(Vec3, f32)>, to: Option<f32>) -> u32 {
        let material = self.settings.material;
        let to = to.unwrap_or_else(|| extinguished_temperature(&material));
        self.workspace
            .flames
            .put_out(&self.particles.position, region);
        extinguish(
            &self.particles.position,
            &mut self.particles.temperature,
            &mut self.particles.state,
            &material,
            region,
            to,
        )
    }

    /// Sets particle `index`, and the unburnt particles within
    /// [`IGNITION_RADIUS`](super::ignition::IGNITION_RADIUS) of it, to the material's seed
    /// temperature (where colder).
    pub fn ignite(&mut self, index: usize) -> Result<(), ClothError> {
        ignite_patch(
            &mut self.particles,
            index,
            self.settings.material.seed_temperature,
        )
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
            + s.spans.capacity() * size_of::<[u32; 2]>()
            + s.span_rule.capacity() * size_of::<super::springs::SpanRule>();
        let t = &self.topology;
        let topology = t.triangles.capacity() * size_of::<[u32; 3]>()
            + t.uv.capacity() * size_of::<glam::Vec2>()
            + t.live_indices.capacity() * size_of::<u32>();
        particles + springs + topology + self.workspace.heap_bytes() + self.outcome.heap_bytes()
    }

    /// Distance particles keep from colliders, m.
    pub fn collision_margin(&self) -> f32 {
        self.settings.solver.collision_margin_factor * self.topology.spacing
    }

    /// The cloth's stable step for symplectic Euler and Verlet, s (Gershgorin's bound).
    pub fn stable_step(&mut self) -> f32 {
        self.workspace.stable_step(&self.particles, &self.springs)
    }

    /// Call after rewriting the cloth's burn states, temperatures or springs from outside
    /// (restoring a burnt cloth to new): which particles burn, what is drawn and what hangs
    /// from what are worked out anew at the next step. Memory is reused.
    pub fn restart(&mut self) {
        self.workspace.restart();
    }

    /// Forgets the cached stable step: call after editing masses or springs by hand.
    pub fn forget_stable_step(&mut self) {
        self.workspace.forget_stable_step();
    }

    /// How a fixed step of `dt` seconds would be run: integrator and substeps.
    pub fn plan(&mut self, dt: f32) -> StepPlan {
        let stable = self.stable_step();
        self.settings.solver.plan(dt, stable, self.topology.spacing)
    }

    /// Advances the cloth by one fixed step of `dt` seconds through every phase, on this
    /// thread.
    pub fn step(&mut self, dt: f32) -> StepReport {
        self.step_on(dt, None)
    }

    /// Advances the cloth by one fixed step of `dt` seconds, sharing a big cloth's work with
    /// the threads of `pool` (with feature `parallel`). The result is the same on any number
    /// of threads.
    pub fn step_on(&mut self, dt: f32, pool: Option<&bevy::tasks::TaskPool>) -> StepReport {
        let inputs = StepInputs {
            colliders: &self.colliders,
            heat_sources: &self.heat_sources,
            pool,
            ..StepInputs::new(dt, self.transform)
        };
        ClothMut {
            particles: &mut self.particles,
            springs: &mut self.springs,
            topology: &mut self.topology,
            settings: &self.settings,
            workspace: &mut self.workspace,
            outcome: &mut self.outcome,
        }
        .step(&inputs);
        if dt.is_finite() && dt > 0.0 {
            self.time += f64::from(dt);
        }
        self.outcome.report
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A cloth with every particle pinned skips its substeps: moved as a whole, it lands on
    /// its targets exactly as when a free particle makes the solver run.
    #[test]
    fn a_cloth_held_at_every_particle_follows_its_pins() {
        let builder = ClothBuilder::grid(6, 5, 0.1).pin_all();
        let mut held = ClothSim::new(&builder, BurnMaterial::COTTON, Affine3A::IDENTITY).unwrap();
        // The same cloth with one corner free, so the solver runs.
        let mut one_free = held.clone();
        one_free.particles.inv_mass[29] = 1.0;
        for frame in 1..=30 {
            let moved = Affine3A::from_translation(Vec3::new(0.01 * frame as f32, 0.0, 0.0));
            for sim in [&mut held, &mut one_free] {
                sim.transform = moved;
                sim.step(1.0 / 60.0);
            }
        }
        for i in 0..29 {
            let target = held.transform.transform_point3(held.particles.anchor[i]);
            assert_eq!(held.particles.position[i], target, "particle {i}");
            assert_eq!(
                one_free.particles.position[i], target,
                "particle {i}, solver ran"
            );
            assert_eq!(held.particles.velocity[i], one_free.particles.velocity[i]);
        }
    }
    use crate::sim::BurnState;

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
            crate::sim::ignition::heat_particle(&mut sim.particles, 0, f32::INFINITY),
            Err(ClothError::InvalidTemperature(f32::INFINITY))
        );
        assert_eq!(
            crate::sim::ignition::heat_particle(&mut sim.particles, 0, -300.0),
            Err(ClothError::InvalidTemperature(-300.0))
        );
        assert_eq!(sim.ignite_nearest(Vec3::new(10.0, -10.0, 0.0)), Ok(15));
        assert_eq!(
            sim.particles.temperature[15],
            sim.material().seed_temperature
        );
        sim.particles.state.fill(BurnState::Burnt);
        assert_eq!(
            sim.ignite_nearest(Vec3::ZERO),
            Err(ClothError::NothingLeftToIgnite)
        );
    }

    #[test]
    fn invalid_settings_are_refused_and_the_old_ones_kept() {
        let mut sim = ClothSim::new(
            &ClothBuilder::grid(4, 4, 0.1),
            BurnMaterial::SILK,
            Affine3A::IDENTITY,
        )
        .unwrap();
        let mut bad = BurnMaterial::COTTON;
        bad.areal_density = f32::NAN;
        assert!(sim.set_material(bad).is_err());
        assert_eq!(*sim.material(), BurnMaterial::SILK);
        sim.set_material(BurnMaterial::COTTON).unwrap();
        assert_eq!(
            sim.workspace.derived().force.drag_per_mass,
            BurnMaterial::COTTON.air_drag / BurnMaterial::COTTON.areal_density,
            "derived parameters follow the material"
        );
    }
}
