//! One benchmark view rendered over and over, for `perf record` (no criterion around it):
//!
//! ```sh
//! cargo build --release -p mazewalk-bench --example profile_frame
//! perf record ./target/release/examples/profile_frame corridor 10 half 200 60 samples 3000
//! perf report
//! ```
//!
//! Arguments: view (`corridor`|`open`), maze side, charset, columns, rows, part (`samples`, `glyphs`,
//! `frame`), repetitions, colour depth (default truecolor). Prints the mean time per repetition.
//!
//! Views in the exit's light: `builtin` (the built-in maze) and `walk` (the walk's generated 20 × 15
//! maze, seed 71): the viewer stands at the centre of cell "maze side" (there a cell's index), facing
//! the heading in degrees given after the colour depth (default 0), as the walk stands there.
//!
//! With `fovea` after the heading, the view is foveated, as the walk draws it (`Camera::fovea`):
//! `profile_frame walk 0 half 120 40 frame 11 256 0 fovea` is a served player's render.

use mazewalk_bench::common;

use std::time::Instant;

use common::{Scene, View};
use mazewalk_maze::generate::{GenOptions, generate};
use mazewalk_maze::{Maze, builtin};
use mazewalk_render::{Camera, Charset, Culling, RenderOptions, Renderer, Target, to_frame};
use mazewalk_term::frame::{ColorDepth, Frame, Region};

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let arg = |i: usize, default: &str| args.get(i).cloned().unwrap_or_else(|| default.to_owned());
    let side: u32 = arg(1, "10").parse().expect("maze side");
    let charset: Charset = arg(2, "half").parse().expect("charset");
    let (cols, rows): (usize, usize) =
        (arg(3, "200").parse().expect("cols"), arg(4, "60").parse().expect("rows"));
    let part = arg(5, "frame");
    let reps: u32 = arg(6, "2000").parse().expect("repetitions");
    let depth: ColorDepth = arg(7, "truecolor").parse().expect("colour depth");

    let heading: f32 = arg(8, "0").parse().expect("heading");
    let fovea = arg(9, "") == "fovea";
    let mut scene = match arg(0, "corridor").as_str() {
        "open" => common::scene(View::Open, side),
        "builtin" => standing(builtin().expect("built-in maze"), side, heading),
        "walk" => standing(generate(&GenOptions::walk(20, 15, 71)).expect("maze"), side, heading),
        _ => common::scene(View::Corridor, side),
    };
    scene.camera.fovea = fovea;
    let options =
        RenderOptions { charset, color_depth: depth, culling: Culling::Portal, ..RenderOptions::default() };
    let (mut renderer, mut frame) = (Renderer::new(), Frame::new(cols, rows));
    let region = Region { col: 0, row: 0, cols, rows };
    let draw = |renderer: &mut Renderer, frame: &mut Frame| {
        renderer
            .render(&scene.maze, &scene.camera, &[], &options, Target::Frame(frame, region))
            .expect("render");
    };
    draw(&mut renderer, &mut frame);
    let start = Instant::now();
    for _ in 0..reps {
        match part.as_str() {
            "samples" => {
                common::render_samples(&mut renderer, &scene.maze, &scene.camera, charset, (cols, rows));
            }
            "glyphs" => to_frame(renderer.samples(), &options, &mut frame, region),
            _ => draw(&mut renderer, &mut frame),
        }
        std::hint::black_box(&frame);
    }
    println!("{part}: {:.1} µs per repetition", start.elapsed().as_secs_f64() * 1e6 / f64::from(reps));
}

/// The viewer at cell `cell`'s centre facing `heading`, as the walk stands there.
fn standing(maze: Maze, cell: u32, heading: f32) -> Scene {
    let v = maze.viewer();
    let camera = Camera {
        eye_z: v.z,
        min_vfov_deg: maze.min_vfov_deg(),
        ..Camera::new(maze.cell_centroid(cell), heading, v.fov_deg)
    };
    eprintln!("cell {cell}: the exit's light level {}", maze.exit_light().level(cell));
    Scene { view: View::Open, side: cell, seed: 0, maze, camera }
}
