//! `grimace capture RECORDING.csv --out ACTS.csv [--rig RIG] [--aus] [--neutral N] [--live]`:
//! each tracked frame's muscle activations and jaw, solved from OpenFace's 3D landmarks on
//! the rig ([`crate::capture`]), written as an activation CSV ([`crate::io::acts`]) that
//! `play` and `render --acts` replay on any fitted head.

use std::fs::File;
use std::io::{BufRead, BufReader, Write};
use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{anyhow, bail, Context};
use clap::Args;
use glam::Vec3;

use crate::capture::{
    AuProjection, Captured, LandmarkModel, NeutralSource, Regularisation, Session,
};
use crate::io::inputs::Inputs;
use crate::io::load::{load_rig_ref, load_table_ref_for, LoadedRig};
use crate::io::openface::{OpenFaceReader, RowOutcome};
use crate::io::{acts, atomic, landmarks, LoadError};
use crate::model::{BoundRig, Deformation};
use crate::play::skips::Skips;

/// Arguments of `grimace capture`.
#[derive(Debug, Args)]
pub struct CaptureArgs {
    /// OpenFace 2.0 FeatureExtraction CSV with the 3D landmarks (X_0..Z_67); `-` with --live
    /// reads rows from stdin.
    #[arg(value_name = "RECORDING.csv", required_unless_present = "udp")]
    pub recording: Option<PathBuf>,
    /// The activation CSV to write (`-` for stdout).
    #[arg(long, value_name = "ACTS.csv")]
    pub out: PathBuf,
    /// The rig to solve on (a *.rig.ron, builtin:default or builtin:paper).
    #[arg(long, value_name = "RIG", default_value = "builtin:default")]
    pub rig: PathBuf,
    /// The 68 landmarks of the rig's mesh, when it is not built in and has no
    /// MESH.landmarks.ron beside it.
    #[arg(long, value_name = "FILE")]
    pub rig_landmarks: Option<PathBuf>,
    /// The AU table for --aus (default: the built-in default table).
    #[arg(long, value_name = "TABLE")]
    pub table: Option<PathBuf>,
    /// Also write AU intensities (AU01_r ..., 0-5) derived from the activations.
    #[arg(long)]
    pub aus: bool,
    /// The frame number (OpenFace's `frame`) of a neutral face; default: estimated from the
    /// recording (with --live: the first tracked frame).
    #[arg(long, value_name = "N")]
    pub neutral: Option<u64>,
    /// The face to capture in a recording of several (OpenFace's `face_id`); default: the face
    /// of the first tracked row.
    #[arg(long, value_name = "ID")]
    pub face: Option<u32>,
    /// Read rows as they arrive (a running OpenFace piped to stdin) and write each frame at
    /// once.
    #[arg(long)]
    pub live: bool,
    /// With --live: read the rows from UDP datagrams on this loopback address (the header
    /// line first; each datagram one or more lines) instead of stdin.
    #[arg(
        long,
        value_name = "ADDR",
        requires = "live",
        conflicts_with = "recording"
    )]
    pub udp: Option<String>,
}

/// The most tracked frames a file may hold (about nine hours at 30 frames a second): every
/// frame's landmarks are kept until the neutral is known.
pub const MAX_FRAMES: usize = 1_000_000;

/// One tracked row of the recording.
struct Tracked {
    source: acts::Source,
    landmarks: Vec<Vec3>,
}

/// The rig and what the solve needs of it.
struct Prepared {
    bound: BoundRig,
    model: LandmarkModel,
    projection: Option<AuProjection>,
    loaded: LoadedRig,
}

