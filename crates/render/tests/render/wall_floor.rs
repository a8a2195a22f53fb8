//! Issue #39, map off: "side walls as dark as the floor". A wall lit at a grazing angle must still
//! read apart from the floor it stands on, in truecolor and in 256 colours, whatever its angle to the
//! eye. Measured on the wall's foot line: along each column, the wall sample just above the seam with
//! the floor against the floor sample just below it (OKLab lightness, what the terminal shows).

use crate::draw;
use mazewalk_maze::generate::{GenOptions, generate};
use mazewalk_render::quality::{self, held_out_views};
use mazewalk_render::samples::{CEILING, FLOOR, NONE};
use mazewalk_render::{Charset, RenderOptions, Renderer};
use mazewalk_term::frame::ColorDepth;

const COLS: usize = 120;
const ROWS: usize = 40;

/// The least OKLab lightness difference between a wall and the floor at its foot. OKLab's just
/// noticeable difference is about 0.02; 0.05 is two and a half of them, and more than half a step of
/// the 256-colour grey ramp (0.03–0.04 in L), so it survives the palette's rounding on both sides.
const MIN_DELTA_L: f32 = 0.05;
/// Floor samples darker than this (far off, in the fog: the fog has left less than a third of the
/// floor's light) are not judged: there everything fades to black together, which is the depth cue,
/// and one sample row of the floor spans so much depth that the floor sample under a far wall's foot
/// is much nearer than the wall.
const JUDGED_FLOOR_L: f32 = 0.3;

/// Foot-line pairs (wall L, floor L, x, y) of one frame: the floor two below a wall's foot (the
/// darkest floor sample two to four below it, up to two columns to either side: cell lines, lighter
/// than the floor, that meet the wall at an angle reach the sample beside the wall and cross some of
/// them, a steep one down the column, a shallow one along the row, two at a cell's corner; in the
/// foveated view's magnified middle two of the way's lines can run side by side two and three below
/// a far wall's foot, where the plain view draws them on one row) and the wall
/// sample just above the foot (where a wall meets the floor one of the two samples at
/// the boundary is an edge, darker on purpose: the wall's foot sample on a near wall, the floor's
/// first sample under a far one). Only inside a wall, one sample or more from its ends: where two walls
/// meet or a wall ends, the line between is an edge, darker than the wall on purpose.
fn foot_pairs(shown: &[glam::Vec3], ids: &[u32], width: usize) -> Vec<(f32, f32, usize, usize)> {
    let height = ids.len() / width;
    let is_wall = |id: u32| id != FLOOR && id != CEILING && id != NONE;
    let mut out = Vec::new();
    for x in 1..width.saturating_sub(1) {
        for y in 1..height.saturating_sub(2) {
            let at = |y: usize| y * width + x;
            let (above, foot, below) = (ids[at(y - 1)], ids[at(y)], ids[at(y + 1)]);
            let inside = ids[at(y - 1) - 1] == foot && ids[at(y - 1) + 1] == foot;
            if is_wall(foot)
                && above == foot
                && below == FLOOR
                && ids.get(at(y + 2)) == Some(&FLOOR)
                && inside
            {
                let near =
                    (2..5).flat_map(|dy| (x.saturating_sub(2)..(x + 3).min(width)).map(move |x| (x, y + dy)));
                let floor = near
                    .map(|(x, y)| y * width + x)
                    .filter(|&i| ids.get(i) == Some(&FLOOR))
                    .map(|i| shown[i].x)
                    .fold(f32::INFINITY, f32::min);
                out.push((shown[at(y - 1)].x, floor, x, y));
            }
        }
    }
    out
}

#[test]
fn walls_read_apart_from_the_floor_at_their_foot_in_every_view() {
    let mut judged = 0;
    let mut failures = Vec::new();
    for seed in [58u64, 71, 3, 12] {
        let maze = generate(&GenOptions::walk(20, 15, seed)).expect("maze");
        let views = held_out_views(&maze, seed, 18).into_iter().enumerate();
        for ((k, (kind, camera)), fovea) in views.flat_map(|view| [(view, false), (view, true)]) {
            let camera = mazewalk_render::Camera { fovea, ..camera };
            for depth in [ColorDepth::TrueColor, ColorDepth::Ansi256] {
                let options =
                    RenderOptions { charset: Charset::Half, color_depth: depth, ..RenderOptions::default() };
                let mut renderer = Renderer::new();
                let frame = draw(&mut renderer, &maze, &camera, &options, COLS, ROWS);
                let shown = quality::shown(&frame, Charset::Half);
                let ids = renderer.samples().id();
                for (wall, floor, x, y) in foot_pairs(&shown, ids, renderer.samples().width()) {
                    if floor < JUDGED_FLOOR_L {
                        continue;
                    }
                    judged += 1;
                    if (wall - floor).abs() < MIN_DELTA_L {
                        failures.push(format!(
                            "seed {seed} view {k} {kind:?} fovea {fovea} {depth:?} at {:?} heading {:.0} sample ({x}, {y}): wall L {wall:.3} floor L {floor:.3}",
                            camera.position, camera.yaw_deg
                        ));
                    }
                }
            }
        }
    }
    crate::none_failed(
        judged,
        1000,
        &failures,
        &format!("foot-line samples within {MIN_DELTA_L} of the floor's lightness"),
    );
}
