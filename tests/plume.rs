//! The plume with cloths in it: a burning cloth drives an updraft, the updraft lights a
//! cloth hung above the fire (and not one beside it) and lifts a light cloth; through the
//! plugin the smoke rides it. Each frame runs as the plugin runs it: the plume acts on the
//! cloths, the cloths step, the burning ones feed the plume, the plume steps.
#![cfg(feature = "fluid")]

use bevy::math::{Affine3A, Vec3};
use bevy_burning_cloth::fluid::{Plume, PlumeSettings, blow_and_heat, feed_plume};
use bevy_burning_cloth::sim::{BurnMaterial, ClothBuilder, ClothSim, GridPlane};
use bevy_burning_cloth::smoke::BurningCloth;

const DT: f32 = 1.0 / 60.0;

/// A 0.6 m square cotton cloth hanging from its top edge, centred on `top` across,
/// its bottom row lit.
fn burning_curtain(top: Vec3) -> ClothSim {
    let mut sim = ClothSim::new(
        &ClothBuilder::grid(21, 21, 0.03).pin_top_every(2),
        BurnMaterial::COTTON,
        Affine3A::from_translation(top),
    )
    .unwrap();
    let grid = sim.topology.grid.unwrap();
    for column in 0..21 {
        sim.ignite(grid.index(column, 20)).unwrap();
    }
    sim
}

/// A horizontal 0.3 m square of `material`, pinned at its four corners, centred at `centre`.
fn canopy(centre: Vec3, material: BurnMaterial) -> ClothSim {
    ClothSim::new(
        &ClothBuilder::grid(11, 11, 0.03)
            .in_plane(GridPlane::Horizontal)
            .pin(0, 0)
            .pin(10, 0)
            .pin(0, 10)
            .pin(10, 10),
        material,
        Affine3A::from_translation(centre),
    )
    .unwrap()
}

fn plume_around(centre: Vec3) -> Plume {
    let settings = PlumeSettings::default();
    let size = settings.resolution[0] as f32 * settings.cell_size;
    Plume::new(settings, centre - Vec3::new(0.5, 0.25, 0.5) * size).unwrap()
}

/// One frame; `coupled[i]` says whether the plume acts on cloth `i`.
fn frame(plume: &mut Plume, cloths: &mut [ClothSim], coupled: &[bool]) {
    for (cloth, coupled) in cloths.iter_mut().zip(coupled) {
        if *coupled {
            let material = *cloth.material();
            blow_and_heat(plume, &mut cloth.particles, &material, 20.0, true, DT);
        }
    }
    for cloth in cloths.iter_mut() {
        cloth.step(DT);
        let material = *cloth.material();
        feed_plume(
            plume,
            &BurningCloth::of(cloth),
            &material,
            &cloth.particles.mass,
            DT,
        );
    }
    plume.step(DT, Vec3::ZERO, Vec3::Y);
}

fn centre_of(sim: &ClothSim) -> Vec3 {
    sim.particles.position.iter().sum::<Vec3>() / sim.particles.len() as f32
}

#[test]
fn the_air_above_a_burning_cloth_rises_hot() {
    let mut cloths = [burning_curtain(Vec3::new(0.0, 1.0, 0.0))];
    let mut plume = plume_around(Vec3::new(0.0, 0.6, 0.0));
    for _ in 0..150 {
        frame(&mut plume, &mut cloths, &[true]);
    }
    let above = Vec3::new(0.0, 1.2, 0.0);
    let velocity = plume.velocity_at(above);
    let excess = plume.temperature_at(above);
    assert!(
        velocity.y > 0.3,
        "air 0.2 m above the cloth moves at {velocity} m/s"
    );
    assert!(
        excess > 20.0,
        "air 0.2 m above the cloth is {excess} K above ambient"
    );
    // The air beside it, 1 m off, is barely warm.
    let beside = plume.temperature_at(Vec3::new(1.0, 1.2, 0.0));
    assert!(beside < 0.1 * excess, "1 m to the side: {beside} K");
    assert!(plume.report().max_divergence <= plume.settings().tolerance);
}

