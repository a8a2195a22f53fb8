//! Issue #15: what textures cost — bytes per walking frame and render time, textures off and on, in
//! the same run.
//!
//! ```sh
//! nice cargo run --release -p mazewalk-bench --example texture_cost
//! ```
//!
//! The walk: through the app's own key handlers at 60 frames a second (forward 2 s, a full turn,
//! strafe, look up and down, stand still), in the built-in maze and in a generated 40×25 maze from
//! their starts, 160×48 half blocks. Bytes: the walkthrough's encoder with its default colour tolerance,
//! frame after frame (mean over the frames where the camera moved). Time: render (samples and glyphs)
//! per frame, median.

use mazewalk_bench::common;

use std::time::Instant;

use mazewalk_maze::Maze;
use mazewalk_maze::generate::{GenOptions, generate};
use mazewalk_render::{Camera, Charset, RenderOptions, Renderer, Target};
use mazewalk_term::encoder::{self, Encoder};
use mazewalk_term::frame::{ColorDepth, Frame};
use mazewalk_walk::App;

const COLS: usize = 160;
const ROWS: usize = 48;

/// Every frame's camera over the scripted walk (the encoder bench's, walking forward 2 s, not 1), and
/// whether it moved.
fn walk(maze: &Maze) -> Vec<(bool, Camera)> {
    let mut app = App::new(maze.clone(), RenderOptions::default(), 0.0).expect("viewer in the maze");
    app.releases = true;
    let mut script = common::walk_script();
    script[0].2 = 2.0;
    let mut cameras = Vec::new();
    common::play_walk(&mut app, &script, |app, _, moved| cameras.push((moved, app.camera)));
    cameras
}

fn main() {
    let builtin = mazewalk_maze::builtin().expect("built-in maze");
    let generated = generate(&GenOptions {
        width: 40,
        height: 25,
        seed: 1,
        loops: 0.1,
        exit: true,
        ..GenOptions::default()
    })
    .expect("generated maze");
    println!(
        "| maze | colours | textures | bytes per walking frame (mean) | ratio | render ms (median) | ratio |"
    );
    println!("|---|---|---|--:|--:|--:|--:|");
    for (name, maze) in [("built-in", &builtin), ("generated 40×25", &generated)] {
        let cameras = walk(maze);
        for depth in [ColorDepth::TrueColor, ColorDepth::Ansi256] {
            let mut base = (0.0, 0.0);
            for textures in [false, true] {
                let options = RenderOptions {
                    charset: Charset::Half,
                    color_depth: depth,
                    textures,
                    ..RenderOptions::default()
                };
                let (mut renderer, mut frame) = (Renderer::new(), Frame::new(COLS, ROWS));
                let mut encoder = Encoder::new();
                encoder.set_tolerance(encoder::DEFAULT_TOLERANCE);
                let (mut bytes, mut walking, mut times) = (0usize, 0usize, Vec::new());
                let mut out = Vec::new();
                for (k, (moved, camera)) in cameras.iter().enumerate() {
                    let region = frame.region();
                    let started = Instant::now();
                    renderer
                        .render(maze, camera, &[], &options, Target::Frame(&mut frame, region))
                        .expect("camera");
                    times.push(started.elapsed().as_secs_f64() * 1e3);
                    out.clear();
                    let sent = encoder.encode(&frame, &mut out).bytes;
                    if k > 0 && *moved {
                        bytes += sent;
                        walking += 1;
                    }
                }
                times.sort_by(f64::total_cmp);
                let (mean, median) = (bytes as f64 / walking.max(1) as f64, times[times.len() / 2]);
                if !textures {
                    base = (mean, median);
                }
                println!(
                    "| {name} | {depth:?} | {} | {mean:.0} | {:.2}× | {median:.3} | {:.2}× |",
                    if textures { "on" } else { "off" },
                    mean / base.0,
                    median / base.1
                );
            }
        }
    }
}
