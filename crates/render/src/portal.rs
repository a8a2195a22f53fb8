//! The portal pass: which walls can be seen, found by walking from cell to cell through portals.
//!
//! # The idea (the classic "Maze" project, made exact)
//!
//! Start in the cell the viewer stands in with the whole grid as the *region* that can still show
//! something. For each edge of the cell, project its wall quad (clipped in homogeneous clip space — no
//! divide before clipping) and intersect its grid footprint with the region. An opaque edge that
//! survives is a wall to draw; a transparent edge (a portal) that survives narrows the region to the
//! part of the grid seen through it, and the neighbour cell is visited with that narrower region.
//!
//! # Why grid space, and why boxes
//!
//! The original narrows a 2D wedge in the maze plane, which is exact only for a level view. Here every
//! test happens on the projected, clipped quads in the grid, so any pitch, eye height, field of view and
//! both projections are handled by the same code. Regions are axis-aligned grid-space boxes ([`Aabb`]:
//! "cull boxes", as in Luebke & Georges, *Portals and Mirrors*, 1995): intersecting two is four `min`/`max`,
//! they cannot degenerate numerically, and inflating them by one sample makes every test conservative
//! despite rounding. They are looser than exact portal polygons, which costs a few extra cells, never a
//! missing wall.
//!
//! # Why it is exact against brute force
//!
//! The pass only *chooses* walls; the pipeline then draws each chosen wall exactly as the brute-force
//! pass would (clipped against the view volume only, in ascending wall order, depth-tested). So the two
//! frames are equal sample for sample as long as every wall that wins a sample in brute force is chosen.
//! It is: a camera ray starts on the near plane (in a *seed* cell), and until it hits a wall it leaves
//! each cell through a portal whose projection contains the ray's sample and which it crosses away from
//! the eye; by induction its sample lies in the region of every cell it passes, so the wall it finally
//! hits is chosen. Seeds are all cells the near-plane rectangle touches (usually just the viewer's), so a
//! viewer standing in a doorway or pressed against a wall is covered too.
//!
//! # Termination without a "visited" flag
//!
//! A cell may be reached through several portals (mazes with loops) and is visited once per distinct
//! region — a global visited flag would hide the second path. A portal is only crossed *away* from the
//! eye (the eye strictly on the near side of its line; for orthographic views, the view direction
//! pointing across it); in a planar convex subdivision that order has no cycles, so the walk ends. A
//! visit whose region lies inside one already explored from the same cell is skipped, and a hard cap on
//! visits falls back to drawing every wall (still exact, just slower) — it exists for safety, not use.
//! The walk uses an explicit stack: no recursion, no depth limit, no stack overflow on 1000×1000 mazes.

use std::collections::hash_map::Entry;

use glam::{Vec2, Vec3};
use rustc_hash::{FxHashMap, FxHashSet};

use super::camera::{Eye, Projection};
use super::wall::{ClipScratch, clip_wall};
use mazewalk_maze::geometry::{CEILING_Z, FLOOR_Z};
use mazewalk_maze::{Aabb, Maze};

/// The pseudo-cell for everything outside the maze's cells (beyond boundary edges).
const OUTSIDE: u32 = u32::MAX;
/// Screen footprints grow by this many samples on every side, so rounding never loses a wall.
const INFLATE: f32 = 1.0;

/// What the portal pass did, for `--stats`, the HUD and the map.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PortalStats {
    /// Cell visits (a cell reached through two portals with different regions counts twice).
    pub cells_visited: usize,
    /// Distinct cells visited.
    pub distinct_cells: usize,
    /// Portals crossed.
    pub portals_traversed: usize,
    /// Seed cells the near plane touches.
    pub seeds: usize,
    /// The safety cap was hit and every wall is drawn instead.
    pub fell_back: bool,
}

