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
use crate::io::rig_file::LoadedRig;
use crate::io::table_file::load_table_ref_for;
use crate::io::timeline::load_timeline;
use crate::model::Rig;
use crate::play::skips::Skips;
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
  FILE.timeline.ron   keyframes of AU combinations or activations (see docs/formats.md)
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
    let (LoadedRig { rig, mesh, .. }, table) = load_face(args)?;
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
        if !io::stdout().is_terminal() {
            bail!("stdout is not a terminal: use --headless to print frames instead of drawing");
        }
        let summary = view::play(args, source, mesh, &rig, &table, &mapper)?;
        println!(
            "played {} frames, skipped {}",
            summary.played, summary.skipped
        );
        if args.stats {
            eprintln!("{}", summary.stats.summary());
        }
        Ok(())
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
                    let clock = clock.get_or_insert_with(|| {
                        PlayClock::new(frame.time, args.speed, Instant::now())
                    });
                    if let Some(due) = clock.due(frame.time) {
                        std::thread::sleep(due.saturating_duration_since(Instant::now()));
                        let lateness = Instant::now().saturating_duration_since(due);
                        summary.stats.shown(lateness, Duration::ZERO);
                    }
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

/// The full-screen terminal view.
mod view {
    use crate::tui::term::Signals;
    use std::io;
    use std::time::{Duration, Instant};

    use anyhow::{Context, Result};
    use crossterm::event::{self, Event as TermEvent, KeyCode, KeyEventKind, KeyModifiers};
    use ratatui::buffer::Buffer;
    use ratatui::layout::{Constraint, Layout, Rect};
    use ratatui::style::{Color, Modifier, Style as TextStyle};
    use ratatui::text::{Line, Span};
    use ratatui::widgets::{Block, Borders, Paragraph};
    use ratatui::Frame as TermFrame;

    use super::{PlayArgs, Summary};
    use crate::facs::AuTable;
    use crate::model::deform::BoundRig;
    use crate::model::{Activations, Mesh, Rig};
    use crate::play::skips::Skips;
    use crate::play::{AuMapper, Frame, FrameSource, Message, Player};
    use crate::render::{
        Camera, CellGrid, CellMode, ColorMode, DotCanvas, Renderer, Rgb, Scene, Style,
    };

    /// The shortest time between two drawn frames: the view shows at most about 64 frames a
    /// second (a little above 60, so a 60 fps source is not thinned by timer jitter).
    const MIN_FRAME_INTERVAL: Duration = Duration::from_micros(15_625);

    /// Restores the terminal however the view ends (return, error or panic unwinding).
    struct TerminalGuard;

    impl Drop for TerminalGuard {
        fn drop(&mut self) {
            ratatui::restore();
            let _ = crossterm::execute!(io::stdout(), crossterm::cursor::Show);
        }
    }

    /// What the view draws from.
    struct Face {
        mesh: Mesh,
        bound: BoundRig,
        renderer: Renderer,
        positions: Vec<glam::Vec3>,
        canvas: DotCanvas,
        grid: CellGrid,
        mode: CellMode,
        colors: ColorMode,
    }

    impl Face {
        /// Deforms the mesh to `act` and renders it into `area` of `buffer`.
        fn draw(&mut self, act: &Activations, area: Rect, buffer: &mut Buffer) {
            if self.bound.deform(act, &mut self.positions).is_err() {
                // Mapped activations are clamped to range; a failure leaves the last pose.
                return;
            }
            let (cols, rows) = (usize::from(area.width), usize::from(area.height));
            self.mode.prepare(&mut self.canvas, cols, rows);
            let mut scene = Scene::new(&self.mesh, &self.positions).with_rest(self.bound.rest());
            // Lines coloured by how far they moved make the motion readable at a glance.
            scene.displacement = self.colors != ColorMode::None;
            self.renderer
                .render(&scene, &Camera::front(), Style::Lines, &mut self.canvas);
            self.grid.fill(&self.canvas, self.mode, self.colors);
            for row in 0..self.grid.height.min(rows) {
                for (col, cell) in self.grid.row(row).iter().enumerate().take(cols) {
                    let x = area.x + col as u16;
                    let y = area.y + row as u16;
                    if let Some(target) = buffer.cell_mut((x, y)) {
                        target.set_char(cell.ch);
                        if let Some(Rgb(r, g, b)) = cell.fg {
                            target.set_fg(Color::Rgb(r, g, b));
                        }
                        if let Some(Rgb(r, g, b)) = cell.bg {
                            target.set_bg(Color::Rgb(r, g, b));
                        }
                    }
                }
            }
        }
    }

    /// What the status lines show.
    struct Status {
        current: Option<Frame>,
        messages: Vec<String>,
        /// Malformed rows, counted; the first few named, printed on stderr at the end.
        skips: Skips,
        named: Vec<String>,
        ended: bool,
    }

