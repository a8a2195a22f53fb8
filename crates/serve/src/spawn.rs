//! Where a newcomer starts: a free spot near the maze's start, never inside another player (issue
//! #34: everyone spawned on the same point, inside the others, and with two players there the figure
//! in front showed one label while the map showed the other's). Pure.
//!
//! The spots tried are a lattice [`LATTICE`] apart, anchored at the start (so the start itself is the
//! first), in the start's cell, then in the cells next to it across an opening, then further out, up to
//! [`MAX_CELLS`] cells. A spot is free when a viewer can stand there (at least the walk's wall margin
//! from every wall) and every other player is at least a cell away (the spot's cell's narrower side;
//! issue #39: three players spawned a metre apart in one cell, the second seeing only the first's
//! back). The first free spot of the nearest ring of cells is taken: a cell's centre (not a spot on a
//! cell's edge, where the floor's and ceiling's cell lines cut the view), then the one nearest the
//! start (of equally near ones, the one most behind the start's heading); with none a cell apart, the first at
//! least [`SPACING`] from everyone; with none of those (a crowd of hundreds in a small maze), the spot
//! farthest from everyone. A newcomer away from the start faces its cell's longest straight way on
//! (the opening through which the most cells follow in a line), not a wall or another's back.
//!
//! A crowd gives no head start on a record (red-team pass 4: with a crowd at the start, the nearest
//! free ring of a generated maze lay along the way on, and a newcomer's clock, record and ghost
//! started up to a third of the way nearer the exit). The cells tried first are those at least as
//! many cells' steps from the exit's cell as the start's cell is ([`hops`]), nearest the start
//! first (reached through any cell, up to [`MAX_CELLS`]); only when none of them has a spot a cell
//! apart (at least [`SPACING`], in the next tier) does a newcomer get a spot nearer the exit, the
//! fewest steps nearer first (of cells' centres, then of other spots), marked so ([`Spot::ahead`]): its finishes are not kept in the records
//! (the server's `walk`) until it walks back to a cell as far from the exit as the start's
//! ([`Spawns::fair`]): there its walk starts again, its clock from zero, a walk the records keep
//! (red-team pass 5: one idle player on the start kept every newcomer's walk from the records). Often the start is the cell farthest from the exit (a `--gen` maze's exit
//! is the cell farthest from the start), so nothing else is as far: putting a crowd in one cell,
//! the players inside one another (issue #34), would be worse than an unrecorded walk. A maze
//! with no exit, or whose exit the start cannot reach, marks no spot.
//!
//! In a shared world a server picks from the players it knows of: two newcomers on two servers at
//! once may get one spot. The later comer then moves to a free one ([`Arrival`], [`Spawns::repick`]).

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
    /// The spots of each ring of cells no nearer the exit than the start's, nearest the start first.
    rings: Vec<Vec<Spot>>,
    /// The spots of the cells nearer the exit, among the [`MAX_CELLS`] nearest the start: cells'
    /// centres first, then the fewest steps nearer, then as the rings.
    ahead: Vec<Spot>,
    /// Each cell: no nearer the exit than the start's ([`Spawns::fair`]).
    fair: Vec<bool>,
}

/// Where a newcomer may stand.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Spot {
    /// The place.
    pub at: Position,
    /// How far from everyone it is a cell apart: its cell's narrower side, at most [`NEAR`].
    apart: f32,
    /// The heading to face there, degrees: `None` in the start's cell (the maze's own heading).
    pub heading: Option<f32>,
    /// How many cells' steps nearer the exit than the start's cell it is (0: none, or no exit): a
    /// walk from here is not the maze's whole way, and its finish is not kept in the records.
    pub ahead: u32,
}

