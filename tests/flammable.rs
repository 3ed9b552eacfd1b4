//! Gameplay heat: `HeatSource` entities and fire jumping between cloths, through the ECS.

use bevy::prelude::*;
use bevy::time::TimeUpdateStrategy;
use bevy_burning_cloth::prelude::*;
use std::time::Duration;

fn app() -> App {
    let mut app = App::new();
    app.add_plugins((MinimalPlugins, BurningClothPlugins::default()))
        .insert_resource(TimeUpdateStrategy::ManualDuration(Duration::from_micros(
            15_625,
        )));
    app
}

/// An app that loads meshes, for `Flammable`.
#[cfg(feature = "render")]
fn mesh_app() -> App {
    let mut app = App::new();
    app.add_plugins((
        MinimalPlugins,
        AssetPlugin::default(),
        TransformPlugin,
        BurningClothPlugins::default(),
    ))
    .init_asset::<Mesh>()
    .insert_resource(TimeUpdateStrategy::ManualDuration(Duration::from_micros(
        15_625,
    )));
    app
}

/// A 12 x 12 silk square, 3 cm spacing, pinned along its top edge at `origin`.
fn spawn_square(app: &mut App, origin: Vec3) -> Entity {
    app.world_mut()
        .spawn((
            ClothBuilder::grid(12, 12, 0.03).pin_top_edge(),
            BurnMaterial::SILK,
            Transform::from_translation(origin),
        ))
        .id()
}

fn ignited_and_burnt(app: &App, cloth: Entity) -> u32 {
    let status = app.world().get::<ClothStatus>(cloth).unwrap();
    status.ignited + status.burnt
}

#[test]
fn a_heat_source_ignites_particles_in_its_reach_and_nowhere_else() {
    let mut app = app();
    let near = spawn_square(&mut app, Vec3::new(0.0, 2.0, 0.0));
    let far = spawn_square(&mut app, Vec3::new(3.0, 2.0, 0.0));
    app.update();
    // A torch just in front of the near cloth's lower middle.
    let target = app.world().get::<ClothParticles>(near).unwrap().position[10 * 12 + 6];
    let torch = target + Vec3::new(0.0, 0.0, 0.02);
    let radius = 0.06;
    app.world_mut().spawn((
        HeatSource::new(radius, 900.0),
        Transform::from_translation(torch),
    ));
    let mut steps = 0;
    while ignited_and_burnt(&app, near) == 0 {
        app.update();
        steps += 1;
        assert!(steps < 64 * 10, "the torch never lit the cloth");
    }
    // At first ignition every ignited particle is within the torch's reach (plus what the
    // cloth moved in the step).
    let particles = app.world().get::<ClothParticles>(near).unwrap();
    for (p, s) in particles.position.iter().zip(&particles.state) {
        if s.is_ignited() {
            assert!(
                p.distance(torch) <= radius + 0.01,
                "ignited {} m away",
                p.distance(torch)
            );
        }
    }
    assert!(
        steps > 1,
        "lit at once: the torch must heat, not set a temperature"
    );
    for _ in 0..64 * 3 {
        app.update();
    }
    assert_eq!(
        ignited_and_burnt(&app, far),
        0,
        "a cloth out of reach caught fire"
    );
    assert!(ignited_and_burnt(&app, near) > 1);
}

#[test]
fn a_moving_heat_source_lights_what_it_passes() {
    let mut app = app();
    let cloth = spawn_square(&mut app, Vec3::new(0.0, 2.0, 0.0));
    app.update();
    // Starts 1 m to the side, out of reach; then sweeps in.
    let torch = app
        .world_mut()
        .spawn((
            HeatSource::new(0.06, 900.0),
            Transform::from_xyz(-1.0, 1.8, 0.02),
        ))
        .id();
    for _ in 0..64 {
        app.update();
    }
    assert_eq!(ignited_and_burnt(&app, cloth), 0);
    app.world_mut()
        .get_mut::<Transform>(torch)
        .unwrap()
        .translation
        .x = 0.15;
    for _ in 0..64 * 5 {
        app.update();
    }
    assert!(
        ignited_and_burnt(&app, cloth) > 0,
        "the torch moved in but lit nothing"
    );
}

/// Two cloths 4 cm apart and one 1 m away; the first is lit.
fn three_cloths(app: &mut App) -> [Entity; 3] {
    let lit = spawn_square(app, Vec3::new(0.0, 2.0, 0.0));
    let close = spawn_square(app, Vec3::new(0.0, 2.0, -0.04));
    let far = spawn_square(app, Vec3::new(1.0, 2.0, 0.0));
    app.update();
    app.world_mut().trigger(Ignite::particle(lit, 11 * 12 + 6));
    [lit, close, far]
}

