//! The grid format: a maze drawn as text, one character per square tile.
//!
//! ```text
//! mazewalk-grid 1
//! ; a comment: lines starting with `;` before the map are ignored
//! tile = 4
//! fov = 90
//! A = #cc8844
//! B = 0.2 0.4 0.9
//! #########
//! #>..A...#
//! #.#.A.#.#
//! #.#...#E#
//! ###BBB###
//! ```
//!
//! - The first line is `mazewalk-grid 1` (the format's version).
//! - Then, before the map, any number of `NAME = VALUE` lines (blank and `;` comment lines allowed):
//!   - `tile = 4` — the side of a tile in maze units (default 4, the original's cell size);
//!   - `fov = 90` — horizontal field of view in degrees (default 90);
//!   - `eye = 0` — eye height, strictly between the floor (-1) and ceiling (+1) (default 0);
//!   - `dir = 90` — heading of an `@` start, degrees counter-clockwise from east (default 0);
//!   - a single character and a colour, `A = #cc8844` or `A = 0.8 0.5 0.3` (RGB in 0..1) — a legend:
//!     `A` tiles are walls of that colour. `# = …` recolours the default walls (grey 0.6).
//! - The map is every line after that; north is up, the first map line's top-left corner is at
//!   x = 0, y = (rows) × tile. Characters:
//!   - `#` or a legend character: a wall tile;
//!   - `.` or space: open floor;
//!   - `>` `^` `<` `v`: the start, facing east, north, west, south; `@`: the start facing `dir`;
//!   - `E`: the exit (open floor).
//!
//!   Short rows are padded with walls; so is everything outside the map.
//! - Each open tile becomes one square cell, numbered row by row from the top-left. A side between
//!   two open tiles is a portal; a side between an open tile and a wall tile (or the outside) is an
//!   opaque wall with the wall tile's colour (the default colour outside the map). Nothing is merged.
//!
//! [`write`] writes any maze that this reader would produce — square tiles on the lattice, whole-tile
//! walls, the viewer at a tile centre — and says why not for any other.

use std::fmt::Write as _;

use glam::{Vec3, vec2, vec3};

use super::load::{Loc, RecordLocs};
use super::{
    CellId, Cells, Edge, EdgeId, Exit, Format, Maze, MazeError, ParseError, ParseErrorKind, VertexId, Viewer,
    WriteError,
};

/// The first word of a grid file.
pub const MAGIC: &str = "mazewalk-grid";
/// The format version this reader reads and the writer writes.
pub const VERSION: u32 = 1;
/// Colour of `#` walls and the outside, unless the legend says otherwise.
pub const DEFAULT_WALL: Vec3 = vec3(0.6, 0.6, 0.6);
/// Tile side when the file does not say.
pub const DEFAULT_TILE: f32 = 4.0;
/// Legend characters the writer hands out, in order.
const LEGEND_POOL: &str = "ABCDFGHIJKLMNOPQRSTUWXYZabcdefghijklmnopqrstuwxyz0123456789%&*+";
/// Characters with a fixed meaning, never legend names.
const RESERVED: &str = " .@<>^vE;=";

/// One tile of a [`TileMap`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Tile {
    /// Floor: one cell.
    Open,
    /// A wall tile of colour `colors[i]`.
    Wall(u16),
}

/// A tile map: the grid format's content, before it becomes a [`Maze`].
#[derive(Clone, Debug, PartialEq)]
pub struct TileMap {
    /// Tiles per row.
    pub width: usize,
    /// Rows.
    pub height: usize,
    /// Tile side, maze units.
    pub tile_size: f32,
    /// Row-major, row 0 at the top (north).
    pub tiles: Vec<Tile>,
    /// Wall colours; `colors[0]` is also the outside's.
    pub colors: Vec<Vec3>,
    /// The start tile (column, row).
    pub start: (usize, usize),
    /// The start heading, degrees.
    pub dir_deg: f32,
    /// Eye height.
    pub eye: f32,
    /// Horizontal field of view, degrees.
    pub fov_deg: f32,
    /// The exit tile (column, row).
    pub exit: Option<(usize, usize)>,
}

impl TileMap {
    fn open(&self, col: usize, row: usize) -> bool {
        self.tiles[row * self.width + col] == Tile::Open
    }

