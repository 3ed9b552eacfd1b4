//! Pieces the windowed examples share: an orbit camera, a lit stage, and a check mode that
//! runs a fixed number of frames, saves a screenshot and exits.
//!
//! Check mode: set `BURNING_CLOTH_SCREENSHOT=path.png` (and optionally
//! `BURNING_CLOTH_FRAMES=N`, default 240). Each frame then advances exactly 1/60 s of
//! simulated time, however slow the renderer, so the picture is the same on any machine.

use bevy::input::mouse::{AccumulatedMouseMotion, AccumulatedMouseScroll};
use bevy::prelude::*;
use bevy::render::view::screenshot::{Screenshot, save_to_disk};
use bevy::time::TimeUpdateStrategy;
use std::time::Duration;

/// Frames, target file of a check run.
#[derive(Resource, Clone, Debug)]
pub struct CheckRun {
    pub frames: u32,
    pub screenshot: String,
}

impl CheckRun {
    /// Reads check mode from the environment.
    pub fn from_env() -> Option<Self> {
        let screenshot = std::env::var("BURNING_CLOTH_SCREENSHOT").ok()?;
        let frames = std::env::var("BURNING_CLOTH_FRAMES")
            .ok()
            .and_then(|f| f.parse().ok())
            .unwrap_or(240);
        Some(Self { frames, screenshot })
    }
}

/// The window, the orbit camera and, when asked for, check mode.
pub struct ExamplePlugin {
    pub camera_target: Vec3,
    pub camera_distance: f32,
}

impl Plugin for ExamplePlugin {
    fn build(&self, app: &mut App) {
        app.insert_resource(OrbitCamera {
            target: self.camera_target,
            distance: self.camera_distance,
            yaw: 0.0,
            pitch: 0.12,
        })
        .insert_resource(ClearColor(Color::srgb(0.05, 0.05, 0.07)))
        .add_systems(Startup, spawn_stage)
        .add_systems(Update, orbit_camera);
        if let Some(check) = CheckRun::from_env() {
            app.insert_resource(TimeUpdateStrategy::ManualDuration(Duration::from_secs_f64(
                1.0 / 60.0,
            )))
            .insert_resource(Time::<Fixed>::from_hz(60.0))
            .insert_resource(check)
            .add_systems(Update, finish_check_run);
        }
    }
}

/// Window settings for an example.
pub fn window(title: &str) -> WindowPlugin {
    WindowPlugin {
        primary_window: Some(Window {
            title: title.into(),
            resolution: (1280, 720).into(),
            ..default()
        }),
        ..default()
    }
}

/// Where the camera looks from.
#[derive(Resource, Clone, Copy, Debug)]
pub struct OrbitCamera {
    pub target: Vec3,
    pub distance: f32,
    pub yaw: f32,
    pub pitch: f32,
}

impl OrbitCamera {
    fn transform(&self) -> Transform {
        let offset = Quat::from_euler(EulerRot::YXZ, self.yaw, -self.pitch, 0.0)
            * Vec3::new(0.0, 0.0, self.distance);
        Transform::from_translation(self.target + offset).looking_at(self.target, Vec3::Y)
    }
}

fn spawn_stage(
    mut commands: Commands,
    orbit: Res<OrbitCamera>,
    mut meshes: ResMut<Assets<Mesh>>,
    mut materials: ResMut<Assets<StandardMaterial>>,
) {
    commands.spawn((Camera3d::default(), orbit.transform()));
    commands.spawn((
        DirectionalLight {
            illuminance: 6_000.0,
            shadow_maps_enabled: true,
            ..default()
        },
        Transform::from_xyz(3.0, 6.0, 5.0).looking_at(Vec3::ZERO, Vec3::Y),
    ));
    commands.insert_resource(GlobalAmbientLight {
        brightness: 250.0,
        ..default()
    });
    commands.spawn((
        Mesh3d(meshes.add(Plane3d::default().mesh().size(12.0, 12.0))),
        MeshMaterial3d(materials.add(StandardMaterial {
            base_color: Color::srgb(0.22, 0.2, 0.18),
            perceptual_roughness: 1.0,
            ..default()
        })),
    ));
}

fn orbit_camera(
    mut orbit: ResMut<OrbitCamera>,
    buttons: Res<ButtonInput<MouseButton>>,
    motion: Res<AccumulatedMouseMotion>,
    scroll: Res<AccumulatedMouseScroll>,
    mut cameras: Query<&mut Transform, With<Camera3d>>,
) {
    if buttons.pressed(MouseButton::Right) {
        orbit.yaw -= motion.delta.x * 0.005;
        orbit.pitch = (orbit.pitch + motion.delta.y * 0.005).clamp(-1.4, 1.4);
    }
    orbit.distance = (orbit.distance * (1.0 - scroll.delta.y * 0.1)).clamp(0.5, 30.0);
    for mut transform in &mut cameras {
        *transform = orbit.transform();
    }
}

fn finish_check_run(
    mut commands: Commands,
    check: Res<CheckRun>,
    mut frame: Local<u32>,
    mut exit: MessageWriter<AppExit>,
) {
    *frame += 1;
    if *frame == check.frames {
        info!("check run: saving {}", check.screenshot);
        commands
            .spawn(Screenshot::primary_window())
            .observe(save_to_disk(check.screenshot.clone()));
    }
    // Give the screenshot a few frames to be captured and written.
    if *frame == check.frames + 8 {
        exit.write(AppExit::Success);
    }
}
