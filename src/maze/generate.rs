//! Random mazes on a grid of square cells, seeded and the same on every platform.
//!
//! Randomness comes from [`Rng`] (SplitMix64), using integer operations only for decisions; colours
//! are built from integers with exact `f32` arithmetic. A W×H maze has cells of side [`CELL_SIZE`]
//! with the origin at (0, 0), numbered row by row from the south-west (cell `y * W + x`), laid out as
//! the original project's generator does: vertices row by row, then the horizontal edges, then the
//! vertical ones; each cell lists its edges `+x +y -x -y`.
//!
//! ```
//! # use mazewalk::maze::generate::{generate, GenOptions};
//! let maze = generate(&GenOptions { width: 8, height: 5, seed: 7, ..GenOptions::default() })?;
//! assert!(maze.is_perfect());
//! assert_eq!(maze.portal_count(), 8 * 5 - 1);
//! # Ok::<(), mazewalk::maze::generate::GenError>(())
//! ```

use std::str::FromStr;

use glam::{Vec3, vec2};

use super::grid::{Tile, TileMap};
use super::{CellId, Cells, Edge, Exit, Maze, MazeError, Viewer};

/// Side of a generated cell, in maze units (as the original's 10×10 file).
pub const CELL_SIZE: f32 = 4.0;
/// Largest width or height accepted.
pub const MAX_SIDE: u32 = 1000;

/// SplitMix64 (Steele, Lea & Flood 2014): a tiny 64-bit generator, fixed here so a seed gives the
/// same maze everywhere. The first outputs for seed 0 are pinned by a test.
#[derive(Clone, Debug)]
pub struct Rng(u64);

impl Rng {
    /// A generator started at `seed`.
    #[must_use]
    pub fn new(seed: u64) -> Rng {
        Rng(seed)
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// A uniform integer in `0..n` (Lemire's multiply-shift with rejection, unbiased).
    ///
    /// # Panics
    /// In debug builds, if `n` is 0.
    pub fn below(&mut self, n: u32) -> u32 {
        debug_assert!(n > 0);
        let n = u64::from(n.max(1));
        let threshold = (1u64 << 32) % n;
        loop {
            let m = (self.next_u64() >> 32) * n;
            if (m & 0xFFFF_FFFF) >= threshold {
                return (m >> 32) as u32;
            }
        }
    }

    /// A uniform `f32` in [0, 1) on a 2^-23 lattice: exact on every platform.
    pub fn unit_f32(&mut self) -> f32 {
        (self.next_u64() >> 41) as f32 * (1.0 / (1u32 << 23) as f32)
    }
}

/// How passages are carved.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Algorithm {
    /// Randomized Prim's (the original project's): bushy, many short dead ends.
    #[default]
    Prim,
    /// Recursive backtracker (iterative, explicit stack): long winding corridors.
    Backtracker,
    /// Wilson's loop-erased random walks: a uniform spanning tree.
    Wilson,
}

impl FromStr for Algorithm {
    type Err = String;
    fn from_str(s: &str) -> Result<Algorithm, String> {
        match s {
            "prim" => Ok(Algorithm::Prim),
            "dfs" | "backtracker" => Ok(Algorithm::Backtracker),
            "wilson" => Ok(Algorithm::Wilson),
            _ => Err(format!("unknown algorithm `{s}` (expected prim, dfs or wilson)")),
        }
    }
}

/// Wall colours.
#[derive(Clone, Debug, Default, PartialEq)]
pub enum Colors {
    /// Each channel uniform in 0.25..0.75, per edge, as the original.
    #[default]
    Random,
    /// Each edge (or wall tile) picks one of these.
    Palette(Vec<Vec3>),
}

/// What the maze is made of.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Layout {
    /// W×H cells separated by thin walls (the original's; CS559 format).
    #[default]
    Walls,
    /// (2W+1)×(2H+1) square tiles, walls being whole tiles (what the grid format expresses).
    Tiles,
}

/// Generator settings.
#[derive(Clone, Debug, PartialEq)]
pub struct GenOptions {
    /// Cells east–west, 1..=[`MAX_SIDE`].
    pub width: u32,
    /// Cells north–south, 1..=[`MAX_SIDE`].
    pub height: u32,
    /// Same seed, same maze.
    pub seed: u64,
    /// Carving algorithm.
    pub algorithm: Algorithm,
    /// Fraction (0..=1) of the walls left inside a perfect maze to remove, adding cycles.
    pub loops: f32,
    /// Wall colours.
    pub colors: Colors,
    /// Mark the cell farthest from the start (by portal steps) as the exit.
    pub exit: bool,
    /// Thin walls or tiles.
    pub layout: Layout,
}

