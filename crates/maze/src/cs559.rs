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
//! extensions, a line `exit CELL` or `exit X Y` and a line `vfov DEG` (the least vertical field of
//! view the walk keeps, 0..=150: [`Maze::min_vfov_deg`], which `mazewalk gen` writes for its mazes);
//! at most one of each, and the original ignores them harmlessly.
//!
//! The writer pads cells to 4 slots with `-1` and prints every `f32` in Rust's shortest
//! round-trip form, so reading what it wrote gives back the same maze.

use glam::{Vec2, Vec3, vec2};

use super::text::{Loc, is_space, is_space_byte, quote};
use super::{
    COORD_BOUND, CellId, Cells, Edge, Edges, Exit, Format, Maze, MazeError, PackedEdge, ParseError,
    ParseErrorKind, Viewer, WriteError,
};

/// Edge slots per cell record.
const CELL_SLOTS: usize = 4;

/// Parses CS559 text (already decoded); `file` names it in errors.
pub fn parse_str(file: &str, text: &str) -> Result<Maze, ParseError> {
    parse_with(file, text, SPLIT_BYTES)
}

/// Texts from which [`parse_str`] reads on two threads (see [`read_split`]).
const SPLIT_BYTES: usize = 1 << 20;

/// [`parse_str`], reading on two threads when the text has `split_bytes` bytes or more.
fn parse_with(file: &str, text: &str, split_bytes: usize) -> Result<Maze, ParseError> {
    let split = if text.len() >= split_bytes { read_split(file, text) } else { None };
    let parts = match split {
        Some(parts) => parts,
        None => read_in_order(file, text)?,
    };
    let Parts { vertices, edges, cells, viewer, exit_at, vfov, nv, ne, nc } = parts;
    let layout = Layout { nv, ne, nc, exit_at: exit_at.as_ref().map(|e| e.1) };
    let exit = exit_at.map(|e| e.0);

    let (exit, exit_point_cell) = match exit {
        Some(ExitSpec::Cell(cell)) => (Some(Exit { cell, point: None }), false),
        Some(ExitSpec::Point(p)) => (Some(Exit { cell: 0, point: Some(p) }), true),
        None => (None, false),
    };
    // an `exit X Y` point picks its cell once the maze stands
    let maze = Maze::new(vertices, edges, cells, viewer, exit.filter(|_| !exit_point_cell))
        .map_err(|e| layout.locate(file, text, e))?
        .with_min_vfov_deg(vfov.unwrap_or(0.0));
    match exit {
        Some(Exit { point: Some(p), .. }) if exit_point_cell => {
            let Some(cell) = maze.cell_at(p) else {
                return Err(layout.locate(file, text, MazeError::ExitOutside { x: p.x, y: p.y }));
            };
            Ok(maze.with_exit(Exit { cell, point: Some(p) }))
        }
        _ => Ok(maze),
    }
}

/// What the text says, before the model checks it.
struct Parts {
    vertices: Vec<Vec2>,
    edges: Edges,
    cells: Cells,
    viewer: Viewer,
    exit_at: Option<(ExitSpec, usize)>,
    vfov: Option<f32>,
    nv: usize,
    ne: usize,
    nc: usize,
}

/// The records one after the other, stopping at the first error.
fn read_in_order(file: &str, text: &str) -> Result<Parts, ParseError> {
    let mut r = Reader { file, text, pos: 0 };
    let (nv, cap) =
        r.count(&|| "vertex count".into(), "vertices", 2).map_err(|e| grid_header_hint(text, e))?;
    let vertices = read_vertices(&mut r, nv, cap)?;
    let (ne, cap) = r.count(&|| "edge count".into(), "edges", 8)?;
    let mut edges = Edges::with_capacity(cap);
    read_edges(&mut r, 0..ne, |_, e| edges.push(e))?;
    let (nc, cells, viewer, exit_at, vfov) = read_cells_to_end(&mut r)?;
    Ok(Parts { vertices, edges, cells, viewer, exit_at, vfov, nv, ne, nc })
}

/// `e`, or a hint in its place when the file starts with a grid header in the wrong letter case
/// (`Mazewalk-Grid 1`), which is read as CS559 and so as a bad vertex count.
fn grid_header_hint(text: &str, e: ParseError) -> ParseError {
    let first = text.split(is_space).find(|w| !w.is_empty()).unwrap_or("");
    if !first.eq_ignore_ascii_case(super::grid::MAGIC) {
        return e;
    }
    let (magic, version) = (super::grid::MAGIC, super::grid::VERSION);
    let msg = format!(
        "`{}` looks like a grid file's header, which is `{magic} {version}` in lower case",
        quote(first)
    );
    ParseError { kind: ParseErrorKind::Grid(msg), ..e }
}

