//! Loading a maze: reading a file with a size limit, detecting its format, and dispatching to the
//! format's reader. The types both formats share live in [`text`](super::text).

use std::io::Read;
use std::path::Path;

use super::text::{Format, ParseError, ParseErrorKind, WriteError, decode};
use super::{Maze, cs559, grid};
use crate::files::OpenError;

/// The default [`LoadOptions::max_bytes`]: 256 MiB, room for the largest maze `gen` writes
/// (1000 × 1000 cells in CS559 format: 160 MB).
pub const DEFAULT_MAX_BYTES: u64 = 256 << 20;

/// How [`load_with`] reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LoadOptions {
    /// Files larger than this are refused before they are read (stdin: once this much has arrived).
    pub max_bytes: u64,
}

impl Default for LoadOptions {
    fn default() -> Self {
        LoadOptions { max_bytes: DEFAULT_MAX_BYTES }
    }
}

/// A loaded maze and the format it was read in.
#[derive(Clone, Debug)]
pub struct Loaded {
    /// The maze.
    pub maze: Maze,
    /// The file's format, as detected.
    pub format: Format,
}

/// Why a maze could not be loaded.
#[derive(Debug, thiserror::Error)]
pub enum LoadError {
    /// The file could not be read.
    #[error("{path}: cannot read: {source}")]
    Io {
        /// The path as given.
        path: String,
        /// The operating system's reason.
        source: std::io::Error,
    },
    /// The path names something other than a regular file (a FIFO, a device, a directory), which
    /// might never end; `-` reads standard input (but for the walk, which reads its keys there).
    #[error(
        "{path}: not a regular file ({what}); save it to a file and give its path (or, but for the walk, \
         give `-` and redirect the pipe to stdin)"
    )]
    NotAFile {
        /// The path as given.
        path: String,
        /// What it is instead.
        what: &'static str,
    },
    /// The file is larger than the limit.
    #[error(
        "{path}: larger than the limit of {limit} bytes ({size}); raise it with --max-file-size if the file is a maze"
    )]
    TooLarge {
        /// The path as given.
        path: String,
        /// The limit, bytes.
        limit: u64,
        /// What is known of the size: `N bytes`, or `more` for a stream.
        size: String,
    },
    /// The file is malformed or describes an invalid maze.
    #[error(transparent)]
    Parse(#[from] ParseError),
}

/// [`load_with`] with the default options.
///
/// # Errors
/// See [`load_with`].
pub fn load(path: impl AsRef<Path>) -> Result<Loaded, LoadError> {
    load_with(path, &LoadOptions::default())
}

/// Reads and parses the maze file at `path` (`-`: standard input), detecting the format.
///
/// Only regular files are opened (without blocking: a FIFO is refused, not waited on); a file
/// larger than `options.max_bytes` is refused before it is read. Reading stops at the first NUL
/// byte or invalid UTF-8, since nothing after it can make the file a maze (binary input costs no
/// more than its first chunk).
///
/// # Errors
/// [`LoadError::Io`], [`LoadError::NotAFile`] and [`LoadError::TooLarge`] before parsing,
/// [`LoadError::Parse`] after.
pub fn load_with(path: impl AsRef<Path>, options: &LoadOptions) -> Result<Loaded, LoadError> {
    let path = path.as_ref();
    let name = super::text::quote_path(&path.display().to_string());
    let io = |source| LoadError::Io { path: name.clone(), source };
    let bytes = if path == Path::new("-") {
        read_text(std::io::stdin().lock(), options.max_bytes).map_err(io)?
    } else {
        let file = open_regular(path, &name)?;
        let size = file.metadata().map_err(io)?.len();
        if size > options.max_bytes {
            return Err(LoadError::TooLarge {
                path: name,
                limit: options.max_bytes,
                size: format!("{size} bytes"),
            });
        }
        read_text(&file, options.max_bytes).map_err(io)?
    };
    let Some(bytes) = bytes else {
        return Err(LoadError::TooLarge { path: name, limit: options.max_bytes, size: "more".into() });
    };
    Ok(parse_loaded(&name, &bytes)?)
}

/// [`crate::files::open_regular`], its refusals as [`LoadError`]s.
fn open_regular(path: &Path, name: &str) -> Result<std::fs::File, LoadError> {
    crate::files::open_regular(path).map_err(|error| match error {
        OpenError::Io(source) => LoadError::Io { path: name.into(), source },
        OpenError::NotAFile(what) => LoadError::NotAFile { path: name.into(), what },
    })
}

