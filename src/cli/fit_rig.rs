//! `grimace fit-rig MESH.obj [--landmarks FILE] --out NAME.rig.ron`: carries a rig (the built-in
//! default rig unless `--template` names another) to a mesh from its 68 landmarks, and
//! writes it as an ordinary rig file that names the mesh. With `--pick` the landmarks are
//! picked first in the terminal ([`super::landmarks`]) and saved (to `--landmarks FILE`, or
//! `MESH.landmarks.ron` beside the mesh), then the rig is fitted from them.
//!
//! The mesh is used as it is, in its own units and orientation. The command prints how the
//! faces were aligned and which parts of the mesh it took for skin, for still parts and for
//! parts that turn with the jaw. Nothing is written when anything fails.
//!
//! When the lips are joined (one surface across the mouth, [`fit::lipcut`]), the skin is cut
//! along the inner lip line unless `--keep-lips` is given: the opened mesh is written beside
//! the rig as `NAME.opened.obj` (the given mesh is never changed, a dark mouth pocket is
//! appended behind the lips, [`fit::pocket`]) with its landmarks as
//! `NAME.opened.landmarks.ron`, and the rig is fitted to it and names it. Separate lips whose
//! insides meet in a mouth bag of skin get the same pocket behind them, written the same way
//! with nothing cut ([`lipcut::pocket_behind_apart_lips`]). Eye openings covered by skin
//! ([`fit::eyecut`]) are cut open into the same file unless `--keep-eyes` is given, with a
//! dark eye behind each.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use anyhow::{anyhow, Context};
use clap::Args;

use crate::fit::eyecut::{self, Lids};
use crate::fit::lipcut::{self, LipCut, Lips};
use crate::fit::weld;
use crate::fit::{self, Part, PartOverrides, Template};
use crate::io::inputs::Inputs;
use crate::io::landmarks::{
    beside, check_against, load_landmarks, parse_landmarks, save_landmarks,
};
use crate::io::load::{load_rig_ref, LoadedRig};
use crate::io::rig_file;
use crate::io::{atomic, error::read_text, obj, reference, LoadError, SaveError, MAX_FILE_BYTES};
use crate::landmarks::{self, Landmarks};
use crate::model::{Deformation, Mesh};

/// A landmark bend (see [`fit::Fitted::bend`]) from which `fit-rig` warns: public faces of
/// other shapes bend up to about half of the face from the built-in template.
const SUSPICIOUS_BEND: f64 = 0.9;

/// Arguments of `grimace fit-rig`.
#[derive(Debug, Args)]
pub struct FitRigArgs {
    /// The mesh to rig (Wavefront OBJ), in its own units and orientation.
    #[arg(value_name = "MESH.obj")]
    pub mesh: PathBuf,
    /// The mesh's 68 iBUG landmarks: a *.landmarks.ron file, MeshLab's picked points (*.pp),
    /// menpo's or landmarker.io's LJSON (*.ljson), a list one a line (*.txt, *.csv, *.xyz: x
    /// y z or a vertex number), or `mediapipe` for a
    /// MediaPipe face mesh (468 or 478 vertices, numbered like MediaPipe's landmarks).
    /// Default: MESH.landmarks.ron beside the mesh (where `grimace landmarks` saves them).
    /// With --pick, the file the picked landmarks are saved to (default: the same).
    #[arg(long, value_name = "FILE|mediapipe")]
    pub landmarks: Option<String>,
    /// Pick the landmarks in the terminal first, then fit.
    #[arg(long)]
    pub pick: bool,
    /// Braille, half-block or ASCII cells for --pick.
    #[command(flatten)]
    pub cells: super::CellsArgs,
    /// The rig file to write.
    #[arg(long, value_name = "NAME.rig.ron")]
    pub out: PathBuf,
    /// The rig to carry over (a *.rig.ron, builtin:default or builtin:paper).
    #[arg(long, value_name = "RIG", default_value = "builtin:default")]
    pub template: PathBuf,
    /// The template's landmarks, when its mesh is not built in and has no
    /// MESH.landmarks.ron beside it.
    #[arg(long, value_name = "FILE")]
    pub template_landmarks: Option<PathBuf>,
    /// Groups of the mesh that are skin, whatever their names say (repeatable).
    #[arg(long = "skin", value_name = "GROUP")]
    pub skin: Vec<String>,
    /// Groups of the mesh that muscles must not move (repeatable); those inside the mouth
    /// below the lips, or named like lower teeth or a tongue, turn with the jaw.
    #[arg(long = "rigid", value_name = "GROUP")]
    pub rigid: Vec<String>,
    /// Keep the mesh's own topology where its lips are joined (one surface across the
    /// mouth): no NAME.opened.obj is written, and the mouth opens by stretching that skin.
    /// Separate lips get no mouth pocket either.
    #[arg(long)]
    pub keep_lips: bool,
    /// Keep the mesh's own topology where skin covers an eye opening: the lids then close
    /// by squeezing that skin, and no dark eye is added.
    #[arg(long)]
    pub keep_eyes: bool,
    /// Keep the mesh's skin split where it is split at its seams (vertices written once per
    /// texture island): the split sides then move apart as the face moves.
    #[arg(long)]
    pub keep_seams: bool,
}