/// The records on two threads. The edge count is found first, by counting tokens past the
/// vertices; then this thread reads the vertices and the first part of the edges while another
/// counts its way to the rest (a token count is a few times cheaper than a parse) and reads from
/// there to the end, each writing its edges into its part of one array. `None` when either meets anything but valid records, or they
/// disagree on where their parts meet: [`read_in_order`] then reads the text again and reports the
/// first error, exactly as if the text had been read in order (the parts are found by the same
/// tokens the reader reads, so the records and their numbers are the same).
fn read_split(file: &str, text: &str) -> Option<Parts> {
    let bytes = text.as_bytes();
    let mut r = Reader { file, text, pos: 0 };
    let (nv, cap) = r.count(&|| "vertex count".into(), "vertices", 2).ok()?;
    // the edge count, found by counting tokens, so the edges can be allocated once (zeroed: no
    // page touched before its thread writes it) and each thread write its share in place
    let mut at_ne = Reader { file, text, pos: skip_tokens(bytes, r.pos, 2 * nv)? };
    let (ne, room) = at_ne.count(&|| "edge count".into(), "edges", 8).ok()?;
    if room < ne {
        return None; // more edges than the text can hold: the reader in order says where it ends
    }
    // this thread's share: the vertices (2 tokens each) and the first 3/5 of the edges (8 each);
    // the other's: counting those edges (a seventh of the cost of reading them, measured), the rest
    // of the edges and the cells (4 each): about even for the usual file
    let split = ne / 5 * 3;
    let mut packed = bytemuck::zeroed_vec::<PackedEdge>(ne);
    let mut opaque = vec![false; ne];
    let (packed_first, packed_rest) = packed.split_at_mut(split);
    let (opaque_first, opaque_rest) = opaque.split_at_mut(split);
    // a reader's sink for edge `i` of a share that starts at `first`
    let put = |records: &mut [PackedEdge], flags: &mut [bool], first: usize, i: usize, e: Edge| {
        records[i - first] = PackedEdge::new(e.start, e.end, e.left, e.right, e.color);
        flags[i - first] = e.opaque;
    };
    let parts = std::thread::scope(|s| {
        let second = s.spawn(|| {
            let mut r = Reader { file, text, pos: skip_tokens(bytes, at_ne.pos, 8 * split)? };
            let start = r.pos;
            read_edges(&mut r, split..ne, |i, e| put(packed_rest, opaque_rest, split, i, e)).ok()?;
            Some((start, read_cells_to_end(&mut r).ok()?))
        });
        let first = (|| {
            let vertices = read_vertices(&mut r, nv, cap).ok()?;
            // the count this thread reads is the one counted to
            r.count(&|| "edge count".into(), "edges", 8).ok().filter(|_| r.pos == at_ne.pos)?;
            read_edges(&mut r, 0..split, |i, e| put(packed_first, opaque_first, 0, i, e)).ok()?;
            r.skip_space();
            Some((vertices, r.pos))
        })();
        let second = second.join().unwrap_or_else(|panic| std::panic::resume_unwind(panic));
        let ((vertices, end), (start, tail)) = (first?, second?);
        (end == start).then_some((vertices, tail))
    });
    let (vertices, (nc, cells, viewer, exit_at, vfov)) = parts?;
    let edges = Edges::from_records(packed, |i, _| opaque[i]);
    Some(Parts { vertices, edges, cells, viewer, exit_at, vfov, nv, ne, nc })
}

/// The offset of the first byte of the token `k` tokens on from `pos` (`k` = 0: the next one), or
/// `None` if the text ends first. Counts token starts (a non-space after a space) 64 bytes at a
/// time, a loop the compiler vectorises (a quarter of the time it took as a filtered count); only
/// the last block is walked byte by byte.
fn skip_tokens(bytes: &[u8], pos: usize, k: usize) -> Option<usize> {
    let (mut at, mut left) = (pos, k);
    while at + 64 <= bytes.len() {
        let block = &bytes[at..at + 64];
        let before = if at == pos { true } else { is_space_byte(bytes[at - 1]) };
        // bytewise `&` and a u8 sum (at most 64 starts), so the compiler vectorises the block
        let space = |b: u8| (b == b' ') | (b.wrapping_sub(b'\t') <= b'\r' - b'\t');
        let inner =
            block[..63].iter().zip(&block[1..]).fold(0u8, |n, (&a, &b)| n + u8::from(space(a) & !space(b)));
        let n = usize::from(inner) + usize::from(before && !space(block[0]));
        if n > left {
            break;
        }
        left -= n;
        at += 64;
    }
    let prev_space = |i: usize| i == pos || is_space_byte(bytes[i - 1]);
    (at..bytes.len()).filter(|&i| !is_space_byte(bytes[i]) && prev_space(i)).nth(left)
}

fn read_vertices(r: &mut Reader, nv: usize, cap: usize) -> Result<Vec<Vec2>, ParseError> {
    let mut vertices = Vec::with_capacity(cap);
    for i in 0..nv {
        if let Some([x, y]) = r.plain(|s| Some([s.float()?, s.float()?])) {
            vertices.push(vec2(x, y));
            continue;
        }
        let within = format!("within ±{COORD_BOUND}");
        let x = r.float(&|| format!("vertex {i} x"), &within)?;
        let y = r.float(&|| format!("vertex {i} y"), &within)?;
        vertices.push(vec2(x, y));
    }
    Ok(vertices)
}

/// Edges `ids`, appended to `edges`.
fn read_edges(
    r: &mut Reader,
    ids: std::ops::Range<usize>,
    mut put: impl FnMut(usize, Edge),
) -> Result<(), ParseError> {
    for i in ids {
        let plain = |s: &mut Plain| {
            let (start, end) = (s.index()?, s.index()?);
            let (left, right) = (s.side()?, s.side()?);
            let opaque = match s.int()? {
                0 => false,
                1 => true,
                _ => return None,
            };
            let color = Vec3::new(s.float()?, s.float()?, s.float()?);
            Some(Edge { start, end, left, right, opaque, color })
        };
        if let Some(edge) = r.plain(plain) {
            put(i, edge);
            continue;
        }
        let start = r.index(&|| format!("edge {i} start vertex"), false)?.unwrap_or_default();
        let end = r.index(&|| format!("edge {i} end vertex"), false)?.unwrap_or_default();
        let left = r.index(&|| format!("edge {i} left cell"), true)?;
        let right = r.index(&|| format!("edge {i} right cell"), true)?;
        let opaque = r.flag(&|| format!("edge {i} opaque flag"))?;
        let mut c = [0.0; 3];
        for (k, name) in ["red", "green", "blue"].iter().enumerate() {
            c[k] = r.float(&|| format!("edge {i} {name}"), "0..=1")?;
        }
        put(i, Edge { start, end, left, right, opaque, color: Vec3::from(c) });
    }
    Ok(())
}

