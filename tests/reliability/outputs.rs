//! Outputs and references: no command writes over one of its inputs or a file they name,
//! however the path is spelt (relative, `..`, a symbolic or hard link); any other file it
//! replaces is kept as `NAME~`; every reference a command writes (a rig's mesh, a table's
//! rig) resolves from where the file really is, loaded from another working directory and
//! through links.

use std::fs;
use std::path::{Path, PathBuf};
use std::process::Output;

use crate::common::grimace_in as grimace;

/// A folder with a head to work on: `meshes/head.obj` (the built-in face's rest mesh),
/// `meshes/head.landmarks.ron`, and `rigs/head.rig.ron` fitted to it.
struct Head {
    _dir: tempfile::TempDir,
    root: PathBuf,
}

impl Head {
    fn new() -> Head {
        let dir = tempfile::tempdir().unwrap();
        let root = fs::canonicalize(dir.path()).unwrap();
        fs::create_dir_all(root.join("meshes")).unwrap();
        fs::create_dir_all(root.join("rigs")).unwrap();
        ok(&grimace(&root, &["export", "--out", "meshes/head.obj"]));
        fs::copy(
            Path::new(env!("CARGO_MANIFEST_DIR")).join("presets/default.landmarks.ron"),
            root.join("meshes/head.landmarks.ron"),
        )
        .unwrap();
        ok(&grimace(
            &root,
            &[
                "fit-rig",
                "meshes/head.obj",
                "--landmarks",
                "meshes/head.landmarks.ron",
                "--out",
                "rigs/head.rig.ron",
            ],
        ));
        Head { _dir: dir, root }
    }

    fn path(&self, name: &str) -> PathBuf {
        self.root.join(name)
    }

    fn run(&self, args: &[&str]) -> Output {
        grimace(&self.root, args)
    }
}