/// Reusable state of the portal pass. What a frame has done per cell and per wall is kept in hash sets
/// and maps, not arrays the size of the maze: a frame visits tens of cells, and every player of a
/// server has a pass of its own (arrays took 36 MB a player on a 1000 × 1000 maze).
#[derive(Debug, Default)]
pub struct PortalPass {
    /// Walls chosen this frame.
    chosen: FxHashSet<u32>,
    /// The cells visited this frame, each with the grid box it was last explored with.
    cell_region: FxHashMap<u32, Aabb>,
    outside_region: Option<Aabb>,
    stack: Vec<(u32, Aabb)>,
    flood: Vec<u32>,
    /// Cells put in the seed flood this frame.
    flooded: FxHashSet<u32>,
    scratch: ClipScratch,
    /// Walls (edge ids) chosen this frame, in the order found.
    pub walls: Vec<u32>,
    /// Distinct cells visited this frame (for the map).
    pub visited: Vec<u32>,
    /// The last run hit the safety cap: every wall was chosen, and [`visited`](Self::visited) holds
    /// only the cells reached before it.
    fell_back: bool,
}

impl PortalPass {
    /// An empty pass; buffers grow to the maze on first use.
    #[must_use]
    pub fn new() -> PortalPass {
        PortalPass::default()
    }

    /// True if the last [`PortalPass::run`] hit its safety cap and chose every wall: what depends on
    /// the cells seen is then drawn for every cell, as without culling.
    #[must_use]
    pub fn fell_back(&self) -> bool {
        self.fell_back
    }

    /// True if `cell` was visited by the last [`PortalPass::run`].
    #[must_use]
    pub fn was_visited(&self, cell: u32) -> bool {
        self.cell_region.contains_key(&cell)
    }

    fn begin(&mut self) {
        self.chosen.clear();
        self.cell_region.clear();
        self.flooded.clear();
        self.walls.clear();
        self.visited.clear();
        self.stack.clear();
        self.outside_region = None;
        self.fell_back = false;
    }

    /// Finds the walls `eye` can see in `maze`; they end up in [`PortalPass::walls`].
    pub fn run(&mut self, maze: &Maze, eye: &Eye) -> PortalStats {
        self.begin();
        let mut stats = PortalStats::default();
        let grid_box = Aabb::new(Vec2::ZERO, Vec2::new(eye.width as f32, eye.height as f32)).expand(INFLATE);

        for seed in self.seeds(maze, eye) {
            stats.seeds += 1;
            self.stack.push((seed, grid_box));
        }
        while let Some((cell, region)) = self.stack.pop() {
            if !self.enter(cell, region) {
                continue;
            }
            stats.cells_visited += 1;
            if past_the_cap(stats.cells_visited, self.visited.len()) {
                (stats.fell_back, self.fell_back) = (true, true);
                self.walls.clear();
                self.walls.extend(maze.edges().opaque_ids()); // every wall, as brute force
                return stats;
            }
            if cell == OUTSIDE {
                for e in 0..maze.edges().len() as u32 {
                    let edge = maze.edge(e);
                    if edge.left.is_none() || edge.right.is_none() {
                        self.visit_edge(maze, eye, OUTSIDE, e, region, &mut stats);
                    }
                }
            } else {
                for &e in maze.cell_edges(cell) {
                    self.visit_edge(maze, eye, cell, e, region, &mut stats);
                }
            }
        }
        stats.distinct_cells = self.visited.len();
        stats
    }

    /// Marks `cell` as explored with `region` (a grid box); false if a region containing it was explored
    /// already.
    fn enter(&mut self, cell: u32, region: Aabb) -> bool {
        if cell == OUTSIDE {
            if self.outside_region.is_some_and(|r| r.contains(&region)) {
                return false;
            }
            self.outside_region = Some(region);
            return true;
        }
        match self.cell_region.entry(cell) {
            Entry::Occupied(mut explored) if !explored.get().contains(&region) => {
                explored.insert(region);
            }
            Entry::Occupied(_) => return false,
            Entry::Vacant(first) => {
                first.insert(region);
                self.visited.push(cell);
            }
        }
        true
    }

