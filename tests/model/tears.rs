//! No tears (`docs/model.md`, "The skin spread"): at every AU and expression of the built-in
//! table at full intensity, every muscle alone at 2.0 and the jaw alone at 4.0, on the
//! built-in face and on the MediaPipe canonical face and the MakeHuman base mesh fitted with
//! the library's fit, no skin triangle turns over (its normal against its rest normal) and
//! no skin edge stretches beyond 2.5 times its rest length. Skin is what the fit's part
//! finder calls skin on every head (the piece holding the landmarks), so eyes, teeth and
//! helpers are left out the same way on all three.

use std::path::Path;

use glam::Vec3;
use grimace::facs::AuTable;
use grimace::fit::parts::find_parts;
use grimace::fit::{fit_rig, Part, PartOverrides, Template};
use grimace::io::{builtin, landmarks::load_landmarks, obj};
use grimace::landmarks::Landmarks;
use grimace::model::{Activations, BoundRig, Mesh, Rig, SkinRules};

use crate::common;

/// The longest a skin edge may become, relative to its rest length.
pub(crate) const MAX_STRETCH: f32 = 2.5;

/// A head with its rig and its skin triangles.
pub(crate) struct Head {
    pub(crate) name: &'static str,
    pub(crate) mesh: Mesh,
    pub(crate) rig: Rig,
    /// Triangles whose three vertices are skin.
    pub(crate) skin: Vec<[u32; 3]>,
    /// The 68 landmarks' vertices.
    pub(crate) landmarks: Vec<u32>,
}

/// The worst a pose does to the skin.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct Damage {
    /// Skin triangles whose normal turned against the rest normal.
    pub(crate) flips: usize,
    /// The largest ratio of a skin edge's length to its rest length.
    pub(crate) stretch: f32,
}

impl Head {
    fn new(name: &'static str, mesh: Mesh, rig: Rig, landmark_vertices: &[u32]) -> Head {
        let points: Vec<Vec3> = landmark_vertices
            .iter()
            .map(|&v| mesh.positions[v as usize])
            .collect();
        let parts = find_parts(&mesh, landmark_vertices, &points, &PartOverrides::default());
        let skin = mesh
            .triangles
            .iter()
            .filter(|t| t.iter().all(|&v| parts.of_vertex[v as usize] == Part::Skin))
            .copied()
            .collect();
        Head {
            name,
            mesh,
            rig,
            skin,
            landmarks: landmark_vertices.to_vec(),
        }
    }

    /// The skin triangles turned over and the largest edge stretch of `pose`.
    pub(crate) fn damage(&self, pose: &[Vec3]) -> Damage {
        let rest = &self.mesh.positions;
        let mut damage = Damage::default();
        for t in &self.skin {
            let [a, b, c] = t.map(|i| rest[i as usize]);
            let [p, q, r] = t.map(|i| pose[i as usize]);
            let n0 = (b - a).cross(c - a);
            if n0.length_squared() > 0.0 && (q - p).cross(r - p).dot(n0) < 0.0 {
                damage.flips += 1;
            }
            for (i, j) in [(0, 1), (1, 2), (2, 0)] {
                let l0 = (rest[t[i] as usize] - rest[t[j] as usize]).length();
                if l0 > 0.0 {
                    let l = (pose[t[i] as usize] - pose[t[j] as usize]).length();
                    damage.stretch = damage.stretch.max(l / l0);
                }
            }
        }
        damage
    }
}

/// The built-in face with the built-in rig.
pub(crate) fn builtin_head() -> Head {
    let mesh = builtin::default_mesh();
    let marks = builtin::landmarks("face").expect("built-in landmarks");
    let vertices = marks.vertices(&mesh);
    Head::new("built-in face", mesh, builtin::default_rig(), &vertices)
}

