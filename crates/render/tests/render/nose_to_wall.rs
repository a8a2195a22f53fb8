//! Issue #39: "At the closest a player can stand, the view still shows where the wall's edges and the
//! floor are." A generated maze keeps the eye 2/5 of a cell from its walls and its view a vertical
//! field of view with which, facing a wall square on from there, the floor shows below it, the
//! ceiling above it and, at 120×40 and wider, what lies beyond both of its ends
//! (`mazewalk_maze::geometry::clearance_for` states the geometry).

use crate::draw;
use glam::Vec2;
use mazewalk_maze::Maze;
use mazewalk_maze::generate::{CELL_SIZE, GenOptions, generate};
use mazewalk_maze::geometry::{MAX_CLEARANCE, WALL_MARGIN};
use mazewalk_maze::movement::{Position, is_clear, settle};
use mazewalk_render::samples::{CEILING, FLOOR};
use mazewalk_render::{Camera, RenderOptions, Renderer};
use proptest::prelude::*;

/// The sample ids of `camera`'s view of `maze` at `cols × rows` (half blocks: two samples a cell).
fn ids(maze: &Maze, camera: &Camera, cols: usize, rows: usize) -> (Vec<u32>, usize) {
    let mut renderer = Renderer::new();
    draw(&mut renderer, maze, camera, &RenderOptions::default(), cols, rows);
    (renderer.samples().id().to_vec(), renderer.samples().width())
}

/// The closest stand facing wall `e` of `cell` square on at `along` of its length (a spot the walk
/// lets a player stand on: 0.4–0.6 of a generated cell's wall), and the heading (degrees) that faces
/// it; `None` for a portal.
fn facing_wall(maze: &Maze, cell: u32, e: u32, along: f32) -> Option<(u32, Vec2, f32)> {
    if !maze.edge(e).opaque {
        return None;
    }
    let (a, b) = maze.edge_points_ccw(e, cell);
    let inward = (b - a).perp().normalize(); // the cell is left of its ccw edges
    let at = a.lerp(b, along) + maze.clearance() * inward;
    let stands = settle(maze, Position { cell, pos: at }, maze.clearance());
    assert!(is_clear(maze, stands, maze.clearance()), "{at}: a spot the walk lets a player stand on");
    assert!(stands.pos.distance(at) < 1e-3, "{at} is as close as the walk lets a player come: {stands:?}");
    Some((e, at, (-inward).y.atan2((-inward).x).to_degrees()))
}

/// A generated maze of `width × height` (`seed`, loops 0.1), and the camera standing at the closest
/// stand facing the first wall round the cell `pick` (0..1 of the cells) from `side`, `along` of its
/// length: the maze, the faced wall, the stand, the heading and the camera; `None` where the cell is
/// open on every side.
fn facing_a_wall_of(
    (width, height, seed): (u32, u32, u64),
    pick: f32,
    side: usize,
    along: impl Fn(&Maze) -> f32,
) -> Option<(Maze, u32, Vec2, f32, Camera)> {
    let maze =
        generate(&GenOptions { width, height, seed, loops: 0.1, ..GenOptions::default() }).expect("maze");
    let cell = ((pick * maze.cell_count() as f32) as u32).min(maze.cell_count() as u32 - 1);
    let edges = maze.cell_edges(cell).to_vec();
    let along = along(&maze);
    let (faced, at, heading) =
        (0..edges.len()).find_map(|k| facing_wall(&maze, cell, edges[(side + k) % edges.len()], along))?;
    let v = maze.viewer();
    let camera = Camera {
        eye_z: v.z,
        min_vfov_deg: maze.min_vfov_deg(),
        fovea: true,
        ..Camera::new(at, heading, v.fov_deg)
    };
    Some((maze, faced, at, heading, camera))
}