/// Runs `grimace fit-rig`.
pub fn run(args: &FitRigArgs) -> anyhow::Result<()> {
    let source = obj::read_obj(&args.mesh)?;
    check_groups(args, &source)?;
    let landmark_arg = landmark_source(args)?;
    let (source_landmarks, landmark_file) = target_landmarks(&landmark_arg, args, &source)?;
    let template = load_rig_ref(&args.template, None)?;
    let (template_points, template_file) = template_landmarks(args, &template)?;
    let mesh_path = mesh_reference(&args.mesh, &args.out)?;
    let mut inputs = Inputs::new();
    inputs.add("the mesh to rig", &args.mesh);
    inputs.add("the landmark file", &landmark_file);
    inputs.add_rig(&template);
    if let Some(path) = &args.template_landmarks {
        inputs.add("the template's landmark file", path);
    }
    inputs.check_output(&args.out)?;
    let marks = source_landmarks.vertices(&source);
    let weld = match args.keep_seams {
        true => None,
        false => weld::weld(&source, &marks),
    };
    let welded = weld.is_some();
    let (source, marks) = match weld {
        Some(w) => (w.mesh, w.landmarks),
        None => (source, marks),
    };
    let lips = lipcut::find(&source, &marks);
    let apart = match lips {
        Lips::Separate if !args.keep_lips => lipcut::pocket_behind_apart_lips(&source, &marks),
        _ => None,
    };
    let eyes = eyecut::find(&source, &marks);
    let opened = to_open(
        args,
        &inputs,
        (&lips, apart, welded),
        (&source, &marks, &eyes),
    )?;
    let (mesh, landmarks) = match &opened {
        Some((cut, _)) => (&cut.mesh, Landmarks::Vertices(cut.landmarks.clone())),
        None => (&source, source_landmarks),
    };
    let overrides = PartOverrides {
        skin: args.skin.clone(),
        rigid: args.rigid.clone(),
    };
    let mut fitted = fit::fit_rig(
        Template {
            rig: &template.rig,
            mesh: &template.mesh,
            landmarks: &template_points,
        },
        mesh,
        &landmarks,
        mesh_path,
        &overrides,
    )
    .map_err(|e| match e {
        // The template's own landmarks are at fault, not the mesh's.
        e @ fit::FitError::Template(_) => {
            anyhow!(LoadError::new(&template_file, e.to_string()))
        }
        e => anyhow!(LoadError::new(&landmark_file, e.to_string())),
    })?;
    if let Some((cut, _)) = &opened {
        lipcut::weights_by_side(&mut fitted.rig, cut);
    }
    warn_order(&landmark_file, &landmarks, mesh);
    for o in fitted.outliers(&template.rig, OUTLIER_FACTOR) {
        eprintln!(
            "warning: {}: its {} came out {:.2} times the template's at this face's scale \
             (check the landmarks around it)",
            o.muscle, o.what, o.ratio
        );
    }
    Deformation::default()
        .bind(&fitted.rig, mesh)
        .with_context(|| format!("the fitted rig does not bind to {}", args.mesh.display()))?;
    match &opened {
        Some((cut, files)) => fitted.rig.mesh = write_opened(args, (cut, welded), files)?,
        None => fitted.rig.landmarks = named_landmarks(args, &landmark_arg, &landmark_file),
    }
    rig_file::save_rig(&args.out, &fitted.rig)?;
    if fitted.bend >= SUSPICIOUS_BEND {
        eprintln!(
            "warning: a landmark bend of {:.0}% of the face usually means a landmark on the wrong feature or another numbering; check {} (docs/fitting.md, \"When a fit looks wrong\")",
            100.0 * fitted.bend,
            landmark_file.display()
        );
    }
    let mut text = summary(args, mesh, &fitted);
    let written = opened.as_ref().map(|(cut, f)| (cut, &f.0));
    let lips_cut = written.filter(|(cut, _)| !cut.copies.is_empty() || cut.pocket.is_some());
    text.push_str(&lips_summary(args, &lips, lips_cut));
    text.push_str(&eyes_summary(args, &eyes, written));
    if let (true, Some((_, obj_file))) = (welded, written) {
        text.push_str(&format!(
            "  seams: the skin was split at its seams; joined in {}: its faces name the first \
             of coincident vertices (--keep-seams leaves them split)\n",
            obj_file.display(),
        ));
    }
    super::print(&text)
}

