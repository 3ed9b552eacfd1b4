//! Crumpling by grid spacing: how far a patch of cloth heated below its ignition pulls the
//! cloth in as its springs shrink (the paper's one shrinking rest length per spring), at
//! several spacings and substep rates. The shrink is a material's property per kelvin and
//! second, so a cloth should crumple the same at any spacing; this study measures how far it
//! does.
//!
//! The case: a [`SIDE`]-metre square cotton cloth hanging from its top corners (default
//! solver, 1/60 s frames, the substep rate of the case), its centre block, a third of its
//! side across, held at [`HELD_AT`] °C (below cotton's ignition, so it does not burn) for
//! [`SECONDS`] s. After that the figures change by at most 0.01 (held for 6 s instead, at
//! 360 Hz and every spacing of the README's table). Measured at the end: the block's width along its middle row and its
//! height along its middle column, as fractions of their built length; the cloth's width
//! along the same row, as a fraction of its built width; and the mean ratio of length to rest
//! length of the structural springs inside the block (1: at their shrunk length).

use crate::sim::{BurnMaterial, ClothBuilder, ClothError, ClothSim, SpringKind};
use glam::{Affine3A, Vec3};

/// The cloth's side, m (a whole number of cells at 50, 25, 12.5 and 5 mm).
pub const SIDE: f32 = 0.75;
/// The heated block's temperature, °C.
pub const HELD_AT: f32 = 200.0;
/// How long the block is held hot, s.
pub const SECONDS: u32 = 3;
/// One frame, s.
const FRAME: f32 = 1.0 / 60.0;

/// A case: a grid spacing and a substep rate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CrumpleCase {
    /// Distance between neighbouring particles, m.
    pub spacing: f32,
    /// XPBD substeps per second of simulated time, Hz.
    pub substep_rate: f32,
    /// The spacing the rate is meant for, m, scaling it as `reference / spacing`
    /// ([`SolverSettings::substep_rate_spacing`](crate::sim::SolverSettings::substep_rate_spacing));
    /// `None`: the same rate at every spacing.
    pub rate_spacing: Option<f32>,
    /// Whether the block is heated (`false`: the same cloth left cold, for comparison).
    pub heated: bool,
}

/// What a case measured.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CrumpleRow {
    /// The case.
    pub case: CrumpleCase,
    /// Particles per side.
    pub particles_per_side: u32,
    /// XPBD substeps a 1/60 s frame.
    pub substeps: u32,
    /// The block's width along its middle row, as a fraction of its built width.
    pub block_width: f32,
    /// The block's height along its middle column, as a fraction of its built height.
    pub block_height: f32,
    /// The cloth's width along the block's middle row, as a fraction of its built width.
    pub cloth_width: f32,
    /// Mean length / rest length of the structural springs with both ends in the block.
    pub block_stretch: f32,
}

/// Runs one case (see the module's notes).
pub fn heated_block(case: CrumpleCase) -> Result<CrumpleRow, ClothError> {
    let material = BurnMaterial::COTTON;
    if !(case.spacing.is_finite() && case.spacing > 0.0) {
        return Err(ClothError::InvalidSpacing(case.spacing));
    }
    // Capped so `cells + 1` cannot overflow; a grid too large is then the builder's error.
    let cells = (SIDE / case.spacing).round().clamp(3.0, 1e9) as u32;
    let n = cells + 1;
    let mut sim = ClothSim::new(
        &ClothBuilder::grid(n, n, case.spacing).pin_top_corners(),
        material,
        Affine3A::from_translation(Vec3::new(0.0, 2.0, 0.0)),
    )?;
    sim.update_settings(|s| {
        s.solver.substep_rate = case.substep_rate;
        s.solver.substep_rate_spacing = case.rate_spacing;
    })?;
    let grid = sim.topology.grid.ok_or(ClothError::EmptyGrid {
        columns: n,
        rows: n,
    })?;
    // The middle third, in cells.
    let (low, high) = (cells / 3, cells - cells / 3);
    let middle = (low + high) / 2;
    let inside =
        |column: u32, row: u32| (low..=high).contains(&column) && (low..=high).contains(&row);
    let block: Vec<usize> = (low..=high)
        .flat_map(|row| (low..=high).map(move |column| grid.index(column, row)))
        .collect();
    let temperature = if case.heated {
        HELD_AT
    } else {
        material.initial_temperature
    };
    for _ in 0..60 * SECONDS {
        for &i in &block {
            sim.particles.temperature[i] = temperature;
        }
        sim.step(FRAME);
    }
    let substeps = sim.plan(FRAME).substeps;
    let position = &sim.particles.position;
    let at = |column: u32, row: u32| position[grid.index(column, row)];
    let built = |from: u32, to: u32| (to - from) as f32 * case.spacing;
    let springs = &sim.springs;
    let in_block = |i: u32| inside(i % n, i / n);
    let (mut sum, mut count) = (0.0, 0);
    let in_block_structural = |s: usize| {
        springs.kind[s] == SpringKind::Structural
            && in_block(springs.a[s])
            && in_block(springs.b[s])
    };
    for stretch in springs.stretches(position, &sim.particles.state, in_block_structural) {
        sum += stretch;
        count += 1;
    }
    Ok(CrumpleRow {
        case,
        particles_per_side: n,
        substeps,
        block_width: at(high, middle).distance(at(low, middle)) / built(low, high),
        block_height: at(middle, high).distance(at(middle, low)) / built(low, high),
        cloth_width: at(cells, middle).distance(at(0, middle)) / built(0, cells),
        block_stretch: sum / count.max(1) as f32,
    })
}

