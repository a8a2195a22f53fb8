//! The maze: a plan of convex cells in the x/y plane, bounded by walls (opaque edges) and portals
//! (transparent edges), plus the viewer's start and an optional exit.
//!
//! Maze plane: x east, y north; walls span z = -1 (floor) to +1 (ceiling). A cell's edges, each
//! oriented so the cell lies on its left, form one counter-clockwise convex loop. Ids are plain
//! `u32` indices into the maze's arrays; cell → edges is stored flat (CSR), see [`Maze::cell_edges`].
//!
//! Modules: [`cs559`] and [`grid`] read and write the two file formats ([`parse`] and [`load()`] pick
//! one; what the formats share, errors and positions and the quoting of input, lives in a module of
//! its own that neither `load` nor a format sits above), [`generate`] makes random mazes, [`movement`]
//! moves a viewer without passing walls. [`Maze::new`] validates in O(n log n) whatever the edges'
//! shape: a bucket grid, or a Shamos–Hoey sweep when long edges crowd the buckets.
//!
//! ```
//! # use mazewalk_maze as maze;
//! let text = "4  0 0  4 0  0 4  4 4
//!             4  0 1 0 -1 1 .5 .5 .5   2 3 -1 0 1 .5 .5 .5   0 2 -1 0 1 .5 .5 .5   1 3 0 -1 1 .5 .5 .5
//!             1  3 1 2 0
//!             2 2 0 90 90";
//! let maze = maze::parse("room.maze", text.as_bytes())?;
//! assert_eq!(maze.cell_count(), 1);
//! assert_eq!(maze.cell_at(glam::vec2(1.0, 3.0)), Some(0));
//! # Ok::<(), maze::LoadError>(())
//! ```

#![forbid(unsafe_code)]

pub mod cs559;
pub mod files;
pub mod generate;
pub mod geometry;
pub mod grid;
mod hash;
mod index;
pub mod light;
mod load;
pub mod movement;
mod sweep;
mod text;
mod validate;

use glam::{DVec2, Vec2, Vec3};

pub use hash::ContentHash;
use index::{SpatialGrid, Threads};
pub use load::{
    DEFAULT_MAX_BYTES, LoadError, LoadOptions, Loaded, detect_format, load, load_with, parse, parse_loaded,
    write,
};
pub use text::{
    Format, ParseError, ParseErrorKind, QUOTE_CHARS, WriteError, escape_json, may_hold_unseen, quote,
    quote_path, quote_within, unseen,
};

/// The maze walked when none is given: `mazes/hand-drawn.grid`, compiled in (loops, colours, an exit).
pub(crate) const BUILTIN: &str = include_str!("../../../mazes/hand-drawn.grid");

/// The name the built-in maze goes by in messages.
pub const BUILTIN_NAME: &str = "built-in maze";

/// Parses [`BUILTIN`].
///
/// # Errors
/// Never in practice (a test loads it); typed anyway, so no caller has to trust that.
pub fn builtin() -> Result<Maze, ParseError> {
    parse(BUILTIN_NAME, BUILTIN.as_bytes())
}

/// Index of a vertex in [`Maze::vertices`].
pub(crate) type VertexId = u32;
/// Index of an edge in [`Maze::edges`].
pub(crate) type EdgeId = u32;
/// Index of a cell, `0..maze.cell_count()`.
pub(crate) type CellId = u32;

/// Largest accepted |x| or |y| of any coordinate, in maze units.
pub const COORD_BOUND: f32 = 1.0e6;

/// Distance (maze units) within which a point counts as on an edge line, so a point exactly on a
/// cell's boundary is inside it despite rounding.
pub(crate) const ON_EDGE_TOLERANCE: f64 = 1.0e-4;

/// Smallest area of a cell, in square maze units: a cell narrower than the on-edge tolerance is a
/// sliver no viewer fits in.
pub(crate) const MIN_CELL_AREA: f64 = 1.0e-6;

/// A wall or portal between two vertices.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Edge {
    /// Start vertex.
    pub start: VertexId,
    /// End vertex.
    pub end: VertexId,
    /// The cell on the left standing at `start` looking toward `end`; `None` = outside.
    pub left: Option<CellId>,
    /// The cell on the right; `None` = outside.
    pub right: Option<CellId>,
    /// `true` for a wall, `false` for a portal between `left` and `right`.
    pub opaque: bool,
    /// Wall colour, RGB in 0..1.
    pub color: Vec3,
}

impl Edge {
    /// The cell across this edge from `cell`, or `None` for the outside.
    ///
    /// # Panics
    /// In debug builds, if `cell` is on neither side.
    #[must_use]
    pub fn other_side(&self, cell: CellId) -> Option<CellId> {
        if self.left == Some(cell) {
            self.right
        } else {
            debug_assert_eq!(self.right, Some(cell), "cell {cell} is not beside this edge");
            self.left
        }
    }

    /// `true` for a transparent edge (a portal between two cells).
    #[must_use]
    pub fn is_portal(&self) -> bool {
        !self.opaque
    }
}

