//! The grid format: a maze drawn in a text editor, one character per square tile.
//!
//! ```text
//! mazewalk-grid 1
//! tile 4
//! facing north
//! A = #cc8844
//!
//! ##########
//! #@..#...E#
//! #.#.A.##.#
//! #........#
//! ##########
//! ```
//!
//! * Line 1 is `mazewalk-grid 1` (the format and its version).
//! * Settings follow, one per line, each optional: `tile SIDE` (tile side in maze units,
//!   at least [`MIN_TILE`] = 0.5002 and at most 1000, default 4),
//!   `facing east|north|west|south` (the `@` start's heading, default east), `eye Z` (eye height,
//!   default 0, strictly between the floor -1 and the ceiling +1), `fov DEG` (horizontal field of
//!   view, default 90), `vfov DEG` (the least vertical field of view the walk keeps, widening the
//!   horizontal one on a wide screen, 0..=150, default 0 = none: [`Maze::min_vfov_deg`]; `mazewalk
//!   gen` writes its generated mazes' own), and colour legend lines `L = #rrggbb` (the spaces optional) giving wall letter `L` (`A`–`Z`
//!   but `E`) a colour; `# = #rrggbb` recolours `#` (default `#808080`). Empty lines are skipped.
//! * The map starts at the first other line (a line of spaces is a map row: space is floor) and runs
//!   to the end of the file, without trailing empty lines. Every character is a
//!   tile; the top line is north (+y), the map's lower-left corner is the origin.
//!   - `#` or a legend letter: a solid wall tile of that colour;
//!   - space or `.`: open floor;
//!   - `@`: the start, facing as `facing` says; or an arrow `>` `^` `<` `v` (east, north, west, south)
//!     instead of `@`; exactly one start, at its tile's centre;
//!   - `E`: the exit (open floor; at most one). A map with an `E` and no start tile starts on the
//!     `E`, facing as `facing` says: so a one-tile maze, whose only cell is start and exit, is written.
//!
//!   Rows may differ in length: past a row's end there is nothing (outside).
//! * Each open tile is one square cell (numbered row by row from the bottom, west to east). The side
//!   between two open tiles is a portal; between an open tile and a wall tile an opaque wall of the
//!   wall tile's colour; between an open tile and the outside an opaque wall coloured as `#`.
//!
//! [`write()`] expresses a maze in this format when it is made of such tiles (e.g. one read from a grid
//! file or made by [`generate_grid`](super::generate::generate_grid)); otherwise it says why not.

use std::fmt::Write as _;

use glam::{Vec2, Vec3, vec2};

use super::geometry::WALL_MARGIN;
use super::movement;
use super::text::{Loc, is_space, quote};
use super::{
    CellId, Cells, EdgeId, Edges, Exit, Format, Maze, PackedEdge, ParseError, ParseErrorKind, Viewer,
    WriteError,
};

/// The first word of a grid file.
pub(crate) const MAGIC: &str = "mazewalk-grid";
/// The format version this reader and writer speak.
pub(crate) const VERSION: u32 = 1;
/// The colour of `#` walls and of the outside unless the legend says otherwise (`#808080`).
pub const DEFAULT_WALL: Vec3 = Vec3::splat(128.0 / 255.0);
/// A tile's side must be at least this: the viewer's disc ([`WALL_MARGIN`] round it) across and the
/// walk's slack of 0.0001 ([`movement::SKIN`]) on each side. Placed in a corridor one tile wide,
/// [`movement::settle`] may leave the viewer `WALL_MARGIN + 2·SKIN` from one wall; with this much the
/// other is still `WALL_MARGIN` away, so it stands clear and walks down the corridor past the tiles'
/// corners. A tile of 0.50009 left it no room to stand, and 0.5001 room to stand but not to walk.
pub const MIN_TILE: f32 = (2.0 * (WALL_MARGIN as f64 + movement::SKIN)) as f32;

/// Most tiles in a map (2048 × 2048), so a 1000 × 1000 generated maze fits.
pub(crate) const MAX_TILES: usize = 2048 * 2048;

/// A parsed grid map: settings plus the tile characters, before it becomes a [`Maze`].
#[derive(Clone, Debug, PartialEq)]
pub struct TileMap {
    /// Tile side, maze units.
    pub tile: f32,
    /// Eye height.
    pub eye: f32,
    /// Horizontal field of view, degrees.
    pub fov_deg: f32,
    /// The least vertical field of view, degrees (0 = none): [`Maze::min_vfov_deg`].
    pub min_vfov_deg: f32,
    /// The `facing` setting, degrees counter-clockwise from +x (`None` = east).
    pub facing_deg: Option<f32>,
    /// Wall letters and their colours.
    pub legend: Vec<(u8, Vec3)>,
    /// Tiles across.
    pub cols: usize,
    /// Tiles down.
    pub rows: usize,
    /// Tile characters, top row first; `0` = outside (past the end of a short row).
    pub tiles: Vec<u8>,
}

impl TileMap {
    /// The letters a legend may define, in the order the writer hands them out.
    pub(crate) const LEGEND_LETTERS: &'static [u8] = b"ABCDFGHIJKLMNOPQRSTUVWXYZ";

    /// The tile at column `x`, `y` rows up from the bottom; `0` outside the map.
    fn at(&self, x: i64, y: i64) -> u8 {
        if x < 0 || y < 0 || x >= self.cols as i64 || y >= self.rows as i64 {
            return 0;
        }
        self.tiles[(self.rows - 1 - y as usize) * self.cols + x as usize]
    }

    fn color(&self, ch: u8) -> Vec3 {
        let ch = if ch == 0 { b'#' } else { ch };
        self.legend.iter().find(|(l, _)| *l == ch).map_or(DEFAULT_WALL, |&(_, c)| c)
    }

    /// Whether the walk starts on the exit: the map has an `E` and no start tile.
    fn starts_on_exit(&self) -> bool {
        !self.tiles.iter().any(|&t| start_dir(t, None, false).is_some()) && self.tiles.contains(&b'E')
    }

