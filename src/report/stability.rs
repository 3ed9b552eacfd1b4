//! The stability matrix: every integrator against stiff and extreme cases.
//!
//! Each cell runs one case twice: raw (blow-up guard off) to show where the solver itself
//! fails, and guarded (the default) to show the cloth stays finite anyway. Measured per cell:
//! whether the raw run stayed finite and bounded, the step where it failed, the largest
//! energy gain relative to the scene's energy scale, the largest stretch, and how many
//! particles the guard had to put back.
//!
//! Energy: `E = kinetic + spring + gravitational (−m g·x)`, over unburnt particles. Damping,
//! drag and Provot's velocity correction only remove energy and pins do no work, so
//! `E(t) ≤ E(0)`, and since spring energy is never negative, the motion's share
//! `kinetic + gravitational` never exceeds `E(0)` either. The gain is the largest
//! `(kinetic + gravitational)(t) − E(0)`: energy that appeared from nowhere in the motion.
//! It is the same test for every method; it does not charge XPBD with `½ k (l − l₀)²` for
//! the stretch its unconverged constraints leave on stiff springs, which its constraint
//! forces do not hold (that stretch is in the stretch column). For a non-burning case any
//! gain is the integrator's. Burning cases shrink rest lengths, which does work on the cloth:
//! their gain is shown, not judged. The scale is `M g H + E_kinetic(0) + E_spring(0)` with
//! `M` the cloth's mass and `H` its height.

use crate::sim::derived::force_params;
use crate::sim::guard::BlowUpGuard;
use crate::sim::{BurnMaterial, ClothBuilder, ClothSim, GuardSettings, Integrator, SpringKind};
use glam::{Affine3A, Vec3};

/// One row of the matrix: a scene and what it stresses.
pub struct StabilityCase {
    /// Short name for the table.
    pub name: String,
    /// True when the case burns (rest lengths shrink: energy may rightly grow).
    pub burning: bool,
    /// Builds the scene for an integrator.
    pub build: Box<dyn Fn(Integrator) -> ClothSim>,
}

/// What one run measured.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RunResult {
    /// No particle went non-finite or past the guard's speed limit.
    pub finite: bool,
    /// The first step with a blown-up particle, if any.
    pub failed_at: Option<u32>,
    /// Largest `(E − E0) / scale` seen before any failure.
    pub energy_gain: f32,
    /// Largest structural length / rest length seen before any failure.
    pub max_stretch: f32,
    /// Particles the guard put back (guarded runs).
    pub repairs: u32,
    /// Substeps per step.
    pub substeps: u32,
}

/// A cell of the matrix: the raw and the guarded run.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Cell {
    /// With the blow-up guard off.
    pub raw: RunResult,
    /// With the blow-up guard on (default).
    pub guarded: RunResult,
}

impl Cell {
    /// True when the raw run stayed finite with an energy gain of at most `tolerance`.
    pub fn stable(&self, tolerance: f32) -> bool {
        self.raw.finite && self.raw.energy_gain <= tolerance
    }
}

const COLUMNS: u32 = 12;
const ROWS: u32 = 12;
const SPACING: f32 = 0.05;
/// The fixed step every case runs at, s.
pub const DT: f32 = 1.0 / 60.0;

/// Cotton with these stiffnesses, its springs as stiff in compression as in tension
/// ([`BurnMaterial::with_linear_springs`]): the linear springs the stability limits are
/// derived for
/// ([`stable_time_step`](crate::sim::integrate::stable_time_step)), which a softer
/// compression leaves as they are (they are set by the stiffness in tension).
fn material(stiffness: f32, bend: f32) -> BurnMaterial {
    BurnMaterial {
        structural_stiffness: stiffness,
        shear_stiffness: stiffness,
        bend_stiffness: bend,
        ..BurnMaterial::COTTON.with_linear_springs()
    }
}

fn scene(material: BurnMaterial, integrator: Integrator, builder: ClothBuilder) -> ClothSim {
    let mut sim = ClothSim::new(
        &builder,
        material,
        Affine3A::from_translation(Vec3::new(0.0, 1.0, 0.0)),
    )
    .expect("stability scenes are valid");
    // The matrix studies each integrator as it is: no switch to XPBD past the substep cap.
    sim.update_settings(|s| {
        s.solver.integrator = integrator;
        s.solver.stiff_fallback = false;
    })
    .expect("every integrator is valid");
    // Start the cloth swinging so every case has motion to integrate.
    for v in &mut sim.particles.velocity {
        *v = Vec3::new(0.0, 0.0, 0.5);
    }
    sim
}

fn hanging(material: BurnMaterial, integrator: Integrator) -> ClothSim {
    scene(
        material,
        integrator,
        ClothBuilder::grid(COLUMNS, ROWS, SPACING).pin_top_corners(),
    )
}

