//! `docs/gallery.md`: every AU and expression of the default table rendered as braille text.
//!
//! `GRIMACE_WRITE_GALLERY=1 cargo test --test model face_gallery::` rewrites the gallery; without it
//! the test checks that the committed gallery shows every AU and expression of the table.

use std::fmt::Write;
use std::path::Path;

use grimace::facs::combo::parse_combo;
use grimace::facs::AuTable;
use grimace::io::builtin;
use grimace::model::{Activations, BoundRig, Mesh, Rig, SkinRules};
use grimace::render::{render_text, Camera, CellMode, Scene, Style};

const COLS: usize = 44;
/// The heading of the hand-written measurements at the end of the gallery, which a rewrite
/// keeps.
const MEASURED: &str = "## Read by an independent face tracker";
const ROWS: usize = 26;

fn picture(mesh: &Mesh, bound: &BoundRig, act: &Activations, camera: &Camera) -> String {
    let mut positions = Vec::new();
    bound
        .deform(act, &mut positions)
        .expect("valid activations");
    let scene = Scene::new(mesh, &positions).with_rest(&mesh.positions);
    let text = render_text(&scene, camera, Style::Lines, CellMode::Braille, COLS, ROWS);
    // trailing spaces are noise in a document
    text.lines()
        .map(str::trim_end)
        .collect::<Vec<_>>()
        .join("\n")
}

fn section(out: &mut String, title: &str, note: &str, art: &str) {
    let _ = writeln!(out, "### {title}\n");
    if !note.is_empty() {
        let _ = writeln!(out, "{note}\n");
    }
    let _ = writeln!(out, "```text\n{art}\n```\n");
}

fn muscles_of(table: &AuTable, key: &grimace::facs::AuKey) -> String {
    let entry = &table.aus[key];
    let mut parts: Vec<String> = entry
        .muscles
        .iter()
        .map(|(m, v)| format!("{m} {v}"))
        .collect();
    if entry.jaw > 0.0 {
        parts.push(format!("jaw {}", entry.jaw));
    }
    if parts.is_empty() {
        "(nothing)".into()
    } else {
        parts.join(", ")
    }
}

fn gallery(mesh: &Mesh, rig: &Rig, table: &AuTable) -> String {
    let bound = BoundRig::bind_with(rig, mesh, SkinRules::DEFAULT).expect("default rig binds");
    let front = Camera::front();
    let mut out = String::new();
    out.push_str(
        "# Gallery: the default face, its AUs and expressions\n\n\
         Every AU of `presets/default.au.ron` and every expression, drawn by grimace's own \
         renderer (`render::render_text`, feature lines, braille, front view, \
         44x26 cells), as it appears in the editor. The face is seen as a photograph: the \
         subject's left (`L` AUs and `L_` muscles) is on the viewer's right.\n\n\
         Regenerate with `GRIMACE_WRITE_GALLERY=1 cargo test --test model face_gallery::`.\n\n",
    );
    out.push_str("## The neutral face\n\n");
    let rest = Activations::zero(rig);
    section(&mut out, "Front", "", &picture(mesh, &bound, &rest, &front));
    section(
        &mut out,
        "Three-quarter",
        "",
        &picture(mesh, &bound, &rest, &Camera::three_quarter()),
    );
    section(
        &mut out,
        "Profile",
        "",
        &picture(mesh, &bound, &rest, &Camera::side()),
    );
    out.push_str("## Action Units\n\n");
    for (key, entry) in &table.aus {
        let act = table.entry_activations(key, rig).expect("AU evaluates");
        let title = format!("AU {key}: {}", entry.name);
        let note = format!("Muscles: {}.", muscles_of(table, key));
        section(
            &mut out,
            &title,
            &note,
            &picture(mesh, &bound, &act, &front),
        );
    }
    out.push_str("## Expressions\n\n");
    for (name, combo) in &table.expressions {
        let parsed = parse_combo(combo).expect("combination parses");
        let act = table.evaluate(&parsed, rig).expect("expression evaluates");
        let title = format!("{name}: {combo}");
        section(&mut out, &title, "", &picture(mesh, &bound, &act, &front));
    }
    out
}

#[test]
fn gallery_shows_every_au_and_expression() {
    let mesh = builtin::default_mesh();
    let rig = builtin::default_rig();
    let table = builtin::default_table();
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/gallery.md");
    if std::env::var("GRIMACE_WRITE_GALLERY").is_ok_and(|v| v == "1") {
        // The sections at the end are kept: the tracker readings (written by hand) and the big
        // heads (written by `tests/render/lod.rs`), in that order.
        let old = std::fs::read_to_string(&path).unwrap_or_default();
        let kept = old.find(MEASURED).map_or("", |at| &old[at..]);
        let text = gallery(&mesh, &rig, &table) + kept;
        std::fs::write(&path, text).expect("gallery written");
    }
    let text = std::fs::read_to_string(&path).expect("docs/gallery.md exists");
    for (key, entry) in &table.aus {
        let title = format!("### AU {key}: {}", entry.name);
        assert!(text.contains(&title), "the gallery lacks `{title}`");
    }
    for (name, combo) in &table.expressions {
        let title = format!("### {name}: {combo}");
        assert!(text.contains(&title), "the gallery lacks `{title}`");
    }
    assert!(text.matches("```text").count() >= table.aus.len() + table.expressions.len());
}
