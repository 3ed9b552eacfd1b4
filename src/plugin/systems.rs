//! The simulation systems: each is a thin loop over cloths calling a phase of
//! [`crate::sim::cloth`].

use super::components::{
    ClothCollider, ClothParticles, ClothScratch, ClothSolver, ClothSprings, ClothStatus,
    ClothTopology, DespawnWhenBurntAway, PendingIgnitions,
};
use super::events::{
    ClothBurntOut, ClothIgnited, ClothInstability, ClothParticlesBurnt, ClothPieceDetached,
    apply_ignition,
};
use super::schedule::{ClothSubstepSchedule, SubstepCounter};
use super::{ClothColliders, ClothEnvironment};
use crate::sim::cloth::{
    collide_phase, combust_phase, constrain_phase, cull_phase, force_params, heat_params,
    heat_phase, integrate_phase,
};
use crate::sim::integrate::drive_pins;
use crate::sim::{BurnMaterial, BurnState, ClothBuilder, MeshClothBuilder};
use bevy::prelude::*;

/// A component that describes a cloth to build: [`ClothBuilder`] (grids) and
/// [`MeshClothBuilder`] (triangle meshes).
pub(crate) trait ClothDescription: Component {
    /// Builds the cloth placed by `transform`.
    fn build_parts(
        &self,
        material: &BurnMaterial,
        transform: bevy::math::Affine3A,
    ) -> Result<crate::sim::ClothParts, crate::sim::ClothError>;
}

impl ClothDescription for ClothBuilder {
    fn build_parts(
        &self,
        material: &BurnMaterial,
        transform: bevy::math::Affine3A,
    ) -> Result<crate::sim::ClothParts, crate::sim::ClothError> {
        self.build(material, transform)
    }
}

impl ClothDescription for MeshClothBuilder {
    fn build_parts(
        &self,
        material: &BurnMaterial,
        transform: bevy::math::Affine3A,
    ) -> Result<crate::sim::ClothParts, crate::sim::ClothError> {
        self.build(material, transform)
    }
}

/// Builds the simulation components of every new or changed cloth description `D`.
pub(crate) fn build_cloths<D: ClothDescription>(
    mut commands: Commands,
    builders: Query<
        (
            Entity,
            &D,
            Option<&BurnMaterial>,
            Option<&ClothSolver>,
            &GlobalTransform,
            Option<&PendingIgnitions>,
        ),
        Changed<D>,
    >,
) {
    for (entity, builder, material, solver, transform, pending) in &builders {
        let material = material.copied().unwrap_or_default();
        // Check the solver before the (costly) build, so a bad one wastes no work.
        let solver = solver.copied().unwrap_or_default();
        if let Err(error) = solver.validate() {
            error!("cloth {entity} not built: {error}");
            continue;
        }
        let parts = builder.build_parts(&material, transform.affine());
        insert_cloth(&mut commands, entity, parts, material, solver, pending);
    }
}

/// Inserts a built cloth's components with its validated solver (or logs why it was not
/// built), applying ignitions that waited for it.
fn insert_cloth(
    commands: &mut Commands,
    entity: Entity,
    parts: Result<crate::sim::ClothParts, crate::sim::ClothError>,
    material: BurnMaterial,
    solver: ClothSolver,
    pending: Option<&PendingIgnitions>,
) {
    let parts = match parts {
        Ok(parts) => parts,
        Err(error) => {
            error!("cloth {entity} not built: {error}");
            return;
        }
    };
    let mut particles = ClothParticles(parts.particles);
    for ignite in pending.iter().flat_map(|p| &p.0) {
        if let Err(error) = apply_ignition(&mut particles, &material, ignite.at, ignite.temperature)
        {
            warn!("Ignite on cloth {entity} ignored: {error}");
        }
    }
    let status = ClothStatus {
        particles: particles.len() as u32,
        pins_left: particles.pins_left() as u32,
        live_triangles: parts.topology.live_triangle_count() as u32,
        ..default()
    };
    commands
        .entity(entity)
        .remove::<PendingIgnitions>()
        .insert((
            particles,
            ClothSprings(parts.springs),
            ClothTopology(parts.topology),
            ClothScratch::new(material, solver.0),
            status,
            material,
            solver,
        ));
}

