//! Generating and loading a 1000×1000-cell maze (the largest the generator makes).
//!
//! - `maze-1000x1000/generate/<algo>`: `generate` with each carving algorithm (seed 1, no loops), and
//!   Prim's with `loops 0.5` (the open-area benchmark maze).
//! - `maze-1000x1000/load/cs559`: `maze::load` of Prim's maze written to a temporary file in the CS559
//!   format (about 128 MB): reading, parsing, validating and indexing.
//! - `maze-1000x1000/load/grid`: the same for Prim's maze in the grid format (4 MB of tiles, 2001 ×
//!   2001, which make 2 M cells and 6 M edges).
//!
//! Peak memory needs a process of its own: `cargo run --release -p mazewalk-bench --example peak_mem -- …`.
//!
//! ```sh
//! nice cargo bench -p mazewalk-bench --bench maze -- --warm-up-time 1 --measurement-time 3 --sample-size 10
//! ```

use std::hint::black_box;

use criterion::Criterion;
use mazewalk_maze as maze;
use mazewalk_maze::generate::{Algorithm, GenOptions, generate, generate_grid};

const SIDE: u32 = 1000;

fn options(algorithm: Algorithm, loops: f32) -> GenOptions {
    GenOptions { width: SIDE, height: SIDE, seed: 1, algorithm, loops, ..GenOptions::default() }
}

fn main() {
    let mut c = Criterion::default().configure_from_args();
    let mut group = c.benchmark_group(format!("maze-{SIDE}x{SIDE}"));
    for (name, algorithm, loops) in [
        ("prim", Algorithm::Prim, 0.0),
        ("dfs", Algorithm::Backtracker, 0.0),
        ("wilson", Algorithm::Wilson, 0.0),
        ("prim-loops-0.5", Algorithm::Prim, 0.5),
    ] {
        let opts = options(algorithm, loops);
        group.bench_function(format!("generate/{name}"), |b| {
            b.iter(|| generate(black_box(&opts)).expect("maze"));
        });
    }

    let maze = generate(&options(Algorithm::Prim, 0.0)).expect("maze");
    let path = std::env::temp_dir().join(format!("mazewalk-bench-{}.maze", std::process::id()));
    {
        let file = std::fs::File::create(&path).expect("temporary file");
        let mut out = std::io::BufWriter::new(file);
        maze::cs559::write_to(&maze, &mut out).expect("write the maze");
        std::io::Write::flush(&mut out).expect("write the maze");
    }
    drop(maze);
    group.bench_function("load/cs559", |b| b.iter(|| maze::load(black_box(&path)).expect("load").maze));
    let _ = std::fs::remove_file(&path);
    let grid = std::env::temp_dir().join(format!("mazewalk-bench-{}.grid", std::process::id()));
    std::fs::write(&grid, generate_grid(&options(Algorithm::Prim, 0.0)).expect("maze").to_text())
        .expect("write the maze");
    group.bench_function("load/grid", |b| b.iter(|| maze::load(black_box(&grid)).expect("load").maze));
    let _ = std::fs::remove_file(&grid);
    group.finish();
    c.final_summary();
}
