//! Flames, smoke and embers against what they must do: appear only on the burning front,
//! rise, stay within their pool, repeat with a seed, and allocate nothing once running.
#![cfg(feature = "smoke")]

use bevy::math::{Affine3A, Vec3};
use bevy_burning_cloth::sim::{BurnMaterial, BurnState, ClothBuilder, ClothSim};
use bevy_burning_cloth::smoke::{
    Air, BurningCloth, KindSettings, SmokeKind, SmokeSettings, SmokeSim,
};

const DT: f32 = 1.0 / 60.0;

fn hanging(columns: u32, rows: u32, material: BurnMaterial) -> ClothSim {
    ClothSim::new(
        &ClothBuilder::grid(columns, rows, 0.03).pin_top_corners(),
        material,
        Affine3A::from_translation(Vec3::new(0.0, 2.0, 0.0)),
    )
    .unwrap()
}

/// Five particles 1 m apart: one intact, two burning, one burnt, one burning hot.
fn row_of_particles() -> (Vec<Vec3>, Vec<f32>, Vec<BurnState>) {
    let material = BurnMaterial::CLOTH;
    let position = (0..5).map(|i| Vec3::new(i as f32, 0.0, 0.0)).collect();
    let temperature = vec![
        20.0,
        material.ignition_temperature + 10.0,
        material.ignition_temperature + 50.0,
        material.burnt_temperature + 10.0,
        material.burnt_temperature - 1.0,
    ];
    let state = vec![
        BurnState::Intact,
        BurnState::Ignited,
        BurnState::Ignited,
        BurnState::Burnt,
        BurnState::Ignited,
    ];
    (position, temperature, state)
}

fn row_cloth<'a>(
    position: &'a [Vec3],
    temperature: &'a [f32],
    state: &'a [BurnState],
) -> BurningCloth<'a> {
    let material = BurnMaterial::CLOTH;
    BurningCloth {
        position,
        temperature,
        state,
        newly_burnt: &[],
        ignition_temperature: material.ignition_temperature,
        burnt_temperature: material.burnt_temperature,
        area_per_particle: 0.1,
    }
}

#[test]
fn flames_and_smoke_are_born_only_at_ignited_unburnt_particles() {
    let (position, temperature, state) = row_of_particles();
    let cloth = row_cloth(&position, &temperature, &state);
    let settings = SmokeSettings::default();
    let mut sim = SmokeSim::new(settings).unwrap();
    let mut born = 0;
    for _ in 0..120 {
        let counts = sim.emit(&cloth, &Air::default(), DT);
        born += counts.born.iter().sum::<u32>();
    }
    assert!(born > 20, "only {born} particles born");
    assert_eq!(sim.pool.live(), born as usize);
    let mut per_source = [0usize; 5];
    for slot in sim.pool.live_slots() {
        let (source, distance) = position
            .iter()
            .enumerate()
            .map(|(i, p)| (i, p.distance(sim.pool.position[slot])))
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .unwrap();
        assert!(
            distance <= settings.birth_radius + 1e-6,
            "particle {distance} m from the nearest cloth particle"
        );
        per_source[source] += 1;
    }
    assert_eq!(per_source[0], 0, "intact particle smoked");
    assert_eq!(per_source[3], 0, "burnt particle smoked");
    assert!(per_source[1] > 0 && per_source[2] > 0 && per_source[4] > 0);
    // Hotter burns harder: the particle near its burnt temperature emits the most.
    assert!(per_source[4] > per_source[1], "{per_source:?}");
}

