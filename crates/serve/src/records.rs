//! The best times of a served maze, kept across restarts: every finish goes to a [`Store`], which
//! answers with the maze's best ten and the player's rank ([`Standing`], shown in the exit box).
//!
//! ```text
//! player's task ─try_send─▶ [bounded queue] ─▶ records thread: Store::record (SQLite) ─oneshot─▶ exit box
//! ```
//!
//! - **Keyed by the maze's content** ([`Maze::content_hash`](mazewalk_maze::Maze::content_hash)), so a
//!   maze keeps its records whatever its file is called, and an edited maze starts afresh.
//! - **Never in a player's way.** A finish is handed to the records thread with `try_send`: a full
//!   queue drops it (counted, reported once); the answer comes back on a oneshot channel the player's
//!   task polls beside its input. The database is touched on that thread only, never on the async
//!   workers.
//! - **Faults are reported once and the game goes on.** A finish the store cannot keep (a database
//!   locked by another program past its busy timeout, read-only, full, damaged, a Redis away) is
//!   kept in memory for the players' ranking — among the store's last best ten and this run's —
//!   and written when the store takes finishes again (the latest [`UNSAVED`] of them): tried with
//!   the next finish, every [`RETRY`] meanwhile, and once more when the thread stops (those still
//!   unsaved then are counted in one log line). The fault is
//!   said once, and again only after the store has worked in between, at most once a minute. A
//!   damaged file found at start is kept aside (`FILE.damaged-UNIXTIME`), never written over, and a
//!   new one made ([`Sqlite::open`]).
//! - **Bounded.** A file keeps each player's best [`FINISHES_PER_PLAYER`] finishes of a maze; a
//!   file full (at [`SqliteOptions::max_bytes`]) deletes the worst quarter (at most [`PRUNE`]) of
//!   the fullest maze's finishes and tries once more, so a flood of finishes cannot lock everyone
//!   out (only a full disk, or a file too small to prune, still fails as [`Fault::Full`]).
//! - **A file deleted or replaced while serving** is noticed before the next finish (the path's
//!   device and inode against the open file's, [`Store::check`]), said, and opened again: made
//!   anew if gone, kept aside if damaged.
//! - **No memory-mapped file, so no SIGBUS** (issue #40). A mapped page that the disk can no longer
//!   back — WAL's `-shm` made immutable, an ext4 remounted read-only after an error — kills the
//!   process on its next write. So `mmap_size` is 0 and the journal is a rollback journal, not WAL
//!   (whose index lives in the mapped `-shm`); a file left in WAL mode by an older mazewalk is taken
//!   out of it under `locking_mode=EXCLUSIVE`, in which SQLite keeps the WAL index in heap memory
//!   and never maps `-shm` (sqlite.org/wal.html, "Use of WAL Without Shared-Memory").
//! - **A file someone else made costs what one of ours does** (red-team pass 8). A records file
//!   is read (`mazewalk records`) or served only if its schema is exactly what this code makes
//!   ([`SCHEMA`], or the previous version's): no view, trigger or virtual table (a file served
//!   is otherwise kept aside as a damaged one). And whatever it holds, every call is bounded
//!   ([`harden`]): [`SqliteOptions::max_steps`] VM steps, values of at most [`MAX_VALUE`] bytes,
//!   sorts and temporary tables in memory under a heap cap, views and triggers off.
//! - **One file, many servers.** A rollback journal with a busy timeout: servers on one file (two
//!   mazes, say) each write their finishes; a write waits for another's, a few milliseconds.
//!
//! - **Runs for ghosts** (issue #43). A finish carries its run ([`Finish::run`], the format of
//!   [`mazewalk_walk::run`]); the store keeps it for the best finish of each of the maze's best
//!   [`TOP`] players and drops the others ([`Store::run`] reads one back). With a [`Race`], the
//!   records thread reads the maze's best run at start, after each finish with a run, when asked
//!   ([`Records::reread_best_run`]: another server in the world finished; read again
//!   [`REREAD_AGAIN`] later, in case its run was stored after its word came) and every
//!   [`REREAD_BEST_RUN`], decodes and checks it as untrusted (a fault said once) and offers it as
//!   [`Records::best_run`]. A finish kept in memory while the store fails keeps no run.
//!
//! [`Store`] is the seam for another backend: with `--world` the best times live in the shared
//! world's Redis ([`RedisStore`](crate::shared::records::RedisStore), a sorted set per maze). The
//! server only calls [`Store::record`]; `mazewalk records` calls [`Store::mazes`].

use std::collections::HashMap;
use std::os::unix::fs::MetadataExt as _;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex, PoisonError, mpsc};
use std::time::{Duration, Instant};

use mazewalk_maze::ContentHash;
use rusqlite::{Connection, ErrorCode, OpenFlags, OptionalExtension as _, params};
use tokio::sync::oneshot;

use crate::identity::player_name;
use mazewalk_maze::Aabb;
use mazewalk_walk::run::{MAX_BYTES, Run};

/// How many best times a [`Standing`] lists.
pub(crate) const TOP: usize = 10;

/// Finishes of one player on one maze kept in a records file, at most: its best (a player finishing
/// again and again adds no rows past these).
pub const FINISHES_PER_PLAYER: usize = 10;

/// Finishes deleted at once when a records file is full, at most: the worst quarter of the maze
/// with the most, up to this many.
const PRUNE: i64 = 4096;

/// Finishes waiting for the records thread, at most; more are dropped (and counted).
pub const QUEUE: usize = 64;

/// One player reaching the exit.
#[derive(Clone, Debug, PartialEq)]
pub struct Finish {
    /// The maze.
    pub maze: ContentHash,
    /// What the host called it (a file name, "built-in maze", "--gen 30x20 --seed 7").
    pub maze_name: String,
    /// The player's name.
    pub player: String,
    /// Seconds from the start to the exit.
    pub seconds: f64,
    /// When, seconds since the Unix epoch.
    pub at: i64,
    /// The run, encoded ([`Run::encode`]): what a ghost replays. `None`: none kept (a walk past
    /// [`MAX_SECONDS`](mazewalk_walk::run::MAX_SECONDS)).
    pub run: Option<Vec<u8>>,
}

/// A stored run as the store gives it back: untrusted bytes, decoded and checked by the caller.
#[derive(Clone, Debug, PartialEq)]
pub struct StoredRun {
    /// Whose finish it is.
    pub player: String,
    /// Its time, seconds.
    pub seconds: f64,
    /// The run, encoded (at most [`MAX_BYTES`] long: longer ones are not given back).
    pub bytes: Vec<u8>,
}

/// A player's best time on a maze.
#[derive(Clone, Debug, PartialEq)]
pub struct Best {
    /// The player's name.
    pub player: String,
    /// Seconds.
    pub seconds: f64,
    /// When it was made, seconds since the Unix epoch.
    pub at: i64,
}

/// Where a player stands on a maze after a finish.
#[derive(Clone, Debug, PartialEq)]
pub struct Standing {
    /// The maze's best [`TOP`] players, best first (each player once, with its best time).
    pub top: Vec<Best>,
    /// The player's own best time on the maze (this finish or an earlier one).
    pub best: f64,
    /// Its rank among the players of the maze by their best times, from 1.
    pub rank: usize,
    /// How many players have finished the maze.
    pub players: usize,
}

/// One maze's records, for `mazewalk records`.
#[derive(Clone, Debug, PartialEq)]
pub struct MazeRecords {
    /// The maze's content hash, in hex.
    pub maze: String,
    /// What the host called it when it was first served.
    pub name: String,
    /// Players who finished it.
    pub players: usize,
    /// Finishes in all.
    pub finishes: usize,
    /// The best [`TOP`].
    pub top: Vec<Best>,
}

/// What went wrong with the records.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Fault {
    /// Another program held the database longer than the busy timeout (this finish is not kept;
    /// the next may be).
    Busy,
    /// The database cannot be written (a read-only file, folder or disk).
    ReadOnly,
    /// A write to the file was cut off (a server killed while it wrote) and the hot journal beside
    /// it holds what it changed: a read-only reader may not roll it back, a server that opens the
    /// file does.
    CutOff,
    /// The file cannot be opened or made.
    CannotOpen,
    /// The file is not a database, or a damaged one.
    Damaged,
    /// The disk, or the database's size limit, is full.
    Full,
    /// A newer mazewalk made it (its schema is unknown here).
    Newer,
    /// A query went past the bound on what one may cost ([`SqliteOptions::max_steps`], or SQLite's
    /// memory cap): a file this mazewalk did not write, or far larger than any it writes.
    TooCostly,
    /// The records' Redis (a shared world's, `--world`) does not answer (this finish is not kept;
    /// the next may be).
    Unreachable,
    /// Anything else SQLite, Redis or the file system said.
    Other,
}