    /// The map as grid-format text.
    #[must_use]
    pub fn to_text(&self) -> String {
        let mut out = String::with_capacity((self.cols + 1) * self.rows + 128);
        let _ = writeln!(out, "{MAGIC} {VERSION}\ntile {}", self.tile);
        if let Some(f) = self.facing_deg {
            let _ = writeln!(out, "facing {}", facing_name(f).unwrap_or("east"));
        }
        if self.eye != 0.0 {
            let _ = writeln!(out, "eye {}", self.eye);
        }
        if self.fov_deg != 90.0 {
            let _ = writeln!(out, "fov {}", self.fov_deg);
        }
        if self.min_vfov_deg > 0.0 {
            let _ = writeln!(out, "vfov {}", self.min_vfov_deg);
        }
        for &(ch, c) in &self.legend {
            let [r, g, b] = (c * 255.0).round().to_array().map(|v| v as u8);
            let _ = writeln!(out, "{} = #{r:02x}{g:02x}{b:02x}", ch as char);
        }
        out.push('\n');
        for row in self.tiles.chunks(self.cols) {
            let line: String = row.iter().map(|&t| if t == 0 { ' ' } else { t as char }).collect();
            out.push_str(line.trim_end());
            out.push('\n');
        }
        out
    }

    /// Builds the maze the map describes.
    ///
    /// # Errors
    /// A [`MazeError`](super::MazeError) when the map breaks the model's rules (no start tile, a
    /// coordinate beyond the bound); [`parse_str`] has ruled these out with located messages.
    pub fn to_maze(&self) -> Result<Maze, super::MazeError> {
        self.build(false)
    }

    /// [`TileMap::build_in_bands`], with the map's least vertical field of view.
    fn build(&self, checked_map: bool) -> Result<Maze, super::MazeError> {
        Ok(self.build_tiles(checked_map)?.with_min_vfov_deg(self.min_vfov_deg))
    }

    /// [`TileMap::to_maze`]; `checked_map` when [`parse_map`] made this map, so that the tiles, the
    /// start and the coordinate bound are known good and the maze is valid by construction.
    fn build_tiles(&self, checked_map: bool) -> Result<Maze, super::MazeError> {
        let bands = if self.tiles.len() >= PARALLEL_TILES { 2 } else { 1 };
        self.build_in_bands(checked_map, bands)
    }

    /// [`TileMap::build`], the map cut into `bands` runs of tile rows built at once on threads of
    /// their own: the result does not depend on `bands`.
    fn build_in_bands(&self, checked_map: bool, bands: usize) -> Result<Maze, super::MazeError> {
        // Numbering (kept from the first, table-driven version of this function, which the tests
        // keep as the oracle): cells are open tiles row by row from the bottom, west to east; edges
        // are the horizontal sides lattice row by row, then the vertical ones tile row by row;
        // vertices are lattice points in the order the horizontal sides first use them, i.e. row by
        // row, west to east (every point beside an open tile touches a horizontal side). So each id
        // is a row's base plus a rank within the row: a band needs only the bases at its first row,
        // which a count of the bands before it gives, and a row or two of ids at a time (not a table
        // per tile: 4 tables of 16 MB for a 1000 × 1000 maze's 2001 × 2001 tiles).
        let sweep = Sweep::new(self);
        let rows = self.rows;
        let bands = bands.clamp(1, rows.max(1));
        let bands: Vec<Band> = (0..bands)
            .map(|k| Band { rows: rows * k / bands..rows * (k + 1) / bands, top: k + 1 == bands })
            .collect();
        let counts = all_at_once(
            bands
                .iter()
                .map(|band| {
                    let sweep = &sweep;
                    move || sweep.count(band)
                })
                .collect(),
        );
        let total = counts.iter().fold(Counts::default(), |sum, c| sum.plus(c));
        // zeroed, so no page is touched before the band that owns it writes it
        let mut packed = bytemuck::zeroed_vec::<PackedEdge>(total.h + total.v);
        let mut vertices = bytemuck::zeroed_vec::<Vec2>(total.points);
        let mut slots = vec![0 as EdgeId; 4 * total.cells];
        // each band's runs, in band order: its horizontal edges among all the horizontal ones, its
        // vertical edges after those, its vertices, its cells' slots
        let (mut h_rest, mut v_rest) = packed.split_at_mut(total.h);
        let (mut vertex_rest, mut slot_rest) = (vertices.as_mut_slice(), slots.as_mut_slice());
        let mut parts = Vec::with_capacity(bands.len());
        let mut base = Counts { h: 0, v: total.h, ..Counts::default() };
        for count in &counts {
            let out = Out {
                h: take_front(&mut h_rest, count.h),
                v: take_front(&mut v_rest, count.v),
                vertices: take_front(&mut vertex_rest, count.points),
                slots: take_front(&mut slot_rest, 4 * count.cells),
            };
            parts.push((base, out));
            base = base.plus(count);
        }
        let found = all_at_once(
            bands
                .iter()
                .zip(parts)
                .map(|(band, (base, out))| {
                    let sweep = &sweep;
                    move || sweep.fill(band, &base, out)
                })
                .collect(),
        );
        let viewer = found.iter().find_map(|f| f.0);
        let exit = found.iter().find_map(|f| f.1);
        drop(sweep); // before the model builds its index
        let edges = Edges::walls_where_outside(packed);
        let cells = Cells::uniform(slots, 4);
        // no start tile: a viewer outside every cell, which Maze::new reports
        let t = self.tile;
        let viewer =
            viewer.unwrap_or(Viewer { pos: vec2(-1.0, -1.0) * t, z: 0.0, dir_deg: 0.0, fov_deg: 90.0 });
        if checked_map {
            Maze::new_valid_by_construction(vertices, edges, cells, viewer, exit)
        } else {
            Maze::new(vertices, edges, cells, viewer, exit)
        }
    }
}

/// Maps from which [`TileMap::build`] takes a second thread (a quarter of a million tiles
/// take tens of ms; a thread costs tens of µs).
const PARALLEL_TILES: usize = 1 << 18;

/// A run of tile rows of a map, built as a piece: the cells of those rows, the vertical sides
/// beside them, the horizontal sides and lattice points along their lower lattice lines, and for
/// the `top` band the map's top line too.
struct Band {
    rows: std::ops::Range<usize>,
    top: bool,
}

impl Band {
    /// The lattice lines whose sides and points are this band's.
    fn lines(&self) -> std::ops::Range<usize> {
        self.rows.start..self.rows.end + usize::from(self.top)
    }
}

/// How many of each thing a band makes; summed over the bands before one, its first ids.
#[derive(Clone, Copy, Debug, Default)]
struct Counts {
    cells: usize,
    points: usize,
    /// Horizontal sides.
    h: usize,
    /// Vertical sides.
    v: usize,
}

impl Counts {
    fn plus(self, o: &Counts) -> Counts {
        Counts {
            cells: self.cells + o.cells,
            points: self.points + o.points,
            h: self.h + o.h,
            v: self.v + o.v,
        }
    }
}

/// Where a band writes: its runs of the horizontal and vertical edges, vertices and cell slots.
struct Out<'a> {
    h: &'a mut [PackedEdge],
    v: &'a mut [PackedEdge],
    vertices: &'a mut [Vec2],
    slots: &'a mut [EdgeId],
}

