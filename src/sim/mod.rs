//! The simulation: plain Rust over `glam` and slices, no ECS.
//!
//! Everything here can be driven without an `App`. One step of one cloth is defined once, in
//! [`step`]: [`ClothMut::step`] runs pins, heat, combustion, dynamics and culling in that
//! order. [`ClothSim`] owns a cloth and runs it (tests, the headless example, reports); the
//! plugin runs the same function on each cloth entity's components.
//!
//! | module | what it holds |
//! |---|---|
//! | [`step`] | the order of one step's phases, [`StepInputs`], [`StepReport`] |
//! | [`cloth`] | [`ClothSim`]: a cloth that owns its data and steps itself |
//! | [`settings`] | [`SolverSettings`], [`HeatModel`], [`Environment`], [`ClothSettings`] |
//! | [`derived`] | parameters derived from the settings, once per change |
//! | [`workspace`] | a cloth's scratch memory, reused every step |
//! | [`material`] | [`BurnMaterial`] presets (the paper's Figure 2) and validation |
//! | [`particles`] | [`Particles`], a structure of arrays, and [`BurnState`] |
//! | [`springs`] | [`Springs`] stored once each, Hooke's law with damping |
//! | [`grid`] | [`ClothBuilder`]: grid particles, 12 springs per particle, triangles, pins |
//! | [`mesh_cloth`] | [`MeshClothBuilder`]: cloth from any triangle mesh, welded, with [`MeshPins`] |
//! | [`forces`] | gravity, springs, air drag, external forces |
//! | [`integrate`] | explicit Euler, symplectic Euler, Verlet, RK4, XPBD; the stability limit |
//! | [`xpbd`] | the XPBD solver: springs as constraints in vectorised runs |
//! | [`provot`] | Provot's stretch correction |
//! | [`collision`] | sphere, capsule and plane colliders |
//! | [`guard`] | the blow-up guard: NaN and runaway particles are put back |
//! | [`heat`] | the paper's upward-biased heat push and proximity heating |
//! | [`conduction`] | the physical heat model: conduction, convection, cooling, burning |
//! | [`heat_sources`] | heat from torches, fireballs and other cloths' fires |
//! | [`spatial_hash`] | the O(n) neighbour search behind proximity heating |
//! | [`front`] | the burning front as lists: burn states, shrinking springs, drawn triangles |
//! | [`combustion`] | extinguishing, and what a combustion update changed |
//! | [`ignition`] | raising a particle to an ignition temperature |
//! | [`topology`] | triangles and culling of burnt ones |
//! | [`mesh`] | a cloth's vertex data for drawing: local positions, normals, burn data |
//! | [`anchors`] | what each particle hangs from: nearest pin and distance through the cloth, kept up to date as it burns; pieces burnt loose |
//! | [`energy`] | a cloth's mechanical energy |
//! | [`parallel`] | work split over Bevy's task pool (parts, or a frame of phases under one scope), the same result on any number of threads |
//!
//! Units: metres, kilograms, seconds, degrees Celsius.
//!
//! Where its accuracy ends: the default heat model is the paper's (heat only grows, fire
//! follows world up by fixed weights; [`HeatModel::PHYSICAL`] is a heat equation instead);
//! the explicit integrators need substeps for stiff cloth, which [`SolverSettings`] picks
//! from the stability limit (up to 64) unless told otherwise, and XPBD trades accuracy for
//! unconditional stability (see the README's stability matrix).

pub mod anchors;
pub mod cloth;
pub mod collision;
pub mod combustion;
pub mod conduction;
pub mod derived;
pub mod energy;
pub mod error;
pub mod flame;
pub mod forces;
pub mod front;
pub mod grid;
mod grid_normals;
pub mod guard;
pub mod heat;
pub mod heat_sources;
pub mod ignition;
pub mod integrate;
pub mod lattice;
pub mod material;
pub mod mesh;
pub mod mesh_cloth;
pub mod parallel;
pub mod particles;
pub mod provot;
pub mod settings;
pub(crate) mod simd;
pub mod spatial_hash;
pub mod springs;
pub mod step;
pub mod topology;
pub mod workspace;
pub mod xpbd;

pub use anchors::{Anchors, DetachedPiece};
pub use cloth::ClothSim;
pub use collision::{ColliderShape, FRICTION_PERIOD, WorldCollider, sliding_kept};
pub use combustion::CombustionReport;
pub use error::ClothError;
pub use forces::ForceParams;
pub use grid::{ClothBuilder, ClothParts, Cutout, GridPlane};
pub use guard::{BlowUpGuard, GuardSettings};
pub use heat_sources::{HashedHeatSources, WorldHeatSource};
pub use integrate::Integrator;
pub use material::{BurnMaterial, MaterialError};
pub use mesh_cloth::{MeshClothBuilder, MeshPins, PinRule};
pub use particles::{BurnState, Particles};
pub use provot::ProvotSettings;
pub use settings::{ClothSettings, Environment, HeatModel, PhysicalHeat, SolverSettings, StepPlan};
pub use spatial_hash::SpatialHash;
pub use springs::{SpanRule, SpringCoefficients, SpringKind, Springs};
pub use step::{ClothMut, PhaseTimes, StepInputs, StepOutcome, StepReport};
pub use topology::{GridShape, Topology};
pub use workspace::ClothWorkspace;