/// Runs `grimace capture`.
pub fn run(args: &CaptureArgs) -> anyhow::Result<()> {
    let started = Instant::now();
    let prepared = prepare(args)?;
    if args.live {
        return live(args, &prepared);
    }
    let Some(recording) = &args.recording else {
        bail!("give the recording (a file), or --live with --udp ADDR");
    };
    let mut inputs = Inputs::new();
    inputs.add_rig(&prepared.loaded);
    inputs.add("the recording", recording);
    if args.out != Path::new("-") {
        inputs.check_output(&args.out)?;
        inputs.check_output(&manifest_path(&args.out))?;
    }
    if let Some(reason) = crate::io::error::not_a_file(recording) {
        bail!("{}: {reason}", recording.display());
    }
    let file =
        File::open(recording).with_context(|| format!("cannot open {}", recording.display()))?;
    let mut reader =
        OpenFaceReader::with_landmarks(BufReader::new(file), recording)?.follow_face(args.face);
    check_face_column(args.face, &reader, recording)?;
    let (rows, skips) = read_rows(&mut reader)?;
    if rows.is_empty() {
        if let (Some(id), false) = (args.face, reader.faces().others().is_empty()) {
            bail!(
                "{}: no tracked row of face {id}; the recording's faces: {}",
                recording.display(),
                list(&reader.faces().others())
            );
        }
    }
    let (mut session, neutral) = file_session(args, recording, &prepared, &rows)?;
    let mut text = String::new();
    text.push_str(&header(&prepared));
    text.push('\n');
    let mut explained = Vec::new();
    let mut unusable = 0;
    let mut last_frame = None;
    for row in &rows {
        // Frames lost, repeated or run backwards (recordings joined end to end): the next
        // is not the same face a frame later, and is solved afresh.
        if last_frame.is_some_and(|f: u64| row.source.frame != f + 1) {
            session.gap();
        }
        last_frame = Some(row.source.frame);
        let Some(captured) = session.frame(&row.landmarks) else {
            unusable += 1;
            continue;
        };
        explained.extend(captured.explained);
        text.push_str(&line(&prepared, row, &captured));
        text.push('\n');
    }
    if rows.len() == unusable {
        bail!("{}: no frame has a usable face", recording.display());
    }
    write_out(&args.out, &text)?;
    let written = rows.len() - unusable;
    let summary = Summary {
        written,
        unusable,
        explained,
        neutral,
        skips,
        faces: reader.faces().summary(),
        seconds: started.elapsed().as_secs_f64(),
    };
    if args.out != Path::new("-") {
        write_manifest(args, recording, &summary)?;
    }
    eprint!("{}", summary.text(args));
    Ok(())
}

/// Loads and binds the rig, finds its landmark vertices, and the AU projection.
fn prepare(args: &CaptureArgs) -> anyhow::Result<Prepared> {
    let loaded = load_rig_ref(&args.rig, None)?;
    let bound = Deformation::default()
        .bind(&loaded.rig, &loaded.mesh)
        .map_err(|e| anyhow!(LoadError::new(&args.rig, e.to_string())))?;
    let vertices = rig_landmarks(args, &loaded)?;
    let model = LandmarkModel::new(&bound, &vertices);
    let projection = if args.aus {
        let table = match &args.table {
            Some(path) => load_table_ref_for(path, &loaded.rig)?,
            None => load_table_ref_for(Path::new("builtin:default"), &loaded.rig)
                .context("the built-in AU table does not fit this rig; give --table")?,
        };
        Some(AuProjection::new(&table, &bound, &model))
    } else {
        None
    };
    Ok(Prepared {
        bound,
        model,
        projection,
        loaded,
    })
}

/// The vertex of each of the 68 landmarks on the rig's mesh: given, built in, or
/// `MESH.landmarks.ron` beside the rig's mesh.
fn rig_landmarks(args: &CaptureArgs, loaded: &LoadedRig) -> anyhow::Result<Vec<u32>> {
    let (set, path) = match &args.rig_landmarks {
        Some(path) => (landmarks::load_landmarks(path)?, path.clone()),
        None => loaded.landmarks("--rig-landmarks")?,
    };
    landmarks::check_against(&set, &loaded.mesh, &path, None)?;
    Ok(set.vertices(&loaded.mesh))
}

