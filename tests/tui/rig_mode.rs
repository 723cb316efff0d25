//! Rig mode in the real binary: move the zygomatic's attachment, turn the jaw's axis and an
//! eye's frame (mirror mode turning its partner), undo rig and activation edits in the order
//! made, save the rig under a new name (the built-in rig has no file), reload it and find the
//! new numbers.

use std::path::Path;

use grimace::io::load::{load_rig, load_rig_ref};
use grimace::model::MuscleKind;

use crate::common::pty::Term;

fn attachment(rig: &grimace::model::Rig, name: &str) -> glam::Vec3 {
    let i = rig.muscle_index(name).expect("the muscle");
    match &rig.muscles[i].kind {
        MuscleKind::Linear(m) => m.attachment,
        other => panic!("{name} is {other:?}"),
    }
}

#[test]
fn move_a_zygomatic_attachment_save_and_reload() {
    let dir = tempfile::tempdir().unwrap();
    let table = dir.path().join("t.au.ron");
    let rig_file = dir.path().join("mine.rig.ron");
    let builtin = load_rig_ref(Path::new("builtin:default"), None).unwrap();
    let before = attachment(&builtin.rig, "L_Zygomatic_Major");
    let (lo, hi) = builtin.mesh.bounds();
    let coarse = (hi - lo).y * grimace::tui::rig::COARSE_FRACTION;
    let fine = (hi - lo).y * grimace::tui::rig::FINE_FRACTION;

    let mut ed = Term::grimace(dir.path(), &["edit", table.to_str().unwrap()], 200, 60);
    ed.wait_for("new table");
    ed.send("R");
    ed.wait_for("L_Zygomatic_Major held at 1.00: attachment");
    // Two coarse steps right (Shift-Right), one fine step up.
    ed.send("\x1b[1;2C");
    ed.send("\x1b[1;2C");
    ed.send("\x1b[A");
    let expected = before + glam::Vec3::new(2.0 * coarse, fine, 0.0);
    let shown = format!("({:.4}, {:.4}, {:.4})", expected.x, expected.y, expected.z);
    ed.wait_for(&shown);
    // The built-in rig has no file: `:w` asks for one.
    ed.send(":w\r");
    ed.wait_for("type a file name");
    ed.send(&format!("{}\r", rig_file.display()));
    // The table goes with the rig: it now names the file, so it has a change to save.
    ed.wait_for("the table now names it");
    ed.send(":wq\r");
    assert!(ed.wait_exit().success());
    ed.wait_restored();
    let written = std::fs::read_to_string(&table).unwrap();
    assert!(written.contains("rig: \"mine.rig.ron\""), "{written}");

    let saved = load_rig(&rig_file).expect("the saved rig loads").rig;
    let after = attachment(&saved, "L_Zygomatic_Major");
    assert!(
        (after - expected).abs().max_element() < 1e-5,
        "{after} vs {expected}"
    );
    // Nothing else moved.
    assert_eq!(
        attachment(&saved, "R_Zygomatic_Major"),
        attachment(&builtin.rig, "R_Zygomatic_Major")
    );

    // Reloaded in the editor, rig mode shows the new numbers.
    let mut ed = Term::grimace(
        dir.path(),
        &[
            "edit",
            "--rig",
            rig_file.to_str().unwrap(),
            dir.path().join("u.au.ron").to_str().unwrap(),
        ],
        200,
        60,
    );
    ed.wait_for("new table");
    ed.send("R");
    ed.wait_for(&shown);
    ed.send(":q\r");
    assert!(ed.wait_exit().success());
}

#[test]
fn a_hangup_mid_edit_keeps_the_rig_and_the_next_launch_recovers_it() {
    let dir = tempfile::tempdir().unwrap();
    let table = dir.path().join("t.au.ron");
    let arg = table.to_str().unwrap();
    let builtin = load_rig_ref(Path::new("builtin:default"), None).unwrap();
    let before = attachment(&builtin.rig, "L_Zygomatic_Major");
    let (lo, hi) = builtin.mesh.bounds();
    let coarse = (hi - lo).y * grimace::tui::rig::COARSE_FRACTION;
    let expected = before + glam::Vec3::new(0.0, -coarse, 0.0);
    let shown = format!("({:.4}, {:.4}, {:.4})", expected.x, expected.y, expected.z);

    let mut ed = Term::grimace(dir.path(), &["edit", arg], 200, 60);
    ed.wait_for("new table");
    ed.send("R");
    ed.wait_for("held at 1.00");
    ed.send("\x1b[1;2B"); // Shift-Down: a coarse step down
    ed.wait_for(&shown);
    ed.hang_up();
    ed.wait_exit();
    ed.wait_restored();
    let recovery = dir.path().join(".t.au.ron.recover");
    let text = std::fs::read_to_string(&recovery).expect("a recovery file");
    assert!(text.contains("L_Zygomatic_Major"), "the rig is kept");

    let mut ed = Term::grimace(dir.path(), &["edit", arg], 200, 60);
    ed.wait_for("recover");
    ed.send("y");
    let screen = ed.wait_for("recovered");
    assert!(
        screen.contains("[+]"),
        "the recovered rig is unsaved: {screen}"
    );
    ed.send("R");
    ed.wait_for(&shown);
    // Undo goes back to the built-in rig's numbers.
    ed.send("u");
    ed.wait_for(&format!(
        "({:.4}, {:.4}, {:.4})",
        before.x, before.y, before.z
    ));
    ed.send(":q!\r");
    assert!(ed.wait_exit().success());
}

