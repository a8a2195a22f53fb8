//! The original course project's maze format, read as its `fscanf` reader does.
//!
//! Whitespace-separated numbers; line breaks carry no meaning:
//!
//! 1. `nv`, then `nv` vertices `x y`;
//! 2. `ne`, then `ne` edges `start end cell_left cell_right opaque r g b` (`-1` = outside;
//!    `opaque` is 1 for a wall, 0 for a portal; colour components in 0..1);
//! 3. `nc`, then `nc` cells of 4 edge indices each (`-1` = no edge; any order);
//! 4. the viewer `x y z dir_deg fov_deg`.
//!
//! Anything after the viewer is ignored, as the original does, except mazewalk's optional
//! extension, a line `exit CELL` or `exit X Y` (which the original ignores harmlessly).
//!
//! The writer pads cells to 4 slots with `-1` and prints every `f32` in Rust's shortest
//! round-trip form, so reading what it wrote gives back the same maze.

use glam::{Vec2, Vec3, vec2};

use super::load::{Loc, RecordLocs, is_space};
use super::{
    CellId, Cells, Edge, Exit, Format, Maze, MazeError, ParseError, ParseErrorKind, Viewer, WriteError,
};

/// Edge slots per cell record.
const CELL_SLOTS: usize = 4;

/// Parses CS559 text (already decoded); `file` names it in errors.
pub fn parse_str(file: &str, text: &str) -> Result<Maze, ParseError> {
    let mut r = Reader { file, text, pos: 0, loc: Loc { line: 1, col: 1 } };
    let mut locs = RecordLocs { start: r.peek_loc(), ..RecordLocs::default() };

    let (nv, cap) = r.count(&|| "vertex count".into(), "vertices", 2)?;
    let mut vertices = Vec::with_capacity(cap);
    for i in 0..nv {
        locs.vertices.push(r.peek_loc());
        let x = r.float(&|| format!("vertex {i} x"))?;
        let y = r.float(&|| format!("vertex {i} y"))?;
        vertices.push(vec2(x, y));
    }

    let (ne, cap) = r.count(&|| "edge count".into(), "edges", 8)?;
    let mut edges = Vec::with_capacity(cap);
    for i in 0..ne {
        locs.edges.push(r.peek_loc());
        let start = r.index(&|| format!("edge {i} start vertex"), false)?.unwrap_or_default();
        let end = r.index(&|| format!("edge {i} end vertex"), false)?.unwrap_or_default();
        let left = r.index(&|| format!("edge {i} left cell"), true)?;
        let right = r.index(&|| format!("edge {i} right cell"), true)?;
        let opaque = r.flag(&|| format!("edge {i} opaque flag"))?;
        let mut c = [0.0; 3];
        for (k, name) in ["red", "green", "blue"].iter().enumerate() {
            c[k] = r.float(&|| format!("edge {i} {name}"))?;
        }
        edges.push(Edge { start, end, left, right, opaque, color: Vec3::from(c) });
    }

    let (nc, cap) = r.count(&|| "cell count".into(), "cells", CELL_SLOTS)?;
    let mut cells = Cells::with_capacity(cap, cap * CELL_SLOTS);
    for i in 0..nc {
        locs.cells.push(r.peek_loc());
        let mut slots = [0; CELL_SLOTS];
        let mut n = 0;
        for k in 0..CELL_SLOTS {
            if let Some(e) = r.index(&|| format!("cell {i} edge {}", k + 1), true)? {
                slots[n] = e;
                n += 1;
            }
        }
        cells.push(&slots[..n]);
    }

    locs.viewer = r.peek_loc();
    let mut v = [0.0; 5];
    for (k, name) in ["x", "y", "z", "direction", "field of view"].iter().enumerate() {
        v[k] = r.float(&|| format!("viewer {name}"))?;
    }
    let viewer = Viewer { pos: vec2(v[0], v[1]), z: v[2], dir_deg: v[3], fov_deg: v[4] };
    let exit = r.exit_extension(&mut locs)?;

    let (exit, exit_point_cell) = match exit {
        Some(ExitSpec::Cell(cell)) => (Some(Exit { cell, point: None }), false),
        Some(ExitSpec::Point(p)) => (Some(Exit { cell: 0, point: Some(p) }), true),
        None => (None, false),
    };
    // an `exit X Y` point picks its cell once the maze stands
    let maze = Maze::new(vertices, edges, cells, viewer, exit.filter(|_| !exit_point_cell))
        .map_err(|e| locs.locate(file, e))?;
    match exit {
        Some(Exit { point: Some(p), .. }) if exit_point_cell => {
            let Some(cell) = maze.cell_at(p) else {
                let loc = locs.exit.unwrap_or(locs.viewer);
                return Err(
                    loc.error(file, ParseErrorKind::Invalid(MazeError::ExitOutside { x: p.x, y: p.y }))
                );
            };
            Ok(Maze { exit: Some(Exit { cell, point: Some(p) }), ..maze })
        }
        _ => Ok(maze),
    }
}