/// The landmark file as the rig names it, when loading would not find it by itself: a file
/// other than `MESH.landmarks.ron` beside the mesh (a MediaPipe mesh's numbering needs none).
/// Without it the views would frame the rig without its landmarks: no face framing, brows or
/// painted eyes.
fn named_landmarks(args: &FitRigArgs, given: &str, file: &Path) -> Option<PathBuf> {
    let real = |p: &Path| std::fs::canonicalize(p).ok();
    let found_anyway = given == "mediapipe" || real(file) == real(&beside(&args.mesh));
    (!found_anyway).then(|| reference::written_reference(&args.out, file))
}

/// The opened mesh to write, with the files it goes to: joined lips unless `--keep-lips`,
/// else the pocket behind lips that are `apart` already, and the covered eyes of
/// `source` unless `--keep-eyes`, and a mesh whose seams were joined (`welded`) even with
/// nothing cut; the files must not be inputs.
fn to_open(
    args: &FitRigArgs,
    inputs: &Inputs,
    (lips, apart, welded): (&Lips, Option<LipCut>, bool),
    (source, marks, eyes): (&Mesh, &[u32], &[Lids; 2]),
) -> anyhow::Result<Option<(LipCut, (PathBuf, PathBuf))>> {
    let cut = match lips {
        Lips::Joined(cut) if !args.keep_lips => Some(cut.clone()),
        _ => apart,
    };
    let cut = match args.keep_eyes {
        true => cut,
        false => lipcut::open_eyes(cut, source, marks, eyes.clone()),
    };
    let uncut = || welded.then(|| LipCut::uncut(source.clone(), marks.to_vec()));
    let Some(cut) = cut.or_else(uncut) else {
        return Ok(None);
    };
    let files = opened_files(&args.out);
    inputs.check_output(&files.0)?;
    inputs.check_output(&files.1)?;
    Ok(Some((cut, files)))
}

/// Writes the opened mesh and its landmarks; returns the mesh as the rig names it.
fn write_opened(
    args: &FitRigArgs,
    (cut, welded): (&LipCut, bool),
    (obj_file, landmark_file): &(PathBuf, PathBuf),
) -> anyhow::Result<PathBuf> {
    let text = read_text(&args.mesh, MAX_FILE_BYTES)?;
    let written = opened_obj(&text, (cut, welded), &args.mesh);
    atomic::write_atomic(obj_file, written.as_bytes()).map_err(|e| SaveError::io(obj_file, &e))?;
    save_landmarks(landmark_file, &Landmarks::Vertices(cut.landmarks.clone()))?;
    Ok(reference::written_reference(&args.out, obj_file))
}

/// The opened mesh and its landmark file for the rig `out`: `NAME.opened.obj` and
/// `NAME.opened.landmarks.ron` beside it (`NAME` the rig's file name without `.rig.ron`).
fn opened_files(out: &Path) -> (PathBuf, PathBuf) {
    let name = out
        .file_name()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let stem = name
        .strip_suffix(".rig.ron")
        .or_else(|| name.strip_suffix(".ron"))
        .unwrap_or(&name);
    let obj_file = out.with_file_name(format!("{stem}.opened.obj"));
    let landmark_file = beside(&obj_file);
    (obj_file, landmark_file)
}

/// What was found at the lips and done about them, for the summary.
fn lips_summary(args: &FitRigArgs, lips: &Lips, written: Option<(&LipCut, &PathBuf)>) -> String {
    let mesh = args.mesh.display();
    match (lips, written) {
        (Lips::Separate, Some((cut, obj_file))) => format!(
            "  lips: separate surfaces (joined only inside the mouth): nothing cut; {} is {} \
             with {}, its landmarks in {}; the rig names it ({} itself is not changed; \
             --keep-lips writes no pocket)\n",
            obj_file.display(),
            mesh,
            pocket_phrase(cut),
            beside(obj_file).display(),
            mesh
        ),
        (Lips::Joined(cut), Some((_, obj_file))) => format!(
            "  lips: joined along the inner lip line ({} vertices{}); cut open there: {} is {} \
             with the {} vertices inside the line copied for the lower lip (vertices {} to {}; \
             its `# copy` lines name each original){}, its landmarks in {}; the rig names it. \
             --keep-lips keeps {}'s own topology (the mouth then opens by stretching the skin \
             between the lips)\n",
            cut.line.len(),
            band_words(cut),
            obj_file.display(),
            mesh,
            cut.copies.len(),
            cut.original_count() + 1,
            cut.original_count() + cut.copies.len(),
            pocket_words(cut),
            beside(obj_file).display(),
            mesh
        ),
        (Lips::Joined(cut), None) => format!(
            "  lips: joined along the inner lip line ({} vertices{}); kept as they are \
             (--keep-lips): the mouth opens by stretching the skin between the lips; without \
             --keep-lips they are cut open into NAME.opened.obj beside the rig\n",
            cut.line.len(),
            band_words(cut)
        ),
        (Lips::Open, _) => {
            "  lips: apart (the inner lip line is an edge of the mesh): nothing cut\n".into()
        }
        (Lips::Separate, _) => {
            "  lips: separate surfaces (joined only inside the mouth): nothing cut\n".into()
        }
        (Lips::NotFound, _) => {
            "  lips: no inner lip line found between landmarks 60-67: nothing cut\n".into()
        }
    }
}

