//! The input line: editing, `Tab` completion, and what a submitted line does.

use super::*;

/// Editing the input line: typing, deleting, moving the cursor, completing.
pub(crate) fn edit(app: &mut App, action: Action) {
    match action {
        Action::InputChar(c) => edit_input(app, |input| {
            let at = byte_index(&input.text, input.cursor);
            input.text.insert(at, c);
            input.cursor += 1;
        }),
        Action::InputBackspace => {
            let empty = matches!(&app.mode, Mode::Input(i) if i.text.is_empty());
            if empty {
                app.mode = Mode::Normal;
            } else {
                edit_input(app, |input| {
                    if input.cursor > 0 {
                        input.cursor -= 1;
                        let at = byte_index(&input.text, input.cursor);
                        input.text.remove(at);
                    }
                });
            }
        }
        Action::InputDelete => edit_input(app, |input| {
            if input.cursor < input.text.chars().count() {
                let at = byte_index(&input.text, input.cursor);
                input.text.remove(at);
            }
        }),
        Action::InputLeft => edit_input(app, |input| input.cursor = input.cursor.saturating_sub(1)),
        Action::InputRight => edit_input(app, |input| {
            input.cursor = (input.cursor + 1).min(input.text.chars().count())
        }),
        Action::InputClear => edit_input(app, |input| {
            let at = byte_index(&input.text, input.cursor);
            input.text.replace_range(..at, "");
            input.cursor = 0;
        }),
        Action::InputHome => edit_input(app, |input| input.cursor = 0),
        Action::InputEnd => edit_input(app, |input| input.cursor = input.text.chars().count()),
        Action::InputComplete => complete(app),
        _ => {}
    }
}

pub(crate) fn open(app: &mut App, kind: InputKind, text: impl Into<String>) {
    app.mode = Mode::Input(Input::new(kind, text));
}

pub(crate) fn edit_input(app: &mut App, f: impl FnOnce(&mut Input)) {
    if let Mode::Input(input) = &mut app.mode {
        f(input);
    }
}

pub(crate) fn byte_index(text: &str, chars: usize) -> usize {
    text.char_indices()
        .nth(chars)
        .map_or(text.len(), |(i, _)| i)
}

pub(crate) fn parse_key(app: &mut App, text: &str) -> Option<AuKey> {
    match text.parse::<AuKey>() {
        Ok(key) => Some(key),
        Err(e) => {
            app.error(e.to_string());
            None
        }
    }
}

pub(crate) fn parse_value(app: &mut App, text: &str) -> Option<f32> {
    match text.trim().parse::<f32>() {
        Ok(v) if v.is_finite() => Some(v),
        _ => {
            app.error(format!("`{}` is not a number", text.trim()));
            None
        }
    }
}

pub(crate) fn submit(app: &mut App, input: Input, fx: &mut Vec<Effect>) {
    let text = input.text.trim().to_string();
    match input.kind {
        InputKind::Command => command::run(app, &text, fx),
        InputKind::Find => find(app, &text),
        InputKind::Value(_) if text.is_empty() => {}
        InputKind::Value(_) => {
            if let Some(v) = parse_value(app, &text) {
                let row = app.selected_row();
                set_rows(app, row, v, fx);
            }
        }
        InputKind::RecordKey => {
            if let Some(key) = parse_key(app, &text) {
                let name = suggested_name(app, key);
                open(app, InputKind::RecordName(key), name);
            }
        }
        InputKind::RecordName(key) => {
            let name = if text.is_empty() {
                suggested_name(app, key)
            } else {
                text
            };
            record_or_ask(app, key, &name, fx);
        }
        InputKind::Rename(key) => rename(app, key, &text, fx),
        InputKind::AddAu => {
            let mut words = text.split_whitespace();
            match words.next() {
                None => app.error("type an AU number, e.g. 12 0.5"),
                Some(what) => {
                    let intensity = words.next().map_or(Some(1.0), |w| parse_value(app, w));
                    if let Some(i) = intensity {
                        add_au(app, what, i, fx);
                    }
                }
            }
        }
        InputKind::ExpressionName => {
            let text = text.replacen('=', " ", 1);
            let mut words = text.split_whitespace();
            match (words.next(), words.next()) {
                (Some(name), Some(combo)) => store_expression(app, name, combo, fx),
                _ => app.error("type a name and a combination, e.g. smile 6+12"),
            }
        }
    }
}

