//! The terminal guard: puts the terminal into full-screen game mode and always puts it back.
//!
//! "Always" means: when the guard drops, when the program panics (a panic hook restores before the
//! message prints), when SIGTERM, SIGHUP (the SSH connection dropped) or SIGINT arrive (restore, then
//! tell the event loop, which returns so that `main` exits with 128 + signal number:
//! [`TerminalGuard::take_exit`]), and around a stop: the Ctrl-Z key ([`TerminalGuard::suspend`]) or
//! SIGTSTP from outside (`kill -TSTP`) restore, stop, and on SIGCONT enter game mode again
//! ([`TerminalGuard::take_resumed`] then tells the app to repaint everything). A stop that gives no
//! warning (SIGSTOP from outside: `kill -STOP`, a debugger) can restore nothing, and the shell may
//! reset the terminal's modes and write over the screen meanwhile: the SIGCONT that ends it takes the
//! terminal back (raw mode, game mode entered again) and asks for the same full repaint. (A terminal
//! that hangs up without SIGHUP is seen by the event loop itself: its reads end.)
//!
//! The event loop sleeps in `poll(2)` on its input and on [`TerminalGuard::wakeups`], a self-pipe
//! that SIGWINCH and the signal thread write to, so resizes, stops and exit signals wake it at once.
//!
//! All those paths share one idempotent restore, [`restore_terminal`], behind one global lock that
//! also serializes frame writes ([`TerminalGuard::write_frame`]): a signal can never cut a frame in
//! half and then leave the rest of it on the restored main screen. A stop holds that lock from the
//! restore until game mode is back, so no frame lands on the main screen meanwhile.
//!
//! No write to the terminal ever blocks in `write(2)` ([`write_tty`]): a terminal that stops reading
//! (a stalled SSH link, output paused by the emulator or multiplexer) leaves a write waiting in
//! `poll(2)`, which gives up when a signal comes that needs the lock (the rest of that frame is
//! dropped, and the screen repainted in full if the walk goes on), and a restore waits at most
//! [`RESTORE_WAIT`] for the terminal to take its bytes; the modes (`tcsetattr`, `TCSANOW`) come back
//! either way. A terminal left non-blocking (`O_NONBLOCK`, by another program) is waited for the same
//! way where it would say `EAGAIN`.
//!
//! The escape sequences are the pure [`mazewalk_term::modes`]' (a server sends the same ones to its
//! players); this module only writes them, and owns raw mode, the signals and the locks.
//!
//! Every byte it writes to the terminal can be copied, as written, to a recording
//! ([`tee_writes`]: `--record`), from whichever thread writes it.

use std::io::{self, Write};
use std::sync::atomic::{AtomicBool, AtomicI32, AtomicUsize, Ordering};
use std::sync::{Mutex, MutexGuard, Once, PoisonError, TryLockError};
use std::time::{Duration, Instant};

use crossterm::terminal;
use mazewalk_term::input::{Input, InputDecoder, MAX_SEQUENCE, Reply};
pub use mazewalk_term::modes::Enabled;
use mazewalk_term::modes::{enter_sequence, reenter_sequence, restore_sequence_for};

/// What [`TerminalGuard::enter`] should turn on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct GuardOptions {
    /// Capture the mouse (drag to look around). Stops the terminal's own text selection.
    pub mouse: bool,
    /// Report focus changes, so the app can release held keys when the window loses focus.
    pub focus_events: bool,
    /// Ask for the kitty keyboard protocol (key releases and repeats) if the terminal supports it.
    pub keyboard_enhancement: bool,
    /// Restore the terminal and end the walk on SIGTERM, SIGHUP and SIGINT; restore, stop and come
    /// back on SIGTSTP; take the terminal back on SIGCONT
    /// after a SIGSTOP (Unix; installed once per process).
    pub handle_signals: bool,
    /// The terminal has an alternate screen (terminfo's `smcup`); without one (the Linux console,
    /// `vt100`), leaving game mode — at the end, around a stop — clears the screen and homes the
    /// cursor ([`restore_sequence_for`]).
    pub alternate_screen: bool,
}

impl Default for GuardOptions {
    /// Everything on.
    fn default() -> Self {
        GuardOptions {
            mouse: true,
            focus_events: true,
            keyboard_enhancement: true,
            handle_signals: true,
            alternate_screen: true,
        }
    }
}

/// What is enabled on the terminal right now (`None`: the terminal is in its normal state).
/// Held while writing a frame and while restoring, so the two never interleave.
static ACTIVE: Mutex<Option<Enabled>> = Mutex::new(None);

/// Raw mode is on and nothing else, while [`ACTIVE`] is `None`: the keyboard query is out and its
/// answer awaited ([`TerminalGuard::enter`]), without the lock, so that a signal meanwhile restores
/// (raw mode off: nothing else was entered) and ends the walk at once. Set and cleared under the lock.
static RAW_ONLY: AtomicBool = AtomicBool::new(false);

/// Whether the terminal has an alternate screen ([`GuardOptions::alternate_screen`]): what every
/// restore, from any thread, writes ([`restore_sequence_for`]). Set when game mode is entered.
static ALTERNATE_SCREEN: AtomicBool = AtomicBool::new(true);

/// The bytes that leave game mode with `enabled` on this terminal ([`ALTERNATE_SCREEN`]).
fn restore_bytes(enabled: Enabled) -> String {
    restore_sequence_for(enabled, ALTERNATE_SCREEN.load(Ordering::SeqCst))
}

/// Set when game mode was entered again after a stop, until the app takes it
/// ([`TerminalGuard::take_resumed`]). Set and read under [`ACTIVE`]'s lock.
static RESUMED: AtomicBool = AtomicBool::new(false);

/// A SIGCONT arrived that the signal thread has not answered yet ([`continue_locked`]). Set by the
/// signal handler itself (see [`install_signal_handler`]), answered under [`ACTIVE`]'s lock. While
/// set, the screen may not be ours any more: [`TerminalGuard::write_frame`] writes nothing.
static CONTINUED: AtomicBool = AtomicBool::new(false);

/// How many threads (the signal thread) wait for [`ACTIVE`]'s lock ([`locked_for_signal`]): a write
/// under the lock that has to wait for the terminal gives up while any do ([`write_tty`]).
static LOCK_WANTED: AtomicUsize = AtomicUsize::new(0);

/// The most a restore waits for a terminal that does not take its bytes (it stopped reading):
/// then the restore's bytes are dropped, and only the modes (raw mode off) come back. A terminal
/// that reads takes the few dozen bytes at once.
pub const RESTORE_WAIT: Duration = Duration::from_millis(250);

/// Set by the signal handler itself when a signal that ends the walk arrives ([`ending_signals`]),
/// before the signal thread answers it: a stop that ends sees it without waiting for the thread,
/// which waits for the stop's lock.
static ENDING: AtomicBool = AtomicBool::new(false);

/// Set (under [`ACTIVE`]'s lock) when our own stop ([`stop_and_continue`]) is over: its SIGCONT is
/// answered already, game mode is back.
#[cfg(unix)]
static OWN_STOP: AtomicBool = AtomicBool::new(false);

/// Set by the signal handler itself on SIGXFSZ (a write passed the file-size limit), which is caught
/// only so that it does not end the process: the write fails with `EFBIG` and says so. Nothing reads it.
static FILE_TOO_LARGE: AtomicBool = AtomicBool::new(false);

/// Set by the signal handler itself on SIGWINCH, until the app takes it
/// ([`TerminalGuard::take_winched`]): a resize, or a nudge at the same size (`kill -WINCH`, a
/// multiplexer's redraw), after which the app paints everything again.
static WINCHED: AtomicBool = AtomicBool::new(false);

/// [`TerminalGuard::write_frame`] dropped a frame while a SIGCONT was unanswered: the screen lacks it
/// even if game mode needs no taking back. Set and read under [`ACTIVE`]'s lock.
static FRAME_HELD: AtomicBool = AtomicBool::new(false);

/// Set by the signal thread once it has restored the terminal for a signal that ends the walk (any
/// of [`ending_signals`]): the signal's number, or [`CANNOT_CONTINUE`]; 0 while none came. The
/// event loop reads it ([`TerminalGuard::take_exit`]) and returns; `main` picks the exit status.
static EXIT: AtomicI32 = AtomicI32::new(0);

