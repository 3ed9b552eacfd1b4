//! Burn materials: the paper's Figure 2 ignition table plus the physical parameters a
//! mass-spring cloth needs.
//!
//! Units are SI with temperatures in degrees Celsius. The paper quotes Fahrenheit; the
//! conversion happens here, once, in [`fahrenheit_to_celsius`].

use bevy::reflect::Reflect;
use core::fmt;

/// Converts a temperature from degrees Fahrenheit to degrees Celsius.
pub const fn fahrenheit_to_celsius(fahrenheit: f32) -> f32 {
    (fahrenheit - 32.0) * 5.0 / 9.0
}

/// The paper's initial particle temperature, 60 °F (15.6 °C), used as ambient.
pub const PAPER_INITIAL_TEMPERATURE: f32 = fahrenheit_to_celsius(60.0);
/// The paper's seed temperature for an ignition point, 1000 °F (537.8 °C).
pub const PAPER_SEED_TEMPERATURE: f32 = fahrenheit_to_celsius(1000.0);
/// The paper's "burnt" temperature, 2000 °F (1093.3 °C): a particle above it is removed.
pub const PAPER_BURNT_TEMPERATURE: f32 = fahrenheit_to_celsius(2000.0);
/// Absolute zero in degrees Celsius: no temperature below it is accepted.
pub const ABSOLUTE_ZERO: f32 = -273.15;
/// Highest temperature accepted from user input (°C). Far above any flame; it only keeps
/// arithmetic finite.
pub const MAX_TEMPERATURE: f32 = 1.0e5;

/// The particle spacing the heat rates given per neighbour are stated for, m: the paper
/// model's [`BurnMaterial::heat_spread_rate`] and the physical model's convection. A cloth
/// with particles `spacing` apart scales them by `REFERENCE_SPACING / spacing`, so fire
/// spreads at the same speed at any resolution.
pub const REFERENCE_SPACING: f32 = 0.03;

/// The presets' [`BurnMaterial::structural_compression_fraction`]: 1 % of the stiffness.
/// Not a measurement of a fabric: with it a flat burning cotton cloth's cold springs stretch
/// no more than at 0.1 % (`examples/stress.rs`, 128 x 128 and 256 x 256).
pub const YARN_COMPRESSION: f32 = 0.01;

/// The presets' [`BurnMaterial::shear_compression_fraction`]: 10 % of the stiffness. Not a
/// measurement of a fabric: the softest of 1, 0.3, 0.1 and 0.01 at which a hanging
/// 256 x 256 cotton cloth's structural springs stay within 10 % of their length
/// (`examples/stress.rs`: 1.099; 1.118 at 0.01).
pub const BIAS_COMPRESSION: f32 = 0.1;

/// What a material file written before the compression fractions existed gets: springs as
/// stiff in compression as in tension, as they then were.
fn full_compression() -> f32 {
    1.0
}

/// The name a material gets when it comes back through reflection.
fn custom_name() -> &'static str {
    "custom"
}

