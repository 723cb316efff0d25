//! Named vertex groups of the default face: landmarks (single vertices) and regions.
//!
//! Rigs are placed from these, and tests check muscle actions on them. Names use the
//! subject's sides (`left_` at x > 0, glTF's convention). Single-vertex landmarks: `nasion`, `nose_tip`,
//! `subnasale`, `upper_lip_centre`, `lower_lip_centre`, `chin`, `gnathion`,
//! `forehead_centre`, and per side `*_inner_eye_corner`, `*_outer_eye_corner`,
//! `*_upper_lid_centre`, `*_lower_lid_centre`, `*_mouth_corner`, `*_brow_inner`,
//! `*_brow_centre`, `*_brow_outer`, `*_cheekbone`, `*_alare`, `*_forehead`. Regions:
//! `upper_lip`, `lower_lip`, `*_upper_lid`, `*_lower_lid`, `*_brow`, `*_brow_hair` (the skin
//! under the eyebrows, drawn darker). The pieces after the
//! skin: the eyeballs, `*_eyeball` (all of it), and within it `*_iris` and `*_pupil`; the
//! mouth's parts ([`super::mouth`]): `upper_teeth`, `upper_gum`, `lower_teeth`, `lower_gum`,
//! `tongue`, `mouth_interior`. Every other group holds skin vertices only.
//!
//! The groups are recomputed from the mesh's positions and slit structure, so they follow
//! the generator; [`find_groups_in`] finds them again in a mesh read back from a file.

use std::collections::BTreeMap;

use glam::{Vec2, Vec3};

use super::anthropometry::*;
use super::generator::{Slit, Slits, Tissue, EYEBALL};
use super::mouth::{self, MouthPart};
use super::surface;
use crate::model::{Mask, Mesh, Rig};

/// Finds every named group of the default face.
pub fn find_groups(mesh: &Mesh, slits: &Slits) -> BTreeMap<String, Vec<u32>> {
    let mut groups = BTreeMap::new();
    let skin = &mesh.positions[..skin_len(mesh)];
    slit_groups(slits, &mut groups);
    landmark_groups(skin, &mut groups);
    region_groups(skin, &groups.clone(), &mut groups);
    piece_groups(mesh, skin.len(), &mut groups);
    for members in groups.values_mut() {
        members.sort_unstable();
        members.dedup();
    }
    groups
}

/// Finds the groups again in a mesh that has the default face's vertices but lost its
/// groups (for example after a round trip through OBJ): the slits are recovered from the
/// boundary edges that are not on the outer rim.
pub fn find_groups_in(mesh: &Mesh) -> BTreeMap<String, Vec<u32>> {
    find_groups(mesh, &recover_slits(mesh))
}

/// The number of skin vertices: the skin is the piece that holds vertex 0, and everything
/// after it (the eyeballs) was appended.
pub fn skin_len(mesh: &Mesh) -> usize {
    let component = crate::fit::parts::components(mesh);
    component
        .iter()
        .position(|&c| c != component[0])
        .unwrap_or(component.len())
}

/// The eyeballs' vertices: they never move.
pub fn still_vertices(mesh: &Mesh) -> Vec<u32> {
    vertices_of(mesh, &["left_eyeball", "right_eyeball"])
}

/// The vertices of the mouth's parts that the mandible carries: the lower teeth, the lower
/// gum and the tongue (jaw weight 1).
pub fn jaw_parts(mesh: &Mesh) -> Vec<u32> {
    let names: Vec<&str> = MouthPart::ALL
        .into_iter()
        .filter(|p| p.turns_with_jaw())
        .map(MouthPart::group)
        .collect();
    vertices_of(mesh, &names)
}

/// Every vertex that is not skin: the eyeballs and the mouth's parts.
pub fn rigid_vertices(mesh: &Mesh) -> Vec<u32> {
    let mut names = vec!["left_eyeball", "right_eyeball"];
    names.extend(MouthPart::ALL.map(MouthPart::group));
    vertices_of(mesh, &names)
}

/// The sorted vertices of the named groups.
fn vertices_of(mesh: &Mesh, names: &[&str]) -> Vec<u32> {
    let mut out: Vec<u32> = names
        .iter()
        .filter_map(|name| mesh.groups.get(*name))
        .flatten()
        .copied()
        .collect();
    out.sort_unstable();
    out.dedup();
    out
}

