//! `grimace play`: animate the face from an OpenFace CSV, a timeline, or a live AU stream.
//!
//! Headless (`--headless`) prints one line per frame played and a final count, as fast as it
//! can unless `--realtime` asks it to keep the source's pace; otherwise a full-screen terminal
//! view plays at the source's frame rate, dropping frames it cannot show in time.

use std::io::{self, BufWriter, IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use anyhow::{bail, Context, Result};
use clap::Args;

use super::export::{self, SourceArgs};
use crate::facs::AuTable;
use crate::io::load::load_table_ref_for;
use crate::io::load::LoadedRig;
use crate::io::timeline::load_timeline;
use crate::model::{Mesh, Rig};
use crate::play::open::{open_file, RecordingOptions};
use crate::play::player::Reopen;
use crate::play::skips::Skips;
use crate::play::{
    AuMapper, Event, Frame, FrameSource, FrameStats, IntensityScale, LiveSource, PlayClock, Player,
    Poll, SourceError, TimelineSource,
};
use crate::tui::keymap;

/// The notes at the end of `grimace play --help`, before the keys.
const NOTES: &str = "\
INPUT:
  FILE.csv            OpenFace 2.0 output (AUxx_r intensities 0-5; rows with success 0 skipped;
                      of several faces, the first tracked face_id or --face ID is played),
                      or a Live Link Face recording (Timecode,BlendShapeCount, then ARKit
                      weights 0-1, played through presets/arkit.map.ron; timecodes at --fps,
                      default 60), or an activation CSV from `grimace capture` (muscles by
                      name onto the rig)
  FILE.timeline.ron   keyframes of AU combinations or activations (see docs/formats.md)
  --stdin             one frame per line: a CSV header line (OpenFace or Live Link Face)
                      then rows, or JSON objects
                      {\"AU1\": 0.0, ..., \"AU45\": 0.0}; ARKit names (\"jawOpen\": 0-1) too
  --udp 127.0.0.1:PORT  JSON objects, one per datagram, on a loopback port (0 picks one)

HEADLESS OUTPUT:
  one line per frame: `TIME AU1=2.10 AU12=0.80 | muscle=0.42 jaw=0.10` (AUs and activations
  that are not zero; `rest` when none), then `played N frames, skipped M`. Skipped rows
  (success 0, malformed) count in M; each malformed row is named by line on stderr.";

/// The notes and the terminal view's keys, from the key table.
fn after_help() -> String {
    let mut text = format!("{NOTES}\n\nKEYS (terminal view):");
    for (keys, what) in keymap::play_help_lines() {
        text.push_str(&format!("\n  {keys:<20}{what}"));
    }
    text
}

/// Arguments of `grimace play`.
#[derive(Debug, Clone, Args)]
#[command(after_help = after_help())]
pub struct PlayArgs {
    /// An OpenFace CSV file, a `grimace capture` activation CSV or a `*.timeline.ron` file.
    #[arg(value_name = "FILE", required_unless_present_any = ["stdin", "udp"], conflicts_with_all = ["stdin", "udp"])]
    pub file: Option<PathBuf>,
    /// Read frames from stdin (CSV with a header line, or one JSON object per line).
    #[arg(long, conflicts_with = "udp")]
    pub stdin: bool,
    /// Listen for JSON frames on a loopback UDP address, e.g. 127.0.0.1:9000.
    #[arg(long, value_name = "ADDR")]
    pub udp: Option<String>,
    /// The rig: a file, or builtin:default or builtin:paper (default: the rig the table
    /// names, else builtin:default).
    #[arg(long, value_name = "RIG")]
    pub rig: Option<PathBuf>,
    /// The AU table mapping AUs to activations: a file or builtin:default (the default).
    #[arg(long, value_name = "TABLE")]
    pub table: Option<PathBuf>,
    /// Intensities are already on a 0-1 scale (default: OpenFace's 0-5).
    #[arg(long)]
    pub scale: bool,
    /// The face to play in an OpenFace recording of several (its `face_id`); default: the
    /// face of the first tracked row.
    #[arg(long, value_name = "ID")]
    pub face: Option<u32>,
    /// Stop at the first malformed row instead of skipping it.
    #[arg(long)]
    pub strict: bool,
    /// Draw nothing: print one line per frame and a final count.
    #[arg(long)]
    pub headless: bool,
    /// With --headless, keep the source's pace (at --speed) instead of running as fast as
    /// possible.
    #[arg(long, requires = "headless")]
    pub realtime: bool,
    /// Playback speed (1 = the source's frame rate; 1/16 to 16).
    #[arg(long, default_value_t = 1.0, value_name = "X")]
    pub speed: f64,
    /// Start again at the end of a file or timeline.
    #[arg(long = "loop")]
    pub repeat: bool,
    /// Frame rate for rows without timestamps (default 30).
    #[arg(long, value_name = "FPS")]
    pub fps: Option<f64>,
    /// Stop after this many frames played.
    #[arg(long, value_name = "N")]
    pub frames: Option<usize>,
    /// End a live stream after this many seconds without data.
    #[arg(long, value_name = "SECS")]
    pub idle_timeout: Option<f64>,
    /// Report frames shown, dropped and late at the end (on stderr).
    #[arg(long)]
    pub stats: bool,
    /// Braille, half-block or ASCII cells.
    #[command(flatten)]
    pub cells: super::CellsArgs,
}

/// Runs `grimace play`, returning the first error (named with file, line and column).
pub fn run(args: &PlayArgs) -> Result<()> {
    check_args(args)?;
    let (face, table) = load_face(args)?;
    let mapper = AuMapper::new(&table, &face.rig);
    let source = open_source(args, &face.rig, &table, &mapper)?;
    if args.headless {
        let stdout = io::stdout();
        let mut out = BufWriter::new(stdout.lock());
        let summary = play_headless(args, source, &face.rig, &table, &mapper, &mut out)?;
        if args.stats {
            eprintln!("{}", summary.stats.summary());
        }
        return Ok(());
    }
    if !io::stdout().is_terminal() {
        bail!("stdout is not a terminal: use --headless to print frames instead of drawing");
    }
    let framing = super::framing(&face, None);
    let summary = view(args, source, face.mesh, framing, &face.rig, &table, &mapper)?;
    println!(
        "played {} frames, skipped {}",
        summary.played, summary.skipped
    );
    if args.stats {
        eprintln!("{}", summary.stats.summary());
    }
    Ok(())
}

fn check_args(args: &PlayArgs) -> Result<()> {
    if !(args.speed.is_finite() && args.speed > 0.0) {
        bail!("--speed must be a positive number (got {})", args.speed);
    }
    if let Some(fps) = args.fps {
        if !(fps.is_finite() && fps > 0.0 && fps <= 1000.0) {
            bail!("--fps must be between 0 and 1000 (got {fps})");
        }
    }
    if let Some(secs) = args.idle_timeout {
        if !(0.0..=1e6).contains(&secs) {
            bail!("--idle-timeout must be a number of seconds (got {secs})");
        }
    }
    Ok(())
}

/// The rig with its mesh, and the table checked against the rig.
///
/// The rig is `--rig` (a file or `builtin:NAME`), else the rig the `--table` names, else the
/// built-in default rig. The table is `--table` (a file or `builtin:NAME`), else the built-in
/// default table.
fn load_face(args: &PlayArgs) -> Result<(LoadedRig, AuTable)> {
    let sources = export::load_sources(&SourceArgs {
        rig: args.rig.clone(),
        mesh: None,
        table: args.table.clone(),
    })?;
    let table = match sources.table {
        Some(table) => table,
        // A rig alone plays through the built-in table, which a custom rig may not fit.
        None => load_table_ref_for(Path::new(export::DEFAULT_TABLE), &sources.rig.rig)
            .context("the built-in AU table does not fit this rig; give --table")?,
    };
    Ok((sources.rig, table))
}

fn is_timeline(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("ron"))
}

/// Opens the input the arguments name.
fn open_source(
    args: &PlayArgs,
    rig: &Rig,
    table: &AuTable,
    mapper: &AuMapper,
) -> Result<Box<dyn FrameSource>> {
    let scale = if args.scale {
        IntensityScale::ZeroToOne
    } else {
        IntensityScale::ZeroToFive
    };
    if let Some(path) = &args.file {
        if is_timeline(path) {
            let timeline = load_timeline(path)?;
            return Ok(Box::new(TimelineSource::new(timeline, path, table, rig)?));
        }
        let options = RecordingOptions {
            mapper: mapper.clone(),
            scale,
            fps: args.fps,
            muscles: rig.muscles.iter().map(|m| m.name.clone()).collect(),
            face: args.face,
        };
        return Ok(open_file(path, &options)?);
    }
    if let Some(address) = &args.udp {
        let (source, bound) = LiveSource::udp(address, mapper.clone(), scale)?;
        // Scripts that asked for port 0 learn the port here.
        eprintln!("listening on udp {bound}");
        return Ok(Box::new(source));
    }
    Ok(Box::new(
        LiveSource::stdin(mapper.clone(), scale, args.fps).follow_face(args.face),
    ))
}

/// Plays in the terminal view (see [`crate::tui::play`]); `--loop` reopens the input.
fn view(
    args: &PlayArgs,
    source: Box<dyn FrameSource>,
    mesh: Mesh,
    framing: crate::render::Framing,
    rig: &Rig,
    table: &AuTable,
    mapper: &AuMapper,
) -> Result<Summary> {
    let reopen = {
        let (args, rig, table, mapper) = (args.clone(), rig.clone(), table.clone(), mapper.clone());
        Box::new(move || {
            open_source(&args, &rig, &table, &mapper).map_err(|e| SourceError::Io {
                what: "cannot reopen the input".into(),
                source: io::Error::other(format!("{e:#}")),
            })
        }) as Reopen
    };
    let reopen = args.repeat.then_some(reopen);
    let mut player = Player::new(source, reopen, args.speed, args.strict, args.frames);
    let cells = args.cells.mode();
    crate::tui::play::run(&mut player, mesh, framing, rig, cells, args.frames)?;
    Ok(Summary {
        played: player.played,
        skipped: player.skipped,
        stats: player.stats,
    })
}

/// What a run did.
#[derive(Debug, Clone, Default)]
pub struct Summary {
    /// Frames played.
    pub played: usize,
    /// Rows skipped: untracked (`success` 0) and malformed.
    pub skipped: usize,
    /// Timing of the frames shown.
    pub stats: FrameStats,
}

/// How long a live poll waits when no idle timeout is set (then it simply polls again).
const LIVE_WAIT: Duration = Duration::from_secs(3600);

/// Plays without drawing: one line per frame on `out`, warnings and malformed rows on stderr.
fn play_headless(
    args: &PlayArgs,
    mut source: Box<dyn FrameSource>,
    rig: &Rig,
    table: &AuTable,
    mapper: &AuMapper,
    out: &mut impl Write,
) -> Result<Summary> {
    let mut summary = Summary::default();
    let mut skips = Skips::default();
    let live = source.is_live();
    let wait = args.idle_timeout.map_or(LIVE_WAIT, Duration::from_secs_f64);
    let mut clock: Option<PlayClock> = None;
    loop {
        if args.frames.is_some_and(|n| summary.played >= n) {
            break;
        }
        match source.poll(wait)? {
            Poll::Event(Event::Frame(frame)) => {
                if args.realtime && !live {
                    wait_until_due(&mut clock, frame.time, args.speed, &mut summary);
                }
                // Live and real-time frames go out when they are due, not at the end.
                let written = writeln!(out, "{}", frame_line(&frame, rig)).and_then(|()| {
                    if live || args.realtime {
                        out.flush()
                    } else {
                        Ok(())
                    }
                });
                if quiet_on_broken_pipe(written)? {
                    return Ok(summary);
                }
                summary.played += 1;
            }
            Poll::Event(Event::Untracked { .. }) => {
                skips.untracked();
                summary.skipped += 1;
            }
            Poll::Event(Event::Malformed { message }) => {
                if args.strict {
                    bail!("{message}");
                }
                if let Some(line) = skips.malformed(&message) {
                    eprintln!("{line}");
                }
                summary.skipped += 1;
            }
            Poll::Event(Event::Notice(notice)) => eprintln!("warning: {notice}"),
            Poll::Pending => {
                if args.idle_timeout.is_some() {
                    break;
                }
            }
            Poll::End => {
                if args.repeat && !live && summary.played > 0 {
                    source = open_source(args, rig, table, mapper)?;
                    clock = None;
                    continue;
                }
                break;
            }
        }
    }
    if let Some(line) = skips.summary() {
        eprintln!("{line}");
    }
    let written = writeln!(
        out,
        "played {} frames, skipped {}",
        summary.played, summary.skipped
    )
    .and_then(|()| out.flush());
    quiet_on_broken_pipe(written)?;
    Ok(summary)
}

/// Sleeps until a file's frame at `time` is due under `--realtime` (the clock starts at the
/// first frame), and counts how late it went out.
fn wait_until_due(clock: &mut Option<PlayClock>, time: f64, speed: f64, summary: &mut Summary) {
    let clock = clock.get_or_insert_with(|| PlayClock::new(time, speed, Instant::now()));
    if let Some(due) = clock.due(time) {
        std::thread::sleep(due.saturating_duration_since(Instant::now()));
        let lateness = Instant::now().saturating_duration_since(due);
        summary.stats.shown(lateness, Duration::ZERO);
    }
}

/// `true` when the reader of our output went away (then we stop quietly, like other tools).
fn quiet_on_broken_pipe(result: io::Result<()>) -> Result<bool> {
    match result {
        Ok(()) => Ok(false),
        Err(e) if e.kind() == io::ErrorKind::BrokenPipe => Ok(true),
        Err(e) => Err(e).context("cannot write to stdout"),
    }
}

/// `TIME AU1=2.10 AU12=0.80 | muscle=0.42 jaw=0.10`: the frame's time, its non-zero AUs as
/// given, and its non-zero activations (`rest` when none).
pub fn frame_line(frame: &Frame, rig: &Rig) -> String {
    let mut line = format!("{:.3}", frame.time);
    // Values that print as 0.00 are left out with the zeros.
    let shows = |v: f32| v.abs() >= 0.005;
    for au in frame.aus.iter().filter(|a| shows(a.value)) {
        line.push_str(&format!(" AU{}={:.2}", au.key, au.value));
    }
    line.push_str(" |");
    let mut any = false;
    for (muscle, value) in rig.muscles.iter().zip(&frame.activations.muscles) {
        if shows(*value) {
            line.push_str(&format!(" {}={value:.2}", muscle.name));
            any = true;
        }
    }
    if shows(frame.activations.jaw) {
        line.push_str(&format!(" jaw={:.2}", frame.activations.jaw));
        any = true;
    }
    if !any {
        line.push_str(" rest");
    }
    line
}