/// "No id here" in a row of ids.
const NONE: u32 = u32::MAX;

/// What the bands share: the open tiles with a border of outside (a look-up without range checks)
/// and the wall colours by tile character.
struct Sweep<'m> {
    map: &'m TileMap,
    /// Row `y + 1` (`y` = -1..=rows), column `x + 1` (`x` = -1..=cols): tile (x, y) is open.
    open_at: Vec<bool>,
    pad: usize,
    palette: [Vec3; 256],
    /// The `E` tile is the start too ([`TileMap::starts_on_exit`]).
    start_on_exit: bool,
}

impl<'m> Sweep<'m> {
    fn new(map: &'m TileMap) -> Sweep<'m> {
        let pad = map.cols + 2;
        let mut open_at = vec![false; pad * (map.rows + 2)];
        for (r, row) in map.tiles.chunks_exact(map.cols.max(1)).enumerate() {
            let at = (map.rows - r) * pad + 1; // tile row y = rows - 1 - r, padded row y + 1
            for (slot, &ch) in open_at[at..at + row.len()].iter_mut().zip(row) {
                *slot = is_open(ch);
            }
        }
        let mut palette = [DEFAULT_WALL; 256];
        for (ch, c) in palette.iter_mut().enumerate() {
            *c = map.color(ch as u8);
        }
        Sweep { map, open_at, pad, palette, start_on_exit: map.starts_on_exit() }
    }

    /// Tile row `y` (-1..=rows), padded: entry `x + 1` says whether tile (x, y) is open.
    fn open_row(&self, y: isize) -> &[bool] {
        &self.open_at[(y + 1) as usize * self.pad..][..self.pad]
    }

    /// The open tiles of row `y` (`cols` entries).
    fn cells_in(&self, y: isize) -> impl Iterator<Item = bool> + '_ {
        self.open_row(y)[1..self.pad - 1].iter().copied()
    }

    /// Along lattice line `y`, under tile x: is there a horizontal side (a cell above or below)?
    fn h_sides_in(&self, y: isize) -> impl Iterator<Item = bool> + '_ {
        let (above, below) = (self.open_row(y), self.open_row(y - 1));
        (1..self.pad - 1).map(move |x| above[x] | below[x])
    }

    /// Lattice points of line `y` (`cols + 1`): is there a cell in any of the four tiles around?
    fn points_in(&self, y: isize) -> impl Iterator<Item = bool> + '_ {
        let (above, below) = (self.open_row(y), self.open_row(y - 1));
        (0..self.pad - 1).map(move |x| above[x] | above[x + 1] | below[x] | below[x + 1])
    }

    /// Vertical sides of tile row `y` (`cols + 1`): a cell to the west or east?
    fn v_sides_in(&self, y: isize) -> impl Iterator<Item = bool> + '_ {
        self.open_row(y).windows(2).map(|w| w[0] | w[1])
    }

    fn count(&self, band: &Band) -> Counts {
        let n = |it: &mut dyn Iterator<Item = bool>| it.filter(|&b| b).count();
        let mut c = Counts::default();
        for y in band.rows.clone() {
            c.cells += n(&mut self.cells_in(y as isize));
            c.v += n(&mut self.v_sides_in(y as isize));
        }
        for y in band.lines() {
            c.points += n(&mut self.points_in(y as isize));
            c.h += n(&mut self.h_sides_in(y as isize));
        }
        c
    }

    /// An opaque side's colour is its wall tile's (`0`, outside, is coloured as `#`); a portal's
    /// is the default.
    fn side_color(&self, opaque: bool, wall: u8) -> Vec3 {
        if opaque { self.palette[wall as usize] } else { DEFAULT_WALL }
    }

    /// Builds `band` into `out`, its ids starting from `base`; returns the first start and exit
    /// tiles in it (row by row from the bottom, west to east).
    fn fill(&self, band: &Band, base: &Counts, out: Out) -> (Option<Viewer>, Option<Exit>) {
        let map = self.map;
        let (cols, t) = (map.cols, map.tile);
        let Out { h: h_out, v: v_out, vertices, slots } = out;
        let (y0, y1) = (band.rows.start as isize, band.rows.end as isize);
        let some = |id: u32| (id != NONE).then_some(id);
        // ids in a row from `base`, `NONE` where there is nothing; returns the next row's base
        let rank = |row: &mut Vec<u32>, base: usize, exists: &mut dyn Iterator<Item = bool>| {
            row.clear();
            let mut next = base as u32;
            row.extend(exists.map(|e| {
                let id = if e { next } else { NONE };
                next += u32::from(e);
                id
            }));
            next as usize
        };
        let mut place_points = |ids: &[u32], y: isize| {
            for (x, &id) in ids.iter().enumerate().filter(|(_, id)| **id != NONE) {
                vertices[id as usize - base.points] = vec2(x as f32, y as f32) * t;
            }
        };
        // the cells below the band, numbered back from its first cell
        let mut below = Vec::new();
        let below_base = base.cells - self.cells_in(y0 - 1).filter(|&o| o).count();
        rank(&mut below, below_base, &mut self.cells_in(y0 - 1));
        let (mut h_here, mut p_here) = (Vec::new(), Vec::new());
        let mut next_h = rank(&mut h_here, base.h, &mut self.h_sides_in(y0));
        let mut next_point = rank(&mut p_here, base.points, &mut self.points_in(y0));
        place_points(&p_here, y0);
        let mut next_cell = base.cells;
        let (mut here, mut h_up, mut p_up, mut v_ids) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        let (mut n_h, mut n_v) = (0, 0);
        let (mut viewer, mut exit) = (None, None);
        // the horizontal sides along lattice line y, between the cells `above` and `below`
        let mut h_sides = |y: isize, ids: &[u32], points: &[u32], above: &[u32], below: &[u32]| {
            for x in 0..cols {
                if ids[x] == NONE {
                    continue;
                }
                let (left, right) = (some(above[x]), some(below[x]));
                let opaque = left.is_none() || right.is_none();
                let wall =
                    if left.is_none() { map.at(x as i64, y as i64) } else { map.at(x as i64, y as i64 - 1) };
                let color = self.side_color(opaque, wall);
                h_out[n_h] = PackedEdge::new(points[x], points[x + 1], left, right, color);
                n_h += 1;
            }
        };
        for y in y0..y1 {
            next_cell = rank(&mut here, next_cell, &mut self.cells_in(y));
            h_sides(y, &h_here, &p_here, &here, &below);
            // the line above: its points are the next band's unless this is the top band's last row
            next_point = rank(&mut p_up, next_point, &mut self.points_in(y + 1));
            if y + 1 < y1 || band.top {
                place_points(&p_up, y + 1);
            }
            next_h = rank(&mut h_up, next_h, &mut self.h_sides_in(y + 1));
            // vertical sides: lattice column x runs north along tile row y, the tile to the west
            // on its left
            v_ids.clear();
            for x in 0..=cols {
                let left = if x > 0 { some(here[x - 1]) } else { None };
                let right = if x < cols { some(here[x]) } else { None };
                if left.is_none() && right.is_none() {
                    v_ids.push(NONE);
                    continue;
                }
                v_ids.push((base.v + n_v) as u32);
                let opaque = left.is_none() || right.is_none();
                let (xi, yi) = (x as i64, y as i64);
                let wall = if left.is_none() { map.at(xi - 1, yi) } else { map.at(xi, yi) };
                v_out[n_v] = PackedEdge::new(p_here[x], p_up[x], left, right, self.side_color(opaque, wall));
                n_v += 1;
            }
            // each cell's 4 slots, in the original's order +x, +y, -x, -y
            for x in 0..cols {
                let Some(c) = some(here[x]) else { continue };
                let at = 4 * (c as usize - base.cells);
                slots[at..at + 4].copy_from_slice(&[v_ids[x + 1], h_up[x], v_ids[x], h_here[x]]);
                let ch = map.at(x as i64, y as i64);
                if ch == b'E' && exit.is_none() {
                    exit = Some(Exit { cell: c, point: None });
                }
                if let Some(dir) = start_dir(ch, map.facing_deg, self.start_on_exit)
                    && viewer.is_none()
                {
                    let pos = (vec2(x as f32, y as f32) + 0.5) * t;
                    viewer = Some(Viewer { pos, z: map.eye, dir_deg: dir, fov_deg: map.fov_deg });
                }
            }
            std::mem::swap(&mut below, &mut here);
            std::mem::swap(&mut h_here, &mut h_up);
            std::mem::swap(&mut p_here, &mut p_up);
        }
        if band.top {
            // the map's top line: nothing above it
            let nothing = vec![NONE; cols];
            h_sides(y1, &h_here, &p_here, &nothing, &below);
        }
        debug_assert_eq!((n_h, n_v), (h_out.len(), v_out.len()), "a band makes what it counted");
        (viewer, exit)
    }
}

