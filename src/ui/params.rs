//! What the control panel lets you change, within which ranges, and the one path every edit
//! takes into a cloth: clamp to the panel's ranges (a NaN keeps the previous value), then the
//! same validation as the builder. Plain Rust, testable without egui or an `App`.

use crate::sim::{
    BurnMaterial, Environment, HeatModel, PhysicalHeat, ProvotSettings, SolverSettings,
};
use std::ops::RangeInclusive;

/// One editable number of a struct: label, unit, allowed range, slider scale, and where it
/// lives.
#[derive(Clone)]
pub struct FieldRange<T> {
    /// Label shown next to the slider.
    pub label: &'static str,
    /// Unit shown after the value.
    pub unit: &'static str,
    /// Allowed values; edits are clamped into it.
    pub range: RangeInclusive<f32>,
    /// Whether the slider is logarithmic.
    pub logarithmic: bool,
    /// The field.
    pub field: fn(&mut T) -> &mut f32,
}

impl<T> FieldRange<T> {
    /// Clamps the field of `value` into the range; a NaN takes the field of `previous`.
    pub fn clamp(&self, value: &mut T, previous: &mut T) {
        let old = *(self.field)(previous);
        let new = (self.field)(value);
        *new = if new.is_nan() {
            old
        } else {
            new.clamp(*self.range.start(), *self.range.end())
        };
    }
}

/// The material fields the panel edits.
pub const MATERIAL_FIELDS: [FieldRange<BurnMaterial>; 18] = [
    FieldRange {
        label: "mass",
        unit: "kg/m²",
        range: 0.01..=2.0,
        logarithmic: true,
        field: |m| &mut m.areal_density,
    },
    FieldRange {
        label: "structural k",
        unit: "N/m",
        range: 1.0..=5000.0,
        logarithmic: true,
        field: |m| &mut m.structural_stiffness,
    },
    FieldRange {
        label: "shear k",
        unit: "N/m",
        range: 0.1..=5000.0,
        logarithmic: true,
        field: |m| &mut m.shear_stiffness,
    },
    FieldRange {
        label: "bend k",
        unit: "N/m",
        range: 0.01..=1000.0,
        logarithmic: true,
        field: |m| &mut m.bend_stiffness,
    },
    FieldRange {
        label: "push k, structural",
        unit: "× k",
        range: 0.0..=1.0,
        logarithmic: false,
        field: |m| &mut m.structural_compression_fraction,
    },
    FieldRange {
        label: "push k, shear",
        unit: "× k",
        range: 0.0..=1.0,
        logarithmic: false,
        field: |m| &mut m.shear_compression_fraction,
    },
    FieldRange {
        label: "damping ratio",
        unit: "",
        range: 0.0..=2.0,
        logarithmic: false,
        field: |m| &mut m.damping_ratio,
    },
    FieldRange {
        label: "air drag",
        unit: "N·s/m³",
        range: 0.0..=5.0,
        logarithmic: false,
        field: |m| &mut m.air_drag,
    },
    FieldRange {
        label: "ignition",
        unit: "°C",
        range: 50.0..=1000.0,
        logarithmic: false,
        field: |m| &mut m.ignition_temperature,
    },
    FieldRange {
        label: "burnt",
        unit: "°C",
        range: 100.0..=3000.0,
        logarithmic: false,
        field: |m| &mut m.burnt_temperature,
    },
    FieldRange {
        label: "heat spread",
        unit: "1/s",
        range: 0.0..=5.0,
        logarithmic: false,
        field: |m| &mut m.heat_spread_rate,
    },
    FieldRange {
        label: "self heating",
        unit: "°C/s",
        range: 0.0..=3000.0,
        logarithmic: false,
        field: |m| &mut m.self_heating_rate,
    },
    FieldRange {
        label: "burn time",
        unit: "s",
        range: 0.0..=5.0,
        logarithmic: false,
        field: |m| &mut m.burn_time,
    },
    FieldRange {
        label: "shrink factor",
        unit: "",
        range: 0.0..=0.2,
        logarithmic: false,
        field: |m| &mut m.shrink_factor,
    },
    FieldRange {
        label: "shrink floor",
        unit: "of length",
        range: 0.1..=1.0,
        logarithmic: false,
        field: |m| &mut m.min_rest_fraction,
    },
    FieldRange {
        label: "flame up",
        unit: "m/s",
        range: 1e-4..=1.0,
        logarithmic: true,
        field: |m| &mut m.flame_spread_up,
    },
    FieldRange {
        label: "flame sideways",
        unit: "m/s",
        range: 1e-4..=1.0,
        logarithmic: true,
        field: |m| &mut m.flame_spread_sideways,
    },
    FieldRange {
        label: "flame down",
        unit: "m/s",
        range: 1e-4..=1.0,
        logarithmic: true,
        field: |m| &mut m.flame_spread_down,
    },
];