    /// Plays in the terminal until `q` (or the frame limit); returns the counts.
    pub fn play(
        args: &PlayArgs,
        source: Box<dyn FrameSource>,
        mesh: Mesh,
        rig: &Rig,
        table: &AuTable,
        mapper: &AuMapper,
    ) -> Result<Summary> {
        let bound = BoundRig::bind(rig, &mesh).context("cannot place the rig on its mesh")?;
        let rest = bound.rest().to_vec();
        let mut face = Face {
            renderer: Renderer::new(&mesh),
            mesh,
            bound,
            positions: rest,
            canvas: DotCanvas::new(0, 0),
            grid: CellGrid::default(),
            mode: args.cells.mode(),
            colors: if std::env::var_os("NO_COLOR").is_some_and(|v| !v.is_empty()) {
                ColorMode::None
            } else {
                ColorMode::Ansi16
            },
        };
        let reopen = {
            let (args, rig, table, mapper) =
                (args.clone(), rig.clone(), table.clone(), mapper.clone());
            Box::new(move || {
                super::open_source(&args, &rig, &table, &mapper).map_err(|e| {
                    crate::play::SourceError::Io {
                        what: "cannot reopen the input".into(),
                        source: io::Error::other(format!("{e:#}")),
                    }
                })
            }) as crate::play::player::Reopen
        };
        let reopen = args.repeat.then_some(reopen);
        let mut player = Player::new(source, reopen, args.speed, args.strict, args.frames);

        let signals = Signals::register().context("cannot watch for termination signals")?;
        let guard = TerminalGuard;
        let mut terminal = ratatui::try_init().context("cannot open the terminal")?;
        let mut status = Status {
            current: None,
            messages: Vec::new(),
            skips: Skips::default(),
            named: Vec::new(),
            ended: false,
        };
        let result = run_loop(
            &mut terminal,
            &mut player,
            &mut face,
            &mut status,
            rig,
            &signals,
            args,
        );
        drop(guard);
        for line in &status.named {
            eprintln!("{line}");
        }
        // The player counts every skipped row; those not malformed were untracked.
        for _ in status.skips.total()..player.skipped {
            status.skips.untracked();
        }
        if let Some(line) = status.skips.summary() {
            eprintln!("{line}");
        }
        result?;
        Ok(Summary {
            played: player.played,
            skipped: player.skipped,
            stats: player.stats,
        })
    }

    #[allow(clippy::too_many_arguments)]
    fn run_loop(
        terminal: &mut ratatui::DefaultTerminal,
        player: &mut Player,
        face: &mut Face,
        status: &mut Status,
        rig: &Rig,
        signals: &Signals,
        args: &PlayArgs,
    ) -> Result<()> {
        let mut redraw = true;
        let mut due: Option<Instant> = None;
        let mut last_shown_due: Option<Instant> = None;
        loop {
            // SIGHUP, SIGTERM, or a terminal that vanished without a signal.
            if signals.pending().is_some() {
                return Ok(());
            }
            // Faster sources than the display rate: frames due in between are dropped.
            let now = Instant::now();
            let display_ready = last_shown_due.is_none_or(|t| now >= t + MIN_FRAME_INTERVAL);
            if display_ready {
                if let Some((frame, when)) = player.tick(now)? {
                    status.current = Some(frame);
                    due = Some(when);
                    redraw = true;
                }
            }
            collect(player, status);
            if player.is_finished() && !status.ended {
                status.ended = true;
                redraw = true;
                if args.frames.is_some_and(|n| player.played >= n) {
                    return Ok(());
                }
            }
            if redraw {
                let started = Instant::now();
                terminal
                    .draw(|f| draw(f, face, status, player, rig))
                    .context("cannot draw")?;
                let done = Instant::now();
                redraw = false;
                if let Some(when) = due.take() {
                    player.shown(when, done, done - started);
                    // Spaced by due times, so a frame drawn late does not delay the next.
                    last_shown_due = Some(when);
                    // The status line was drawn before this frame counted as shown; after
                    // the last frame nothing else redraws, so show the final counts.
                    redraw = status.ended;
                }
            }
            let now = Instant::now();
            let display_free = last_shown_due.map_or(now, |t| t + MIN_FRAME_INTERVAL);
            let wait = match player.next_due() {
                Some(when) => when.max(display_free).saturating_duration_since(now),
                None if player.is_live() && !player.is_paused() => Duration::from_millis(4),
                None => Duration::from_millis(250),
            };
            if !event::poll(wait).context("cannot read the keyboard")? {
                continue;
            }
            match event::read().context("cannot read the keyboard")? {
                TermEvent::Key(key) if key.kind != KeyEventKind::Release => {
                    let now = Instant::now();
                    match key.code {
                        KeyCode::Char('q') | KeyCode::Esc => return Ok(()),
                        KeyCode::Char('c') if key.modifiers.contains(KeyModifiers::CONTROL) => {
                            return Ok(())
                        }
                        KeyCode::Char(' ') => player.toggle_pause(now),
                        KeyCode::Char('.' | 'n') | KeyCode::Right => {
                            if let Some(frame) = player.step(now)? {
                                status.current = Some(frame);
                            }
                        }
                        KeyCode::Char('+' | '=') | KeyCode::Up => player.change_speed(2.0, now),
                        KeyCode::Char('-' | '_') | KeyCode::Down => player.change_speed(0.5, now),
                        _ => continue,
                    }
                    redraw = true;
                }
                TermEvent::Resize(..) => redraw = true,
                _ => {}
            }
        }
    }