/// [`EXIT`]'s value when game mode could not come back after a stop (the terminal is gone?).
const CANNOT_CONTINUE: i32 = -1;

/// The self-pipe that wakes the event loop: SIGWINCH writes to it (in the signal handler), and the
/// signal thread does after anything the loop must see (a stop ended, an exit signal).
#[cfg(unix)]
static WAKE: std::sync::OnceLock<(std::os::unix::net::UnixStream, std::os::unix::net::UnixStream)> =
    std::sync::OnceLock::new();

/// Wakes the event loop (a full pipe is awake already).
fn wake() {
    #[cfg(unix)]
    if let Some((_, writer)) = WAKE.get() {
        let _ = (&*writer).write(&[1]);
    }
}

/// Game mode was entered again: a full repaint is due (which also makes up for any held frame).
fn resumed_locked() {
    RESUMED.store(true, Ordering::SeqCst);
    FRAME_HELD.store(false, Ordering::SeqCst);
}

/// Where a copy of every byte written to the terminal goes ([`tee_writes`]), if anywhere. Locked
/// only inside [`ACTIVE`]'s lock, by the writes.
type Tee = Box<dyn FnMut(&[u8]) + Send>;
static TEE: Mutex<Option<Tee>> = Mutex::new(None);

/// What [`TerminalGuard::enter`] asks the terminal before game mode: the kitty keyboard flags query
/// ([`KEYBOARD_FLAGS_QUERY`](mazewalk_term::modes::KEYBOARD_FLAGS_QUERY)), then device attributes
/// ([`DEVICE_ATTRIBUTES_QUERY`](mazewalk_term::modes::DEVICE_ATTRIBUTES_QUERY)), which every terminal
/// answers, and only after the first if it answers that ([`QueryAnswer`]).
const KEYBOARD_QUERY: &[u8] = b"\x1b[?u\x1b[c";

/// Hands `bytes`, just written to the terminal, to the [`tee_writes`] copy if there is one.
fn tee(bytes: &[u8]) {
    if let Some(tee) = TEE.lock().unwrap_or_else(PoisonError::into_inner).as_mut() {
        tee(bytes);
    }
}

/// Until the returned [`Teeing`] drops, every byte the guard writes to the terminal — game mode on,
/// the keyboard query, frames, game mode off, from any thread (a signal's restore too) — is also
/// handed to `copy`, in the order written, right after it was written (`--record`).
pub fn tee_writes(copy: impl FnMut(&[u8]) + Send + 'static) -> Teeing {
    let _active = active(); // ordered with the writes
    *TEE.lock().unwrap_or_else(PoisonError::into_inner) = Some(Box::new(copy));
    Teeing { _private: () }
}

/// Copies the terminal's bytes while it lives ([`tee_writes`]); dropping it stops (and drops the copy).
#[derive(Debug)]
#[must_use = "the copy stops when this drops"]
pub struct Teeing {
    _private: (),
}

impl Drop for Teeing {
    fn drop(&mut self) {
        let _active = active();
        let copy = TEE.lock().unwrap_or_else(PoisonError::into_inner).take();
        drop(copy);
    }
}

/// The global state, whether or not a panic poisoned the lock (the state is a plain value, always valid).
fn active() -> MutexGuard<'static, Option<Enabled>> {
    ACTIVE.lock().unwrap_or_else(PoisonError::into_inner)
}

/// Restores the terminal if a guard has it in game mode; does nothing otherwise. Idempotent, callable
/// from any thread (the signal thread, the panic hook, `Drop`).
///
/// The restore sequence is waited for at most [`RESTORE_WAIT`]; raw mode goes off regardless.
///
/// # Errors
/// Writing the restore sequence or leaving raw mode failed (e.g. the terminal is gone after SIGHUP),
/// or the terminal did not take the sequence in time (`TimedOut`). The state is marked restored
/// anyway: there is nothing more to try.
pub fn restore_terminal() -> io::Result<()> {
    restore_locked(&mut active())
}

fn restore_locked(active: &mut Option<Enabled>) -> io::Result<()> {
    let Some(enabled) = active.take() else {
        // Raw mode alone, for the keyboard query's answer: the query needs no undoing.
        return if RAW_ONLY.swap(false, Ordering::SeqCst) { terminal::disable_raw_mode() } else { Ok(()) };
    };
    let written = write_restore(enabled);
    let raw_off = terminal::disable_raw_mode(); // (`TCSANOW`: not waiting for the output to drain)
    written.and(raw_off)
}

/// Writes the bytes that leave game mode with `enabled`, waiting at most [`RESTORE_WAIT`] for the
/// terminal to take them.
///
/// # Errors
/// The write failed, or the terminal took not all of them in time (`TimedOut`).
fn write_restore(enabled: Enabled) -> io::Result<()> {
    let restore = restore_bytes(enabled);
    match write_tty(restore.as_bytes(), Wait::Until(Instant::now() + RESTORE_WAIT))? {
        true => Ok(()),
        false => Err(io::Error::new(
            io::ErrorKind::TimedOut,
            "the terminal took no output: its screen may still be the walk's",
        )),
    }
}

/// How long [`write_tty`] waits for a terminal that does not take the bytes.
#[derive(Clone, Copy, Debug)]
enum Wait {
    /// Until a signal that needs [`ACTIVE`]'s lock comes ([`ENDING`], [`LOCK_WANTED`]): for frames
    /// and game mode's sequences, whose writer holds the lock.
    ForSignal,
    /// Until then, whatever comes: for the restore, which a signal's own path writes.
    Until(Instant),
}

/// How often, at least, a write waiting for the terminal ([`Wait::ForSignal`]) looks whether a
/// signal came (in nanoseconds): 0.1 s. The signal thread wakes it at once ([`locked_for_signal`]),
/// but not while that thread writes itself (game mode again after a SIGCONT).
const SIGNAL_SLICE_NANOS: u32 = 100_000_000;

/// Writes `bytes` to the terminal (stdout), each write handed on to the [`tee_writes`] copy as it is
/// made, without ever blocking in `write(2)`: a write the terminal cannot take now (`EAGAIN`) waits
/// in `poll(2)` for room, as `wait` says. Returns whether all were written (`false`: it gave up, part
/// of `bytes` may be out).
///
/// Each `write(2)` is made with `O_NONBLOCK` set on the terminal's open file description for just
/// that call, then put back as it was: the description is the shell's too (and its other jobs'), so
/// it stays as they left it but for those moments.
///
/// # Errors
/// A write or `poll` failed (`EIO`: the terminal is gone).
#[cfg(unix)]
fn write_tty(mut bytes: &[u8], wait: Wait) -> io::Result<bool> {
    use rustix::event::{PollFd, PollFlags, Timespec};
    use rustix::io::Errno;
    use std::os::fd::AsFd as _;

    let stdout = io::stdout();
    let fd = stdout.as_fd();
    while !bytes.is_empty() {
        match write_nonblocking(fd, bytes) {
            Ok(n) => {
                tee(&bytes[..n]);
                bytes = &bytes[n..];
                continue;
            }
            Err(Errno::INTR) => continue,
            Err(Errno::AGAIN) => {}
            Err(err) => return Err(err.into()),
        }
        // Only a write that has to wait gives up: one the terminal takes is made whole.
        if matches!(wait, Wait::ForSignal) && signal_waits() {
            return Ok(false);
        }
        let timeout = match wait {
            // (in slices: a signal that comes while the signal thread itself writes wakes nobody)
            Wait::ForSignal => Some(Timespec { tv_sec: 0, tv_nsec: SIGNAL_SLICE_NANOS.into() }),
            Wait::Until(deadline) => {
                let left = deadline.saturating_duration_since(Instant::now());
                if left.is_zero() {
                    return Ok(false);
                }
                Some(Timespec { tv_sec: left.as_secs() as i64, tv_nsec: left.subsec_nanos().into() })
            }
        };
        let mut fds = Vec::with_capacity(2);
        fds.push(PollFd::new(&fd, PollFlags::OUT));
        if let (Wait::ForSignal, Some((reader, _))) = (wait, WAKE.get()) {
            fds.push(PollFd::new(reader, PollFlags::IN)); // the signal thread wakes it (`wake`)
        }
        match rustix::event::poll(&mut fds, timeout.as_ref()) {
            Ok(_) | Err(Errno::INTR) => {}
            Err(err) => return Err(err.into()),
        }
        if fds.get(1).is_some_and(|fd| !fd.revents().is_empty()) {
            // (the event loop looks at every flag when this returns: the wake-up is not lost)
            drain_wake_pipe();
        }
    }
    Ok(true)
}