/// Where the viewer starts, as in the maze file: `x y z dir_deg fov_deg`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Viewer {
    /// Position in the maze plane.
    pub pos: Vec2,
    /// Eye height; the floor is at -1, the ceiling at +1.
    pub z: f32,
    /// Heading, degrees counter-clockwise from +x.
    pub dir_deg: f32,
    /// Horizontal field of view, degrees.
    pub fov_deg: f32,
}

/// The goal: a cell, optionally with a point in it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Exit {
    /// The exit cell.
    pub cell: CellId,
    /// A point in `cell`, when the file gave one.
    pub point: Option<Vec2>,
}

/// An axis-aligned box in any 2D space (the maze plane, the sample grid): name each value by its space,
/// `world_box`, `grid_box`. Empty when `min` > `max` on either axis; every test is inclusive.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    /// Smallest x and y.
    pub min: Vec2,
    /// Largest x and y.
    pub max: Vec2,
}

impl Aabb {
    /// The empty box (`min` > `max`), the identity of [`Aabb::union_point`].
    pub const EMPTY: Aabb = Aabb { min: Vec2::splat(f32::INFINITY), max: Vec2::splat(f32::NEG_INFINITY) };

    /// The box from `min` to `max`.
    #[must_use]
    pub const fn new(min: Vec2, max: Vec2) -> Aabb {
        Aabb { min, max }
    }

    /// The smallest box holding `self` and `p`.
    #[must_use]
    pub fn union_point(self, p: Vec2) -> Aabb {
        Aabb { min: self.min.min(p), max: self.max.max(p) }
    }

    /// `true` when the boxes overlap or touch.
    #[must_use]
    pub fn intersects(&self, other: &Aabb) -> bool {
        self.min.cmple(other.max).all() && other.min.cmple(self.max).all()
    }

    /// The overlap of two boxes (may be empty; touching boxes overlap in a line).
    #[must_use]
    pub fn intersection(self, other: Aabb) -> Aabb {
        Aabb { min: self.min.max(other.min), max: self.max.min(other.max) }
    }

    /// `true` when the box holds no point.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        !self.min.cmple(self.max).all()
    }

    /// `true` when `other` lies inside `self` (boundary included).
    #[must_use]
    pub fn contains(&self, other: &Aabb) -> bool {
        self.min.cmple(other.min).all() && self.max.cmpge(other.max).all()
    }

    /// The box's centre.
    #[must_use]
    pub fn centre(&self) -> Vec2 {
        (self.min + self.max) * 0.5
    }

    /// The box grown by `d` on every side.
    #[must_use]
    pub fn expand(self, d: f32) -> Aabb {
        Aabb { min: self.min - d, max: self.max + d }
    }

    /// `true` when segment `a`–`b` meets the closed box (Liang–Barsky on the slab intervals).
    #[must_use]
    pub fn touches_segment(&self, a: Vec2, b: Vec2) -> bool {
        let d = b - a;
        let (mut t0, mut t1) = (0.0f32, 1.0f32);
        let slabs = [
            (-d.x, a.x - self.min.x),
            (d.x, self.max.x - a.x),
            (-d.y, a.y - self.min.y),
            (d.y, self.max.y - a.y),
        ];
        for (p, q) in slabs {
            if p == 0.0 {
                if q < 0.0 {
                    return false; // parallel to this slab and outside it
                }
            } else {
                let t = q / p;
                if p < 0.0 {
                    t0 = t0.max(t);
                } else {
                    t1 = t1.min(t);
                }
            }
        }
        t0 <= t1
    }
}

/// Cells as a flat list of edge ids (CSR): cell `c` owns `edges[offsets[c]..offsets[c + 1]]`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Cells {
    offsets: Vec<u32>,
    edges: Vec<EdgeId>,
}

impl Default for Cells {
    fn default() -> Self {
        Cells { offsets: vec![0], edges: Vec::new() }
    }
}

impl Cells {
    /// No cells.
    #[must_use]
    pub fn new() -> Cells {
        Cells::default()
    }

    /// No cells, with room for `cells` cells of `edges` edge slots in all.
    #[must_use]
    pub fn with_capacity(cells: usize, edges: usize) -> Cells {
        let mut offsets = Vec::with_capacity(cells + 1);
        offsets.push(0);
        Cells { offsets, edges: Vec::with_capacity(edges) }
    }

    /// Cells of `per_cell` edges each, cell `c` owning `edges[c * per_cell..][..per_cell]`.
    ///
    /// # Panics
    /// In debug builds, if `edges.len()` is not a multiple of `per_cell`; always, if it exceeds
    /// `u32::MAX`.
    #[must_use]
    pub fn uniform(edges: Vec<EdgeId>, per_cell: usize) -> Cells {
        debug_assert!(per_cell > 0 && edges.len().is_multiple_of(per_cell), "whole cells");
        u32::try_from(edges.len()).expect("fewer than 2^32 edge slots");
        let offsets = (0..=edges.len() / per_cell).map(|c| (c * per_cell) as u32).collect();
        Cells { offsets, edges }
    }

