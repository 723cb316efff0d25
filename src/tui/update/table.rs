//! The AU table: recording, loading, deleting, renaming, adding AUs, expressions; saving,
//! quitting and the answers to questions.

use super::*;

pub(crate) fn selected_item(app: &App) -> Option<TableItem> {
    let items = app.table_items();
    items
        .get(
            app.selection
                .table_selected
                .min(items.len().saturating_sub(1)),
        )
        .cloned()
}

pub(crate) fn save(app: &mut App, to: Option<PathBuf>, quit_after: bool, fx: &mut Vec<Effect>) {
    let path = match to.or_else(|| app.doc.file.clone()) {
        Some(path) => path,
        None => {
            app.error("the built-in table has no file: save it with :w FILE");
            return;
        }
    };
    let expected = if Some(&path) == app.doc.file.as_ref() {
        app.doc.file_stamp
    } else {
        None
    };
    fx.push(Effect::Save {
        path,
        table: Box::new(app.doc.table.clone()),
        expected,
        force: false,
        quit_after,
    });
}

pub(crate) fn quit(app: &mut App, fx: &mut Vec<Effect>) {
    if app.dirty() {
        app.mode = Mode::Confirm(Question::QuitUnsaved);
    } else {
        fx.push(Effect::RemoveRecovery);
        fx.push(Effect::Quit);
    }
}

pub(crate) fn answer(app: &mut App, question: Question, yes: bool, fx: &mut Vec<Effect>) {
    match (question, yes) {
        (Question::QuitUnsaved, true) => {
            fx.push(Effect::RemoveRecovery);
            fx.push(Effect::Quit);
        }
        (Question::OverwriteAu { key, name }, true) => record(app, key, &name, fx),
        (Question::DeleteAu(key), true) => delete_au(app, key, fx),
        (
            Question::AddMissingAus {
                name,
                combo,
                missing,
            },
            true,
        ) => add_missing_and_store(app, &name, &combo, &missing, fx),
        (Question::OverwriteFile { path, quit_after }, true) => fx.push(Effect::Save {
            path,
            table: Box::new(app.doc.table.clone()),
            expected: None,
            force: true,
            quit_after,
        }),
        (Question::Recover(found), true) => {
            begin_edit(app);
            app.doc.activations = found.activations;
            app.doc.table = found.table;
            app.doc.file_stamp = found.base;
            if let Some(rig) = found.rig {
                crate::tui::rig::recover(app, rig);
            }
            app.doc.face.deform(&app.doc.activations);
            app.info("recovered the unsaved changes; :w saves them");
            edited(app, fx);
        }
        (Question::Recover(_), false) => {
            fx.push(Effect::RemoveRecovery);
            app.info("discarded the recovered changes");
        }
        (_, false) => app.info("cancelled"),
    }
}

pub(crate) fn activate(app: &mut App, fx: &mut Vec<Effect>) {
    if app.selection.focus == Focus::Muscles {
        update_into(app, Action::StartSetValue, fx);
        return;
    }
    match selected_item(app) {
        Some(TableItem::Au(key)) => load_au(app, key, fx),
        Some(TableItem::Expression(name)) => load_expression(app, &name, fx),
        None => app.error("the table is empty: record an AU with r"),
    }
}

pub(crate) fn load_au(app: &mut App, key: AuKey, fx: &mut Vec<Effect>) {
    match table_ops::activations_of(&app.doc.table, key, app.rig()) {
        Ok(activations) => {
            replace_activations(app, activations, Some(key), fx);
            let name = super::au_name(app, key);
            app.info(format!("loaded AU {key} {name}"));
        }
        Err(e) => app.error(e),
    }
}

pub(crate) fn load_expression(app: &mut App, name: &str, fx: &mut Vec<Effect>) {
    let Some(combo) = app.doc.table.expressions.get(name).cloned() else {
        app.error(format!("the table has no expression named `{name}`"));
        return;
    };
    match table_ops::evaluate(&app.doc.table, &combo, app.rig()) {
        Ok(activations) => {
            replace_activations(app, activations, None, fx);
            app.info(format!("loaded expression {name} = {combo}"));
        }
        Err(e) => app.error(e),
    }
}

pub(crate) fn record(app: &mut App, key: AuKey, name: &str, fx: &mut Vec<Effect>) {
    let mut table = app.doc.table.clone();
    match table_ops::record(&mut table, key, name, app.rig(), &app.doc.activations) {
        Ok(()) => {
            begin_edit(app);
            app.doc.table = table;
            app.doc.loaded = Some(key);
            if let Some(i) = app
                .table_items()
                .iter()
                .position(|it| *it == TableItem::Au(key))
            {
                app.selection.table_selected = i;
            }
            app.info(format!("recorded AU {key} {name}"));
            edited(app, fx);
        }
        Err(e) => app.error(e),
    }
}