#[test]
fn turn_the_jaw_axis_then_undo_an_activation_and_the_turn_in_order() {
    let dir = tempfile::tempdir().unwrap();
    let table = dir.path().join("t.au.ron");
    let rig_file = dir.path().join("jaw.rig.ron");
    let builtin = load_rig_ref(Path::new("builtin:default"), None).unwrap();
    let jaw = builtin.rig.jaw.clone().expect("the default rig has a jaw");
    assert_eq!(jaw.axis, glam::Vec3::X, "the default jaw turns about x");

    let mut ed = Term::grimace(dir.path(), &["edit", table.to_str().unwrap()], 200, 60);
    ed.wait_for("new table");
    ed.send("/jaw\r");
    ed.wait_for("found jaw");
    ed.send("R");
    ed.wait_for("jaw held at 1.00: pivot");
    ed.send("p");
    ed.wait_for("axis angle 0.0 deg");
    ed.send("L"); // five degrees counter-clockwise on screen
    ed.wait_for("axis angle 5.0 deg");
    // An activation edit after the rig change, outside rig mode.
    ed.send("R");
    ed.wait_for("rig mode off");
    ed.send("l");
    ed.send("u");
    ed.wait_for("undone (1 more to undo)");
    ed.send("u");
    ed.wait_for("undone the rig change to jaw axis angle (0 more to undo)");
    ed.send("u");
    ed.wait_for("nothing to undo");
    ed.send("U");
    ed.wait_for("redone the rig change to jaw axis angle (1 more to redo)");
    ed.send("R");
    ed.wait_for("axis angle 5.0 deg");
    ed.send(&format!(":w {}\r", rig_file.display()));
    ed.wait_for("saved the rig");
    ed.send(":q!\r");
    assert!(ed.wait_exit().success());
    ed.wait_restored();

    let saved = load_rig(&rig_file).expect("the saved rig loads").rig;
    let axis = saved.jaw.expect("a jaw").axis;
    let want = glam::Vec3::new(5f32.to_radians().cos(), 5f32.to_radians().sin(), 0.0);
    assert!((axis - want).abs().max_element() < 1e-5, "{axis} vs {want}");
}

/// The keys that select a muscle of the built-in rig from the top of the list (a name search
/// would stop first at the longer names that contain it).
fn select_keys(name: &str) -> String {
    let (rig, mesh, table) = grimace::cli::edit::default_face().expect("the built-in face");
    let i = rig.muscle_index(name).expect("the muscle");
    let scene = grimace::tui::face::Face::new(rig, mesh).expect("binds");
    let app = grimace::tui::app::App::new(scene, table, None);
    let rows = &app.selection.rows;
    let at = rows
        .iter()
        .position(|r| *r == grimace::tui::app::Row::Muscle(i))
        .expect("listed");
    format!("g{}", "j".repeat(at))
}