/// A fault, with the file and what SQLite said.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{}: {}{}", mazewalk_maze::quote_path(&path.display().to_string()), fault_text(*fault), if detail.is_empty() { String::new() } else { format!(" ({detail})") })]
pub struct RecordsError {
    /// The database file.
    pub path: PathBuf,
    /// What kind of fault.
    pub fault: Fault,
    /// SQLite's or the system's words.
    pub detail: String,
}

fn fault_text(fault: Fault) -> &'static str {
    match fault {
        Fault::Busy => "the database is locked by another program",
        Fault::ReadOnly => "the database cannot be written",
        Fault::CutOff => "a write to it was cut off",
        Fault::CannotOpen => "the database cannot be opened",
        Fault::Damaged => "not a records database, or a damaged one",
        Fault::Full => "the database is full",
        Fault::Newer => "made by a newer mazewalk",
        Fault::TooCostly => "a query went past what reading a records file may cost",
        Fault::Unreachable => "Redis does not answer",
        Fault::Other => "the database failed",
    }
}

impl RecordsError {
    fn new(path: &Path, fault: Fault, detail: impl Into<String>) -> RecordsError {
        RecordsError { path: path.to_path_buf(), fault, detail: detail.into() }
    }

    fn sqlite(path: &Path, err: &rusqlite::Error) -> RecordsError {
        let fault = match err.sqlite_error_code() {
            Some(ErrorCode::DatabaseBusy | ErrorCode::DatabaseLocked) => Fault::Busy,
            Some(ErrorCode::ReadOnly) => Fault::ReadOnly,
            Some(ErrorCode::CannotOpen | ErrorCode::PermissionDenied) => Fault::CannotOpen,
            // (a value longer than the length limit: none of ours is)
            Some(ErrorCode::NotADatabase | ErrorCode::DatabaseCorrupt | ErrorCode::TooBig) => Fault::Damaged,
            // (the progress handler's step bound, or the heap limit)
            Some(ErrorCode::OperationInterrupted | ErrorCode::OutOfMemory) => Fault::TooCostly,
            Some(ErrorCode::DiskFull) => Fault::Full,
            // (past MAX_SCHEMA_OBJECTS, said by whichever statement first reads the schema: a
            // plain SQLITE_ERROR, told apart by SQLite's words)
            _ if err.to_string().contains("too many schema objects") => Fault::Damaged,
            _ => Fault::Other,
        };
        // A read-only connection finding a hot journal must not roll it back; SQLite's own words,
        // "attempt to write a readonly database", would have the reader look at permissions.
        if let rusqlite::Error::SqliteFailure(e, _) = err
            && e.extended_code == rusqlite::ffi::SQLITE_READONLY_ROLLBACK
        {
            let why = "a server stopped while it wrote; the -journal beside it holds what it changed, \
                       which a server that opens the file rolls back; nothing was changed here";
            return RecordsError::new(path, Fault::CutOff, why);
        }
        RecordsError::new(path, fault, crate::logs::clip(&err.to_string(), crate::logs::ERROR_CHARS))
    }

    /// Whether the next finish may fare better (a lock held for a while, a Redis away for a while).
    #[must_use]
    pub fn is_transient(&self) -> bool {
        matches!(self.fault, Fault::Busy | Fault::Unreachable)
    }
}

/// Where best times are kept: the server calls [`record`](Self::record) for every finish (on a
/// thread of its own, never on the async workers), `mazewalk records` calls [`mazes`](Self::mazes).
pub trait Store: Send + 'static {
    /// Keeps `finish`, and says where its player stands on its maze now.
    ///
    /// # Errors
    /// The store failed; nothing was kept.
    fn record(&mut self, finish: &Finish) -> Result<Standing, RecordsError>;

    /// Every maze with finishes (or only `maze`), each with its best [`TOP`].
    ///
    /// # Errors
    /// The store failed.
    fn mazes(&mut self, maze: Option<&ContentHash>) -> Result<Vec<MazeRecords>, RecordsError>;

    /// The run of `player`'s best finish on `maze`, or with `None` the maze's best run, if kept. Runs
    /// are kept for the best finish of each of the maze's best [`TOP`] players, no others.
    ///
    /// # Errors
    /// The store failed.
    fn run(&mut self, maze: &ContentHash, player: Option<&str>) -> Result<Option<StoredRun>, RecordsError> {
        let _ = (maze, player);
        Ok(None)
    }

    /// Called before each [`record`](Self::record): whether the store is still the one it opened. A
    /// file deleted or replaced meanwhile is opened again; the line says what happened (for the log,
    /// once per change). `None`: nothing changed (or the store has no file).
    fn check(&mut self) -> Option<String> {
        None
    }
}

/// How a SQLite database is opened.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SqliteOptions {
    /// How long a write waits for another program's lock before giving up on that finish.
    pub busy_timeout: Duration,
    /// The database's size limit, bytes: past it, writes fail as a full disk would ([`Fault::Full`]).
    pub max_bytes: u64,
    /// The most SQLite virtual-machine steps one call may take (an open, a finish kept, a listing,
    /// a run read): past it the call fails as [`Fault::TooCostly`]. A bound on what a file someone
    /// else made can cost, whatever its contents; a full file of ours needs a small part of it.
    pub max_steps: u64,
}

impl Default for SqliteOptions {
    fn default() -> Self {
        // 64 MiB: about a million finishes.
        SqliteOptions { busy_timeout: Duration::from_secs(2), max_bytes: 64 << 20, max_steps: MAX_STEPS }
    }
}

/// The records in a SQLite file (bundled SQLite, a rollback journal, nothing memory-mapped).
#[derive(Debug)]
pub struct Sqlite {
    conn: Connection,
    path: PathBuf,
    options: SqliteOptions,
    /// The device and inode of the file opened (`None`: none there), to notice another in its place.
    file: Option<(u64, u64)>,
    /// The file went and none could be opened in its place: nothing is written.
    lost: bool,
    /// What the current call may still spend, in [`STEP_CHUNK`]s of VM steps (see [`harden`]).
    steps: Arc<AtomicU64>,
}

/// Whether a WAL index or log is beside `path` (a server of an older mazewalk runs on it, or was
/// killed): such a `-shm` may be one the disk no longer backs. (Looked at without opening anything:
/// closing any descriptor of the database file would drop SQLite's locks on it in this process.)
fn wal_beside(path: &Path) -> bool {
    ["-wal", "-shm"].iter().any(|suffix| {
        let mut name = path.as_os_str().to_owned();
        name.push(suffix);
        Path::new(&name).exists()
    })
}

/// Whether the records file at `path` is to be read as a file in WAL mode: its header says WAL (a
/// server of an older mazewalk ran on it), or an empty `-wal` is beside it. Read-only, SQLite reads
/// such a file through a `-wal` and a `-shm` it makes beside it if they are not there, and maps the
/// `-shm` (red-team pass 13: `mazewalk records` on one left two files beside it, one mapped, the
/// hazard issue #40 took out of the server; in a folder the reader may not write, it failed, "the
/// database cannot be written"). With no log to read, the file alone is the whole database: it is
/// read as immutable, without locks, nothing made or mapped. A `-wal` that holds anything is
/// refused: the finishes in it are not yet in the file, and reading them needs the mapped index.
///
/// # Errors
/// A `-wal` beside the file that holds anything ([`Fault::CannotOpen`]), or the file cannot be read.
fn wal_to_read(path: &Path) -> Result<bool, RecordsError> {
    use std::io::Read as _;
    let mut name = path.as_os_str().to_owned();
    name.push("-wal");
    let log = std::fs::symlink_metadata(&name).ok();
    if let Some(log) = &log
        && log.len() > 0
    {
        let shown = mazewalk_maze::quote_path(&Path::new(&name).display().to_string());
        let why = format!(
            "{shown} beside it holds {} bytes of finishes not yet in the file: a server of an older \
             mazewalk runs on it, or was killed; a server that opens the file takes them in",
            log.len()
        );
        return Err(RecordsError::new(path, Fault::CannotOpen, why));
    }
    // the header: "SQLite format 3\0", …, the write and read versions at 18 and 19 (2: WAL)
    let mut header = [0u8; 20];
    let file =
        std::fs::File::open(path).map_err(|e| RecordsError::new(path, Fault::CannotOpen, e.to_string()))?;
    let read = file.take(20).read(&mut header).unwrap_or(0);
    let wal = read == 20 && header.starts_with(b"SQLite format 3\0") && (header[18] == 2 || header[19] == 2);
    Ok(wal || log.is_some())
}

