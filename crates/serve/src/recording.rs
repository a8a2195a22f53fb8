//! `mazewalk serve --record-dir DIR`: each player's session written as an asciicast v2 file
//! ([`mazewalk_walk::cast`]) — exactly the bytes its terminal was sent over the SSH channel (game
//! mode on, the questions, every frame, the goodbye), resizes as `"r"` events, a raised colour depth
//! as a `"m"` marker, the size and colour depth in the header. Opt-in by the host, and the player is
//! told: its HUD says `recorded` for as long as it is.
//!
//! Off the players' tasks: a player's task hands each write to a bounded channel ([`Tap`]) and a
//! thread of the recording's own writes the file (flushed whenever it has caught up, so a cast is
//! whole up to the last write even if the server is killed). A channel that is full (more than
//! [`QUEUED_EVENTS`] writes or [`QUEUED_BYTES`] bytes waiting: the disk is slower than the game) is
//! never waited on: the write is dropped, counted, and the recording stops there, so that a cast
//! never has a gap in it (a gap would replay as a wrong screen).
//!
//! Bounded, whatever the players do:
//! - a file ends at `max_bytes` (`--record-max-bytes`): the first event that would pass it is not
//!   written, nor any after it, so the file is whole lines of valid asciicast;
//! - the directory holds at most `max_total` bytes (`--record-max-total`) and `max_files`
//!   (`--record-max-files`, [`MAX_FILES`] unless told) files of ours. A recording starts only if
//!   every recording in progress, each counted at its cap, fits under `max_total` (so those in
//!   progress can always be given room), fewer than [`MAX_RECORDING`] are in progress (a thread
//!   each), fewer than `max_per_address` (`--record-max-per-address`) from the player's address
//!   group, and the casts finished and in progress number fewer than `max_files`; otherwise the
//!   newcomer is not recorded, and that is counted (a full count is also said in the log, once
//!   each time it fills). Finished casts are deleted, oldest first, only for bytes actually
//!   written: each recording claims its bytes written, rounded up to [`STEP`], and the oldest
//!   finished casts go when the finished ones and the claims no longer fit (checked as each
//!   recording passes its claim). Each make-room that deletes says so in one log line.
//!   (Before, a newcomer's whole cap was paid for at once by deleting finished casts: 16 idle
//!   connections from one address deleted a whole archive.)
//! - the count deletes nothing (red-team pass 7): a session that logs in and quits leaves a cast
//!   of 2 KB, 8 of them a second from one address, so a count that made room by deleting the
//!   oldest casts let one stranger wipe every other player's recordings in 21 minutes while
//!   writing 17 MB. Deleting only the casts of the address group holding the most would fail to
//!   the same stranger spread over many IPv6 /64s (then a regular player's group holds the most),
//!   and not keeping short sessions only raises the price (a stranger holds each session longer);
//!   refusing newcomers while the count is full is the one rule under which nobody's cheap
//!   sessions delete anyone's cast. The price is that recording stops until the host removes
//!   casts, which it is told. A walk of 6 s at 120×40 already writes 656 KB (README), six times
//!   the 107 KB a cast that 1 GiB over 10,000 leaves, so with players who play, the bytes make
//!   room long before the count is full.
//!
//! The directory is listed (each of our casts' name and size) at the first recording and then at
//! most once a [`RESCAN`], not at each join: between listings the count and sizes are kept here
//! (a recording ended is added), so casts another server wrote or the host removed are seen at
//! the next listing (at once if DIR itself was removed and is made again).
//!
//! File names cannot be steered by a client: `mazewalk-UNIXTIME-PID-N-NAME.cast`, NAME being the SSH
//! user name cleaned as everywhere ([`player_name`]: letters, digits, `-`, `_`, `.`, at most 16),
//! created new (never over a file or through a link), readable by the host's user only. Only files
//! named so are ever counted or deleted. Spectators are not recorded: they see only what a
//! player sees, and that player's own cast has it.
//!
//! Every failure (a file that cannot be made, a write, a full channel, a refusal, a cap reached) is
//! counted in `/metrics` and said in the log at most once a recording; a newcomer not recorded for
//! want of room, or for a cast that could not be made, is said only the first time since a
//! recording last started (as a full count is); none ends a player's game.

use std::collections::{HashMap, VecDeque};
use std::fs::{File, OpenOptions};
use std::io::{self, BufWriter};
use std::net::IpAddr;
use std::os::unix::fs::OpenOptionsExt;
use std::path::PathBuf;
use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex, PoisonError};
use std::time::{Duration, Instant};

use tokio::sync::mpsc;
use tracing::{info, warn};

use crate::identity::player_name;
use crate::metrics::Metrics;
use mazewalk_term::frame::ColorDepth;
use mazewalk_walk::cast::{CastWriter, Header};

