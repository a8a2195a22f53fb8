//! What the readers and writers of both formats share: the formats' names, located errors, text
//! decoding and positions. Pieces of a file that a message shows go through [`quote`] (mazewalk-names).
//!
//! [`load`](super::load()) dispatches to [`cs559`](super::cs559) and [`grid`](super::grid); both import
//! this module and nothing of each other or of `load`, so the modules form no cycle.

pub use mazewalk_names::{
    QUOTE_CHARS, escape_json, may_hold_unseen, quote, quote_path, quote_within, unseen,
};
use std::fmt;

use super::MazeError;

/// A maze file format.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// The original course project's numbers-only format, see [`cs559`](super::cs559).
    Cs559,
    /// mazewalk's hand-editable tile format, see [`grid`](super::grid).
    Grid,
}

mazewalk_names::named!(Format, "format", [("cs559", Format::Cs559), ("grid", Format::Grid)]);

/// A maze that a format cannot express.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("cannot write as {format}: {reason}")]
pub struct WriteError {
    /// The format asked for.
    pub format: Format,
    /// Why not.
    pub reason: String,
}

/// A malformed or invalid maze file: where, and what is wrong. Displays as `FILE:LINE:COL: message`,
/// with control characters in the file name escaped.
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
        write!(f, "{}:{}:{}: {}", quote_path(&self.file), self.line, self.col, self.kind)
    }
}

impl std::error::Error for ParseError {}

/// What is wrong with a maze file. Every piece of the file a message shows went through [`quote`]:
/// at most [`QUOTE_CHARS`] characters, control characters escaped.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[allow(missing_docs)] // the fields are named by the messages
pub enum ParseErrorKind {
    #[error("invalid UTF-8 (byte 0x{byte:02x}); a maze file is text")]
    InvalidUtf8 { byte: u8 },
    #[error("a NUL byte; a maze file is text, not binary data")]
    NulByte,
    #[error("this looks like UTF-16; save the file as UTF-8")]
    Utf16,
    #[error("unexpected end of file: expected {expected}")]
    UnexpectedEof { expected: String },
    #[error("expected {expected}, found `{found}`")]
    Expected { expected: String, found: String },
    #[error("{what} {value} is not a finite number")]
    NotFinite { what: String, value: String },
    #[error("{what} is {value}, out of range ({range})")]
    OutOfRange { what: String, value: String, range: String },
    #[error("a second {what} (the first is on line {first_line})")]
    Duplicate { what: String, first_line: u32 },
    #[error("the file claims {count} {what}; at most {max} are supported")]
    CountTooLarge { what: &'static str, count: u64, max: u64 },
    #[error("a carriage return inside a line: lines end in LF or CRLF, not CR alone")]
    LoneCarriageReturn,
    #[error("{0}")]
    Grid(String),
    #[error("{0}")]
    Invalid(MazeError),
}

/// Strips a byte-order mark and checks that `bytes` is UTF-8 text without NUL bytes; on failure returns
/// the good prefix and the error at the first bad byte (with a hint for UTF-16).
pub(crate) fn decode<'a>(name: &str, bytes: &'a [u8]) -> Result<&'a str, (&'a str, ParseError)> {
    if looks_like_utf16(bytes) {
        return Err(("", Loc { line: 1, col: 1 }.error(name, ParseErrorKind::Utf16)));
    }
    let bytes = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
    let (good, kind) = match std::str::from_utf8(bytes) {
        Ok(text) => match text.find('\0') {
            None => return Ok(text),
            Some(at) => (&text[..at], ParseErrorKind::NulByte),
        },
        Err(e) => {
            let good = std::str::from_utf8(&bytes[..e.valid_up_to()]).unwrap_or_default();
            match good.find('\0') {
                Some(at) => (&good[..at], ParseErrorKind::NulByte),
                None => (good, ParseErrorKind::InvalidUtf8 { byte: bytes[e.valid_up_to()] }),
            }
        }
    };
    let (line, col) = line_col(good, good.len());
    Err((good, ParseError { file: name.into(), line, col, kind }))
}

/// A UTF-16 byte-order mark, or NUL bytes in every other place among the first bytes (ASCII as
/// UTF-16).
pub(crate) fn looks_like_utf16(bytes: &[u8]) -> bool {
    if bytes.starts_with(b"\xFF\xFE") || bytes.starts_with(b"\xFE\xFF") {
        return true;
    }
    let head = &bytes[..bytes.len().min(64) & !1];
    if head.len() < 2 {
        return false;
    }
    let zeros = |odd: usize| head.iter().skip(odd).step_by(2).filter(|&&b| b == 0).count();
    let (even, odd) = (zeros(0), zeros(1));
    let pairs = head.len() / 2;
    (odd == pairs && even == 0) || (even == pairs && odd == 0)
}

/// 1-based line and character column of byte offset `at` in `text`.
pub(crate) fn line_col(text: &str, at: usize) -> (u32, u32) {
    let before = &text[..at];
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    let line = before.bytes().filter(|&b| b == b'\n').count() + 1;
    let col = before[line_start..].chars().count() + 1;
    (sat(line), sat(col))
}

/// `n` as a `u32`, saturating.
pub(crate) fn sat(n: usize) -> u32 {
    u32::try_from(n).unwrap_or(u32::MAX)
}

/// A position in a file, 1-based.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct Loc {
    pub line: u32,
    pub col: u32,
}

impl Loc {
    /// The position of byte offset `at` in `text`.
    pub(crate) fn of(text: &str, at: usize) -> Loc {
        let (line, col) = line_col(text, at);
        Loc { line, col }
    }

    pub(crate) fn error(self, file: &str, kind: ParseErrorKind) -> ParseError {
        ParseError { file: file.into(), line: self.line, col: self.col, kind }
    }
}

/// Whitespace as C's `isspace` in the "C" locale.
pub(crate) fn is_space(c: char) -> bool {
    matches!(c, ' ' | '\t' | '\n' | '\r' | '\x0B' | '\x0C')
}

/// [`is_space`] on a byte: space, or `\t` `\n` `\x0B` `\x0C` `\r` (9..=13), in two comparisons.
pub(crate) fn is_space_byte(b: u8) -> bool {
    b == b' ' || b.wrapping_sub(b'\t') <= b'\r' - b'\t'
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn utf16_is_recognised() {
        assert!(looks_like_utf16(b"\xFF\xFE4\x00"));
        assert!(looks_like_utf16(b"4\x00\n\x000\x00 \x00"));
        assert!(looks_like_utf16(b"\x004\x00\n"));
        assert!(!looks_like_utf16(b"4\n0 0\n"));
        assert!(!looks_like_utf16(b"\x00\x00\x00\x00"));
        let e = decode("f", b"4\x00\n\x00").unwrap_err().1;
        assert_eq!(e.to_string(), "f:1:1: this looks like UTF-16; save the file as UTF-8");
    }

    #[test]
    fn space_bytes_are_the_space_chars() {
        for b in 0..=255u8 {
            assert_eq!(is_space_byte(b), is_space(b as char), "{b}");
        }
    }

    #[test]
    fn nul_is_binary() {
        let (good, e) = decode("f", b"4\n0 \x000").unwrap_err();
        assert_eq!(good, "4\n0 ");
        assert_eq!(e.to_string(), "f:2:3: a NUL byte; a maze file is text, not binary data");
    }
}
