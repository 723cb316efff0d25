//! Helper geometry (MakeHuman's `helper-*` proxies, `joint-*` markers) is not drawn: a
//! proxy in front of the face leaves the face visible, while the same sheet under a name
//! that is not a helper's still covers it.

use glam::Vec3;
use grimace::model::Mesh;
use grimace::render::{Camera, CellMode, Renderer, Scene, Style};

/// A face: a square pyramid whose apex (the nose, at z = 1) points at the viewer, and a
/// square sheet at z = 2 in front of it, in a group named `cover`.
fn covered_face(cover: &str) -> Mesh {
    let mut positions = vec![
        Vec3::new(-1.0, -1.0, 0.0),
        Vec3::new(1.0, -1.0, 0.0),
        Vec3::new(1.0, 1.0, 0.0),
        Vec3::new(-1.0, 1.0, 0.0),
        Vec3::new(0.0, 0.0, 1.0),
    ];
    let mut triangles = vec![[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]];
    positions.extend([
        Vec3::new(-1.2, -1.2, 2.0),
        Vec3::new(1.2, -1.2, 2.0),
        Vec3::new(1.2, 1.2, 2.0),
        Vec3::new(-1.2, 1.2, 2.0),
    ]);
    triangles.extend([[5, 6, 7], [5, 7, 8]]);
    let mut mesh = Mesh::new(positions, triangles).expect("a valid mesh");
    mesh.groups.insert("body".into(), (0..5).collect());
    mesh.groups.insert(cover.into(), (5..9).collect());
    mesh
}

/// Depth drawn at the nose's dot, with the depth of the nose itself and of the sheet there.
fn depth_at_nose(mesh: &Mesh, style: Style) -> (f32, f32, f32) {
    let mut canvas = CellMode::Braille.canvas(60, 30);
    let scene = Scene::new(mesh, &mesh.positions);
    let camera = Camera::front();
    Renderer::new(mesh).render(&scene, &camera, style, &mut canvas);
    let proj = camera.fit_points(
        &mesh.positions,
        canvas.width(),
        canvas.height(),
        canvas.dot_aspect,
    );
    let nose = proj.project(mesh.positions[4]);
    let sheet = proj.project(Vec3::new(0.0, 0.0, 2.0));
    let drawn = canvas.depth(nose.x as usize, nose.y as usize);
    (drawn, nose.z, sheet.z)
}

#[test]
fn helper_geometry_in_front_of_the_face_is_not_drawn() {
    for style in [Style::Shaded, Style::Lines] {
        let (drawn, nose, sheet) = depth_at_nose(&covered_face("helper-hair"), style);
        assert!(
            (drawn - nose).abs() < 0.05 * (sheet - nose).abs(),
            "{style:?}: depth {drawn} at the nose's dot, the nose is at {nose}, the helper at {sheet}"
        );
        // Lash cards (hairs cut out of a card by a texture no style reads) are not drawn.
        let (drawn, nose, sheet) = depth_at_nose(&covered_face("upper_eyelashes"), style);
        assert!(
            (drawn - nose).abs() < 0.05 * (sheet - nose).abs(),
            "{style:?}: depth {drawn} at the nose's dot under a lash card at {sheet}"
        );
        let (drawn, nose, sheet) = depth_at_nose(&covered_face("hair"), style);
        assert!(
            (drawn - sheet).abs() < 0.05 * (sheet - nose).abs(),
            "{style:?}: depth {drawn} at the nose's dot, the cover at {sheet}, the nose at {nose}"
        );
    }
}

#[test]
fn a_mesh_without_helper_groups_draws_every_triangle() {
    let mesh = covered_face("hair");
    assert_eq!(grimace::fit::parts::drawn_triangles(&mesh), None);
    let helper = covered_face("joint-head");
    let drawn = grimace::fit::parts::drawn_triangles(&helper).expect("the marker is left out");
    assert_eq!(drawn, helper.triangles[..4].to_vec());
}