/// How a cloth burns: its mechanics, its ignition and burnt temperatures, and how heat moves.
///
/// Presets reproduce the paper's Figure 2 ignition thresholds; the other numbers are
/// chosen so the materials differ the way the paper's Figure 9 shows (silk light and quick,
/// denim heavy and slow). All fields are public; [`BurnMaterial::validate`] checks them.
#[derive(Clone, Copy, Debug, PartialEq, Reflect)]
#[reflect(Clone, Debug, PartialEq)]
pub struct BurnMaterial {
    /// Display name. Not reflected (a `&'static str` cannot be loaded from a scene file): a
    /// material loaded through reflection is named "custom".
    #[reflect(ignore, default = "custom_name")]
    pub name: &'static str,
    /// Colour of fresh cloth, sRGB components in [0, 1].
    pub base_colour: [f32; 3],
    /// Mass per area of cloth, kg/m².
    pub areal_density: f32,
    /// Stiffness of structural springs (grid neighbours), N/m.
    pub structural_stiffness: f32,
    /// Stiffness of shear springs (grid diagonals), N/m.
    pub shear_stiffness: f32,
    /// Stiffness of bending springs (two apart), N/m.
    pub bend_stiffness: f32,
    /// Stiffness of structural springs while they are shorter than their rest length, as a
    /// fraction of `structural_stiffness` (dimensionless, in [0, 1]). Woven cloth buckles its
    /// yarns rather than shorten them, so it gives far more to a push along a yarn than to a
    /// pull. Without this, a flat cloth around a shrinking front has to take the front's pull
    /// in stretched springs instead of giving sideways: a flat 256 x 256 cotton cloth's cold
    /// springs stretched to 2.5 times their length with springs as stiff both ways, 1.7 with
    /// the presets' fractions (`examples/stress.rs`). Files written before this field
    /// existed load with 1, the behaviour they were written for.
    #[reflect(default = "full_compression")]
    pub structural_compression_fraction: f32,
    /// Stiffness of shear springs (grid diagonals) while they are shorter than their rest
    /// length, as a fraction of `shear_stiffness` (dimensionless, in [0, 1]). Cloth pushed
    /// along its bias shears its weave (trellising) rather than buckle a yarn, so it gives
    /// less readily than along a yarn. Bending springs (two apart) resist bending by resisting
    /// compression, so they keep their full stiffness. Files written before this field
    /// existed load with 1.
    #[reflect(default = "full_compression")]
    pub shear_compression_fraction: f32,
    /// Damping ratio of every spring (dimensionless, 0 = undamped, 1 = critical).
    pub damping_ratio: f32,
    /// Air drag per unit area, N·s/m³: force = -drag × area × (velocity - wind).
    pub air_drag: f32,
    /// Temperature above which a particle is ignited, °C (the paper's Figure 2).
    pub ignition_temperature: f32,
    /// Temperature above which a particle is burnt and removed, °C.
    pub burnt_temperature: f32,
    /// Temperature of fresh cloth and of the surrounding air, °C.
    pub initial_temperature: f32,
    /// Temperature an ignition point is raised to, °C.
    pub seed_temperature: f32,
    /// Heat push rate of the paper's model, 1/s, for particles [`REFERENCE_SPACING`] apart:
    /// a neighbour straight to the side of an ignited particle gains
    /// `rate × (REFERENCE_SPACING / spacing) × dt × (T_ignited - T_initial)` per step. The
    /// front then crosses a neighbour in a time proportional to the spacing, so it moves
    /// the same metres per second on a fine cloth as on a coarse one.
    pub heat_spread_rate: f32,
    /// How fast an ignited particle heats itself while it burns under the paper's model, °C/s,
    /// for particles [`REFERENCE_SPACING`] apart; a cloth with particles `spacing` apart heats
    /// at `rate × REFERENCE_SPACING / spacing`, like the push, so a burning particle is as hot
    /// when the front has crossed to its neighbour at any resolution. (The plume reads the
    /// unscaled rate for how long the material burns.)
    pub self_heating_rate: f32,
    /// How long a particle of this cloth burns once alight before it burns away, s: the
    /// width of the burning band behind the front is this time its speed, at any spacing.
    /// At least: where the front takes longer to cross a particle's patch than this (a grid
    /// much coarser than [`REFERENCE_SPACING`] under the paper's model, or the slow
    /// sideways and downward fronts of the physical one), the particle burns on until its
    /// temperature passes `burnt_temperature` (see [`super::front::Front::scan`]). The
    /// presets' values are the times the paper's model burnt a particle for at the reference
    /// spacing before this field existed (median over a flat 1.5 m panel lit near its
    /// bottom), so a cloth at that spacing burns as it did; a finer one no longer burns
    /// through faster.
    pub burn_time: f32,
    /// Rest-length shrink factor, N/(m·s·°C): a spring shrinks by
    /// `factor × dt × l_init × (ΔT_a + ΔT_b) / k` per step (Larboulette's rule).
    pub shrink_factor: f32,
    /// Smallest rest length a spring may shrink to, as a fraction of its initial length.
    pub min_rest_fraction: f32,
    /// Flame spread straight up a vertical panel of this cloth in still air, m/s (the
    /// physical heat model; see [`super::flame`]). The flame at the burning edge heats the
    /// cloth next to it with `speed × areal heat capacity × (T_ignition − T_initial)` per
    /// metre of edge, so this is the speed a straight front climbs when nothing else heats or
    /// cools it.
    pub flame_spread_up: f32,
    /// Flame spread sideways along a vertical panel, m/s (physical heat model).
    pub flame_spread_sideways: f32,
    /// Flame spread straight down a vertical panel, m/s (physical heat model).
    pub flame_spread_down: f32,
}

