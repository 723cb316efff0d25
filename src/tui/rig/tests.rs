use super::*;
use crate::tui::fixture;
use crate::tui::update::update as run;

fn rig_app() -> App {
    let mut app = fixture::app();
    run(&mut app, Action::Rig(RigAction::Toggle));
    app
}

fn linear(app: &App, i: usize) -> crate::model::Linear {
    match &app.rig().muscles[i].kind {
        MuscleKind::Linear(l) => l.clone(),
        other => panic!("{other:?}"),
    }
}

#[test]
fn the_selected_muscle_is_held_and_released() {
    let mut app = fixture::app();
    let rest = app.doc.face.positions().to_vec();
    run(&mut app, Action::Rig(RigAction::Toggle));
    assert_ne!(app.doc.face.positions(), rest.as_slice());
    assert!(app.doc.activations.is_rest(), "holding is not an edit");
    run(&mut app, Action::Rig(RigAction::Toggle));
    assert_eq!(app.doc.face.positions(), rest.as_slice());
}

#[test]
fn moving_a_point_goes_right_in_the_front_view_and_undoes() {
    let mut app = rig_app();
    let Row::Muscle(i) = app.selected_row() else {
        panic!("a muscle is selected first")
    };
    let before = linear(&app, i);
    run(
        &mut app,
        Action::Rig(RigAction::Move {
            right: 1,
            up: 0,
            coarse: true,
        }),
    );
    let after = linear(&app, i);
    let step = face_size(&app) * COARSE_FRACTION;
    assert_ne!(after, before, "{:?}", app.message);
    assert!((after.attachment.x - before.attachment.x - step).abs() < 1e-6);
    assert_eq!(after.attachment.y, before.attachment.y);
    assert_eq!(after.insertion, before.insertion);
    assert!(app.rig_edit.dirty(app.rig()));
    run(&mut app, Action::Undo);
    assert_eq!(linear(&app, i), before);
    run(&mut app, Action::Redo);
    assert_eq!(linear(&app, i), after);
}

#[test]
fn mirror_mode_moves_the_partner_the_other_way() {
    let mut app = rig_app();
    let Row::Muscle(i) = app.selected_row() else {
        panic!()
    };
    let p = app.rig().mirror_of(i).expect("fixture pair");
    let before = linear(&app, p);
    run(&mut app, Action::ToggleMirror);
    run(
        &mut app,
        Action::Rig(RigAction::Move {
            right: 1,
            up: 1,
            coarse: false,
        }),
    );
    let step = face_size(&app) * FINE_FRACTION;
    let after = linear(&app, p);
    assert!((after.attachment.x - (before.attachment.x - step)).abs() < 1e-6);
    assert!((after.attachment.y - (before.attachment.y + step)).abs() < 1e-6);
}

#[test]
fn an_invalid_value_is_refused_with_the_reason() {
    let mut app = rig_app();
    let Row::Muscle(i) = app.selected_row() else {
        panic!()
    };
    let before = app.rig().clone();
    // The zone must stay below 90 degrees.
    for _ in 0..20 {
        run(
            &mut app,
            Action::Rig(RigAction::Param {
                by: 1,
                coarse: true,
            }),
        );
    }
    let zone = linear(&app, i).zone;
    assert!((85.0..90.0).contains(&zone), "{zone}");
    let message = app.message.clone().unwrap();
    assert_eq!(message.severity, crate::tui::app::Severity::Error);
    assert!(message.text.contains("zone"), "{}", message.text);
    assert_ne!(app.rig(), &before);
}

#[test]
fn write_and_quit_does_not_leave_an_unsaved_rig_behind() {
    let mut app = rig_app();
    let step = Action::Rig(RigAction::Move {
        right: 0,
        up: 1,
        coarse: false,
    });
    run(&mut app, step);
    let fx = run(&mut app, Action::Command("wq".into()));
    assert!(!fx.contains(&Effect::Quit), "{fx:?}");
    assert_eq!(app.message.as_ref().unwrap().text, UNSAVED_RIG);
    // Plain quit asks.
    run(&mut app, Action::Quit);
    assert!(matches!(app.mode, Mode::Confirm(_)));
}

#[test]
fn the_zone_overlay_follows_the_kind() {
    use crate::render::Shape;
    let mut app = rig_app();
    let mut out = Vec::new();
    crate::tui::view::rig::zone_overlays(&app, &mut out);
    // A linear muscle: two cone edges, two arcs of segments, and the point's mark.
    assert!(out.len() > 5, "{}", out.len());
    assert!(matches!(out.last().unwrap().shape, Shape::Point { .. }));
    let last = app.selection.rows.len() - 1;
    app.selection.selected = last; // the jaw
    out.clear();
    crate::tui::view::rig::zone_overlays(&app, &mut out);
    let jaw = app.rig().jaw.as_ref().unwrap();
    // One coloured mark per weighted vertex, the axis line and the pivot's mark.
    assert_eq!(out.len(), jaw.weights.len() + 2);
}

