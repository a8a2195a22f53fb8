//! A slow link in real time (issue #33): the real `mazewalk` binary in a pseudo-terminal whose output
//! crosses a metered link to a far terminal, as over SSH.
//!
//! ```text
//! mazewalk ─pty─▶ reader ─unbounded queue─▶ link: bytes_per_s, then one_way ─▶ far terminal (vt100)
//!    ▲                                                                           │ answers CSI c
//!    └──────────── uplink: keys and answers, one_way later ◀─────────────────────┘
//! ```
//!
//! The reader takes everything the walk writes at once (an unbounded sender-side queue, as SSH's
//! window and the TCP buffers are: the walk never blocks on a write); the link lets it out at
//! `bytes_per_s`, in pieces of at most [`PIECE`] bytes, each arriving `one_way` after it left. The far
//! terminal answers a device-attributes query (`CSI c`) when the bytes before it have arrived — not
//! the kitty keyboard query nor anything else (an xterm) — and the answer reaches the walk `one_way`
//! later, as do the keys "typed" there. The far screen's HUD tells the heading it shows.
//!
//! Shared by the short test (`tests/slow_link_pty.rs`) and the full measurement
//! (`benches/examples/slow_link_pty.rs`); threads and a real clock, so figures vary a little from run
//! to run (the measurement repeats and takes medians).
#![allow(missing_docs)]
// moved from the tests that share it, whose items were not documented one by one

// A child's session and controlling terminal are set between fork and exec (`pre_exec`), as in
// tests/e2e_tui.rs.
#![allow(unsafe_code)]

use std::collections::BinaryHeap;
use std::fs::File;
use std::io::{Read, Write};
use std::num::NonZeroU16;
use std::os::unix::process::CommandExt;
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::sync::mpsc;
use std::sync::{Arc, Mutex, PoisonError};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use rustix::termios::Winsize;

/// The largest piece the link carries at once (bytes): about a TCP segment.
pub const PIECE: usize = 1400;

/// The device-attributes query and the answer the far terminal gives (an xterm's).
const DA_QUERY: &[u8] = b"\x1b[c";
const DA_ANSWER: &[u8] = b"\x1b[?62;22c";

/// The link between the walk and the far terminal.
#[derive(Clone, Copy, Debug)]
pub struct Link {
    /// The bottleneck's rate, bytes per second (125,000 = 1 Mbit/s).
    pub bytes_per_s: f64,
    /// Delay each way, seconds.
    pub one_way: f64,
    /// Answers lost on the way back during a [`measure`]: the first device-attributes query to
    /// arrive at the far end at least this many seconds after the key went down, for each (none on a
    /// real link; bytes dropped by a rate limit, or a harness that misses queries, lose some).
    pub lost_answers: &'static [f64],
}

/// A key held as a terminal without key-release events sends it: one press, then after
/// `repeat_delay` the auto-repeat every `repeat_every`, until `hold` after the press.
#[derive(Clone, Copy, Debug)]
pub struct Hold {
    /// The key's bytes.
    pub key: &'static [u8],
    /// How long it is held, seconds.
    pub hold: f64,
    /// The auto-repeat's initial delay, seconds.
    pub repeat_delay: f64,
    /// The auto-repeat's interval, seconds.
    pub repeat_every: f64,
}

/// What the far terminal saw.
#[derive(Debug, Default)]
pub struct Seen {
    /// (seconds since the start, heading on the far screen's HUD) at each change of it.
    pub headings: Vec<(f64, f32)>,
    /// When each frame's end (its query) arrived, seconds since the start.
    pub frames: Vec<f64>,
    /// Bytes that crossed the link.
    pub bytes: u64,
}

/// The outcome of one hold over the link.
#[derive(Debug)]
pub struct Outcome {
    /// When the key was pressed and let go, seconds since the start (as typed at the far end).
    pub press: f64,
    /// See [`Outcome::press`].
    pub release: f64,
    /// What the far terminal saw.
    pub seen: Seen,
}

impl Outcome {
    /// Seconds from the release to the far screen's last heading change.
    #[must_use]
    pub fn tail(&self) -> f64 {
        self.seen.headings.last().map_or(0.0, |&(t, _)| (t - self.release).max(0.0))
    }

    /// Degrees the far screen's heading still turned after the release (summed, each change taken
    /// the short way round).
    #[must_use]
    pub fn degrees_after_release(&self) -> f32 {
        let shown_at_release = self.seen.headings.iter().rev().find(|(t, _)| *t <= self.release);
        let mut last = shown_at_release.map(|&(_, h)| h);
        let mut sum = 0.0;
        for &(_, h) in self.seen.headings.iter().filter(|(t, _)| *t > self.release) {
            if let Some(l) = last {
                sum += ((h - l + 540.0).rem_euclid(360.0) - 180.0).abs();
            }
            last = Some(h);
        }
        sum
    }

