//! The simulation systems. Each is a thin loop over cloth entities; the physics of a step is
//! [`ClothMut::step`](crate::sim::ClothMut::step), called once per cloth.

use super::components::{
    ClothCollider, ClothInUse, ClothParticles, ClothScratch, ClothSolver, ClothSprings,
    ClothStatus, ClothTopology, DespawnWhenBurntAway, HoldBuild, HoldDespawn, PendingIgnitions,
};
use super::control::ClothStepTiming;
use super::events::{
    ClothBurntOut, ClothIgnited, ClothInstability, ClothParticlesBurnt, ClothPieceDetached,
    apply_ignition,
};
use super::heat_sources::ClothHeatSources;
use super::{ClothColliders, ClothEnvironment};
use crate::sim::{
    self, BurnMaterial, ClothBuilder, ClothMut, ClothSettings, MeshClothBuilder, StepInputs,
};
use bevy::ecs::batching::BatchingStrategy;
use bevy::prelude::*;
use bevy::tasks::{ComputeTaskPool, TaskPool};

/// A component that describes a cloth to build: [`ClothBuilder`] (grids) and
/// [`MeshClothBuilder`] (triangle meshes).
pub(crate) trait ClothDescription: Component {
    /// Builds the cloth placed by `transform`.
    fn build_parts(
        &self,
        material: &BurnMaterial,
        transform: bevy::math::Affine3A,
    ) -> Result<sim::ClothParts, sim::ClothError>;
}

impl ClothDescription for ClothBuilder {
    fn build_parts(
        &self,
        material: &BurnMaterial,
        transform: bevy::math::Affine3A,
    ) -> Result<sim::ClothParts, sim::ClothError> {
        self.build(material, transform)
    }
}

impl ClothDescription for MeshClothBuilder {
    fn build_parts(
        &self,
        material: &BurnMaterial,
        transform: bevy::math::Affine3A,
    ) -> Result<sim::ClothParts, sim::ClothError> {
        self.build(material, transform)
    }
}

/// Builds the simulation components of every new or changed cloth description `D`.
pub(crate) fn build_cloths<D: ClothDescription>(
    mut commands: Commands,
    environment: Res<ClothEnvironment>,
    builders: Query<
        (
            Entity,
            &D,
            Option<&BurnMaterial>,
            Option<&ClothSolver>,
            &GlobalTransform,
            Option<&PendingIgnitions>,
        ),
        (Changed<D>, Without<HoldBuild>),
    >,
) {
    for (entity, builder, material, solver, transform, pending) in &builders {
        let settings = ClothSettings {
            material: material.copied().unwrap_or_default(),
            solver: solver.copied().unwrap_or_default().0,
            environment: if environment.validate().is_ok() {
                environment.0
            } else {
                sim::Environment::default()
            },
        };
        // Check the solver before the (costly) build, so a bad one wastes no work; the build
        // checks the material.
        if let Err(error) = settings.solver.validate() {
            error!("cloth {entity} not built: {error}");
            continue;
        }
        match builder.build_parts(&settings.material, transform.affine()) {
            Ok(parts) => insert_cloth(&mut commands, entity, parts, settings, pending),
            Err(error) => error!("cloth {entity} not built: {error}"),
        }
    }
}

/// Inserts a built cloth's components with its validated settings, applying ignitions that
/// waited for it.
fn insert_cloth(
    commands: &mut Commands,
    entity: Entity,
    parts: sim::ClothParts,
    settings: ClothSettings,
    pending: Option<&PendingIgnitions>,
) {
    let mut particles = ClothParticles(parts.particles);
    for ignite in pending.iter().flat_map(|p| &p.0) {
        if let Err(error) = apply_ignition(
            &mut particles,
            &settings.material,
            ignite.at,
            ignite.temperature,
        ) {
            warn!("Ignite on cloth {entity} ignored: {error}");
        }
    }
    let status = ClothStatus {
        particles: particles.len() as u32,
        pins_left: particles.pins_left() as u32,
        live_triangles: parts.topology.live_triangle_count() as u32,
        burnt: particles.count(sim::BurnState::Burnt) as u32,
        integrator: settings.solver.integrator,
        ..default()
    };
    let scratch = ClothScratch(sim::ClothWorkspace::new(&settings, &parts.topology));
    commands
        .entity(entity)
        .remove::<PendingIgnitions>()
        .insert((
            particles,
            ClothSprings(parts.springs),
            ClothTopology(parts.topology),
            ClothInUse::new(settings),
            scratch,
            status,
            settings.material,
            ClothSolver(settings.solver),
        ));
}

