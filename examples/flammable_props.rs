//! A corner of a room full of things that burn: a swallowtail banner loaded from a glTF file
//! (`Flammable` on the scene root), a curtain and a flag (grid cloths) hung close together, a
//! paper poster made from a Bevy primitive mesh pinned at two corners by a rule of its own, a
//! torch you carry and fireballs you throw. Fire spreads from one to the next.
//!
//! Controls: the torch follows the mouse across the wall; `F` throws a fireball from the
//! camera at the pointer; `E` douses everything within 0.4 m of the torch; `R` resets;
//! right drag orbits, scroll zooms. A line at the top lists what is burning.
//!
//! Unattended (`BURNING_CLOTH_SCREENSHOT`), the clock waits until every prop is a cloth (the
//! glTF banner arrives a varying number of frames after start), then a script holds the torch
//! to the banner for 2 s and throws one fireball at the poster at 6 s, so every check run sees
//! the same scene.
//!
//! ```sh
//! cargo run --example flammable_props
//! ```

#[path = "common/mod.rs"]
mod common;

use bevy::prelude::*;
use bevy::window::PrimaryWindow;
use bevy_burning_cloth::prelude::*;

/// The plane the torch moves in: just in front of the hangings.
const TORCH_Z: f32 = 0.07;
/// A fireball bursts when it comes this close to a cloth particle, m.
const FIREBALL_HIT: f32 = 0.08;
/// Where the paper poster hangs (its centre).
const POSTER_AT: Vec3 = Vec3::new(-1.55, 1.45, -0.04);
/// How long a burst fireball keeps heating where it hit, s.
const FIREBALL_BURST_SECONDS: f32 = 0.8;

fn main() -> AppExit {
    let checking = common::CheckRun::from_env().is_some();
    App::new()
        .add_plugins((
            DefaultPlugins.set(common::window("bevy_burning_cloth: flammable props")),
            BurningClothPlugins::default(),
            common::ExamplePlugin {
                camera_target: Vec3::new(-0.25, 1.3, 0.0),
                camera_distance: 3.2,
            },
        ))
        .insert_resource(ClothEnvironment(bevy_burning_cloth::sim::Environment {
            wind: Vec3::new(0.25, 0.0, 0.1),
            ..default()
        }))
        .init_resource::<Burning>()
        .add_observer(
            |e: On<ClothIgnited>, props: PropNames, mut burning: ResMut<Burning>| {
                let name = props.of(e.entity);
                info!("{name} caught fire");
                burning.0.push(name);
            },
        )
        .add_observer(
            |e: On<ClothBurntOut>, props: PropNames, mut burning: ResMut<Burning>| {
                let name = props.of(e.entity);
                info!("{name} burnt out ({:.0} % gone)", 100.0 * e.burnt_fraction);
                burning.0.retain(|n| *n != name);
            },
        )
        .add_systems(Startup, (spawn_room, spawn_props, spawn_torch, spawn_help))
        // Before `Update`, where the check counts its frames.
        .add_systems(PreUpdate, hold_clock_until_built.run_if(move || checking))
        .add_systems(
            Update,
            (
                move_torch.run_if(move || !checking),
                (script_torch, script_fireball).run_if(move || checking),
                throw_fireball,
                fly_fireballs,
                douse,
                reset,
                show_burning,
            ),
        )
        .run()
}

/// Marks what `R` respawns.
#[derive(Component)]
struct Prop;

#[derive(Component)]
struct Torch;

#[derive(Component)]
struct Fireball {
    velocity: Vec3,
    age: f32,
}

#[derive(Component)]
struct BurningList;

/// Names of the props on fire, in the order they caught.
#[derive(Resource, Default)]
struct Burning(Vec<String>);

/// The name of the prop a cloth belongs to: its own `Name`, or (for a mesh a glTF scene
/// spawned) the name of the `Prop` above it.
#[derive(bevy::ecs::system::SystemParam)]
struct PropNames<'w, 's> {
    props: Query<'w, 's, &'static Name, With<Prop>>,
    parents: Query<'w, 's, &'static ChildOf>,
}

impl PropNames<'_, '_> {
    fn of(&self, cloth: Entity) -> String {
        std::iter::once(cloth)
            .chain(self.parents.iter_ancestors(cloth))
            .find_map(|entity| self.props.get(entity).ok())
            .map_or("?".to_owned(), |name| name.to_string())
    }
}

