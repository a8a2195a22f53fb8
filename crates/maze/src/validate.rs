//! The checks behind [`Maze::new`](super::Maze::new).

use glam::{DVec2, Vec2};

use super::geometry::{CLEARANCE_SHARE, WALL_MARGIN};
use super::index::{SpatialGrid, Threads};
use super::movement;
use super::sweep::{self, Conflict, conflict};
use super::{
    Aabb, COORD_BOUND, CellId, Cells, EdgeId, Edges, MIN_CELL_AREA, Maze, MazeError, ON_EDGE_TOLERANCE,
    VertexId,
};

/// Indices, sides, cell ↔ edge consistency, and each cell a closed convex counter-clockwise loop.
pub(super) fn structure(vertices: &[Vec2], edges: &Edges, cells: &Cells) -> Result<(), MazeError> {
    let max = u32::MAX as usize - 1;
    for (what, count) in [("vertices", vertices.len()), ("edges", edges.len()), ("cells", cells.len())] {
        if count > max {
            return Err(MazeError::TooMany { what, count, max });
        }
    }
    if cells.is_empty() {
        return Err(MazeError::NoCells);
    }
    for (v, p) in vertices.iter().enumerate() {
        if !(p.is_finite() && p.abs().max_element() <= COORD_BOUND) {
            return Err(MazeError::VertexOutOfBounds { vertex: v as VertexId });
        }
    }
    let nc = cells.len();
    for (e, edge) in edges.iter().enumerate() {
        let edge_id = e as EdgeId;
        for vertex in [edge.start, edge.end] {
            if vertex as usize >= vertices.len() {
                return Err(MazeError::EdgeVertexOutOfRange { edge: edge_id, vertex, count: vertices.len() });
            }
        }
        if vertices[edge.start as usize] == vertices[edge.end as usize] {
            return Err(MazeError::EdgeDegenerate { edge: edge_id, start: edge.start, end: edge.end });
        }
        for cell in [edge.left, edge.right].into_iter().flatten() {
            if cell as usize >= nc {
                return Err(MazeError::EdgeCellOutOfRange { edge: edge_id, cell, count: nc });
            }
        }
        match (edge.left, edge.right) {
            (None, None) => return Err(MazeError::EdgeNoCell { edge: edge_id }),
            (Some(l), Some(r)) if l == r => {
                return Err(MazeError::EdgeSameCellBothSides { edge: edge_id, cell: l });
            }
            (None, _) | (_, None) if !edge.opaque => {
                return Err(MazeError::PortalToOutside { edge: edge_id });
            }
            _ => {}
        }
        if !edge.color.is_finite() || edge.color.min_element() < 0.0 || edge.color.max_element() > 1.0 {
            return Err(MazeError::EdgeColor { edge: edge_id });
        }
    }
    // each (edge, side) names a cell that lists the edge, and vice versa: count the listings
    let mut listed = vec![0u8; edges.len()];
    for c in 0..nc {
        let cell = c as CellId;
        for &e in cells.get(c) {
            if e as usize >= edges.len() {
                return Err(MazeError::CellEdgeOutOfRange { cell, edge: e, count: edges.len() });
            }
            let edge = edges.get(e as usize);
            if edge.left != Some(cell) && edge.right != Some(cell) {
                return Err(MazeError::CellEdgeNotNeighbour { cell, edge: e });
            }
            listed[e as usize] += 1;
            if listed[e as usize] > u8::from(edge.left.is_some()) + u8::from(edge.right.is_some()) {
                return Err(MazeError::CellEdgeDuplicate { cell, edge: e });
            }
        }
    }
    for (e, edge) in edges.iter().enumerate() {
        if listed[e] != u8::from(edge.left.is_some()) + u8::from(edge.right.is_some()) {
            // find the side whose cell does not list it
            for (side, cell) in [("left", edge.left), ("right", edge.right)] {
                if let Some(cell) = cell
                    && !cells.get(cell as usize).contains(&(e as EdgeId))
                {
                    return Err(MazeError::CellMissingEdge { edge: e as EdgeId, cell, side });
                }
            }
        }
    }
    let mut scratch = Vec::new();
    for c in 0..nc {
        cell_loop(vertices, edges, cells, c as CellId, &mut scratch)?;
    }
    Ok(())
}