    /// One edge of a visited cell: draw it if opaque, walk through it if it is a portal facing away.
    fn visit_edge(
        &mut self,
        maze: &Maze,
        eye: &Eye,
        cell: u32,
        e: u32,
        region: Aabb,
        stats: &mut PortalStats,
    ) {
        let edge = maze.edge(e);
        // Projection is the pass's cost, so it comes last: a wall already chosen is not projected again,
        // and a portal only once it is known to be crossed.
        if edge.opaque {
            if !self.chosen.contains(&e) && self.seen(maze, eye, e, region).is_some() {
                self.chosen.insert(e);
                self.walls.push(e);
            }
            return;
        }
        // The cell on the other side; `cell` is on the left or right of start → end.
        let (cell_on_left, beyond) = if cell == OUTSIDE {
            (edge.left.is_none(), edge.left.or(edge.right)) // a boundary edge: its one cell
        } else {
            (edge.left == Some(cell), edge.other_side(cell))
        };
        let beyond = beyond.unwrap_or(OUTSIDE);
        if beyond == cell {
            return;
        }
        let (a, b) = maze.edge_points(e);
        // Cross only away from the eye: rays from the eye (or, orthographic, along the view) leave the
        // near side of the portal's line for the far side and never come back.
        let along = b - a;
        let toward_left = match eye.camera.projection {
            Projection::Perspective => along.perp_dot(eye.position.truncate() - a),
            Projection::Orthographic => -along.perp_dot(eye.forward.truncate()),
        };
        let crosses_away = if cell_on_left { toward_left > 0.0 } else { toward_left < 0.0 };
        // (So the portal a cell was entered by is never projected from that side.)
        if crosses_away && let Some(seen) = self.seen(maze, eye, e, region) {
            stats.portals_traversed += 1;
            self.stack.push((beyond, seen));
        }
    }

    /// The part of `region` edge `e`'s footprint covers, if any.
    fn seen(&mut self, maze: &Maze, eye: &Eye, e: u32, region: Aabb) -> Option<Aabb> {
        let seen = region.intersection(self.footprint(maze, eye, e)?);
        (!seen.is_empty()).then_some(seen)
    }

    /// The inflated grid-space bounding box of edge `e`'s wall quad, clipped to the view volume.
    fn footprint(&mut self, maze: &Maze, eye: &Eye, e: u32) -> Option<Aabb> {
        let poly = clip_wall(maze, eye, e, &mut self.scratch)?;
        let grid_box = poly.iter().fold(Aabb::EMPTY, |b, v| b.union_point(eye.grid(v.clip).truncate()));
        Some(grid_box.expand(INFLATE))
    }

    /// The cells where camera rays start: every cell the near-plane rectangle (within the floor-to-ceiling
    /// slab) touches, plus [`OUTSIDE`] if it reaches beyond the maze's cells.
    fn seeds(&mut self, maze: &Maze, eye: &Eye) -> Vec<u32> {
        let (w, h) = (eye.width as f32, eye.height as f32);
        let corners = [(0.0, 0.0), (w, 0.0), (w, h), (0.0, h)].map(|(x, y)| eye.ray(x, y).0);
        let Some(world_box) = slab_footprint(&corners) else { return Vec::new() };
        // The flood starts in the eye's cell, so the box must hold the eye too: an eye on a vertex or
        // an edge line may be "in" a cell the near plane itself never touches.
        let eye_world = eye.position.truncate();
        let world_box = world_box.union_point(eye_world);
        // Rounding must not lose a seed: grow the footprint a little.
        let world_box = world_box.expand(1e-3 + 1e-5 * (world_box.max.x.abs().max(world_box.max.y.abs())));

        let mut seeds = Vec::new();
        let mut outside = false;
        self.flood.clear();
        let push = |pass: &mut PortalPass, cell: Option<u32>, outside: &mut bool| match cell {
            Some(c) if pass.flooded.insert(c) => pass.flood.push(c),
            Some(_) => {}
            None => *outside = true,
        };
        let start = maze.cell_at(eye_world).or_else(|| maze.cell_at(world_box.centre()));
        push(self, start, &mut outside);
        let mut i = 0;
        loop {
            while i < self.flood.len() {
                let cell = self.flood[i];
                i += 1;
                seeds.push(cell);
                for &e in maze.cell_edges(cell) {
                    let (a, b) = maze.edge_points(e);
                    if world_box.touches_segment(a, b) {
                        push(self, maze.edge(e).other_side(cell), &mut outside);
                    }
                }
            }
            if !outside || seeds.contains(&OUTSIDE) {
                break;
            }
            // Rays start beyond the maze's cells too: the outside is a seed, and through it every cell
            // whose boundary edge the footprint touches (the maze may have holes or several parts).
            seeds.push(OUTSIDE);
            for (e, edge) in (0..).zip(maze.edges()) {
                if edge.left.is_some() && edge.right.is_some() {
                    continue;
                }
                let (a, b) = maze.edge_points(e);
                if world_box.touches_segment(a, b) {
                    push(self, edge.left.or(edge.right), &mut outside);
                }
            }
        }
        seeds
    }
}

