//! The simulation's timings and counts as Bevy [diagnostics](bevy::diagnostic), so
//! `LogDiagnosticsPlugin`, any diagnostics overlay and the Bevy Remote Protocol show them
//! (as Avian's `PhysicsDiagnostics` does for its solver).
//!
//! One measurement per simulation step, taken after every cloth has stepped. Times are wall
//! time in milliseconds; the per-phase times are summed over every cloth (cloths that step in
//! parallel overlap, so the phases can add up to more than the step). Nothing is measured
//! while no cloth exists or the simulation is paused.

use super::components::{ClothInUse, ClothStatus};
use super::control::ClothStepTiming;
use bevy::diagnostic::{Diagnostic, DiagnosticPath, Diagnostics, RegisterDiagnostic};
use bevy::prelude::*;

/// The paths of the simulation's diagnostics.
pub struct ClothDiagnostics;

impl ClothDiagnostics {
    /// Wall time of the whole simulation step (every cloth, heat sources, colliders), ms.
    pub const STEP: DiagnosticPath = DiagnosticPath::const_new("burning_cloth/step");
    /// Heat: the heat model, heat sources and fire between cloths, ms (summed over cloths).
    pub const HEAT: DiagnosticPath = DiagnosticPath::const_new("burning_cloth/heat");
    /// Combustion: burn states, cut springs, shrinking rest lengths, ms.
    pub const COMBUSTION: DiagnosticPath = DiagnosticPath::const_new("burning_cloth/combustion");
    /// What hangs from what and the pieces that came loose, ms.
    pub const PIECES: DiagnosticPath = DiagnosticPath::const_new("burning_cloth/pieces");
    /// The substeps and the blow-up guard, ms.
    pub const DYNAMICS: DiagnosticPath = DiagnosticPath::const_new("burning_cloth/dynamics");
    /// Removing burnt triangles from the drawn list, ms.
    pub const CULLING: DiagnosticPath = DiagnosticPath::const_new("burning_cloth/culling");
    /// Cloths simulated.
    pub const CLOTHS: DiagnosticPath = DiagnosticPath::const_new("burning_cloth/cloths");
    /// Particles not yet burnt away, over every cloth.
    pub const PARTICLES_ALIVE: DiagnosticPath =
        DiagnosticPath::const_new("burning_cloth/particles_alive");
    /// Particles on fire now, over every cloth.
    pub const PARTICLES_BURNING: DiagnosticPath =
        DiagnosticPath::const_new("burning_cloth/particles_burning");

    /// Every path with its unit suffix.
    pub const ALL: [(DiagnosticPath, &'static str); 9] = [
        (Self::STEP, "ms"),
        (Self::HEAT, "ms"),
        (Self::COMBUSTION, "ms"),
        (Self::PIECES, "ms"),
        (Self::DYNAMICS, "ms"),
        (Self::CULLING, "ms"),
        (Self::CLOTHS, ""),
        (Self::PARTICLES_ALIVE, ""),
        (Self::PARTICLES_BURNING, ""),
    ];
}

/// Registers every path of [`ClothDiagnostics`].
pub(crate) fn register(app: &mut App) {
    for (path, suffix) in ClothDiagnostics::ALL {
        app.register_diagnostic(Diagnostic::new(path).with_suffix(suffix));
    }
}

/// Last system of a step: records its timings and counts.
pub(crate) fn measure(
    mut diagnostics: Diagnostics,
    timing: Res<ClothStepTiming>,
    cloths: Query<(&ClothInUse, &ClothStatus)>,
) {
    let milliseconds = |d: core::time::Duration| d.as_secs_f64() * 1e3;
    diagnostics.add_measurement(&ClothDiagnostics::STEP, || milliseconds(timing.last_step));
    let phases: [(
        &DiagnosticPath,
        fn(&crate::sim::PhaseTimes) -> core::time::Duration,
    ); 5] = [
        (&ClothDiagnostics::HEAT, |t| t.heat),
        (&ClothDiagnostics::COMBUSTION, |t| t.combustion),
        (&ClothDiagnostics::PIECES, |t| t.pieces),
        (&ClothDiagnostics::DYNAMICS, |t| t.dynamics),
        (&ClothDiagnostics::CULLING, |t| t.culling),
    ];
    for (path, phase) in phases {
        diagnostics.add_measurement(path, || {
            cloths
                .iter()
                .map(|(in_use, _)| milliseconds(phase(&in_use.last_step().times)))
                .sum()
        });
    }
    diagnostics.add_measurement(&ClothDiagnostics::CLOTHS, || cloths.iter().count() as f64);
    diagnostics.add_measurement(&ClothDiagnostics::PARTICLES_ALIVE, || {
        cloths
            .iter()
            .map(|(_, status)| f64::from(status.particles.saturating_sub(status.burnt)))
            .sum()
    });
    diagnostics.add_measurement(&ClothDiagnostics::PARTICLES_BURNING, || {
        cloths
            .iter()
            .map(|(_, status)| f64::from(status.ignited))
            .sum()
    });
}
