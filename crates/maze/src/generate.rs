//! Random mazes on a square lattice, seeded and deterministic on every platform.
//!
//! A `width × height` grid of square cells of side [`CELL_SIZE`] with its lower-left corner at the
//! origin is carved by one of three [`Algorithm`]s into a perfect maze (one path between any two
//! cells), then `loops` removes a fraction of the remaining interior walls. Every decision comes from
//! [`SplitMix64`] (integer arithmetic only; colours are picked from a fixed table of 8-bit ones,
//! [`WALL_COLOURS`]), so a seed gives the same maze everywhere.
//!
//! [`generate`] builds the thin-wall maze (walls are edges between cells, like the course files);
//! [`generate_grid`] lays the same layout out as tiles for the [`grid`](super::grid) format, where
//! walls are tiles: cell `(i, j)` becomes tile `(2i+1, 2j+1)`.
//!
//! ```
//! # use mazewalk_maze::generate::{GenOptions, generate};
//! let maze = generate(&GenOptions { width: 8, height: 5, seed: 7, ..GenOptions::default() })?;
//! assert_eq!(maze.cell_count(), 40);
//! assert!(maze.is_perfect());
//! # Ok::<(), mazewalk_maze::generate::GenError>(())
//! ```

use std::collections::VecDeque;

use glam::{Vec3, vec2};

use super::geometry::{NARROW_ASPECT, clearance_for, ends_showing_half_tan, floor_showing_half_tan};
use super::grid::TileMap;
use super::{CellId, Cells, Edge, Edges, Exit, Maze, Viewer};

/// Side of a generated cell, in maze units.
pub const CELL_SIZE: f32 = 4.0;
/// Largest width and largest height, in cells.
pub const MAX_SIDE: u32 = 1000;

/// SplitMix64 (Steele, Lea, Flood 2014; the seeder of xoshiro): a 64-bit state advanced by the golden
/// gamma and mixed by two xor-shift-multiplies. Small, fast, and fixed here so seeds never change meaning.
#[derive(Clone, Debug)]
pub struct SplitMix64(u64);

impl SplitMix64 {
    /// A generator starting from `seed`.
    #[must_use]
    pub fn new(seed: u64) -> SplitMix64 {
        SplitMix64(seed)
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// A number in `0..n` (multiply-shift of the high 32 bits; bias below 2^-32 · n).
    ///
    /// # Panics
    /// In debug builds, if `n` is 0.
    pub fn below(&mut self, n: u32) -> u32 {
        debug_assert!(n > 0);
        (((self.next_u64() >> 32) * u64::from(n)) >> 32) as u32
    }

    /// A number in `[0, 1)` with 24 random bits (exact in `f32`).
    pub fn unit_f32(&mut self) -> f32 {
        (self.next_u64() >> 40) as f32 * (1.0 / (1u32 << 24) as f32)
    }
}

/// How the perfect maze is carved.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Algorithm {
    /// Randomized Prim's: grow from the start, opening a random frontier wall (the original's).
    #[default]
    Prim,
    /// Recursive backtracker (depth-first, explicit stack): long winding corridors.
    Backtracker,
    /// Wilson's: loop-erased random walks; a uniformly random spanning tree.
    Wilson,
}

mazewalk_names::named!(
    Algorithm,
    "algorithm",
    [
        ("prim", Algorithm::Prim),
        ("dfs", Algorithm::Backtracker),
        ("wilson", Algorithm::Wilson),
        ("backtracker", Algorithm::Backtracker),
    ]
);

/// What to generate.
#[derive(Clone, Debug, PartialEq)]
pub struct GenOptions {
    /// Cells across (x), `1..=MAX_SIDE`.
    pub width: u32,
    /// Cells up (y), `1..=MAX_SIDE`.
    pub height: u32,
    /// The carving algorithm.
    pub algorithm: Algorithm,
    /// The PRNG seed.
    pub seed: u64,
    /// Fraction (0..=1) of the interior walls left after carving that are removed, adding cycles.
    pub loops: f32,
    /// Mark the cell farthest from the start (by portal steps) as the exit (in a 1×1 maze, the start).
    pub exit: bool,
    /// Wall colours to pick from; `None` = one of [`WALL_COLOURS`] (one OKLab lightness, any hue but green).
    pub palette: Option<Vec<Vec3>>,
}