/// The `file:` URI of the file at `path`, opened immutable (`mode=ro&immutable=1`: no lock, no
/// journal or WAL looked for): every byte of the path but the unreserved ones percent-encoded.
fn immutable_uri(path: &Path) -> std::ffi::OsString {
    use std::fmt::Write as _;
    use std::os::unix::ffi::OsStrExt as _;
    let bytes = path.as_os_str().as_bytes();
    // (an absolute path after an empty authority: `file:///tmp/x`)
    let mut uri = String::from(if bytes.first() == Some(&b'/') { "file://" } else { "file:" });
    for &b in bytes {
        if b.is_ascii_alphanumeric() || b"-._~/".contains(&b) {
            uri.push(char::from(b));
        } else {
            let _ = write!(uri, "%{b:02X}");
        }
    }
    uri.push_str("?mode=ro&immutable=1");
    uri.into()
}

/// The device and inode of the file at `path`, if any.
fn file_id(path: &Path) -> Option<(u64, u64)> {
    std::fs::metadata(path).ok().map(|m| (m.dev(), m.ino()))
}

/// The schema, version 2 (`PRAGMA user_version`).
const SCHEMA: &str = "
    CREATE TABLE mazes (
        hash TEXT PRIMARY KEY,     -- Maze::content_hash, hex
        name TEXT NOT NULL,        -- what the host called it when first served
        first_seen INTEGER NOT NULL
    );
    CREATE TABLE finishes (
        maze TEXT NOT NULL REFERENCES mazes(hash),
        player TEXT NOT NULL,
        seconds REAL NOT NULL,
        at INTEGER NOT NULL,       -- Unix seconds
        run BLOB                   -- the run (mazewalk_walk::run), kept for the best TOP players' bests
    );
    CREATE INDEX finishes_by_maze ON finishes (maze, player, seconds);
    PRAGMA user_version = 2;
";

/// Version 1 → 2: the finishes' runs (issue #43); older finishes have none.
const MIGRATE_1_TO_2: &str = "
    ALTER TABLE finishes ADD COLUMN run BLOB;
    PRAGMA user_version = 2;
";

/// The schema, version 1, as the mazewalk before runs made it (a25dcd1): the files it left are read,
/// and migrated by a server. Only its table `finishes` differs from [`SCHEMA`]'s (no `run`).
const SCHEMA_1: &str = "
    CREATE TABLE mazes (
        hash TEXT PRIMARY KEY,     -- Maze::content_hash, hex
        name TEXT NOT NULL,        -- what the host called it when first served
        first_seen INTEGER NOT NULL
    );
    CREATE TABLE finishes (
        maze TEXT NOT NULL REFERENCES mazes(hash),
        player TEXT NOT NULL,
        seconds REAL NOT NULL,
        at INTEGER NOT NULL        -- Unix seconds
    );
    CREATE INDEX finishes_by_maze ON finishes (maze, player, seconds);
    PRAGMA user_version = 1;
";

/// The default [`SqliteOptions::max_steps`]: 10⁸ VM steps. Listing an 84 MB file of our schema
/// (400,000 finishes of as many players, more than a server keeps in its 64 MiB) takes 18 million,
/// keeping a finish in it 27 million (BENCHMARKS.md, "Red-team pass 8, the local side"); an endless
/// query with a sort is stopped after a few seconds.
pub const MAX_STEPS: u64 = 100_000_000;

/// VM steps between two calls of the progress handler that counts them.
const STEP_CHUNK: u32 = 1000;

/// The longest string or blob a query may make or read, bytes: runs are at most [`MAX_BYTES`] and
/// names are short, so a value past this is no records file's (SQLite's own limit is 10⁹).
const MAX_VALUE: i32 = 1 << 20;

/// SQLite's heap, at most, bytes (process-wide: only SQLite's allocations count, and only the
/// records use SQLite here). With temporary tables and sorts kept in memory, a query that would
/// have filled the disk with a sort's spill fails here instead.
const MAX_HEAP: u64 = 256 << 20;

/// Schema objects (tables, indexes, triggers, views) a records file may define, at most: ours has
/// four; a file listing millions is refused while its schema is read, before anything is built.
const MAX_SCHEMA_OBJECTS: i32 = 16;

/// Bounds what any statement on `conn` can cost, whatever the file it opened holds (red-team pass 8,
/// the local side, finding 1: an 8 KB file whose `mazes` was a view over an endless recursive query
/// made `mazewalk records` spin while its sort filled the disk): views and triggers off, the
/// schema not trusted to call functions with side effects, the defensive flag on, values and the
/// schema's size limited, temporary storage in memory under a heap cap, and every call stopped
/// after `max_steps` VM steps (counted by a progress handler against the returned budget, which
/// each call fills again).
fn harden(conn: &mut Connection, max_steps: u64) -> rusqlite::Result<Arc<AtomicU64>> {
    use rusqlite::config::DbConfig;
    use rusqlite::limits::Limit;
    conn.set_db_config(DbConfig::SQLITE_DBCONFIG_DEFENSIVE, true)?;
    conn.set_db_config(DbConfig::SQLITE_DBCONFIG_TRUSTED_SCHEMA, false)?;
    conn.set_db_config(DbConfig::SQLITE_DBCONFIG_ENABLE_VIEW, false)?;
    conn.set_db_config(DbConfig::SQLITE_DBCONFIG_ENABLE_TRIGGER, false)?;
    conn.set_limit(Limit::SQLITE_LIMIT_LENGTH, MAX_VALUE)?;
    conn.set_limit(Limit::SQLITE_LIMIT_SCHEMA, MAX_SCHEMA_OBJECTS)?;
    conn.set_limit(Limit::SQLITE_LIMIT_ATTACHED, 0)?;
    conn.pragma_update(None, "temp_store", "MEMORY")?;
    // (it can only be lowered: a second connection sets the same)
    let _: i64 = conn.query_row(&format!("PRAGMA hard_heap_limit = {MAX_HEAP}"), [], |r| r.get(0))?;
    let steps = Arc::new(AtomicU64::new(max_steps / u64::from(STEP_CHUNK)));
    let left = Arc::clone(&steps);
    conn.progress_handler(
        STEP_CHUNK as i32,
        Some(move || left.fetch_update(Ordering::Relaxed, Ordering::Relaxed, |n| n.checked_sub(1)).is_err()),
    )?;
    Ok(steps)
}

/// One object of a schema as `sqlite_schema` lists it: its type, name, table and SQL text
/// ([`canonical`]; `None` for an index SQLite made itself).
type SchemaRow = (String, String, String, Option<String>);

/// `sql` with its `--` comments dropped and its white space reduced to what separates two words, so
/// that the text a table was made with and the one `ALTER TABLE … ADD COLUMN` leaves compare equal
/// when they define the same thing. (Naive about quotes, safely: what this code makes holds none, so
/// a text with a quote in it, or a `--` inside one, never compares equal to one of ours.)
fn canonical(sql: &str) -> String {
    let mut out = String::with_capacity(sql.len());
    let mut space = false;
    for line in sql.split('\n') {
        let code = line.split_once("--").map_or(line, |(code, _)| code);
        for c in code.chars().chain(['\n']) {
            // (SQLite's white space is ASCII's)
            if c.is_ascii_whitespace() {
                space = true;
                continue;
            }
            let tight = matches!(c, '(' | ')' | ',') || out.ends_with(['(', ')', ',']);
            if space && !tight && !out.is_empty() {
                out.push(' ');
            }
            space = false;
            out.push(c);
        }
    }
    out
}

/// The schema objects of `conn`'s main database, sorted.
fn schema_rows(conn: &Connection) -> rusqlite::Result<Vec<SchemaRow>> {
    let mut rows: Vec<SchemaRow> = conn
        .prepare("SELECT type, name, tbl_name, sql FROM sqlite_schema")?
        .query_map([], |r| {
            let sql: Option<String> = r.get(3)?;
            Ok((r.get(0)?, r.get(1)?, r.get(2)?, sql.as_deref().map(canonical)))
        })?
        .collect::<rusqlite::Result<_>>()?;
    rows.sort();
    Ok(rows)
}

/// The schema objects this code makes for records of `version` (0: none), as [`schema_rows`] lists
/// them: made in a database in memory from [`SCHEMA_1`] or [`SCHEMA`], so they are what SQLite
/// itself writes for them. A version 1 file migrated ([`MIGRATE_1_TO_2`]) lists the same as a new
/// version 2 one.
fn made_schema(version: i64) -> rusqlite::Result<Vec<SchemaRow>> {
    let conn = Connection::open_in_memory()?;
    match version {
        1 => conn.execute_batch(SCHEMA_1)?,
        2 => conn.execute_batch(SCHEMA)?,
        _ => {}
    }
    schema_rows(&conn)
}

