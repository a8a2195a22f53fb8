//! The local walkthrough: a [`Session`] plus the terminal guard plus stdin and stdout — the one place
//! where the pure walk meets this process's terminal.
//!
//! ```text
//! stdin bytes ─▶ Session::feed        SIGWINCH / stop / exit signal ─▶ guard's wake-up pipe
//!        ╲                                         ╱
//!         poll(2) on both, until Session::next_wake ─▶ Session::frame ─▶ one write to stdout
//! ```
//!
//! Event-driven: while nothing moves it sleeps in `poll` and sends nothing at all. Local and served
//! play share one path: the bytes the terminal sends go through the same decoder either way. (Unix
//! only: elsewhere crossterm's reader would have to stand in for `poll` on stdin, and it hands out
//! decoded events, not bytes.)

use std::io;
use std::time::Instant;

use crate::cast::Recorder;
use crate::guard::{self, GuardOptions, TerminalGuard};
use mazewalk_term::input::Input;
use mazewalk_walk::Session;
use mazewalk_walk::flow::{LAST_QUERY, LastAnswer};

/// How a walk ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Ended {
    /// The player quit.
    Quit,
    /// A signal ended it (any of [`crate::guard::ending_signals`]); the terminal was restored.
    Signal(i32),
    /// The terminal hung up (its reads ended) without a SIGHUP.
    HangUp,
}

impl Ended {
    /// The signal the process should report having died of: its own, or SIGHUP for a hang-up (as
    /// if the terminal had sent one); `None` after a quit.
    #[must_use]
    pub fn signal(self) -> Option<i32> {
        match self {
            Ended::Quit => None,
            Ended::Signal(signal) => Some(signal),
            Ended::HangUp => Some(SIGHUP),
        }
    }
}

/// SIGHUP's number (1 on every Unix).
const SIGHUP: i32 = 1;

/// Runs `session` on this process's terminal until the player quits, a signal ends it or the
/// terminal hangs up. `clock` is the zero of the session's time (the instant its `App` was made at
/// time 0). With `ask_truecolor`, the terminal is asked whether it shows 24-bit colour before the
/// first frame ([`Session::ask_truecolor`]; its answer comes in with the keys). The terminal is
/// restored on return, on error, on panic, on every catchable signal that would end the process, and
/// around a stop (Ctrl-Z, SIGTSTP; taken back after SIGSTOP) (the guard).
///
/// With a `recorder` (`--record`), every byte written to the terminal goes into it as well (the
/// guard's [`tee_writes`](guard::tee_writes), from game mode on to game mode off), with each resize
/// seen and a marker when the colour depth changes; the caller flushes it ([`Recorder::finish`]).
/// `guard` says what game mode turns on, and whether the terminal has an alternate screen.
///
/// # Errors
/// The terminal could not be set up, read or written.
#[cfg(unix)]
pub fn run(
    session: &mut Session,
    clock: Instant,
    ask_truecolor: bool,
    recorder: Option<&Recorder>,
    guard: GuardOptions,
) -> io::Result<Ended> {
    use rustix::event::{PollFd, PollFlags, Timespec};

    // Declared before the terminal, so dropped after it: a restore on the way out is recorded too.
    let _teeing = recorder.map(|recorder| {
        let recorder = recorder.clone();
        guard::tee_writes(move |bytes| recorder.output(bytes))
    });
    let record_size = |cols, rows| {
        if let Some(recorder) = recorder {
            recorder.resize(cols, rows);
        }
    };
    let mut depth = session.color_depth();
    let mut terminal = TerminalGuard::enter(guard)?;
    // Cut short while the guard's keyboard query was answered: by a signal (the terminal restored
    // already), or a hang-up (nothing to restore but raw mode, and nothing to write to).
    if let Some(signal) = terminal.take_exit()? {
        return Ok(Ended::Signal(signal));
    }
    if terminal.input_ended() {
        let _ = terminal.restore();
        return Ok(Ended::HangUp);
    }
    session.app_mut().releases = terminal.enabled().reports_key_releases();
    if ask_truecolor {
        // after the guard's own keyboard query is answered (it reads that answer itself), before the
        // first frame, which paints over whatever a terminal that does not understand it shows
        let mut question = Vec::new();
        session.ask_truecolor(&mut question);
        terminal.write_frame(&question)?;
    }
    let (mut cols, mut rows) = guard::size()?;
    record_size(cols, rows);
    let now = || clock.elapsed().as_secs_f64();
    session.input(Input::Resize { cols, rows }, now());
    let typed_ahead = terminal.take_typed_ahead(); // keys typed as the walk started
    if !typed_ahead.is_empty() {
        session.feed(&typed_ahead, now());
    }
    let stdin = io::stdin();
    let mut buf = [0u8; 4096];
    let mut bytes = Vec::new();
    let ended = loop {
        if let Some(signal) = terminal.take_exit()? {
            break Ended::Signal(signal);
        }
        if terminal.take_resumed() {
            // Back from a stop: the screen was cleared, releases may have been missed, and the size
            // may have changed meanwhile.
            session.invalidate();
            (cols, rows) = (0, 0);
        }
        let winched = terminal.take_winched();
        let size = guard::size()?;
        if size != (cols, rows) {
            (cols, rows) = size;
            record_size(cols, rows);
            session.input(Input::Resize { cols, rows }, now());
        } else if winched {
            session.repaint(); // a SIGWINCH at the same size: paint everything again, as Ctrl-L
        }
        if session.take_suspend() {
            terminal.suspend()?; // Ctrl-Z; back here after `fg`
            continue;
        }
        if session.is_over() {
            // The answers to the last frames' queries, read before the restore: one arriving after
            // it would be echoed onto the shell's line (`^[[?62;22c`).
            drain_answers(&terminal, session, &stdin, &mut buf, now)?;
            break Ended::Quit;
        }
        if let Some(recorder) = recorder
            && session.color_depth() != depth
        {
            depth = session.color_depth(); // the terminal's answer raised it: marked before the repaint
            recorder.marker(&format!("color_depth {depth}"));
        }
        bytes.clear();
        let started = Instant::now();
        if session.frame(now(), &mut bytes) {
            session.frame_cost(started.elapsed().as_secs_f64()); // the HUD shows it next frame
            terminal.write_frame(&bytes)?;
        }

        // Sleep until input, a wake-up from the guard, or the session's next deadline.
        let timeout = session.next_wake(now()).map(|at| {
            let wait = (at - now()).max(0.0);
            Timespec { tv_sec: wait.trunc() as i64, tv_nsec: (wait.fract() * 1e9) as _ }
        });
        let wakeups = terminal.wakeups();
        let reading = !terminal.ending(); // else the guard's wake-up with the signal is all to wait for
        let mut fds = Vec::with_capacity(2);
        if reading {
            fds.push(PollFd::new(&stdin, PollFlags::IN));
        }
        if let Some(fd) = &wakeups {
            fds.push(PollFd::from_borrowed_fd(*fd, PollFlags::IN));
        }
        match rustix::event::poll(&mut fds, timeout.as_ref()) {
            Ok(_) | Err(rustix::io::Errno::INTR) => {}
            Err(err) => return Err(err.into()),
        }
        let input_ready = if reading { fds[0].revents() } else { PollFlags::empty() };
        drop(fds);
        terminal.drain_wakeups();
        if input_ready.intersects(PollFlags::IN | PollFlags::HUP | PollFlags::ERR) {
            match rustix::io::read(&stdin, &mut buf) {
                Ok(0) | Err(rustix::io::Errno::IO) => break Ended::HangUp,
                Ok(n) => session.feed(&buf[..n], now()),
                Err(rustix::io::Errno::INTR | rustix::io::Errno::AGAIN) => {}
                Err(err) => return Err(err.into()),
            }
        }
    };
    let restored = terminal.restore();
    if ended != Ended::HangUp {
        restored?; // a terminal that hung up cannot be written to: nothing to restore
    }
    Ok(ended)
}

