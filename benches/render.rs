//! Frame time (visibility + clipping + raster + glyphs, no output) in mazes of 10×10, 100×100 and
//! 1000×1000 cells, portal pass beside brute force, for like views: a corridor (recursive backtracker,
//! viewer at the generator's start looking down its first corridor) and an open area (Prim's with half
//! the inner walls removed). Grid sizes 80×24, 200×60 and 320×90 in half blocks; every charset at 200×60.
//!
//! `cargo bench --bench render` (add `-- portal` or `-- brute` to filter). The portal pass's counts per
//! view are printed once at the start, so BENCHMARKS.md can cite what was drawn.

use std::hint::black_box;
use std::time::Duration;

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use mazewalk::frame::{ColorDepth, Frame};
use mazewalk::maze::Maze;
use mazewalk::maze::generate::{Algorithm, GenOptions, generate};
use mazewalk::render::{Camera, Charset, Culling, RenderOptions, Renderer};

/// A maze of `side × side` cells and the camera for a view of the given kind.
fn scene(side: u32, open: bool) -> (Maze, Camera) {
    let opts = if open {
        GenOptions { width: side, height: side, seed: 11, algorithm: Algorithm::Prim, loops: 0.5, ..GenOptions::default() }
    } else {
        GenOptions { width: side, height: side, seed: 11, algorithm: Algorithm::Backtracker, ..GenOptions::default() }
    };
    let maze = generate(&opts).expect("generate");
    let v = *maze.viewer();
    (maze, Camera::new(v.pos, v.dir_deg, 90.0))
}

fn options(charset: Charset, culling: Culling) -> RenderOptions {
    RenderOptions { charset, color_depth: ColorDepth::TrueColor, culling, cell_aspect: 0.5 }
}

fn bench(c: &mut Criterion) {
    let scenes: Vec<(String, Maze, Camera)> = [10u32, 100, 1000]
        .iter()
        .flat_map(|&side| {
            [false, true].map(|open| {
                let (maze, camera) = scene(side, open);
                (format!("{}{side}x{side}", if open { "open-" } else { "corridor-" }), maze, camera)
            })
        })
        .collect();
    for (name, maze, camera) in &scenes {
        let mut r = Renderer::new();
        let mut f = Frame::new(0, 0);
        let s = r.render(maze, camera, &options(Charset::Half, Culling::Portal), 200, 60, &mut f).unwrap();
        eprintln!(
            "{name}: {} cells; portal pass visits {} cells, crosses {} portals, draws {} walls of {}",
            maze.cell_count(),
            s.portal.distinct_cells,
            s.portal.portals_traversed,
            s.walls_drawn,
            maze.edges().len()
        );
    }

    let mut group = c.benchmark_group("render");
    group.sample_size(20).warm_up_time(Duration::from_millis(500)).measurement_time(Duration::from_secs(2));
    let mut renderer = Renderer::new();
    let mut frame = Frame::new(0, 0);
    for (name, maze, camera) in &scenes {
        for (cols, rows) in [(80, 24), (200, 60), (320, 90)] {
            for culling in [Culling::Portal, Culling::None] {
                if culling == Culling::None && (cols, rows) != (200, 60) {
                    continue; // brute force once per maze is enough for the ratio
                }
                let label = format!("{}/half/{cols}x{rows}/{name}", if culling == Culling::Portal { "portal" } else { "brute" });
                group.bench_function(BenchmarkId::from_parameter(label), |b| {
                    b.iter(|| {
                        renderer.render(maze, camera, &options(Charset::Half, culling), cols, rows, &mut frame).unwrap();
                        black_box(&frame);
                    })
                });
            }
        }
    }
    let (_, maze, camera) = &scenes[2]; // corridor in 100×100
    for charset in Charset::ALL {
        let label = format!("charset/{}/200x60/corridor-100x100", charset.name());
        group.bench_function(BenchmarkId::from_parameter(label), |b| {
            b.iter(|| {
                renderer.render(maze, camera, &options(charset, Culling::Portal), 200, 60, &mut frame).unwrap();
                black_box(&frame);
            })
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