/// Writes waiting for a recording's thread, at most.
pub const QUEUED_EVENTS: usize = 256;
/// Bytes waiting for a recording's thread, at most.
pub const QUEUED_BYTES: usize = 4 << 20;
/// Recordings in progress at once, at most (each has a thread).
pub const MAX_RECORDING: usize = 256;
/// Our files kept in the directory, at most, unless told (`--record-max-files`): when there are
/// this many, newcomers are not recorded (none is deleted for the count).
pub const MAX_FILES: usize = 10_000;
/// The directory is listed again at most this often (and at the first recording).
pub const RESCAN: Duration = Duration::from_secs(60);
/// A recording claims room in the directory this many bytes at a time (at most its cap).
pub const STEP: u64 = 64 << 10;
/// Recordings in progress at once from one address group, unless told (`--record-max-per-address`).
pub const MAX_PER_ADDRESS: usize = 2;
/// Recordings in progress at once from one block (an IPv4 /24, an IPv6 /48: the first of
/// [`address_prefixes`](crate::slots::address_prefixes)), at most this many times
/// `max_per_address` (red-team pass 18: 8 addresses of one /24, or 8 /64s of one /48, holding 2
/// each held all 16 places the defaults have, and nobody else was recorded).
pub const BLOCK_SHARE: usize = 2;
/// What a file of ours is called: this, then the time, the process, a counter and the name.
const PREFIX: &str = "mazewalk-";
/// … and this at the end.
const SUFFIX: &str = ".cast";

/// What the host asked for (`--record-dir`, `--record-max-bytes`, `--record-max-total`).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RecordOptions {
    /// Where the casts go (made if missing).
    pub dir: PathBuf,
    /// The most bytes of one cast.
    pub max_bytes: u64,
    /// The most bytes of all our casts in `dir`; a recording starts only if those in progress,
    /// each counted at `max_bytes`, fit.
    pub max_total: u64,
    /// Recordings in progress at once from one address group (an IPv4 address, an IPv6 /64).
    pub max_per_address: usize,
    /// The most of our casts in `dir`, finished and in progress: a newcomer past it is not
    /// recorded.
    pub max_files: usize,
}

impl RecordOptions {
    /// The defaults: 64 MiB a cast, 1 GiB and [`MAX_FILES`] casts in all.
    #[must_use]
    pub fn new(dir: PathBuf) -> RecordOptions {
        RecordOptions {
            dir,
            max_bytes: 64 << 20,
            max_total: 1 << 30,
            max_per_address: MAX_PER_ADDRESS,
            max_files: MAX_FILES,
        }
    }
}

/// The server's recordings: the options, the files in progress, the counts.
#[derive(Debug)]
pub(crate) struct Recordings {
    options: RecordOptions,
    metrics: Metrics,
    /// A counter for file names.
    next: AtomicU64,
    /// The recordings in progress and the finished casts; the lock also makes one make-room at a
    /// time.
    active: Arc<Mutex<Dir>>,
}

/// What is in the directory, as far as the recordings know.
#[derive(Debug, Default)]
struct Dir {
    /// The recordings in progress by file name (never deleted): their address group and the bytes
    /// they claim.
    active: HashMap<String, (IpAddr, u64)>,
    /// Our finished casts and their sizes, oldest first: listed at most once a [`RESCAN`]
    /// (another server may share the directory, the host remove casts), a recording added when it
    /// ends.
    finished: VecDeque<(String, u64)>,
    /// When `finished` was last listed from the directory (`None`: never).
    listed: Option<Instant>,
    /// Whether the count is full and that has been said (said again only after a recording
    /// started).
    full_said: bool,
    /// Whether a newcomer not recorded for want of room, or for a cast that could not be made (a
    /// full disk), has been said (said again only after a recording started: red-team pass 10, it
    /// was said at each join, ten lines a second from one address, past the log's limits).
    refusal_said: bool,
}

impl Dir {
    /// Deletes the oldest finished casts until they and the claims of the recordings in progress
    /// and `bytes_more` fit under `options.max_total` (bytes only: the count deletes nothing); says
    /// in one line what it deleted. An error: a file that could not be deleted (the rest are kept).
    fn make_room(&mut self, options: &RecordOptions, bytes_more: u64) -> io::Result<()> {
        let claimed: u64 =
            self.active.values().map(|(_, claim)| claim).sum::<u64>().saturating_add(bytes_more);
        let mut total: u64 = self.finished.iter().map(|(_, len)| len).sum::<u64>().saturating_add(claimed);
        let (mut deleted, mut freed) = (0usize, 0u64);
        let mut result = Ok(());
        while let Some((file_name, len)) = self.finished.front()
            && total > options.max_total
        {
            // (gone already, say another server pruned it: as good)
            match std::fs::remove_file(options.dir.join(file_name)) {
                Ok(()) => {}
                Err(err) if err.kind() == io::ErrorKind::NotFound => {}
                Err(err) => {
                    result = Err(err);
                    break;
                }
            }
            total -= len;
            deleted += 1;
            freed += len;
            self.finished.pop_front();
        }
        if deleted > 0 {
            info!(dir = %options.dir.display(), deleted, bytes = freed, "recording: the oldest casts deleted to make room (--record-max-total)");
        }
        result
    }
}

/// What a recording's thread is handed.
#[derive(Debug)]
enum Event {
    Output(f64, Vec<u8>),
    Resize(f64, u16, u16),
    Marker(f64, String),
}

