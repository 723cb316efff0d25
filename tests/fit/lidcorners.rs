//! The lids' corners on a fitted head: the lower lid's ring (AU7) fades along the skin to the
//! canthi (`src/fit/lowerlid.rs`). The closing ring's fold rows at the canthi (AU43/45/46,
//! `src/fit/lids.rs`) are checked in `lidfold.rs`.

use grimace::fit::quality::{Expect, Gauge};
use grimace::model::{BoundRig, MuscleKind, SkinRules};

/// AU7 and its one-sided forms on the fitted MakeHuman head. The lower lid ring's carried
/// mask stepped from 0 to 1 between two rows of a canthus's fold 0.6 mm apart: 12 triangles
/// turned over at AU7 (6 per side) and an edge stretched 2.64x. Now none turns and no edge
/// stretches past 2.5x.
#[test]
fn makehuman_lid_tightener_tears_nothing() {
    let Some((_, mesh, landmarks)) = crate::shared_makehuman() else {
        return;
    };
    let fitted = crate::fit_default(&mesh, &landmarks);
    let bound = BoundRig::bind_with(&fitted.rig, &mesh, SkinRules::DEFAULT).unwrap();
    let gauge = Gauge::new(&mesh, &landmarks.vertices(&mesh), None).unwrap();
    for key in ["7", "L7", "R7"] {
        let q = gauge.measure(&crate::positions_at_au(&bound, key), Expect::default());
        println!(
            "MakeHuman AU{key}: {} turned, stretch {:.2}",
            q.turned, q.stretch
        );
        assert_eq!(q.turned, 0, "AU{key}: {} turned", q.turned);
        assert!(q.stretch < 2.5, "AU{key}: stretch {}", q.stretch);
    }
}

/// The lower lid ring's weight on the fitted MakeHuman head changes smoothly over the skin
/// round each eye: across no skin edge inside the ring by more than 0.3 of its weight at the
/// lower lid's landmarks per millimetre (its carried mask stepped from 0.05 to 0.94 across
/// 0.6 mm at the inner canthus, 1.5 per mm), and it fades toward each canthus (under half
/// its weight at the lower lid's landmarks).
#[test]
fn makehuman_lower_lid_weight_is_continuous_at_the_canthi() {
    let Some((_, mesh, landmarks)) = crate::shared_makehuman() else {
        return;
    };
    let fitted = crate::fit_default(&mesh, &landmarks);
    let marks = landmarks.vertices(&mesh);
    let mm = Gauge::new(&mesh, &marks, None).unwrap().mm_per_unit();
    // (ring, corners, lower lid landmarks)
    for (name, corners, lower) in [
        ("R_Orbicularis_Oculi_Lower", [36, 39], [40, 41]),
        ("L_Orbicularis_Oculi_Lower", [42, 45], [46, 47]),
    ] {
        let muscle = fitted.rig.muscles.iter().find(|m| m.name == name).unwrap();
        let MuscleKind::Sphincter(ring) = &muscle.kind else {
            panic!("{name} is not a ring");
        };
        let w = |v: u32| fitted.rig.mask_weight(name, v) as f32;
        let near = |v: u32| mesh.positions[v as usize].distance(ring.centre) < ring.semi_major;
        let at_lid = lower
            .map(|i| w(marks[i]))
            .into_iter()
            .fold(f32::INFINITY, f32::min);
        let at_corners = corners
            .map(|i| w(marks[i]))
            .into_iter()
            .fold(0.0f32, f32::max);
        let worst = mesh
            .edges()
            .into_iter()
            .filter(|&[a, b]| near(a) && near(b))
            .filter(|&[a, b]| {
                fitted.parts.of_vertex[a as usize] == grimace::fit::Part::Skin
                    && fitted.parts.of_vertex[b as usize] == grimace::fit::Part::Skin
            })
            .map(|[a, b]| {
                let length = mesh.positions[a as usize].distance(mesh.positions[b as usize]) * mm;
                ((w(a) - w(b)).abs() / at_lid / length.max(1e-3), a, b)
            })
            .fold(
                (0.0f32, 0, 0),
                |best, x| if x.0 > best.0 { x } else { best },
            );
        println!(
            "{name}: steepest {:.3} of the lid's weight per mm (edge {}-{}), at the lower lid {at_lid:.3}, \
             at the corners {at_corners:.3}",
            worst.0, worst.1, worst.2
        );
        assert!(
            worst.0 < 0.3,
            "{name}: {:.3} per mm at edge {}-{}",
            worst.0,
            worst.1,
            worst.2
        );
        assert!(at_lid > 0.0, "{name}: no pull at the lower lid");
        assert!(
            at_corners < 0.5 * at_lid,
            "{name}: {at_corners} at a corner, {at_lid} at the lid"
        );
    }
}
