//! Moving the viewer: cross portals, stop `radius` short of walls, slide along them.
//!
//! The viewer is a disc of radius `radius` in the maze plane. [`step`] sweeps it along the motion
//! and stops at the first contact with any opaque edge (its flat sides or its end points), removes
//! the into-wall part of what is left and sweeps again (sliding; a corner stops it). Being a sweep,
//! a step of any length cannot tunnel through a wall. All collision arithmetic is in `f64`.
//!
//! ```
//! # use mazewalk_maze::{self as maze, movement::{Position, step}};
//! # let text = "4 0 0 4 0 0 4 4 4  4 0 1 0 -1 1 1 1 1  2 3 -1 0 1 1 1 1  0 2 -1 0 1 1 1 1  1 3 0 -1 1 1 1 1
//! #             1 3 1 2 0  2 2 0 0 90";
//! # let maze = maze::parse("room", text.as_bytes())?;
//! let here = Position::of_viewer(&maze);
//! let there = step(&maze, here, glam::vec2(10.0, 0.0), 0.25); // run east into the wall at x = 4
//! assert!((there.pos.x - 3.75).abs() < 1e-3 && there.pos.y == 2.0);
//! # Ok::<(), maze::ParseError>(())
//! ```

use std::collections::{HashSet, VecDeque};

use glam::{DVec2, Vec2};

use super::{Aabb, CellId, Maze};

/// The viewer's place: a point and the cell holding it (tracked, so no search is needed).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Position {
    /// The cell containing `pos` (boundary included).
    pub cell: CellId,
    /// The point in the maze plane.
    pub pos: Vec2,
}

impl Position {
    /// The maze's viewer start.
    #[must_use]
    pub fn of_viewer(maze: &Maze) -> Position {
        let pos = maze.viewer().pos;
        // Maze::new checked that the viewer is in a cell
        Position { cell: maze.cell_at(pos).unwrap_or(0), pos }
    }
}

/// Distance kept beyond `radius` after a contact, so rounding never lands inside the margin.
pub const SKIN: f64 = 1e-4;
/// Contacts handled per step: enough to slide along one wall into a corner and stop.
const MAX_SLIDES: usize = 4;

/// Moves from `from` by `delta`, never bringing the viewer closer than `radius` to an opaque edge
/// (flat side or end point), sliding along walls hit at an angle. Portals are crossed and the
/// returned cell contains the returned point. Non-finite input returns `from` unchanged.
///
/// # Panics
/// In debug builds, if `from.cell` is not a cell of `maze`.
#[must_use]
pub fn step(maze: &Maze, from: Position, delta: Vec2, radius: f32) -> Position {
    sweep(maze, from, delta, radius, None)
}

/// Like [`step`], also returning the path taken: the start, each point where the viewer met a wall
/// and turned to slide, and the end (a polyline, for tests and debugging).
#[must_use]
pub fn step_traced(maze: &Maze, from: Position, delta: Vec2, radius: f32) -> (Position, Vec<Vec2>) {
    let mut path = vec![from.pos];
    let to = sweep(maze, from, delta, radius, Some(&mut path));
    if to == from {
        path.truncate(1);
    }
    (to, path)
}

fn sweep(
    maze: &Maze,
    from: Position,
    delta: Vec2,
    radius: f32,
    mut path: Option<&mut Vec<Vec2>>,
) -> Position {
    debug_assert!((from.cell as usize) < maze.cell_count(), "cell {} out of range", from.cell);
    if (from.cell as usize) >= maze.cell_count()
        || !(delta.is_finite() && from.pos.is_finite() && radius.is_finite() && radius >= 0.0)
    {
        return from;
    }
    let r = f64::from(radius);
    let reach = delta.length() + radius + 1e-3;
    let region = Aabb { min: from.pos, max: from.pos }.expand(reach);
    let cells = cells_near(maze, from.cell, &region);
    let walls = walls_of(maze, &cells);

    let mut p = from.pos.as_dvec2();
    let mut m = delta.as_dvec2();
    for _ in 0..MAX_SLIDES {
        let len = m.length();
        if len < 1e-12 {
            break;
        }
        let Some((t, n)) =
            walls.iter().filter_map(|w| contact(p, m, w, r, from.cell)).min_by(|a, b| a.0.total_cmp(&b.0))
        else {
            p += m;
            break;
        };
        // stop SKIN short of the contact, then keep only the part of the motion along the wall
        let t_safe = (t - SKIN / len).max(0.0);
        p += m * t_safe;
        if let Some(path) = path.as_deref_mut() {
            path.push(p.as_vec2());
        }
        let rest = m * (1.0 - t_safe);
        m = rest - n * rest.dot(n).min(0.0);
    }

    let pos = p.as_vec2();
    if let Some(path) = path {
        path.push(pos);
    }
    let cell = cells.iter().copied().find(|&c| maze.cell_contains(c, pos)).or_else(|| maze.cell_at(pos));
    match cell {
        Some(cell) => Position { cell, pos },
        None => from, // rounding put the point outside every cell: do not move
    }
}