fn spawn_room(
    mut commands: Commands,
    mut meshes: ResMut<Assets<Mesh>>,
    mut materials: ResMut<Assets<StandardMaterial>>,
) {
    let wood = materials.add(StandardMaterial {
        base_color: Color::srgb(0.33, 0.24, 0.16),
        perceptual_roughness: 0.9,
        ..default()
    });
    // The banner's rod and the flag's pole.
    commands.spawn((
        Mesh3d(meshes.add(Cylinder::new(0.012, 0.62))),
        MeshMaterial3d(wood.clone()),
        Transform::from_xyz(-0.88, 2.01, 0.0)
            .with_rotation(Quat::from_rotation_z(std::f32::consts::FRAC_PI_2)),
    ));
    commands.spawn((
        Mesh3d(meshes.add(Cylinder::new(0.018, 1.95))),
        MeshMaterial3d(wood.clone()),
        Transform::from_xyz(0.0, 0.975, -0.02),
    ));
    // The curtain's rail.
    commands.spawn((
        Mesh3d(meshes.add(Cylinder::new(0.012, 0.85))),
        MeshMaterial3d(wood),
        Transform::from_xyz(-0.3, 2.21, -0.05)
            .with_rotation(Quat::from_rotation_z(std::f32::consts::FRAC_PI_2)),
    ));
}

fn spawn_props(
    mut commands: Commands,
    assets: Res<AssetServer>,
    mut meshes: ResMut<Assets<Mesh>>,
    mut materials: ResMut<Assets<StandardMaterial>>,
) {
    // A banner from a glTF file. `Flammable` on the scene root is handed down to the mesh the
    // scene spawns; `pinned_top` pins its top edge without knowing the file's coordinates. Its
    // glTF material becomes the base of the burning look.
    commands.spawn((
        Prop,
        Name::new("banner"),
        WorldAssetRoot(assets.load(GltfAssetLabel::Scene(0).from_asset("models/banner.gltf"))),
        Flammable::pinned_top(0.005),
        BurnMaterial::CLOTH,
        Transform::from_xyz(-0.88, 1.6, 0.0),
    ));
    // A cotton curtain just behind, overlapping the banner's edge by a few centimetres.
    commands.spawn((
        Prop,
        Name::new("curtain"),
        ClothBuilder::grid(22, 30, 0.035).pin_top_every(3),
        BurnMaterial::COTTON,
        Transform::from_xyz(-0.3, 2.2, -0.05),
    ));
    // A silk flag on the pole, flying in the breeze, its hoist 3 cm in front of the
    // curtain's edge.
    let columns = 18;
    let mut flag = ClothBuilder::grid(columns, 12, 0.04);
    for row in 0..12 {
        flag = flag.pin(0, row);
    }
    commands.spawn((
        Prop,
        Name::new("flag"),
        flag,
        BurnMaterial::SILK,
        Transform::from_xyz(0.5 * (columns - 1) as f32 * 0.04 + 0.02, 1.9, -0.02),
    ));
    // A paper poster from a Bevy primitive mesh, tacked to the wall by its two top corners
    // (a pin rule of the game's own); it is gone for good once it has burnt away.
    commands.spawn((
        Prop,
        Name::new("poster"),
        Mesh3d(
            meshes.add(
                Plane3d::new(Vec3::Z, Vec2::new(0.16, 0.22))
                    .mesh()
                    .subdivisions(10),
            ),
        ),
        MeshMaterial3d(materials.add(StandardMaterial {
            base_color: Color::srgb(0.85, 0.78, 0.6),
            perceptual_roughness: 0.95,
            ..default()
        })),
        Flammable {
            pins: MeshPins::custom(|_, p| p.y > 0.21 && p.x.abs() > 0.15),
        },
        BurnMaterial::PAPER,
        DespawnWhenBurntAway,
        Transform::from_translation(POSTER_AT),
    ));
}