/// What was found at the eyes and done about them, for the summary.
fn eyes_summary(
    args: &FitRigArgs,
    found: &[Lids; 2],
    written: Option<(&LipCut, &PathBuf)>,
) -> String {
    let cut = written.and_then(|(cut, file)| cut.eyes.as_ref().map(|e| (cut, e, file)));
    let covered = found
        .iter()
        .filter(|l| matches!(l, Lids::Covered(_)))
        .count();
    let each: Vec<String> = ["right", "left"]
        .iter()
        .zip(found)
        .map(|(side, lids)| format!("{side} {}", lids_words(lids)))
        .collect();
    let found_words = each.join(", ");
    match cut {
        Some((cut, eyes, obj_file)) => format!(
            "  eyes: {found_words}; cut open: in {} the skin across each covered eye moved onto \
             {} copies set back behind the opening and closed into a dark eye (vertices {} to {}, \
             group {}; `# copy` lines name each original). --keep-eyes keeps {}'s own topology \
             (the lids then close by squeezing that skin)\n",
            obj_file.display(),
            eyes.copies.len(),
            eyes.first + 1,
            cut.mesh.vertex_count(),
            eyecut::GROUP,
            args.mesh.display()
        ),
        None if covered > 0 => format!(
            "  eyes: {found_words}; kept as they are (--keep-eyes): the lids close by squeezing \
             the skin across the eye; without --keep-eyes it is cut open into NAME.opened.obj\n"
        ),
        None => format!("  eyes: {found_words}: nothing cut\n"),
    }
}

/// One eye's finding in words.
fn lids_words(lids: &Lids) -> String {
    match lids {
        Lids::Covered(c) => format!(
            "covered by {} triangles between lid margins of {} and {} vertices",
            c.band.len(),
            c.upper.len(),
            c.lower.len()
        ),
        Lids::Open => "open (its lid margins are edges of the mesh)".into(),
        Lids::Apart => "open (the lids fold inward to an opening)".into(),
        Lids::OneRow => "shut (both lids share one row of vertices; not cut)".into(),
        Lids::NotFound => "no lid margins found between its landmarks".into(),
    }
}

fn pocket_words(cut: &LipCut) -> String {
    match &cut.pocket {
        Some(_) => format!(" and {}", pocket_phrase(cut)),
        None => String::new(),
    }
}

/// The mouth pocket of `cut` in words: its size, vertices and group.
fn pocket_phrase(cut: &LipCut) -> String {
    match &cut.pocket {
        Some(p) => format!(
            "a mouth pocket of {} triangles behind the lips (vertices {} to {}, group {}: drawn \
             dark, its lower half turning with the jaw)",
            p.triangles,
            p.first + 1,
            cut.mesh.vertex_count(),
            fit::pocket::GROUP
        ),
        None => "no mouth pocket".into(),
    }
}

fn band_words(cut: &LipCut) -> String {
    if cut.band == 0 {
        String::new()
    } else {
        format!(
            ", with a band of {} triangles closing the mouth below it",
            cut.band
        )
    }
}

