//! Shared by the benchmarks and the examples: the mazes and the "like" viewpoints. The encoder's
//! yardsticks are `mazewalk_testkit::baseline` (the term crate's tests use them too).
//!
//! Two views, found the same way in every maze size so that a 10×10 and a 1000×1000 maze show alike
//! geometry and any difference in frame time comes from the maze's size alone:
//!
//! - **corridor**: a perfect maze carved by the backtracker (long corridors); the viewer stands in the
//!   middle of the first cell of a straight dead-end corridor [`CORRIDOR_CELLS`] cells long whose side
//!   walls are all closed, looking down it (the first seed from [`SEED`] on whose maze has one). The
//!   visible walls are then the same in every maze (only their colours differ).
//! - **open area**: Prim's maze with half the remaining walls removed ([`OPEN_LOOPS`]); the viewer stands
//!   in a cell centre looking along one of 8 headings. The 10×10 maze's first view that sees at least
//!   [`OPEN_MIN_CELLS`] distinct cells is the reference; the larger mazes use their first view (scanning
//!   outward from the centre) whose distinct cells and walls drawn are both within ±10 % of it.
//!
//! Candidates are scanned in a fixed order, so the views are deterministic.

use glam::{Vec2, vec2};
use mazewalk_maze::Maze;
use mazewalk_maze::generate::{Algorithm, CELL_SIZE, GenOptions, Layout, generate, layout};
use mazewalk_render::{Camera, Charset, Culling, RenderOptions, RenderStats, Renderer, Target};
use mazewalk_term::input::{Key, KeyPhase};
use mazewalk_walk::App;
use mazewalk_walk::state::TURN_SPEED;

/// Maze sides benchmarked (cells across and up).
pub const SIDES: [u32; 3] = [10, 100, 1000];
/// Seed of every benchmark maze.
pub const SEED: u64 = 1;
/// The corridor view: the viewer's cell plus the cells ahead, up to the dead end.
pub const CORRIDOR_CELLS: u32 = 5;
/// Loops of the open-area maze.
pub const OPEN_LOOPS: f32 = 0.5;
/// The open-area reference view sees at least this many distinct cells.
pub const OPEN_MIN_CELLS: usize = 40;
/// Horizontal field of view of every view (the generated mazes' own).
pub const FOV_DEG: f32 = 90.0;
/// The grid the open-area views are matched on (the target size: 200×60 half blocks).
const MATCH_GRID: (usize, usize) = (200, 60);

/// Which view.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum View {
    /// Down a straight dead-end corridor.
    Corridor,
    /// Across an open area of a maze with loops.
    Open,
}

impl View {
    /// Both views.
    pub const ALL: [View; 2] = [View::Corridor, View::Open];

    /// Short name for benchmark ids.
    pub fn name(self) -> &'static str {
        match self {
            View::Corridor => "corridor",
            View::Open => "open",
        }
    }
}

/// A maze and a camera in it.
pub struct Scene {
    /// Which view.
    pub view: View,
    /// Cells across (= cells up).
    pub side: u32,
    /// The maze's seed.
    pub seed: u64,
    /// The maze.
    pub maze: Maze,
    /// The viewer.
    pub camera: Camera,
}

/// Generation options of the maze behind `view` at `side × side` cells.
pub fn maze_options(view: View, side: u32, seed: u64) -> GenOptions {
    match view {
        View::Corridor => GenOptions {
            width: side,
            height: side,
            seed,
            algorithm: Algorithm::Backtracker,
            ..GenOptions::default()
        },
        View::Open => GenOptions {
            width: side,
            height: side,
            seed,
            algorithm: Algorithm::Prim,
            loops: OPEN_LOOPS,
            ..GenOptions::default()
        },
    }
}

/// The scene for `view` in a `side × side` maze.
///
/// # Panics
/// If no matching viewpoint exists (it does for the sizes and seed above).
pub fn scene(view: View, side: u32) -> Scene {
    match view {
        View::Corridor => {
            // A small maze may have no such corridor: the first seed from SEED on that has one.
            let (seed, camera) = (SEED..SEED + 1000)
                .find_map(|seed| {
                    let l = layout(&maze_options(view, side, seed)).expect("benchmark layout");
                    corridor_camera(&l).map(|camera| (seed, camera))
                })
                .expect("a straight corridor");
            let maze = generate(&maze_options(view, side, seed)).expect("benchmark maze");
            Scene { view, side, seed, maze, camera }
        }
        View::Open => {
            let maze = generate(&maze_options(view, side, SEED)).expect("benchmark maze");
            let reference = open_reference();
            let camera =
                if side == reference.0 { reference.1 } else { open_camera(&maze, side, reference.2) };
            Scene { view, side, seed: SEED, maze, camera }
        }
    }
}

/// Cells in scan order: row-major over a window of at most 40 × 40 cells around the maze's centre.
fn candidates(side: u32) -> impl Iterator<Item = (u32, u32)> {
    let m = side.min(40);
    let off = (side - m) / 2;
    (off..off + m).flat_map(move |j| (off..off + m).map(move |i| (i, j)))
}

fn centre(i: u32, j: u32) -> Vec2 {
    (vec2(i as f32, j as f32) + 0.5) * CELL_SIZE
}

/// Directions as the layout numbers them: +x, +y, -x, -y.
fn step(c: u32, d: u8, w: u32) -> u32 {
    match d {
        0 => c + 1,
        1 => c + w,
        2 => c - 1,
        _ => c - w,
    }
}

