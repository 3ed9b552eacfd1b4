//! A silk cloth burning with no window: the paper's Figure 4 scene, printed.
//!
//! A 32 x 32 silk cloth hangs from its two top corners and is ignited near a bottom corner.
//! The app steps as fast as it can in simulated time and prints, every simulated second,
//! how much has burnt and how many pins still hold, until the cloth has burnt away.
//!
//! ```sh
//! cargo run --release --example headless --no-default-features
//! ```

use bevy::prelude::*;
use bevy::time::TimeUpdateStrategy;
use bevy_burning_cloth::prelude::*;
use std::time::{Duration, Instant};

/// One fixed step per update at Bevy's default 64 Hz (exact in nanoseconds).
const STEP: Duration = Duration::from_micros(15_625);
/// Give up after this much simulated time.
const MAX_SECONDS: f32 = 240.0;

fn main() {
    let mut app = App::new();
    app.add_plugins((MinimalPlugins, BurningClothPlugins::default()))
        .insert_resource(TimeUpdateStrategy::ManualDuration(STEP))
        .add_observer(|event: On<ClothIgnited>| {
            println!("cloth {} caught fire", event.entity);
        })
        .add_observer(|event: On<ClothBurntOut>| {
            println!(
                "cloth {} went out with {:.1} % burnt",
                event.entity,
                100.0 * event.burnt_fraction
            );
        });

    let spacing = 0.03;
    let cloth = app
        .world_mut()
        .spawn((
            ClothBuilder::grid(32, 32, spacing).pin_top_corners(),
            BurnMaterial::SILK,
            Transform::from_xyz(0.0, 2.0, 0.0),
        ))
        .id();
    // Near the bottom-right corner, two particles in from each edge.
    let near_corner = Vec3::new(13.5 * spacing, 2.0 - 29.0 * spacing, 0.0);
    app.world_mut()
        .trigger(Ignite::at_world_point(cloth, near_corner));

    let started = Instant::now();
    let steps_per_second = (1.0 / STEP.as_secs_f32()).round() as u32;
    println!("  time   burnt   burning   pins   triangles   substeps");
    let mut step = 0u32;
    loop {
        app.update();
        step += 1;
        let status = *app.world().get::<ClothStatus>(cloth).expect("cloth built");
        let time = step as f32 * STEP.as_secs_f32();
        let gone = status.burnt == status.particles;
        if step.is_multiple_of(steps_per_second) || gone {
            println!(
                "{time:6.1}s {:6.1} % {:8} {:6} {:11} {:10}",
                100.0 * status.burnt_fraction(),
                status.ignited,
                status.pins_left,
                status.live_triangles,
                status.substeps,
            );
        }
        if gone {
            let particles = app.world().get::<ClothParticles>(cloth).unwrap();
            assert!(particles.is_finite());
            println!(
                "burnt away after {time:.1} s of simulated time: both pins burnt ({} left), \
                 {} triangles left; {:.2} s of wall time",
                status.pins_left,
                status.live_triangles,
                started.elapsed().as_secs_f32()
            );
            break;
        }
        if time > MAX_SECONDS {
            println!(
                "still {:.1} % unburnt after {MAX_SECONDS} s: stopping",
                100.0 * (1.0 - status.burnt_fraction())
            );
            std::process::exit(1);
        }
    }
}
