//! Render time per frame: visibility + clipping + raster + glyphs into a `Frame` (no output), for like
//! views (a corridor; an open area of a maze with loops, see `common`) in 10×10, 100×100 and
//! 1000×1000 mazes, with the portal pass and with brute force (`Culling::None`).
//!
//! The default matrix is every charset at 200×60 plus half blocks at 80×24 and 320×90 (72 cases, a few
//! minutes); `MAZEWALK_BENCH_FULL=1` runs the whole cross product (every charset at every size).
//! `breakdown/…` splits the 200×60 frame into its parts (portal pass alone, samples, glyphs).
//!
//! Before measuring, each case's counts (cells visited, walls drawn, …) are printed and written to
//! `target/criterion/render-stats.tsv` (see `scripts/bench_table.py`).
//!
//! ```sh
//! nice cargo bench -p mazewalk-bench --bench render -- --warm-up-time 1 --measurement-time 3 --sample-size 10
//! ```

use mazewalk_bench::common;

use std::fmt::Write as _;
use std::hint::black_box;

use common::{SIDES, Scene, View, render_samples};
use criterion::{BenchmarkId, Criterion};
use mazewalk_render::{Charset, Culling, PortalPass, RenderOptions, Renderer, Target, to_frame};
use mazewalk_term::frame::{ColorDepth, Frame, Region};

/// Terminal sizes (columns × rows).
const SIZES: [(usize, usize); 3] = [(80, 24), (200, 60), (320, 90)];
/// The size every charset is measured at by default.
const MAIN_SIZE: (usize, usize) = (200, 60);

fn cullings() -> [(Culling, &'static str); 2] {
    [(Culling::Portal, "portal"), (Culling::None, "none")]
}

/// (charset, cols, rows) to measure.
fn grids() -> Vec<(Charset, usize, usize)> {
    let full = std::env::var_os("MAZEWALK_BENCH_FULL").is_some_and(|v| v != "0");
    let mut grids = Vec::new();
    for (cols, rows) in SIZES {
        for charset in Charset::ALL {
            if full || (cols, rows) == MAIN_SIZE || charset == Charset::Half {
                grids.push((charset, cols, rows));
            }
        }
    }
    grids
}

fn options(charset: Charset, culling: Culling) -> RenderOptions {
    RenderOptions { charset, color_depth: ColorDepth::TrueColor, culling, ..RenderOptions::default() }
}

/// Prints and saves the counts of every case (they do not depend on timing).
fn record_stats(scenes: &[Scene], grids: &[(Charset, usize, usize)]) {
    let mut tsv = String::from(
        "view\tmaze\tcharset\tsize\tculling\tcells_visited\tdistinct_cells\tportals\twalls_drawn\ttriangles\tsamples_written\tcamera\n",
    );
    let (mut renderer, mut frame) = (Renderer::new(), Frame::default());
    for scene in scenes {
        for &(charset, cols, rows) in grids {
            frame.resize(cols, rows);
            for (culling, culling_name) in cullings() {
                let s = renderer
                    .render(
                        &scene.maze,
                        &scene.camera,
                        &[],
                        &options(charset, culling),
                        Target::Frame(&mut frame, Region { col: 0, row: 0, cols, rows }),
                    )
                    .expect("benchmark camera");
                let c = &scene.camera;
                let _ = writeln!(
                    tsv,
                    "{}\t{n}x{n}\t{charset}\t{cols}x{rows}\t{culling_name}\t{}\t{}\t{}\t{}\t{}\t{}\t({}, {}) heading {} seed {}",
                    scene.view.name(),
                    s.portal.cells_visited,
                    s.portal.distinct_cells,
                    s.portal.portals_traversed,
                    s.walls_drawn,
                    s.triangles,
                    s.samples_written,
                    c.position.x,
                    c.position.y,
                    c.yaw_deg,
                    scene.seed,
                    n = scene.side,
                );
            }
        }
    }
    eprint!("{tsv}");
    let dir = std::path::Path::new(&std::env::var("CARGO_TARGET_DIR").unwrap_or_else(|_| "target".into()))
        .join("criterion");
    if std::fs::create_dir_all(&dir).is_ok() {
        let _ = std::fs::write(dir.join("render-stats.tsv"), tsv);
    }
}

fn bench_frames(c: &mut Criterion, scenes: &[Scene], grids: &[(Charset, usize, usize)]) {
    let (mut renderer, mut frame) = (Renderer::new(), Frame::default());
    for scene in scenes {
        for &(charset, cols, rows) in grids {
            frame.resize(cols, rows);
            let n = scene.side;
            let mut group =
                c.benchmark_group(format!("render/{}/{n}x{n}/{charset}/{cols}x{rows}", scene.view.name()));
            for (culling, name) in cullings() {
                let opts = options(charset, culling);
                group.bench_function(BenchmarkId::from_parameter(name), |b| {
                    b.iter(|| {
                        renderer
                            .render(
                                &scene.maze,
                                &scene.camera,
                                &[],
                                black_box(&opts),
                                Target::Frame(&mut frame, Region { col: 0, row: 0, cols, rows }),
                            )
                            .expect("benchmark camera")
                    });
                });
            }
            group.finish();
        }
    }
}

/// Where a 200×60 frame's time goes: the portal pass alone, everything but glyphs, glyphs alone.
fn bench_breakdown(c: &mut Criterion, scenes: &[Scene]) {
    let (cols, rows) = MAIN_SIZE;
    let mut renderer = Renderer::new();
    let mut frame = Frame::new(cols, rows);
    let mut pass = PortalPass::new();
    for scene in scenes.iter().filter(|s| s.side == *SIDES.last().expect("sizes")) {
        for charset in Charset::ALL {
            let n = scene.side;
            let mut group =
                c.benchmark_group(format!("breakdown/{}/{n}x{n}/{charset}/{cols}x{rows}", scene.view.name()));
            let (sx, sy) = charset.samples_per_cell();
            let eye = scene.camera.eye(cols * sx, rows * sy, charset.sample_aspect(0.5)).expect("camera");
            group.bench_function("portal_pass", |b| b.iter(|| pass.run(&scene.maze, black_box(&eye))));
            let mut samples =
                || render_samples(&mut renderer, &scene.maze, &scene.camera, charset, (cols, rows));
            group.bench_function("render_samples", |b| b.iter(&mut samples));
            // The samples to_frame reads (also when a filter skips the bench above).
            samples();
            for depth in [ColorDepth::TrueColor, ColorDepth::Ansi256] {
                group.bench_function(format!("to_frame_{depth:?}"), |b| {
                    b.iter(|| {
                        to_frame(
                            black_box(renderer.samples()),
                            &RenderOptions { charset, color_depth: depth, ..RenderOptions::default() },
                            &mut frame,
                            Region { col: 0, row: 0, cols, rows },
                        )
                    });
                });
            }
            group.finish();
        }
    }
}

fn main() {
    let mut c = Criterion::default().configure_from_args();
    let scenes: Vec<Scene> =
        View::ALL.iter().flat_map(|&view| SIDES.iter().map(move |&side| common::scene(view, side))).collect();
    let grids = grids();
    record_stats(&scenes, &grids);
    bench_frames(&mut c, &scenes, &grids);
    bench_breakdown(&mut c, &scenes);
    c.final_summary();
}