fn select(app: &mut App, name: &str) -> usize {
    let i = app.rig().muscle_index(name).expect("the muscle");
    run(app, Action::SelectRow(Row::Muscle(i)));
    assert_eq!(app.selected_row(), Row::Muscle(i));
    i
}

fn param(app: &mut App, by: i8, coarse: bool) {
    run(app, Action::Rig(RigAction::Param { by, coarse }));
}

fn sphincter(app: &App, i: usize) -> crate::model::Sphincter {
    match &app.rig().muscles[i].kind {
        MuscleKind::Sphincter(s) => s.clone(),
        other => panic!("{other:?}"),
    }
}

/// The default face in an editor, rig mode on.
fn default_app() -> App {
    let (rig, mesh, table) = crate::cli::edit::default_face().expect("the built-in face");
    let scene = crate::tui::face::Face::new(rig, mesh).expect("binds");
    let mut app = App::new(scene, table, None);
    run(&mut app, Action::Rig(RigAction::Toggle));
    app
}

/// The rig as bound from scratch deforms the held face exactly as the rebound one.
fn assert_bound_as_from_scratch(app: &App) {
    let scratch = crate::model::Deformation::default()
        .bind(app.rig(), app.doc.face.mesh())
        .unwrap();
    let activations = held_activations(app, app.selected_row(), app.rig_edit.held);
    let mut out = Vec::new();
    scratch.deform(&activations, &mut out).unwrap();
    let bits = |p: &[Vec3]| -> Vec<[u32; 3]> {
        p.iter().map(|v| v.to_array().map(f32::to_bits)).collect()
    };
    assert_eq!(bits(app.doc.face.positions()), bits(&out));
}

#[test]
fn the_sphincter_frame_turns_about_the_view_and_mirrors_and_undoes() {
    let mut app = default_app();
    let l = select(&mut app, "L_Orbicularis_Oculi");
    let r = app.rig().mirror_of(l).expect("the eyes are a pair");
    let (l0, r0) = (sphincter(&app, l), sphincter(&app, r));
    run(&mut app, Action::ToggleMirror);
    run(&mut app, Action::Rig(RigAction::NextParam));
    run(&mut app, Action::Rig(RigAction::NextParam));
    run(&mut app, Action::Rig(RigAction::NextParam));
    assert!(describe(&app).contains("frame angle"), "{}", describe(&app));
    let angle_l = view_angle(&app, l0.frame.axis_x()).unwrap();
    let angle_r = view_angle(&app, r0.frame.axis_x()).unwrap();
    param(&mut app, 1, true);
    let (l1, r1) = (sphincter(&app, l), sphincter(&app, r));
    // Counter-clockwise on screen by 5 degrees; the partner clockwise by as much.
    let turned_l = view_angle(&app, l1.frame.axis_x()).unwrap();
    let turned_r = view_angle(&app, r1.frame.axis_x()).unwrap();
    assert!(
        (turned_l - angle_l - 5.0).abs() < 1e-3,
        "{angle_l} -> {turned_l}"
    );
    assert!(
        (turned_r - angle_r + 5.0).abs() < 1e-3,
        "{angle_r} -> {turned_r}"
    );
    assert!(app.message.as_ref().unwrap().text.contains("deg"));
    // The frame stays a frame: the ellipse keeps its plane's normal facing the viewer.
    assert!(l1.frame.check().is_ok());
    assert_eq!((l1.centre, l1.semi_major), (l0.centre, l0.semi_major));
    assert_bound_as_from_scratch(&app);
    run(&mut app, Action::Undo);
    assert_eq!((sphincter(&app, l), sphincter(&app, r)), (l0, r0));
    assert_bound_as_from_scratch(&app);
    run(&mut app, Action::Redo);
    assert_eq!((sphincter(&app, l), sphincter(&app, r)), (l1, r1));
}

