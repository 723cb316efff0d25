//! One deformation everywhere: every AU and expression of the built-in table, on the built-in
//! face and on a fitted head, gives the same vertex positions through the library
//! ([`Deformation::default`]), `grimace export` (OBJ), the glTF morph targets (rest plus
//! delta, read back from the .glb), `render`'s positions and the editor's scene.

use grimace::io::load::{load_rig_ref, load_table_ref_for};
use std::path::{Path, PathBuf};

use clap::Parser;
use glam::{Quat, Vec3};
use grimace::cli::{self, Cli, Command};
use grimace::facs::AuTable;
use grimace::io::{builtin, landmarks, obj};
use grimace::model::{Activations, Deformation, Rig};
use grimace::tui::face::Face;
use grimace::tui::table_ops;

use super::gltf_export::read_glb;
use crate::common::grimace_in;

/// Largest difference allowed between two consumers' positions.
const SAME: f32 = 1e-5;

/// Parses a command line as `grimace` does.
fn command(args: &[&str]) -> Command {
    let mut all = vec!["grimace"];
    all.extend_from_slice(args);
    Cli::try_parse_from(all)
        .unwrap_or_else(|e| panic!("{args:?}: {e}"))
        .command
        .expect("a subcommand")
}

/// Runs `grimace export ARGS` in this process.
fn export(args: &[&str]) {
    match command(&[&["export"], args].concat()) {
        Command::Export(a) => cli::export::run(&a).unwrap_or_else(|e| panic!("{args:?}: {e:#}")),
        _ => unreachable!(),
    }
}

fn render_args(args: &[&str]) -> cli::render::RenderArgs {
    match command(&[&["render"], args].concat()) {
        Command::Render(a) => a,
        _ => unreachable!(),
    }
}

fn largest_difference(a: &[Vec3], b: &[Vec3]) -> f32 {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .map(|(p, q)| (*p - *q).abs().max_element())
        .fold(0.0, f32::max)
}

/// One state of the table: its name, the flag that selects it and its activations (as the
/// editor gives them).
struct State {
    name: String,
    flag: [String; 2],
    act: Activations,
}

fn states(table: &AuTable, rig: &Rig) -> Vec<State> {
    let mut out = Vec::new();
    for key in table.aus.keys() {
        out.push(State {
            name: grimace::io::morph::au_target_name(key),
            flag: ["--au".into(), key.to_string()],
            act: table_ops::activations_of(table, *key, rig).unwrap(),
        });
    }
    for (name, combo) in &table.expressions {
        out.push(State {
            name: name.clone(),
            flag: ["--expr".into(), name.clone()],
            act: table_ops::evaluate(table, combo, rig).unwrap(),
        });
    }
    out
}

/// Every consumer agrees with the library on the face `rig_args` names; returns the largest
/// difference seen.
fn every_consumer_agrees(dir: &Path, rig_args: &[&str]) -> f32 {
    let (rig_path, table_path) = (PathBuf::from(rig_args[1]), PathBuf::from(rig_args[3]));
    let loaded = load_rig_ref(&rig_path, None).unwrap();
    let table = load_table_ref_for(&table_path, &loaded.rig).unwrap();
    let bound = Deformation::default()
        .bind(&loaded.rig, &loaded.mesh)
        .unwrap();
    let mut scene = Face::new(loaded.rig.clone(), loaded.mesh.clone()).unwrap();
    let glb = dir.join("face.glb");
    let glb_arg = glb.to_str().unwrap();
    export(&[rig_args, &["--gltf", glb_arg, "--targets", "aus"]].concat());
    let aus = read_glb(&glb);
    export(&[rig_args, &["--gltf", glb_arg, "--targets", "expressions"]].concat());
    let expressions = read_glb(&glb);
    // render's own loading and binding, once: the states differ only in their activations
    let (sources, drawn_bound) = cli::render::load(&render_args(rig_args)).unwrap();
    let obj_path = dir.join("state.obj");
    let obj_arg = obj_path.to_str().unwrap();
    let mut worst = 0.0f32;
    for state in states(&table, &loaded.rig) {
        let mut library = Vec::new();
        bound.deform(&state.act, &mut library).unwrap();
        let flag = [state.flag[0].as_str(), state.flag[1].as_str()];
        export(&[rig_args, &flag, &["--out", obj_arg]].concat());
        let exported = obj::read_obj(&obj_path).unwrap().positions;
        let drawn = cli::render::state_positions(
            &render_args(&[rig_args, &flag[..]].concat()),
            &sources,
            &drawn_bound,
        )
        .unwrap();
        scene.deform(&state.act);
        let read = if state.flag[0] == "--au" {
            &aus
        } else {
            &expressions
        };
        let index = read.names.iter().position(|n| *n == state.name).unwrap();
        let target: Vec<Vec3> = read
            .rest
            .iter()
            .zip(&read.deltas[index])
            .map(|(r, d)| *r + *d)
            .collect();
        for (what, positions) in [
            ("export OBJ", &exported),
            ("render", &drawn),
            ("the editor", &scene.positions().to_vec()),
            ("the glTF target", &target),
        ] {
            let difference = largest_difference(&library, positions);
            assert!(
                difference <= SAME,
                "{}: {what} differs from the library by {difference}",
                state.name
            );
            worst = worst.max(difference);
        }
    }
    worst
}

