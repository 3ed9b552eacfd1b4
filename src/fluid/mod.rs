//! The fire's air (feature `fluid`): a coarse stable-fluids grid around the fire that the
//! burning cloths heat, whose hot air rises as a plume, carries the smoke, pushes the cloth
//! as wind and heats the cloth it reaches (Stam 1999, "Stable Fluids"; Fedkiw, Stam & Jensen
//! 2001, "Visual Simulation of Smoke"). Plain Rust over slices, no ECS.
//!
//! | piece | what it holds |
//! |---|---|
//! | [`grid`] | [`GridShape`]: cells, staggered faces, trilinear sampling and splatting |
//! | [`active`] | [`ActiveSpans`](active::ActiveSpans): the rows of cells near busy air, where advection runs |
//! | [`advect`] | semi-Lagrangian advection of the scalars and the velocity |
//! | [`forces`] | buoyancy and vorticity confinement |
//! | [`pressure`] | [`PressureSolver`]: multigrid-preconditioned CG for the projection |
//! | [`settings`] | [`PlumeSettings`]: box size and the air's physics |
//! | [`plume`] | [`Plume`]: the state and its step |
//! | [`coupling`] | burning cloth feeds the plume; the plume blows on and heats the cloth |
//! | [`FluidPlugin`] | the scene's [`FirePlume`] and its systems |
//!
//! One step (`Plume::step`): advect temperature, smoke and velocity by the current divergence-free
//! velocity plus the uniform wind; cool the air and thin the smoke; add buoyancy `up (β ΔT − κ s)`
//! and vorticity confinement `ε h (N × ω)` (in hot air); project (zero the faces into solids and
//! closed walls, solve `∇²φ = ∇·u`, subtract `∇φ`). Open walls hold ambient pressure, so the plume
//! leaves through them. While nothing feeds it and the air has settled, a step costs nothing.

pub mod active;
pub mod advect;
pub mod coupling;
pub mod forces;
pub mod grid;
mod plugin;
pub mod plume;
pub mod pressure;
mod reduce;
pub mod settings;
#[cfg(test)]
mod validation;

pub use coupling::{PlumeOnCloth, blow_and_heat, blow_and_heat_on, feed_plume};
pub use grid::{GridShape, Stagger};
pub use plugin::{FirePlume, FluidPlugin, PlumeDiagnostics, PlumeSystems};
pub use plume::{Plume, PlumeReport};
pub use pressure::{PressureSolver, SolveReport, Wall, Walls};
pub use settings::{AIR_HEAT_CAPACITY, PlumeSettings, PlumeSettingsError};
