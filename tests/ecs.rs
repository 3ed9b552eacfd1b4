//! The plugin through Bevy's ECS: `MinimalPlugins` + `BurningClothPlugins`, no renderer.

use bevy::prelude::*;
use bevy::time::TimeUpdateStrategy;
use bevy_burning_cloth::prelude::*;
use std::time::Duration;

mod common;

/// 64 Hz: Bevy's default fixed step, exact in nanoseconds, so each update runs one step.
const STEP: Duration = Duration::from_micros(15_625);

#[derive(Resource, Default)]
struct Seen {
    ignited: Vec<Entity>,
    burnt_out: Vec<(Entity, f32)>,
}

fn app() -> App {
    let mut app = App::new();
    app.add_plugins((MinimalPlugins, BurningClothPlugins::default()))
        .insert_resource(TimeUpdateStrategy::ManualDuration(STEP))
        .init_resource::<Seen>()
        .add_observer(|event: On<ClothIgnited>, mut seen: ResMut<Seen>| {
            seen.ignited.push(event.entity);
        })
        .add_observer(|event: On<ClothBurntOut>, mut seen: ResMut<Seen>| {
            seen.burnt_out.push((event.entity, event.burnt_fraction));
        });
    app
}

fn spawn_silk(app: &mut App) -> Entity {
    app.world_mut()
        .spawn((
            ClothBuilder::grid(16, 16, 0.03).pin_top_corners(),
            BurnMaterial::SILK,
            Transform::from_xyz(0.0, 2.0, 0.0),
        ))
        .id()
}

#[test]
fn a_cloth_burns_away_through_the_ecs() {
    let mut app = app();
    let cloth = spawn_silk(&mut app);
    // Ignite before the cloth is built: the request waits for it.
    app.world_mut()
        .trigger(Ignite::at_world_point(cloth, Vec3::new(0.2, 1.6, 0.0)));
    app.update();
    let particles = app
        .world()
        .get::<ClothParticles>(cloth)
        .expect("cloth built");
    assert_eq!(particles.len(), 256);
    // The transform placed it: the top row hangs at y = 2.
    assert!((particles.position[0].y - 2.0).abs() < 1e-5);

    for _ in 0..64 * 90 {
        app.update();
        if !app.world().resource::<Seen>().burnt_out.is_empty() {
            break;
        }
    }
    let seen = app.world().resource::<Seen>();
    assert_eq!(seen.ignited, vec![cloth]);
    assert_eq!(seen.burnt_out.len(), 1, "the fire went out once");
    let (entity, fraction) = seen.burnt_out[0];
    assert_eq!(entity, cloth);
    assert_eq!(fraction, 1.0, "the whole cloth burnt");
    let status = app.world().get::<ClothStatus>(cloth).unwrap();
    assert_eq!(status.pins_left, 0);
    assert_eq!(status.live_triangles, 0);
    assert!(
        app.world()
            .get::<ClothParticles>(cloth)
            .unwrap()
            .is_finite()
    );
}

#[test]
fn a_cloth_hangs_still_without_fire_and_its_pins_follow_the_entity() {
    let mut app = app();
    let cloth = spawn_silk(&mut app);
    for _ in 0..64 * 3 {
        app.update();
    }
    let status = *app.world().get::<ClothStatus>(cloth).unwrap();
    assert_eq!(status.burnt, 0);
    assert!(!status.burning);
    assert!(status.substeps >= 1);
    // Move the cloth: its pins go with it.
    app.world_mut()
        .get_mut::<Transform>(cloth)
        .unwrap()
        .translation
        .x += 1.0;
    for _ in 0..3 {
        app.update();
    }
    let particles = app.world().get::<ClothParticles>(cloth).unwrap();
    assert!((particles.position[0].x - (1.0 - 0.225)).abs() < 1e-4);
    assert!(particles.is_finite());
}

