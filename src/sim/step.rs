//! One step of one cloth: the order of the phases, defined here and nowhere else.
//!
//! [`ClothMut::step`] advances a cloth by one fixed step of `dt` seconds:
//!
//! 1. **pins** follow the cloth's transform (so heating sees the cloth where it is);
//! 2. **heat**: the cloth's heat model (the paper's push or the physical model, with
//!    proximity heating across folds), then heat sources (torches, fireballs) and the burning
//!    particles of other cloths;
//! 3. **combustion**: ignition and burning by temperature, spans over burnt particles cut,
//!    rest lengths shrink, what each particle hangs from brought up to date (pieces that lost
//!    every pin found);
//! 4. **dynamics**: `substeps` × (integrate, Provot's correction, colliders); external forces
//!    act for the whole step and are cleared after it; the blow-up guard puts back particles
//!    that went non-finite or ran away;
//! 5. **culling**: the index list keeps the triangles with three unburnt particles.
//!
//! [`ClothSim`](super::ClothSim) runs it on a cloth it owns; the plugin runs it on each cloth
//! entity's components. Both give bit-identical results for the same inputs.

use super::anchors::DetachedPiece;
use super::collision::{WorldCollider, resolve_collisions};
use super::combustion::CombustionReport;
use super::conduction::{Air, conduction_step};
use super::flame::{FlameParams, flame_step};
use super::front::Counts;
use super::guard::BlowUpGuard;
use super::heat::{paper_heat_step, proximity_heat_step};
use super::heat_sources::{
    HashedHeatSources, WorldHeatSource, apply_hashed_heat_sources, apply_heat_sources,
    unburnt_bounds,
};
use super::integrate::{Integrator, drive_pins, integrate};
use super::particles::Particles;
use super::provot::{ProvotReport, provot_correct};
use super::settings::{ClothSettings, StepPlan};
use super::springs::Springs;
use super::topology::Topology;
use super::workspace::ClothWorkspace;
use super::xpbd::{StretchLimit, Surroundings};
use bevy::platform::time::Instant;
use core::time::Duration;
use glam::{Affine3A, Vec3};

/// Most rounds of Provot's limit per substep XPBD runs over the heated springs (it takes six
/// or more substeps a frame), each over every heated spring, stopping after one that
/// corrects nothing. Four made a burning 64 x 64 cloth's dynamics half as dear again (0.72
/// against 0.50 ms, `examples/stress.rs`) and held a shrunk block to a mean stretch of 1.16
/// where two hold it to 1.21 (`tests/burning.rs`, springs as stiff in compression as in
/// tension; two hold it to 1.14 with the presets' softer compression).
const XPBD_STRETCH_LIMIT_PASSES: u32 = 2;

/// The world as one cloth's step sees it.
#[derive(Clone, Copy)]
pub struct StepInputs<'a> {
    /// The step, s.
    pub dt: f32,
    /// Where the cloth's anchors are placed: pins go to `transform × anchor`.
    pub transform: Affine3A,
    /// Colliders in world space.
    pub colliders: &'a [WorldCollider],
    /// Heat sources in world space (torches, fireballs).
    pub heat_sources: &'a [WorldHeatSource],
    /// The burning particles of every cloth, hashed; this cloth's own (`owner`) are skipped.
    pub fire_spread: Option<&'a HashedHeatSources>,
    /// This cloth's id among the owners in `fire_spread`.
    pub owner: u64,
    /// Threads to share a big cloth's work with (Bevy's compute task pool), if any. The
    /// result is the same with or without.
    pub pool: Option<&'a bevy::tasks::TaskPool>,
}

impl<'a> StepInputs<'a> {
    /// A step of `dt` seconds with the cloth placed by `transform`, and nothing around it.
    pub fn new(dt: f32, transform: Affine3A) -> Self {
        Self {
            dt,
            transform,
            colliders: &[],
            heat_sources: &[],
            fire_spread: None,
            owner: WorldHeatSource::NO_OWNER,
            pool: None,
        }
    }
}

/// Wall time of each phase of a step.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PhaseTimes {
    /// Pins and heat: the heat model, heat sources, other cloths' fires.
    pub heat: Duration,
    /// Burn states, cut springs, shrinking rest lengths.
    pub combustion: Duration,
    /// What hangs from what, and the pieces that came loose.
    pub pieces: Duration,
    /// The substeps and the blow-up guard.
    pub dynamics: Duration,
    /// Removing burnt triangles from the drawn list.
    pub culling: Duration,
}

impl PhaseTimes {
    /// The whole step.
    pub fn total(&self) -> Duration {
        self.heat + self.combustion + self.pieces + self.dynamics + self.culling
    }
}