impl Default for GenOptions {
    fn default() -> GenOptions {
        GenOptions {
            width: 10,
            height: 10,
            algorithm: Algorithm::Prim,
            seed: 0,
            loops: 0.0,
            exit: false,
            palette: None,
        }
    }
}

impl GenOptions {
    /// The maze `mazewalk --gen WxH --seed N` walks: `width × height` cells from `seed`, a tenth of
    /// the walls left closed removed (loops), and an exit at the cell farthest from the start: the
    /// one `mazewalk gen --size WxH --seed N --loops 0.1 --exit` writes.
    #[must_use]
    pub fn walk(width: u32, height: u32, seed: u64) -> GenOptions {
        GenOptions { width, height, seed, loops: 0.1, exit: true, ..GenOptions::default() }
    }
}

/// Options the generator refuses.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum GenError {
    /// Width or height outside `1..=MAX_SIDE`.
    #[error("size {width}x{height} is out of range: width and height must be 1..={MAX_SIDE}")]
    Size {
        /// Requested width.
        width: u32,
        /// Requested height.
        height: u32,
    },
    /// `loops` not a number in 0..=1.
    #[error("loops {0} is out of range: it must be a fraction in 0..=1")]
    Loops(f32),
    /// An empty palette, or a colour outside 0..1.
    #[error("the palette must hold at least one colour, each channel in 0..=1")]
    Palette,
}

/// Directions, in the order cells list their edges (as the original): +x, +y, -x, -y.
const EAST: u8 = 0;
const NORTH: u8 = 1;
const WEST: u8 = 2;
const SOUTH: u8 = 3;

/// Which walls of a `width × height` cell grid are open. Cell `(i, j)` has id `j * width + i`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Layout {
    /// Cells across.
    pub width: u32,
    /// Cells up.
    pub height: u32,
    /// `east_open[c]`: the wall between cell `c` and its +x neighbour is open.
    pub east_open: Vec<bool>,
    /// `north_open[c]`: the wall between cell `c` and its +y neighbour is open.
    pub north_open: Vec<bool>,
    /// The viewer's cell (cell 0, the lower-left corner).
    pub start: CellId,
    /// The exit cell, if asked for.
    pub exit: Option<CellId>,
}

impl Layout {
    fn neighbour(&self, c: CellId, d: u8) -> Option<CellId> {
        let (w, h) = (self.width, self.height);
        let (i, j) = (c % w, c / w);
        match d {
            EAST if i + 1 < w => Some(c + 1),
            NORTH if j + 1 < h => Some(c + w),
            WEST if i > 0 => Some(c - 1),
            SOUTH if j > 0 => Some(c - w),
            _ => None,
        }
    }

    /// `true` when the wall from `c` towards `d` is open (`false` at the boundary).
    #[must_use]
    pub fn is_open(&self, c: CellId, d: u8) -> bool {
        match (d, self.neighbour(c, d)) {
            (_, None) => false,
            (EAST, _) => self.east_open[c as usize],
            (NORTH, _) => self.north_open[c as usize],
            (WEST, Some(n)) => self.east_open[n as usize],
            (_, Some(n)) => self.north_open[n as usize],
        }
    }

    fn open(&mut self, c: CellId, d: u8) {
        match (d, self.neighbour(c, d)) {
            (_, None) => debug_assert!(false, "opening the boundary"),
            (EAST, _) => self.east_open[c as usize] = true,
            (NORTH, _) => self.north_open[c as usize] = true,
            (WEST, Some(n)) => self.east_open[n as usize] = true,
            (_, Some(n)) => self.north_open[n as usize] = true,
        }
    }

    /// Portal steps from `from` to each cell.
    fn distances(&self, from: CellId) -> Vec<u32> {
        let mut dist = vec![u32::MAX; (self.width * self.height) as usize];
        dist[from as usize] = 0;
        let mut queue = VecDeque::from([from]);
        while let Some(c) = queue.pop_front() {
            for d in 0..4 {
                if let Some(n) = self.neighbour(c, d).filter(|_| self.is_open(c, d))
                    && dist[n as usize] == u32::MAX
                {
                    dist[n as usize] = dist[c as usize] + 1;
                    queue.push_back(n);
                }
            }
        }
        dist
    }