/// The cell count, the cells, the viewer, the optional exit line and the optional `vfov` line.
type Tail = (usize, Cells, Viewer, Option<(ExitSpec, usize)>, Option<f32>);

fn read_cells_to_end(r: &mut Reader) -> Result<Tail, ParseError> {
    let (nc, cap) = r.count(&|| "cell count".into(), "cells", CELL_SLOTS)?;
    let mut cells = Cells::with_capacity(cap, cap * CELL_SLOTS);
    for i in 0..nc {
        let mut slots = [0; CELL_SLOTS];
        let mut n = 0;
        let plain = |s: &mut Plain| {
            let mut slots = [0; CELL_SLOTS];
            let mut n = 0;
            for _ in 0..CELL_SLOTS {
                if let Some(e) = s.side()? {
                    slots[n] = e;
                    n += 1;
                }
            }
            Some((slots, n))
        };
        if let Some((slots, n)) = r.plain(plain) {
            cells.push(&slots[..n]);
            continue;
        }
        for k in 0..CELL_SLOTS {
            if let Some(e) = r.index(&|| format!("cell {i} edge {}", k + 1), true)? {
                slots[n] = e;
                n += 1;
            }
        }
        cells.push(&slots[..n]);
    }
    let mut v = [0.0; 5];
    let within = format!("within ±{COORD_BOUND}");
    let fields = [
        ("x", within.as_str()),
        ("y", &within),
        ("z", "strictly between -1 and 1"),
        ("direction", &within),
        ("field of view", "strictly between 0 and 180"),
    ];
    for (k, (name, range)) in fields.iter().enumerate() {
        v[k] = r.float(&|| format!("viewer {name}"), range)?;
    }
    let viewer = Viewer { pos: vec2(v[0], v[1]), z: v[2], dir_deg: v[3], fov_deg: v[4] };
    let after_viewer = r.pos;
    r.misplaced_keywords()?;
    r.pos = after_viewer;
    let vfov = r.vfov_extension()?;
    r.pos = after_viewer;
    Ok((nc, cells, viewer, r.exit_extension()?, vfov))
}

/// Where the records are, as token numbers: enough to find any record again when the model
/// rejects it (a rare event, so it re-scans the text rather than keep a position per record).
struct Layout {
    nv: usize,
    ne: usize,
    nc: usize,
    /// Byte offset of the `exit` line's first word.
    exit_at: Option<usize>,
}

impl Layout {
    /// The error located at the record, and within it the field, that `err` is about.
    fn locate(&self, file: &str, text: &str, err: MazeError) -> ParseError {
        use MazeError::*;
        let (nv, ne, nc) = (self.nv, self.ne, self.nc);
        let vertex = |v: u32| 1 + 2 * v as usize;
        let edge = |e: u32| 2 + 2 * nv + 8 * e as usize;
        let cell = |c: u32| 3 + 2 * nv + 8 * ne + 4 * c as usize;
        let viewer = 3 + 2 * nv + 8 * ne + 4 * nc;
        // the record's first token, and which of its fields is at fault (by the values in the file)
        let (first, field): (usize, &FieldOf) = match err {
            NoCells | TooMany { .. } => (0, &|_, _| 0),
            VertexOutOfBounds { vertex: v } => {
                (vertex(v), &|_, f| usize::from(f[0].is_finite() && f[0].abs() <= COORD_BOUND))
            }
            EdgeVertexOutOfRange { edge: e, vertex: v, .. } => {
                (edge(e), &move |i, _| usize::from(i[0] != i64::from(v)))
            }
            EdgeDegenerate { edge: e, .. } => (edge(e), &|_, _| 1),
            EdgeCellOutOfRange { edge: e, cell: c, .. } => {
                (edge(e), &move |i, _| if i[2] == i64::from(c) { 2 } else { 3 })
            }
            EdgeSameCellBothSides { edge: e, .. } => (edge(e), &|_, _| 3),
            EdgeNoCell { edge: e } => (edge(e), &|_, _| 2),
            PortalToOutside { edge: e } => (edge(e), &|_, _| 4),
            EdgeColor { edge: e } => {
                (edge(e), &|_, f| (5..8).find(|&k| !(0.0..=1.0).contains(&f[k])).unwrap_or(5))
            }
            CellMissingEdge { edge: e, side, .. } => {
                (edge(e), if side == "left" { &|_, _| 2 } else { &|_, _| 3 })
            }
            EdgesCross { a, b } | EdgesOverlap { a, b } => (edge(a.max(b)), &|_, _| 0),
            CellEdgeOutOfRange { cell: c, edge: e, .. } | CellEdgeNotNeighbour { cell: c, edge: e } => {
                (cell(c), &move |i, _| i.iter().position(|&x| x == i64::from(e)).unwrap_or(0))
            }
            CellEdgeDuplicate { cell: c, edge: e } => (cell(c), &move |i, _| {
                i.iter().enumerate().filter(|&(_, &x)| x == i64::from(e)).nth(1).map_or(0, |p| p.0)
            }),
            CellTooFewEdges { cell: c, .. }
            | CellNotClosed { cell: c, .. }
            | CellNotConvex { cell: c, .. }
            | CellTooSmall { cell: c, .. }
            | CellsOverlap { cell: c, .. }
            | CellClockwise { cell: c } => (cell(c), &|_, _| 0),
            ViewerNotFinite => (viewer, &|_, f| {
                let ok = [COORD_BOUND, COORD_BOUND, f32::MAX, COORD_BOUND, f32::MAX];
                (0..5).find(|&k| !(f[k].is_finite() && f[k].abs() <= ok[k])).unwrap_or(0)
            }),
            ViewerHeight { .. } => (viewer, &|_, _| 2),
            ViewerFov { .. } => (viewer, &|_, _| 4),
            ViewerOutside { .. } | ViewerOnWall { .. } | ViewerNoRoom { .. } => (viewer, &|_, _| 0),
            ExitCellOutOfRange { .. } | ExitOutside { .. } | ExitPointOutside { .. } => {
                let at = self.exit_at.unwrap_or(0);
                return Loc::of(text, at).error(file, ParseErrorKind::Invalid(err));
            }
        };
        let tokens: Vec<(usize, &str)> = tokens(text).skip(first).take(8).collect();
        let mut ints: Vec<i64> = tokens.iter().map(|t| t.1.parse().unwrap_or(i64::MIN)).collect();
        let mut floats: Vec<f32> = tokens.iter().map(|t| t.1.parse().unwrap_or(f32::NAN)).collect();
        ints.resize(8, i64::MIN);
        floats.resize(8, f32::NAN);
        let at = tokens.get(field(&ints, &floats)).or(tokens.first()).map_or(0, |t| t.0);
        Loc::of(text, at).error(file, ParseErrorKind::Invalid(err))
    }
}