#[test]
fn the_built_in_face_is_the_same_everywhere() {
    let dir = tempfile::tempdir().unwrap();
    let worst = every_consumer_agrees(
        dir.path(),
        &["--rig", "builtin:default", "--table", "builtin:default"],
    );
    println!("built-in face: largest difference {worst:e}");
}

/// The built-in face turned, scaled and moved, written as an OBJ with its landmarks beside
/// it, and fitted with `grimace fit-rig`.
fn fitted_head(dir: &Path) -> PathBuf {
    let mesh = builtin::default_mesh();
    let turn = Quat::from_rotation_y(0.4) * Quat::from_rotation_x(-0.2);
    let moved: Vec<Vec3> = mesh
        .positions
        .iter()
        .map(|p| turn * (*p * 7.5) + Vec3::new(40.0, -12.0, 5.0))
        .collect();
    obj::save_obj(&dir.join("head.obj"), &mesh, &moved).unwrap();
    let marks = builtin::landmarks("face").unwrap();
    landmarks::save_landmarks(&dir.join("head.landmarks.ron"), &marks).unwrap();
    crate::common::fit_head(dir)
}

#[test]
fn a_fitted_head_is_the_same_everywhere() {
    let dir = tempfile::tempdir().unwrap();
    let rig = fitted_head(dir.path());
    let worst = every_consumer_agrees(
        dir.path(),
        &["--rig", rig.to_str().unwrap(), "--table", "builtin:default"],
    );
    println!("fitted head: largest difference {worst:e}");
}

#[test]
fn one_sided_aus_derived_from_bilateral_ones_export_and_render() {
    let dir = tempfile::tempdir().unwrap();
    let out = grimace_in(dir.path(), &["export", "--au", "L9", "--out", "l9.obj"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let rest = builtin::default_mesh().positions;
    let l9 = obj::read_obj(&dir.path().join("l9.obj")).unwrap().positions;
    // the left side moves more than the right (x > 0 is the subject's left)
    let moved = |side: f32| -> f32 {
        rest.iter()
            .zip(&l9)
            .filter(|(r, _)| r.x * side > 0.5)
            .map(|(r, p)| r.distance(*p))
            .sum()
    };
    assert!(moved(1.0) > 2.0 * moved(-1.0), "L9 moves the left side");
    let out = grimace_in(dir.path(), &["render", "--au", "L45", "--out", "l45.svg"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(dir.path().join("l45.svg").is_file());
}

#[test]
fn paper_is_available_by_name_and_differs_from_the_skin() {
    let dir = tempfile::tempdir().unwrap();
    export(&[
        "--au",
        "12",
        "--model",
        "paper",
        "--out",
        dir.path().join("paper.obj").to_str().unwrap(),
    ]);
    let paper = obj::read_obj(&dir.path().join("paper.obj"))
        .unwrap()
        .positions;
    let rig = builtin::default_rig();
    let act = builtin::default_table()
        .entry_activations(&"12".parse().unwrap(), &rig)
        .unwrap();
    let mut want = Vec::new();
    Deformation::Paper
        .bind(&rig, &builtin::default_mesh())
        .unwrap()
        .deform(&act, &mut want)
        .unwrap();
    assert!(largest_difference(&paper, &want) <= SAME);
    let mut skin = Vec::new();
    Deformation::Skin
        .bind(&rig, &builtin::default_mesh())
        .unwrap()
        .deform(&act, &mut skin)
        .unwrap();
    assert!(
        largest_difference(&paper, &skin) > 1e-3,
        "the skin rules act on AU12"
    );
}
