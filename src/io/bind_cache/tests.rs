use super::*;
use crate::io::builtin;
use crate::model::{Activations, SkinRules};

/// The built-in face and rig, with a jaw, masks-free muscles and the skin rules on.
fn face() -> (Rig, Mesh) {
    (builtin::default_rig(), builtin::default_mesh())
}

fn bits(p: &[glam::Vec3]) -> Vec<[u32; 3]> {
    p.iter().map(|v| v.to_array().map(f32::to_bits)).collect()
}

/// A smile with the jaw open: muscles, slide, area bound and jaw all at work.
fn pose(bound: &BoundRig) -> Vec<[u32; 3]> {
    let rig = bound.rig();
    let mut act = builtin::default_table()
        .expression_activations("happiness", rig)
        .unwrap_or_else(|_| Activations::zero(rig));
    act.jaw = 2.5;
    let mut out = Vec::new();
    bound.deform(&act, &mut out).unwrap();
    bits(&out)
}

#[test]
fn a_cached_bind_is_the_fresh_bind_bit_for_bit() {
    let dir = tempfile::tempdir().unwrap();
    let cache = BindCache::at(dir.path());
    let (rig, mesh) = face();
    for model in Deformation::ALL {
        let first = cache.bind(model, &rig, &mesh).unwrap();
        assert!(!first.from_cache, "{model}: nothing cached yet");
        assert!(first.warnings.is_empty(), "{:?}", first.warnings);
        let path = cache.path(model, &rig, &mesh).unwrap();
        assert!(path.is_file(), "{model}: the cache file is written");
        let second = cache.bind(model, &rig, &mesh).unwrap();
        assert!(second.from_cache, "{model}: read back");
        assert!(second.warnings.is_empty(), "{:?}", second.warnings);
        let fresh = model.bind(&rig, &mesh).unwrap();
        assert!(
            second.bound == fresh,
            "{model}: the cached bind equals a fresh one"
        );
        assert_eq!(pose(&second.bound), pose(&fresh));
    }
    if SkinRules::DEFAULT.slide > 0.0 {
        let d = Deformation::Skin;
        let p = Deformation::Paper;
        assert_ne!(cache.path(d, &rig, &mesh), cache.path(p, &rig, &mesh));
    }
}

/// Binds once to write the file, damages it with `damage`, then binds again: the damaged
/// file must be refused with a warning and the bind must equal a fresh one.
fn refused_after(damage: impl Fn(&mut Vec<u8>)) -> Vec<String> {
    let dir = tempfile::tempdir().unwrap();
    let cache = BindCache::at(dir.path());
    let (rig, mesh) = face();
    let model = Deformation::Skin;
    cache.bind(model, &rig, &mesh).unwrap();
    let path = cache.path(model, &rig, &mesh).unwrap();
    let mut bytes = fs::read(&path).unwrap();
    damage(&mut bytes);
    fs::write(&path, &bytes).unwrap();
    let again = cache.bind(model, &rig, &mesh).unwrap();
    assert!(!again.from_cache, "a damaged file is never trusted");
    assert!(again.bound == model.bind(&rig, &mesh).unwrap());
    assert_eq!(again.warnings.len(), 1, "{:?}", again.warnings);
    // it was written again, whole
    let third = cache.bind(model, &rig, &mesh).unwrap();
    assert!(third.from_cache && third.warnings.is_empty());
    again.warnings
}

#[test]
fn a_damaged_cache_is_bound_afresh_with_a_warning_and_written_again() {
    let flipped = refused_after(|b| {
        let at = b.len() / 2;
        b[at] ^= 0x10;
    });
    assert!(flipped[0].contains("checksum"), "{flipped:?}");
    let cut = refused_after(|b| b.truncate(b.len() - 100));
    assert!(cut[0].contains("cut short"), "{cut:?}");
    let header = refused_after(|b| b.truncate(20));
    assert!(header[0].contains("header"), "{header:?}");
    let longer = refused_after(|b| b.extend_from_slice(&[0; 8]));
    assert!(longer[0].contains("length"), "{longer:?}");
    let foreign = refused_after(|b| b[..8].copy_from_slice(b"NOTBINDS"));
    assert!(foreign[0].contains("not a bind cache"), "{foreign:?}");
    let version = refused_after(|b| b[8] = b[8].wrapping_add(1));
    assert!(version[0].contains("version"), "{version:?}");
    let key = refused_after(|b| b[20] ^= 1);
    assert!(key[0].contains("another rig"), "{key:?}");
}

