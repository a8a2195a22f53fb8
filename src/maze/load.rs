//! Reading and writing maze files: format detection, text decoding, located errors.

use std::fmt;
use std::path::Path;

use super::{Maze, MazeError, Subject, cs559, grid};

/// A maze file format.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// The original course project's numbers-only format, see [`cs559`].
    Cs559,
    /// mazewalk's hand-editable tile format, see [`grid`].
    Grid,
}

impl fmt::Display for Format {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Format::Cs559 => "cs559",
            Format::Grid => "grid",
        })
    }
}

/// A malformed or invalid maze file: where, and what is wrong. Displays as `FILE:LINE:COL: message`.
#[derive(Clone, Debug, PartialEq)]
pub struct ParseError {
    /// The file name given to the reader.
    pub file: String,
    /// 1-based line.
    pub line: u32,
    /// 1-based column, in characters.
    pub col: u32,
    /// What is wrong.
    pub kind: ParseErrorKind,
}

impl fmt::Display for ParseError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}:{}: {}", self.file, self.line, self.col, self.kind)
    }
}

impl std::error::Error for ParseError {}

/// What is wrong with a maze file.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[allow(missing_docs)] // the fields are named by the messages
pub enum ParseErrorKind {
    #[error("invalid UTF-8 (byte 0x{byte:02x})")]
    InvalidUtf8 { byte: u8 },
    #[error("unexpected end of file: expected {expected}")]
    UnexpectedEof { expected: String },
    #[error("expected {expected}, found `{found}`")]
    Expected { expected: String, found: String },
    #[error("{what} {value} is not a finite number")]
    NotFinite { what: String, value: String },
    #[error("{what} is {value}, out of range ({range})")]
    OutOfRange { what: String, value: String, range: String },
    #[error("the file claims {count} {what}; at most {max} are supported")]
    CountTooLarge { what: &'static str, count: u64, max: u64 },
    #[error("{0}")]
    Grid(String),
    #[error("{0}")]
    Invalid(MazeError),
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
    /// The file is malformed or describes an invalid maze.
    #[error(transparent)]
    Parse(#[from] ParseError),
}

/// A maze that a format cannot express.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("cannot write as {format}: {reason}")]
pub struct WriteError {
    /// The format asked for.
    pub format: Format,
    /// Why not.
    pub reason: String,
}

/// Reads and parses the maze file at `path`, detecting the format.
pub fn load(path: impl AsRef<Path>) -> Result<Maze, LoadError> {
    let path = path.as_ref();
    let name = path.display().to_string();
    let bytes = std::fs::read(path).map_err(|source| LoadError::Io { path: name.clone(), source })?;
    Ok(parse(&name, &bytes)?)
}

/// Parses a maze from `bytes` (a grid file if it starts with `mazewalk-grid`, else CS559);
/// `name` is the file name used in error messages.
pub fn parse(name: &str, bytes: &[u8]) -> Result<Maze, ParseError> {
    match decode(name, bytes) {
        Ok(text) => match detect_format(text) {
            Format::Cs559 => cs559::parse_str(name, text),
            Format::Grid => grid::parse_str(name, text),
        },
        Err((prefix, bad_utf8)) => match detect_format(prefix) {
            // the original reader stops after the viewer: junk after it is ignored, even binary
            Format::Cs559 => match cs559::parse_str(name, prefix) {
                Err(ParseError { kind: ParseErrorKind::UnexpectedEof { .. }, .. }) => Err(bad_utf8),
                other => other,
            },
            Format::Grid => Err(bad_utf8),
        },
    }
}

/// The format of a decoded text: [`Format::Grid`] if its first word is `mazewalk-grid`.
#[must_use]
pub fn detect_format(text: &str) -> Format {
    if text.trim_start().starts_with(grid::MAGIC) { Format::Grid } else { Format::Cs559 }
}

/// Writes `maze` in `format`, or says why the format cannot express it.
pub fn write(maze: &Maze, format: Format) -> Result<String, WriteError> {
    match format {
        Format::Cs559 => cs559::write(maze),
        Format::Grid => grid::write(maze),
    }
}

/// Strips a byte-order mark and checks UTF-8; on failure returns the valid prefix and the error
/// naming the first bad byte's position.
pub(crate) fn decode<'a>(name: &str, bytes: &'a [u8]) -> Result<&'a str, (&'a str, ParseError)> {
    let bytes = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
    std::str::from_utf8(bytes).map_err(|e| {
        let good = std::str::from_utf8(&bytes[..e.valid_up_to()]).unwrap_or_default();
        let (line, col) = line_col(good, good.len());
        let kind = ParseErrorKind::InvalidUtf8 { byte: bytes[e.valid_up_to()] };
        (good, ParseError { file: name.into(), line, col, kind })
    })
}

/// 1-based line and character column of byte offset `at` in `text`.
pub(crate) fn line_col(text: &str, at: usize) -> (u32, u32) {
    let before = &text[..at];
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    let line = before.bytes().filter(|&b| b == b'\n').count() + 1;
    let col = before[line_start..].chars().count() + 1;
    (sat(line), sat(col))
}

fn sat(n: usize) -> u32 {
    u32::try_from(n).unwrap_or(u32::MAX)
}

/// A position in a file, 1-based.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct Loc {
    pub line: u32,
    pub col: u32,
}

impl Loc {
    pub(crate) fn error(self, file: &str, kind: ParseErrorKind) -> ParseError {
        ParseError { file: file.into(), line: self.line, col: self.col, kind }
    }
}

/// Whitespace as C's `isspace` in the "C" locale.
pub(crate) fn is_space(c: char) -> bool {
    matches!(c, ' ' | '\t' | '\n' | '\r' | '\x0B' | '\x0C')
}

/// Where each record of a file starts, so a [`MazeError`] can point at the record at fault.
#[derive(Debug, Default)]
pub(crate) struct RecordLocs {
    pub start: Loc,
    pub vertices: Vec<Loc>,
    pub edges: Vec<Loc>,
    pub cells: Vec<Loc>,
    pub viewer: Loc,
    pub exit: Option<Loc>,
}

impl RecordLocs {
    pub(crate) fn locate(&self, file: &str, err: MazeError) -> ParseError {
        let loc = match err.subject() {
            Subject::Maze => Some(self.start),
            Subject::Vertex(v) => self.vertices.get(v as usize).copied(),
            Subject::Edge(e) => self.edges.get(e as usize).copied(),
            Subject::Cell(c) => self.cells.get(c as usize).copied(),
            Subject::Viewer => Some(self.viewer),
            Subject::Exit => self.exit.or(Some(self.viewer)),
        };
        loc.unwrap_or(self.start).error(file, ParseErrorKind::Invalid(err))
    }
}
