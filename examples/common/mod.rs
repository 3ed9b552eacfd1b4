//! Pieces the windowed examples share: an orbit camera, a lit stage, and a check mode that
//! runs a fixed number of frames, saves a screenshot and exits.
//!
//! Check mode: set `BURNING_CLOTH_SCREENSHOT=path.png` (and optionally
//! `BURNING_CLOTH_FRAMES=N`, default 240). Each frame then advances exactly 1/60 s of
//! simulated time, however slow the renderer, so the picture is the same on any machine.
//! The screenshot's pixels are classified (light cloth, char, fire, and smoke: grey veiling
//! the sky above the cloth's highest row) and the counts printed;
//! `BURNING_CLOTH_REQUIRE=cloth,char,fire,smoke` makes the app exit with an error when any of the
//! named classes covers less than 50 pixels of the full-size window.
//! `BURNING_CLOTH_RENDER_SCALE=0.5` renders the window at half its pixels in each direction,
//! laid out as at full size (text and panel scaled down with it), and a class then needs a
//! quarter as many: a software renderer shades every pixel on the CPU, so CI's check runs
//! take that.

use bevy::input::mouse::{AccumulatedMouseMotion, AccumulatedMouseScroll};
use bevy::prelude::*;
use bevy::render::view::screenshot::{Screenshot, save_to_disk};
use bevy::time::TimeUpdateStrategy;
use bevy_burning_cloth::prelude::*;
use std::time::Duration;

/// Frames, target file and required pixel classes of a check run.
#[derive(Resource, Clone, Debug)]
pub struct CheckRun {
    pub frames: u32,
    pub screenshot: String,
    pub require: Vec<String>,
}

