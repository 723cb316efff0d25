//! Which parts of a mesh are skin, which stay still and which turn with the jaw.
//!
//! Muscles move skin only. Eyeballs, teeth, tongue, eyelashes and helper geometry are found
//! from the mesh's named groups (OBJ `g`, `o` and `usemtl`) and its connected pieces:
//!
//! - skin is every piece (connected component) that holds a landmark, and, when the mesh has
//!   named groups, only the groups that hold a landmark;
//! - everything else is a rigid part; a part named like lower teeth or a tongue, or a piece
//!   inside the mouth below the lip line, turns with the jaw; the rest keeps still;
//! - a group named like the mouth's parts but for neither jaw (`teeth`, `Mouth_Teeth_Tongue`,
//!   one material for all of them) is split into its connected pieces, and each piece turns
//!   with the jaw when its centre lies below the occlusal plane ([`MouthTest`]).
//!
//! `--skin GROUP` and `--rigid GROUP` override the choice for whole groups.

use std::cmp::Reverse;
use std::collections::{BTreeMap, BinaryHeap};

use glam::DVec3;

use crate::landmarks::{
    eye_centre, FaceFrame, CHIN, EYES, INNER_LOWER, INNER_UPPER, MOUTH_CORNERS,
};
use crate::model::mesh::Distance;
use crate::model::{Mask, Mesh, Rig};

/// What a vertex is for fitting.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Part {
    /// Moved by muscles (and by the jaw, by its weights).
    Skin,
    /// Moved by nothing.
    Still,
    /// Turned rigidly with the jaw, never moved by muscles.
    Jaw,
}

/// One named piece of the mesh and what it was taken for, for the report.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PartChoice {
    /// A group name, or `piece N` for an unnamed connected component.
    pub name: String,
    /// Number of vertices.
    pub vertices: usize,
    /// What it was taken for.
    pub part: Part,
    /// Why: `landmarks`, `name`, `position`, `--skin`, `--rigid`.
    pub reason: &'static str,
}

/// The reason given for a part taken from where a piece sits.
const BY_POSITION: &str = "position";

/// The skin's edges from each vertex, with their lengths (skin to skin only; edges of no
/// length are left out, so a distance's neighbours are always apart).
pub(super) struct SkinGraph {
    /// Each vertex's skin neighbours and the edge's length.
    pub(super) next: Vec<Vec<(u32, f64)>>,
}

impl SkinGraph {
    /// The graph of `mesh`'s skin edges as `parts` sorts them.
    pub(super) fn new(mesh: &Mesh, parts: &Parts) -> SkinGraph {
        let skin = |v: u32| parts.of_vertex[v as usize] == Part::Skin;
        let mut next = vec![Vec::new(); mesh.vertex_count()];
        for [a, b] in mesh.edges() {
            if skin(a) && skin(b) {
                let d = f64::from(mesh.positions[a as usize].distance(mesh.positions[b as usize]));
                if d > 0.0 {
                    next[a as usize].push((b, d));
                    next[b as usize].push((a, d));
                }
            }
        }
        SkinGraph { next }
    }

    /// The distance along the skin from the nearest of `seeds` to every vertex, walked no
    /// further than `limit` (infinite beyond, and off the seeds' pieces).
    pub(super) fn distances(&self, seeds: &[u32], limit: f64) -> Vec<f64> {
        let mut d = vec![f64::INFINITY; self.next.len()];
        let mut queue = BinaryHeap::new();
        for &s in seeds {
            d[s as usize] = 0.0;
            queue.push((Reverse(Distance(0.0)), s));
        }
        while let Some((Reverse(Distance(here)), v)) = queue.pop() {
            if here > d[v as usize] {
                continue;
            }
            for &(u, length) in &self.next[v as usize] {
                let there = here + length;
                if there < d[u as usize] && there <= limit {
                    d[u as usize] = there;
                    queue.push((Reverse(Distance(there)), u));
                }
            }
        }
        d
    }
}

/// The parts of a mesh: one per vertex, and the choices per named piece.
#[derive(Debug, Clone, PartialEq)]
pub struct Parts {
    /// The part of each vertex.
    pub of_vertex: Vec<Part>,
    /// The choice made for each group or unnamed piece.
    pub choices: Vec<PartChoice>,
}

