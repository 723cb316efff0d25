//! The landmark picker end to end: the real binary in a pseudo-terminal, driven by keys.
//!
//! The keys are planned on the library's own picker state (the same pure update the binary
//! runs, on a terminal of the same size): move the cursor cell by cell toward the wanted
//! vertex, turn the view when it is hidden, zoom in when it shares a cell with another, and
//! Enter. The binary gets only the keys; the file it writes is compared with the preset.

use std::path::{Path, PathBuf};

use crossterm::event::{KeyCode, KeyEvent, KeyModifiers};
use grimace::landmarks::Landmarks;
use grimace::landmarks::COUNT;
use grimace::render::CellMode;
use grimace::tui::pick::keys::dispatch;
use grimace::tui::pick::PickApp;

use crate::common;
use crate::common::pty::Term;

const COLS: u16 = 120;
const ROWS: u16 = 40;

fn face_obj() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("assets/face.obj")
}

/// The default face's landmarks as vertex numbers (presets/default.landmarks.ron).
fn preset() -> Vec<u32> {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("presets/default.landmarks.ron");
    match grimace::io::landmarks::load_landmarks(&path).unwrap() {
        Landmarks::Vertices(v) => v,
        other => panic!("the preset holds vertices: {other:?}"),
    }
}

/// The picker state the binary starts with for `mesh` on a `COLS` x `ROWS` terminal.
fn planner(mesh: &Path, out: &Path) -> PickApp {
    let loaded = grimace::io::obj::read_obj(mesh).unwrap();
    PickApp::new(
        loaded,
        mesh.to_path_buf(),
        out.to_path_buf(),
        (COLS, ROWS),
        CellMode::Braille,
    )
}

/// Presses `key` on the planner and returns the bytes the terminal sends for it.
fn press(app: &mut PickApp, key: char) -> String {
    let code = match key {
        '\r' => KeyCode::Enter,
        '\t' => KeyCode::Tab,
        c => KeyCode::Char(c),
    };
    let action = dispatch(&app.mode, KeyEvent::new(code, KeyModifiers::NONE))
        .unwrap_or_else(|| panic!("`{key}` does nothing"));
    app.update(action);
    key.to_string()
}

/// The keys that take vertex `target` for the current landmark (pressed on the planner).
fn keys_for(app: &mut PickApp, target: u32) -> String {
    let mut keys = String::new();
    for _ in 0..400 {
        if app.snapped == Some(target) {
            keys += &press(app, '\r');
            return keys;
        }
        let screen = app.screen.as_ref().expect("a viewport");
        let on_screen = screen.dot_of(target).is_some_and(|at| screen.contains(at));
        if !on_screen && app.camera != grimace::render::Camera::front() {
            // Out of the zoomed or turned view: back to the whole face.
            keys += &press(app, 'v');
            continue;
        }
        if on_screen && !screen.visible[target as usize] {
            // Turn the hidden side toward the viewer.
            let left = app.mesh.positions[target as usize].x > 0.0;
            keys += &press(app, if left { ']' } else { '[' });
            continue;
        }
        let d = screen.dot_of(target).unwrap() - app.cursor;
        let (cw, ch) = (screen.cell.0 as f32, screen.cell.1 as f32);
        let (dx, dy) = ((d.x / cw).round() as i32, (d.y / ch).round() as i32);
        let key = match (dx.signum(), dy.signum()) {
            (0, 0) => '+',
            (1, _) => 'l',
            (-1, _) => 'h',
            (_, 1) => 'j',
            _ => 'k',
        };
        keys += &press(app, key);
    }
    let screen = app.screen.as_ref().unwrap();
    panic!(
        "vertex {target} could not be reached by keys: visible {}, at {:?}, cursor {}, on {:?}, camera {:?}, keys {keys}",
        screen.visible[target as usize],
        screen.dot_of(target),
        app.cursor,
        app.snapped,
        app.camera
    );
}

/// What the info panel says for the planner's current landmark.
fn heading(app: &PickApp) -> String {
    match app.current {
        Some(l) => format!("Landmark {l}: "),
        None => "All 68 landmarks picked".to_string(),
    }
}

/// Picks `count` landmarks in the picking order, each with the preset's vertex, typing the
/// planned keys into `ed` and waiting for each step to show.
fn pick(ed: &mut Term, app: &mut PickApp, preset: &[u32], count: usize) {
    for _ in 0..count {
        let l = app.current.expect("a landmark to pick");
        let keys = keys_for(app, preset[l]);
        ed.send(&keys);
        ed.wait_for(&heading(app));
    }
}