/// A shared mesh fitted with the built-in template, as `fit-rig` does.
fn fitted(name: &'static str, mesh: Mesh, landmarks: &Landmarks) -> Head {
    let face = builtin::default_mesh();
    let rig = builtin::default_rig();
    let marks = builtin::landmarks("face").expect("built-in landmarks");
    let points = marks.positions(&face).expect("landmarks on the face");
    let fitted = fit_rig(
        Template {
            rig: &rig,
            mesh: &face,
            landmarks: &points,
        },
        &mesh,
        landmarks,
        "mesh.obj".into(),
        &PartOverrides::default(),
    )
    .expect("fits");
    let vertices = landmarks.vertices(&mesh);
    Head::new(name, mesh, fitted.rig, &vertices)
}

/// MediaPipe's canonical face and MakeHuman's base mesh, fitted, when the shared meshes are
/// there (a loud failure under `CI=true`, else skipped with the reason printed).
pub(crate) fn shared_heads() -> Vec<Head> {
    let mut heads = Vec::new();
    let needed = [
        "meshes/mediapipe_canonical_face.obj",
        "meshes/makehuman_base.obj",
    ];
    let Some(shared) = common::shared_with(&needed) else {
        return heads;
    };
    let mesh = obj::read_obj(&shared.join(needed[0])).expect("reads");
    let landmarks = Landmarks::mediapipe(&mesh).expect("MediaPipe landmarks");
    heads.push(fitted("MediaPipe canonical face", mesh, &landmarks));
    let mesh = obj::read_obj(&shared.join(needed[1])).expect("reads");
    let landmarks = load_landmarks(Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/fit_data/makehuman_base.landmarks.ron"
    )))
    .expect("MakeHuman landmarks");
    heads.push(fitted("MakeHuman base mesh", mesh, &landmarks));
    heads
}

/// Every pose the tear test covers: each AU and expression of `table` at full intensity,
/// each muscle alone at 2.0, the jaw alone at 4.0.
pub(crate) fn poses(table: &AuTable, rig: &Rig) -> Vec<(String, Activations)> {
    let mut poses = Vec::new();
    for key in table.aus.keys() {
        let act = table.entry_activations(key, rig).expect("AU evaluates");
        poses.push((format!("AU{key}"), act));
    }
    for name in table.expressions.keys() {
        let act = table
            .expression_activations(name, rig)
            .expect("expression evaluates");
        poses.push((name.clone(), act));
    }
    for (m, muscle) in rig.muscles.iter().enumerate() {
        let mut act = Activations::zero(rig);
        act.muscles[m] = 2.0;
        poses.push((format!("{} at 2", muscle.name), act));
    }
    let mut act = Activations::zero(rig);
    act.jaw = 4.0;
    poses.push(("jaw at 4".to_string(), act));
    poses
}

/// The poses of `head` that tear with `skin` (name, damage), printed with the worst figures.
fn tears(head: &Head, skin: SkinRules) -> Vec<(String, Damage)> {
    let bound = BoundRig::bind_with(&head.rig, &head.mesh, skin).expect("binds");
    let table = builtin::default_table();
    let mut worst = Damage::default();
    let mut torn = Vec::new();
    let mut out = Vec::new();
    for (name, act) in poses(&table, &head.rig) {
        bound.deform(&act, &mut out).expect("in range");
        assert!(out.iter().all(|p| p.is_finite()), "{name}: not finite");
        let d = head.damage(&out);
        worst.flips = worst.flips.max(d.flips);
        worst.stretch = worst.stretch.max(d.stretch);
        if d.flips > 0 || d.stretch > MAX_STRETCH {
            torn.push((name, d));
        }
    }
    println!(
        "{} (spread {}): {} poses tear, {} triangles turned over in all; most in one pose {}, \
         largest stretch {:.2}",
        head.name,
        skin.spread,
        torn.len(),
        torn.iter().map(|(_, d)| d.flips).sum::<usize>(),
        worst.flips,
        worst.stretch
    );
    for (name, d) in &torn {
        println!("  {name}: {} flips, stretch {:.2}", d.flips, d.stretch);
    }
    torn
}