/// Overrides from the command line: groups forced to skin or to rigid.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct PartOverrides {
    /// Groups that are skin.
    pub skin: Vec<String>,
    /// Groups that are rigid (still, or turning with the jaw when named so).
    pub rigid: Vec<String>,
}

/// Words in a group name that mark a rigid part; the first list turns with the jaw.
const JAW_WORDS: [&str; 2] = ["tongue", "lower"];
/// Anatomy that never stretches with the skin.
const ANATOMY_WORDS: [&str; 10] = [
    "eye",
    "iris",
    "pupil",
    "cornea",
    "sclera",
    "teeth",
    "tooth",
    "gum",
    "tongue",
    "mouth_interior",
];
/// Proxies, markers and hair: kept still, and (`helper`, `joint`) not drawn unless they name
/// anatomy ([`helper_name`]).
const PROXY_WORDS: [&str; 3] = ["helper", "joint", "hair"];

/// Words in a group's name (lower case, letters and digits only) that mark the thin films
/// game-engine heads lay over the eye and along the lids for their shaders (Unreal's digital
/// humans and the models that follow them: `EyeOcclusion`, `EyeBlend`, `eyeshell`,
/// `LacrimalFluid`, `TearLine`, `eyeEdge`): drawn through transparency there, they hug the
/// lids and move with them in the artists' own shapes.
const EYE_FILM_WORDS: [&str; 6] = [
    "occlusion",
    "eyeblend",
    "eyeshell",
    "lacrimal",
    "tearline",
    "eyeedge",
];

/// True when a group's name says it holds eyelashes or a film over the eye
/// ([`EYE_FILM_WORDS`]): they are not rigid but skin, moved by the lid muscles' fields where
/// they sit at the lid's edge, so they close with their lid (a still lash or film would
/// stay where the open lid was), and they are not drawn ([`undrawn_name`]).
pub fn lash_name(name: &str) -> bool {
    let plain: String = name
        .chars()
        .filter(char::is_ascii_alphanumeric)
        .map(|c| c.to_ascii_lowercase())
        .collect();
    plain.contains("lash") || EYE_FILM_WORDS.iter().any(|w| plain.contains(w))
}

/// True when a group's name says it is a rigid part.
fn rigid_name(name: &str) -> bool {
    let lower = name.to_ascii_lowercase();
    if lash_name(name) {
        return false;
    }
    // "eyebrow" and "brow" are skin on most heads (or hair cards that should follow it).
    if lower.contains("brow") {
        return false;
    }
    ANATOMY_WORDS
        .iter()
        .chain(&PROXY_WORDS)
        .any(|w| lower.contains(w))
}

/// True when a group's name says it is helper geometry that is not anatomy: a joint
/// marker (`joint-jaw`, `joint-l-eye-target`: never anatomy), or a rigid `helper` proxy
/// that names no anatomy (eye, tooth, gum, tongue, mouth interior) or lash (`helper-hair`, `helper-skirt`).
/// Modelling tools keep such proxies and markers in the file but never show them; grimace
/// does not draw them either ([`drawn_triangles`]). A plain `hair` group is the user's hair
/// and is drawn.
pub fn helper_name(name: &str) -> bool {
    let lower = name.to_ascii_lowercase();
    rigid_name(name)
        && (lower.contains("joint")
            || (lower.contains("helper") && !ANATOMY_WORDS.iter().any(|w| lower.contains(w))))
}

/// True when a group's triangles are not drawn: helper geometry ([`helper_name`]), and
/// eyelashes and the eye's films ([`lash_name`]). Lashes are modelled as cards that a
/// texture's transparency cuts into hairs, and the films are drawn through transparency;
/// drawn opaque (no style reads textures) a card is a pale band over the lid and under the
/// eye, not lashes, and a face tracker took MakeHuman's for part of the eye
/// (`docs/gallery.md`, "Lash cards"), while a film is a grey shell over the iris. They still
/// move with their lids, and export keeps them.
pub fn undrawn_name(name: &str) -> bool {
    helper_name(name) || lash_name(name)
}

