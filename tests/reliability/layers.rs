//! The layers of `docs/architecture.md`, checked: no module of `src/` names a module of its
//! own row or a row above it (test code aside: tests may build fixtures from any layer), and
//! the picture in `src/lib.rs` is the one in `docs/architecture.md`.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

const ROOT: &str = env!("CARGO_MANIFEST_DIR");

/// The rows of the layer picture in the code block under `heading` of `text`, top row first:
/// the top-level modules each line names as `name/`. Lines naming none (continuations) are
/// skipped.
fn picture(text: &str, heading: &str) -> Vec<Vec<String>> {
    let after = &text[text.find(heading).expect("the layer heading")..];
    let block = after
        .split("```")
        .nth(1)
        .expect("a code block after the heading");
    block
        .lines()
        .map(|line| {
            line.split(|c: char| !(c.is_ascii_alphanumeric() || c == '_' || c == '/'))
                .filter_map(|word| word.strip_suffix('/'))
                .filter(|name| !name.is_empty() && !name.contains('/'))
                .map(str::to_string)
                .collect::<Vec<_>>()
        })
        .filter(|row| !row.is_empty())
        .collect()
}

/// Each top-level module's rank: 0 for the bottom row.
fn ranks(rows: &[Vec<String>]) -> BTreeMap<String, usize> {
    let mut ranks = BTreeMap::new();
    for (i, row) in rows.iter().rev().enumerate() {
        for name in row {
            assert!(
                ranks.insert(name.clone(), i).is_none(),
                "{name} drawn twice"
            );
        }
    }
    ranks
}