    /// Appends a cell bounded by `edges` (any order).
    ///
    /// # Panics
    /// If the total number of edge slots exceeds `u32::MAX`.
    pub fn push(&mut self, edges: &[EdgeId]) {
        self.edges.extend_from_slice(edges);
        self.offsets.push(u32::try_from(self.edges.len()).expect("fewer than 2^32 edge slots"));
    }

    /// Number of cells.
    #[must_use]
    pub fn len(&self) -> usize {
        self.offsets.len() - 1
    }

    /// `true` when there are no cells.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The edges of cell `c`.
    #[must_use]
    pub fn get(&self, c: usize) -> &[EdgeId] {
        &self.edges[self.offsets[c] as usize..self.offsets[c + 1] as usize]
    }
}

/// Edges, stored in 28 bytes each where an [`Edge`] takes 40 (`Option<CellId>` has no spare value
/// to mark `None` in, and the flag pads the record to the next 4 bytes): a 1000 × 1000 grid file's
/// 6 M edges take 170 MB instead of 240. A side is a plain `u32` with [`NO_CELL`] for the outside (no
/// cell id reaches it: there are at most `u32::MAX - 1` cells); the opaque flags are a bit set beside
/// the records. Colours are kept exactly as given. Reads hand out [`Edge`]s by value.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Edges {
    packed: Vec<PackedEdge>,
    /// Bit `e % 64` of word `e / 64`: edge `e` is opaque. Bits past the last edge are 0.
    opaque: Vec<u64>,
}

/// The side value that means "outside" in [`Edges`]' storage.
const NO_CELL: u32 = u32::MAX;

/// An [`Edge`] without its opaque flag, sides as `u32` ([`NO_CELL`] = outside). `Zeroable`: a big
/// array of them can be allocated zeroed and filled in parts (see the grid reader).
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Zeroable)]
struct PackedEdge {
    start: VertexId,
    end: VertexId,
    left: u32,
    right: u32,
    color: Vec3,
}

impl PackedEdge {
    fn new(start: VertexId, end: VertexId, left: Option<CellId>, right: Option<CellId>, color: Vec3) -> Self {
        let side = |c: Option<CellId>| c.unwrap_or(NO_CELL);
        PackedEdge { start, end, left: side(left), right: side(right), color }
    }
}

impl Edges {
    /// No edges.
    #[must_use]
    pub fn new() -> Edges {
        Edges::default()
    }

    /// No edges, with room for `n`.
    #[must_use]
    pub fn with_capacity(n: usize) -> Edges {
        Edges { packed: Vec::with_capacity(n), opaque: Vec::with_capacity(n.div_ceil(64)) }
    }

    /// Appends `edge`.
    ///
    /// # Panics
    /// In debug builds, if a side is `Some(u32::MAX)` (no maze has that many cells; the readers
    /// refuse such an id before building an edge).
    pub fn push(&mut self, edge: Edge) {
        debug_assert!(edge.left != Some(NO_CELL) && edge.right != Some(NO_CELL), "cell id u32::MAX");
        let n = self.packed.len();
        if n.is_multiple_of(64) {
            self.opaque.push(0);
        }
        if let Some(word) = self.opaque.last_mut() {
            *word |= u64::from(edge.opaque) << (n % 64);
        }
        self.packed.push(PackedEdge::new(edge.start, edge.end, edge.left, edge.right, edge.color));
    }

    /// Edges from their records and each one's opaque flag (`opaque(id, record)`).
    fn from_records(packed: Vec<PackedEdge>, opaque: impl Fn(usize, &PackedEdge) -> bool) -> Edges {
        let opaque = packed
            .chunks(64)
            .enumerate()
            .map(|(w, run)| {
                run.iter().enumerate().fold(0, |word, (i, p)| word | u64::from(opaque(64 * w + i, p)) << i)
            })
            .collect();
        Edges { packed, opaque }
    }

    /// Edges from their records, each a wall when it has the outside on a side and a portal
    /// otherwise (the grid format's rule).
    fn walls_where_outside(packed: Vec<PackedEdge>) -> Edges {
        Edges::from_records(packed, |_, p| p.left == NO_CELL || p.right == NO_CELL)
    }

    /// Number of edges.
    #[must_use]
    pub fn len(&self) -> usize {
        self.packed.len()
    }