/// The triangles to draw: every triangle but those whose corners all belong to undrawn
/// groups ([`undrawn_name`]) and to no other group. `None` when that is every triangle
/// (a mesh without such groups draws exactly as read). Export keeps every triangle.
pub fn drawn_triangles(mesh: &Mesh) -> Option<Vec<[u32; 3]>> {
    let helpers: Vec<&Vec<u32>> = mesh
        .groups
        .iter()
        .filter(|(name, _)| undrawn_name(name))
        .map(|(_, members)| members)
        .collect();
    if helpers.is_empty() {
        return None;
    }
    let mut hidden = vec![false; mesh.vertex_count()];
    for &v in helpers.into_iter().flatten() {
        hidden[v as usize] = true;
    }
    // A vertex a drawn group also holds stays drawn.
    for (name, members) in &mesh.groups {
        if !undrawn_name(name) {
            for &v in members {
                hidden[v as usize] = false;
            }
        }
    }
    let drawn: Vec<[u32; 3]> = mesh
        .triangles
        .iter()
        .filter(|t| !t.iter().all(|&v| hidden[v as usize]))
        .copied()
        .collect();
    (drawn.len() < mesh.triangles.len()).then_some(drawn)
}

/// True when a rigid group's name says it holds the mouth's parts without saying which jaw
/// they belong to (`teeth`, `gums`, `mouth`, `teeth_tongue`, but not `upper_teeth` or a
/// lone `tongue`): its pieces are sorted by the occlusal plane.
fn mixed_mouth_name(name: &str) -> bool {
    let lower = name.to_ascii_lowercase();
    let mouth = ["teeth", "tooth", "gum", "mouth"]
        .iter()
        .any(|w| lower.contains(w));
    let sided = ["upper", "lower", "top", "bottom", "interior"]
        .iter()
        .any(|w| lower.contains(w));
    mouth && !sided
}

/// True when a rigid part's name says it turns with the jaw (lower teeth, lower gums, tongue).
fn jaw_name(name: &str) -> bool {
    let lower = name.to_ascii_lowercase();
    lower.contains(JAW_WORDS[0])
        || (lower.contains(JAW_WORDS[1])
            && ["teeth", "tooth", "gum", "jaw"]
                .iter()
                .any(|w| lower.contains(w)))
}

/// Whether each vertex lies on a piece of `mesh` (a connected component) that holds one of
/// `landmarks` (the vertex nearest each landmark names its piece): a template's skin, as its
/// teeth, tongue and eyeballs are pieces of their own.
pub fn on_landmark_pieces(mesh: &Mesh, landmarks: &[glam::Vec3]) -> Vec<bool> {
    let component = components(mesh);
    let positions = &mesh.positions;
    let mut pieces: Vec<u32> = landmarks
        .iter()
        .filter_map(|l| {
            (0..positions.len())
                .min_by(|&a, &b| {
                    positions[a]
                        .distance_squared(*l)
                        .total_cmp(&positions[b].distance_squared(*l))
                })
                .map(|v| component[v])
        })
        .collect();
    pieces.sort_unstable();
    pieces.dedup();
    component
        .iter()
        .map(|c| pieces.binary_search(c).is_ok())
        .collect()
}

/// Connected components of the mesh's vertices (by triangles): a component id per vertex.
pub fn components(mesh: &Mesh) -> Vec<u32> {
    let n = mesh.vertex_count();
    let mut parent: Vec<u32> = (0..n as u32).collect();
    fn find(parent: &mut [u32], mut v: u32) -> u32 {
        while parent[v as usize] != v {
            let up = parent[parent[v as usize] as usize];
            parent[v as usize] = up;
            v = up;
        }
        v
    }
    for t in &mesh.triangles {
        for k in 1..3 {
            let (a, b) = (find(&mut parent, t[0]), find(&mut parent, t[k]));
            if a != b {
                parent[a.max(b) as usize] = a.min(b);
            }
        }
    }
    (0..n as u32).map(|v| find(&mut parent, v)).collect()
}