/// The walk runs on Unix only: elsewhere, a plain write.
#[cfg(not(unix))]
fn write_tty(bytes: &[u8], _: Wait) -> io::Result<bool> {
    let mut stdout = io::stdout().lock();
    stdout.write_all(bytes)?;
    tee(bytes);
    stdout.flush().map(|()| true)
}

/// One `write(2)` of `bytes` to `fd` that does not block: `O_NONBLOCK` set for the call unless it
/// is set already, then put back.
#[cfg(unix)]
fn write_nonblocking(fd: std::os::fd::BorrowedFd<'_>, bytes: &[u8]) -> rustix::io::Result<usize> {
    use rustix::fs::{OFlags, fcntl_getfl, fcntl_setfl};
    let flags = fcntl_getfl(fd)?;
    if flags.contains(OFlags::NONBLOCK) {
        return rustix::io::write(fd, bytes);
    }
    fcntl_setfl(fd, flags | OFlags::NONBLOCK)?;
    let written = rustix::io::write(fd, bytes);
    fcntl_setfl(fd, flags)?;
    written
}

/// Whether a write under [`ACTIVE`]'s lock should give up waiting for the terminal: a signal that
/// ends the walk came ([`ENDING`]), or the signal thread waits for the lock ([`LOCK_WANTED`]).
fn signal_waits() -> bool {
    ENDING.load(Ordering::SeqCst) || LOCK_WANTED.load(Ordering::SeqCst) > 0
}

/// [`ACTIVE`]'s lock, for the signal thread: it says it waits ([`LOCK_WANTED`]) and wakes the
/// writer, so that a write waiting for a terminal that stopped reading gives up the lock at once.
fn locked_for_signal() -> MutexGuard<'static, Option<Enabled>> {
    LOCK_WANTED.fetch_add(1, Ordering::SeqCst);
    wake();
    let active = active();
    LOCK_WANTED.fetch_sub(1, Ordering::SeqCst);
    active
}

/// Raw mode, alternate screen and friends for as long as it lives; see the [module docs](self).
///
/// ```no_run
/// use mazewalk::guard::{GuardOptions, TerminalGuard};
///
/// let guard = TerminalGuard::enter(GuardOptions::default())?;
/// if !guard.enabled().reports_key_releases() {
///     // time out held keys instead
/// }
/// guard.write_frame(b"\x1b[Hhello")?;
/// drop(guard); // the terminal is back to normal
/// # Ok::<(), std::io::Error>(())
/// ```
#[derive(Debug)]
pub struct TerminalGuard {
    enabled: Enabled,
    /// Keys typed while the keyboard query was awaited, as the terminal sent them ([`QueryAnswer`]).
    typed_ahead: Vec<u8>,
    /// The terminal's input ended while the keyboard query was awaited ([`input_ended`](Self::input_ended)).
    input_ended: bool,
}

impl TerminalGuard {
    /// Enters game mode with `options`; returns the guard, whose [`enabled`](Self::enabled) tells what
    /// the terminal accepted. Installs the panic hook (and the signal thread) on first use.
    ///
    /// With [`GuardOptions::keyboard_enhancement`], the terminal is first asked in raw mode whether
    /// it speaks the kitty keyboard protocol ([`KEYBOARD_QUERY`]), and its answer awaited for at most
    /// [`ACK_TIMEOUT`](mazewalk_walk::flow::ACK_TIMEOUT) ([`await_answer`]), without the lock: a signal
    /// that ends the walk meanwhile restores raw mode and ends the wait at once; then game mode is not
    /// entered, and [`take_exit`](Self::take_exit) tells the signal at once. Nor is it when the
    /// terminal's input ends meanwhile (it hung up): [`input_ended`](Self::input_ended). A stop
    /// meanwhile gives the terminal back, and raw mode comes back with the continue.
    ///
    /// # Errors
    /// Another guard is active (`AlreadyExists`), the signal handler could not be installed, or the
    /// terminal refused raw mode or a write (then whatever was enabled is restored first).
    pub fn enter(options: GuardOptions) -> io::Result<TerminalGuard> {
        install_panic_hook();
        if options.handle_signals {
            install_signal_handler()?;
        }
        let mut active = active();
        if active.is_some() || RAW_ONLY.load(Ordering::SeqCst) {
            return Err(already_in_game_mode());
        }
        terminal::enable_raw_mode()?;
        let mut answer = QueryAnswer::default();
        if options.keyboard_enhancement && cfg!(unix) {
            // Raw mode: the answer must not wait for a line's end, nor be echoed.
            RAW_ONLY.store(true, Ordering::SeqCst);
            write_locked(&mut active, KEYBOARD_QUERY)?;
            drop(active);
            let input_ended = await_answer(&mut answer, options.handle_signals);
            active = self::active();
            if input_ended || ENDING.load(Ordering::SeqCst) || EXIT.load(Ordering::SeqCst) != 0 {
                // No game mode; raw mode goes with the signal thread's restore, or the guard's drop.
                drop(active);
                signal_answered();
                return Ok(TerminalGuard {
                    enabled: Enabled::default(),
                    typed_ahead: Vec::new(),
                    input_ended,
                });
            }
            if active.is_some() {
                return Err(already_in_game_mode()); // another guard, after a stop turned raw mode off
            }
            if !RAW_ONLY.swap(false, Ordering::SeqCst) {
                terminal::enable_raw_mode()?; // a stop meanwhile could not take it back
            }
        }
        let (keyboard_enhancement, typed_ahead) = answer.finish();
        let enabled = Enabled {
            mouse: options.mouse,
            focus_events: options.focus_events,
            keyboard_enhancement: options.keyboard_enhancement && keyboard_enhancement,
        };
        RESUMED.store(false, Ordering::SeqCst);
        ALTERNATE_SCREEN.store(options.alternate_screen, Ordering::SeqCst);
        enter_locked(&mut active, enabled, &enter_sequence(enabled))?;
        Ok(TerminalGuard { enabled, typed_ahead, input_ended: false })
    }

    /// The keys typed while the terminal's answer to the keyboard query was awaited (a player who
    /// starts walking before the first frame), as the bytes the terminal sent for them (at most
    /// [`TYPED_AHEAD_MAX`]): for the walk's own decoder, once.
    pub fn take_typed_ahead(&mut self) -> Vec<u8> {
        std::mem::take(&mut self.typed_ahead)
    }

    /// Whether the terminal's input ended (it hung up) while the keyboard query was awaited: then
    /// game mode was not entered, and the walk ends as when its reads end later.
    #[must_use]
    pub fn input_ended(&self) -> bool {
        self.input_ended
    }

    /// What is enabled (e.g. whether key releases are reported).
    #[must_use]
    pub fn enabled(&self) -> Enabled {
        self.enabled
    }

    /// Writes one encoded frame to the terminal and flushes, unless the terminal was restored meanwhile
    /// (a signal arrived), or game mode came back after a stop that the app has not taken yet
    /// ([`take_resumed`](Self::take_resumed)): that frame was encoded for the screen before the stop;
    /// or a SIGCONT has not been answered yet: the terminal may be someone else's until then (it is
    /// taken back, or the frame made up for, with a full repaint). Then nothing is written. A terminal
    /// that does not take the frame now is waited for ([`write_tty`]) until a signal needs the lock:
    /// then the rest of the frame is dropped, and the signal ends the walk or its stop or continue
    /// repaints everything.
    ///
    /// # Errors
    /// The write failed (the terminal is gone).
    pub fn write_frame(&self, bytes: &[u8]) -> io::Result<()> {
        let active = active();
        if active.is_none() || bytes.is_empty() || RESUMED.load(Ordering::SeqCst) {
            return Ok(());
        }
        if CONTINUED.load(Ordering::SeqCst) {
            FRAME_HELD.store(true, Ordering::SeqCst);
            return Ok(());
        }
        if !write_tty(bytes, Wait::ForSignal)? {
            // A signal needs the lock: it ends the walk, or its stop or continue repaints in full.
            FRAME_HELD.store(true, Ordering::SeqCst);
        }
        Ok(())
    }

    /// Restores the terminal now (as `Drop` would); idempotent.
    ///
    /// # Errors
    /// See [`restore_terminal`].
    pub fn restore(&mut self) -> io::Result<()> {
        restore_terminal()
    }

