//! The render crate's integration tests, one binary (one link) for all of them: frames as text, the
//! rasterizer and lines, golden frames, the picture and its quality measures, the portal pass against
//! brute force, figures.

mod cell_lines;
mod chalk;
mod exit_light;
mod far_wall_height;
mod flat_walls;
mod fovea;
mod glow_way;
mod glyph_frames;
mod near_black;
mod nose_to_wall;
mod openings;
mod picture_quality;
mod raster_fill;
mod raster_lines;
mod render_golden;
mod render_picture;
mod render_portal;
mod render_sprites;
mod tone;
mod wall_floor;

use mazewalk_maze::Maze;
use mazewalk_render::{Camera, RenderOptions, Renderer, Target};
use mazewalk_term::frame::Frame;

/// `camera`'s view of `maze`, drawn by `renderer` with `options` into a new `cols` × `rows` frame:
/// the frame (the renderer keeps the samples).
pub fn draw(
    renderer: &mut Renderer,
    maze: &Maze,
    camera: &Camera,
    options: &RenderOptions,
    cols: usize,
    rows: usize,
) -> Frame {
    let mut frame = Frame::new(cols, rows);
    let region = frame.region();
    renderer.render(maze, camera, &[], options, Target::Frame(&mut frame, region)).expect("camera");
    frame
}

/// A property over many samples: more than `least` were judged, and none failed; else the count and
/// the first few failures, `what` saying what failing means.
pub fn none_failed(judged: usize, least: usize, failures: &[String], what: &str) {
    assert!(judged > least, "too few judged: {judged}");
    assert!(
        failures.is_empty(),
        "{} of {judged} {what}; first: {:#?}",
        failures.len(),
        &failures[..failures.len().min(10)]
    );
}
