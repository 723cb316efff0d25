//! `grimace check`: a row per AU and expression with its numbers, on the built-in rig and on
//! the paper's; a rig torn on purpose exits 1 and names the entry that tears.

use std::path::Path;

use crate::common::grimace_in;
use grimace::io::builtin;

fn check(dir: &Path, args: &[&str]) -> (bool, String) {
    let out = grimace_in(dir, &[&["check"], args].concat());
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(
        !stderr.contains("grimace check:"),
        "check did not run: {stderr}"
    );
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
    )
}

/// The row of an entry (`AU 12`, `happiness`).
fn row<'a>(report: &'a str, entry: &str) -> &'a str {
    report
        .lines()
        .find(|l| l.split("  ").next().map(str::trim) == Some(entry))
        .unwrap_or_else(|| panic!("no row for {entry} in\n{report}"))
}

#[test]
fn every_entry_of_the_built_in_table_gets_a_row_with_its_numbers() {
    let dir = tempfile::tempdir().unwrap();
    for rig in ["builtin:default", "builtin:paper"] {
        let (_, report) = check(dir.path(), &["--rig", rig, "--table", "builtin:default"]);
        let table = builtin::default_table();
        for key in table.aus.keys() {
            row(&report, &format!("AU {key}"));
        }
        for name in table.expressions.keys() {
            row(&report, name);
        }
        assert!(row(&report, "AU 45").contains('%'), "a lid gap at AU45");
        let au12 = row(&report, "AU 12");
        assert!(au12.contains(" mm") && au12.contains("mouth"), "{au12}");
        // AU1 is the default rig's medial frontalis, which the paper's rig lacks
        assert!(
            rig == "builtin:paper" || row(&report, "AU 1").contains("brow"),
            "the inner brow raise"
        );
        assert!(row(&report, "AU 45").contains("eye"), "the blink");
        println!("{report}");
    }
}

#[test]
fn a_torn_rig_exits_1_and_names_the_entry() {
    let dir = tempfile::tempdir().unwrap();
    let (_, report) = check(dir.path(), &[]);
    assert!(row(&report, "AU 12").ends_with("ok"), "{report}");
    // the left smile muscle with a gain of 40 over the whole face tears the mouth
    let vertices = builtin::default_mesh().vertex_count();
    let weights: Vec<String> = (0..vertices).map(|v| format!("({v}, 1.0)")).collect();
    let mask = format!(
        "masks: [\n(muscles: [\"L_Zygomatic_Major\"], gain: 40.0, weights: [{}]),\n",
        weights.join(", ")
    );
    let rig = builtin::DEFAULT_RIG.replacen("masks: [\n", &mask, 1);
    assert_ne!(rig, builtin::DEFAULT_RIG);
    std::fs::write(dir.path().join("torn.rig.ron"), rig).unwrap();
    let (ok, report) = check(dir.path(), &["--rig", "torn.rig.ron"]);
    assert!(!ok, "a torn rig fails:\n{report}");
    assert!(row(&report, "AU 12").contains("FAIL"), "{report}");
    assert!(row(&report, "AU L12").contains("FAIL"), "{report}");
}