/// Where the viewer stands when put at `at`: at least `radius` from every opaque edge, as a [`step`]
/// keeps it. A place closer is pushed out, away from the nearest wall first, a few rounds, each a
/// [`step`] (so never through a wall). Where no place within reach is clear (a corridor narrower than
/// the disc), the viewer stays as close to clear as the pushes got it. Non-finite input returns `at`.
///
/// The renderer relies on it: its near plane lies inside the margin, so an eye closer to a wall would
/// see through it.
#[must_use]
pub fn settle(maze: &Maze, at: Position, radius: f32) -> Position {
    const ROUNDS: usize = 8;
    if (at.cell as usize) >= maze.cell_count() || !(at.pos.is_finite() && radius.is_finite() && radius > 0.0)
    {
        return at;
    }
    let r = f64::from(radius) + SKIN;
    let region = Aabb { min: at.pos, max: at.pos }.expand(2.0 * radius + 1e-3);
    let walls = walls_of(maze, &cells_near(maze, at.cell, &region));
    let mut here = at;
    for _ in 0..ROUNDS {
        let p = here.pos.as_dvec2();
        // The wall the disc overlaps most, and the way out of it.
        let deepest = walls
            .iter()
            .filter_map(|w| match w.away(p, here.cell) {
                (d, Some(out)) if d < r => Some((r - d, out)),
                _ => None,
            })
            .max_by(|a, b| a.0.total_cmp(&b.0));
        let Some((depth, out)) = deepest else { break };
        // Pushed as a disc that touches nothing yet: the full disc overlaps the walls it is pushed
        // from, and the end of a wall's next piece along the same line (a grid's walls come a tile at
        // a time) would block the push as a corner.
        let nearest = walls.iter().map(|w| w.away(p, here.cell).0).fold(f64::INFINITY, f64::min);
        let fits = ((nearest - 2.0 * SKIN).max(0.0) as f32).min(radius);
        let next = step(maze, here, (out * (depth + SKIN)).as_vec2(), fits);
        if next == here {
            break;
        }
        here = next;
    }
    here
}

/// Whether the disc of `radius` round `at` is clear of every wall (as [`settle`] leaves it where
/// there is room).
#[must_use]
pub fn is_clear(maze: &Maze, at: Position, radius: f32) -> bool {
    let region = Aabb { min: at.pos, max: at.pos }.expand(radius + 1e-3);
    let walls = walls_of(maze, &cells_near(maze, at.cell, &region));
    walls.iter().all(|w| w.away(at.pos.as_dvec2(), at.cell).0 >= f64::from(radius) - SKIN)
}

/// Cells reachable from `start` through portals without leaving cells that touch `region`,
/// `start` first, in breadth-first order.
fn cells_near(maze: &Maze, start: CellId, region: &Aabb) -> Vec<CellId> {
    let mut seen = HashSet::from([start]);
    let mut order = vec![start];
    let mut queue = VecDeque::from([start]);
    while let Some(c) = queue.pop_front() {
        for &e in maze.cell_edges(c) {
            let edge = maze.edge(e);
            if let Some(n) = edge.other_side(c).filter(|_| edge.is_portal())
                && maze.cell_aabb(n).intersects(region)
                && seen.insert(n)
            {
                order.push(n);
                queue.push_back(n);
            }
        }
    }
    order
}