    /// `true` when there are no edges.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.packed.is_empty()
    }

    /// Edge `e`.
    ///
    /// # Panics
    /// If `e` is out of range.
    #[must_use]
    pub fn get(&self, e: usize) -> Edge {
        let p = self.packed[e];
        let side = |c: u32| (c != NO_CELL).then_some(c);
        Edge {
            start: p.start,
            end: p.end,
            left: side(p.left),
            right: side(p.right),
            opaque: self.is_opaque(e),
            color: p.color,
        }
    }

    /// Edge `e`'s start and end vertices (cheaper than [`Edges::get`], for the hot loops).
    #[must_use]
    pub fn ends(&self, e: usize) -> (VertexId, VertexId) {
        let p = &self.packed[e];
        (p.start, p.end)
    }

    /// `true` when `cell` is on edge `e`'s left (cheaper than [`Edges::get`], for the hot loops).
    #[must_use]
    pub(crate) fn is_left_of(&self, e: usize, cell: CellId) -> bool {
        self.packed[e].left == cell
    }

    /// `true` when edge `e` is a wall (cheaper than [`Edges::get`]).
    #[must_use]
    pub fn is_opaque(&self, e: usize) -> bool {
        self.opaque[e / 64] >> (e % 64) & 1 == 1
    }

    /// Number of opaque edges, a word of flags at a time.
    #[must_use]
    pub(crate) fn opaque_count(&self) -> usize {
        self.opaque.iter().map(|w| w.count_ones() as usize).sum()
    }

    /// The opaque edges' ids, ascending, a word of flags at a time: an open floor's portals cost
    /// their words only (red-team pass 9: drawing every edge of a 2046 × 2046 floor of tiny tiles
    /// clipped its 8 million portals, which no one sees, for each frame).
    pub fn opaque_ids(&self) -> impl Iterator<Item = EdgeId> + '_ {
        self.opaque.iter().zip((0..).step_by(64)).flat_map(|(&word, first): (&u64, EdgeId)| {
            let mut left = word;
            std::iter::from_fn(move || {
                let bit = (left != 0).then(|| left.trailing_zeros())?;
                left &= left - 1; // the lowest set bit cleared
                Some(first + bit)
            })
        })
    }

    /// Every edge, in id order.
    #[must_use]
    pub fn iter(&self) -> EdgesIter<'_> {
        EdgesIter { edges: self, ids: 0..self.len() }
    }
}

/// The iterator of [`Edges::iter`].
#[derive(Clone, Debug)]
pub struct EdgesIter<'a> {
    edges: &'a Edges,
    ids: std::ops::Range<usize>,
}

impl Iterator for EdgesIter<'_> {
    type Item = Edge;

    fn next(&mut self) -> Option<Edge> {
        self.ids.next().map(|e| self.edges.get(e))
    }

    fn size_hint(&self) -> (usize, Option<usize>) {
        self.ids.size_hint()
    }
}

impl ExactSizeIterator for EdgesIter<'_> {}

impl<'a> IntoIterator for &'a Edges {
    type Item = Edge;
    type IntoIter = EdgesIter<'a>;

    fn into_iter(self) -> EdgesIter<'a> {
        self.iter()
    }
}

impl Extend<Edge> for Edges {
    fn extend<I: IntoIterator<Item = Edge>>(&mut self, iter: I) {
        let iter = iter.into_iter();
        self.packed.reserve(iter.size_hint().0);
        for e in iter {
            self.push(e);
        }
    }
}

impl FromIterator<Edge> for Edges {
    fn from_iter<I: IntoIterator<Item = Edge>>(iter: I) -> Edges {
        let mut edges = Edges::new();
        edges.extend(iter);
        edges
    }
}

/// A validated maze. Build one with [`Maze::new`], a reader ([`parse`], [`load()`]) or [`generate`].
#[derive(Clone, Debug)]
pub struct Maze {
    vertices: Vec<Vec2>,
    edges: Edges,
    cells: Cells,
    viewer: Viewer,
    exit: Option<Exit>,
    extents: Aabb,
    /// Cells by bucket, for [`Maze::cell_at`].
    cell_index: SpatialGrid,
    /// How close the viewer's eye comes to a wall ([`Maze::clearance`]), derived from the cells.
    clearance: f32,
    /// The least vertical field of view the walk's camera keeps ([`Maze::min_vfov_deg`]); 0 = none.
    min_vfov_deg: f32,
    /// The exit's light ([`Maze::exit_light`]), searched on first use and kept: a maze's walls and
    /// exit never change once built.
    exit_light: std::sync::OnceLock<light::ExitLight>,
}

/// Two mazes are equal when their vertices, edges, cells, viewer and exit are (the index and the
/// clearance are derived; the least vertical field of view is a hint of the generator no file keeps).
impl PartialEq for Maze {
    fn eq(&self, other: &Maze) -> bool {
        self.vertices == other.vertices
            && self.edges == other.edges
            && self.cells == other.cells
            && self.viewer == other.viewer
            && self.exit == other.exit
    }
}