impl Spawns {
    /// The spots of `maze`; `None` when its start is in no cell.
    #[must_use]
    pub fn new(maze: &Maze) -> Option<Spawns> {
        let start = stand(maze, maze.viewer().pos)?;
        // how many steps (from cell to cell) nearer the exit than the start's a cell is
        let to_exit = maze.exit().map(|exit| hops(maze, exit.cell));
        let ahead = |cell: u32| match &to_exit {
            Some(to_exit) => match (to_exit[start.cell as usize], to_exit[cell as usize]) {
                (Some(start), Some(here)) => start.saturating_sub(here),
                _ => 0, // (the start cannot reach the exit: nothing to gain)
            },
            None => 0,
        };
        let spots_of = |rings: Vec<Vec<u32>>, fair: bool| -> Vec<Vec<Spot>> {
            rings
                .into_iter()
                .map(|ring| {
                    let mut spots: Vec<Spot> = ring
                        .iter()
                        .flat_map(|&cell| {
                            let size = maze.cell_aabb(cell).max - maze.cell_aabb(cell).min;
                            let heading = (cell != start.cell).then(|| longest_way(maze, cell));
                            let apart = size.x.min(size.y).clamp(SPACING, NEAR);
                            spots_in(maze, cell, start.pos)
                                .into_iter()
                                .map(move |at| Spot { at, apart, heading, ahead: ahead(at.cell) })
                                .filter(move |spot| (spot.ahead == 0) == fair) // (a spot on an opening may stand in the next cell)
                        })
                        .collect();
                    // cells' centres first (not a spot on a cell's edge, the view cut by the floor's and
                    // ceiling's cell lines); then nearest the start; of equally near, the one most behind
                    // it (out of the view of whoever stands on the start, with them in view)
                    let forward = heading_dir(maze.viewer().dir_deg);
                    let key = |p: &Spot| {
                        let d = p.at.pos - start.pos;
                        let off_centre = p.at.pos.distance(maze.cell_centroid(p.at.cell)) > 1e-3;
                        (off_centre, (d.length() / LATTICE * 4.0).round() as i64, d.dot(forward))
                    };
                    spots.sort_by(|a, b| {
                        let (ka, kb) = (key(a), key(b));
                        ka.0.cmp(&kb.0).then(ka.1.cmp(&kb.1)).then(ka.2.total_cmp(&kb.2))
                    });
                    spots
                })
                .collect()
        };
        let rings = spots_of(self::rings(maze, start.cell, &|cell| ahead(cell) == 0), true);
        let mut nearer: Vec<Spot> =
            spots_of(self::rings(maze, start.cell, &|cell| ahead(cell) > 0), false).concat();
        // cells' centres first, as in a ring; then the fewest steps nearer (stable: then the rings' order)
        nearer
            .sort_by_key(|spot| (spot.at.pos.distance(maze.cell_centroid(spot.at.cell)) > 1e-3, spot.ahead));
        let fair = (0..maze.cell_count() as u32).map(|cell| ahead(cell) == 0).collect();
        Some(Spawns { start, rings, ahead: nearer, fair })
    }

    /// Whether `cell` is as many cells' steps from the exit as the start's cell, or more (every cell
    /// of a maze without an exit): a walk from a head start that comes back to such a cell starts
    /// again there, its clock from zero, as a walk the records keep (the start line, `walk`).
    #[must_use]
    pub fn fair(&self, cell: u32) -> bool {
        self.fair.get(cell as usize).copied().unwrap_or(false)
    }

    /// A free spot for a newcomer whose other players stand at `others` (see the module's doc), in
    /// one pass over the spots: the first a cell apart from everyone; else the first at least
    /// [`SPACING`] from everyone; else the one farthest from everyone. Each spot reads only the others
    /// within [`NEAR`] of it ([`Crowd`]), and the pass stops after [`MAX_PICK_WORK`] distances, with the
    /// best spot found so far: the pick holds the world's lock, which every player's frame needs
    /// (red-team pass 8: with 1,024 players a Redis writer invented, every join in an arena of 30-unit
    /// cells measured each of ~230,000 spots against each of them, ~90 ms a join under the lock).
    #[must_use]
    pub fn pick(&self, others: &[Vec2]) -> Spot {
        self.pick_counted(&Crowd::new(others)).0
    }

