//! The simulation's diagnostics reach `LogDiagnosticsPlugin`'s log output, as any Bevy
//! diagnostic does. One test in its own binary: it installs the process-wide logger (Bevy's
//! `LogPlugin` would forward the same records to its tracing output).

use bevy::diagnostic::LogDiagnosticsPlugin;
use bevy::prelude::*;
use bevy::time::TimeUpdateStrategy;
use bevy_burning_cloth::prelude::*;
use std::sync::Mutex;
use std::time::Duration;

/// Keeps every log record's text.
struct Collect(Mutex<Vec<String>>);

impl log::Log for Collect {
    fn enabled(&self, _: &log::Metadata) -> bool {
        true
    }
    fn log(&self, record: &log::Record) {
        self.0.lock().unwrap().push(record.args().to_string());
    }
    fn flush(&self) {}
}

static LINES: Collect = Collect(Mutex::new(Vec::new()));

#[test]
fn log_diagnostics_prints_the_cloth_timings_and_counts() {
    log::set_logger(&LINES).expect("the only logger");
    log::set_max_level(log::LevelFilter::Info);

    let mut app = App::new();
    app.add_plugins((
        MinimalPlugins,
        LogDiagnosticsPlugin {
            wait_duration: Duration::from_millis(1),
            ..default()
        },
        BurningClothPlugins::default(),
    ))
    .insert_resource(TimeUpdateStrategy::ManualDuration(Duration::from_micros(
        15_625,
    )));
    let cloth = app
        .world_mut()
        .spawn((
            ClothBuilder::grid(16, 16, 0.03).pin_top_corners(),
            BurnMaterial::SILK,
            Transform::from_xyz(0.0, 2.0, 0.0),
        ))
        .id();
    app.world_mut()
        .trigger(Ignite::at_world_point(cloth, Vec3::new(0.2, 1.6, 0.0)));
    for _ in 0..64 {
        app.update();
        // Real time must pass for the log timer.
        std::thread::sleep(Duration::from_millis(2));
    }
    let lines = LINES.0.lock().unwrap();
    let mut expected = vec![
        "burning_cloth/step",
        "burning_cloth/dynamics",
        "burning_cloth/heat",
        "burning_cloth/particles_alive",
        "burning_cloth/particles_burning",
    ];
    if cfg!(feature = "smoke") {
        expected.extend(["burning_cloth/smoke_step", "burning_cloth/smoke_particles"]);
    }
    for path in expected {
        assert!(
            lines.iter().any(|line| line.contains(path)),
            "{path} not logged; the log:\n{}",
            lines.join("\n")
        );
    }
}
