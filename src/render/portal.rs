//! The portal pass: which walls can be seen, found by walking from cell to cell through portals.
//!
//! # The idea (the classic "Maze" project, made exact)
//!
//! Start in the cell the viewer stands in with the whole screen as the *region* that can still show
//! something. For each edge of the cell, project its wall quad (clipped in homogeneous clip space — no
//! divide before clipping) and intersect its screen footprint with the region. An opaque edge that
//! survives is a wall to draw; a transparent edge (a portal) that survives narrows the region to the
//! part of the screen seen through it, and the neighbour cell is visited with that narrower region.
//!
//! # Why screen space, and why rectangles
//!
//! The original narrows a 2D wedge in the maze plane, which is exact only for a level view. Here every
//! test happens on the projected, clipped quads in the grid, so any pitch, eye height, field of view and
//! both projections are handled by the same code. Regions are axis-aligned screen rectangles ("cull
//! boxes", as in Luebke & Georges, *Portals and Mirrors*, 1995): intersecting two is four `min`/`max`,
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

use glam::{Vec2, Vec3};

use super::camera::{CEILING_Z, Eye, FLOOR_Z, Projection};
use super::wall::{ClipScratch, clip_wall};
use crate::maze::Maze;

/// The pseudo-cell for everything outside the maze's cells (beyond boundary edges).
const OUTSIDE: u32 = u32::MAX;
/// Screen footprints grow by this many samples on every side, so rounding never loses a wall.
const INFLATE: f32 = 1.0;

/// An axis-aligned rectangle in grid space (samples), `x0 <= x1`, `y0 <= y1` when not empty.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rect {
    /// Left.
    pub x0: f32,
    /// Top.
    pub y0: f32,
    /// Right.
    pub x1: f32,
    /// Bottom.
    pub y1: f32,
}

impl Rect {
    /// Nothing at all.
    pub const EMPTY: Rect =
        Rect { x0: f32::INFINITY, y0: f32::INFINITY, x1: f32::NEG_INFINITY, y1: f32::NEG_INFINITY };

    /// The overlap of two rectangles (may be empty).
    #[must_use]
    pub fn intersect(self, o: Rect) -> Rect {
        Rect { x0: self.x0.max(o.x0), y0: self.y0.max(o.y0), x1: self.x1.min(o.x1), y1: self.y1.min(o.y1) }
    }

    /// True when the rectangle has no points (touching edges count as overlap: the test is inclusive).
    #[must_use]
    pub fn is_empty(self) -> bool {
        !(self.x0 <= self.x1 && self.y0 <= self.y1)
    }

    /// True when `o` lies inside `self`.
    #[must_use]
    pub fn contains(self, o: Rect) -> bool {
        self.x0 <= o.x0 && self.y0 <= o.y0 && self.x1 >= o.x1 && self.y1 >= o.y1
    }

    /// Grows the rectangle to include `p`.
    fn add(&mut self, p: Vec2) {
        self.x0 = self.x0.min(p.x);
        self.y0 = self.y0.min(p.y);
        self.x1 = self.x1.max(p.x);
        self.y1 = self.y1.max(p.y);
    }
}

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

/// Reusable state of the portal pass (sized once per maze, reused every frame: no per-frame clearing).
#[derive(Debug, Default)]
pub struct PortalPass {
    stamp: u32,
    wall_stamp: Vec<u32>,
    cell_stamp: Vec<u32>,
    cell_region: Vec<Rect>,
    outside_region: Option<Rect>,
    stack: Vec<(u32, Rect)>,
    flood: Vec<u32>,
    seed_stamp: Vec<u32>,
    scratch: ClipScratch,
    /// Walls (edge ids) chosen this frame, in the order found.
    pub walls: Vec<u32>,
    /// Distinct cells visited this frame (for the map).
    pub visited: Vec<u32>,
}