    /// The first open direction from the start (east if none), as degrees counter-clockwise from +x.
    fn start_dir_deg(&self) -> f32 {
        (0..4).find(|&d| self.is_open(self.start, d)).map_or(0.0, |d| f32::from(d) * 90.0)
    }
}

fn check(opts: &GenOptions) -> Result<(), GenError> {
    let side = 1..=MAX_SIDE;
    if !side.contains(&opts.width) || !side.contains(&opts.height) {
        return Err(GenError::Size { width: opts.width, height: opts.height });
    }
    if !(0.0..=1.0).contains(&opts.loops) {
        return Err(GenError::Loops(opts.loops));
    }
    if let Some(p) = &opts.palette
        && (p.is_empty() || p.iter().any(|c| !(c.min_element() >= 0.0 && c.max_element() <= 1.0)))
    {
        return Err(GenError::Palette);
    }
    Ok(())
}

/// Carves the layout `opts` asks for.
pub fn layout(opts: &GenOptions) -> Result<Layout, GenError> {
    check(opts)?;
    let n = (opts.width * opts.height) as usize;
    let mut l = Layout {
        width: opts.width,
        height: opts.height,
        east_open: vec![false; n],
        north_open: vec![false; n],
        start: 0,
        exit: None,
    };
    let mut rng = SplitMix64::new(opts.seed);
    match opts.algorithm {
        Algorithm::Prim => prim(&mut l, &mut rng),
        Algorithm::Backtracker => backtracker(&mut l, &mut rng),
        Algorithm::Wilson => wilson(&mut l, &mut rng),
    }
    add_loops(&mut l, opts.loops, &mut rng);
    if opts.exit {
        let dist = l.distances(l.start);
        // the farthest cell; the lowest id among ties
        let far = (0..n).max_by_key(|&c| (dist[c], std::cmp::Reverse(c))).unwrap_or(0);
        l.exit = Some(far as CellId);
    }
    Ok(l)
}

/// Randomized Prim's: a frontier of walls (cell, direction) out of the carved region; open a random
/// one whose far side is new.
fn prim(l: &mut Layout, rng: &mut SplitMix64) {
    let n = (l.width * l.height) as usize;
    let mut inside = vec![false; n];
    let mut frontier: Vec<(CellId, u8)> = Vec::new();
    let start = rng.below(n as u32);
    inside[start as usize] = true;
    frontier.extend((0..4).filter(|&d| l.neighbour(start, d).is_some()).map(|d| (start, d)));
    while !frontier.is_empty() {
        let (c, d) = frontier.swap_remove(rng.below(frontier.len() as u32) as usize);
        let Some(next) = l.neighbour(c, d) else { continue };
        if inside[next as usize] {
            continue;
        }
        l.open(c, d);
        inside[next as usize] = true;
        for d in 0..4 {
            if let Some(m) = l.neighbour(next, d)
                && !inside[m as usize]
            {
                frontier.push((next, d));
            }
        }
    }
}

/// Recursive backtracker with an explicit stack: step to a random unvisited neighbour, else back up.
fn backtracker(l: &mut Layout, rng: &mut SplitMix64) {
    let n = (l.width * l.height) as usize;
    let mut visited = vec![false; n];
    let start = rng.below(n as u32);
    visited[start as usize] = true;
    let mut stack = vec![start];
    while let Some(&c) = stack.last() {
        let mut options = [0u8; 4];
        let mut k = 0;
        for d in 0..4 {
            if l.neighbour(c, d).is_some_and(|m| !visited[m as usize]) {
                options[k] = d;
                k += 1;
            }
        }
        if k == 0 {
            stack.pop();
            continue;
        }
        let d = options[rng.below(k as u32) as usize];
        let next = l.neighbour(c, d).unwrap_or(c);
        l.open(c, d);
        visited[next as usize] = true;
        stack.push(next);
    }
}