/// The spread tears fewer poses, and turns no more triangles over, than the muscles' own
/// fields with the same slide and area bound; as few where those turn none. (Fewer, before
/// the lips' muscles' masks were eased on fitted heads, `fit::ease`: the flips without the
/// spread on MediaPipe fell to those with it, 44 each. Since the slide's lift is capped in
/// steep triangles, MediaPipe turns none either way and tears the same five poses, the jaw
/// stretching its joined lips.)
fn assert_the_spread_tears_less(head: &Head) {
    let before = tears(head, SkinRules::DEFAULT);
    let after = tears(head, SkinRules::TISSUE);
    let flips = |t: &[(String, Damage)]| t.iter().map(|(_, d)| d.flips).sum::<usize>();
    let fewer = after.len() < before.len() || (flips(&before) == 0 && after.len() == before.len());
    assert!(
        fewer && flips(&after) <= flips(&before),
        "{}: {} poses tear with the spread ({} flips), {} without ({} flips)",
        head.name,
        after.len(),
        flips(&after),
        before.len(),
        flips(&before)
    );
}

/// The built-in face tears in no pose (every AU and expression, each muscle alone at 2.0,
/// the jaw at 4.0), with or without the spread. (Before the default rig's muscle ranges,
/// 12 muscles alone at 2.0 tore it without the spread and 8 with it, which the spread's
/// comparison here measured.)
#[test]
fn the_builtin_face_tears_in_no_pose_with_or_without_the_spread() {
    let head = builtin_head();
    for skin in [SkinRules::DEFAULT, SkinRules::TISSUE] {
        let torn = tears(&head, skin);
        assert!(torn.is_empty(), "spread {}: {torn:?}", skin.spread);
    }
}

#[test]
fn the_spread_tears_fitted_shared_heads_less() {
    for head in shared_heads() {
        assert_the_spread_tears_less(&head);
    }
}

/// What the fitted shared heads reach with the default deformation, pinned so it only gets
/// better (`docs/model.md`, "Measured"; tighten the bounds as the fit and the skin improve):
/// poses that tear (of the built-in table's AUs and expressions at full intensity, each
/// muscle at 2.0 and the jaw at 4.0) and skin triangles turned over in all of them.
#[test]
fn fitted_shared_heads_tear_no_more_than_measured() {
    for head in shared_heads() {
        let (poses, flips) = match head.name {
            // (29, 242 before the default rig's muscle ranges and the slide kept out of the
            // skin's folds: docs/model.md, "The slide at folds")
            // (16, 54 before the slide's normal took its patch's mean in folds)
            // (16, 48 before its midline read both sides of the template: AU10 2.58x)
            // (15, 48 before the lips' muscles' masks were eased: `fit::ease`)
            // (15, 44 before the slide's lift was capped in steep triangles: docs/model.md,
            // "The slide at folds"; what tears is the jaw stretching the joined lips)
            "MediaPipe canonical face" => (5, 0),
            // With the lids shaped from the mesh (57, 1760 before AU1's medial frontalis
            // sheet), the brow's sheets kept out of the eye sockets (the sheet lifted the
            // socket's lining at AU1, sadness and at 2.0), the jaw's weights found along the
            // mesh beyond the template (AU26, AU27 and the jaw at 4 turned the skin under the
            // chin over), the default rig's muscle ranges and the slide kept out of the skin's
            // folds (60, 1941 before these four); the lids closing at their free edges
            // (`fit::lidedge`), the slide's normal taking its patch's mean in folds and the
            // lips' linings reading their carried masks from their own lip (35, 468 before);
            // the lips' muscles' masks eased (`fit::ease`), the lower lid's ring faded along the
            // skin to the canthi and the closing ring's fold rows kept from passing each other
            // (`fit::lowerlid`, `fit::lids`; 29, 129 before: AU7, AU10, AU43/45/46 and the
            // closing ring at 2.0 no longer tear); the slide's lift capped in steep triangles
            // (14, 48 before: AU12 and its halves no longer tear)
            "MakeHuman base mesh" => (9, 34),
            other => panic!("no bound for {other}"),
        };
        let torn = tears(&head, SkinRules::DEFAULT);
        let turned: usize = torn.iter().map(|(_, d)| d.flips).sum();
        assert!(
            torn.len() <= poses && turned <= flips,
            "{}: {} poses tear ({} flips), measured {poses} ({flips}): {:?}",
            head.name,
            torn.len(),
            turned,
            torn.iter()
                .map(|(name, d)| (name, d.flips))
                .collect::<Vec<_>>()
        );
    }
}

