//! A walk written as an [asciicast v2] file as it goes — a header line, then one JSON array a
//! line: `[time, "o", data]` for every write to the terminal (game mode on, the queries, each frame,
//! game mode off), `[time, "r", "COLSxROWS"]` for each resize the walk sees, and `[time, "m",
//! "color_depth truecolor"]` (a marker) when the terminal's answer raises the colour depth
//! mid-walk. Times are seconds since the walk's start, to the microsecond.
//!
//! The header carries the standard `version`, `width`, `height`, `timestamp`, `title` and `env`
//! (`TERM`, and `COLORTERM` when set), and one key of our own, `mazewalk`: `{"color_depth": …,
//! "charset": …, "asked_truecolor": …, "version": …}` — the depth the walk started at (`none`,
//! `16`, `256`, `truecolor`), its glyphs, whether it asked the terminal for truecolor (then a `m`
//! event marks an upgrade) and the program's version. Players ignore keys they do not know.
//!
//! [`CastWriter`] is the format over any writer, with the times given (no clock, no file: the
//! local walk's `--record` puts a file and its clock round it in the binary, `mazewalk serve
//! --record-dir` one file per player on a writer thread). It can be capped in bytes: an event that
//! would pass the cap is not written, nor any after it, so a capped cast is still whole lines of
//! valid asciicast. A write error stops the recording (kept for the caller to tell); the writer may
//! then hold part of a line, and [`CastWriter::flushed`] says where the whole lines end (a file cut
//! back there is whole lines again).
//!
//! [asciicast v2]: https://docs.asciinema.org/manual/asciicast/v2/

use std::io::{self, Write};

use mazewalk_render::Charset;
use mazewalk_term::frame::ColorDepth;

/// What the header line says.
#[derive(Clone, Debug)]
pub struct Header {
    /// The terminal's columns at the start.
    pub width: u16,
    /// The terminal's rows at the start.
    pub height: u16,
    /// When the walk started, seconds since the Unix epoch (none if the system clock is before it).
    pub timestamp: Option<u64>,
    /// A title for players that show one.
    pub title: String,
    /// `TERM`, if set.
    pub term: Option<String>,
    /// `COLORTERM`, if set.
    pub colorterm: Option<String>,
    /// The colour depth the walk starts at.
    pub color_depth: ColorDepth,
    /// The glyphs it draws with.
    pub charset: Charset,
    /// Whether it asks the terminal whether it shows truecolor (a yes raises the depth mid-walk).
    pub asked_truecolor: bool,
}

impl Header {
    /// The header line, without its newline.
    #[must_use]
    pub fn to_json(&self) -> String {
        let mut env = serde_json::Map::new();
        for (key, value) in [("TERM", &self.term), ("COLORTERM", &self.colorterm)] {
            if let Some(value) = value {
                env.insert(key.into(), value.as_str().into());
            }
        }
        let ours = serde_json::json!({
            "color_depth": self.color_depth.to_string(),
            "charset": self.charset.to_string(),
            "asked_truecolor": self.asked_truecolor,
            "version": env!("CARGO_PKG_VERSION"),
        });
        // Written key by key: the standard keys first, in the specification's order.
        let mut line = format!("{{\"version\": 2, \"width\": {}, \"height\": {}", self.width, self.height);
        if let Some(timestamp) = self.timestamp {
            line += &format!(", \"timestamp\": {timestamp}");
        }
        line += &format!(", \"title\": {}", serde_json::Value::from(self.title.as_str()));
        line += &format!(", \"env\": {}", serde_json::Value::Object(env));
        line += &format!(", \"mazewalk\": {ours}}}");
        // `TERM` and `COLORTERM` are a client's to choose (a served player's): a host reading the
        // cast with `head` must not have its terminal act on a C1 control or bidi override in them
        mazewalk_maze::escape_json(&line)
    }
}

/// The largest incomplete UTF-8 sequence kept for the next write (a 4-byte sequence's first 3).
const MAX_PENDING: usize = 3;

