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

/// What this terminal can show, from the environment (`NO_COLOR`, `TERM`, `COLORTERM`,
/// `TERM_PROGRAM`; see [`crate::render::ColorMode::detect`]). The front ends decide; the
/// renderer only takes the mode it is given.
pub fn colors_from_env() -> crate::render::ColorMode {
    let var = |name: &str| std::env::var(name).unwrap_or_default();
    crate::render::ColorMode::detect(
        std::env::var_os("NO_COLOR").is_some_and(|v| !v.is_empty()),
        &var("TERM"),
        &var("COLORTERM"),
        &var("TERM_PROGRAM"),
    )
}

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

    /// The signal received, if any. A terminal that has gone away without a SIGHUP reaching
    /// us (its emulator killed while a shell sat between it and us) counts as a hangup.
    pub fn pending(&self) -> Option<Stop> {
        if self.hangup.load(Ordering::SeqCst) || terminal_gone() {
            Some(Stop::Hangup)
        } else if self.terminate.load(Ordering::SeqCst) {
            Some(Stop::Terminate)
        } else {
            None
        }
    }
}

/// Whether the terminal has hung up (its other end closed): standard input or output, when
/// it is a character device, reports a hangup. A pipe on standard input (`play --stdin`)
/// reports one at the end of its data, which is not the terminal going away.
#[cfg(unix)]
fn terminal_gone() -> bool {
    [libc::STDIN_FILENO, libc::STDOUT_FILENO]
        .into_iter()
        .any(|fd| is_character_device(fd) && hung_up(fd))
}

/// Whether `fd` is a character device (a terminal, even one that has hung up and so no
/// longer answers as a terminal).
#[cfg(unix)]
fn is_character_device(fd: libc::c_int) -> bool {
    // SAFETY: fstat only writes the zeroed struct it is given.
    unsafe {
        let mut stat: libc::stat = std::mem::zeroed();
        libc::fstat(fd, &mut stat) == 0 && stat.st_mode & libc::S_IFMT == libc::S_IFCHR
    }
}

/// Whether the other end of `fd` is closed.
///
/// Asks poll(2) for no events at all, so only hangup, error and invalid-descriptor
/// conditions can be reported, and does not wait.
#[cfg(unix)]
fn hung_up(fd: libc::c_int) -> bool {
    let mut poll_fd = libc::pollfd {
        fd,
        events: 0,
        revents: 0,
    };
    // SAFETY: one valid pollfd, count 1, zero timeout; poll only writes `revents`.
    let ready = unsafe { libc::poll(&mut poll_fd, 1, 0) };
    ready > 0 && poll_fd.revents & (libc::POLLHUP | libc::POLLERR | libc::POLLNVAL) != 0
}

/// Whether the terminal has hung up (not detectable here; signals still stop the editor).
#[cfg(not(unix))]
fn terminal_gone() -> bool {
    false
}

#[cfg(all(test, unix))]
mod tests {
    use super::{hung_up, is_character_device};
    use std::os::fd::{AsRawFd, FromRawFd, OwnedFd};

    #[test]
    fn a_closed_other_end_is_a_hangup_and_pending_input_is_not() {
        let mut fds = [0; 2];
        // SAFETY: pipe fills two fresh descriptors, each then owned exactly once.
        assert_eq!(unsafe { libc::pipe(fds.as_mut_ptr()) }, 0);
        let (reader, writer) =
            unsafe { (OwnedFd::from_raw_fd(fds[0]), OwnedFd::from_raw_fd(fds[1])) };
        let mut writer = std::fs::File::from(writer);
        assert!(!hung_up(reader.as_raw_fd()), "an open, empty pipe");
        std::io::Write::write_all(&mut writer, b"j").unwrap();
        assert!(
            !hung_up(reader.as_raw_fd()),
            "input waiting is not a hangup"
        );
        drop(writer);
        assert!(hung_up(reader.as_raw_fd()), "the writer is gone");
        assert!(
            !is_character_device(reader.as_raw_fd()),
            "a pipe is not a terminal"
        );
        let null = std::fs::File::open("/dev/null").unwrap();
        assert!(is_character_device(null.as_raw_fd()));
        assert!(!hung_up(null.as_raw_fd()), "/dev/null never hangs up");
    }
}
