//! Where a newcomer starts: a free spot near the maze's start, never inside another player (issue
//! #34: everyone spawned on the same point, inside the others, and with two players there the figure
//! in front showed one label while the map showed the other's). Pure.
//!
//! The spots tried are a lattice [`LATTICE`] apart, anchored at the start (so the start itself is the
//! first), in the start's cell, then in the cells next to it across an opening, then further out, up to
//! [`MAX_CELLS`] cells. A spot is free when a viewer can stand there (at least the walk's wall margin
//! from every wall) and every other player is at least [`SPACING`] away. The first free spot of the
//! nearest ring of cells is taken, the one nearest the start (of equally near ones, the one most
//! behind the start's heading: newcomers see those before them, not the other way); with none free anywhere (a crowd of
//! hundreds in a small maze), the spot farthest from everyone.

use std::collections::{HashSet, VecDeque};

use glam::Vec2;

use mazewalk_maze::Maze;
use mazewalk_maze::geometry::heading_dir;
use mazewalk_maze::movement::Position;
use mazewalk_walk::state::stand;

/// How close another player may be to a newcomer's spot, maze units: a figure is 0.7 wide, a viewer's
/// disc 0.5; a metre apart, side by side, each sees the other as a figure, not a wall of colour.
pub(crate) const SPACING: f32 = 1.0;

/// The lattice of spots tried, maze units.
pub(crate) const LATTICE: f32 = 0.5;

/// Cells searched at most, from the start's outwards.
pub(crate) const MAX_CELLS: usize = 64;

/// Spots tried at most in one cell (a huge cell is sampled around the start).
const MAX_SPOTS_PER_CELL: usize = 4096;

/// The spots a newcomer may get, worked out once per maze (the choice among them, [`Spawns::pick`],
/// is made under the world's lock, so it is kept cheap).
#[derive(Clone, Debug)]
pub(crate) struct Spawns {
    /// The maze's start, where a viewer stands.
    start: Position,
    /// The spots of each ring of cells, nearest the start first.
    rings: Vec<Vec<Position>>,
}

impl Spawns {
    /// The spots of `maze`; `None` when its start is in no cell.
    #[must_use]
    pub fn new(maze: &Maze) -> Option<Spawns> {
        let start = stand(maze, maze.viewer().pos)?;
        let rings = rings(maze, start.cell)
            .into_iter()
            .map(|ring| {
                let mut spots: Vec<Position> =
                    ring.iter().flat_map(|&cell| spots_in(maze, cell, start.pos)).collect();
                // nearest the start first; of equally near, the one most behind it (out of the view
                // of whoever stands on the start, with them in view)
                let ahead = heading_dir(maze.viewer().dir_deg);
                let key = |p: &Position| {
                    let d = p.pos - start.pos;
                    ((d.length() / LATTICE * 4.0).round() as i64, d.dot(ahead))
                };
                spots.sort_by(|a, b| {
                    let (ka, kb) = (key(a), key(b));
                    ka.0.cmp(&kb.0).then(ka.1.total_cmp(&kb.1))
                });
                spots
            })
            .collect();
        Some(Spawns { start, rings })
    }

    /// A free spot for a newcomer whose other players stand at `others` (see the module's doc).
    #[must_use]
    pub fn pick(&self, others: &[Vec2]) -> Position {
        let clearance = |p: Vec2| others.iter().map(|o| o.distance(p)).fold(f32::INFINITY, f32::min);
        let mut best_crowded: Option<(f32, Position)> = None;
        for spot in self.rings.iter().flatten() {
            let room = clearance(spot.pos);
            if room >= SPACING {
                return *spot;
            }
            if best_crowded.is_none_or(|(best, _)| room > best) {
                best_crowded = Some((room, *spot));
            }
        }
        best_crowded.map_or(self.start, |(_, spot)| spot)
    }
}

/// A free spot for a newcomer in `maze` whose other players stand at `others` ([`Spawns`]); `None`
/// only when the maze's start is in no cell.
#[must_use]
#[cfg(test)]
pub(crate) fn free_spot(maze: &Maze, others: &[Vec2]) -> Option<Position> {
    Some(Spawns::new(maze)?.pick(others))
}

