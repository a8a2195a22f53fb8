//! Rasterizer and glyph throughput on a terminal-sized grid (200×60 cells).

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use glam::{Vec2, Vec3};
use mazewalk_render::{Charset, GridVertex, RenderOptions, SampleBuffer, fill_polygon, to_frame};
use mazewalk_term::frame::{ColorDepth, Frame};

const COLS: usize = 200;
const ROWS: usize = 60;

/// A corridor-like scene: 16 overlapping wall quads spanning the grid at different depths.
fn scene(width: f32, height: f32) -> Vec<[GridVertex<Vec3>; 4]> {
    (0..16)
        .map(|k| {
            let t = k as f32 / 16.0;
            let (x0, x1) = (width * t * 0.5, width * (1.0 - t * 0.5));
            let (y0, y1) = (height * t * 0.4, height * (1.0 - t * 0.4));
            let depth = 0.9 - 0.05 * k as f32;
            [(x0, y0), (x1, y0 + 3.0), (x1, y1 - 3.0), (x0, y1)].map(|(x, y)| GridVertex {
                pos: Vec2::new(x, y),
                depth,
                inv_w: 1.0 / (1.0 + k as f32),
                attrs: Vec3::new(t, 1.0 - t, 0.5),
            })
        })
        .collect()
}

fn bench(c: &mut Criterion) {
    for charset in [Charset::Ascii, Charset::Half, Charset::Sextant] {
        let (sx, sy) = charset.samples_per_cell();
        let mut samples = SampleBuffer::new(COLS * sx, ROWS * sy);
        let walls = scene((COLS * sx) as f32, (ROWS * sy) as f32);
        c.bench_function(&format!("fill 16 walls, {charset}"), |b| {
            b.iter(|| {
                samples.clear(Vec3::ZERO);
                let mut written = 0;
                for (id, wall) in walls.iter().rev().enumerate() {
                    written += fill_polygon(&mut samples, wall, id as u32, |a| a);
                }
                black_box(written)
            });
        });
        let mut frame = Frame::new(COLS, ROWS);
        for depth in [ColorDepth::TrueColor, ColorDepth::Ansi16] {
            c.bench_function(&format!("to_frame {charset} {depth:?}"), |b| {
                let region = frame.region();
                let options = RenderOptions { charset, color_depth: depth, ..RenderOptions::default() };
                b.iter(|| to_frame(black_box(&samples), &options, &mut frame, region));
            });
        }
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