    /// [`pick`](Self::pick)'s spot among `crowd`, and the distances it measured.
    fn pick_counted(&self, crowd: &Crowd) -> (Spot, usize) {
        let mut work = 0;
        let mut first_spaced: Option<Spot> = None;
        let mut best_crowded: Option<(f32, Spot)> = None;
        // no nearer the exit than the start first, then the fewest cells nearer
        for spot in self.rings.iter().flatten().chain(&self.ahead) {
            let room = crowd.clearance(spot.at.pos, &mut work);
            if room >= spot.apart {
                return (*spot, work); // a cell apart
            }
            if room >= SPACING {
                first_spaced.get_or_insert(*spot);
            } else if best_crowded.is_none_or(|(best, _)| room > best) {
                best_crowded = Some((room, *spot));
            }
            if work > MAX_PICK_WORK {
                break;
            }
        }
        let start = Spot { at: self.start, apart: SPACING, heading: None, ahead: 0 };
        (first_spaced.or(best_crowded.map(|(_, spot)| spot)).unwrap_or(start), work)
    }
}

/// How far a spot's room is measured, maze units: a spot this far from everyone is a cell apart in
/// any cell ([`Spot::apart`] is at most this).
const NEAR: f32 = 8.0;

/// The distances measured at most in one [`Spawns::pick`], a millisecond or so: past it the best
/// spot found so far is taken. (A crowd spread evenly so that no spot is free costs about 4 spots ×
/// (the others within [`NEAR`]) a square unit; 1,024 others over a 240-unit arena, ~2.4 million.)
const MAX_PICK_WORK: usize = 1 << 20;

/// The other players' positions in square buckets [`NEAR`] wide: a spot's room up to [`NEAR`] reads
/// the 3 × 3 buckets around it, not every other player.
struct Crowd {
    buckets: std::collections::HashMap<(i32, i32), Vec<Vec2>>,
}

impl Crowd {
    fn new(others: &[Vec2]) -> Crowd {
        let mut buckets: std::collections::HashMap<(i32, i32), Vec<Vec2>> = std::collections::HashMap::new();
        for &other in others.iter().filter(|o| o.is_finite()) {
            buckets.entry(Crowd::bucket(other)).or_default().push(other);
        }
        Crowd { buckets }
    }

    /// The bucket of `p` (far-off positions saturate into the outermost buckets).
    fn bucket(p: Vec2) -> (i32, i32) {
        ((p.x / NEAR).floor() as i32, (p.y / NEAR).floor() as i32)
    }

    /// The distance from `p` to the nearest other, or [`NEAR`] when none is nearer; adds the
    /// distances measured to `work`.
    fn clearance(&self, p: Vec2, work: &mut usize) -> f32 {
        let (bx, by) = Crowd::bucket(p);
        let mut room = NEAR;
        for x in bx.saturating_sub(1)..=bx.saturating_add(1) {
            for y in by.saturating_sub(1)..=by.saturating_add(1) {
                if let Some(bucket) = self.buckets.get(&(x, y)) {
                    *work += bucket.len();
                    room = bucket.iter().map(|o| o.distance(p)).fold(room, f32::min);
                }
            }
        }
        room
    }
}

impl Spawns {
    /// A spot with more room than `at` for a newcomer who stands there among `others` (found on
    /// its spot by another server's earlier player: `World::came_first_near`), if the maze has one:
    /// [`pick`](Self::pick)'s choice, when it is farther from everyone than `at` is. Never a move to
    /// a spot no better, so a crowd that leaves no room moves nobody.
    #[must_use]
    pub fn repick(&self, at: Vec2, others: &[Vec2]) -> Option<Spot> {
        let crowd = Crowd::new(others);
        let (spot, mut work) = self.pick_counted(&crowd);
        (crowd.clearance(spot.at.pos, &mut work) > crowd.clearance(at, &mut work) + LATTICE * 0.5)
            .then_some(spot)
    }
}

/// How long a newcomer who has not stepped off its spawn spot may still be moved off it, seconds
/// ([`Arrival`]): long enough for a server that started, or came back online, to hear everyone (a
/// full message a second), with room for a Redis that stalled for a few seconds meanwhile.
pub(crate) const SETTLE_SECONDS: f64 = 10.0;

