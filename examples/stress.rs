//! Measures what a burning cloth costs per 1/60 s frame, by size and solver, phase by phase;
//! twenty small cloths against one big one through the plugin; and the smoke pool.
//!
//! ```sh
//! cargo run --release --example stress --no-default-features --features smoke,parallel
//! ```
//!
//! `-- --default-only`: the size table for the default solver alone (a minute, for iterating);
//! `-- --physical-heat-only`: the same under `HeatModel::PHYSICAL` (its flame front);
//! `--substep-rate 720`: XPBD's substeps per second in the size table (360 by default);
//! `--substep-rate-spacing 25`: that rate meant for 25 mm, scaled by each cloth's spacing
//! (`SolverSettings::substep_rate_spacing`);
//! `--sizes 32 64`: only those sizes in the size table, or plume grids with `--plume-only`
//! (for profiling one);
//! `-- --many-only`: the twenty-cloth scene alone; `-- --wake-only`: what handing a task to
//! the compute pool costs after it has idled; `-- --smoke-only` (with `smoke`): the smoke
//! pool's table alone; `-- --plume-only` (with `fluid`): the plume's
//! tables alone (its cost by grid size, and its pull on cloths by size).
//!
//! Each run: a cotton cloth 1.5 m wide, pinned at every 4th particle of its top edge, lit at the
//! bottom centre, burning for 2 s before the measured frames, then measured over the next 8 s
//! (480 frames) at every size, so every size is timed over the same stretch of its fire: what
//! burning costs grows with the fire. The median of 5 runs (3 for the slow force-based
//! solver) is printed, with its mean over the 8 s and its dearest second. "frame" is the
//! simulation step (heat, combustion, pieces, dynamics, culling) plus the smoke (with feature
//! `smoke`) plus the CPU side of the mesh update ([`MeshData::update`]: local positions,
//! normals, burn data). Threads: Bevy's compute task pool
//! with a thread per core (Bevy's default leaves one on a 2-core machine).

use bevy::math::{Affine3A, Vec3};
use bevy::tasks::{ComputeTaskPool, TaskPool};
use bevy_burning_cloth::sim::mesh::MeshData;
use bevy_burning_cloth::sim::{
    BurnMaterial, ClothBuilder, ClothSim, HeatModel, Integrator, PhaseTimes, SpringKind,
};
use std::time::{Duration, Instant};

const DT: f32 = 1.0 / 60.0;

/// The measured window: seconds of burning timed at every size, after 2 s untimed.
const MEASURED_SECONDS: u32 = 8;

/// One measured run: phase times per frame (ms), the dearest second's mean frame (ms), the
/// share of the cloth burnt away at the end, how the steps ran, and the hanging cloth's
/// largest structural stretch before it was lit.
#[derive(Clone, Copy, Default)]
struct Run {
    phases: [f64; 7],
    worst: f64,
    burnt: f32,
    substeps: u32,
    integrator: Integrator,
    stretch: f32,
    burning_stretch: BurningStretch,
}

/// How far the burning cloth's structural springs stretch, sampled every half second of the
/// measured window (outside the clock): the largest ratio to rest length of the springs heat
/// has not shrunk (`Springs::is_shrunk`), and the 90th percentile of those it has (against
/// their shrunk length), the largest of the samples of each.
#[derive(Clone, Copy, Default)]
struct BurningStretch {
    unheated: f32,
    shrunk_p90: f32,
}

impl BurningStretch {
    /// Takes in the cloth as it is now.
    fn sample(&mut self, sim: &ClothSim, shrunk: &mut Vec<f32>) {
        let (springs, particles) = (&sim.springs, &sim.particles);
        let structural = |s: usize| springs.kind[s] == SpringKind::Structural;
        let unheated = springs.max_stretch_of(&particles.position, &particles.state, |s| {
            structural(s) && !springs.is_shrunk(s)
        });
        shrunk.clear();
        shrunk.extend(
            springs.stretches(&particles.position, &particles.state, |s| {
                structural(s) && springs.is_shrunk(s)
            }),
        );
        shrunk.sort_by(f32::total_cmp);
        let p90 = shrunk.get(shrunk.len() * 9 / 10).copied().unwrap_or(1.0);
        self.unheated = self.unheated.max(unheated);
        self.shrunk_p90 = self.shrunk_p90.max(p90);
    }
}

