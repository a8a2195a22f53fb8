//! What the end-to-end tests of `mazewalk serve` share (`tests/serve_e2e.rs`,
//! `tests/serve_world_e2e.rs`, `tests/serve_http.rs`): a scratch folder, the server binary with its
//! log, the stock OpenSSH client's options (testkit's [`ssh_args`]), and `ssh -tt` in a
//! pseudo-terminal (testkit's [`ssh_in_pty`]) read by a `vt100` emulator. Loopback only; every wait
//! has a deadline and wakes on the event it waits for (a log line, a screen update), not on a timer;
//! every child is killed on drop. The `redis-server` they need is [`mazewalk_testkit::redis_server`].
#![allow(dead_code)] // each test file uses a part

use std::fs::File;
use std::io::{BufRead, BufReader, Read, Write};
use std::num::NonZeroU16;
use std::path::Path;
use std::process::{Child, Command, ExitStatus, Output, Stdio};
use std::sync::{Arc, Condvar, Mutex, MutexGuard, PoisonError};
use std::time::{Duration, Instant};

pub use mazewalk_testkit::scratch::Scratch;
pub use mazewalk_testkit::ssh_args;
use mazewalk_testkit::{require_tool, ssh_in_pty};
use rustix::termios::{self, Winsize};

/// Longest wait for anything. Generous for a loaded CI machine; each step takes well under a second.
pub const TIMEOUT: Duration = Duration::from_secs(20);

pub fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(PoisonError::into_inner)
}

/// Something a thread appends to and a test waits on: each change wakes the waiters.
struct Watched<T> {
    value: Mutex<T>,
    changed: Condvar,
}

impl<T> Watched<T> {
    fn new(value: T) -> Arc<Watched<T>> {
        Arc::new(Watched { value: Mutex::new(value), changed: Condvar::new() })
    }

    fn update(&self, f: impl FnOnce(&mut T)) {
        f(&mut lock(&self.value));
        self.changed.notify_all();
    }

    /// Waits until `ok` holds, woken by each change (and every 100 ms, for a condition that also
    /// depends on something else, such as a child's exit); `Err` with the value's guard after
    /// [`TIMEOUT`].
    fn wait(&self, ok: impl Fn(&T) -> bool) -> Result<MutexGuard<'_, T>, MutexGuard<'_, T>> {
        let deadline = Instant::now() + TIMEOUT;
        let mut value = lock(&self.value);
        loop {
            if ok(&value) {
                return Ok(value);
            }
            let now = Instant::now();
            if now >= deadline {
                return Err(value);
            }
            let wait = (deadline - now).min(Duration::from_millis(100));
            value = self.changed.wait_timeout(value, wait).unwrap_or_else(PoisonError::into_inner).0;
        }
    }
}