/// Reads at most `max` bytes, stopping early after a NUL byte or invalid UTF-8 (keeping a few
/// bytes past it for the error message); `None` if there were more than `max`. The buffer grows
/// with what has been read, a chunk at a time, never sized by what the file claims (`stat`'s size,
/// or the limit): a file of a few text bytes and then zeros costs its first chunks, whatever its size.
fn read_text(mut source: impl Read, max: u64) -> std::io::Result<Option<Vec<u8>>> {
    const CHUNK: u64 = 64 << 10;
    let mut bytes = Vec::new();
    let mut checked = 0; // bytes[..checked] is UTF-8 without NUL
    loop {
        if (&mut source).take(CHUNK).read_to_end(&mut bytes)? == 0 {
            break;
        }
        if bytes.len() as u64 > max {
            return Ok(None);
        }
        let (mut bad, valid_end) = match std::str::from_utf8(&bytes[checked..]) {
            Ok(_) => (None, bytes.len()),
            // a character cut by the chunk's end: the next chunk completes it
            Err(e) if e.error_len().is_none() => (None, checked + e.valid_up_to()),
            Err(e) => (Some(checked + e.valid_up_to()), checked + e.valid_up_to()),
        };
        // `contains` on bytes is a memchr: most chunks have no NUL
        let new = &bytes[checked..valid_end];
        if new.contains(&0) {
            bad = new.iter().position(|&b| b == 0).map(|p| checked + p);
        }
        if let Some(at) = bad {
            bytes.truncate((at + 64).min(bytes.len()));
            break;
        }
        checked = valid_end;
    }
    Ok(Some(bytes))
}

/// Parses a maze from `bytes` (a grid file if it starts with `mazewalk-grid`, else CS559);
/// `name` is the file name used in error messages.
///
/// # Errors
/// The first thing wrong, located.
pub fn parse(name: &str, bytes: &[u8]) -> Result<Maze, ParseError> {
    parse_loaded(name, bytes).map(|l| l.maze)
}

/// [`parse`], also saying which format the text was in.
///
/// # Errors
/// As [`parse`].
pub fn parse_loaded(name: &str, bytes: &[u8]) -> Result<Loaded, ParseError> {
    let (format, maze) = match decode(name, bytes) {
        Ok(text) => {
            let format = detect_format(text);
            (format, parse_str(format, name, text))
        }
        Err((prefix, bad)) => {
            let format = detect_format(prefix);
            let maze = match format {
                // the original reader stops after the viewer: junk after it is ignored, even binary
                Format::Cs559 if !matches!(bad.kind, ParseErrorKind::Utf16) => {
                    match cs559::parse_str(name, prefix) {
                        Err(ParseError { kind: ParseErrorKind::UnexpectedEof { .. }, .. }) => Err(bad),
                        other => other,
                    }
                }
                _ => Err(bad),
            };
            (format, maze)
        }
    };
    Ok(Loaded { maze: maze?, format })
}

fn parse_str(format: Format, name: &str, text: &str) -> Result<Maze, ParseError> {
    match format {
        Format::Cs559 => cs559::parse_str(name, text),
        Format::Grid => grid::parse_str(name, text),
    }
}

/// The format of a decoded text: [`Format::Grid`] if its first word is `mazewalk-grid`.
#[must_use]
pub fn detect_format(text: &str) -> Format {
    if text.trim_start().starts_with(grid::MAGIC) { Format::Grid } else { Format::Cs559 }
}

/// Writes `maze` in `format`, or says why the format cannot express it.
///
/// # Errors
/// When the format cannot express the maze.
pub fn write(maze: &Maze, format: Format) -> Result<String, WriteError> {
    match format {
        Format::Cs559 => cs559::write(maze),
        Format::Grid => grid::write(maze),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_big_file_reads_whole_and_binary_still_stops_early() {
        let dir = std::env::temp_dir().join(format!("mazewalk-read-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("big.txt");
        // 5 MiB and a bit, across many chunks; every byte a different place
        let text: Vec<u8> =
            (0..5_000_003u32).map(|i| b"0123456789 \n"[(i % 7 + i / 13 % 5) as usize]).collect();
        std::fs::write(&path, &text).unwrap();
        let read = |max| {
            let file = std::fs::File::open(&path).unwrap();
            read_text(&file, max).unwrap()
        };
        assert_eq!(read(1 << 30).unwrap(), text);
        assert_eq!(read(text.len() as u64).unwrap(), text);
        assert_eq!(read(text.len() as u64 - 1), None);
        // binary in the first chunk: the read stops there
        let mut binary = text.clone();
        binary[1000] = 0;
        std::fs::write(&path, &binary).unwrap();
        assert_eq!(read(1 << 30).unwrap(), &binary[..1064]);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn reading_stops_at_binary_and_at_the_limit() {
        let zeros = std::io::repeat(0).take(1 << 30);
        assert_eq!(read_text(zeros, 1 << 40).unwrap().unwrap().len(), 64);
        let text = std::io::repeat(b'1').take(1 << 20);
        assert_eq!(read_text(text, 1000).unwrap(), None);
        let text = std::io::repeat(b'1').take(1000);
        assert_eq!(read_text(text, 1000).unwrap().unwrap().len(), 1000);
        // a character split across chunks is not an error
        let s = "é".repeat(100_000);
        assert_eq!(read_text(s.as_bytes(), 1 << 30).unwrap().unwrap(), s.as_bytes());
        let bad = [&b"12 "[..], &[0xff; 10], &[b'1'; 1000]].concat();
        assert_eq!(read_text(&bad[..], 1 << 30).unwrap().unwrap().len(), 3 + 64);
    }
}
