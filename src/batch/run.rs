//! Running a shard: each item deformed, drawn and written atomically (a temporary file
//! renamed into place, so a killed run leaves no half file), its label row appended after
//! the file is in place. A rerun keeps the rows that check out (planned fields, file and
//! checksum) and makes the rest.

use std::collections::HashSet;
use std::fs::{File, OpenOptions};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use glam::{Quat, Vec3};
use rayon::prelude::*;

use super::items::{expand, sha256_hex, Expanded, FaceRef, Item, Shard, State};
use super::labels::{self, csv_line, header, read_rows, row_checks_out};
use super::plan::{Output, Plan};
use super::BatchError;
use crate::facs::AuTable;
use crate::io::atomic::{replace_unsynced, write_atomic_no_backup};
use crate::io::gltf::{write_glb, Placement};
use crate::io::obj::MovedObj;
use crate::io::LoadedRig;
use crate::model::BoundRig;
use crate::render::{
    png, svg, to_text, Camera, CellGrid, CellMode, ColorMode, Framing, Renderer, Scene,
};

/// A face of the batch, loaded and bound.
#[derive(Debug)]
pub struct Face {
    /// The rig and its mesh.
    pub rig: LoadedRig,
    /// Its AU table.
    pub table: AuTable,
    /// The rig bound to the mesh with the deformation used.
    pub bound: BoundRig,
    /// The face's axes and the region views fit.
    pub framing: Framing,
    /// Metres per mesh unit for glTF output.
    pub metres_per_unit: f32,
    /// How its OBJ output is written (over the mesh file's own text).
    pub obj: MovedObj,
}

/// A plan with its faces, expanded into items.
#[derive(Debug)]
pub struct Batch {
    /// The plan.
    pub plan: Plan,
    /// Its faces, in the plan's order.
    pub faces: Vec<Face>,
    /// The states and items.
    pub expanded: Expanded,
}

/// How a shard runs.
pub struct RunOptions<'a> {
    /// Worker threads.
    pub jobs: usize,
    /// Set (by Ctrl-C) to stop after the items being drawn.
    pub stop: &'a AtomicBool,
    /// Called after each group of items.
    pub progress: &'a mut dyn FnMut(&Progress),
}

/// Where a shard stands.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Progress {
    /// The shard's items.
    pub total: usize,
    /// Items found finished by an earlier run.
    pub skipped: usize,
    /// Items made by this run so far.
    pub made: usize,
    /// Time since this run started making items.
    pub elapsed: Duration,
}

/// What a shard run did.
#[derive(Debug, Clone, PartialEq)]
pub struct Summary {
    /// The final progress.
    pub progress: Progress,
    /// Bytes written by this run.
    pub bytes: u64,
    /// Whether it stopped early (Ctrl-C).
    pub stopped: bool,
}

impl Batch {
    /// Expands the plan on its faces (errors name the place in the plan).
    pub fn new(plan: Plan, faces: Vec<Face>) -> Result<Batch, crate::io::LoadError> {
        let refs: Vec<FaceRef> = faces
            .iter()
            .map(|f| FaceRef {
                rig: &f.rig.rig,
                table: &f.table,
            })
            .collect();
        let expanded = expand(&plan, &refs)?;
        Ok(Batch {
            plan,
            faces,
            expanded,
        })
    }

    fn state(&self, item: &Item) -> &State {
        &self.expanded.states[item.face][item.state]
    }

    /// An item's planned label fields: every column but the checksum.
    pub fn planned_fields(&self, item: &Item) -> Vec<String> {
        let state = self.state(item);
        let rig = &self.faces[item.face].rig.rig;
        let aus: Vec<String> = state.aus.iter().map(|(k, f)| format!("{k}={f}")).collect();
        let muscles: Vec<String> = rig
            .muscles
            .iter()
            .zip(&state.act.muscles)
            .filter(|(_, &v)| v != 0.0)
            .map(|(m, v)| format!("{}={v}", m.name))
            .collect();
        let opt = |v: Option<String>| v.unwrap_or_default();
        vec![
            item.id.clone(),
            self.plan.file.faces[item.face].name.clone(),
            state.code.clone(),
            aus.join(";"),
            muscles.join(";"),
            state.act.jaw.to_string(),
            opt(item.view.map(|v| v.yaw.to_string())),
            opt(item.view.map(|v| v.pitch.to_string())),
            opt(item.style.map(|s| s.style().name().to_string())),
            item.output.ext().to_string(),
            opt(item.size.map(|s| s.0.to_string())),
            opt(item.size.map(|s| s.1.to_string())),
            item.file.clone(),
        ]
    }