    /// The maze: one square cell per open tile (see the module docs for the numbering).
    pub fn to_maze(&self) -> Result<Maze, MazeError> {
        let (w, h, s) = (self.width, self.height, self.tile_size);
        let mut cell_of = vec![u32::MAX; self.tiles.len()];
        let mut n = 0u32;
        for (t, tile) in self.tiles.iter().enumerate() {
            if *tile == Tile::Open {
                cell_of[t] = n;
                n += 1;
            }
        }
        let mut lattice = vec![u32::MAX; (w + 1) * (h + 1)];
        let mut vertices = Vec::new();
        let mut vertex = |x: usize, y: usize| -> VertexId {
            let slot = &mut lattice[y * (w + 1) + x];
            if *slot == u32::MAX {
                *slot = vertices.len() as u32;
                vertices.push(vec2(x as f32, y as f32) * s);
            }
            *slot
        };
        let mut edges: Vec<Edge> = Vec::new();
        let mut east_edge = vec![u32::MAX; self.tiles.len()];
        let mut south_edge = vec![u32::MAX; self.tiles.len()];
        let mut cells = Cells::with_capacity(n as usize, 4 * n as usize);
        let color = |t: Option<usize>| match t.map(|t| self.tiles[t]) {
            Some(Tile::Wall(i)) => self.colors.get(i as usize).copied().unwrap_or(DEFAULT_WALL),
            _ => self.colors.first().copied().unwrap_or(DEFAULT_WALL),
        };
        let cell = |t: Option<usize>| t.map(|t| cell_of[t]).filter(|&c| c != u32::MAX);
        for r in 0..h {
            for c in 0..w {
                let t = r * w + c;
                let Some(k) = cell(Some(t)) else { continue };
                let y0 = h - 1 - r; // lattice rows count from the south
                let mut add = |start, end, left: Option<CellId>, right: Option<CellId>, nb: Option<usize>| {
                    let opaque = left.is_none() || right.is_none();
                    edges.push(Edge { start, end, left, right, opaque, color: color(nb) });
                    (edges.len() - 1) as EdgeId
                };
                // vertical edges run north with the west cell on the left; horizontal ones run east
                // with the north cell on the left (the original's layout)
                let east = (c + 1 < w).then_some(t + 1);
                let e = add(vertex(c + 1, y0), vertex(c + 1, y0 + 1), Some(k), cell(east), east);
                east_edge[t] = e;
                let north = (r > 0).then(|| t - w);
                let nth = match cell(north) {
                    Some(_) => south_edge[t - w],
                    None => add(vertex(c, y0 + 1), vertex(c + 1, y0 + 1), None, Some(k), north),
                };
                let west = (c > 0).then(|| t - 1);
                let wst = match cell(west) {
                    Some(_) => east_edge[t - 1],
                    None => add(vertex(c, y0), vertex(c, y0 + 1), None, Some(k), west),
                };
                let south = (r + 1 < h).then_some(t + w);
                let sth = add(vertex(c, y0), vertex(c + 1, y0), Some(k), cell(south), south);
                south_edge[t] = sth;
                cells.push(&[e, nth, wst, sth]);
            }
        }
        let (sc, sr) = self.start;
        let pos = vec2(sc as f32 + 0.5, (h as f32 - 1.0 - sr as f32) + 0.5) * s;
        let viewer = Viewer { pos, z: self.eye, dir_deg: self.dir_deg, fov_deg: self.fov_deg };
        if sc >= w || sr >= h || !self.open(sc, sr) {
            return Err(MazeError::ViewerOutside { x: pos.x, y: pos.y });
        }
        let exit = match self.exit {
            Some((ec, er)) if ec < w && er < h && self.open(ec, er) => {
                Some(Exit { cell: cell_of[er * w + ec], point: None })
            }
            Some((ec, er)) => return Err(MazeError::ExitOutside { x: ec as f32, y: er as f32 }),
            None => None,
        };
        Maze::new(vertices, edges, cells, viewer, exit)
    }