/// One player's recording, as its task sees it: hands writes to the recording's thread without
/// waiting. Dropping it ends the recording (the thread writes what is queued and closes the file).
#[derive(Debug)]
pub(crate) struct Tap {
    /// `None` once the recording stopped (the channel was full, or the thread gone).
    tx: Option<mpsc::Sender<Event>>,
    /// Bytes handed over and not yet written.
    queued: Arc<AtomicUsize>,
    /// The server time of the recording's time 0.
    start: f64,
    /// The colour depth last recorded.
    depth: ColorDepth,
    metrics: Metrics,
}

impl Tap {
    /// The bytes sent to the player's terminal at server time `now`.
    pub(crate) fn output(&mut self, now: f64, bytes: &[u8]) {
        if !bytes.is_empty() {
            self.send(Event::Output(now - self.start, bytes.to_vec()), bytes.len());
        }
    }

    /// The player's terminal is now `cols × rows` (as drawn: clamped to the limits).
    pub(crate) fn resize(&mut self, now: f64, cols: u16, rows: u16) {
        self.send(Event::Resize(now - self.start, cols, rows), 0);
    }

    /// The session's colour depth now: a change (the terminal said it shows truecolor) is marked.
    pub(crate) fn depth(&mut self, now: f64, depth: ColorDepth) {
        if depth != self.depth {
            self.depth = depth;
            self.send(Event::Marker(now - self.start, format!("color_depth {depth}")), 0);
        }
    }

    fn send(&mut self, event: Event, bytes: usize) {
        let Some(tx) = &self.tx else { return };
        let queued = self.queued.load(Ordering::Relaxed);
        if queued.saturating_add(bytes) > QUEUED_BYTES {
            self.metrics.recording_dropped();
            self.tx = None;
            return;
        }
        self.queued.fetch_add(bytes, Ordering::Relaxed);
        match tx.try_send(event) {
            Ok(()) => {}
            Err(mpsc::error::TrySendError::Full(_)) => {
                self.metrics.recording_dropped();
                self.tx = None;
            }
            Err(mpsc::error::TrySendError::Closed(_)) => self.tx = None, // stopped: counted there
        }
    }
}

impl Recordings {
    /// The recordings under `options`, counted in `metrics`.
    pub(crate) fn new(options: RecordOptions, metrics: Metrics) -> Recordings {
        Recordings { options, metrics, next: AtomicU64::new(0), active: Arc::default() }
    }

    /// Starts recording the session of `user` (its SSH user name: cleaned here) whose cast starts
    /// with `header`, at server time `now`: makes room and the file on a blocking thread, then
    /// writes there. `None`: not recorded (no room, or the file could not be made: said and counted).
    /// `group` is the player's address group ([`address_group`](crate::slots::address_group)).
    pub(crate) async fn start(&self, user: &str, group: IpAddr, header: Header, now: f64) -> Option<Tap> {
        let number = self.next.fetch_add(1, Ordering::Relaxed);
        let options = self.options.clone();
        let active = Arc::clone(&self.active);
        let depth = header.color_depth;
        let name = player_name(user);
        let opened =
            tokio::task::spawn_blocking(move || open(&options, &active, group, &name, number, &header)).await;
        let (file_name, cast) = match opened {
            Ok(Ok(opened)) => opened,
            Ok(Err(Refused::NoRoom)) => {
                self.metrics.recording_refused();
                if self.say_refusal() {
                    warn!(dir = %self.options.dir.display(), "recording: no room for another cast (--record-max-total); new players are not recorded until a recording ends (said once until one starts)");
                }
                return None;
            }
            Ok(Err(Refused::Full { said })) => {
                self.metrics.recording_refused();
                if !said {
                    warn!(dir = %self.options.dir.display(), casts = self.options.max_files, "recording: the directory holds as many casts as it may (--record-max-files); new players are not recorded until casts are removed (none is deleted for the count)");
                }
                return None;
            }
            Ok(Err(Refused::PerAddress)) => {
                // (counted, not logged: one address's connections could fill the log)
                self.metrics.recording_refused();
                return None;
            }
            Ok(Err(Refused::Io(err))) => {
                self.metrics.recording_failed();
                if self.say_refusal() {
                    warn!(dir = %self.options.dir.display(), "recording: cannot make a cast: {err}; this player is not recorded, nor those after it that fail so (said once until a recording starts)");
                }
                return None;
            }
            Err(_) => return None, // the runtime is shutting down
        };
        self.metrics.recording_started();
        let (tx, rx) = mpsc::channel(QUEUED_EVENTS);
        let queued = Arc::new(AtomicUsize::new(0));
        let writer = Writer {
            cast,
            rx,
            queued: Arc::clone(&queued),
            metrics: self.metrics.clone(),
            claimed: STEP.min(self.options.max_bytes),
            entry: Entry { active: Arc::clone(&self.active), file_name, options: self.options.clone() },
        };
        let spawned = std::thread::Builder::new().name("recording".into()).spawn(move || writer.run());
        if let Err(err) = spawned {
            // (the writer, dropped with the closure, gave its file's name back)
            self.metrics.recording_failed();
            warn!("recording: cannot start its thread: {err}; this player is not recorded");
            return None;
        }
        Some(Tap { tx: Some(tx), queued, start: now, depth, metrics: self.metrics.clone() })
    }
}