    /// Ctrl-Z: restores the terminal, stops the process as SIGTSTP would and, once continued
    /// (SIGCONT), enters game mode again; then [`take_resumed`](Self::take_resumed) is true. SIGTSTP
    /// from outside takes the same path, on the signal thread. Elsewhere than Unix there is no job
    /// control: this only makes `take_resumed` true (a full repaint).
    ///
    /// # Errors
    /// Restoring, stopping or re-entering failed.
    pub fn suspend(&mut self) -> io::Result<()> {
        stop_and_continue(active())
    }

    /// Whether game mode was entered again after a stop (the Ctrl-Z key, SIGTSTP, or SIGSTOP then
    /// SIGCONT from outside) since the last call. If so, the screen was cleared and its size may have
    /// changed: invalidate the encoder, re-read the [`size`] and draw a full frame. Until then
    /// [`write_frame`](Self::write_frame) writes nothing.
    #[must_use]
    pub fn take_resumed(&self) -> bool {
        let _active = active(); // ordered with a stop in progress
        RESUMED.swap(false, Ordering::SeqCst)
    }

    /// The signal that ended the walk, once the signal thread has restored the terminal for it (any
    /// of [`ending_signals`]): the event loop should return, and the process exit with
    /// [`exit_code_for_signal`].
    ///
    /// # Errors
    /// Game mode could not be entered again after a stop (the terminal is gone?); it was restored.
    pub fn take_exit(&self) -> io::Result<Option<i32>> {
        match EXIT.swap(0, Ordering::SeqCst) {
            0 => Ok(None),
            CANNOT_CONTINUE => Err(io::Error::other("cannot continue after a stop")),
            signal => Ok(Some(signal)),
        }
    }

    /// Whether a SIGWINCH arrived since the last call: at the same [`size`] too, the app paints
    /// everything again (as a resize would: cheap, and the screen may have been written over).
    #[must_use]
    pub fn take_winched(&self) -> bool {
        WINCHED.swap(false, Ordering::SeqCst)
    }

    /// Whether a signal that ends the walk has arrived, perhaps before the signal thread has restored
    /// the terminal for it and set [`take_exit`](Self::take_exit). Then read no more input: in the
    /// background (`kill %1` continues a stopped walk there) a read would stop the process (SIGTTIN)
    /// with the signal unanswered. The [`wakeups`](Self::wakeups) come all the same.
    #[must_use]
    pub fn ending(&self) -> bool {
        ENDING.load(Ordering::SeqCst)
    }

    /// A file descriptor that becomes readable when the event loop must look at the guard: a
    /// resize (SIGWINCH), a stop that ended ([`take_resumed`](Self::take_resumed)), a signal that
    /// ends the walk ([`take_exit`](Self::take_exit)). Poll it beside the input; read it empty with
    /// [`drain_wakeups`](Self::drain_wakeups). `None` without signal handling.
    #[cfg(unix)]
    #[must_use]
    pub fn wakeups(&self) -> Option<std::os::fd::BorrowedFd<'static>> {
        use std::os::fd::AsFd;
        WAKE.get().map(|(reader, _)| reader.as_fd())
    }

    /// Empties the [`wakeups`](Self::wakeups) pipe.
    pub fn drain_wakeups(&self) {
        drain_wake_pipe();
    }
}

/// Empties the wake-up pipe ([`TerminalGuard::wakeups`]).
fn drain_wake_pipe() {
    #[cfg(unix)]
    if let Some((reader, _)) = WAKE.get() {
        use std::io::Read;
        let mut buf = [0u8; 64];
        while matches!((&*reader).read(&mut buf), Ok(n) if n > 0) {}
    }
}

/// Once a signal that ends the walk has arrived ([`ENDING`]), waits for the signal thread to answer
/// it ([`EXIT`] set, the terminal restored), as it does within moments (at most a quarter of a
/// second is waited): then [`TerminalGuard::take_exit`] tells the signal.
fn signal_answered() {
    let deadline = std::time::Instant::now() + std::time::Duration::from_millis(250);
    while ENDING.load(Ordering::SeqCst)
        && EXIT.load(Ordering::SeqCst) == 0
        && std::time::Instant::now() < deadline
    {
        std::thread::sleep(std::time::Duration::from_millis(1));
    }
}

/// [`TerminalGuard::enter`]'s error while another guard is active.
fn already_in_game_mode() -> io::Error {
    io::Error::new(io::ErrorKind::AlreadyExists, "the terminal is already in game mode")
}

/// A stop, from the Ctrl-Z key or SIGTSTP: restores the terminal if it is in game mode, stops the
/// process unless nothing would ever continue it ([`stopping_is_safe`]) and, once continued, enters
/// game mode again and sets [`RESUMED`] (raw mode alone, while the keyboard query's answer is
/// awaited: [`RAW_ONLY`], set again). All under the lock: no frame is written half before and half
/// after, nor on the main screen. If the shell continues us in the background (`bg`), re-entering raw
/// mode stops us again (SIGTTOU, default action) before anything is written, until `fg`. The SIGCONT
/// that ended the stop is marked answered ([`OWN_STOP`]): the signal thread leaves game mode alone.
#[cfg(unix)]
fn stop_and_continue(mut active: MutexGuard<'static, Option<Enabled>>) -> io::Result<()> {
    let (enabled, raw_only) = (*active, RAW_ONLY.load(Ordering::SeqCst));
    match restore_locked(&mut active) {
        // A terminal that reads nothing did not take the restore: raw mode is off all the same.
        Err(e) if e.kind() != io::ErrorKind::TimedOut => return Err(e),
        _ => {}
    }
    if stopping_is_safe() {
        // SIGTSTP's default action, emulated with SIGSTOP (signal-hook handles SIGTSTP now); returns
        // after SIGCONT.
        signal_hook::low_level::emulate_default_handler(signal_hook::consts::SIGTSTP)?;
        OWN_STOP.store(true, Ordering::SeqCst);
        if stopped_for_fg()? {
            return Ok(()); // the terminal stays restored; the signal thread ends the walk
        }
    }
    if let Some(enabled) = enabled {
        terminal::enable_raw_mode()?;
        enter_locked(&mut active, enabled, &enter_sequence(enabled))?;
        resumed_locked();
    } else if raw_only {
        terminal::enable_raw_mode()?; // the keyboard query's answer is still awaited
        RAW_ONLY.store(true, Ordering::SeqCst);
    }
    Ok(())
}

/// Answers a SIGCONT ([`CONTINUED`]), on the signal thread. The one that ended our own stop
/// ([`OWN_STOP`]) needs nothing more (but a repaint, if a frame was held meanwhile); nor does one
/// while not in game mode (but raw mode, set again while the keyboard query's answer is awaited:
/// [`RAW_ONLY`]). Any other ended a stop that restored nothing, an uncatchable SIGSTOP from
/// outside, or no stop at all: the job-control shell may have reset the terminal's modes and written
/// over the screen, so raw mode is set again, game mode re-entered ([`reenter_sequence`]) and
/// [`RESUMED`] set. All under the lock, as a stop: no frame is written half before and half after.
/// In the background (`bg`), setting raw mode stops us (SIGTTOU) before anything is written, until
/// `fg`. Returns whether the app must repaint everything.
#[cfg(unix)]
fn continue_locked(active: &mut Option<Enabled>) -> io::Result<bool> {
    if !CONTINUED.swap(false, Ordering::SeqCst) {
        return Ok(false);
    }
    let own = OWN_STOP.swap(false, Ordering::SeqCst);
    let Some(enabled) = *active else {
        if !own && RAW_ONLY.load(Ordering::SeqCst) {
            // Stopped while the keyboard query's answer was awaited: raw mode again, as below.
            terminal::disable_raw_mode()?;
            terminal::enable_raw_mode()?;
        }
        return Ok(false);
    };
    if own {
        let held = FRAME_HELD.swap(false, Ordering::SeqCst);
        RESUMED.fetch_or(held, Ordering::SeqCst);
        return Ok(held);
    }
    if in_background() {
        // Continued in the background (`kill -CONT`, `bg`) after a stop that restored nothing: the
        // shell has the terminal, its prompt on our alternate screen with mouse reporting on. Give
        // both back (a write is allowed from the background; setting modes is not), then wait
        // stopped for `fg` as a real SIGTTOU would make us; game mode comes back below.
        let _ = write_restore(enabled);
        if stopped_for_fg()? {
            *active = None; // restored above; the signal thread ends the walk
            return Ok(false);
        }
        CONTINUED.store(false, Ordering::SeqCst);
        terminal::disable_raw_mode()?;
        terminal::enable_raw_mode()?;
        enter_locked(active, enabled, &enter_sequence(enabled))?;
        resumed_locked();
        return Ok(true);
    }
    // crossterm skips enabling raw mode while it believes it on: off (back to the modes from before
    // game mode, which stay the ones to restore at the end), then on.
    terminal::disable_raw_mode()?;
    terminal::enable_raw_mode()?;
    // A SIGCONT meanwhile (`fg`, which let the raw mode through after a stop in the background) is
    // answered by this same re-entering.
    CONTINUED.store(false, Ordering::SeqCst);
    enter_locked(active, enabled, &reenter_sequence(enabled))?;
    resumed_locked();
    Ok(true)
}