#[test]
fn bad_requests_are_ignored_without_panicking() {
    let mut app = app();
    let cloth = spawn_silk(&mut app);
    let broken = app
        .world_mut()
        .spawn((ClothBuilder::grid(0, 10, f32::NAN), Transform::default()))
        .id();
    let negative = app
        .world_mut()
        .spawn((
            ClothBuilder::grid(4, 4, 0.1).with_total_mass(-1.0),
            Transform::default(),
        ))
        .id();
    app.update();
    assert!(app.world().get::<ClothParticles>(broken).is_none());
    assert!(app.world().get::<ClothParticles>(negative).is_none());

    let ghost = app.world_mut().spawn_empty().id();
    app.world_mut().despawn(ghost);
    app.world_mut().trigger(Ignite::particle(ghost, 0));
    app.world_mut().trigger(Ignite::particle(cloth, 10_000));
    app.world_mut()
        .trigger(Ignite::at_world_point(cloth, Vec3::NAN));
    app.world_mut()
        .trigger(Ignite::particle(cloth, 3).with_temperature(f32::INFINITY));
    app.world_mut()
        .trigger(Ignite::particle(cloth, 3).with_temperature(-500.0));
    // An invalid material change mid-run is refused; the old one stays in use.
    app.world_mut()
        .get_mut::<BurnMaterial>(cloth)
        .unwrap()
        .structural_stiffness = f32::NAN;
    app.world_mut().resource_mut::<ClothEnvironment>().gravity = Vec3::INFINITY;
    for _ in 0..64 {
        app.update();
    }
    let particles = app.world().get::<ClothParticles>(cloth).unwrap();
    assert!(particles.is_finite());
    assert_eq!(particles.count(BurnState::Ignited), 0, "nothing was lit");
    let status = app.world().get::<ClothStatus>(cloth).unwrap();
    assert!(!status.burning);
}

#[derive(Resource, Default)]
struct SimulateRuns(u32);

#[test]
fn systems_do_no_work_until_a_cloth_exists() {
    let mut app = app();
    app.init_resource::<SimulateRuns>().add_systems(
        FixedUpdate,
        (|mut runs: ResMut<SimulateRuns>| runs.0 += 1).in_set(BurningClothSystems::Simulate),
    );
    for _ in 0..10 {
        app.update();
    }
    assert_eq!(app.world().resource::<SimulateRuns>().0, 0);
    assert_eq!(app.world().resource::<ClothStepTiming>().steps, 0);
    spawn_silk(&mut app);
    for _ in 0..10 {
        app.update();
    }
    assert!(app.world().resource::<SimulateRuns>().0 > 0);
    assert!(app.world().resource::<ClothStepTiming>().steps > 0);
}

#[test]
fn a_falling_cloth_lands_on_a_collider_entity() {
    let mut app = app();
    app.world_mut()
        .spawn((ClothCollider::plane(), Transform::from_xyz(0.0, 0.5, 0.0)));
    let cloth = app
        .world_mut()
        .spawn((
            ClothBuilder::grid(8, 8, 0.05).in_plane(GridPlane::Horizontal),
            BurnMaterial::COTTON,
            Transform::from_xyz(0.0, 1.0, 0.0),
        ))
        .id();
    for _ in 0..64 * 2 {
        app.update();
    }
    let particles = app.world().get::<ClothParticles>(cloth).unwrap();
    for p in &particles.position {
        assert!(p.y >= 0.5, "fell through the floor collider: {p}");
        assert!(p.y < 0.55, "did not land: {p}");
    }
}

/// Spawns a 24 x 24 cotton cloth at 4 cm with springs of `stiffness` N/m, pinned along its
/// top edge at y = 2 m, stepped by `solver`.
fn spawn_stiff(app: &mut App, stiffness: f32, solver: SolverSettings) -> Entity {
    let material = BurnMaterial {
        structural_stiffness: stiffness,
        shear_stiffness: stiffness,
        bend_stiffness: 0.1 * stiffness,
        ..BurnMaterial::COTTON
    };
    app.world_mut()
        .spawn((
            ClothBuilder::grid(24, 24, 0.04).pin_top_every(4),
            material,
            ClothSolver(solver),
            Transform::from_xyz(0.0, 2.0, 0.0),
        ))
        .id()
}