    /// The planned rows of every item as CSV (`items.csv`).
    pub fn items_csv(&self) -> String {
        let mut text = header(labels::COLUMNS.len() - 1);
        for item in &self.expanded.items {
            text.push_str(&csv_line(&self.planned_fields(item)));
        }
        text
    }

    /// Deforms a face into a state.
    pub fn deform(
        &self,
        face: usize,
        state: usize,
        positions: &mut Vec<Vec3>,
    ) -> Result<(), BatchError> {
        self.faces[face]
            .bound
            .deform(&self.expanded.states[face][state].act, positions)
            .map_err(|e| {
                BatchError::new(format!("face `{}`: {e}", self.plan.file.faces[face].name))
            })
    }

    /// Draws one item from its face's deformed positions with a renderer of that face's
    /// mesh: the file's bytes.
    pub fn draw(
        &self,
        item: &Item,
        positions: &[Vec3],
        renderer: &mut Renderer,
    ) -> Result<Vec<u8>, BatchError> {
        let face = &self.faces[item.face];
        let mesh = &face.rig.mesh;
        let (w, h) = item.size.map_or((0, 0), |(w, h)| (w as usize, h as usize));
        let mut camera = Camera::front();
        if let Some(view) = item.view {
            camera.yaw = view.yaw.to_radians();
            camera.pitch = view.pitch.to_radians();
        }
        camera.basis = face.framing.basis;
        let scene = Scene::new(mesh, positions)
            .with_rest(&mesh.positions)
            .with_framing(&face.framing);
        let style = item.style.map(|s| s.style()).unwrap_or_default();
        let failed = |e: &dyn std::fmt::Display| BatchError::new(format!("{}: {e}", item.file));
        Ok(match item.output {
            Output::Png => png::render_png_with(renderer, &scene, &camera, style, (w, h))
                .map_err(|e| failed(&e))?,
            Output::Svg => svg::render_svg(&scene, &camera, style, w, h).into_bytes(),
            Output::Txt => {
                let mut canvas = CellMode::Braille.canvas(w, h);
                renderer.render(&scene, &camera, style, &mut canvas);
                let mut grid = CellGrid::default();
                grid.fill(&canvas, CellMode::Braille, ColorMode::None);
                to_text(&grid).into_bytes()
            }
            Output::Obj => face.obj.write(mesh, positions).into_bytes(),
            Output::Glb => {
                let mut posed = mesh.clone();
                posed.positions = positions.to_vec();
                let placement = Placement {
                    metres_per_unit: face.metres_per_unit,
                    rotation: Quat::from_mat3(&face.framing.basis),
                };
                write_glb(&posed, &[], placement).map_err(|e| failed(&e))?
            }
        })
    }

    /// A renderer for each face's mesh.
    pub fn renderers(&self) -> Vec<Renderer> {
        self.faces
            .iter()
            .map(|f| Renderer::new(&f.rig.mesh))
            .collect()
    }

    /// The positions in plan order of a shard's items.
    pub fn shard_items(&self, shard: Shard) -> Vec<usize> {
        (0..self.expanded.items.len())
            .filter(|&i| shard.takes(i))
            .collect()
    }

    /// Runs one shard into `dir`: skips items an earlier run finished, makes the rest.
    pub fn run_shard(
        &self,
        dir: &Path,
        shard: Shard,
        options: RunOptions,
    ) -> Result<Summary, BatchError> {
        self.prepare(dir)?;
        let mine = self.shard_items(shard);
        let labels_path = dir.join(labels::SHARD_FOLDER).join(shard.labels_name());
        let finished = self.resume(dir, &labels_path, &mine)?;
        sweep_temporaries(dir, &self.expanded.items, &mine);
        let todo = self.unfinished_groups(&mine, &finished);
        let todo_items: usize = todo.iter().map(Vec::len).sum();
        let mut out = OpenOptions::new()
            .append(true)
            .open(&labels_path)
            .map_err(|e| BatchError::io(&labels_path, "cannot open", &e))?;
        let mut progress = Progress {
            total: mine.len(),
            skipped: mine.len() - todo_items,
            made: 0,
            elapsed: Duration::ZERO,
        };
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(options.jobs.max(1))
            .build()
            .map_err(|e| BatchError::new(format!("cannot start {} threads: {e}", options.jobs)))?;
        let spare = Spare::default();
        let start = Instant::now();
        let mut bytes = 0;
        (options.progress)(&progress);
        for groups in todo.chunks(options.jobs.max(1) * 2) {
            if options.stop.load(Ordering::Relaxed) {
                break;
            }
            let made = pool.install(|| self.make_groups(dir, groups, options.stop, &spare));
            let mut first_error = None;
            for result in made {
                match result {
                    Ok((line, size)) => {
                        write_row(&mut out, &labels_path, &line)?;
                        progress.made += 1;
                        bytes += size;
                    }
                    Err(e) => {
                        first_error.get_or_insert(e);
                    }
                }
            }
            progress.elapsed = start.elapsed();
            (options.progress)(&progress);
            if let Some(e) = first_error {
                return Err(e);
            }
        }
        let stopped = progress.skipped + progress.made < progress.total;
        Ok(Summary {
            progress,
            bytes,
            stopped,
        })
    }