/// Cell `c`'s edges, each oriented with the cell on its left, chain into one convex
/// counter-clockwise loop.
fn cell_loop(
    vertices: &[Vec2],
    edges: &Edges,
    cells: &Cells,
    c: CellId,
    directed: &mut Vec<(VertexId, VertexId)>,
) -> Result<(), MazeError> {
    let ids = cells.get(c as usize);
    if ids.len() < 3 {
        return Err(MazeError::CellTooFewEdges { cell: c, count: ids.len() });
    }
    directed.clear();
    directed.extend(ids.iter().map(|&e| {
        let edge = edges.get(e as usize);
        if edge.left == Some(c) { (edge.start, edge.end) } else { (edge.end, edge.start) }
    }));
    // small cells (the usual 4 edges) search linearly; big ones sort and bisect
    let small = directed.len() <= 8;
    if small {
        for (i, d) in directed.iter().enumerate() {
            if directed[..i].iter().any(|e| e.0 == d.0) {
                return Err(MazeError::CellNotClosed { cell: c, vertex: d.0 });
            }
        }
    } else {
        directed.sort_unstable();
        // each vertex starts exactly one edge of the loop
        if let Some(w) = directed.windows(2).find(|w| w[0].0 == w[1].0) {
            return Err(MazeError::CellNotClosed { cell: c, vertex: w[0].0 });
        }
    }
    let p = |v: VertexId| vertices[v as usize].as_dvec2();
    let first = directed[0];
    let (mut from, mut to) = first;
    let mut twice_area = 0.0;
    let mut steps = 0;
    let mut concave_at = None; // reported after the orientation, which explains more
    loop {
        let found = if small {
            directed.iter().position(|d| d.0 == to)
        } else {
            directed.binary_search_by_key(&to, |d| d.0).ok()
        };
        let Some(i) = found else {
            return Err(MazeError::CellNotClosed { cell: c, vertex: to });
        };
        let next = directed[i].1;
        let (a, b, n) = (p(from), p(to), p(next));
        let (u, v) = (b - a, n - b);
        // a right turn, or a straight-back spike, breaks convexity (tolerance for rounding)
        if concave_at.is_none()
            && (u.perp_dot(v) < -1e-9 * u.length() * v.length() || (u.perp_dot(v) <= 0.0 && u.dot(v) < 0.0))
        {
            concave_at = Some(to);
        }
        twice_area += a.perp_dot(b);
        (from, to) = (to, next);
        steps += 1;
        if (from, to) == first {
            break;
        }
        if steps >= directed.len() {
            return Err(MazeError::CellNotClosed { cell: c, vertex: to });
        }
    }
    // one loop through every edge, not two smaller ones
    if steps != directed.len() {
        return Err(MazeError::CellNotClosed { cell: c, vertex: first.0 });
    }
    if twice_area <= 0.0 {
        return Err(MazeError::CellClockwise { cell: c });
    }
    if twice_area / 2.0 < MIN_CELL_AREA {
        return Err(MazeError::CellTooSmall { cell: c, area: twice_area / 2.0 });
    }
    match concave_at {
        Some(vertex) => Err(MazeError::CellNotConvex { cell: c, vertex }),
        None => Ok(()),
    }
}