#[test]
fn a_consistent_file_with_wrong_parts_is_refused_by_the_model() {
    // A file whose checksum is right but whose counts do not fit the rig (written for one
    // muscle fewer): only the model's own checks can catch it.
    let dir = tempfile::tempdir().unwrap();
    let cache = BindCache::at(dir.path());
    let (rig, mesh) = face();
    let model = Deformation::Skin;
    let bound = model.bind(&rig, &mesh).unwrap();
    let key = key(model.skin(), &rig, &mesh);
    let mut parts = bound.cache_parts();
    parts.fields = &parts.fields[1..];
    let path = cache.path(model, &rig, &mesh).unwrap();
    let mut out = std::io::Cursor::new(Vec::new());
    format::write(&mut out, &key, &parts).unwrap();
    fs::write(&path, out.into_inner()).unwrap();
    let again = cache.bind(model, &rig, &mesh).unwrap();
    assert!(!again.from_cache);
    assert!(
        again.warnings[0].contains("fields kept for"),
        "{:?}",
        again.warnings
    );
}

#[test]
fn the_key_follows_the_rig_the_mesh_and_the_rules() {
    let (rig, mesh) = face();
    let base = key(SkinRules::DEFAULT, &rig, &mesh);
    assert_eq!(base, key(SkinRules::DEFAULT, &rig, &mesh));
    let rules = SkinRules {
        patch: SkinRules::DEFAULT.patch * 1.01,
        ..SkinRules::DEFAULT
    };
    assert_ne!(key(rules, &rig, &mesh), base);
    let mut moved = mesh.clone();
    moved.positions[17].y += 1e-6;
    assert_ne!(key(SkinRules::DEFAULT, &rig, &moved), base);
    let mut edited = rig.clone();
    if let Some(jaw) = &mut edited.jaw {
        jaw.weights[0].1 *= 0.5;
    }
    assert_ne!(key(SkinRules::DEFAULT, &edited, &mesh), base);
    let mut renamed = rig.clone();
    renamed.muscles[0].name.push('x');
    assert_ne!(key(SkinRules::DEFAULT, &renamed, &mesh), base);
    // the rig's mesh file name is not part of what a bind reads
    let mut elsewhere = rig.clone();
    elsewhere.mesh = "elsewhere.obj".into();
    assert_eq!(key(SkinRules::DEFAULT, &elsewhere, &mesh), base);
}

#[test]
fn a_cache_that_cannot_be_written_is_a_warning_and_small_meshes_are_not_cached() {
    let dir = tempfile::tempdir().unwrap();
    let blocker = dir.path().join("file");
    fs::write(&blocker, b"not a folder").unwrap();
    let (rig, mesh) = face();
    let done = BindCache::at(&blocker)
        .bind(Deformation::Skin, &rig, &mesh)
        .unwrap();
    assert!(!done.from_cache);
    assert!(
        done.warnings[0].contains("cannot write"),
        "{:?}",
        done.warnings
    );
    let small = BindCache {
        dir: Some(dir.path().join("small")),
        min_vertices: CACHE_MIN_VERTICES,
    };
    assert!(mesh.positions.len() < CACHE_MIN_VERTICES);
    small.bind(Deformation::Skin, &rig, &mesh).unwrap();
    assert!(!dir.path().join("small").exists());
}

#[test]
fn old_files_are_pruned_beyond_the_kept_count() {
    let dir = tempfile::tempdir().unwrap();
    for i in 0..KEEP_FILES + 3 {
        fs::write(dir.path().join(format!("{i:032x}.bind")), b"x").unwrap();
    }
    fs::write(dir.path().join("other.txt"), b"kept").unwrap();
    let keep = dir.path().join(format!("{:032x}.bind", 0));
    prune(dir.path(), &keep);
    let left: Vec<_> = fs::read_dir(dir.path()).unwrap().collect();
    assert_eq!(
        left.len(),
        KEEP_FILES + 1,
        "the newest files and the other file"
    );
    assert!(keep.exists() && dir.path().join("other.txt").exists());
}