/// A decimal integer with an optional sign, as `str::parse::<i64>` reads it (a third of its time on
/// the short numbers of a maze file, where `integer` is half of the reader's time).
fn parse_i64(tok: &str) -> Option<i64> {
    let (negative, digits) = match tok.as_bytes() {
        [b'-', rest @ ..] => (true, rest),
        [b'+', rest @ ..] => (false, rest),
        rest => (false, rest),
    };
    if digits.is_empty() {
        return None;
    }
    // accumulate negatively, so i64::MIN fits
    let mut n: i64 = 0;
    for &b in digits {
        let d = b.wrapping_sub(b'0');
        if d > 9 {
            return None;
        }
        n = n.checked_mul(10)?.checked_sub(i64::from(d))?;
    }
    if negative { Some(n) } else { n.checked_neg() }
}

/// The token at the start of `bytes` (up to a space or the end) and its length, if it is a plain
/// decimal of at most 7 digits (`-12.5`, `0.57`, `3996`: what mazes hold); `None` for anything else,
/// which `str::parse` then reads. Exact: both the digits (below 2^24) and the power of
/// ten are `f32`s, and one IEEE division rounds correctly (Clinger's fast path).
fn short_f32(bytes: &[u8]) -> Option<(f32, usize)> {
    const TENS: [f32; 8] = [1.0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7];
    let (negative, skip) = match bytes.first() {
        Some(b'-') => (true, 1),
        Some(b'+') => (false, 1),
        _ => (false, 0),
    };
    let (mut m, mut digits, mut frac, mut point) = (0u32, 0usize, 0usize, false);
    let mut len = skip;
    for &b in &bytes[skip..] {
        match b {
            b'0'..=b'9' => {
                m = m * 10 + u32::from(b - b'0');
                digits += 1;
                frac += usize::from(point);
                if digits > 7 {
                    return None;
                }
            }
            b'.' if !point => point = true,
            _ if is_space_byte(b) => break,
            _ => return None,
        }
        len += 1;
    }
    if digits == 0 {
        return None;
    }
    let v = m as f32 / TENS[frac];
    Some((if negative { -v } else { v }, len))
}

/// An integer of at most 18 digits (no overflow) at the start of `bytes`, up to a space or the end,
/// with its length; `None` for anything else, which [`parse_i64`] then reads.
fn short_i64(bytes: &[u8]) -> Option<(i64, usize)> {
    let skip = usize::from(matches!(bytes.first(), Some(b'-' | b'+')));
    let mut n: i64 = 0;
    let mut len = skip;
    for &b in &bytes[skip..] {
        match b {
            b'0'..=b'9' if len - skip < 18 => n = n * 10 + i64::from(b - b'0'),
            _ if is_space_byte(b) => break,
            _ => return None,
        }
        len += 1;
    }
    if len == skip {
        return None;
    }
    Some((if bytes[0] == b'-' { -n } else { n }, len))
}

/// Which field of a record is at fault, from the record's tokens read as integers and as numbers.
type FieldOf = dyn Fn(&[i64], &[f32]) -> usize;

/// The whitespace-separated tokens of `text` and their byte offsets.
fn tokens(text: &str) -> impl Iterator<Item = (usize, &str)> {
    let base = text.as_ptr() as usize;
    text.split(is_space).filter(|t| !t.is_empty()).map(move |t| (t.as_ptr() as usize - base, t))
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
    if maze.min_vfov_deg() > 0.0 {
        writeln!(out, "vfov {}", maze.min_vfov_deg())?;
    }
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

/// A cursor over the text handing out whitespace-separated tokens with their byte offsets (lines and
/// columns are worked out only for an error).
/// The fast path for a record: its tokens read in one pass over the bytes, each a plain number
/// within its field's range, or `None` at the first that is not (the [`Reader`] then reads the
/// record again token by token, and reports what is wrong). Most of loading a big file is here:
/// without the per-token `Result`s, messages and cursor updates, and with [`digits`], parsing a
/// 300 × 300 maze takes 12 % fewer instructions.
struct Plain<'a> {
    bytes: &'a [u8],
    pos: usize,
}