pub(crate) fn delete_au(app: &mut App, key: AuKey, fx: &mut Vec<Effect>) {
    let mut table = app.doc.table.clone();
    if let Err(e) = table_ops::remove(&mut table, key) {
        app.error(e);
        return;
    }
    begin_edit(app);
    app.doc.table = table;
    if app.doc.loaded == Some(key) {
        app.doc.loaded = None;
    }
    let items = app.table_items().len();
    app.selection.table_selected = app.selection.table_selected.min(items.saturating_sub(1));
    app.info(format!("deleted AU {key} (u undoes)"));
    edited(app, fx);
}

pub(crate) fn delete_expression(app: &mut App, name: &str, fx: &mut Vec<Effect>) {
    if !app.doc.table.expressions.contains_key(name) {
        app.error(format!("the table has no expression named `{name}`"));
        return;
    }
    begin_edit(app);
    app.doc.table.expressions.remove(name);
    let items = app.table_items().len();
    app.selection.table_selected = app.selection.table_selected.min(items.saturating_sub(1));
    app.info(format!("deleted expression {name} (u undoes)"));
    edited(app, fx);
}

pub(crate) fn rename(app: &mut App, key: AuKey, name: &str, fx: &mut Vec<Effect>) {
    let name = name.trim();
    if name.is_empty() {
        app.error("an AU's name cannot be empty");
        return;
    }
    if !app.doc.table.aus.contains_key(&key) {
        app.error(format!("the table has no AU {key}"));
        return;
    }
    begin_edit(app);
    if let Some(entry) = app.doc.table.aus.get_mut(&key) {
        entry.name = name.to_string();
    }
    app.info(format!("AU {key} renamed to {name}"));
    edited(app, fx);
}

/// Adds an AU (`12`) or a combination with FACS intensities (`12C`, `6+12B`) at `intensity`
/// to the current state.
pub(crate) fn add_au(app: &mut App, what: &str, intensity: f32, fx: &mut Vec<Effect>) {
    if !intensity.is_finite() || !(0.0..=2.0).contains(&intensity) {
        app.error(format!(
            "intensity must be between 0 and 2; {intensity} rejected"
        ));
        return;
    }
    let add = match what.parse::<AuKey>() {
        Ok(key) => table_ops::activations_of(&app.doc.table, key, app.rig()),
        Err(_) => table_ops::evaluate(&app.doc.table, what, app.rig()),
    };
    match add {
        Ok(add) => {
            let sum = table_ops::add_scaled(&app.doc.activations, &add, intensity);
            replace_activations(app, sum, None, fx);
            app.info(format!("added {what} at {}", format_value(intensity)));
        }
        Err(e) => app.error(e),
    }
}

pub(crate) fn store_expression(app: &mut App, name: &str, combo: &str, fx: &mut Vec<Effect>) {
    if let Some(offer) = offer_missing(app, name, combo) {
        app.mode = Mode::Confirm(offer);
        return;
    }
    let mut table = app.doc.table.clone();
    if let Err(e) = table_ops::set_expression(&mut table, name, combo) {
        app.error(e);
        return;
    }
    begin_edit(app);
    app.doc.table = table;
    app.info(format!("expression {name} = {combo} stored"));
    edited(app, fx);
}

pub(crate) fn set_combo(app: &mut App, combo: &str, fx: &mut Vec<Effect>) {
    match table_ops::evaluate(&app.doc.table, combo, app.rig()) {
        Ok(activations) => {
            replace_activations(app, activations, None, fx);
            app.info(format!("state set from {combo}"));
        }
        Err(e) => app.error(e),
    }
}

/// The name an AU is recorded under when none is typed: its current name, else the FACS name.
pub(crate) fn suggested_name(app: &App, key: AuKey) -> String {
    app.doc
        .table
        .aus
        .get(&key)
        .map(|e| e.name.clone())
        .or_else(|| table_ops::facs_name(key.number).map(str::to_string))
        .unwrap_or_else(|| format!("AU {key}"))
}

pub(crate) fn record_or_ask(app: &mut App, key: AuKey, name: &str, fx: &mut Vec<Effect>) {
    if app.doc.table.aus.contains_key(&key) {
        app.mode = Mode::Confirm(Question::OverwriteAu {
            key,
            name: name.to_string(),
        });
    } else {
        record(app, key, name, fx);
    }
}