/// Writes asciicast v2 to `out`: the header, then events in the order given. After the first write
/// error it writes nothing more and keeps the error ([`finish`](Self::finish) returns it); after the
/// first event that would pass its cap ([`with_limit`](Self::with_limit)), nothing more either.
#[derive(Debug)]
pub struct CastWriter<W: Write> {
    out: W,
    /// The end of the last output, when it stopped inside a UTF-8 sequence (at most [`MAX_PENDING`]).
    pending: Vec<u8>,
    /// The size last recorded.
    size: (u16, u16),
    /// The time of the last event: events never go back in time.
    last: f64,
    /// Bytes that were not UTF-8, each written as U+FFFD (none from the walk, whose frames are text).
    replaced: u64,
    /// The first write error; nothing is written after it.
    error: Option<io::Error>,
    /// Bytes written so far, the header's line too.
    written: u64,
    /// `written` at the last flush that went well: the writer below holds whole lines up to there.
    flushed: u64,
    /// The most bytes written in all.
    limit: u64,
    /// An event did not fit under the limit; nothing is written after it.
    capped: bool,
    /// One event's line, reused.
    line: Vec<u8>,
}

impl<W: Write> CastWriter<W> {
    /// Writes `header`'s line to `out`.
    ///
    /// # Errors
    /// Writing the header failed.
    pub fn new(out: W, header: &Header) -> io::Result<CastWriter<W>> {
        CastWriter::with_limit(out, header, u64::MAX)
    }

    /// Writes `header`'s line to `out`, and then events while the whole stays within `limit` bytes:
    /// the first event that would pass it ends the recording ([`capped`](Self::capped)).
    ///
    /// # Errors
    /// Writing the header failed, or the header alone is longer than `limit` (`FileTooLarge`).
    pub fn with_limit(mut out: W, header: &Header, limit: u64) -> io::Result<CastWriter<W>> {
        let line = header.to_json() + "\n";
        if line.len() as u64 > limit {
            return Err(io::Error::new(
                io::ErrorKind::FileTooLarge,
                "the cast's header is over its byte cap",
            ));
        }
        out.write_all(line.as_bytes())?;
        Ok(CastWriter {
            out,
            pending: Vec::new(),
            size: (header.width, header.height),
            last: 0.0,
            replaced: 0,
            error: None,
            written: line.len() as u64,
            flushed: 0,
            limit,
            capped: false,
            line: Vec::new(),
        })
    }

    /// Records `data` written to the terminal at `time`. A UTF-8 sequence cut at the end of `data` is
    /// completed by the next output; bytes that are not UTF-8 are written as U+FFFD (asciicast data
    /// is text) and counted ([`replaced`](Self::replaced)).
    pub fn output(&mut self, time: f64, data: &[u8]) {
        if data.is_empty() || self.stopped() {
            return;
        }
        if self.pending.is_empty()
            && let Ok(text) = std::str::from_utf8(data)
        {
            self.event(time, "o", text); // the usual case: a whole frame, UTF-8, not copied
            return;
        }
        let joined;
        let mut rest: &[u8] = if self.pending.is_empty() {
            data
        } else {
            joined = [std::mem::take(&mut self.pending).as_slice(), data].concat();
            &joined
        };
        let mut text = String::new();
        while let Err(e) = std::str::from_utf8(rest) {
            let (valid, after) = rest.split_at(e.valid_up_to());
            text.push_str(std::str::from_utf8(valid).unwrap_or_default());
            match e.error_len() {
                // cut short: the rest of the sequence comes with the next write
                None if after.len() <= MAX_PENDING => {
                    self.pending = after.to_vec();
                    rest = &[];
                }
                None => {
                    replace_bad(&mut text, &mut self.replaced, after.len());
                    rest = &[];
                }
                Some(bad) => {
                    replace_bad(&mut text, &mut self.replaced, bad);
                    rest = &after[bad..];
                }
            }
        }
        text.push_str(std::str::from_utf8(rest).unwrap_or_default());
        if !text.is_empty() {
            self.event(time, "o", &text);
        }
    }

    /// Records a resize to `cols × rows` at `time`, unless that is the size recorded last.
    pub fn resize(&mut self, time: f64, cols: u16, rows: u16) {
        if (cols, rows) != self.size {
            self.size = (cols, rows);
            self.event(time, "r", &format!("{cols}x{rows}"));
        }
    }

    /// Records a marker labelled `label` at `time`.
    pub fn marker(&mut self, time: f64, label: &str) {
        self.event(time, "m", label);
    }

    /// How many bytes were not UTF-8 and were written as U+FFFD.
    #[must_use]
    pub fn replaced(&self) -> u64 {
        self.replaced
    }

    /// Whether a write failed (the recording stopped there).
    #[must_use]
    pub fn failed(&self) -> bool {
        self.error.is_some()
    }

    /// Whether an event would have passed the byte cap (the recording stopped before it).
    #[must_use]
    pub fn capped(&self) -> bool {
        self.capped
    }