    /// The tile map a maze came from, if the grid format can express it.
    pub fn from_maze(maze: &Maze) -> Result<TileMap, String> {
        let b = maze.cell_aabb(0);
        let s = b.max.x - b.min.x;
        let mut tile_of = Vec::with_capacity(maze.cell_count());
        let (mut w, mut h) = (0usize, 0usize);
        for c in 0..maze.cell_count() as CellId {
            let b = maze.cell_aabb(c);
            let (tx, ty) = ((b.min.x / s) as usize, (b.min.y / s) as usize);
            let on_lattice = b.min.x >= 0.0
                && b.min.y >= 0.0
                && tx as f32 * s == b.min.x
                && ty as f32 * s == b.min.y
                && b.max.x == (tx + 1) as f32 * s
                && b.max.y == (ty + 1) as f32 * s;
            let sides_axis_aligned = maze.cell_edges(c).iter().all(|&e| {
                let (p, q) = maze.edge_points(e);
                p.x == q.x || p.y == q.y
            });
            if !(on_lattice && sides_axis_aligned && maze.cell_edges(c).len() == 4) {
                return Err(format!("cell {c} is not a {s}×{s} square tile on the lattice of cell 0"));
            }
            tile_of.push((tx, ty));
            w = w.max(tx + 2); // a wall column east of the last open tile
            h = h.max(ty + 2); // and a wall row north of it
        }
        let row = |ty: usize| h - 1 - ty;
        let mut tiles = vec![Tile::Wall(u16::MAX); w * h];
        for &(tx, ty) in &tile_of {
            tiles[row(ty) * w + tx] = Tile::Open;
        }
        let mut outside: Option<Vec3> = None;
        let mut colors: Vec<Vec3> = vec![DEFAULT_WALL];
        let mut wall_color: Vec<Option<Vec3>> = vec![None; w * h];
        for c in 0..maze.cell_count() as CellId {
            let (tx, ty) = tile_of[c as usize];
            let centre = vec2(tx as f32 + 0.5, ty as f32 + 0.5) * s;
            for &e in maze.cell_edges(c) {
                let edge = maze.edge(e);
                let (p, q) = maze.edge_points(e);
                // the neighbouring tile, one step from this tile's centre toward the edge's middle
                let towards = ((p + q) * 0.5 - centre) / (0.5 * s);
                let (nx, ny) = (tx as isize + towards.x as isize, ty as isize + towards.y as isize);
                match edge.other_side(c) {
                    Some(other) if edge.opaque => {
                        return Err(format!(
                            "edge {e} is a wall between two open tiles (cells {c} and {other}); grid walls are whole tiles"
                        ));
                    }
                    Some(_) => {}
                    None if nx < 0 || ny < 0 => match outside {
                        Some(col) if col != edge.color => {
                            return Err(format!("walls facing the outside have different colours (edge {e})"));
                        }
                        _ => outside = Some(edge.color),
                    },
                    None => {
                        let t = row(ny as usize) * w + nx as usize;
                        match wall_color[t] {
                            Some(col) if col != edge.color => {
                                return Err(format!(
                                    "the wall tile beside cell {c} would need two colours (edge {e} differs)"
                                ));
                            }
                            _ => wall_color[t] = Some(edge.color),
                        }
                    }
                }
            }
        }
        colors[0] = outside.unwrap_or(DEFAULT_WALL);
        for (t, col) in wall_color.iter().enumerate() {
            if tiles[t] == Tile::Open {
                continue;
            }
            let col = col.unwrap_or(colors[0]);
            let i = colors.iter().position(|&k| k == col).unwrap_or_else(|| {
                colors.push(col);
                colors.len() - 1
            });
            if i > LEGEND_POOL.len() {
                return Err(format!("more than {} wall colours", LEGEND_POOL.len() + 1));
            }
            tiles[t] = Tile::Wall(i as u16);
        }
        let v = maze.viewer();
        let g = v.pos / s - 0.5;
        let start = (g.x as usize, g.y as usize);
        if !(g.x >= 0.0 && g.y >= 0.0 && g.x.fract() == 0.0 && g.y.fract() == 0.0 && tile_of.contains(&start)) {
            return Err(format!("the viewer at ({}, {}) is not at the centre of an open tile", v.pos.x, v.pos.y));
        }
        let exit = match maze.exit() {
            None => None,
            Some(Exit { point: Some(_), .. }) => {
                return Err("the exit is a point; the grid format marks only an exit tile".into());
            }
            Some(&Exit { cell, .. }) => Some(tile_of[cell as usize]),
        };
        if exit == Some(start) {
            return Err("the exit is the start tile".into());
        }
        let to_rc = |(tx, ty): (usize, usize)| (tx, row(ty));
        Ok(TileMap {
            width: w,
            height: h,
            tile_size: s,
            tiles,
            colors,
            start: to_rc(start),
            dir_deg: v.dir_deg,
            eye: v.z,
            fov_deg: v.fov_deg,
            exit: exit.map(to_rc),
        })
    }

