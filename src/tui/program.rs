//! The one event loop of the full-screen programs (the editor, the landmark picker and the
//! player): terminal set-up and restore on every exit path, signals, drawing inside a
//! synchronized update, and events drained before the next frame. Each program says what it
//! does with an event, a tick and a signal ([`Program`]); [`run`] does the rest.

use std::io::{self, IsTerminal};
use std::time::{Duration, Instant};

use crossterm::event::{self, Event};
use ratatui::backend::CrosstermBackend;
use ratatui::{Frame, Terminal};

use super::term;

/// A full-screen program driven by [`run`].
pub trait Program {
    /// What the program is called in messages (`the editor`).
    const NAME: &'static str;
    /// Whether standard input must be the terminal too. The player reads its frames from
    /// standard input when asked, and its keys from the terminal device.
    const KEYS_ON_STDIN: bool = true;

    /// Draws one frame. Reads the state only.
    fn draw(&mut self, frame: &mut Frame);

    /// Handles one terminal event (the first is a resize to the terminal's size); returns
    /// whether the screen changed.
    fn event(&mut self, event: &Event) -> anyhow::Result<bool>;

    /// Called once per turn of the loop, before drawing: timers and sources. Returns whether
    /// the screen changed.
    fn tick(&mut self, _now: Instant) -> anyhow::Result<bool> {
        Ok(false)
    }

    /// How long the loop may wait for a key before the next tick.
    fn wait(&self, _now: Instant) -> Duration {
        Duration::from_millis(200)
    }

    /// A frame went out: drawing started at `started` and was flushed at `done`. Returns
    /// whether to draw again at once.
    fn drawn(&mut self, _started: Instant, _done: Instant) -> bool {
        false
    }

    /// A termination signal (SIGTERM, SIGHUP, a vanished terminal) stops the loop: keep what
    /// must not be lost.
    fn signalled(&mut self) {}

    /// The program panicked (the terminal is already restored): keep what must not be lost.
    fn panicked(&mut self) {}

    /// The loop ended, by quitting, a signal or an error: last words before the terminal is
    /// restored.
    fn left(&mut self) {}

    /// Whether the program is done.
    fn finished(&self) -> bool;
}

/// Runs `program` on the terminal until it is finished or a signal stops it. Refuses at once
/// when standard output (and, for most programs, standard input) is not a terminal.
pub fn run<P: Program>(program: &mut P) -> anyhow::Result<()> {
    let stdin_ok = !P::KEYS_ON_STDIN || io::stdin().is_terminal();
    if !stdin_ok || !io::stdout().is_terminal() {
        anyhow::bail!(
            "{} needs a terminal: run it with standard input and output on a terminal",
            P::NAME
        );
    }
    let signals = term::Signals::register()?;
    let guard = term::enter()?;
    let mut terminal = Terminal::new(CrosstermBackend::new(io::stdout()))?;
    let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        turn(program, &signals, &mut terminal)
    }));
    let result = match result {
        Ok(result) => result,
        Err(panic) => {
            program.panicked();
            std::panic::resume_unwind(panic);
        }
    };
    program.left();
    drop(terminal);
    drop(guard);
    term::restore();
    result
}

/// The loop itself: tick, draw when something changed, stop on a signal, wait for keys and
/// handle everything already waiting before the next frame (typing ahead or pasting over a
/// slow link costs one frame, not one per key).
fn turn<P: Program>(
    program: &mut P,
    signals: &term::Signals,
    terminal: &mut Terminal<CrosstermBackend<io::Stdout>>,
) -> anyhow::Result<()> {
    let size = terminal.size()?;
    program.event(&Event::Resize(size.width, size.height))?;
    let mut redraw = true;
    loop {
        redraw |= program.tick(Instant::now())?;
        if program.finished() {
            return Ok(());
        }
        if redraw {
            let started = Instant::now();
            term::begin_frame(terminal.backend_mut())?;
            terminal.draw(|frame| program.draw(frame))?;
            term::end_frame(terminal.backend_mut())?;
            redraw = program.drawn(started, Instant::now());
        }
        if signals.pending().is_some() {
            program.signalled();
            return Ok(());
        }
        if !event::poll(program.wait(Instant::now()))? {
            continue;
        }
        loop {
            let ev = event::read()?;
            if matches!(ev, Event::Resize(..)) {
                terminal.autoresize()?;
                redraw = true;
            }
            redraw |= program.event(&ev)?;
            // A tiny timeout rather than zero: crossterm returns events it has already
            // parsed only from a wait that has time left.
            if program.finished() || !event::poll(Duration::from_micros(1))? {
                break;
            }
        }
    }
}
