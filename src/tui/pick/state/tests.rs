use super::*;
use crate::tui::pick::{LEFT, MIDLINE, MINIMAL};

fn preset() -> Vec<u32> {
    let mesh = crate::io::builtin::default_mesh();
    crate::io::builtin::landmarks("face")
        .unwrap()
        .vertices(&mesh)
}

fn picker(mesh: Mesh) -> PickApp {
    PickApp::new(
        mesh,
        PathBuf::from("face.obj"),
        PathBuf::from("face.landmarks.ron"),
        (120, 40),
        CellMode::Braille,
    )
}

/// Takes vertex `v` for the current landmark, as if the cursor had been moved there.
fn take(app: &mut PickApp, v: u32) -> Vec<PickEffect> {
    app.snapped = Some(v);
    app.update(PickAction::Confirm)
}

#[test]
fn a_conflict_asks_and_yes_saves_anyway() {
    let mut app = picker(crate::io::builtin::default_mesh());
    for v in preset() {
        take(&mut app, v);
    }
    assert_eq!(app.update(PickAction::SaveConflict(true)), Vec::new());
    assert_eq!(
        app.mode,
        Mode::Confirm(Question::Overwrite { quit_after: true })
    );
    let effects = app.update(PickAction::Answer(true));
    assert!(
        matches!(
            &effects[..],
            [PickEffect::Save {
                force: true,
                quit_after: true,
                ..
            }]
        ),
        "{effects:?}"
    );
}

#[test]
fn a_set_that_fit_rig_would_refuse_is_not_saved() {
    let mut app = picker(crate::io::builtin::default_mesh());
    let v = preset()[30];
    while app.current.is_some() {
        take(&mut app, v);
    }
    assert_eq!(app.update(PickAction::Save), Vec::new());
    let message = &app.message.as_ref().unwrap().text;
    assert!(message.starts_with("not saved:"), "{message}");
    assert!(app.dirty, "the picks are kept");
}

#[test]
fn the_cursor_moves_by_cells_and_snaps_to_the_nearest_visible_vertex() {
    let mut app = picker(crate::io::builtin::default_mesh());
    let before = app.cursor;
    app.update(PickAction::Move(3, -2));
    let screen = app.screen.clone().unwrap();
    assert_eq!(app.cursor - before, glam::Vec2::new(6.0, -8.0));
    let v = app.snapped.unwrap();
    assert!(screen.visible[v as usize]);
    // No visible vertex is nearer the cursor on the screen.
    let d = |w: u32| {
        let p = screen.dot_of(w).unwrap() - app.cursor;
        glam::Vec2::new(p.x * screen.aspect, p.y).length()
    };
    for w in 0..app.mesh.vertex_count() as u32 {
        if screen.visible[w as usize] {
            assert!(d(w) >= d(v), "vertex {w} is nearer than {v}");
        }
    }
    // Turned to show its left profile, the right eye's corners cannot be picked.
    let preset = preset();
    assert!(screen.visible[preset[36] as usize] && screen.visible[preset[39] as usize]);
    let mut side = app.clone();
    side.update(PickAction::Turn(75.0, 0.0));
    let turned = side.screen.as_ref().unwrap();
    assert!(!turned.visible[preset[36] as usize] && !turned.visible[preset[39] as usize]);
    assert!(turned.visible[preset[45] as usize]);
    // Pushing past the edge moves the view, not the cursor off the viewport.
    let pan = app.camera.pan;
    for _ in 0..100 {
        app.update(PickAction::Move(-COARSE, 0));
    }
    assert!(app.cursor.x >= 0.0 && app.camera.pan.x < pan.x);
}