#[test]
fn embers_come_from_particles_that_just_burnt() {
    let (position, temperature, state) = row_of_particles();
    let mut cloth = row_cloth(&position, &temperature, &state);
    let newly_burnt = [3u32];
    cloth.newly_burnt = &newly_burnt;
    // 15 embers per square metre, and the particle stands for 0.1 m².
    let settings = SmokeSettings::default()
        .with_kind(SmokeKind::Flame, KindSettings::NONE)
        .with_kind(SmokeKind::Smoke, KindSettings::NONE)
        .with_kind(
            SmokeKind::Ember,
            KindSettings {
                rate: 15.0,
                ..KindSettings::EMBER
            },
        );
    let mut sim = SmokeSim::new(settings).unwrap();
    let mut embers = 0;
    for _ in 0..100 {
        embers += sim.emit(&cloth, &Air::default(), DT).born[SmokeKind::Ember as usize];
    }
    // 1.5 per burnt particle on average: 100 draws give 150 ± a few tens.
    assert!((100..=200).contains(&embers), "{embers} embers");
    for slot in sim.pool.live_slots() {
        assert_eq!(sim.pool.kind[slot], SmokeKind::Ember);
        assert!(sim.pool.position[slot].distance(position[3]) <= settings.birth_radius + 1e-6);
    }
}

/// The same area burnt away throws the same embers at any spacing: 0.36 m² burnt as 400
/// particles 30 mm apart or as 1 600 particles 15 mm apart gives the default's 1 200 a square
/// metre, 432 embers, both ways (each particle's draw is its whole part plus one with the
/// chance of its fraction, so the counts differ from 432 by a few tens at most).
#[test]
fn embers_follow_the_area_burnt_not_the_particles() {
    let settings = SmokeSettings::default()
        .with_kind(SmokeKind::Flame, KindSettings::NONE)
        .with_kind(SmokeKind::Smoke, KindSettings::NONE)
        .with_capacity(4096);
    for (spacing, particles) in [(0.03f32, 400usize), (0.015, 1600)] {
        let position = vec![Vec3::ZERO; particles];
        let material = BurnMaterial::COTTON;
        let temperature = vec![material.burnt_temperature + 1.0; particles];
        let state = vec![BurnState::Burnt; particles];
        let newly_burnt: Vec<u32> = (0..particles as u32).collect();
        let cloth = BurningCloth {
            position: &position,
            temperature: &temperature,
            state: &state,
            newly_burnt: &newly_burnt,
            ignition_temperature: material.ignition_temperature,
            burnt_temperature: material.burnt_temperature,
            area_per_particle: spacing * spacing,
        };
        let mut sim = SmokeSim::new(settings).unwrap();
        let embers = sim.emit(&cloth, &Air::default(), DT).born[SmokeKind::Ember as usize];
        let expected = KindSettings::EMBER.rate * 0.36;
        assert!(
            (embers as f32 - expected).abs() < 0.1 * expected,
            "{embers} embers at {spacing} m spacing, {expected} expected"
        );
    }
}

#[test]
fn a_burnt_out_cloth_emits_nothing_and_its_particles_finish() {
    let mut cloth = hanging(10, 10, BurnMaterial::PAPER);
    cloth.ignite(55).unwrap();
    let mut sim = SmokeSim::new(SmokeSettings::default()).unwrap();
    let mut steps = 0;
    while cloth.particles.count(BurnState::Ignited) > 0 || steps == 0 {
        cloth.step(DT);
        sim.emit(&BurningCloth::of(&cloth), &Air::default(), DT);
        sim.advance(&Air::default(), DT);
        steps += 1;
        assert!(steps < 20_000, "the cloth never burnt out");
    }
    assert!(sim.pool.live() > 0, "a burning cloth made no smoke");
    // Nothing on fire: no births, and every particle dies within the longest lifetime.
    let longest = SmokeSettings::default()
        .kind
        .iter()
        .map(|k| k.lifetime[1])
        .fold(0.0, f32::max);
    for _ in 0..((longest / DT) as usize + 2) {
        cloth.step(DT);
        let counts = sim.emit(&BurningCloth::of(&cloth), &Air::default(), DT);
        assert_eq!(counts.born, [0, 0, 0]);
        sim.advance(&Air::default(), DT);
    }
    assert_eq!(sim.pool.live(), 0);
}