/// Wilson's: from each cell not yet in the tree, random-walk until the tree is hit, remembering only the
/// last exit direction from each cell (which erases loops), then carve the remembered path.
fn wilson(l: &mut Layout, rng: &mut SplitMix64) {
    let (w, h) = (l.width, l.height);
    let n = (w * h) as usize;
    let mut in_tree = vec![false; n];
    let mut exit_dir = vec![0u8; n];
    in_tree[rng.below(n as u32) as usize] = true;
    for s in 0..n as CellId {
        let mut c = s;
        while !in_tree[c as usize] {
            // the hot loop: neighbours from (i, j) directly, one division per step
            let (i, j) = (c % w, c / w);
            let mut options = [(0u8, 0u32); 4];
            let mut k = 0;
            for (d, ok, next) in [
                (EAST, i + 1 < w, c.wrapping_add(1)),
                (NORTH, j + 1 < h, c.wrapping_add(w)),
                (WEST, i > 0, c.wrapping_sub(1)),
                (SOUTH, j > 0, c.wrapping_sub(w)),
            ] {
                if ok {
                    options[k] = (d, next);
                    k += 1;
                }
            }
            let (d, next) = options[rng.below(k as u32) as usize];
            exit_dir[c as usize] = d;
            c = next;
        }
        let mut c = s;
        while !in_tree[c as usize] {
            let d = exit_dir[c as usize];
            l.open(c, d);
            in_tree[c as usize] = true;
            c = l.neighbour(c, d).unwrap_or(c);
        }
    }
}

/// Removes `round(loops × k)` of the `k` interior walls still closed, chosen by a partial
/// Fisher–Yates shuffle of them in id order.
fn add_loops(l: &mut Layout, loops: f32, rng: &mut SplitMix64) {
    if loops <= 0.0 {
        return;
    }
    let n = l.width * l.height;
    let mut closed: Vec<(CellId, u8)> = Vec::new();
    for c in 0..n {
        for d in [EAST, NORTH] {
            if l.neighbour(c, d).is_some() && !l.is_open(c, d) {
                closed.push((c, d));
            }
        }
    }
    let k = (f64::from(loops) * closed.len() as f64).round() as usize;
    for i in 0..k.min(closed.len()) {
        let j = i + rng.below((closed.len() - i) as u32) as usize;
        closed.swap(i, j);
        let (c, d) = closed[i];
        l.open(c, d);
    }
}

/// The colour source for edges or tiles: the given palette's (kept as given), or one of
/// [`WALL_COLOURS`].
fn pick_color(rng: &mut SplitMix64, palette: Option<&[Vec3]>) -> Vec3 {
    match palette {
        Some(p) => p[rng.below(p.len() as u32) as usize],
        None => wall_colour(rng.below(WALL_COLOURS.len() as u32) as usize),
    }
}

/// [`WALL_COLOURS`]' entry `k`, sRGB in 0..1.
fn wall_colour(k: usize) -> Vec3 {
    let [r, g, b] = WALL_COLOURS[k];
    Vec3::new(f32::from(r), f32::from(g), f32::from(b)) / 255.0
}

/// The OKLab hue (degrees) of [`WALL_COLOURS`]' entry `k`: the table runs round the circle every 3°
/// from 0°, leaving out the green hues 117°–180°.
#[must_use]
pub const fn wall_colour_hue(k: usize) -> u32 {
    let k = k as u32;
    if k < 39 { 3 * k } else { 3 * (k + 22) }
}

/// How far apart in hue (degrees) two generated walls in one line meeting at a seam are at least
/// (issue #39): picked independently, one seam in ten joined two walls within 15° of each other, which
/// 256 colours show as one entry, and a player lost count of the cells along a corridor. 60° apart at
/// the table's chroma is an OKLab distance of 0.09, several 256-colour steps.
pub const SEAM_HUE_APART: u32 = 60;