#[test]
fn confirm_records_the_vertex_and_undo_takes_it_back() {
    let mut app = picker(crate::io::builtin::default_mesh());
    assert_eq!(app.current, Some(LEFT[0]));
    app.update(PickAction::Move(1, 1));
    let v = app.snapped.unwrap();
    let effects = app.update(PickAction::Confirm);
    assert_eq!(effects, vec![PickEffect::WriteRecovery]);
    assert_eq!(app.picks[LEFT[0]], Some(v));
    assert_eq!(app.current, Some(LEFT[1]));
    assert!(app.dirty);
    app.update(PickAction::Undo);
    assert_eq!(app.picks[LEFT[0]], None);
    assert_eq!(app.current, Some(LEFT[0]));
    assert_eq!(
        app.update(PickAction::Undo),
        Vec::new(),
        "nothing left to undo"
    );
}

#[test]
fn skipped_landmarks_come_back_after_the_others() {
    let mut app = picker(crate::io::builtin::default_mesh());
    app.update(PickAction::Skip);
    assert!(app.skipped[LEFT[0]]);
    assert_eq!(app.current, Some(LEFT[1]));
    // Undo brings the skipped landmark back as it was.
    app.update(PickAction::Undo);
    assert_eq!((app.current, app.skipped[LEFT[0]]), (Some(LEFT[0]), false));
    app.update(PickAction::Skip);
    let preset = preset();
    for _ in 1..COUNT {
        let l = app.current.unwrap();
        take(&mut app, preset[l]);
    }
    assert_eq!(
        app.current,
        Some(LEFT[0]),
        "the skipped one is asked for last"
    );
    // The save is refused while it has no vertex.
    assert_eq!(app.update(PickAction::Save), Vec::new());
    assert!(app.message.as_ref().unwrap().text.contains("45"));
    take(&mut app, preset[LEFT[0]]);
    assert_eq!(app.current, None);
    let effects = app.update(PickAction::Save);
    assert_eq!(
        effects,
        vec![PickEffect::Save {
            landmarks: Landmarks::Vertices(preset.clone()),
            quit_after: false,
            force: false,
        }]
    );
    // n and p go through the picked landmarks, the cursor on each one's vertex.
    app.update(PickAction::Step(1));
    assert_eq!(app.current, Some(LEFT[0]));
    assert_eq!(app.snapped, Some(preset[LEFT[0]]));
    app.update(PickAction::Step(-1));
    assert_eq!(app.current, Some(crate::tui::pick::order()[COUNT - 1]));
}

#[test]
fn the_right_side_is_proposed_by_symmetry_and_the_rest_by_the_warp() {
    let preset = preset();
    // The default face turned and moved: the mirror plane is not x = 0.
    let mut mesh = crate::io::builtin::default_mesh();
    let turn = glam::Quat::from_rotation_y(0.4) * glam::Quat::from_rotation_x(0.2);
    for p in &mut mesh.positions {
        *p = turn * *p + Vec3::new(3.0, -1.0, 2.0);
    }
    let mut app = picker(mesh);
    for &l in LEFT.iter().chain(&MIDLINE) {
        assert_eq!(app.current, Some(l));
        assert_eq!(
            app.proposals[l], None,
            "nothing proposed before the left half"
        );
        take(&mut app, preset[l]);
    }
    for &l in &MINIMAL[11..] {
        assert_eq!(app.current, Some(l));
        assert_eq!(app.proposals[l], Some((preset[l], Source::Mirror)), "{l}");
        assert_eq!(
            app.snapped,
            Some(preset[l]),
            "the cursor is on the proposal"
        );
        app.update(PickAction::Confirm);
    }
    // After the minimal set, every other landmark is proposed: exactly the preset's.
    for (l, &v) in preset.iter().enumerate() {
        if app.picks[l].is_none() {
            assert_eq!(app.proposals[l].map(|p| p.0), Some(v), "{l}");
        }
    }
    while let Some(l) = app.current {
        assert_eq!(app.snapped, Some(preset[l]));
        app.update(PickAction::Confirm);
    }
    assert_eq!(
        app.picks,
        preset.iter().map(|&v| Some(v)).collect::<Vec<_>>()
    );
}