/// The cells around `start` in rings: the start's cell, then the cells across its openings, then
/// theirs…, [`MAX_CELLS`] in all.
fn rings(maze: &Maze, start: u32) -> Vec<Vec<u32>> {
    let mut seen = HashSet::from([start]);
    let mut rings = vec![vec![start]];
    let mut queue = VecDeque::from([start]);
    let mut counted = 1;
    while counted < MAX_CELLS && !queue.is_empty() {
        let mut ring = Vec::new();
        for _ in 0..queue.len() {
            let cell = queue.pop_front().unwrap_or(start);
            for &e in maze.cell_edges(cell) {
                let edge = maze.edge(e);
                let next = if edge.opaque { None } else { edge.other_side(cell) };
                if let Some(next) = next.filter(|&n| counted < MAX_CELLS && seen.insert(n)) {
                    ring.push(next);
                    queue.push_back(next);
                    counted += 1;
                }
            }
        }
        if ring.is_empty() {
            break;
        }
        rings.push(ring);
    }
    rings
}

/// The lattice spots of `cell` where a viewer stands (anchored at `anchor`, nearest it first when the
/// cell is too large to try every spot).
fn spots_in(maze: &Maze, cell: u32, anchor: Vec2) -> Vec<Position> {
    let bounds = maze.cell_aabb(cell);
    let steps = |lo: f32, hi: f32, at: f32| {
        let first = ((lo - at) / LATTICE).ceil() as i64;
        let last = ((hi - at) / LATTICE).floor() as i64;
        first..=last
    };
    let (xs, ys) = (steps(bounds.min.x, bounds.max.x, anchor.x), steps(bounds.min.y, bounds.max.y, anchor.y));
    let mut points: Vec<Vec2> = Vec::new();
    'fill: for i in xs {
        for j in ys.clone() {
            points.push(anchor + LATTICE * Vec2::new(i as f32, j as f32));
            if points.len() >= 16 * MAX_SPOTS_PER_CELL {
                break 'fill; // (a cell thousands of units wide: plenty)
            }
        }
    }
    points.sort_by(|a, b| a.distance_squared(anchor).total_cmp(&b.distance_squared(anchor)));
    points
        .into_iter()
        .filter(|&p| maze.cell_contains(cell, p))
        .take(MAX_SPOTS_PER_CELL)
        .filter_map(|p| stand(maze, p).filter(|s| s.pos.distance(p) < 1e-3)) // no wall within the margin
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A corridor 3 cells long, 4 units wide, the start in the west cell.
    const CORRIDOR: &str = "mazewalk-grid 1\ntile 4\nfacing east\n\n#####\n#@..#\n#####\n";

    fn maze(text: &str) -> Maze {
        mazewalk_maze::parse("test.grid", text.as_bytes()).unwrap()
    }

    /// Issue #34: every player spawned on the same point. Now the first gets the start, each next a
    /// spot at least SPACING from everyone, in the start's cell while it has room.
    #[test]
    fn newcomers_spread_out_from_the_start() {
        let maze = maze(CORRIDOR);
        let start = stand(&maze, maze.viewer().pos).unwrap();
        let mut here: Vec<Vec2> = Vec::new();
        for n in 0..12 {
            let spot = free_spot(&maze, &here).unwrap();
            if n == 0 {
                assert_eq!(spot.pos, start.pos, "the first stands on the start");
            }
            for other in &here {
                assert!(other.distance(spot.pos) >= SPACING, "{n}: {:?} too near {other:?}", spot.pos);
            }
            assert_eq!(maze.cell_at(spot.pos), Some(spot.cell));
            assert_eq!(stand(&maze, spot.pos).unwrap().pos, spot.pos, "clear of the walls");
            here.push(spot.pos);
        }
        let in_start_cell = here.iter().filter(|p| maze.cell_at(**p) == Some(start.cell)).count();
        assert!(in_start_cell >= 4, "the start's cell first: {in_start_cell}");
        assert!(here[1].x < start.pos.x, "the second behind the first (facing east): {:?}", here[1]);
    }

    #[test]
    fn a_crowd_too_big_for_the_maze_still_gets_the_emptiest_spot() {
        let maze = maze("mazewalk-grid 1\ntile 1\n\n###\n#@#\n###\n");
        let others = [maze.viewer().pos];
        let spot = free_spot(&maze, &others).unwrap();
        assert_eq!(maze.cell_at(spot.pos), Some(spot.cell), "still in the maze");
    }
}