/// Applies valid material and solver changes, drives pins, picks each cloth's substeps.
pub(crate) fn prepare_cloths(
    time: Res<Time>,
    environment: Res<ClothEnvironment>,
    mut counter: ResMut<SubstepCounter>,
    mut cloths: Query<(
        Entity,
        &mut ClothParticles,
        &ClothSprings,
        &ClothTopology,
        Ref<BurnMaterial>,
        Ref<ClothSolver>,
        &GlobalTransform,
        &mut ClothScratch,
        &mut ClothStatus,
    )>,
) {
    let dt = time.delta_secs();
    counter.count = 0;
    if let Err(error) = environment.validate() {
        warn_once!("ClothEnvironment ignored, previous values kept: {error}");
    }
    for (
        entity,
        mut particles,
        springs,
        topology,
        material,
        solver,
        transform,
        mut scratch,
        mut status,
    ) in &mut cloths
    {
        if material.is_changed() && *material != scratch.material {
            match material.validate() {
                Ok(()) => {
                    scratch.material = *material;
                    scratch.workspace.invalidate_stable_step();
                }
                Err(error) => warn!("cloth {entity}: material change ignored: {error}"),
            }
        }
        if solver.is_changed() && solver.0 != scratch.solver {
            match solver.validate() {
                Ok(()) => scratch.solver = solver.0,
                Err(error) => warn!("cloth {entity}: solver change ignored: {error}"),
            }
        }
        if environment.validate().is_ok() {
            scratch.environment = environment.0;
        }
        let affine = transform.affine();
        if affine.matrix3.is_finite() && affine.translation.is_finite() {
            drive_pins(&mut particles, affine, dt);
        } else {
            warn_once!("cloth {entity}: non-finite transform, pins left where they were");
        }
        let params = force_params(&scratch.material, topology, &scratch.environment);
        let ClothScratch {
            workspace, solver, ..
        } = &mut *scratch;
        workspace.guard.remember(&particles);
        let stable = workspace.stable_step(&particles, springs, &params.coefficients);
        status.substeps = if dt > 0.0 {
            solver.substeps_for(dt, stable)
        } else {
            0
        };
        counter.count = counter.count.max(status.substeps);
    }
}

/// Collects every [`ClothCollider`] in world space for this step.
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
        cache.0.push(crate::sim::WorldCollider {
            shape: collider.shape,
            transform: bevy::math::Affine3A::from_rotation_translation(rotation, translation),
            friction: collider.friction,
        });
    }
}

/// Spreads heat on every cloth.
pub(crate) fn spread_heat(
    time: Res<Time>,
    mut cloths: Query<(
        &mut ClothParticles,
        &ClothSprings,
        &ClothTopology,
        &mut ClothScratch,
    )>,
) {
    let dt = time.delta_secs();
    for (mut particles, springs, topology, mut scratch) in &mut cloths {
        let scratch = &mut *scratch;
        let params = heat_params(
            &scratch.material,
            topology,
            &scratch.solver,
            &scratch.environment,
        );
        heat_phase(&mut particles, springs, &params, &mut scratch.workspace, dt);
    }
}

/// Ignites and burns particles, shrinks springs, tracks loose pieces, and triggers
/// [`ClothIgnited`], [`ClothParticlesBurnt`], [`ClothPieceDetached`] and [`ClothBurntOut`].
pub(crate) fn combust(
    time: Res<Time>,
    mut commands: Commands,
    mut cloths: Query<(
        Entity,
        &mut ClothParticles,
        &mut ClothSprings,
        &ClothTopology,
        &mut ClothScratch,
        &mut ClothStatus,
    )>,
) {
    let dt = time.delta_secs();
    for (entity, mut particles, mut springs, topology, mut scratch, mut status) in &mut cloths {
        let scratch = &mut *scratch;
        let report = combust_phase(
            &mut particles,
            &mut springs,
            &scratch.material,
            topology,
            &mut scratch.workspace,
            dt,
        );
        status.ignited = report.ignited;
        status.burnt += report.newly_burnt;
        let newly_burnt = &scratch.workspace.newly_burnt;
        if !newly_burnt.is_empty() || !scratch.pieces.tracks(particles.len()) {
            scratch.detached.clear();
            scratch
                .pieces
                .update(&particles, &springs, &mut scratch.detached);
            for piece in &scratch.detached {
                commands.trigger(ClothPieceDetached {
                    entity,
                    particles: piece.particles,
                    centroid: piece.centroid,
                });
            }
        }
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
        status.pins_left = particles.pins_left() as u32;
        let burning = report.ignited > 0;
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
    }
}