    /// Degrees turned in all, as the far screen shows it at the end.
    #[must_use]
    pub fn degrees_turned(&self) -> f32 {
        let mut sum = 0.0;
        for w in self.seen.headings.windows(2).filter(|w| w[1].0 > self.press) {
            sum += ((w[1].1 - w[0].1 + 540.0).rem_euclid(360.0) - 180.0).abs();
        }
        sum
    }

    /// Seconds the far screen waited for its last heading change: from the end of the frame before
    /// to the change.
    #[must_use]
    pub fn last_gap(&self) -> f64 {
        let Some(&(changed, _)) = self.seen.headings.last() else { return 0.0 };
        let before = self.seen.frames.iter().copied().rfind(|&t| t < changed);
        before.map_or(0.0, |t| changed - t)
    }

    /// The heading the far screen showed last.
    #[must_use]
    pub fn final_heading(&self) -> Option<f32> {
        self.seen.headings.last().map(|&(_, h)| h)
    }
}

/// Something for the uplink to write at a time: keys or an answer.
struct Due {
    at: Instant,
    seq: u64,
    bytes: Vec<u8>,
}

impl PartialEq for Due {
    fn eq(&self, other: &Self) -> bool {
        (self.at, self.seq) == (other.at, other.seq)
    }
}
impl Eq for Due {}
impl PartialOrd for Due {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for Due {
    /// Reversed: the earliest first out of a `BinaryHeap`.
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        (other.at, other.seq).cmp(&(self.at, self.seq))
    }
}

/// The binary on one end of the link.
pub struct Walk {
    child: Child,
    start: Instant,
    link: Link,
    seen: Arc<Mutex<Seen>>,
    uplink: Option<mpsc::Sender<(Instant, Vec<u8>)>>,
    threads: Vec<JoinHandle<()>>,
    last_arrival: Arc<Mutex<Instant>>,
    /// When answers are to be lost, seconds since the start (see [`Link::lost_answers`]).
    lose_at: Arc<Mutex<Vec<f64>>>,
}

fn nz(n: u16) -> NonZeroU16 {
    NonZeroU16::new(n).expect("a terminal is at least 1×1")
}

/// The heading a HUD row shows (`… heading 123° …`).
fn hud_heading(row: &str) -> Option<f32> {
    row.split("heading ").nth(1)?.split('°').next()?.trim().parse().ok()
}