impl Plain<'_> {
    /// Skips spaces; `None` at the end of the text.
    fn skip_space(&mut self) -> Option<()> {
        while is_space_byte(*self.bytes.get(self.pos)?) {
            self.pos += 1;
        }
        Some(())
    }

    /// `true` when the token ends here (a space or the end of the text follows).
    fn token_ends(&self) -> bool {
        self.bytes.get(self.pos).is_none_or(|&b| is_space_byte(b))
    }

    /// An integer of 1 to 7 digits, `-` allowed.
    fn int(&mut self) -> Option<i64> {
        self.skip_space()?;
        let negative = self.bytes[self.pos] == b'-';
        self.pos += usize::from(negative);
        let (n, len) = digits(&self.bytes[self.pos..])?;
        self.pos += len;
        (len > 0 && self.token_ends()).then_some(if negative { -(n as i64) } else { n as i64 })
    }

    /// An id, `0..2^32-1`.
    fn index(&mut self) -> Option<u32> {
        self.int().and_then(|n| u32::try_from(n).ok()).filter(|&n| n != u32::MAX)
    }

    /// A cell id or `-1` (outside).
    fn side(&mut self) -> Option<Option<u32>> {
        match self.int()? {
            -1 => Some(None),
            n => u32::try_from(n).ok().filter(|&n| n != u32::MAX).map(Some),
        }
    }

    /// A number as [`short_f32`] reads it.
    fn float(&mut self) -> Option<f32> {
        self.skip_space()?;
        let (value, len) = short_f32(&self.bytes[self.pos..])?;
        self.pos += len;
        Some(value)
    }
}

/// The value and length of the run of ASCII digits at the start of `bytes`, if it has at most 7
/// (and 8 bytes can be read: the last few bytes of a text take the token reader). One word at a
/// time: find the first non-digit byte, then sum the digits by pairs, quads and the whole word,
/// a multiply each (the first digit in the lowest byte, as a little-endian load puts it). A
/// fifth fewer instructions than a loop over the bytes, for the ids of a 1000 × 1000 maze.
fn digits(bytes: &[u8]) -> Option<(u64, usize)> {
    let word = u64::from_le_bytes(*bytes.first_chunk::<8>()?);
    let d = word.wrapping_sub(0x3030_3030_3030_3030);
    // a byte's top bit: below '0' (wrapped) or above '9' (+ 0x76 carries into it); the bytes
    // before the first such are digits, and carry or borrow nothing into it
    let non_digit = (d | d.wrapping_add(0x7676_7676_7676_7676)) & 0x8080_8080_8080_8080;
    let len = (non_digit.trailing_zeros() / 8) as usize;
    if len == 0 || len > 7 {
        return (len == 0).then_some((0, 0));
    }
    // the digits to the top bytes, zeros (leading zero digits) below them
    let d = d << (8 * (8 - len));
    let d = ((d & 0x0F0F_0F0F_0F0F_0F0F).wrapping_mul(2561)) >> 8;
    let d = ((d & 0x00FF_00FF_00FF_00FF).wrapping_mul(6_553_601)) >> 16;
    let d = ((d & 0x0000_FFFF_0000_FFFF).wrapping_mul(42_949_672_960_001)) >> 32;
    Some((d, len))
}

struct Reader<'a> {
    file: &'a str,
    text: &'a str,
    /// Byte offset of the cursor.
    pos: usize,
}

impl<'a> Reader<'a> {
    /// A record by its fast path `read` (see [`Plain`]); the cursor moves only when it succeeds.
    fn plain<T>(&mut self, read: impl FnOnce(&mut Plain) -> Option<T>) -> Option<T> {
        let mut plain = Plain { bytes: self.text.as_bytes(), pos: self.pos };
        let record = read(&mut plain)?;
        self.pos = plain.pos;
        Some(record)
    }

    fn skip_space(&mut self) {
        let rest = &self.text.as_bytes()[self.pos..];
        self.pos += rest.iter().position(|&b| !is_space_byte(b)).unwrap_or(rest.len());
    }

    fn error(&self, at: usize, kind: ParseErrorKind) -> ParseError {
        Loc::of(self.text, at).error(self.file, kind)
    }

    /// The next token and its byte offset, or an end-of-file error naming `expected`.
    fn token(&mut self, expected: &dyn Fn() -> String) -> Result<(&'a str, usize), ParseError> {
        self.skip_space();
        let start = self.pos;
        let rest = &self.text.as_bytes()[start..];
        let len = rest.iter().position(|&b| is_space_byte(b)).unwrap_or(rest.len());
        if len == 0 {
            return Err(self.error(start, ParseErrorKind::UnexpectedEof { expected: expected() }));
        }
        self.pos += len;
        // spaces are ASCII, so the token ends on a character boundary
        Ok((&self.text[start..start + len], start))
    }

    fn expected(&self, at: usize, expected: &str, found: &str) -> ParseError {
        self.error(at, ParseErrorKind::Expected { expected: expected.into(), found: quote(found) })
    }

    fn integer(&mut self, what: &dyn Fn() -> String) -> Result<(i64, usize), ParseError> {
        // the common case in one pass over the bytes; anything unusual takes the token path
        self.skip_space();
        if let Some((value, len)) = short_i64(&self.text.as_bytes()[self.pos..]) {
            let at = self.pos;
            self.pos += len;
            return Ok((value, at));
        }
        let (tok, at) = self.token(what)?;
        let value = parse_i64(tok).ok_or_else(|| {
            // All digits, but more than 64 bits hold: an integer, out of range.
            let digits = tok.strip_prefix(['-', '+']).unwrap_or(tok);
            if !digits.is_empty() && digits.bytes().all(|b| b.is_ascii_digit()) {
                let range = "a 64-bit integer; the counts and indices are far smaller";
                self.error(
                    at,
                    ParseErrorKind::OutOfRange { what: what(), value: quote(tok), range: range.into() },
                )
            } else {
                self.expected(at, &format!("an integer ({})", what()), tok)
            }
        })?;
        Ok((value, at))
    }