/// After a stop, while continued in the background: stops again until `fg`, as taking the terminal
/// back would (SIGTTOU), unless a signal that ends the walk comes; then returns `true` and the
/// terminal is left alone. `kill %1` on the stopped walk sends SIGTERM and then SIGCONT: it wakes in
/// the background, and stopping again would leave the SIGTERM unanswered until `fg`. The signal's
/// handler may run on another thread a moment after this one wakes (on a loaded machine, tens of
/// milliseconds later): a wait of up to a quarter of a second lets it land.
#[cfg(unix)]
fn stopped_for_fg() -> io::Result<bool> {
    let ending = || {
        let deadline = std::time::Instant::now() + std::time::Duration::from_millis(250);
        while !ENDING.load(Ordering::SeqCst) && std::time::Instant::now() < deadline {
            std::thread::sleep(std::time::Duration::from_millis(2));
        }
        ENDING.load(Ordering::SeqCst)
    };
    while in_background() && stopping_is_safe() {
        if ending() {
            return Ok(true);
        }
        signal_hook::low_level::emulate_default_handler(signal_hook::consts::SIGTSTP)?;
    }
    Ok(ENDING.load(Ordering::SeqCst))
}

/// Whether our process group is in the background of the terminal (stdin): another group is its
/// foreground. A terminal that is not our controlling one cannot tell: not in the background.
#[cfg(unix)]
fn in_background() -> bool {
    nix::unistd::tcgetpgrp(io::stdin()).is_ok_and(|foreground| foreground != nix::unistd::getpgrp())
}

/// Whether the terminal (stdin) has hung up: `poll(2)` says so at once.
#[cfg(unix)]
fn terminal_hung_up() -> bool {
    use rustix::event::{PollFd, PollFlags, Timespec};
    let stdin = io::stdin();
    let mut fds = [PollFd::new(&stdin, PollFlags::IN)];
    let now = Timespec { tv_sec: 0, tv_nsec: 0 };
    rustix::event::poll(&mut fds, Some(&now)).is_ok()
        && fds[0].revents().intersects(PollFlags::HUP | PollFlags::ERR | PollFlags::NVAL)
}

#[cfg(not(unix))]
fn stop_and_continue(_active: MutexGuard<'static, Option<Enabled>>) -> io::Result<()> {
    resumed_locked(); // nothing to stop: just a full repaint
    Ok(())
}

/// Whether a job-control shell may continue us after a stop. The kernel discards SIGTSTP's default
/// stop in an orphaned process group (no shell of its session would ever send SIGCONT), but SIGSTOP,
/// which emulates it here, always stops; so this mirrors the kernel's rule for the usual cases: our
/// parent is in our session (a shell, or `cargo run` under one) and our process group is not the
/// session leader's. Under `xterm -e`, `setsid`, `ssh -t host mazewalk` or a tmux command we lead our
/// own session: no stop, as the kernel would do for a real SIGTSTP.
///
/// Ids are as seen from our PID namespace: one outside it reads as 0 (a container or CI sandbox whose
/// session leader is outside). Then the session still compares equal between us and our parent, but a
/// parent outside (ppid 0) or a process group led from outside (pgrp 0) says nothing: no stop.
#[cfg(unix)]
fn stopping_is_safe() -> bool {
    use nix::unistd::{getpgrp, getppid, getsid};
    let outside = |id: nix::unistd::Pid| id.as_raw() <= 0;
    let (parent, group) = (getppid(), getpgrp());
    if outside(parent) || outside(group) {
        return false;
    }
    let Ok(session) = getsid(None) else { return false };
    getsid(Some(parent)).ok() == Some(session) && group != session
}

impl Drop for TerminalGuard {
    fn drop(&mut self) {
        let _ = restore_terminal(); // nothing better to do with an error while dropping
    }
}

/// With raw mode on: marks `enabled` active, then writes `sequence`, which enters it (restoring on
/// failure).
fn enter_locked(active: &mut Option<Enabled>, enabled: Enabled, sequence: &str) -> io::Result<()> {
    // Marked before writing, so a failure half-way is restored in full.
    *active = Some(enabled);
    write_locked(active, sequence.as_bytes())
}

/// Writes `bytes` to the terminal, under the lock (`active`), and flushes; on failure, restores.
/// A signal that needs the lock while the terminal takes nothing cuts the write short
/// ([`write_tty`]): its restore, or its stop, writes the whole of game mode's sequences again where
/// needed; so does its continue, even the one that ends our own stop (no longer counted as ours:
/// [`OWN_STOP`], cleared), which would otherwise leave game mode half entered.
fn write_locked(active: &mut Option<Enabled>, bytes: &[u8]) -> io::Result<()> {
    match write_tty(bytes, Wait::ForSignal) {
        Ok(true) => {}
        #[cfg(unix)]
        Ok(false) => OWN_STOP.store(false, Ordering::SeqCst),
        #[cfg(not(unix))]
        Ok(false) => {}
        Err(e) => {
            let _ = restore_locked(active);
            return Err(e);
        }
    }
    Ok(())
}

/// How long a [`Patient`] writer waits, in all, for an output that cannot take its bytes now.
const PATIENCE: Duration = Duration::from_secs(2);

/// A writer for the lines said after the walk (an error, a recording that stopped) that waits for
/// an output left non-blocking (`O_NONBLOCK`: the terminal's open file description is the shell's,
/// and another program may have left it so) where it says `EAGAIN`, `poll(2)` telling when it has
/// room, for [`PATIENCE`] in all: the line reaches the screen rather than being lost. On an output
/// that blocks, it writes as the writer inside would.
#[derive(Debug)]
pub struct Patient<W> {
    inner: W,
    deadline: Option<Instant>,
}

impl<W> Patient<W> {
    /// `inner`, patient.
    #[must_use]
    pub fn new(inner: W) -> Patient<W> {
        Patient { inner, deadline: None }
    }
}

#[cfg(unix)]
impl<W: Write + std::os::fd::AsFd> Write for Patient<W> {
    fn write(&mut self, bytes: &[u8]) -> io::Result<usize> {
        use rustix::event::{PollFd, PollFlags, Timespec};
        loop {
            match self.inner.write(bytes) {
                Err(e) if e.kind() == io::ErrorKind::WouldBlock => {}
                written => return written,
            }
            let deadline = *self.deadline.get_or_insert_with(|| Instant::now() + PATIENCE);
            let left = deadline.saturating_duration_since(Instant::now());
            if left.is_zero() {
                return Err(io::ErrorKind::WouldBlock.into());
            }
            let timeout = Timespec { tv_sec: left.as_secs() as i64, tv_nsec: left.subsec_nanos().into() };
            let mut fds = [PollFd::new(&self.inner, PollFlags::OUT)];
            match rustix::event::poll(&mut fds, Some(&timeout)) {
                Ok(_) | Err(rustix::io::Errno::INTR) => {}
                Err(err) => return Err(err.into()),
            }
        }
    }

    fn flush(&mut self) -> io::Result<()> {
        self.inner.flush()
    }
}

/// Elsewhere than Unix, as the writer inside.
#[cfg(not(unix))]
impl<W: Write> Write for Patient<W> {
    fn write(&mut self, bytes: &[u8]) -> io::Result<usize> {
        self.inner.write(bytes)
    }

    fn flush(&mut self) -> io::Result<()> {
        self.inner.flush()
    }
}