/// What makes a maze invalid; each names the vertex, edge or cell at fault.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[allow(missing_docs)] // the fields are named by the messages
pub enum MazeError {
    #[error("the maze has no cells")]
    NoCells,
    #[error("too many {what} ({count}; at most {max})")]
    TooMany { what: &'static str, count: usize, max: usize },
    #[error("vertex {vertex} has a coordinate that is not finite or beyond ±{COORD_BOUND}")]
    VertexOutOfBounds { vertex: VertexId },
    #[error("edge {edge} names vertex {vertex}, but there {}", only(*count, "vertex", "vertices"))]
    EdgeVertexOutOfRange { edge: EdgeId, vertex: VertexId, count: usize },
    #[error("edge {edge} has zero length (vertices {start} and {end} coincide)")]
    EdgeDegenerate { edge: EdgeId, start: VertexId, end: VertexId },
    #[error("edge {edge} names cell {cell}, but there {}", only(*count, "cell", "cells"))]
    EdgeCellOutOfRange { edge: EdgeId, cell: CellId, count: usize },
    #[error("edge {edge} has cell {cell} on both sides")]
    EdgeSameCellBothSides { edge: EdgeId, cell: CellId },
    #[error("edge {edge} borders no cell (-1 on both sides)")]
    EdgeNoCell { edge: EdgeId },
    #[error("edge {edge} is transparent but leads outside the maze (a portal needs a cell on both sides)")]
    PortalToOutside { edge: EdgeId },
    #[error("edge {edge} has a colour component outside 0..1")]
    EdgeColor { edge: EdgeId },
    #[error("edge {edge} lists cell {cell} on its {side} but cell {cell} does not list edge {edge}")]
    CellMissingEdge { edge: EdgeId, cell: CellId, side: &'static str },
    #[error("cell {cell} lists edge {edge}, but there {}", only(*count, "edge", "edges"))]
    CellEdgeOutOfRange { cell: CellId, edge: EdgeId, count: usize },
    #[error("cell {cell} lists edge {edge}, but edge {edge} names neither of its sides as cell {cell}")]
    CellEdgeNotNeighbour { cell: CellId, edge: EdgeId },
    #[error("cell {cell} lists edge {edge} twice")]
    CellEdgeDuplicate { cell: CellId, edge: EdgeId },
    #[error("cell {cell} has {count} edges; a cell needs at least 3")]
    CellTooFewEdges { cell: CellId, count: usize },
    #[error("cell {cell}'s edges do not form one closed loop (at vertex {vertex})")]
    CellNotClosed { cell: CellId, vertex: VertexId },
    #[error("cell {cell} is not convex (at vertex {vertex})")]
    CellNotConvex { cell: CellId, vertex: VertexId },
    #[error("cell {cell} winds clockwise or has no area: its edges' left/right sides are swapped")]
    CellClockwise { cell: CellId },
    #[error("cell {cell} has an area of {area:e}; a cell needs at least {MIN_CELL_AREA:e}")]
    CellTooSmall { cell: CellId, area: f64 },
    #[error("cell {cell} lies inside cell {other}: cells may share edges, not area")]
    CellsOverlap { cell: CellId, other: CellId },
    #[error("edges {a} and {b} cross")]
    EdgesCross { a: EdgeId, b: EdgeId },
    #[error("edges {a} and {b} overlap (collinear)")]
    EdgesOverlap { a: EdgeId, b: EdgeId },
    #[error(
        "the viewer has a value that is not finite, or a coordinate or direction (degrees) beyond ±{COORD_BOUND}"
    )]
    ViewerNotFinite,
    #[error("the viewer's eye height {z} is not strictly between the floor (-1) and the ceiling (+1)")]
    ViewerHeight { z: f32 },
    #[error("the viewer's field of view {fov_deg}° is not strictly between 0 and 180")]
    ViewerFov { fov_deg: f32 },
    #[error("the viewer at ({x}, {y}) is in no cell")]
    ViewerOutside { x: f32, y: f32 },
    #[error("the viewer at ({x}, {y}) stands on wall {edge}; place it inside a cell")]
    ViewerOnWall { x: f32, y: f32, edge: EdgeId },
    #[error(
        "the viewer at ({x}, {y}) has no room to stand: the walk keeps it {margin} from every wall, and no \
         place in cell {cell} or beside it is that far from them"
    )]
    ViewerNoRoom { x: f32, y: f32, cell: CellId, margin: f32 },
    #[error("the exit names cell {cell}, but there {}", only(*count, "cell", "cells"))]
    ExitCellOutOfRange { cell: CellId, count: usize },
    #[error("the exit point ({x}, {y}) is in no cell")]
    ExitOutside { x: f32, y: f32 },
    #[error("the exit point ({x}, {y}) is not inside cell {cell}")]
    ExitPointOutside { cell: CellId, x: f32, y: f32 },
}

/// "are only 4 cells", "is only 1 cell": the end of a message that an index is out of range.
fn only(count: usize, one: &str, many: &str) -> String {
    if count == 1 { format!("is only 1 {one}") } else { format!("are only {count} {many}") }
}