/// How many times at most a newcomer looks for a better spot ([`Arrival::crowded`]), whether it
/// finds one or not: three newcomers racing on three servers take two moves; a Redis that lies
/// about players on every spot, or a crowd that leaves no better one, costs no more than this many
/// picks under the world's lock.
pub(crate) const MAX_SETTLE_TRIES: u32 = 3;

/// A newcomer of a shared world on the spot it was given, which it may still be moved off when
/// another server's earlier player turns out to stand there (`World::came_first_near`): while it
/// has not stepped off it, for [`SETTLE_SECONDS`], [`MAX_SETTLE_TRIES`] times, and only to a spot
/// with more room than its own ([`Spawns::repick`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Arrival {
    /// Where it stands.
    at: Vec2,
    /// Until when (the server's clock, seconds).
    until: f64,
    /// Looks for a better spot so far.
    tries: u32,
}

impl Arrival {
    /// A newcomer put at `at` at `now`.
    #[must_use]
    pub fn new(at: Vec2, now: f64) -> Arrival {
        Arrival { at, until: now + SETTLE_SECONDS, tries: 0 }
    }

    /// Whether the newcomer, now at `at` at `now`, may still be moved (once not, never again).
    #[must_use]
    pub fn settling(&self, at: Vec2, now: f64) -> bool {
        now <= self.until && self.tries < MAX_SETTLE_TRIES && at == self.at
    }

    /// Another server's earlier player stands on the newcomer's spot, among `others` (everyone but
    /// it): the spot to move it to, if the maze has a better one (a try, counted either way). Tell
    /// it where it was put ([`placed`](Self::placed)).
    pub fn crowded(&mut self, spawns: &Spawns, others: &[Vec2]) -> Option<Spot> {
        self.tries += 1;
        spawns.repick(self.at, others)
    }

    /// The newcomer now stands at `at`.
    pub fn placed(&mut self, at: Vec2) {
        self.at = at;
    }
}

/// A free spot for a newcomer in `maze` whose other players stand at `others` ([`Spawns`]); `None`
/// only when the maze's start is in no cell.
#[must_use]
#[cfg(test)]
pub(crate) fn free_spot(maze: &Maze, others: &[Vec2]) -> Option<Position> {
    Some(Spawns::new(maze)?.pick(others).at)
}

/// The heading (degrees) from `cell` through its opening with the most cells in a straight line
/// beyond it (up to 16; ties: the first opening), or the maze's heading in a cell with no opening.
fn longest_way(maze: &Maze, cell: u32) -> f32 {
    let centre = maze.cell_centroid(cell);
    let mut best: Option<(usize, Vec2)> = None;
    for &e in maze.cell_edges(cell) {
        let edge = maze.edge(e);
        let Some(mut next) = edge.other_side(cell).filter(|_| !edge.opaque) else { continue };
        let (a, b) = maze.edge_points(e);
        let way = ((a + b) * 0.5 - centre).normalize_or_zero();
        let mut run = 1;
        // On through the opening of each next cell that keeps the line (within about 25°).
        while run < 16 {
            let from = maze.cell_centroid(next);
            let ahead = maze.cell_edges(next).iter().find_map(|&f| {
                let other = maze.edge(f);
                let (p, q) = maze.edge_points(f);
                let towards = ((p + q) * 0.5 - from).normalize_or_zero();
                (!other.opaque && towards.dot(way) > 0.9).then(|| other.other_side(next)).flatten()
            });
            let Some(beyond) = ahead else { break };
            (next, run) = (beyond, run + 1);
        }
        if best.is_none_or(|(longest, _)| run > longest) {
            best = Some((run, way));
        }
    }
    best.map_or(maze.viewer().dir_deg, |(_, way)| way.y.atan2(way.x).to_degrees().rem_euclid(360.0))
}