#[test]
fn picking_the_default_face_by_keys_gives_the_preset_landmarks_back() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("face.landmarks.ron");
    let mesh = face_obj();
    let preset = preset();
    let mut app = planner(&mesh, &out);
    let (m, o) = (mesh.to_str().unwrap(), out.to_str().unwrap());
    let mut ed = Term::grimace(dir.path(), &["landmarks", m, "--out", o], COLS, ROWS);
    ed.wait_for("Landmark 45: ");
    // A skip and its undo on the way.
    ed.send(&press(&mut app, '\t'));
    ed.wait_for("Landmark 42: ");
    ed.send(&press(&mut app, 'u'));
    ed.wait_for("undone: landmark 45");
    pick(&mut ed, &mut app, &preset, 11);
    // The right side is proposed by symmetry: Enter alone takes each.
    let screen = ed.wait_for("proposed by symmetry");
    assert!(screen.contains("11 of 68 picked"), "{screen}");
    pick(&mut ed, &mut app, &preset, COUNT - 11);
    assert_eq!(app.current, None);
    ed.send(":w\r");
    ed.wait_for("saved");
    ed.send("q");
    assert!(ed.wait_exit().success());
    let written = grimace::io::landmarks::load_landmarks(&out).unwrap();
    assert_eq!(written, Landmarks::Vertices(preset));
    assert!(
        !dir.path().join(".face.landmarks.ron.recover").exists(),
        "the recovery file goes once the landmarks are saved"
    );
}

#[test]
fn a_hangup_mid_pick_loses_no_point_and_the_next_start_offers_them() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("face.landmarks.ron");
    let recovery = dir.path().join(".face.landmarks.ron.recover");
    let mesh = face_obj();
    let preset = preset();
    let mut app = planner(&mesh, &out);
    let (m, o) = (mesh.to_str().unwrap(), out.to_str().unwrap());
    let mut ed = Term::grimace(dir.path(), &["landmarks", m, "--out", o], COLS, ROWS);
    ed.wait_for("Landmark 45: ");
    pick(&mut ed, &mut app, &preset, 3);
    ed.hang_up();
    ed.wait_exit();
    ed.wait_restored();
    assert!(!out.exists(), "nothing is saved until :w");
    let kept = grimace::io::pick_recovery::read(&recovery)
        .unwrap()
        .expect("a recovery file");
    assert_eq!(kept.picked(), 3);
    for l in [45, 42, 26] {
        assert_eq!(kept.picks[l], Some(preset[l]), "landmark {l}");
    }

    let mut ed = Term::grimace(dir.path(), &["landmarks", m, "--out", o], COLS, ROWS);
    ed.wait_for("Take them back? (y/n)");
    ed.send("y");
    let screen = ed.wait_for("recovered 3 picks");
    assert!(screen.contains("Landmark 22: "), "{screen}");
    assert!(screen.contains("3 of 68 picked"), "{screen}");
    // Leaving without saving asks, and a yes gives the picks up.
    ed.send("q");
    ed.wait_for("Quit anyway? (y/n)");
    ed.send("y");
    assert!(ed.wait_exit().success());
    assert!(!out.exists());
    assert!(!recovery.exists());
}

#[test]
fn a_bad_mesh_stops_with_its_place_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("bad.obj"),
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n",
    )
    .unwrap();
    std::fs::write(dir.path().join("flat.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\n").unwrap();
    for (mesh, expected) in [
        ("bad.obj", "bad.obj:4:"),
        ("flat.obj", "flat.obj: the mesh has no faces"),
        ("missing.obj", "missing.obj"),
    ] {
        let run = common::grimace_in(dir.path(), &["landmarks", mesh, "--out", "x.landmarks.ron"]);
        let stderr = String::from_utf8_lossy(&run.stderr);
        assert_eq!(run.status.code(), Some(1), "{mesh}: {stderr}");
        assert!(stderr.contains(expected), "{mesh}: {stderr}");
        let run = common::grimace_in(
            dir.path(),
            &["fit-rig", mesh, "--pick", "--out", "x.rig.ron"],
        );
        assert_eq!(run.status.code(), Some(1), "{mesh}");
    }
    let mut left: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    left.sort();
    assert_eq!(left, ["bad.obj", "flat.obj"], "nothing written");
}