    /// A record count, and how many records of `tokens` tokens the rest of the file could hold.
    fn count(
        &mut self,
        what: &dyn Fn() -> String,
        plural: &'static str,
        tokens: usize,
    ) -> Result<(usize, usize), ParseError> {
        let (n, at) = self.integer(what)?;
        if n < 0 {
            return Err(self.out_of_range(at, what, n, "0 or more"));
        }
        let max = u64::from(u32::MAX - 1); // ids are u32, with one value left for "none"
        if n as u64 > max {
            return Err(self.error(at, ParseErrorKind::CountTooLarge { what: plural, count: n as u64, max }));
        }
        // reserve only what the rest of the file could hold: each token takes a character and a separator
        let room = (self.text.len() - self.pos) / (2 * tokens) + 1;
        Ok((n as usize, (n as usize).min(room)))
    }

    /// An index, or `None` for `-1` when `may_be_none`. Range against counts is the model's check.
    fn index(&mut self, what: &dyn Fn() -> String, may_be_none: bool) -> Result<Option<u32>, ParseError> {
        let (n, at) = self.integer(what)?;
        match n {
            -1 if may_be_none => Ok(None),
            0..=0xFFFF_FFFE => Ok(Some(n as u32)),
            _ => {
                Err(self.out_of_range(at, what, n, if may_be_none { "-1 or 0..2^32-1" } else { "0..2^32-1" }))
            }
        }
    }

    fn flag(&mut self, what: &dyn Fn() -> String) -> Result<bool, ParseError> {
        let (n, at) = self.integer(what)?;
        match n {
            0 => Ok(false),
            1 => Ok(true),
            _ => Err(self.out_of_range(at, what, n, "0 or 1")),
        }
    }

    fn out_of_range(&self, at: usize, what: &dyn Fn() -> String, n: i64, range: &str) -> ParseError {
        self.error(at, ParseErrorKind::OutOfRange { what: what(), value: n.to_string(), range: range.into() })
    }

    /// A finite `f32`; `range` is the field's, which a number too large for an `f32` is told.
    fn float(&mut self, what: &dyn Fn() -> String, range: &str) -> Result<f32, ParseError> {
        self.skip_space();
        if let Some((value, len)) = short_f32(&self.text.as_bytes()[self.pos..]) {
            self.pos += len;
            return Ok(value);
        }
        let (tok, at) = self.token(what)?;
        let value =
            tok.parse::<f32>().map_err(|_| self.expected(at, &format!("a number ({})", what()), tok))?;
        if !value.is_finite() {
            if tok.parse::<f64>().is_ok_and(f64::is_finite) {
                // A number, too large for the 32-bit floats a maze is made of, and so for the field.
                let range = range.into();
                return Err(
                    self.error(at, ParseErrorKind::OutOfRange { what: what(), value: quote(tok), range })
                );
            }
            return Err(self.error(at, ParseErrorKind::NotFinite { what: what(), value: quote(tok) }));
        }
        Ok(value)
    }

    /// After the viewer: refuses an `exit` or `vfov` that would otherwise be dropped without a word
    /// (the lines are found by their exact lower-case first word; all else after the viewer is
    /// ignored): one on the viewer's own line, or one in another case (`EXIT 1`, `Vfov 60`).
    fn misplaced_keywords(&self) -> Result<(), ParseError> {
        const KEYWORDS: [&str; 2] = ["exit", "vfov"];
        let keyword = |w: &str| KEYWORDS.into_iter().find(|k| w.eq_ignore_ascii_case(k));
        let rest = &self.text[self.pos..];
        let (viewer_line, after) = rest.split_once('\n').unwrap_or((rest, ""));
        let offset = |w: &str| w.as_ptr() as usize - self.text.as_ptr() as usize;
        if let Some(w) = viewer_line.split(is_space).find(|w| keyword(w).is_some()) {
            // a file saved with CR alone ending its lines (classic Mac OS) is one line to this
            // reader: say so, at the first such CR, not that the keyword shares the viewer's line
            let before = &viewer_line[..offset(w) - offset(viewer_line)];
            if let Some(cr) = before.find('\r') {
                return Err(self.error(offset(viewer_line) + cr, ParseErrorKind::LoneCarriageReturn));
            }
            let k = keyword(w).unwrap_or("exit");
            let expected = format!("`{k}` on a line of its own, after the viewer's line");
            return Err(self.expected(offset(w), &expected, w));
        }
        for line in after.split('\n') {
            let Some(w) = line.split(is_space).find(|w| !w.is_empty()) else { continue };
            if let Some(k) = keyword(w)
                && w != k
            {
                return Err(self.expected(offset(w), &format!("`{k}` in lower case"), w));
            }
        }
        Ok(())
    }

    /// After the viewer: the number of the line starting with the word `vfov`, if any (0..=150); a
    /// second such line is refused, all else is ignored.
    fn vfov_extension(&mut self) -> Result<Option<f32>, ParseError> {
        let Some(nl) = self.text[self.pos..].find('\n') else { return Ok(None) };
        let first_word = |l: &str| l.split(is_space).find(|w| !w.is_empty()) == Some("vfov");
        let mut lines = self.text[self.pos + nl + 1..].split('\n');
        let Some(line) = lines.find(|l| first_word(l)) else { return Ok(None) };
        let start = line.as_ptr() as usize - self.text.as_ptr() as usize;
        let word = start + line.find("vfov").unwrap_or(0);
        if line.split(is_space).filter(|w| !w.is_empty()).count() != 2 {
            return Err(self.expected(word, "`vfov DEG`", line.trim()));
        }
        if let Some(second) = lines.find(|l| first_word(l)) {
            let at =
                second.as_ptr() as usize - self.text.as_ptr() as usize + second.find("vfov").unwrap_or(0);
            let first_line = Loc::of(self.text, word).line;
            let what = "`vfov` line".to_string();
            return Err(self.error(at, ParseErrorKind::Duplicate { what, first_line }));
        }
        self.pos = word + "vfov".len();
        self.skip_space();
        let at = self.pos;
        let range = "within 0..=150";
        let value = self.float(&|| "least vertical field of view".into(), range)?;
        if !(0.0..=150.0).contains(&value) {
            let kind = ParseErrorKind::OutOfRange {
                what: "least vertical field of view".into(),
                value: value.to_string(),
                range: range.into(),
            };
            return Err(self.error(at, kind));
        }
        Ok(Some(value))
    }