#[test]
fn a_generated_maze_keeps_two_fifths_of_a_cell_and_course_files_keep_theirs() {
    let maze =
        generate(&GenOptions { width: 6, height: 5, seed: 11, ..GenOptions::default() }).expect("maze");
    assert_eq!(maze.clearance(), CELL_SIZE * 2.0 / 5.0);
    assert_eq!(maze.clearance(), MAX_CLEARANCE);
    assert!(maze.min_vfov_deg() > 90.0, "{}", maze.min_vfov_deg());
    let tiny = mazewalk_maze::load(mazewalk_testkit::maze_path("tiny.grid")).expect("tiny").maze;
    assert_eq!(tiny.min_vfov_deg(), 0.0, "a file keeps its own field of view");
    assert!(tiny.clearance() >= WALL_MARGIN);
}

proptest! {
    #![proptest_config(mazewalk_testkit::config_cases(24))]

    // Facing a wall square on from the closest stand (any of the four headings a wall of a generated
    // maze is faced at, any cell, anywhere the clearance lets the eye stand before the wall), at 120×40
    // and 80×24: every column that
    // shows the wall shows floor below it and ceiling above it, and the wall spans most of the view.
    // (Turned from square on, or beside a wall's end, the nearest columns meet a wall closer than the
    // clearance, where no field of view a screen can show keeps the floor in: the geometry's doc.)
    #[test]
    fn facing_a_wall_from_the_closest_stand_floor_and_ceiling_show(
        (width, height, seed) in (3u32..=20, 3u32..=15, any::<u64>()),
        pick in 0.0f32..1.0,
        side in 0usize..4,
        along in 0.41f32..=0.59,
    ) {
        let found = facing_a_wall_of((width, height, seed), pick, side, |_| along);
        prop_assume!(found.is_some(), "a cell open on all four sides (the maze has loops)");
        let (maze, faced, at, heading, camera) = found.unwrap();
        for (cols, rows) in [(120, 40), (80, 24)] {
            let (ids, w) = ids(&maze, &camera, cols, rows);
            let mut wall_columns = 0;
            for x in 0..w {
                let column: Vec<u32> = ids.iter().skip(x).step_by(w).copied().collect();
                if column.contains(&faced) {
                    wall_columns += 1;
                    let top = column.iter().position(|&id| id == faced).unwrap();
                    let bottom = column.iter().rposition(|&id| id == faced).unwrap();
                    prop_assert!(column[..top].contains(&CEILING), "{cols}×{rows} column {x}: no ceiling above the wall at {at} facing {heading}°");
                    prop_assert!(column[bottom..].contains(&FLOOR), "{cols}×{rows} column {x}: no floor below the wall at {at} facing {heading}°");
                }
            }
            prop_assert!(wall_columns * 2 > w, "{cols}×{rows}: the faced wall in {wall_columns} of {w} columns");
        }
    }
}

proptest! {
    #![proptest_config(mazewalk_testkit::config_cases(24))]

    // Facing a wall square on from the closest stand, anywhere in the band the clearance lets the eye
    // stand in before it (0.4 units either side of the middle in a generated maze; right up to its
    // corners), at 120×40 and 80×24: neither the first nor the last column of the view shows the faced
    // wall, so both of its ends show with what is beyond them (a side wall, the floor of a side
    // opening, the next cell's wall). With a quarter-cell clearance one wall filled every column.
    #[test]
    fn facing_a_wall_from_the_closest_stand_both_its_ends_show(
        (width, height, seed) in (3u32..=20, 3u32..=15, any::<u64>()),
        pick in 0.0f32..1.0,
        side in 0usize..4,
        off in -0.98f32..=0.98,
    ) {
        // how far off-centre the eye may stand: `off` of the band either side of the middle
        let along = |maze: &Maze| 0.5 + off * (0.5 * CELL_SIZE - maze.clearance()) / CELL_SIZE;
        let found = facing_a_wall_of((width, height, seed), pick, side, along);
        prop_assume!(found.is_some(), "a cell open on all four sides (the maze has loops)");
        let (maze, faced, at, heading, camera) = found.unwrap();
        for (cols, rows) in [(120, 40), (80, 24)] {
            let (ids, w) = ids(&maze, &camera, cols, rows);
            for x in [0, w - 1] {
                let column: Vec<u32> = ids.iter().skip(x).step_by(w).copied().collect();
                prop_assert!(!column.contains(&faced), "{cols}×{rows} column {x}: the faced wall {faced} at the view's edge, at {at} facing {heading}°");
            }
        }
    }
}