/// Normalises a name for matching: lower case, spaces and underscores alike.
pub(crate) fn fold(name: &str) -> String {
    name.to_lowercase().replace(' ', "_")
}

pub(crate) fn find(app: &mut App, text: &str) {
    if text.is_empty() {
        return;
    }
    let wanted = fold(text);
    let start = app.selection.selected + 1;
    let n = app.selection.rows.len();
    let hit = (0..n)
        .map(|k| (start + k) % n)
        .find(|&i| fold(app.row_name(app.selection.rows[i])).contains(&wanted));
    match hit {
        Some(i) => {
            app.selection.selected = i;
            app.selection.focus = Focus::Muscles;
            app.info(format!("found {}", app.row_name(app.selection.rows[i])));
        }
        None => app.error(format!("no muscle matches `{text}`")),
    }
}

pub(crate) fn row_by_name(app: &App, name: &str) -> Option<Row> {
    if fold(name) == "jaw" {
        return app.selection.rows.iter().copied().find(|r| *r == Row::Jaw);
    }
    let wanted = fold(name);
    app.rig()
        .muscles
        .iter()
        .position(|m| fold(&m.name) == wanted)
        .map(Row::Muscle)
}

/// The completions of the word being typed.
pub(crate) fn candidates(app: &App, kind: &InputKind, before: &str) -> Vec<String> {
    let first_word = !before.contains(' ');
    match kind {
        InputKind::Find => command::muscle_names(app),
        InputKind::RecordKey | InputKind::AddAu if first_word => command::au_keys(app),
        InputKind::Command => command::candidates(app, before),
        _ => Vec::new(),
    }
}

pub(crate) fn complete(app: &mut App) {
    let Mode::Input(input) = &app.mode else {
        return;
    };
    let at = byte_index(&input.text, input.cursor);
    let before = input.text[..at].to_string();
    let word_start = before.rfind(' ').map_or(0, |i| i + 1);
    let word = &before[word_start..];
    let folded = fold(word);
    let matches: Vec<String> = candidates(app, &input.kind, &before)
        .into_iter()
        .filter(|c| fold(c).starts_with(&folded))
        .collect();
    if matches.is_empty() {
        app.error(format!("nothing completes `{word}`"));
        return;
    }
    let common = common_prefix(&matches);
    let replacement = if common.len() >= word.len() {
        common
    } else {
        word.to_string()
    };
    let suffix = if matches.len() == 1 { " " } else { "" };
    let many = (matches.len() > 1).then(|| matches.join("  "));
    if let Mode::Input(input) = &mut app.mode {
        let rest = input.text[at..].to_string();
        input.text = format!("{}{}{}{}", &before[..word_start], replacement, suffix, rest);
        input.cursor = before[..word_start].chars().count()
            + replacement.chars().count()
            + suffix.chars().count();
    }
    match many {
        Some(list) => app.info(list),
        None => app.message = None,
    }
}

pub(crate) fn common_prefix(words: &[String]) -> String {
    let first = &words[0];
    let mut len = first.len();
    for w in &words[1..] {
        len = first
            .char_indices()
            .zip(w.chars())
            .take_while(|((_, a), b)| a.eq_ignore_ascii_case(b))
            .map(|((i, a), _)| i + a.len_utf8())
            .last()
            .unwrap_or(0)
            .min(len);
    }
    first[..len].to_string()
}