fn spawn_torch(
    mut commands: Commands,
    mut meshes: ResMut<Assets<Mesh>>,
    mut materials: ResMut<Assets<StandardMaterial>>,
) {
    commands
        .spawn((
            Torch,
            HeatSource::default(),
            Mesh3d(meshes.add(Sphere::new(0.025))),
            MeshMaterial3d(materials.add(StandardMaterial {
                base_color: Color::BLACK,
                emissive: LinearRgba::rgb(12.0, 4.0, 0.6),
                ..default()
            })),
            Transform::from_xyz(-0.2, 0.5, TORCH_Z),
        ))
        .with_child(PointLight {
            color: Color::srgb(1.0, 0.6, 0.25),
            intensity: 40_000.0,
            range: 3.0,
            ..default()
        });
}

fn spawn_help(mut commands: Commands) {
    commands.spawn(common::help_line(
        "mouse: carry the torch   F: fireball   E: douse near the torch   R: reset   right drag: orbit",
    ));
    commands.spawn((
        BurningList,
        Text::new(""),
        TextFont {
            font_size: FontSize::Px(18.0),
            ..default()
        },
        TextColor(Color::srgb(1.0, 0.75, 0.4)),
        Node {
            position_type: PositionType::Absolute,
            left: Val::Px(12.0),
            top: Val::Px(10.0),
            ..default()
        },
    ));
}

/// Where the pointer meets the torch's plane.
fn pointer_on_wall(
    window: &Window,
    camera: &Camera,
    camera_transform: &GlobalTransform,
) -> Option<Vec3> {
    let cursor = window.cursor_position()?;
    let ray = camera.viewport_to_world(camera_transform, cursor).ok()?;
    let distance =
        ray.intersect_plane(Vec3::new(0.0, 0.0, TORCH_Z), InfinitePlane3d::new(Vec3::Z))?;
    Some(ray.get_point(distance))
}

fn move_torch(
    windows: Query<&Window, With<PrimaryWindow>>,
    cameras: Query<(&Camera, &GlobalTransform)>,
    mut torches: Query<&mut Transform, With<Torch>>,
) {
    let (Ok(window), Ok((camera, camera_transform))) = (windows.single(), cameras.single()) else {
        return;
    };
    if let Some(point) = pointer_on_wall(window, camera, camera_transform) {
        for mut transform in &mut torches {
            transform.translation = point;
        }
    }
}

/// The props that become cloths: the banner, the curtain, the flag and the poster.
const PROPS: usize = 4;

/// Frames the clock waits for the props before it starts anyway (with an error: a prop that
/// never became a cloth fails the check's fire test).
const MOST_FRAMES_HELD: u32 = 600;

/// Check mode: holds the clock (and so the simulation, the script and the check's frame count)
/// until every prop is a cloth.
fn hold_clock_until_built(
    cloths: Query<(), With<ClothParticles>>,
    mut time: ResMut<Time<Virtual>>,
    mut frames: Local<u32>,
) {
    if *frames == u32::MAX {
        return;
    }
    let built = cloths.iter().count();
    if built >= PROPS || *frames >= MOST_FRAMES_HELD {
        if built < PROPS {
            error!("check run: only {built} of {PROPS} props became cloths; starting anyway");
        }
        info!("check run: the clock starts after {} frames", *frames);
        time.unpause();
        *frames = u32::MAX;
    } else {
        time.pause();
        *frames += 1;
    }
}

/// In check mode: hold the torch to the banner's lower corner for two seconds, then take it
/// away, so what burns after that caught fire from its neighbour.
fn script_torch(time: Res<Time>, mut torches: Query<&mut Transform, With<Torch>>) {
    let t = time.elapsed_secs();
    let at = if t < 2.0 {
        Vec3::new(-0.68, 1.3, TORCH_Z)
    } else {
        Vec3::new(-0.2, 0.4, TORCH_Z)
    };
    for mut transform in &mut torches {
        transform.translation = at;
    }
}

fn throw_fireball(
    keys: Res<ButtonInput<KeyCode>>,
    mut commands: Commands,
    windows: Query<&Window, With<PrimaryWindow>>,
    cameras: Query<(&Camera, &GlobalTransform)>,
    mut meshes: ResMut<Assets<Mesh>>,
    mut materials: ResMut<Assets<StandardMaterial>>,
) {
    if !keys.just_pressed(KeyCode::KeyF) {
        return;
    }
    let (Ok(window), Ok((camera, camera_transform))) = (windows.single(), cameras.single()) else {
        return;
    };
    let start = camera_transform.translation();
    let target = pointer_on_wall(window, camera, camera_transform)
        .unwrap_or(start + camera_transform.forward() * 3.0);
    spawn_fireball(&mut commands, &mut meshes, &mut materials, start, target);
}