/// The first straight dead-end corridor of [`CORRIDOR_CELLS`] cells with closed side walls.
fn corridor_camera(l: &Layout) -> Option<Camera> {
    let w = l.width;
    for (i, j) in candidates(w) {
        'dir: for d in 0..4u8 {
            let (left, right) = ((d + 1) % 4, (d + 3) % 4);
            let mut c = j * w + i;
            for k in 0..CORRIDOR_CELLS {
                if l.is_open(c, left) || l.is_open(c, right) {
                    continue 'dir;
                }
                let last = k + 1 == CORRIDOR_CELLS;
                if l.is_open(c, d) == last {
                    continue 'dir; // open all along, closed at the end
                }
                if !last {
                    c = step(c, d, w);
                }
            }
            return Some(Camera::new(centre(i, j), f32::from(d) * 90.0, FOV_DEG));
        }
    }
    None
}

fn portal_stats(renderer: &mut Renderer, maze: &Maze, camera: &Camera) -> RenderStats {
    render_samples(renderer, maze, camera, Charset::Half, MATCH_GRID)
}

/// Renders the samples alone (no glyphs) of a `cols × rows` view in `charset`, with portal culling.
pub fn render_samples(
    renderer: &mut Renderer,
    maze: &Maze,
    camera: &Camera,
    charset: Charset,
    (cols, rows): (usize, usize),
) -> RenderStats {
    renderer
        .render(
            maze,
            camera,
            &[],
            &RenderOptions { charset, culling: Culling::Portal, ..RenderOptions::default() },
            Target::Samples { cols, rows },
        )
        .expect("benchmark camera")
}

fn cameras(side: u32) -> impl Iterator<Item = Camera> {
    candidates(side)
        .flat_map(|(i, j)| (0..8).map(move |h| Camera::new(centre(i, j), h as f32 * 45.0, FOV_DEG)))
}

/// The open-area reference: (side, camera, stats) in the smallest maze.
fn open_reference() -> (u32, Camera, RenderStats) {
    let side = SIDES[0];
    let maze = generate(&maze_options(View::Open, side, SEED)).expect("benchmark maze");
    let mut renderer = Renderer::new();
    cameras(side)
        .map(|camera| (side, camera, portal_stats(&mut renderer, &maze, &camera)))
        .find(|(_, _, s)| s.portal.distinct_cells >= OPEN_MIN_CELLS)
        .expect("an open view in the small maze")
}

/// The first view of `maze` like `reference`: cell visits, distinct cells and walls drawn within ±10 %,
/// wall samples within ±20 %.
fn open_camera(maze: &Maze, side: u32, reference: RenderStats) -> Camera {
    let near = |a: usize, b: usize, percent: usize| a.abs_diff(b) * 100 <= b * percent;
    let mut renderer = Renderer::new();
    cameras(side)
        .find(|camera| {
            let (s, r) = (portal_stats(&mut renderer, maze, camera), reference);
            near(s.portal.cells_visited, r.portal.cells_visited, 10)
                && near(s.portal.distinct_cells, r.portal.distinct_cells, 10)
                && near(s.walls_drawn, r.walls_drawn, 10)
                && near(s.samples_written, r.samples_written, 20)
        })
        .expect("an open view like the reference")
}

/// The walk's starting point: an [`App`] at the open view of the `side`×`side` maze with loops, in
/// `charset` and `depth`, reporting presses and releases (as the kitty keyboard protocol does).
pub fn walk_app(side: u32, charset: Charset, depth: mazewalk_term::frame::ColorDepth) -> App {
    let scene = scene(View::Open, side);
    let options =
        RenderOptions { charset, color_depth: depth, culling: Culling::Portal, ..RenderOptions::default() };
    let mut app = App::new(scene.maze, options, 0.0).expect("viewer in the maze");
    app.camera = scene.camera;
    app.cell = app.maze().cell_at(scene.camera.position).expect("camera in the maze");
    app.releases = true;
    app
}

/// Frames a second of the scripted walk.
pub const WALK_FPS: f64 = 60.0;

/// The scripted walk the encoder bench and the examples replay: a phase name, the key held (none:
/// stand still) and for how long (seconds).
pub fn walk_script() -> Vec<(&'static str, Option<Key>, f64)> {
    vec![
        ("forward", Some(Key::Char('w')), 1.0),
        ("turn 360°", Some(Key::Left), 360.0 / f64::from(TURN_SPEED)),
        ("strafe", Some(Key::Char('d')), 0.5),
        ("look up", Some(Key::Up), 1.0),
        ("look down", Some(Key::Down), 2.0),
        ("back to level", Some(Key::Up), 1.0),
        ("stand still", None, 1.0),
    ]
}

/// Plays `script` through `app`'s own key handlers at [`WALK_FPS`] (each key pressed, held for its
/// time, released): `frame(app, phase, moved)` for the first frame and after every tick.
pub fn play_walk(
    app: &mut App,
    script: &[(&'static str, Option<Key>, f64)],
    mut frame: impl FnMut(&App, &'static str, bool),
) {
    let (mut now, mut frame_no) = (0.0, 0u32);
    frame(app, "first frame", true);
    for &(phase, key, seconds) in script {
        if let Some(key) = key {
            app.key(key, KeyPhase::Press, now);
        }
        for _ in 0..(seconds * WALK_FPS).round() as u32 {
            frame_no += 1;
            now = f64::from(frame_no) / WALK_FPS;
            let moved = app.tick(now);
            frame(app, phase, moved);
        }
        if let Some(key) = key {
            app.key(key, KeyPhase::Release, now);
        }
    }
}