impl Recordings {
    /// Whether a newcomer not recorded for want of room or for a cast that could not be made is to
    /// be said in the log: only the first since a recording last started (each is counted).
    fn say_refusal(&self) -> bool {
        !std::mem::replace(&mut self.active.lock().unwrap_or_else(PoisonError::into_inner).refusal_said, true)
    }
}

/// Why a recording did not start.
#[derive(Debug)]
enum Refused {
    /// The recordings in progress leave no room under `max_total`.
    NoRoom,
    /// `max_per_address` recordings from the player's address group are in progress.
    PerAddress,
    /// The casts finished and in progress number `max_files`; `said`: already said in the log
    /// since it filled.
    Full { said: bool },
    /// The directory or the file could not be made, or the header written.
    Io(io::Error),
}

impl From<io::Error> for Refused {
    fn from(err: io::Error) -> Refused {
        Refused::Io(err)
    }
}

/// Whether `name` is one of our casts' names.
fn ours(name: &str) -> bool {
    name.starts_with(PREFIX) && name.ends_with(SUFFIX)
}

/// Lists our finished casts in `options.dir` (those not in progress) with their sizes, oldest
/// first (the name starts with the time, zero-padded).
fn list(
    options: &RecordOptions,
    active: &HashMap<String, (IpAddr, u64)>,
) -> io::Result<VecDeque<(String, u64)>> {
    let mut finished: Vec<(String, u64)> = Vec::new();
    for entry in std::fs::read_dir(&options.dir)? {
        let Ok(entry) = entry else { continue };
        let Ok(file_name) = entry.file_name().into_string() else { continue };
        if !ours(&file_name) || active.contains_key(&file_name) {
            continue;
        }
        match entry.metadata() {
            Ok(meta) if meta.is_file() => finished.push((file_name, meta.len())),
            _ => {}
        }
    }
    finished.sort_unstable();
    Ok(finished.into())
}

/// Makes room for one more cast in the directory and makes it (see the module's doc), its header
/// written; the file's name is added to `active`.
fn open(
    options: &RecordOptions,
    active: &Mutex<Dir>,
    group: IpAddr,
    name: &str,
    number: u64,
    header: &Header,
) -> Result<(String, CastWriter<BufWriter<File>>), Refused> {
    let mut dir = active.lock().unwrap_or_else(PoisonError::into_inner);
    let reserved = (dir.active.len() as u64 + 1).saturating_mul(options.max_bytes);
    if reserved > options.max_total || dir.active.len() >= MAX_RECORDING {
        return Err(Refused::NoRoom);
    }
    // (the address's own, and its block's: an IPv4 /24, an IPv6 /48)
    let block = crate::slots::address_prefixes(group)[0];
    let (mine, blocks) = dir.active.values().fold((0, 0), |(mine, blocks), &(g, _)| {
        (mine + usize::from(g == group), blocks + usize::from(crate::slots::address_prefixes(g)[0] == block))
    });
    if mine >= options.max_per_address || blocks >= BLOCK_SHARE.saturating_mul(options.max_per_address) {
        return Err(Refused::PerAddress);
    }
    if !options.dir.is_dir() {
        // DIR again if it went while serving, never its folders (a typo must not make a tree)
        use std::os::unix::fs::DirBuilderExt as _;
        match std::fs::DirBuilder::new().mode(0o700).create(&options.dir) {
            Err(e) if e.kind() != std::io::ErrorKind::AlreadyExists => return Err(e.into()),
            _ => {}
        }
        dir.listed = None; // (its casts went with it: listed anew)
    }
    if dir.listed.is_none_or(|listed| listed.elapsed() >= RESCAN) {
        dir.finished = list(options, &dir.active)?;
        dir.listed = Some(Instant::now());
    }
    if dir.finished.len() + dir.active.len() >= options.max_files {
        let said = std::mem::replace(&mut dir.full_said, true);
        return Err(Refused::Full { said });
    }
    let claim = STEP.min(options.max_bytes);
    dir.make_room(options, claim)?; // (the newcomer's first step)
    let seconds =
        std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).map_or(0, |d| d.as_secs());
    let pid = std::process::id();
    let name = if name.is_empty() { "player" } else { name };
    let mut attempt = number;
    loop {
        let file_name = format!("{PREFIX}{seconds:011}-{pid}-{attempt:06}-{name}{SUFFIX}");
        let path = options.dir.join(&file_name);
        match OpenOptions::new().write(true).create_new(true).mode(0o600).open(&path) {
            Ok(file) => {
                // (the header flushed at once: a cast cut back after a write error keeps it)
                let cast = CastWriter::with_limit(BufWriter::new(file), header, options.max_bytes)
                    .and_then(|mut cast| {
                        cast.flush();
                        if cast.failed() { cast.finish().map(|()| cast) } else { Ok(cast) }
                    })
                    .inspect_err(|_| {
                        let _ = std::fs::remove_file(&path);
                    })?;
                dir.active.insert(file_name.clone(), (group, claim));
                dir.full_said = false;
                dir.refusal_said = false;
                return Ok((file_name, cast));
            }
            // (a name taken, by another server in the same directory: the next number)
            Err(err) if err.kind() == io::ErrorKind::AlreadyExists && attempt < number + 16 => attempt += 1,
            Err(err) => return Err(Refused::Io(err)),
        }
    }
}

