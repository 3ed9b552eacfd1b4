//! The simulation: plain Rust over `glam` and slices, no ECS.
//!
//! Everything here can be driven without an `App`; tests, the headless example, benchmarks
//! and reports call it directly, and the ECS systems in [`crate::plugin`] are thin wrappers
//! around the phase functions in [`cloth`].
//!
//! | module | what it holds |
//! |---|---|
//! | [`material`] | [`BurnMaterial`] presets (the paper's Figure 2) and validation |
//! | [`particles`] | [`Particles`], a structure of arrays, and [`BurnState`] |
//! | [`springs`] | [`Springs`] stored once each, Hooke's law with damping |
//! | [`grid`] | [`ClothBuilder`]: grid particles, 12 springs per particle, triangles, pins |
//! | [`mesh_cloth`] | [`MeshClothBuilder`]: cloth from any triangle mesh, welded, with [`MeshPins`] |
//! | [`guard`] | the blow-up guard: NaN and runaway particles are put back |
//! | [`forces`] | gravity, springs, air drag, external forces |
//! | [`integrate`] | explicit Euler, symplectic Euler, Verlet, RK4, XPBD; the stability limit |
//! | [`provot`] | Provot's stretch correction |
//! | [`heat`] | the paper's upward-biased heat push and proximity heating |
//! | [`conduction`] | the physical heat model: conduction, convection, cooling, burning |
//! | [`collision`] | sphere, capsule and plane colliders |
//! | [`combustion`] | ignition, burning, rest-length shrink, extinguishing |
//! | [`heat_sources`] | heat from torches, fireballs and other cloths' fires |
//! | [`spatial_hash`] | the O(n) neighbour search behind proximity heating |
//! | [`topology`] | triangles and culling of burnt ones |
//! | [`pieces`] | connected pieces of a cloth and which have burnt loose from every pin |
//! | [`cloth`] | one step as phases, and [`ClothSim`] that runs them all |
//!
//! Units: metres, kilograms, seconds, degrees Celsius.
//!
//! Where its accuracy ends: the default heat model is the paper's (heat only grows, fire
//! follows world up by fixed weights; [`HeatModel::PHYSICAL`] is a heat equation instead); the explicit integrators need substeps for stiff cloth, which
//! [`SolverSettings`] picks from the stability limit (up to 64) unless told otherwise, and
//! XPBD trades accuracy for unconditional stability (see the README's stability matrix).

pub mod cloth;
pub mod collision;
pub mod combustion;
pub mod conduction;
pub mod error;
pub mod forces;
pub mod grid;
pub mod guard;
pub mod heat;
pub mod heat_sources;
pub mod integrate;
pub mod material;
pub mod mesh_cloth;
pub mod particles;
pub mod pieces;
pub mod provot;
pub mod spatial_hash;
pub mod springs;
pub mod topology;

pub use cloth::{ClothSim, ClothWorkspace, Environment, HeatModel, SolverSettings, StepReport};
pub use collision::{ColliderShape, WorldCollider};
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
pub use pieces::{DetachedPiece, PieceTracker, Pieces};
pub use provot::ProvotSettings;
pub use spatial_hash::SpatialHash;
pub use springs::{SpringCoefficients, SpringKind, Springs};
pub use topology::{GridShape, Topology};
