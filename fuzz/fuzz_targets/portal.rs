//! Arbitrary small mazes (generated from fuzzed options, then their vertices moved by fuzzed offsets;
//! whatever still validates) and arbitrary cameras: the portal pass must match brute force sample for
//! sample (up to the bounded corner ties of `render::oracle`), and nothing may panic.

#![no_main]

use arbitrary::Arbitrary;
use glam::Vec2;
use libfuzzer_sys::fuzz_target;
use mazewalk_maze::generate::{Algorithm, GenOptions, generate};
use mazewalk_maze::{Cells, Maze};
use mazewalk_render::oracle::portal_matches_brute;
use mazewalk_render::{Camera, Charset, Projection};

#[derive(Arbitrary, Debug)]
struct Input {
    width: u8,
    height: u8,
    seed: u64,
    algorithm: u8,
    loops: u8,
    nudges: Vec<(u16, i8, i8)>,
    /// Camera: which cell, where in it (fractions toward a corner), heading, pitch, height, fov.
    cell: u16,
    corner: u8,
    toward: u8,
    yaw: f32,
    pitch: f32,
    eye_z: f32,
    fov: f32,
    cols: u8,
    rows: u8,
    charset: u8,
    ortho: bool,
}

fn maze(input: &Input) -> Option<Maze> {
    let algorithm =
        [Algorithm::Prim, Algorithm::Backtracker, Algorithm::Wilson][usize::from(input.algorithm % 3)];
    let opts = GenOptions {
        width: u32::from(input.width % 6) + 1,
        height: u32::from(input.height % 6) + 1,
        seed: input.seed,
        algorithm,
        loops: f32::from(input.loops) / 255.0,
        ..GenOptions::default()
    };
    let base = generate(&opts).ok()?;
    let mut vertices = base.vertices().to_vec();
    for &(v, dx, dy) in input.nudges.iter().take(64) {
        let n = vertices.len();
        vertices[usize::from(v) % n] += Vec2::new(f32::from(dx), f32::from(dy)) / 64.0;
    }
    let mut cells = Cells::new();
    for c in 0..base.cell_count() as u32 {
        cells.push(base.cell_edges(c));
    }
    let ids = base.cell_edges(0);
    let centroid =
        ids.iter().map(|&e| vertices[base.edge(e).start as usize]).sum::<Vec2>() / ids.len() as f32;
    let viewer = mazewalk_maze::Viewer { pos: centroid, ..*base.viewer() };
    Maze::new(vertices, base.edges().clone(), cells, viewer, None).ok()
}

fuzz_target!(|input: Input| {
    let Some(maze) = maze(&input) else { return };
    let cell = u32::from(input.cell) % maze.cell_count() as u32;
    let ids = maze.cell_edges(cell);
    let centroid = ids.iter().map(|&e| maze.edge_points(e).0).sum::<Vec2>() / ids.len() as f32;
    let corner = maze.edge_points(ids[usize::from(input.corner) % ids.len()]).0;
    let position = centroid.lerp(corner, f32::from(input.toward) / 255.0);
    let finite = |x: f32, lo: f32, hi: f32| if x.is_finite() { x.clamp(lo, hi) } else { (lo + hi) / 2.0 };
    let camera = Camera {
        eye_z: finite(input.eye_z, -0.99, 0.99),
        pitch_deg: finite(input.pitch, -90.0, 90.0),
        projection: if input.ortho { Projection::Orthographic } else { Projection::Perspective },
        ..Camera::new(position, finite(input.yaw, -1e4, 1e4), finite(input.fov, 10.0, 170.0))
    };
    let charset = Charset::ALL[usize::from(input.charset) % Charset::ALL.len()];
    let (cols, rows) = (usize::from(input.cols % 48) + 1, usize::from(input.rows % 16) + 1);
    if let Err(why) = portal_matches_brute(&maze, &camera, charset, cols, rows) {
        let text = mazewalk_maze::write(&maze, mazewalk_maze::Format::Cs559).unwrap_or_default();
        panic!("{why}\ncamera {camera:?}, {cols}×{rows} {charset:?}\nmaze:\n{text}");
    }
});
