//! The editing commands end to end, in a pseudo-terminal: `=` with an empty field, Ctrl-u,
//! `:import`, `:expr` offering missing AUs, and the jaw's steps.

use crate::common::pty::Term;

#[test]
fn typing_after_equals_gives_the_typed_value_and_ctrl_u_clears() {
    let dir = tempfile::tempdir().unwrap();
    let mut ed = Term::grimace(dir.path(), &["edit", "new.au.ron"], 120, 40);
    ed.wait_for("new table");
    ed.send("=");
    ed.wait_for("value (");
    ed.send("2\r");
    ed.wait_for("2.00");
    ed.send(":set nonsense\x15jaw 3\r");
    ed.wait_for("jaw = 3.00");
    ed.send(":q!\r");
    assert!(ed.wait_exit().success());
}

#[test]
fn a_new_table_imports_the_builtin_aus_and_expr_offers_the_missing_ones() {
    let dir = tempfile::tempdir().unwrap();
    let mut ed = Term::grimace(dir.path(), &["edit", "new.au.ron"], 120, 40);
    ed.wait_for("new table");
    ed.send(":expr surprise 1+2+5+26\r");
    let screen = ed.wait_for("(y/n)");
    assert!(screen.contains("5 Upper Lid Raiser"), "{screen}");
    ed.send("y");
    ed.wait_for("expression surprise = 1+2+5+26 stored");
    ed.send(":import builtin:default\r");
    ed.wait_for("from builtin:default; 4 already here, kept");
    ed.send(":wq\r");
    assert!(ed.wait_exit().success());
    let saved = grimace::io::load_table(&dir.path().join("new.au.ron")).unwrap();
    let builtin = grimace::io::builtin::default_table();
    assert_eq!(saved.aus, builtin.aus);
    assert_eq!(saved.expressions["surprise"], "1+2+5+26");
}

#[test]
fn the_jaw_steps_by_half_coarsely_and_four_fine_steps_make_exactly_point_two() {
    let dir = tempfile::tempdir().unwrap();
    let mut ed = Term::grimace(dir.path(), &["edit", "new.au.ron"], 120, 40);
    ed.wait_for("new table");
    ed.send("/jaw\r");
    ed.wait_for("found jaw");
    ed.send("llll:record 26\r");
    ed.wait_for("recorded AU 26");
    ed.send(":w\r");
    ed.wait_for("saved");
    let text = std::fs::read_to_string(dir.path().join("new.au.ron")).unwrap();
    assert!(text.contains("jaw: 0.2,"), "{text}");
    ed.send("L");
    ed.wait_for("0.70");
    ed.send(":q!\r");
    assert!(ed.wait_exit().success());
}