/// Refuses a records file at `path` whose schema is not exactly the one this code makes for
/// `version` (1 or 2; 0: an empty file, no objects): no view, trigger, virtual table or other
/// table or index, and each of ours as made. Every query here then runs on tables and an index of
/// ours, and costs what their rows make it cost.
///
/// # Errors
/// [`Fault::Damaged`], saying what is not as this code makes it (or SQLite's reason the schema
/// cannot be read); a busy database as [`Fault::Busy`].
fn check_schema(conn: &Connection, path: &Path, version: i64) -> Result<(), RecordsError> {
    let found = schema_rows(conn).map_err(|e| match RecordsError::sqlite(path, &e) {
        err if err.fault == Fault::Busy => err,
        err => RecordsError::new(path, Fault::Damaged, format!("its schema cannot be read: {}", err.detail)),
    })?;
    let made = made_schema(version).map_err(|e| RecordsError::sqlite(path, &e))?;
    if found == made {
        return Ok(());
    }
    let quoted = |name: &str| mazewalk_maze::quote(name);
    // (most telling first: what no records file has, then what is not ours, then what is missing)
    let mut wrong: Vec<(u8, String)> = found
        .iter()
        .filter(|row| !made.contains(row))
        .map(|(kind, name, _, sql)| {
            let ours = made.iter().any(|(k, n, _, _)| k == kind && n == name);
            let virtual_table = sql.as_deref().is_some_and(|sql| sql.starts_with("CREATE VIRTUAL TABLE"));
            let (kind, name) = (quoted(kind), quoted(name));
            if virtual_table {
                (0, format!("a virtual table `{name}`"))
            } else if ours {
                (2, format!("its {kind} `{name}` is not as mazewalk makes it"))
            } else if matches!(kind.as_str(), "table" | "index") {
                (1, format!("a {kind} `{name}` of its own"))
            } else {
                (0, format!("a {kind} `{name}`"))
            }
        })
        .collect();
    wrong.extend(
        made.iter()
            .filter(|(kind, name, _, _)| !found.iter().any(|(k, n, _, _)| k == kind && n == name))
            .map(|(kind, name, _, _)| (3, format!("no {kind} `{name}`"))),
    );
    wrong.sort();
    let more = wrong.len().saturating_sub(3);
    let more = if more > 0 { format!(" and {more} more") } else { String::new() };
    let wrong: Vec<String> = wrong.into_iter().take(3).map(|(_, w)| w).collect();
    let detail = format!("its schema is not mazewalk's version {version}: {}{more}", wrong.join("; "));
    Err(RecordsError::new(path, Fault::Damaged, detail))
}

/// Refuses a `path` at which something other than a regular file is (a directory, a device, a
/// FIFO): no records file, and nothing to open, made beside it or waited on.
fn not_regular(path: &Path) -> Result<(), RecordsError> {
    match mazewalk_maze::files::not_regular(path) {
        Some(what) => Err(RecordsError::new(path, Fault::CannotOpen, format!("{what}, not a regular file"))),
        None => Ok(()),
    }
}

/// Refuses a records file beside which a `-journal`, `-wal` or `-shm` is something other than a
/// regular file (links followed): SQLite opens them itself, a hot journal's to read its first bytes,
/// and a FIFO put there (in a folder others write to, or a tar of a records file) had `mazewalk
/// records` wait for a writer for ever and `mazewalk serve` never start (red-team pass 13).
/// Looked at before every call, as a FIFO may come while serving.
fn beside_not_regular(path: &Path) -> Result<(), RecordsError> {
    for suffix in ["-journal", "-wal", "-shm"] {
        let mut name = path.as_os_str().to_owned();
        name.push(suffix);
        if let Some(what) = mazewalk_maze::files::not_regular(Path::new(&name)) {
            let shown = mazewalk_maze::quote_path(&Path::new(&name).display().to_string());
            let why = format!("{shown} beside it is {what}, not a regular file: SQLite would open it");
            return Err(RecordsError::new(path, Fault::CannotOpen, why));
        }
    }
    Ok(())
}

/// Makes the records file at `path`, mode 0600, if there is none, before SQLite opens it (so its
/// journal, made with the file's mode, is private too). A file already there is left as it is.
fn make_private(path: &Path) -> Result<(), RecordsError> {
    use std::os::unix::fs::OpenOptionsExt as _;
    match std::fs::OpenOptions::new().write(true).create_new(true).mode(0o600).open(path) {
        Ok(_) => Ok(()),
        Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => Ok(()),
        Err(e) => Err(RecordsError::new(path, Fault::CannotOpen, e.to_string())),
    }
}