/// No two edges cross or overlap; they may share end points (or one may end on another).
///
/// A bucket grid finds the candidate pairs in O(n) when the buckets stay small; long edges (a comb
/// of tall thin cells, long diagonals) crowd every bucket, so when the grid would test more than a
/// few pairs per edge, the Shamos–Hoey sweep ([`sweep`]) decides in O(n log n) instead.
///
/// Only from the vertices and edges, so it can run while the cells are checked: when a vertex is
/// out of bounds or an edge's end out of range or at its start, it says `Ok` and leaves the error to
/// [`structure`], which reports it first.
pub(super) fn crossings_of_parts(vertices: &[Vec2], edges: &Edges) -> Result<(), MazeError> {
    let n = vertices.len();
    let usable = vertices.iter().all(|p| p.is_finite() && p.abs().max_element() <= COORD_BOUND)
        && (0..edges.len()).map(|e| edges.ends(e)).all(|(start, end)| {
            (start as usize) < n && (end as usize) < n && vertices[start as usize] != vertices[end as usize]
        });
    if !usable {
        return Ok(());
    }
    let extents = super::extents(vertices);
    let n = edges.len();
    let segment = |e: usize| {
        let (start, end) = edges.ends(e);
        [vertices[start as usize], vertices[end as usize]]
    };
    let edge_box = |e: usize| {
        let [a, b] = segment(e);
        Aabb { min: a.min(b), max: a.max(b) }
    };
    // one thread: a big maze runs this beside the cell checks (`Maze::new`)
    let grid = SpatialGrid::build(n, edge_box, extents, Threads::One);
    let pairs: usize = (0..grid.bucket_count()).map(|b| grid.bucket_items(b).len()).map(|k| k * k / 2).sum();
    let found = if pairs > PAIRS_PER_EDGE * n + 1024 {
        drop(grid);
        sweep::first_conflict(n, |e| segment(e as usize))
    } else {
        grid_conflict(&grid, edge_box, segment)
    };
    match found {
        None => Ok(()),
        Some((a, b, Conflict::Cross)) => Err(MazeError::EdgesCross { a, b }),
        Some((a, b, _)) => Err(MazeError::EdgesOverlap { a, b }),
    }
}

/// Candidate pairs per edge above which the sweep is used (an ordinary maze's grid tests about 4).
const PAIRS_PER_EDGE: usize = 32;

/// The bad pair with the smallest bucket, testing every pair that shares a bucket.
fn grid_conflict(
    grid: &SpatialGrid,
    edge_box: impl Fn(usize) -> Aabb,
    segment: impl Fn(usize) -> [Vec2; 2],
) -> Option<(u32, u32, Conflict)> {
    for bucket in 0..grid.bucket_count() {
        let items = grid.bucket_items(bucket);
        for (i, &a) in items.iter().enumerate() {
            let (box_a, [p1, p2]) = (edge_box(a as usize), segment(a as usize));
            for &b in &items[i + 1..] {
                if !box_a.intersects(&edge_box(b as usize)) {
                    continue; // the common case: cheap to rule out
                }
                let [q1, q2] = segment(b as usize);
                match conflict(p1.as_dvec2(), p2.as_dvec2(), q1.as_dvec2(), q2.as_dvec2()) {
                    Conflict::None => {}
                    c => return Some((a.min(b), a.max(b), c)),
                }
            }
        }
    }
    None
}

/// No cell lies inside another. Edges do not cross (checked before), so two convex cells can share
/// area only when one holds the other whole, and then the inner one's centre (the mean of its corners)
/// lies strictly inside the outer one: one point location a cell. Strictly, with no tolerance: the
/// centre of a sliver beside a cell lies within the point location's tolerance of that cell. Of two
/// that overlap, the smaller is the inner one.
///
/// The point location tests the cells whose boxes hold the bucket of the point: a handful in an
/// ordinary maze, but long or thin cells (a fan round one corner, long diagonal corridors) crowd
/// every bucket. When the locations would test more than a few cells a cell, the sweep
/// ([`sweep::first_overlap`]) decides in O(n log n) instead.
pub(super) fn nesting(maze: &Maze) -> Result<(), MazeError> {
    let cells = maze.cell_count();
    nesting_within(maze, CANDIDATES_PER_CELL * cells + 1024)
}

/// Point-location candidates per cell above which the sweep decides (an ordinary maze tests 1–4).
const CANDIDATES_PER_CELL: usize = 32;