/// Runs `steps`, returning the lowest particle's height and the largest distance any
/// particle moved along z (the swing) after a 1 m/s push along z.
fn hang_and_swing(app: &mut App, cloth: Entity, steps: u32) -> (f32, f32) {
    app.update();
    app.world_mut()
        .get_mut::<ClothParticles>(cloth)
        .unwrap()
        .velocity
        .fill(Vec3::new(0.0, 0.0, 1.0));
    let mut swing = 0.0f32;
    for _ in 0..steps {
        app.update();
        let particles = app.world().get::<ClothParticles>(cloth).unwrap();
        assert!(particles.is_finite());
        swing = particles
            .position
            .iter()
            .fold(swing, |m, p| m.max(p.z.abs()));
    }
    for _ in 0..3 * 64 {
        app.update();
    }
    let particles = app.world().get::<ClothParticles>(cloth).unwrap();
    let bottom = particles
        .position
        .iter()
        .map(|p| p.y)
        .fold(f32::MAX, f32::min);
    (bottom, swing)
}

#[test]
fn every_stiffness_from_1e1_to_1e7_hangs_and_swings_with_default_settings() {
    // 23 rows of 4 cm below the pins: unstretched, the bottom edge hangs at 2 - 0.92 m.
    let unstretched = 2.0 - 23.0 * 0.04;
    for exponent in 1..=7 {
        let mut app = app();
        let cloth = spawn_stiff(&mut app, 10f32.powi(exponent), SolverSettings::default());
        let (bottom, swing) = hang_and_swing(&mut app, cloth, 32);
        let status = *app.world().get::<ClothStatus>(cloth).unwrap();
        assert_eq!(status.repairs, 0, "1e{exponent}: {status:?}");
        // At most the tethers' 3 % longer, and not frozen short of hanging.
        assert!(
            bottom < unstretched + 0.01 && bottom > unstretched - 0.03 * 0.92 - 0.01,
            "1e{exponent} N/m: bottom at {bottom} m"
        );
        // The push moved it: a 1 m/s push for 0.5 s moves a cloth hung from its top edge
        // several centimetres before its weight swings it back.
        assert!(swing > 0.05, "1e{exponent} N/m: swung only {swing} m");
    }
}

#[test]
fn an_explicit_integrator_past_its_cap_is_switched_to_xpbd_not_frozen() {
    // 1e4 and 1e6 N/m need far more than 64 symplectic Euler substeps at 4 cm.
    let unstretched = 2.0 - 23.0 * 0.04;
    for stiffness in [1e4, 1e6] {
        let mut app = app();
        let solver = SolverSettings {
            integrator: Integrator::SymplecticEuler,
            ..default()
        };
        let cloth = spawn_stiff(&mut app, stiffness, solver);
        let (bottom, swing) = hang_and_swing(&mut app, cloth, 32);
        let status = *app.world().get::<ClothStatus>(cloth).unwrap();
        assert_eq!(status.integrator, Integrator::Xpbd, "{stiffness}");
        assert_eq!(status.repairs, 0, "{stiffness}: {status:?}");
        assert!((bottom - unstretched).abs() < 0.04, "{stiffness}: {bottom}");
        assert!(swing > 0.05, "{stiffness}: swung only {swing} m");
    }
}