impl Sqlite {
    /// Opens the records at `path` for a server, making the file (mode 0600, as the casts: it holds
    /// names and whole runs) if there is none; its folder must be there. A file that is not a records database, or a damaged one, is kept aside as
    /// `FILE.damaged-UNIXTIME` (never written over) and a new one made: the second value says where
    /// it went.
    ///
    /// # Errors
    /// The file cannot be opened, made or written, or a newer mazewalk made it.
    pub fn open(path: &Path, options: SqliteOptions) -> Result<(Sqlite, Option<PathBuf>), RecordsError> {
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty() && !d.is_dir()) {
            let why = format!(
                "no folder {} (it is not made)",
                mazewalk_maze::quote_path(&dir.display().to_string())
            );
            return Err(RecordsError::new(path, Fault::CannotOpen, why));
        }
        // SQLite would open a device or a FIFO, fail on it, and leave a journal beside it (red-team
        // pass 11: `--records /dev/zero` made `/dev/zero-journal`, mode 0666 as the device's)
        not_regular(path)?;
        beside_not_regular(path)?;
        make_private(path)?;
        match Sqlite::open_writable_within(path, options) {
            Err(err) if err.fault == Fault::Damaged => {
                let aside = keep_aside(path)?;
                make_private(path)?;
                Ok((Sqlite::open_writable(path, options)?, Some(aside)))
            }
            opened => opened.map(|db| (db, None)),
        }
    }

    /// [`open_writable`](Self::open_writable), tried again while another writer makes it answer
    /// "busy" at once (see [`Store::record`]), within the busy timeout.
    fn open_writable_within(path: &Path, options: SqliteOptions) -> Result<Sqlite, RecordsError> {
        let started = std::time::Instant::now();
        loop {
            match Sqlite::open_writable(path, options) {
                Err(err) if err.fault == Fault::Busy && started.elapsed() < options.busy_timeout => {
                    std::thread::sleep(Duration::from_millis(10));
                }
                done => return done,
            }
        }
    }

    fn open_writable(path: &Path, options: SqliteOptions) -> Result<Sqlite, RecordsError> {
        let sqlite = |e: rusqlite::Error| RecordsError::sqlite(path, &e);
        let flags = OpenFlags::SQLITE_OPEN_READ_WRITE
            | OpenFlags::SQLITE_OPEN_CREATE
            | OpenFlags::SQLITE_OPEN_NO_MUTEX;
        let mut conn = Connection::open_with_flags(path, flags).map_err(sqlite)?;
        let steps = harden(&mut conn, options.max_steps).map_err(sqlite)?;
        // (SQLite opens a file it may not write read-only, silently: asked, it says so)
        if conn.is_readonly(rusqlite::MAIN_DB).map_err(sqlite)? {
            return Err(RecordsError::new(
                path,
                Fault::ReadOnly,
                "opened read-only: the file may not be written",
            ));
        }
        conn.busy_timeout(options.busy_timeout).map_err(sqlite)?;
        // Nothing mapped (see the module's doc): no mmap, and out of WAL without touching `-shm`.
        // (`open` reads nothing: the first statement finds a file that is not a database.)
        let _: i64 = conn.pragma_update_and_check(None, "mmap_size", 0, |r| r.get(0)).map_err(sqlite)?;
        let leftover = wal_beside(path);
        if leftover {
            let _: String = conn
                .pragma_update_and_check(None, "locking_mode", "EXCLUSIVE", |r| r.get(0))
                .map_err(sqlite)?;
        }
        // (Only WAL persists in the file; every connection starts in DELETE otherwise. A WAL file
        // without a `-shm` beside gets a new one of ours for the moment it takes to leave WAL.)
        let mode: String = conn.query_row("PRAGMA journal_mode", [], |r| r.get(0)).map_err(sqlite)?;
        if mode.eq_ignore_ascii_case("wal") {
            let mode: String =
                conn.pragma_update_and_check(None, "journal_mode", "DELETE", |r| r.get(0)).map_err(sqlite)?;
            if !mode.eq_ignore_ascii_case("delete") {
                // (a read-only file answers with its old mode)
                return Err(RecordsError::new(
                    path,
                    Fault::ReadOnly,
                    format!("journal mode {mode}, not delete"),
                ));
            }
        }
        if leftover {
            // (the lock goes at the next statement's end)
            let _: String =
                conn.pragma_update_and_check(None, "locking_mode", "NORMAL", |r| r.get(0)).map_err(sqlite)?;
        }
        // (only a schema of ours is read further, or written to: a file made for this one is kept aside)
        let version: i64 = conn.query_row("PRAGMA user_version", [], |r| r.get(0)).map_err(sqlite)?;
        if version > 2 {
            return Err(RecordsError::new(path, Fault::Newer, format!("schema version {version}")));
        }
        check_schema(&conn, path, version)?;
        let page: i64 = conn.query_row("PRAGMA page_size", [], |r| r.get(0)).map_err(sqlite)?;
        let pages = (options.max_bytes / page.max(512) as u64).max(8);
        let _: i64 =
            conn.query_row(&format!("PRAGMA max_page_count = {pages}"), [], |r| r.get(0)).map_err(sqlite)?;
        let check: String = conn.query_row("PRAGMA quick_check", [], |r| r.get(0)).map_err(sqlite)?;
        if check != "ok" {
            return Err(RecordsError::new(path, Fault::Damaged, check));
        }
        let mut db = Sqlite { conn, path: path.to_path_buf(), options, file: None, lost: false, steps };
        match version {
            0 => db.conn.execute_batch(&format!("BEGIN IMMEDIATE; {SCHEMA} COMMIT;")).map_err(sqlite)?,
            1 => db
                .conn
                .execute_batch(&format!("BEGIN IMMEDIATE; {MIGRATE_1_TO_2} COMMIT;"))
                .map_err(sqlite)?,
            _ => {}
        }
        db.file = file_id(path);
        Ok(db)
    }

    /// Opens the records at `path` to read them (`mazewalk records`); changes nothing. The file may
    /// be anyone's: only one whose schema is exactly one this code makes is read, and every query
    /// on it is bounded as a server's are (see [`Sqlite::open`]).
    ///
    /// # Errors
    /// The file does not exist, cannot be read, is not a records database (its schema not ours), or
    /// is a newer one.
    pub fn open_to_read(path: &Path) -> Result<Sqlite, RecordsError> {
        let sqlite = |e: rusqlite::Error| RecordsError::sqlite(path, &e);
        not_regular(path)?;
        beside_not_regular(path)?;
        if !path.is_file() {
            return Err(RecordsError::new(path, Fault::CannotOpen, "no such file: no records yet"));
        }
        let flags = OpenFlags::SQLITE_OPEN_READ_ONLY | OpenFlags::SQLITE_OPEN_NO_MUTEX;
        let mut conn = match wal_to_read(path)? {
            // (read as it is: no `-wal` or `-shm` made beside it, nothing mapped)
            true => Connection::open_with_flags(immutable_uri(path), flags | OpenFlags::SQLITE_OPEN_URI),
            false => Connection::open_with_flags(path, flags),
        }
        .map_err(sqlite)?;
        let options = SqliteOptions::default();
        let steps = harden(&mut conn, options.max_steps).map_err(sqlite)?;
        conn.busy_timeout(Duration::from_secs(2)).map_err(sqlite)?;
        let _: i64 = conn.pragma_update_and_check(None, "mmap_size", 0, |r| r.get(0)).map_err(sqlite)?;
        let db = Sqlite { conn, path: path.to_path_buf(), options, file: file_id(path), lost: false, steps };
        match db.version()? {
            version @ (1 | 2) => check_schema(&db.conn, path, version).map(|()| db),
            0 => Err(RecordsError::new(path, Fault::Damaged, "no records tables")),
            newer => Err(RecordsError::new(path, Fault::Newer, format!("schema version {newer}"))),
        }
    }

    /// Fills the step budget again for a call ([`SqliteOptions::max_steps`]).
    fn budget(&self) {
        self.steps.store(self.options.max_steps / u64::from(STEP_CHUNK), Ordering::Relaxed);
    }

    fn version(&self) -> Result<i64, RecordsError> {
        self.conn
            .query_row("PRAGMA user_version", [], |r| r.get(0))
            .map_err(|e| RecordsError::sqlite(&self.path, &e))
    }

    /// Keeps the runs of the best finish of each of `maze`'s best [`TOP`] players with runs, and
    /// forgets the others (so a maze holds at most `TOP` runs, each at most [`MAX_BYTES`]).
    fn keep_top_runs(conn: &Connection, maze: &str) -> rusqlite::Result<()> {
        let rows: Vec<(i64, String)> = conn
            .prepare(
                "SELECT rowid, player FROM finishes WHERE maze = ?1 AND run IS NOT NULL ORDER BY seconds, at",
            )?
            .query_map(params![maze], |r| Ok((r.get(0)?, r.get(1)?)))?
            .collect::<rusqlite::Result<_>>()?;
        let mut players: Vec<&str> = Vec::new();
        for (rowid, player) in &rows {
            if players.len() < TOP && !players.contains(&player.as_str()) {
                players.push(player);
            } else {
                conn.execute("UPDATE finishes SET run = NULL WHERE rowid = ?1", params![rowid])?;
            }
        }
        Ok(())
    }

    /// The best [`TOP`] of `maze`, best first.
    fn top(conn: &Connection, maze: &str) -> rusqlite::Result<Vec<Best>> {
        // (SQLite gives the bare column `at` of the row holding the MIN)
        let mut stmt = conn.prepare(
            "SELECT player, MIN(seconds) AS best, at FROM finishes WHERE maze = ?1
             GROUP BY player ORDER BY best, at, player LIMIT ?2",
        )?;
        let rows = stmt.query_map(params![maze, TOP as i64], |r| {
            Ok(Best { player: r.get(0)?, seconds: r.get(1)?, at: r.get(2)? })
        })?;
        rows.collect()
    }
}

/// Moves a damaged database (and its `-wal` and `-shm`) aside; returns the new name.
fn keep_aside(path: &Path) -> Result<PathBuf, RecordsError> {
    let secs = std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).map_or(0, |d| d.as_secs());
    let with = |suffix: &str| {
        let mut name = path.as_os_str().to_owned();
        name.push(suffix);
        PathBuf::from(name)
    };
    let aside =
        (0..100)
            .map(|n| {
                if n == 0 { with(&format!(".damaged-{secs}")) } else { with(&format!(".damaged-{secs}-{n}")) }
            })
            .find(|p| !p.exists())
            .ok_or_else(|| RecordsError::new(path, Fault::Damaged, "no free name to keep it aside"))?;
    std::fs::rename(path, &aside)
        .map_err(|e| RecordsError::new(path, Fault::Damaged, format!("cannot keep it aside: {e}")))?;
    for part in ["-wal", "-shm"] {
        let (from, to) = (with(part), {
            let mut n = aside.as_os_str().to_owned();
            n.push(part);
            PathBuf::from(n)
        });
        if from.exists() {
            let _ = std::fs::rename(from, to);
        }
    }
    Ok(aside)
}

impl Sqlite {
    /// One try at [`Store::record`]'s transaction.
    fn record_once(&mut self, finish: &Finish) -> Result<Standing, RecordsError> {
        let path = self.path.clone();
        let sqlite = |e: rusqlite::Error| RecordsError::sqlite(&path, &e);
        let maze = finish.maze.to_string();
        let tx =
            self.conn.transaction_with_behavior(rusqlite::TransactionBehavior::Immediate).map_err(sqlite)?;
        tx.execute(
            "INSERT OR IGNORE INTO mazes (hash, name, first_seen) VALUES (?1, ?2, ?3)",
            params![maze, finish.maze_name, finish.at],
        )
        .map_err(sqlite)?;
        let run = finish.run.as_deref().filter(|r| r.len() <= MAX_BYTES);
        tx.execute(
            "INSERT INTO finishes (maze, player, seconds, at, run) VALUES (?1, ?2, ?3, ?4, ?5)",
            params![maze, finish.player, finish.seconds, finish.at, run],
        )
        .map_err(sqlite)?;
        // (the player's best FINISHES_PER_PLAYER kept: finishing again and again cannot fill it)
        tx.execute(
            "DELETE FROM finishes WHERE maze = ?1 AND player = ?2 AND rowid NOT IN
             (SELECT rowid FROM finishes WHERE maze = ?1 AND player = ?2 ORDER BY seconds, at LIMIT ?3)",
            params![maze, finish.player, FINISHES_PER_PLAYER as i64],
        )
        .map_err(sqlite)?;
        if run.is_some() {
            Sqlite::keep_top_runs(&tx, &maze).map_err(sqlite)?;
        }
        let best: f64 = tx
            .query_row(
                "SELECT MIN(seconds) FROM finishes WHERE maze = ?1 AND player = ?2",
                params![maze, finish.player],
                |r| r.get(0),
            )
            .map_err(sqlite)?;
        let ahead: i64 = tx
            .query_row(
                "SELECT COUNT(*) FROM (SELECT player FROM finishes WHERE maze = ?1 AND player <> ?2
                 GROUP BY player HAVING MIN(seconds) < ?3)",
                params![maze, finish.player, best],
                |r| r.get(0),
            )
            .map_err(sqlite)?;
        let players: i64 = tx
            .query_row("SELECT COUNT(DISTINCT player) FROM finishes WHERE maze = ?1", params![maze], |r| {
                r.get(0)
            })
            .map_err(sqlite)?;
        let top = Sqlite::top(&tx, &maze).map_err(sqlite)?;
        tx.commit().map_err(sqlite)?;
        Ok(Standing { top, best, rank: ahead as usize + 1, players: players as usize })
    }
}