#[test]
fn fire_spreads_to_a_cloth_close_by_and_not_to_one_far_away() {
    let mut app = app();
    let [lit, close, far] = three_cloths(&mut app);
    let mut steps = 0;
    while ignited_and_burnt(&app, close) == 0 {
        app.update();
        steps += 1;
        assert!(steps < 64 * 30, "fire never jumped 4 cm");
    }
    assert!(ignited_and_burnt(&app, lit) > 0);
    for _ in 0..64 * 5 {
        app.update();
    }
    assert_eq!(ignited_and_burnt(&app, far), 0, "fire jumped 1 m");

    // With spreading off, the close cloth does not catch.
    let mut app = self::app();
    app.insert_resource(FireSpread {
        enabled: false,
        ..FireSpread::default()
    });
    let [_, close, _] = three_cloths(&mut app);
    for _ in 0..steps + 64 * 3 {
        app.update();
    }
    assert_eq!(
        ignited_and_burnt(&app, close),
        0,
        "fire jumped with spreading off"
    );
}

#[test]
fn extinguishing_the_first_cloth_stops_the_fire_reaching_the_second() {
    let mut app = app();
    let [lit, close, _] = three_cloths(&mut app);
    for _ in 0..8 {
        app.update();
    }
    assert!(ignited_and_burnt(&app, lit) > 0);
    assert_eq!(
        ignited_and_burnt(&app, close),
        0,
        "spread before it could be stopped"
    );
    app.world_mut().trigger(Extinguish::all(lit));
    for _ in 0..64 * 10 {
        app.update();
    }
    assert_eq!(
        ignited_and_burnt(&app, close),
        0,
        "the fire reached the second cloth"
    );
    let status = *app.world().get::<ClothStatus>(lit).unwrap();
    assert_eq!(status.ignited, 0, "the first cloth relit");
}

#[test]
fn invalid_heat_sources_are_skipped() {
    let mut app = app();
    let cloth = spawn_square(&mut app, Vec3::new(0.0, 2.0, 0.0));
    app.update();
    let centre = app.world().get::<ClothParticles>(cloth).unwrap().position[60];
    for source in [
        HeatSource::new(f32::NAN, 900.0),
        HeatSource::new(-1.0, 900.0),
        HeatSource::new(0.1, f32::INFINITY),
        HeatSource::new(0.1, 900.0).with_rate(f32::NAN),
        HeatSource::new(0.1, 900.0).with_falloff(-2.0),
    ] {
        app.world_mut()
            .spawn((source, Transform::from_translation(centre)));
    }
    for _ in 0..64 * 2 {
        app.update();
    }
    let particles = app.world().get::<ClothParticles>(cloth).unwrap();
    assert!(
        particles
            .temperature
            .iter()
            .all(|t| t.is_finite() && *t < 30.0)
    );
}

#[test]
fn burning_away_reports_how_many_particles_and_where() {
    /// Count reported, and each reported centroid beside the mean of the particles the
    /// cloth says burnt in that step.
    #[derive(Resource, Default)]
    struct Burnt(u32, Vec<(Vec3, Vec3)>);
    let mut app = app();
    app.init_resource::<Burnt>().add_observer(
        |e: On<ClothParticlesBurnt>,
         cloths: Query<(&ClothParticles, &ClothInUse)>,
         mut burnt: ResMut<Burnt>| {
            let (particles, in_use) = cloths.get(e.entity).unwrap();
            let newly = in_use.newly_burnt();
            let mean = newly
                .iter()
                .map(|&i| particles.position[i as usize])
                .sum::<Vec3>()
                / newly.len() as f32;
            burnt.0 += e.count;
            burnt.1.push((e.centroid, mean));
        },
    );
    let cloth = spawn_square(&mut app, Vec3::new(0.0, 2.0, 0.0));
    app.update();
    app.world_mut()
        .trigger(Ignite::particle(cloth, 11 * 12 + 6));
    for _ in 0..64 * 6 {
        app.update();
    }
    let status = *app.world().get::<ClothStatus>(cloth).unwrap();
    let burnt = app.world().resource::<Burnt>();
    assert!(status.burnt > 0);
    assert_eq!(burnt.0, status.burnt, "every burnt particle reported once");
    for (centroid, mean) in &burnt.1 {
        assert!(centroid.distance(*mean) < 1e-5, "{centroid} vs {mean}");
        // Never beside the 0.33 m square, nor more than 10 cm above its pins (y = 2): the
        // fire's plume (feature `fluid`) lifts a burning edge or piece above the pins by
        // centimetres (5.4 cm here, 2026-12-03), as real burning fabric rises in its updraft;
        // pieces that burn loose fall, so no lower bound.
        assert!(centroid.x.abs() < 0.5 && centroid.y < 2.1, "{centroid}");
    }
}