/// Every row of the recording: the tracked ones kept, the others counted (malformed rows
/// named while few, as `play` does).
fn read_rows<R: BufRead>(reader: &mut OpenFaceReader<R>) -> anyhow::Result<(Vec<Tracked>, Skips)> {
    let mut rows = Vec::new();
    let mut skips = Skips::default();
    let name = reader.path().display().to_string();
    while let Some(outcome) = reader.next_row()? {
        match outcome {
            RowOutcome::Malformed(e) => {
                if let Some(message) = skips.malformed(&format!("{name}:{e}")) {
                    eprintln!("warning: {message}");
                }
            }
            RowOutcome::Row(row) if !row.success => skips.untracked(),
            RowOutcome::Row(_) if rows.len() >= MAX_FRAMES => bail!(
                "{name}: more than {MAX_FRAMES} tracked frames; capture a recording this long in parts, or with --live"
            ),
            RowOutcome::Row(row) => {
                let frame = row
                    .frame
                    .map_or(rows.len() as u64 + 1, |f| f.max(0.0) as u64);
                rows.push(tracked(frame, row));
            }
        }
    }
    Ok((rows, skips))
}

/// The session for a whole file: its neutral given (`--neutral N`) or estimated.
fn file_session<'a>(
    args: &CaptureArgs,
    recording: &Path,
    prepared: &'a Prepared,
    rows: &[Tracked],
) -> anyhow::Result<(Session<'a>, NeutralSource)> {
    let at = |e: crate::capture::CaptureError| anyhow!(LoadError::new(recording, e.to_string()));
    let session = match args.neutral {
        Some(n) => {
            let row = rows.iter().find(|r| r.source.frame == n).ok_or_else(|| {
                anyhow!(LoadError::new(
                    recording,
                    format!("--neutral {n}: no tracked frame {n} in the recording")
                ))
            })?;
            Session::from_frame(
                &prepared.bound,
                &prepared.model,
                &row.landmarks,
                NeutralSource::Frame(n),
                Regularisation::default(),
            )
            .map_err(at)?
        }
        None => {
            let frames: Vec<&[Vec3]> = rows.iter().map(|r| r.landmarks.as_slice()).collect();
            let (neutral, _) = crate::capture::pose::estimate_neutral(&frames)
                .ok_or(crate::capture::CaptureError::NoUsableFrames)
                .map_err(at)?;
            let regularisation = Regularisation::default();
            let (neutral, found) = crate::capture::neutral::least_work(
                &prepared.bound,
                &prepared.model,
                &frames,
                neutral,
                regularisation,
            )
            .map_err(at)?;
            let source = NeutralSource::LeastWork {
                used: found.used,
                of: found.of,
                passes: found.passes,
            };
            Session::new(
                &prepared.bound,
                &prepared.model,
                neutral,
                source,
                regularisation,
            )
            .map_err(at)?
        }
    };
    let source = session.source.clone();
    Ok((session, source))
}

/// The output's header line.
fn header(prepared: &Prepared) -> String {
    let muscles: Vec<String> = prepared
        .loaded
        .rig
        .muscles
        .iter()
        .map(|m| m.name.clone())
        .collect();
    let aus = prepared
        .projection
        .as_ref()
        .map(AuProjection::names)
        .unwrap_or_default();
    acts::header_line(&muscles, &aus)
}

/// One frame's output line.
fn line(prepared: &Prepared, row: &Tracked, captured: &Captured) -> String {
    let aus = prepared
        .projection
        .as_ref()
        .map(|p| p.intensities(&captured.motion))
        .unwrap_or_default();
    acts::row_line(row.source, captured.explained, &captured.activations, &aus)
}

/// Writes the output atomically, or to stdout for `-`.
fn write_out(out: &Path, text: &str) -> anyhow::Result<()> {
    if out == Path::new("-") {
        return super::print(text);
    }
    atomic::write_atomic(out, text.as_bytes())
        .with_context(|| format!("cannot write {}", out.display()))
}