/// A recording's thread.
struct Writer {
    cast: CastWriter<BufWriter<File>>,
    rx: mpsc::Receiver<Event>,
    queued: Arc<AtomicUsize>,
    metrics: Metrics,
    /// The bytes this recording claims in the directory (as in `entry`'s place, read without the
    /// lock).
    claimed: u64,
    entry: Entry,
}

/// A recording's place among those in progress, given up when dropped.
struct Entry {
    active: Arc<Mutex<Dir>>,
    file_name: String,
    options: RecordOptions,
}

impl Writer {
    /// Writes the events until the player's task drops its [`Tap`] (or the recording stops), then
    /// flushes and closes the file.
    fn run(mut self) {
        while let Some(event) = self.rx.blocking_recv() {
            match event {
                Event::Output(time, bytes) => {
                    self.cast.output(time, &bytes);
                    self.queued.fetch_sub(bytes.len(), Ordering::Relaxed);
                }
                Event::Resize(time, cols, rows) => self.cast.resize(time, cols, rows),
                Event::Marker(time, label) => self.cast.marker(time, &label),
            }
            if self.cast.failed() || self.cast.capped() || !self.claim() {
                break;
            }
            if self.rx.is_empty() {
                self.cast.flush(); // caught up: the file is whole up to here
            }
        }
        self.rx.close(); // the tap's next write learns it stopped
        let path = self.entry.options.dir.join(&self.entry.file_name);
        if self.cast.capped() {
            self.metrics.recording_capped();
            warn!(file = %path.display(), bytes = self.cast.written(), "recording: the cast reached its cap (--record-max-bytes); it stops here");
        }
        if let Err(err) = self.cast.finish() {
            self.metrics.recording_failed();
            // Part of a line may have reached the file (a full disk): cut back to the last flush
            // that went well, so that the cast is whole lines; what is still buffered is dropped.
            let flushed = self.cast.flushed();
            let (file, _) = self.cast.into_inner().into_parts();
            let cut = match file.set_len(flushed) {
                Ok(()) => String::new(),
                Err(cut) => format!(" (and it could not be cut back to whole lines: {cut})"),
            };
            warn!(file = %path.display(), bytes = flushed, "recording: cannot write the cast: {err}; it stops here{cut}");
        }
    }
}

impl Writer {
    /// Claims the room for the bytes written and the next [`STEP`] when the cast has passed its
    /// claim, deleting the oldest finished casts if need be. `false`: no room could be made (a
    /// cast that cannot be deleted): the recording stops, said and counted.
    fn claim(&mut self) -> bool {
        let written = self.cast.written();
        if written <= self.claimed {
            return true; // (the usual case: no lock taken)
        }
        let entry = &self.entry;
        let mut dir = entry.active.lock().unwrap_or_else(PoisonError::into_inner);
        let Some((_, claim)) = dir.active.get_mut(&entry.file_name) else { return true };
        *claim = written.saturating_add(STEP).min(entry.options.max_bytes.max(written));
        self.claimed = *claim;
        match dir.make_room(&entry.options, 0) {
            Ok(()) => true,
            Err(err) => {
                drop(dir);
                self.metrics.recording_failed();
                warn!(dir = %self.entry.options.dir.display(), "recording: cannot delete an old cast to make room: {err}; this cast stops here");
                false
            }
        }
    }
}