#[test]
fn buoyant_smoke_rises_and_cools() {
    let (position, temperature, state) = row_of_particles();
    let cloth = row_cloth(&position, &temperature, &state);
    let settings = SmokeSettings::default()
        .with_kind(SmokeKind::Flame, KindSettings::NONE)
        .with_kind(SmokeKind::Ember, KindSettings::NONE);
    let mut sim = SmokeSim::new(settings).unwrap();
    for _ in 0..20 {
        sim.emit(&cloth, &Air::default(), DT);
    }
    assert!(
        sim.pool.live() > 5,
        "{} smoke particles born",
        sim.pool.live()
    );
    let mean = |sim: &SmokeSim| {
        let slots: Vec<usize> = sim.pool.live_slots().collect();
        let y = slots.iter().map(|&s| sim.pool.position[s].y).sum::<f32>() / slots.len() as f32;
        let t = slots.iter().map(|&s| sim.pool.temperature[s]).sum::<f32>() / slots.len() as f32;
        (y, t)
    };
    let (y0, t0) = mean(&sim);
    for _ in 0..60 {
        sim.advance(&Air::default(), DT);
    }
    let (y1, t1) = mean(&sim);
    assert!(y1 > y0 + 0.3, "smoke rose from {y0} to {y1} m in 1 s");
    assert!(t1 < t0, "smoke did not cool: {t0} -> {t1}");
}

/// With no turbulence and no cooling, a particle's velocity relaxes to the terminal velocity
/// v∞ = a / drag as v∞ + (v0 − v∞)·e^(−drag·t); the implicit update converges to it.
#[test]
fn drag_and_buoyancy_match_the_exponential_approach() {
    let mut kind = KindSettings::SMOKE;
    kind.turbulence = 0.0;
    kind.cooling = 0.0;
    kind.lifetime = [100.0, 100.0];
    kind.spread_speed = 0.0;
    kind.rise_speed = 0.0;
    let mut settings = SmokeSettings::default()
        .with_kind(SmokeKind::Flame, KindSettings::NONE)
        .with_kind(SmokeKind::Ember, KindSettings::NONE)
        .with_kind(SmokeKind::Smoke, kind);
    settings.birth_radius = 0.0;
    let temperature = [1020.0f32];
    let position = [Vec3::ZERO];
    let state = [BurnState::Ignited];
    let cloth = BurningCloth {
        position: &position,
        temperature: &temperature,
        state: &state,
        newly_burnt: &[],
        ignition_temperature: 500.0,
        burnt_temperature: 1000.0,
        area_per_particle: 1.0,
    };
    let mut sim = SmokeSim::new(settings).unwrap();
    while sim.pool.live() == 0 {
        sim.emit(&cloth, &Air::default(), 1e-3);
    }
    let slot = sim.pool.live_slots().next().unwrap();
    let acceleration = kind.buoyancy * (1020.0 - 20.0) * 1e-3;
    let terminal = acceleration / kind.drag;
    let h = 1e-4;
    let t = 1.0;
    for _ in 0..(t / h) as usize {
        sim.advance(&Air::default(), h);
    }
    let exact = terminal * (1.0 - (-kind.drag * t).exp());
    let speed = sim.pool.velocity[slot].y;
    assert!(
        (speed - exact).abs() < 2e-3 * terminal,
        "v = {speed}, exact {exact}"
    );
}

#[test]
fn the_pool_never_exceeds_its_capacity_and_never_allocates() {
    let mut cloth = hanging(24, 24, BurnMaterial::SILK);
    for i in [100, 300, 500] {
        cloth.ignite(i).unwrap();
    }
    let mut sim = SmokeSim::new(SmokeSettings::default().with_capacity(300)).unwrap();
    let bytes = sim.pool.heap_bytes();
    let mut most = 0;
    for _ in 0..1_500 {
        cloth.step(DT);
        sim.emit(&BurningCloth::of(&cloth), &Air::default(), DT);
        sim.advance(&Air::default(), DT);
        most = most.max(sim.pool.live());
        assert!(sim.pool.live() <= sim.pool.capacity());
        assert_eq!(sim.pool.heap_bytes(), bytes, "the pool reallocated");
    }
    assert_eq!(most, 300, "the burn never filled the small pool");
    assert!(sim.pool.replaced() > 0);
}