#[test]
fn without_the_fallback_the_guard_catches_a_cloth_too_stiff_and_says_so() {
    let mut app = app();
    #[derive(Resource, Default)]
    struct Repaired(u32);
    app.init_resource::<Repaired>().add_observer(
        |event: On<ClothInstability>, mut repaired: ResMut<Repaired>| {
            repaired.0 += event.repaired;
        },
    );
    let solver = SolverSettings {
        integrator: Integrator::SymplecticEuler,
        stiff_fallback: false,
        ..default()
    };
    let cloth = spawn_stiff(&mut app, 1e7, solver);
    hang_and_swing(&mut app, cloth, 60);
    let status = *app.world().get::<ClothStatus>(cloth).unwrap();
    assert_eq!(status.integrator, Integrator::SymplecticEuler);
    assert!(status.repairs > 0, "the guard never had to act: {status:?}");
    assert_eq!(app.world().resource::<Repaired>().0, status.repairs);
    assert!(
        app.world()
            .get::<ClothParticles>(cloth)
            .unwrap()
            .is_finite()
    );
}

#[test]
fn pausing_stops_every_cloth_and_single_steps_advance_exactly_one_step() {
    let mut app = app();
    let cloth = spawn_silk(&mut app);
    app.update();
    app.world_mut()
        .trigger(Ignite::at_world_point(cloth, Vec3::new(0.2, 1.6, 0.0)));
    for _ in 0..10 {
        app.update();
    }
    app.world_mut()
        .resource_mut::<ClothSimulationControl>()
        .paused = true;
    let frozen = app.world().get::<ClothParticles>(cloth).unwrap().clone();
    let steps_before = app.world().resource::<ClothStepTiming>().steps;
    for _ in 0..20 {
        app.update();
    }
    let after = app.world().get::<ClothParticles>(cloth).unwrap();
    assert_eq!(after.position, frozen.position, "a paused cloth moved");
    assert_eq!(
        after.temperature, frozen.temperature,
        "a paused cloth heated"
    );
    assert_eq!(
        app.world().resource::<ClothStepTiming>().steps,
        steps_before
    );

    app.world_mut()
        .resource_mut::<ClothSimulationControl>()
        .step_once();
    for _ in 0..5 {
        app.update();
    }
    let timing = *app.world().resource::<ClothStepTiming>();
    assert_eq!(timing.steps, steps_before + 1, "one single step, once");
    assert!(timing.last_step.as_nanos() > 0 && timing.substeps > 0);
    let stepped = app.world().get::<ClothParticles>(cloth).unwrap();
    assert_ne!(stepped.position, frozen.position);
    assert_eq!(
        app.world()
            .resource::<ClothSimulationControl>()
            .pending_steps,
        0
    );
}

#[test]
fn extinguishing_a_region_puts_it_out_and_a_bad_request_is_ignored() {
    let mut app = app();
    let cloth = spawn_silk(&mut app);
    app.update();
    app.world_mut().trigger(Ignite::particle(cloth, 8 * 16 + 8));
    for _ in 0..40 {
        app.update();
    }
    let status = *app.world().get::<ClothStatus>(cloth).unwrap();
    assert!(status.ignited > 0, "the fire did not take");
    // Bad requests: logged, nothing changes, no panic.
    let before = app
        .world()
        .get::<ClothParticles>(cloth)
        .unwrap()
        .temperature
        .clone();
    app.world_mut()
        .trigger(Extinguish::within(cloth, Vec3::NAN, 1.0));
    app.world_mut()
        .trigger(Extinguish::all(cloth).to_temperature(f32::NAN));
    let despawned = app.world_mut().spawn_empty().id();
    app.world_mut().despawn(despawned);
    app.world_mut().trigger(Extinguish::all(despawned));
    assert_eq!(
        app.world()
            .get::<ClothParticles>(cloth)
            .unwrap()
            .temperature,
        before
    );
    // Douse everything within 1 m of the cloth: the fire is out and stays out.
    let centre = app.world().get::<ClothParticles>(cloth).unwrap().position[8 * 16 + 8];
    app.world_mut()
        .trigger(Extinguish::within(cloth, centre, 1.0));
    let particles = app.world().get::<ClothParticles>(cloth).unwrap();
    assert_eq!(particles.count(BurnState::Ignited), 0);
    let burnt = particles.count(BurnState::Burnt);
    for _ in 0..200 {
        app.update();
    }
    let particles = app.world().get::<ClothParticles>(cloth).unwrap();
    assert_eq!(particles.count(BurnState::Ignited), 0, "the fire came back");
    assert_eq!(particles.count(BurnState::Burnt), burnt);
}