/// Keeps the parts that are not skin ([`rigid_vertices`]: eyeballs, teeth, gums, tongue,
/// the mouth's back wall) out of every muscle of `rig`: one mask of weight 0 on them naming
/// all its muscles, replacing an earlier one on the same vertices. The jaw's weights give
/// them 1 or 0 on their own ([`jaw_parts`]).
pub fn hold_still(mesh: &Mesh, rig: &mut Rig) {
    let weights: Vec<(u32, f32)> = rigid_vertices(mesh).into_iter().map(|v| (v, 0.0)).collect();
    if weights.is_empty() {
        return;
    }
    rig.masks.retain(|m| m.weights != weights);
    rig.masks.push(Mask {
        muscles: rig.muscles.iter().map(|m| m.name.clone()).collect(),
        gain: 1.0,
        weights,
    });
}

/// The groups of the pieces after the skin: a piece whose centre lies inside an eyeball's
/// globe is that eyeball, any other is the mouth's part whose designed centre lies nearest.
fn piece_groups(mesh: &Mesh, skin_len: usize, groups: &mut BTreeMap<String, Vec<u32>>) {
    let component = crate::fit::parts::components(mesh);
    let mut pieces: BTreeMap<u32, Vec<u32>> = BTreeMap::new();
    for (v, &c) in component.iter().enumerate().skip(skin_len) {
        pieces.entry(c).or_default().push(v as u32);
    }
    let [ex, ey, ez] = EYEBALL.centre;
    for members in pieces.values() {
        let mut centre = [0.0f64; 3];
        for &v in members {
            let [x, y, z] = mm_of(mesh.positions[v as usize]);
            centre = [centre[0] + x, centre[1] + y, centre[2] + z];
        }
        let centre = centre.map(|c| c / members.len() as f64);
        let from_eye = (centre[0].abs() - ex)
            .hypot(centre[1] - ey)
            .hypot(centre[2] - ez);
        if from_eye < EYEBALL.radius {
            eyeball_groups(mesh, members, groups);
        } else {
            let name = mouth::nearest_part(centre).group();
            groups.entry(name.to_string()).or_default().extend(members);
        }
    }
}

/// A mesh position in the generator's millimetres (x, height above the nasion, z).
fn mm_of(p: Vec3) -> [f64; 3] {
    [
        f64::from(p.x) * MM_PER_UNIT,
        f64::from(p.y) * MM_PER_UNIT + Y_ORIGIN_MM,
        f64::from(p.z) * MM_PER_UNIT,
    ]
}

/// `*_eyeball`, `*_iris` and `*_pupil` for the vertices of one eyeball, told apart by where
/// they lie on [`EYEBALL`]'s profile.
fn eyeball_groups(mesh: &Mesh, members: &[u32], groups: &mut BTreeMap<String, Vec<u32>>) {
    let profile = EYEBALL.profile();
    let [cx, cy, cz] = EYEBALL.centre;
    for &i in members {
        let p = mesh.positions[i as usize];
        let side = if p.x > 0.0 { "left" } else { "right" };
        let x = f64::from(p.x.abs()) * MM_PER_UNIT - cx;
        let y = f64::from(p.y) * MM_PER_UNIT + Y_ORIGIN_MM - cy;
        let z = f64::from(p.z) * MM_PER_UNIT - cz;
        let rho = x.hypot(y);
        let tissue = profile
            .iter()
            .min_by(|a, b| {
                let da = (a.0 - rho).hypot(a.1 - z);
                let db = (b.0 - rho).hypot(b.1 - z);
                da.total_cmp(&db)
            })
            .map_or(Tissue::Sclera, |ring| ring.2);
        groups.entry(format!("{side}_eyeball")).or_default().push(i);
        let part = match tissue {
            Tissue::Sclera => continue,
            Tissue::Iris => "iris",
            Tissue::Pupil => "pupil",
        };
        groups.entry(format!("{side}_{part}")).or_default().push(i);
    }
}

fn slit_groups(slits: &Slits, groups: &mut BTreeMap<String, Vec<u32>>) {
    for &(slit, upper, lower) in &slits.pairs {
        let (up, low) = match slit {
            Slit::LeftEye => ("left_upper_lid", "left_lower_lid"),
            Slit::RightEye => ("right_upper_lid", "right_lower_lid"),
            Slit::Mouth => ("upper_lip", "lower_lip"),
        };
        groups.entry(up.to_string()).or_default().push(upper);
        groups.entry(low.to_string()).or_default().push(lower);
    }
    for &(slit, low, high) in &slits.corners {
        let names: [&str; 2] = match slit {
            Slit::LeftEye => ["left_inner_eye_corner", "left_outer_eye_corner"],
            Slit::RightEye => ["right_outer_eye_corner", "right_inner_eye_corner"],
            Slit::Mouth => ["right_mouth_corner", "left_mouth_corner"],
        };
        groups.insert(names[0].to_string(), vec![low]);
        groups.insert(names[1].to_string(), vec![high]);
    }
}

