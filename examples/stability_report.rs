//! Prints the stability matrix (every integrator against stiff and extreme cases) and writes
//! it as Markdown.
//!
//! ```sh
//! cargo run --release --example stability_report --no-default-features --features report [-- OUT_DIR [STEPS]]
//! ```
//!
//! Writes `OUT_DIR/stability.md` (default `target/report/`); 600 steps of 1/60 s by default.

use bevy_burning_cloth::report::{self, stability};
use std::time::Instant;

fn main() -> std::io::Result<()> {
    let mut args = std::env::args().skip(1);
    let dir = args.next().unwrap_or_else(|| "target/report".to_owned());
    let steps = args.next().and_then(|s| s.parse().ok()).unwrap_or(600);
    let started = Instant::now();
    let rows = stability::matrix(steps);
    let table = stability::markdown(&rows, steps);
    report::print_and_write(&table, &dir, "stability.md", started)?;
    Ok(())
}