/// Writes `maze` in CS559 format; fails for a cell with more than 4 edges.
pub fn write(maze: &Maze) -> Result<String, WriteError> {
    let mut out = Vec::with_capacity(64 * maze.edges().len() + 32 * maze.vertices().len());
    write_to(maze, &mut out).map_err(|e| match e {
        WriteToError::Format(e) => e,
        WriteToError::Io(e) => unreachable!("writing to a Vec cannot fail: {e}"),
    })?;
    Ok(String::from_utf8(out).unwrap_or_default()) // only ASCII was written
}

/// Why [`write_to`] stopped.
#[derive(Debug, thiserror::Error)]
pub enum WriteToError {
    /// The format cannot express the maze (nothing was written).
    #[error(transparent)]
    Format(#[from] WriteError),
    /// The sink failed.
    #[error(transparent)]
    Io(#[from] std::io::Error),
}

/// Streams `maze` in CS559 format into `out` (use a buffered writer), without building the text
/// in memory; checks first that every cell fits the format's 4 edge slots.
pub fn write_to(maze: &Maze, out: &mut impl std::io::Write) -> Result<(), WriteToError> {
    if let Some(c) = (0..maze.cell_count() as CellId).find(|&c| maze.cell_edges(c).len() > CELL_SLOTS) {
        let n = maze.cell_edges(c).len();
        let reason = format!("cell {c} has {n} edges; the format holds at most {CELL_SLOTS}");
        return Err(WriteError { format: Format::Cs559, reason }.into());
    }
    writeln!(out, "{}", maze.vertices().len())?;
    for v in maze.vertices() {
        writeln!(out, "{} {}", v.x, v.y)?;
    }
    writeln!(out, "{}", maze.edges().len())?;
    let side = |c: Option<CellId>| c.map_or(-1, i64::from);
    for e in maze.edges() {
        let (l, r, o, c) = (side(e.left), side(e.right), u8::from(e.opaque), e.color);
        writeln!(out, "{} {} {l} {r} {o} {} {} {}", e.start, e.end, c.x, c.y, c.z)?;
    }
    writeln!(out, "{}", maze.cell_count())?;
    for c in 0..maze.cell_count() as CellId {
        let ids = maze.cell_edges(c);
        for k in 0..CELL_SLOTS {
            let sep = if k + 1 == CELL_SLOTS { '\n' } else { ' ' };
            match ids.get(k) {
                Some(e) => write!(out, "{e}{sep}")?,
                None => write!(out, "-1{sep}")?,
            }
        }
    }
    let v = maze.viewer();
    writeln!(out, "{} {} {} {} {}", v.pos.x, v.pos.y, v.z, v.dir_deg, v.fov_deg)?;
    if let Some(exit) = maze.exit() {
        match exit.point {
            Some(p) => writeln!(out, "exit {} {}", p.x, p.y)?,
            None => writeln!(out, "exit {}", exit.cell)?,
        }
    }
    Ok(())
}

enum ExitSpec {
    Cell(CellId),
    Point(Vec2),
}

/// A cursor over the text handing out whitespace-separated tokens with their positions.
struct Reader<'a> {
    file: &'a str,
    text: &'a str,
    /// Byte offset of the cursor, and its line and column (kept in step: O(1) per character).
    pos: usize,
    loc: Loc,
}

impl<'a> Reader<'a> {
    /// Moves the cursor `len` bytes on, counting lines and characters.
    fn advance(&mut self, len: usize) {
        for c in self.text[self.pos..self.pos + len].chars() {
            if c == '\n' {
                self.loc = Loc { line: self.loc.line.saturating_add(1), col: 1 };
            } else {
                self.loc.col = self.loc.col.saturating_add(1);
            }
        }
        self.pos += len;
    }

    fn skip_space(&mut self) {
        let rest = &self.text[self.pos..];
        self.advance(rest.len() - rest.trim_start_matches(is_space).len());
    }

    /// Where the next token starts (or the end of the file).
    fn peek_loc(&mut self) -> Loc {
        self.skip_space();
        self.loc
    }

    /// The next token and where it starts, or an end-of-file error naming `expected`.
    fn token(&mut self, expected: &dyn Fn() -> String) -> Result<(&'a str, Loc), ParseError> {
        self.skip_space();
        let start = self.pos;
        let rest = &self.text[start..];
        let len = rest.find(is_space).unwrap_or(rest.len());
        let loc = self.loc;
        if len == 0 {
            return Err(loc.error(self.file, ParseErrorKind::UnexpectedEof { expected: expected() }));
        }
        self.advance(len);
        Ok((&rest[..len], loc))
    }

