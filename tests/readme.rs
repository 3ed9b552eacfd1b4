//! The README's first program is `examples/quickstart.rs`, word for word, so the program a
//! new user pastes is one CI builds (clippy `--all-targets`) and one a screenshot was taken
//! of. The README's Rust blocks are also compiled as doctests (`src/lib.rs`).

#[test]
fn the_readme_program_is_the_quickstart_example() {
    let readme = include_str!("../README.md");
    let example = include_str!("../examples/quickstart.rs");
    let program: String = example
        .lines()
        .skip_while(|line| line.starts_with("//!") || line.is_empty())
        .map(|line| format!("{line}\n"))
        .collect();
    assert!(program.starts_with("use bevy::prelude::*;"), "{program}");
    assert!(
        readme.contains(&format!("```rust,no_run\n{program}```\n")),
        "README.md's first program differs from examples/quickstart.rs"
    );
}