/// Range of Provot's stretch limit: the relative stretch `τ` of
/// [`ProvotSettings::max_stretch`](crate::sim::ProvotSettings::max_stretch) (0.1 = 10 %).
pub const PROVOT_MAX_STRETCH: RangeInclusive<f32> = 0.01..=1.0;
/// Range of Provot's passes.
pub const PROVOT_PASSES: RangeInclusive<u32> = 1..=16;
/// Range of fixed substeps.
pub const SUBSTEPS: RangeInclusive<u32> = 1..=64;
/// Range of [`SolverSettings::substep_rate`](crate::sim::SolverSettings::substep_rate), Hz:
/// the automatic substeps' rate, from one substep a 1/60 s frame to the 64-substep cap. A
/// fine cloth crumples as a coarse one does only at a higher rate (README, Crumpling by
/// spacing), at a proportional cost.
pub const SUBSTEP_RATE: RangeInclusive<f32> = 60.0..=3840.0;
/// Range of each wind component, m/s.
pub const WIND: RangeInclusive<f32> = -20.0..=20.0;
/// Range of each gravity component, m/s².
pub const GRAVITY: RangeInclusive<f32> = -30.0..=30.0;
/// Ranges of the physical heat model: diffusivity (m²/s), convection, i.e. the upward bias
/// (1/s), cooling (1/s), burn heating (°C/s).
pub const PHYSICAL_HEAT: [RangeInclusive<f32>; 4] =
    [1e-8..=1e-2, 0.0..=20.0, 0.0..=2.0, 0.0..=5000.0];

/// Everything the panel edits for one cloth and the world.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PanelValues {
    /// The cloth's material.
    pub material: BurnMaterial,
    /// The cloth's solver.
    pub solver: SolverSettings,
    /// Gravity, wind and up for every cloth.
    pub environment: Environment,
}

/// The parameters of a physical heat model, in [`PHYSICAL_HEAT`] order.
fn physical_parts(model: HeatModel) -> Option<[f32; 4]> {
    match model {
        HeatModel::Physical(heat) => Some(heat.to_array()),
        HeatModel::Paper => None,
    }
}

fn clamp_or(value: f32, range: &RangeInclusive<f32>, previous: f32) -> f32 {
    if value.is_nan() {
        previous
    } else {
        value.clamp(*range.start(), *range.end())
    }
}

fn clamp_vec(value: &mut glam::Vec3, range: &RangeInclusive<f32>, previous: glam::Vec3) {
    for axis in 0..3 {
        value[axis] = clamp_or(value[axis], range, previous[axis]);
    }
}

impl PanelValues {
    /// The edit brought into the panel's ranges: every field clamped, a NaN replaced by its
    /// value in `previous`, the burnt temperature kept above ignition.
    pub fn clamped(mut self, previous: &PanelValues) -> Self {
        let mut old = *previous;
        for field in &MATERIAL_FIELDS {
            field.clamp(&mut self.material, &mut old.material);
        }
        let m = &mut self.material;
        m.burnt_temperature = m.burnt_temperature.max(m.ignition_temperature + 1.0);
        if let Some(provot) = &mut self.solver.provot {
            let old_stretch = old
                .solver
                .provot
                .map_or(ProvotSettings::default().max_stretch, |p| p.max_stretch);
            provot.max_stretch = clamp_or(provot.max_stretch, &PROVOT_MAX_STRETCH, old_stretch);
            provot.passes = provot
                .passes
                .clamp(*PROVOT_PASSES.start(), *PROVOT_PASSES.end());
        }
        if let Some(substeps) = &mut self.solver.substeps {
            *substeps = (*substeps).clamp(*SUBSTEPS.start(), *SUBSTEPS.end());
        }
        self.solver.substep_rate = clamp_or(
            self.solver.substep_rate,
            &SUBSTEP_RATE,
            old.solver.substep_rate,
        );
        if let HeatModel::Physical(heat) = &mut self.solver.heat_model {
            let fallback =
                physical_parts(old.solver.heat_model).unwrap_or(PhysicalHeat::GAME.to_array());
            let mut values = heat.to_array();
            for (i, value) in values.iter_mut().enumerate() {
                *value = clamp_or(*value, &PHYSICAL_HEAT[i], fallback[i]);
            }
            *heat = PhysicalHeat::from_array(values);
        }
        clamp_vec(&mut self.environment.wind, &WIND, old.environment.wind);
        clamp_vec(
            &mut self.environment.gravity,
            &GRAVITY,
            old.environment.gravity,
        );
        self
    }

    /// The builder's checks: material, solver and environment.
    pub fn validate(&self) -> Result<(), String> {
        self.material.validate().map_err(|e| e.to_string())?;
        self.solver.validate().map_err(|e| e.to_string())?;
        self.environment.validate().map_err(|e| e.to_string())
    }

    /// The one path of an edit into a cloth: clamped to the panel's ranges against the
    /// values in use, then validated. `Err` says why the values in use should stay.
    pub fn apply(self, in_use: &PanelValues) -> Result<PanelValues, String> {
        let values = self.clamped(in_use);
        values.validate()?;
        Ok(values)
    }
}
