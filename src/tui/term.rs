//! Terminal hygiene: raw mode, the alternate screen and mouse capture, restored on every exit
//! path (normal return, error, panic, SIGTERM, SIGHUP); frames wrapped in synchronized-update
//! sequences so a slow link never shows half a frame.

use std::io::{self, Write};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

use crossterm::event::{DisableMouseCapture, EnableMouseCapture};
use crossterm::terminal::{
    disable_raw_mode, enable_raw_mode, BeginSynchronizedUpdate, EndSynchronizedUpdate,
    EnterAlternateScreen, LeaveAlternateScreen,
};
use crossterm::{cursor, execute, queue};

/// Whether the terminal is currently set up by us (so restoring twice is harmless).
static ACTIVE: AtomicBool = AtomicBool::new(false);

/// Puts the terminal in editor mode; the returned guard restores it when dropped.
pub fn enter() -> io::Result<TerminalGuard> {
    install_panic_hook();
    enable_raw_mode()?;
    ACTIVE.store(true, Ordering::SeqCst);
    let mut out = io::stdout();
    if let Err(e) = execute!(out, EnterAlternateScreen, EnableMouseCapture, cursor::Hide) {
        restore();
        return Err(e);
    }
    Ok(TerminalGuard)
}

/// Restores the terminal (idempotent; errors are ignored because the terminal may be gone,
/// as after SIGHUP).
pub fn restore() {
    if ACTIVE.swap(false, Ordering::SeqCst) {
        let mut out = io::stdout();
        let _ = execute!(
            out,
            EndSynchronizedUpdate,
            DisableMouseCapture,
            LeaveAlternateScreen,
            cursor::Show
        );
        let _ = disable_raw_mode();
        let _ = out.flush();
    }
}

/// Restores the terminal when dropped.
#[derive(Debug)]
pub struct TerminalGuard;

impl Drop for TerminalGuard {
    fn drop(&mut self) {
        restore();
    }
}

fn install_panic_hook() {
    static INSTALLED: AtomicBool = AtomicBool::new(false);
    if INSTALLED.swap(true, Ordering::SeqCst) {
        return;
    }
    let previous = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        // Restore first so the panic message lands on a usable screen.
        restore();
        previous(info);
    }));
}

/// Starts a synchronized update (the terminal holds the frame until it ends).
pub fn begin_frame(out: &mut impl Write) -> io::Result<()> {
    queue!(out, BeginSynchronizedUpdate)
}

/// Ends a synchronized update and flushes.
pub fn end_frame(out: &mut impl Write) -> io::Result<()> {
    queue!(out, EndSynchronizedUpdate)?;
    out.flush()
}

/// Flags raised by SIGHUP and SIGTERM (and SIGINT, which raw mode normally keeps away).
#[derive(Debug, Clone)]
pub struct Signals {
    hangup: Arc<AtomicBool>,
    terminate: Arc<AtomicBool>,
}

/// What a signal asks for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stop {
    /// The terminal is gone (SIGHUP).
    Hangup,
    /// Asked to stop (SIGTERM, SIGINT).
    Terminate,
}

impl Signals {
    /// Registers the handlers.
    pub fn register() -> io::Result<Signals> {
        let hangup = Arc::new(AtomicBool::new(false));
        let terminate = Arc::new(AtomicBool::new(false));
        #[cfg(unix)]
        {
            use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM};
            signal_hook::flag::register(SIGHUP, Arc::clone(&hangup))?;
            signal_hook::flag::register(SIGTERM, Arc::clone(&terminate))?;
            signal_hook::flag::register(SIGINT, Arc::clone(&terminate))?;
        }
        Ok(Signals { hangup, terminate })
    }

    /// The signal received, if any.
    pub fn pending(&self) -> Option<Stop> {
        if self.hangup.load(Ordering::SeqCst) {
            Some(Stop::Hangup)
        } else if self.terminate.load(Ordering::SeqCst) {
            Some(Stop::Terminate)
        } else {
            None
        }
    }
}