impl PortalPass {
    /// An empty pass; buffers grow to the maze on first use.
    #[must_use]
    pub fn new() -> PortalPass {
        PortalPass::default()
    }

    /// True if `cell` was visited by the last [`PortalPass::run`].
    #[must_use]
    pub fn was_visited(&self, cell: u32) -> bool {
        self.cell_stamp.get(cell as usize).is_some_and(|&s| s == self.stamp)
    }

    fn begin(&mut self, maze: &Maze) {
        let (cells, edges) = (maze.cell_count(), maze.edges().len());
        if self.cell_stamp.len() != cells || self.wall_stamp.len() != edges {
            self.cell_stamp = vec![0; cells];
            self.seed_stamp = vec![0; cells];
            self.cell_region = vec![Rect::EMPTY; cells];
            self.wall_stamp = vec![0; edges];
            self.stamp = 0;
        }
        self.stamp = self.stamp.wrapping_add(1);
        if self.stamp == 0 {
            // Wrapped after 4 billion frames: forget every old stamp once.
            self.cell_stamp.fill(0);
            self.seed_stamp.fill(0);
            self.wall_stamp.fill(0);
            self.stamp = 1;
        }
        self.walls.clear();
        self.visited.clear();
        self.stack.clear();
        self.outside_region = None;
    }

