//! Label files: CSV rows, one per item, and the merge that checks a finished batch.
//!
//! Columns ([`COLUMNS`]): the item's ID, face, FACS code, each AU's intensity factor
//! (`1=0.5;2=0.5`), the muscle activations that are not zero (`NAME=VALUE;...`, rig order),
//! the jaw, the view (yaw, pitch in degrees), style, format, size, the file (relative to the
//! output folder) and the file's SHA-256. `items.csv` holds the planned rows (every column
//! but the checksum); each shard appends its finished rows to `labels/shard-K-of-N.csv`;
//! [`merge`] writes `labels.csv` in plan order and `manifest.json`.

use std::collections::{BTreeMap, HashMap};
use std::path::{Path, PathBuf};

use rayon::prelude::*;

use super::items::sha256_hex;
use super::BatchError;
use crate::io::atomic::write_atomic;

/// The columns of a label row.
pub const COLUMNS: [&str; 14] = [
    "id", "face", "facs", "aus", "muscles", "jaw", "yaw", "pitch", "style", "format", "width",
    "height", "file", "sha256",
];

/// Index of the `file` column.
pub const FILE: usize = 12;

/// The folder of the shards' label files, inside the output folder.
pub const SHARD_FOLDER: &str = "labels";

/// The planned items' file, inside the output folder.
pub const ITEMS_FILE: &str = "items.csv";

/// The copy of the plan, inside the output folder.
pub const PLAN_COPY: &str = "plan.ron";

/// One CSV field, quoted when it holds a comma, quote or line break.
fn field(text: &str) -> String {
    if text.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", text.replace('"', "\"\""))
    } else {
        text.to_string()
    }
}

/// One CSV line (with its line end).
pub fn csv_line(fields: &[String]) -> String {
    let mut line = fields
        .iter()
        .map(|f| field(f))
        .collect::<Vec<_>>()
        .join(",");
    line.push('\n');
    line
}

/// The CSV header of `n` columns.
pub fn header(n: usize) -> String {
    let names: Vec<String> = COLUMNS[..n].iter().map(|s| s.to_string()).collect();
    csv_line(&names)
}

/// Parses CSV text into records. A last record without its line end (a write cut short) is
/// left out, as is a record with a stray quote.
pub fn parse_csv(text: &str) -> Vec<Vec<String>> {
    let mut records = Vec::new();
    let mut record = Vec::new();
    let mut cur = String::new();
    let mut quoted = false;
    let mut chars = text.chars().peekable();
    let mut broken = false;
    while let Some(c) = chars.next() {
        match (quoted, c) {
            (true, '"') if chars.peek() == Some(&'"') => {
                chars.next();
                cur.push('"');
            }
            (true, '"') => quoted = false,
            (true, c) => cur.push(c),
            (false, '"') if cur.is_empty() => quoted = true,
            (false, '"') => broken = true,
            (false, ',') => record.push(std::mem::take(&mut cur)),
            (false, '\n') => {
                record.push(std::mem::take(&mut cur));
                if !broken {
                    records.push(std::mem::take(&mut record));
                }
                record.clear();
                broken = false;
            }
            (false, '\r') => {}
            (false, c) => cur.push(c),
        }
    }
    records
}

/// Reads a CSV file's records after its header (none when the file does not exist).
pub fn read_rows(path: &Path) -> Result<Vec<Vec<String>>, BatchError> {
    match std::fs::read(path) {
        Ok(bytes) => {
            let text = String::from_utf8_lossy(&bytes);
            Ok(parse_csv(&text).into_iter().skip(1).collect())
        }
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(Vec::new()),
        Err(e) => Err(BatchError::io(path, "cannot read", &e)),
    }
}

/// Whether a finished row checks out: the planned fields, and the file holding exactly the
/// bytes of its checksum.
pub fn row_checks_out(dir: &Path, planned: &[String], row: &[String]) -> bool {
    row.len() == COLUMNS.len()
        && row[..planned.len()] == *planned
        && std::fs::read(dir.join(&row[FILE])).is_ok_and(|bytes| sha256_hex(&bytes) == row[13])
}

/// What a merge found.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct MergeSummary {
    /// Items planned.
    pub items: usize,
    /// Bytes of all files.
    pub bytes: u64,
}