#[test]
fn turn_an_eye_frame_in_mirror_mode_save_and_reload() {
    let dir = tempfile::tempdir().unwrap();
    let table = dir.path().join("t.au.ron");
    let rig_file = dir.path().join("eyes.rig.ron");

    let mut ed = Term::grimace(dir.path(), &["edit", table.to_str().unwrap()], 200, 60);
    ed.wait_for("new table");
    ed.send(&select_keys("L_Orbicularis_Oculi"));
    ed.send("R");
    ed.wait_for("L_Orbicularis_Oculi held at 1.00: centre");
    ed.send("m");
    ed.send("ppp");
    ed.wait_for("frame angle 0.0 deg");
    ed.send("H"); // five degrees clockwise; the right eye turns the other way
    ed.wait_for("frame angle -5.0 deg (and R_Orbicularis_Oculi)");
    ed.send(&format!(":w {}\r", rig_file.display()));
    ed.wait_for("the table now names it");
    ed.send(":q!\r");
    assert!(ed.wait_exit().success());
    ed.wait_restored();

    let saved = load_rig(&rig_file).expect("the saved rig loads").rig;
    let frame = |name: &str| match &saved.muscles[saved.muscle_index(name).unwrap()].kind {
        MuscleKind::Sphincter(s) => s.frame,
        other => panic!("{other:?}"),
    };
    let (l, r) = (frame("L_Orbicularis_Oculi"), frame("R_Orbicularis_Oculi"));
    let a = (-5f32).to_radians();
    let want = glam::Vec3::new(a.cos(), a.sin(), 0.0);
    assert!((l.axis_x() - want).abs().max_element() < 1e-5, "{l:?}");
    let mirrored = l.mirrored_x();
    assert!(
        (r.axis_x() - mirrored.axis_x()).abs().max_element() < 1e-5
            && (r.axis_y() - mirrored.axis_y()).abs().max_element() < 1e-5,
        "{r:?} mirrors {l:?}"
    );

    // Reloaded, rig mode shows the turned frame.
    let mut ed = Term::grimace(
        dir.path(),
        &[
            "edit",
            "--rig",
            rig_file.to_str().unwrap(),
            dir.path().join("u.au.ron").to_str().unwrap(),
        ],
        200,
        60,
    );
    ed.wait_for("new table");
    ed.send(&select_keys("R_Orbicularis_Oculi"));
    ed.send("Rppp");
    ed.wait_for("frame angle 5.0 deg");
    ed.send(":q\r");
    assert!(ed.wait_exit().success());
}

/// Rig mode's save-as chain on a fitted head: `:w sub/a.rig.ron`, another change, `:w`,
/// then the table: every file written names the others relative to where it lies, and all
/// of them load from another working directory.
#[test]
fn save_as_chains_write_references_that_load_from_anywhere() {
    use crate::common::grimace_in;
    let dir = tempfile::tempdir().unwrap();
    let root = std::fs::canonicalize(dir.path()).unwrap();
    for folder in ["meshes", "rigs", "sub"] {
        std::fs::create_dir_all(root.join(folder)).unwrap();
    }
    let ok = |out: std::process::Output| {
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
    };
    ok(grimace_in(&root, &["export", "--out", "meshes/head.obj"]));
    std::fs::copy(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("presets/default.landmarks.ron"),
        root.join("meshes/head.landmarks.ron"),
    )
    .unwrap();
    ok(grimace_in(
        &root,
        &[
            "fit-rig",
            "meshes/head.obj",
            "--landmarks",
            "meshes/head.landmarks.ron",
            "--out",
            "rigs/head.rig.ron",
        ],
    ));

    let mut ed = Term::grimace(
        &root,
        &["edit", "--rig", "rigs/head.rig.ron", "t.au.ron"],
        200,
        60,
    );
    ed.wait_for("new table");
    ed.send("R");
    ed.wait_for("held at 1.00: attachment");
    ed.send("\x1b[1;2C");
    ed.send(":w sub/a.rig.ron\r");
    ed.wait_for("the table now names it");
    // The second save goes to the new file, which lies in another folder than the first.
    ed.send("\x1b[1;2C");
    ed.send(":w\r");
    ed.wait_for("saved the rig to sub/a.rig.ron");
    // Saving the rig onto the mesh is refused for what it is.
    ed.send(":w meshes/head.obj\r");
    ed.wait_for("an input of this command");
    ed.send("R");
    ed.wait_for("rig mode off");
    ed.send(":wq\r");
    assert!(ed.wait_exit().success());
    ed.wait_restored();

    let rig = std::fs::read_to_string(root.join("sub/a.rig.ron")).unwrap();
    assert!(rig.contains("mesh: \"../meshes/head.obj\""), "{rig}");
    let table = std::fs::read_to_string(root.join("t.au.ron")).unwrap();
    assert!(table.contains("rig: \"sub/a.rig.ron\""), "{table}");
    let elsewhere = tempfile::tempdir().unwrap();
    let out = elsewhere.path().join("x.obj");
    ok(grimace_in(
        elsewhere.path(),
        &[
            "export",
            "--table",
            root.join("t.au.ron").to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ],
    ));
    ok(grimace_in(
        elsewhere.path(),
        &[
            "export",
            "--rig",
            root.join("sub/a.rig.ron").to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ],
    ));
}