impl BurnMaterial {
    /// Generic cloth: ignites at 482 °F (250 °C).
    pub const CLOTH: Self = Self {
        name: "cloth",
        base_colour: [0.72, 0.16, 0.14],
        areal_density: 0.20,
        structural_stiffness: 40.0,
        shear_stiffness: 20.0,
        bend_stiffness: 4.0,
        structural_compression_fraction: YARN_COMPRESSION,
        shear_compression_fraction: BIAS_COMPRESSION,
        damping_ratio: 0.05,
        air_drag: 0.5,
        ignition_temperature: fahrenheit_to_celsius(482.0),
        burnt_temperature: PAPER_BURNT_TEMPERATURE,
        initial_temperature: PAPER_INITIAL_TEMPERATURE,
        seed_temperature: PAPER_SEED_TEMPERATURE,
        heat_spread_rate: 0.25,
        self_heating_rate: 260.0,
        burn_time: 0.8,
        shrink_factor: 0.015,
        min_rest_fraction: 0.5,
        // Generic woven cloth, 200 g/m²: between cotton and denim (no measurement of its own).
        flame_spread_up: 0.070,
        flame_spread_sideways: 0.008,
        flame_spread_down: 0.0015,
    };

    /// Silk: light, ignites at 289 °F (142.8 °C), burns fast.
    pub const SILK: Self = Self {
        name: "silk",
        base_colour: [0.93, 0.86, 0.72],
        areal_density: 0.06,
        structural_stiffness: 12.0,
        shear_stiffness: 6.0,
        bend_stiffness: 0.6,
        structural_compression_fraction: YARN_COMPRESSION,
        shear_compression_fraction: BIAS_COMPRESSION,
        damping_ratio: 0.05,
        air_drag: 0.5,
        ignition_temperature: fahrenheit_to_celsius(289.0),
        burnt_temperature: PAPER_BURNT_TEMPERATURE,
        initial_temperature: PAPER_INITIAL_TEMPERATURE,
        seed_temperature: PAPER_SEED_TEMPERATURE,
        heat_spread_rate: 0.35,
        self_heating_rate: 400.0,
        burn_time: 0.5,
        shrink_factor: 0.008,
        min_rest_fraction: 0.4,
        // 60 g/m²: lighter than cotton, so quicker (spread on a thin fuel goes as one over its
        // mass per area); ordered as the paper's Figure 9, no measurement of its own.
        flame_spread_up: 0.120,
        flame_spread_sideways: 0.015,
        flame_spread_down: 0.003,
    };

    /// Denim: heavy, ignites at 410 °F (210 °C), burns slowly.
    pub const DENIM: Self = Self {
        name: "denim",
        base_colour: [0.20, 0.30, 0.52],
        areal_density: 0.40,
        structural_stiffness: 80.0,
        shear_stiffness: 40.0,
        bend_stiffness: 12.0,
        structural_compression_fraction: YARN_COMPRESSION,
        shear_compression_fraction: BIAS_COMPRESSION,
        damping_ratio: 0.08,
        air_drag: 0.5,
        ignition_temperature: fahrenheit_to_celsius(410.0),
        burnt_temperature: PAPER_BURNT_TEMPERATURE,
        initial_temperature: PAPER_INITIAL_TEMPERATURE,
        seed_temperature: PAPER_SEED_TEMPERATURE,
        heat_spread_rate: 0.15,
        self_heating_rate: 160.0,
        burn_time: 1.3,
        shrink_factor: 0.03,
        min_rest_fraction: 0.6,
        // 400 g/m²: heavier than cotton, so slower (Figure 9's order; no measurement of its own).
        flame_spread_up: 0.045,
        flame_spread_sideways: 0.005,
        flame_spread_down: 0.001,
    };