#[test]
fn diagnostics_report_the_step_and_the_particles_on_fire() {
    use bevy::diagnostic::{DiagnosticPath, DiagnosticsStore};
    let mut app = app();
    let cloth = spawn_silk(&mut app);
    app.world_mut()
        .trigger(Ignite::at_world_point(cloth, Vec3::new(0.2, 1.6, 0.0)));
    for _ in 0..64 {
        app.update();
    }
    let store = app.world().resource::<DiagnosticsStore>();
    let value = |path: &DiagnosticPath| -> f64 {
        store
            .get(path)
            .and_then(|d| d.measurement())
            .map(|m| m.value)
            .unwrap_or_else(|| panic!("no measurement for {path}"))
    };
    let status = *app.world().get::<ClothStatus>(cloth).unwrap();
    assert_eq!(value(&ClothDiagnostics::CLOTHS), 1.0);
    assert_eq!(
        value(&ClothDiagnostics::PARTICLES_ALIVE),
        f64::from(status.particles - status.burnt)
    );
    assert_eq!(
        value(&ClothDiagnostics::PARTICLES_BURNING),
        f64::from(status.ignited)
    );
    assert!(status.ignited > 0, "the fire is burning after 1 s");
    let step = value(&ClothDiagnostics::STEP);
    let dynamics = value(&ClothDiagnostics::DYNAMICS);
    assert!(
        step > 0.0 && dynamics > 0.0 && dynamics <= step,
        "{dynamics} of {step} ms"
    );
    #[cfg(feature = "smoke")]
    {
        use bevy_burning_cloth::smoke::{SmokeDiagnostics, SmokeEmitter};
        let live = app
            .world()
            .get::<SmokeEmitter>(cloth)
            .unwrap()
            .pool()
            .live();
        assert!(live > 0, "smoke rises from the fire");
        assert_eq!(value(&SmokeDiagnostics::PARTICLES), live as f64);
        assert!(value(&SmokeDiagnostics::STEP) > 0.0);
    }
}

#[test]
fn a_cloth_description_comes_back_through_reflection_and_burns() {
    use bevy::ecs::reflect::ReflectComponent;
    use std::any::TypeId;
    // Bevy registers `Transform` itself where its reflection auto-registration is on (its
    // default features); this headless build has it off.
    let mut source = app();
    source.register_type::<Transform>();
    let [cloth, torch] = common::spawn_description(source.world_mut());
    let described = [
        (TypeId::of::<ClothBuilder>(), "ClothBuilder"),
        (TypeId::of::<BurnMaterial>(), "BurnMaterial"),
        (TypeId::of::<ClothSolver>(), "ClothSolver"),
        (TypeId::of::<HeatSource>(), "HeatSource"),
        (TypeId::of::<Transform>(), "Transform"),
    ];
    // Every component of the description, copied as dynamic values through the type
    // registry into a fresh app (what a scene does, short of the file).
    let mut target = app();
    target.register_type::<Transform>();
    let registry = source.world().resource::<AppTypeRegistry>().clone();
    let registry = registry.read();
    for entity in [cloth, torch] {
        let copy = target.world_mut().spawn_empty().id();
        for (type_id, name) in described {
            let reflect = registry
                .get(type_id)
                .and_then(|registration| registration.data::<ReflectComponent>())
                .unwrap_or_else(|| panic!("{name} is not registered as a component"));
            if let Some(value) = reflect.reflect(source.world().entity(entity)) {
                let value = value.to_dynamic();
                reflect.insert(
                    &mut target.world_mut().entity_mut(copy),
                    value.as_partial_reflect(),
                    &registry,
                );
            }
        }
    }
    drop(registry);
    common::assert_built_and_burning(&mut target);
}