/// A generated wall's colour index when the wall before it in its line (`before`, its index) is
/// also a wall: uniform over the entries at least [`SEAM_HUE_APART`] from it in hue; otherwise any.
fn seam_colour_index(rng: &mut SplitMix64, before: Option<usize>) -> usize {
    let Some(before) = before else {
        return rng.below(WALL_COLOURS.len() as u32) as usize;
    };
    let apart = |k: usize| {
        let d = wall_colour_hue(k).abs_diff(wall_colour_hue(before));
        d.min(360 - d) >= SEAM_HUE_APART
    };
    let allowed = (0..WALL_COLOURS.len()).filter(|&k| apart(k)).count();
    let pick = rng.below(allowed as u32) as usize;
    (0..WALL_COLOURS.len()).filter(|&k| apart(k)).nth(pick).unwrap_or(0)
}

/// OKLab lightness of every generated wall colour ([`WALL_COLOURS`]).
pub const WALL_LIGHTNESS: f32 = 0.75;
/// OKLab chroma of every generated wall colour ([`WALL_COLOURS`]).
pub const WALL_CHROMA: f32 = 0.09;

/// A generated maze's wall colours (8-bit sRGB): **one lightness, hue alone tells them apart**
/// (issue #39). Lightness is left to the geometry (the headlight lights a wall faced square on more
/// than one along the view, the fog darkens the far one), so a light side wall can no longer pass for
/// a dark wall faced square on through an opening; hue carries identity (which wall, where a seam
/// is). OKLab L [`WALL_LIGHTNESS`] (about what the renderer's walls-apart rule already raised most
/// of the old random colours to), chroma [`WALL_CHROMA`] (moderate: the 256-colour cube has an entry
/// within about 0.05 of each; of 0.06 and 0.09 tried, 0.09 kept the 256-colour picture's hue error
/// and grain nearer the old colours'), hue every 3° round the circle except where the colour is green by
/// [`not_green`]'s rule, the one statement of it (at this lightness and chroma, OKLab hues 117°–180°).
/// Each is its OKLch colour rounded to 8 bits (L within 0.002, chroma within 0.002: the maze tests
/// check every entry against an OKLab oracle), a table so that no float function of the platform's
/// can change a seed's maze.
pub const WALL_COLOURS: [[u8; 3]; 98] = [
    [222, 150, 171],
    [223, 150, 168],
    [223, 150, 165],
    [224, 150, 162],
    [225, 150, 159],
    [225, 151, 156],
    [225, 151, 152],
    [225, 151, 149],
    [225, 152, 146],
    [225, 152, 143],
    [225, 153, 140],
    [225, 153, 137],
    [224, 154, 134],
    [224, 154, 132],
    [223, 155, 129],
    [222, 156, 126],
    [221, 157, 124],
    [220, 158, 121],
    [219, 159, 119],
    [218, 160, 117],
    [216, 161, 115],
    [215, 162, 113],
    [213, 163, 112],
    [211, 164, 110],
    [210, 165, 109],
    [208, 166, 108],
    [205, 167, 107],
    [203, 168, 106],
    [201, 169, 106],
    [199, 171, 106],
    [196, 172, 106],
    [193, 173, 106],
    [191, 174, 106],
    [188, 175, 107],
    [185, 176, 108],
    [182, 177, 109],
    [179, 179, 110],
    [176, 180, 112],
    [173, 181, 113],
    [102, 193, 179],
    [100, 193, 182],
    [99, 192, 185],
    [98, 192, 188],
    [97, 192, 191],
    [97, 192, 194],
    [96, 191, 197],
    [97, 191, 200],
    [97, 190, 203],
    [98, 190, 205],
    [99, 189, 208],
    [101, 188, 210],
    [102, 188, 213],
    [104, 187, 215],
    [106, 186, 217],
    [109, 185, 219],
    [111, 185, 221],
    [114, 184, 222],
    [117, 183, 224],
    [119, 182, 225],
    [122, 181, 227],
    [126, 180, 228],
    [129, 179, 229],
    [132, 178, 230],
    [135, 177, 230],
    [138, 176, 231],
    [142, 175, 231],
    [145, 174, 232],
    [148, 173, 232],
    [152, 172, 232],
    [155, 170, 232],
    [158, 169, 231],
    [161, 168, 231],
    [164, 167, 230],
    [168, 166, 229],
    [171, 165, 228],
    [174, 164, 227],
    [177, 163, 226],
    [180, 162, 224],
    [182, 161, 223],
    [185, 160, 221],
    [188, 159, 220],
    [191, 159, 218],
    [193, 158, 216],
    [196, 157, 213],
    [198, 156, 211],
    [200, 155, 209],
    [203, 155, 206],
    [205, 154, 204],
    [207, 153, 201],
    [209, 153, 199],
    [211, 152, 196],
    [212, 152, 193],
    [214, 151, 190],
    [216, 151, 187],
    [217, 151, 184],
    [218, 150, 181],
    [220, 150, 178],
    [221, 150, 175],
];

