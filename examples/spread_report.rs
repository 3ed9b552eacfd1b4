//! Prints how fast fire spreads up, sideways and down a vertical panel and up a 45° strip
//! (16 CFR 1610), for every material, both heat models and several grid spacings, beside
//! published figures, and writes it as Markdown.
//!
//! ```sh
//! cargo run --release --example spread_report --no-default-features --features report [-- OUT_DIR [LIMIT_S [SPACING_MM ...]]]
//! ```
//!
//! Writes `OUT_DIR/spread.md` (default `target/report/`); each case runs at most 480 s of
//! simulated time by default (denim's physical downward front, 1 mm/s, needs 400 s to reach
//! 0.4 m; a shorter limit reports slow fronts as "never"), at spacings of 50, 25, 12.5 and
//! 5 mm; then cotton on meshes of irregular triangles at 25 and 12.5 mm beside the grid.
//!
//! Then how far a heated patch crumples a hanging cloth at the same spacings, at the default
//! substep rate (360 Hz), at eight times it, and at 360 Hz meant for 25 mm and scaled by the
//! spacing (`SolverSettings::substep_rate_spacing`) (`report::crumple`), written to
//! `OUT_DIR/crumple.md`.

use bevy_burning_cloth::report::{self, crumple, spread};
use std::time::Instant;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let dir = args.next().unwrap_or_else(|| "target/report".to_owned());
    let limit: f32 = args.next().map_or(Ok(480.0), |s| s.parse())?;
    let mut spacings: Vec<f32> = args
        .map(|s| s.parse::<f32>().map(|mm| mm / 1000.0))
        .collect::<Result<_, _>>()?;
    if spacings.is_empty() {
        spacings = vec![0.05, 0.025, 0.0125, 0.005];
    }
    let started = Instant::now();
    let rows = spread::study(&spread::cases(&spacings), limit)?;
    let meshes = spread::mesh_study(&[0.025, 0.0125], limit)?;
    let table = format!(
        "{}\n{}",
        spread::markdown(&rows, limit),
        spread::mesh_markdown(&meshes)
    );
    report::print_and_write(&table, &dir, "spread.md", started)?;
    let started = Instant::now();
    let default_rate = bevy_burning_cloth::sim::SolverSettings::default().substep_rate;
    let crumpling = crumple::study(
        &spacings,
        &[
            (default_rate, None),
            (8.0 * default_rate, None),
            (default_rate, Some(0.025)),
        ],
    )?;
    report::print_and_write(&crumple::markdown(&crumpling), &dir, "crumple.md", started)?;
    Ok(())
}