#[test]
fn quitting_with_unsaved_picks_asks_and_commands_run() {
    let mut app = picker(crate::io::builtin::default_mesh());
    assert_eq!(app.update(PickAction::Quit), vec![PickEffect::Quit]);
    app.update(PickAction::Move(0, 1));
    app.update(PickAction::Confirm);
    assert_eq!(app.update(PickAction::Quit), Vec::new());
    assert_eq!(app.mode, Mode::Confirm(Question::Quit));
    assert_eq!(app.update(PickAction::Answer(false)), Vec::new());
    assert_eq!(app.mode, Mode::Normal);
    app.update(PickAction::Command);
    for c in "q!".chars() {
        app.update(PickAction::Input(c));
    }
    assert_eq!(
        app.update(PickAction::Submit),
        vec![PickEffect::RemoveRecovery, PickEffect::Quit]
    );
    app.update(PickAction::Command);
    app.update(PickAction::Input('z'));
    app.update(PickAction::Submit);
    assert!(app
        .message
        .as_ref()
        .unwrap()
        .text
        .contains("unknown command"));
}

#[test]
fn a_click_puts_the_cursor_on_the_cell_and_snaps() {
    let mut app = picker(crate::io::builtin::default_mesh());
    let preset = preset();
    let area = app.viewport();
    let screen = app.screen.clone().unwrap();
    let (col, row) = screen.cell_of(screen.dot_of(preset[30]).unwrap()).unwrap();
    app.update(PickAction::Click(area.x + col, area.y + row));
    assert_eq!(app.cursor, screen.cell_centre(col, row));
    let v = app.snapped.unwrap();
    assert_eq!(screen.cell_of(screen.dot_of(v).unwrap()), Some((col, row)));
    // Outside the mesh's viewport a click does nothing.
    app.update(PickAction::Click(area.right() + 2, area.y + 1));
    assert_eq!(app.snapped, Some(v));
}

#[test]
fn turning_keeps_the_cursor_on_its_vertex_and_zoom_keeps_it_in_place() {
    let mut app = picker(crate::io::builtin::default_mesh());
    app.update(PickAction::Move(4, -3));
    let v = app.snapped.unwrap();
    let at = app.cursor;
    app.update(PickAction::Zoom(ZOOM_STEP));
    assert_eq!(app.snapped, Some(v));
    let moved = app.screen.as_ref().unwrap().dot_of(v).unwrap();
    assert!(
        moved.distance(at) > 0.5,
        "the vertex moves away from the cursor's point"
    );
    assert!(
        app.cursor.distance(moved) < 1e-3,
        "the cursor sits on its vertex"
    );
    app.update(PickAction::Turn(TURN_DEGREES, 0.0));
    assert!((app.camera.yaw.to_degrees() - TURN_DEGREES).abs() < 1e-4);
    if let Some(v) = app.snapped {
        assert!(app.screen.as_ref().unwrap().visible[v as usize]);
    }
    app.update(PickAction::ResetView);
    assert_eq!(app.camera, Camera::front());
}

/// A bust known by its shape alone opens with its head filling the view: the head's crown
/// and the neck's top land near the screen's top and bottom, the shoulders off it.
#[test]
fn a_bust_opens_with_its_head_filling_the_view() {
    let bust = crate::render::framing::column(&[
        (10.0, 0.3),
        (9.0, 1.0),
        (8.0, 1.0),
        (7.0, 0.9),
        (6.5, 0.5),
        (6.0, 0.5),
        (5.5, 2.5),
        (0.0, 2.5),
    ]);
    let app = picker(bust);
    let screen = app.screen.as_ref().unwrap();
    let row = |v: u32| screen.dot_of(v).unwrap().y / screen.height as f32;
    // Rings of 16 vertices: the crown is ring 0, the neck's top ring 4, the chest ring 7.
    assert!(row(0) < 0.2, "crown at {}", row(0));
    assert!(row(4 * 16) > 0.8, "neck at {}", row(4 * 16));
    assert!(
        row(7 * 16) > 1.0,
        "the chest is off the view: {}",
        row(7 * 16)
    );
}