/// Point in mesh units on the front of the face from millimetres (x, height above nasion).
fn mm(x: f64, y: f64) -> Vec2 {
    Vec2::new(units(x) as f32, y_units(y) as f32)
}

/// The front-facing vertex nearest `target` in the x-y plane (front view). Vertices round
/// the sides are skipped so a landmark never lands behind the face.
fn nearest(positions: &[Vec3], target: Vec2) -> u32 {
    let front = units(-45.0) as f32;
    let mut best = (f32::INFINITY, 0u32);
    for (i, p) in positions.iter().enumerate() {
        if p.z < front {
            continue;
        }
        let d = (Vec2::new(p.x, p.y) - target).length_squared();
        if d < best.0 {
            best = (d, i as u32);
        }
    }
    best.1
}

/// The midline vertex (x = 0) that maximises `score`.
fn best_on_midline(positions: &[Vec3], score: impl Fn(Vec3) -> f32) -> u32 {
    let mut best = (f32::NEG_INFINITY, 0u32);
    for (i, p) in positions.iter().enumerate() {
        if p.x == 0.0 && score(*p) > best.0 {
            best = (score(*p), i as u32);
        }
    }
    best.1
}

fn landmark_groups(positions: &[Vec3], groups: &mut BTreeMap<String, Vec<u32>>) {
    let mut put = |name: &str, v: u32| {
        groups.insert(name.to_string(), vec![v]);
    };
    let at_height = |y_mm: f64| {
        let y = y_units(y_mm) as f32;
        move |p: Vec3| -(p.y - y).abs()
    };
    put("nasion", best_on_midline(positions, at_height(0.0)));
    put("nose_tip", best_on_midline(positions, |p| p.z));
    put(
        "subnasale",
        best_on_midline(positions, at_height(SUBNASALE_Y)),
    );
    put("chin", best_on_midline(positions, at_height(POGONION_Y)));
    put("gnathion", best_on_midline(positions, |p| -p.y));
    put(
        "forehead_centre",
        best_on_midline(positions, at_height(40.0)),
    );
    for (side, sign) in [("left", 1.0), ("right", -1.0)] {
        let s = |x: f64| sign * x;
        let mut side_put = |name: &str, x: f64, y: f64| {
            put(&format!("{side}_{name}"), nearest(positions, mm(s(x), y)));
        };
        side_put("brow_inner", ENDOCANTHION_X + 2.0, BROW_Y - 1.0);
        side_put(
            "brow_centre",
            0.5 * (ENDOCANTHION_X + EXOCANTHION_X),
            BROW_Y + 1.0,
        );
        side_put("brow_outer", EXOCANTHION_X, BROW_Y - 2.0);
        side_put("cheekbone", 46.0, -30.0);
        side_put("alare", ALARE_X - 1.0, SUBNASALE_Y + 5.0);
        side_put("forehead", 25.0, 38.0);
    }
}

/// Lid centres, lip centres, lip vermilion and brow bands.
fn region_groups(
    positions: &[Vec3],
    found: &BTreeMap<String, Vec<u32>>,
    groups: &mut BTreeMap<String, Vec<u32>>,
) {
    for side in ["left", "right"] {
        let lid = |which: &str, pick: fn(f32, f32) -> bool| -> Option<u32> {
            let members = found.get(&format!("{side}_{which}_lid"))?;
            members.iter().copied().reduce(|a, b| {
                if pick(positions[b as usize].y, positions[a as usize].y) {
                    b
                } else {
                    a
                }
            })
        };
        if let Some(v) = lid("upper", |b, a| b > a) {
            groups.insert(format!("{side}_upper_lid_centre"), vec![v]);
        }
        if let Some(v) = lid("lower", |b, a| b < a) {
            groups.insert(format!("{side}_lower_lid_centre"), vec![v]);
        }
    }
    let midline_of = |name: &str| -> Option<u32> {
        found
            .get(name)?
            .iter()
            .copied()
            .find(|&v| positions[v as usize].x == 0.0)
    };
    if let Some(v) = midline_of("upper_lip") {
        groups.insert("upper_lip_centre".into(), vec![v]);
    }
    if let Some(v) = midline_of("lower_lip") {
        groups.insert("lower_lip_centre".into(), vec![v]);
    }
    vermilion(positions, found, groups);
    brows(positions, groups);
    super::brow::hair_groups(positions, groups);
}