/// For an expression naming AUs the table lacks: the question offering to add them from the
/// built-in table, when it has every one of them for this rig. `None` when nothing is missing
/// or they cannot all be added (storing then says which are missing).
fn offer_missing(app: &App, name: &str, combo: &str) -> Option<Question> {
    let parsed = crate::facs::combo::parse_combo(combo).ok()?;
    let missing = app.doc.table.missing(&parsed);
    if missing.is_empty() {
        return None;
    }
    let builtin = crate::io::builtin::default_table();
    let mut table = app.doc.table.clone();
    let added = import_missing(&mut table, &builtin, app.rig()).added;
    missing
        .iter()
        .all(|k| added.contains(k))
        .then(|| Question::AddMissingAus {
            name: name.to_string(),
            combo: combo.to_string(),
            missing,
        })
}

/// Yes to [`Question::AddMissingAus`]: adds the missing AUs from the built-in table and stores
/// the expression, as one edit.
pub(crate) fn add_missing_and_store(
    app: &mut App,
    name: &str,
    combo: &str,
    missing: &[AuKey],
    fx: &mut Vec<Effect>,
) {
    let mut source = crate::io::builtin::default_table();
    source.aus.retain(|k, _| missing.contains(k));
    let mut table = app.doc.table.clone();
    import_missing(&mut table, &source, app.rig());
    if let Err(e) = table_ops::set_expression(&mut table, name, combo) {
        app.error(e);
        return;
    }
    begin_edit(app);
    app.doc.table = table;
    let keys: Vec<String> = missing.iter().map(|k| k.to_string()).collect();
    app.info(format!(
        "added AU {} from the built-in table; expression {name} = {combo} stored",
        keys.join(", ")
    ));
    edited(app, fx);
}

/// What [`import_missing`] did.
#[derive(Debug, Default, PartialEq)]
pub(crate) struct Imported {
    /// AUs added, in key order.
    pub added: Vec<AuKey>,
    /// AUs the table already had (kept as they are).
    pub present: usize,
    /// AUs left out because they move muscles this rig lacks.
    pub unfit: Vec<AuKey>,
    /// AUs left out because the table is full.
    pub no_room: Vec<AuKey>,
}

/// Adds to `table` every AU of `from` it lacks, when the AU's muscles are in `rig` and the
/// table has room. AUs the table has are never replaced.
pub(crate) fn import_missing(
    table: &mut crate::facs::AuTable,
    from: &crate::facs::AuTable,
    rig: &crate::model::Rig,
) -> Imported {
    let mut done = Imported::default();
    for (key, entry) in &from.aus {
        if table.aus.contains_key(key) {
            done.present += 1;
        } else if entry.muscles.keys().any(|m| rig.muscle_index(m).is_none())
            || (entry.jaw != 0.0 && rig.jaw.is_none())
        {
            done.unfit.push(*key);
        } else if table.aus.len() >= crate::facs::table::MAX_AUS {
            done.no_room.push(*key);
        } else {
            table.aus.insert(*key, entry.clone());
            done.added.push(*key);
        }
    }
    done
}

/// `:import`: adds the AUs of another table (`from`, read from `source`) that this one lacks.
pub(crate) fn import(
    app: &mut App,
    source: &str,
    from: &crate::facs::AuTable,
    fx: &mut Vec<Effect>,
) {
    let mut table = app.doc.table.clone();
    let done = import_missing(&mut table, from, app.rig());
    let keys = |keys: &[AuKey]| {
        keys.iter()
            .map(|k| k.to_string())
            .collect::<Vec<_>>()
            .join(", ")
    };
    let mut text = if done.added.is_empty() {
        format!("nothing to add from {source}")
    } else {
        format!("added AU {} from {source}", keys(&done.added))
    };
    if done.present > 0 {
        text.push_str(&format!("; {} already here, kept", done.present));
    }
    if !done.unfit.is_empty() {
        text.push_str(&format!(
            "; AU {} left out: they move muscles this rig lacks",
            keys(&done.unfit)
        ));
    }
    if !done.no_room.is_empty() {
        text.push_str(&format!(
            "; AU {} left out: a table holds at most {} AUs",
            keys(&done.no_room),
            crate::facs::table::MAX_AUS
        ));
    }
    if done.added.is_empty() {
        app.warn(text);
        return;
    }
    begin_edit(app);
    app.doc.table = table;
    app.info(text);
    edited(app, fx);
}