#[test]
fn the_same_seed_gives_the_same_particles() {
    let run = |seed: u64| {
        let mut cloth = hanging(12, 12, BurnMaterial::COTTON);
        cloth.ignite(70).unwrap();
        let mut sim = SmokeSim::new(SmokeSettings::default().with_seed(seed)).unwrap();
        for _ in 0..200 {
            cloth.step(DT);
            sim.emit(&BurningCloth::of(&cloth), &Air::default(), DT);
            sim.advance(&Air::default(), DT);
        }
        sim.pool
            .live_slots()
            .map(|s| sim.pool.position[s].to_array().map(f32::to_bits))
            .collect::<Vec<_>>()
    };
    let a = run(7);
    assert!(!a.is_empty());
    assert_eq!(a, run(7));
    assert_ne!(a, run(8));
}

#[test]
fn bad_input_is_refused_or_ignored() {
    assert!(SmokeSim::new(SmokeSettings::default().with_capacity(0)).is_err());
    let mut sim = SmokeSim::new(SmokeSettings::default()).unwrap();
    let position = [Vec3::NAN, Vec3::ZERO];
    let temperature = [900.0, f32::NAN];
    let state = [BurnState::Ignited, BurnState::Ignited];
    let cloth = BurningCloth {
        position: &position,
        temperature: &temperature,
        state: &state,
        newly_burnt: &[7, 1],
        ignition_temperature: 300.0,
        burnt_temperature: 800.0,
        area_per_particle: f32::INFINITY,
    };
    sim.emit(&cloth, &Air::default(), DT);
    sim.emit(&cloth, &Air::default(), f32::NAN);
    let air = Air {
        wind: Vec3::new(1e30, 0.0, 0.0),
        ..Air::default()
    };
    for _ in 0..10 {
        sim.advance(&air, DT);
    }
    for slot in sim.pool.live_slots() {
        assert!(sim.pool.position[slot].is_finite());
    }
    let mut settings = SmokeSettings::default();
    settings.of_mut(SmokeKind::Smoke).drag = -1.0;
    assert!(sim.set_settings(settings).is_err());
    assert_eq!(sim.settings(), &SmokeSettings::default());
}

/// Through the ECS: every built cloth gets an emitter that smokes while it burns; a cloth
/// whose emitter is removed makes none, and the smoke systems then have nothing to do.
#[test]
fn the_plugin_gives_every_cloth_an_emitter_and_smokes_only_while_burning() {
    use bevy::prelude::*;
    use bevy::time::TimeUpdateStrategy;
    use bevy_burning_cloth::prelude::*;
    use std::time::Duration;

    let mut app = App::new();
    app.add_plugins((MinimalPlugins, BurningClothPlugins::default()))
        .insert_resource(TimeUpdateStrategy::ManualDuration(Duration::from_micros(
            15_625,
        )));
    let spawn = |app: &mut App, x: f32| {
        app.world_mut()
            .spawn((
                ClothBuilder::grid(12, 12, 0.03).pin_top_corners(),
                BurnMaterial::PAPER,
                Transform::from_xyz(x, 2.0, 0.0),
            ))
            .id()
    };
    let smoking = spawn(&mut app, 0.0);
    let silent = spawn(&mut app, 3.0);
    app.update();
    assert!(app.world().get::<SmokeEmitter>(smoking).is_some());
    app.world_mut().entity_mut(silent).remove::<SmokeEmitter>();
    for cloth in [smoking, silent] {
        app.world_mut().trigger(Ignite::particle(cloth, 66));
    }
    for _ in 0..120 {
        app.update();
    }
    let pool = app.world().get::<SmokeEmitter>(smoking).unwrap().pool();
    assert!(pool.live() > 0, "a burning cloth made no smoke");
    assert!(app.world().get::<SmokeEmitter>(silent).is_none());
    let status = app.world().get::<ClothStatus>(silent).unwrap();
    assert!(
        status.ignited + status.burnt > 0,
        "the cloth without an emitter did not burn"
    );
}