    /// Moves the player's messages into the status (malformed rows are kept for stderr).
    fn collect(player: &mut Player, status: &mut Status) {
        for message in player.take_messages() {
            let text = match message {
                Message::Notice(text) => format!("warning: {text}"),
                Message::Malformed(text) => {
                    if let Some(line) = status.skips.malformed(&text) {
                        status.named.push(line);
                    }
                    format!("{text} (row skipped)")
                }
            };
            status.messages.push(text);
        }
        let excess = status.messages.len().saturating_sub(2);
        status.messages.drain(..excess);
    }

    fn draw(f: &mut TermFrame, face: &mut Face, status: &Status, player: &Player, rig: &Rig) {
        let [main, bottom] =
            Layout::vertical([Constraint::Min(3), Constraint::Length(3)]).areas(f.area());
        let side_width = if main.width >= 70 { 30 } else { 0 };
        let [viewport, side] =
            Layout::horizontal([Constraint::Min(10), Constraint::Length(side_width)]).areas(main);
        let rest = Activations::zero(rig);
        let act = status.current.as_ref().map_or(&rest, |c| &c.activations);
        face.draw(act, viewport, f.buffer_mut());
        if side_width > 0 {
            f.render_widget(side_panel(status, rig), side);
        }
        f.render_widget(status_lines(status, player), bottom);
    }

    fn side_panel<'a>(status: &'a Status, rig: &'a Rig) -> Paragraph<'a> {
        let mut lines = Vec::new();
        let bar = |value: f32, full: f32| {
            let n = ((value / full).clamp(0.0, 1.0) * 10.0).round() as usize;
            format!("{}{}", "#".repeat(n), ".".repeat(10 - n))
        };
        if let Some(frame) = &status.current {
            for au in frame.aus.iter().filter(|a| a.value >= 0.005) {
                lines.push(Line::from(format!(
                    "AU{:<4}{:5.2} {}",
                    au.key.to_string(),
                    au.value,
                    bar(au.factor, 1.0)
                )));
            }
            if !frame.aus.is_empty() {
                lines.push(Line::from(""));
            }
            for (muscle, value) in rig.muscles.iter().zip(&frame.activations.muscles) {
                if *value >= 0.005 {
                    let name: String = muscle.name.chars().take(13).collect();
                    lines.push(Line::from(format!(
                        "{name:<13} {value:4.2} {}",
                        bar(*value, 2.0)
                    )));
                }
            }
            if frame.activations.jaw >= 0.005 {
                let jaw = frame.activations.jaw;
                lines.push(Line::from(format!(
                    "{:<13} {jaw:4.2} {}",
                    "jaw",
                    bar(jaw, 4.0)
                )));
            }
        }
        Paragraph::new(lines).block(Block::default().borders(Borders::LEFT).title(" AUs "))
    }

    fn status_lines<'a>(status: &'a Status, player: &'a Player) -> Paragraph<'a> {
        let state = if status.ended {
            "end"
        } else if player.is_paused() {
            "paused"
        } else {
            "playing"
        };
        let time = status
            .current
            .as_ref()
            .map_or("-".to_string(), |c| format!("{:.3} s", c.time));
        let stats = &player.stats;
        let first = Line::from(vec![
            Span::styled(
                format!(" {state} "),
                TextStyle::default().add_modifier(Modifier::REVERSED),
            ),
            Span::raw(format!(
                " {time}  x{:.2}  frames {}  shown {}  dropped {}  late {}  skipped {}",
                player.speed(),
                player.played,
                stats.shown,
                stats.dropped,
                stats.late,
                player.skipped
            )),
        ]);
        let keys = Line::from(" space pause   . or n step   + - speed   q quit");
        let message = Line::from(status.messages.last().cloned().unwrap_or_default());
        Paragraph::new(vec![first, message, keys])
    }
}
