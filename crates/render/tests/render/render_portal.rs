//! The portal pass against brute force: for random mazes (perfect and with loops, rotated, with
//! irregular convex cells, and the original course files) and random cameras (anywhere in a cell,
//! on portals, pressed against walls; any heading, pitch, eye height, fov, grid and both projections),
//! the frame drawn from the walls the portal pass chooses equals the frame drawn from every wall,
//! sample for sample: same wall id, same depth, same colour — except where a sample's ray runs exactly
//! through a corner shared by two walls (a true depth tie, resolved by wall id in brute force), which
//! is bounded and checked below.

use mazewalk_testkit as common;

use glam::{Mat2, Vec2};
use mazewalk_maze::generate::{Algorithm, GenOptions, generate};
use mazewalk_maze::geometry::{WALL_MARGIN, heading_dir};
use mazewalk_maze::movement::{Position, step};
use mazewalk_maze::{self as maze, Cells, Maze, Viewer};
use mazewalk_render::oracle::{Agreement, portal_matches_brute};
use mazewalk_render::{Camera, Charset, Culling, Projection, RenderOptions, Renderer, Target};
use proptest::prelude::*;

/// A generated maze, maybe rotated and with its vertices jittered (cells stay convex or it is
/// rejected by validation and the case is skipped).
fn maze_strategy() -> impl Strategy<Value = Maze> {
    (
        1u32..9,
        1u32..9,
        any::<u64>(),
        0usize..3,
        prop_oneof![Just(0.0f32), 0.0f32..1.0],
        0.0f32..6.3,
        0.0f32..0.3,
    )
        .prop_filter_map("jitter broke convexity", |(w, h, seed, algo, loops, angle, jitter)| {
            let algorithm = [Algorithm::Prim, Algorithm::Backtracker, Algorithm::Wilson][algo];
            let base = generate(&GenOptions {
                width: w,
                height: h,
                seed,
                algorithm,
                loops,
                ..GenOptions::default()
            })
            .ok()?;
            transformed(&base, angle, jitter, seed)
        })
}

/// `maze` rotated by `angle` about the origin, each vertex moved by up to `jitter` cell sides.
fn transformed(maze: &Maze, angle: f32, jitter: f32, seed: u64) -> Option<Maze> {
    let rot = Mat2::from_angle(angle);
    let side = maze.extents().max.x.max(1.0) / 16.0; // a rough cell size
    let mut rng = seed | 1;
    let mut next = move || {
        rng ^= rng << 13;
        rng ^= rng >> 7;
        rng ^= rng << 17;
        (rng >> 40) as f32 / (1u64 << 24) as f32 - 0.5
    };
    let vertices: Vec<Vec2> =
        maze.vertices().iter().map(|&v| rot * (v + Vec2::new(next(), next()) * jitter * side)).collect();
    let mut cells = Cells::new();
    for c in 0..maze.cell_count() as u32 {
        cells.push(maze.cell_edges(c));
    }
    // Any viewer inside cell 0 will do: cameras are chosen below.
    let centroid = |c: u32| {
        let ids = maze.cell_edges(c);
        ids.iter().map(|&e| vertices[maze.edge(e).start as usize]).sum::<Vec2>() / ids.len() as f32
    };
    let viewer = Viewer { pos: centroid(0), ..*maze.viewer() };
    Maze::new(vertices, maze.edges().clone(), cells, viewer, None).ok()
}

/// Where the camera stands, in terms of the maze (resolved once the maze is known).
#[derive(Clone, Debug)]
enum Place {
    /// A point between a cell's centroid and one of its corners (`t` = 1 is the corner).
    InCell { cell: usize, corner: usize, t: f32 },
    /// A point on a portal (or any edge if the maze has none), `t` along it.
    OnEdge { edge: usize, t: f32 },
    /// Walked from a cell's centroid until a wall stops it (pressed against the wall).
    AgainstWall { cell: usize, heading: f32 },
}

fn place_strategy() -> impl Strategy<Value = Place> {
    prop_oneof![
        (any::<usize>(), any::<usize>(), prop_oneof![0.0f32..1.0, Just(0.999), Just(1.0)])
            .prop_map(|(cell, corner, t)| Place::InCell { cell, corner, t }),
        (any::<usize>(), prop_oneof![0.0f32..=1.0, Just(0.5), Just(0.0)])
            .prop_map(|(edge, t)| Place::OnEdge { edge, t }),
        (any::<usize>(), 0.0f32..360.0).prop_map(|(cell, heading)| Place::AgainstWall { cell, heading }),
    ]
}