    /// Finds the walls `eye` can see in `maze`; they end up in [`PortalPass::walls`].
    pub fn run(&mut self, maze: &Maze, eye: &Eye) -> PortalStats {
        self.begin(maze);
        let mut stats = PortalStats::default();
        let screen = Rect { x0: 0.0, y0: 0.0, x1: eye.width as f32, y1: eye.height as f32 };
        let screen = Rect {
            x0: screen.x0 - INFLATE,
            y0: screen.y0 - INFLATE,
            x1: screen.x1 + INFLATE,
            y1: screen.y1 + INFLATE,
        };

        for seed in self.seeds(maze, eye) {
            stats.seeds += 1;
            self.stack.push((seed, screen));
        }
        // A generous cap: the walk is acyclic, so this only guards against pathological inputs.
        let cap = 16 * (maze.cell_count() + 1) + 4096;
        while let Some((cell, region)) = self.stack.pop() {
            if !self.enter(cell, region) {
                continue;
            }
            stats.cells_visited += 1;
            if stats.cells_visited > cap {
                stats.fell_back = true;
                self.walls.clear();
                self.walls.extend(0..maze.edges().len() as u32);
                return stats;
            }
            if cell == OUTSIDE {
                for e in 0..maze.edges().len() as u32 {
                    let edge = &maze.edges()[e as usize];
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

    /// Marks `cell` as explored with `region`; false if a region containing it was explored already.
    fn enter(&mut self, cell: u32, region: Rect) -> bool {
        if cell == OUTSIDE {
            if self.outside_region.is_some_and(|r| r.contains(region)) {
                return false;
            }
            self.outside_region = Some(region);
            return true;
        }
        let i = cell as usize;
        if self.cell_stamp[i] == self.stamp {
            if self.cell_region[i].contains(region) {
                return false;
            }
        } else {
            self.cell_stamp[i] = self.stamp;
            self.visited.push(cell);
        }
        self.cell_region[i] = region;
        true
    }

    /// One edge of a visited cell: draw it if opaque, walk through it if it is a portal facing away.
    fn visit_edge(
        &mut self,
        maze: &Maze,
        eye: &Eye,
        cell: u32,
        e: u32,
        region: Rect,
        stats: &mut PortalStats,
    ) {
        let edge = &maze.edges()[e as usize];
        let Some(footprint) = self.footprint(maze, eye, e) else { return };
        let seen = region.intersect(footprint);
        if seen.is_empty() {
            return;
        }
        if edge.opaque {
            if self.wall_stamp[e as usize] != self.stamp {
                self.wall_stamp[e as usize] = self.stamp;
                self.walls.push(e);
            }
            return;
        }
        // The cell on the other side; `cell` is on the left or right of start → end.
        let cell_on_left = if cell == OUTSIDE { edge.left.is_none() } else { edge.left == Some(cell) };
        let beyond = if cell_on_left { edge.right } else { edge.left };
        let beyond = beyond.unwrap_or(OUTSIDE);
        if beyond == cell {
            return;
        }
        let (a, b) = (maze.vertices()[edge.start as usize], maze.vertices()[edge.end as usize]);
        // Cross only away from the eye: rays from the eye (or, orthographic, along the view) leave the
        // near side of the portal's line for the far side and never come back.
        let along = b - a;
        let toward_left = match eye.camera.projection {
            Projection::Perspective => along.perp_dot(eye.position.truncate() - a),
            Projection::Orthographic => -along.perp_dot(eye.forward.truncate()),
        };
        let crosses_away = if cell_on_left { toward_left > 0.0 } else { toward_left < 0.0 };
        if crosses_away {
            stats.portals_traversed += 1;
            self.stack.push((beyond, seen));
        }
    }

    /// The inflated grid-space bounding box of edge `e`'s wall quad, clipped to the view volume.
    fn footprint(&mut self, maze: &Maze, eye: &Eye, e: u32) -> Option<Rect> {
        let poly = clip_wall(maze, eye, e, &mut self.scratch)?;
        let mut r = Rect::EMPTY;
        for v in poly {
            r.add(eye.grid(v.clip).truncate());
        }
        Some(Rect { x0: r.x0 - INFLATE, y0: r.y0 - INFLATE, x1: r.x1 + INFLATE, y1: r.y1 + INFLATE })
    }

    /// The cells where camera rays start: every cell the near-plane rectangle (within the floor-to-ceiling
    /// slab) touches, plus [`OUTSIDE`] if it reaches beyond the maze's cells.
    fn seeds(&mut self, maze: &Maze, eye: &Eye) -> Vec<u32> {
        let (w, h) = (eye.width as f32, eye.height as f32);
        let corners = [(0.0, 0.0), (w, 0.0), (w, h), (0.0, h)].map(|(x, y)| eye.ray(x, y).0);
        let Some(mut bounds) = slab_footprint(&corners) else { return Vec::new() };
        // The flood starts in the eye's cell, so the box must hold the eye too: an eye on a vertex or
        // an edge line may be "in" a cell the near plane itself never touches.
        bounds.add(eye.position.truncate());
        // Rounding must not lose a seed: grow the footprint a little.
        let pad = 1e-3 + 1e-5 * (bounds.x1.abs().max(bounds.y1.abs()));
        bounds = Rect { x0: bounds.x0 - pad, y0: bounds.y0 - pad, x1: bounds.x1 + pad, y1: bounds.y1 + pad };

        let mut seeds = Vec::new();
        let mut outside = false;
        self.flood.clear();
        let push = |pass: &mut PortalPass, cell: Option<u32>, outside: &mut bool| match cell {
            Some(c) if pass.seed_stamp[c as usize] != pass.stamp => {
                pass.seed_stamp[c as usize] = pass.stamp;
                pass.flood.push(c);
            }
            Some(_) => {}
            None => *outside = true,
        };
        let centre = Vec2::new((bounds.x0 + bounds.x1) * 0.5, (bounds.y0 + bounds.y1) * 0.5);
        push(
            self,
            maze.cell_containing(eye.position.truncate()).or_else(|| maze.cell_containing(centre)),
            &mut outside,
        );
        let mut i = 0;
        loop {
            while i < self.flood.len() {
                let cell = self.flood[i];
                i += 1;
                seeds.push(cell);
                for &e in maze.cell_edges(cell) {
                    let edge = &maze.edges()[e as usize];
                    let (a, b) = (maze.vertices()[edge.start as usize], maze.vertices()[edge.end as usize]);
                    if segment_touches_rect(a, b, bounds) {
                        let other = if edge.left == Some(cell) { edge.right } else { edge.left };
                        push(self, other, &mut outside);
                    }
                }
            }
            if !outside || seeds.contains(&OUTSIDE) {
                break;
            }
            // Rays start beyond the maze's cells too: the outside is a seed, and through it every cell
            // whose boundary edge the footprint touches (the maze may have holes or several parts).
            seeds.push(OUTSIDE);
            for edge in maze.edges() {
                if edge.left.is_some() && edge.right.is_some() {
                    continue;
                }
                let (a, b) = (maze.vertices()[edge.start as usize], maze.vertices()[edge.end as usize]);
                if segment_touches_rect(a, b, bounds) {
                    push(self, edge.left.or(edge.right), &mut outside);
                }
            }
        }
        seeds
    }
}

/// The maze-plane bounding box of a planar convex polygon cut to the slab FLOOR_Z <= z <= CEILING_Z.
fn slab_footprint(corners: &[Vec3; 4]) -> Option<Rect> {
    let mut r = Rect::EMPTY;
    let n = corners.len();
    for i in 0..n {
        let (p, q) = (corners[i], corners[(i + 1) % n]);
        if (FLOOR_Z..=CEILING_Z).contains(&p.z) {
            r.add(p.truncate());
        }
        // Where the edge p→q crosses the floor or the ceiling plane.
        for z in [FLOOR_Z, CEILING_Z] {
            if (p.z - z) * (q.z - z) < 0.0 {
                let t = (z - p.z) / (q.z - p.z);
                r.add(p.truncate().lerp(q.truncate(), t));
            }
        }
    }
    (!r.is_empty()).then_some(r)
}

/// True if segment `a`–`b` meets the closed rectangle `r` (Liang–Barsky on the slab intervals).
pub fn segment_touches_rect(a: Vec2, b: Vec2, r: Rect) -> bool {
    let d = b - a;
    let (mut t0, mut t1) = (0.0f32, 1.0f32);
    for (p, q) in [(-d.x, a.x - r.x0), (d.x, r.x1 - a.x), (-d.y, a.y - r.y0), (d.y, r.y1 - a.y)] {
        if p == 0.0 {
            if q < 0.0 {
                return false;
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rect_intersection_and_containment_are_inclusive() {
        let a = Rect { x0: 0.0, y0: 0.0, x1: 2.0, y1: 2.0 };
        let b = Rect { x0: 2.0, y0: 1.0, x1: 3.0, y1: 3.0 };
        assert!(!a.intersect(b).is_empty(), "touching rectangles overlap (conservative)");
        assert!(a.intersect(Rect { x0: 2.1, ..b }).is_empty());
        assert!(a.contains(a));
        assert!(!a.contains(b));
        assert!(Rect::EMPTY.is_empty());
    }

    #[test]
    fn segments_touching_a_rect() {
        let r = Rect { x0: 0.0, y0: 0.0, x1: 1.0, y1: 1.0 };
        assert!(segment_touches_rect(Vec2::new(-1.0, 0.5), Vec2::new(2.0, 0.5), r));
        assert!(segment_touches_rect(Vec2::new(1.0, 1.0), Vec2::new(3.0, 3.0), r), "touching a corner");
        assert!(!segment_touches_rect(Vec2::new(1.5, -1.0), Vec2::new(1.5, 3.0), r));
        assert!(segment_touches_rect(Vec2::new(0.5, 0.5), Vec2::new(0.5, 0.5), r), "a point inside");
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
        let r = slab_footprint(&c).expect("crosses the slab");
        assert_eq!((r.x0, r.x1), (0.0, 1.0));
        // Entirely under the floor: no footprint.
        let below = c.map(|p| Vec3::new(p.x, p.y, -5.0));
        assert!(slab_footprint(&below).is_none());
    }
}