    /// The shard's unfinished items, by state (each group one state's items).
    fn unfinished_groups(&self, mine: &[usize], finished: &HashSet<String>) -> Vec<Vec<usize>> {
        let items = &self.expanded.items;
        let mut groups: Vec<Vec<usize>> = Vec::new();
        for &i in mine.iter().filter(|&&i| !finished.contains(&items[i].id)) {
            match groups.last_mut() {
                Some(last) if items[last[0]].group == items[i].group => last.push(i),
                _ => groups.push(vec![i]),
            }
        }
        groups
    }

    /// Makes groups of items in parallel, one state deformed once for its group: each item's
    /// label line and size; a group not started when `stop` was set gives nothing.
    fn make_groups(
        &self,
        dir: &Path,
        groups: &[Vec<usize>],
        stop: &AtomicBool,
        spare: &Spare,
    ) -> Vec<Result<(String, u64), BatchError>> {
        let made: Vec<Vec<Result<(String, u64), BatchError>>> = groups
            .par_iter()
            .map_init(
                || (Vec::new(), spare.take(self)),
                |(positions, renderers), group| {
                    if stop.load(Ordering::Relaxed) {
                        return Vec::new();
                    }
                    let first = &self.expanded.items[group[0]];
                    if let Err(e) = self.deform(first.face, first.state, positions) {
                        return vec![Err(e)];
                    }
                    group
                        .iter()
                        .map(|&i| {
                            self.make_item(
                                dir,
                                &self.expanded.items[i],
                                positions,
                                &mut renderers.0[first.face],
                            )
                        })
                        .collect()
                },
            )
            .collect();
        made.into_iter().flatten().collect()
    }

    /// Draws and writes one item: its label line and size.
    fn make_item(
        &self,
        dir: &Path,
        item: &Item,
        positions: &[Vec3],
        renderer: &mut Renderer,
    ) -> Result<(String, u64), BatchError> {
        let bytes = self.draw(item, positions, renderer)?;
        write_item(&dir.join(&item.file), &bytes)?;
        let mut fields = self.planned_fields(item);
        fields.push(sha256_hex(&bytes));
        Ok((csv_line(&fields), bytes.len() as u64))
    }

    /// Makes the output folder and records the plan in it (`plan.ron`, `items.csv`); a
    /// folder that holds another plan is refused.
    fn prepare(&self, dir: &Path) -> Result<(), BatchError> {
        if dir.exists() && !dir.is_dir() {
            return Err(BatchError::new(format!(
                "{}: the output folder is a file",
                dir.display()
            )));
        }
        let shards = dir.join(labels::SHARD_FOLDER);
        std::fs::create_dir_all(&shards)
            .map_err(|e| BatchError::io(&shards, "cannot create the folder", &e))?;
        record(&dir.join(labels::PLAN_COPY), self.plan.text.as_bytes(), dir)?;
        record(
            &dir.join(labels::ITEMS_FILE),
            self.items_csv().as_bytes(),
            dir,
        )
    }

