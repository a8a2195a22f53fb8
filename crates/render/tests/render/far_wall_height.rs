//! Issue #39: a far wall's height is how a player judges its distance, so on the picture it must be
//! as tall as it is, no taller and no shorter. Two new players misjudged it two ways: with its top and
//! bottom samples darkened into edges, a wall two rows tall read as one (twice as far); with those
//! edges moved onto the floor and ceiling beside it in the wall's own darkened colour, it read 1.5–2×
//! nearer (a wall 22 units off taken for one at 12).
//!
//! Measured as a person sees it: down each column through a short wall (fewer samples than the
//! renderer's far-wall limit, inside the wall, with ceiling above and floor below), every sample the
//! wall covers looks more like the wall than like the plane beside it, and the ceiling's and floor's
//! first samples look more like their plane than like the wall (OKLab, what the terminal shows).

use crate::draw;
use mazewalk_maze::generate::{GenOptions, generate};
use mazewalk_render::quality::{self, ViewKind, held_out_views};
use mazewalk_render::samples::{CEILING, FLOOR};
use mazewalk_render::{Charset, RenderOptions, Renderer};
use mazewalk_term::frame::ColorDepth;

const COLS: usize = 120;
const ROWS: usize = 40;
/// Walls shorter than this many samples are judged: far walls (the renderer's limit is 12).
const SHORT: usize = 10;
/// A sample looks like the wall when it is nearer the wall's colour than this share of its distance
/// to the plane's (OKLab).
const LIKE: f32 = 0.7;

#[test]
fn a_far_wall_looks_as_tall_as_it_is_in_truecolor_256_and_16_colours() {
    let (mut judged, mut failures) = (0, Vec::new());
    for seed in [58u64, 71, 3, 12, 5392] {
        let maze = generate(&GenOptions::walk(20, 15, seed)).expect("maze");
        let walls = maze.edges().len() as u32;
        let views = held_out_views(&maze, seed, 30);
        for (k, (_, camera)) in views.iter().enumerate().filter(|(_, (kind, _))| *kind == ViewKind::Corridor)
        {
            for depth in [ColorDepth::TrueColor, ColorDepth::Ansi256, ColorDepth::Ansi16] {
                let options =
                    RenderOptions { charset: Charset::Half, color_depth: depth, ..RenderOptions::default() };
                let mut renderer = Renderer::new();
                let frame = draw(&mut renderer, &maze, camera, &options, COLS, ROWS);
                let shown = quality::shown(&frame, Charset::Half);
                let ids = renderer.samples().id();
                let width = renderer.samples().width();
                let height = ids.len() / width;
                for x in 1..width - 1 {
                    let mut y = 2;
                    while y + 3 < height {
                        let id = ids[y * width + x];
                        let top = y;
                        while y < height && ids[y * width + x] == id {
                            y += 1;
                        }
                        let bottom = y; // one past the run
                        let at = |y: usize| y * width + x;
                        let run = bottom - top;
                        let whole_inside =
                            (top..bottom).all(|r| ids[at(r) - 1] == id && ids[at(r) + 1] == id);
                        if id >= walls
                            || !(2..=SHORT).contains(&run)
                            || top < 4
                            || bottom + 4 > height
                            || !whole_inside
                            || (1..=4)
                                .any(|d| ids[at(top - d)] != CEILING || ids[at(bottom + d - 1)] != FLOOR)
                        {
                            continue;
                        }
                        judged += 1;
                        // The plane beside the wall, as it shows a little way off (three samples:
                        // one of them may be a cell line across it).
                        let wall = shown[at(top + run / 2)];
                        let ceiling = [shown[at(top - 2)], shown[at(top - 3)], shown[at(top - 4)]];
                        let floor = [shown[at(bottom + 1)], shown[at(bottom + 2)], shown[at(bottom + 3)]];
                        let nearest = |s: glam::Vec3, plane: &[glam::Vec3; 3]| {
                            plane.iter().map(|p| s.distance(*p)).fold(f32::INFINITY, f32::min)
                        };
                        // Nearer the wall than the plane by a margin: a third colour between (a light
                        // cell line on a dark plane in 16 colours) is neither.
                        let looks_like_wall = |s: glam::Vec3, plane: &[glam::Vec3; 3]| {
                            s.distance(wall) < LIKE * nearest(s, plane)
                        };
                        let wall_ok = (top..bottom).all(|r| {
                            looks_like_wall(shown[at(r)], if r - top < run / 2 { &ceiling } else { &floor })
                        });
                        let planes_ok = !looks_like_wall(shown[at(top - 1)], &ceiling)
                            && !looks_like_wall(shown[at(bottom)], &floor);
                        if !(wall_ok && planes_ok) {
                            failures.push(format!(
                                "seed {seed} view {k} {depth:?} at {:?} heading {:.0} column {x}: wall samples {top}..{bottom} \
                                 (its own colour throughout: {wall_ok}; ceiling and floor beside it their own: {planes_ok})",
                                camera.position, camera.yaw_deg
                            ));
                        }
                    }
                }
            }
        }
    }
    crate::none_failed(judged, 500, &failures, "far-wall columns look taller or shorter than the wall");
}