impl Run {
    fn total(&self) -> f64 {
        self.phases.iter().sum()
    }
}

const PHASES: [&str; 7] = [
    "heat",
    "combustion",
    "pieces",
    "dynamics",
    "culling",
    "smoke",
    "mesh",
];

fn ms(duration: Duration) -> f64 {
    duration.as_secs_f64() * 1e3
}

/// A cloth `size` particles square, 1.5 m wide, pinned at every 4th particle of its top edge
/// at 2 m.
fn hanging(size: u32, material: BurnMaterial) -> ClothSim {
    ClothSim::new(
        &ClothBuilder::grid(size, size, 1.5 / size as f32).pin_top_every(4),
        material,
        Affine3A::from_translation(Vec3::new(0.0, 2.0, 0.0)),
    )
    .expect("valid cloth")
}

fn run(size: u32, integrator: Integrator, heat_model: HeatModel, pool: &TaskPool) -> Run {
    let mut sim = hanging(size, BurnMaterial::COTTON);
    sim.update_settings(|s| {
        s.solver.integrator = integrator;
        s.solver.heat_model = heat_model;
        if let Some(rate) = substep_rate() {
            s.solver.substep_rate = rate;
        }
        s.solver.substep_rate_spacing = substep_rate_spacing();
    })
    .expect("valid settings");
    // Hang for 2 s, then measure the stretch and set it alight.
    for _ in 0..120 {
        sim.step_on(DT, Some(pool));
    }
    let stretch = sim
        .springs
        .max_stretch(&sim.particles.position, &sim.particles.state, |k| {
            k == SpringKind::Structural
        });
    let grid = sim.topology.grid.expect("a grid");
    sim.ignite(grid.index(size / 2, size - 2)).unwrap();
    #[cfg(feature = "smoke")]
    let mut smoke = bevy_burning_cloth::smoke::SmokeSim::new(Default::default()).unwrap();
    let mut mesh = MeshData::default();
    let to_local = sim.transform.inverse();
    let mut frame = |sim: &mut ClothSim, times: Option<&mut Run>| {
        let report = sim.step_on(DT, Some(pool));
        let clock = Instant::now();
        #[cfg(feature = "smoke")]
        {
            use bevy_burning_cloth::smoke::{Air, BurningCloth};
            smoke.emit(&BurningCloth::of(sim), &Air::default(), DT);
            smoke.advance(&Air::default(), DT);
        }
        let smoked = Instant::now();
        mesh.update(
            &sim.particles,
            &sim.topology,
            sim.material(),
            to_local,
            Some(pool),
        );
        let meshed = Instant::now();
        if let Some(run) = times {
            let PhaseTimes {
                heat,
                combustion,
                pieces,
                dynamics,
                culling,
            } = report.times;
            let phases = [
                heat,
                combustion,
                pieces,
                dynamics,
                culling,
                smoked - clock,
                meshed - smoked,
            ];
            for (sum, phase) in run.phases.iter_mut().zip(phases) {
                *sum += ms(phase);
            }
            run.substeps = report.substeps;
            run.integrator = report.integrator;
        }
    };
    // Burn for 2 s, then measure.
    for _ in 0..120 {
        frame(&mut sim, None);
    }
    let mut measured = Run {
        stretch,
        ..Run::default()
    };
    let mut shrunk = Vec::new();
    for _ in 0..MEASURED_SECONDS {
        let before = measured.total();
        for k in 0..60 {
            frame(&mut sim, Some(&mut measured));
            if k % 30 == 29 {
                measured.burning_stretch.sample(&sim, &mut shrunk);
            }
        }
        measured.worst = measured.worst.max((measured.total() - before) / 60.0);
    }
    let frames = f64::from(60 * MEASURED_SECONDS);
    for phase in &mut measured.phases {
        *phase /= frames;
    }
    let burnt = sim.particles.state.iter().filter(|s| s.is_burnt()).count();
    measured.burnt = burnt as f32 / sim.particles.len() as f32;
    assert!(sim.particles.is_finite());
    measured
}