/// The first `n` items of `rest`, which keeps the others.
fn take_front<'a, T>(rest: &mut &'a mut [T], n: usize) -> &'a mut [T] {
    let (front, back) = std::mem::take(rest).split_at_mut(n);
    *rest = back;
    front
}

/// Runs `jobs` at once, the first on this thread and each other on a thread of its own; their
/// results in order.
fn all_at_once<'a, T: Send + 'a>(jobs: Vec<impl FnOnce() -> T + Send + 'a>) -> Vec<T> {
    let mut jobs = jobs.into_iter();
    let Some(first) = jobs.next() else { return Vec::new() };
    std::thread::scope(|s| {
        let others: Vec<_> = jobs.map(|job| s.spawn(job)).collect();
        let mut results = vec![first()];
        for other in others {
            results.push(other.join().unwrap_or_else(|panic| std::panic::resume_unwind(panic)));
        }
        results
    })
}

fn is_open(ch: u8) -> bool {
    matches!(ch, b' ' | b'.' | b'@' | b'>' | b'^' | b'<' | b'v' | b'E')
}

fn is_wall(ch: u8) -> bool {
    ch == b'#' || TileMap::LEGEND_LETTERS.contains(&ch)
}

/// The heading of a start tile, or `None` for any other tile; `E` is one when `on_exit`.
fn start_dir(ch: u8, facing: Option<f32>, on_exit: bool) -> Option<f32> {
    match ch {
        b'@' => Some(facing.unwrap_or(0.0)),
        b'E' if on_exit => Some(facing.unwrap_or(0.0)),
        b'>' => Some(0.0),
        b'^' => Some(90.0),
        b'<' => Some(180.0),
        b'v' => Some(270.0),
        _ => None,
    }
}

fn facing_name(deg: f32) -> Option<&'static str> {
    ["east", "north", "west", "south"]
        .into_iter()
        .zip([0.0, 90.0, 180.0, 270.0])
        .find(|&(_, d)| d == deg)
        .map(|(n, _)| n)
}

/// Parses grid text (already decoded); `file` names it in errors.
pub fn parse_str(file: &str, text: &str) -> Result<Maze, ParseError> {
    let (map, places) = parse_placed(file, text)?;
    map.build(true).map_err(|e| {
        use super::MazeError::*;
        // the error's place: the start tile for the viewer's, the `tile` line when the viewer has no
        // room (tiles too small), else the header (the map as a whole)
        let (line, col) = match e {
            ViewerNoRoom { .. } => places.tile.unwrap_or(places.start),
            ViewerNotFinite | ViewerOutside { .. } | ViewerOnWall { .. } => places.start,
            _ => (0, 0),
        };
        let sat = |n: usize| u32::try_from(n + 1).unwrap_or(u32::MAX);
        Loc { line: sat(line), col: sat(col) }.error(file, ParseErrorKind::Invalid(e))
    })
}

/// Parses grid text into its tile map, checking every setting and tile.
pub fn parse_map(file: &str, text: &str) -> Result<TileMap, ParseError> {
    parse_placed(file, text).map(|(map, _)| map)
}

/// Where [`parse_placed`] found the things a built maze's errors are about: line and column from 0.
struct Places {
    /// The start tile (the `E` when the walk starts on the exit).
    start: (usize, usize),
    /// The `tile` setting's value, if the file sets it.
    tile: Option<(usize, usize)>,
}