/// Checks every planned item of the batch in `dir` and writes `labels.csv` and
/// `manifest.json`; names what is missing or damaged otherwise.
pub fn merge(dir: &Path) -> Result<MergeSummary, BatchError> {
    let items_path = dir.join(ITEMS_FILE);
    if !items_path.is_file() {
        return Err(BatchError::new(format!(
            "{}: not found; is {} a batch's output folder (`grimace batch PLAN --out DIR`)?",
            items_path.display(),
            dir.display()
        )));
    }
    let planned = read_rows(&items_path)?;
    let rows = shard_rows(dir)?;
    let checked: Vec<Result<(Vec<String>, u64), String>> = planned
        .par_iter()
        .map(|plan_row| check_item(dir, plan_row, rows.get(&plan_row[0])))
        .collect();
    let mut problems = Vec::new();
    let mut text = header(COLUMNS.len());
    let mut bytes = 0;
    let mut by_format: BTreeMap<String, usize> = BTreeMap::new();
    let mut by_face: BTreeMap<String, usize> = BTreeMap::new();
    for result in checked {
        match result {
            Ok((row, size)) => {
                text.push_str(&csv_line(&row));
                bytes += size;
                *by_format.entry(row[9].clone()).or_default() += 1;
                *by_face.entry(row[1].clone()).or_default() += 1;
            }
            Err(problem) => problems.push(problem),
        }
    }
    if !problems.is_empty() {
        let shown: Vec<&str> = problems.iter().take(20).map(String::as_str).collect();
        let more = problems.len().saturating_sub(shown.len());
        return Err(BatchError::new(format!(
            "{}: {} of {} planned items are missing or damaged (rerun their shards):\n  {}{}",
            dir.display(),
            problems.len(),
            planned.len(),
            shown.join("\n  "),
            if more > 0 {
                format!("\n  ... and {more} more")
            } else {
                String::new()
            }
        )));
    }
    let labels = dir.join("labels.csv");
    write_atomic(&labels, text.as_bytes())
        .map_err(|e| BatchError::io(&labels, "cannot save", &e))?;
    let manifest = manifest(dir, planned.len(), bytes, &by_format, &by_face)?;
    let path = dir.join("manifest.json");
    write_atomic(&path, manifest.as_bytes())
        .map_err(|e| BatchError::io(&path, "cannot save", &e))?;
    Ok(MergeSummary {
        items: planned.len(),
        bytes,
    })
}

/// Every shard's finished rows by item ID (any number of shards, any sharding).
fn shard_rows(dir: &Path) -> Result<HashMap<String, Vec<String>>, BatchError> {
    let folder = dir.join(SHARD_FOLDER);
    let mut rows = HashMap::new();
    let entries = match std::fs::read_dir(&folder) {
        Ok(entries) => entries,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(rows),
        Err(e) => return Err(BatchError::io(&folder, "cannot read the folder", &e)),
    };
    let mut files: Vec<PathBuf> = entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "csv"))
        .collect();
    files.sort();
    for file in files {
        for row in read_rows(&file)? {
            if let Some(id) = row.first() {
                rows.insert(id.clone(), row);
            }
        }
    }
    Ok(rows)
}

/// One planned item against its finished row: the row, and the file's size.
fn check_item(
    dir: &Path,
    planned: &[String],
    row: Option<&Vec<String>>,
) -> Result<(Vec<String>, u64), String> {
    let id = planned.first().map(String::as_str).unwrap_or("?");
    let file = planned.get(FILE).map(String::as_str).unwrap_or("?");
    let Some(row) = row else {
        return Err(format!("{id} ({file}): no label row"));
    };
    if row.len() != COLUMNS.len() || row[..planned.len()] != *planned {
        return Err(format!(
            "{id} ({file}): the label row differs from the plan"
        ));
    }
    let bytes = std::fs::read(dir.join(file))
        .map_err(|e| format!("{id} ({file}): {}", crate::io::error::io_reason(&e)))?;
    if sha256_hex(&bytes) != row[13] {
        return Err(format!(
            "{id} ({file}): the file does not match its checksum"
        ));
    }
    Ok((row.clone(), bytes.len() as u64))
}

/// The manifest: the plan's hash, this grimace's version and the counts.
fn manifest(
    dir: &Path,
    items: usize,
    bytes: u64,
    by_format: &BTreeMap<String, usize>,
    by_face: &BTreeMap<String, usize>,
) -> Result<String, BatchError> {
    let plan = dir.join(PLAN_COPY);
    let text = std::fs::read(&plan).map_err(|e| BatchError::io(&plan, "cannot read", &e))?;
    let value = serde_json::json!({
        "plan_sha256": sha256_hex(&text),
        "grimace_version": env!("CARGO_PKG_VERSION"),
        "items": items,
        "bytes": bytes,
        "by_format": by_format,
        "by_face": by_face,
        "labels": "labels.csv",
    });
    let mut out =
        serde_json::to_string_pretty(&value).map_err(|e| BatchError::new(e.to_string()))?;
    out.push('\n');
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn csv_round_trips_and_drops_a_cut_line() {
        let rows = vec![
            vec!["a".to_string(), "b,c".to_string(), "say \"hi\"".to_string()],
            vec!["x".to_string(), String::new(), "z".to_string()],
        ];
        let mut text: String = rows.iter().map(|r| csv_line(r)).collect();
        assert_eq!(parse_csv(&text), rows);
        text.push_str("cut,off");
        assert_eq!(parse_csv(&text), rows);
    }
}
