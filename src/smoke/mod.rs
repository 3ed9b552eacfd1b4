//! Flames, smoke and embers rising from the burning front (feature `smoke`).
//!
//! | piece | what it holds |
//! |---|---|
//! | [`pool`] | [`SmokePool`]: a fixed-capacity structure of arrays, slots reused |
//! | [`settings`] | [`SmokeSettings`] and [`KindSettings`] for flames, smoke and embers |
//! | [`turbulence`] | [`Turbulence`]: a divergence-free curl-noise air field |
//! | [`emitter`] | [`SmokeSim`]: emission from a burning cloth, buoyant motion |
//! | [`tongues`] | [`FlameTongue`]s along the burning front: root, lean, height, strength |
//! | [`SmokePlugin`] | the [`SmokeEmitter`] component and its systems |
//! | `render` (feature `render`) | camera-facing billboards, one mesh per blend mode |
//! | `flame_render` (feature `render`) | flame tongues: one mesh, a noise flame shader |
//!
//! Flames and smoke are born at ignited, unburnt cloth particles, at a rate proportional to
//! how hard each burns ([`BurningCloth::intensity`]) and the area it stands for; embers at
//! the particles that burn away. Nothing is born where the cloth is already gone, and a
//! cloth that has burnt out emits nothing while its live particles finish their lives.
//!
//! Particles rise by buoyancy (proportional to how much hotter than the air they are, cooling
//! exponentially), relax to the air velocity (wind plus curl-noise turbulence) through
//! implicit drag, and embers feel part of gravity. Emission draws from a seeded generator,
//! so the same seed and burn give the same particles.

pub mod emitter;
#[cfg(feature = "render")]
pub mod flame_render;
mod plugin;
pub mod pool;
#[cfg(feature = "render")]
mod quads;
#[cfg(feature = "render")]
pub mod render;
pub mod settings;
pub mod tongues;
pub mod turbulence;

pub use emitter::{Air, BurningCloth, SmokeCounts, SmokeSim};
#[cfg(feature = "fluid")]
pub(crate) use plugin::air;
pub use plugin::{SmokeDiagnostics, SmokeEmitter, SmokePlugin, SmokeSystems};
pub use pool::{NewParticle, SmokeKind, SmokePool};
pub use settings::{KindSettings, MAX_SMOKE_CAPACITY, SmokeSettings, SmokeSettingsError};
pub use tongues::{FlameTongue, TongueSettings, gather_tongues};
pub use turbulence::Turbulence;