/// An opaque edge seen from one of its cells.
struct Wall {
    a: DVec2,
    b: DVec2,
    /// The cell it was collected from, and the unit normal pointing into that cell.
    cell: CellId,
    inward: DVec2,
}

impl Wall {
    /// How far `p` is from the wall, and the unit normal out of it towards `p`: on the wall line,
    /// out into `current` if the wall is one of its sides (`None` for another cell's wall).
    fn away(&self, p: DVec2, current: CellId) -> (f64, Option<DVec2>) {
        let e = self.b - self.a;
        let closest = self.a + e * ((p - self.a).dot(e) / e.length_squared()).clamp(0.0, 1.0);
        let dist = p.distance(closest);
        let out = if dist > 1e-9 {
            Some((p - closest) / dist)
        } else {
            (self.cell == current).then_some(self.inward) // on the wall line: the current cell's side is out
        };
        (dist, out)
    }
}

fn walls_of(maze: &Maze, cells: &[CellId]) -> Vec<Wall> {
    let mut walls = Vec::new();
    for &c in cells {
        for &e in maze.cell_edges(c) {
            if maze.edge(e).opaque {
                let (a, b) = maze.edge_points_ccw(e, c);
                let (a, b) = (a.as_dvec2(), b.as_dvec2());
                // the cell is on the left of a → b
                walls.push(Wall { a, b, cell: c, inward: (b - a).perp().normalize() });
            }
        }
    }
    walls
}