/// A primitive plane mesh made `Flammable` becomes a cloth: one particle per vertex, one
/// structural spring per edge, one bending spring per interior edge, pinned along its top.
#[cfg(feature = "render")]
#[test]
fn a_flammable_plane_mesh_becomes_a_cloth_and_burns() {
    use bevy_burning_cloth::sim::SpringKind;
    let mut app = mesh_app();
    // Plane3d facing +z, 1 m x 1 m, 4 subdivisions: 6 x 6 vertices, 5 x 5 quads.
    let mesh = Plane3d::new(Vec3::Z, Vec2::splat(0.5))
        .mesh()
        .subdivisions(4)
        .build();
    let vertices = mesh.count_vertices();
    assert_eq!(vertices, 36);
    let handle = app.world_mut().resource_mut::<Assets<Mesh>>().add(mesh);
    let banner = app
        .world_mut()
        .spawn((
            Flammable::pinned_above(0.49),
            Mesh3d(handle),
            BurnMaterial::PAPER,
            Transform::from_xyz(0.0, 2.0, 0.0),
        ))
        .id();
    app.update();
    app.update();
    let particles = app
        .world()
        .get::<ClothParticles>(banner)
        .expect("the mesh became a cloth");
    assert_eq!(particles.len(), 36);
    let pinned = (0..36).filter(|&i| particles.is_pinned(i)).count();
    assert_eq!(pinned, 6, "the top row of vertices is pinned");
    let springs = app.world().get::<ClothSprings>(banner).unwrap();
    let count = |kind| springs.kind.iter().filter(|k| **k == kind).count();
    let edges = 2 * 6 * 5 + 5 * 5;
    assert_eq!(count(SpringKind::Structural), edges);
    assert_eq!(count(SpringKind::Bend), edges - 4 * 5);
    let total_mass: f32 = particles.mass.iter().sum();
    assert!((total_mass - BurnMaterial::PAPER.areal_density).abs() < 1e-4);

    // It hangs from its pins and burns like any cloth.
    app.world_mut()
        .trigger(Ignite::at_world_point(banner, Vec3::new(0.0, 1.6, 0.0)));
    for _ in 0..64 * 8 {
        app.update();
    }
    let status = *app.world().get::<ClothStatus>(banner).unwrap();
    assert!(status.burnt > 0, "the banner did not burn");
    let particles = app.world().get::<ClothParticles>(banner).unwrap();
    assert!(particles.is_finite());
}

#[cfg(feature = "render")]
#[test]
fn a_mesh_that_cannot_burn_is_left_alone() {
    let mut app = mesh_app();
    let lines = Mesh::new(
        bevy::mesh::PrimitiveTopology::LineList,
        bevy::asset::RenderAssetUsages::default(),
    )
    .with_inserted_attribute(Mesh::ATTRIBUTE_POSITION, vec![[0.0f32; 3]; 4]);
    let handle = app.world_mut().resource_mut::<Assets<Mesh>>().add(lines);
    let entity = app
        .world_mut()
        .spawn((Flammable::default(), Mesh3d(handle), Transform::default()))
        .id();
    app.update();
    app.update();
    assert!(app.world().get::<ClothParticles>(entity).is_none());
    assert!(app.world().get::<Flammable>(entity).is_none());
}

#[test]
fn a_piece_cut_loose_by_burning_is_reported_once() {
    #[derive(Resource, Default)]
    struct Detached(Vec<u32>);
    let mut app = app();
    app.init_resource::<Detached>().add_observer(
        |e: On<ClothPieceDetached>, mut seen: ResMut<Detached>| {
            seen.0.push(e.particles);
        },
    );
    let cloth = spawn_square(&mut app, Vec3::new(0.0, 2.0, 0.0));
    app.update();
    for _ in 0..10 {
        app.update();
    }
    assert!(app.world().resource::<Detached>().0.is_empty());
    // Burn row 6 across: rows 7 to 11 (60 particles) come loose.
    {
        let mut particles = app.world_mut().get_mut::<ClothParticles>(cloth).unwrap();
        for i in 6 * 12..7 * 12 {
            particles.temperature[i] = 5_000.0;
        }
    }
    for _ in 0..30 {
        app.update();
    }
    let seen = &app.world().resource::<Detached>().0;
    assert!(!seen.is_empty(), "no piece reported");
    assert!(seen[0] <= 60 && seen[0] >= 40, "{seen:?}");
}

