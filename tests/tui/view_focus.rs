//! Zooming in centres the picture on the selected muscle's region, or on the mouth.

use glam::Vec3;
use grimace::model::MuscleKind;
use grimace::tui::action::Action;
use grimace::tui::app::{App, Row};
use grimace::tui::face::Face;
use grimace::tui::update::update;

fn app() -> App {
    let (rig, mesh, table) = grimace::cli::edit::default_face().expect("the built-in face");
    let scene = Face::new(rig, mesh).expect("the default rig binds");
    let mut app = App::new(scene, table, None);
    update(&mut app, Action::Resize(120, 40));
    app
}

/// Where `p` lands on a 200 x 160 dot canvas, as a fraction of the canvas from its centre.
fn from_centre(app: &App, p: Vec3) -> f32 {
    let mesh = app.doc.face.mesh();
    let proj = app.camera().fit_points(&mesh.positions, 200, 160, 1.0);
    let q = proj.project(p);
    ((q.x - 100.0) / 200.0).hypot((q.y - 80.0) / 160.0)
}

fn select(app: &mut App, name: &str) -> Vec3 {
    let i = app
        .rig()
        .muscles
        .iter()
        .position(|m| m.name == name)
        .unwrap_or_else(|| panic!("{name} in the default rig"));
    while app.selected_row() != Row::Muscle(i) {
        update(app, Action::SelectNext);
    }
    match &app.rig().muscles[i].kind {
        MuscleKind::Linear(l) => {
            let dir = (l.insertion - l.attachment).normalize();
            l.attachment + dir * (0.5 * (l.falloff_start + l.falloff_end))
        }
        MuscleKind::Sphincter(s) => s.centre,
        MuscleKind::Sheet(s) => {
            (s.attachment[0] + s.attachment[1] + s.insertion[0] + s.insertion[1]) / 4.0
        }
    }
}

#[test]
fn zooming_in_centres_on_the_selected_muscle() {
    for (name, yaw) in [
        ("L_Zygomatic_Major", 0.0),
        ("R_Frontalis_Inner", 0.0),
        ("L_Zygomatic_Major", 35.0),
    ] {
        let mut app = app();
        update(&mut app, Action::Rotate(yaw, 0.0));
        let region = select(&mut app, name);
        let before = from_centre(&app, region);
        for _ in 0..4 {
            update(&mut app, Action::Zoom(1.25));
        }
        let after = from_centre(&app, region);
        assert!(before > 0.1, "{name}: starts off centre ({before})");
        assert!(
            after < 0.01,
            "{name} at yaw {yaw}: {after} from the centre after zooming in"
        );
    }
}

#[test]
fn with_the_jaw_selected_zooming_in_centres_on_the_mouth_and_zooming_out_recentres() {
    let mut app = app();
    while app.selected_row() != Row::Jaw {
        update(&mut app, Action::SelectNext);
    }
    let mouth = app
        .rig()
        .muscles
        .iter()
        .find_map(|m| match &m.kind {
            MuscleKind::Sphincter(s) if m.name == "Orbicularis_Oris" => Some(s.centre),
            _ => None,
        })
        .expect("the mouth sphincter");
    update(&mut app, Action::Zoom(1.25));
    assert!(from_centre(&app, mouth) < 0.01);
    update(&mut app, Action::Zoom(0.5));
    assert_eq!(app.view.pan, (0.0, 0.0), "back at the whole face");
}