/// Sorts the mesh's vertices into skin, still and jaw parts.
///
/// `landmark_vertices` are the landmarks' vertices; `points` their positions (for the mouth
/// test of pieces that hold no landmark).
pub fn find_parts(
    mesh: &Mesh,
    landmark_vertices: &[u32],
    points: &[glam::Vec3],
    overrides: &PartOverrides,
) -> Parts {
    let n = mesh.vertex_count();
    let component = components(mesh);
    let mut marked = vec![false; n];
    for &v in landmark_vertices {
        if let Some(slot) = marked.get_mut(v as usize) {
            *slot = true;
        }
    }
    let mouth = MouthTest::new(points);
    let lashes = LashTest::new(points);
    let pieces = Pieces::new(mesh, &component, &marked, mouth.as_ref(), lashes.as_ref());
    let mut of_vertex: Vec<Part> = component.iter().map(|c| pieces.part[c].0).collect();
    let mut grouped = vec![false; n];
    let mut choices = Vec::new();
    // Named groups: a rigid name or an override decides for the whole group; otherwise the
    // group follows its pieces.
    for (name, members) in mesh.groups.iter().filter(|(_, m)| !m.is_empty()) {
        for &v in members {
            grouped[v as usize] = true;
        }
        let holds_landmark = members.iter().any(|&v| marked[v as usize]);
        let forced_rigid = overrides.rigid.iter().any(|g| g == name);
        let split = mixed_mouth_name(name)
            && !overrides.skin.iter().any(|g| g == name)
            && (forced_rigid || !holds_landmark);
        if let (true, Some(mouth)) = (split, &mouth) {
            let reason = if forced_rigid {
                "--rigid"
            } else {
                "occlusal plane"
            };
            let split = split_mouth_group(mesh, mouth, members, &component);
            for (k, (piece, part)) in split.iter().enumerate() {
                for &v in piece {
                    of_vertex[v as usize] = *part;
                }
                choices.push(PartChoice {
                    name: format!("{name} piece {}", k + 1),
                    vertices: piece.len(),
                    part: *part,
                    reason,
                });
            }
            continue;
        }
        let group = GroupFacts {
            name,
            members,
            holds_landmark,
            forced_rigid,
        };
        let (part, reason) = group_part(mesh, &group, overrides, mouth.as_ref());
        if let Some(part) = part {
            for &v in members {
                of_vertex[v as usize] = part;
            }
        }
        let shown =
            part.unwrap_or_else(|| majority(members.iter().map(|&v| of_vertex[v as usize])));
        choices.push(PartChoice {
            name: name.clone(),
            vertices: members.len(),
            part: shown,
            reason,
        });
    }
    // Vertices a group's override made skin stay skin even where a rigid group shares them.
    for (name, members) in &mesh.groups {
        if overrides.skin.iter().any(|g| g == name) {
            for &v in members {
                of_vertex[v as usize] = Part::Skin;
            }
        }
    }
    choices.extend(pieces.ungrouped_choices(&grouped));
    Parts { of_vertex, choices }
}

/// The mesh's connected pieces and the part each takes on its own: skin when it holds a
/// landmark, else by where it sits.
struct Pieces {
    /// Each piece's vertices, by the piece's smallest vertex.
    members: BTreeMap<u32, Vec<u32>>,
    /// Each piece's part, and why as [`PartChoice::reason`] says it.
    part: BTreeMap<u32, (Part, &'static str)>,
}

impl Pieces {
    fn new(
        mesh: &Mesh,
        component: &[u32],
        marked: &[bool],
        mouth: Option<&MouthTest>,
        lashes: Option<&LashTest>,
    ) -> Pieces {
        let mut members: BTreeMap<u32, Vec<u32>> = BTreeMap::new();
        for (v, &c) in component.iter().enumerate() {
            members.entry(c).or_default().push(v as u32);
        }
        let part = members
            .iter()
            .map(|(c, piece)| {
                let choice = if piece.iter().any(|&v| marked[v as usize]) {
                    (Part::Skin, "landmarks")
                } else if lashes.is_some_and(|l| l.at_a_lid(mesh, piece)) {
                    (Part::Skin, "lashes at a lid's edge: move with their lid")
                } else if mouth.is_some_and(|m| m.turns_with_jaw(mesh, piece)) {
                    (Part::Jaw, BY_POSITION)
                } else {
                    (Part::Still, BY_POSITION)
                };
                (*c, choice)
            })
            .collect();
        Pieces { members, part }
    }