/// Despawns the cloths marked [`DespawnWhenBurntAway`] of which nothing is left.
pub(crate) fn despawn_burnt_away(
    mut commands: Commands,
    cloths: Query<(Entity, &ClothStatus), With<DespawnWhenBurntAway>>,
    #[cfg(feature = "smoke")] emitters: Query<&crate::smoke::SmokeEmitter>,
) {
    for (entity, status) in &cloths {
        let gone = status.live_triangles == 0 && status.burnt > 0 && !status.burning;
        #[cfg(feature = "smoke")]
        let gone = gone
            && emitters
                .get(entity)
                .ok()
                .is_none_or(|e| e.pool().is_empty());
        if gone {
            commands.entity(entity).despawn();
        }
    }
}

/// Runs the substep schedule as many times as the neediest cloth asks.
pub(crate) fn run_substeps(world: &mut World) {
    let count = world.resource::<SubstepCounter>().count;
    for index in 0..count {
        world.resource_mut::<SubstepCounter>().index = index;
        world.run_schedule(ClothSubstepSchedule);
    }
}

/// Refreshes each cloth's force parameters from its material and the environment.
pub(crate) fn prepare_forces(mut cloths: Query<(&ClothTopology, &mut ClothScratch)>) {
    for (topology, mut scratch) in &mut cloths {
        let scratch = &mut *scratch;
        scratch.force_params = force_params(&scratch.material, topology, &scratch.environment);
    }
}

/// The substep size (s) of a cloth in the running substep, or `None` when the cloth needs
/// fewer substeps than the neediest one and sits this one out.
fn substep_size(counter: &SubstepCounter, status: &ClothStatus, dt: f32) -> Option<f32> {
    (counter.index < status.substeps).then(|| dt / status.substeps as f32)
}

/// Integrates each cloth that takes part in this substep.
pub(crate) fn integrate_cloths(
    time: Res<Time>,
    counter: Res<SubstepCounter>,
    mut cloths: Query<(
        &mut ClothParticles,
        &ClothSprings,
        &mut ClothScratch,
        &ClothStatus,
    )>,
) {
    for (mut particles, springs, mut scratch, status) in &mut cloths {
        let Some(h) = substep_size(&counter, status, time.delta_secs()) else {
            continue;
        };
        let scratch = &mut *scratch;
        integrate_phase(
            &mut particles,
            springs,
            &scratch.force_params,
            scratch.solver.integrator,
            &mut scratch.workspace,
            h,
        );
    }
}

/// Applies Provot's correction and the colliders to each cloth taking part in this substep.
pub(crate) fn constrain_cloths(
    time: Res<Time>,
    counter: Res<SubstepCounter>,
    colliders: Res<ClothColliders>,
    mut cloths: Query<(
        &mut ClothParticles,
        &ClothSprings,
        &ClothTopology,
        &mut ClothScratch,
        &ClothStatus,
    )>,
) {
    for (mut particles, springs, topology, mut scratch, status) in &mut cloths {
        let Some(h) = substep_size(&counter, status, time.delta_secs()) else {
            continue;
        };
        let scratch = &mut *scratch;
        constrain_phase(
            &mut particles,
            springs,
            scratch.solver.provot,
            &mut scratch.workspace,
            h,
        );
        collide_phase(&mut particles, &colliders.0, &scratch.solver, topology);
    }
}

/// Puts back particles that went non-finite or ran away, and reports it.
pub(crate) fn guard_cloths(
    mut commands: Commands,
    mut cloths: Query<(Entity, &mut ClothParticles, &ClothScratch, &mut ClothStatus)>,
) {
    for (entity, mut particles, scratch, mut status) in &mut cloths {
        let repaired = scratch.workspace.guard.check(
            &mut particles,
            &scratch.solver.guard,
            scratch.material.initial_temperature,
        );
        if repaired > 0 {
            if status.repairs == 0 {
                warn!(
                    "cloth {entity}: {repaired} particles blew up and were put back \
                     (raise substeps or lower stiffness); further repairs are counted in \
                     ClothStatus::repairs and reported by ClothInstability"
                );
            }
            status.repairs = status.repairs.saturating_add(repaired);
            commands.trigger(ClothInstability { entity, repaired });
        }
    }
}

/// Rebuilds each cloth's live index list and counts.
pub(crate) fn cull_cloths(
    mut cloths: Query<(&ClothParticles, &mut ClothTopology, &mut ClothStatus)>,
) {
    for (particles, mut topology, mut status) in &mut cloths {
        cull_phase(particles, &mut topology);
        status.live_triangles = topology.live_triangle_count() as u32;
        status.burnt = particles.count(BurnState::Burnt) as u32;
    }
}
