//! Measures the cost of simulating burning cloth: milliseconds per 1/60 s step and
//! particle-substeps per millisecond, by cloth size and integrator.
//!
//! ```sh
//! cargo run --release --example stress --no-default-features
//! ```
//!
//! Sizes 32 x 32 and 64 x 64. Each run: a cotton cloth pinned along its top edge, lit at the bottom centre, stepped
//! 120 times (2 s) after a 30-step warm-up; the median of 3 runs is printed.

use bevy::math::{Affine3A, Vec3};
use bevy_burning_cloth::sim::{BurnMaterial, ClothBuilder, ClothSim, Integrator};
use std::time::Instant;

fn run(size: u32, integrator: Integrator) -> (f64, u32) {
    let mut sim = ClothSim::new(
        &ClothBuilder::grid(size, size, 1.5 / size as f32).pin_top_every(4),
        BurnMaterial::COTTON,
        Affine3A::from_translation(Vec3::new(0.0, 2.0, 0.0)),
    )
    .expect("valid cloth");
    sim.solver.integrator = integrator;
    let grid = sim.topology.grid.unwrap();
    sim.ignite(grid.index(size / 2, size - 2)).unwrap();
    let dt = 1.0 / 60.0;
    for _ in 0..30 {
        sim.step(dt);
    }
    let steps = 120;
    let started = Instant::now();
    let mut substeps = 0;
    for _ in 0..steps {
        substeps = sim.step(dt).substeps;
    }
    assert!(sim.particles.is_finite());
    (
        started.elapsed().as_secs_f64() * 1e3 / f64::from(steps),
        substeps,
    )
}

fn main() {
    println!(
        "| cloth | particles | integrator | substeps | ms per 1/60 s step | particle-substeps per ms |"
    );
    println!("|---|---|---|---|---|---|");
    for size in [32u32, 64] {
        for integrator in [
            Integrator::SymplecticEuler,
            Integrator::Verlet,
            Integrator::Rk4,
            Integrator::Xpbd,
        ] {
            let mut times: Vec<(f64, u32)> = (0..3).map(|_| run(size, integrator)).collect();
            times.sort_by(|a, b| a.0.total_cmp(&b.0));
            let (ms, substeps) = times[1];
            let particles = size * size;
            println!(
                "| {size} x {size} | {particles} | {} | {substeps} | {ms:.2} | {:.0} |",
                integrator.name(),
                f64::from(particles * substeps) / ms
            );
        }
    }
}