impl Default for GenOptions {
    fn default() -> Self {
        GenOptions {
            width: 10,
            height: 10,
            seed: 0,
            algorithm: Algorithm::Prim,
            loops: 0.0,
            colors: Colors::Random,
            exit: false,
            layout: Layout::Walls,
        }
    }
}

/// Settings the generator refuses.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[allow(missing_docs)] // the fields are named by the messages
pub enum GenError {
    #[error("size {width}x{height} is out of range (each side 1..={MAX_SIDE})")]
    Size { width: u32, height: u32 },
    #[error("loops {0} is out of range (0..=1)")]
    Loops(f32),
    #[error("the palette is empty")]
    EmptyPalette,
    #[error("internal error: the generated maze is invalid: {0}")]
    Invalid(#[from] MazeError),
}

/// Generates a maze: a spanning tree of the W×H cells (perfect), plus `loops`.
pub fn generate(opts: &GenOptions) -> Result<Maze, GenError> {
    let (w, h) = (opts.width, opts.height);
    if !(1..=MAX_SIDE).contains(&w) || !(1..=MAX_SIDE).contains(&h) {
        return Err(GenError::Size { width: w, height: h });
    }
    if !(0.0..=1.0).contains(&opts.loops) {
        return Err(GenError::Loops(opts.loops));
    }
    if opts.colors == Colors::Palette(Vec::new()) {
        return Err(GenError::EmptyPalette);
    }
    let mut rng = Rng::new(opts.seed);
    let mut grid = Passages::new(w as usize, h as usize);
    match opts.algorithm {
        Algorithm::Prim => grid.prim(&mut rng),
        Algorithm::Backtracker => grid.backtracker(&mut rng),
        Algorithm::Wilson => grid.wilson(&mut rng),
    }
    grid.add_loops(&mut rng, opts.loops);
    match opts.layout {
        Layout::Walls => grid.to_maze(&mut rng, opts),
        Layout::Tiles => Ok(grid.to_tiles(&mut rng, opts).to_maze()?),
    }
}

/// Directions: east, north, west, south (the original's `+x +y -x -y`).
const DIRS: [(isize, isize); 4] = [(1, 0), (0, 1), (-1, 0), (0, -1)];

/// The carved grid: which walls between neighbouring cells are open.
struct Passages {
    w: usize,
    h: usize,
    /// `open_east[c]`: the wall between cell c and its east neighbour is open.
    open_east: Vec<bool>,
    open_north: Vec<bool>,
}

impl Passages {
    fn new(w: usize, h: usize) -> Passages {
        Passages { w, h, open_east: vec![false; w * h], open_north: vec![false; w * h] }
    }

    /// The neighbour of cell `c` in direction `d`, if inside the grid.
    fn neighbour(&self, c: usize, d: usize) -> Option<usize> {
        let (x, y) = ((c % self.w) as isize + DIRS[d].0, (c / self.w) as isize + DIRS[d].1);
        ((0..self.w as isize).contains(&x) && (0..self.h as isize).contains(&y))
            .then(|| y as usize * self.w + x as usize)
    }

    fn is_open(&self, c: usize, d: usize) -> bool {
        match d {
            0 => self.open_east[c],
            1 => self.open_north[c],
            _ => self.neighbour(c, d).is_some_and(|n| self.is_open(n, d - 2)),
        }
    }

    fn open(&mut self, c: usize, d: usize) {
        match d {
            0 => self.open_east[c] = true,
            1 => self.open_north[c] = true,
            _ => {
                if let Some(n) = self.neighbour(c, d) {
                    self.open(n, d - 2);
                }
            }
        }
    }

    /// Randomized Prim's: grow from a random cell through a random frontier wall.
    fn prim(&mut self, rng: &mut Rng) {
        let n = self.w * self.h;
        let mut visited = vec![false; n];
        let mut frontier: Vec<u32> = Vec::new(); // wall = cell * 4 + direction
        let start = rng.below(n as u32) as usize;
        visited[start] = true;
        let push = |c: usize, frontier: &mut Vec<u32>, visited: &[bool], me: &Passages| {
            for d in 0..4 {
                if me.neighbour(c, d).is_some_and(|m| !visited[m]) {
                    frontier.push((c * 4 + d) as u32);
                }
            }
        };
        push(start, &mut frontier, &visited, self);
        while !frontier.is_empty() {
            let wall = frontier.swap_remove(rng.below(frontier.len() as u32) as usize) as usize;
            let (c, d) = (wall / 4, wall % 4);
            let Some(m) = self.neighbour(c, d) else { continue };
            if !visited[m] {
                visited[m] = true;
                self.open(c, d);
                push(m, &mut frontier, &visited, self);
            }
        }
    }