/// Meshes as importers (glTF) deliver them: vertices duplicated along UV seams, 16-bit
/// indices, normals. The seam is welded, so the cloth hangs together across it.
#[cfg(feature = "render")]
#[test]
fn an_imported_style_mesh_with_seams_and_u16_indices_is_welded() {
    use bevy::asset::RenderAssetUsages;
    use bevy::mesh::{Indices, PrimitiveTopology};
    use bevy_burning_cloth::render::flammable::mesh_cloth_builder;
    // Two 2 x 2-vertex quads side by side, each with its own copy of the shared middle edge
    // (a UV seam): 8 vertices, 4 triangles, 6 distinct positions.
    let positions: Vec<[f32; 3]> = vec![
        [0.0, 0.0, 0.0],
        [0.5, 0.0, 0.0],
        [0.0, -0.5, 0.0],
        [0.5, -0.5, 0.0],
        [0.5, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.5, -0.5, 0.0],
        [1.0, -0.5, 0.0],
    ];
    let uvs: Vec<[f32; 2]> = vec![
        [0.0, 0.0],
        [1.0, 0.0],
        [0.0, 1.0],
        [1.0, 1.0],
        [0.0, 0.0],
        [1.0, 0.0],
        [0.0, 1.0],
        [1.0, 1.0],
    ];
    let mesh = Mesh::new(
        PrimitiveTopology::TriangleList,
        RenderAssetUsages::default(),
    )
    .with_inserted_attribute(Mesh::ATTRIBUTE_POSITION, positions)
    .with_inserted_attribute(Mesh::ATTRIBUTE_NORMAL, vec![[0.0f32, 0.0, 1.0]; 8])
    .with_inserted_attribute(Mesh::ATTRIBUTE_UV_0, uvs)
    .with_inserted_indices(Indices::U16(vec![0, 2, 1, 1, 2, 3, 4, 6, 5, 5, 6, 7]));
    let builder = mesh_cloth_builder(&mesh, MeshPins::Above(-0.01)).unwrap();
    let parts = builder
        .build(&BurnMaterial::CLOTH, bevy::math::Affine3A::IDENTITY)
        .unwrap();
    assert_eq!(
        parts.particles.len(),
        6,
        "the seam's copies are one particle each"
    );
    assert_eq!(parts.topology.triangles.len(), 4);
    // Edges: 3 horizontal... a 3 x 2 grid of vertices with two diagonals: 7 + 2 = 9 edges,
    // of which the 3 shared between two triangles (two diagonals and the seam) bend.
    let count = |kind| parts.springs.kind.iter().filter(|k| **k == kind).count();
    use bevy_burning_cloth::sim::SpringKind;
    assert_eq!(count(SpringKind::Structural), 9);
    assert_eq!(count(SpringKind::Bend), 3);
    let pinned = (0..6).filter(|&i| parts.particles.is_pinned(i)).count();
    assert_eq!(pinned, 3, "the top row, seam included");
}