#[test]
fn the_jaw_pivot_axis_and_degrees_change_and_undo_in_order() {
    let mut app = rig_app();
    run(&mut app, Action::SelectRow(Row::Jaw));
    let jaw0 = app.rig().jaw.clone().unwrap();
    // The side view looks along the axis: turning it is refused with the reason.
    run(&mut app, Action::Preset(crate::tui::app::ViewPreset::Side));
    run(&mut app, Action::Rig(RigAction::NextParam));
    assert!(
        describe(&app).contains("axis angle along the view"),
        "{}",
        describe(&app)
    );
    param(&mut app, 1, false);
    assert_eq!(app.rig().jaw.as_ref(), Some(&jaw0));
    assert!(app
        .message
        .as_ref()
        .unwrap()
        .text
        .contains("along the view"));
    assert!(app.history.undo.is_empty());
    run(&mut app, Action::Preset(crate::tui::app::ViewPreset::Front));
    run(
        &mut app,
        Action::Rig(RigAction::Move {
            right: 0,
            up: 1,
            coarse: false,
        }),
    );
    let step = face_size(&app) * FINE_FRACTION;
    let jaw1 = app.rig().jaw.clone().unwrap();
    assert!((jaw1.pivot.y - jaw0.pivot.y - step).abs() < 1e-6);
    run(&mut app, Action::Rig(RigAction::NextParam));
    param(&mut app, 1, false); // degrees per unit, by 0.1
    let jaw2 = app.rig().jaw.clone().unwrap();
    assert!((jaw2.degrees_per_unit - jaw0.degrees_per_unit - 0.1).abs() < 1e-6);
    run(&mut app, Action::Rig(RigAction::NextParam));
    assert!(
        describe(&app).contains("axis angle 0.0 deg"),
        "{}",
        describe(&app)
    );
    param(&mut app, -2, false); // the axis, 2 degrees clockwise in the front view
    let jaw3 = app.rig().jaw.clone().unwrap();
    let tilt = jaw3.axis.y.atan2(jaw3.axis.x).to_degrees();
    assert!((tilt + 2.0).abs() < 1e-4, "{tilt}");
    assert_eq!(jaw3.weights, jaw0.weights);
    assert_bound_as_from_scratch(&app);
    // Undo goes back through the three jaw changes in the order made.
    for want in [&jaw2, &jaw1, &jaw0] {
        run(&mut app, Action::Undo);
        assert_eq!(app.rig().jaw.as_ref(), Some(want));
    }
    assert_bound_as_from_scratch(&app);
}

#[test]
fn one_history_undoes_rig_and_activation_edits_in_the_order_made() {
    let mut app = rig_app();
    let Row::Muscle(i) = app.selected_row() else {
        panic!()
    };
    let rig0 = app.rig().clone();
    let act0 = app.doc.activations.clone();
    run(&mut app, Action::StepCoarse(1)); // an activation edit of the selected muscle
    let act1 = app.doc.activations.clone();
    assert_ne!(act1, act0);
    run(
        &mut app,
        Action::Rig(RigAction::Move {
            right: 1,
            up: 0,
            coarse: false,
        }),
    );
    let rig1 = app.rig().clone();
    run(&mut app, Action::StepCoarse(1)); // a second activation edit, after the rig's
    let act2 = app.doc.activations.clone();
    assert_ne!(act2, act1);
    run(&mut app, Action::Undo);
    assert_eq!((app.rig(), &app.doc.activations), (&rig1, &act1));
    run(&mut app, Action::Undo);
    assert_eq!((app.rig(), &app.doc.activations), (&rig0, &act1));
    let text = &app.message.as_ref().unwrap().text;
    assert!(
        text.starts_with(&format!(
            "undone the rig change to {} attachment",
            app.row_name(Row::Muscle(i))
        )),
        "{text}"
    );
    run(&mut app, Action::Undo);
    assert_eq!((app.rig(), &app.doc.activations), (&rig0, &act0));
    run(&mut app, Action::Undo);
    assert_eq!(app.message.as_ref().unwrap().text, "nothing to undo");
    for (rig, act) in [(&rig0, &act1), (&rig1, &act1), (&rig1, &act2)] {
        run(&mut app, Action::Redo);
        assert_eq!((app.rig(), &app.doc.activations), (rig, act));
    }
    // Leaving rig mode and undoing a rig change shows the face with the rig as it was.
    run(&mut app, Action::Undo);
    run(&mut app, Action::Undo);
    run(&mut app, Action::Rig(RigAction::Toggle));
    run(&mut app, Action::Undo);
    assert_eq!(app.rig(), &rig0);
    let scratch = crate::model::Deformation::default()
        .bind(&rig0, app.doc.face.mesh())
        .unwrap();
    let mut out = Vec::new();
    scratch.deform(&app.doc.activations, &mut out).unwrap();
    assert_eq!(app.doc.face.positions(), out.as_slice());
}

#[test]
fn every_kind_of_change_rebinds_as_binding_from_scratch() {
    let mut app = default_app();
    run(&mut app, Action::ToggleMirror);
    for name in [
        "L_Zygomatic_Major",
        "L_Orbicularis_Oculi",
        "L_Frontalis_Sheet",
    ] {
        select(&mut app, name);
        for _ in 0..4 {
            run(&mut app, Action::Rig(RigAction::NextPoint));
            run(
                &mut app,
                Action::Rig(RigAction::Move {
                    right: 1,
                    up: -1,
                    coarse: false,
                }),
            );
            run(&mut app, Action::Rig(RigAction::NextParam));
            param(&mut app, 1, false);
            assert_bound_as_from_scratch(&app);
        }
    }
}

#[test]
fn a_built_in_rig_asks_for_a_file_name() {
    let mut app = rig_app();
    let mut fx = Vec::new();
    save(&mut app, None, &mut fx);
    assert!(fx.is_empty());
    assert!(matches!(&app.mode, Mode::Input(i) if i.text == "w "));
    save(&mut app, Some(PathBuf::from("a.rig.ron")), &mut fx);
    assert!(matches!(&fx[..], [Effect::SaveRig { expected: None, .. }]));
}
