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

use mazewalk_bench::common;

use std::time::Instant;

use common::View;
use mazewalk_render::{Charset, Culling, RenderOptions, Renderer, Target, to_frame};
use mazewalk_term::frame::{ColorDepth, Frame, Region};

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let arg = |i: usize, default: &str| args.get(i).cloned().unwrap_or_else(|| default.to_owned());
    let view = if arg(0, "corridor") == "open" { View::Open } else { View::Corridor };
    let side: u32 = arg(1, "10").parse().expect("maze side");
    let charset: Charset = arg(2, "half").parse().expect("charset");
    let (cols, rows): (usize, usize) =
        (arg(3, "200").parse().expect("cols"), arg(4, "60").parse().expect("rows"));
    let part = arg(5, "frame");
    let reps: u32 = arg(6, "2000").parse().expect("repetitions");
    let depth: ColorDepth = arg(7, "truecolor").parse().expect("colour depth");

    let scene = common::scene(view, side);
    let options =
        RenderOptions { charset, color_depth: depth, culling: Culling::Portal, ..RenderOptions::default() };
    let (mut renderer, mut frame) = (Renderer::new(), Frame::new(cols, rows));
    renderer
        .render(
            &scene.maze,
            &scene.camera,
            &[],
            &options,
            Target::Frame(&mut frame, Region { col: 0, row: 0, cols, rows }),
        )
        .expect("render");
    let start = Instant::now();
    for _ in 0..reps {
        match part.as_str() {
            "samples" => {
                renderer
                    .render(
                        &scene.maze,
                        &scene.camera,
                        &[],
                        &RenderOptions { charset, culling: Culling::Portal, ..RenderOptions::default() },
                        Target::Samples { cols, rows },
                    )
                    .expect("render");
            }
            "glyphs" => {
                to_frame(renderer.samples(), &options, &mut frame, Region { col: 0, row: 0, cols, rows })
            }
            _ => {
                renderer
                    .render(
                        &scene.maze,
                        &scene.camera,
                        &[],
                        &options,
                        Target::Frame(&mut frame, Region { col: 0, row: 0, cols, rows }),
                    )
                    .expect("render");
            }
        }
        std::hint::black_box(&frame);
    }
    println!("{part}: {:.1} µs per repetition", start.elapsed().as_secs_f64() * 1e6 / f64::from(reps));
}