/// What one step did, in numbers.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StepReport {
    /// Substeps run.
    pub substeps: u32,
    /// The integrator that ran: the chosen one, or XPBD when a force-based integrator would
    /// have needed more than its substep cap (see
    /// [`SolverSettings::stiff_fallback`](super::SolverSettings::stiff_fallback)).
    pub integrator: Integrator,
    /// Combustion changes.
    pub combustion: CombustionReport,
    /// Provot's report from the last substep, if enabled.
    pub provot: Option<ProvotReport>,
    /// Particles the blow-up guard had to put back.
    pub repaired: u32,
    /// Particles burnt away in total, after the step.
    pub burnt: u32,
    /// Pinned particles not burnt, after the step.
    pub pins_left: u32,
    /// Triangles drawn, after the step.
    pub live_triangles: u32,
    /// Wall time of each phase.
    pub times: PhaseTimes,
}

/// What the latest step did: its report, the particles that burnt away in it and the pieces
/// that came loose in it. Kept until the next step.
#[derive(Clone, Debug, Default)]
pub struct StepOutcome {
    /// The numbers.
    pub report: StepReport,
    pub(crate) newly_burnt: Vec<u32>,
    pub(crate) detached: Vec<DetachedPiece>,
}

impl StepOutcome {
    /// Indices of the particles that burnt away in the latest step.
    pub fn newly_burnt(&self) -> &[u32] {
        &self.newly_burnt
    }

    /// Pieces that lost their last pin in the latest step.
    pub fn detached(&self) -> &[DetachedPiece] {
        &self.detached
    }

    /// Heap memory held, bytes (capacity, not length).
    pub fn heap_bytes(&self) -> usize {
        self.newly_burnt.capacity() * size_of::<u32>()
            + self.detached.capacity() * size_of::<DetachedPiece>()
    }
}

/// One cloth, borrowed: what [`ClothMut::step`] reads and writes. The plugin builds it from a
/// cloth entity's components, [`ClothSim`](super::ClothSim) from its fields.
pub struct ClothMut<'a> {
    /// Particles.
    pub particles: &'a mut Particles,
    /// Springs.
    pub springs: &'a mut Springs,
    /// Triangles and scale.
    pub topology: &'a mut Topology,
    /// The validated settings in use.
    pub settings: &'a ClothSettings,
    /// Derived parameters and scratch memory.
    pub workspace: &'a mut ClothWorkspace,
    /// What the step did.
    pub outcome: &'a mut StepOutcome,
}