/// The opened mesh as OBJ text: `source`'s text line for line (texture coordinates, normals,
/// groups and materials kept), with the faces below the cut naming the copies, the copies'
/// `v` lines after the last original `v` line, and a `# copy K of V` comment for each (OBJ
/// numbers, from 1). Negative vertex indices are written as absolute ones, since the copies
/// shift what they count back from.
fn opened_obj(text: &str, (cut, welded): (&LipCut, bool), source: &Path) -> String {
    let n = cut.original_count();
    let is_v = |line: &str| {
        line.split('#')
            .next()
            .unwrap_or("")
            .split_whitespace()
            .next()
            == Some("v")
    };
    let last_v = text
        .split_inclusive('\n')
        .enumerate()
        .filter(|(_, l)| is_v(l))
        .last()
        .map(|(i, _)| i);
    let mut out = if cut.copies.is_empty() && cut.pocket.is_none() {
        format!(
            "# grimace fit-rig: {}. Vertices 1-{n} are its vertices.\n",
            source.display()
        )
    } else if cut.copies.is_empty() {
        format!(
            "# grimace fit-rig: {} with a mouth pocket behind its lips (apart already). Vertices \
             1-{n} are its vertices.\n",
            source.display()
        )
    } else {
        format!(
            "# grimace fit-rig: {} with its lips cut open along the inner lip line. Vertices 1-{n} \
             are its vertices; each copy below (vertex K a copy of vertex V) is the lower lip's \
             side of the cut.\n",
            source.display()
        )
    };
    if welded {
        let _ = writeln!(
            out,
            "# Its skin, split at its seams, is joined: faces name the first of coincident \
             vertices; the other copies stay at their numbers in no face and move with the \
             vertex each lies on."
        );
    }
    if let Some(eyes) = &cut.eyes {
        let _ = writeln!(
            out,
            "# Its covered eye openings are cut open: vertices {}-{} are the eyes' insides (group \
             {}), the skin that covered each opening moved onto copies (`# copy K of V`) set back \
             behind it, then the domes closing them.",
            eyes.first + 1,
            cut.mesh.vertex_count(),
            eyecut::GROUP
        );
    }
    let (mut defined, mut triangle) = (0usize, 0usize);
    let mut naming = EyeNaming::default();
    for (number, piece) in text.split_inclusive('\n').enumerate() {
        let line = piece.trim_end_matches(['\n', '\r']);
        let mut words = line.split('#').next().unwrap_or("").split_whitespace();
        match words.next() {
            Some("v") => {
                defined += 1;
                out.push_str(piece);
            }
            Some("f") => {
                let corners: Vec<&str> = words.collect();
                let count = corners.len().saturating_sub(2);
                naming.before_face(&mut out, in_eye(cut, triangle..triangle + count));
                out.push_str(&opened_face(&corners, defined, cut, triangle));
                out.push_str(&piece[line.len()..]);
                triangle += count;
            }
            Some(keyword @ ("o" | "g" | "usemtl")) => {
                naming.before_name(&mut out, keyword, piece);
                out.push_str(piece);
            }
            _ => out.push_str(piece),
        }
        if Some(number) == last_v {
            if !out.ends_with('\n') {
                out.push('\n');
            }
            push_copies(&mut out, cut, n);
        }
    }
    push_pocket(&mut out, cut);
    push_eyes(&mut out, cut);
    out
}

/// Whether the triangles `range` of the opened mesh are a covered eye's band, set back onto
/// the eye's copies (every corner one of the eyes' vertices).
fn in_eye(cut: &LipCut, range: std::ops::Range<usize>) -> bool {
    let Some(eyes) = &cut.eyes else {
        return false;
    };
    !range.is_empty()
        && cut.mesh.triangles[range]
            .iter()
            .all(|t| t.iter().all(|&v| v >= eyes.first))
}

/// Puts a covered eye's band faces, written where they were in the file, in the object, group
/// and material `eye_interior` with the domes, and gives the faces after them the names the
/// file had given them. A group of an OBJ is the vertices of its faces: named only on the
/// domes, the band's inner copies (on any mesh finer than the lids' two margins) read back
/// as no part of the eye, were drawn as skin over it and hid its painted iris.
#[derive(Default)]
struct EyeNaming {
    /// The file's last `o`, `g` and `usemtl` lines (the whole line), in that order.
    names: [Option<String>; 3],
    /// Whether the faces written last were a band's, under `eye_interior`.
    in_eye: bool,
}