/// The cells around `start` that `fair` lets in, in rings by steps from `start` (through any cell):
/// the start's cell, then those across its openings, then theirs…, [`MAX_CELLS`] in all. Visits
/// every cell at most once.
fn rings(maze: &Maze, start: u32, fair: &impl Fn(u32) -> bool) -> Vec<Vec<u32>> {
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
                if let Some(next) = next.filter(|&n| seen.insert(n)) {
                    queue.push_back(next); // (on through a cell left out, to those beyond it)
                    if counted < MAX_CELLS && fair(next) {
                        ring.push(next);
                        counted += 1;
                    }
                }
            }
        }
        if !ring.is_empty() {
            rings.push(ring);
        }
    }
    rings
}

/// Each cell's steps (across openings) from `from`; `None` where it cannot be reached.
fn hops(maze: &Maze, from: u32) -> Vec<Option<u32>> {
    let mut hops = vec![None; maze.cell_count()];
    let Some(first) = hops.get_mut(from as usize) else { return hops };
    *first = Some(0);
    let mut queue = VecDeque::from([(from, 0u32)]);
    while let Some((cell, n)) = queue.pop_front() {
        for &e in maze.cell_edges(cell) {
            let edge = maze.edge(e);
            let Some(next) = edge.other_side(cell).filter(|_| !edge.opaque) else { continue };
            if let Some(slot @ None) = hops.get_mut(next as usize) {
                *slot = Some(n + 1);
                queue.push_back((next, n + 1));
            }
        }
    }
    hops
}