/// In check mode: throw one fireball from the camera at the poster at 6 s.
fn script_fireball(
    time: Res<Time>,
    mut thrown: Local<bool>,
    mut commands: Commands,
    cameras: Query<&GlobalTransform, With<Camera>>,
    mut meshes: ResMut<Assets<Mesh>>,
    mut materials: ResMut<Assets<StandardMaterial>>,
) {
    if *thrown || time.elapsed_secs() < 6.0 {
        return;
    }
    let Ok(camera) = cameras.single() else {
        return;
    };
    *thrown = true;
    let start = camera.translation();
    spawn_fireball(&mut commands, &mut meshes, &mut materials, start, POSTER_AT);
}

fn spawn_fireball(
    commands: &mut Commands,
    meshes: &mut Assets<Mesh>,
    materials: &mut Assets<StandardMaterial>,
    start: Vec3,
    target: Vec3,
) {
    commands.spawn((
        Fireball {
            velocity: (target - start).normalize_or_zero() * 4.0,
            age: 0.0,
        },
        HeatSource::new(0.12, 1100.0).with_rate(6.0),
        Mesh3d(meshes.add(Sphere::new(0.06))),
        MeshMaterial3d(materials.add(StandardMaterial {
            base_color: Color::BLACK,
            emissive: LinearRgba::rgb(20.0, 6.0, 1.0),
            ..default()
        })),
        Transform::from_translation(start),
    ));
}

/// Fireballs fly straight; one that reaches a cloth (or the floor) bursts there: it stops and
/// keeps heating what it touches for a moment, then dies out.
fn fly_fireballs(
    time: Res<Time>,
    mut commands: Commands,
    mut fireballs: Query<(Entity, &mut Fireball, &mut Transform)>,
    cloths: Query<&ClothParticles>,
) {
    let dt = time.delta_secs();
    for (entity, mut fireball, mut transform) in &mut fireballs {
        fireball.age += dt;
        if fireball.velocity != Vec3::ZERO {
            transform.translation += fireball.velocity * dt;
            let at = transform.translation;
            let hit_cloth =
                cloths.iter().any(|cloth| {
                    cloth.position.iter().zip(&cloth.state).any(|(p, s)| {
                        !s.is_burnt() && p.distance_squared(at) < FIREBALL_HIT.powi(2)
                    })
                });
            if hit_cloth || at.y < 0.05 {
                fireball.velocity = Vec3::ZERO;
                fireball.age = 3.0 - FIREBALL_BURST_SECONDS;
                transform.scale = Vec3::splat(1.6);
            }
        }
        // It burns out three seconds after it was thrown, or after its burst.
        if fireball.age > 3.0 || transform.translation.z < -1.0 {
            commands.entity(entity).despawn();
        }
    }
}

fn douse(
    keys: Res<ButtonInput<KeyCode>>,
    mut commands: Commands,
    torches: Query<&Transform, With<Torch>>,
    cloths: Query<Entity, With<ClothParticles>>,
) {
    if !keys.just_pressed(KeyCode::KeyE) {
        return;
    }
    for torch in &torches {
        for cloth in &cloths {
            commands.trigger(Extinguish::within(cloth, torch.translation, 0.4));
        }
    }
}

fn reset(
    keys: Res<ButtonInput<KeyCode>>,
    mut commands: Commands,
    props: Query<Entity, With<Prop>>,
    mut burning: ResMut<Burning>,
    assets: Res<AssetServer>,
    meshes: ResMut<Assets<Mesh>>,
    materials: ResMut<Assets<StandardMaterial>>,
) {
    if !keys.just_pressed(KeyCode::KeyR) {
        return;
    }
    for entity in &props {
        commands.entity(entity).despawn();
    }
    burning.0.clear();
    spawn_props(commands, assets, meshes, materials);
}

fn show_burning(burning: Res<Burning>, mut texts: Query<&mut Text, With<BurningList>>) {
    if !burning.is_changed() {
        return;
    }
    for mut text in &mut texts {
        text.0 = if burning.0.is_empty() {
            "nothing is burning".to_owned()
        } else {
            format!("burning: {}", burning.0.join(", "))
        };
    }
}