/// Adds the vermilion of each lip (between the mouth line and the vermilion border) to the
/// `upper_lip` and `lower_lip` groups.
fn vermilion(
    positions: &[Vec3],
    found: &BTreeMap<String, Vec<u32>>,
    groups: &mut BTreeMap<String, Vec<u32>>,
) {
    let on_slit: Vec<u32> = ["upper_lip", "lower_lip"]
        .iter()
        .filter_map(|n| found.get(*n))
        .flatten()
        .copied()
        .collect();
    let sto = y_units(STOMION_Y) as f32;
    let corner = units(CHEILION_X) as f32;
    for (i, p) in positions.iter().enumerate() {
        let i = i as u32;
        if p.x.abs() >= corner || on_slit.contains(&i) || p.z < units(-45.0) as f32 {
            continue;
        }
        let x_mm = f64::from(p.x.abs()) * MM_PER_UNIT;
        let up = units(surface::upper_vermilion_height(x_mm) + 0.5) as f32;
        let down = units(surface::lower_vermilion_height(x_mm) + 0.5) as f32;
        if p.y > sto && p.y <= sto + up {
            groups.entry("upper_lip".into()).or_default().push(i);
        } else if p.y < sto && p.y >= sto - down {
            groups.entry("lower_lip".into()).or_default().push(i);
        }
    }
}

/// The brow bands: skin along the brow line over each eye.
fn brows(positions: &[Vec3], groups: &mut BTreeMap<String, Vec<u32>>) {
    let lo = y_units(BROW_Y - 5.0) as f32;
    let hi = y_units(BROW_Y + 4.0) as f32;
    let inner = units(ENDOCANTHION_X - 4.0) as f32;
    let outer = units(EXOCANTHION_X + 4.0) as f32;
    for (i, p) in positions.iter().enumerate() {
        if p.y < lo || p.y > hi || p.x.abs() < inner || p.x.abs() > outer {
            continue;
        }
        let name = if p.x > 0.0 { "left_brow" } else { "right_brow" };
        groups.entry(name.into()).or_default().push(i as u32);
    }
}

/// Recovers the slits of a default-face mesh from its boundary: every boundary loop but the
/// longest (the outer rim) is an eye or the mouth; the upper copies are the loop's vertices
/// above the line through its two corners (its vertices of lowest and highest x).
fn recover_slits(mesh: &Mesh) -> Slits {
    let mut slits = Slits::default();
    let mut loops = crate::face::topology::boundary_loops(mesh);
    loops.sort_by_key(|l| std::cmp::Reverse(l.len()));
    for lp in loops.iter().skip(1) {
        let p = |v: u32| mesh.positions[v as usize];
        let Some(low) = lp
            .iter()
            .copied()
            .min_by(|&a, &b| p(a).x.total_cmp(&p(b).x))
        else {
            continue;
        };
        let Some(high) = lp
            .iter()
            .copied()
            .max_by(|&a, &b| p(a).x.total_cmp(&p(b).x))
        else {
            continue;
        };
        let centre = 0.5 * (p(low) + p(high));
        let slit = if centre.x.abs() < 1e-6 {
            Slit::Mouth
        } else if centre.x > 0.0 {
            Slit::LeftEye
        } else {
            Slit::RightEye
        };
        slits.corners.push((slit, low, high));
        let mut uppers = Vec::new();
        let mut lowers = Vec::new();
        for &v in lp {
            if v == low || v == high {
                continue;
            }
            let t = (p(v).x - p(low).x) / (p(high).x - p(low).x);
            let line_y = p(low).y + t * (p(high).y - p(low).y);
            if p(v).y > line_y {
                uppers.push(v);
            } else {
                lowers.push(v);
            }
        }
        let by_x = |a: &u32, b: &u32| p(*a).x.total_cmp(&p(*b).x);
        uppers.sort_by(by_x);
        lowers.sort_by(by_x);
        for (u, l) in uppers.into_iter().zip(lowers) {
            slits.pairs.push((slit, u, l));
        }
    }
    slits
}