/// How long a quitting walk waits at least for the terminal's answers to queries still in flight.
const DRAIN_SECONDS: f64 = 0.25;

/// How long it waits: twice the link's round trip (answers come a round trip after their queries),
/// at least [`DRAIN_SECONDS`], at most the flow control's [`ACK_TIMEOUT`](mazewalk_walk::flow::ACK_TIMEOUT),
/// after which a terminal counts as one that does not answer. Over a 0.6 s round trip, a quarter of a
/// second let the last answer land on the shell's line.
fn drain_seconds(round_trip: Option<f64>) -> f64 {
    (2.0 * round_trip.unwrap_or(0.0)).clamp(DRAIN_SECONDS, mazewalk_walk::flow::ACK_TIMEOUT)
}

/// Reads and decodes input until the terminal's answers to the frames' queries are all in, it hangs
/// up, or [`drain_seconds`] pass: when the terminal has answered a query before, until it answers
/// [`LAST_QUERY`], sent now (the frames' own count of answers is not enough: after the terminal
/// stopped reading for a while, the frames sent meanwhile were counted lost, and their answers,
/// arriving after the restore, were typed onto the shell's line, `^[[?62;22c`); else while frames
/// are counted in flight and the terminal is not known to be silent.
fn drain_answers(
    terminal: &TerminalGuard,
    session: &mut Session,
    stdin: &io::Stdin,
    buf: &mut [u8],
    now: impl Fn() -> f64,
) -> io::Result<()> {
    use rustix::event::{PollFd, PollFlags, Timespec};

    let deadline = now() + drain_seconds(session.flow().round_trip());
    let answers = session.flow().round_trip().is_some();
    if answers {
        terminal.write_frame(LAST_QUERY)?;
    }
    let (mut last, mut answered) = (LastAnswer::default(), false);
    let waiting = |session: &Session, answered: bool| {
        if answers { !answered } else { session.flow().in_flight() > 0 && !session.flow().silent() }
    };
    while waiting(session, answered) {
        let wait = deadline - now();
        if wait <= 0.0 {
            break;
        }
        let timeout = Timespec { tv_sec: 0, tv_nsec: (wait.min(0.999) * 1e9) as _ };
        let mut fds = [PollFd::new(stdin, PollFlags::IN)];
        match rustix::event::poll(&mut fds, Some(&timeout)) {
            Ok(0) => continue, // the deadline decides
            Ok(_) | Err(rustix::io::Errno::INTR) => {}
            Err(err) => return Err(err.into()),
        }
        match rustix::io::read(stdin, &mut *buf) {
            Ok(0) | Err(rustix::io::Errno::IO) => break,
            Ok(n) => {
                session.feed(&buf[..n], now());
                answered = last.read(&buf[..n]);
            }
            Err(rustix::io::Errno::INTR | rustix::io::Errno::AGAIN) => {}
            Err(err) => return Err(err.into()),
        }
    }
    Ok(())
}