/// [`nesting`], by point location while it tests at most `budget` candidates, else by the sweep.
fn nesting_within(maze: &Maze, budget: usize) -> Result<(), MazeError> {
    let corners =
        |c: CellId| maze.cell_edges(c).iter().map(move |&e| maze.edge_points_ccw(e, c).0.as_dvec2());
    let strictly_inside = |c: CellId, p: DVec2| {
        maze.cell_edges(c).iter().all(|&e| {
            let (a, b) = maze.edge_points_ccw(e, c);
            let (a, b) = (a.as_dvec2(), b.as_dvec2());
            (b - a).perp_dot(p - a) > 0.0
        })
    };
    // (The shoelace sum over the cell's edges, each from the end its cell is left of: any order.)
    let twice_area = |c: CellId| -> f64 {
        let edges = maze.cell_edges(c).iter().map(|&e| maze.edge_points_ccw(e, c));
        edges.map(|(a, b)| a.as_dvec2().perp_dot(b.as_dvec2())).sum()
    };
    let inner_first = |(a, b): (CellId, CellId)| if twice_area(a) <= twice_area(b) { (a, b) } else { (b, a) };
    // The first overlap among cells `range`, by the lower cell of the two; `Err` past the budget.
    let first_in = |range: std::ops::Range<CellId>, mut budget: usize| -> Result<_, Crowded> {
        for c in range {
            let centre = corners(c).sum::<DVec2>() / maze.cell_edges(c).len() as f64;
            let candidates = maze.cell_index.query(centre.as_vec2());
            budget = budget.checked_sub(candidates.len()).ok_or(Crowded)?;
            if let Some(other) = candidates.iter().copied().find(|&o| o != c && strictly_inside(o, centre)) {
                return Ok(Some(inner_first((c, other))));
            }
        }
        Ok(None)
    };
    let cells = maze.cell_count() as CellId;
    // A big maze on two threads (a million cells: 0.1 s each), the error the same as on one.
    let located = if maze.edges.len() >= super::PARALLEL_CHECK_EDGES {
        let half = cells / 2;
        std::thread::scope(|s| {
            let second = s.spawn(|| first_in(half..cells, budget / 2));
            let first = first_in(0..half, budget / 2);
            let second = second.join().unwrap_or_else(|panic| std::panic::resume_unwind(panic));
            Ok(first?.or(second?))
        })
    } else {
        first_in(0..cells, budget)
    };
    let found = located.unwrap_or_else(|Crowded| {
        let edges = &maze.edges;
        let segment = |e: u32| {
            let (start, end) = edges.ends(e as usize);
            [maze.vertices[start as usize], maze.vertices[end as usize]]
        };
        let sides = |e: u32| {
            let edge = edges.get(e as usize);
            [edge.left, edge.right]
        };
        sweep::first_overlap(edges.len(), segment, sides).map(inner_first)
    });
    match found {
        Some((cell, other)) => Err(MazeError::CellsOverlap { cell, other }),
        None => Ok(()),
    }
}

/// The point location would test too many cells.
struct Crowded;

/// The viewer finite, at a sane height and fov, in a cell; the exit in range.
#[allow(clippy::nonminimal_bool)] // written as "not (valid)" so NaN fails every test
pub(super) fn viewer_and_exit(maze: &Maze) -> Result<(), MazeError> {
    let v = maze.viewer();
    if !(v.pos.is_finite() && v.pos.abs().max_element() <= COORD_BOUND)
        || !v.z.is_finite()
        || !(v.dir_deg.is_finite() && v.dir_deg.abs() <= COORD_BOUND)
        || !v.fov_deg.is_finite()
    {
        return Err(MazeError::ViewerNotFinite);
    }
    if !(v.z > -1.0 && v.z < 1.0) {
        return Err(MazeError::ViewerHeight { z: v.z });
    }
    if !(v.fov_deg > 0.0 && v.fov_deg < 180.0) {
        return Err(MazeError::ViewerFov { fov_deg: v.fov_deg });
    }
    let Some(cell) = maze.cell_at(v.pos) else {
        return Err(MazeError::ViewerOutside { x: v.pos.x, y: v.pos.y });
    };
    // on a wall line or vertex, the viewer could walk along the wall at distance 0. A wall through
    // the point lies in the box of a cell it borders, and the index lists every cell whose box holds
    // the point: those are all searched, the cell found and its portal neighbours first (the wall
    // the message names, when several pass through the point)
    let on_wall = |c: CellId| {
        maze.cell_edges(c).iter().copied().find(|&e| {
            let (a, b) = maze.edge_points(e);
            maze.edge(e).opaque
                && segment_distance(v.pos.as_dvec2(), a.as_dvec2(), b.as_dvec2()) <= ON_EDGE_TOLERANCE
        })
    };
    let near = std::iter::once(cell)
        .chain(maze.cell_edges(cell).iter().filter_map(|&e| {
            let edge = maze.edge(e);
            edge.other_side(cell).filter(|_| edge.is_portal())
        }))
        .chain(maze.cell_index.query(v.pos).iter().copied());
    for c in near {
        if let Some(edge) = on_wall(c) {
            return Err(MazeError::ViewerOnWall { x: v.pos.x, y: v.pos.y, edge });
        }
    }
    // The walk keeps the viewer a disc of the maze's clearance (WALL_MARGIN or more) round clear of every wall (the renderer's near
    // plane lies inside it) and moves a viewer closer out when it starts; a cell narrower than the
    // disc has no such place, and from its middle the near plane would cut every wall away.
    let stands = movement::settle(maze, movement::Position { cell, pos: v.pos }, maze.clearance());
    if !movement::is_clear(maze, stands, maze.clearance()) {
        let (x, y, margin) = (v.pos.x, v.pos.y, maze.clearance());
        return Err(MazeError::ViewerNoRoom { x, y, cell, margin });
    }
    if let Some(exit) = maze.exit() {
        if exit.cell as usize >= maze.cell_count() {
            return Err(MazeError::ExitCellOutOfRange { cell: exit.cell, count: maze.cell_count() });
        }
        if let Some(p) = exit.point
            && !maze.cell_contains(exit.cell, p)
        {
            return Err(MazeError::ExitPointOutside { cell: exit.cell, x: p.x, y: p.y });
        }
    }
    Ok(())
}