    /// Recursive backtracker, iterative: walk to a random unvisited neighbour, back up at dead ends.
    fn backtracker(&mut self, rng: &mut Rng) {
        let n = self.w * self.h;
        let mut visited = vec![false; n];
        let start = rng.below(n as u32) as usize;
        visited[start] = true;
        let mut stack = vec![start];
        while let Some(&c) = stack.last() {
            let mut options = [0usize; 4];
            let mut k = 0;
            for d in 0..4 {
                if self.neighbour(c, d).is_some_and(|m| !visited[m]) {
                    options[k] = d;
                    k += 1;
                }
            }
            if k == 0 {
                stack.pop();
                continue;
            }
            let d = options[rng.below(k as u32) as usize];
            let m = self.neighbour(c, d).unwrap_or(c);
            visited[m] = true;
            self.open(c, d);
            stack.push(m);
        }
    }

    /// Wilson's: from each cell not yet in the tree, random-walk until the tree is hit, remembering
    /// only the last exit from each cell (which erases loops), then add that path.
    fn wilson(&mut self, rng: &mut Rng) {
        let n = self.w * self.h;
        let mut in_tree = vec![false; n];
        let mut exit_dir = vec![0u8; n];
        in_tree[rng.below(n as u32) as usize] = true;
        for c in 0..n {
            let mut u = c;
            while !in_tree[u] {
                let d = self.random_dir(u, rng);
                exit_dir[u] = d as u8;
                u = self.neighbour(u, d).unwrap_or(u);
            }
            let mut u = c;
            while !in_tree[u] {
                in_tree[u] = true;
                let d = exit_dir[u] as usize;
                self.open(u, d);
                u = self.neighbour(u, d).unwrap_or(u);
            }
        }
    }

    /// A uniformly chosen direction leading to a cell inside the grid (a 1×1 grid has none: 0).
    fn random_dir(&self, c: usize, rng: &mut Rng) -> usize {
        let mut options = [0usize; 4];
        let mut k = 0;
        for d in 0..4 {
            if self.neighbour(c, d).is_some() {
                options[k] = d;
                k += 1;
            }
        }
        if k == 0 { 0 } else { options[rng.below(k as u32) as usize] }
    }

    /// Opens `loops` × (the closed interior walls), chosen by a partial Fisher–Yates shuffle.
    fn add_loops(&mut self, rng: &mut Rng, loops: f32) {
        if loops <= 0.0 {
            return;
        }
        let mut closed: Vec<(u32, u8)> = Vec::new();
        for c in 0..self.w * self.h {
            for d in 0..2 {
                if self.neighbour(c, d).is_some() && !self.is_open(c, d) {
                    closed.push((c as u32, d as u8));
                }
            }
        }
        let k = closed.len();
        let remove = ((f64::from(loops) * k as f64).round() as usize).min(k);
        for i in 0..remove {
            let j = i + rng.below((k - i) as u32) as usize;
            closed.swap(i, j);
            self.open(closed[i].0 as usize, closed[i].1 as usize);
        }
    }

    /// The start cell (0, south-west) and the heading of its first open side (east, north, …).
    fn start(&self) -> (usize, f32) {
        let d = (0..4).find(|&d| self.is_open(0, d)).unwrap_or(0);
        (0, d as f32 * 90.0)
    }

    fn color(rng: &mut Rng, colors: &Colors) -> Vec3 {
        match colors {
            Colors::Random => {
                Vec3::new(0.25 + 0.5 * rng.unit_f32(), 0.25 + 0.5 * rng.unit_f32(), 0.25 + 0.5 * rng.unit_f32())
            }
            Colors::Palette(p) => p[rng.below(p.len() as u32) as usize],
        }
    }