impl Drop for Entry {
    /// The file is no longer in progress (also when its thread could not start): it is now a
    /// finished cast of its size.
    fn drop(&mut self) {
        let mut dir = self.active.lock().unwrap_or_else(PoisonError::into_inner);
        if dir.active.remove(&self.file_name).is_some() {
            let size = std::fs::metadata(self.options.dir.join(&self.file_name)).map_or(0, |m| m.len());
            dir.finished.push_back((std::mem::take(&mut self.file_name), size));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use mazewalk_render::Charset;
    use std::path::Path;

    fn header() -> Header {
        Header {
            width: 80,
            height: 24,
            timestamp: None,
            title: "t".into(),
            term: None,
            colorterm: None,
            color_depth: ColorDepth::Ansi256,
            charset: Charset::Half,
            asked_truecolor: false,
        }
    }

    struct Dir(PathBuf);
    impl Drop for Dir {
        fn drop(&mut self) {
            let _ = std::fs::remove_dir_all(&self.0);
        }
    }
    fn scratch(name: &str) -> Dir {
        let dir = std::env::temp_dir().join(format!("mazewalk-recording-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        Dir(dir)
    }

    fn names(dir: &Path) -> Vec<String> {
        let mut names: Vec<String> =
            std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().file_name().into_string().unwrap()).collect();
        names.sort();
        names
    }

    /// A tap on a channel of `capacity`, and its other end.
    fn a_tap(capacity: usize) -> (Tap, mpsc::Receiver<Event>, Metrics) {
        let (tx, rx) = mpsc::channel(capacity);
        let metrics = Metrics::default();
        let queued = Arc::new(AtomicUsize::new(0));
        let tap =
            Tap { tx: Some(tx), queued, start: 10.0, depth: ColorDepth::Ansi256, metrics: metrics.clone() };
        (tap, rx, metrics)
    }

    #[test]
    fn a_tap_times_from_its_start_and_marks_a_raised_depth_once() {
        let (mut tap, mut rx, _) = a_tap(8);
        tap.output(10.5, b"frame");
        tap.depth(10.75, ColorDepth::Ansi256); // unchanged: nothing
        tap.depth(11.0, ColorDepth::TrueColor);
        tap.depth(11.25, ColorDepth::TrueColor);
        tap.resize(12.0, 90, 28);
        tap.output(12.5, b""); // nothing to record
        let mut events = Vec::new();
        while let Ok(event) = rx.try_recv() {
            events.push(format!("{event:?}"));
        }
        assert_eq!(
            events,
            [
                format!("{:?}", Event::Output(0.5, b"frame".to_vec())),
                format!("{:?}", Event::Marker(1.0, "color_depth truecolor".into())),
                format!("{:?}", Event::Resize(2.0, 90, 28)),
            ]
        );
    }

    // A writer slower than the game: the tap never waits; the first write that does not fit (in
    // writes or in bytes) is dropped, counted, and the recording stops there (no gap in a cast).
    #[test]
    fn a_full_queue_stops_the_recording_and_is_counted() {
        let (mut tap, _rx, metrics) = a_tap(2);
        for _ in 0..5 {
            tap.output(11.0, b"frame");
        }
        assert!(tap.tx.is_none(), "still recording after a drop");
        assert_eq!(metrics.recordings().1, [0, 0, 0, 1], "one drop counted, once");
        let (mut tap, _rx, metrics) = a_tap(QUEUED_EVENTS);
        let big = vec![b'x'; QUEUED_BYTES / 2 + 1];
        tap.output(11.0, &big);
        assert!(tap.tx.is_some());
        tap.output(11.5, &big); // over the bytes waiting
        assert!(tap.tx.is_none());
        assert_eq!(metrics.recordings().1[3], 1);
    }

    const HOME: IpAddr = IpAddr::V4(std::net::Ipv4Addr::LOCALHOST);

    #[test]
    fn a_hostile_name_is_cleaned_and_never_a_path() {
        let dir = scratch("names");
        let options = RecordOptions { max_per_address: 8, ..RecordOptions::new(dir.0.clone()) };
        let active = Mutex::default();
        for user in ["../../etc/passwd", "a/b\u{1b}[31m", "", ".."] {
            open(&options, &active, HOME, &player_name(user), 7, &header()).map_err(|_| "open").unwrap();
        }
        for name in names(&dir.0) {
            assert!(ours(&name) && !name.contains('/') && !name.contains('\u{1b}'), "{name}");
        }
        assert_eq!(names(&dir.0).len(), 4, "each its own file: {:?}", names(&dir.0));
    }

    fn old_casts(dir: &Path, n: u64, len: usize) {
        std::fs::create_dir_all(dir).unwrap();
        for t in 1..=n {
            std::fs::write(dir.join(format!("mazewalk-{t:011}-1-000000-old.cast")), vec![b'x'; len]).unwrap();
        }
    }

    fn olds(dir: &Path) -> usize {
        names(dir).iter().filter(|n| n.ends_with("-old.cast")).count()
    }

    // The red team's HIGH finding: recordings that have written nearly nothing delete no finished
    // cast, however many start (before, each newcomer's whole cap was paid for by deleting them).
    #[test]
    fn recordings_in_progress_delete_nothing_for_bytes_not_written() {
        let dir = scratch("reserve");
        // 12 finished casts of 1 MiB under a 16 MiB total, 1 MiB a cast
        old_casts(&dir.0, 12, 1 << 20);
        std::fs::write(dir.0.join("notes.txt"), [b'x'; 5000]).unwrap();
        let options = RecordOptions {
            dir: dir.0.clone(),
            max_bytes: 1 << 20,
            max_total: 16 << 20,
            max_per_address: 64,
            max_files: MAX_FILES,
        };
        let active = Mutex::default();
        let mut casts = Vec::new();
        for n in 0..16 {
            let group = IpAddr::V4(std::net::Ipv4Addr::new(127, 0, 0, n as u8 + 1));
            casts.push(open(&options, &active, group, "idle", n, &header()).map_err(|_| "open").unwrap());
        }
        assert_eq!(olds(&dir.0), 12, "finished casts deleted for bytes never written: {:?}", names(&dir.0));
        // a 17th would not fit even at nothing written once the others reach their caps: refused
        assert!(matches!(open(&options, &active, HOME, "late", 99, &header()), Err(Refused::NoRoom)));
        assert_eq!(olds(&dir.0), 12);
        assert!(names(&dir.0).contains(&"notes.txt".to_string()));
    }

    #[test]
    fn one_address_holds_at_most_its_recordings() {
        let dir = scratch("peraddress");
        let options = RecordOptions { max_per_address: 2, ..RecordOptions::new(dir.0.clone()) };
        let active = Mutex::default();
        let other = IpAddr::V4(std::net::Ipv4Addr::new(127, 0, 0, 2));
        let _a = open(&options, &active, HOME, "a", 0, &header()).map_err(|_| "open").unwrap();
        let _b = open(&options, &active, HOME, "b", 1, &header()).map_err(|_| "open").unwrap();
        assert!(matches!(open(&options, &active, HOME, "c", 2, &header()), Err(Refused::PerAddress)));
        let _d = open(&options, &active, other, "d", 3, &header()).map_err(|_| "open").unwrap();
        assert_eq!(names(&dir.0).len(), 3);
    }

    // Red-team pass 18: the per-address cap counted an address alone, so 8 addresses of a /24 (or 8
    // /64s of a /48) with 2 idle players each held all 16 places of the defaults.
    #[test]
    fn one_block_holds_at_most_twice_an_addresss_recordings() {
        let dir = scratch("perblock");
        let options = RecordOptions { max_bytes: 1 << 20, ..RecordOptions::new(dir.0.clone()) };
        let active = Mutex::default();
        let mut casts = Vec::new();
        let mut try_open = |group: IpAddr, n: u64| {
            open(&options, &active, group, "idle", n, &header()).map(|cast| casts.push(cast)).is_ok()
        };
        let v4 = |k: u8| IpAddr::V4(std::net::Ipv4Addr::new(192, 0, 2, k));
        let from_24 =
            (1..=8u8).flat_map(|k| [k, k]).enumerate().filter(|&(n, k)| try_open(v4(k), n as u64)).count();
        assert_eq!(from_24, BLOCK_SHARE * MAX_PER_ADDRESS, "8 addresses of a /24, 2 players each");
        assert!(try_open(IpAddr::V4(std::net::Ipv4Addr::new(192, 0, 3, 1)), 50), "another /24");
        let v6 = |k: u16| IpAddr::V6(std::net::Ipv6Addr::new(0x2001, 0xdb8, 7, k, 0, 0, 0, 0));
        let from_48 = (1..=8u16)
            .flat_map(|k| [k, k])
            .enumerate()
            .filter(|&(n, k)| try_open(v6(k), 60 + n as u64))
            .count();
        assert_eq!(from_48, BLOCK_SHARE * MAX_PER_ADDRESS, "8 /64s of a /48");
        assert!(
            try_open(IpAddr::V6(std::net::Ipv6Addr::new(0x2001, 0xdb8, 8, 0, 0, 0, 0, 0)), 90),
            "another /48"
        );
    }

    /// Records a session of `user` from `group` that ends at once (a header only, as a stranger's
    /// login-and-quit leaves).
    fn quick(
        options: &RecordOptions,
        active: &Arc<Mutex<super::Dir>>,
        group: IpAddr,
        user: &str,
        number: u64,
    ) -> Result<(), Refused> {
        let (file_name, mut cast) = open(options, active, group, user, number, &header())?;
        cast.finish().expect("the header written");
        drop(Entry { active: Arc::clone(active), file_name, options: options.clone() });
        Ok(())
    }

    // Red-team pass 7: one address's quick sessions (2 KB casts, 8 a second) filled the count of
    // casts, and from then on each newcomer deleted the oldest cast, anyone's. Now a full count
    // refuses newcomers (said once each time it fills) and deletes nothing; casts the host removes
    // are seen at the next listing, and recording goes on.
    #[test]
    fn a_full_count_refuses_newcomers_and_deletes_no_cast() {
        let dir = scratch("count");
        let options = RecordOptions { max_files: 6, ..RecordOptions::new(dir.0.clone()) };
        let active = Arc::new(Mutex::default());
        let alice = IpAddr::V4(std::net::Ipv4Addr::new(192, 0, 2, 7));
        quick(&options, &active, alice, "alice", 0).map_err(|_| "alice's").unwrap();
        let mut said = Vec::new();
        for n in 1..=20 {
            match quick(&options, &active, HOME, "eve", n) {
                Ok(()) => said.push("recorded"),
                Err(Refused::Full { said: false }) => said.push("full, said"),
                Err(Refused::Full { said: true }) => said.push("full"),
                Err(other) => panic!("{other:?}"),
            }
        }
        assert_eq!(
            &said[..7],
            ["recorded"; 5].iter().chain(&["full, said", "full"]).copied().collect::<Vec<_>>()
        );
        assert!(said[7..].iter().all(|s| *s == "full"), "{said:?}");
        let left = names(&dir.0);
        assert_eq!(left.len(), 6, "{left:?}");
        assert!(left.iter().any(|n| n.ends_with("-alice.cast")), "alice's cast deleted: {left:?}");
        // The host removes two of eve's casts: seen at the next listing, then two more recorded.
        for name in left.iter().filter(|n| n.ends_with("-eve.cast")).take(2) {
            std::fs::remove_file(dir.0.join(name)).unwrap();
        }
        active.lock().unwrap().listed = None; // (as a [`RESCAN`] later)
        let again: Vec<bool> = (21..24).map(|n| quick(&options, &active, HOME, "eve", n).is_ok()).collect();
        assert_eq!(again, [true, true, false]);
        assert!(names(&dir.0).iter().any(|n| n.ends_with("-alice.cast")));
        // DIR removed whole: made again and listed anew at once
        std::fs::remove_dir_all(&dir.0).unwrap();
        quick(&options, &active, HOME, "eve", 30).map_err(|_| "after DIR went").unwrap();
        assert_eq!(names(&dir.0).len(), 1);
    }

    /// A `tracing` writer into a shared buffer, to read what was logged.
    #[derive(Clone, Default)]
    struct Logged(Arc<Mutex<Vec<u8>>>);
    impl io::Write for Logged {
        fn write(&mut self, bytes: &[u8]) -> io::Result<usize> {
            self.0.lock().unwrap().extend_from_slice(bytes);
            Ok(bytes.len())
        }
        fn flush(&mut self) -> io::Result<()> {
            Ok(())
        }
    }

    // Red-team pass 10: on a full disk (or with no room left under --record-max-total) every
    // join said "cannot make a cast" (or "no room") in the log, ten lines a second from one
    // address, past the log's per-address limits. Now it is said once, then counted only, until a
    // recording starts; a failure after that is said again.
    #[tokio::test]
    async fn a_cast_that_cannot_be_made_is_said_once_until_a_recording_starts() {
        let dir = scratch("unmade");
        std::fs::write(&dir.0, b"a file where DIR should be").unwrap();
        let logged = Logged::default();
        let writer = logged.clone();
        let subscriber = tracing_subscriber::fmt().with_writer(move || writer.clone()).finish();
        let _default = tracing::subscriber::set_default(subscriber);
        let metrics = Metrics::default();
        let recordings = Recordings::new(RecordOptions::new(dir.0.clone()), metrics.clone());
        let said =
            || String::from_utf8_lossy(&logged.0.lock().unwrap()).matches("cannot make a cast").count();
        for _ in 0..10 {
            assert!(recordings.start("eve", HOME, header(), 0.0).await.is_none(), "DIR is a file");
        }
        assert_eq!(said(), 1, "said once for ten joins");
        std::fs::remove_file(&dir.0).unwrap();
        let tap = recordings.start("ada", HOME, header(), 0.0).await;
        assert!(tap.is_some(), "DIR made: recorded");
        drop(tap);
        std::fs::remove_dir_all(&dir.0).unwrap();
        std::fs::write(&dir.0, b"a file again").unwrap();
        for _ in 0..10 {
            assert!(recordings.start("eve", HOME, header(), 0.0).await.is_none());
        }
        assert_eq!(said(), 2, "said again after a recording started, once");
        let text = crate::metrics::encode(&crate::metrics::registry(
            &metrics,
            crate::metrics::Live(Box::new(crate::metrics::Snapshot::default)),
        ));
        assert!(text.lines().any(|l| l == "mazewalk_recording_errors_total 20"), "each counted:\n{text}");
        std::fs::remove_file(&dir.0).unwrap();
    }

    // A recording that grows claims room as it writes: the oldest finished casts go then, as many
    // as its bytes written need, and no more; when it ends it is a finished cast like the others.
    #[test]
    fn the_oldest_finished_casts_make_room_for_bytes_written() {
        let dir = scratch("prune");
        // 4 finished casts of 100 KiB under 500 KiB in all, 300 KiB a cast
        old_casts(&dir.0, 4, 100 << 10);
        let options = RecordOptions {
            dir: dir.0.clone(),
            max_bytes: 300 << 10,
            max_total: 500 << 10,
            max_per_address: 2,
            max_files: MAX_FILES,
        };
        let active = Arc::new(Mutex::default());
        let (file_name, cast) = open(&options, &active, HOME, "a", 0, &header()).map_err(|_| "open").unwrap();
        assert_eq!(olds(&dir.0), 4, "400 KiB + a 64 KiB claim fit");
        let (tx, rx) = mpsc::channel(QUEUED_EVENTS);
        let writer = Writer {
            cast,
            rx,
            queued: Arc::default(),
            metrics: Metrics::default(),
            claimed: STEP.min(options.max_bytes),
            entry: Entry { active: Arc::clone(&active), file_name, options: options.clone() },
        };
        let thread = std::thread::spawn(move || writer.run());
        // about 200 KB written (claims of up to 257 KiB): the two oldest go, the others stay
        for i in 0..200 {
            tx.blocking_send(Event::Output(f64::from(i), vec![b'y'; 1000])).unwrap();
        }
        drop(tx);
        thread.join().unwrap();
        let left = names(&dir.0);
        assert!(!left.iter().any(|n| n.contains("00000000001-") || n.contains("00000000002-")), "{left:?}");
        assert!(
            left.iter().any(|n| n.contains("00000000003-"))
                && left.iter().any(|n| n.contains("00000000004-")),
            "{left:?}"
        );
        let dir_state = active.lock().unwrap();
        assert!(dir_state.active.is_empty());
        assert_eq!(
            dir_state.finished.len(),
            3,
            "the ended cast counted as finished: {:?}",
            dir_state.finished
        );
        let total: u64 = left.iter().map(|n| std::fs::metadata(dir.0.join(n)).unwrap().len()).sum();
        assert!(total <= options.max_total, "{total}");
    }
}