    /// What is said of the pieces (or their parts) that no named group covers. Vertices no
    /// face uses (a piece of one vertex each: exporters leave them behind when parts are
    /// deleted) are said in one line, not one a vertex.
    fn ungrouped_choices(&self, grouped: &[bool]) -> Vec<PartChoice> {
        let mut choices = Vec::new();
        // single vertices in no face, counted by the part their place gives them
        let mut loose = [(Part::Still, 0), (Part::Jaw, 0), (Part::Skin, 0)];
        for (number, (c, members)) in self.members.iter().enumerate() {
            if members.iter().all(|&v| grouped[v as usize]) {
                continue;
            }
            let (part, reason) = self.part[c];
            if members.len() == 1 && reason == BY_POSITION {
                if let Some(slot) = loose.iter_mut().find(|(p, _)| *p == part) {
                    slot.1 += 1;
                }
                continue;
            }
            choices.push(PartChoice {
                name: format!("piece {}", number + 1),
                vertices: members.iter().filter(|&&v| !grouped[v as usize]).count(),
                part,
                reason,
            });
        }
        for (part, count) in loose.into_iter().filter(|&(_, n)| n > 0) {
            choices.push(PartChoice {
                name: "loose vertices (in no face)".to_string(),
                vertices: count,
                part,
                reason: BY_POSITION,
            });
        }
        choices
    }
}

/// What decides a named group's part.
struct GroupFacts<'a> {
    name: &'a str,
    members: &'a [u32],
    holds_landmark: bool,
    forced_rigid: bool,
}

/// A named group's part and why: an override or a name decides for the whole group; `None`
/// leaves each vertex its piece's part.
fn group_part(
    mesh: &Mesh,
    group: &GroupFacts<'_>,
    overrides: &PartOverrides,
    mouth: Option<&MouthTest>,
) -> (Option<Part>, &'static str) {
    let name = group.name;
    if overrides.skin.iter().any(|g| g == name) {
        (Some(Part::Skin), "--skin")
    } else if group.forced_rigid {
        let jaw = jaw_name(name) || mouth.is_some_and(|m| m.turns_with_jaw(mesh, group.members));
        (Some(if jaw { Part::Jaw } else { Part::Still }), "--rigid")
    } else if lash_name(name) {
        (Some(Part::Skin), "lashes or eye film: move with their lid")
    } else if rigid_name(name) && !group.holds_landmark {
        let part = if jaw_name(name) {
            Part::Jaw
        } else {
            Part::Still
        };
        (Some(part), "name")
    } else if group.holds_landmark {
        (None, "landmarks")
    } else {
        (None, BY_POSITION)
    }
}

/// A group of teeth, gums and tongue together, split by its connected pieces: each piece
/// below the occlusal plane turns with the jaw, the others stay.
fn split_mouth_group(
    mesh: &Mesh,
    mouth: &MouthTest,
    members: &[u32],
    component: &[u32],
) -> Vec<(Vec<u32>, Part)> {
    split_pieces(members, component)
        .into_iter()
        .map(|piece| {
            let part = if mouth.below_occlusal_plane(mesh, &piece) {
                Part::Jaw
            } else {
                Part::Still
            };
            (piece, part)
        })
        .collect()
}

/// A group's vertices split by the connected piece each lies on, pieces in order of their
/// first vertex.
fn split_pieces(members: &[u32], component: &[u32]) -> Vec<Vec<u32>> {
    let mut pieces: BTreeMap<u32, Vec<u32>> = BTreeMap::new();
    for &v in members {
        pieces.entry(component[v as usize]).or_default().push(v);
    }
    let mut out: Vec<Vec<u32>> = pieces.into_values().collect();
    out.sort_by_key(|p| p[0]);
    out
}

/// The most common part among some vertices.
fn majority(parts: impl Iterator<Item = Part>) -> Part {
    let mut counts = [0usize; 3];
    for p in parts {
        counts[p as usize] += 1;
    }
    [Part::Skin, Part::Still, Part::Jaw]
        .into_iter()
        .max_by_key(|p| counts[*p as usize])
        .unwrap_or(Part::Skin)
}