impl Maze {
    /// Validates the parts and builds the maze and its cell index.
    ///
    /// Checks, in order: sizes, coordinates finite and within [`COORD_BOUND`], edge indices and sides,
    /// cell ↔ edge consistency, each cell a closed counter-clockwise convex loop, no two edges crossing
    /// or overlapping (sharing an endpoint is fine), no cell inside another, the viewer in a cell, the
    /// exit in range.
    pub fn new(
        vertices: Vec<Vec2>,
        edges: Edges,
        cells: Cells,
        viewer: Viewer,
        exit: Option<Exit>,
    ) -> Result<Maze, MazeError> {
        // The crossing check needs only the vertices and edges: a big maze runs it on a second
        // thread beside the cell checks and the cell index. The errors and their order are those
        // of one check after the other: a crossing counts only once the cells have passed.
        let cells_then_index = || {
            validate::structure(&vertices, &edges, &cells)?;
            // one thread for the index: the crossing check has the other core when the maze is big
            Ok(cell_index(&vertices, &edges, &cells, Threads::One))
        };
        let crossings = || validate::crossings_of_parts(&vertices, &edges);
        let (index, crossings) = if edges.len() >= PARALLEL_CHECK_EDGES {
            std::thread::scope(|s| {
                let crossings = s.spawn(crossings);
                let index = cells_then_index();
                (index, crossings.join().unwrap_or_else(|panic| std::panic::resume_unwind(panic)))
            })
        } else {
            let index = cells_then_index();
            let crossings = if index.is_ok() { crossings() } else { Ok(()) };
            (index, crossings)
        };
        let (extents, cell_index) = index?;
        crossings?;
        let maze = Maze::assemble(vertices, edges, cells, viewer, exit, extents, cell_index);
        validate::nesting(&maze)?;
        validate::viewer_and_exit(&maze)?;
        Ok(maze)
    }

    /// Like [`Maze::new`] for parts valid by construction (the grid reader's square tiles, whose
    /// map it has checked): in release builds only the viewer and exit are checked, which saves
    /// about 40 % of loading a 1000 × 1000 grid file; debug builds check everything.
    ///
    /// # Panics
    /// In debug builds, if the parts break a rule the maker vouched for.
    pub(crate) fn new_valid_by_construction(
        vertices: Vec<Vec2>,
        edges: Edges,
        cells: Cells,
        viewer: Viewer,
        exit: Option<Exit>,
    ) -> Result<Maze, MazeError> {
        if cfg!(debug_assertions) {
            validate::structure(&vertices, &edges, &cells).expect("valid by construction");
            validate::crossings_of_parts(&vertices, &edges).expect("valid by construction");
        }
        let (extents, cell_index) = cell_index(&vertices, &edges, &cells, Threads::Two);
        let maze = Maze::assemble(vertices, edges, cells, viewer, exit, extents, cell_index);
        validate::viewer_and_exit(&maze)?;
        Ok(maze)
    }

    /// The maze of checked parts and their index: its clearance measured, no field of view of its
    /// own yet, the exit's light not yet searched.
    fn assemble(
        vertices: Vec<Vec2>,
        edges: Edges,
        cells: Cells,
        viewer: Viewer,
        exit: Option<Exit>,
        extents: Aabb,
        cell_index: SpatialGrid,
    ) -> Maze {
        let clearance = geometry::clearance_for(validate::narrowest_passage(&vertices, &edges, &cells));
        Maze {
            vertices,
            edges,
            cells,
            viewer,
            exit,
            extents,
            cell_index,
            clearance,
            min_vfov_deg: 0.0,
            exit_light: std::sync::OnceLock::new(),
        }
    }

    /// How close (maze units) the viewer's eye comes to a wall in this maze: 2/5 of its narrowest
    /// passage, between [`geometry::WALL_MARGIN`] and [`geometry::MAX_CLEARANCE`]
    /// ([`geometry::clearance_for`]); 1.6 in a generated maze. The walk, `mazewalk render --at` and the
    /// viewer's start keep this far from every wall.
    #[must_use]
    pub fn clearance(&self) -> f32 {
        self.clearance
    }

    /// The least vertical field of view (degrees) the walk's camera keeps in this maze, widening its
    /// horizontal field where the screen is too wide for it; 0 (files: they keep their own field of
    /// view) or, for a generated maze, the field with which the floor, the ceiling and a faced wall's
    /// ends show from the closest stand ([`generate::generated_min_vfov_deg`]).
    #[must_use]
    pub fn min_vfov_deg(&self) -> f32 {
        self.min_vfov_deg
    }

    /// The exit's light through this maze's cells ([`light::ExitLight::of`]), searched once, on first
    /// use, and kept with the maze (the renderer asks for it every frame).
    #[must_use]
    pub fn exit_light(&self) -> &light::ExitLight {
        self.exit_light.get_or_init(|| light::ExitLight::of(self))
    }

    /// This maze with its exit at `exit` (a cell the caller has checked), its exit's light searched anew.
    pub(crate) fn with_exit(self, exit: Exit) -> Maze {
        Maze { exit: Some(exit), exit_light: std::sync::OnceLock::new(), ..self }
    }