    /// Bytes written so far, the header's line too.
    #[must_use]
    pub fn written(&self) -> u64 {
        self.written
    }

    /// Bytes written up to the last flush that went well: whole lines. After a write or a flush
    /// fails, the writer below may hold part of a line past these (a full disk): a file cut back to
    /// this length is whole lines again.
    #[must_use]
    pub fn flushed(&self) -> u64 {
        self.flushed
    }

    /// The writer below, not flushed (with a buffered writer, what is still buffered can then be
    /// dropped: [`std::io::BufWriter::into_parts`]).
    pub fn into_inner(self) -> W {
        self.out
    }

    /// Whether nothing more is written: a write failed or the cap was reached.
    fn stopped(&self) -> bool {
        self.error.is_some() || self.capped
    }

    /// Writes out a UTF-8 sequence still cut short (as U+FFFD) and flushes.
    ///
    /// # Errors
    /// The first write error of the recording, or the flush's.
    pub fn finish(&mut self) -> io::Result<()> {
        if !self.pending.is_empty() {
            let cut = std::mem::take(&mut self.pending).len();
            let mut text = String::new();
            replace_bad(&mut text, &mut self.replaced, cut);
            let last = self.last;
            self.event(last, "o", &text);
        }
        if let Some(error) = self.error.take() {
            self.error = Some(io::Error::new(error.kind(), error.to_string()));
            return Err(error);
        }
        self.out.flush().inspect_err(|e| self.error = Some(io::Error::new(e.kind(), e.to_string())))?;
        self.flushed = self.written;
        Ok(())
    }

    /// Flushes what was written so far (a UTF-8 sequence cut short stays pending); an error stops
    /// the recording as a write's does.
    pub fn flush(&mut self) {
        if self.error.is_none() {
            match self.out.flush() {
                Ok(()) => self.flushed = self.written,
                Err(e) => self.error = Some(e),
            }
        }
    }

    /// The underlying writer.
    pub fn get_ref(&self) -> &W {
        &self.out
    }

    fn event(&mut self, time: f64, kind: &str, data: &str) {
        if self.stopped() {
            return;
        }
        // to the microsecond, as asciinema writes them; never before the last event
        let time = ((time.max(self.last) * 1e6).round() / 1e6).max(0.0);
        self.last = time;
        self.line.clear();
        // (serializing a tuple of a number and two strings into a Vec cannot fail)
        let _ = serde_json::to_writer(&mut self.line, &(time, kind, data));
        escape_unseen(&mut self.line);
        self.line.push(b'\n');
        if self.written.saturating_add(self.line.len() as u64) > self.limit {
            self.capped = true; // whole lines only: the cast stays valid up to here
            return;
        }
        match self.out.write_all(&self.line) {
            Ok(()) => self.written += self.line.len() as u64,
            Err(e) => self.error = Some(e),
        }
    }
}

/// `line`, a line of JSON, with the characters serde_json leaves raw that a terminal would act on
/// or hide (C1 controls, DEL, bidi overrides: [`mazewalk_maze::unseen`]) escaped, as the header's
/// are: the cast is text a host may read in a terminal, whatever was sent. A frame's line is looked
/// at byte by byte only ([`mazewalk_maze::may_hold_unseen`]).
fn escape_unseen(line: &mut Vec<u8>) {
    if mazewalk_maze::may_hold_unseen(line)
        && let Ok(text) = std::str::from_utf8(line)
        && text.chars().any(mazewalk_maze::unseen)
    {
        *line = mazewalk_maze::escape_json(text).into_bytes();
    }
}

/// Appends one U+FFFD for `bytes` bytes that are not UTF-8, and counts them.
fn replace_bad(text: &mut String, replaced: &mut u64, bytes: usize) {
    text.push(char::REPLACEMENT_CHARACTER);
    *replaced += bytes as u64;
}

#[cfg(test)]
mod tests {
    use super::*;

    fn header() -> Header {
        Header {
            width: 80,
            height: 24,
            timestamp: Some(1_700_000_000),
            title: "mazewalk \"x\"".into(),
            term: Some("xterm-256color".into()),
            colorterm: None,
            color_depth: ColorDepth::Ansi256,
            charset: Charset::Half,
            asked_truecolor: true,
        }
    }

    fn lines(cast: &CastWriter<Vec<u8>>) -> Vec<serde_json::Value> {
        let text = std::str::from_utf8(cast.get_ref()).unwrap();
        text.lines().map(|l| serde_json::from_str(l).unwrap()).collect()
    }