fn centroid(maze: &Maze, c: u32) -> Vec2 {
    let ids = maze.cell_edges(c);
    ids.iter().map(|&e| maze.edge_points(e).0).sum::<Vec2>() / ids.len() as f32
}

fn resolve(maze: &Maze, place: &Place) -> Vec2 {
    match *place {
        Place::InCell { cell, corner, t } => {
            let c = (cell % maze.cell_count()) as u32;
            let ids = maze.cell_edges(c);
            let v = maze.edge_points(ids[corner % ids.len()]).0;
            centroid(maze, c).lerp(v, t)
        }
        Place::OnEdge { edge, t } => {
            let portals: Vec<u32> =
                (0..maze.edges().len() as u32).filter(|&e| maze.edge(e).is_portal()).collect();
            let e = if portals.is_empty() {
                (edge % maze.edges().len()) as u32
            } else {
                portals[edge % portals.len()]
            };
            let (a, b) = maze.edge_points(e);
            a.lerp(b, t)
        }
        Place::AgainstWall { cell, heading } => {
            let c = (cell % maze.cell_count()) as u32;
            let from = Position { cell: c, pos: centroid(maze, c) };
            let dir = heading_dir(heading.to_radians());
            step(maze, from, dir * 100.0, WALL_MARGIN).pos
        }
    }
}

#[derive(Clone, Debug)]
struct Shot {
    place: Place,
    yaw: f32,
    pitch: f32,
    eye_z: f32,
    fov: f32,
    cols: usize,
    rows: usize,
    charset: Charset,
    projection: Projection,
}

fn shot_strategy() -> impl Strategy<Value = Shot> {
    (
        place_strategy(),
        0.0f32..360.0,
        prop_oneof![-90.0f32..=90.0, Just(0.0), Just(90.0), Just(-90.0)],
        prop_oneof![-0.95f32..0.95, Just(0.0)],
        prop_oneof![20.0f32..160.0, Just(60.0), Just(170.0)],
        1usize..40,
        1usize..16,
        prop::sample::select(Charset::ALL.to_vec()),
        prop_oneof![Just(Projection::Perspective), Just(Projection::Orthographic)],
    )
        .prop_map(|(place, yaw, pitch, eye_z, fov, cols, rows, charset, projection)| Shot {
            place,
            yaw,
            pitch,
            eye_z,
            fov,
            cols,
            rows,
            charset,
            projection,
        })
}

/// Renders `shot` both ways and compares every sample; on failure leaves a replayable maze file.
fn portal_equals_brute(maze: &Maze, shot: &Shot) -> Result<Agreement, TestCaseError> {
    let position = resolve(maze, &shot.place);
    let camera = Camera {
        eye_z: shot.eye_z,
        pitch_deg: shot.pitch,
        projection: shot.projection,
        ..Camera::new(position, shot.yaw, shot.fov)
    };
    portal_matches_brute(maze, &camera, shot.charset, shot.cols, shot.rows).map_err(|why| {
        let path = std::env::temp_dir().join("mazewalk-portal-failure.maze");
        if let Ok(text) = maze::write(maze, maze::Format::Cs559) {
            let _ = std::fs::write(&path, text);
        }
        TestCaseError::fail(format!(
            "{why}\nreplay: mazewalk render {} --at {},{} --height {} --heading {} --pitch {} --fov {} \
             --size {}x{} --charset {} --projection {} --stats [--culling none]",
            path.display(),
            position.x,
            position.y,
            shot.eye_z,
            shot.yaw,
            shot.pitch,
            shot.fov,
            shot.cols,
            shot.rows,
            shot.charset,
            shot.projection
        ))
    })
}

proptest! {
    #![proptest_config(common::config())]

    #[test]
    fn portal_frames_equal_brute_force_frames(maze in maze_strategy(), shot in shot_strategy()) {
        portal_equals_brute(&maze, &shot)?;
    }
}

proptest! {
    #![proptest_config(common::config())]

    #[test]
    fn portal_frames_equal_brute_force_in_the_course_files(file in 0usize..3, shot in shot_strategy()) {
        let name = ["maze-1x1-45.maze", "maze-3x3-50.maze", "maze-10x10-100.maze"][file];
        let maze = maze::load(common::maze_path(&format!("cs559/{name}"))).unwrap().maze;
        portal_equals_brute(&maze, &shot)?;
    }
}