/// What a run did.
struct Summary {
    written: usize,
    unusable: usize,
    explained: Vec<f64>,
    neutral: NeutralSource,
    skips: Skips,
    /// Which face was followed, when the recording holds several.
    faces: Option<String>,
    seconds: f64,
}

impl Summary {
    fn median_explained(&self) -> Option<f64> {
        let mut v = self.explained.clone();
        v.sort_by(f64::total_cmp);
        (!v.is_empty()).then(|| v[v.len() / 2])
    }

    fn text(&self, args: &CaptureArgs) -> String {
        let mut out = format!(
            "{}: {} frames solved in {:.2} s; neutral: {}\n",
            args.out.display(),
            self.written,
            self.seconds,
            self.neutral
        );
        match self.median_explained() {
            Some(m) => out.push_str(&format!(
                "  median explained {:.3} over {} frames that moved above the noise floor\n",
                m,
                self.explained.len()
            )),
            None => out.push_str("  no frame moved above the landmarks' noise floor\n"),
        }
        if self.unusable > 0 {
            out.push_str(&format!(
                "  skipped {} frames whose landmarks are not a usable face (non-finite or degenerate)\n",
                self.unusable
            ));
        }
        if let Some(s) = self.skips.summary() {
            out.push_str(&format!("  {s}\n"));
        }
        if let Some(s) = &self.faces {
            out.push_str(&format!("  {s}\n"));
        }
        out
    }
}

/// `ACTS.csv` -> `ACTS.capture.txt`: how the file was made (the neutral, the counts), kept
/// beside it so the CSV itself stays readable by OpenFace tools.
pub fn manifest_path(out: &Path) -> PathBuf {
    let stem = out
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    out.with_file_name(format!("{stem}.capture.txt"))
}

fn write_manifest(args: &CaptureArgs, recording: &Path, summary: &Summary) -> anyhow::Result<()> {
    let text = format!(
        "grimace capture\nrecording: {}\nrig: {}\n{}",
        recording.display(),
        args.rig.display(),
        summary.text(args)
    );
    let path = manifest_path(&args.out);
    atomic::write_atomic(&path, text.as_bytes())
        .with_context(|| format!("cannot write {}", path.display()))
}

/// `--live`: rows from stdin or loopback UDP, each frame written as it is solved; the
/// neutral is frame `--neutral N` (frames before it are skipped) or the first tracked frame.
fn live(args: &CaptureArgs, prepared: &Prepared) -> anyhow::Result<()> {
    if let Some(address) = &args.udp {
        let address = crate::play::live::loopback_address(address)?;
        let socket = std::net::UdpSocket::bind(address)
            .with_context(|| format!("cannot listen on udp {address}"))?;
        eprintln!("listening on udp {}", socket.local_addr()?);
        // Room for the largest datagram, so none is cut.
        let input = BufReader::with_capacity(1 << 17, Datagrams { socket });
        let reader =
            OpenFaceReader::with_landmarks(input, Path::new("udp"))?.follow_face(args.face);
        return live_rows(args, prepared, reader);
    }
    if args.recording.as_deref() != Some(Path::new("-")) {
        bail!("--live reads rows from stdin (give `-` as the recording) or from --udp ADDR");
    }
    let reader = OpenFaceReader::with_landmarks(std::io::stdin().lock(), Path::new("-"))?
        .follow_face(args.face);
    live_rows(args, prepared, reader)
}

/// UDP datagrams read as one stream of lines (a datagram without a final line end gets one).
struct Datagrams {
    socket: std::net::UdpSocket,
}

impl std::io::Read for Datagrams {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let n = self.socket.recv(buf)?;
        if n > 0 && n < buf.len() && buf[n - 1] != b'\n' {
            buf[n] = b'\n';
            return Ok(n + 1);
        }
        Ok(n)
    }
}