    /// This maze with [`Maze::min_vfov_deg`] set to `deg` (clamped to 0..=150; NaN is 0).
    #[must_use]
    pub fn with_min_vfov_deg(mut self, deg: f32) -> Maze {
        self.min_vfov_deg = if deg.is_nan() { 0.0 } else { deg.clamp(0.0, 150.0) };
        self
    }

    /// All vertices; a [`VertexId`] indexes this.
    #[must_use]
    pub fn vertices(&self) -> &[Vec2] {
        &self.vertices
    }

    /// All edges; an [`EdgeId`] indexes this.
    #[must_use]
    pub fn edges(&self) -> &Edges {
        &self.edges
    }

    /// The edge `e`.
    #[must_use]
    pub fn edge(&self, e: EdgeId) -> Edge {
        self.edges.get(e as usize)
    }

    /// The vertex `v`.
    #[must_use]
    pub fn vertex(&self, v: VertexId) -> Vec2 {
        self.vertices[v as usize]
    }

    /// Number of cells.
    #[must_use]
    pub fn cell_count(&self) -> usize {
        self.cells.len()
    }

    /// The cells, in their flat layout.
    #[must_use]
    pub fn cells(&self) -> &Cells {
        &self.cells
    }

    /// The edges bounding cell `c`, in file order.
    #[must_use]
    pub fn cell_edges(&self, c: CellId) -> &[EdgeId] {
        self.cells.get(c as usize)
    }

    /// Edge `e`'s end points, start first.
    #[must_use]
    pub fn edge_points(&self, e: EdgeId) -> (Vec2, Vec2) {
        let (start, end) = self.edges.ends(e as usize);
        (self.vertex(start), self.vertex(end))
    }

    /// Edge `e`'s end points ordered counter-clockwise around `cell` (the cell on their left).
    #[must_use]
    pub fn edge_points_ccw(&self, e: EdgeId, cell: CellId) -> (Vec2, Vec2) {
        let (a, b) = self.edge_points(e);
        if self.edges.is_left_of(e as usize, cell) { (a, b) } else { (b, a) }
    }

    /// The viewer's start.
    #[must_use]
    pub fn viewer(&self) -> &Viewer {
        &self.viewer
    }

    /// The exit, if the maze has one.
    #[must_use]
    pub fn exit(&self) -> Option<&Exit> {
        self.exit.as_ref()
    }

    /// The exit's point, or its cell's centroid.
    #[must_use]
    pub fn exit_point(&self) -> Option<Vec2> {
        self.exit.map(|x| x.point.unwrap_or_else(|| self.cell_centroid(x.cell)))
    }

    /// The bounding box of all vertices.
    #[must_use]
    pub fn extents(&self) -> Aabb {
        self.extents
    }

    /// The bounding box of cell `c`.
    #[must_use]
    pub fn cell_aabb(&self, c: CellId) -> Aabb {
        cell_aabb(&self.vertices, &self.edges, &self.cells, c as usize)
    }

    /// The mean of cell `c`'s edge end points (inside, as the cell is convex).
    #[must_use]
    pub fn cell_centroid(&self, c: CellId) -> Vec2 {
        let ids = self.cell_edges(c);
        let sum: Vec2 = ids.iter().map(|&e| self.edge_points_ccw(e, c).0).sum();
        sum / ids.len() as f32
    }

    /// `true` when `p` is inside cell `c` or on its boundary (within [`ON_EDGE_TOLERANCE`]).
    #[must_use]
    pub fn cell_contains(&self, c: CellId, p: Vec2) -> bool {
        let p = p.as_dvec2();
        self.cell_edges(c).iter().all(|&e| {
            let (a, b) = self.edge_points_ccw(e, c);
            let (a, b) = (a.as_dvec2(), b.as_dvec2());
            // signed distance of p from the edge line, positive on the cell's side (left); the square
            // root only for a point on the outer side (the map asks thousands of these a frame)
            let side = (b - a).perp_dot(p - a);
            side >= 0.0 || side >= -ON_EDGE_TOLERANCE * (b - a).length()
        })
    }

    /// A cell containing `p`, or `None` outside the maze. Uses a bucket index: O(1) per query.
    #[must_use]
    pub fn cell_at(&self, p: Vec2) -> Option<CellId> {
        if !p.is_finite() {
            return None;
        }
        self.cell_index.query(p).iter().copied().find(|&c| self.cell_contains(c, p))
    }

    /// Number of transparent edges.
    #[must_use]
    pub fn portal_count(&self) -> usize {
        self.edges.len() - self.edges.opaque_count()
    }

    /// Number of opaque edges.
    #[must_use]
    pub fn wall_count(&self) -> usize {
        self.edges.opaque_count()
    }

    /// Portal steps from `from` to every cell (`u32::MAX` = unreachable), by breadth-first search.
    #[must_use]
    pub fn portal_distances(&self, from: CellId) -> Vec<u32> {
        let mut dist = vec![u32::MAX; self.cell_count()];
        let mut queue = std::collections::VecDeque::from([from]);
        dist[from as usize] = 0;
        while let Some(c) = queue.pop_front() {
            for &e in self.cell_edges(c) {
                let edge = self.edges.get(e as usize);
                if let Some(n) = edge.other_side(c).filter(|_| edge.is_portal())
                    && dist[n as usize] == u32::MAX
                {
                    dist[n as usize] = dist[c as usize] + 1;
                    queue.push_back(n);
                }
            }
        }
        dist
    }