/// [`parse_map`], and where the start tile and the `tile` setting are.
fn parse_placed(file: &str, text: &str) -> Result<(TileMap, Places), ParseError> {
    let sat = |n: usize| u32::try_from(n).unwrap_or(u32::MAX);
    // line and column from 0, as `lines` and `chars` count them
    let loc = |line: usize, col: usize| Loc { line: sat(line + 1), col: sat(col + 1) };
    let err = |line: usize, col: usize, msg: String| loc(line, col).error(file, ParseErrorKind::Grid(msg));
    // lines one at a time: a file of ten million newlines costs no memory per line
    let mut lines = text.split('\n').map(|l| l.strip_suffix('\r').unwrap_or(l)).enumerate().peekable();
    // line 1: magic and version
    let first = lines.next().map_or("", |l| l.1);
    if let Some(at) = first.find('\r') {
        let col = first[..at].chars().count();
        return Err(loc(0, col).error(file, ParseErrorKind::LoneCarriageReturn));
    }
    let mut words = first.split(is_space).filter(|w| !w.is_empty());
    if words.next() != Some(MAGIC) {
        let blank =
            if first.trim().is_empty() { " (the very first: nothing may come before it)" } else { "" };
        return Err(err(0, 0, format!("expected `{MAGIC} {VERSION}` on the first line{blank}")));
    }
    match words.next() {
        Some(v) if v == VERSION.to_string() => {}
        Some(v) => {
            let col = first.find(v).map_or(0, |b| first[..b].chars().count());
            return Err(err(
                0,
                col,
                format!("unsupported grid version `{}` (this reader knows {VERSION})", quote(v)),
            ));
        }
        None => return Err(err(0, first.chars().count(), format!("expected the version after `{MAGIC}`"))),
    }
    let mut map = TileMap {
        tile: 4.0,
        eye: 0.0,
        fov_deg: 90.0,
        min_vfov_deg: 0.0,
        facing_deg: None,
        legend: Vec::new(),
        cols: 0,
        rows: 0,
        tiles: Vec::new(),
    };
    // settings, until the first line that is none; empty lines are skipped, but a line with a space
    // in it is a map row (space is floor)
    let mut last = 0;
    // each setting's name (a legend's letter) and the line that gave it: a second is refused
    let mut seen: Vec<(&str, usize)> = Vec::new();
    let mut tile_at = None;
    while let Some(&(n, line)) = lines.peek() {
        last = n;
        // four words tell a setting; a longer line is a map row or an error
        let words: Vec<&str> = line.split(is_space).filter(|w| !w.is_empty()).take(4).collect();
        let col_of = |w: &str| line[..w.as_ptr() as usize - line.as_ptr() as usize].chars().count();
        let number = |w: &str, what: &str| -> Result<f32, ParseError> {
            match w.parse::<f32>() {
                Ok(v) if v.is_finite() => Ok(v),
                // too large for an f32 (1e308): past every setting's range, which the caller then says
                _ if w.parse::<f64>().is_ok_and(f64::is_finite) => {
                    Ok(f32::MAX.copysign(w.parse().unwrap_or(1.0)))
                }
                _ => Err(err(n, col_of(w), format!("expected a number ({what}), found `{}`", quote(w)))),
            }
        };
        let legend = legend_words(&words);
        let setting = match words.as_slice() {
            [name @ ("tile" | "eye" | "fov" | "vfov" | "facing"), ..] => Some(*name),
            _ => legend.map(|(letter, _)| letter),
        };
        if let Some(name) = setting {
            if let Some(&(_, first)) = seen.iter().find(|(s, _)| *s == name) {
                let what = if words.get(1) == Some(&"=") {
                    format!("legend line for `{}`", quote(name))
                } else {
                    format!("`{name}` setting")
                };
                let kind = ParseErrorKind::Duplicate { what, first_line: sat(first + 1) };
                return Err(loc(n, col_of(words[0])).error(file, kind));
            }
            seen.push((name, n));
        }
        match words.as_slice() {
            [] if line.is_empty() || !line.contains(' ') => {}
            ["tile", v] => {
                map.tile = number(v, "tile side")?;
                tile_at = Some((n, col_of(v)));
                if !(map.tile >= MIN_TILE && map.tile <= 1000.0) {
                    let why = "the viewer, a disc 0.5 across, must fit between walls a tile apart";
                    let msg = format!(
                        "tile side {} is out of range: at least {MIN_TILE} ({why}), at most 1000",
                        quote(v)
                    );
                    return Err(err(n, col_of(v), msg));
                }
            }
            ["eye", v] => {
                map.eye = number(v, "eye height")?;
                if !(map.eye > -1.0 && map.eye < 1.0) {
                    let msg = format!("eye height {} is not strictly between -1 and 1", quote(v));
                    return Err(err(n, col_of(v), msg));
                }
            }
            ["fov", v] => {
                map.fov_deg = number(v, "field of view")?;
                if !(map.fov_deg > 0.0 && map.fov_deg < 180.0) {
                    let msg = format!("field of view {} is not strictly between 0 and 180", quote(v));
                    return Err(err(n, col_of(v), msg));
                }
            }
            ["vfov", v] => {
                map.min_vfov_deg = number(v, "least vertical field of view")?;
                if !(0.0..=150.0).contains(&map.min_vfov_deg) {
                    let msg = format!("least vertical field of view {} is not within 0..=150", quote(v));
                    return Err(err(n, col_of(v), msg));
                }
            }
            ["facing", v] => {
                let dir = ["east", "north", "west", "south"].iter().position(|d| d == v);
                let Some(d) = dir else {
                    let msg = format!("facing `{}`: expected east, north, west or south", quote(v));
                    return Err(err(n, col_of(v), msg));
                };
                map.facing_deg = Some(d as f32 * 90.0);
            }
            _ if let Some((letter, value)) = legend => {
                let ch = letter.as_bytes()[0];
                if !is_wall(ch) {
                    let msg = format!("legend letter `{}`: use A-Z (not E) or #", quote(letter));
                    return Err(err(n, col_of(letter), msg));
                }
                let hex = value
                    .strip_prefix('#')
                    .filter(|h| h.len() == 6 && h.bytes().all(|b| b.is_ascii_hexdigit()));
                let Some(hex) = hex else {
                    let msg = format!("colour `{}`: expected #rrggbb", quote(value));
                    return Err(err(n, col_of(value), msg));
                };
                let channel = |k: usize| u8::from_str_radix(&hex[k..k + 2], 16).unwrap_or(0) as f32 / 255.0;
                map.legend.push((ch, Vec3::new(channel(0), channel(2), channel(4))));
            }
            [name @ ("tile" | "eye" | "fov" | "vfov"), ..] => {
                let what = match *name {
                    "tile" => "the tile side, e.g. `tile 4`",
                    "eye" => "the eye height, e.g. `eye 0.2`",
                    "vfov" => "the least vertical field of view in degrees, e.g. `vfov 96`",
                    _ => "the field of view in degrees, e.g. `fov 90`",
                };
                let msg = format!("`{name}` takes one number: {what}");
                return Err(err(n, col_of(words[0]), msg));
            }
            ["facing", ..] => {
                let msg = "`facing` takes one word: east, north, west or south".to_string();
                return Err(err(n, col_of(words[0]), msg));
            }
            [word, ..] if word.bytes().all(|b| b.is_ascii_lowercase()) && *word != "v" => {
                return Err(err(n, col_of(word), format!("unknown setting `{}`", quote(word))));
            }
            _ => break,
        }
        lines.next();
    }
    // the map: to the end, without trailing empty lines (counted, not stored, until a row follows)
    let top = lines.peek().map_or(last, |l| l.0);
    let mut rows: Vec<&str> = Vec::new();
    let mut empty = 0usize;
    for (n, line) in lines {
        if line.is_empty() {
            empty += 1;
            continue;
        }
        if rows.len() + empty >= MAX_TILES {
            return Err(err(n, 0, format!("the map has more than {MAX_TILES} rows")));
        }
        rows.extend(std::iter::repeat_n("", empty));
        empty = 0;
        rows.push(line);
    }
    let n = top;
    if rows.is_empty() {
        return Err(err(n, 0, "expected the map after the settings".into()));
    }
    let cols = rows.iter().map(|r| r.chars().count()).max().unwrap_or(0);
    if cols.saturating_mul(rows.len()) > MAX_TILES {
        return Err(err(n, 0, format!("the map is {cols}×{} tiles; at most {MAX_TILES} tiles", rows.len())));
    }
    if map.tile * cols.max(rows.len()) as f32 > super::COORD_BOUND {
        return Err(err(
            n,
            0,
            format!("tile side × map size exceeds the coordinate bound {}", super::COORD_BOUND),
        ));
    }
    let (mut start, mut exit) = (None, None);
    map.tiles = vec![0; cols * rows.len()];
    for (r, row) in rows.iter().enumerate() {
        for (c, ch) in row.chars().enumerate() {
            let b = if ch.is_ascii() { ch as u8 } else { 0 };
            if ch == '\r' {
                return Err(loc(n + r, c).error(file, ParseErrorKind::LoneCarriageReturn));
            }
            if !(is_open(b) || is_wall(b)) {
                let hint = if ch == '\t' { " (a tab: use spaces or `.` for floor)" } else { "" };
                return Err(err(n + r, c, format!("unknown tile `{}`{hint}", quote(&ch.to_string()))));
            }
            if b != b'#' && is_wall(b) && !map.legend.iter().any(|(l, _)| *l == b) {
                return Err(err(
                    n + r,
                    c,
                    format!("wall letter `{ch}` has no colour in the legend (`{ch} = #rrggbb`)"),
                ));
            }
            if start_dir(b, None, false).is_some() && start.replace((r, c)).is_some() {
                return Err(err(n + r, c, "a second start tile (only one of @ > ^ < v)".into()));
            }
            if b == b'E' && exit.replace((r, c)).is_some() {
                return Err(err(n + r, c, "a second exit tile `E`".into()));
            }
            map.tiles[r * cols + c] = b;
        }
    }
    let Some((r, c)) = start.or(exit) else {
        return Err(err(n, 0, "the map has no start tile (@ or an arrow > ^ < v)".into()));
    };
    map.cols = cols;
    map.rows = rows.len();
    Ok((map, Places { start: (n + r, c), tile: tile_at }))
}