/// `Flammable` on a scene root reaches the meshes a scene spawns under it later (as a glTF scene
/// does: root, node with its own transform, mesh entity), with the root's material and clean-up,
/// and pins each mesh's top edge in that mesh's own frame; meshes elsewhere stay plain.
#[cfg(feature = "render")]
#[test]
fn flammable_on_a_scene_root_reaches_meshes_spawned_under_it() {
    let mut app = mesh_app();
    let banner_mesh = Plane3d::new(Vec3::Z, Vec2::new(0.25, 0.4))
        .mesh()
        .subdivisions(6)
        .build();
    let handle = app
        .world_mut()
        .resource_mut::<Assets<Mesh>>()
        .add(banner_mesh);
    let root = app
        .world_mut()
        .spawn((
            Flammable::pinned_top(0.01),
            BurnMaterial::SILK,
            DespawnWhenBurntAway,
            Transform::from_xyz(1.0, 0.5, 0.0),
        ))
        .id();
    // A plain mesh elsewhere, not under the root.
    let plain = app
        .world_mut()
        .spawn((Mesh3d(handle.clone()), Transform::default()))
        .id();
    app.update();
    // The "scene" arrives a frame later: a node 1.2 m up, turned 90° about y, holding the
    // mesh.
    let node = app
        .world_mut()
        .spawn((
            ChildOf(root),
            Transform::from_xyz(0.0, 1.2, 0.0)
                .with_rotation(Quat::from_rotation_y(std::f32::consts::FRAC_PI_2)),
        ))
        .id();
    let mesh = app
        .world_mut()
        .spawn((ChildOf(node), Mesh3d(handle), Transform::default()))
        .id();
    app.update();
    app.update();
    let particles = app
        .world()
        .get::<ClothParticles>(mesh)
        .expect("the scene's mesh became a cloth");
    assert_eq!(particles.len(), 8 * 8);
    assert_eq!(
        *app.world().get::<BurnMaterial>(mesh).unwrap(),
        BurnMaterial::SILK
    );
    assert!(app.world().get::<DespawnWhenBurntAway>(mesh).is_some());
    let pinned: Vec<Vec3> = (0..particles.len())
        .filter(|&i| particles.is_pinned(i))
        .map(|i| particles.position[i])
        .collect();
    assert_eq!(pinned.len(), 8, "the top row of the mesh");
    for p in &pinned {
        // World: root (1, 0.5, 0) + node (0, 1.2, 0) + the mesh's top edge at local y 0.4;
        // the node's turn lays the banner's width along world z.
        assert!((p.y - 2.1).abs() < 1e-4, "pin at {p}");
        assert!((p.x - 1.0).abs() < 1e-4, "pin at {p}");
        assert!(p.z.abs() <= 0.25 + 1e-4, "pin at {p}");
    }
    assert!(app.world().get::<ClothParticles>(plain).is_none());
    assert!(app.world().get::<Flammable>(plain).is_none());
    assert!(app.world().get::<ClothParticles>(root).is_none());

    // Made flammable after its meshes exist: handed down at once.
    let late_root = app.world_mut().spawn(Transform::default()).id();
    let late_mesh = {
        let handle = app
            .world()
            .get::<Mesh3d>(mesh)
            .map(|m| m.0.clone())
            .unwrap();
        app.world_mut()
            .spawn((ChildOf(late_root), Mesh3d(handle), Transform::default()))
            .id()
    };
    app.update();
    assert!(app.world().get::<ClothParticles>(late_mesh).is_none());
    app.world_mut()
        .entity_mut(late_root)
        .insert(Flammable::default());
    app.update();
    app.update();
    assert!(app.world().get::<ClothParticles>(late_mesh).is_some());
}

/// A cloth marked `DespawnWhenBurntAway` is despawned once it has burnt away completely and
/// its smoke has died; one whose fire went out with part of it left stays.
#[test]
fn a_cloth_that_burnt_away_is_despawned_and_one_partly_burnt_stays() {
    let mut app = app();
    let whole = app
        .world_mut()
        .spawn((
            ClothBuilder::grid(8, 8, 0.03).pin_top_edge(),
            BurnMaterial::PAPER,
            Transform::from_xyz(0.0, 2.0, 0.0),
            DespawnWhenBurntAway,
        ))
        .id();
    let partly = app
        .world_mut()
        .spawn((
            ClothBuilder::grid(8, 8, 0.03).pin_top_edge(),
            BurnMaterial::PAPER,
            Transform::from_xyz(2.0, 2.0, 0.0),
            DespawnWhenBurntAway,
        ))
        .id();
    app.update();
    for (cloth, rows) in [(whole, 0..8), (partly, 6..8)] {
        let mut particles = app.world_mut().get_mut::<ClothParticles>(cloth).unwrap();
        for i in rows.start * 8..rows.end * 8 {
            particles.temperature[i] = 5_000.0;
        }
    }
    // The partly burnt one is cooled above its lowest rows every step, so its fire stops.
    let step = |app: &mut App| {
        let mut particles = app.world_mut().get_mut::<ClothParticles>(partly).unwrap();
        for i in 0..5 * 8 {
            particles.temperature[i] = 20.0;
        }
        app.update();
    };
    let mut steps = 0;
    while app.world().get_entity(whole).is_ok() {
        step(&mut app);
        steps += 1;
        assert!(steps < 64 * 30, "the burnt-away cloth was never despawned");
        if let Some(status) = app.world().get::<ClothStatus>(whole) {
            assert!(
                status.burnt > 0 || steps < 64,
                "despawn must wait for the burn"
            );
        }
    }
    for _ in 0..64 * 2 {
        step(&mut app);
    }
    let status = app
        .world()
        .get::<ClothStatus>(partly)
        .expect("the partly burnt cloth stays");
    assert!(status.burnt > 0 && status.live_triangles > 0);
}