impl Walk {
    /// Starts `binary ARGS` in a `cols × rows` pty with `env` (over a cleared environment), as the
    /// leader of its own session with the pty as its controlling terminal, behind `link`.
    pub fn spawn(
        binary: &Path,
        args: &[&str],
        env: &[(&str, &str)],
        cols: u16,
        rows: u16,
        link: Link,
    ) -> Walk {
        let size = Winsize { ws_row: rows, ws_col: cols, ws_xpixel: 0, ws_ypixel: 0 };
        let pty = rustix_openpty::openpty(None, Some(&size)).expect("openpty");
        let master = File::from(pty.controller);
        let stdio = || Stdio::from(pty.user.try_clone().expect("dup the pty"));
        let mut command = Command::new(binary);
        command
            .args(args)
            .env_clear()
            .envs(env.iter().copied())
            .stdin(stdio())
            .stdout(stdio())
            .stderr(stdio());
        own_session_on_stdin(&mut command);
        let child = command.spawn().expect("spawn the walk");
        drop(command);
        drop(pty.user);
        let start = Instant::now();
        let seen = Arc::new(Mutex::new(Seen::default()));
        let last_arrival = Arc::new(Mutex::new(start));
        let (up_tx, up_rx) = mpsc::channel::<(Instant, Vec<u8>)>();
        let (down_tx, down_rx) = mpsc::channel::<(Instant, Vec<u8>)>();
        let mut threads = Vec::new();

        // The reader: everything the walk writes, at once, into the unbounded queue.
        let mut input = master.try_clone().expect("dup the pty");
        threads.push(std::thread::spawn(move || {
            let mut buf = vec![0u8; 1 << 16];
            while let Ok(n) = input.read(&mut buf) {
                if n == 0 || down_tx.send((Instant::now(), buf[..n].to_vec())).is_err() {
                    break;
                }
            }
        }));

        // The link and the far terminal.
        let (seen_far, arrival, answers) = (Arc::clone(&seen), Arc::clone(&last_arrival), up_tx.clone());
        let lose_at = Arc::new(Mutex::new(Vec::<f64>::new()));
        let lose = Arc::clone(&lose_at);
        threads.push(std::thread::spawn(move || {
            let mut terminal = vt100::Parser::new(nz(rows), nz(cols), 0);
            let one_way = Duration::from_secs_f64(link.one_way);
            let mut free_at = Instant::now();
            let mut tail: Vec<u8> = Vec::new(); // the last bytes, for a query split across pieces
            while let Ok((read_at, bytes)) = down_rx.recv() {
                for piece in bytes.chunks(PIECE) {
                    let left =
                        free_at.max(read_at) + Duration::from_secs_f64(piece.len() as f64 / link.bytes_per_s);
                    free_at = left;
                    let arrives = left + one_way;
                    if let Some(wait) = arrives.checked_duration_since(Instant::now()) {
                        std::thread::sleep(wait);
                    }
                    let now = Instant::now();
                    terminal.process(piece);
                    tail.extend_from_slice(piece);
                    let queries = tail.windows(DA_QUERY.len()).filter(|w| *w == DA_QUERY).count();
                    let keep = tail.len().min(DA_QUERY.len() - 1);
                    let tail_start = tail.len() - keep;
                    // a query's last bytes kept in the tail must not be counted twice
                    let kept_query = tail[tail_start..].windows(DA_QUERY.len()).any(|w| w == DA_QUERY);
                    debug_assert!(!kept_query);
                    tail.drain(..tail_start);
                    let t = now.duration_since(start).as_secs_f64();
                    for _ in 0..queries {
                        let mut lose = lose.lock().unwrap_or_else(PoisonError::into_inner);
                        if let Some(i) = lose.iter().position(|&at| t >= at) {
                            lose.remove(i); // this one is lost
                        } else {
                            let _ = answers.send((now + one_way, DA_ANSWER.to_vec()));
                        }
                    }
                    let screen = terminal.screen();
                    let hud = screen.rows(0, cols).nth(usize::from(rows) - 1).unwrap_or_default();
                    let mut seen = seen_far.lock().unwrap_or_else(PoisonError::into_inner);
                    seen.bytes += piece.len() as u64;
                    seen.frames.extend(std::iter::repeat_n(t, queries));
                    if let Some(h) = hud_heading(&hud)
                        && seen.headings.last().is_none_or(|&(_, last)| last != h)
                    {
                        seen.headings.push((t, h));
                    }
                    *arrival.lock().unwrap_or_else(PoisonError::into_inner) = now;
                }
            }
        }));

        // The uplink: keys and answers written to the walk when they are due.
        let mut output = master;
        threads.push(std::thread::spawn(move || {
            let mut due: BinaryHeap<Due> = BinaryHeap::new();
            let mut seq = 0;
            loop {
                let next = due.peek().map(|d| d.at);
                let got = match next {
                    Some(at) => up_rx.recv_timeout(at.saturating_duration_since(Instant::now())),
                    None => up_rx.recv().map_err(|_| mpsc::RecvTimeoutError::Disconnected),
                };
                match got {
                    Ok((at, bytes)) => {
                        seq += 1;
                        due.push(Due { at, seq, bytes });
                    }
                    Err(mpsc::RecvTimeoutError::Timeout) => {}
                    Err(mpsc::RecvTimeoutError::Disconnected) if due.is_empty() => return,
                    Err(mpsc::RecvTimeoutError::Disconnected) => {
                        std::thread::sleep(
                            next.map_or(Duration::ZERO, |at| at.saturating_duration_since(Instant::now())),
                        );
                    }
                }
                while due.peek().is_some_and(|d| d.at <= Instant::now()) {
                    let d = due.pop().expect("peeked");
                    if output.write_all(&d.bytes).is_err() {
                        return;
                    }
                }
            }
        }));
        Walk { child, start, link, seen, uplink: Some(up_tx), threads, last_arrival, lose_at }
    }

    /// Seconds since the start.
    #[must_use]
    pub fn now(&self) -> f64 {
        self.start.elapsed().as_secs_f64()
    }

    /// Types `bytes` at the far end now: they reach the walk one way later.
    pub fn type_keys(&self, bytes: &[u8]) {
        let at = Instant::now() + Duration::from_secs_f64(self.link.one_way);
        if let Some(up) = &self.uplink {
            let _ = up.send((at, bytes.to_vec()));
        }
    }

