//! Bad plans and arguments: a clear message naming the place, exit 1.

use super::*;

/// Runs a plan of `text` and returns its error message, asserting exit 1.
fn refused(text: &str, extra: &[&str]) -> String {
    let tmp = tempfile::tempdir().unwrap();
    let plan = plan(tmp.path(), text);
    let out_dir = tmp.path().join("out");
    let mut args = vec![plan.as_os_str(), "--out".as_ref(), out_dir.as_os_str()];
    args.extend(extra.iter().map(|a| std::ffi::OsStr::new(*a)));
    let out = run(&args);
    let message = stderr(&out);
    assert_eq!(out.status.code(), Some(1), "{message}");
    message
}

#[test]
fn bad_plans_are_refused_at_their_place() {
    let cases: [(&str, &str, &str); 6] = [
        (
            r#""builtin:default")"#,
            r#""missing.rig.ron")"#,
            "test.plan.ron:3:",
        ),
        (
            r#"Aus(["1", "12"])"#,
            r#"Aus(["1", "3"])"#,
            "AU 3 is not in its table",
        ),
        (
            r#"Aus(["1", "12"])"#,
            r#"Combos(["1+2+5Q"])"#,
            "test.plan.ron:4:26: combination `1+2+5Q`",
        ),
        (
            r#"["C"]"#,
            r#"["F"]"#,
            "test.plan.ron:5:19: `F` is not a FACS intensity letter",
        ),
        (r#"[Txt, Png]"#, r#"[Txt, Jpeg]"#, "test.plan.ron:8:"),
        (r#"version: 1"#, r#"version: 7"#, "version 7"),
    ];
    for (from, to, expected) in cases {
        let message = refused(&TINY.replacen(from, to, 1), &[]);
        assert!(message.contains(expected), "{to}: {message}");
    }
    let missing = refused(
        &TINY.replacen(r#""builtin:default")"#, r#""missing.rig.ron")"#, 1),
        &[],
    );
    assert!(
        missing.contains("missing.rig.ron") && missing.contains("face `face`"),
        "{missing}"
    );
}

#[test]
fn impossible_shards_and_output_folders_are_refused() {
    assert!(refused(TINY, &["--shard", "5/4"]).contains("no shard 5 of 4"));
    assert!(refused(TINY, &["--shard", "slurm"]).contains("not a Slurm array job"));
    let tmp = tempfile::tempdir().unwrap();
    let plan = plan(tmp.path(), TINY);
    let file = tmp.path().join("file");
    std::fs::write(&file, "x").unwrap();
    for out_dir in [file.clone(), file.join("sub")] {
        let out = run(&[plan.as_os_str(), "--out".as_ref(), out_dir.as_os_str()]);
        let message = stderr(&out);
        assert_eq!(out.status.code(), Some(1), "{message}");
        assert!(message.contains(&file.display().to_string()), "{message}");
    }
}

#[test]
fn a_folder_of_another_plan_is_refused_and_merge_names_a_non_batch() {
    let tmp = tempfile::tempdir().unwrap();
    let out_dir = tmp.path().join("out");
    let first = plan(tmp.path(), TINY);
    assert!(
        run(&[first.as_os_str(), "--out".as_ref(), out_dir.as_os_str()])
            .status
            .success()
    );
    let other = plan(tmp.path(), &TINY.replacen(r#"["C"]"#, r#"["D"]"#, 1));
    let out = run(&[other.as_os_str(), "--out".as_ref(), out_dir.as_os_str()]);
    assert_eq!(out.status.code(), Some(1));
    assert!(stderr(&out).contains("another plan"), "{}", stderr(&out));
    let out = run(&["merge".as_ref(), tmp.path().as_os_str()]);
    assert_eq!(out.status.code(), Some(1));
    assert!(stderr(&out).contains("items.csv"), "{}", stderr(&out));
}

#[test]
fn validate_checks_a_plan_against_its_faces() {
    let example = Path::new(env!("CARGO_MANIFEST_DIR")).join("presets/example.plan.ron");
    let out = Command::new(env!("CARGO_BIN_EXE_grimace"))
        .arg("validate")
        .arg(&example)
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success() && text.contains("168 states, 336 items"),
        "{text}{}",
        stderr(&out)
    );
    let tmp = tempfile::tempdir().unwrap();
    let bad = plan(
        tmp.path(),
        &TINY.replacen(r#"Aus(["1", "12"])"#, r#"Aus(["1", "3"])"#, 1),
    );
    let out = Command::new(env!("CARGO_BIN_EXE_grimace"))
        .arg("validate")
        .arg(&bad)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    assert!(
        stderr(&out).contains("test.plan.ron:4:22: face `face`: AU 3 is not in its table"),
        "{}",
        stderr(&out)
    );
}