    #[test]
    fn header_and_events_are_asciicast_v2() {
        let mut cast = CastWriter::new(Vec::new(), &header()).unwrap();
        cast.output(0.000_000_4, b"\x1b[?1049h\"\\ \xe2\x96\x80");
        cast.resize(1.25, 80, 24); // the same size: nothing
        cast.resize(1.5, 100, 30);
        cast.marker(2.0, "color_depth truecolor");
        cast.output(1.0, b"late"); // never before the last event
        cast.finish().unwrap();
        let lines = lines(&cast);
        let h = &lines[0];
        assert_eq!(
            (h["version"].as_u64(), h["width"].as_u64(), h["height"].as_u64()),
            (Some(2), Some(80), Some(24))
        );
        assert_eq!(h["timestamp"], 1_700_000_000);
        assert_eq!(h["title"], "mazewalk \"x\"");
        assert_eq!(h["env"]["TERM"], "xterm-256color");
        assert!(h["env"].get("COLORTERM").is_none());
        assert_eq!(h["mazewalk"]["color_depth"], "256");
        assert_eq!(h["mazewalk"]["charset"], "half");
        assert_eq!(h["mazewalk"]["asked_truecolor"], true);
        assert!(std::str::from_utf8(cast.get_ref()).unwrap().starts_with("{\"version\": 2, \"width\": 80,"));
        assert_eq!(lines[1], serde_json::json!([0.0, "o", "\x1b[?1049h\"\\ ▀"]));
        assert_eq!(lines[2], serde_json::json!([1.5, "r", "100x30"]));
        assert_eq!(lines[3], serde_json::json!([2.0, "m", "color_depth truecolor"]));
        assert_eq!(lines[4], serde_json::json!([2.0, "o", "late"]));
        assert_eq!(lines.len(), 5);
    }

    /// Red-team pass 17: a served player's `TERM` and `COLORTERM` (64 characters each of whatever
    /// the client sent) went into the header with serde_json's escaping alone, which leaves C1
    /// controls, DEL and bidi overrides raw: `head` of the cast had the host's terminal take U+009B
    /// for CSI. Every line is still JSON meaning the same, with none of them raw.
    #[test]
    fn a_clients_terminal_names_reach_the_cast_escaped() {
        let hostile =
            "xterm\x1b]52;c;cHduZWQ=\x07\u{9b}31m\u{202e}gnp\u{61c}\u{2028}\r\n\"q\" \\\u{7f}\u{e0041}";
        let header = Header { term: Some(hostile.into()), colorterm: Some(hostile.into()), ..header() };
        let mut cast = CastWriter::new(Vec::new(), &header).unwrap();
        cast.output(0.5, "\u{9b}2J\u{202e}▀".as_bytes());
        cast.marker(1.0, "a \u{85} marker");
        cast.finish().unwrap();
        let text = std::str::from_utf8(cast.get_ref()).unwrap();
        let raw: Vec<char> = text.chars().filter(|&c| c != '\n' && mazewalk_maze::unseen(c)).collect();
        assert!(raw.is_empty(), "raw {raw:?} in:\n{text}");
        let lines = lines(&cast);
        assert_eq!(
            (&lines[0]["env"]["TERM"], &lines[0]["env"]["COLORTERM"]),
            (&hostile.into(), &hostile.into())
        );
        assert_eq!(lines[1], serde_json::json!([0.5, "o", "\u{9b}2J\u{202e}▀"]));
        assert_eq!(lines[2], serde_json::json!([1.0, "m", "a \u{85} marker"]));
        assert_eq!(cast.written(), text.len() as u64, "the bytes counted are the bytes written");
    }

    #[test]
    fn a_utf8_sequence_cut_between_writes_is_joined_and_bad_bytes_are_replaced() {
        let mut cast = CastWriter::new(Vec::new(), &header()).unwrap();
        let block = "▀".as_bytes(); // 3 bytes
        cast.output(0.1, &[b'a', block[0], block[1]]);
        cast.output(0.2, &[block[2], b'b']);
        cast.output(0.3, b"c\xffd\xe2");
        cast.finish().unwrap(); // the cut-short end is written as U+FFFD
        let lines = lines(&cast);
        assert_eq!(lines[1], serde_json::json!([0.1, "o", "a"]));
        assert_eq!(lines[2], serde_json::json!([0.2, "o", "▀b"]));
        assert_eq!(lines[3], serde_json::json!([0.3, "o", "c\u{fffd}d"]));
        assert_eq!(lines[4], serde_json::json!([0.3, "o", "\u{fffd}"]));
        assert_eq!(cast.replaced(), 2);
    }