    fn expected(&self, loc: Loc, expected: &str, found: &str) -> ParseError {
        let found: String = found.chars().take(40).collect();
        loc.error(self.file, ParseErrorKind::Expected { expected: expected.into(), found })
    }

    fn integer(&mut self, what: &dyn Fn() -> String) -> Result<(i64, Loc), ParseError> {
        let (tok, loc) = self.token(what)?;
        let value =
            tok.parse::<i64>().map_err(|_| self.expected(loc, &format!("an integer ({})", what()), tok))?;
        Ok((value, loc))
    }

    /// A record count, and how many records of `tokens` tokens the rest of the file could hold.
    fn count(
        &mut self,
        what: &dyn Fn() -> String,
        plural: &'static str,
        tokens: usize,
    ) -> Result<(usize, usize), ParseError> {
        let (n, loc) = self.integer(what)?;
        if n < 0 {
            return Err(self.out_of_range(loc, what, n, "0 or more"));
        }
        let max = u64::from(u32::MAX - 1); // ids are u32, with one value left for "none"
        if n as u64 > max {
            return Err(
                loc.error(self.file, ParseErrorKind::CountTooLarge { what: plural, count: n as u64, max })
            );
        }
        // reserve only what the rest of the file could hold: each token takes a character and a separator
        let room = (self.text.len() - self.pos) / (2 * tokens) + 1;
        Ok((n as usize, (n as usize).min(room)))
    }

    /// An index, or `None` for `-1` when `may_be_none`. Range against counts is the model's check.
    fn index(&mut self, what: &dyn Fn() -> String, may_be_none: bool) -> Result<Option<u32>, ParseError> {
        let (n, loc) = self.integer(what)?;
        match n {
            -1 if may_be_none => Ok(None),
            0..=0xFFFF_FFFE => Ok(Some(n as u32)),
            _ => Err(self.out_of_range(
                loc,
                what,
                n,
                if may_be_none { "-1 or 0..2^32-1" } else { "0..2^32-1" },
            )),
        }
    }

    fn flag(&mut self, what: &dyn Fn() -> String) -> Result<bool, ParseError> {
        let (n, loc) = self.integer(what)?;
        match n {
            0 => Ok(false),
            1 => Ok(true),
            _ => Err(self.out_of_range(loc, what, n, "0 or 1")),
        }
    }

    fn out_of_range(&self, loc: Loc, what: &dyn Fn() -> String, n: i64, range: &str) -> ParseError {
        loc.error(
            self.file,
            ParseErrorKind::OutOfRange { what: what(), value: n.to_string(), range: range.into() },
        )
    }

    /// A finite `f32`.
    fn float(&mut self, what: &dyn Fn() -> String) -> Result<f32, ParseError> {
        let (tok, loc) = self.token(what)?;
        let value =
            tok.parse::<f32>().map_err(|_| self.expected(loc, &format!("a number ({})", what()), tok))?;
        if !value.is_finite() {
            return Err(loc.error(self.file, ParseErrorKind::NotFinite { what: what(), value: tok.into() }));
        }
        Ok(value)
    }

    /// After the viewer: the first line starting with the word `exit`, if any; all else is ignored.
    fn exit_extension(&mut self, locs: &mut RecordLocs) -> Result<Option<ExitSpec>, ParseError> {
        // the rest of the viewer's line is ignored too
        let Some(nl) = self.text[self.pos..].find('\n') else { return Ok(None) };
        for line in self.text[self.pos + nl + 1..].split('\n') {
            let mut words = line.split(is_space).filter(|w| !w.is_empty());
            if words.next() != Some("exit") {
                continue;
            }
            let start = line.as_ptr() as usize - self.text.as_ptr() as usize;
            let word = start + line.find("exit").unwrap_or(0);
            self.advance(word - self.pos);
            let loc = self.loc;
            self.advance("exit".len());
            locs.exit = Some(loc);
            let args = words.count();
            return Ok(Some(match args {
                1 => {
                    let (n, nloc) = self.integer(&|| "exit cell".into())?;
                    match u32::try_from(n) {
                        Ok(c) if c < u32::MAX => ExitSpec::Cell(c),
                        _ => return Err(self.out_of_range(nloc, &|| "exit cell".into(), n, "a cell index")),
                    }
                }
                2 => {
                    ExitSpec::Point(vec2(self.float(&|| "exit x".into())?, self.float(&|| "exit y".into())?))
                }
                _ => return Err(self.expected(loc, "`exit CELL` or `exit X Y`", line.trim())),
            }));
        }
        Ok(None)
    }
}