    /// Thin walls, in the original's layout (see the module docs).
    fn to_maze(&self, rng: &mut Rng, opts: &GenOptions) -> Result<Maze, GenError> {
        let (w, h) = (self.w, self.h);
        let vid = |i: usize, j: usize| (j * (w + 1) + i) as u32;
        let cid = |i: usize, j: usize| (j * w + i) as CellId;
        let mut vertices = Vec::with_capacity((w + 1) * (h + 1));
        for j in 0..=h {
            for i in 0..=w {
                vertices.push(vec2(i as f32, j as f32) * CELL_SIZE);
            }
        }
        let mut edges = Vec::with_capacity((h + 1) * w + h * (w + 1));
        // horizontal edges, west to east: the cell north of it is on the left
        for j in 0..=h {
            for i in 0..w {
                let (left, right) = ((j < h).then(|| cid(i, j)), (j > 0).then(|| cid(i, j - 1)));
                let open = j > 0 && j < h && self.open_north[cid(i, j - 1) as usize];
                let color = Self::color(rng, &opts.colors);
                edges.push(Edge { start: vid(i, j), end: vid(i + 1, j), left, right, opaque: !open, color });
            }
        }
        // vertical edges, south to north: the cell west of it is on the left
        let base = (h + 1) * w;
        for j in 0..h {
            for i in 0..=w {
                let (left, right) = ((i > 0).then(|| cid(i - 1, j)), (i < w).then(|| cid(i, j)));
                let open = i > 0 && i < w && self.open_east[cid(i - 1, j) as usize];
                let color = Self::color(rng, &opts.colors);
                edges.push(Edge { start: vid(i, j), end: vid(i, j + 1), left, right, opaque: !open, color });
            }
        }
        let mut cells = Cells::with_capacity(w * h, 4 * w * h);
        let horizontal = |i: usize, j: usize| (j * w + i) as u32;
        let vertical = |i: usize, j: usize| (base + j * (w + 1) + i) as u32;
        for j in 0..h {
            for i in 0..w {
                cells.push(&[vertical(i + 1, j), horizontal(i, j + 1), vertical(i, j), horizontal(i, j)]);
            }
        }
        let (start, dir_deg) = self.start();
        let centre = |c: usize| (vec2((c % w) as f32, (c / w) as f32) + 0.5) * CELL_SIZE;
        let viewer = Viewer { pos: centre(start), z: 0.0, dir_deg, fov_deg: 90.0 };
        let exit = opts.exit.then(|| Exit { cell: self.farthest_from(start) as CellId, point: None });
        Ok(Maze::new(vertices, edges, cells, viewer, exit)?)
    }

    /// Cell (x, y) becomes tile (2x+1, 2y+1) counted from the south-west; an open wall between two
    /// cells becomes an open tile; all else is wall tiles.
    fn to_tiles(&self, rng: &mut Rng, opts: &GenOptions) -> TileMap {
        let (tw, th) = (2 * self.w + 1, 2 * self.h + 1);
        let palette = match &opts.colors {
            Colors::Random => vec![super::grid::DEFAULT_WALL],
            Colors::Palette(p) => p.clone(),
        };
        let mut tiles = Vec::with_capacity(tw * th);
        for _ in 0..tw * th {
            tiles.push(Tile::Wall(rng.below(palette.len() as u32) as u16));
        }
        // row 0 of the tile map is the north edge
        let at = |x: usize, y: usize| (th - 1 - y) * tw + x;
        for c in 0..self.w * self.h {
            let (x, y) = (2 * (c % self.w) + 1, 2 * (c / self.w) + 1);
            tiles[at(x, y)] = Tile::Open;
            if self.open_east[c] {
                tiles[at(x + 1, y)] = Tile::Open;
            }
            if self.open_north[c] {
                tiles[at(x, y + 1)] = Tile::Open;
            }
        }
        let (start, dir_deg) = self.start();
        let tile_of = |c: usize| (2 * (c % self.w) + 1, th - 1 - (2 * (c / self.w) + 1));
        TileMap {
            width: tw,
            height: th,
            tile_size: CELL_SIZE,
            tiles,
            colors: palette,
            start: tile_of(start),
            dir_deg,
            eye: 0.0,
            fov_deg: 90.0,
            exit: opts.exit.then(|| tile_of(self.farthest_from(start))),
        }
    }

    /// The cell farthest from `start` by passage steps (the lowest-numbered on ties).
    fn farthest_from(&self, start: usize) -> usize {
        let mut dist = vec![u32::MAX; self.w * self.h];
        let mut queue = std::collections::VecDeque::from([start]);
        dist[start] = 0;
        let mut far = start;
        while let Some(c) = queue.pop_front() {
            if dist[c] > dist[far] || (dist[c] == dist[far] && c < far) {
                far = c;
            }
            for d in 0..4 {
                if self.is_open(c, d)
                    && let Some(m) = self.neighbour(c, d)
                    && dist[m] == u32::MAX
                {
                    dist[m] = dist[c] + 1;
                    queue.push_back(m);
                }
            }
        }
        far
    }
}