    /// Paper: light and stiff in bending, ignites at 451 °F (232.8 °C).
    pub const PAPER: Self = Self {
        name: "paper",
        base_colour: [0.95, 0.94, 0.88],
        areal_density: 0.08,
        structural_stiffness: 60.0,
        shear_stiffness: 40.0,
        bend_stiffness: 15.0,
        structural_compression_fraction: YARN_COMPRESSION,
        shear_compression_fraction: BIAS_COMPRESSION,
        damping_ratio: 0.1,
        air_drag: 0.6,
        ignition_temperature: fahrenheit_to_celsius(451.0),
        burnt_temperature: PAPER_BURNT_TEMPERATURE,
        initial_temperature: PAPER_INITIAL_TEMPERATURE,
        seed_temperature: PAPER_SEED_TEMPERATURE,
        heat_spread_rate: 0.3,
        self_heating_rate: 350.0,
        burn_time: 0.5,
        shrink_factor: 0.05,
        min_rest_fraction: 0.3,
        // 80 g/m² paper: about 4 mm/s horizontally, from the mass burning rates in Thomas &
        // Law's review of flame spread over thin fuels; upward and downward chosen between
        // (a thin fuel burns down about as fast as sideways in still air).
        flame_spread_up: 0.060,
        flame_spread_sideways: 0.004,
        flame_spread_down: 0.003,
    };

    /// Cotton: medium weight, ignites at 410 °F (210 °C).
    pub const COTTON: Self = Self {
        name: "cotton",
        base_colour: [0.90, 0.90, 0.86],
        areal_density: 0.15,
        structural_stiffness: 30.0,
        shear_stiffness: 15.0,
        bend_stiffness: 2.0,
        structural_compression_fraction: YARN_COMPRESSION,
        shear_compression_fraction: BIAS_COMPRESSION,
        damping_ratio: 0.06,
        air_drag: 0.5,
        ignition_temperature: fahrenheit_to_celsius(410.0),
        burnt_temperature: PAPER_BURNT_TEMPERATURE,
        initial_temperature: PAPER_INITIAL_TEMPERATURE,
        seed_temperature: PAPER_SEED_TEMPERATURE,
        heat_spread_rate: 0.22,
        self_heating_rate: 240.0,
        burn_time: 0.8,
        shrink_factor: 0.02,
        min_rest_fraction: 0.5,
        // Vertical cotton panels: about 90 mm/s up, 11 mm/s sideways and 2 mm/s down (Mathur,
        // Vikas and Kale, flame spread on textiles).
        flame_spread_up: 0.090,
        flame_spread_sideways: 0.011,
        flame_spread_down: 0.002,
    };

    /// Every preset, in the order of the paper's Figure 2.
    pub const PRESETS: [Self; 5] = [
        Self::CLOTH,
        Self::SILK,
        Self::DENIM,
        Self::PAPER,
        Self::COTTON,
    ];

    /// This material with springs as stiff in compression as in tension (both compression
    /// fractions 1): the paper's linear mass-spring model.
    pub const fn with_linear_springs(self) -> Self {
        Self {
            structural_compression_fraction: 1.0,
            shear_compression_fraction: 1.0,
            ..self
        }
    }

    /// The fraction of a spring kind's stiffness that resists compression (dimensionless):
    /// the structural and shear fractions, 1 for bending springs.
    pub fn compression(&self, kind: super::SpringKind) -> f32 {
        match kind {
            super::SpringKind::Structural => self.structural_compression_fraction,
            super::SpringKind::Shear => self.shear_compression_fraction,
            super::SpringKind::Bend => 1.0,
        }
    }