impl Sqlite {
    /// [`record_once`](Self::record_once), again while "busy" within the busy timeout. Two writers
    /// on one file with a rollback journal can each wait for the other; SQLite then answers one of
    /// them "busy" at once rather than wait (sqlite.org/c3ref/busy_handler.html).
    fn record_busy(&mut self, finish: &Finish) -> Result<Standing, RecordsError> {
        let started = std::time::Instant::now();
        loop {
            match self.record_once(finish) {
                Err(err) if err.fault == Fault::Busy && started.elapsed() < self.options.busy_timeout => {
                    std::thread::sleep(Duration::from_millis(10));
                }
                done => return done,
            }
        }
    }

    /// Deletes the worst quarter (at most [`PRUNE`]) of the finishes of the maze with the most, if
    /// more than `TOP × FINISHES_PER_PLAYER` stay (so every best-[`TOP`] player's best stays: at
    /// most that many finishes are better than the last of them); whether any went.
    fn prune_worst(&mut self) -> rusqlite::Result<bool> {
        let tx = self.conn.transaction_with_behavior(rusqlite::TransactionBehavior::Immediate)?;
        let fullest: Option<(String, i64)> = tx
            .query_row(
                "SELECT maze, COUNT(*) AS n FROM finishes GROUP BY maze ORDER BY n DESC LIMIT 1",
                [],
                |r| Ok((r.get(0)?, r.get(1)?)),
            )
            .optional()?;
        let Some((maze, n)) = fullest else { return Ok(false) };
        let prune = (n / 4).min(PRUNE);
        if prune == 0 || n - prune <= (TOP * FINISHES_PER_PLAYER) as i64 {
            return Ok(false);
        }
        let gone = tx.execute(
            "DELETE FROM finishes WHERE rowid IN
             (SELECT rowid FROM finishes WHERE maze = ?1 ORDER BY seconds DESC, at DESC LIMIT ?2)",
            params![maze, prune],
        )?;
        tx.commit()?;
        Ok(gone > 0)
    }
}

impl Store for Sqlite {
    fn record(&mut self, finish: &Finish) -> Result<Standing, RecordsError> {
        if self.lost {
            return Err(RecordsError::new(&self.path, Fault::CannotOpen, "gone while serving"));
        }
        beside_not_regular(&self.path)?;
        self.budget();
        match self.record_busy(finish) {
            // Full (at its size limit, or the disk): the worst finishes make room, once.
            Err(err) if err.fault == Fault::Full && self.prune_worst().unwrap_or(false) => {
                self.budget();
                self.record_busy(finish)
            }
            done => done,
        }
    }

    fn run(&mut self, maze: &ContentHash, player: Option<&str>) -> Result<Option<StoredRun>, RecordsError> {
        beside_not_regular(&self.path)?;
        self.budget();
        if self.version()? < 2 {
            return Ok(None); // (a file of an older mazewalk, read only: no runs)
        }
        let path = self.path.clone();
        self.conn
            .query_row(
                "SELECT player, seconds, run FROM finishes WHERE maze = ?1 AND run IS NOT NULL
                 AND length(run) <= ?3 AND (?2 IS NULL OR player = ?2) ORDER BY seconds, at LIMIT 1",
                params![maze.to_string(), player, MAX_BYTES as i64],
                |r| Ok(StoredRun { player: r.get(0)?, seconds: r.get(1)?, bytes: r.get(2)? }),
            )
            .optional()
            .map_err(|e| RecordsError::sqlite(&path, &e))
    }

    fn check(&mut self) -> Option<String> {
        let now = file_id(&self.path);
        if now == self.file {
            return None;
        }
        self.file = now; // (said once per change)
        let what = if now.is_none() { "was deleted" } else { "was replaced" };
        let path = mazewalk_maze::quote_path(&self.path.display().to_string());
        Some(match Sqlite::open(&self.path, self.options) {
            Ok((db, aside)) => {
                let made = if now.is_none() { "a new one is made" } else { "the new one is used" };
                let aside = aside.map(|a| {
                    format!(
                        " (the file found there kept as {})",
                        mazewalk_maze::quote_path(&a.display().to_string())
                    )
                });
                let line =
                    format!("records: {path} {what} while serving; {made}{}", aside.unwrap_or_default());
                *self = db;
                line
            }
            Err(err) => {
                self.lost = true;
                format!("records: {path} {what} while serving and cannot be opened again: {err}")
            }
        })
    }

    fn mazes(&mut self, maze: Option<&ContentHash>) -> Result<Vec<MazeRecords>, RecordsError> {
        beside_not_regular(&self.path)?;
        self.budget();
        let path = self.path.clone();
        let sqlite = |e: rusqlite::Error| RecordsError::sqlite(&path, &e);
        let only = maze.map(ToString::to_string);
        let mut stmt = self
            .conn
            .prepare(
                "SELECT m.hash, m.name, COUNT(DISTINCT f.player), COUNT(f.player) FROM mazes m
                 LEFT JOIN finishes f ON f.maze = m.hash WHERE ?1 IS NULL OR m.hash = ?1
                 GROUP BY m.hash ORDER BY m.first_seen, m.hash",
            )
            .map_err(sqlite)?;
        let rows: Vec<(String, String, i64, i64)> = stmt
            .query_map(params![only], |r| Ok((r.get(0)?, r.get(1)?, r.get(2)?, r.get(3)?)))
            .and_then(Iterator::collect)
            .map_err(sqlite)?;
        rows.into_iter()
            .map(|(hash, name, players, finishes)| {
                let top = Sqlite::top(&self.conn, &hash).map_err(sqlite)?;
                Ok(MazeRecords {
                    maze: hash,
                    name,
                    players: players as usize,
                    finishes: finishes as usize,
                    top,
                })
            })
            .collect()
    }
}

impl Sqlite {
    /// Whether the database holds `maze` (for a clear message when it does not).
    ///
    /// # Errors
    /// The database failed.
    pub fn knows(&self, maze: &ContentHash) -> Result<bool, RecordsError> {
        self.budget();
        self.conn
            .query_row("SELECT 1 FROM mazes WHERE hash = ?1", params![maze.to_string()], |_| Ok(()))
            .optional()
            .map(|found| found.is_some())
            .map_err(|e| RecordsError::sqlite(&self.path, &e))
    }
}

/// What the records thread says to the host (the server logs it; tests collect it).
pub type Report = Arc<dyn Fn(&str) + Send + Sync>;

/// A finish on its way to the records thread, with where to send the answer.
enum Job {
    /// A finish to keep, and where its standing goes.
    Finish(Finish, oneshot::Sender<Option<Standing>>),
    /// Read the best run again ([`Records::reread_best_run`]).
    Reread,
}

/// The records thread's handle: hands it finishes without waiting (see the module's doc). Clones share
/// the thread, which ends when the last clone is dropped.
#[derive(Clone)]
pub struct Records {
    jobs: mpsc::SyncSender<Job>,
    dropped: Arc<AtomicU64>,
    tally: Arc<Tally>,
    report: Report,
    /// Hangs up when the thread ends (every clone holds the receiving end's partner).
    done: Arc<Mutex<mpsc::Receiver<()>>>,
    /// The served maze's best run, decoded and checked, for its ghost ([`Race`]).
    best_run: BestRun,
    /// A [`Job::Reread`] waits in the queue (at most one does).
    reread_queued: Arc<AtomicBool>,
}

/// The best run as the records thread last read it (`None`: none, or none valid).
type BestRun = Arc<Mutex<Option<Arc<Run>>>>;

/// The maze whose best run the records thread reads (at start and after each finish with a run),
/// checks and offers to its players as a ghost ([`Records::best_run`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Race {
    /// The maze's content hash.
    pub maze: ContentHash,
    /// The maze's extents: a run outside them is refused.
    pub extents: Aabb,
}

impl std::fmt::Debug for Records {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Records")
            .field("dropped", &self.dropped.load(Ordering::Relaxed))
            .finish_non_exhaustive()
    }
}

impl Records {
    /// Starts the records thread over `store`; what goes wrong is said once through `report`.
    ///
    /// # Errors
    /// The thread cannot be started.
    pub fn start(store: impl Store, report: Report) -> std::io::Result<Records> {
        Records::start_racing(store, report, None)
    }