    /// Reads the shard's earlier rows, keeps those that check out and rewrites the file
    /// with them (dropping a row cut short by a kill): the IDs of finished items.
    fn resume(
        &self,
        dir: &Path,
        path: &Path,
        mine: &[usize],
    ) -> Result<HashSet<String>, BatchError> {
        let rows = read_rows(path)?;
        let by_id: std::collections::HashMap<&str, usize> = mine
            .iter()
            .map(|&i| (self.expanded.items[i].id.as_str(), i))
            .collect();
        let kept: Vec<&Vec<String>> = rows
            .par_iter()
            .filter(|row| {
                let Some(&i) = row.first().and_then(|id| by_id.get(id.as_str())) else {
                    return false;
                };
                row_checks_out(dir, &self.planned_fields(&self.expanded.items[i]), row)
            })
            .collect();
        let mut text = header(labels::COLUMNS.len());
        let mut finished = HashSet::new();
        for row in kept {
            if finished.insert(row[0].clone()) {
                text.push_str(&csv_line(row));
            }
        }
        write_atomic_no_backup(path, text.as_bytes())
            .map_err(|e| BatchError::io(path, "cannot save", &e))?;
        Ok(finished)
    }
}

/// Renderers kept between groups of items: building one (a mesh's edges and tones) costs
/// as much as drawing a picture, and rayon asks for a new one on every split of the work.
#[derive(Default)]
struct Spare(std::sync::Mutex<Vec<Vec<Renderer>>>);

impl Spare {
    /// A set of renderers (one per face), given back when dropped.
    fn take<'a>(&'a self, batch: &Batch) -> Lent<'a> {
        let spare = self.0.lock().ok().and_then(|mut v| v.pop());
        Lent(spare.unwrap_or_else(|| batch.renderers()), self)
    }
}

/// Renderers lent by [`Spare`].
struct Lent<'a>(Vec<Renderer>, &'a Spare);

impl Drop for Lent<'_> {
    fn drop(&mut self) {
        if let Ok(mut spare) = self.1 .0.lock() {
            spare.push(std::mem::take(&mut self.0));
        }
    }
}

/// Writes a plan record into the output folder, or checks that the one there is the same.
fn record(path: &Path, bytes: &[u8], dir: &Path) -> Result<(), BatchError> {
    match std::fs::read(path) {
        Ok(old) if old == bytes => Ok(()),
        Ok(_) => Err(BatchError::new(format!(
            "{}: {} holds another plan's batch (its {} differs); use another --out folder",
            path.display(),
            dir.display(),
            path.file_name()
                .map(|n| n.to_string_lossy())
                .unwrap_or_default()
        ))),
        Err(_) => {
            write_atomic_no_backup(path, bytes).map_err(|e| BatchError::io(path, "cannot save", &e))
        }
    }
}

/// Writes an item's file: a temporary file renamed into place. A file left by a run killed
/// before its row was written is replaced, not kept as a backup.
fn write_item(path: &Path, bytes: &[u8]) -> Result<(), BatchError> {
    if let Some(parent) = path.parent() {
        std::fs::create_dir_all(parent)
            .map_err(|e| BatchError::io(parent, "cannot create the folder", &e))?;
    }
    if path.is_file() {
        let _ = std::fs::remove_file(path);
    }
    replace_unsynced(path, bytes).map_err(|e| BatchError::io(path, "cannot save", &e))
}

/// Appends one label row, flushed so a kill loses at most the row being written.
fn write_row(out: &mut File, path: &Path, line: &str) -> Result<(), BatchError> {
    out.write_all(line.as_bytes())
        .and_then(|()| out.flush())
        .map_err(|e| BatchError::io(path, "cannot save a label row", &e))
}

/// Removes temporary files a killed run of this shard left (`.ID.EXT.tmp-...`), and only
/// this shard's: another shard may be writing beside them.
fn sweep_temporaries(dir: &Path, items: &[Item], mine: &[usize]) {
    let mut folders: HashSet<PathBuf> = HashSet::new();
    let mut names: HashSet<String> = HashSet::new();
    for &i in mine {
        let path = dir.join(&items[i].file);
        if let (Some(parent), Some(name)) = (path.parent(), path.file_name()) {
            folders.insert(parent.to_path_buf());
            names.insert(name.to_string_lossy().into_owned());
        }
    }
    for folder in folders {
        let Ok(entries) = std::fs::read_dir(&folder) else {
            continue;
        };
        for entry in entries.flatten() {
            let name = entry.file_name().to_string_lossy().into_owned();
            let own = name
                .strip_prefix('.')
                .and_then(|n| n.split_once(".tmp-"))
                .is_some_and(|(file, _)| names.contains(file));
            if own {
                let _ = std::fs::remove_file(entry.path());
            }
        }
    }
}