/// Takes valid material, solver and environment changes into use (Prepare); invalid ones
/// are logged and the previous values kept.
pub(crate) fn take_settings_into_use(
    environment: Res<ClothEnvironment>,
    mut cloths: Query<(
        Entity,
        Ref<BurnMaterial>,
        Ref<ClothSolver>,
        &ClothTopology,
        &mut ClothInUse,
        &mut ClothScratch,
    )>,
) {
    let environment_changed = environment.is_changed();
    let valid_environment = match environment.validate() {
        Ok(()) => Some(environment.0),
        Err(error) => {
            if environment_changed {
                warn_once!("ClothEnvironment ignored, previous values kept: {error}");
            }
            None
        }
    };
    for (entity, material, solver, topology, mut in_use, mut scratch) in &mut cloths {
        let mut settings = in_use.settings;
        if material.is_changed() && *material != settings.material {
            match material.validate() {
                Ok(()) => settings.material = *material,
                Err(error) => warn!("cloth {entity}: material change ignored: {error}"),
            }
        }
        if solver.is_changed() && solver.0 != settings.solver {
            match solver.validate() {
                Ok(()) => settings.solver = solver.0,
                Err(error) => warn!("cloth {entity}: solver change ignored: {error}"),
            }
        }
        if let Some(environment) = valid_environment {
            settings.environment = environment;
        }
        if settings != in_use.settings {
            let material_changed = settings.material != in_use.settings.material;
            scratch
                .0
                .settings_changed(&settings, topology, material_changed);
            in_use.settings = settings;
        }
    }
}

/// Collects every [`ClothCollider`] in world space for this step (Prepare).
pub(crate) fn gather_colliders(
    mut cache: ResMut<ClothColliders>,
    colliders: Query<(Entity, &ClothCollider, &GlobalTransform)>,
) {
    cache.0.clear();
    for (entity, collider, transform) in &colliders {
        let affine = transform.affine();
        let valid = collider.shape.is_valid()
            && collider.friction.is_finite()
            && affine.matrix3.is_finite()
            && affine.translation.is_finite();
        if !valid {
            warn_once!("ClothCollider on {entity} skipped: invalid shape, friction or transform");
            continue;
        }
        // Keep rotation and translation only: colliders are rigid.
        let (_, rotation, translation) = transform.to_scale_rotation_translation();
        cache.0.push(sim::WorldCollider {
            shape: collider.shape,
            transform: bevy::math::Affine3A::from_rotation_translation(rotation, translation),
            friction: collider.friction,
        });
    }
}

/// Particles from which a cloth's own work is split over the compute pool; smaller cloths
/// step one per task, side by side.
const SPLIT_CLOTH_PARTICLES: usize = 8192;

/// Steps every cloth once (Simulate): small cloths side by side on the compute task pool,
/// each on one thread; big ones one after another, each split
/// over the pool. Every cloth's step reads only the world gathered in Prepare, so neither the
/// order nor the number of threads changes the result.
pub(crate) fn simulate_cloths(
    time: Res<Time>,
    colliders: Res<ClothColliders>,
    sources: Res<ClothHeatSources>,
    mut cloths: Query<(
        Entity,
        &mut ClothParticles,
        &mut ClothSprings,
        &mut ClothTopology,
        &mut ClothInUse,
        &mut ClothScratch,
        &GlobalTransform,
    )>,
) {
    let dt = time.delta_secs();
    let world = Surroundings {
        colliders: &colliders.0,
        sources: &sources,
        dt,
    };
    let is_small = |particles: &ClothParticles| particles.len() < SPLIT_CLOTH_PARTICLES;
    // One cloth per task, so cloths of different sizes share the threads evenly. (Bevy runs
    // this on one thread when its compute pool has one, as on a 2-core machine by default:
    // see the README for giving it both cores.)
    cloths
        .par_iter_mut()
        .batching_strategy(BatchingStrategy::fixed(1))
        .for_each(|cloth| {
            if is_small(&cloth.1) {
                step_cloth(cloth, &world, None);
            }
        });
    let pool = ComputeTaskPool::try_get().map(|pool| &**pool);
    for cloth in cloths.iter_mut().filter(|cloth| !is_small(&cloth.1)) {
        step_cloth(cloth, &world, pool);
    }
}

/// What every cloth steps against.
struct Surroundings<'a> {
    colliders: &'a [sim::WorldCollider],
    sources: &'a ClothHeatSources,
    dt: f32,
}

