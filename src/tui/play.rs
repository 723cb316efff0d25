//! `grimace play`'s full-screen view, on the editor's terminal code: the same raw mode,
//! alternate screen and restore on every exit ([`term`]), the same signals and hangup check,
//! the same colour detection, the face drawn by the same widget ([`CellGridView`]) and the
//! keys in the key table ([`keymap::PLAY_BINDINGS`]).
//!
//! It plays at the source's frame rate, dropping frames it cannot show in time.

use std::io;
use std::time::{Duration, Instant};

use anyhow::{Context, Result};
use crossterm::event::{self, Event as TermEvent, KeyEventKind};
use ratatui::backend::CrosstermBackend;
use ratatui::buffer::Buffer;
use ratatui::layout::{Constraint, Layout, Rect};
use ratatui::style::{Modifier, Style as TextStyle};
use ratatui::text::{Line, Span};
use ratatui::widgets::{Block, Borders, Paragraph, Widget};
use ratatui::{Frame as TermFrame, Terminal};

use super::keymap::{self, PlayKey};
use super::term::{self, Signals};
use super::view::cells::CellGridView;
use super::view::theme::Theme;
use crate::model::deform::BoundRig;
use crate::model::{Activations, Mesh, Rig};
use crate::play::player::PlayState;
use crate::play::skips::Skips;
use crate::play::{Frame, Message, Player};
use crate::render::{
    Camera, CellGrid, CellMode, ColorMode, DotCanvas, Framing, Renderer, Scene, Style,
};

/// The shortest time between two drawn frames: the view shows at most about 64 frames a
/// second (a little above 60, so a 60 fps source is not thinned by timer jitter).
const MIN_FRAME_INTERVAL: Duration = Duration::from_micros(15_625);

/// What the view draws from.
struct Face {
    mesh: Mesh,
    bound: BoundRig,
    framing: Framing,
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
        let mut scene = Scene::new(&self.mesh, &self.positions)
            .with_rest(self.bound.rest())
            .with_framing(&self.framing);
        // Lines coloured by how far they moved make the motion readable at a glance.
        scene.displacement = self.colors != ColorMode::None;
        let camera = Camera::front().with_basis(self.framing.basis);
        self.renderer
            .render(&scene, &camera, Style::Lines, &mut self.canvas);
        self.grid.fill(&self.canvas, self.mode, self.colors);
        CellGridView {
            grid: &self.grid,
            colors: self.colors,
            plain: Theme::new(self.colors).face(),
        }
        .render(area, buffer);
    }
}

/// Where playback stands, as the status line says it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Playback {
    /// Frames show as they come due.
    Playing,
    /// Stopped on the current frame until resumed or stepped.
    Paused,
    /// Nothing more to show (the source ended or the frame limit was reached).
    Ended,
}

impl Playback {
    fn of(player: &Player, ended: bool) -> Playback {
        if ended {
            Playback::Ended
        } else if player.is_paused() {
            Playback::Paused
        } else {
            Playback::Playing
        }
    }

    fn name(self) -> &'static str {
        match self {
            Playback::Playing => "playing",
            Playback::Paused => "paused",
            Playback::Ended => "end",
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
    playback: Playback,
}

/// Plays in the terminal until `q`, a signal, or `frames` frames; the counts stay in
/// `player`. Skipped rows are named and counted on stderr once the terminal is restored.
pub fn run(
    player: &mut Player,
    mesh: Mesh,
    rig: &Rig,
    cells: CellMode,
    frames: Option<usize>,
) -> Result<()> {
    let bound = crate::model::Deformation::default()
        .bind(rig, &mesh)
        .context("cannot place the rig on its mesh")?;
    let rest = bound.rest().to_vec();
    let mut face = Face {
        framing: Framing::of_rig(rig, &mesh),
        renderer: Renderer::new(&mesh),
        mesh,
        bound,
        positions: rest,
        canvas: DotCanvas::new(0, 0),
        grid: CellGrid::default(),
        mode: cells,
        colors: term::colors_from_env(),
    };
    let signals = Signals::register().context("cannot watch for termination signals")?;
    let guard = term::enter().context("cannot open the terminal")?;
    let mut terminal =
        Terminal::new(CrosstermBackend::new(io::stdout())).context("cannot open the terminal")?;
    let mut status = Status {
        current: None,
        messages: Vec::new(),
        skips: Skips::default(),
        named: Vec::new(),
        playback: Playback::Playing,
    };
    let result = run_loop(
        &mut terminal,
        player,
        &mut face,
        &mut status,
        rig,
        &signals,
        frames,
    );
    drop(terminal);
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
    result
}

fn run_loop(
    terminal: &mut Terminal<CrosstermBackend<io::Stdout>>,
    player: &mut Player,
    face: &mut Face,
    status: &mut Status,
    rig: &Rig,
    signals: &Signals,
    frames: Option<usize>,
) -> Result<()> {
    let mut redraw = true;
    let mut due: Option<Instant> = None;
    let mut last_shown_due: Option<Instant> = None;
    let mut ended = false;
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
        if player.is_finished() && !ended {
            ended = true;
            redraw = true;
            if frames.is_some_and(|n| player.played >= n) {
                return Ok(());
            }
        }
        status.playback = Playback::of(player, ended);
        if redraw {
            let started = Instant::now();
            term::begin_frame(terminal.backend_mut()).context("cannot draw")?;
            terminal
                .draw(|f| draw(f, face, status, player, rig))
                .context("cannot draw")?;
            term::end_frame(terminal.backend_mut()).context("cannot draw")?;
            let done = Instant::now();
            redraw = false;
            if let Some(when) = due.take() {
                player.shown(when, done, done - started);
                // Spaced by due times, so a frame drawn late does not delay the next.
                last_shown_due = Some(when);
                // The status line was drawn before this frame counted as shown; after
                // the last frame nothing else redraws, so show the final counts.
                redraw = ended;
            }
        }
        let now = Instant::now();
        let display_free = last_shown_due.map_or(now, |t| t + MIN_FRAME_INTERVAL);
        let wait = match player.next_due() {
            Some(when) => when.max(display_free).saturating_duration_since(now),
            None if player.is_live() && player.state() == PlayState::Playing => {
                Duration::from_millis(4)
            }
            None => Duration::from_millis(250),
        };
        if !event::poll(wait).context("cannot read the keyboard")? {
            continue;
        }
        match event::read().context("cannot read the keyboard")? {
            TermEvent::Key(key) if key.kind != KeyEventKind::Release => {
                let now = Instant::now();
                match keymap::play_dispatch(key) {
                    Some(PlayKey::Quit) => return Ok(()),
                    Some(PlayKey::Pause) => player.toggle_pause(now),
                    Some(PlayKey::Step) => {
                        if let Some(frame) = player.step(now)? {
                            status.current = Some(frame);
                        }
                    }
                    Some(PlayKey::Faster) => player.change_speed(2.0, now),
                    Some(PlayKey::Slower) => player.change_speed(0.5, now),
                    None => continue,
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
    let time = status
        .current
        .as_ref()
        .map_or("-".to_string(), |c| format!("{:.3} s", c.time));
    let stats = &player.stats;
    let first = Line::from(vec![
        Span::styled(
            format!(" {} ", status.playback.name()),
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
    let keys = Line::from(format!(" {}", keymap::play_hints()));
    let message = Line::from(status.messages.last().cloned().unwrap_or_default());
    Paragraph::new(vec![first, message, keys])
}