/// The AUs and expressions of the built-in table that move no jaw turn no skin triangle of
/// the built-in face over, with or without the spread.
#[test]
fn no_jawless_au_or_expression_turns_the_builtin_face_over() {
    let head = builtin_head();
    let table = builtin::default_table();
    for skin in [SkinRules::DEFAULT, SkinRules::TISSUE] {
        let bound = BoundRig::bind_with(&head.rig, &head.mesh, skin).expect("binds");
        let mut out = Vec::new();
        for (name, act) in poses(&table, &head.rig) {
            let at_most_one = act.muscles.iter().filter(|&&a| a > 0.0).count() <= 1;
            if act.jaw > 0.0 || (at_most_one && name.ends_with("at 2")) {
                continue;
            }
            bound.deform(&act, &mut out).expect("in range");
            let d = head.damage(&out);
            assert_eq!(d.flips, 0, "{name} (spread {}): {d:?}", skin.spread);
        }
    }
}

/// What `grimace check` measures (`fit::quality`), on the built-in face with the default
/// deformation: every AU and expression of the built-in table at full intensity tears no
/// skin (no triangle turned over, no edge beyond 2.5x), the lids close to under 10 % of their
/// opening at AU43/45 and the jaw drops at least 15 mm at AU26/27; and the jaw alone at 4.0
/// tears nothing either. (Before the lip masks turned about the mouth corners and the jaw's
/// weights were held along the slit, AU10 stretched the skin below the corners 2.98x and
/// AU27 3.15x, the jaw at 4 3.18x; before the lids reached the brow and the jaw's weights
/// were relaxed, the lids stretched an edge 3.55x, AU26 3.95x and surprise 2.51x.)
#[test]
fn the_builtin_table_passes_check_on_the_builtin_face() {
    use grimace::fit::quality::{Expect, Eyes, Gauge};
    let head = builtin_head();
    let rig = &head.rig;
    let table = builtin::default_table();
    let marks = builtin::landmarks("face").expect("built-in landmarks");
    let gauge =
        Gauge::new(&head.mesh, &marks.vertices(&head.mesh), Some(11.5)).expect("measurable");
    let bound = grimace::model::Deformation::default()
        .bind(rig, &head.mesh)
        .expect("binds");
    let mut out = Vec::new();
    let mut checked = 0;
    for key in table.aus.keys() {
        let expect = Expect {
            lids_close: matches!(key.number, 43 | 45).then_some(match key.side {
                Some(grimace::model::Side::Left) => Eyes::Left,
                Some(grimace::model::Side::Right) => Eyes::Right,
                _ => Eyes::Both,
            }),
            jaw_opens: matches!(key.number, 26 | 27) && key.side.is_none(),
        };
        let act = table.entry_activations(key, rig).expect("AU evaluates");
        bound.deform(&act, &mut out).expect("in range");
        let quality = gauge.measure(&out, expect);
        assert!(quality.failures().is_empty(), "AU{key}: {quality:?}");
        checked += 1;
    }
    for name in table.expressions.keys() {
        let act = table
            .expression_activations(name, rig)
            .expect("expression evaluates");
        bound.deform(&act, &mut out).expect("in range");
        let quality = gauge.measure(&out, Expect::default());
        assert!(quality.failures().is_empty(), "{name}: {quality:?}");
        checked += 1;
    }
    assert!(checked >= 55, "the table has 48 AUs and 7 expressions");
    let mut act = Activations::zero(rig);
    act.jaw = 4.0;
    bound.deform(&act, &mut out).expect("in range");
    let d = head.damage(&out);
    assert!(
        d.flips == 0 && d.stretch <= MAX_STRETCH,
        "the jaw at 4 tears: {d:?}"
    );
}
