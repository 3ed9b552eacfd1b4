//! Errors of the public simulation entry points.

use super::material::MaterialError;
use core::fmt;

/// Why a cloth could not be built or a request on it was refused.
#[derive(Clone, Debug, PartialEq)]
pub enum ClothError {
    /// A grid needs at least 2 × 2 particles.
    EmptyGrid {
        /// Requested columns.
        columns: u32,
        /// Requested rows.
        rows: u32,
    },
    /// More particles than [`MAX_PARTICLES`](super::grid::MAX_PARTICLES).
    TooManyParticles {
        /// Requested particle count.
        requested: u64,
        /// The limit.
        max: u64,
    },
    /// Grid spacing must be finite and positive (m).
    InvalidSpacing(f32),
    /// Total or particle mass must be finite and positive (kg).
    InvalidMass(f32),
    /// A pin outside the grid.
    PinOutOfRange {
        /// Pin column.
        column: u32,
        /// Pin row.
        row: u32,
        /// Grid columns.
        columns: u32,
        /// Grid rows.
        rows: u32,
    },
    /// The material has an unusable field.
    InvalidMaterial(MaterialError),
    /// The cloth's transform contains NaN or infinity.
    NonFiniteTransform,
    /// A particle index past the end of the cloth.
    ParticleOutOfRange {
        /// The index given.
        index: usize,
        /// Number of particles.
        len: usize,
    },
    /// A temperature that is not finite or lies outside [−273.15 °C, 1e5 °C].
    InvalidTemperature(f32),
    /// A point or vector with NaN or infinity.
    NonFinitePoint,
    /// Every particle has burnt: there is nothing left to ignite.
    NothingLeftToIgnite,
    /// A triangle mesh that cannot become a cloth, and why.
    InvalidMesh(&'static str),
    /// A solver setting with an unusable value.
    InvalidSetting {
        /// The setting's name.
        name: &'static str,
        /// The rejected value.
        value: f32,
    },
}

impl fmt::Display for ClothError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::EmptyGrid { columns, rows } => write!(
                f,
                "a cloth grid needs at least 2 x 2 particles, got {columns} x {rows}"
            ),
            Self::TooManyParticles { requested, max } => {
                write!(f, "{requested} particles requested, at most {max} allowed")
            }
            Self::InvalidSpacing(spacing) => {
                write!(f, "grid spacing must be finite and > 0 m, got {spacing}")
            }
            Self::InvalidMass(mass) => write!(f, "mass must be finite and > 0 kg, got {mass}"),
            Self::PinOutOfRange {
                column,
                row,
                columns,
                rows,
            } => write!(
                f,
                "pin ({column}, {row}) lies outside the {columns} x {rows} grid"
            ),
            Self::InvalidMaterial(error) => write!(f, "{error}"),
            Self::NonFiniteTransform => write!(f, "the cloth transform is not finite"),
            Self::ParticleOutOfRange { index, len } => {
                write!(f, "particle {index} does not exist (the cloth has {len})")
            }
            Self::InvalidTemperature(t) => write!(
                f,
                "temperature {t} °C is not finite or outside [-273.15, 1e5] °C"
            ),
            Self::NonFinitePoint => write!(f, "a point or vector is not finite"),
            Self::NothingLeftToIgnite => write!(f, "every particle has burnt already"),
            Self::InvalidMesh(why) => write!(f, "the mesh cannot become a cloth: {why}"),
            Self::InvalidSetting { name, value } => {
                write!(f, "solver setting {name} = {value} is not usable")
            }
        }
    }
}

impl std::error::Error for ClothError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Self::InvalidMaterial(error) => Some(error),
            _ => None,
        }
    }
}

impl From<MaterialError> for ClothError {
    fn from(error: MaterialError) -> Self {
        Self::InvalidMaterial(error)
    }
}