    /// `true` when every cell can be reached from cell 0 through portals.
    #[must_use]
    pub fn is_connected(&self) -> bool {
        self.portal_distances(0).iter().all(|&d| d != u32::MAX)
    }

    /// `true` for a perfect maze: connected, and exactly one path between any two cells
    /// (portals = cells − 1). The boundary is always closed: a portal never leads outside.
    #[must_use]
    pub fn is_perfect(&self) -> bool {
        // cells − 1 portals that close no loop form one tree, which is connected
        self.portal_count() + 1 == self.cell_count() && !self.portals_close_a_loop()
    }

    /// Whether a walker can pass from cell `a` to cell `b` through portals (transparent edges), as
    /// far as the cells' links go (the width of each opening is not weighed); `false` for a cell
    /// that does not exist. Union-find over the portals, as [`Maze::is_perfect`]'s.
    #[must_use]
    pub fn connected(&self, a: CellId, b: CellId) -> bool {
        let n = self.cell_count();
        if a as usize >= n || b as usize >= n {
            return false;
        }
        let mut sets = CellSets::new(n);
        for edge in self.edges.iter().filter(Edge::is_portal) {
            let (Some(l), Some(r)) = (edge.left, edge.right) else { continue };
            sets.join(l, r);
        }
        sets.root(a) == sets.root(b)
    }

    /// `true` when some portals form a cycle: union-find over the portals in id order, with path
    /// halving (neighbouring ids are neighbouring cells in the usual maze, so this runs in cache
    /// where a breadth-first search hops across the maze: `check` of the 1000 × 1000 grid file,
    /// 2 M cells, took 1.1–1.3 s of CPU with the search and 0.7–0.8 s with this).
    fn portals_close_a_loop(&self) -> bool {
        let mut sets = CellSets::new(self.cell_count());
        for edge in self.edges.iter().filter(Edge::is_portal) {
            let (Some(l), Some(r)) = (edge.left, edge.right) else { continue };
            if !sets.join(l, r) {
                return true;
            }
        }
        false
    }
}

/// Union-find over a maze's cells, with path halving; a set's root is its least cell id.
struct CellSets(Vec<CellId>);

impl CellSets {
    /// `n` cells, each a set of its own.
    fn new(n: usize) -> CellSets {
        CellSets((0..n as CellId).collect())
    }

    /// The root of `c`'s set.
    fn root(&mut self, mut c: CellId) -> CellId {
        let parent = &mut self.0;
        while parent[c as usize] != c {
            let grand = parent[parent[c as usize] as usize];
            parent[c as usize] = grand;
            c = grand;
        }
        c
    }

    /// Joins the sets of `a` and `b`: `false` when they were one set already.
    fn join(&mut self, a: CellId, b: CellId) -> bool {
        let (a, b) = (self.root(a), self.root(b));
        if a == b {
            return false;
        }
        self.0[a.max(b) as usize] = a.min(b);
        true
    }
}

/// Edges from which [`Maze::new`] checks crossings on a second thread (spawning one costs tens of µs).
const PARALLEL_CHECK_EDGES: usize = 1 << 14;

/// The extents of the vertices, and the cells by bucket, for [`Maze::cell_at`]: for checked cells.
fn cell_index(vertices: &[Vec2], edges: &Edges, cells: &Cells, threads: Threads) -> (Aabb, SpatialGrid) {
    let extents = extents(vertices);
    // boxes grown by the tolerance, so a point that counts as in a cell finds it
    let cell_box = |c| cell_aabb(vertices, edges, cells, c).expand(ON_EDGE_TOLERANCE as f32);
    (extents, SpatialGrid::build(cells.len(), cell_box, extents, threads))
}

/// The bounding box of `vertices`.
fn extents(vertices: &[Vec2]) -> Aabb {
    vertices.iter().fold(Aabb::EMPTY, |b, &v| b.union_point(v))
}

/// The box of cell `c`, a closed loop: every corner starts one of its edges counter-clockwise, so
/// one end point per edge is enough.
fn cell_aabb(vertices: &[Vec2], edges: &Edges, cells: &Cells, c: usize) -> Aabb {
    cells.get(c).iter().fold(Aabb::EMPTY, |b, &e| {
        let edge = edges.packed[e as usize]; // not `get`: no flag or colour needed
        let corner = if edge.left == c as CellId { edge.start } else { edge.end };
        b.union_point(vertices[corner as usize])
    })
}

/// Twice the signed area of triangle (a, b, c), in f64: positive when counter-clockwise.
fn orient(a: DVec2, b: DVec2, c: DVec2) -> f64 {
    (b - a).perp_dot(c - a)
}
