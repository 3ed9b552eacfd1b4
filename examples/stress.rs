//! Measures the cost of simulating burning cloth: milliseconds per 1/60 s step and
//! particle-substeps per millisecond, by cloth size and integrator.
//!
//! ```sh
//! cargo run --release --example stress --no-default-features --features smoke
//! ```
//!
//! Sizes 32 x 32 and 64 x 64. Each run: a cotton cloth pinned along its top edge, lit at the
//! bottom centre, stepped 120 times (2 s) after a 30-step warm-up; the median of 3 runs is
//! printed. With the `smoke` feature it also times the smoke pool on a 64 x 64 paper cloth
//! lit at five points, at the default birth rates and at 8 times them (a dense pool),
//! emission and motion timed separately, as live particles advanced per millisecond.

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
    sim.update_settings(|s| s.solver.integrator = integrator)
        .expect("valid integrator");
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

/// Times the smoke pool on a burning cloth: (ms per step emitting, ms per step advancing,
/// mean live particles).
#[cfg(feature = "smoke")]
fn smoke_run(capacity: usize, rate_scale: f32) -> (f64, f64, f64) {
    use bevy_burning_cloth::smoke::{Air, BurningCloth, SmokeSettings, SmokeSim};
    let size = 64;
    let mut cloth = ClothSim::new(
        &ClothBuilder::grid(size, size, 1.5 / size as f32).pin_top_every(4),
        BurnMaterial::PAPER,
        Affine3A::from_translation(Vec3::new(0.0, 2.0, 0.0)),
    )
    .expect("valid cloth");
    let grid = cloth.topology.grid.unwrap();
    for (column, row) in [(8, 56), (24, 40), (32, 60), (40, 20), (56, 50)] {
        cloth.ignite(grid.index(column, row)).unwrap();
    }
    let mut settings = SmokeSettings::default().with_capacity(capacity);
    for kind in &mut settings.kind {
        kind.rate *= rate_scale;
    }
    let mut smoke = SmokeSim::new(settings).expect("valid smoke");
    let (dt, air) = (1.0 / 60.0, Air::default());
    for _ in 0..240 {
        cloth.step(dt);
        smoke.emit(&BurningCloth::of(&cloth), &air, dt);
        smoke.advance(&air, dt);
    }
    let steps = 120;
    let (mut emitting, mut advancing, mut live) = (0.0, 0.0, 0.0);
    for _ in 0..steps {
        cloth.step(dt);
        let started = Instant::now();
        smoke.emit(&BurningCloth::of(&cloth), &air, dt);
        let emitted = Instant::now();
        smoke.advance(&air, dt);
        emitting += (emitted - started).as_secs_f64();
        advancing += emitted.elapsed().as_secs_f64();
        live += smoke.pool.live() as f64;
    }
    let per_step = 1e3 / f64::from(steps);
    (
        emitting * per_step,
        advancing * per_step,
        live / f64::from(steps),
    )
}

#[cfg(feature = "smoke")]
fn smoke_table() {
    println!();
    println!(
        "| birth rates | pool capacity | live particles | emit ms per step | advance ms per step | particles advanced per ms |"
    );
    println!("|---|---|---|---|---|---|");
    for (rate_scale, capacity) in [(1.0, 4096), (8.0, 16384)] {
        let mut runs: Vec<(f64, f64, f64)> =
            (0..3).map(|_| smoke_run(capacity, rate_scale)).collect();
        runs.sort_by(|a, b| a.1.total_cmp(&b.1));
        let (emit, advance, live) = runs[1];
        println!(
            "| {rate_scale}x | {capacity} | {live:.0} | {emit:.3} | {advance:.3} | {:.0} |",
            live / advance
        );
    }
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
    #[cfg(feature = "smoke")]
    smoke_table();
}