/// Decides whether a piece sits inside the mouth below the lip line (lower teeth, tongue):
/// its centre lies between the mouth corners, behind the lips and below the occlusal plane,
/// within a mouth's height of it.
///
/// The occlusal plane passes through the lip line (the inner lip landmarks 60-67, where the
/// teeth meet behind closed lips) across the face; its normal is the face's vertical from
/// the chin (8) to the eyes, made perpendicular to the left-right axis. Not the direction
/// from the mouth to the eyes: the eyes lie behind the lips, so that leans back, and not the
/// chin-to-lips direction, which leans forward with the chin; over the 30 mm the teeth reach
/// back, a lean of 10 degrees moves the plane 5 mm, about the depth of a crown.
struct MouthTest {
    frame: FaceFrame,
    centre: DVec3,
    half_width: f64,
    /// Normal of the occlusal plane (through `centre`).
    occlusal_up: DVec3,
    /// Into the face along the plane, perpendicular to the left-right axis.
    occlusal_back: DVec3,
}

impl MouthTest {
    fn new(points: &[glam::Vec3]) -> Option<MouthTest> {
        let frame = FaceFrame::of(points)?;
        let p = |i: usize| points[i].as_dvec3();
        let centre = (INNER_UPPER
            .iter()
            .chain(&INNER_LOWER)
            .map(|&i| p(i))
            .sum::<DVec3>())
            / (INNER_UPPER.len() + INNER_LOWER.len()) as f64;
        let half_width = 0.5 * p(MOUTH_CORNERS[0]).distance(p(MOUTH_CORNERS[1]));
        let eyes = (36..48).map(p).sum::<DVec3>() / 12.0;
        let rise = eyes - p(CHIN);
        let rise = rise - frame.lateral * rise.dot(frame.lateral);
        let occlusal_up = rise.try_normalize().unwrap_or(frame.up);
        let occlusal_back = -occlusal_up.cross(frame.lateral).normalize_or_zero()
            * occlusal_up.cross(frame.lateral).dot(frame.forward).signum();
        Some(MouthTest {
            frame,
            centre,
            half_width,
            occlusal_up,
            occlusal_back,
        })
    }

    /// The centre of `members` relative to the lip line: (across, up from the occlusal plane,
    /// back into the face).
    fn local(&self, mesh: &Mesh, members: &[u32]) -> DVec3 {
        let mean = members
            .iter()
            .map(|&v| mesh.positions[v as usize].as_dvec3())
            .sum::<DVec3>()
            / members.len().max(1) as f64;
        let d = mean - self.centre;
        DVec3::new(
            d.dot(self.frame.lateral),
            d.dot(self.occlusal_up),
            d.dot(self.occlusal_back),
        )
    }

    /// True when the centre of `members` lies below the occlusal plane (on the chin's side).
    fn below_occlusal_plane(&self, mesh: &Mesh, members: &[u32]) -> bool {
        self.local(mesh, members).y < 0.0
    }

    fn turns_with_jaw(&self, mesh: &Mesh, members: &[u32]) -> bool {
        if members.is_empty() {
            return false;
        }
        let local = self.local(mesh, members);
        local.x.abs() < 1.2 * self.half_width
            && local.y < 0.0
            && local.y > -1.5 * self.half_width
            && local.z > 0.0
            && local.z < 3.0 * self.half_width
    }
}

/// How far from an eye's centre a lash piece reaches, in eye widths (corner to corner): the
/// lid's edge lies within half a width of the centre, and a lash is about a third of one.
const LASH_REACH: f64 = 0.9;
/// The least extent of a lash piece across the eye, in eye widths: a row of lashes runs
/// along most of its lid.
const LASH_SPAN: f64 = 0.5;
/// The most a lash piece rises across its lid (up the face), as a share of its extent
/// along it: a row of lashes is a narrow arc, where an iris, a cornea or an eyeball is as
/// tall as it is wide.
const LASH_RISE: f64 = 0.45;
/// The most a lash piece reaches front to back, in eye widths: an eyeball is about 0.8 eye
/// widths deep, a row of lashes curls forward a third of a width (MakeHuman's upper lashes
/// 0.41).
const LASH_DEPTH: f64 = 0.5;