    /// [`start`](Self::start), and with `race` the maze's best run read, checked and offered as
    /// [`best_run`](Self::best_run).
    ///
    /// # Errors
    /// The thread cannot be started.
    pub fn start_racing(store: impl Store, report: Report, race: Option<Race>) -> std::io::Result<Records> {
        let best_run: BestRun = Arc::default();
        let thread_best = Arc::clone(&best_run);
        let (jobs, queue) = mpsc::sync_channel::<Job>(QUEUE);
        let reread_queued = Arc::new(AtomicBool::new(false));
        let thread_reread = Arc::clone(&reread_queued);
        let (ended, done) = mpsc::channel::<()>();
        let thread_report = Arc::clone(&report);
        let tally = Arc::new(Tally::default());
        let thread_tally = Arc::clone(&tally);
        std::thread::Builder::new().name("records".into()).spawn(move || {
            let race = race.map(|race| (race, &*thread_best));
            keep(store, (&queue, &thread_reread), &*thread_report, &thread_tally, race);
            drop(ended);
        })?;
        let done = Arc::new(Mutex::new(done));
        Ok(Records {
            jobs,
            dropped: Arc::new(AtomicU64::new(0)),
            tally,
            report,
            done,
            best_run,
            reread_queued,
        })
    }

    /// The served maze's best run, for its ghost: read by the records thread at start and after each
    /// finish that kept a run, decoded and checked against the maze ([`Race`]). `None` without a
    /// race, before any finish with a run, or while the one stored is damaged.
    #[must_use]
    pub fn best_run(&self) -> Option<Arc<Run>> {
        self.best_run.lock().unwrap_or_else(PoisonError::into_inner).clone()
    }

    /// Asks the records thread to read the best run again now (and once more [`REREAD_AGAIN`] later):
    /// another server in the world reached the exit, and its run may be the best. Never waits; while
    /// one such request waits in the queue, more are the same one (a full queue drops it: the
    /// thread reads again every [`REREAD_BEST_RUN`] anyway).
    pub fn reread_best_run(&self) {
        if !self.reread_queued.swap(true, Ordering::AcqRel) && self.jobs.try_send(Job::Reread).is_err() {
            self.reread_queued.store(false, Ordering::Release);
        }
    }

    /// Lets the thread finish what it was handed (once every other clone is gone too) and waits for it,
    /// `within` at most. Returns whether it finished.
    #[must_use]
    pub fn close(self, within: Duration) -> bool {
        let Records { jobs, done, .. } = self;
        drop(jobs);
        let done = done.lock().unwrap_or_else(PoisonError::into_inner);
        matches!(done.recv_timeout(within), Err(mpsc::RecvTimeoutError::Disconnected))
    }

    /// Hands `finish` to the records thread without waiting: the answer (the player's standing, from
    /// the store or, while it fails, from memory) comes on the returned channel. `None` when the queue is full
    /// (the finish is dropped and counted; the first drop is reported) or the thread is gone.
    #[must_use]
    pub fn finish(&self, finish: Finish) -> Option<oneshot::Receiver<Option<Standing>>> {
        let (answer, standing) = oneshot::channel();
        match self.jobs.try_send(Job::Finish(finish, answer)) {
            Ok(()) => Some(standing),
            Err(mpsc::TrySendError::Full(_)) => {
                if self.dropped.fetch_add(1, Ordering::Relaxed) == 0 {
                    (self.report)("records: the database is slow: finishes are dropped while it catches up");
                }
                None
            }
            Err(mpsc::TrySendError::Disconnected(_)) => None,
        }
    }

    /// Finishes dropped so far because the queue was full.
    #[must_use]
    pub fn dropped(&self) -> u64 {
        self.dropped.load(Ordering::Relaxed)
    }

    /// Finishes the store kept as they came, and those it could not (kept in memory for the ranking
    /// and written once it works again), so far.
    #[must_use]
    pub fn written_failed(&self) -> (u64, u64) {
        (self.tally.written.load(Ordering::Relaxed), self.tally.failed.load(Ordering::Relaxed))
    }
}

/// What the records thread did with the finishes as they came ([`Records::written_failed`]).
#[derive(Debug, Default)]
struct Tally {
    written: AtomicU64,
    failed: AtomicU64,
}

/// Finishes the store could not keep that are written when it takes them again, at most (the
/// latest; the ranking in memory keeps every player's best whatever this says).
pub const UNSAVED: usize = 256;
/// Players' bests kept in memory for the ranking while the store fails, at most, in all mazes.
const MEMORY: usize = 10_000;
/// A fault is said again at most this often (after the store worked in between).
const SAY_AGAIN: Duration = Duration::from_secs(60);
/// While the store fails, the finishes it missed are tried again this often, finish or no finish.
pub(crate) const RETRY: Duration = Duration::from_secs(2);

/// A maze's ranking while its store fails: the store's last answer, and this run's bests.
#[derive(Debug, Default)]
struct Remembered {
    /// The store's last best ten, and how many players it had.
    top: Vec<Best>,
    players: usize,
    /// Each player's best in this run (kept by the store or not).
    bests: HashMap<String, Best>,
}

/// The records thread's memory: what the players' ranking needs while the store fails (bounded by
/// [`MEMORY`] players and [`UNSAVED`] finishes).
#[derive(Debug, Default)]
struct Memory {
    mazes: HashMap<ContentHash, Remembered>,
    bests: usize,
    unsaved: std::collections::VecDeque<Finish>,
}

impl Memory {
    /// The store kept `finish` and answered `standing`: the maze's ranking as the store has it.
    fn stored(&mut self, finish: &Finish, standing: &Standing) {
        if let Some(maze) = self.maze(finish.maze) {
            maze.top.clone_from(&standing.top);
            maze.players = standing.players;
        }
        self.note(finish);
    }

    /// `finish`'s player's best on its maze, kept (if there is room).
    fn note(&mut self, finish: &Finish) {
        let room = self.bests < MEMORY;
        let Some(maze) = self.maze(finish.maze) else { return };
        let mine = Best { player: finish.player.clone(), seconds: finish.seconds, at: finish.at };
        match maze.bests.get_mut(&finish.player) {
            Some(best) if best.seconds <= mine.seconds => {}
            Some(best) => *best = mine,
            None if room => {
                maze.bests.insert(finish.player.clone(), mine);
                self.bests += 1;
            }
            None => {}
        }
    }

    /// The maze's memory, if it has one or there is room for one.
    fn maze(&mut self, maze: ContentHash) -> Option<&mut Remembered> {
        if !self.mazes.contains_key(&maze) && self.mazes.len() >= MEMORY {
            return None;
        }
        Some(self.mazes.entry(maze).or_default())
    }

    /// Writes the finishes the store missed, oldest first, until one fails; whether all went.
    fn flush(&mut self, store: &mut impl Store) -> bool {
        while let Some(unsaved) = self.unsaved.pop_front() {
            if store.record(&unsaved).is_err() {
                self.unsaved.push_front(unsaved);
                return false;
            }
        }
        true
    }

    /// The store could not keep `finish`: remembered, and the player's standing among what is known.
    fn remember(&mut self, finish: &Finish) -> Standing {
        // (without its run: 256 unsaved runs could take 16 MiB; a finish the store missed keeps none)
        self.unsaved.push_back(Finish { run: None, ..finish.clone() });
        if self.unsaved.len() > UNSAVED {
            self.unsaved.pop_front();
        }
        let mine = Best { player: finish.player.clone(), seconds: finish.seconds, at: finish.at };
        self.note(finish);
        let none = Remembered::default();
        Memory::standing(self.mazes.get(&finish.maze).unwrap_or(&none), mine)
    }

    /// Where `mine`'s player stands among `maze`'s store's best ten and this run's bests (players of
    /// earlier runs below the ten are not known: the rank may be higher than the store's would be).
    fn standing(maze: &Remembered, mine: Best) -> Standing {
        let mut all: HashMap<&str, &Best> = HashMap::new();
        for best in maze.top.iter().chain(maze.bests.values()).chain(std::iter::once(&mine)) {
            let kept = all.entry(best.player.as_str()).or_insert(best);
            if best.seconds < kept.seconds {
                *kept = best;
            }
        }
        let mut list: Vec<Best> = all.into_values().cloned().collect();
        list.sort_by(|a, b| {
            a.seconds.total_cmp(&b.seconds).then(a.at.cmp(&b.at)).then(a.player.cmp(&b.player))
        });
        let best = list.iter().find(|b| b.player == mine.player).map_or(mine.seconds, |b| b.seconds);
        let ahead = list.iter().filter(|b| b.seconds < best && b.player != mine.player).count();
        let players = maze.players.max(list.len());
        list.truncate(TOP);
        Standing { top: list, best, rank: ahead + 1, players }
    }
}