type ClothItem<'a> = (
    Entity,
    Mut<'a, ClothParticles>,
    Mut<'a, ClothSprings>,
    Mut<'a, ClothTopology>,
    Mut<'a, ClothInUse>,
    Mut<'a, ClothScratch>,
    &'a GlobalTransform,
);

/// One cloth's step, its own work split over `pool` if given.
fn step_cloth(cloth: ClothItem, world: &Surroundings, pool: Option<&TaskPool>) {
    let (entity, mut particles, mut springs, mut topology, mut in_use, mut scratch, transform) =
        cloth;
    let affine = transform.affine();
    if !(affine.matrix3.is_finite() && affine.translation.is_finite()) {
        warn_once!("cloth {entity}: non-finite transform, pins left where they were");
    }
    let inputs = StepInputs {
        colliders: world.colliders,
        heat_sources: &world.sources.explicit,
        fire_spread: Some(&world.sources.burning),
        owner: entity.to_bits(),
        pool,
        ..StepInputs::new(world.dt, affine)
    };
    let in_use = &mut *in_use;
    ClothMut {
        particles: &mut particles.0,
        springs: &mut springs.0,
        topology: &mut topology.0,
        settings: &in_use.settings,
        workspace: &mut scratch.0,
        outcome: &mut in_use.outcome,
    }
    .step(&inputs);
}

/// Writes each cloth's [`ClothStatus`] from its latest step and triggers the events
/// (Report): [`ClothPieceDetached`], [`ClothParticlesBurnt`], [`ClothIgnited`],
/// [`ClothBurntOut`], [`ClothInstability`].
pub(crate) fn report_cloths(
    mut commands: Commands,
    mut timing: ResMut<ClothStepTiming>,
    mut cloths: Query<(Entity, &ClothParticles, &ClothInUse, &mut ClothStatus)>,
) {
    let mut most_substeps = 0;
    for (entity, particles, in_use, mut status) in &mut cloths {
        let report = in_use.last_step();
        most_substeps = most_substeps.max(report.substeps);
        for piece in in_use.detached() {
            commands.trigger(ClothPieceDetached {
                entity,
                particles: piece.particles,
                centroid: piece.centroid,
            });
        }
        let newly_burnt = in_use.newly_burnt();
        if !newly_burnt.is_empty() {
            let sum: Vec3 = newly_burnt
                .iter()
                .map(|&i| particles.position[i as usize])
                .sum();
            commands.trigger(ClothParticlesBurnt {
                entity,
                count: newly_burnt.len() as u32,
                centroid: sum / newly_burnt.len() as f32,
            });
        }
        status.ignited = report.combustion.ignited;
        status.burnt = report.burnt;
        status.pins_left = report.pins_left;
        status.live_triangles = report.live_triangles;
        status.substeps = report.substeps;
        let chosen = in_use.solver().integrator;
        if report.integrator != chosen && report.integrator != status.integrator {
            info!(
                "cloth {entity}: {} would need more than {} substeps here; stepping it with {} \
                 instead (SolverSettings::stiff_fallback)",
                chosen.name(),
                in_use.solver().max_substeps,
                report.integrator.name(),
            );
        }
        status.integrator = report.integrator;
        let burning = report.combustion.ignited > 0;
        if burning && !status.burning {
            commands.trigger(ClothIgnited { entity });
        }
        if !burning && status.burning {
            commands.trigger(ClothBurntOut {
                entity,
                burnt_fraction: status.burnt_fraction(),
            });
        }
        status.burning = burning;
        let repaired = report.repaired;
        if repaired > 0 {
            if status.repairs == 0 {
                warn!(
                    "cloth {entity}: {repaired} particles blew up and were put back \
                     (use XPBD, raise substeps or lower stiffness); further repairs are counted in \
                     ClothStatus::repairs and reported by ClothInstability"
                );
            }
            status.repairs = status.repairs.saturating_add(repaired);
            commands.trigger(ClothInstability { entity, repaired });
        }
    }
    timing.substeps = most_substeps;
}

/// Despawns the cloths marked [`DespawnWhenBurntAway`] of which nothing is left and that
/// nothing holds with [`HoldDespawn`].
pub(crate) fn despawn_burnt_away(
    mut commands: Commands,
    cloths: Query<(Entity, &ClothStatus), (With<DespawnWhenBurntAway>, Without<HoldDespawn>)>,
) {
    for (entity, status) in &cloths {
        if status.live_triangles == 0 && status.burnt > 0 && !status.burning {
            commands.entity(entity).despawn();
        }
    }
}