/// `color`, or where it is green (the exit's hue: its beacon and the light it casts tint toward
/// green, so a green wall reads as the exit's glow from afar) the same colour with green and blue
/// swapped: as saturated, a blue hue (190°–290°) instead. (Red and green swapped gave muted browns,
/// which 256 colours render too orange.) Green is a hue of 70°–170° (HSV; yellow-greens too, which
/// 256 colours draw green) with a saturation (max − min) / max over 0.12; greys and near-greys stay.
///
/// ```
/// # use glam::Vec3;
/// # use mazewalk_maze::generate::not_green;
/// assert_eq!(not_green(Vec3::new(0.3, 0.7, 0.4)), Vec3::new(0.3, 0.4, 0.7));
/// assert_eq!(not_green(Vec3::new(0.7, 0.3, 0.4)), Vec3::new(0.7, 0.3, 0.4));
/// assert_eq!(not_green(Vec3::splat(0.5)), Vec3::splat(0.5));
/// ```
#[must_use]
pub fn not_green(color: Vec3) -> Vec3 {
    let (max, min) = (color.max_element(), color.min_element());
    if max <= 0.0 || (max - min) / max <= 0.12 || color.y < max {
        return color; // grey, or green is not the strongest channel
    }
    // green strongest: the hue is 60° (yellow, red = max) to 180° (cyan, blue = max), 120° at pure green
    let hue = 120.0 + 60.0 * (color.z - color.x) / (max - min);
    if (70.0..=170.0).contains(&hue) { Vec3::new(color.x, color.z, color.y) } else { color }
}

/// A random thin-wall maze: `opts.width × opts.height` square cells of side [`CELL_SIZE`].
///
/// Vertex `(i, j)` is `j * (width + 1) + i` at `(4i, 4j)`; edges list the horizontal ones row by row,
/// then the vertical ones; each cell lists its edges +x, +y, -x, -y. The viewer stands in the centre of
/// cell 0 at eye height 0 with a 90° field of view, facing its first open side; its clearance is 1.6
/// (2/5 of a cell) and the walk keeps a vertical field of view of 96° or more
/// ([`Maze::min_vfov_deg`]), so that from the closest stand the floor, the ceiling and the wall's ends
/// show.
pub fn generate(opts: &GenOptions) -> Result<Maze, GenError> {
    let l = layout(opts)?;
    // colours come from their own stream, so the layout does not depend on the palette
    let mut rng = SplitMix64::new(opts.seed ^ 0xC010_C010_C010_C010);
    Ok(thin_maze(&l, &mut rng, opts.palette.as_deref()))
}

