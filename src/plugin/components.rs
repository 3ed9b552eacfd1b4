//! Components of a cloth entity. The simulation data lives here; particles are not entities.

use crate::sim::{self, BurnMaterial, ClothBuilder, MeshClothBuilder};
use bevy::ecs::component::{Mutable, StorageType};
use bevy::prelude::*;

/// A cloth to build: spawn it with a [`BurnMaterial`] (default: [`BurnMaterial::CLOTH`]) and a
/// [`Transform`]. After transforms propagate, the plugin replaces it with the simulated
/// components ([`ClothParticles`], [`ClothSprings`], [`ClothTopology`], …). An invalid
/// builder is logged as an error and removed.
impl Component for ClothBuilder {
    const STORAGE_TYPE: StorageType = StorageType::Table;
    type Mutability = Mutable;
}

/// A cloth to build from a triangle mesh (local positions and triangles; pins by rule), like
/// [`ClothBuilder`] for grids: spawn it with a [`BurnMaterial`] and a [`Transform`]; changing
/// or re-inserting it rebuilds the cloth. With the `render` feature, `Flammable` on an entity
/// with a `Mesh3d` makes one from the mesh.
impl Component for MeshClothBuilder {
    const STORAGE_TYPE: StorageType = StorageType::Table;
    type Mutability = Mutable;
}

/// A cloth's material; changing it mid-burn takes effect on the next step (an invalid
/// material is logged and the change ignored).
impl Component for BurnMaterial {
    const STORAGE_TYPE: StorageType = StorageType::Table;
    type Mutability = Mutable;
}

/// The particles of a cloth: positions (world space, m), velocities, masses, temperatures
/// (°C) and burn states, as arrays.
#[derive(Component, Clone, Debug, Default, Deref, DerefMut)]
pub struct ClothParticles(pub sim::Particles);

/// The springs of a cloth, each stored once with its own rest length.
#[derive(Component, Clone, Debug, Default, Deref, DerefMut)]
pub struct ClothSprings(pub sim::Springs);

/// Triangles, texture coordinates and the live index list of a cloth.
#[derive(Component, Clone, Debug, Default, Deref, DerefMut)]
pub struct ClothTopology(pub sim::Topology);

/// How a cloth is stepped: integrator, substeps, Provot, proximity heating. Optional on a
/// cloth entity; defaults are inserted at build time. Changing it takes effect on the next
/// step (an invalid solver is logged and the change ignored).
#[derive(Component, Clone, Copy, Debug, Default, PartialEq, Deref, DerefMut, Reflect)]
#[reflect(Component, Default, Clone, Debug, PartialEq)]
pub struct ClothSolver(pub sim::SolverSettings);

/// What the simulation is using for a cloth and what the cloth's latest step did. Read it;
/// the plugin writes it.
///
/// Changes to [`BurnMaterial`], [`ClothSolver`] or
/// [`ClothEnvironment`](crate::plugin::ClothEnvironment) are copied in here only after they
/// validate, so a bad value never reaches the simulation: this is the one place that says
/// which material, solver and environment a cloth runs with.
#[derive(Component, Clone, Debug)]
pub struct ClothInUse {
    pub(crate) settings: sim::ClothSettings,
    pub(crate) outcome: sim::StepOutcome,
}

impl ClothInUse {
    pub(crate) fn new(settings: sim::ClothSettings) -> Self {
        Self {
            settings,
            outcome: sim::StepOutcome::default(),
        }
    }

    /// The material, solver and environment in use.
    pub fn settings(&self) -> &sim::ClothSettings {
        &self.settings
    }

    /// The material in use.
    pub fn material(&self) -> &BurnMaterial {
        &self.settings.material
    }

    /// The solver settings in use.
    pub fn solver(&self) -> &sim::SolverSettings {
        &self.settings.solver
    }

    /// The environment in use.
    pub fn environment(&self) -> &sim::Environment {
        &self.settings.environment
    }

    /// What the latest step did, in numbers.
    pub fn last_step(&self) -> &sim::StepReport {
        &self.outcome.report
    }

    /// Indices of the particles that burnt away in the latest step.
    pub fn newly_burnt(&self) -> &[u32] {
        self.outcome.newly_burnt()
    }

    /// Pieces that lost their last pin in the latest step.
    pub fn detached(&self) -> &[sim::DetachedPiece] {
        self.outcome.detached()
    }
}

/// A cloth's derived parameters and scratch memory (private to the plugin).
#[derive(Component, Clone, Debug)]
pub(crate) struct ClothScratch(pub(crate) sim::ClothWorkspace);