#[test]
fn fit_rig_pick_saves_the_landmarks_then_writes_a_rig() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = dir.path().join("face.obj");
    std::fs::copy(face_obj(), &mesh).unwrap();
    let landmarks = dir.path().join("face.landmarks.ron");
    let rig = dir.path().join("face.rig.ron");
    let preset = preset();
    let mut app = planner(&mesh, &landmarks);
    let (m, r) = (mesh.to_str().unwrap(), rig.to_str().unwrap());
    let mut ed = Term::grimace(
        dir.path(),
        &["fit-rig", m, "--pick", "--out", r],
        COLS,
        ROWS,
    );
    ed.wait_for("Landmark 45: ");
    pick(&mut ed, &mut app, &preset, COUNT);
    ed.send(":wq\r");
    assert!(ed.wait_exit().success(), "{}", ed.screen());
    assert_eq!(
        grimace::io::landmarks::load_landmarks(&landmarks).unwrap(),
        Landmarks::Vertices(preset)
    );
    let loaded = grimace::io::load_rig(&rig).unwrap();
    assert!(!loaded.rig.muscles.is_empty());

    // Leaving the picker without saving fits nothing.
    let other = dir.path().join("other.rig.ron");
    let fresh = dir.path().join("new.landmarks.ron");
    let (o, f) = (other.to_str().unwrap(), fresh.to_str().unwrap());
    let mut ed = Term::grimace(
        dir.path(),
        &["fit-rig", m, "--pick", "--landmarks", f, "--out", o],
        COLS,
        ROWS,
    );
    ed.wait_for("Landmark 45: ");
    ed.send("q");
    assert!(!ed.wait_exit().success());
    assert!(!other.exists() && !fresh.exists());
}

#[test]
fn a_landmark_file_changed_on_disk_is_replaced_only_when_confirmed() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("face.landmarks.ron");
    let preset_file =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("presets/default.landmarks.ron");
    std::fs::copy(&preset_file, &out).unwrap();
    let mesh = face_obj();
    let (m, o) = (mesh.to_str().unwrap(), out.to_str().unwrap());
    let mut ed = Term::grimace(dir.path(), &["landmarks", m, "--out", o], COLS, ROWS);
    ed.wait_for("loaded");
    // Someone else changes the file meanwhile.
    let theirs = format!(
        "{}// corrected by a colleague\n",
        std::fs::read_to_string(&preset_file).unwrap()
    );
    std::fs::write(&out, &theirs).unwrap();
    ed.send(":w\r");
    let screen = ed.wait_for("Overwrite it? (y/n)");
    assert!(screen.contains("changed on disk since it"), "{screen}");
    ed.send("n");
    ed.wait_for("the file on disk is kept");
    assert_eq!(std::fs::read_to_string(&out).unwrap(), theirs);
    ed.send(":w\r");
    ed.wait_for("Overwrite it? (y/n)");
    ed.send("y");
    ed.wait_for("saved");
    // Saved once, the picker's own file is saved again without asking.
    ed.send(":wq\r");
    assert!(ed.wait_exit().success());
    let written = grimace::io::landmarks::load_landmarks(&out).unwrap();
    assert_eq!(written, Landmarks::Vertices(preset()));
}

#[test]
fn a_points_file_saved_unchanged_stays_the_same_points() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("face.landmarks.ron");
    let mesh = face_obj();
    let loaded = grimace::io::obj::read_obj(&mesh).unwrap();
    // Points a little off their vertices, as a scan's landmarks are.
    let points: Vec<glam::Vec3> = preset()
        .iter()
        .map(|&v| loaded.positions[v as usize] + glam::Vec3::new(0.01, -0.02, 0.005))
        .collect();
    let original = Landmarks::Points(points);
    std::fs::write(&out, grimace::io::landmarks::landmarks_to_ron(&original)).unwrap();
    let (m, o) = (mesh.to_str().unwrap(), out.to_str().unwrap());
    let mut ed = Term::grimace(dir.path(), &["landmarks", m, "--out", o], COLS, ROWS);
    ed.wait_for("loaded");
    ed.send(":wq\r");
    assert!(ed.wait_exit().success());
    assert_eq!(
        grimace::io::landmarks::load_landmarks(&out).unwrap(),
        original
    );
}