/// The terminal size in (columns, rows).
///
/// # Errors
/// There is no terminal to ask.
pub fn size() -> io::Result<(u16, u16)> {
    terminal::size()
}

/// Restores the terminal before the panic message prints (else it would vanish with the alternate
/// screen, in raw mode). Installed once, chained to the previous hook.
fn install_panic_hook() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            match ACTIVE.try_lock() {
                Ok(mut active) => drop(restore_locked(&mut active)),
                Err(TryLockError::Poisoned(p)) => drop(restore_locked(&mut p.into_inner())),
                // Held by another thread (restoring already) or by this one mid-write: the guard's
                // `Drop` restores during unwinding, once the lock is released.
                Err(TryLockError::WouldBlock) => {}
            }
            previous(info);
        }));
    });
}

/// Exit status for death by `signal`, as shells report it.
#[must_use]
pub fn exit_code_for_signal(signal: i32) -> i32 {
    128 + signal
}

/// The signals that end the walk (restore, then exit with 128 + the signal's number): every signal
/// whose default action ends the process and that can be caught — SIGHUP, SIGINT, SIGQUIT, SIGABRT,
/// SIGUSR1, SIGUSR2, SIGALRM, SIGTERM, SIGSTKFLT, SIGXCPU, SIGVTALRM, SIGPROF, SIGIO, SIGPWR (those
/// that exist here) and the real-time signals SIGRTMIN..=SIGRTMAX — but the faults a program raises
/// on itself (SIGSEGV, SIGBUS, SIGILL, SIGFPE, SIGTRAP, SIGSYS: a handler that returns would fault
/// again), SIGPIPE, which Rust programs ignore (a write to a closed pipe fails instead), and SIGXFSZ,
/// which the walk catches for the same reason ([`install_signal_handler`]): a write past the
/// file-size limit (`ulimit -f`) fails with `EFBIG`, and `--record` stops while the walk goes on.
#[cfg(unix)]
#[must_use]
pub fn ending_signals() -> Vec<i32> {
    use signal_hook::consts::*;
    let mut signals = vec![SIGHUP, SIGINT, SIGQUIT, SIGABRT, SIGUSR1, SIGUSR2, SIGALRM, SIGTERM];
    signals.extend([SIGXCPU, SIGVTALRM, SIGPROF, SIGIO]);
    #[cfg(any(target_os = "linux", target_os = "android"))]
    signals.extend([libc::SIGSTKFLT, libc::SIGPWR]);
    #[cfg(any(target_os = "linux", target_os = "android"))]
    signals.extend(libc::SIGRTMIN()..=libc::SIGRTMAX());
    signals
}

/// Every ending signal ([`ending_signals`]): restore the terminal, then set [`EXIT`] and wake the event loop, which
/// returns (`main` exits with 128 + signo). SIGTSTP (`kill -TSTP`; the Ctrl-Z key arrives as a key in
/// raw mode): the same stop as [`TerminalGuard::suspend`], then a wake-up, so that the event loop sees
/// [`TerminalGuard::take_resumed`] even when idle. SIGCONT: [`continue_locked`] (game mode back after a
/// SIGSTOP from outside), then the same wake-up if a repaint is due. SIGWINCH writes to the wake-up
/// pipe from the handler itself. A thread waits on `signal_hook::iterator::Signals`, so all else runs
/// in normal (not signal-handler) context; only [`CONTINUED`] is set in the handler itself, registered
/// first so that it is set by the time the thread hears of the SIGCONT. Linux runs that handler on the
/// main thread whenever it can, before the thread goes on with its own code, so no frame gets out
/// between a SIGCONT and the flag; where a kernel picks another thread, one frame might, and the full
/// repaint that follows covers it.
///
/// SIGXFSZ is caught and does nothing ([`FILE_TOO_LARGE`]): a write past the file-size limit then
/// fails with `EFBIG` instead of the signal ending the process (red-team pass 8: `--record` under
/// `ulimit -f` ended the walk with exit 153, its cast cut mid-line).
///
/// SIGTTIN and SIGTTOU keep their default action (stop): the kernel sends them when a background job
/// touches the terminal, and we only run in the background after a stop (`bg`), when re-entering game
/// mode, before anything is written. Catching them would turn that into a spin: the kernel re-sends
/// SIGTTOU on every restarted `tcsetattr`, and the thread that would handle it is the one retrying.
#[cfg(unix)]
fn install_signal_handler() -> io::Result<()> {
    use signal_hook::consts::{SIGCONT, SIGHUP, SIGTSTP, SIGWINCH};
    static INSTALLED: Mutex<bool> = Mutex::new(false);
    let mut installed = INSTALLED.lock().unwrap_or_else(PoisonError::into_inner);
    if *installed {
        return Ok(());
    }
    let (reader, writer) = std::os::unix::net::UnixStream::pair()?;
    reader.set_nonblocking(true)?;
    writer.set_nonblocking(true)?;
    signal_hook::flag::register(SIGWINCH, &WINCHED)?; // before the wake-up: set when the loop looks
    signal_hook::low_level::pipe::register(SIGWINCH, writer.try_clone()?)?;
    let _ = WAKE.set((reader, writer));
    signal_hook::flag::register(signal_hook::consts::SIGXFSZ, &FILE_TOO_LARGE)?;
    // Before the iterator's own handler: actions run in the order registered.
    signal_hook::flag::register(SIGCONT, &CONTINUED)?;
    for signal in ending_signals() {
        signal_hook::flag::register(signal, &ENDING)?;
    }
    let mut signals =
        signal_hook::iterator::Signals::new(ending_signals().into_iter().chain([SIGTSTP, SIGCONT]))?;
    std::thread::Builder::new().name("mazewalk-signals".into()).spawn(move || {
        for signal in signals.forever() {
            if signal == SIGTSTP || signal == SIGCONT {
                let repaint = if signal == SIGTSTP {
                    stop_and_continue(locked_for_signal()).map(|()| true)
                } else {
                    // (the lock is released at the end of this statement)
                    continue_locked(&mut locked_for_signal())
                };
                match repaint {
                    Ok(true) => wake(),
                    Ok(false) => {}
                    Err(err) => {
                        // Game mode could not come back (the terminal is gone?): restore and end.
                        let _ = restore_locked(&mut locked_for_signal());
                        // A hang-up sends SIGHUP and SIGCONT together, and the terminal is then gone:
                        // it ends as a hang-up, whichever of the two the thread answers first (a
                        // SIGHUP not answered yet stores itself on its turn; none is overwritten).
                        let hung_up = err.raw_os_error() == Some(rustix::io::Errno::IO.raw_os_error())
                            || terminal_hung_up();
                        if !ENDING.load(Ordering::SeqCst) {
                            let exit = if hung_up { SIGHUP } else { CANNOT_CONTINUE };
                            let _ = EXIT.compare_exchange(0, exit, Ordering::SeqCst, Ordering::SeqCst);
                        }
                        wake();
                    }
                }
                continue;
            }
            // Restored first; no frame is written after it (`write_frame` sees the terminal restored).
            let _ = restore_locked(&mut locked_for_signal());
            EXIT.store(signal, Ordering::SeqCst);
            wake();
        }
    })?;
    *installed = true;
    Ok(())
}

#[cfg(not(unix))]
fn install_signal_handler() -> io::Result<()> {
    Ok(()) // no POSIX signals; crossterm reports Ctrl-C as a key in raw mode
}

/// The most bytes typed while the keyboard query's answer is awaited that the walk gets
/// ([`TerminalGuard::take_typed_ahead`]): hundreds of keys. Input past it is simply dropped (not
/// counted), from the first chunk that would not fit until the answer: a flood (a paste into a
/// terminal without bracketed paste, a held key) costs no memory, and the keys kept are the first
/// ones, in order.
const TYPED_AHEAD_MAX: usize = 4096;

