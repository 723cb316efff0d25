//! The README's library example is the program `examples/embed.rs` (which `cargo test`
//! compiles): the two must show the same code.

#[test]
fn the_readme_example_is_the_compiled_example() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let readme = std::fs::read_to_string(root.join("README.md")).unwrap();
    let example = std::fs::read_to_string(root.join("examples/embed.rs")).unwrap();
    let start = readme
        .find("```rust\n")
        .expect("the README has a Rust example")
        + 8;
    let end = start + readme[start..].find("```").unwrap();
    let shown: Vec<&str> = readme[start..end]
        .lines()
        .filter(|l| !l.trim().is_empty())
        .collect();
    let compiled: Vec<&str> = example
        .lines()
        .skip_while(|l| !l.starts_with("fn main"))
        .skip(1)
        .take_while(|l| l.trim() != "Ok(())")
        .filter(|l| !l.trim().is_empty())
        .map(|l| l.strip_prefix("    ").unwrap_or(l))
        .collect();
    assert_eq!(shown, compiled, "README.md and examples/embed.rs differ");
}