/// Where the eyes are, for telling a piece of its own that no group names: a row of lashes
/// (or a strip along a lid, as tear lines are) is skin that moves with its lid, so the lid
/// muscles close it with the lid (`lids.rs` gives it the travel of the lid edge it grows
/// from); kept still, the lashes stayed where the open lid was, and the lids' free edges
/// were looked for behind them as if they were the eyeball. A piece is taken for one when it
/// lies within [`LASH_REACH`] of an eye's centre, runs along the eye ([`LASH_SPAN`]) as a
/// narrow arc ([`LASH_RISE`]) and is shallow ([`LASH_DEPTH`]).
struct LashTest {
    /// The face's axes: across, up, forward.
    axes: [DVec3; 3],
    /// Per eye: its centre and its width.
    eyes: Vec<(DVec3, f64)>,
}

impl LashTest {
    fn new(points: &[glam::Vec3]) -> Option<LashTest> {
        let frame = FaceFrame::of(points)?;
        let p = |i: usize| points[i].as_dvec3();
        let eyes = EYES
            .iter()
            .map(|eye| (eye_centre(points, *eye), p(eye[0]).distance(p(eye[3]))))
            .filter(|&(_, width)| width > 0.0)
            .collect();
        Some(LashTest {
            axes: [frame.lateral, frame.up, frame.forward],
            eyes,
        })
    }

    /// True when the piece `members` sits at an eye as a row of lashes does.
    fn at_a_lid(&self, mesh: &Mesh, members: &[u32]) -> bool {
        let axes = self.axes;
        self.eyes.iter().any(|&(centre, width)| {
            let mut low = DVec3::splat(f64::INFINITY);
            let mut high = DVec3::splat(f64::NEG_INFINITY);
            for &v in members {
                let d = mesh.positions[v as usize].as_dvec3() - centre;
                if d.length() > LASH_REACH * width {
                    return false;
                }
                let q = DVec3::new(d.dot(axes[0]), d.dot(axes[1]), d.dot(axes[2]));
                low = low.min(q);
                high = high.max(q);
            }
            let size = high - low;
            !members.is_empty()
                && size.x >= LASH_SPAN * width
                && size.y <= LASH_RISE * size.x
                && size.z <= LASH_DEPTH * width
        })
    }
}

