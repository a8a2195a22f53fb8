//! Chalk marks (issue #39, with the map off): the cells a player has walked carry a pale blue cross
//! on their floors ([`Renderer::set_chalk`]), drawn through the same chain as the floor's cell lines, in
//! every colour depth and charset; without marks the picture is as it was.

use glam::Vec2;
use mazewalk_maze::Maze;
use mazewalk_maze::generate::{GenOptions, generate};
use mazewalk_render::samples::FLOOR;
use mazewalk_render::shade::luminance;
use mazewalk_render::{Camera, Charset, RenderOptions, Renderer};
use mazewalk_term::frame::{ColorDepth, Frame};
use proptest::prelude::*;

/// A view from the centroid of `cell` toward the centroid of an open neighbour (the first through a
/// portal from `side` round the cell), with that neighbour: `None` for a cell walled all round.
fn view_to_neighbour(maze: &Maze, cell: u32, side: usize) -> Option<(Camera, u32)> {
    let edges = maze.cell_edges(cell);
    let next = (0..edges.len()).find_map(|k| {
        let edge = maze.edge(edges[(side + k) % edges.len()]);
        edge.other_side(cell).filter(|_| !edge.opaque)
    })?;
    let (from, to) = (maze.cell_centroid(cell), maze.cell_centroid(next));
    let d = to - from;
    let v = maze.viewer();
    let camera = Camera {
        eye_z: v.z,
        min_vfov_deg: maze.min_vfov_deg(),
        fovea: true,
        ..Camera::new(from, d.y.atan2(d.x).to_degrees(), v.fov_deg)
    };
    Some((camera, next))
}

/// The frame and the samples' colours and ids of `camera`'s view with `chalk` marked, by `renderer`.
fn draw(
    renderer: &mut Renderer,
    maze: &Maze,
    camera: &Camera,
    options: &RenderOptions,
    chalk: &[u32],
) -> (Frame, Vec<glam::Vec3>, Vec<u32>) {
    renderer.set_chalk(chalk);
    let frame = crate::draw(renderer, maze, camera, options, 120, 40);
    (frame, renderer.samples().color().to_vec(), renderer.samples().id().to_vec())
}

fn maze(width: u32, height: u32, seed: u64) -> Maze {
    generate(&GenOptions { width, height, seed, loops: 0.1, ..GenOptions::default() }).expect("maze")
}

proptest! {
    #![proptest_config(mazewalk_testkit::config_cases(16))]

    // Looking from a cell's centre into an open neighbour, a mark on the neighbour's floor changes
    // floor samples only, each to a lighter colour, and shows in every colour depth and charset;
    // marks on no cell (after a marked frame, by the same renderer) draw what a fresh renderer draws.
    #[test]
    fn a_chalked_cell_shows_a_lighter_mark_on_its_floor_only(
        (width, height, seed) in (3u32..=20, 3u32..=15, any::<u64>()),
        pick in 0.0f32..1.0,
        side in 0usize..4,
    ) {
        let maze = maze(width, height, seed);
        let cell = ((pick * maze.cell_count() as f32) as u32).min(maze.cell_count() as u32 - 1);
        let (camera, next) = view_to_neighbour(&maze, cell, side).expect("a perfect maze's cells are joined");
        let options = RenderOptions::default();
        let mut renderer = Renderer::new();
        let (_, plain, ids) = draw(&mut renderer, &maze, &camera, &options, &[]);
        let (_, marked, marked_ids) = draw(&mut renderer, &maze, &camera, &options, &[next]);
        prop_assert_eq!(&ids, &marked_ids, "a mark changes colours, not what a sample shows");
        let changed: Vec<usize> = (0..plain.len()).filter(|&i| plain[i] != marked[i]).collect();
        prop_assert!(changed.len() >= 4, "the mark 4 units ahead shows: {} samples", changed.len());
        for &i in &changed {
            prop_assert_eq!(ids[i], FLOOR, "sample {} is no floor", i);
            prop_assert!(luminance(marked[i]) > luminance(plain[i]), "sample {}: {} → {}", i, plain[i], marked[i]);
            // blue, where the floor's cell lines are grey: a mark squashed by the angle a few cells
            // off is not taken for a line
            prop_assert!(marked[i].z > 1.5 * marked[i].x.max(marked[i].y), "sample {}: {} is not blue", i, marked[i]);
        }
        let (_, again, _) = draw(&mut renderer, &maze, &camera, &options, &[]);
        let (_, fresh, _) = draw(&mut Renderer::new(), &maze, &camera, &options, &[]);
        prop_assert_eq!(again, fresh);
        for charset in [Charset::Half, Charset::Ascii] {
            for color_depth in [ColorDepth::TrueColor, ColorDepth::Ansi256, ColorDepth::Ansi16, ColorDepth::None] {
                let options = RenderOptions { charset, color_depth, ..RenderOptions::default() };
                let (without, ..) = draw(&mut renderer, &maze, &camera, &options, &[]);
                let (with, ..) = draw(&mut renderer, &maze, &camera, &options, &[next]);
                let differ = without.cells().iter().zip(with.cells()).filter(|(a, b)| a != b).count();
                prop_assert!(differ >= 2, "{:?} {:?}: the mark shows in {} cells", charset, color_depth, differ);
            }
        }
    }
}

#[test]
fn marks_outside_the_maze_or_out_of_view_change_nothing() {
    let maze = maze(8, 6, 5);
    let (camera, _) = view_to_neighbour(&maze, 0, 0).expect("joined");
    let options = RenderOptions::default();
    let mut renderer = Renderer::new();
    let (plain, ..) = draw(&mut renderer, &maze, &camera, &options, &[]);
    let (outside, ..) = draw(&mut renderer, &maze, &camera, &options, &[u32::MAX, maze.cell_count() as u32]);
    assert_eq!(plain.cells(), outside.cells());
    // the cell farthest from the view's (behind it, or walls away): not seen, not drawn
    let from = maze.cell_centroid(0);
    let far = (0..maze.cell_count() as u32)
        .max_by(|&a, &b| {
            let d = |c| maze.cell_centroid(c).distance_squared(from);
            d(a).total_cmp(&d(b))
        })
        .expect("cells");
    let behind = Camera { yaw_deg: camera.yaw_deg + 180.0, ..camera };
    let (plain, ..) = draw(&mut renderer, &maze, &behind, &options, &[]);
    let (marked, ..) = draw(&mut renderer, &maze, &behind, &options, &[far]);
    assert_eq!(plain.cells(), marked.cells(), "cell {far} at {}", maze.cell_centroid(far) - Vec2::ZERO);
}
