//! The one harness for driving a real program (mostly the `grimace` binary) in a
//! pseudo-terminal: start it in a folder with arguments, environment and optionally piped
//! standard input at a size, type keys, read the screen back through a VT parser (vt100),
//! wait for what the screen or the raw output shows, resize, hang up, kill hard, wait for the
//! exit, and capture the screen to a file for a look.
//!
//! The pseudo-terminal and the process come from portable-pty; libc is used only for what it
//! has no call for: polling the master end (so the reader thread can let go of it), clearing
//! the end-of-file character before the terminal vanishes, and SIGKILL.
//!
//! Every wait has a generous timeout ([`TIMEOUT`]): the tests run in parallel on small
//! machines, and a wait that succeeds returns as soon as its condition holds.

use std::io::{Read, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use portable_pty::{native_pty_system, Child, CommandBuilder, ExitStatus, MasterPty, PtySize};

/// How long any wait lasts before the test fails with the screen.
pub const TIMEOUT: Duration = Duration::from_secs(30);

/// How often a wait looks again.
const POLL: Duration = Duration::from_millis(20);

/// What to start, and how: built with [`Launch::grimace`] or [`Launch::program`], then
/// [`Launch::start`].
pub struct Launch {
    program: String,
    args: Vec<String>,
    dir: PathBuf,
    env: Vec<(String, String)>,
    stdin: Option<String>,
    cols: u16,
    rows: u16,
}

impl Launch {
    /// The `grimace` binary, run in `dir` with its state folder (`XDG_STATE_HOME`) there too.
    pub fn grimace(dir: &Path) -> Launch {
        Launch::program(env!("CARGO_BIN_EXE_grimace"), dir)
    }

    /// Any program, run in `dir` with `XDG_STATE_HOME=dir`, `TERM=xterm-256color` and no
    /// `NO_COLOR` or `COLORTERM` from the environment the tests run in; 80 x 24 unless
    /// [`Launch::size`] says otherwise.
    pub fn program(program: &str, dir: &Path) -> Launch {
        Launch {
            program: program.to_string(),
            args: Vec::new(),
            dir: dir.to_path_buf(),
            env: Vec::new(),
            stdin: None,
            cols: 80,
            rows: 24,
        }
    }

    /// Adds arguments.
    pub fn args(mut self, args: &[&str]) -> Launch {
        self.args.extend(args.iter().map(|a| a.to_string()));
        self
    }

    /// Sets an environment variable (after the defaults, so it can override them).
    pub fn env(mut self, key: &str, value: &str) -> Launch {
        self.env.push((key.to_string(), value.to_string()));
        self
    }

    /// Pipes `text` into the program's standard input (`cat FILE | program ...` in `sh`, so
    /// the terminal stays the program's terminal while its input is a pipe). The process
    /// started, and so [`Term::pid`], is then the shell.
    pub fn stdin(mut self, text: &str) -> Launch {
        self.stdin = Some(text.to_string());
        self
    }

    /// The terminal's size in columns and rows.
    pub fn size(mut self, cols: u16, rows: u16) -> Launch {
        self.cols = cols;
        self.rows = rows;
        self
    }

    /// Opens the pseudo-terminal and starts the program in it.
    pub fn start(self) -> Term {
        let pair = native_pty_system()
            .openpty(PtySize {
                rows: self.rows,
                cols: self.cols,
                pixel_width: 0,
                pixel_height: 0,
            })
            .expect("a pseudo-terminal");
        let mut stdin_file = None;
        let mut cmd = match &self.stdin {
            None => {
                let mut cmd = CommandBuilder::new(&self.program);
                cmd.args(&self.args);
                cmd
            }
            Some(text) => {
                let mut file = tempfile::NamedTempFile::new().expect("a file for the input");
                file.write_all(text.as_bytes()).unwrap();
                let quoted: Vec<String> = std::iter::once(&self.program)
                    .chain(&self.args)
                    .map(|a| shell_quote(a))
                    .collect();
                let script = format!(
                    "cat {} | {}",
                    shell_quote(&file.path().display().to_string()),
                    quoted.join(" ")
                );
                stdin_file = Some(file);
                let mut cmd = CommandBuilder::new("sh");
                cmd.args(["-c", &script]);
                cmd
            }
        };
        cmd.cwd(&self.dir);
        cmd.env("XDG_STATE_HOME", &self.dir);
        cmd.env("TERM", "xterm-256color");
        cmd.env_remove("NO_COLOR");
        cmd.env_remove("COLORTERM");
        for (k, v) in &self.env {
            cmd.env(k, v);
        }
        let child = pair
            .slave
            .spawn_command(cmd)
            .unwrap_or_else(|e| panic!("{} did not start: {e}", self.program));
        drop(pair.slave);
        let mut reader = pair.master.try_clone_reader().unwrap();
        let writer = pair.master.take_writer().unwrap();
        let master_fd = pair.master.as_raw_fd().expect("a unix pseudo-terminal");
        let shared = Arc::new(Mutex::new(Shared {
            parser: vt100::Parser::new(self.rows, self.cols, 0),
            raw: Vec::new(),
            closed: false,
        }));
        let stop_reading = Arc::new(AtomicBool::new(false));
        let (sh, stop) = (Arc::clone(&shared), Arc::clone(&stop_reading));
        let reader = std::thread::spawn(move || {
            let mut buf = [0u8; 8192];
            // Wait with a timeout so the thread can be told to let go of the master end.
            while !stop.load(Ordering::SeqCst) {
                if !readable(master_fd, 50) {
                    continue;
                }
                match reader.read(&mut buf) {
                    Ok(0) | Err(_) => break,
                    Ok(n) => {
                        let mut sh = sh.lock().unwrap();
                        sh.parser.process(&buf[..n]);
                        sh.raw.extend_from_slice(&buf[..n]);
                    }
                }
            }
            sh.lock().unwrap().closed = true;
        });
        Term {
            what: self.program,
            child,
            writer: Some(writer),
            master: Some(pair.master),
            shared,
            stop_reading,
            reader: Some(reader),
            released: false,
            _stdin_file: stdin_file,
        }
    }
}

/// `text` in single quotes for `sh`.
fn shell_quote(text: &str) -> String {
    format!("'{}'", text.replace('\'', r"'\''"))
}

/// What the reader thread fills in.
struct Shared {
    parser: vt100::Parser,
    /// Every byte the program wrote, in order.
    raw: Vec<u8>,
    /// The reader saw the end of the output (every copy of the terminal's other end closed).
    closed: bool,
}

/// A program running in a pseudo-terminal. Dropped while the program still runs, it kills
/// the program (SIGKILL) and reaps it.
pub struct Term {
    what: String,
    child: Box<dyn Child + Send + Sync>,
    writer: Option<Box<dyn Write + Send>>,
    master: Option<Box<dyn MasterPty + Send>>,
    shared: Arc<Mutex<Shared>>,
    /// Stops the reader thread, which holds a copy of the master end.
    stop_reading: Arc<AtomicBool>,
    reader: Option<JoinHandle<()>>,
    /// The terminal was closed under the program on purpose; it is left to run.
    released: bool,
    _stdin_file: Option<tempfile::NamedTempFile>,
}

impl Term {
    /// Starts `grimace ARGS` in `dir` at `cols` x `rows` (see [`Launch::program`] for the
    /// environment).
    pub fn grimace(dir: &Path, args: &[&str], cols: u16, rows: u16) -> Term {
        Launch::grimace(dir).args(args).size(cols, rows).start()
    }

    /// Types `keys`.
    pub fn send(&mut self, keys: &str) {
        let writer = self.writer.as_mut().expect("the terminal is open");
        writer.write_all(keys.as_bytes()).unwrap();
        writer.flush().unwrap();
    }

    /// The screen's text.
    pub fn screen(&self) -> String {
        self.shared.lock().unwrap().parser.screen().contents()
    }

    /// The screen as the parser holds it (for colours, the cursor and the modes).
    pub fn with_screen<T>(&self, f: impl FnOnce(&vt100::Screen) -> T) -> T {
        f(self.shared.lock().unwrap().parser.screen())
    }

    /// Everything the program wrote so far, as text (invalid UTF-8 replaced), escapes and
    /// all: what went to the main screen before an alternate screen hid it is here too.
    pub fn output(&self) -> String {
        String::from_utf8_lossy(&self.shared.lock().unwrap().raw).into_owned()
    }

    /// How many bytes the program wrote so far.
    pub fn bytes_read(&self) -> usize {
        self.shared.lock().unwrap().raw.len()
    }

    /// The process id of the program started (the shell when input is piped).
    pub fn pid(&self) -> u32 {
        self.child.process_id().expect("a process id")
    }

    /// Waits until `done(self)` holds and returns the screen; after [`TIMEOUT`] fails naming
    /// `what` and showing the screen.
    pub fn wait_until(&self, what: &str, mut done: impl FnMut(&Term) -> bool) -> String {
        let start = Instant::now();
        loop {
            if done(self) {
                return self.screen();
            }
            if start.elapsed() > TIMEOUT {
                panic!(
                    "{what}: not seen within {TIMEOUT:?} from {}; the screen:\n{}",
                    self.what,
                    self.screen()
                );
            }
            std::thread::sleep(POLL);
        }
    }

    /// Waits until `done(screen text)` holds and returns the screen (see [`Term::wait_until`]).
    pub fn wait_screen(&self, what: &str, done: impl Fn(&str) -> bool) -> String {
        self.wait_until(what, |t| done(&t.screen()))
    }

    /// Waits until the screen contains `needle` and returns the screen.
    pub fn wait_for(&self, needle: &str) -> String {
        self.wait_screen(&format!("`{needle}`"), |s| s.contains(needle))
    }

    /// Waits until the program has left the alternate screen (the terminal is restored).
    pub fn wait_restored(&self) {
        self.wait_until("the terminal restored (main screen)", |t| {
            !t.with_screen(|s| s.alternate_screen())
        });
    }

    /// The exit status, if the program has exited.
    pub fn try_wait(&mut self) -> Option<ExitStatus> {
        self.child.try_wait().unwrap()
    }

    /// Waits for the program to exit and for its last output to reach the screen; its exit
    /// status. After [`TIMEOUT`] it is killed and the test fails with the screen.
    pub fn wait_exit(&mut self) -> ExitStatus {
        let start = Instant::now();
        let status = loop {
            if let Some(status) = self.child.try_wait().unwrap() {
                break status;
            }
            if start.elapsed() > TIMEOUT {
                self.signal(libc::SIGKILL);
                panic!(
                    "{} did not exit within {TIMEOUT:?}; the screen:\n{}",
                    self.what,
                    self.screen()
                );
            }
            std::thread::sleep(POLL);
        };
        // The last output: read until the terminal's other end is closed everywhere (a
        // process the program left behind may hold it open; then a short while only).
        let drained = Instant::now();
        while !self.shared.lock().unwrap().closed && drained.elapsed() < Duration::from_secs(2) {
            std::thread::sleep(POLL);
        }
        status
    }

    /// Sends SIGHUP, as when the connection to the terminal drops.
    pub fn hang_up(&mut self) {
        // portable-pty's killer sends SIGHUP on unix.
        self.child.clone_killer().kill().unwrap();
    }

    /// Kills the program without giving it a chance to clean up, like a crash or `kill -9`,
    /// and waits for it to be gone.
    pub fn kill_hard(&mut self) -> ExitStatus {
        self.signal(libc::SIGKILL);
        self.wait_exit()
    }

    fn signal(&self, signal: libc::c_int) {
        let pid = self.pid() as libc::pid_t;
        // SAFETY: signalling the process this harness started (not yet reaped).
        unsafe { libc::kill(pid, signal) };
    }

    /// Changes the terminal's size (the program gets SIGWINCH) and the parser's with it.
    pub fn resize(&mut self, cols: u16, rows: u16) {
        self.master
            .as_ref()
            .expect("the terminal is open")
            .resize(PtySize {
                rows,
                cols,
                pixel_width: 0,
                pixel_height: 0,
            })
            .expect("the terminal resizes");
        self.shared.lock().unwrap().parser.set_size(rows, cols);
    }

    /// Closes every copy of the master end, as when a terminal emulator is killed: the
    /// terminal is gone, and only the session leader gets a SIGHUP from the kernel. The
    /// program is left to end by itself.
    pub fn close_terminal(mut self) {
        self.stop_reader();
        // portable-pty's writer types end-of-file on drop; a vanishing emulator types
        // nothing, so clear the end-of-file character first.
        let master = self.master.take().expect("the terminal is open");
        let fd = master.as_raw_fd().unwrap();
        // SAFETY: plain termios calls on an open descriptor with a zeroed struct to fill.
        unsafe {
            let mut t: libc::termios = std::mem::zeroed();
            if libc::tcgetattr(fd, &mut t) == 0 {
                t.c_cc[libc::VEOF] = 0;
                libc::tcsetattr(fd, libc::TCSANOW, &t);
            }
        }
        drop(self.writer.take());
        drop(master);
        self.released = true;
    }

    /// Writes the screen with its colours (SGR escapes, the form `tmux capture-pane -p -e`
    /// gives) to `name` in the folder named by `GRIMACE_CAPTURE`, when that is set, for a
    /// look with `screen2png`. Returns the file written.
    pub fn capture(&self, name: &str) -> Option<PathBuf> {
        let dir = std::env::var_os("GRIMACE_CAPTURE")?;
        let path = Path::new(&dir).join(name);
        let text = self.with_screen(screen_with_colours);
        std::fs::write(&path, text)
            .unwrap_or_else(|e| panic!("cannot write the capture {}: {e}", path.display()));
        Some(path)
    }

    fn stop_reader(&mut self) {
        self.stop_reading.store(true, Ordering::SeqCst);
        if let Some(reader) = self.reader.take() {
            // A reader that panicked has nothing more to give; the test goes on.
            let _ = reader.join();
        }
    }
}

impl Drop for Term {
    fn drop(&mut self) {
        if !self.released {
            if let Ok(None) = self.child.try_wait() {
                self.signal(libc::SIGKILL);
                let _ = self.child.wait();
            }
        }
        self.stop_reader();
    }
}

/// Whether `fd` has something to read (or is at its end) within `timeout_ms`.
fn readable(fd: i32, timeout_ms: i32) -> bool {
    let mut pfd = libc::pollfd {
        fd,
        events: libc::POLLIN,
        revents: 0,
    };
    // SAFETY: one valid pollfd, count 1.
    unsafe { libc::poll(&mut pfd, 1, timeout_ms) > 0 }
}

/// The screen as lines of text with SGR escapes for colours, bold and reverse.
fn screen_with_colours(screen: &vt100::Screen) -> String {
    let (rows, cols) = screen.size();
    let mut out = String::new();
    for row in 0..rows {
        let mut last = String::new();
        for col in 0..cols {
            let Some(cell) = screen.cell(row, col) else {
                continue;
            };
            if cell.is_wide_continuation() {
                continue;
            }
            let sgr = sgr(cell);
            if sgr != last {
                out.push_str("\x1b[0");
                out.push_str(&sgr);
                out.push('m');
                last = sgr;
            }
            let text = cell.contents();
            out.push_str(if text.is_empty() { " " } else { &text });
        }
        out.push_str("\x1b[0m\n");
    }
    out
}

/// The SGR parameters (each after a `;`) of a cell's look.
fn sgr(cell: &vt100::Cell) -> String {
    let mut s = String::new();
    if cell.bold() {
        s.push_str(";1");
    }
    if cell.inverse() {
        s.push_str(";7");
    }
    for (color, base) in [(cell.fgcolor(), 38), (cell.bgcolor(), 48)] {
        match color {
            vt100::Color::Default => {}
            vt100::Color::Idx(i) => s.push_str(&format!(";{base};5;{i}")),
            vt100::Color::Rgb(r, g, b) => s.push_str(&format!(";{base};2;{r};{g};{b}")),
        }
    }
    s
}