/// Writes `maze` in grid format, if it is made of the format's square tiles in its numbering.
pub fn write(maze: &Maze) -> Result<String, WriteError> {
    let map = to_map(maze)?;
    if map.tile < MIN_TILE {
        let why = "so that the viewer fits between walls";
        return Err(no(format!(
            "its tiles are {} across; a grid file's are at least {MIN_TILE}, {why}",
            map.tile
        )));
    }
    let text = map.to_text();
    // the writer's guarantee: reading it back gives this very maze
    match parse_str("", &text) {
        Ok(back) if back == *maze => Ok(text),
        _ => Err(no("its cells, edges or ids are not laid out as the grid format numbers them")),
    }
}

fn no(reason: impl Into<String>) -> WriteError {
    WriteError { format: Format::Grid, reason: reason.into() }
}

/// The tile map of a maze made of square tiles on a lattice anchored at the origin.
fn to_map(maze: &Maze) -> Result<TileMap, WriteError> {
    // the reader puts lattice point i at `i as f32 * tile`, so an edge's length can be off by rounding
    // (tile 0.1): try the side of cell 0 and the quotients of its corners, each give or take 2 ulps
    let bb = maze.cell_aabb(0);
    let d = (bb.max - bb.min).max_element();
    let mut guesses = vec![d];
    for (lo, hi) in [(bb.min.x, bb.max.x), (bb.min.y, bb.max.y)] {
        let i = (lo / d).round();
        if i >= 1.0 {
            guesses.extend([lo / i, hi / (i + 1.0)]);
        }
    }
    let mut fails = None;
    for g in guesses {
        for k in -2i32..=2 {
            let t = f32::from_bits(g.to_bits().wrapping_add_signed(k));
            match lattice(maze, t) {
                Ok((place, max_x, max_y)) => return tiles_of(maze, t, place, max_x, max_y),
                Err(e) => _ = fails.get_or_insert(e),
            }
        }
    }
    Err(fails.unwrap_or_else(|| no("cell 0 has no extent")))
}

/// Each cell's tile `(x, y)`, and the largest `x` and `y`.
type Placement = (Vec<(i64, i64)>, i64, i64);

/// Each cell's tile, if every cell is an axis-aligned square of side `t` on the lattice from the
/// origin; with the largest tile coordinates.
fn lattice(maze: &Maze, t: f32) -> Result<Placement, WriteError> {
    if !(t.is_finite() && t > 0.0) {
        return Err(no("cell 0 has no extent"));
    }
    let mut place = Vec::with_capacity(maze.cell_count());
    let (mut max_x, mut max_y) = (0i64, 0i64);
    for c in 0..maze.cell_count() as CellId {
        let bb = maze.cell_aabb(c);
        let (x, y) = ((bb.min.x / t).round(), (bb.min.y / t).round());
        let square = maze.cell_edges(c).len() == 4
            && x >= 0.0
            && y >= 0.0
            && x * t == bb.min.x
            && y * t == bb.min.y
            && (x + 1.0) * t == bb.max.x
            && (y + 1.0) * t == bb.max.y;
        if !square || x > 2046.0 || y > 2046.0 {
            return Err(no(format!(
                "cell {c} is not a square tile of side {t} on a lattice from the origin"
            )));
        }
        let (x, y) = (x as i64, y as i64);
        (max_x, max_y) = (max_x.max(x), max_y.max(y));
        place.push((x, y));
    }
    Ok((place, max_x, max_y))
}