/// The cases of the matrix.
pub fn cases() -> Vec<StabilityCase> {
    let mut cases: Vec<StabilityCase> = Vec::new();
    for exponent in 1..=7 {
        let k = 10f32.powi(exponent);
        cases.push(StabilityCase {
            name: format!("stiffness 1e{exponent} N/m, auto substeps"),
            burning: false,
            build: Box::new(move |i| hanging(material(k, 0.1 * k), i)),
        });
    }
    for exponent in [0, 3, 6] {
        let ratio = 10f32.powi(exponent);
        cases.push(StabilityCase {
            name: format!("structural/bend ratio 1e{exponent}"),
            burning: false,
            build: Box::new(move |i| hanging(material(100.0, 100.0 / ratio), i)),
        });
    }
    for factor in [0.1f32, 0.5, 1.0, 2.0, 10.0] {
        cases.push(StabilityCase {
            name: format!("step {factor}x the stability limit"),
            burning: false,
            build: Box::new(move |i| {
                let mut sim = hanging(material(2_000.0, 200.0), i);
                let stable = sim.stable_step();
                let substeps = (DT / (factor * stable)).round().max(1.0) as u32;
                sim.update_settings(|s| s.solver.substeps = Some(substeps))
                    .expect("at least one substep");
                sim
            }),
        });
    }
    cases.push(StabilityCase {
        name: "particle mass 1e-6 kg".into(),
        burning: false,
        build: Box::new(|i| {
            scene(
                material(100.0, 10.0),
                i,
                ClothBuilder::grid(COLUMNS, ROWS, SPACING)
                    .pin_top_corners()
                    .with_total_mass(1e-6 * (COLUMNS * ROWS) as f32),
            )
        }),
    });
    cases.push(StabilityCase {
        name: "heavy weight on light cloth, 1:1e5".into(),
        burning: false,
        build: Box::new(|i| {
            let mut sim = hanging(material(100.0, 10.0), i);
            let grid = sim.topology.grid.unwrap();
            let weight = grid.index(COLUMNS / 2, ROWS - 1);
            sim.particles.mass[weight] *= 1e5;
            sim.particles.inv_mass[weight] = 1.0 / sim.particles.mass[weight];
            sim
        }),
    });
    cases.push(StabilityCase {
        name: "all particles pinned".into(),
        burning: false,
        build: Box::new(|i| {
            let mut sim = hanging(material(100.0, 10.0), i);
            sim.particles.inv_mass.fill(0.0);
            sim
        }),
    });
    cases.push(StabilityCase {
        name: "none pinned (free fall)".into(),
        burning: false,
        build: Box::new(|i| {
            scene(
                material(100.0, 10.0),
                i,
                ClothBuilder::grid(COLUMNS, ROWS, SPACING),
            )
        }),
    });
    cases.push(StabilityCase {
        name: "coincident particles, zero-length springs".into(),
        burning: false,
        build: Box::new(|i| {
            let mut sim = hanging(material(100.0, 10.0), i);
            let grid = sim.topology.grid.unwrap();
            // Row 6 collapses onto row 5, and the springs between them have zero rest length.
            for column in 0..COLUMNS {
                let above = sim.particles.position[grid.index(column, 5)];
                sim.particles.position[grid.index(column, 6)] = above;
            }
            for s in 0..sim.springs.len() {
                let (a, b) = (sim.springs.a[s] as usize, sim.springs.b[s] as usize);
                if sim.particles.position[a] == sim.particles.position[b] {
                    sim.springs.rest_length[s] = 0.0;
                    sim.springs.initial_rest_length[s] = 0.0;
                }
            }
            sim
        }),
    });
    cases.push(StabilityCase {
        name: "rest lengths shrunk to the floor".into(),
        burning: false,
        build: Box::new(|i| {
            let mut sim = hanging(material(100.0, 10.0), i);
            let floor = sim.material().min_rest_fraction;
            for s in 0..sim.springs.len() {
                sim.springs.rest_length[s] = floor * sim.springs.initial_rest_length[s];
            }
            sim
        }),
    });
    cases.push(StabilityCase {
        name: "temperatures -273.15 C and 1e5 C".into(),
        burning: true,
        build: Box::new(|i| {
            let mut sim = hanging(material(100.0, 10.0), i);
            for (n, t) in sim.particles.temperature.iter_mut().enumerate() {
                *t = if n % 2 == 0 { -273.15 } else { 1.0e5 };
            }
            sim
        }),
    });
    cases.push(StabilityCase {
        name: "burning while stretched 3x".into(),
        burning: true,
        build: Box::new(|i| {
            let mut sim = hanging(material(100.0, 10.0), i);
            let top = Vec3::new(0.0, 1.0, 0.0);
            for p in &mut sim.particles.position {
                *p = top + (*p - top) * 3.0;
            }
            let grid = sim.topology.grid.unwrap();
            sim.ignite(grid.index(COLUMNS / 2, ROWS - 2)).unwrap();
            sim.ignite(grid.index(2, ROWS / 2)).unwrap();
            sim
        }),
    });
    cases
}