    /// After the viewer: the first line starting with the word `exit`, if any, and where it starts;
    /// a second such line is refused, all else is ignored.
    fn exit_extension(&mut self) -> Result<Option<(ExitSpec, usize)>, ParseError> {
        // the rest of the viewer's line is ignored too
        let Some(nl) = self.text[self.pos..].find('\n') else { return Ok(None) };
        for line in self.text[self.pos + nl + 1..].split('\n') {
            let mut words = line.split(is_space).filter(|w| !w.is_empty());
            if words.next() != Some("exit") {
                continue;
            }
            let start = line.as_ptr() as usize - self.text.as_ptr() as usize;
            let word = start + line.find("exit").unwrap_or(0);
            self.pos = word + "exit".len();
            let args = words.count();
            let spec = match args {
                1 => {
                    let (n, at) = self.integer(&|| "exit cell".into())?;
                    match u32::try_from(n) {
                        Ok(c) if c < u32::MAX => ExitSpec::Cell(c),
                        _ => return Err(self.out_of_range(at, &|| "exit cell".into(), n, "a cell index")),
                    }
                }
                2 => {
                    let within = format!("within ±{COORD_BOUND}");
                    let x = self.float(&|| "exit x".into(), &within)?;
                    ExitSpec::Point(vec2(x, self.float(&|| "exit y".into(), &within)?))
                }
                _ => return Err(self.expected(word, "`exit CELL` or `exit X Y`", line.trim())),
            };
            // a second `exit` line is refused: which one the walk would take is anyone's guess
            let rest = &self.text[start + line.len()..];
            let second = rest.split('\n').find(|l| l.split(is_space).find(|w| !w.is_empty()) == Some("exit"));
            if let Some(second) = second {
                let at =
                    second.as_ptr() as usize - self.text.as_ptr() as usize + second.find("exit").unwrap_or(0);
                let first_line = Loc::of(self.text, word).line;
                let what = "`exit` line".to_string();
                return Err(self.error(at, ParseErrorKind::Duplicate { what, first_line }));
            }
            return Ok(Some((spec, word)));
        }
        Ok(None)
    }
}

#[cfg(test)]
mod tests {
    use super::{Plain, parse_i64, short_f32, short_i64};

    fn parse_short_f32(tok: &str) -> Option<f32> {
        short_f32(tok.as_bytes()).filter(|&(_, len)| len == tok.len()).map(|(v, _)| v)
    }

    #[test]
    fn short_decimals_read_as_std_reads_them() {
        let mut tokens: Vec<String> =
            ["0", "-0", "0.5", ".5", "5.", "-12.5", "+3", "3996", "0.57", "9999999", "0.123456", "-.0000001"]
                .map(String::from)
                .to_vec();
        // every 4-digit decimal with the point anywhere
        for m in (0..10_000).step_by(7) {
            for k in 0..=4 {
                let s = format!("{m:04}");
                tokens.push(format!("{}.{}", &s[..4 - k], &s[4 - k..]));
            }
        }
        for tok in &tokens {
            let want: f32 = tok.parse().unwrap();
            assert_eq!(parse_short_f32(tok).map(f32::to_bits), Some(want.to_bits()), "{tok}");
        }
        for tok in ["", ".", "-", "1e3", "12345678", "0.12345678", "1.2.3", "nan", "inf", "1_0"] {
            assert_eq!(parse_short_f32(tok), None, "{tok}");
        }
    }

    #[test]
    fn two_threads_read_what_one_reads() {
        use crate::generate::{GenOptions, generate};
        let opts =
            GenOptions { width: 9, height: 5, seed: 3, loops: 0.3, exit: true, ..GenOptions::default() };
        let text = super::write(&generate(&opts).unwrap()).unwrap();
        // every text: split at any size (0), and read in order (usize::MAX)
        let both = |text: &str| (super::parse_with("f", text, 0), super::parse_with("f", text, usize::MAX));
        let (split, in_order) = both(&text);
        assert_eq!(split.unwrap(), in_order.unwrap());
        assert!(super::read_split("f", &text).is_some(), "a valid text is read on two threads");
        // records across lines, and errors in either part or in the counts: the same first error
        let lines: Vec<&str> = text.lines().collect();
        // (the `exit` and `vfov` lines stay lines of their own: on the viewer's line they are refused)
        let (extensions, records): (Vec<&str>, Vec<&str>) =
            lines.iter().partition(|l| l.starts_with("exit") || l.starts_with("vfov"));
        assert_eq!(extensions.len(), 2, "the premise: gen writes an exit and a vfov line");
        let joined = format!("{}\n{}\n", records.join("  \n ").replace("\n", " "), extensions.join("\n"));
        let (split, in_order) = both(&joined);
        assert_eq!(split.unwrap(), in_order.unwrap());
        // a claimed count beyond the text: the same end-of-file error, and no room reserved for it
        let claims = format!("3 0 0 1 0 0 1 4294967294 {}", "0 1 0 -1 1 .5 .5 .5 ".repeat(50));
        let (split, in_order) = both(&claims);
        assert_eq!(split.map_err(|e| e.to_string()), in_order.map_err(|e| e.to_string()));
        for at in [0, 1, 3, lines.len() / 3, lines.len() / 2, 2 * lines.len() / 3, lines.len() - 2] {
            for bad in ["x", "7", "", "1 2 3 4 5 6 7 8 9"] {
                let mut broken = lines.clone();
                broken[at] = bad;
                let broken = broken.join("\n");
                let (split, in_order) = both(&broken);
                assert_eq!(
                    split.map_err(|e| e.to_string()),
                    in_order.map_err(|e| e.to_string()),
                    "line {at} `{bad}`"
                );
            }
        }
    }