fn tiles_of(
    maze: &Maze,
    t: f32,
    place: Vec<(i64, i64)>,
    max_x: i64,
    max_y: i64,
) -> Result<TileMap, WriteError> {
    let (cols, rows) = (max_x as usize + 2, max_y as usize + 2);
    let mut map = TileMap {
        tile: t,
        eye: maze.viewer().z,
        fov_deg: maze.viewer().fov_deg,
        min_vfov_deg: maze.min_vfov_deg(),
        facing_deg: None,
        legend: Vec::new(),
        cols,
        rows,
        tiles: vec![b'#'; cols * rows],
    };
    let index = |x: i64, y: i64| (rows - 1 - y as usize) * cols + x as usize;
    for &(x, y) in &place {
        map.tiles[index(x, y)] = b'.';
    }
    if let Some(e) = maze.edges().iter().position(|e| e.opaque && e.left.is_some() && e.right.is_some()) {
        return Err(no(format!("edge {e} is a wall between two cells (walls are tiles here)")));
    }
    // each wall edge and the tile across it: one step from its cell along the mid-point's larger axis
    let behind: Vec<(usize, i64, i64)> = (maze.edges().iter().enumerate())
        .filter_map(|(e, edge)| {
            let cell = if edge.opaque { edge.left.or(edge.right)? } else { return None };
            let (x, y) = place[cell as usize];
            let (p, q) = maze.edge_points(e as EdgeId);
            let mid = (p + q) / 2.0 / t - vec2(x as f32 + 0.5, y as f32 + 0.5);
            let across = if mid.x.abs() > mid.y.abs() {
                (x + mid.x.signum() as i64, y)
            } else {
                (x, y + mid.y.signum() as i64)
            };
            Some((e, across.0, across.1))
        })
        .collect();
    // `#` takes the colour of the outside (left of and below the map), as the reader gives it
    let hash = behind
        .iter()
        .find(|&&(_, nx, ny)| nx < 0 || ny < 0)
        .map_or(DEFAULT_WALL, |&(e, ..)| maze.edges().get(e).color);
    if hash != DEFAULT_WALL {
        check_rgb(hash)?;
        map.legend.push((b'#', hash));
    }
    // wall colours, from the opaque edges onto the wall tiles behind them
    let mut colored = vec![false; map.tiles.len()];
    for (e, nx, ny) in behind {
        let letter = legend_letter(&mut map.legend, hash, maze.edges().get(e).color)?;
        if nx < 0 || ny < 0 {
            if letter != b'#' {
                return Err(no(format!("edge {e} faces the outside with a colour other than `#`")));
            }
            continue;
        }
        let i = index(nx, ny);
        if colored[i] && map.tiles[i] != letter {
            return Err(no(format!("the wall tile behind edge {e} would need two colours")));
        }
        map.tiles[i] = letter;
        colored[i] = true;
    }
    let v = maze.viewer();
    let start = maze.cell_at(v.pos).unwrap_or(0);
    let (x, y) = place[start as usize];
    let arrow = [0.0, 90.0, 180.0, 270.0].iter().position(|&d| d == v.dir_deg).map(|k| b">^<v"[k]);
    match arrow {
        Some(ch) if (vec2(x as f32, y as f32) + 0.5) * t == v.pos => map.tiles[index(x, y)] = ch,
        _ => return Err(no("the viewer is not at a tile centre facing east, north, west or south")),
    }
    if let Some(exit) = maze.exit() {
        let (x, y) = place[exit.cell as usize];
        if exit.point.is_some() {
            return Err(no("the exit has a point of its own"));
        }
        if exit.cell == start {
            // the `E` is the start too, facing as the setting says (east, the default, unwritten)
            map.facing_deg = (v.dir_deg != 0.0).then_some(v.dir_deg);
        }
        map.tiles[index(x, y)] = b'E';
    }
    Ok(map)
}

/// Only colours a `#rrggbb` reads back exactly.
fn check_rgb(c: Vec3) -> Result<(), WriteError> {
    let bytes = (c * 255.0).round();
    if bytes / 255.0 == c { Ok(()) } else { Err(no(format!("wall colour {c} is not a #rrggbb colour"))) }
}

/// A legend line's letter and value, `L = #rrggbb` with or without spaces around `=` (`L=#rrggbb`,
/// `L= #rrggbb`, `L =#rrggbb`): each a slice of the line, so that an error can point into it.
fn legend_words<'a>(words: &[&'a str]) -> Option<(&'a str, &'a str)> {
    let (letter, value) = match *words {
        [letter, "=", value] => (letter, value),
        [one] => one.split_once('=')?,
        [letter, value] => match (letter.strip_suffix('='), value.strip_prefix('=')) {
            (Some(letter), None) => (letter, value),
            (None, Some(value)) => (letter, value),
            _ => return None,
        },
        _ => return None,
    };
    (letter.chars().count() == 1 && !value.is_empty()).then_some((letter, value))
}