fn thin_maze(l: &Layout, rng: &mut SplitMix64, palette: Option<&[Vec3]>) -> Maze {
    let (w, h) = (l.width, l.height);
    let vid = |i: u32, j: u32| j * (w + 1) + i;
    let cell = |i: u32, j: u32| j * w + i;
    let mut vertices = Vec::with_capacity(((w + 1) * (h + 1)) as usize);
    for j in 0..=h {
        for i in 0..=w {
            vertices.push(vec2(i as f32, j as f32) * CELL_SIZE);
        }
    }
    let horizontal = w * (h + 1);
    let mut edges = Edges::with_capacity((horizontal + (w + 1) * h) as usize);
    // Each wall's colour: from the given palette, or from WALL_COLOURS apart in hue from the wall
    // before it in its line where both are walls (`seam_colour_index`).
    let mut colour = |opaque: bool, before: Option<(bool, usize)>| -> (Vec3, usize) {
        if let Some(p) = palette {
            return (pick_color(rng, Some(p)), 0);
        }
        let before = before.filter(|&(wall, _)| wall && opaque).map(|(_, k)| k);
        let k = seam_colour_index(rng, before);
        (wall_colour(k), k)
    };
    // the colour index of each edge, for the next one in its line
    let mut index: Vec<usize> = Vec::with_capacity((horizontal + (w + 1) * h) as usize);
    // horizontal edge (i, j) runs east along y = 4j: the cell above is on its left
    for j in 0..=h {
        for i in 0..w {
            let left = (j < h).then(|| cell(i, j));
            let right = (j > 0).then(|| cell(i, j - 1));
            let opaque = right.is_none_or(|below| !l.north_open[below as usize]) || left.is_none();
            let before = (i > 0).then(|| {
                let e = edges.len() - 1;
                (edges.is_opaque(e), index[e])
            });
            let (color, k) = colour(opaque, before);
            index.push(k);
            edges.push(Edge { start: vid(i, j), end: vid(i + 1, j), left, right, opaque, color });
        }
    }
    // vertical edge (i, j) runs north along x = 4i: the cell to the west is on its left
    for j in 0..h {
        for i in 0..=w {
            let left = (i > 0).then(|| cell(i - 1, j));
            let right = (i < w).then(|| cell(i, j));
            let opaque = left.is_none_or(|west| !l.east_open[west as usize]) || right.is_none();
            let before = (j > 0).then(|| {
                let e = edges.len() - (w as usize + 1);
                (edges.is_opaque(e), index[e])
            });
            let (color, k) = colour(opaque, before);
            index.push(k);
            edges.push(Edge { start: vid(i, j), end: vid(i, j + 1), left, right, opaque, color });
        }
    }
    let mut cells = Cells::with_capacity((w * h) as usize, (4 * w * h) as usize);
    for j in 0..h {
        for i in 0..w {
            let east = horizontal + j * (w + 1) + i + 1;
            let north = (j + 1) * w + i;
            let west = horizontal + j * (w + 1) + i;
            let south = j * w + i;
            cells.push(&[east, north, west, south]);
        }
    }
    let (si, sj) = (l.start % w, l.start / w);
    let viewer = Viewer {
        pos: (vec2(si as f32, sj as f32) + 0.5) * CELL_SIZE,
        z: 0.0,
        dir_deg: l.start_dir_deg(),
        fov_deg: 90.0,
    };
    let exit = l.exit.map(|cell| Exit { cell, point: None });
    // correct by construction; validating costs little next to generating
    let maze = Maze::new(vertices, edges, cells, viewer, exit)
        .unwrap_or_else(|e| unreachable!("generated maze invalid: {e}"));
    let vfov = generated_min_vfov_deg(CELL_SIZE, viewer.z);
    maze.with_min_vfov_deg(vfov)
}

/// The least vertical field of view (degrees) of a generated maze whose narrowest passage is `passage`
/// across (its clearance [`clearance_for`] of it) and whose eye is at height `eye_z`: the one with
/// which, from the closest stand facing a wall square on, the floor and the ceiling show
/// ([`floor_showing_half_tan`]) and, in the narrowest view the walk is played in ([`NARROW_ASPECT`]:
/// 120×40 half blocks), both ends of the wall do ([`ends_showing_half_tan`]). For cells 4 wide, eye
/// mid-way: the ends ask for tan 1.67/1.5 = 1.11 vertically, 96° (horizontally 118° at 120×40, 123°
/// at 80×24), the floor for 69°. Both of [`generate`]'s and [`generate_grid`]'s mazes have it, and
/// `mazewalk gen` writes it (CS559: a `vfov DEG` line; grid: a `vfov DEG` setting), so a maze written
/// and loaded again looks as `--gen` shows it.
#[must_use]
pub fn generated_min_vfov_deg(passage: f32, eye_z: f32) -> f32 {
    let clearance = clearance_for(passage);
    let floor = floor_showing_half_tan(clearance, eye_z);
    let ends = ends_showing_half_tan(passage, clearance) / NARROW_ASPECT;
    // in f64, rounded once: the same f32 whether the compiler folds the arctangent or the library does
    (2.0 * f64::from(floor.max(ends)).atan().to_degrees()) as f32
}

