//! Studies of the simulation that print tables: plain Rust over [`crate::sim`], shared by the
//! report examples and the tests that check them.
//!
//! | module | what it measures |
//! |---|---|
//! | [`stability`] | every integrator against stiff and extreme cases, raw and guarded |
//! | [`accuracy`] | error against run time of every integrator on reference problems |
//! | [`spread`] | fire spread speed by direction, material, heat model and grid spacing |
//! | [`crumple`] | how far a heated patch pulls the cloth in, by grid spacing and substep rate |

pub mod accuracy;
pub mod crumple;
pub mod spread;
pub mod stability;

/// Prints a Markdown `table`, writes it to `dir/file` (creating `dir`), and prints where it
/// went and how long the study took since `started`: the ending every report example shares.
pub fn print_and_write(
    table: &str,
    dir: &str,
    file: &str,
    started: std::time::Instant,
) -> std::io::Result<()> {
    println!("{table}");
    std::fs::create_dir_all(dir)?;
    let path = std::path::Path::new(dir).join(file);
    std::fs::write(&path, table)?;
    println!(
        "written to {} in {:.1} s",
        path.display(),
        started.elapsed().as_secs_f32()
    );
    Ok(())
}