#[test]
fn a_cloth_hung_above_the_fire_catches_from_the_plume_and_one_beside_it_does_not() {
    let mut cloths = [
        burning_curtain(Vec3::new(0.0, 1.0, 0.0)),
        canopy(Vec3::new(0.0, 1.25, 0.0), BurnMaterial::PAPER),
        canopy(Vec3::new(0.8, 1.25, 0.0), BurnMaterial::PAPER),
    ];
    let mut plume = plume_around(Vec3::new(0.0, 0.6, 0.0));
    let mut caught = None;
    for frame_index in 0..900 {
        frame(&mut plume, &mut cloths, &[true, true, true]);
        if caught.is_none() && cloths[1].particles.state.iter().any(|s| s.is_ignited()) {
            caught = Some(frame_index as f32 * DT);
        }
    }
    let caught = caught.expect("the cloth above the fire never caught");
    assert!(
        caught > 0.5,
        "caught at {caught} s: too soon for heating by hot air"
    );
    assert!(
        cloths[2]
            .particles
            .state
            .iter()
            .all(|s| !s.is_ignited() && !s.is_burnt()),
        "the cloth 0.8 m to the side caught fire"
    );
    let side = cloths[2]
        .particles
        .temperature
        .iter()
        .fold(f32::MIN, |m, t| m.max(*t));
    assert!(side < 100.0, "the cloth beside the fire reached {side} °C");
    // Without the plume acting on it, the cloth above does not catch in the same time.
    let mut uncoupled = [
        burning_curtain(Vec3::new(0.0, 1.0, 0.0)),
        canopy(Vec3::new(0.0, 1.25, 0.0), BurnMaterial::PAPER),
    ];
    let mut plume = plume_around(Vec3::new(0.0, 0.6, 0.0));
    for _ in 0..900 {
        frame(&mut plume, &mut uncoupled, &[true, false]);
    }
    assert!(uncoupled[1].particles.state.iter().all(|s| !s.is_ignited()));
}

#[test]
fn the_updraft_lifts_a_light_cloth_above_the_fire() {
    let run = |coupled: bool| {
        let mut cloths = [
            burning_curtain(Vec3::new(0.0, 1.0, 0.0)),
            canopy(Vec3::new(0.0, 1.5, 0.0), BurnMaterial::SILK),
        ];
        let mut plume = plume_around(Vec3::new(0.0, 0.6, 0.0));
        let start = centre_of(&cloths[1]);
        let mut highest = f32::MIN;
        for index in 0..150 {
            frame(&mut plume, &mut cloths, &[true, coupled]);
            if index >= 60 {
                highest = highest.max(centre_of(&cloths[1]).y - start.y);
            }
        }
        (centre_of(&cloths[1]).y - start.y, highest)
    };
    let (still, _) = run(false);
    let (blown, highest) = run(true);
    assert!(
        blown > still + 0.01 && highest > still + 0.01,
        "silk canopy sag: {still} m with no updraft, {blown} m in it (highest {highest})"
    );
}

#[test]
fn the_same_burn_gives_the_same_air_and_cloth_bit_for_bit() {
    let run = || {
        let mut cloths = [
            burning_curtain(Vec3::new(0.0, 1.0, 0.0)),
            canopy(Vec3::new(0.0, 1.25, 0.0), BurnMaterial::PAPER),
        ];
        let mut plume = plume_around(Vec3::new(0.0, 0.6, 0.0));
        for _ in 0..60 {
            frame(&mut plume, &mut cloths, &[true, true]);
        }
        (
            plume.temperature().to_vec(),
            cloths[1].particles.position.clone(),
        )
    };
    assert!(run() == run());
}