/// The terminal's answer to [`KEYBOARD_QUERY`], read out of its input, and the rest of that input (keys
/// typed meanwhile) kept as the very bytes the terminal sent, for the walk's own decoder: each key
/// then means what it means after the first frame (Alt-↑ is `ESC [ 1 ; 3 A`, not Esc then ↑). The
/// answers are told by that same decoder ([`Reply::KeyboardFlags`], [`Reply::DeviceAttributes`]);
/// an answer is a CSI sequence, so its bytes are those from the last ESC on. Pure: bytes in.
#[derive(Debug, Default)]
struct QueryAnswer {
    decoder: InputDecoder,
    inputs: Vec<Input>,
    /// The kitty flags came: the terminal speaks the protocol.
    kitty: bool,
    /// The device attributes came: the answer is whole; the rest is typed ahead.
    done: bool,
    /// The bytes from the last ESC on, held until known not to be an answer; dropped once longer
    /// than the decoder keeps an unfinished sequence ([`MAX_SEQUENCE`]).
    held: Vec<u8>,
    /// The typed-ahead bytes kept, at most [`TYPED_AHEAD_MAX`].
    typed: Vec<u8>,
    /// [`TYPED_AHEAD_MAX`] was reached: the rest is dropped.
    full: bool,
}

impl QueryAnswer {
    /// Reads `bytes`, the next the terminal sent.
    fn feed(&mut self, bytes: &[u8]) {
        for (i, &byte) in bytes.iter().enumerate() {
            if self.done {
                self.keep_held();
                self.keep(&bytes[i..]);
                return;
            }
            if byte == 0x1B {
                self.keep_held();
            }
            if self.held.is_empty() && byte != 0x1B {
                self.keep(&[byte]);
            } else {
                self.held.push(byte);
                if self.held.len() > MAX_SEQUENCE {
                    self.held.clear(); // dropped whole, as the decoder drops it: no answer, no key
                }
            }
            self.inputs.clear();
            self.decoder.feed(&[byte], 0.0, &mut self.inputs); // (no pause is ever taken)
            match self.inputs[..] {
                [Input::Reply(Reply::KeyboardFlags(_))] => self.kitty = true,
                [Input::Reply(Reply::DeviceAttributes)] => self.done = true,
                _ => continue,
            }
            self.held.clear(); // the answer's bytes
        }
    }

    /// Whether the whole answer came (the device attributes).
    fn done(&self) -> bool {
        self.done
    }

    /// Whether the terminal speaks the kitty keyboard protocol, and the typed-ahead bytes.
    fn finish(mut self) -> (bool, Vec<u8>) {
        self.keep_held();
        (self.kitty, self.typed)
    }

    fn keep_held(&mut self) {
        let held = std::mem::take(&mut self.held);
        self.keep(&held);
        self.held = held;
        self.held.clear();
    }

    fn keep(&mut self, bytes: &[u8]) {
        self.full |= self.typed.len() + bytes.len() > TYPED_AHEAD_MAX;
        if !self.full {
            self.typed.extend_from_slice(bytes);
        }
    }
}

/// Reads the terminal's input (stdin) into `answer` until the whole answer came, or
/// [`ACK_TIMEOUT`](mazewalk_walk::flow::ACK_TIMEOUT) passed (a terminal that answers no queries), or
/// a signal that ends the walk came (`signals`: the signal thread is installed; it has restored the
/// terminal by the time it wakes this wait). Returns whether the input ended (end of file, a hang-up,
/// an error): no more waiting then, and nothing more to read. With the walk's own reader: `poll(2)` on
/// stdin and the wake-up pipe, then a `read` that cannot block.
#[cfg(unix)]
fn await_answer(answer: &mut QueryAnswer, signals: bool) -> bool {
    use rustix::event::{PollFd, PollFlags, Timespec};
    use rustix::io::Errno;

    let deadline = Instant::now() + Duration::from_secs_f64(mazewalk_walk::flow::ACK_TIMEOUT);
    let stdin = io::stdin();
    let wake = WAKE.get().filter(|_| signals).map(|(reader, _)| reader);
    let mut buf = [0u8; 4096];
    while !answer.done() && !ENDING.load(Ordering::SeqCst) {
        let left = deadline.saturating_duration_since(Instant::now());
        if left.is_zero() {
            break;
        }
        let timeout = Timespec { tv_sec: left.as_secs() as i64, tv_nsec: left.subsec_nanos().into() };
        let mut fds = Vec::with_capacity(2);
        fds.push(PollFd::new(&stdin, PollFlags::IN));
        if let Some(reader) = wake {
            fds.push(PollFd::new(reader, PollFlags::IN));
        }
        match rustix::event::poll(&mut fds, Some(&timeout)) {
            Ok(_) | Err(Errno::INTR) => {}
            Err(_) => return true,
        }
        let ready = fds[0].revents();
        if fds.get(1).is_some_and(|fd| !fd.revents().is_empty()) {
            drain_wake_pipe(); // a resize (seen later through its flag), or the signal seen above
        }
        drop(fds);
        if ready.intersects(PollFlags::HUP | PollFlags::ERR | PollFlags::NVAL) {
            return true; // hung up: whatever it sent last is no answer to wait for
        }
        if ready.contains(PollFlags::IN) {
            match rustix::io::read(&stdin, &mut buf) {
                Ok(0) => return true,
                Ok(n) => answer.feed(&buf[..n]),
                Err(Errno::INTR | Errno::AGAIN) => {}
                Err(_) => return true,
            }
        }
    }
    false
}

/// The walk runs on Unix only: no answer is awaited elsewhere.
#[cfg(not(unix))]
fn await_answer(_: &mut QueryAnswer, _: bool) -> bool {
    false
}

#[cfg(test)]
mod tests {
    use super::*;
    use mazewalk_term::modes::restore_sequence;
    use proptest::prelude::*;

    /// What the walk's decoder makes of `bytes`, fed at once.
    fn decoded(bytes: &[u8]) -> Vec<Input> {
        let mut out = Vec::new();
        InputDecoder::new().feed(bytes, 0.0, &mut out);
        out
    }

    /// The answer read from `chunks`: (kitty, done, typed ahead).
    fn answer(chunks: &[&[u8]]) -> (bool, bool, Vec<u8>) {
        let mut answer = QueryAnswer::default();
        chunks.iter().for_each(|chunk| answer.feed(chunk));
        let done = answer.done();
        let (kitty, typed) = answer.finish();
        (kitty, done, typed)
    }

    #[test]
    fn the_query_is_the_flags_then_device_attributes() {
        use mazewalk_term::modes::{DEVICE_ATTRIBUTES_QUERY, KEYBOARD_FLAGS_QUERY};
        assert_eq!(KEYBOARD_QUERY, [KEYBOARD_FLAGS_QUERY, DEVICE_ATTRIBUTES_QUERY].concat());
    }

    /// The answers are taken out; whatever was typed around them stays, byte for byte (red-team
    /// pass 7, finding 6: Alt-↑ stays `ESC [ 1 ; 3 A`, which the decoder reads as Alt-↑, not Esc).
    #[test]
    fn the_answer_is_read_and_the_keys_around_it_kept_as_sent() {
        // (what the terminal sent, in reads; the kitty flags came; the answer is whole; typed ahead)
        type Case = (&'static [&'static [u8]], bool, bool, &'static [u8]);
        let cases: [Case; 6] = [
            (&[b"\x1b[?1u\x1b[?62;22c"], true, true, b""),
            (&[b"\x1b[?62;22c"], false, true, b""),
            (&[b"w\x1b[1;3Ax\x1b[?0u\xc3\xa9\x1b[?62;22cy\x1b[A"], true, true, b"w\x1b[1;3Ax\xc3\xa9y\x1b[A"),
            // split anywhere, even inside the answers
            (&[b"w\x1b", b"[1;3", b"A\x1b[?", b"1", b"u\x1b[?62;2", b"2c", b"q"], true, true, b"w\x1b[1;3Aq"),
            // an unfinished sequence typed before the answer: kept, the answer still read
            (&[b"\x1b[", b"\x1b[?1u\x1b[?62c"], true, true, b"\x1b["),
            // no device attributes (yet): not done, and the flags alone tell the protocol
            (&[b"s\x1b[?1u"], true, false, b"s"),
        ];
        for (chunks, kitty, done, typed) in cases {
            assert_eq!(answer(chunks), (kitty, done, typed.to_vec()), "{chunks:?}");
        }
        // What the walk reads from Alt-↑ typed ahead: Alt-↑ (and no Esc, which quits).
        let (_, _, typed) = answer(&[b"\x1b[1;3A\x1b[?62;22c"]);
        let alt = mazewalk_term::input::Modifiers { alt: true, ..mazewalk_term::input::Modifiers::NONE };
        let up = Input::Key {
            key: mazewalk_term::input::Key::Up,
            phase: mazewalk_term::input::KeyPhase::Press,
            modifiers: alt,
        };
        assert_eq!(decoded(&typed), [up]);
    }