    /// The tile map as grid text.
    #[must_use]
    pub fn to_text(&self) -> String {
        let mut out = format!("{MAGIC} {VERSION}\n");
        if self.tile_size != DEFAULT_TILE {
            let _ = writeln!(out, "tile = {}", self.tile_size);
        }
        if self.eye != 0.0 {
            let _ = writeln!(out, "eye = {}", self.eye);
        }
        if self.fov_deg != 90.0 {
            let _ = writeln!(out, "fov = {}", self.fov_deg);
        }
        let arrow = ARROWS.iter().find(|a| a.1 == self.dir_deg).map(|a| a.0);
        if arrow.is_none() && self.dir_deg != 0.0 {
            let _ = writeln!(out, "dir = {}", self.dir_deg);
        }
        let legend: Vec<char> = std::iter::once('#').chain(LEGEND_POOL.chars()).collect();
        for (i, c) in self.colors.iter().enumerate() {
            if i > 0 || *c != DEFAULT_WALL {
                let _ = writeln!(out, "{} = {} {} {}", legend[i], c.x, c.y, c.z);
            }
        }
        for r in 0..self.height {
            for c in 0..self.width {
                out.push(match self.tiles[r * self.width + c] {
                    _ if (c, r) == self.start => arrow.unwrap_or('@'),
                    _ if Some((c, r)) == self.exit => 'E',
                    Tile::Open => '.',
                    Tile::Wall(i) => legend.get(i as usize).copied().unwrap_or('#'),
                });
            }
            out.push('\n');
        }
        out
    }
}

/// Start characters and their headings.
const ARROWS: [(char, f32); 4] = [('>', 0.0), ('^', 90.0), ('<', 180.0), ('v', 270.0)];

/// Writes `maze` as grid text, if the grid reader would give back exactly this maze.
pub fn write(maze: &Maze) -> Result<String, WriteError> {
    let err = |reason| WriteError { format: Format::Grid, reason };
    let map = TileMap::from_maze(maze).map_err(err)?;
    if !map.to_maze().is_ok_and(|m| m == *maze) {
        return Err(err("the maze is not numbered the way the grid reader numbers tiles; write it as cs559".into()));
    }
    Ok(map.to_text())
}