    #[test]
    fn skipping_tokens_lands_where_reading_them_does() {
        let text = "  12 3\n\n-4   5.5 x\t7 ".repeat(30);
        let bytes = text.as_bytes();
        let starts: Vec<usize> = (0..bytes.len())
            .filter(|&i| {
                bytes[i] != b' '
                    && !bytes[i].is_ascii_whitespace()
                    && (i == 0 || bytes[i - 1].is_ascii_whitespace())
            })
            .collect();
        for (k, &at) in starts.iter().enumerate() {
            assert_eq!(super::skip_tokens(bytes, 0, k), Some(at), "{k}");
            if k > 0 {
                // from just after the previous token
                let after = starts[k - 1] + text[starts[k - 1]..].find(char::is_whitespace).unwrap();
                assert_eq!(super::skip_tokens(bytes, after, 0), Some(at), "{k}");
            }
        }
        assert_eq!(super::skip_tokens(bytes, 0, starts.len()), None);
    }

    #[test]
    fn the_plain_record_reader_reads_as_std_reads_or_leaves_the_token() {
        let mut tokens = Vec::new();
        for sign in ["", "-", "+"] {
            for whole in ["", "0", "7", "42", "1234567", "12345678", "00000001", "9999999"] {
                tokens.push(format!("{sign}{whole}"));
                for frac in ["", "5", "25", "0625", "1234567"] {
                    tokens.push(format!("{sign}{whole}.{frac}"));
                }
            }
        }
        tokens.extend(
            ["1e3", "1x", "--1", "0x10", "٣", "1.2.3", "1..2", "-.", "1-", "12/3", "9:"].map(String::from),
        );
        let mut taken = 0;
        for tok in tokens.iter().filter(|t| !t.is_empty()) {
            // a space after, more tokens, or the end of the text (too short for a word: left alone)
            for tail in [" 1 2 3 4 5 6 7 8", "\n", "\t9 9 9 9 9 9 9 9", ""] {
                let text = format!("{tok}{tail}");
                let mut p = Plain { bytes: text.as_bytes(), pos: 0 };
                if let Some(v) = p.int() {
                    assert_eq!(Ok(v), tok.parse::<i64>(), "{text:?}");
                    assert_eq!(p.pos, tok.len(), "{text:?}");
                    taken += 1;
                }
                let mut p = Plain { bytes: text.as_bytes(), pos: 0 };
                if let Some(v) = p.float() {
                    assert_eq!(v.to_bits(), tok.parse::<f32>().unwrap().to_bits(), "{text:?}");
                    assert_eq!(p.pos, tok.len(), "{text:?}");
                    taken += 1;
                }
            }
        }
        assert!(taken > 100, "{taken}");
        // what mazes hold is taken, with a space or a line after it
        for (tok, int) in [("42", Some(42)), ("-1", Some(-1)), ("1234567", Some(1_234_567)), ("0.57", None)] {
            for tail in [" 0 0 0 0 0 0 0 0", "\n0 0 0 0 0 0 0 0"] {
                let text = format!("{tok}{tail}");
                assert_eq!(Plain { bytes: text.as_bytes(), pos: 0 }.int(), int, "{text:?}");
                let float = tok.parse::<f32>().ok();
                assert_eq!(Plain { bytes: text.as_bytes(), pos: 0 }.float(), float, "{text:?}");
            }
        }
        // every value of 1 to 7 digits (a sample: all below 10^5, every 997th above)
        for n in (0..100_000).chain((100_000..10_000_000).step_by(997)).chain([9_999_999]) {
            let text = format!("{n} 0.57 -3.5 0 0 0 0");
            let mut p = Plain { bytes: text.as_bytes(), pos: 0 };
            assert_eq!((p.int(), p.float(), p.float()), (Some(n), Some(0.57), Some(-3.5)), "{text}");
        }
    }

    #[test]
    fn integers_read_as_std_reads_them() {
        for tok in ["0", "-1", "+7", "42", "-0", "9223372036854775807", "-9223372036854775808"] {
            assert_eq!(parse_i64(tok), tok.parse().ok(), "{tok}");
        }
        for tok in
            ["", "-", "+", "1.5", "x", "9223372036854775808", "-9223372036854775809", "1e3", "--1", "٣"]
        {
            assert_eq!(parse_i64(tok), None, "{tok}");
            assert!(tok.parse::<i64>().is_err(), "{tok}");
            assert_eq!(short_i64(tok.as_bytes()), None, "{tok}");
        }
        // the one-pass reader stops at a space, and leaves long numbers to parse_i64
        assert_eq!(short_i64(b"-12 7"), Some((-12, 3)));
        assert_eq!(short_i64(b"123456789012345678"), Some((123_456_789_012_345_678, 18)));
        assert_eq!(short_i64(b"1234567890123456789"), None);
        assert_eq!(short_f32(b"0.5\n1"), Some((0.5, 3)));
        assert_eq!(short_f32(b"0.5x"), None);
    }
}
