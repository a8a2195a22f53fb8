//! The work of each command of the `mazewalk` binary, one module a command; `main.rs` parses the
//! command line, dispatches here and turns the outcome into an exit code. What the commands share:
//! the maze the flags name, usage errors, and writing to standard output that may be closed or go
//! away.

use std::sync::atomic::{AtomicU8, Ordering};

use anyhow::bail;

use crate::cli::MazeArgs;
use mazewalk_maze::generate::{GenOptions, generate};
use mazewalk_maze::{self as maze, Maze};

pub mod check;
pub mod generate;
pub mod records;
pub mod render;
pub mod serve;
#[cfg(unix)]
pub mod walk;

/// A flag value that parsed but makes no sense here (e.g. --at outside the maze): exit 2.
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct Usage(pub String);

/// A file named on the command line, other than a maze, that cannot be read (a run): exit 66, as a
/// maze file's.
#[derive(Debug, thiserror::Error)]
#[error("cannot read {what}")]
pub struct NoInput {
    /// What the file is, and its path, quoted.
    pub what: String,
    /// Why.
    #[source]
    pub source: std::io::Error,
}

/// A file named on the command line, other than a maze, whose contents are not what it should be (a
/// run that does not decode, or is of another maze): exit 65, as a malformed maze's.
#[derive(Debug, thiserror::Error)]
#[error("{what}")]
pub struct BadData {
    /// What the file is, and its path, quoted.
    pub what: String,
    /// What is wrong.
    #[source]
    pub source: Box<dyn std::error::Error + Send + Sync>,
}

/// The path that names standard output in `render --png`, `--depth-out` and `gen -o`.
pub const STDOUT: &str = "-";

/// Whether `err` is, or was caused by, writing to a pipe nobody reads.
pub fn is_broken_pipe(err: &anyhow::Error) -> bool {
    let broken = |e: &std::io::Error| e.kind() == std::io::ErrorKind::BrokenPipe;
    err.chain().any(|e| match e.downcast_ref::<maze::cs559::WriteToError>() {
        Some(maze::cs559::WriteToError::Io(e)) => broken(e),
        _ => e.downcast_ref::<std::io::Error>().is_some_and(broken),
    })
}

/// What fd 1 was when the process started, as [`note_stdout_at_start`] saw it: not looked at (a
/// library caller), open, or closed.
static STDOUT_AT_START: AtomicU8 = AtomicU8::new(NOT_LOOKED);
const NOT_LOOKED: u8 = 0;
const OPEN: u8 = 1;
const CLOSED: u8 = 2;

/// Looks at standard output (fd 1) before Rust's start-up does, for [`stdout_open`]: the binary
/// calls it from a function the loader runs before `main` (`main.rs`). The start-up opens /dev/null
/// read-write in place of a closed standard descriptor, after which a closed stdout (`>&-`) and one
/// on /dev/null opened read-write (`1<>/dev/null`, Python's `subprocess.DEVNULL`, systemd's
/// `StandardOutput=null`) look the same.
pub fn note_stdout_at_start() {
    let closed = rustix::io::fcntl_getfd(std::io::stdout()).is_err(); // (EBADF: no such descriptor)
    STDOUT_AT_START.store(if closed { CLOSED } else { OPEN }, Ordering::Relaxed);
}

/// Fails if stdout was closed (`>&-`), so that a command does not exit 0 having written nothing.
/// Whether it was is known from before Rust's start-up replaced it ([`note_stdout_at_start`]);
/// a descriptor closed since then fails `fstat`. (Red-team pass 8, the local side, finding 8: this
/// took any /dev/null opened read-write for a closed stdout, so `check 1<>/dev/null` exited 1 for
/// good mazes and bad alike.)
pub fn stdout_open() -> anyhow::Result<()> {
    let closed =
        STDOUT_AT_START.load(Ordering::Relaxed) == CLOSED || rustix::fs::fstat(std::io::stdout()).is_err();
    if closed {
        bail!("stdout is closed: nowhere to write");
    }
    Ok(())
}

/// What the maze the flags name is called in messages and records: its path as given, the built-in
/// maze's name, or the `--gen` flags that make it.
#[must_use]
pub fn maze_name(args: &MazeArgs) -> String {
    match (&args.maze, args.generate) {
        (_, Some((w, h))) => format!("--gen {w}x{h} --seed {}", args.seed),
        (Some(path), None) => maze::quote_path(&path.display().to_string()),
        (None, None) => maze::BUILTIN_NAME.to_string(),
    }
}

/// What the maze the flags name is called where others may read it (`serve --http`: the status page,
/// `/maze.json`; `--world`: the shared world's records, read by every server's host): a file's name
/// without its folders, else as [`maze_name`]. The path as given told whoever could reach the page,
/// or the world's Redis, the host's folders (`/home/alice/…`); the full path stays in the host's own
/// records file and messages.
#[must_use]
pub fn public_maze_name(args: &MazeArgs) -> String {
    match (&args.maze, args.generate) {
        (Some(path), None) => {
            // (a path with no name, `..` say, is a folder and fails to load before this is asked)
            let name = path.file_name().map_or_else(|| "maze".into(), |n| n.to_string_lossy());
            maze::quote_path(&name)
        }
        _ => maze_name(args),
    }
}

/// Loads, generates or unpacks the maze the flags name.
pub fn load_maze(args: &MazeArgs) -> anyhow::Result<Maze> {
    if let Some((width, height)) = args.generate {
        let opts = GenOptions::walk(width, height, args.seed);
        return Ok(generate(&opts)?);
    }
    match &args.maze {
        Some(path) => Ok(maze::load_with(path, &args.read.options())?.maze),
        None => Ok(maze::builtin()?),
    }
}

/// The most bytes `--world-ca FILE` may hold: a whole system's bundle of CAs is about 200 KiB.
#[cfg(all(unix, feature = "serve"))]
const MAX_CA_FILE: u64 = 1 << 20;

/// The bytes of `--world-ca FILE` (`serve`, `records`): a regular file of at most [`MAX_CA_FILE`]
/// bytes. Red-team pass 9: read whole as named, `/dev/zero` took 3.7 GB in 3 s and a FIFO held the
/// server before it listened, for good.
#[cfg(all(unix, feature = "serve"))]
pub fn read_world_ca(path: &std::path::Path) -> anyhow::Result<Vec<u8>> {
    use std::io::Read as _;

    use anyhow::Context as _;
    let shown = maze::quote_path(&path.display().to_string());
    let file = maze::files::open_regular(path).with_context(|| format!("--world-ca {shown}"))?;
    let mut bytes = Vec::new();
    // (one byte past the limit tells a file over it, whatever its size said when opened)
    file.take(MAX_CA_FILE + 1).read_to_end(&mut bytes).with_context(|| format!("--world-ca {shown}"))?;
    if bytes.len() as u64 > MAX_CA_FILE {
        bail!("--world-ca {shown}: larger than {} KiB, not a CA's certificate", MAX_CA_FILE >> 10);
    }
    Ok(bytes)
}