/// In a 200×200 maze, a view down a corridor visits a tiny fraction of the cells.
#[test]
fn the_portal_pass_visits_few_cells_of_a_large_maze() {
    let opts = GenOptions {
        width: 200,
        height: 200,
        seed: 7,
        algorithm: Algorithm::Backtracker,
        ..GenOptions::default()
    };
    let maze = generate(&opts).unwrap();
    let viewer = maze.viewer();
    let camera = Camera::new(viewer.pos, viewer.dir_deg, 90.0);
    let mut renderer = Renderer::new();
    let stats = renderer
        .render(
            &maze,
            &camera,
            &[],
            &RenderOptions { charset: Charset::Half, culling: Culling::Portal, ..RenderOptions::default() },
            Target::Samples { cols: 120, rows: 40 },
        )
        .unwrap();
    let ratio = maze.cell_count() as f64 / stats.portal.distinct_cells as f64;
    eprintln!(
        "200×200 corridor view: {} of {} cells visited ({ratio:.0}× fewer), {} portals crossed, {} walls drawn",
        stats.portal.distinct_cells,
        maze.cell_count(),
        stats.portal.portals_traversed,
        stats.walls_drawn
    );
    assert!(!stats.portal.fell_back);
    assert!(stats.portal.distinct_cells >= 1);
    assert!(ratio > 100.0, "visited {} of {} cells", stats.portal.distinct_cells, maze.cell_count());
    // and the frame still equals brute force
    let shot = Shot {
        place: Place::InCell { cell: maze.cell_at(viewer.pos).unwrap() as usize, corner: 0, t: 0.0 },
        yaw: viewer.dir_deg,
        pitch: 0.0,
        eye_z: 0.0,
        fov: 90.0,
        cols: 120,
        rows: 40,
        charset: Charset::Half,
        projection: Projection::Perspective,
    };
    portal_equals_brute(&maze, &shot).unwrap();
}

/// Red-team pass 8: an open floor of half-unit tiles makes the portal pass give up (its safety cap)
/// and draw every wall. The frame is then brute force's, cell for cell, the floor's cell lines
/// included: they were drawn only for the cells reached before the cap.
#[test]
fn past_the_portal_pass_cap_the_frame_is_brute_forces() {
    let n = 100;
    let rows: Vec<String> =
        (0..n).map(|r| format!("#{}{}#", if r == n / 2 { '@' } else { '.' }, ".".repeat(n - 1))).collect();
    let wall = "#".repeat(n + 2);
    let text = format!("mazewalk-grid 1\ntile 0.5002\nfacing east\n\n{wall}\n{}\n{wall}\n", rows.join("\n"));
    let floor = maze::grid::parse_str("floor.grid", &text).unwrap();
    let camera = Camera::new(Vec2::splat(n as f32 * 0.5002 / 2.0), 30.0, 90.0);
    let draw = |culling| {
        let mut renderer = Renderer::new();
        let mut frame = mazewalk_term::frame::Frame::new(120, 39);
        let region = frame.region();
        let options = RenderOptions { charset: Charset::Half, culling, ..RenderOptions::default() };
        let stats =
            renderer.render(&floor, &camera, &[], &options, Target::Frame(&mut frame, region)).unwrap();
        (frame, stats.portal.fell_back, stats.walls_drawn)
    };
    let ((portal, fell_back, portal_walls), (brute, _, brute_walls)) =
        (draw(Culling::Portal), draw(Culling::None));
    assert!(fell_back, "the premise: the cap was hit");
    // Walls only go to the raster, never the floor's portals (red-team pass 9: past the cap, and in
    // brute force, every portal of a 2046 × 2046 floor was clipped to the view each frame, and counted).
    for walls in [portal_walls, brute_walls] {
        assert!((1..=floor.wall_count()).contains(&walls), "{walls} of {} walls", floor.wall_count());
    }
    let differ = (0..39)
        .flat_map(|y| (0..120).map(move |x| (x, y)))
        .filter(|&(x, y)| portal.get(x, y) != brute.get(x, y));
    assert_eq!(differ.count(), 0, "cells unlike brute force's");
}