/// A mask holding a rig's still parts: weight 0 everywhere it lists, for every muscle.
pub(super) fn is_still(rig: &Rig, mask: &Mask) -> bool {
    mask.weights.iter().all(|&(_, w)| w == 0.0)
        && rig
            .muscles
            .iter()
            .all(|muscle| mask.muscles.contains(&muscle.name))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A row of lashes along the built-in face's upper lid is told from an eyeball and an
    /// iris at the same eye, and from the same row away from the eyes.
    #[test]
    fn lashes_are_found_by_where_they_sit() {
        let face = crate::io::builtin::default_mesh();
        let points = crate::io::builtin::landmarks("face")
            .unwrap()
            .positions(&face)
            .unwrap();
        let test = LashTest::new(&points).unwrap();
        let ((centre, width), axes) = (test.eyes[0], test.axes);
        let at = |across: f64, up: f64, forward: f64| {
            (centre + axes[0] * across + axes[1] * up + axes[2] * forward).as_vec3()
        };
        let piece = |positions: Vec<glam::Vec3>| {
            let n = positions.len() as u32;
            let triangles = (1..n - 1).map(|k| [0, k, k + 1]).collect();
            (
                Mesh::new(positions, triangles).unwrap(),
                (0..n).collect::<Vec<u32>>(),
            )
        };
        // an arc over the opening, a few millimetres deep
        let arc: Vec<_> = (0..12)
            .map(|k| {
                let t = k as f64 / 11.0 - 0.5;
                at(
                    0.9 * width * t,
                    0.2 * width - 0.3 * width * t * t,
                    0.05 * width * (k % 2) as f64,
                )
            })
            .collect();
        let (mesh, members) = piece(arc.clone());
        assert!(test.at_a_lid(&mesh, &members));
        // the same arc on the cheek
        let low: Vec<_> = arc
            .iter()
            .map(|p| *p - (axes[1] * width).as_vec3())
            .collect();
        let (mesh, members) = piece(low);
        assert!(!test.at_a_lid(&mesh, &members));
        // a ball behind the opening, and a disc in it
        let ring = |radius: f64, depth: f64| -> Vec<glam::Vec3> {
            (0..16)
                .map(|k| {
                    let a = std::f64::consts::TAU * k as f64 / 16.0;
                    at(radius * a.cos(), radius * a.sin(), -depth * (k % 2) as f64)
                })
                .collect()
        };
        for (radius, depth) in [(0.4 * width, 0.8 * width), (0.2 * width, 0.05 * width)] {
            let (mesh, members) = piece(ring(radius, depth));
            assert!(!test.at_a_lid(&mesh, &members), "{radius} {depth}");
        }
    }

    #[test]
    fn names() {
        for name in ["helper-l-eye", "Eyeball_L", "teeth_upper", "helper-tongue"] {
            assert!(rigid_name(name), "{name}");
        }
        for name in [
            "body",
            "Head",
            "skin",
            "eyebrows",
            "lashes",
            "helper-l-eyelashes-1",
        ] {
            assert!(!rigid_name(name), "{name}");
        }
        for name in [
            "helper-hair",
            "helper-Skirt",
            "joint-jaw",
            "joint-l-eye-target",
        ] {
            assert!(helper_name(name), "{name}");
        }
        for name in [
            "hair",
            "body",
            "helper-tongue",
            "helper-upper-teeth",
            "Eyelashes",
        ] {
            assert!(!helper_name(name), "{name}");
        }
        assert!(!helper_name("helper-l-eyelashes-1"));
        assert!(lash_name("helper-r-eyelashes-2") && lash_name("Eyelashes"));
        assert!(!lash_name("eyebrows"));
        // the films of game-engine heads (ICT's and Unreal's names) close with their lids
        for name in [
            "M_EyeOcclusion",
            "M_EyeBlend",
            "M_LacrimalFluid",
            "eyeshell_lod0",
            "FaceTearLine",
            "eyeEdge_lod0_mesh",
        ] {
            assert!(
                lash_name(name) && undrawn_name(name) && !rigid_name(name),
                "{name}"
            );
        }
        for name in [
            "M_ScleraLeft",
            "M_IrisRight",
            "Eye_L",
            "M_Face",
            "M_BackHead",
        ] {
            assert!(!lash_name(name), "{name}");
        }
        assert!(jaw_name("helper-lower-teeth"));
        assert!(jaw_name("Tongue"));
        assert!(!jaw_name("helper-upper-teeth"));
        assert!(!jaw_name("helper-l-eye"));
        for name in ["teeth", "Mouth_Teeth_Tongue", "material:TeethGums", "mouth"] {
            assert!(mixed_mouth_name(name), "{name}");
        }
        for name in [
            "upper_teeth",
            "lower_gum",
            "tongue",
            "helper-l-eye",
            "mouth_interior",
        ] {
            assert!(!mixed_mouth_name(name), "{name}");
        }
    }

    #[test]
    fn components_split_separate_pieces() {
        let p = glam::Vec3::ZERO;
        let mesh = Mesh::new(vec![p; 7], vec![[0, 1, 2], [2, 3, 0], [4, 5, 6]]).unwrap();
        let c = components(&mesh);
        assert_eq!(c[0], c[3]);
        assert_ne!(c[0], c[4]);
        assert_eq!(c[4], c[6]);
    }

    #[test]
    fn loose_vertices_are_said_in_one_line() {
        let p = glam::Vec3::ZERO;
        let mut points = vec![p; 3];
        points.extend((0..500).map(|k| glam::Vec3::splat(k as f32)));
        let mesh = Mesh::new(points, vec![[0, 1, 2]]).unwrap();
        let parts = find_parts(&mesh, &[0], &[p], &PartOverrides::default());
        let loose: Vec<_> = parts
            .choices
            .iter()
            .filter(|c| c.name.starts_with("loose"))
            .collect();
        assert_eq!(loose.len(), 1, "{:?}", parts.choices);
        assert_eq!(loose[0].vertices, 500);
        assert_eq!(loose[0].part, Part::Still);
        assert_eq!(parts.choices.len(), 2, "{:?}", parts.choices);
    }
}
