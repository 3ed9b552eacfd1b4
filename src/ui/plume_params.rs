//! What the control panel lets you change in the fire's air, within which ranges, and the
//! one path every edit takes into the plume: clamp to the ranges (a NaN keeps the previous
//! value), then [`PlumeSettings::validate`]. Plain Rust, testable without egui or an `App`.

use super::params::FieldRange;
use crate::fluid::PlumeSettings;
use std::ops::RangeInclusive;

/// Cells along each side of the plume's box (the panel keeps the box cubic in cells and its
/// size in metres: a finer grid has smaller cells).
pub const PLUME_CELLS: RangeInclusive<usize> = 8..=64;

/// The plume's rates and strengths the panel edits; changing them keeps the air moving.
pub const PLUME_FIELDS: [FieldRange<PlumeSettings>; 8] = [
    FieldRange {
        label: "buoyancy",
        unit: "m/s²K",
        range: 0.0..=0.2,
        logarithmic: false,
        field: |s| &mut s.buoyancy,
    },
    FieldRange {
        label: "smoke weight",
        unit: "m/s²",
        range: 0.0..=5.0,
        logarithmic: false,
        field: |s| &mut s.smoke_weight,
    },
    FieldRange {
        label: "vorticity",
        unit: "",
        range: 0.0..=5.0,
        logarithmic: false,
        field: |s| &mut s.vorticity,
    },
    FieldRange {
        label: "damping",
        unit: "1/s",
        range: 0.0..=5.0,
        logarithmic: false,
        field: |s| &mut s.damping,
    },
    FieldRange {
        label: "cooling",
        unit: "1/s",
        range: 0.0..=5.0,
        logarithmic: false,
        field: |s| &mut s.cooling,
    },
    FieldRange {
        label: "smoke decay",
        unit: "1/s",
        range: 0.0..=5.0,
        logarithmic: false,
        field: |s| &mut s.smoke_decay,
    },
    FieldRange {
        label: "heat into the air",
        unit: "share",
        range: 0.0..=1.0,
        logarithmic: false,
        field: |s| &mut s.convective_fraction,
    },
    FieldRange {
        label: "heat to cloth",
        unit: "W/m²K",
        range: 0.0..=500.0,
        logarithmic: false,
        field: |s| &mut s.cloth_heat_transfer,
    },
];

/// The one path of a panel edit into the plume: `cells` along each side (clamped to
/// [`PLUME_CELLS`]; the box keeps its size in metres, taken from `in_use`) and the fields
/// clamped to their ranges against the settings in use (a NaN keeps the value in use), then
/// validated. `Err` says why the settings in use should stay.
pub fn edit_plume(
    mut edited: PlumeSettings,
    cells: usize,
    in_use: &PlumeSettings,
) -> Result<PlumeSettings, String> {
    let mut old = *in_use;
    for field in &PLUME_FIELDS {
        field.clamp(&mut edited, &mut old);
    }
    let cells = cells.clamp(*PLUME_CELLS.start(), *PLUME_CELLS.end());
    if edited.resolution != [cells; 3] {
        let width = in_use.resolution[0] as f32 * in_use.cell_size;
        edited.resolution = [cells; 3];
        edited.cell_size = width / cells as f32;
    }
    edited.validate().map_err(|e| e.to_string())?;
    Ok(edited)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_edit_is_clamped_and_a_nan_keeps_the_value_in_use() {
        let in_use = PlumeSettings::default();
        let mut edited = in_use;
        edited.buoyancy = f32::NAN;
        edited.vorticity = 50.0;
        edited.cooling = -1.0;
        let out = edit_plume(edited, in_use.resolution[0], &in_use).unwrap();
        assert_eq!(out.buoyancy, in_use.buoyancy);
        assert_eq!(out.vorticity, 5.0);
        assert_eq!(out.cooling, 0.0);
        assert_eq!(out.resolution, in_use.resolution);
        assert_eq!(out.cell_size, in_use.cell_size);
    }

    #[test]
    fn a_finer_grid_keeps_the_box_and_shrinks_its_cells() {
        let in_use = PlumeSettings::default();
        let width = in_use.resolution[0] as f32 * in_use.cell_size;
        let out = edit_plume(in_use, 48, &in_use).unwrap();
        assert_eq!(out.resolution, [48; 3]);
        assert!((out.resolution[0] as f32 * out.cell_size - width).abs() < 1e-5);
        let coarsest = edit_plume(in_use, 1, &in_use).unwrap();
        assert_eq!(coarsest.resolution, [*PLUME_CELLS.start(); 3]);
    }

    #[test]
    fn every_field_range_passes_validation_at_both_ends() {
        for field in &PLUME_FIELDS {
            for end in [*field.range.start(), *field.range.end()] {
                let mut settings = PlumeSettings::default();
                *(field.field)(&mut settings) = end;
                assert!(settings.validate().is_ok(), "{} = {end}", field.label);
            }
        }
    }
}
