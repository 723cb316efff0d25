//! The built-in face's lids: AU45 and AU43 close the eye across the whole lid width, the
//! upper lid sliding over the eyeball, never into it; AU5 opens the eye wider.

use glam::Vec3;
use grimace::face::anthropometry::units;
use grimace::face::anthropometry::y_units;
use grimace::face::generator::EYEBALL;
use grimace::facs::combo::parse_combo;
use grimace::io::builtin;
use grimace::model::{Activations, BoundRig, Mesh, SkinRules};

/// The face at AU `key` at full intensity, bound with `skin`.
fn deformed(mesh: &Mesh, key: &str, skin: SkinRules) -> Vec<Vec3> {
    let rig = builtin::default_rig();
    let table = builtin::default_table();
    let combo = parse_combo(&format!("{key}E")).expect("AU parses");
    let act: Activations = table.evaluate(&combo, &rig).expect("AU evaluates");
    let bound = BoundRig::bind_with(&rig, mesh, skin).expect("rig binds");
    let mut out = Vec::new();
    bound.deform(&act, &mut out).expect("deforms");
    out
}

/// Each column of the lid: `(upper margin vertex, lower margin vertex)` with the same rest
/// x, the corners (shared by both lids) left out.
fn lid_columns(mesh: &Mesh, side: &str) -> Vec<(u32, u32)> {
    let upper = &mesh.groups[&format!("{side}_upper_lid")];
    let lower = &mesh.groups[&format!("{side}_lower_lid")];
    let mut columns = Vec::new();
    for &u in upper {
        let x = mesh.positions[u as usize].x;
        if let Some(&l) = lower
            .iter()
            .find(|&&l| l != u && mesh.positions[l as usize].x == x)
        {
            columns.push((u, l));
        }
    }
    columns
}

/// The largest gap at `positions`, as a fraction of the rest gap of the same column.
fn worst_gap(mesh: &Mesh, positions: &[Vec3], columns: &[(u32, u32)]) -> (f32, usize) {
    let mut worst = (0.0f32, 0);
    for (i, &(u, l)) in columns.iter().enumerate() {
        let rest = mesh.positions[u as usize].y - mesh.positions[l as usize].y;
        let now = positions[u as usize].y - positions[l as usize].y;
        let share = now / rest;
        if share > worst.0 {
            worst = (share, i);
        }
    }
    worst
}

#[test]
fn blink_and_closed_eyes_meet_across_the_whole_lid() {
    let mesh = builtin::default_mesh();
    for skin in [SkinRules::DEFAULT, SkinRules::PAPER] {
        for key in ["45", "43"] {
            let out = deformed(&mesh, key, skin);
            for side in ["left", "right"] {
                let columns = lid_columns(&mesh, side);
                assert!(columns.len() >= 5, "{side}: {} lid columns", columns.len());
                let (share, at) = worst_gap(&mesh, &out, &columns);
                println!("AU{key} {side} ({skin:?}): largest gap {:.1} % of the rest gap (column {at} of {})", 100.0 * share, columns.len());
                assert!(
                    share.abs() < 0.1,
                    "AU{key}: the {side} lids keep {:.0} % of their opening at column {at}",
                    100.0 * share
                );
            }
        }
    }
}

#[test]
fn no_lid_vertex_goes_inside_the_eyeball() {
    let mesh = builtin::default_mesh();
    let [cx, cy, cz] = EYEBALL.centre;
    let radius = units(EYEBALL.radius) as f32;
    for key in ["45", "43", "5", "7", "6"] {
        let out = deformed(&mesh, key, SkinRules::DEFAULT);
        for (side, sign) in [("left", 1.0f32), ("right", -1.0)] {
            let centre = Vec3::new(
                sign * units(cx) as f32,
                y_units(cy) as f32,
                units(cz) as f32,
            );
            for lid in ["upper_lid", "lower_lid"] {
                for &v in &mesh.groups[&format!("{side}_{lid}")] {
                    let d = out[v as usize].distance(centre);
                    assert!(
                        d >= radius,
                        "AU{key}: {side} {lid} vertex {v} lies {:.2} mm inside the eyeball",
                        (radius - d) * 11.5
                    );
                }
            }
        }
    }
}

#[test]
fn au5_opens_the_eye_wider() {
    let mesh = builtin::default_mesh();
    let out = deformed(&mesh, "5", SkinRules::DEFAULT);
    for side in ["left", "right"] {
        let columns = lid_columns(&mesh, side);
        let (u, l) = columns[columns.len() / 2];
        let rest = mesh.positions[u as usize].y - mesh.positions[l as usize].y;
        let now = out[u as usize].y - out[l as usize].y;
        assert!(
            now > 1.15 * rest,
            "AU5: the {side} eye opens {now} from {rest}"
        );
    }
}