/// Distance from `p` to the segment `a`–`b`.
fn segment_distance(p: DVec2, a: DVec2, b: DVec2) -> f64 {
    let ab = b - a;
    let t = ((p - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0);
    (a + ab * t).distance(p)
}

/// Cells with more edges than this count in [`narrowest_passage`] as narrow as gives [`WALL_MARGIN`]
/// (its cost grows with the square of a cell's edges; no maker draws such cells).
const MAX_WIDTH_EDGES: usize = 64;

/// The narrowest passage of a maze: the least width of its cells (a convex cell's width is the least,
/// over its edges, of its farthest vertex from the edge's line) and the shortest opening between two
/// cells. `∞` for no cells. The parts must have passed [`structure`].
pub(crate) fn narrowest_passage(vertices: &[Vec2], edges: &Edges, cells: &Cells) -> f32 {
    let point = |v: VertexId| vertices.get(v as usize).copied().unwrap_or(Vec2::NAN);
    // The least of the cells' widths, two halves on two threads in a large maze (a minimum: the same
    // whichever half is done first).
    let n = cells.len();
    let widths = |range: std::ops::Range<usize>| narrowest_width(point, edges, cells, range);
    let mut narrowest = if n >= PARALLEL_CELLS {
        std::thread::scope(|scope| {
            let second = scope.spawn(|| widths(n / 2..n));
            let first = widths(0..n / 2);
            match second.join() {
                Ok(second) => first.min(second),
                Err(panic) => std::panic::resume_unwind(panic), // as one thread would have
            }
        })
    } else {
        widths(0..n)
    };
    for edge in edges.iter().filter(|e| !e.opaque && e.left.is_some() && e.right.is_some()) {
        narrowest = narrowest.min(point(edge.start).distance(point(edge.end)));
    }
    narrowest
}

/// Cells from which [`narrowest_passage`] takes a second thread.
const PARALLEL_CELLS: usize = 1 << 15;

/// The least width of `cells` in `range` (`∞` for none), by [`narrowest_passage`]'s definition.
fn narrowest_width(
    point: impl Fn(VertexId) -> Vec2,
    edges: &Edges,
    cells: &Cells,
    range: std::ops::Range<usize>,
) -> f32 {
    let mut narrowest = f32::INFINITY;
    // A cell's edges' ends, each edge's (start, end) in turn: read once a cell, then scanned once an
    // edge (a million-cell maze's load spent most of its time fetching them edge by edge).
    let mut ends = [Vec2::ZERO; 2 * MAX_WIDTH_EDGES];
    for c in range {
        let ids = cells.get(c);
        if ids.len() > MAX_WIDTH_EDGES {
            narrowest = narrowest.min(WALL_MARGIN / CLEARANCE_SHARE);
            continue;
        }
        let ends = &mut ends[..2 * ids.len()];
        for (pair, &e) in ends.chunks_exact_mut(2).zip(ids) {
            let edge = edges.get(e as usize);
            (pair[0], pair[1]) = (point(edge.start), point(edge.end));
        }
        for pair in ends.chunks_exact(2) {
            let a = pair[0];
            let along = (pair[1] - a).normalize_or_zero();
            let far = ends.iter().map(|&p| along.perp_dot(p - a).abs()).fold(0.0f32, f32::max);
            narrowest = narrowest.min(far);
        }
    }
    narrowest
}

#[cfg(test)]
mod tests {
    use glam::{Vec3, vec2};
    use proptest::prelude::*;

    use super::*;
    use crate::Edge;
    use crate::generate::{Algorithm, GenOptions, generate};

    /// A generated maze with one more cell added, a convex polygon of `corners` (counter-clockwise),
    /// walls all round; built as `Maze::new` builds it, but unchecked.
    fn with_cell(maze: &Maze, corners: &[Vec2]) -> Maze {
        let (mut vertices, mut edges, mut cells) =
            (maze.vertices.clone(), maze.edges.clone(), maze.cells.clone());
        let (first_vertex, first_edge, cell) =
            (vertices.len() as u32, edges.len() as u32, cells.len() as u32);
        vertices.extend(corners);
        let k = corners.len() as u32;
        for i in 0..k {
            let (start, end) = (first_vertex + i, first_vertex + (i + 1) % k);
            edges.push(Edge { start, end, left: Some(cell), right: None, opaque: true, color: Vec3::ONE });
        }
        cells.push(&(first_edge..first_edge + k).collect::<Vec<_>>());
        let (extents, cell_index) = super::super::cell_index(&vertices, &edges, &cells, Threads::One);
        Maze::assemble(vertices, edges, cells, *maze.viewer(), None, extents, cell_index)
    }

    /// Cell `c`'s corners, counter-clockwise.
    fn corners(maze: &Maze, c: CellId) -> Vec<Vec2> {
        let mut at: Vec<Vec2> = maze.cell_edges(c).iter().map(|&e| maze.edge_points_ccw(e, c).0).collect();
        let centre = at.iter().sum::<Vec2>() / at.len() as f32;
        at.sort_by(|a, b| (*a - centre).to_angle().total_cmp(&(*b - centre).to_angle()));
        at
    }

    fn maze(side: (u32, u32), seed: u64, loops: f32) -> Maze {
        let (width, height) = side;
        let algorithm = [Algorithm::Prim, Algorithm::Backtracker, Algorithm::Wilson][seed as usize % 3];
        generate(&GenOptions { width, height, algorithm, seed, loops, ..GenOptions::default() }).unwrap()
    }

    /// [`narrowest_passage`] as its doc defines it, edge by edge: the oracle of its fast path.
    fn narrowest_by_definition(m: &Maze) -> f32 {
        let point = |v: VertexId| m.vertices[v as usize];
        let mut least = f32::INFINITY;
        for c in 0..m.cells.len() {
            let ids = m.cells.get(c);
            for &e in ids {
                let edge = m.edges.get(e as usize);
                let (a, b) = (point(edge.start), point(edge.end));
                let along = (b - a).normalize_or_zero();
                let far = ids
                    .iter()
                    .map(|&o| m.edges.get(o as usize))
                    .flat_map(|o| [point(o.start), point(o.end)])
                    .map(|p| along.perp_dot(p - a).abs())
                    .fold(0.0f32, f32::max);
                least = least.min(far);
            }
        }
        for edge in m.edges.iter().filter(|e| !e.opaque && e.left.is_some() && e.right.is_some()) {
            least = least.min(point(edge.start).distance(point(edge.end)));
        }
        least
    }

    /// A maze past [`PARALLEL_CELLS`], its cells' widths on two threads: the same bits as the
    /// definition's, with a thin cell added last (in the second thread's half) and without it.
    #[test]
    fn a_large_mazes_narrowest_passage_on_two_threads_is_its_definition() {
        let options = GenOptions { width: 200, height: 200, seed: 5, loops: 0.2, ..GenOptions::default() };
        let big = generate(&options).unwrap();
        assert!(big.cell_count() >= PARALLEL_CELLS, "the premise: {} cells", big.cell_count());
        let thin = with_cell(&big, &[vec2(-3.0, -3.0), vec2(-1.0, -3.0), vec2(-3.0, -2.9)]);
        for m in [&big, &thin] {
            let fast = narrowest_passage(&m.vertices, &m.edges, &m.cells);
            assert_eq!(fast.to_bits(), narrowest_by_definition(m).to_bits());
        }
        assert!(narrowest_passage(&thin.vertices, &thin.edges, &thin.cells) < 0.2, "the thin cell counts");
    }

    proptest! {
        // Each case generates and validates a maze: 256 cases, proptest's own default.
        #![proptest_config(mazewalk_testkit::config_cases(256))]

        /// The point location (an unbounded budget) and the sweep (none) agree: nothing overlaps in a
        /// generated maze; a cell shrunk inside one of its cells, toward any point inside it, lies
        /// inside that one; and a box round the whole maze holds every cell.
        #[test]
        fn the_sweep_and_the_point_location_find_the_same_overlaps(
            side in (1u32..7, 1u32..7),
            seed in 0u64..1000,
            loops in 0.0f32..1.0,
            host in any::<prop::sample::Index>(),
            toward in (0.01f32..1.0, 0.01f32..1.0, 0.01f32..1.0),
            scale in 0.01f32..0.99,
        ) {
            let maze = maze(side, seed, loops);
            let both = |m: &Maze| (nesting_within(m, usize::MAX), nesting_within(m, 0));
            prop_assert_eq!(both(&maze), (Ok(()), Ok(())));
            let host = host.index(maze.cell_count()) as CellId;
            let around = corners(&maze, host);
            let weights = [toward.0, toward.1, toward.2];
            let inside = around.iter().zip(weights.iter().cycle()).map(|(&p, &w)| p * w).sum::<Vec2>()
                / around.iter().zip(weights.iter().cycle()).map(|(_, &w)| w).sum::<f32>();
            let shrunk: Vec<Vec2> = around.iter().map(|&p| inside + (p - inside) * scale).collect();
            let inner = with_cell(&maze, &shrunk);
            let want = Err(MazeError::CellsOverlap { cell: maze.cell_count() as CellId, other: host });
            prop_assert_eq!(both(&inner), (want.clone(), want));
            let e = maze.extents();
            let (lo, hi) = (e.min - 1.0, e.max + 1.0);
            let round = with_cell(&maze, &[lo, vec2(hi.x, lo.y), hi, vec2(lo.x, hi.y)]);
            let all = maze.cell_count() as CellId;
            for found in [nesting_within(&round, usize::MAX), nesting_within(&round, 0)] {
                prop_assert!(matches!(found, Err(MazeError::CellsOverlap { cell, other }) if cell < all && other == all), "{:?}", found);
            }
        }

        /// `narrowest_passage` is its definition, bit for bit: the least, over every cell's edges, of
        /// the farthest of the cell's edge ends from the edge's line, and over the openings their
        /// lengths. Generated mazes, and each with a random convex cell of 3–9 corners added.
        #[test]
        fn the_narrowest_passage_is_its_definition(
            side in (1u32..7, 1u32..7),
            seed in 0u64..1000,
            loops in 0.0f32..1.0,
            corners in 3usize..10,
            radius in 0.05f32..20.0,
            turn in 0.0f32..1.0,
        ) {
            let maze = maze(side, seed, loops);
            let far_corner = maze.extents().max + radius + 1.0;
            let ring: Vec<Vec2> = (0..corners)
                .map(|k| {
                    let angle = (k as f32 + turn) / corners as f32 * std::f32::consts::TAU;
                    far_corner + Vec2::from_angle(angle) * radius
                })
                .collect();
            for m in [maze.clone(), with_cell(&maze, &ring)] {
                let fast = narrowest_passage(&m.vertices, &m.edges, &m.cells);
                prop_assert_eq!(fast.to_bits(), narrowest_by_definition(&m).to_bits());
            }
        }
    }

    /// A fan of thin triangles round one corner crowds every bucket of the point location: the
    /// check goes to the sweep, which finds the cell inside one of them.
    #[test]
    fn a_fan_of_thin_cells_is_checked_by_the_sweep() {
        let n = 2000;
        let rim = |k: u32| {
            let a = std::f32::consts::TAU * (k % n) as f32 / n as f32;
            vec2(a.cos(), a.sin()) * 1000.0
        };
        let mut vertices = vec![Vec2::ZERO];
        vertices.extend((0..n).map(rim));
        let (mut edges, mut cells) = (Edges::new(), Cells::new());
        let grey = Vec3::splat(0.5);
        for k in 0..n {
            // spoke k from the centre to rim k: triangle k on its left, k - 1 on its right
            let (left, right) = (Some(k), Some((k + n - 1) % n));
            edges.push(Edge { start: 0, end: k + 1, left, right, opaque: false, color: grey });
        }
        for k in 0..n {
            let (start, end) = (k + 1, (k + 1) % n + 1);
            edges.push(Edge { start, end, left: Some(k), right: None, opaque: true, color: grey });
            cells.push(&[k, n + k, (k + 1) % n]);
        }
        let (extents, cell_index) = super::super::cell_index(&vertices, &edges, &cells, Threads::One);
        let viewer = crate::Viewer { pos: (rim(0) + rim(1)) / 3.0, z: 0.0, dir_deg: 0.0, fov_deg: 90.0 };
        let fan = Maze::assemble(vertices, edges, cells, viewer, None, extents, cell_index);
        let crowded = || {
            let centre = corners(&fan, 700).iter().sum::<Vec2>() / 3.0;
            fan.cell_index.query(centre).len()
        };
        assert!(crowded() > CANDIDATES_PER_CELL, "the premise: {} candidates", crowded());
        assert_eq!(nesting(&fan), Ok(()));
        let centre = corners(&fan, 700).iter().sum::<Vec2>() / 3.0;
        let shrunk: Vec<Vec2> = corners(&fan, 700).iter().map(|&p| centre + (p - centre) * 0.5).collect();
        let inner = with_cell(&fan, &shrunk);
        assert_eq!(nesting(&inner), Err(MazeError::CellsOverlap { cell: n, other: 700 }));
    }

    #[test]
    fn the_clearance_is_two_fifths_of_the_narrowest_passage() {
        let parse = |text: &str| crate::parse("t.grid", text.as_bytes()).unwrap();
        let grid = |tile: f32| parse(&format!("mazewalk-grid 1\ntile {tile}\n#####\n#@..#\n#.#.#\n#####\n"));
        assert_eq!(grid(4.0).clearance(), 1.6, "2/5 of a 4-unit corridor");
        assert_eq!(grid(2.0).clearance(), 0.8);
        assert_eq!(grid(0.6).clearance(), WALL_MARGIN, "never less than the near plane needs");
        assert_eq!(grid(40.0).clearance(), 1.6, "never more than 2/5 of a generated corridor");
        for seed in 0..4 {
            let m = generate(&GenOptions { width: 7, height: 5, seed, loops: 0.3, ..GenOptions::default() })
                .unwrap();
            assert_eq!(m.clearance(), 1.6);
        }
        // Two 4 × 4 rooms whose shared side is a 1.5-wide opening between two walls: the opening counts.
        let v = [(0., 0.), (4., 0.), (4., 1.), (4., 2.5), (4., 4.), (0., 4.), (8., 0.), (8., 4.)];
        let vertices: Vec<Vec2> = v.iter().map(|&(x, y)| vec2(x, y)).collect();
        let wall = |start, end, left| Edge {
            start,
            end,
            left: Some(left),
            right: None,
            opaque: true,
            color: Vec3::ONE,
        };
        let mut edges: Edges =
            [wall(0, 1, 0), wall(4, 5, 0), wall(5, 0, 0), wall(1, 6, 1), wall(6, 7, 1), wall(7, 4, 1)]
                .into_iter()
                .collect();
        let e = edges.len() as u32;
        edges.push(Edge { start: 1, end: 2, left: Some(0), right: Some(1), opaque: true, color: Vec3::ONE });
        edges.push(Edge { start: 2, end: 3, left: Some(0), right: Some(1), opaque: false, color: Vec3::ONE });
        edges.push(Edge { start: 3, end: 4, left: Some(0), right: Some(1), opaque: true, color: Vec3::ONE });
        let mut cells = Cells::new();
        cells.push(&[0, e, e + 1, e + 2, 1, 2]);
        cells.push(&[3, 4, 5, e + 2, e + 1, e]);
        let viewer = crate::Viewer { pos: vec2(2.0, 2.0), z: 0.0, dir_deg: 0.0, fov_deg: 90.0 };
        let m = Maze::new(vertices, edges, cells, viewer, None).unwrap();
        assert_eq!(m.clearance(), 1.5 * 0.4);
    }
}