/// The heated block at every spacing, at each substep rate, each with the spacing it is
/// meant for or `None` (rate by rate, spacings in the order given).
pub fn study(
    spacings: &[f32],
    rates: &[(f32, Option<f32>)],
) -> Result<Vec<CrumpleRow>, ClothError> {
    rates
        .iter()
        .flat_map(|&(substep_rate, rate_spacing)| {
            spacings.iter().map(move |&spacing| CrumpleCase {
                spacing,
                substep_rate,
                rate_spacing,
                heated: true,
            })
        })
        .map(heated_block)
        .collect()
}

/// The study as a Markdown table with its caption.
pub fn markdown(rows: &[CrumpleRow]) -> String {
    let mut out = format!(
        "Crumpling: a {SIDE} m square cotton cloth hanging from its top corners, its middle \
         third held at {HELD_AT:.0} °C for {SECONDS} s (its springs shrink to their floor, \
         half their length). Widths and heights as fractions of their built length; stretch: \
         mean length / rest length of the block's structural springs.\n\n"
    );
    out.push_str("| substep rate Hz | spacing mm | particles | substeps a frame | block width | block height | cloth width | stretch in block |\n");
    out.push_str("|---|---|---|---|---|---|---|---|\n");
    for row in rows {
        let rate = match row.case.rate_spacing {
            Some(reference) => format!(
                "{:.0} x ({:.0} mm / spacing)",
                row.case.substep_rate,
                reference * 1000.0
            ),
            None => format!("{:.0}", row.case.substep_rate),
        };
        out.push_str(&format!(
            "| {rate} | {:.1} | {} x {} | {} | {:.2} | {:.2} | {:.2} | {:.2} |\n",
            row.case.spacing * 1000.0,
            row.particles_per_side,
            row.particles_per_side,
            row.substeps,
            row.block_width,
            row.block_height,
            row.cloth_width,
            row.block_stretch,
        ));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_heated_block_pulls_in_and_a_cold_one_does_not() {
        let case = CrumpleCase {
            spacing: 0.05,
            substep_rate: 360.0,
            rate_spacing: None,
            heated: false,
        };
        let cold = heated_block(case).unwrap();
        let hot = heated_block(CrumpleCase {
            heated: true,
            ..case
        })
        .unwrap();
        // Cold, the block hangs at its built size, stretched by its own weight only (under
        // the stress example's 1.10 for the hanging cloth).
        for fraction in [cold.block_width, cold.block_height, cold.block_stretch] {
            assert!((0.97..1.10).contains(&fraction), "cold: {cold:?}");
        }
        // Hot, its springs shrink to half their length: the block pulls in by a good part of
        // that, and the cloth around it with it.
        assert!(
            hot.block_width < 0.75 && hot.block_height < 0.75,
            "hot: {hot:?}"
        );
        assert!(
            hot.cloth_width < cold.cloth_width - 0.1,
            "{hot:?} against {cold:?}"
        );
    }

    #[test]
    fn with_the_rate_scaled_by_spacing_a_block_crumples_alike_at_two_spacings() {
        // The shrink is per kelvin and second, so a block held hot pulls in the same at any
        // spacing once one projection holds a spring as firmly on either grid.
        let at = |spacing| {
            heated_block(CrumpleCase {
                spacing,
                substep_rate: 360.0,
                rate_spacing: Some(0.025),
                heated: true,
            })
            .unwrap()
        };
        let (coarse, fine) = (at(0.025), at(0.0125));
        assert_eq!((coarse.substeps, fine.substeps), (6, 12));
        for (a, b, name, tolerance) in [
            (coarse.block_width, fine.block_width, "block width", 0.03),
            (coarse.block_height, fine.block_height, "block height", 0.04),
            (coarse.cloth_width, fine.cloth_width, "cloth width", 0.04),
            (coarse.block_stretch, fine.block_stretch, "stretch", 0.03),
        ] {
            assert!(
                (a - b).abs() < tolerance,
                "{name}: {a} at 25 mm, {b} at 12.5 mm"
            );
        }
        // And it did crumple: the springs are near their shrunk length, half the built one.
        assert!(
            coarse.block_width < 0.6 && fine.block_width < 0.6,
            "{coarse:?} {fine:?}"
        );
    }

    #[test]
    fn a_bad_spacing_or_rate_is_an_error() {
        for spacing in [0.0, -0.01, f32::NAN, f32::INFINITY, 1e-9] {
            let case = CrumpleCase {
                spacing,
                substep_rate: 360.0,
                rate_spacing: None,
                heated: true,
            };
            assert!(heated_block(case).is_err(), "spacing {spacing}");
        }
        let case = CrumpleCase {
            spacing: 0.05,
            substep_rate: f32::NAN,
            rate_spacing: None,
            heated: true,
        };
        assert!(heated_block(case).is_err());
    }
}