/// Solves and writes each row of a live stream as it arrives.
fn live_rows<R: BufRead>(
    args: &CaptureArgs,
    prepared: &Prepared,
    mut reader: OpenFaceReader<R>,
) -> anyhow::Result<()> {
    let mut out: Box<dyn Write> = if args.out == Path::new("-") {
        Box::new(std::io::stdout().lock())
    } else {
        Box::new(
            File::create(&args.out)
                .with_context(|| format!("cannot create {}", args.out.display()))?,
        )
    };
    check_face_column(args.face, &reader, reader.path())?;
    writeln!(out, "{}", header(prepared))?;
    out.flush()?;
    let mut session: Option<Session> = None;
    let mut skips = Skips::default();
    let mut unusable = 0usize;
    while let Some(next) = next_tracked(&mut reader, &mut skips)? {
        let Some(row) = next else {
            // A lost frame: the next is solved afresh, not held near the one before.
            if let Some(session) = session.as_mut() {
                session.gap();
            }
            continue;
        };
        if session.is_none() && args.neutral.is_none_or(|n| n == row.source.frame) {
            let source = match args.neutral {
                Some(n) => NeutralSource::Frame(n),
                None => NeutralSource::FirstFrame(row.source.frame),
            };
            let regularisation = Regularisation::default();
            session = Session::from_frame(
                &prepared.bound,
                &prepared.model,
                &row.landmarks,
                source,
                regularisation,
            )
            .ok();
        }
        let Some(session) = session.as_mut() else {
            continue;
        };
        let Some(captured) = session.frame(&row.landmarks) else {
            unusable += 1;
            continue;
        };
        writeln!(out, "{}", line(prepared, &row, &captured))?;
        out.flush()?;
    }
    if unusable > 0 {
        eprintln!("skipped {unusable} frames whose landmarks are not a usable face");
    }
    if let Some(s) = skips.summary() {
        eprintln!("{s}");
    }
    if let Some(s) = reader.faces().summary() {
        eprintln!("{s}");
    }
    Ok(())
}

/// `--face ID` other than 0 on a recording without `face_id` (one face) is a mistake worth
/// naming rather than a capture of the only face.
fn check_face_column<R: BufRead>(
    face: Option<u32>,
    reader: &OpenFaceReader<R>,
    recording: &Path,
) -> anyhow::Result<()> {
    match face {
        Some(id) if id != 0 && reader.columns().face_id.is_none() => bail!(
            "{}: --face {id}: the recording has no face_id column (it holds one face)",
            recording.display()
        ),
        _ => Ok(()),
    }
}

/// A tracked row as frame `frame`.
fn tracked(frame: u64, row: crate::io::openface::OpenFaceRow) -> Tracked {
    Tracked {
        source: acts::Source {
            frame,
            face: row.face.unwrap_or(0),
            timestamp: row.timestamp.unwrap_or(0.0),
            confidence: row.confidence,
        },
        landmarks: row.landmarks,
    }
}

/// `0, 1, 2`.
fn list(ids: &[u32]) -> String {
    ids.iter()
        .map(u32::to_string)
        .collect::<Vec<_>>()
        .join(", ")
}

/// The next row of a stream: `None` at its end, `Some(None)` for a row skipped (untracked or
/// malformed, counted), `Some(Some(row))` for a tracked one.
fn next_tracked<R: BufRead>(
    reader: &mut OpenFaceReader<R>,
    skips: &mut Skips,
) -> anyhow::Result<Option<Option<Tracked>>> {
    let Some(outcome) = reader.next_row()? else {
        return Ok(None);
    };
    if let Some(notice) = reader.take_face_notice() {
        eprintln!("note: {notice}");
    }
    Ok(Some(match outcome {
        RowOutcome::Malformed(e) => {
            if let Some(message) = skips.malformed(&format!("-:{e}")) {
                eprintln!("warning: {message}");
            }
            None
        }
        RowOutcome::Row(row) if !row.success => {
            skips.untracked();
            None
        }
        RowOutcome::Row(row) => Some(tracked(row.frame.map_or(0, |f| f.max(0.0) as u64), row)),
    }))
}