fn ok(out: &Output) {
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// Exit 1, a message saying the output is an input, and the input unchanged.
fn refused(out: &Output, input: &Path, before: &[u8], what: &str) {
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{what}: {stderr}");
    assert!(
        stderr.contains("an input of this command"),
        "{what}: {stderr}"
    );
    assert_eq!(
        fs::read(input).unwrap(),
        before,
        "{what}: the input changed"
    );
    let backup = format!("{}~", input.file_name().unwrap().to_string_lossy());
    assert!(
        !input.with_file_name(backup).exists(),
        "{what}: nothing was replaced, so there is no backup"
    );
}

#[test]
fn no_command_writes_over_its_inputs_however_spelt() {
    let head = Head::new();
    let mesh = head.path("meshes/head.obj");
    let rig = head.path("rigs/head.rig.ron");
    let marks = head.path("meshes/head.landmarks.ron");
    let mesh_bytes = fs::read(&mesh).unwrap();
    let rig_bytes = fs::read(&rig).unwrap();
    let marks_bytes = fs::read(&marks).unwrap();
    #[cfg(unix)]
    {
        std::os::unix::fs::symlink(&mesh, head.path("link.obj")).unwrap();
        std::os::unix::fs::symlink(&mesh, head.path("link.svg")).unwrap();
        std::os::unix::fs::symlink(&rig, head.path("rig-link.glb")).unwrap();
        fs::hard_link(&mesh, head.path("hard.obj")).unwrap();
    }
    let fit = |out: &str| {
        head.run(&[
            "fit-rig",
            "meshes/head.obj",
            "--landmarks",
            "meshes/head.landmarks.ron",
            "--out",
            out,
        ])
    };
    refused(
        &fit("meshes/head.obj"),
        &mesh,
        &mesh_bytes,
        "fit-rig onto its mesh",
    );
    refused(
        &fit("rigs/../meshes/./head.obj"),
        &mesh,
        &mesh_bytes,
        "fit-rig, `..`",
    );
    refused(
        &fit("meshes/head.landmarks.ron"),
        &marks,
        &marks_bytes,
        "fit-rig onto its landmarks",
    );
    let export = |out: &str| {
        head.run(&[
            "export",
            "--rig",
            "rigs/head.rig.ron",
            "--table",
            "builtin:default",
            "--au",
            "12",
            "--out",
            out,
        ])
    };
    // The rig's mesh: every later command would start from a smile.
    refused(
        &export("meshes/head.obj"),
        &mesh,
        &mesh_bytes,
        "export onto the rig's mesh",
    );
    refused(
        &export("rigs/head.rig.ron"),
        &rig,
        &rig_bytes,
        "export onto the rig",
    );
    let gltf = head.run(&[
        "export",
        "--gltf",
        "rigs/head.rig.ron",
        "--rig",
        "rigs/head.rig.ron",
        "--table",
        "builtin:default",
    ]);
    refused(&gltf, &rig, &rig_bytes, "glTF onto the rig");
    let render = |out: &str| {
        head.run(&[
            "render",
            "--rig",
            "rigs/head.rig.ron",
            "--table",
            "builtin:default",
            "--au",
            "12",
            "--out",
            out,
        ])
    };
    let in_mesh_folder = head.run(&[
        "export",
        "--mesh",
        "meshes/head.obj",
        "--rig",
        "rigs/head.rig.ron",
        "--out",
        "./meshes/head.obj",
    ]);
    refused(&in_mesh_folder, &mesh, &mesh_bytes, "export onto --mesh");
    #[cfg(unix)]
    {
        refused(
            &fit("link.obj"),
            &mesh,
            &mesh_bytes,
            "fit-rig through a link",
        );
        refused(
            &export("hard.obj"),
            &mesh,
            &mesh_bytes,
            "export onto a hard link",
        );
        refused(
            &render("link.svg"),
            &mesh,
            &mesh_bytes,
            "render through a link",
        );
        let gltf = head.run(&[
            "export",
            "--gltf",
            "rig-link.glb",
            "--rig",
            "rigs/head.rig.ron",
            "--table",
            "builtin:default",
        ]);
        refused(&gltf, &rig, &rig_bytes, "glTF through a link");
    }
    // The rig still loads and starts from the rest mesh.
    ok(&export("smile.obj"));
}

#[test]
fn replaced_outputs_are_kept_as_backups() {
    let head = Head::new();
    let out = head.path("smile.obj");
    fs::write(&out, "my own file\n").unwrap();
    ok(&head.run(&["export", "--au", "12", "--out", "smile.obj"]));
    assert_eq!(
        fs::read_to_string(head.path("smile.obj~")).unwrap(),
        "my own file\n"
    );
    fs::write(head.path("face.glb"), "older\n").unwrap();
    ok(&head.run(&["export", "--gltf", "face.glb"]));
    assert_eq!(
        fs::read_to_string(head.path("face.glb~")).unwrap(),
        "older\n"
    );
    fs::write(head.path("s.svg"), "older\n").unwrap();
    ok(&head.run(&["render", "--au", "12", "--out", "s.svg"]));
    assert_eq!(fs::read_to_string(head.path("s.svg~")).unwrap(), "older\n");
    fs::create_dir(head.path("all")).unwrap();
    fs::write(head.path("all/au-12.txt"), "older\n").unwrap();
    ok(&head.run(&["render", "--all", "--format", "txt", "--out", "all"]));
    assert_eq!(
        fs::read_to_string(head.path("all/au-12.txt~")).unwrap(),
        "older\n"
    );
}

/// Loads `rig` (and `table` with it, if given) from a folder unrelated to both.
fn loads_from_elsewhere(rig: &Path, table: Option<&Path>) {
    let elsewhere = tempfile::tempdir().unwrap();
    let out = elsewhere.path().join("x.obj");
    let mut args = vec!["export", "--rig", rig.to_str().unwrap()];
    if let Some(table) = table {
        args.extend(["--table", table.to_str().unwrap(), "--au", "12"]);
    }
    args.extend(["--out", out.to_str().unwrap()]);
    ok(&grimace(elsewhere.path(), &args));
    if let Some(table) = table {
        // The table's own rig reference, without --rig.
        ok(&grimace(
            elsewhere.path(),
            &[
                "export",
                "--table",
                table.to_str().unwrap(),
                "--au",
                "12",
                "--out",
                out.to_str().unwrap(),
            ],
        ));
    }
}

#[test]
fn written_references_resolve_from_the_files_real_folder() {
    let head = Head::new();
    // The fitted rig names its mesh relative to its folder, not absolutely.
    let text = fs::read_to_string(head.path("rigs/head.rig.ron")).unwrap();
    assert!(text.contains("mesh: \"../meshes/head.obj\""), "{text}");
    loads_from_elsewhere(&head.path("rigs/head.rig.ron"), None);

    // Fitted through a link in another folder: the reference goes from the real file.
    fs::create_dir_all(head.path("real")).unwrap();
    fs::create_dir_all(head.path("links/deeper")).unwrap();
    fs::write(head.path("real/b.rig.ron"), "").unwrap();
    fs::write(head.path("real/t.au.ron"), "").unwrap();
    ok(&head.run(&[
        "export",
        "--rig",
        "rigs/head.rig.ron",
        "--table",
        "builtin:default",
        "--au",
        "12",
        "--out",
        "smile.obj",
    ]));
    #[cfg(unix)]
    {
        std::os::unix::fs::symlink(
            head.path("real/b.rig.ron"),
            head.path("links/deeper/b.rig.ron"),
        )
        .unwrap();
        std::os::unix::fs::symlink(head.path("real/t.au.ron"), head.path("links/t.au.ron"))
            .unwrap();
        fs::remove_file(head.path("real/t.au.ron")).unwrap();
        ok(&head.run(&[
            "fit-rig",
            "meshes/head.obj",
            "--landmarks",
            "meshes/head.landmarks.ron",
            "--out",
            "links/deeper/b.rig.ron",
        ]));
        loads_from_elsewhere(&head.path("links/deeper/b.rig.ron"), None);
        loads_from_elsewhere(&head.path("real/b.rig.ron"), None);
        // fit-au writes a new table through a link: its rig reference goes from the real file.
        ok(&head.run(&[
            "fit-au",
            "smile.obj",
            "--rig",
            "links/deeper/b.rig.ron",
            "--au",
            "12",
            "--table",
            "links/t.au.ron",
        ]));
        let table = fs::read_to_string(head.path("real/t.au.ron")).unwrap();
        assert!(table.contains("rig: \"b.rig.ron\""), "{table}");
        loads_from_elsewhere(
            &head.path("links/deeper/b.rig.ron"),
            Some(&head.path("links/t.au.ron")),
        );
        loads_from_elsewhere(
            &head.path("real/b.rig.ron"),
            Some(&head.path("real/t.au.ron")),
        );
    }
    // A table in another folder names the rig with `..`, not an absolute path.
    fs::create_dir_all(head.path("tables")).unwrap();
    ok(&head.run(&[
        "fit-au",
        "smile.obj",
        "--rig",
        "rigs/head.rig.ron",
        "--au",
        "12",
        "--table",
        "tables/t.au.ron",
    ]));
    let table = fs::read_to_string(head.path("tables/t.au.ron")).unwrap();
    assert!(table.contains("rig: \"../rigs/head.rig.ron\""), "{table}");
    loads_from_elsewhere(
        &head.path("rigs/head.rig.ron"),
        Some(&head.path("tables/t.au.ron")),
    );
}