    #[test]
    fn the_byte_cap_stops_before_the_event_that_would_pass_it() {
        let header_len = header().to_json().len() as u64 + 1;
        assert!(CastWriter::with_limit(Vec::new(), &header(), header_len - 1).is_err());
        let event = br#"[0.5,"o","frame"]"#.len() as u64 + 1;
        let mut cast = CastWriter::with_limit(Vec::new(), &header(), header_len + 2 * event + 3).unwrap();
        for i in 0..5 {
            cast.output(0.5 + f64::from(i), b"frame"); // each event as long
            assert_eq!(cast.capped(), i >= 2, "after event {i}");
        }
        cast.resize(3.0, 10, 10);
        cast.finish().unwrap();
        assert_eq!(cast.written(), header_len + 2 * event);
        assert_eq!(cast.get_ref().len() as u64, cast.written());
        let lines = lines(&cast); // whole lines, each valid JSON
        assert_eq!(lines.len(), 3);
        assert_eq!(lines[2], serde_json::json!([1.5, "o", "frame"]));
    }

    /// A writer that fails after `left` bytes.
    struct Full {
        left: usize,
        writes: usize,
    }

    impl Write for Full {
        fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
            self.writes += 1;
            if self.left == 0 {
                return Err(io::Error::new(io::ErrorKind::StorageFull, "disk full"));
            }
            let n = buf.len().min(self.left);
            self.left -= n;
            Ok(n)
        }
        fn flush(&mut self) -> io::Result<()> {
            Ok(())
        }
    }

    #[test]
    fn a_write_error_stops_the_recording_and_is_kept() {
        let mut cast = CastWriter::new(Full { left: 400, writes: 0 }, &header()).unwrap();
        for i in 0..100 {
            cast.output(f64::from(i), b"frame frame frame");
        }
        assert!(cast.failed());
        let writes = cast.get_ref().writes;
        cast.output(101.0, b"more");
        cast.resize(102.0, 10, 10);
        assert_eq!(cast.get_ref().writes, writes, "written to after the error");
        let err = cast.finish().unwrap_err();
        assert_eq!(err.kind(), io::ErrorKind::StorageFull);
        assert!(cast.finish().is_err(), "the error is forgotten");
    }

    /// What went through before a full disk: the bytes a buffered file got, torn line and all.
    struct Disk {
        got: Vec<u8>,
        left: usize,
    }

    impl Write for Disk {
        fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
            if self.left == 0 {
                return Err(io::Error::new(io::ErrorKind::StorageFull, "disk full"));
            }
            let n = buf.len().min(self.left);
            self.left -= n;
            self.got.extend_from_slice(&buf[..n]);
            Ok(n)
        }
        fn flush(&mut self) -> io::Result<()> {
            Ok(())
        }
    }

    // The red team's LOW finding: a full disk left a torn last line. `flushed` says where the whole
    // lines end, whatever the buffer below did: what a file cut back there holds parses, line by line.
    #[test]
    fn after_a_write_error_the_flushed_bytes_are_whole_lines() {
        for room in [700, 1000, 1234, 2000, 4321] {
            let disk = io::BufWriter::with_capacity(256, Disk { got: Vec::new(), left: room });
            let mut cast = CastWriter::new(disk, &header()).unwrap();
            for i in 0..200u32 {
                cast.output(f64::from(i), "frame \u{2588} ".repeat(i as usize % 7 + 1).as_bytes());
                cast.flush();
            }
            assert!(cast.failed(), "room {room}");
            let flushed = usize::try_from(cast.flushed()).unwrap();
            let (disk, _) = cast.into_inner().into_parts();
            assert!(disk.got.len() > flushed, "room {room}: no torn line to cut ({})", disk.got.len());
            assert!(!disk.got.ends_with(b"\n"), "room {room}: the disk's bytes end in a torn line");
            let kept = &disk.got[..flushed];
            assert!(kept.ends_with(b"\n") && flushed > 0, "room {room}");
            for line in std::str::from_utf8(kept).unwrap().lines() {
                serde_json::from_str::<serde_json::Value>(line).unwrap_or_else(|e| panic!("{e}: {line}"));
            }
        }
    }
}