fn architecture() -> Vec<Vec<String>> {
    let text = std::fs::read_to_string(Path::new(ROOT).join("docs/architecture.md")).unwrap();
    picture(&text, "## Layers")
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// The source without comments, and without the items marked `#[cfg(test)]`; also the names
/// of the modules declared `#[cfg(test)] mod NAME;` (their files are test code).
fn production_code(text: &str) -> (String, Vec<String>) {
    let without_comments = blank_literals_and_comments(text);
    let mut out = String::new();
    let mut test_modules = Vec::new();
    let mut rest = without_comments.as_str();
    while let Some(at) = rest.find("#[cfg(test)]") {
        out.push_str(&rest[..at]);
        let item = rest[at + "#[cfg(test)]".len()..].trim_start();
        let end = item.find(['{', ';']).expect("an item after #[cfg(test)]");
        if item.as_bytes()[end] == b';' {
            if let Some(name) = item[..end].trim().strip_prefix("mod ") {
                test_modules.push(name.trim().to_string());
            }
            rest = &item[end + 1..];
        } else {
            let mut depth = 0;
            let close = item[end..]
                .char_indices()
                .find(|&(_, c)| {
                    depth += match c {
                        '{' => 1,
                        '}' => -1,
                        _ => 0,
                    };
                    depth == 0
                })
                .expect("a closed block")
                .0;
            rest = &item[end + close + 1..];
        }
    }
    out.push_str(rest);
    (out, test_modules)
}

/// `text` with comments and the insides of string and character literals made spaces, so
/// that braces and `crate::` inside them do not count.
fn blank_literals_and_comments(text: &str) -> String {
    let chars: Vec<char> = text.chars().collect();
    let mut out = String::with_capacity(text.len());
    let mut i = 0;
    while i < chars.len() {
        let rest = |k: usize| chars.get(i + k).copied();
        if chars[i] == '/' && rest(1) == Some('/') {
            while i < chars.len() && chars[i] != '\n' {
                i += 1;
            }
        } else if chars[i] == '/' && rest(1) == Some('*') {
            let end = (i + 2..chars.len().saturating_sub(1))
                .find(|&k| chars[k] == '*' && chars[k + 1] == '/')
                .map_or(chars.len(), |k| k + 2);
            out.extend(
                chars[i..end]
                    .iter()
                    .map(|&c| if c == '\n' { c } else { ' ' }),
            );
            i = end;
        } else if chars[i] == 'r' && matches!(rest(1), Some('"' | '#')) {
            let hashes = chars[i + 1..].iter().take_while(|&&c| c == '#').count();
            if rest(1 + hashes) != Some('"') {
                out.push(chars[i]);
                i += 1;
                continue;
            }
            let close: String = std::iter::once('"')
                .chain("#".repeat(hashes).chars())
                .collect();
            let body: String = chars[i + 2 + hashes..].iter().collect();
            let len = body
                .find(&close)
                .map_or(body.chars().count(), |b| body[..b].chars().count());
            out.push_str("\"\"");
            i += 2 + hashes + len + close.chars().count();
        } else if chars[i] == '"' {
            i += 1;
            while i < chars.len() && chars[i] != '"' {
                i += if chars[i] == '\\' { 2 } else { 1 };
            }
            out.push_str("\"\"");
            i += 1;
        } else if chars[i] == '\'' && (rest(2) == Some('\'') || rest(1) == Some('\\')) {
            // A character literal ('{', '\n'); a lifetime ('a) has no closing quote.
            let len = if rest(1) == Some('\\') {
                (i + 2..chars.len())
                    .find(|&k| chars[k] == '\'')
                    .map_or(1, |k| k - i)
            } else {
                2
            };
            out.push_str("' '");
            i += len + 1;
        } else {
            out.push(chars[i]);
            i += 1;
        }
    }
    out
}

/// The top-level modules `code` names through `crate::`: `crate::io::x`, and the first names
/// of `use crate::{io::x, fit}`.
fn crate_uses(code: &str) -> BTreeSet<String> {
    path_uses(code, "crate::")
}

/// The first names after `prefix` in `code`: `prefix` `io::x`, and the first names of
/// `prefix` `{io::x, fit}`.
fn path_uses(code: &str, prefix: &str) -> BTreeSet<String> {
    let mut names = BTreeSet::new();
    for (at, _) in code.match_indices(prefix) {
        let word_before = code[..at]
            .chars()
            .next_back()
            .is_some_and(|c| c.is_ascii_alphanumeric() || c == '_' || c == ':');
        if word_before {
            continue;
        }
        let after = &code[at + prefix.len()..];
        if let Some(group) = after.strip_prefix('{') {
            let mut depth = 0;
            let mut item_start = true;
            for (i, c) in group.char_indices() {
                match c {
                    '{' => depth += 1,
                    '}' if depth == 0 => break,
                    '}' => depth -= 1,
                    ',' if depth == 0 => item_start = true,
                    c if item_start && depth == 0 && !c.is_whitespace() => {
                        item_start = false;
                        let name: String = group[i..]
                            .chars()
                            .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
                            .collect();
                        names.insert(name);
                    }
                    _ => {}
                }
            }
        } else {
            let name: String = after
                .chars()
                .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
                .collect();
            names.insert(name);
        }
    }
    names
}

/// The top-level module a file of `src/` belongs to (`src/io/obj.rs` -> `io`).
fn top_module(path: &Path) -> String {
    let relative = path.strip_prefix(Path::new(ROOT).join("src")).unwrap();
    let first = relative.components().next().unwrap().as_os_str();
    Path::new(first)
        .file_stem()
        .unwrap()
        .to_string_lossy()
        .into_owned()
}

/// Every file of `src/` that is not test code, with its production code
/// ([`production_code`]), in path order.
fn production_sources() -> Vec<(PathBuf, String)> {
    let mut files = Vec::new();
    rust_files(&Path::new(ROOT).join("src"), &mut files);
    files.sort();
    let mut test_files = BTreeSet::new();
    let mut sources = Vec::new();
    for path in files {
        let (code, test_modules) = production_code(&std::fs::read_to_string(&path).unwrap());
        let dir = match path.file_name().unwrap().to_str().unwrap() {
            "mod.rs" | "lib.rs" | "main.rs" => path.parent().unwrap().to_path_buf(),
            _ => path.with_extension(""),
        };
        for name in test_modules {
            test_files.insert(dir.join(format!("{name}.rs")));
            test_files.insert(dir.join(name).join("mod.rs"));
        }
        sources.push((path, code));
    }
    sources.retain(|(path, _)| !test_files.contains(path));
    sources
}

/// For a file of `src/TOP/...`, its top module and the sub-module of it the file belongs to
/// (`src/fit/lids.rs` -> `fit`, `lids`), with the prefix naming a sibling sub-module from
/// the file (`super::`, or `super::super::` one folder deeper); `None` for `src/TOP.rs`.
fn sub_module(path: &Path) -> Option<(String, String, &'static str)> {
    let relative = path.strip_prefix(Path::new(ROOT).join("src")).unwrap();
    let parts: Vec<String> = relative
        .components()
        .map(|c| {
            c.as_os_str()
                .to_string_lossy()
                .trim_end_matches(".rs")
                .to_string()
        })
        .collect();
    match parts.as_slice() {
        [top, sub] if sub != "mod" => Some((top.clone(), sub.clone(), "super::")),
        [top, sub, file] => {
            let prefix = if file == "mod" {
                "super::"
            } else {
                "super::super::"
            };
            Some((top.clone(), sub.clone(), prefix))
        }
        _ => None,
    }
}

#[test]
fn no_two_sub_modules_use_each_other() {
    // (top, sub) -> the sibling sub-modules it names
    let mut uses: BTreeMap<(String, String), BTreeSet<String>> = BTreeMap::new();
    for (file, code) in production_sources() {
        let Some((top, sub, prefix)) = sub_module(&file) else {
            continue;
        };
        let mut named = path_uses(&code, prefix);
        named.extend(path_uses(&code, &format!("crate::{top}::")));
        named.remove(&sub);
        uses.entry((top, sub)).or_default().extend(named);
    }
    let mut cycles = Vec::new();
    for ((top, a), named) in &uses {
        for b in named {
            let back = uses.get(&(top.clone(), b.clone()));
            if a < b && back.is_some_and(|n| n.contains(a)) {
                cycles.push(format!("{top}::{a} <-> {top}::{b}"));
            }
        }
    }
    assert!(
        cycles.is_empty(),
        "sub-modules that use each other (one must not know the other): {cycles:?}"
    );
}

#[test]
fn no_module_uses_its_own_row_or_a_row_above() {
    let ranks = ranks(&architecture());
    let sources = production_sources();
    let mut wrong = Vec::new();
    let mut checked = 0;
    for (path, code) in &sources {
        let name = path.file_name().unwrap();
        if name == "lib.rs" || name == "main.rs" {
            continue;
        }
        let top = top_module(path);
        let Some(&own) = ranks.get(&top) else {
            wrong.push(format!(
                "{}: module `{top}` is not in the picture",
                path.display()
            ));
            continue;
        };
        checked += 1;
        for used in crate_uses(code) {
            if used == top {
                continue;
            }
            match ranks.get(&used) {
                Some(&rank) if rank < own => {}
                Some(_) => wrong.push(format!(
                    "{}: `{top}` uses `{used}`, which is not below it",
                    path.display()
                )),
                None => wrong.push(format!(
                    "{}: uses `crate::{used}`, not in the picture",
                    path.display()
                )),
            }
        }
    }
    assert!(checked > 100, "only {checked} files checked");
    assert!(wrong.is_empty(), "layer violations:\n{}", wrong.join("\n"));
}

#[test]
fn the_picture_names_every_top_level_module_once_and_lib_rs_draws_the_same() {
    let rows = architecture();
    let drawn: BTreeSet<String> = ranks(&rows).into_keys().collect();
    let lib = std::fs::read_to_string(Path::new(ROOT).join("src/lib.rs")).unwrap();
    let declared: BTreeSet<String> = lib
        .lines()
        .filter_map(|l| l.trim().strip_prefix("pub mod "))
        .map(|l| l.trim_end_matches(';').to_string())
        .collect();
    assert_eq!(
        drawn, declared,
        "docs/architecture.md against src/lib.rs's modules"
    );
    let doc: String = lib
        .lines()
        .filter_map(|l| l.strip_prefix("//!"))
        .map(|l| l.strip_prefix(' ').unwrap_or(l))
        .collect::<Vec<_>>()
        .join("\n");
    assert_eq!(picture(&doc, "Layers"), rows, "src/lib.rs's picture");
}

#[test]
fn the_checker_sees_a_use_from_above_and_ignores_test_code() {
    let (code, tests) = production_code(
        "use crate::{io::{self, landmarks}, fit};\n// crate::tui in a comment\n\
         const A: &str = \"crate::cli {\"; const B: char = '{';\n\
         #[cfg(test)]\nmod tests {\n    use crate::cli::x;\n    fn f() { if true {} }\n}\n\
         #[cfg(test)]\nmod more;\nfn g() { crate::render::draw(); }\n",
    );
    assert_eq!(tests, ["more"]);
    let uses: Vec<String> = crate_uses(&code).into_iter().collect();
    assert_eq!(uses, ["fit", "io", "render"]);
}
