//! The README's "Embedding grimace" example as a program, so `cargo test` compiles it (and
//! `tests/cli/readme_example.rs` checks that the README shows exactly this code):
//! `cargo run --example embed` prints the smiling built-in face.

// Kept as the README shows it, line for line.
#[rustfmt::skip]
fn main() -> Result<(), Box<dyn std::error::Error>> {
    use grimace::io::builtin;
    use grimace::model::Deformation;
    use grimace::render::{render_text, Camera, CellMode, Scene, Style};

    let (mesh, rig, table) = (builtin::default_mesh(), builtin::default_rig(), builtin::default_table());
    // the deformation the editor, render and export use (Deformation::Paper: the paper's model)
    let bound = Deformation::default().bind(&rig, &mesh)?;
    let smile = table.expression_activations("happiness", &rig)?;
    let mut positions = Vec::new();
    bound.deform(&smile, &mut positions)?;
    let scene = Scene::new(&mesh, &positions).with_rest(&mesh.positions);
    print!("{}", render_text(&scene, &Camera::front(), Style::Lines, CellMode::Braille, 80, 24));
    Ok(())
}