/// Through the plugin: the plume is built when the fire starts, its smoke particles ride it
/// (they rise faster than in still air), its diagnostics are recorded, and it goes to sleep
/// once the fire is out.
#[test]
fn through_the_plugin_the_plume_carries_the_smoke_and_sleeps_after_the_fire() {
    use bevy::diagnostic::DiagnosticsStore;
    use bevy::prelude::*;
    use bevy::time::TimeUpdateStrategy;
    use bevy_burning_cloth::fluid::{FirePlume, PlumeDiagnostics};
    use bevy_burning_cloth::prelude::*;
    use std::time::Duration;

    let mut app = App::new();
    app.add_plugins((MinimalPlugins, BurningClothPlugins::default()))
        .insert_resource(TimeUpdateStrategy::ManualDuration(Duration::from_micros(
            15_625,
        )));
    let cloth = app
        .world_mut()
        .spawn((
            ClothBuilder::grid(16, 16, 0.03).pin_top_corners(),
            BurnMaterial::PAPER,
            Transform::from_xyz(0.0, 1.0, 0.0),
        ))
        .id();
    app.update();
    assert!(
        app.world().resource::<FirePlume>().plume().is_none(),
        "no fire, no plume"
    );
    app.world_mut()
        .trigger(Ignite::at_world_point(cloth, Vec3::new(0.0, 0.6, 0.0)));
    let mut fastest_smoke = 0.0f32;
    for _ in 0..64 * 3 {
        app.update();
        if let Some(emitter) = app.world().get::<SmokeEmitter>(cloth) {
            let pool = emitter.pool();
            for slot in pool.live_slots() {
                if pool.kind[slot] == SmokeKind::Smoke {
                    fastest_smoke = fastest_smoke.max(pool.velocity[slot].y);
                }
            }
        }
    }
    let fire = app.world().resource::<FirePlume>();
    let plume = fire
        .plume()
        .expect("the plume is built once the cloth burns");
    assert!(plume.report().max_speed > 0.5, "{:?}", plume.report());
    // Still air would carry smoke up at its rise speed at most; the plume carries it faster.
    let still_air = SmokeSettings::default().of(SmokeKind::Smoke).rise_speed;
    assert!(
        fastest_smoke > still_air + 0.3,
        "smoke rose at most {fastest_smoke} m/s (still air: {still_air})"
    );
    let store = app.world().resource::<DiagnosticsStore>();
    let step = store.get(&PlumeDiagnostics::STEP).and_then(|d| d.value());
    assert!(
        step.is_some_and(|ms| ms > 0.0),
        "plume step diagnostic: {step:?}"
    );
    // Once the cloth has burnt out the air settles and the plume stops working.
    for _ in 0..64 * 60 {
        app.update();
        if app.world().resource::<FirePlume>().active().is_none() {
            return;
        }
    }
    let fire = app.world().resource::<FirePlume>();
    panic!(
        "the plume never settled after the fire: {:?}, max smoke {}",
        fire.report(),
        fire.plume()
            .unwrap()
            .smoke()
            .iter()
            .fold(0.0f32, |m, s| m.max(*s))
    );
}

#[test]
fn retuning_keeps_the_air_moving_and_a_new_grid_is_refused() {
    let mut plume = plume_around(Vec3::ZERO);
    plume.add_heat(Vec3::new(0.0, 0.5, 0.0), 2.0e4);
    for _ in 0..30 {
        plume.step(DT, Vec3::ZERO, Vec3::Y);
    }
    let rising = plume.velocity_at(Vec3::new(0.0, 0.9, 0.0)).y;
    assert!(rising > 0.05, "the hot air rises: {rising} m/s");
    let (velocity, temperature) = (plume.velocity().clone(), plume.temperature().to_vec());
    let mut untouched = plume.clone();
    let calmer = PlumeSettings {
        buoyancy: 0.0,
        vorticity: 0.0,
        ..*plume.settings()
    };
    plume.retune(calmer).unwrap();
    assert_eq!(plume.settings().buoyancy, 0.0);
    assert_eq!(plume.velocity(), &velocity, "the air is kept");
    assert_eq!(plume.temperature(), temperature.as_slice());
    let finer = PlumeSettings {
        resolution: [40; 3],
        ..*plume.settings()
    };
    assert!(plume.retune(finer).is_err(), "a new grid needs a new plume");
    assert_eq!(plume.settings(), &calmer);
    let invalid = PlumeSettings {
        cooling: f32::NAN,
        ..calmer
    };
    assert!(plume.retune(invalid).is_err());
    // The new rates act at once: without buoyancy the hot air rises slower than it would.
    for sim in [&mut plume, &mut untouched] {
        for _ in 0..10 {
            sim.step(DT, Vec3::ZERO, Vec3::Y);
        }
    }
    let point = Vec3::new(0.0, 0.9, 0.0);
    let (calm, driven) = (plume.velocity_at(point).y, untouched.velocity_at(point).y);
    assert!(
        calm < driven - 0.01,
        "{calm} m/s without buoyancy, {driven} with"
    );
}