/// Waits for `child`'s exit, within [`TIMEOUT`]: `who` did not exit is a failure.
fn wait_exit(child: &mut Child, who: &str) -> ExitStatus {
    let deadline = Instant::now() + TIMEOUT;
    loop {
        if let Some(status) = child.try_wait().unwrap_or_else(|err| panic!("wait for {who}: {err}")) {
            return status;
        }
        assert!(Instant::now() < deadline, "{who} did not exit");
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// The server binary (`mazewalk serve`), with its log.
pub struct Server {
    pub child: Child,
    pub port: u16,
    log: Arc<Watched<String>>,
}

impl Server {
    /// `mazewalk serve ARGS` on a free loopback port, its host key `host_key` in `scratch`.
    pub fn start(scratch: &Scratch, args: &[&str]) -> Server {
        Server::start_on(scratch, "127.0.0.1:0", "host_key", args)
    }

    /// A server of its own host key `name` on the maze file `maze`, open to anyone, in the world at
    /// `world` (a `redis://` URL), with `more` arguments: one of several servers sharing a world.
    pub fn in_world(scratch: &Scratch, name: &str, maze: &Path, world: &str, more: &[&str]) -> Server {
        let maze = maze.to_str().expect("a UTF-8 path");
        let args = [&["--open", "--world", world, maze][..], more].concat();
        Server::start_on(scratch, "127.0.0.1:0", &format!("host_key_{name}"), &args)
    }

    /// `mazewalk serve --listen LISTEN ARGS`, its host key `host_key` in `scratch` (which is also its
    /// `HOME`, so the records file goes there); waits for its first line, which names the port.
    pub fn start_on(scratch: &Scratch, listen: &str, host_key: &str, args: &[&str]) -> Server {
        Server::spawn(Command::new(env!("CARGO_BIN_EXE_mazewalk")), scratch, listen, host_key, args)
    }

    /// [`start`](Self::start), from a `sh` that runs `setup` first (`ulimit`, `trap`: what the
    /// server inherits) and then `exec`s it.
    pub fn start_after(scratch: &Scratch, setup: &str, args: &[&str]) -> Server {
        let mut shell = Command::new("sh");
        shell.arg("-c").arg(format!("{setup}\nexec \"$0\" \"$@\"")).arg(env!("CARGO_BIN_EXE_mazewalk"));
        Server::spawn(shell, scratch, "127.0.0.1:0", "host_key", args)
    }

    fn spawn(mut command: Command, scratch: &Scratch, listen: &str, host_key: &str, args: &[&str]) -> Server {
        let mut child = command
            .arg("serve")
            .args(["--listen", listen, "--host-key"])
            .arg(scratch.join(host_key))
            .args(args)
            .env("HOME", scratch.path())
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("start mazewalk serve");
        let mut stdout = BufReader::new(child.stdout.take().expect("stdout"));
        let log = Watched::new(String::new());
        let stderr = child.stderr.take().expect("stderr");
        let sink = Arc::clone(&log);
        std::thread::spawn(move || {
            for line in BufReader::new(stderr).lines() {
                let Ok(line) = line else { break };
                sink.update(|log| {
                    log.push_str(&line);
                    log.push('\n');
                });
            }
        });
        let mut line = String::new();
        stdout.read_line(&mut line).expect("the first line");
        let port = line
            .trim()
            .split(", ")
            .next()
            .and_then(|first| first.rsplit_once(':'))
            .and_then(|(_, port)| port.parse().ok());
        let Some(port) = port else {
            let _ = child.kill();
            let _ = child.wait(); // the log's last lines have arrived once the process is gone
            std::thread::sleep(Duration::from_millis(100));
            panic!("expected `mazewalk: serving on ADDR:PORT`, got {line:?}; log:\n{}", lock(&log.value));
        };
        std::thread::spawn(move || std::io::copy(&mut stdout, &mut std::io::sink())); // the rest
        Server { child, port, log }
    }

    /// Waits for the server's exit (within [`TIMEOUT`]).
    pub fn wait_exit(&mut self) -> ExitStatus {
        wait_exit(&mut self.child, "the server")
    }

    /// The log so far.
    pub fn log(&self) -> String {
        lock(&self.log.value).clone()
    }

    /// Waits until the log holds `n` lines containing `what`.
    pub fn wait_log(&self, what: &str, n: usize) {
        if let Err(log) = self.log.wait(|log| log.matches(what).count() >= n) {
            panic!("timed out waiting for {n}× {what:?} in the log:\n{}", *log);
        }
    }

    /// `ssh` to this server, not in a terminal: its exit status, stdout and stderr.
    pub fn ssh_batch(&self, key: Option<&Path>, user: &str, args: &[&str]) -> (ExitStatus, String, String) {
        require_tool("ssh", "openssh-client");
        let out = Command::new("ssh")
            .args(ssh_args(self.port, key, user))
            .args(args)
            .stdin(Stdio::null())
            .output()
            .expect("run ssh");
        (out.status, String::from_utf8_lossy(&out.stdout).into(), String::from_utf8_lossy(&out.stderr).into())
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// `mazewalk records --records DB ARGS`, DB the records of a server started in `scratch` (its `HOME`):
/// its exit status and output.
pub fn records(scratch: &Scratch, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_mazewalk"))
        .args(["records", "--records"])
        .arg(scratch.db())
        .args(args)
        .output()
        .expect("mazewalk records")
}

/// What the reader thread shares with the test.
struct Screen {
    parser: vt100::Parser,
    raw: Vec<u8>,
}

/// `ssh -tt` in a pty (its controlling terminal, through `setsid -c`, so that resizing the pty
/// sends it SIGWINCH), read by a `vt100` emulator that answers the device-attributes queries as a
/// terminal would.
pub struct Player {
    child: Child,
    master: File,
    shared: Arc<Watched<Screen>>,
}

pub fn winsize(cols: u16, rows: u16) -> Winsize {
    Winsize { ws_row: rows, ws_col: cols, ws_xpixel: 0, ws_ypixel: 0 }
}

pub fn nz(n: u16) -> NonZeroU16 {
    NonZeroU16::new(n).expect("non-zero")
}

impl Player {
    /// `user` at the server on `port` with `key` (none: no key), in a `cols × rows` terminal.
    pub fn connect(port: u16, key: Option<&Path>, user: &str, cols: u16, rows: u16) -> Player {
        Player::connect_from(None, port, key, user, cols, rows)
    }

    /// As [`connect`](Self::connect), from the loopback address `bind` (`ssh -b`, e.g. `127.0.0.2`:
    /// another address group) when given.
    pub fn connect_from(
        bind: Option<&str>,
        port: u16,
        key: Option<&Path>,
        user: &str,
        cols: u16,
        rows: u16,
    ) -> Player {
        Player::connect_sending(bind, port, key, user, (cols, rows), &[])
    }

    /// As [`connect_from`](Self::connect_from), with `env` set for `ssh` and sent to the server
    /// (`-o SendEnv=NAME` each, as Debian's `ssh_config` sends `LANG` and `LC_*`).
    pub fn connect_sending(
        bind: Option<&str>,
        port: u16,
        key: Option<&Path>,
        user: &str,
        (cols, rows): (u16, u16),
        env: &[(&str, &str)],
    ) -> Player {
        let (child, master) = ssh_in_pty(bind, port, key, user, (cols, rows), env);
        let shared =
            Watched::new(Screen { parser: vt100::Parser::new(nz(rows), nz(cols), 0), raw: Vec::new() });
        let mut input = master.try_clone().expect("dup");
        let mut answer = master.try_clone().expect("dup");
        let sink = Arc::clone(&shared);
        std::thread::spawn(move || {
            let mut buf = vec![0u8; 1 << 16];
            let mut scanned = 0usize;
            loop {
                let n = match input.read(&mut buf) {
                    Ok(0) | Err(_) => break, // EIO once ssh and every copy of the terminal side are gone
                    Ok(n) => n,
                };
                let (mut queries, mut statuses) = (0, 0);
                sink.update(|s| {
                    s.raw.extend_from_slice(&buf[..n]);
                    s.parser.process(&buf[..n]);
                    // Answer each device-attributes query (flow control) and status report (asked
                    // last, before a goodbye), as an xterm would; a query may straddle two reads.
                    let from = scanned.saturating_sub(2);
                    queries = s.raw[from..].windows(3).filter(|w| *w == b"\x1b[c").count();
                    statuses =
                        s.raw[scanned.saturating_sub(3)..].windows(4).filter(|w| *w == b"\x1b[5n").count();
                    scanned = s.raw.len();
                });
                for _ in 0..queries {
                    let _ = answer.write_all(b"\x1b[?62;22c");
                }
                for _ in 0..statuses {
                    let _ = answer.write_all(b"\x1b[0n");
                }
            }
        });
        Player { child, master, shared }
    }

    pub fn send(&mut self, bytes: &[u8]) {
        self.master.write_all(bytes).expect("write to the pty");
    }

    pub fn resize(&mut self, cols: u16, rows: u16) {
        self.shared.update(|s| s.parser.screen_mut().set_size(nz(rows), nz(cols)));
        termios::tcsetwinsize(&self.master, winsize(cols, rows)).expect("resize the pty");
    }

    /// Waits until `ok` holds for the screen and the bytes so far, woken by each read; panics with
    /// the screen after [`TIMEOUT`].
    pub fn wait_for(&self, what: &str, ok: impl Fn(&vt100::Screen, &[u8]) -> bool) {
        if let Err(s) = self.shared.wait(|s| ok(s.parser.screen(), &s.raw)) {
            let tail = String::from_utf8_lossy(&s.raw[s.raw.len().saturating_sub(400)..]).into_owned();
            panic!(
                "timed out waiting for {what}; the screen shows:\n{}\nlast bytes: {tail:?}",
                s.parser.screen().contents()
            );
        }
    }

    /// Waits for ssh's exit (within [`TIMEOUT`]).
    pub fn wait_exit(&mut self) -> ExitStatus {
        wait_exit(&mut self.child, "ssh")
    }

    /// Every byte the terminal got.
    pub fn raw(&self) -> Vec<u8> {
        lock(&self.shared.value).raw.clone()
    }

    /// Whether `ok` holds for the screen as it is now.
    pub fn shows(&self, ok: impl Fn(&vt100::Screen) -> bool) -> bool {
        self.read(ok)
    }

    /// What `f` reads off the screen as it is now.
    pub fn read<T>(&self, f: impl Fn(&vt100::Screen) -> T) -> T {
        f(lock(&self.shared.value).parser.screen())
    }
}

impl Drop for Player {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// The HUD's row.
pub fn hud_row(screen: &vt100::Screen) -> String {
    let rows = screen.size().0.get();
    screen.contents_between(rows - 1, 0, rows - 1, u16::MAX)
}

/// The game is on screen: the HUD's help hint on the bottom row.
pub fn playing(screen: &vt100::Screen, _: &[u8]) -> bool {
    screen.alternate_screen() && hud_row(screen).contains("? help")
}

/// Whether `ch` shows in the corner map (the top third of the right third of the screen).
pub fn on_map(screen: &vt100::Screen, ch: char) -> bool {
    let (rows, cols) = (screen.size().0.get(), screen.size().1.get());
    let width = (cols / 3).min(40);
    (0..rows / 3).any(|row| screen.contents_between(row, cols - width, row, cols).contains(ch))
}

/// Each cell's glyph and colours, as it looks ([`looks`]).
pub type Cells = Vec<Vec<(String, vt100::Color, vt100::Color)>>;

/// The cells of `rows` of the screen, as they look: a half block is its two halves' colours (the
/// encoder may send `▀` with equal colours, `▄` with them swapped, or a space or `█` for one colour:
/// they look alike), any other character itself in its colours.
pub fn looks(screen: &vt100::Screen, rows: std::ops::Range<u16>) -> Cells {
    let cols = screen.size().1.get();
    let look = |row, col| {
        let cell = screen.cell(row, col).expect("in the screen");
        let (fg, bg) = (cell.fgcolor(), cell.bgcolor());
        match cell.contents() {
            "" | " " => (String::new(), bg, bg),
            "▀" => (String::new(), fg, bg),
            "▄" => (String::new(), bg, fg),
            "█" => (String::new(), fg, fg),
            other => (other.to_string(), fg, bg),
        }
    };
    rows.map(|row| (0..cols).map(|col| look(row, col)).collect()).collect()
}