/// The records thread: keeps each finish in the store (or, while it fails, in [`Memory`]), and
/// answers every finish with its standing; says each change of the store's file and each fault.
fn keep(
    mut store: impl Store,
    (queue, reread_queued): (&mpsc::Receiver<Job>, &AtomicBool),
    report: &(dyn Fn(&str) + Send + Sync),
    tally: &Tally,
    race: Option<(Race, &Mutex<Option<Arc<Run>>>)>,
) {
    // the best run's fault last said (each said once, until a read goes well)
    let mut run_fault: Option<String> = None;
    let mut read_best = |store: &mut dyn StoreRuns| {
        if let Some((race, best)) = race {
            let run = match best_run(store, race) {
                Ok(run) => {
                    run_fault = None;
                    run
                }
                Err(line) => {
                    if run_fault.as_ref() != Some(&line) {
                        report(&line);
                        run_fault = Some(line);
                    }
                    None
                }
            };
            *best.lock().unwrap_or_else(PoisonError::into_inner) = run.map(Arc::new);
        }
    };
    read_best(&mut store);
    let mut memory = Memory::default();
    let mut failing = false;
    let mut said: Option<std::time::Instant> = None;
    // (read again now and then: another server on the file, or in the world, may have beaten it;
    // and once more a little after a remote finish, whose run may have been stored after its word)
    let mut read_at = Instant::now() + REREAD_BEST_RUN;
    let mut again_at: Option<Instant> = None;
    let mut retry_at = Instant::now() + RETRY;
    loop {
        let mut next = again_at.map_or(read_at, |again| again.min(read_at));
        if failing {
            next = next.min(retry_at);
        }
        let (finish, answer) = match queue.recv_timeout(next.saturating_duration_since(Instant::now())) {
            Ok(Job::Finish(finish, answer)) => (finish, answer),
            Ok(Job::Reread) => {
                reread_queued.store(false, Ordering::Release);
                read_best(&mut store);
                again_at = Some(Instant::now() + REREAD_AGAIN);
                continue;
            }
            Err(mpsc::RecvTimeoutError::Timeout) => {
                let now = Instant::now();
                if failing && retry_at <= now {
                    // (the finishes it missed, tried again even if no finish comes to carry them)
                    retry_at = now + RETRY;
                    if let Some(line) = store.check() {
                        report(&line);
                    }
                    failing = !memory.flush(&mut store);
                }
                if read_at <= now || again_at.is_some_and(|again| again <= now) {
                    read_best(&mut store);
                    again_at = again_at.filter(|&again| again > now);
                    if read_at <= now {
                        read_at = now + REREAD_BEST_RUN;
                    }
                }
                continue;
            }
            Err(mpsc::RecvTimeoutError::Disconnected) => break,
        };
        if let Some(line) = store.check() {
            report(&line);
        }
        // While it fails, the finishes it missed go first, oldest first; while they cannot, this
        // one is not tried either.
        let tried = if failing && !memory.flush(&mut store) { None } else { Some(store.record(&finish)) };
        let written = matches!(tried, Some(Ok(_)));
        (if written { &tally.written } else { &tally.failed }).fetch_add(1, Ordering::Relaxed);
        let standing = match tried {
            Some(Ok(standing)) => {
                failing = false;
                memory.stored(&finish, &standing);
                if finish.run.is_some() {
                    read_best(&mut store);
                }
                standing
            }
            Some(Err(err)) => {
                retry_at = Instant::now() + RETRY;
                if !std::mem::replace(&mut failing, true) && said.is_none_or(|at| at.elapsed() >= SAY_AGAIN) {
                    said = Some(std::time::Instant::now());
                    report(&format!("records: {err}; finishes are kept in memory for the ranking meanwhile"));
                }
                memory.remember(&finish)
            }
            None => memory.remember(&finish), // (said already)
        };
        let _ = answer.send(Some(standing));
    }
    // Stopping: one last try for the finishes it missed (at most one busy timeout: the first that
    // fails stops it), and those that could not be kept said.
    if !memory.unsaved.is_empty() {
        if let Some(line) = store.check() {
            report(&line);
        }
        memory.flush(&mut store);
        if !memory.unsaved.is_empty() {
            report(&format!(
                "records: {} finishes could not be kept (the store failed to the end); they are lost",
                memory.unsaved.len()
            ));
        }
    }
}

/// [`Store::run`] as an object (the records thread reads the best run through it).
trait StoreRuns {
    fn best(&mut self, maze: &ContentHash) -> Result<Option<StoredRun>, RecordsError>;
}

impl<S: Store> StoreRuns for S {
    fn best(&mut self, maze: &ContentHash) -> Result<Option<StoredRun>, RecordsError> {
        self.run(maze, None)
    }
}

/// How often the records thread reads the best run again with no finish of its own (another server
/// on the same file, or in the same world, may have made a better one).
const REREAD_BEST_RUN: Duration = Duration::from_secs(30);

/// After a read asked for ([`Records::reread_best_run`]), the next, in case the remote server's
/// run reached the store after its word reached this server.
const REREAD_AGAIN: Duration = Duration::from_secs(3);

/// `race`'s maze's best run from `store`, decoded and checked, labelled with its player's name as
/// [`player_name`] cleans it (`None`: none kept); a run that fails, or a store that does, is the line
/// to say, and no ghost.
fn best_run(store: &mut dyn StoreRuns, race: Race) -> Result<Option<Run>, String> {
    let stored = match store.best(&race.maze) {
        Ok(Some(stored)) => stored,
        Ok(None) => return Ok(None),
        Err(err) => return Err(format!("records: cannot read the best run: {err}")),
    };
    let checked =
        Run::decode(&stored.bytes).and_then(|run| run.check_maze(race.maze, race.extents).map(|()| run));
    match checked {
        Ok(mut run) => {
            run.holder = player_name(&stored.player); // (ASCII, at most 16 characters)
            Ok(Some(run))
        }
        Err(err) => {
            let who = player_name(&stored.player);
            Err(format!("records: the best run ({who}'s) is not usable, no ghost: {err}"))
        }
    }
}

/// A server's records: where finishes go, and the maze they are kept under.
#[derive(Clone, Debug)]
pub struct Keeper {
    /// The records thread.
    pub records: Records,
    /// The maze's content hash.
    pub maze: ContentHash,
    /// What the host calls the maze.
    pub maze_name: String,
}

impl Keeper {
    /// Hands over `player`'s finish in `seconds`, now, with its `run` if it kept one (encoded:
    /// [`Run::encode`]; [`Records::finish`]).
    #[must_use]
    pub fn finish(
        &self,
        player: &str,
        seconds: f64,
        run: Option<Vec<u8>>,
    ) -> Option<oneshot::Receiver<Option<Standing>>> {
        let at =
            std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).map_or(0, |d| d.as_secs());
        self.records.finish(Finish {
            maze: self.maze,
            maze_name: self.maze_name.clone(),
            player: player.to_string(),
            seconds,
            at: i64::try_from(at).unwrap_or(i64::MAX),
            run,
        })
    }
}

/// The lines of the exit box, where the best times would stand, for a walk that started `ahead`
/// cells' steps nearer the exit than the maze's start (a crowd took the cells behind it,
/// [`crate::spawn`]): why it is not kept in the records.
#[must_use]
pub fn head_start_lines(ahead: u32) -> Vec<String> {
    let cells = if ahead == 1 { "1 cell".to_string() } else { format!("{ahead} cells") };
    vec![
        String::new(),
        "Not kept in the records: this walk".to_string(),
        format!("started {cells} nearer the exit"),
        "than the maze's start (a crowd".to_string(),
        "stood on the cells behind it).".to_string(),
        "Walk back to the start: there".to_string(),
        "the clock starts again, for the".to_string(),
        "records.".to_string(),
    ]
}

/// The lines of the exit box for `standing`: the maze's best ten, the player's row marked, and its
/// rank below them when it is not among them. Every name is shown as [`player_name`] cleans it
/// (issue #40: the records file, or whoever wrote it, may hold anything).
#[must_use]
pub fn standing_lines(standing: &Standing, player: &str) -> Vec<String> {
    let clock = mazewalk_walk::clock::clock_text;
    let names: Vec<String> = standing.top.iter().map(|b| player_name(&b.player)).collect();
    let player = player_name(player);
    let width = names.iter().map(|n| n.chars().count()).max().unwrap_or(0);
    let players =
        if standing.players == 1 { "1 player".to_string() } else { format!("{} players", standing.players) };
    let mut lines = vec![String::new(), format!("Best times here ({players})")];
    for (i, (best, name)) in standing.top.iter().zip(&names).enumerate() {
        let you = if *name == player { "  you" } else { "" };
        lines.push(format!("{:>2}. {name:<width$}  {}{you}", i + 1, clock(best.seconds)));
    }
    if !names.contains(&player) {
        lines.push(format!("{:>2}. {player}  {}  you", standing.rank, clock(standing.best)));
    }
    lines
}
