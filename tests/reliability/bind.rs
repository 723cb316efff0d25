//! Binding memory has a budget: a rig whose muscles would move more (vertex, muscle) pairs
//! than `MAX_INFLUENCES` is refused with a message before any field is kept, instead of
//! aborting on a failed allocation.

use std::fmt::Write;

use grimace::model::deform::MAX_INFLUENCES;
use grimace::model::rig::RIG_VERSION;

use crate::common;
use common::grimace_in as grimace;

/// A flat grid of `side` x `side` vertices in -1..1, two triangles per cell.
fn grid_obj(side: usize) -> String {
    let mut text = String::new();
    let step = 2.0 / (side - 1) as f64;
    for row in 0..side {
        for column in 0..side {
            let _ = writeln!(
                text,
                "v {:.5} {:.5} 0.1",
                -1.0 + column as f64 * step,
                -1.0 + row as f64 * step
            );
        }
    }
    for row in 0..side - 1 {
        for column in 0..side - 1 {
            let a = row * side + column + 1;
            let _ = writeln!(text, "f {a} {} {}", a + 1, a + side + 1);
            let _ = writeln!(text, "f {a} {} {}", a + side + 1, a + side);
        }
    }
    text
}

/// `count` sphincters, each reaching the whole grid.
fn wide_rig(count: usize) -> String {
    let mut text = format!("(version: {RIG_VERSION}, mesh: \"grid.obj\", muscles: [\n");
    for i in 0..count {
        let _ = writeln!(
            text,
            "(name: \"m{i}\", side: Centre, kind: Sphincter(centre: (0.013, 0.017, 0.0), \
             semi_major: 100.0, semi_minor: 100.0, convergence: Centre, bulge: 0.1)),"
        );
    }
    text.push_str("])\n");
    text
}

#[test]
fn a_rig_past_the_binding_budget_is_refused_with_a_message() {
    let side = 370;
    let muscles = 256;
    assert!(muscles * (side * side - 1) > MAX_INFLUENCES);
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("grid.obj"), grid_obj(side)).unwrap();
    std::fs::write(dir.path().join("wide.rig.ron"), wide_rig(muscles)).unwrap();
    let out = grimace(dir.path(), &["validate", "wide.rig.ron"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    // Every muscle moves every vertex: the count passes the limit at muscle `m245`.
    let passed = MAX_INFLUENCES / (side * side);
    assert_eq!(
        stderr.trim_end(),
        format!(
            "grimace validate: wide.rig.ron: the muscles move more than {MAX_INFLUENCES} (vertex, muscle) pairs of this {}-vertex mesh (passed at muscle `m{passed}`), about 1.2 GB bound; use fewer or smaller muscles, or a smaller mesh",
            side * side
        )
    );
    // Under the budget the same mesh binds.
    std::fs::write(dir.path().join("some.rig.ron"), wide_rig(8)).unwrap();
    let out = grimace(dir.path(), &["validate", "some.rig.ron"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}