/// The earliest fraction t ∈ [0, 1] of motion `m` from `p` at which the disc of radius `r` touches
/// `wall`, with the contact normal (pointing from the wall to the disc).
fn contact(p: DVec2, m: DVec2, wall: &Wall, r: f64, current: CellId) -> Option<(f64, DVec2)> {
    let (a, b) = (wall.a, wall.b);
    let e = b - a;
    let (dist, out) = wall.away(p, current);
    if dist < r + SKIN {
        // already touching: block only motion further in
        return out.filter(|&n| m.dot(n) < 0.0).map(|n| (0.0, n));
    }
    let mut best: Option<(f64, DVec2)> = None;
    let mut consider = |t: f64, n: DVec2| {
        if (0.0..=1.0).contains(&t) && best.is_none_or(|(bt, _)| t < bt) {
            best = Some((t, n));
        }
    };
    // the flat side facing p: the signed distance along its normal falls to r
    let side = if wall.inward.dot(p - a) >= 0.0 { wall.inward } else { -wall.inward };
    let (s0, sm) = ((p - a).dot(side), m.dot(side));
    if sm < 0.0 {
        let t = (s0 - r) / -sm;
        let u = (p + m * t - a).dot(e) / e.length_squared();
        if (0.0..=1.0).contains(&u) {
            consider(t, side);
        }
    }
    // the end points: |p + t m − v| = r, the smaller root
    for v in [a, b] {
        let f = p - v;
        let (qa, qb, qc) = (m.dot(m), 2.0 * f.dot(m), f.dot(f) - r * r);
        let disc = qb * qb - 4.0 * qa * qc;
        if qb < 0.0 && disc >= 0.0 {
            let t = (-qb - disc.sqrt()) / (2.0 * qa);
            let n = (p + m * t - v).normalize_or_zero();
            consider(t, n);
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::parse;
    use glam::vec2;

    /// Two 4×4 cells side by side, a portal between them at x = 4; walls all around.
    fn two_rooms() -> Maze {
        let text = "6  0 0 4 0 8 0 0 4 4 4 8 4
            7
            0 1 0 -1 1 1 1 1
            1 2 1 -1 1 1 1 1
            3 4 -1 0 1 1 1 1
            4 5 -1 1 1 1 1 1
            0 3 -1 0 1 1 1 1
            1 4 0 1 0 1 1 1
            2 5 1 -1 1 1 1 1
            2
            5 2 4 0
            6 3 5 1
            2 2 0 0 90";
        parse("two", text.as_bytes()).unwrap()
    }

    /// The distance from `p` to the nearest opaque edge of `m`.
    fn clearance(m: &Maze, p: Vec2) -> f32 {
        (0..m.edges().len() as u32)
            .filter(|&e| m.edge(e).opaque)
            .map(|e| {
                let (a, b) = m.edge_points(e);
                let t = ((p - a).dot(b - a) / (b - a).length_squared()).clamp(0.0, 1.0);
                p.distance(a + (b - a) * t)
            })
            .fold(f32::INFINITY, f32::min)
    }

    /// A viewer put closer than the margin to walls (on a wall line, in a corner, beside a portal's
    /// end) stands at the margin, in a cell holding it, moved no further than it had to be; one put
    /// clear of every wall, or beside a portal, stays put.
    #[test]
    fn a_viewer_put_against_a_wall_stands_at_the_margin() {
        let m = two_rooms();
        let mut moved = 0;
        for i in 0..=80 {
            for j in 0..=40 {
                let pos = vec2(i as f32 * 0.1, j as f32 * 0.1);
                let Some(cell) = m.cell_at(pos) else { continue };
                let at = Position { cell, pos };
                let settled = settle(&m, at, 0.25);
                assert!(m.cell_contains(settled.cell, settled.pos), "{at:?} → {settled:?}");
                assert!(clearance(&m, settled.pos) >= 0.25, "{at:?} → {settled:?}");
                let before = clearance(&m, pos);
                if before >= 0.25 + 2e-4 {
                    assert_eq!(settled, at, "clear already");
                } else {
                    moved += 1;
                    // In a corner the way out is the diagonal: √2 × the margin.
                    assert!(settled.pos.distance(pos) <= 0.36, "{at:?} → {settled:?}");
                }
            }
        }
        assert!(moved > 200, "{moved}");
        // Beside the portal, between the rooms: no wall there.
        let by_portal = Position { cell: 0, pos: vec2(3.99, 2.0) };
        assert_eq!(settle(&m, by_portal, 0.25), by_portal);
    }

    /// A grid's walls come a tile at a time: in a room of 3 × 3 tiles 0.3 across, a viewer put
    /// anywhere in the corner tile (the ends of the wall pieces beside it inside its disc) is pushed
    /// clear. The full disc's push was blocked by those ends, as by corners, and stayed put.
    #[test]
    fn a_viewer_in_a_corner_of_split_walls_is_pushed_clear() {
        let mut map =
            crate::grid::parse_map("m", "mazewalk-grid 1\n#####\n#...#\n#.@.#\n#...#\n#####\n").expect("map");
        map.tile = 0.3;
        let m = map.to_maze().expect("room for the viewer in the middle");
        let mut starts = vec![vec2(0.450_000_02, 1.050_000_1)];
        for i in 0..=12 {
            for j in 0..=12 {
                starts.push(vec2(0.3 + 0.3 * i as f32 / 12.0, 0.9 + 0.3 * j as f32 / 12.0));
            }
        }
        for pos in starts {
            let Some(cell) = m.cell_at(pos) else { continue };
            let settled = settle(&m, Position { cell, pos }, 0.25);
            assert!(is_clear(&m, settled, 0.25), "{pos:?} → {settled:?}");
        }
    }

    /// A cell narrower than the disc has no clear place: the viewer stays inside it, never pushed
    /// through a wall, and the input that means nothing leaves it where it is.
    #[test]
    fn a_viewer_in_a_cell_narrower_than_its_disc_stays_inside() {
        // (The viewer stands in a room of its own beside it: a maze that starts in the thin cell is
        // refused.)
        let thin = "8 0 0 0.3 0 0.3 4 0 4 10 0 14 0 14 4 10 4
            8 0 1 0 -1 1 1 1 1 1 2 0 -1 1 1 1 1 2 3 0 -1 1 1 1 1 3 0 0 -1 1 1 1 1
              4 5 1 -1 1 1 1 1 5 6 1 -1 1 1 1 1 6 7 1 -1 1 1 1 1 7 4 1 -1 1 1 1 1
            2 0 1 2 3 4 5 6 7 12 2 0 90 90";
        let m = parse("thin", thin.as_bytes()).unwrap();
        for x in [0.0, 0.01, 0.15, 0.29, 0.3] {
            let at = Position { cell: 0, pos: vec2(x, 2.0) };
            let settled = settle(&m, at, 0.25);
            assert!(m.cell_contains(0, settled.pos) && settled.cell == 0, "{at:?} → {settled:?}");
        }
        let at = Position { cell: 0, pos: vec2(0.1, 2.0) };
        assert_eq!(settle(&m, at, f32::NAN), at);
        assert_eq!(settle(&m, Position { cell: 0, pos: vec2(f32::NAN, 2.0) }, 0.25).pos.y, 2.0);
    }

    #[test]
    fn crosses_a_portal_and_tracks_the_cell() {
        let m = two_rooms();
        let p = step(&m, Position { cell: 0, pos: vec2(2.0, 2.0) }, vec2(4.0, 0.0), 0.25);
        assert_eq!(p, Position { cell: 1, pos: vec2(6.0, 2.0) });
    }

    #[test]
    fn stops_radius_short_of_a_wall() {
        let m = two_rooms();
        let p = step(&m, Position { cell: 0, pos: vec2(2.0, 2.0) }, vec2(0.0, 5.0), 0.25);
        assert!((p.pos.y - 3.75).abs() < 1e-3 && p.pos.y < 3.75, "{p:?}");
    }

    // issue #3: the original looped forever with the viewer exactly on an edge line
    #[test]
    fn viewer_exactly_on_a_portal_line_moves_on() {
        let m = two_rooms();
        let p = step(&m, Position { cell: 0, pos: vec2(4.0, 2.0) }, vec2(1.0, 0.0), 0.25);
        assert_eq!(p, Position { cell: 1, pos: vec2(5.0, 2.0) });
        let p = step(&m, Position { cell: 1, pos: vec2(4.0, 2.0) }, vec2(-1.0, 0.0), 0.25);
        assert_eq!(p, Position { cell: 0, pos: vec2(3.0, 2.0) });
    }

    #[test]
    fn viewer_exactly_on_a_wall_line_can_only_move_in() {
        let m = two_rooms();
        let on = Position { cell: 0, pos: vec2(2.0, 0.0) };
        assert_eq!(step(&m, on, vec2(0.0, -1.0), 0.25), on);
        let p = step(&m, on, vec2(0.0, 1.0), 0.25);
        assert_eq!(p, Position { cell: 0, pos: vec2(2.0, 1.0) });
    }

    #[test]
    fn viewer_exactly_on_a_vertex_keeps_its_cell() {
        let m = two_rooms();
        for cell in [0, 1] {
            let on = Position { cell, pos: vec2(4.0, 4.0) };
            let p = step(&m, on, vec2(0.0, 0.0), 0.25);
            assert_eq!(p, on);
            let p = step(&m, on, vec2(0.0, -1.0), 0.25);
            assert!(m.cell_contains(p.cell, p.pos) && p.pos.y <= 4.0, "{p:?}");
        }
    }

    #[test]
    fn slides_along_a_wall_hit_at_45_degrees() {
        let m = two_rooms();
        let p = step(&m, Position { cell: 0, pos: vec2(1.0, 3.0) }, vec2(2.0, 2.0), 0.25);
        // y stops at 3.75; x keeps what is left of the motion after the contact
        assert!((p.pos.y - 3.75).abs() < 1e-3, "{p:?}");
        assert!(p.pos.x > 2.9 && p.pos.x <= 3.0 + 1e-3, "{p:?}");
    }

    #[test]
    fn walking_into_a_corner_stops_radius_from_both_walls() {
        let m = two_rooms();
        let p = step(&m, Position { cell: 1, pos: vec2(6.0, 2.0) }, vec2(10.0, 7.0), 0.25);
        assert!((p.pos - vec2(7.75, 3.75)).abs().max_element() < 1e-3, "{p:?}");
        assert_eq!(p.cell, 1);
    }

    #[test]
    fn a_huge_step_does_not_tunnel() {
        let m = two_rooms();
        let p = step(&m, Position { cell: 0, pos: vec2(2.0, 2.0) }, vec2(-1e5, 0.0), 0.25);
        assert!((p.pos.x - 0.25).abs() < 1e-3, "{p:?}");
    }
}
