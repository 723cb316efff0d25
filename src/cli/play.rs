//! `grimace play`: animate the face from an OpenFace CSV, a timeline, or a live AU stream.
//!
//! Headless (`--headless`) prints one line per frame played and a final count, as fast as it
//! can unless `--realtime` asks it to keep the source's pace; otherwise a full-screen terminal
//! view plays at the source's frame rate, dropping frames it cannot show in time.

use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::{Duration, Instant};

use anyhow::{bail, Context, Result};
use clap::Args;

use crate::facs::AuTable;
use crate::io::parse_rig;
use crate::io::table_file::load_table_for;
use crate::io::timeline::load_timeline;
use crate::model::Rig;
use crate::play::source::DEFAULT_FRAME_RATE;
use crate::play::{
    AuMapper, Event, Frame, FrameSource, FrameStats, IntensityScale, LiveSource, OpenFaceSource,
    PlayClock, Poll, TimelineSource,
};

/// Arguments of `grimace play`.
#[derive(Debug, Clone, Args)]
#[command(after_help = "\
INPUT:
  FILE.csv            OpenFace 2.0 output (AUxx_r intensities 0-5; rows with success 0 skipped)
  FILE.timeline.ron   keyframes of AU combinations or activations (see docs on timelines)
  --stdin             one frame per line: a CSV header line then rows, or JSON objects
                      {\"AU1\": 0.0, ..., \"AU45\": 0.0}
  --udp 127.0.0.1:PORT  JSON objects, one per datagram, on a loopback port (0 picks one)

HEADLESS OUTPUT:
  one line per frame: `TIME AU1=2.10 AU12=0.80 | muscle=0.42 jaw=0.10` (AUs and activations
  that are not zero; `rest` when none), then `played N frames, skipped M`. Skipped rows
  (success 0, malformed) count in M; each malformed row is named by line on stderr.

KEYS (terminal view):
  space pause/resume   . or n  step one frame (pauses)   + / -  speed x2 / /2   q  quit")]
pub struct PlayArgs {
    /// An OpenFace CSV file or a `*.timeline.ron` file.
    #[arg(value_name = "FILE", required_unless_present_any = ["stdin", "udp"], conflicts_with_all = ["stdin", "udp"])]
    pub file: Option<PathBuf>,
    /// Read frames from stdin (CSV with a header line, or one JSON object per line).
    #[arg(long, conflicts_with = "udp")]
    pub stdin: bool,
    /// Listen for JSON frames on a loopback UDP address, e.g. 127.0.0.1:9000.
    #[arg(long, value_name = "ADDR")]
    pub udp: Option<String>,
    /// The rig (default: the built-in default face).
    #[arg(long, value_name = "RIG")]
    pub rig: Option<PathBuf>,
    /// The AU table mapping AUs to activations (default: the built-in table).
    #[arg(long, value_name = "TABLE")]
    pub table: Option<PathBuf>,
    /// Intensities are already on a 0-1 scale (default: OpenFace's 0-5).
    #[arg(long)]
    pub scale: bool,
    /// Stop at the first malformed row instead of skipping it.
    #[arg(long)]
    pub strict: bool,
    /// Draw nothing: print one line per frame and a final count.
    #[arg(long)]
    pub headless: bool,
    /// With --headless, keep the source's pace instead of running as fast as possible.
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
}

/// Runs `grimace play`: 0 when the input was played, 1 on an error (named on stderr).
pub fn main(args: &PlayArgs) -> ExitCode {
    match run(args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(err) => {
            eprintln!("grimace play: {err:#}");
            ExitCode::from(1)
        }
    }
}

/// Runs `grimace play`, returning the first error.
pub fn run(args: &PlayArgs) -> Result<()> {
    check_args(args)?;
    let (rig, table) = load_face(args)?;
    let mapper = AuMapper::new(&table, &rig);
    let source = open_source(args, &rig, &table, &mapper)?;
    if args.headless {
        let stdout = io::stdout();
        let mut out = BufWriter::new(stdout.lock());
        let summary = play_headless(args, source, &rig, &table, &mapper, &mut out)?;
        if args.stats {
            eprintln!("{}", summary.stats.summary());
        }
        Ok(())
    } else {
        bail!("the terminal view is not available yet; use --headless")
    }
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

/// The rig and table: from files when given, else the built-in default face. Headless play
/// needs no mesh, so a rig file is only parsed then; the table is checked against the rig.
fn load_face(args: &PlayArgs) -> Result<(Rig, AuTable)> {
    let rig = match &args.rig {
        Some(path) => {
            let text = std::fs::read_to_string(path)
                .with_context(|| format!("cannot read rig {}", path.display()))?;
            parse_rig(&text, path)?
        }
        None => bail!("no --rig given and this build has no built-in face yet"),
    };
    let table = match &args.table {
        Some(path) => load_table_for(path, &rig)?,
        None => bail!("no --table given and this build has no built-in AU table yet"),
    };
    Ok((rig, table))
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
    let fps = args.fps.unwrap_or(DEFAULT_FRAME_RATE);
    if let Some(path) = &args.file {
        if is_timeline(path) {
            let timeline = load_timeline(path)?;
            return Ok(Box::new(TimelineSource::new(timeline, path, table, rig)?));
        }
        return Ok(Box::new(OpenFaceSource::open(
            path,
            mapper.clone(),
            scale,
            fps,
        )?));
    }
    if let Some(address) = &args.udp {
        let (source, bound) = LiveSource::udp(address, mapper.clone(), scale)?;
        // Scripts that asked for port 0 learn the port here.
        eprintln!("listening on udp {bound}");
        return Ok(Box::new(source));
    }
    Ok(Box::new(LiveSource::stdin(mapper.clone(), scale, fps)))
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
                    let clock = clock.get_or_insert_with(|| {
                        PlayClock::new(frame.time, args.speed, Instant::now())
                    });
                    if let Some(due) = clock.due(frame.time) {
                        std::thread::sleep(due.saturating_duration_since(Instant::now()));
                        let lateness = Instant::now().saturating_duration_since(due);
                        summary.stats.shown(lateness, Duration::ZERO);
                    }
                }
                let written = writeln!(out, "{}", frame_line(&frame, rig)).and_then(|()| {
                    if live {
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
            Poll::Event(Event::Untracked { .. }) => summary.skipped += 1,
            Poll::Event(Event::Malformed { message }) => {
                if args.strict {
                    bail!("{message}");
                }
                eprintln!("{message} (row skipped)");
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
    let written = writeln!(
        out,
        "played {} frames, skipped {}",
        summary.played, summary.skipped
    )
    .and_then(|()| out.flush());
    quiet_on_broken_pipe(written)?;
    Ok(summary)
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
    for au in frame.aus.iter().filter(|a| a.value != 0.0) {
        line.push_str(&format!(" AU{}={:.2}", au.key, au.value));
    }
    line.push_str(" |");
    let mut any = false;
    for (muscle, value) in rig.muscles.iter().zip(&frame.activations.muscles) {
        if *value != 0.0 {
            line.push_str(&format!(" {}={value:.2}", muscle.name));
            any = true;
        }
    }
    if frame.activations.jaw != 0.0 {
        line.push_str(&format!(" jaw={:.2}", frame.activations.jaw));
        any = true;
    }
    if !any {
        line.push_str(" rest");
    }
    line
}
