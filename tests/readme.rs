//! The README's first program is `examples/quickstart.rs`, word for word, so the program a
//! new user pastes is one CI builds (clippy `--all-targets`) and one a screenshot was taken
//! of. The README's Rust blocks are also compiled as doctests (`src/lib.rs`), and each of its
//! sections appears once.

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

/// Each section of the README appears once: an edit that pasted a second copy of half the
/// file (as 4bfd6de did, 792 lines) shows up as a heading seen twice.
#[test]
fn each_readme_section_appears_once() {
    let readme = include_str!("../README.md");
    let mut in_code = false;
    let mut seen: Vec<&str> = Vec::new();
    for line in readme.lines() {
        if line.starts_with("```") {
            in_code = !in_code;
            continue;
        }
        if in_code || !line.starts_with("## ") {
            continue;
        }
        assert!(
            !seen.contains(&line),
            "README.md has the section {line:?} twice"
        );
        seen.push(line);
    }
    assert!(seen.len() >= 5, "README.md sections found: {seen:?}");
}