/// The spots of `cell` where a viewer stands: its centre, then the lattice's (anchored at `anchor`,
/// nearest it first when the cell is too large to try every spot).
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
    let centre = maze.cell_centroid(cell);
    points.retain(|p| p.distance(centre) > 1e-3);
    std::iter::once(centre)
        .chain(points)
        .filter(|&p| maze.cell_contains(cell, p))
        .take(MAX_SPOTS_PER_CELL)
        .filter_map(|p| stand(maze, p).filter(|s| s.pos.distance(p) < 1e-3)) // no wall within the margin
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// A corridor 3 cells long, 4 units wide, the start in the west cell.
    const CORRIDOR: &str = "mazewalk-grid 1\ntile 4\nfacing east\n\n#####\n#@..#\n#####\n";

    fn maze(text: &str) -> Maze {
        mazewalk_maze::parse("test.grid", text.as_bytes()).unwrap()
    }

    /// Issue #34: every player spawned on the same point. Issue #39: three spawned a metre apart in
    /// one cell, the second seeing the first's back. Now the first gets the start, each next a cell
    /// apart from everyone while the maze has room (here, one a cell), then at least SPACING while it
    /// has room for that (here 9: the walk's clearance, 1.6, leaves the corridor one line of spots,
    /// y = 6, x = 6…14), then the spot farthest from everyone (a lattice step).
    #[test]
    fn newcomers_spread_out_from_the_start_a_cell_apart() {
        let maze = maze(CORRIDOR);
        let start = stand(&maze, maze.viewer().pos).unwrap();
        let mut here: Vec<Vec2> = Vec::new();
        for n in 0..12 {
            let spot = free_spot(&maze, &here).unwrap();
            if n == 0 {
                assert_eq!(spot.pos, start.pos, "the first stands on the start");
            }
            let nearest = here.iter().map(|o| o.distance(spot.pos)).fold(f32::INFINITY, f32::min);
            let wanted = if n < 3 {
                4.0
            } else if n < 9 {
                SPACING
            } else {
                LATTICE
            };
            assert!(nearest >= wanted, "{n}: {:?} only {nearest} from another", spot.pos);
            assert_eq!(maze.cell_at(spot.pos), Some(spot.cell));
            assert_eq!(stand(&maze, spot.pos).unwrap().pos, spot.pos, "clear of the walls");
            here.push(spot.pos);
        }
        let cells: HashSet<Option<u32>> = here[..3].iter().map(|p| maze.cell_at(*p)).collect();
        assert_eq!(cells.len(), 3, "the first three, one a cell: {:?}", &here[..3]);
    }

    /// A newcomer away from the start faces the longest straight way out of its cell.
    #[test]
    fn a_newcomer_faces_the_longest_way_on() {
        // An L: the start's cell at the corner; east three cells, north one.
        let maze = maze("mazewalk-grid 1\ntile 4\nfacing north\n\n######\n#.####\n#@...#\n######\n");
        let spawns = Spawns::new(&maze).unwrap();
        let first = spawns.pick(&[]);
        assert_eq!(first.heading, None, "the first faces as the maze says");
        let second = spawns.pick(&[first.at.pos]);
        let heading = second.heading.expect("away from the start: a heading");
        let way = Vec2::from_angle(heading.to_radians());
        // Whichever cell it got, it looks down the corridor's length, not into the wall it stands by.
        let cell = second.at.cell;
        let straight_on = |d: Vec2| {
            (1..=3).filter(|k| maze.cell_at(maze.cell_centroid(cell) + d * 4.0 * *k as f32).is_some()).count()
        };
        let best = [Vec2::X, Vec2::Y, -Vec2::X, -Vec2::Y].into_iter().map(straight_on).max().unwrap();
        assert_eq!(straight_on(way.round()), best, "heading {heading}° from {:?}", second.at.pos);
    }

    /// A tester's fourth newcomer in a generated maze stood on a cell's edge, (10, 4), the view cut by
    /// the floor's and ceiling's cell lines: while cells a cell apart are free, newcomers get their
    /// centres.
    #[test]
    fn newcomers_stand_at_cells_centres_while_there_are_free_ones() {
        use mazewalk_maze::generate::{GenOptions, generate};
        let maze = generate(&GenOptions::walk(30, 20, 7)).unwrap();
        let spawns = Spawns::new(&maze).unwrap();
        let mut here: Vec<Vec2> = Vec::new();
        for n in 0..24 {
            let spot = spawns.pick(&here);
            let centre = maze.cell_centroid(spot.at.cell);
            assert!(
                spot.at.pos.distance(centre) < 1e-3,
                "newcomer {n} at {:?}, its cell's centre {centre:?}",
                spot.at.pos
            );
            here.push(spot.at.pos);
        }
    }

    /// Two newcomers on two servers took the start at once: the later one moves a cell away, the
    /// way a newcomer who had known of the other would have been placed; where the maze has no
    /// better spot, nobody moves.
    #[test]
    fn a_newcomer_found_on_anothers_spot_moves_to_a_free_one() {
        let maze = maze(CORRIDOR);
        let spawns = Spawns::new(&maze).unwrap();
        let start = spawns.pick(&[]).at.pos;
        let moved = spawns.repick(start, &[start]).expect("the corridor has room");
        assert_eq!(moved, spawns.pick(&[start]), "as if it had known");
        assert!(moved.at.pos.distance(start) >= 4.0, "a cell away: {:?}", moved.at.pos);
        assert_eq!(spawns.repick(moved.at.pos, &[start]), None, "already a cell apart");
        let tiny = self::maze("mazewalk-grid 1\ntile 1\n\n###\n#@#\n###\n");
        let tiny = Spawns::new(&tiny).unwrap();
        let only = tiny.pick(&[]).at.pos;
        assert_eq!(tiny.repick(only, &[only]), None, "no room: it stays");
    }

    /// A writer on Redis who puts an earlier player wherever the newcomer stands moves it three
    /// times, no more; a newcomer that stepped off its spot, or after SETTLE_SECONDS, is never moved.
    #[test]
    fn a_newcomer_is_moved_a_bounded_number_of_times() {
        let maze = maze(CORRIDOR);
        let spawns = Spawns::new(&maze).unwrap();
        let mut at = spawns.pick(&[]).at.pos;
        let mut arrival = Arrival::new(at, 100.0);
        let mut moves = 0;
        for step in 0..20 {
            if !arrival.settling(at, 100.0 + f64::from(step) * 0.1) {
                break;
            }
            if let Some(spot) = arrival.crowded(&spawns, &[at]) {
                at = spot.at.pos;
                arrival.placed(at);
                moves += 1;
            }
        }
        assert_eq!(moves, MAX_SETTLE_TRIES, "chased, then left where it is");
        let start = spawns.pick(&[]).at.pos;
        let arrival = Arrival::new(start, 0.0);
        assert!(arrival.settling(start, SETTLE_SECONDS));
        assert!(!arrival.settling(start, SETTLE_SECONDS + 0.1), "too late");
        assert!(!arrival.settling(start + Vec2::new(0.1, 0.0), 1.0), "it stepped off");
    }

    /// What a newcomer joining `others` gets in `maze`, checked: a spot marked with how many cells
    /// nearer the exit than the start it is (as `to_exit` counts them from the start's `start`), and
    /// one nearer only when no spot as far as the start's is a cell apart from everyone.
    fn checked_pick(spawns: &Spawns, to_exit: &[Option<u32>], start: u32, others: &[Vec2]) -> Spot {
        let spot = spawns.pick(others);
        let steps = to_exit[spot.at.cell as usize].expect("a generated maze is connected");
        assert_eq!(spot.ahead, start.saturating_sub(steps), "{steps} cells from the exit, the start {start}");
        let clearance = |p: Vec2| others.iter().map(|o| o.distance(p)).fold(f32::INFINITY, f32::min);
        let behind_free = spawns.rings.iter().flatten().any(|s| clearance(s.at.pos) >= s.apart);
        assert!(spot.ahead == 0 || !behind_free, "{} cells ahead with a spot behind free", spot.ahead);
        spot
    }

    /// Red-team pass 4, F3, on the reproducer's maze (`--gen 20x15 --seed 7`): with 47 players
    /// standing where newcomers were put, the 48th started 21 cells from the exit, the start 33. Now
    /// the first 27 newcomers (as many as the cells as far from the exit as the start's, within
    /// reach) start no nearer, a cell apart; the later ones are marked nearer.
    #[test]
    fn a_crowd_at_the_start_moves_no_newcomer_nearer_the_exit_while_it_can() {
        use mazewalk_maze::generate::{GenOptions, generate};
        let maze = generate(&GenOptions::walk(20, 15, 7)).unwrap();
        let to_exit = hops(&maze, maze.exit().unwrap().cell);
        let spawns = Spawns::new(&maze).unwrap();
        let start = to_exit[spawns.start.cell as usize].unwrap();
        assert_eq!(start, 33, "the reproducer's start");
        let behind: HashSet<u32> = spawns.rings.iter().flatten().map(|spot| spot.at.cell).collect();
        assert_eq!(behind.len(), 27);
        let mut here: Vec<Vec2> = Vec::new();
        for n in 0..48 {
            let spot = checked_pick(&spawns, &to_exit, start, &here);
            assert_eq!(spot.ahead == 0, n < 27, "newcomer {n}");
            here.push(spot.at.pos);
        }
    }

    /// A generated maze of any shape (2 to 24 cells a side), seed and share of loops, with an exit.
    fn arb_maze() -> impl Strategy<Value = Maze> {
        use mazewalk_maze::generate::{GenOptions, generate};
        (2u32..=24, 2u32..=24, any::<u64>(), prop_oneof![Just(0.0f32), Just(0.1), Just(0.5)]).prop_map(
            |(width, height, seed, loops)| {
                let options = GenOptions { loops, ..GenOptions::walk(width, height, seed) };
                generate(&options).expect("a size within the generator's range")
            },
        )
    }

    proptest! {
        // (64 cases: each generates a maze and places up to 40 newcomers, scanning every spot)
        #![proptest_config(mazewalk_testkit::config_cases(64))]

        /// Red-team pass 4, F3: over generated mazes, a newcomer's spot is nearer the exit than the
        /// start's only when no spot as far is a cell apart, and marked with how much nearer; and
        /// newcomers get cells of their own while any are left among those tried.
        #[test]
        fn a_spawn_nearer_the_exit_is_a_last_resort_and_marked(maze in arb_maze(), crowd in 1usize..40) {
            let to_exit = hops(&maze, maze.exit().expect("generated with an exit").cell);
            let spawns = Spawns::new(&maze).expect("the start is in a cell");
            let start = to_exit[spawns.start.cell as usize].expect("a generated maze is connected");
            let cells: HashSet<u32> =
                spawns.rings.iter().flatten().chain(&spawns.ahead).map(|spot| spot.at.cell).collect();
            let mut here: Vec<Vec2> = Vec::new();
            let mut taken: HashSet<u32> = HashSet::new();
            for n in 0..crowd {
                let spot = checked_pick(&spawns, &to_exit, start, &here);
                if n < cells.len() {
                    prop_assert!(taken.insert(spot.at.cell), "newcomer {} shares a cell, {} free", n, cells.len() - n);
                }
                here.push(spot.at.pos);
            }
        }
    }

    /// A maze without an exit marks no spot nearer it.
    #[test]
    fn without_an_exit_no_spot_is_ahead() {
        let maze = maze(CORRIDOR);
        assert!(maze.exit().is_none());
        let spawns = Spawns::new(&maze).unwrap();
        let mut here: Vec<Vec2> = Vec::new();
        for _ in 0..6 {
            let spot = spawns.pick(&here);
            assert_eq!(spot.ahead, 0);
            here.push(spot.at.pos);
        }
        assert!(spawns.ahead.is_empty());
    }

    #[test]
    fn a_crowd_too_big_for_the_maze_still_gets_the_emptiest_spot() {
        let maze = maze("mazewalk-grid 1\ntile 1\n\n###\n#@#\n###\n");
        let others = [maze.viewer().pos];
        let spot = free_spot(&maze, &others).unwrap();
        assert_eq!(maze.cell_at(spot.pos), Some(spot.cell), "still in the maze");
    }
    /// Red-team pass 8: in an arena of 30-unit cells, with 1,024 others spread so that no spot is a
    /// cell apart from all of them, a join measured every spot against every other (~230,000 ×
    /// 1,024 distances, under the world's lock). The pick reads only the others near each spot and
    /// stops at its budget, and still gives the spot with the most room it saw.
    #[test]
    fn a_pick_among_a_spread_crowd_in_huge_cells_measures_a_bounded_number_of_distances() {
        let rows: String =
            (0..8).map(|y| format!("#{}#\n", if y == 0 { "@......." } else { "........" })).collect();
        let maze = maze(&format!("mazewalk-grid 1\ntile 30\n\n##########\n{rows}##########\n"));
        let spawns = Spawns::new(&maze).unwrap();
        let spots: usize = spawns.rings.iter().map(Vec::len).sum::<usize>() + spawns.ahead.len();
        let (lo, hi) = (maze.extents().min, maze.extents().max);
        let others: Vec<Vec2> = (0..32 * 32)
            .map(|k| lo + (hi - lo) * Vec2::new((k % 32) as f32 + 0.5, (k / 32) as f32 + 0.5) / 32.0)
            .collect();
        assert!(spots * others.len() > 100_000_000, "the premise: {spots} spots");
        let (spot, work) = spawns.pick_counted(&Crowd::new(&others));
        assert!(work <= MAX_PICK_WORK + 9 * others.len(), "{work} distances");
        let room = |p: Vec2| others.iter().map(|o| o.distance(p)).fold(f32::INFINITY, f32::min);
        assert!(room(spot.at.pos) >= SPACING, "a spot {} from the nearest other", room(spot.at.pos));
        assert_eq!(maze.cell_at(spot.at.pos), Some(spot.at.cell));
    }

    /// A spot's room counts every other within [`NEAR`], across the buckets' edges.
    #[test]
    fn a_spots_room_is_the_distance_to_the_nearest_other_up_to_near() {
        let others = [Vec2::new(7.9, 0.0), Vec2::new(-3.0, 4.0), Vec2::new(100.0, 100.0)];
        let (crowd, mut work) = (Crowd::new(&others), 0);
        for p in [Vec2::new(0.0, 0.0), Vec2::new(8.1, 0.0), Vec2::new(-0.5, 7.9), Vec2::new(50.0, 50.0)] {
            let exact = others.iter().map(|o| o.distance(p)).fold(NEAR, f32::min);
            assert_eq!(crowd.clearance(p, &mut work), exact, "at {p}");
        }
    }
}