    /// Inside a paste everything is the paste's, answers too: the wait ends at its deadline.
    #[test]
    fn answers_inside_a_paste_are_not_answers() {
        let (kitty, done, typed) = answer(&[b"\x1b[200~text\x1b[?1u\x1b[?62;22c"]);
        assert!(!kitty && !done);
        assert_eq!(typed, b"\x1b[200~text\x1b[?1u\x1b[?62;22c");
    }

    /// Red-team pass 7, finding 7: a flood typed while the answer is awaited keeps at most
    /// [`TYPED_AHEAD_MAX`] bytes, the first ones, whole keys only; the answer after it is still read.
    #[test]
    fn typed_ahead_input_is_kept_up_to_a_bound() {
        let flood = b"u\x1b[A".repeat(10_000);
        let (kitty, done, typed) = answer(&[&flood, b"\x1b[?1u", b"w", b"\x1b[?62;22c", b"x"]);
        assert!(kitty && done);
        // The first whole keys (a cut inside `ESC [ A` would end in ESC or `[`), nothing after the cut.
        let whole = flood.starts_with(&typed) && matches!(typed.last(), Some(b'u' | b'A'));
        assert!(whole && typed.len() > TYPED_AHEAD_MAX - 4, "{} bytes kept", typed.len());
        let (_, _, typed) = answer(&[&[b'u'; 3 * TYPED_AHEAD_MAX], b"\x1b[?62;22c"]);
        assert_eq!(typed.len(), TYPED_AHEAD_MAX);
        // An endless sequence is dropped where the decoder drops it; what follows is read afresh.
        let mut long = b"\x1b[".to_vec();
        long.extend([b'1'; MAX_SEQUENCE + 100]);
        let (kitty, done, typed) = answer(&[&long, b"\x1b[?1u\x1b[?62c"]);
        assert!(kitty && done);
        assert_eq!(decoded(&typed), decoded(&long)); // the same keys: the `1`s after the cut
        assert!(typed == long[MAX_SEQUENCE + 1..], "{} bytes kept", typed.len());
    }

    /// Whole keys of many kinds, for [`typed_ahead_reads_as_the_keys_typed`].
    fn arb_key() -> impl Strategy<Value = &'static [u8]> {
        proptest::sample::select(vec![
            &b"w"[..],
            "é".as_bytes(),
            b"\x1b[A",
            b"\x1b[1;3A",
            b"\x1b[5;3~",
            b"\x1bw",
            b"\x1bOA",
            b"\x03",
            b"\r",
            b"\x1b[<0;10;5M",
            b"\x1b[I",
            b"\x1b[119;1:3u",
        ])
    }

    proptest! {
        #![proptest_config(mazewalk_testkit::config())]

        /// Whatever keys come before, between and after the answers, in whatever reads: the walk's
        /// decoder reads the same keys from the typed-ahead bytes as from everything the terminal
        /// sent, but the answers; which say whether the protocol is spoken.
        #[test]
        fn typed_ahead_reads_as_the_keys_typed(
            keys in proptest::collection::vec(arb_key(), 0..40),
            kitty_at in proptest::option::of(0usize..40),
            da_after in 0usize..40,
            cuts in proptest::collection::vec(1usize..16, 1..60),
        ) {
            let kitty_at = kitty_at.map(|at| at.min(keys.len()));
            let da_at = (kitty_at.unwrap_or(0) + da_after).min(keys.len());
            let mut sent = Vec::new();
            for (i, key) in keys.iter().enumerate().chain([(keys.len(), &&b""[..])]) {
                if kitty_at == Some(i) {
                    sent.extend_from_slice(b"\x1b[?1u");
                }
                if da_at == i {
                    sent.extend_from_slice(b"\x1b[?62;22c");
                }
                sent.extend_from_slice(key);
            }
            let mut chunks = Vec::new();
            let mut rest = &sent[..];
            for cut in cuts.iter().cycle() {
                if rest.is_empty() {
                    break;
                }
                let (chunk, tail) = rest.split_at((*cut).min(rest.len()));
                chunks.push(chunk);
                rest = tail;
            }
            let (kitty, done, typed) = answer(&chunks);
            prop_assert!(done);
            prop_assert_eq!(kitty, kitty_at.is_some());
            let keys_sent: Vec<_> = decoded(&sent).into_iter().filter(|i| !matches!(i, Input::Reply(_))).collect();
            prop_assert_eq!(decoded(&typed), keys_sent);
        }
    }

    /// The modes' hand-written bytes are crossterm's (the commands this guard used to write).
    #[test]
    fn the_mode_sequences_are_crossterms_commands() {
        use crossterm::Command;
        use crossterm::{cursor, event, style, terminal};
        fn ansi(commands: &[&dyn Fn(&mut String)]) -> String {
            let mut s = String::new();
            commands.iter().for_each(|c| c(&mut s));
            s
        }
        let flags = event::KeyboardEnhancementFlags::DISAMBIGUATE_ESCAPE_CODES
            | event::KeyboardEnhancementFlags::REPORT_EVENT_TYPES;
        let enter = ansi(&[
            &|s| terminal::EnterAlternateScreen.write_ansi(s).unwrap(),
            &|s| cursor::Hide.write_ansi(s).unwrap(),
            &|s| event::EnableBracketedPaste.write_ansi(s).unwrap(),
            &|s| event::EnableMouseCapture.write_ansi(s).unwrap(),
            &|s| event::EnableFocusChange.write_ansi(s).unwrap(),
            &|s| event::PushKeyboardEnhancementFlags(flags).write_ansi(s).unwrap(),
        ]);
        assert_eq!(enter_sequence(Enabled::ALL), enter);
        let restore = ansi(&[
            &|s| s.push_str("\x1b[?2026l"),
            &|s| event::PopKeyboardEnhancementFlags.write_ansi(s).unwrap(),
            &|s| event::DisableMouseCapture.write_ansi(s).unwrap(),
            &|s| event::DisableFocusChange.write_ansi(s).unwrap(),
            &|s| event::DisableBracketedPaste.write_ansi(s).unwrap(),
            &|s| cursor::Show.write_ansi(s).unwrap(),
            &|s| style::ResetColor.write_ansi(s).unwrap(),
            &|s| terminal::LeaveAlternateScreen.write_ansi(s).unwrap(),
        ]);
        assert_eq!(restore_sequence(Enabled::ALL), restore);
    }

    #[test]
    fn restoring_an_inactive_terminal_does_nothing() {
        // No guard is active in tests (no tty): the shared restore path is a no-op, twice.
        assert!(active().is_none());
        restore_terminal().unwrap();
        restore_terminal().unwrap();
    }

    /// Red-team pass 8, finding 5: on an output left non-blocking and full, a line said after the
    /// walk was lost (`EAGAIN`); a patient writer waits until the reader makes room.
    #[cfg(unix)]
    #[test]
    fn a_patient_writer_waits_for_a_full_non_blocking_output() {
        use std::io::Read as _;
        let (writer, mut reader) = std::os::unix::net::UnixStream::pair().unwrap();
        writer.set_nonblocking(true).unwrap();
        let mut filled = 0usize;
        loop {
            match (&writer).write(&[b'x'; 4096]) {
                Ok(n) => filled += n,
                Err(e) if e.kind() == io::ErrorKind::WouldBlock => break,
                Err(e) => panic!("{e}"),
            }
        }
        let line = b"mazewalk: the line after the walk\n";
        let plain = (&writer).write(line);
        assert_eq!(plain.map_err(|e| e.kind()).err(), Some(io::ErrorKind::WouldBlock), "not full");
        let drain = std::thread::spawn(move || {
            std::thread::sleep(Duration::from_millis(50)); // (the line is written only after this)
            let mut all = Vec::new();
            reader.read_to_end(&mut all).unwrap();
            all
        });
        Patient::new(&writer).write_all(line).expect("the patient writer waits for room");
        drop(writer);
        let all = drain.join().unwrap();
        assert_eq!(all.len(), filled + line.len());
        assert!(all.ends_with(line));
    }

    #[test]
    fn signals_exit_as_shells_report_them() {
        assert_eq!(exit_code_for_signal(1), 129); // SIGHUP
        assert_eq!(exit_code_for_signal(2), 130); // SIGINT
        assert_eq!(exit_code_for_signal(15), 143); // SIGTERM
    }
}