/// The letter for wall colour `c`: `#` for the `hash` colour, else a legend letter (added if new).
fn legend_letter(legend: &mut Vec<(u8, Vec3)>, hash: Vec3, c: Vec3) -> Result<u8, WriteError> {
    if c == hash {
        return Ok(b'#');
    }
    if let Some(&(l, _)) = legend.iter().find(|(_, lc)| *lc == c) {
        return Ok(l);
    }
    check_rgb(c)?;
    let letters = legend.iter().filter(|(l, _)| *l != b'#').count();
    let l =
        *TileMap::LEGEND_LETTERS.get(letters).ok_or_else(|| no("more wall colours than legend letters"))?;
    legend.push((l, c));
    Ok(l)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Edge, VertexId};

    const SMALL: &str = "mazewalk-grid 1\nA = #cc8844\n\n#####\n#>.E#\n#.A.#\n#####\n";

    #[test]
    fn a_small_map_reads_as_documented() {
        let m = parse_str("small", SMALL).unwrap();
        // open tiles: bottom row (y = 1) x = 1, 3; top row (y = 2) x = 1, 2, 3
        assert_eq!(m.cell_count(), 5);
        assert_eq!(m.viewer().pos, vec2(6.0, 10.0));
        assert_eq!(m.viewer().dir_deg, 0.0);
        assert_eq!(m.exit().map(|x| x.cell), Some(4));
        assert_eq!(m.portal_count(), 4);
        // the A tile's side facing the cell above it has A's colour
        let a = Vec3::new(0xcc as f32, 0x88 as f32, 0x44 as f32) / 255.0;
        assert_eq!(m.edges().iter().filter(|e| e.color == a && e.opaque).count(), 3);
    }

    #[test]
    fn the_row_sweep_numbers_as_the_tables_did() {
        use crate::generate::{GenOptions, generate_grid};
        let mut maps = vec![parse_map("small", SMALL).unwrap(), parse_map("b", crate::BUILTIN).unwrap()];
        for (seed, loops) in [(1, 0.0), (2, 0.3), (3, 1.0)] {
            let opts = GenOptions { width: 13, height: 7, seed, loops, exit: true, ..GenOptions::default() };
            maps.push(generate_grid(&opts).unwrap());
        }
        // ragged rows, floor at the map's edge (outside beyond it)
        maps.push(parse_map("r", "mazewalk-grid 1\n\n  .\n#@..\n.\n").unwrap());
        // one band, and cut into bands (as many as rows, and more: one row each)
        for map in &maps {
            let oracle = build_with_tables(map);
            for bands in [1, 2, 3, map.rows, map.rows + 5] {
                assert_eq!(
                    map.build_in_bands(true, bands).unwrap(),
                    oracle,
                    "{bands} bands: {}",
                    map.to_text()
                );
            }
        }
    }

    /// The first, table-driven version of `TileMap::build`: the oracle for its numbering.
    fn build_with_tables(map: &TileMap) -> Maze {
        let this = map;
        let (cols, rows) = (this.cols as i64, this.rows as i64);
        let t = this.tile;
        let tile_index = |x: i64, y: i64| ((rows - 1 - y) * cols + x) as usize;
        // cells: open tiles, row by row from the bottom, west to east
        let mut cell_of = vec![u32::MAX; this.tiles.len()];
        let mut n_cells = 0u32;
        for y in 0..rows {
            for x in 0..cols {
                if is_open(this.at(x, y)) {
                    cell_of[tile_index(x, y)] = n_cells;
                    n_cells += 1;
                }
            }
        }
        let cell = |x: i64, y: i64| {
            (x >= 0 && y >= 0 && x < cols && y < rows)
                .then(|| cell_of[tile_index(x, y)])
                .filter(|&c| c != u32::MAX)
        };
        // exact sizes, so the two big arrays are allocated once and not doubled (4 M edges of a
        // 1000 × 1000 maze are 160 MB): a side with a cell on either hand is an edge, a lattice point
        // with a cell in any of its four tiles a vertex
        let open = |x: i64, y: i64| cell(x, y).is_some();
        let (mut n_edges, mut n_vertices) = (0usize, 0usize);
        for y in 0..=rows {
            for x in 0..=cols {
                n_edges += usize::from(x < cols && (open(x, y) || open(x, y - 1)));
                n_edges += usize::from(y < rows && (open(x - 1, y) || open(x, y)));
                n_vertices +=
                    usize::from(open(x, y) || open(x - 1, y) || open(x, y - 1) || open(x - 1, y - 1));
            }
        }
        // vertices: lattice points, numbered as the edges first use them
        let mut vertex_of = vec![u32::MAX; ((cols + 1) * (rows + 1)) as usize];
        let mut vertices = Vec::with_capacity(n_vertices);
        let mut vertex = |x: i64, y: i64| -> VertexId {
            let slot = &mut vertex_of[(y * (cols + 1) + x) as usize];
            if *slot == u32::MAX {
                *slot = vertices.len() as VertexId;
                vertices.push(vec2(x as f32, y as f32) * t);
            }
            *slot
        };
        let mut edges = Edges::with_capacity(n_edges);
        // horizontal side (x, y) runs east along the lattice line y: the tile above is on its left
        let mut h_edge = vec![u32::MAX; (cols * (rows + 1)) as usize];
        for y in 0..=rows {
            for x in 0..cols {
                let (left, right) = (cell(x, y), cell(x, y - 1));
                if left.is_none() && right.is_none() {
                    continue;
                }
                let wall = if left.is_none() { this.at(x, y) } else { this.at(x, y - 1) };
                h_edge[(y * cols + x) as usize] = edges.len() as EdgeId;
                let (start, end) = (vertex(x, y), vertex(x + 1, y));
                let opaque = left.is_none() || right.is_none();
                let color = if opaque { this.color(wall) } else { DEFAULT_WALL };
                edges.push(Edge { start, end, left, right, opaque, color });
            }
        }
        // vertical side (x, y) runs north along the lattice line x: the tile to the west is on its left
        let mut v_edge = vec![u32::MAX; ((cols + 1) * rows) as usize];
        for y in 0..rows {
            for x in 0..=cols {
                let (left, right) = (cell(x - 1, y), cell(x, y));
                if left.is_none() && right.is_none() {
                    continue;
                }
                let wall = if left.is_none() { this.at(x - 1, y) } else { this.at(x, y) };
                v_edge[(y * (cols + 1) + x) as usize] = edges.len() as EdgeId;
                let (start, end) = (vertex(x, y), vertex(x, y + 1));
                let opaque = left.is_none() || right.is_none();
                let color = if opaque { this.color(wall) } else { DEFAULT_WALL };
                edges.push(Edge { start, end, left, right, opaque, color });
            }
        }
        let mut cells = Cells::with_capacity(n_cells as usize, 4 * n_cells as usize);
        let (mut viewer, mut exit) = (None, None);
        for y in 0..rows {
            for x in 0..cols {
                let Some(c) = cell(x, y) else { continue };
                let h = |x: i64, y: i64| h_edge[(y * cols + x) as usize];
                let v = |x: i64, y: i64| v_edge[(y * (cols + 1) + x) as usize];
                // +x, +y, -x, -y, as the original lists them
                cells.push(&[v(x + 1, y), h(x, y + 1), v(x, y), h(x, y)]);
                let ch = this.at(x, y);
                if ch == b'E' && exit.is_none() {
                    exit = Some(Exit { cell: c, point: None });
                }
                if let Some(dir) = start_dir(ch, this.facing_deg, this.starts_on_exit())
                    && viewer.is_none()
                {
                    let pos = (vec2(x as f32, y as f32) + 0.5) * t;
                    viewer = Some(Viewer { pos, z: this.eye, dir_deg: dir, fov_deg: this.fov_deg });
                }
            }
        }
        // the lookup tables are done with: free them before the model builds its own
        drop((cell_of, vertex_of, h_edge, v_edge));
        // no start tile: a viewer outside every cell, which Maze::new reports
        let viewer =
            viewer.unwrap_or(Viewer { pos: vec2(-1.0, -1.0) * t, z: 0.0, dir_deg: 0.0, fov_deg: 90.0 });
        Maze::new(vertices, edges, cells, viewer, exit).expect("a valid map")
    }

    #[test]
    fn write_then_read_is_the_identity() {
        let m = parse_str("small", SMALL).unwrap();
        let text = write(&m).unwrap();
        assert_eq!(parse_str("again", &text).unwrap(), m, "{text}");
    }
}
