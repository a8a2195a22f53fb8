//! `Maze::new` (validation and indexing) over N cells, for shapes that defeat a bucket grid
//! (issue #13): time per edge should stay flat as N grows 100-fold.
//!
//! - `comb`: N unit-wide cells side by side, each N tall: N + 1 long vertical edges.
//! - `diagonal`: N parallelogram cells between N + 1 parallel diagonals, each crossing the whole maze.
//! - `ordinary`: a generated (Prim's) maze of about N cells.
//! - `fan`: N thin triangles round one corner: every cell's box holds the corner, so a point
//!   location tests many cells (the check that no cell lies inside another then sweeps instead).
//!
//! Also `cell_at/<shape>/N`: 1000 point locations at points spread over the maze.
//!
//! ```sh
//! nice cargo bench -p mazewalk-bench --bench validate -- --warm-up-time 1 --measurement-time 3 --sample-size 10
//! ```

use std::hint::black_box;

use criterion::{BatchSize, Criterion, Throughput};
use glam::{Vec2, Vec3, vec2};
use mazewalk_maze::generate::{GenOptions, generate};
use mazewalk_maze::{Cells, Edge, Edges, Maze, Viewer};

/// The parts `Maze::new` takes.
type Parts = (Vec<Vec2>, Edges, Cells, Viewer);

const GREY: Vec3 = Vec3::splat(0.5);

/// N cells between N + 1 long edges from `(i, 0)` to `(i + shear, h)`: a comb for shear 0, long
/// parallel diagonals otherwise. Vertices: bottom row `0..=n`, then top row.
fn slanted(n: u32, h: f32, shear: f32) -> Parts {
    let bottom = |i: u32| i;
    let top = |i: u32| n + 1 + i;
    let mut vertices: Vec<Vec2> = (0..=n).map(|i| vec2(i as f32, 0.0)).collect();
    vertices.extend((0..=n).map(|i| vec2(i as f32 + shear, h)));
    let mut edges = Edges::new();
    let mut cells = vec![Vec::new(); n as usize];
    // long edge i runs up: the cell to its west (i - 1) on its left, cell i on its right
    for i in 0..=n {
        let left = i.checked_sub(1);
        let right = (i < n).then_some(i);
        let opaque = left.is_none() || right.is_none();
        for c in [left, right].into_iter().flatten() {
            cells[c as usize].push(edges.len() as u32);
        }
        edges.push(Edge { start: bottom(i), end: top(i), left, right, opaque, color: GREY });
    }
    for i in 0..n {
        cells[i as usize].push(edges.len() as u32);
        edges.push(Edge {
            start: bottom(i),
            end: bottom(i + 1),
            left: Some(i),
            right: None,
            opaque: true,
            color: GREY,
        });
        cells[i as usize].push(edges.len() as u32);
        edges.push(Edge {
            start: top(i),
            end: top(i + 1),
            left: None,
            right: Some(i),
            opaque: true,
            color: GREY,
        });
    }
    let mut flat = Cells::with_capacity(n as usize, 4 * n as usize);
    for c in &cells {
        flat.push(c);
    }
    let viewer = Viewer { pos: vec2(0.5 + shear / 2.0, h / 2.0), z: 0.0, dir_deg: 0.0, fov_deg: 90.0 };
    (vertices, edges, flat, viewer)
}

/// N triangles round the origin, of radius N: spoke k from the centre to rim point k is a portal
/// between triangles k - 1 and k, and triangle k's third side, from rim k to rim k + 1, a wall.
fn fan(n: u32) -> Parts {
    let rim = |k: u32| {
        let a = std::f64::consts::TAU * f64::from(k % n) / f64::from(n);
        vec2(a.cos() as f32, a.sin() as f32) * n as f32
    };
    let mut vertices = vec![Vec2::ZERO];
    vertices.extend((0..n).map(rim));
    let (mut edges, mut cells) = (Edges::new(), Cells::with_capacity(n as usize, 3 * n as usize));
    for k in 0..n {
        let (left, right) = (Some(k), Some((k + n - 1) % n));
        edges.push(Edge { start: 0, end: k + 1, left, right, opaque: false, color: GREY });
    }
    for k in 0..n {
        let (start, end) = (k + 1, (k + 1) % n + 1);
        edges.push(Edge { start, end, left: Some(k), right: None, opaque: true, color: GREY });
        cells.push(&[k, n + k, (k + 1) % n]);
    }
    let viewer = Viewer { pos: (rim(0) + rim(1)) / 3.0, z: 0.0, dir_deg: 0.0, fov_deg: 90.0 };
    (vertices, edges, cells, viewer)
}

/// A generated maze of about `n` cells, taken apart.
fn ordinary(n: u32) -> Parts {
    let side = (n as f64).sqrt().round() as u32;
    let maze =
        generate(&GenOptions { width: side, height: side, seed: 1, ..GenOptions::default() }).expect("maze");
    (maze.vertices().to_vec(), maze.edges().clone(), maze.cells().clone(), *maze.viewer())
}

fn build(parts: &Parts) -> Maze {
    let (v, e, c, viewer) = parts.clone();
    Maze::new(v, e, c, viewer, None).expect("a valid maze")
}

fn main() {
    let mut c = Criterion::default().configure_from_args();
    for n in [1_000u32, 10_000, 100_000] {
        let shapes: [(&str, Parts); 4] = [
            ("comb", slanted(n, n as f32, 0.0)),
            ("diagonal", slanted(n, n as f32, n as f32)),
            ("ordinary", ordinary(n)),
            ("fan", fan(n)),
        ];
        for (name, parts) in &shapes {
            let mut group = c.benchmark_group(format!("validate/{name}"));
            group.throughput(Throughput::Elements(parts.1.len() as u64));
            group.bench_function(format!("{n}"), |b| {
                b.iter_batched(
                    || parts.clone(),
                    |(v, e, c, viewer)| Maze::new(v, e, c, viewer, None),
                    BatchSize::LargeInput,
                );
            });
            group.finish();
            let maze = build(parts);
            let ext = maze.extents();
            // a fixed spread of points over the extents (a low-discrepancy sequence)
            let points: Vec<Vec2> = (0..1000)
                .map(|k| {
                    let f = vec2((k as f32 * 0.618_034).fract(), (k as f32 * 0.754_877_7).fract());
                    ext.min + (ext.max - ext.min) * f
                })
                .collect();
            let mut group = c.benchmark_group(format!("cell_at/{name}"));
            group.throughput(Throughput::Elements(points.len() as u64));
            group.bench_function(format!("{n}"), |b| {
                b.iter(|| points.iter().filter(|&&p| black_box(&maze).cell_at(p).is_some()).count());
            });
            group.finish();
        }
    }
    c.final_summary();
}