impl ClothMut<'_> {
    /// Advances the cloth by one step: pins, heat, combustion, dynamics, culling (see the
    /// [module docs](self)). A step that is not finite and positive does nothing.
    pub fn step(&mut self, inputs: &StepInputs) {
        self.outcome.newly_burnt.clear();
        self.outcome.detached.clear();
        if !(inputs.dt.is_finite() && inputs.dt > 0.0) {
            self.outcome.report = StepReport::default();
            return;
        }
        let mut times = PhaseTimes::default();
        let mut clock = Instant::now();
        let mut lap = |phase: &mut Duration| {
            let now = Instant::now();
            *phase = now - clock;
            clock = now;
        };
        self.workspace
            .front
            .prepare(self.particles, self.springs, self.topology);
        self.drive_pins(inputs);
        self.heat(inputs);
        lap(&mut times.heat);
        let (combustion, counts) = self.combust(inputs.dt);
        lap(&mut times.combustion);
        self.hang();
        lap(&mut times.pieces);
        let (plan, provot, repaired) = self.dynamics(inputs);
        lap(&mut times.dynamics);
        self.cull();
        lap(&mut times.culling);
        self.outcome.report = StepReport {
            substeps: plan.substeps,
            integrator: plan.integrator,
            combustion,
            provot,
            repaired,
            burnt: counts.burnt,
            pins_left: counts.pins_left,
            live_triangles: self.topology.live_triangle_count() as u32,
            times,
        };
    }

    /// Phase 1: pins follow the transform (a non-finite transform leaves them where they are).
    fn drive_pins(&mut self, inputs: &StepInputs) {
        let affine = inputs.transform;
        if affine.matrix3.is_finite() && affine.translation.is_finite() {
            let pins = self.workspace.front.pins();
            drive_pins(self.particles, pins, affine, inputs.dt);
        }
    }

    /// Phase 2: the cloth's heat model, then heat sources and other cloths' fires.
    fn heat(&mut self, inputs: &StepInputs) {
        let h = inputs.dt;
        let particles = &mut *self.particles;
        let ClothWorkspace {
            derived,
            heat,
            front,
            conduction,
            flames,
            ..
        } = &mut *self.workspace;
        let params = &derived.heat;
        match &params.physical {
            None => paper_heat_step(front, self.springs, particles, params, heat, h),
            Some(physical) => {
                // Nothing to conduct until something has been warm.
                if front.any_warm() {
                    let air = Air {
                        temperature: params.initial_temperature,
                        up: params.up,
                    };
                    conduction_step(
                        self.springs,
                        &particles.position,
                        &particles.mass,
                        &mut particles.temperature,
                        &particles.state,
                        physical,
                        air,
                        conduction,
                        h,
                    );
                }
                if !(front.ignited().is_empty() && flames.sources().is_empty()) {
                    let flame = FlameParams {
                        material: &self.settings.material,
                        up: params.up,
                    };
                    flame_step(front, self.springs, particles, &flame, flames, h);
                }
                proximity_heat_step(front, particles, params, heat, h);
            }
        }
        let spreading = inputs
            .fire_spread
            .filter(|spread| !spread.sources.is_empty());
        if inputs.heat_sources.is_empty() && spreading.is_none() {
            return;
        }
        let Some(bounds) = unburnt_bounds(&particles.position, &particles.state) else {
            return;
        };
        if !inputs.heat_sources.is_empty() {
            apply_heat_sources(
                &particles.position,
                &mut particles.temperature,
                &particles.state,
                bounds,
                inputs.heat_sources,
                h,
            );
        }
        if let Some(spread) = spreading {
            apply_hashed_heat_sources(
                &particles.position,
                &mut particles.temperature,
                &particles.state,
                bounds,
                inputs.owner,
                spread,
                h,
            );
        }
    }

    /// Phase 3: burn states from temperatures; springs over newly burnt particles cut; rest
    /// lengths shrink by `h` seconds of heat; what hangs from what brought up to date (pieces
    /// that lost every pin found).
    fn combust(&mut self, h: f32) -> (CombustionReport, Counts) {
        let particles = &mut *self.particles;
        let newly_burnt = &mut self.outcome.newly_burnt;
        // Room for every particle once, so a big burn never reallocates mid-game.
        newly_burnt.reserve(particles.len());
        self.outcome.detached.reserve(particles.len());
        let material = &self.settings.material;
        let front = &mut self.workspace.front;
        let (report, counts) = front.scan(particles, self.springs, material, h, newly_burnt);
        if !newly_burnt.is_empty() {
            front.sever(self.springs, &particles.state, newly_burnt);
        }
        let coefficients = &self.workspace.derived.force.coefficients;
        front.shrink(self.springs, particles, material, coefficients, h);
        (report, counts)
    }

    /// Phase 3b: what each particle hangs from, after this step's burns; the pieces that lost
    /// every pin.
    fn hang(&mut self) {
        self.workspace.anchors.update(
            self.particles,
            self.springs,
            &self.outcome.newly_burnt,
            &mut self.outcome.detached,
        );
    }

    /// Phase 4: the substeps and the blow-up guard. Returns how the step ran, Provot's
    /// report from the last substep and the particles put back.
    fn dynamics(&mut self, inputs: &StepInputs) -> (StepPlan, Option<ProvotReport>, u32) {
        let solver = &self.settings.solver;
        let stable = self.workspace.stable_step(self.particles, self.springs);
        let plan = solver.plan(inputs.dt, stable, self.topology.spacing);
        let substeps = plan.substeps;
        let h = inputs.dt / substeps as f32;
        let workspace = &mut *self.workspace;
        let margin = solver.collision_margin_factor * self.topology.spacing;
        if plan.integrator == Integrator::Xpbd {
            let around = Surroundings {
                params: &workspace.derived.force,
                colliders: inputs.colliders,
                margin,
                guard: solver.guard,
                tethers: solver
                    .tether_stretch
                    .map(|stretch| (&workspace.anchors, stretch)),
                stretch_limit: solver.provot.map(|provot| StretchLimit {
                    springs: workspace.front.shrunk(),
                    stretch: provot.max_stretch,
                    passes: provot.passes.min(XPBD_STRETCH_LIMIT_PASSES),
                }),
                pool: inputs.pool,
            };
            let (moved, pins_changed) = workspace.integrator.xpbd.advance(
                self.particles,
                self.springs,
                self.topology.grid,
                &around,
                h,
                substeps,
            );
            if pins_changed {
                workspace.anchors.invalidate();
            }
            let heated = BlowUpGuard::repair_temperatures(
                self.particles,
                &solver.guard,
                self.settings.material.initial_temperature,
            );
            self.particles.external_force.fill(Vec3::ZERO);
            return (plan, None, moved + heated);
        }
        workspace.guard.remember(self.particles);
        let mut provot = None;
        for _ in 0..substeps {
            integrate(
                plan.integrator,
                self.particles,
                self.springs,
                &workspace.derived.force,
                &mut workspace.integrator,
                h,
            );
            provot = solver.provot.map(|settings| {
                provot_correct(
                    self.particles,
                    self.springs,
                    &settings,
                    &mut workspace.provot,
                    h,
                )
            });
            resolve_collisions(self.particles, inputs.colliders, margin, h);
        }
        self.particles.external_force.fill(Vec3::ZERO);
        let repaired = workspace.guard.check(
            self.particles,
            &solver.guard,
            self.settings.material.initial_temperature,
        );
        (plan, provot, repaired)
    }

    /// Phase 5: the triangles of the particles burnt in this step leave the drawn list.
    fn cull(&mut self) {
        let newly_burnt = &self.outcome.newly_burnt;
        self.workspace.front.cull(self.topology, newly_burnt);
    }
}