    /// The stiffness of a spring kind, N/m.
    pub fn stiffness(&self, kind: super::SpringKind) -> f32 {
        match kind {
            super::SpringKind::Structural => self.structural_stiffness,
            super::SpringKind::Shear => self.shear_stiffness,
            super::SpringKind::Bend => self.bend_stiffness,
        }
    }

    /// Air drag per unit mass, 1/s: the drag per area over the mass per area, so
    /// `f = −drag_per_mass × m × (v − wind)` for a particle of mass `m`.
    pub fn drag_per_mass(&self) -> f32 {
        self.air_drag / self.areal_density
    }

    /// Checks every field for a usable value.
    ///
    /// Rejects NaN and infinity everywhere, non-positive density, negative stiffness,
    /// damping or drag, temperatures outside [−273.15 °C, 1e5 °C], an ignition temperature
    /// not between the initial and burnt temperatures, and a shrink floor outside (0, 1].
    pub fn validate(&self) -> Result<(), MaterialError> {
        let positive = [("areal_density", self.areal_density)];
        for (field, value) in positive {
            if !(value.is_finite() && value > 0.0) {
                return Err(MaterialError::new(field, value, "must be finite and > 0"));
            }
        }
        let non_negative = [
            ("structural_stiffness", self.structural_stiffness),
            ("shear_stiffness", self.shear_stiffness),
            ("bend_stiffness", self.bend_stiffness),
            ("damping_ratio", self.damping_ratio),
            ("air_drag", self.air_drag),
            ("heat_spread_rate", self.heat_spread_rate),
            ("self_heating_rate", self.self_heating_rate),
            ("burn_time", self.burn_time),
            ("shrink_factor", self.shrink_factor),
            ("flame_spread_up", self.flame_spread_up),
            ("flame_spread_sideways", self.flame_spread_sideways),
            ("flame_spread_down", self.flame_spread_down),
        ];
        for (field, value) in non_negative {
            if !(value.is_finite() && value >= 0.0) {
                return Err(MaterialError::new(field, value, "must be finite and >= 0"));
            }
        }
        let temperatures = [
            ("initial_temperature", self.initial_temperature),
            ("ignition_temperature", self.ignition_temperature),
            ("burnt_temperature", self.burnt_temperature),
            ("seed_temperature", self.seed_temperature),
        ];
        for (field, value) in temperatures {
            if !valid_temperature(value) {
                return Err(MaterialError::new(
                    field,
                    value,
                    "must be a temperature in [-273.15, 1e5] °C",
                ));
            }
        }
        if self.ignition_temperature <= self.initial_temperature {
            return Err(MaterialError::new(
                "ignition_temperature",
                self.ignition_temperature,
                "must be above initial_temperature",
            ));
        }
        if self.burnt_temperature <= self.ignition_temperature {
            return Err(MaterialError::new(
                "burnt_temperature",
                self.burnt_temperature,
                "must be above ignition_temperature",
            ));
        }
        if let Some(&value) = self
            .base_colour
            .iter()
            .find(|c| !(c.is_finite() && (0.0..=1.0).contains(*c)))
        {
            return Err(MaterialError::new(
                "base_colour",
                value,
                "components must be in [0, 1]",
            ));
        }
        let fractions = [
            (
                "structural_compression_fraction",
                self.structural_compression_fraction,
            ),
            (
                "shear_compression_fraction",
                self.shear_compression_fraction,
            ),
        ];
        for (field, value) in fractions {
            if !(0.0..=1.0).contains(&value) {
                return Err(MaterialError::new(field, value, "must be in [0, 1]"));
            }
        }
        if !(self.min_rest_fraction > 0.0 && self.min_rest_fraction <= 1.0) {
            return Err(MaterialError::new(
                "min_rest_fraction",
                self.min_rest_fraction,
                "must be in (0, 1]",
            ));
        }
        Ok(())
    }
}

impl Default for BurnMaterial {
    fn default() -> Self {
        Self::CLOTH
    }
}