impl EyeNaming {
    const KEYWORDS: [&'static str; 3] = ["o", "g", "usemtl"];

    /// Before a face: switches to `eye_interior` for a band face, back to the file's names
    /// after one.
    fn before_face(&mut self, out: &mut String, band: bool) {
        if band == self.in_eye {
            return;
        }
        if !out.ends_with('\n') {
            out.push('\n');
        }
        if band {
            let name = eyecut::GROUP;
            let _ = writeln!(out, "o {name}\ng {name}\nusemtl {name}");
        } else {
            for (keyword, line) in Self::KEYWORDS.iter().zip(&self.names) {
                match line {
                    Some(line) => out.push_str(line.trim_end_matches(['\n', '\r'])),
                    None => out.push_str(keyword),
                }
                out.push('\n');
            }
        }
        self.in_eye = band;
    }

    /// Before an `o`, `g` or `usemtl` line of the file (`piece`): the file's names come back
    /// first if a band's faces were written last, then this line is the file's own.
    fn before_name(&mut self, out: &mut String, keyword: &str, piece: &str) {
        self.before_face(out, false);
        if let Some(k) = Self::KEYWORDS.iter().position(|&w| w == keyword) {
            self.names[k] = Some(piece.to_string());
        }
    }
}

/// The mouth pocket's vertices (after the copies) and triangles (at the end of the file, in
/// its own object, group and material `mouth_interior`).
fn push_pocket(out: &mut String, cut: &LipCut) {
    let Some(pocket) = &cut.pocket else {
        return;
    };
    if !out.ends_with('\n') {
        out.push('\n');
    }
    let first = pocket.first as usize;
    let _ = writeln!(
        out,
        "# the mouth pocket: vertices {} to {}, drawn dark behind the opened lips",
        first + 1,
        cut.mesh.vertex_count()
    );
    let name = fit::pocket::GROUP;
    let _ = writeln!(out, "o {name}\ng {name}\nusemtl {name}");
    let end = cut.mesh.triangles.len() - cut.eyes.as_ref().map_or(0, |e| e.triangles);
    let triangles = &cut.mesh.triangles[end - pocket.triangles..end];
    for t in triangles {
        let _ = writeln!(out, "f {} {} {}", t[0] + 1, t[1] + 1, t[2] + 1);
    }
}

fn push_copies(out: &mut String, cut: &LipCut, n: usize) {
    for (k, &original) in cut.copies.iter().enumerate() {
        let p = cut.mesh.positions[n + k];
        let _ = writeln!(out, "v {} {} {}", p.x, p.y, p.z);
        let _ = writeln!(out, "# copy {} of {}", n + k + 1, original + 1);
    }
    let eyes = cut
        .eyes
        .as_ref()
        .map_or(cut.mesh.vertex_count(), |e| e.first as usize);
    if let Some(pocket) = &cut.pocket {
        for p in &cut.mesh.positions[pocket.first as usize..eyes] {
            let _ = writeln!(out, "v {} {} {}", p.x, p.y, p.z);
        }
    }
    if let Some(e) = &cut.eyes {
        for (k, p) in cut.mesh.positions[eyes..].iter().enumerate() {
            let _ = writeln!(out, "v {} {} {}", p.x, p.y, p.z);
            if let Some(original) = e.copies.get(k) {
                let _ = writeln!(out, "# copy {} of {}", eyes + k + 1, original + 1);
            }
        }
    }
}

/// The eyes' insides: each covered opening's band (its faces where they were, naming the
/// set-back copies) closed by a dome, whose triangles end the file in their own object,
/// group and material (`eye_interior`).
fn push_eyes(out: &mut String, cut: &LipCut) {
    let Some(eyes) = &cut.eyes else {
        return;
    };
    if !out.ends_with('\n') {
        out.push('\n');
    }
    let _ = writeln!(
        out,
        "# the eyes: vertices {} to {}, the covering skin set back and closed into a dark eye",
        eyes.first + 1,
        cut.mesh.vertex_count()
    );
    let name = eyecut::GROUP;
    let _ = writeln!(out, "o {name}\ng {name}\nusemtl {name}");
    for t in &cut.mesh.triangles[cut.mesh.triangles.len() - eyes.triangles..] {
        let _ = writeln!(out, "f {} {} {}", t[0] + 1, t[1] + 1, t[2] + 1);
    }
}

/// One `f` line of the opened mesh: the corners as given, vertex numbers absolute and
/// replaced by copies where the cut put them; a face whose triangles lie on both sides of
/// the cut (the line along its diagonal) is written as its triangles.
fn opened_face(corners: &[&str], defined: usize, cut: &LipCut, first: usize) -> String {
    let vertex = |corner: &str| -> u32 {
        let v = &corner[..corner.find('/').unwrap_or(corner.len())];
        let index: i64 = v.parse().unwrap_or(0);
        let absolute = if index < 0 {
            defined as i64 + index
        } else {
            index - 1
        };
        absolute as u32
    };
    let rest = |corner: &str| corner[corner.find('/').unwrap_or(corner.len())..].to_string();
    let fan: Vec<[usize; 3]> = (1..corners.len().saturating_sub(1))
        .map(|i| [0, i, i + 1])
        .collect();
    // The vertex each corner takes in each triangle of the fan.
    let mut taken: Vec<Option<u32>> = vec![None; corners.len()];
    let mut split = false;
    for (k, tri) in fan.iter().enumerate() {
        let t = first + k;
        for (slot, &c) in tri.iter().enumerate() {
            let v = cut.mesh.triangles[t][slot];
            split |= taken[c].is_some_and(|w| w != v);
            taken[c] = Some(v);
        }
    }
    let write = |c: usize, v: u32| format!(" {}{}", v + 1, rest(corners[c]));
    let mut out = String::new();
    if split {
        for (k, tri) in fan.iter().enumerate() {
            out.push('f');
            for (slot, &c) in tri.iter().enumerate() {
                out.push_str(&write(c, cut.mesh.triangles[first + k][slot]));
            }
            if k + 1 < fan.len() {
                out.push('\n');
            }
        }
    } else {
        out.push('f');
        for (c, v) in taken.iter().enumerate() {
            out.push_str(&write(c, v.unwrap_or_else(|| vertex(corners[c]))));
        }
    }
    out
}

/// Refuses `--skin`/`--rigid` groups the mesh does not have, listing those it has.
fn check_groups(args: &FitRigArgs, mesh: &Mesh) -> anyhow::Result<()> {
    for group in args.skin.iter().chain(&args.rigid) {
        if !mesh.groups.contains_key(group) {
            let known: Vec<&str> = mesh.groups.keys().map(String::as_str).collect();
            return Err(anyhow!(LoadError::new(
                &args.mesh,
                format!(
                    "has no group `{group}`; its groups are: {}",
                    if known.is_empty() {
                        "none".to_string()
                    } else {
                        known.join(", ")
                    }
                ),
            )));
        }
    }
    Ok(())
}

/// The landmarks argument: `--landmarks` as given, or with `--pick` the file the picker
/// saved (the template and the outputs are checked before the picking starts).
fn landmark_source(args: &FitRigArgs) -> anyhow::Result<String> {
    Ok(match (&args.landmarks, args.pick) {
        (Some(l), true) if l == "mediapipe" => {
            return Err(anyhow!(
                "--pick saves the picked landmarks to a file: give --landmarks FILE, not mediapipe"
            ))
        }
        (Some(l), false) => l.clone(),
        (given, true) => {
            let file = given
                .as_ref()
                .map_or_else(|| beside(&args.mesh), PathBuf::from);
            // The template and the output folder are checked before the picking starts.
            let template = load_rig_ref(&args.template, None)?;
            mesh_reference(&args.mesh, &args.out)?;
            let mut inputs = Inputs::new();
            inputs.add("the mesh to rig", &args.mesh);
            inputs.add_rig(&template);
            inputs.check_output(&file)?;
            inputs.add("the landmark file", &file);
            inputs.check_output(&args.out)?;
            let saved =
                super::landmarks::pick_landmarks(&args.mesh, &file, args.cells.mode(), None)?;
            if !saved {
                return Err(anyhow!(
                    "no landmarks were saved (:w saves them in the picker); no rig was fitted"
                ));
            }
            file.to_string_lossy().into_owned()
        }
        (None, false) => {
            let file = beside(&args.mesh);
            if !file.is_file() {
                return Err(anyhow!(
                    "no landmarks for {}: {} is not there; give --landmarks FILE (or \
                     `--landmarks mediapipe` for a MediaPipe face mesh), pick them with --pick, \
                     or first with `grimace landmarks {}`",
                    args.mesh.display(),
                    file.display(),
                    args.mesh.display()
                ));
            }
            file.to_string_lossy().into_owned()
        }
    })
}

/// A fitted muscle whose size or strength is more than this many times off the template's
/// (times the face's scale) is warned about.
const OUTLIER_FACTOR: f64 = 2.0;

/// Warns about landmarks out of the iBUG scheme's order (a contour listed backwards, a point
/// on the wrong side): the fit goes ahead, but crosses what is out of order.
fn warn_order(file: &Path, landmarks: &Landmarks, mesh: &Mesh) {
    let Ok(points) = landmarks.positions(mesh) else {
        return;
    };
    for problem in landmarks::order_problems(&points) {
        eprintln!("warning: {}: {problem}", file.display());
    }
}

/// The mesh's landmarks and the file to name in messages about them.
fn target_landmarks(
    given: &str,
    args: &FitRigArgs,
    mesh: &Mesh,
) -> anyhow::Result<(Landmarks, PathBuf)> {
    if given == "mediapipe" {
        let landmarks = Landmarks::mediapipe(mesh)
            .map_err(|e| anyhow!(LoadError::new(&args.mesh, e.to_string())))?;
        check_against(&landmarks, mesh, &args.mesh, None)?;
        return Ok((landmarks, args.mesh.clone()));
    }
    let path = PathBuf::from(given);
    let text = read_text(&path, MAX_FILE_BYTES)?;
    let landmarks = parse_landmarks(&text, &path)?;
    check_against(&landmarks, mesh, &path, Some(&text))?;
    Ok((landmarks, path))
}

/// The template's landmark positions: given, built in, or `MESH.landmarks.ron` beside the
/// template's mesh.
fn template_landmarks(
    args: &FitRigArgs,
    template: &LoadedRig,
) -> anyhow::Result<(Vec<glam::Vec3>, PathBuf)> {
    let (landmarks, path) = match &args.template_landmarks {
        Some(path) => (load_landmarks(path)?, path.clone()),
        None => template.landmarks("--template-landmarks")?,
    };
    let points = check_against(&landmarks, &template.mesh, &path, None)?;
    Ok((points, path))
}

/// The mesh as the new rig names it: relative to the rig file's real folder (see
/// [`crate::io::reference`]).
fn mesh_reference(mesh: &Path, out: &Path) -> anyhow::Result<PathBuf> {
    std::fs::canonicalize(mesh).with_context(|| format!("cannot resolve {}", mesh.display()))?;
    if let Some(dir) = out.parent().filter(|p| !p.as_os_str().is_empty()) {
        if !dir.is_dir() {
            return Err(anyhow!("the folder of {} does not exist", out.display()));
        }
    }
    Ok(reference::written_reference(out, mesh))
}

fn summary(args: &FitRigArgs, mesh: &Mesh, fitted: &fit::Fitted) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "{}: {} muscles from {} fitted to {} ({} vertices): scale {:.4}, landmark bend {:.1}% of the face",
        args.out.display(),
        fitted.rig.muscles.len(),
        args.template.display(),
        args.mesh.display(),
        mesh.vertex_count(),
        fitted.scale,
        100.0 * fitted.bend
    );
    for choice in &fitted.parts.choices {
        let what = match choice.part {
            Part::Skin => "skin",
            Part::Still => "kept still",
            Part::Jaw => "turns with the jaw",
        };
        let _ = writeln!(
            out,
            "  {}: {} ({} vertices, by {})",
            choice.name, what, choice.vertices, choice.reason
        );
    }
    let count = |p: Part| fitted.parts.of_vertex.iter().filter(|&&x| x == p).count();
    let _ = writeln!(
        out,
        "  vertices: {} skin, {} kept still, {} turn with the jaw",
        count(Part::Skin),
        count(Part::Still),
        count(Part::Jaw)
    );
    let copies = mesh.followers().len();
    if copies > 0 {
        let _ = writeln!(
            out,
            "  seam copies (in no face): {copies} vertices, each moving with the vertex it lies on"
        );
    }
    if let Some(jaw) = &fitted.rig.jaw {
        let _ = writeln!(out, "  jaw: {} weighted vertices", jaw.weights.len());
    }
    if let Some(landmarks) = &fitted.rig.landmarks {
        let _ = writeln!(
            out,
            "  landmarks: {} (named in the rig, where the views find them)",
            landmarks.display()
        );
    }
    for (opening, upper, lower) in &fitted.sides {
        if !upper.is_empty() || !lower.is_empty() {
            let _ = writeln!(
                out,
                "  {opening}: {} muscles kept above its line, {} below",
                upper.len(),
                lower.len()
            );
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    /// A quad whose diagonal is the cut: its two triangles lie on both sides, so the face is
    /// written as its triangles; the copy goes after the last vertex, texture coordinates
    /// stay, and a negative index becomes absolute.
    #[test]
    fn opened_obj_names_a_covered_eyes_band_and_gives_the_faces_after_it_their_names() {
        let text = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\ng skin\nusemtl face\nf 1 2 3\nf 1 3 4\nf 2 5 3\n";
        let source = obj::parse_obj(text, Path::new("e.obj")).unwrap();
        let mut mesh = source.clone();
        // the second face is the band: set back onto copies of its corners
        for v in [0, 2, 3] {
            mesh.positions.push(source.positions[v] - Vec3::Z);
        }
        mesh.triangles[1] = [5, 6, 7];
        let cut = LipCut {
            mesh,
            copies: vec![],
            line: vec![],
            band: 0,
            landmarks: vec![],
            pocket: None,
            eyes: Some(Box::new(eyecut::EyeCut {
                found: [Lids::NotFound, Lids::NotFound],
                first: 5,
                triangles: 0,
                copies: vec![0, 2, 3],
            })),
        };
        let written = opened_obj(text, (&cut, false), Path::new("e.obj"));
        assert!(
            written.contains("f 1 2 3\no eye_interior\ng eye_interior\nusemtl eye_interior\nf 6 7 8\no\ng skin\nusemtl face\nf 2 5 3\n"),
            "{written}"
        );
        let back = obj::parse_obj(&written, Path::new("o.obj")).unwrap();
        assert_eq!(back.triangles, cut.mesh.triangles);
        // every copy is the eye's, none of the skin's
        assert_eq!(back.groups[eyecut::GROUP], vec![5, 6, 7]);
        assert_eq!(back.groups["material:eye_interior"], vec![5, 6, 7]);
        assert_eq!(back.groups["skin"], vec![0, 1, 2, 4]);
        assert_eq!(back.groups["material:face"], vec![0, 1, 2, 4]);
    }

    #[test]
    fn opened_obj_keeps_the_file_and_splits_a_face_across_the_cut() {
        let text = "# a quad\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nusemtl skin\nf 1/1 2/1 3/1 -1/1\n";
        let source = obj::parse_obj(text, Path::new("q.obj")).unwrap();
        let mut mesh = source.clone();
        mesh.positions.push(Vec3::new(1.0, 1.0, 0.0));
        mesh.triangles[1] = [0, 4, 3];
        let cut = LipCut {
            mesh,
            copies: vec![2],
            line: vec![0, 2, 1],
            band: 0,
            landmarks: vec![],
            pocket: None,
            eyes: None,
        };
        let written = opened_obj(text, (&cut, false), Path::new("q.obj"));
        assert!(
            written.contains("v 0 1 0\nv 1 1 0\n# copy 5 of 3\nvt 0 0\nusemtl skin\nf 1/1 2/1 3/1\nf 1/1 5/1 4/1\n"),
            "{written}"
        );
        let back = obj::parse_obj(&written, Path::new("o.obj")).unwrap();
        assert_eq!(back.positions, cut.mesh.positions);
        assert_eq!(back.triangles, cut.mesh.triangles);
        assert_eq!(back.groups["material:skin"], vec![0, 1, 2, 3, 4]);
    }
}