fn median(mut runs: Vec<Run>) -> Run {
    runs.sort_by(|a, b| a.total().total_cmp(&b.total()));
    runs[runs.len() / 2]
}

/// XPBD's substeps per second from `--substep-rate` (the size table's runs), when given:
/// what more substeps cost, and buy in stretch.
fn substep_rate() -> Option<f32> {
    flag_value("--substep-rate")
}

/// The spacing the substep rate is meant for, m, from `--substep-rate-spacing MM` (the size
/// table's runs), when given: what a rate scaled by the spacing costs, and buys.
fn substep_rate_spacing() -> Option<f32> {
    flag_value("--substep-rate-spacing").map(|mm| mm / 1000.0)
}

/// The number after `flag` on the command line, if both are there.
fn flag_value(flag: &str) -> Option<f32> {
    let args: Vec<String> = std::env::args().collect();
    let at = args.iter().position(|a| a == flag)?;
    args.get(at + 1)?.parse().ok()
}

/// The cloth sizes of the size table: 32, 64, 128 and 256, or those after `--sizes` (for
/// profiling one, e.g. `--sizes 32`); with `--plume-only`, the plume grid's cells a side
/// (16 to 48 by default).
fn sizes(default: &[u32]) -> Vec<u32> {
    let args: Vec<String> = std::env::args().collect();
    let given: Vec<u32> = args
        .iter()
        .skip_while(|a| *a != "--sizes")
        .skip(1)
        .map_while(|a| a.parse().ok())
        .filter(|&n| n >= 2)
        .collect();
    if given.is_empty() {
        default.to_vec()
    } else {
        given
    }
}

fn size_table(pool: &TaskPool, integrators: &[Integrator], heat_model: HeatModel) {
    println!(
        "| cloth | particles | solver chosen | ran as | substeps | ms per frame | dearest second | ns per particle | heat | combustion | pieces | dynamics | culling | smoke | mesh | burnt at the end | max stretch hanging | burning: unheated max | burning: shrunk p90 |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    for size in sizes(&[32, 64, 128, 256]) {
        let particles = size * size;
        for &integrator in integrators {
            // Fewer runs for the slow one, so the table takes minutes, not hours.
            let slow = !integrator.is_unconditionally_stable();
            let repeats = if slow { 3 } else { 5 };
            let runs = (0..repeats).map(|_| run(size, integrator, heat_model, pool));
            let run = median(runs.collect());
            let total = run.total();
            let phases: Vec<String> = run.phases.iter().map(|p| format!("{p:.3}")).collect();
            let default = if integrator == Integrator::default() {
                " (default)"
            } else {
                ""
            };
            println!(
                "| {size} x {size} | {particles} | {}{default} | {} | {} | {total:.3} | {:.3} | {:.0} | {} | {:.0} % | {:.3} | {:.3} | {:.3} |",
                integrator.name(),
                run.integrator.name(),
                run.substeps,
                run.worst,
                total * 1e6 / f64::from(particles),
                phases.join(" | "),
                100.0 * run.burnt,
                run.stretch,
                run.burning_stretch.unheated,
                run.burning_stretch.shrunk_p90,
            );
        }
    }
    println!(
        "\nColumns heat to mesh: ms per frame. {}. \"ran as\": a force-based solver that \
         would need more than its 64-substep cap is stepped with XPBD. Burning: structural \
         springs sampled every 0.5 s of the measured window, the largest sample of each: the \
         largest ratio to rest length of the springs heat has not shrunk (by over 1 %), and the \
         90th percentile of those it has, against their shrunk length.",
        PHASES.join(", ")
    );
}