/// `true` once the walk has made more visits than any real view needs: 16 for each distinct cell it
/// has reached so far, plus 4096. The walk is acyclic, so this only guards against pathological
/// inputs: an open floor of tiny cells reaches each cell with hundreds of regions (red-team pass 8:
/// a 400 × 400 floor of half-unit tiles made 2.6 million visits, 0.6 s a frame, when the cap counted
/// the whole maze's cells; drawing every wall took 29 ms). Past it the pass draws every wall, which
/// is exactly the brute-force frame: the cap's value changes the time a frame takes, never the
/// picture (so its mutants are excluded from mutation testing, MUTANTS.md).
fn past_the_cap(visits: usize, distinct_cells: usize) -> bool {
    visits > 16 * (distinct_cells + 1) + 4096
}

/// The maze-plane (world x, y) bounding box of a planar convex polygon (world space) cut to the slab
/// FLOOR_Z <= z <= CEILING_Z.
fn slab_footprint(corners: &[Vec3; 4]) -> Option<Aabb> {
    let mut world_box = Aabb::EMPTY;
    let n = corners.len();
    for i in 0..n {
        let (p, q) = (corners[i], corners[(i + 1) % n]);
        if (FLOOR_Z..=CEILING_Z).contains(&p.z) {
            world_box = world_box.union_point(p.truncate());
        }
        // Where the edge p→q crosses the floor or the ceiling plane.
        for z in [FLOOR_Z, CEILING_Z] {
            if (p.z - z) * (q.z - z) < 0.0 {
                let t = (z - p.z) / (q.z - p.z);
                world_box = world_box.union_point(p.truncate().lerp(q.truncate(), t));
            }
        }
    }
    (!world_box.is_empty()).then_some(world_box)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Camera;
    use mazewalk_maze::grid;

    fn maze(text: &str) -> Maze {
        grid::parse_str("t.grid", text).unwrap()
    }

    fn eye_at(maze: &Maze, yaw: f32) -> Eye {
        let viewer = maze.viewer();
        Camera::new(viewer.pos, yaw, 90.0).eye(80, 48, 1.0).unwrap()
    }

    /// No "visited" flag: a cell is explored again only through a region its earlier ones do not cover
    /// (the rule that keeps the pass from redoing work a cell reached through two portals already did).
    #[test]
    fn a_cell_is_explored_again_only_through_a_region_not_covered_yet() {
        let mut pass = PortalPass::default();
        pass.begin();
        let wide = Aabb::new(Vec2::new(0.0, 0.0), Vec2::new(40.0, 20.0));
        let inside = Aabb::new(Vec2::new(5.0, 5.0), Vec2::new(30.0, 15.0));
        let beside = Aabb::new(Vec2::new(30.0, 0.0), Vec2::new(60.0, 20.0));
        assert!(pass.enter(3, inside), "first time");
        assert!(pass.enter(3, wide), "a region the first does not cover");
        assert!(!pass.enter(3, inside), "covered by the region explored last");
        assert!(pass.enter(3, beside), "not covered");
        assert_eq!(pass.visited, [3], "listed once, however often explored");
        assert!(pass.enter(OUTSIDE, wide) && !pass.enter(OUTSIDE, inside), "outside the maze alike");
    }

    /// Red-team pass 8: an open floor of half-unit tiles reaches each cell in view through dozens
    /// of regions (~40 visits a cell at 100 × 100). The pass gives up at 16 visits a distinct cell
    /// reached (plus 4096) and draws every wall, not at 16 for every cell of the whole maze.
    #[test]
    fn an_open_floor_of_tiny_tiles_falls_back_within_the_cells_it_reached() {
        let n = 100;
        let rows: Vec<String> = (0..n)
            .map(|r| format!("#{}{}#", if r == n / 2 { '@' } else { '.' }, ".".repeat(n - 1)))
            .collect();
        let wall = "#".repeat(n + 2);
        let floor = maze(&format!(
            "mazewalk-grid 1\ntile 0.5002\nfacing east\n\n{wall}\n{}\n{wall}\n",
            rows.join("\n")
        ));
        let centre = Vec2::splat(n as f32 * 0.5002 / 2.0);
        let eye = Camera::new(centre, 30.0, 90.0).eye(120, 78, 1.0).unwrap();
        let mut pass = PortalPass::new();
        let stats = pass.run(&floor, &eye);
        assert!(stats.fell_back, "{stats:?}");
        assert!(stats.cells_visited <= 16 * (pass.visited.len() + 1) + 4097, "{stats:?}");
        // Every wall, and no portal (red-team pass 9: the 8 million portals of a 2046 × 2046 floor,
        // never drawn, were each clipped to the view for every frame past the cap).
        let walls: Vec<u32> = (0..floor.edges().len() as u32).filter(|&e| floor.edge(e).opaque).collect();
        assert_eq!(pass.walls, walls, "every wall, no portal");
    }

    /// Five tiles in a row, looking down them from the first: one seed, each cell entered once, each of
    /// the four portals crossed once, walls on both sides of every tile and at the far end.
    #[test]
    fn a_straight_corridor_is_counted_exactly() {
        let corridor = maze("mazewalk-grid 1\n#######\n#>....#\n#######\n");
        let mut pass = PortalPass::new();
        let stats = pass.run(&corridor, &eye_at(&corridor, 0.0));
        assert_eq!(
            (
                stats.seeds,
                stats.cells_visited,
                stats.distinct_cells,
                stats.portals_traversed,
                stats.fell_back
            ),
            (1, 5, 5, 4, false)
        );
        let mut visited = pass.visited.clone();
        visited.sort_unstable();
        assert_eq!(visited, [0, 1, 2, 3, 4]);
        assert!((0..5).all(|c| pass.was_visited(c)) && !pass.was_visited(5) && !pass.was_visited(u32::MAX));
        assert_eq!(pass.walls.len(), 11, "{:?}", pass.walls);
        // Turned round, the first tile's back wall is all there is.
        let stats = pass.run(&corridor, &eye_at(&corridor, 180.0));
        assert_eq!((stats.cells_visited, stats.portals_traversed), (1, 0));
        assert!(pass.was_visited(0) && !pass.was_visited(1), "the last run's cells only");
    }

    /// One pass reused across mazes of other sizes (as the walk does when a file is reloaded, and a
    /// server for several mazes would) finds what a fresh pass finds, also when only the number of cells
    /// or only the number of edges changes, and after a frame that saw more.
    #[test]
    fn a_reused_pass_equals_a_fresh_one() {
        let room = maze("mazewalk-grid 1\n####\n#..#\n#>.#\n####\n"); // 4 cells, 12 edges
        let row = maze("mazewalk-grid 1\n######\n#>...#\n######\n"); // 4 cells, 13 edges
        let long = maze("mazewalk-grid 1\n##########\n#>.......#\n##########\n"); // 8 cells
        let wide = maze("mazewalk-grid 1\n#####\n#...#\n#>..#\n#####\n"); // 6 cells, 17 edges
        let apart = maze("mazewalk-grid 1\n########\n#>...#.#\n########\n"); // 5 cells, 17 edges
        assert_eq!((room.cell_count(), row.cell_count()), (4, 4));
        assert_ne!(room.edges().len(), row.edges().len());
        assert_eq!((apart.cell_count(), wide.cell_count()), (5, 6));
        assert_eq!(apart.edges().len(), wide.edges().len());
        let result = |pass: &PortalPass| {
            let (mut walls, mut cells) = (pass.walls.clone(), pass.visited.clone());
            walls.sort_unstable();
            cells.sort_unstable();
            (walls, cells)
        };
        let fresh = |m: &Maze, yaw: f32| {
            let mut pass = PortalPass::new();
            pass.run(m, &eye_at(m, yaw));
            result(&pass)
        };
        let mut pass = PortalPass::new();
        for m in [&room, &row, &long, &room, &long, &row, &apart, &wide, &apart] {
            pass.run(m, &eye_at(m, 30.0));
            assert_eq!(result(&pass), fresh(m, 30.0));
        }
        // A frame that sees little after one that saw much: nothing of the first is left marked.
        let mut pass = PortalPass::new();
        pass.run(&long, &eye_at(&long, 0.0));
        pass.run(&long, &eye_at(&long, 180.0));
        assert_eq!(result(&pass), fresh(&long, 180.0));
        assert!(!(0..8).all(|c| pass.was_visited(c)), "{:?}", pass.visited);
    }

    /// A 2 × 3 room (tile side 4): west column x 4..8, east column 8..12, rows y 4..8, 8..12, 12..16.
    fn room_2x3() -> Maze {
        maze("mazewalk-grid 1\n####\n#..#\n#..#\n#>.#\n####\n")
    }

    fn counts(stats: PortalStats) -> (usize, usize) {
        (stats.seeds, stats.portals_traversed)
    }

    /// Rays from the eye never cross a portal whose line runs through the eye: an eye on the line
    /// x = 8 between the room's two columns, looking north along it, seeds both bottom cells (it
    /// stands on their shared portal) and crosses only the two northward portals of each column —
    /// never the edge-on portals x = 8 ahead of it, from either side.
    #[test]
    fn a_portal_in_line_with_the_eye_is_crossed_neither_way() {
        let room = room_2x3();
        let eye = Camera::new(Vec2::new(8.0, 6.0), 90.0, 90.0).eye(80, 48, 1.0).unwrap();
        let mut pass = PortalPass::new();
        assert_eq!(counts(pass.run(&room, &eye)), (2, 4));
    }

    /// The orthographic rule: rays all run along the view, so a portal parallel to it is crossed
    /// neither way. A 3 × 2 room looked along from its west end, exactly east (the view's direction
    /// is exact at yaw 0): the near plane spans both rows, so both west cells are seeds, each row's
    /// two eastward portals are crossed, and the three portals between the rows (parallel to the
    /// view) are not.
    #[test]
    fn an_orthographic_view_never_crosses_a_portal_parallel_to_it() {
        let room = maze("mazewalk-grid 1\n#####\n#...#\n#>..#\n#####\n"); // x 4..16, y 4..12
        let mut camera = Camera::new(Vec2::new(6.0, 8.0), 0.0, 90.0);
        camera.projection = Projection::Orthographic;
        let eye = camera.eye(80, 48, 1.0).unwrap();
        assert_eq!(eye.forward.truncate(), Vec2::X);
        let mut pass = PortalPass::new();
        let stats = pass.run(&room, &eye);
        let outside = usize::from(eye.ray(0.0, 24.0).0.y > 12.0);
        assert_eq!(counts(stats), (2 + outside, 4), "{stats:?}");
    }

    /// The seed footprint is grown by a rounding allowance that scales with the coordinates
    /// (1e-3 + 1e-5 × the largest, 0.021 at x ≈ 2,000): far from the origin, a cell whose edge lies
    /// within the allowance of the near plane is a seed, one beyond it is not.
    #[test]
    fn the_seed_allowance_grows_with_the_coordinates() {
        let corridor = maze("mazewalk-grid 1\ntile 1000\n#####\n#>..#\n#####\n"); // x 1,000..4,000
        let seeds_at = |gap: f32| {
            let near = Camera::new(Vec2::new(1500.0, 1500.0), 0.0, 90.0).eye(80, 48, 1.0).unwrap().near;
            // the near plane `gap` short of the portal x = 2,000 between cells 0 and 1
            let eye =
                Camera::new(Vec2::new(2000.0 - near - gap, 1500.0), 0.0, 90.0).eye(80, 48, 1.0).unwrap();
            PortalPass::new().run(&corridor, &eye).seeds
        };
        assert_eq!(seeds_at(0.01), 2, "within the allowance");
        assert_eq!(seeds_at(0.035), 1, "beyond it");
    }

    /// An eye just outside the maze whose near plane already lies inside a cell: rays start in that
    /// cell, so it must be a seed, found through the outside (the eye and the footprint's centre are
    /// both outside every cell). The pass agrees with brute force, sample for sample.
    #[test]
    fn an_eye_outside_with_the_near_plane_inside_a_cell_sees_the_cell() {
        let room = room_2x3();
        let near = Camera::new(Vec2::new(6.0, 6.0), 90.0, 90.0).eye(80, 48, 1.0).unwrap().near;
        // south of the room's bottom wall y = 4, facing north: the near plane 0.4 near inside
        let camera = Camera::new(Vec2::new(6.0, 4.0 - 0.6 * near), 90.0, 90.0);
        let eye = camera.eye(80, 48, 1.0).unwrap();
        assert!(
            room.cell_at(eye.position.truncate()).is_none()
                && room.cell_at(eye.ray(40.0, 24.0).0.truncate()).is_some()
        );
        let stats = PortalPass::new().run(&room, &eye);
        assert!(stats.seeds >= 2, "the outside and the cell beyond the wall: {stats:?}");
        crate::oracle::portal_matches_brute(&room, &camera, crate::Charset::Half, 40, 24)
            .expect("the portal pass agrees with brute force");
    }

    #[test]
    fn slab_footprint_cuts_at_floor_and_ceiling() {
        // A tall vertical rectangle at x = 0..1 reaching from z = -3 to z = 3.
        let c = [
            Vec3::new(0.0, 0.0, -3.0),
            Vec3::new(1.0, 0.0, -3.0),
            Vec3::new(1.0, 0.0, 3.0),
            Vec3::new(0.0, 0.0, 3.0),
        ];
        let world_box = slab_footprint(&c).expect("crosses the slab");
        assert_eq!((world_box.min.x, world_box.max.x), (0.0, 1.0));
        // A slanted parallelogram: its sides run x = z + 3 and x = z + 4, so the slab -1 <= z <= 1 cuts
        // them at x = 2, 4 (floor) and 3, 5 (ceiling).
        let slanted = [
            Vec3::new(0.0, 0.0, -3.0),
            Vec3::new(1.0, 0.0, -3.0),
            Vec3::new(7.0, 0.0, 3.0),
            Vec3::new(6.0, 0.0, 3.0),
        ];
        let cut = slab_footprint(&slanted).expect("crosses the slab");
        assert!((cut.min.x - 2.0).abs() < 1e-5 && (cut.max.x - 5.0).abs() < 1e-5, "{cut:?}");
        // Entirely under the floor: no footprint.
        let below = c.map(|p| Vec3::new(p.x, p.y, -5.0));
        assert!(slab_footprint(&below).is_none());
    }
}