impl CheckRun {
    /// Reads check mode from the environment.
    pub fn from_env() -> Option<Self> {
        let screenshot = std::env::var("BURNING_CLOTH_SCREENSHOT").ok()?;
        let frames = std::env::var("BURNING_CLOTH_FRAMES")
            .ok()
            .and_then(|f| f.parse().ok())
            .unwrap_or(240);
        let require = std::env::var("BURNING_CLOTH_REQUIRE")
            .map(|r| r.split(',').map(|c| c.trim().to_owned()).collect())
            .unwrap_or_default();
        Some(Self {
            frames,
            screenshot,
            require,
        })
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
        .insert_resource(ClearColor(Color::srgb(0.22, 0.32, 0.46)))
        .add_systems(Startup, spawn_stage)
        .add_systems(Update, orbit_camera);
        // The control panel, when the crate is built with it (default).
        // `BURNING_CLOTH_VIEWS=1` starts with the heat map and the pin gizmos on.
        #[cfg(feature = "egui")]
        {
            app.add_plugins(bevy_burning_cloth::ui::BurningClothUiPlugin);
            if std::env::var_os("BURNING_CLOTH_VIEWS").is_some() {
                let mut panel = app
                    .world_mut()
                    .resource_mut::<bevy_burning_cloth::ui::ClothPanel>();
                panel.heat_map = true;
                panel.show_pins = true;
            }
        }
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

/// A line of help text along the bottom left of the window.
#[allow(dead_code)] // Not every example shows one.
pub fn help_line(text: &str) -> impl Bundle {
    (
        Text::new(text),
        TextFont {
            font_size: FontSize::Px(16.0),
            ..default()
        },
        Node {
            position_type: PositionType::Absolute,
            left: Val::Px(12.0),
            bottom: Val::Px(10.0),
            ..default()
        },
    )
}

/// Window settings for an example: 1280 x 720 logical pixels, rendered at
/// `BURNING_CLOTH_RENDER_SCALE` (0.1 to 1, default 1) times as many in each direction.
pub fn window(title: &str) -> WindowPlugin {
    let scale = render_scale();
    let mut resolution = bevy::window::WindowResolution::new(
        (1280.0 * scale).round() as u32,
        (720.0 * scale).round() as u32,
    );
    if scale != 1.0 {
        resolution = resolution.with_scale_factor_override(scale);
    }
    WindowPlugin {
        primary_window: Some(Window {
            title: title.into(),
            resolution,
            ..default()
        }),
        ..default()
    }
}

/// `BURNING_CLOTH_RENDER_SCALE`: the fraction of the window's logical size rendered, in
/// each direction. Out of range or unreadable values are reported and ignored.
fn render_scale() -> f32 {
    let Ok(text) = std::env::var("BURNING_CLOTH_RENDER_SCALE") else {
        return 1.0;
    };
    match text.trim().parse::<f32>() {
        Ok(scale) if (0.1..=1.0).contains(&scale) => scale,
        _ => {
            eprintln!(
                "BURNING_CLOTH_RENDER_SCALE={text}: not a number from 0.1 to 1; rendering at full size"
            );
            1.0
        }
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
        brightness: 600.0,
        ..default()
    });
    commands.spawn((
        // The floor: burnt-loose pieces land on it.
        ClothCollider::plane(),
        Mesh3d(meshes.add(Plane3d::default().mesh().size(12.0, 12.0))),
        MeshMaterial3d(materials.add(StandardMaterial {
            base_color: Color::srgb(0.42, 0.38, 0.33),
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
    #[cfg_attr(not(feature = "egui"), allow(unused_variables))] windows: Query<&Window>,
    #[cfg(feature = "egui")] panel: Option<Res<bevy_burning_cloth::ui::ClothPanel>>,
    mut cameras: Query<&mut Transform, With<Camera3d>>,
) {
    // The wheel over the control panel scrolls the panel, not the camera.
    #[cfg(feature = "egui")]
    let over_panel = panel
        .and_then(|p| p.screen_rect)
        .zip(windows.iter().next().and_then(Window::cursor_position))
        .is_some_and(|(rect, cursor)| rect.contains(cursor));
    #[cfg(not(feature = "egui"))]
    let over_panel = false;
    if buttons.pressed(MouseButton::Right) {
        orbit.yaw -= motion.delta.x * 0.005;
        orbit.pitch = (orbit.pitch + motion.delta.y * 0.005).clamp(-1.4, 1.4);
    }
    if !over_panel {
        orbit.distance = (orbit.distance * (1.0 - scroll.delta.y * 0.1)).clamp(0.5, 30.0);
    }
    for mut transform in &mut cameras {
        *transform = orbit.transform();
    }
}

fn finish_check_run(
    mut commands: Commands,
    check: Res<CheckRun>,
    verdict: Option<Res<PixelVerdict>>,
    time: Res<Time<Virtual>>,
    mut frame: Local<u32>,
    mut exit: MessageWriter<AppExit>,
) {
    // Frames count while the clock runs (an example may hold it until its scene is ready).
    if time.is_paused() {
        return;
    }
    *frame += 1;
    if *frame == check.frames {
        info!("check run: saving {}", check.screenshot);
        commands
            .spawn(Screenshot::primary_window())
            .observe(save_to_disk(check.screenshot.clone()))
            .observe(classify_screenshot);
    }
    // Give the screenshot a few frames to be captured, classified and written.
    if *frame >= check.frames + 8
        && let Some(verdict) = verdict
    {
        exit.write(if verdict.0 {
            AppExit::Success
        } else {
            AppExit::error()
        });
    }
    if *frame == check.frames + 600 {
        error!("check run: the screenshot never arrived");
        exit.write(AppExit::error());
    }
}

/// Whether the screenshot had every required pixel class.
#[derive(Resource)]
struct PixelVerdict(bool);

/// Pixel classes of a frame, by sRGB bytes.
#[derive(Debug, Default, Clone, Copy)]
pub struct PixelCounts {
    /// Light, unsaturated pixels: fresh pale cloth under light.
    pub cloth: u32,
    /// Near-black or dark brown pixels: charred and scorched cloth, often seen through
    /// flames. Background, floor and its shadows are lighter or greyer: the darkest shadow
    /// measures about (64, 56, 48), red only 16 above blue; char and scorch under flame
    /// light are brown, red more than 25 above blue.
    pub char: u32,
    /// Bright orange pixels: the glowing front.
    pub fire: u32,
    /// Grey pixels veiling the blue sky above the cloth's highest row: smoke or flames
    /// rising off the cloth. The sky measures (56, 82, 117); the floor is warm (red above
    /// blue) and the cloth is below the row, so neither counts.
    pub smoke: u32,
}

impl PixelCounts {
    fn add(&mut self, [r, g, b]: [u8; 3]) {
        let (r, g, b) = (i32::from(r), i32::from(g), i32::from(b));
        let (max, min) = (r.max(g).max(b), r.min(g).min(b));
        if min > 150 && max - min < 40 {
            self.cloth += 1;
        } else if max < 48 || (max < 90 && r >= g && g >= b && r - b > 25) {
            self.char += 1;
        } else if r >= 170 && 4 * r > 5 * g && 10 * g > 14 * b && b < 140 {
            self.fire += 1;
        }
    }

    /// Whether a pixel above the cloth is smoke (or flame) rather than sky.
    fn is_smoke([r, g, b]: [u8; 3]) -> bool {
        let (r, g, b) = (i32::from(r), i32::from(g), i32::from(b));
        let (max, min) = (r.max(g).max(b), r.min(g).min(b));
        let grey_over_sky = b + 3 >= r && b - r < 40 && max >= 70 && max - min < 50;
        let flame = r >= 170 && r > b + 40;
        grey_over_sky || flame
    }

    fn get(&self, class: &str) -> Option<u32> {
        match class {
            "cloth" => Some(self.cloth),
            "char" => Some(self.char),
            "fire" => Some(self.fire),
            "smoke" => Some(self.smoke),
            _ => None,
        }
    }
}

fn classify_screenshot(
    captured: On<bevy::render::view::screenshot::ScreenshotCaptured>,
    check: Res<CheckRun>,
    #[cfg(feature = "egui")] panel: Option<Res<bevy_burning_cloth::ui::ClothPanel>>,
    windows: Query<&Window, With<bevy::window::PrimaryWindow>>,
    mut commands: Commands,
) {
    let image = &captured.image;
    let mut counts = PixelCounts::default();
    // The control panel's own dark and light pixels are not the scene's: leave them out.
    // Its rectangle is in logical pixels; the screenshot's are physical.
    let scale = windows.single().map_or(1.0, Window::scale_factor);
    #[cfg(feature = "egui")]
    let skip = panel.and_then(|p| p.screen_rect);
    #[cfg(not(feature = "egui"))]
    let skip: Option<Rect> = None;
    let skip = skip.map(|r| {
        let r = Rect::from_corners(r.min * scale, r.max * scale).inflate(2.0);
        (
            r.min.x.max(0.0) as u32..r.max.x.max(0.0) as u32,
            r.min.y.max(0.0) as u32..r.max.y.max(0.0) as u32,
        )
    });
    let in_panel = |x: u32, y: u32| {
        skip.as_ref()
            .is_some_and(|(xs, ys)| xs.contains(&x) && ys.contains(&y))
    };
    // The cloth's highest row: the first with a few dozen cloth pixels.
    let mut cloth_top = image.height();
    for y in 0..image.height() {
        let before = counts.cloth;
        for x in 0..image.width() {
            if in_panel(x, y) {
                continue;
            }
            if let Ok(colour) = image.get_color_at(x, y) {
                counts.add(colour.to_srgba().to_u8_array_no_alpha());
            }
        }
        if counts.cloth - before >= 24 && cloth_top == image.height() {
            cloth_top = y;
        }
    }
    for y in 0..cloth_top {
        for x in 0..image.width() {
            if in_panel(x, y) {
                continue;
            }
            if let Ok(colour) = image.get_color_at(x, y)
                && PixelCounts::is_smoke(colour.to_srgba().to_u8_array_no_alpha())
            {
                counts.smoke += 1;
            }
        }
    }
    if let Some((xs, ys)) = &skip {
        println!("pixel check: control panel at x {xs:?}, y {ys:?} left out");
    }
    println!(
        "pixel check: cloth {} char {} fire {} smoke {} (of {} x {})",
        counts.cloth,
        counts.char,
        counts.fire,
        counts.smoke,
        image.width(),
        image.height()
    );
    // 50 pixels of the full-size window, in the pixels rendered.
    let least = (50.0 * scale * scale).ceil() as u32;
    let mut ok = true;
    for class in &check.require {
        match counts.get(class) {
            Some(n) if n >= least => {}
            Some(n) => {
                println!("pixel check FAILED: only {n} {class} pixels, of {least} needed");
                ok = false;
            }
            None => {
                println!("pixel check FAILED: unknown class {class}");
                ok = false;
            }
        }
    }
    commands.insert_resource(PixelVerdict(ok));
}