/// A cloth of the many-cloths scene: its grid, where it hangs, and the particles lit.
struct SceneCloth {
    columns: u32,
    rows: u32,
    at: Vec3,
    lit: Vec<usize>,
}

/// Wall time of the simulation step of all cloths in an app (the plugin's `ClothStepTiming`),
/// ms, median over `steps` steps after 2 s of burning.
fn app_step_ms(cloths: &[SceneCloth], steps: usize) -> f64 {
    use bevy::prelude::*;
    use bevy::time::TimeUpdateStrategy;
    use bevy_burning_cloth::prelude::*;
    let mut app = App::new();
    // The task pools `main` made are Bevy's global pools; `TaskPoolPlugin` keeps them.
    app.add_plugins((MinimalPlugins, BurningClothPlugins::default()))
        .insert_resource(TimeUpdateStrategy::ManualDuration(Duration::from_secs_f32(
            DT,
        )))
        .insert_resource(Time::<Fixed>::from_seconds(f64::from(DT)));
    let entities: Vec<Entity> = cloths
        .iter()
        .map(|cloth| {
            app.world_mut()
                .spawn((
                    ClothBuilder::grid(cloth.columns, cloth.rows, 0.75 / 32.0).pin_top_every(4),
                    BurnMaterial::COTTON,
                    Transform::from_translation(cloth.at),
                ))
                .id()
        })
        .collect();
    app.update();
    for (&entity, cloth) in entities.iter().zip(cloths) {
        for &index in &cloth.lit {
            app.world_mut().trigger(Ignite::particle(entity, index));
        }
    }
    for _ in 0..120 {
        app.update();
    }
    let mut times: Vec<f64> = (0..steps)
        .map(|_| {
            app.update();
            ms(app.world().resource::<ClothStepTiming>().last_step)
        })
        .collect();
    times.sort_by(f64::total_cmp);
    times[times.len() / 2]
}

/// Twenty 32 x 32 cloths, each lit near its bottom centre, against one 160 x 128 cloth (the
/// same 20 480 particles: the twenty tiled five across and four down) lit at the same twenty
/// places, so both scenes burn the same fronts.
fn many_cloths_table() {
    const TILE: u32 = 32;
    // Near the bottom centre of a tile: two rows above its last.
    let lit_in_tile = |columns: u32, tile_column: u32, tile_row: u32| {
        ((tile_row * TILE + TILE - 2) * columns + tile_column * TILE + TILE / 2) as usize
    };
    let twenty: Vec<SceneCloth> = (0..20)
        .map(|i| SceneCloth {
            columns: TILE,
            rows: TILE,
            at: Vec3::new((i % 5) as f32, 2.0 + (i / 5) as f32, 0.0),
            lit: vec![lit_in_tile(TILE, 0, 0)],
        })
        .collect();
    let (columns, rows) = (5 * TILE, 4 * TILE);
    let one = [SceneCloth {
        columns,
        rows,
        at: Vec3::new(0.0, 4.0, 0.0),
        lit: (0..20)
            .map(|i| lit_in_tile(columns, i % 5, i / 5))
            .collect(),
    }];
    println!("\n| scene (through the plugin) | particles | fires | ms per step (median of 240) |");
    println!("|---|---|---|---|");
    let many = app_step_ms(&twenty, 240);
    println!("| twenty 32 x 32 cloths | 20480 | 20 | {many:.3} |");
    let single = app_step_ms(&one, 240);
    println!("| one 160 x 128 cloth | 20480 | 20 | {single:.3} |");
    // The same cloth with one fire, near its bottom centre: what the front's work adds.
    let one_fire = [SceneCloth {
        lit: vec![((rows - 2) * columns + columns / 2) as usize],
        ..one[0]
    }];
    let quiet = app_step_ms(&one_fire, 240);
    println!("| one 160 x 128 cloth | 20480 | 1 | {quiet:.3} |");
}