/// Despawns the cloth entity (and its children) once nothing of it is left: no triangle is
/// drawn, no particle is burning, and nothing holds it with [`HoldDespawn`] (the smoke plugin
/// does while the cloth's smoke is still in the air). A cloth whose fire goes out with part of
/// it left stays. Put it on the cloth entity (with the `ClothBuilder`, the
/// `MeshClothBuilder`, or the flammable mesh).
#[derive(Component, Clone, Copy, Debug, Default, PartialEq, Eq, Reflect)]
#[reflect(Component, Default, Clone, Debug, PartialEq)]
pub struct DespawnWhenBurntAway;

/// Keeps a burnt-away cloth from being despawned by [`DespawnWhenBurntAway`] while present:
/// another plugin (the smoke, whose particles still fly) or a game system still needs the
/// entity. Remove it when done.
#[derive(Component, Clone, Copy, Debug, Default, PartialEq, Eq, Reflect)]
#[reflect(Component, Default, Clone, Debug, PartialEq)]
pub struct HoldDespawn;

/// Keeps a cloth description ([`ClothBuilder`] or [`MeshClothBuilder`]) from being built while
/// present: something it needs has not arrived yet (a material file still loading holds its
/// cloth this way). Whoever removes it marks the builder changed, so the cloth is built then.
/// Not reflected: a scene saves the description, not the wait.
#[derive(Component, Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct HoldBuild;

/// Live numbers about a cloth, updated every fixed step, for gameplay and UI.
#[derive(Component, Clone, Copy, Debug, Default, PartialEq, Reflect)]
#[reflect(Component, Default, Clone, Debug, PartialEq)]
pub struct ClothStatus {
    /// Particles in total.
    pub particles: u32,
    /// Particles on fire now.
    pub ignited: u32,
    /// Particles burnt away.
    pub burnt: u32,
    /// Pinned particles not burnt.
    pub pins_left: u32,
    /// Triangles still drawn.
    pub live_triangles: u32,
    /// Substeps used by the latest fixed step.
    pub substeps: u32,
    /// The integrator that ran the latest fixed step: the chosen one, or XPBD when a
    /// force-based integrator would have needed more than its substep cap.
    pub integrator: sim::Integrator,
    /// True from the first ignition until the fire goes out.
    pub burning: bool,
    /// Particles the blow-up guard has put back since the cloth was built.
    pub repairs: u32,
}

impl ClothStatus {
    /// Fraction of particles burnt away, in [0, 1].
    pub fn burnt_fraction(&self) -> f32 {
        if self.particles == 0 {
            0.0
        } else {
            self.burnt as f32 / self.particles as f32
        }
    }
}

/// A collider every cloth rests on and drapes over: put it on any entity with a
/// [`Transform`] (a rod, a table top, the floor). Rigid; the transform's scale is ignored.
/// A shape with NaN, infinite or negative dimensions is skipped with a warning.
#[derive(Component, Clone, Copy, Debug, PartialEq, Reflect)]
#[reflect(Component, Clone, Debug, PartialEq)]
#[require(Transform)]
pub struct ClothCollider {
    /// The shape in the entity's frame.
    pub shape: sim::ColliderShape,
    /// Fraction of the sliding velocity removed per 1/60 s of contact
    /// ([`FRICTION_PERIOD`](sim::FRICTION_PERIOD)), in [0, 1]: the same over a frame whatever
    /// the cloth's substeps.
    pub friction: f32,
}

/// Default friction of spheres and capsules per 1/60 s: what half per substep removed at the
/// default six substeps a frame (`1 − 0.5⁶`), so the look did not change when friction became
/// per second.
const ROUND_FRICTION: f32 = 0.98;
/// Default friction of a floor per 1/60 s (`1 − 0.4⁶`, as above).
const FLOOR_FRICTION: f32 = 0.996;

impl ClothCollider {
    /// A sphere of `radius` metres.
    pub fn sphere(radius: f32) -> Self {
        Self {
            shape: sim::ColliderShape::Sphere { radius },
            friction: ROUND_FRICTION,
        }
    }

    /// A capsule along the entity's local Y axis, `length` metres between its cap centres.
    pub fn capsule(length: f32, radius: f32) -> Self {
        Self {
            shape: sim::ColliderShape::Capsule {
                half_length: 0.5 * length,
                radius,
            },
            friction: ROUND_FRICTION,
        }
    }

    /// The half-space below the entity's local XZ plane: a floor.
    pub fn plane() -> Self {
        Self {
            shape: sim::ColliderShape::Plane,
            friction: FLOOR_FRICTION,
        }
    }

    /// Sets the friction.
    pub fn with_friction(mut self, friction: f32) -> Self {
        self.friction = friction;
        self
    }
}

/// Ignitions asked for before the cloth was built; applied when it is.
#[derive(Component, Clone, Debug, Default)]
pub(crate) struct PendingIgnitions(pub(crate) Vec<crate::plugin::Ignite>);
