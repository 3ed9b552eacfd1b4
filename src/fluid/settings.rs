//! [`PlumeSettings`]: the size of the air box and the physics of the hot air in it.

use super::pressure::Walls;
use bevy::reflect::{Reflect, std_traits::ReflectDefault};

/// Volumetric heat capacity of air at room temperature, J/(m³·K) (1.2 kg/m³ × 1005 J/(kg·K)).
pub const AIR_HEAT_CAPACITY: f32 = 1206.0;

/// How the fire's air is simulated. Every rate is per second and per metre, so a finer grid
/// gives the same plume, only sharper.
#[derive(Clone, Copy, Debug, PartialEq, Reflect)]
#[reflect(Default)]
pub struct PlumeSettings {
    /// Cells along x, y (up) and z. Each at least 4, at most 256. Cost grows with the cell
    /// count: 24³ is the default (the stress example prints the cost of each size).
    pub resolution: [usize; 3],
    /// Edge of a cell, m. The box is `resolution × cell_size` (2.4 m a side by default).
    pub cell_size: f32,
    /// Buoyant acceleration per kelvin of excess temperature, m/(s²·K): `g / T_ambient` for
    /// an ideal gas in the Boussinesq approximation (9.81 / 293 K).
    pub buoyancy: f32,
    /// Downward acceleration per unit of smoke density, m/s² (soot makes air heavier).
    pub smoke_weight: f32,
    /// Vorticity confinement strength (dimensionless; the force is `ε h (N × ω)`, in hot air
    /// only, fading below 20 K of excess temperature): puts
    /// back the swirl numerical diffusion removes. 0 turns it off.
    pub vorticity: f32,
    /// Rate the air's own motion dies away once nothing drives it (turbulent mixing with the
    /// still room around), 1/s.
    pub damping: f32,
    /// Rate hot air loses its excess temperature to radiation and mixing, 1/s.
    pub cooling: f32,
    /// Rate smoke thins out, 1/s.
    pub smoke_decay: f32,
    /// Heat of combustion of the cloth, J/kg (cellulose: cotton 16.5 MJ/kg, paper about
    /// 15; Babrauskas, "Heat release rates", SFPE Handbook).
    pub heat_of_combustion: f32,
    /// Share of the heat of combustion that goes into the air (the rest is radiated), in
    /// [0, 1] (about 0.7 for small fires).
    pub convective_fraction: f32,
    /// Smoke given off per kilogram of cloth burnt, density·m³/kg (density is unitless: 1 is
    /// thick smoke).
    pub smoke_yield: f32,
    /// Heat transfer from hot air to a cloth in it, W/(m²·K), both faces counted:
    /// convection (about 20 per face in a plume of a few m/s) plus the hot gas's radiation
    /// linearised (`4 ε σ T³`, about 25 per face near 500 K).
    pub cloth_heat_transfer: f32,
    /// Specific heat of cloth, J/(kg·K) (cellulose: about 1300).
    pub cloth_specific_heat: f32,
    /// Largest divergence left after the pressure solve, 1/s.
    pub tolerance: f32,
    /// Most conjugate-gradient iterations per step (each one V-cycle).
    pub max_iterations: u32,
    /// Largest excess temperature the air may hold, K.
    pub max_temperature: f32,
    /// What lies beyond each face of the box.
    pub walls: Walls,
}

impl Default for PlumeSettings {
    fn default() -> Self {
        Self {
            resolution: [24, 24, 24],
            cell_size: 0.1,
            buoyancy: 9.81 / 293.0,
            smoke_weight: 0.0,
            vorticity: 2.0,
            damping: 0.3,
            cooling: 0.3,
            smoke_decay: 0.15,
            heat_of_combustion: 16.5e6,
            convective_fraction: 0.7,
            smoke_yield: 50.0,
            cloth_heat_transfer: 80.0,
            cloth_specific_heat: 1300.0,
            tolerance: 0.05,
            max_iterations: 12,
            max_temperature: 1200.0,
            walls: Walls::OPEN,
        }
    }
}

/// Why plume settings were refused.
#[derive(Clone, Debug, PartialEq)]
pub struct PlumeSettingsError(pub String);

impl core::fmt::Display for PlumeSettingsError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(f, "invalid plume settings: {}", self.0)
    }
}

impl std::error::Error for PlumeSettingsError {}

impl PlumeSettings {
    /// Checks every field: a resolution of 4 to 256 cells per axis, a positive finite cell
    /// size, finite non-negative rates and coefficients, a positive tolerance and iteration
    /// count.
    pub fn validate(&self) -> Result<(), PlumeSettingsError> {
        if let Some(n) = self.resolution.iter().find(|n| !(4..=256).contains(*n)) {
            return Err(PlumeSettingsError(format!(
                "resolution {n} is outside 4..=256 cells"
            )));
        }
        let non_negative = [
            ("buoyancy", self.buoyancy),
            ("smoke_weight", self.smoke_weight),
            ("vorticity", self.vorticity),
            ("damping", self.damping),
            ("cooling", self.cooling),
            ("smoke_decay", self.smoke_decay),
            ("heat_of_combustion", self.heat_of_combustion),
            ("convective_fraction", self.convective_fraction),
            ("smoke_yield", self.smoke_yield),
            ("cloth_heat_transfer", self.cloth_heat_transfer),
        ];
        if let Some((name, value)) = non_negative
            .iter()
            .find(|(_, v)| !(v.is_finite() && *v >= 0.0))
        {
            return Err(PlumeSettingsError(format!(
                "{name} = {value} must be finite and non-negative"
            )));
        }
        let positive = [
            ("cell_size", self.cell_size),
            ("cloth_specific_heat", self.cloth_specific_heat),
            ("tolerance", self.tolerance),
            ("max_temperature", self.max_temperature),
        ];
        if let Some((name, value)) = positive.iter().find(|(_, v)| !(v.is_finite() && *v > 0.0)) {
            return Err(PlumeSettingsError(format!(
                "{name} = {value} must be finite and positive"
            )));
        }
        if self.convective_fraction > 1.0 {
            return Err(PlumeSettingsError(format!(
                "convective_fraction = {} is above 1",
                self.convective_fraction
            )));
        }
        if self.max_iterations == 0 {
            return Err(PlumeSettingsError(
                "max_iterations must be at least 1".into(),
            ));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_are_valid_and_bad_values_are_named() {
        assert!(PlumeSettings::default().validate().is_ok());
        let bad = PlumeSettings {
            cell_size: f32::NAN,
            ..Default::default()
        };
        assert!(bad.validate().unwrap_err().0.contains("cell_size"));
        let bad = PlumeSettings {
            resolution: [0, 32, 32],
            ..Default::default()
        };
        assert!(bad.validate().is_err());
        let bad = PlumeSettings {
            cooling: -1.0,
            ..Default::default()
        };
        assert!(bad.validate().unwrap_err().0.contains("cooling"));
    }
}