/// Parses grid text (already decoded); `file` names it in errors.
pub fn parse_str(file: &str, text: &str) -> Result<Maze, ParseError> {
    let mut lines = text.split('\n').map(|l| l.strip_suffix('\r').unwrap_or(l)).enumerate().peekable();
    let at = |line: usize, col: usize| Loc { line: line as u32 + 1, col: col as u32 + 1 };

    // header
    let Some((hl, header)) = lines.find(|(_, l)| !l.trim().is_empty()) else {
        return fail(file, at(0, 0), "empty file".into());
    };
    let mut words = header.split_whitespace();
    let indent = header.len() - header.trim_start().len();
    if words.next() != Some(MAGIC) {
        return fail(file, at(hl, indent), format!("expected `{MAGIC} {VERSION}`"));
    }
    match words.next() {
        Some(v) if v == VERSION.to_string() => {}
        Some(v) => return fail(file, at(hl, col_of(header, v)), format!("unsupported grid version `{v}` (this reads {VERSION})")),
        None => return fail(file, at(hl, header.chars().count()), format!("expected the version `{VERSION}`")),
    }
    if let Some(extra) = words.next() {
        return fail(file, at(hl, col_of(header, extra)), format!("unexpected `{extra}` after the version"));
    }

    // options and legend
    let mut map = TileMap {
        width: 0,
        height: 0,
        tile_size: DEFAULT_TILE,
        tiles: Vec::new(),
        colors: vec![DEFAULT_WALL],
        start: (0, 0),
        dir_deg: 0.0,
        eye: 0.0,
        fov_deg: 90.0,
        exit: None,
    };
    let mut legend: Vec<(char, u16)> = Vec::new();
    while let Some(&(ln, line)) = lines.peek() {
        let trimmed = line.trim();
        if trimmed.is_empty() || trimmed.starts_with(';') {
            lines.next();
            continue;
        }
        let Some((name, value)) = line.split_once('=') else { break };
        lines.next();
        let (name, vcol) = (name.trim(), col_of(line, value.trim()));
        let ncol = col_of(line, name);
        let number = |lo: f32, hi: f32, what: &str| -> Result<f32, ParseError> {
            match value.trim().parse::<f32>() {
                Ok(x) if x > lo && x < hi => Ok(x),
                _ => fail(file, at(ln, vcol), format!("{what} must be a number in ({lo}, {hi}), found `{}`", value.trim())),
            }
        };
        match name {
            "tile" => map.tile_size = number(0.0, 1.0e4, "tile")?,
            "fov" => map.fov_deg = number(0.0, 180.0, "fov")?,
            "eye" => map.eye = number(-1.0, 1.0, "eye")?,
            "dir" => map.dir_deg = number(-1.0e6, 1.0e6, "dir")?,
            _ if name.chars().count() == 1 => {
                let ch = name.chars().next().unwrap_or('#');
                if RESERVED.contains(ch) {
                    return fail(file, at(ln, ncol), format!("`{ch}` has a fixed meaning and cannot be a legend entry"));
                }
                let Some(color) = parse_color(value.trim()) else {
                    return fail(file, 
                        at(ln, vcol),
                        format!("expected a colour `#rrggbb` or `r g b` in 0..1, found `{}`", value.trim()),
                    );
                };
                if ch == '#' {
                    map.colors[0] = color;
                } else if legend.iter().any(|l| l.0 == ch) {
                    return fail(file, at(ln, ncol), format!("`{ch}` is in the legend twice"));
                } else {
                    legend.push((ch, map.colors.len() as u16));
                    map.colors.push(color);
                }
            }
            _ => return fail(file, at(ln, ncol), format!("unknown option `{name}` (expected tile, fov, eye, dir or a legend character)")),
        }
    }

    // the map
    let rows: Vec<(usize, &str)> = lines.collect();
    let rows = &rows[..rows.iter().rposition(|(_, l)| !l.trim().is_empty()).map_or(0, |i| i + 1)];
    let Some(&(first_line, _)) = rows.first() else {
        return fail(file, at(text.split('\n').count().saturating_sub(1), 0), "expected a map after the header".into());
    };
    map.height = rows.len();
    map.width = rows.iter().map(|(_, l)| l.chars().count()).max().unwrap_or(0);
    if map.width.saturating_mul(map.height) > 16 * text.len() + 1024 {
        return fail(file, at(first_line, 0), format!("the map is {}×{} tiles: too large", map.width, map.height));
    }
    map.tiles = vec![Tile::Wall(0); map.width * map.height];
    let mut start: Option<Loc> = None;
    let mut exit: Option<Loc> = None;
    let mut cell_locs = Vec::new();
    for (r, &(ln, line)) in rows.iter().enumerate() {
        for (c, ch) in line.chars().enumerate() {
            let loc = at(ln, c);
            let tile = match ch {
                '#' => Tile::Wall(0),
                ' ' | '.' | 'E' | '@' | '>' | '^' | '<' | 'v' => Tile::Open,
                '\t' => return fail(file, loc, "a tab in the map: use `.` or spaces for floor".into()),
                _ => match legend.iter().find(|l| l.0 == ch) {
                    Some(&(_, i)) => Tile::Wall(i),
                    None => return fail(file, loc, format!("unknown tile `{}` (not in the legend)", ch.escape_debug())),
                },
            };
            if tile == Tile::Open {
                cell_locs.push(loc);
            }
            map.tiles[r * map.width + c] = tile;
            if ch == 'E' {
                if let Some(first) = exit {
                    return fail(file, loc, format!("a second exit (the first is at {}:{})", first.line, first.col));
                }
                exit = Some(loc);
                map.exit = Some((c, r));
            } else if let Some(dir) = ARROWS.iter().find(|a| a.0 == ch).map(|a| a.1).or((ch == '@').then_some(map.dir_deg)) {
                if let Some(first) = start {
                    return fail(file, loc, format!("a second start (the first is at {}:{})", first.line, first.col));
                }
                start = Some(loc);
                map.start = (c, r);
                map.dir_deg = dir;
            }
        }
    }
    let Some(start) = start else {
        return fail(file, at(first_line, 0), "the map has no start (`@`, `>`, `^`, `<` or `v`)".into());
    };
    let locs = RecordLocs { start: at(hl, 0), cells: cell_locs, viewer: start, exit, ..RecordLocs::default() };
    map.to_maze().map_err(|e| locs.locate(file, e))
}

fn fail<T>(file: &str, loc: Loc, msg: String) -> Result<T, ParseError> {
    Err(loc.error(file, ParseErrorKind::Grid(msg)))
}

/// The 0-based character column where `part` (a sub-slice of `line`) starts.
fn col_of(line: &str, part: &str) -> usize {
    let offset = (part.as_ptr() as usize).saturating_sub(line.as_ptr() as usize).min(line.len());
    line[..offset].chars().count()
}

/// `#rrggbb` or three numbers in 0..1.
fn parse_color(s: &str) -> Option<Vec3> {
    if let Some(hex) = s.strip_prefix('#') {
        if hex.len() != 6 || !hex.is_ascii() {
            return None;
        }
        let channel = |i: usize| u8::from_str_radix(&hex[i..i + 2], 16).ok().map(|v| f32::from(v) / 255.0);
        return Some(vec3(channel(0)?, channel(2)?, channel(4)?));
    }
    let v: Vec<f32> = s.split_whitespace().map(str::parse).collect::<Result<_, _>>().ok()?;
    (v.len() == 3 && v.iter().all(|x| (0.0..=1.0).contains(x))).then(|| vec3(v[0], v[1], v[2]))
}