    /// Waits until nothing has arrived at the far end for `quiet` seconds (at most `limit` seconds).
    /// Returns whether it got quiet.
    pub fn settle(&self, quiet: f64, limit: f64) -> bool {
        let deadline = Instant::now() + Duration::from_secs_f64(limit);
        loop {
            let last = *self.last_arrival.lock().unwrap_or_else(PoisonError::into_inner);
            if last.elapsed().as_secs_f64() >= quiet {
                return true;
            }
            if Instant::now() > deadline {
                return false;
            }
            std::thread::sleep(Duration::from_millis(10));
        }
    }

    /// Waits until the far screen's heading has not changed for `quiet` seconds (at most `limit`
    /// seconds; frames that change other things, such as the exit clock, may come meanwhile).
    pub fn settle_heading(&self, quiet: f64, limit: f64) {
        let deadline = self.now() + limit;
        loop {
            let last =
                self.seen.lock().unwrap_or_else(PoisonError::into_inner).headings.last().map(|&(t, _)| t);
            if self.now() - last.unwrap_or(0.0) >= quiet || self.now() > deadline {
                return;
            }
            std::thread::sleep(Duration::from_millis(10));
        }
    }

    /// Holds a key as `hold` says, from now, then waits until the far screen's heading has been still
    /// for `quiet` seconds (at most `limit`).
    pub fn hold(&self, hold: Hold, quiet: f64, limit: f64) -> (f64, f64) {
        let press = self.now();
        *self.lose_at.lock().unwrap_or_else(PoisonError::into_inner) =
            self.link.lost_answers.iter().map(|after| press + after).collect();
        self.type_keys(hold.key);
        let mut next = press + hold.repeat_delay;
        while next <= press + hold.hold {
            let wait = next - self.now();
            if wait > 0.0 {
                std::thread::sleep(Duration::from_secs_f64(wait));
            }
            self.type_keys(hold.key);
            next += hold.repeat_every;
        }
        let release = press + hold.hold;
        let wait = release - self.now();
        if wait > 0.0 {
            std::thread::sleep(Duration::from_secs_f64(wait));
        }
        self.settle_heading(quiet, limit);
        (press, release)
    }

    /// A copy of what the far terminal saw so far.
    #[must_use]
    pub fn seen(&self) -> Seen {
        let s = self.seen.lock().unwrap_or_else(PoisonError::into_inner);
        Seen { headings: s.headings.clone(), frames: s.frames.clone(), bytes: s.bytes }
    }

    /// Quits (`q`) and waits for the walk to end (kills it after `limit` seconds).
    pub fn quit(mut self, limit: f64) {
        self.type_keys(b"q");
        let deadline = Instant::now() + Duration::from_secs_f64(limit);
        while self.child.try_wait().ok().flatten().is_none() && Instant::now() < deadline {
            std::thread::sleep(Duration::from_millis(20));
        }
    }
}

impl Drop for Walk {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
        drop(self.uplink.take());
        for thread in self.threads.drain(..) {
            let _ = thread.join();
        }
    }
}

/// Starts the walk behind `link`, waits for its first picture to settle, holds `hold`, and reports.
#[must_use]
pub fn measure(
    binary: &Path,
    args: &[&str],
    env: &[(&str, &str)],
    cols: u16,
    rows: u16,
    link: Link,
    hold: Hold,
) -> Outcome {
    let walk = Walk::spawn(binary, args, env, cols, rows, link);
    // the first frame, then quiet (answers come back; nothing moves)
    let deadline = Instant::now() + Duration::from_secs(20);
    while walk.seen().headings.is_empty() && Instant::now() < deadline {
        std::thread::sleep(Duration::from_millis(20));
    }
    walk.settle(0.5, 10.0);
    // still for longer than the flow control's 2 s timeout, so a late last change is seen
    let (press, release) = walk.hold(hold, 3.0, 15.0);
    let seen = walk.seen();
    walk.quit(3.0);
    Outcome { press, release, seen }
}

/// Makes `command`'s child the leader of a session of its own whose controlling terminal is its
/// standard input (a pty's user side): what a program that opens `/dev/tty` needs.
pub fn own_session_on_stdin(command: &mut Command) {
    // SAFETY: runs in the forked child before exec and only makes two system calls (setsid, ioctl),
    // which are async-signal-safe; it allocates nothing and takes no locks.
    unsafe {
        command.pre_exec(|| {
            rustix::process::setsid()?;
            rustix::process::ioctl_tiocsctty(rustix::stdio::stdin())?;
            Ok(())
        });
    }
}