/// True for a finite temperature in the accepted range [−273.15 °C, 1e5 °C].
pub fn valid_temperature(celsius: f32) -> bool {
    celsius.is_finite() && (ABSOLUTE_ZERO..=MAX_TEMPERATURE).contains(&celsius)
}

/// A material field with an unusable value.
#[derive(Clone, Debug, PartialEq)]
pub struct MaterialError {
    /// The field's name.
    pub field: &'static str,
    /// The rejected value.
    pub value: f32,
    /// What the field requires.
    pub requirement: &'static str,
}

impl MaterialError {
    fn new(field: &'static str, value: f32, requirement: &'static str) -> Self {
        Self {
            field,
            value,
            requirement,
        }
    }
}

impl fmt::Display for MaterialError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "invalid burn material: {} = {} ({})",
            self.field, self.value, self.requirement
        )
    }
}

impl std::error::Error for MaterialError {}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn figure_two_thresholds_convert_to_celsius() {
        let expected_fahrenheit = [482.0, 289.0, 410.0, 451.0, 410.0];
        for (material, fahrenheit) in BurnMaterial::PRESETS.iter().zip(expected_fahrenheit) {
            let back = material.ignition_temperature * 9.0 / 5.0 + 32.0;
            assert!(
                (back - fahrenheit).abs() < 1e-3,
                "{}: {back} °F",
                material.name
            );
        }
        assert!((BurnMaterial::SILK.ignition_temperature - 142.777_78).abs() < 1e-3);
        assert!((PAPER_BURNT_TEMPERATURE - 1_093.333_3).abs() < 1e-2);
    }

    #[test]
    fn presets_are_valid() {
        for material in BurnMaterial::PRESETS {
            material.validate().unwrap();
        }
    }

    #[test]
    fn a_compression_fraction_outside_zero_to_one_is_rejected() {
        for bad in [-0.1, 1.5, f32::NAN, f32::INFINITY] {
            let structural = BurnMaterial {
                structural_compression_fraction: bad,
                ..BurnMaterial::COTTON
            };
            let shear = BurnMaterial {
                shear_compression_fraction: bad,
                ..BurnMaterial::COTTON
            };
            assert_eq!(
                structural.validate().unwrap_err().field,
                "structural_compression_fraction",
                "{bad}"
            );
            assert_eq!(
                shear.validate().unwrap_err().field,
                "shear_compression_fraction",
                "{bad}"
            );
        }
        for good in [0.0, 0.01, 1.0] {
            let material = BurnMaterial {
                structural_compression_fraction: good,
                shear_compression_fraction: good,
                ..BurnMaterial::COTTON
            };
            material.validate().unwrap();
        }
        // Bending springs keep their full stiffness in compression: they resist bending by it.
        use crate::sim::SpringKind;
        let cotton = BurnMaterial::COTTON;
        assert_eq!(cotton.compression(SpringKind::Bend), 1.0);
        assert_eq!(cotton.compression(SpringKind::Shear), BIAS_COMPRESSION);
        assert_eq!(cotton.compression(SpringKind::Structural), YARN_COMPRESSION);
    }

    #[test]
    fn invalid_fields_are_rejected_with_their_name() {
        let mut material = BurnMaterial::SILK;
        material.areal_density = -1.0;
        assert_eq!(material.validate().unwrap_err().field, "areal_density");
        let mut material = BurnMaterial::SILK;
        material.shear_stiffness = f32::NAN;
        assert_eq!(material.validate().unwrap_err().field, "shear_stiffness");
        let mut material = BurnMaterial::SILK;
        material.burnt_temperature = 2.0e5;
        assert_eq!(material.validate().unwrap_err().field, "burnt_temperature");
        let mut material = BurnMaterial::SILK;
        material.ignition_temperature = material.burnt_temperature + 1.0;
        assert_eq!(material.validate().unwrap_err().field, "burnt_temperature");
        let mut material = BurnMaterial::SILK;
        material.min_rest_fraction = 0.0;
        assert_eq!(material.validate().unwrap_err().field, "min_rest_fraction");
    }
}
