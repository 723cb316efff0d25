//! The embedded default face, rigs and AU table load with the project's own loaders and fit
//! together; the committed presets are exactly what the generator writes.

use std::path::Path;

use grimace::face::generate;
use grimace::io::builtin;
use grimace::io::presets;
use grimace::model::BoundRig;

#[test]
fn embedded_files_load_and_fit_together() {
    let mesh = builtin::load_mesh().expect("embedded face loads");
    let paper = builtin::load_rig(builtin::PAPER_RIG, "paper.rig.ron").expect("paper rig loads");
    let default =
        builtin::load_rig(builtin::DEFAULT_RIG, "default.rig.ron").expect("default rig loads");
    let table = builtin::load_table(builtin::DEFAULT_TABLE, "default.au.ron").expect("table loads");
    for rig in [&paper, &default] {
        grimace::io::rig_file::check_rig_mesh(rig, &mesh).expect("rig fits the face");
    }
    BoundRig::bind(&paper, &mesh).expect("paper rig binds to the face");
    BoundRig::bind(&default, &mesh).expect("default rig binds to the face");
    table
        .check_rig(&default)
        .expect("every muscle of the table is in the default rig");
    assert_eq!(
        mesh.groups,
        generate().groups,
        "groups are found again in the embedded face"
    );
}

#[test]
fn builtin_names_resolve() {
    assert!(builtin::mesh("face").is_some());
    assert!(builtin::rig("default").is_some());
    assert!(builtin::rig("paper").is_some());
    assert!(builtin::table("default").is_some());
    assert!(builtin::mesh("nonesuch").is_none());
    assert!(builtin::rig("face").is_none());
    assert_eq!(
        builtin::builtin_name(Path::new("builtin:paper")),
        Some("paper")
    );
    assert_eq!(builtin::builtin_name(Path::new("rigs/paper.rig.ron")), None);
    assert_eq!(builtin::default_rig().mesh, Path::new("builtin:face"));
    assert_eq!(builtin::default_table().rig, Path::new("builtin:default"));
}

#[test]
fn committed_presets_are_exactly_what_the_generator_writes() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("presets");
    for (name, text) in presets::preset_files(&generate()).expect("rigs place") {
        let committed = std::fs::read_to_string(root.join(name)).expect("preset readable");
        assert!(
            committed == text,
            "presets/{name} differs from the generator: run `grimace gen-face --presets presets`"
        );
    }
}
