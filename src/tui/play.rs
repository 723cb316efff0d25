//! `grimace play`'s full-screen view, on the editor's terminal code: the same raw mode,
//! alternate screen and restore on every exit ([`term`]), the same signals and hangup check,
//! the same colour detection, the face drawn by the same widget ([`CellGridView`]) and the
//! keys in the key table ([`keymap::PLAY_BINDINGS`]).
//!
//! It plays at the source's frame rate, dropping frames it cannot show in time.

use std::time::{Duration, Instant};

use anyhow::{Context, Result};
use crossterm::event::{Event as TermEvent, KeyEventKind};
use ratatui::buffer::Buffer;
use ratatui::layout::{Constraint, Layout, Rect};
use ratatui::style::{Modifier, Style as TextStyle};
use ratatui::text::{Line, Span};
use ratatui::widgets::{Block, Borders, Paragraph, Widget};
use ratatui::Frame as TermFrame;

use super::keymap::{self, PlayKey};
use super::program::{self, Program};
use super::term;
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

/// Plays in the terminal until `q`, a signal, or `frames` frames, the face shown as
/// `framing` frames it ([`Framing::of_loaded`]); the counts stay in `player`. Skipped rows
/// are named and counted on stderr once the terminal is restored.
pub fn run(
    player: &mut Player,
    mesh: Mesh,
    framing: Framing,
    rig: &Rig,
    cells: CellMode,
    frames: Option<usize>,
) -> Result<()> {
    // Before the terminal is taken: the bind cache's warnings go to stderr.
    let done = crate::io::bind_cache::bind(crate::model::Deformation::default(), rig, &mesh)
        .context("cannot place the rig on its mesh")?;
    for warning in &done.warnings {
        eprintln!("warning: {warning}");
    }
    let bound = done.bound;
    let rest = bound.rest().to_vec();
    let face = Face {
        framing,
        renderer: Renderer::new(&mesh),
        mesh,
        bound,
        positions: rest,
        canvas: DotCanvas::new(0, 0),
        grid: CellGrid::default(),
        mode: cells,
        colors: term::colors_from_env(),
    };
    let mut playing = Playing {
        player,
        face,
        status: Status {
            current: None,
            messages: Vec::new(),
            skips: Skips::default(),
            named: Vec::new(),
            playback: Playback::Playing,
        },
        rig,
        frames,
        due: None,
        last_shown_due: None,
        ended: false,
        quit: false,
    };
    let result = program::run(&mut playing);
    let Playing { player, status, .. } = &mut playing;
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

/// Playback as the event loop runs it.
struct Playing<'a> {
    player: &'a mut Player,
    face: Face,
    status: Status,
    rig: &'a Rig,
    /// Stop after this many frames.
    frames: Option<usize>,
    /// When the frame waiting to be drawn was due.
    due: Option<Instant>,
    /// When the last drawn frame was due: frames are spaced by due times, so a frame drawn
    /// late does not delay the next.
    last_shown_due: Option<Instant>,
    ended: bool,
    quit: bool,
}

impl Program for Playing<'_> {
    const NAME: &'static str = "the player";
    // Frames may come on standard input; the keys come from the terminal device.
    const KEYS_ON_STDIN: bool = false;

    fn draw(&mut self, f: &mut TermFrame) {
        draw(f, &mut self.face, &self.status, self.player, self.rig);
    }

    fn tick(&mut self, now: Instant) -> Result<bool> {
        let mut changed = false;
        // Faster sources than the display rate: frames due in between are dropped.
        let display_ready = self
            .last_shown_due
            .is_none_or(|t| now >= t + MIN_FRAME_INTERVAL);
        if display_ready {
            if let Some((frame, when)) = self.player.tick(now)? {
                self.status.current = Some(frame);
                self.due = Some(when);
                changed = true;
            }
        }
        collect(self.player, &mut self.status);
        if self.player.is_finished() && !self.ended {
            self.ended = true;
            changed = true;
            if self.frames.is_some_and(|n| self.player.played >= n) {
                self.quit = true;
            }
        }
        self.status.playback = Playback::of(self.player, self.ended);
        Ok(changed)
    }

    fn drawn(&mut self, started: Instant, done: Instant) -> bool {
        let Some(when) = self.due.take() else {
            return false;
        };
        self.player.shown(when, done, done - started);
        self.last_shown_due = Some(when);
        // The status line was drawn before this frame counted as shown; after the last
        // frame nothing else redraws, so show the final counts.
        self.ended
    }

    fn wait(&self, now: Instant) -> Duration {
        let display_free = self.last_shown_due.map_or(now, |t| t + MIN_FRAME_INTERVAL);
        match self.player.next_due() {
            Some(when) => when.max(display_free).saturating_duration_since(now),
            None if self.player.is_live() && self.player.state() == PlayState::Playing => {
                Duration::from_millis(4)
            }
            None => Duration::from_millis(250),
        }
    }

    fn event(&mut self, ev: &TermEvent) -> Result<bool> {
        let key = match ev {
            TermEvent::Key(key) if key.kind != KeyEventKind::Release => *key,
            TermEvent::Resize(..) => return Ok(true),
            _ => return Ok(false),
        };
        let now = Instant::now();
        match keymap::play_dispatch(key) {
            Some(PlayKey::Quit) => self.quit = true,
            Some(PlayKey::Pause) => self.player.toggle_pause(now),
            Some(PlayKey::Step) => {
                if let Some(frame) = self.player.step(now)? {
                    self.status.current = Some(frame);
                }
            }
            Some(PlayKey::Faster) => self.player.change_speed(2.0, now),
            Some(PlayKey::Slower) => self.player.change_speed(0.5, now),
            None => return Ok(false),
        }
        Ok(true)
    }

    fn finished(&self) -> bool {
        self.quit
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