/// Times the smoke pool on a burning cloth: (ms per step emitting, ms per step advancing,
/// mean live particles).
#[cfg(feature = "smoke")]
fn smoke_run(capacity: usize, rate_scale: f32) -> (f64, f64, f64) {
    use bevy_burning_cloth::smoke::{Air, BurningCloth, SmokeSettings, SmokeSim};
    let size = 64;
    let mut cloth = hanging(size, BurnMaterial::PAPER);
    let grid = cloth.topology.grid.unwrap();
    for (column, row) in [(8, 56), (24, 40), (32, 60), (40, 20), (56, 50)] {
        cloth.ignite(grid.index(column, row)).unwrap();
    }
    let mut settings = SmokeSettings::default().with_capacity(capacity);
    for kind in &mut settings.kind {
        kind.rate *= rate_scale;
    }
    let mut smoke = SmokeSim::new(settings).expect("valid smoke");
    let air = Air::default();
    for _ in 0..240 {
        cloth.step(DT);
        smoke.emit(&BurningCloth::of(&cloth), &air, DT);
        smoke.advance(&air, DT);
    }
    let steps = 120;
    let (mut emitting, mut advancing, mut live) = (0.0, 0.0, 0.0);
    for _ in 0..steps {
        cloth.step(DT);
        let started = Instant::now();
        smoke.emit(&BurningCloth::of(&cloth), &air, DT);
        let emitted = Instant::now();
        smoke.advance(&air, DT);
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

/// What [`plume_run`] measured, medians over the measured frames.
#[cfg(feature = "fluid")]
#[derive(Clone, Copy)]
struct PlumeRun {
    /// ms per frame feeding and stepping the air.
    step: f64,
    /// CG iterations per frame.
    iterations: f64,
    /// ms per frame the plume acting on the cloth.
    coupling: f64,
    /// Share of the cells advected.
    active: f64,
    /// ms per frame stepping the cloth in its plume.
    cloth: f64,
}

/// Times the plume over a burning cloth.
#[cfg(feature = "fluid")]
fn plume_run(resolution: usize, pool: &TaskPool) -> PlumeRun {
    use bevy_burning_cloth::fluid::{Plume, PlumeSettings, blow_and_heat, feed_plume};
    use bevy_burning_cloth::smoke::BurningCloth;
    let size = 64;
    let mut cloth = hanging(size, BurnMaterial::COTTON);
    let grid = cloth.topology.grid.unwrap();
    cloth.ignite(grid.index(size / 2, size - 1)).unwrap();
    // The same box whatever the resolution: 2.56 m a side.
    let settings = PlumeSettings {
        resolution: [resolution; 3],
        cell_size: 2.56 / resolution as f32,
        ..Default::default()
    };
    let mut plume = Plume::new(settings, Vec3::new(-1.28, 0.0, -1.28)).expect("valid plume");
    let material = *cloth.material();
    let mut frame = |timed: bool| {
        let started = Instant::now();
        blow_and_heat(&plume, &mut cloth.particles, &material, 20.0, true, DT);
        let coupled = started.elapsed();
        let started = Instant::now();
        cloth.step_on(DT, Some(pool));
        let cloth_step = started.elapsed();
        let started = Instant::now();
        feed_plume(
            &mut plume,
            &BurningCloth::of(&cloth),
            &material,
            &cloth.particles.mass,
            DT,
        );
        let report = plume.step_on(DT, Vec3::ZERO, Vec3::Y, Some(pool));
        let stepped = started.elapsed();
        let active = report.active_cells as f64 / resolution.pow(3) as f64;
        timed.then_some(PlumeRun {
            step: ms(stepped),
            iterations: f64::from(report.solve.iterations),
            coupling: ms(coupled),
            active,
            cloth: ms(cloth_step),
        })
    };
    for _ in 0..120 {
        frame(false);
    }
    let mut samples: Vec<PlumeRun> = (0..60).filter_map(|_| frame(true)).collect();
    let middle = samples.len() / 2;
    let mut pick = |key: fn(&PlumeRun) -> f64| {
        samples.sort_by(|a, b| key(a).total_cmp(&key(b)));
        key(&samples[middle])
    };
    PlumeRun {
        step: pick(|s| s.step),
        iterations: pick(|s| s.iterations),
        coupling: pick(|s| s.coupling),
        active: pick(|s| s.active),
        cloth: pick(|s| s.cloth),
    }
}

#[cfg(feature = "fluid")]
fn plume_table(pool: &TaskPool) {
    println!();
    println!(
        "| plume grid (2.56 m box) | cells | step ms per frame (median of 60) | CG iterations | cells advected | plume on the 64 x 64 cloth, ms | the cloth's own step, ms |"
    );
    println!("|---|---|---|---|---|---|---|");
    for resolution in sizes(&[16, 24, 32, 40, 48]).into_iter().map(|n| n as usize) {
        let run = plume_run(resolution, pool);
        println!(
            "| {resolution}³ | {} | {:.3} | {:.0} | {:.0} % | {:.3} | {:.3} |",
            resolution.pow(3),
            run.step,
            run.iterations,
            100.0 * run.active,
            run.coupling,
            run.cloth,
        );
    }
}

/// The plume's pull on cloths of each size (wind and heat on every particle,
/// `blow_and_heat_on`) in a 32³ plume over a fire, on one thread and split over the pool:
/// medians of 61 calls, ms.
#[cfg(feature = "fluid")]
fn pull_table(pool: &TaskPool) {
    use bevy_burning_cloth::fluid::{Plume, PlumeSettings, blow_and_heat_on};
    let settings = PlumeSettings {
        resolution: [32; 3],
        cell_size: 0.08,
        ..Default::default()
    };
    let mut plume = Plume::new(settings, Vec3::new(-1.28, 0.0, -1.28)).expect("valid plume");
    // A second of a small fire's heat: the air over it rises and spreads.
    for _ in 0..60 {
        plume.add_heat(Vec3::new(0.0, 0.5, 0.0), 2000.0);
        plume.step_on(DT, Vec3::ZERO, Vec3::Y, Some(pool));
    }
    println!();
    println!(
        "| cloth in a 32³ plume | particles | the plume's pull, ms, one thread | split over the pool |"
    );
    println!("|---|---|---|---|");
    for size in [64, 128, 256] {
        let cloth = hanging(size, BurnMaterial::COTTON);
        let material = *cloth.material();
        let median = |pool: Option<&TaskPool>| {
            let mut times: Vec<f64> = (0..61)
                .map(|_| {
                    let mut particles = cloth.particles.clone();
                    let started = Instant::now();
                    let report = blow_and_heat_on(
                        &plume,
                        &mut particles,
                        &material,
                        [material.initial_temperature, DT],
                        true,
                        pool,
                    );
                    let elapsed = ms(started.elapsed());
                    assert!(report.inside > 0, "the cloth hangs in the plume");
                    elapsed
                })
                .collect();
            times.sort_by(f64::total_cmp);
            times[times.len() / 2]
        };
        println!(
            "| {size} x {size} | {} | {:.3} | {:.3} |",
            size * size,
            median(None),
            median(Some(pool))
        );
    }
}

fn main() {
    // Bevy's default pools give compute one thread on a 2-core machine, and its schedule
    // runs systems on compute threads only: give compute every core, as a game that wants
    // both cores for its simulation would (`TaskPoolPlugin { task_pool_options }`).
    let mut pools = bevy::app::TaskPoolOptions::default();
    pools.compute.min_threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    pools.create_default_pools();
    let pool: &TaskPool = ComputeTaskPool::get();
    println!(
        "compute pool: {} thread(s); feature parallel: {}\n",
        pool.thread_num(),
        cfg!(feature = "parallel")
    );
    if std::env::args().any(|a| a == "--plume-only") {
        #[cfg(feature = "fluid")]
        {
            plume_table(pool);
            pull_table(pool);
        }
        return;
    }
    if std::env::args().any(|a| a == "--many-only") {
        many_cloths_table();
        return;
    }
    if std::env::args().any(|a| a == "--wake-only") {
        wake_table(pool);
        return;
    }
    if std::env::args().any(|a| a == "--smoke-only") {
        #[cfg(feature = "smoke")]
        smoke_table();
        return;
    }
    if std::env::args().any(|a| a == "--default-only") {
        size_table(pool, &[Integrator::default()], HeatModel::default());
        return;
    }
    if std::env::args().any(|a| a == "--physical-heat-only") {
        println!("Heat model: physical (the flame front of `sim::flame`).\n");
        size_table(pool, &[Integrator::default()], HeatModel::PHYSICAL);
        return;
    }
    size_table(
        pool,
        &[Integrator::default(), Integrator::SymplecticEuler],
        HeatModel::default(),
    );
    many_cloths_table();
    wake_table(pool);
    #[cfg(feature = "smoke")]
    smoke_table();
    #[cfg(feature = "fluid")]
    {
        plume_table(pool);
        pull_table(pool);
    }
}

/// What handing work to the compute pool costs, by how long the pool has been idle: one
/// task spawned in a scope while the calling thread works on for 60 µs (as a small cloth's
/// step would), 300 times. "spawn" is how long the spawn kept the caller; "task starts" how
/// long after the scope opened a pool thread began the task (up to the caller's 60 µs, when
/// the caller runs it itself); "scope" the whole scope. These decide how small a job is
/// worth sharing: a 32 x 32 cloth's whole frame is about 150 µs.
fn wake_table(pool: &TaskPool) {
    use std::sync::atomic::{AtomicU64, Ordering};
    println!(
        "Handing work to the compute pool ({} thread(s)), medians of 300:
",
        pool.thread_num()
    );
    println!(
        "| pool idle before | spawn, µs | task starts after, µs (10th–90th percentile) | scope, µs (caller works 60) |"
    );
    println!("|---|---|---|---|");
    let micros = |ns: u64| ns as f64 / 1e3;
    for idle in [0u64, 100, 1_000, 16_000] {
        let (mut spawn, mut start, mut whole) = (Vec::new(), Vec::new(), Vec::new());
        for _ in 0..300 {
            std::thread::sleep(Duration::from_micros(idle));
            let opened = Instant::now();
            let (started, spawned) = (AtomicU64::new(0), AtomicU64::new(0));
            pool.scope(|scope| {
                scope.spawn(async {
                    started.store(opened.elapsed().as_nanos() as u64, Ordering::Release);
                });
                spawned.store(opened.elapsed().as_nanos() as u64, Ordering::Release);
                let until = Instant::now() + Duration::from_micros(60);
                while Instant::now() < until {
                    std::hint::spin_loop();
                }
            });
            whole.push(opened.elapsed().as_nanos() as u64);
            spawn.push(spawned.load(Ordering::Acquire));
            start.push(started.load(Ordering::Acquire));
        }
        for list in [&mut spawn, &mut start, &mut whole] {
            list.sort_unstable();
        }
        let idle = match idle {
            0 => "none".to_string(),
            1..1_000 => format!("{idle} µs"),
            _ => format!("{} ms", idle / 1_000),
        };
        println!(
            "| {idle} | {:.1} | {:.1} ({:.1}–{:.1}) | {:.1} |",
            micros(spawn[150]),
            micros(start[150]),
            micros(start[30]),
            micros(start[270]),
            micros(whole[150]),
        );
    }
    println!();
}