/// The same random layout as [`generate`], as a tile map for the grid format: a
/// `(2·width+1) × (2·height+1)` map where walls are tiles, each a random palette letter (`#` grey
/// without a palette), the start `@`-arrow in the lower-left cell and `E` at the exit.
pub fn generate_grid(opts: &GenOptions) -> Result<TileMap, GenError> {
    let l = layout(opts)?;
    let mut rng = SplitMix64::new(opts.seed ^ 0xC010_C010_C010_C010);
    let (cols, rows) = (2 * l.width as usize + 1, 2 * l.height as usize + 1);
    let legend: Vec<(u8, Vec3)> = match &opts.palette {
        Some(p) => TileMap::LEGEND_LETTERS.iter().zip(p).map(|(&ch, &c)| (ch, c)).collect(),
        None => Vec::new(),
    };
    let mut tiles = vec![b'#'; cols * rows];
    for t in &mut tiles {
        if !legend.is_empty() {
            *t = legend[rng.below(legend.len() as u32) as usize].0;
        }
    }
    // tile (x, y) counts y up from the bottom; text rows run top to bottom
    let mut set = |x: usize, y: usize, ch: u8| tiles[(rows - 1 - y) * cols + x] = ch;
    let mut facing_deg = None;
    for c in 0..l.width * l.height {
        let (i, j) = ((c % l.width) as usize, (c / l.width) as usize);
        let ch = if c == l.start && Some(c) == l.exit {
            // a 1×1 maze: the `E` is the start too, facing as the setting says (east unwritten)
            facing_deg = Some(l.start_dir_deg()).filter(|&d| d != 0.0);
            b'E'
        } else if c == l.start {
            b">^<v"[(l.start_dir_deg() / 90.0) as usize]
        } else if Some(c) == l.exit {
            b'E'
        } else {
            b'.'
        };
        set(2 * i + 1, 2 * j + 1, ch);
        if l.is_open(c, EAST) {
            set(2 * i + 2, 2 * j + 1, b'.');
        }
        if l.is_open(c, NORTH) {
            set(2 * i + 1, 2 * j + 2, b'.');
        }
    }
    // cells and openings a tile (CELL_SIZE) across: the clearance of a generated maze
    let min_vfov_deg = generated_min_vfov_deg(CELL_SIZE, 0.0);
    Ok(TileMap {
        tile: CELL_SIZE,
        eye: 0.0,
        fov_deg: 90.0,
        min_vfov_deg,
        facing_deg,
        legend,
        cols,
        rows,
        tiles,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    // SplitMix64's published reference outputs for seed 0 (e.g. the xoshiro authors' splitmix64.c)
    #[test]
    fn splitmix64_first_outputs_are_pinned() {
        let mut r = SplitMix64::new(0);
        assert_eq!(r.next_u64(), 0xE220_A839_7B1D_CDAF);
        assert_eq!(r.next_u64(), 0x6E78_9E6A_A1B9_65F4);
        assert_eq!(r.next_u64(), 0x06C4_5D18_8009_454F);
    }

    #[test]
    fn below_stays_in_range() {
        let mut r = SplitMix64::new(3);
        assert!((0..10_000).all(|_| r.below(7) < 7));
        assert!((0..10_000).all(|_| (0.0..1.0).contains(&r.unit_f32())));
    }

    #[test]
    fn absurd_options_are_refused() {
        let o = |width, height, loops| GenOptions { width, height, loops, ..GenOptions::default() };
        assert_eq!(generate(&o(0, 5, 0.0)).unwrap_err(), GenError::Size { width: 0, height: 5 });
        assert!(matches!(generate(&o(1001, 5, 0.0)), Err(GenError::Size { .. })));
        assert!(matches!(generate(&o(5, 5, f32::NAN)), Err(GenError::Loops(_))));
        assert!(matches!(generate(&o(5, 5, 1.5)), Err(GenError::Loops(_))));
    }
}