/// Total energy of the unburnt particles, J (see the module docs).
pub fn total_energy(sim: &ClothSim) -> f32 {
    crate::sim::energy::cloth_energy(
        &sim.particles,
        &sim.springs,
        sim.material(),
        &sim.topology,
        sim.environment(),
    )
}

fn energy_scale(sim: &ClothSim) -> f32 {
    let params = force_params(sim.material(), &sim.topology, sim.environment());
    let height = (ROWS - 1) as f32 * SPACING;
    let p = &sim.particles;
    p.live_mass() * sim.environment().gravity.length() * height
        + p.kinetic_energy()
        + sim
            .springs
            .potential_energy(&p.position, &p.state, &params.coefficients)
}

/// Runs one case for `steps` fixed steps with the guard on or off.
pub fn run(case: &StabilityCase, integrator: Integrator, steps: u32, guarded: bool) -> RunResult {
    let mut sim = (case.build)(integrator);
    sim.update_settings(|s| s.solver.guard.enabled = guarded)
        .expect("the guard switch is valid");
    let e0 = total_energy(&sim);
    let scale = energy_scale(&sim).max(1e-12);
    let mut result = RunResult {
        finite: true,
        max_stretch: 1.0,
        substeps: sim.plan(DT).substeps,
        ..Default::default()
    };
    let limits = GuardSettings::default();
    for step in 0..steps {
        let report = sim.step(DT);
        result.repairs += report.repaired;
        let blown =
            (0..sim.particles.len()).any(|i| BlowUpGuard::is_blown_up(&sim.particles, i, &limits));
        if blown || !sim.particles.is_finite() {
            result.finite = false;
            result.failed_at.get_or_insert(step);
            if !guarded {
                break;
            }
            continue;
        }
        let motion = crate::sim::energy::motion_energy(&sim.particles, sim.environment());
        let gain = (motion - e0) / scale;
        result.energy_gain = result.energy_gain.max(gain);
        let stretch = sim
            .springs
            .max_stretch(&sim.particles.position, &sim.particles.state, |k| {
                k == SpringKind::Structural
            });
        result.max_stretch = result.max_stretch.max(stretch);
    }
    result
}

/// Runs every case with every integrator, raw and guarded.
pub fn matrix(steps: u32) -> Vec<(String, bool, Vec<Cell>)> {
    cases()
        .iter()
        .map(|case| {
            let cells = Integrator::ALL
                .iter()
                .map(|&integrator| Cell {
                    raw: run(case, integrator, steps, false),
                    guarded: run(case, integrator, steps, true),
                })
                .collect();
            (case.name.clone(), case.burning, cells)
        })
        .collect()
}

/// The matrix as a Markdown table: per integrator, "raw" (finite or the failing step,
/// energy gain, max stretch) and the guarded run's finiteness and repairs.
pub fn markdown(rows: &[(String, bool, Vec<Cell>)], steps: u32) -> String {
    let mut out = format!(
        "Each cell: raw run (guard off, no switch to XPBD past the substep cap) `ok` or \
         `FAILED@step`, dE (largest kinetic + gravitational energy above the start's total, \
         over M g H + E_kinetic(0) + E_spring(0)), max structural stretch, substeps per step; \
         then the guarded run: `finite` and particles repaired. {steps} steps of {DT:.4} s, \
         12 x 12 cloth.\n\n| case |"
    );
    for integrator in Integrator::ALL {
        out.push_str(&format!(" {} |", integrator.name()));
    }
    out.push_str("\n|---|");
    for _ in Integrator::ALL {
        out.push_str("---|");
    }
    out.push('\n');
    for (name, burning, cells) in rows {
        out.push_str(&format!(
            "| {name}{} |",
            if *burning { " (burning)" } else { "" }
        ));
        for cell in cells {
            let raw = match cell.raw.failed_at {
                Some(step) => format!("FAILED@{step}"),
                None => "ok".to_owned(),
            };
            let guarded = if cell.guarded.finite {
                format!("finite, {} repaired", cell.guarded.repairs)
            } else {
                "NOT FINITE".to_owned()
            };
            out.push_str(&format!(
                " {raw}, dE {:+.3}, stretch {:.2}, {} sub; {guarded} |",
                cell.raw.energy_gain, cell.raw.max_stretch, cell.raw.substeps
            ));
        }
        out.push('\n');
    }
    out
}
